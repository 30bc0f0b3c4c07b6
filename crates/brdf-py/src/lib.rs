//! Python bindings of brdf-core: convert, validate, release the GIL and map errors. Every function
//! follows one shape: check the arguments, view the NumPy arrays without copying, release the GIL for
//! large batches and run on the pool (`threads.rs`), call the core, map its error (`errors.rs`).
//! One file per Python-visible area; the Python package `brdfpy` wraps these in typed functions.

use pyo3::prelude::*;

mod arrays;
mod checks;
mod errors;
mod fresnel;
mod measured;
mod microfacet;
mod models;
mod pickle;
mod raster;
mod raycast;
mod sampling;
mod threads;
mod tonemap;
mod vectors;
mod views;

/// The compiled module `brdfpy._brdfpy`; the public API is re-exported by `brdfpy/__init__.py`.
#[pymodule]
mod _brdfpy {
    use pyo3::prelude::*;

    #[pymodule_export]
    use super::checks::{check, d_normalization, directional_albedo, positivity, reciprocity_error};
    #[pymodule_export]
    use super::fresnel::{
        color_shift, conductor, dielectric, dielectric_sp, f0_from_ior, ior_from_f0, metal_f0, metal_names,
        schlick, split,
    };
    #[pymodule_export]
    use super::measured::{
        AnisotropicTabulated, RglBsdf, Tabulated, aniso_table_samples, fit_model, read_samples_csv_bytes,
        sh_basis, sh_clamped_cosine_zonal, sh_max_order, sh_project, sh_quadrature, sh_reconstruct,
        table_samples,
    };
    #[pymodule_export]
    use super::microfacet::{distribution, masking, microfacet_names, smith_lambda};
    #[pymodule_export]
    use super::models::{Model, model_names, model_spec};
    #[pymodule_export]
    use super::pickle::{_frame_from_state, _frame_state, _light_with_direction, _mesh_from_parts};
    #[pymodule_export]
    use super::raster::{
        RasterAreaLight, RasterCamera, RasterEnvironment, RasterFrame, RasterLight, RasterMesh,
        RasterTexture, builtin_mesh, builtin_mesh_names, cube, icosphere, load_gltf, load_gltf_bytes,
        load_mesh, load_mesh_bytes, load_obj_scene, occlusion_cache_info, open_box, plane, polygon_normal,
        raster_limits, render_scene, torus,
    };
    #[pymodule_export]
    use super::raycast::{RayCaster, mesh_obscurance};
    #[pymodule_export]
    use super::sampling::{chi2_test, model_pdf, model_sample, pdf_integral, uniform};
    #[pymodule_export]
    use super::threads::{_reset_after_fork, get_num_threads, set_num_threads};
    #[pymodule_export]
    use super::tonemap::{
        aces, clamp, exposure, reinhard, reinhard_extended, srgb_decode, srgb_encode, to_uint8,
        tonemap_operators,
    };
    #[pymodule_export]
    use super::vectors::{halfway, reflect, refract};
    #[pymodule_export]
    use super::views::{
        view_albedo, view_cell_angles, view_half_diff_slice, view_lit_sphere, view_lobe, view_polar,
        view_quadrature,
    };

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add("BrdfError", m.py().get_type::<super::errors::BrdfError>())?;
        Ok(())
    }
}
