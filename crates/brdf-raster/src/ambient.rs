//! The ambient reflectance `k_a` a material gets when the caller gives none: what the material reflects
//! under a uniform white sky, so that a scene's ambient light `I_a` lights every object through its own
//! reflectance model (a copper sphere under a grey sky looks copper, a white Lambert one shows `I_a`).
//!
//! ## Which albedo
//! A uniform sky of radiance `I_a` reflects `I_a · ρ(v)` toward `v`, with `ρ(v) = ∫ f_r(l, v) cos θ_l dω_l`
//! the directional albedo seen from `v` ([`brdf_core::views::albedo::Over::Light`]). The ambient term of
//! the Phong illumination model is one colour per surface, independent of the view, so `k_a` is the
//! cosine-weighted mean of `ρ` over the view hemisphere, the *white-sky* (bihemispherical) albedo
//!
//! ```text
//! ρ_hh = (1/π) ∫_{H²} ρ(v) cos θ_v dω_v = 2 ∫₀¹ ρ̄(μ) μ dμ        (dimensionless, ≤ 1 for a passive surface)
//! ```
//!
//! (Nicodemus et al. 1977, "Geometrical Considerations and Nomenclature for Reflectance", NBS Monograph
//! 160: the bihemispherical reflectance; `ρ̄` is `ρ` averaged over the view azimuth). It is computed with
//! [`AMBIENT_MU_NODES`] Gauss–Legendre nodes in `μ = cos θ_v` (and [`AMBIENT_PHI_NODES`] azimuths for
//! anisotropic models), each `ρ` by brdf-core's graded hemisphere rule
//! ([`brdf_core::views::albedo::VIEW_QUADRATURE`]): white Lambert gives 1 to 1e-5. The view-dependent
//! `ρ(v)` itself (the Fresnel brightening toward grazing views) is what environment lighting gives.
//!
//! For classic (course) models, whose `shade` is the textbook formula rather than `f_r·cos`, the integral
//! is divided by π, the scale of the lit-sphere view ([`brdf_core::views::sphere`]): a classic Lambert
//! `kd·max(n·l, 0)` gets `k_a = kd`, the textbook's usual choice.

use std::sync::Mutex;

use brdf_core::Model;
use brdf_core::views::albedo::{Over, VIEW_QUADRATURE, hemispherical};
use brdf_core::views::direction;
use glam::{DVec3, Vec3};

use crate::RasterError;

/// Gauss–Legendre nodes in `μ = cos θ_v` of the white-sky albedo.
pub const AMBIENT_MU_NODES: usize = 8;
/// View azimuths (midpoints of `[0, π/2]`) of the white-sky albedo of anisotropic models; isotropic
/// models use one.
pub const AMBIENT_PHI_NODES: usize = 4;

/// Materials whose white-sky albedo was computed, most recent last (a script that renders a scene in a
/// loop asks for the same few materials every frame; each costs ~10⁵ evaluations).
static CACHE: Mutex<Vec<(Model, Vec3)>> = Mutex::new(Vec::new());
const CACHE_LEN: usize = 16;

/// The white-sky albedo `ρ_hh` of `model` (see the module docs), per linear RGB channel, ≥ 0.
pub fn white_sky_albedo(model: &Model) -> Result<Vec3, RasterError> {
    {
        let cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, a)) = cache.iter().rev().find(|(m, _)| m == model) {
            return Ok(*a);
        }
    }
    let spec = model.spec();
    let (x, w) = brdf_core::sh::gauss_legendre(AMBIENT_MU_NODES);
    let phis: Vec<f64> = if spec.anisotropic {
        (0..AMBIENT_PHI_NODES)
            .map(|j| (j as f64 + 0.5) * std::f64::consts::FRAC_PI_2 / AMBIENT_PHI_NODES as f64)
            .collect()
    } else {
        vec![0.0]
    };
    // 2 ∫₀¹ ρ̄(μ) μ dμ with μ = (x + 1)/2, dμ = dx/2: Σ_k w_k μ_k ρ̄(μ_k). In node order, in f64: the same
    // bits at any thread count.
    let mut sum = DVec3::ZERO;
    for (xk, wk) in x.iter().zip(&w) {
        let mu = 0.5 * (xk + 1.0);
        let mut mean = DVec3::ZERO;
        for &phi in &phis {
            let v = direction(mu.acos(), phi);
            mean += hemispherical(model, v, Over::Light, &VIEW_QUADRATURE)?.as_dvec3();
        }
        sum += mean / phis.len() as f64 * (wk * mu);
    }
    let scale = if spec.physical { 1.0 } else { std::f64::consts::FRAC_1_PI };
    // A model that is negative somewhere (a classic formula) must not make the ambient term negative.
    let albedo = (sum * scale).as_vec3().max(Vec3::ZERO);
    if !albedo.is_finite() {
        return Err(RasterError::arg("material", format!("white-sky albedo is not finite ({albedo})")));
    }
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if cache.len() == CACHE_LEN {
        cache.remove(0);
    }
    cache.push((model.clone(), albedo));
    Ok(albedo)
}

