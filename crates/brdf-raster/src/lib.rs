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
pub use camera::{Camera, Projection};
pub use framebuffer::Frame;
pub use mesh::Mesh;
pub use render::{NoOcclusion, Occlusion, RenderOptions, ShadePoint, coverage_counts, render, render_with};
pub use scene::{Instance, Material, Scene};
pub use shading::ShadingMode;
