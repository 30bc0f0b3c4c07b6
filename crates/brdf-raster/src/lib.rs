//! # brdf-raster
//!
//! A tiled, multithreaded software rasterizer that shades meshes with `brdf-core` models.

pub mod ao;
pub mod bvh;
pub mod error;
pub mod io;
pub mod mesh;
pub mod normals;
pub mod procedural;

pub use error::RasterError;
pub use mesh::Mesh;
