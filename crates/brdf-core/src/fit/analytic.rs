//! Analytic Jacobians `∂f/∂p` for the models fitted most (Lambert; Cook–Torrance with a single GGX lobe,
//! height-correlated Smith masking and Schlick's Fresnel, the benchmarked case), used by [`super`] in place
//! of finite differences when they apply ([`super::Jacobian::Auto`]); the tests compare them with central
//! differences.
//!
//! The model values themselves are never recomputed here: the terms come from the model's own formulas
//! ([`ggx::d_half`], [`ggx::visibility_height_correlated`], [`schlick_weight_lanes`]); only the derivative
//! of `D·V` with respect to α is written out. With `f = kd/π + ks ∘ F(v·h) D V`:
//! - `∂f_c/∂kd_c = 1/π`, `∂f_c/∂ks_c = F_c D V`, `∂f_c/∂f0_c = ks_c (1 − w) D V` (`w = (1 − v·h)⁵`);
//! - `∂f_c/∂α = ks_c F_c D V · ∂ln(D V)/∂α` where, with GGX in the un-normalised half vector
//!   (`D = α²|h̃|⁴/(π t²)`, `t = α²(n·h̃)² + |h̃⊥|²`) and `V = ½/((n·v) Λ_l + (n·l) Λ_v)`,
//!   `Λ_w = √((n·w)²(1 − α²) + α²)`: `∂ln D/∂α = 2/α − 4α(n·h̃)²/t` and
//!   `∂ln V/∂α = −((n·v) ∂Λ_l + (n·l) ∂Λ_v)/((n·v) Λ_l + (n·l) Λ_v)`, `∂Λ_w/∂α = α (1 − (n·w)²)/Λ_w`
//!   (0 below the floor α < 10⁻⁴, where the model holds α constant).

use rayon::prelude::*;

use super::{Data, Free};
use crate::fresnel::{Fresnel, schlick_weight_lanes};
use crate::masking::Masking;
use crate::microfacet::{ALPHA_MIN, Distribution, HalfVector, ggx};
use crate::simd::LaneGeometry;
use crate::{Geometry, Model};

/// The models with an analytic Jacobian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Analytic {
    /// `lambert` (free: `kd`).
    Lambert,
    /// `cook_torrance` with one GGX lobe, `smith` masking, `schlick` Fresnel, no metal preset (free: any
    /// of `kd`, `ks`, `roughness`, `f0`).
    CookTorranceGgx,
}

impl Analytic {
    /// The analytic form that applies to `model` (built from the problem's fixed values) with these free
    /// parameters, if any.
    pub fn for_problem(model: &Model, free: &[Free]) -> Option<Self> {
        let names_in = |ok: &[&str]| free.iter().all(|f| ok.contains(&f.name));
        match model {
            Model::Lambert(_) if names_in(&["kd"]) => Some(Self::Lambert),
            Model::CookTorrance(ct)
                if names_in(&["kd", "ks", "roughness", "f0"])
                    && matches!(ct.distribution.as_single(), Some(Distribution::Ggx { .. }))
                    && ct.masking == Masking::Smith
                    && matches!(ct.fresnel, Fresnel::Schlick { .. }) =>
            {
                Some(Self::CookTorranceGgx)
            }
            _ => None,
        }
    }

    /// `∂f_c/∂p_j` at every sample for `model` (built from `p`), row-major: entry `(3 i + c) k + j`.
    pub fn model_jacobian(self, model: &Model, free: &[Free], p: &[f64], data: &Data) -> Vec<f64> {
        let k = p.len();
        let mut out = vec![0.0; 3 * k * data.len()];
        // Where each free parameter sits in p.
        let mut slot = [usize::MAX; 4];
        let mut at = 0;
        for f in free {
            let s = match f.name {
                "kd" => 0,
                "ks" => 1,
                "roughness" => 2,
                _ => 3,
            };
            slot[s] = at;
            at += f.width();
        }
        let inv_pi = std::f64::consts::FRAC_1_PI;
        match (self, model) {
            (Self::Lambert, _) => {
                out.par_chunks_mut(3 * k).for_each(|row| {
                    for c in 0..3 {
                        row[c * k + slot[0] + c] = inv_pi;
                    }
                });
            }
            (Self::CookTorranceGgx, Model::CookTorrance(ct)) => {
                let Some(Distribution::Ggx { alpha_x, .. }) = ct.distribution.as_single() else { return out };
                let Fresnel::Schlick { f0 } = ct.fresnel else { return out };
                let alpha = *alpha_x;
                let free_alpha = slot[2] != usize::MAX && p[slot[2]] >= f64::from(ALPHA_MIN);
                let (ks, a) = (ct.ks, f64::from(alpha));
                out.par_chunks_mut(3 * k).enumerate().for_each(|(i, row)| {
                    if slot[0] != usize::MAX {
                        for c in 0..3 {
                            row[c * k + slot[0] + c] = inv_pi;
                        }
                    }
                    let Some(g) = Geometry::new(data.ls[i], data.vs[i], data.ns[i], None) else { return };
                    let lg = LaneGeometry::<f32>::from(&g);
                    let h = HalfVector::from_directions(lg.l, lg.v, lg.n);
                    let (nl, nv) = (g.nl, g.nv);
                    let d = ggx::d_half(&h, alpha);
                    if !(nl > 0.0 && nv > 0.0 && h.len2 > 1e-12 && d != 0.0) {
                        return;
                    }
                    let vh = 0.5 * h.len2.sqrt();
                    let dv = f64::from(d) * f64::from(ggx::visibility_height_correlated(nl, nv, alpha));
                    let w = f64::from(schlick_weight_lanes(vh));
                    let dlog = if free_alpha {
                        let (nl, nv, nh2) = (f64::from(nl), f64::from(nv), f64::from(h.n_dot).powi(2));
                        let t = a * a * nh2 + f64::from(h.perp2);
                        let (ll, lv) = (
                            (nl * nl * (1.0 - a * a) + a * a).sqrt(),
                            (nv * nv * (1.0 - a * a) + a * a).sqrt(),
                        );
                        let (dll, dlv) = (a * (1.0 - nl * nl) / ll, a * (1.0 - nv * nv) / lv);
                        2.0 / a - 4.0 * a * nh2 / t - (nv * dll + nl * dlv) / (nv * ll + nl * lv)
                    } else {
                        0.0
                    };
                    for c in 0..3 {
                        let (ksc, f0c) = (f64::from(ks[c]), f64::from(f0[c]));
                        let fc = f0c + (1.0 - f0c) * w;
                        let r = &mut row[c * k..(c + 1) * k];
                        if slot[1] != usize::MAX {
                            r[slot[1] + c] = fc * dv;
                        }
                        if slot[2] != usize::MAX {
                            r[slot[2]] = ksc * fc * dv * dlog;
                        }
                        if slot[3] != usize::MAX {
                            r[slot[3] + c] = ksc * (1.0 - w) * dv;
                        }
                    }
                });
            }
            _ => {}
        }
        out
    }
}
