//! # brdf-raster
//!
//! A tiled, multithreaded software rasterizer that shades meshes with `brdf-core` models.

pub mod bvh;
pub mod error;
pub mod mesh;
pub mod normals;

pub use error::RasterError;
pub use mesh::Mesh;
