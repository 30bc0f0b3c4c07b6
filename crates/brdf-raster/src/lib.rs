//! # brdf-raster
//!
//! A tiled, multithreaded software rasterizer that shades meshes with `brdf-core` models.