/// The ambient light `I_a` and a material's ambient reflectance `k_a` from what the caller gave, the rule
/// of the Python `Scene`:
///
/// - `ambient_light = Some(I_a)`: every material without its own `ambient` gets its white-sky albedo
///   ([`white_sky_albedo`]), so the ambient light lights every object; a given `ambient` overrides it.
/// - `ambient_light = None` (no ambient light asked for): `I_a = 1`, and only a material with its own
///   `ambient` shows an ambient term, exactly `k_a` (the colour it asked for).
///
/// Returns `(I_a, k_a)`.
pub fn resolve(
    model: &Model,
    ambient: Option<Vec3>,
    ambient_light: Option<Vec3>,
) -> Result<(Vec3, Vec3), RasterError> {
    let light = ambient_light.unwrap_or(Vec3::ONE);
    let ka = match (ambient, ambient_light) {
        (Some(ka), _) => ka,
        // No light to reflect: skip the quadrature.
        (None, Some(ia)) if ia == Vec3::ZERO => Vec3::ZERO,
        (None, Some(_)) => white_sky_albedo(model)?,
        (None, None) => Vec3::ZERO,
    };
    Ok((light, ka))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_core::Input;

    fn model(name: &str, params: &[(&str, Input)]) -> Model {
        let p: Vec<(String, Input)> = params.iter().map(|(k, v)| ((*k).to_string(), v.clone())).collect();
        Model::build(name, &p).unwrap()
    }

    #[test]
    fn white_lambert_reflects_the_whole_sky_and_a_grey_one_its_albedo() {
        let white = model("lambert", &[("kd", Input::Number(1.0))]);
        let a = white_sky_albedo(&white).unwrap();
        assert!((a - Vec3::ONE).abs().max_element() < 1e-5, "{a}");
        let tinted = model("lambert", &[("kd", Input::Numbers(vec![0.8, 0.3, 0.2]))]);
        let a = white_sky_albedo(&tinted).unwrap();
        assert!((a - Vec3::new(0.8, 0.3, 0.2)).abs().max_element() < 1e-5, "{a}");
    }

    #[test]
    fn a_classic_lambert_gets_its_kd_on_the_course_scale() {
        let m = model("lambert_classic", &[("kd", Input::Numbers(vec![0.5, 0.25, 0.125]))]);
        let a = white_sky_albedo(&m).unwrap();
        assert!((a - Vec3::new(0.5, 0.25, 0.125)).abs().max_element() < 1e-5, "{a}");
    }

    #[test]
    fn copper_is_copper_coloured_and_loses_energy_only_to_single_scattering() {
        let cu = model(
            "cook_torrance",
            &[("metal", Input::Text("cu".into())), ("roughness", Input::Number(0.25))],
        );
        let a = white_sky_albedo(&cu).unwrap();
        // Red above green above blue, below the F0 bound 1, and well above black.
        assert!(a.x > a.y && a.y > a.z && a.z > 0.3 && a.x < 1.0, "{a}");
    }

    #[test]
    fn resolve_follows_the_scene_rule() {
        let m = model("lambert", &[("kd", Input::Number(0.5))]);
        let (ia, ka) = resolve(&m, None, Some(Vec3::splat(0.2))).unwrap();
        assert_eq!(ia, Vec3::splat(0.2));
        assert!((ka - Vec3::splat(0.5)).abs().max_element() < 1e-5);
        assert_eq!(resolve(&m, Some(Vec3::splat(0.1)), Some(Vec3::splat(0.2))).unwrap().1, Vec3::splat(0.1));
        assert_eq!(resolve(&m, None, None).unwrap(), (Vec3::ONE, Vec3::ZERO));
        assert_eq!(resolve(&m, Some(Vec3::splat(0.3)), None).unwrap(), (Vec3::ONE, Vec3::splat(0.3)));
        assert_eq!(resolve(&m, None, Some(Vec3::ZERO)).unwrap(), (Vec3::ZERO, Vec3::ZERO));
    }
}
