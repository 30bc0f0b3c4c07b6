//! # brdf-raster
//!
//! A tiled, multithreaded software rasterizer that shades meshes with `brdf-core` models.

pub mod ambient;
pub mod ao;
pub mod area_light;
pub mod area_lighting;
pub mod bvh;
pub mod camera;
pub mod clip;
pub mod environment;
pub mod error;
pub mod framebuffer;
pub mod io;
pub mod mesh;
pub mod normals;
pub mod occlusion;
pub mod procedural;
pub mod render;
pub mod scene;
pub mod setup;
pub mod shading;
pub mod shadows;
pub mod texture;
pub mod tiles;

pub use camera::{Camera, Projection};
pub use error::RasterError;
pub use framebuffer::Frame;
pub use mesh::Mesh;
pub use render::{
    NoOcclusion, Occlusion, Outputs, RenderOptions, ShadePoint, coverage_counts, render, render_with,
};
pub use scene::{Instance, Material, Scene};
pub use shading::ShadingMode;
pub use texture::{ColorSpace, MaterialTextures, Texture};
