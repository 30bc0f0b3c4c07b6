//! What a material reads from textures: any colour or scalar parameter of its model, a tangent-space
//! normal map, an occlusion map and an emission map, resolved once when the material is built.
//!
//! **Parameters.** A bound parameter's value at a shaded sample replaces the model's value there; the
//! parameter's slot in the model's [`Params`] is found once ([`MaterialTextures::bind`]), and per
//! sample only the bound slots are written and the model rebuilt from them (`Bxdf::from_params`, the
//! one constructor every model has, so every model and every colour or scalar parameter can be
//! bound; a model keeps precomputed terms, e.g. Cook–Torrance's distribution from `roughness`, that a
//! field write alone would leave stale). A colour parameter takes a texture's RGB (a 1-channel texture
//! reads as grey), a scalar one a chosen channel (glTF packs roughness in G and metallic in B of one
//! texture: `Channel::One(1)`, `Channel::One(2)`). Each value is `factor ∘ texel`, clamped into the
//! parameter's documented range (a float texture may hold anything ≥ 0).
//!
//! **glTF 2.0 metallic-roughness** (appendix B) maps onto `cook_torrance` with two derived colours,
//! [`ParamSource::MetallicDiffuse`] (`kd = (1 − metallic)·baseColor`) and [`ParamSource::MetallicF0`]
//! (`f0 = mix(0.04, baseColor, metallic)`), each read from the base-colour and metallic textures.
//!
//! **Maps.** The normal map is in tangent space (glTF `normalTexture`): `n' = normalize(T·x·s + B·y·s
//! + N·z)` with `(x, y, z) = 2·rgb − 1`, `s` the scale, `N` the interpolated normal, `T` the
//! interpolated tangent made perpendicular to `N` and `B = w·(N × T)` (the mesh's tangents, e.g. from
//! [`super::tangents`]). The occlusion map multiplies the ambient and indirect terms by `1 + k·(r − 1)`
//! (glTF `occlusionTexture` with strength `k`); the emission map multiplies the material's emission by
//! its RGB (glTF `emissiveTexture` × `emissiveFactor`).

use std::sync::Arc;

use brdf_core::params::{ParamKind, Params, Value};
use glam::{Vec2, Vec3, Vec4};

use super::Texture;
use crate::RasterError;

/// Which texel channels a binding reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// Red, green and blue (a 1-channel texture: its one value, as grey).
    Rgb,
    /// One channel: 0 red, 1 green, 2 blue, 3 alpha (a colour parameter reads it as grey).
    One(u8),
}

/// A texture read by a binding, or a constant: `factor ∘ texel` (texel 1 without a texture).
#[derive(Debug, Clone, PartialEq)]
pub struct TextureRef {
    /// The texture, or `None` for the constant `factor`.
    pub texture: Option<Arc<Texture>>,
    /// The channels read.
    pub channel: Channel,
    /// Multiplies what is read (per channel; a scalar binding uses `factor.x`).
    pub factor: Vec3,
}

impl TextureRef {
    /// The RGB of `texture`, factor 1.
    pub fn rgb(texture: Arc<Texture>) -> Self {
        Self { texture: Some(texture), channel: Channel::Rgb, factor: Vec3::ONE }
    }

    /// Channel `k` of `texture`, factor 1.
    pub fn channel(texture: Arc<Texture>, k: u8) -> Self {
        Self { texture: Some(texture), channel: Channel::One(k), factor: Vec3::ONE }
    }

    /// The constant `value` (no texture).
    pub fn constant(value: Vec3) -> Self {
        Self { texture: None, channel: Channel::Rgb, factor: value }
    }

    /// The same with `factor` multiplying what is read.
    pub fn with_factor(mut self, factor: Vec3) -> Self {
        self.factor = factor;
        self
    }

    fn check(&self, name: &'static str, scalar: bool) -> Result<(), RasterError> {
        if !self.factor.is_finite() || self.factor.min_element() < 0.0 {
            return Err(RasterError::arg(
                name,
                format!("factor must be finite and ≥ 0, got {}", self.factor),
            ));
        }
        let Some(t) = &self.texture else { return Ok(()) };
        match self.channel {
            Channel::One(k) if usize::from(k) >= t.channels() => Err(RasterError::arg(
                name,
                format!("reads channel {k} of a texture with {} channel(s)", t.channels()),
            )),
            Channel::Rgb if scalar && t.channels() != 1 => Err(RasterError::arg(
                name,
                format!(
                    "is a scalar parameter: it reads one channel of a {}-channel texture; choose it (e.g. \
                     channel 1, green, for glTF's roughness)",
                    t.channels()
                ),
            )),
            _ => Ok(()),
        }
    }
}

/// Where a bound parameter's value comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamSource {
    /// `factor ∘ texel` of one texture (RGB for a colour parameter, one channel for a scalar one).
    Texture(TextureRef),
    /// The square of what one texture gives, `(factor ∘ texel)²`: glTF's perceptual roughness `r` of
    /// the metallic-roughness texture (G) is the microfacet `α = r²` of `cook_torrance`'s `roughness`
    /// (glTF 2.0 appendix B).
    Squared(TextureRef),
    /// glTF 2.0 appendix B's diffuse colour `(1 − metallic)·baseColor` (colour parameters).
    MetallicDiffuse {
        /// The base colour (RGB).
        base_color: TextureRef,
        /// The metalness (one channel, glTF's B of the metallic-roughness texture).
        metallic: TextureRef,
    },
    /// glTF 2.0 appendix B's normal-incidence reflectance `mix(0.04, baseColor, metallic)` (colour
    /// parameters).
    MetallicF0 {
        /// The base colour (RGB).
        base_color: TextureRef,
        /// The metalness (one channel).
        metallic: TextureRef,
    },
}

/// A [`TextureRef`] resolved against the material's list of distinct textures.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Read {
    /// Index into [`MaterialTextures::textures`], or `None` for a constant.
    texture: Option<u16>,
    channel: Channel,
    factor: Vec3,
}

impl Read {
    /// `factor ∘ texel`, from the values of every texture at the sample.
    #[inline(always)]
    fn rgb(&self, texels: &[Vec4]) -> Vec3 {
        let t = match self.texture {
            None => return self.factor,
            Some(i) => texels[i as usize],
        };
        let c = match self.channel {
            Channel::Rgb => t.truncate(),
            Channel::One(k) => Vec3::splat(t[usize::from(k)]),
        };
        self.factor * c
    }

    #[inline(always)]
    fn scalar(&self, texels: &[Vec4]) -> f32 {
        self.rgb(texels).x
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Source {
    Texture(Read),
    Squared(Read),
    MetallicDiffuse(Read, Read),
    MetallicF0(Read, Read),
}

/// One bound parameter: its slot in the model's [`Params`], whether it is a colour, its range, and
/// where its value comes from.
#[derive(Debug, Clone, PartialEq)]
struct Bound {
    name: &'static str,
    slot: usize,
    color: bool,
    min: f32,
    max: f32,
    source: Source,
}

/// The textures of a material (see the module docs): bound parameters of its model, normal,
/// occlusion and emission maps. Built once; read at every shaded sample.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialTextures {
    /// The model's parameters at which the textures are not read (the unbound ones are used as they
    /// are; the bound slots are overwritten per sample).
    params: Params,
    /// Distinct textures (a texture read by several bindings is sampled once per sample).
    textures: Vec<Arc<Texture>>,
    bound: Vec<Bound>,
    normal: Option<(Read, f32)>,
    occlusion: Option<(Read, f32)>,
    emission: Option<Read>,
    /// Alpha test: the texture read for coverage and the cutoff below which a sample is not drawn.
    alpha: Option<AlphaMask>,
}

/// An alpha mask (glTF `alphaMode` `MASK`): a sample whose `factor · texel` is below `cutoff` is not
/// drawn (it neither writes depth nor hides what is behind it).
#[derive(Debug, Clone, PartialEq)]
pub struct AlphaMask {
    texture: Arc<Texture>,
    channel: usize,
    factor: f32,
    cutoff: f32,
}

impl AlphaMask {
    /// Whether the sample at `uv` (changing by `duv_dx`, `duv_dy` per sample column and row: the mip
    /// level, as for shading) is drawn: `factor · texel ≥ cutoff`.
    #[inline]
    pub fn passes(&self, uv: Vec2, duv_dx: Vec2, duv_dy: Vec2) -> bool {
        self.factor * self.texture.sample(uv, duv_dx, duv_dy)[self.channel] >= self.cutoff
    }
}

/// What the textures give at one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexturedPoint {
    /// The tangent-space normal `(x·s, y·s, z)` of the normal map, if there is one.
    pub normal: Option<Vec3>,
    /// Factor on the ambient and indirect terms (1 without an occlusion map).
    pub occlusion: f32,
    /// Factor on the emission (1 without an emission map).
    pub emission: Vec3,
}

impl MaterialTextures {
    /// No textures yet, over the model's parameters `params` (e.g. `Params::resolve(spec, inputs)`).
    pub fn new(params: Params) -> Self {
        Self {
            params,
            textures: Vec::new(),
            bound: Vec::new(),
            normal: None,
            occlusion: None,
            emission: None,
            alpha: None,
        }
    }

    /// The model's parameters (bound slots at their untextured values).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The distinct textures the material reads.
    pub fn textures(&self) -> &[Arc<Texture>] {
        &self.textures
    }

    /// The names of the bound parameters, in binding order.
    pub fn bound_names(&self) -> Vec<&'static str> {
        self.bound.iter().map(|b| b.name).collect()
    }

    /// Whether a normal map is bound (the mesh then needs tangents).
    pub fn has_normal_map(&self) -> bool {
        self.normal.is_some()
    }

    /// Whether anything at all is read from a texture (a constant [`TextureRef`] is not).
    pub fn reads_textures(&self) -> bool {
        !self.textures.is_empty()
    }

    fn resolve(&mut self, r: &TextureRef) -> Result<Read, RasterError> {
        let texture = match &r.texture {
            None => None,
            Some(t) => {
                let i = match self.textures.iter().position(|u| Arc::ptr_eq(u, t)) {
                    Some(i) => i,
                    None => {
                        self.textures.push(t.clone());
                        self.textures.len() - 1
                    }
                };
                Some(u16::try_from(i).map_err(|_| RasterError::arg("textures", "more than 65535 textures"))?)
            }
        };
        Ok(Read { texture, channel: r.channel, factor: r.factor })
    }

    /// Bind parameter `name` of the model to `source`.
    ///
    /// Errors: the model has no parameter `name`, or it is neither a colour nor a scalar; a scalar
    /// bound to several channels, a channel the texture does not have, a negative or non-finite factor;
    /// a metallic source on a scalar parameter.
    pub fn bind(mut self, name: &str, source: ParamSource) -> Result<Self, RasterError> {
        let model = self.params.model();
        let spec = brdf_core::models::spec(model)
            .ok_or_else(|| RasterError::arg("textures", format!("unknown model {model:?}")))?;
        let Some(p) = spec.params.iter().find(|p| p.name == name) else {
            let known = spec.params.iter().map(|p| p.name).collect::<Vec<_>>().join(", ");
            return Err(RasterError::arg(
                "textures",
                format!("{model} has no parameter {name:?} (it has {known})"),
            ));
        };
        let color = match p.kind {
            ParamKind::Color => true,
            ParamKind::Scalar => false,
            _ => {
                return Err(RasterError::arg(
                    p.name,
                    format!(
                        "is a {:?} parameter of {model}: only colour and scalar parameters take a texture",
                        p.kind
                    ),
                ));
            }
        };
        let slot = self.params.index_of(p.name).expect("resolved params hold every parameter of their spec");
        let source = match source {
            ParamSource::Texture(r) => {
                r.check(p.name, !color)?;
                Source::Texture(self.resolve(&r)?)
            }
            ParamSource::Squared(r) => {
                r.check(p.name, !color)?;
                Source::Squared(self.resolve(&r)?)
            }
            ParamSource::MetallicDiffuse { base_color, metallic }
            | ParamSource::MetallicF0 { base_color, metallic }
                if !color =>
            {
                let _ = (base_color, metallic);
                return Err(RasterError::arg(
                    p.name,
                    "is a scalar: a metallic-roughness colour binds to a colour",
                ));
            }
            ParamSource::MetallicDiffuse { base_color, metallic } => {
                base_color.check(p.name, false)?;
                metallic.check(p.name, true)?;
                Source::MetallicDiffuse(self.resolve(&base_color)?, self.resolve(&metallic)?)
            }
            ParamSource::MetallicF0 { base_color, metallic } => {
                base_color.check(p.name, false)?;
                metallic.check(p.name, true)?;
                Source::MetallicF0(self.resolve(&base_color)?, self.resolve(&metallic)?)
            }
        };
        self.bound.retain(|b| b.name != p.name);
        self.bound.push(Bound { name: p.name, slot, color, min: p.min, max: p.max, source });
        Ok(self)
    }

    /// A tangent-space normal map (RGB) with glTF's `scale` on its x and y.
    pub fn with_normal_map(mut self, map: TextureRef, scale: f32) -> Result<Self, RasterError> {
        map.check("normal_map", false)?;
        if !scale.is_finite() {
            return Err(RasterError::arg("normal_map", format!("scale must be finite, got {scale}")));
        }
        self.normal = Some((self.resolve(&map)?, scale));
        Ok(self)
    }

    /// An occlusion map (one channel, glTF's R) with glTF's `strength` in `[0, 1]`.
    pub fn with_occlusion_map(mut self, map: TextureRef, strength: f32) -> Result<Self, RasterError> {
        map.check("occlusion_map", true)?;
        if !(0.0..=1.0).contains(&strength) {
            return Err(RasterError::arg(
                "occlusion_map",
                format!("strength must be in [0, 1], got {strength}"),
            ));
        }
        self.occlusion = Some((self.resolve(&map)?, strength));
        Ok(self)
    }

    /// An emission map (RGB) multiplying the material's emission.
    pub fn with_emission_map(mut self, map: TextureRef) -> Result<Self, RasterError> {
        map.check("emission", false)?;
        self.emission = Some(self.resolve(&map)?);
        Ok(self)
    }

    /// An alpha mask (glTF `MASK`): one channel of `map` (glTF: the base colour's alpha, channel 3, times
    /// `baseColorFactor`'s alpha) against `cutoff` (glTF's `alphaCutoff`, finite and ≥ 0). The mask
    /// decides coverage only: the texture is not read by shading for it.
    pub fn with_alpha_mask(mut self, map: TextureRef, cutoff: f32) -> Result<Self, RasterError> {
        map.check("alpha_mask", true)?;
        if !(cutoff.is_finite() && cutoff >= 0.0) {
            return Err(RasterError::arg("alpha_cutoff", format!("must be finite and ≥ 0, got {cutoff}")));
        }
        let Some(texture) = map.texture else {
            return Err(RasterError::arg("alpha_mask", "needs a texture (a constant alpha is a plain cut)"));
        };
        let channel = match map.channel {
            Channel::One(k) => usize::from(k),
            Channel::Rgb => 0,
        };
        self.alpha = Some(AlphaMask { texture, channel, factor: map.factor.x, cutoff });
        Ok(self)
    }

    /// The alpha mask, if any.
    pub fn alpha_mask(&self) -> Option<&AlphaMask> {
        self.alpha.as_ref()
    }

    /// Whether anything is read at shaded samples (parameters or maps; an alpha mask alone only decides
    /// coverage).
    pub fn shades_textures(&self) -> bool {
        !self.bound.is_empty() || self.normal.is_some() || self.occlusion.is_some() || self.emission.is_some()
    }

    /// Every distinct texture's filtered value at `uv` (see [`Texture::sample`]) into `texels`
    /// (resized to the texture count).
    #[inline]
    pub fn sample_all(&self, uv: Vec2, duv_dx: Vec2, duv_dy: Vec2, texels: &mut Vec<Vec4>) {
        texels.clear();
        texels.extend(self.textures.iter().map(|t| t.sample(uv, duv_dx, duv_dy)));
    }

    /// Write the bound parameters' values at a sample (from [`MaterialTextures::sample_all`]) into
    /// `params` (a copy of [`MaterialTextures::params`]), each clamped into its documented range.
    #[inline]
    pub fn apply(&self, texels: &[Vec4], params: &mut Params) {
        self.each_value(texels, |slot, v| {
            params.set_at(slot, v);
            true
        });
    }

    /// Call `f(slot, value)` with every bound parameter's slot in the model's [`Params`] and its value
    /// at a sample (clamped as [`MaterialTextures::apply`] does), in binding order, until `f` returns
    /// `false`; `false` then, else `true`.
    #[inline]
    pub fn each_value(&self, texels: &[Vec4], mut f: impl FnMut(usize, Value) -> bool) -> bool {
        for b in &self.bound {
            let rgb = match b.source {
                Source::Texture(r) => {
                    if !b.color {
                        if !f(b.slot, Value::Scalar(r.scalar(texels).clamp(b.min, b.max))) {
                            return false;
                        }
                        continue;
                    }
                    r.rgb(texels)
                }
                Source::Squared(r) => {
                    if !b.color {
                        let x = r.scalar(texels);
                        if !f(b.slot, Value::Scalar((x * x).clamp(b.min, b.max))) {
                            return false;
                        }
                        continue;
                    }
                    let c = r.rgb(texels);
                    c * c
                }
                Source::MetallicDiffuse(base, m) => {
                    base.rgb(texels) * (1.0 - m.scalar(texels).clamp(0.0, 1.0))
                }
                Source::MetallicF0(base, m) => {
                    let m = m.scalar(texels).clamp(0.0, 1.0);
                    Vec3::splat(0.04) * (1.0 - m) + base.rgb(texels) * m
                }
            };
            let c = rgb.clamp(Vec3::splat(b.min), Vec3::splat(b.max));
            if !f(b.slot, Value::Color(c.to_array())) {
                return false;
            }
        }
        true
    }

    /// The maps' values at a sample (from [`MaterialTextures::sample_all`]).
    #[inline]
    pub fn maps(&self, texels: &[Vec4]) -> TexturedPoint {
        TexturedPoint {
            normal: self.normal.map(|(r, s)| {
                let t = r.rgb(texels) * 2.0 - Vec3::ONE;
                Vec3::new(t.x * s, t.y * s, t.z)
            }),
            occlusion: self.occlusion.map_or(1.0, |(r, k)| 1.0 + k * (r.scalar(texels) - 1.0)),
            emission: self.emission.map_or(Vec3::ONE, |r| r.rgb(texels)),
        }
    }

    /// The parameters with every bound value at the textures' means (what a model without texture
    /// coordinates, or a material's default ambient reflectance, uses).
    pub fn mean_params(&self) -> Params {
        let means: Vec<Vec4> = self.textures.iter().map(|t| t.mean()).collect();
        let mut p = self.params.clone();
        self.apply(&means, &mut p);
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Filter, Sampler, Wrap};

    fn grey(v: f32) -> Arc<Texture> {
        Arc::new(Texture::new(1, 1, 1, vec![v], Sampler::new(Wrap::Repeat, Filter::Nearest)).unwrap())
    }

    #[test]
    fn bindings_resolve_names_once_and_refuse_what_cannot_be_textured() {
        let params = Params::resolve(brdf_core::models::spec("cook_torrance").unwrap(), &[]).unwrap();
        let rgb = Arc::new(Texture::new(1, 1, 3, vec![0.2, 0.9, 0.4], Sampler::default()).unwrap());
        let mt = MaterialTextures::new(params.clone())
            .bind("kd", ParamSource::Texture(TextureRef::rgb(rgb.clone())))
            .unwrap()
            .bind("roughness", ParamSource::Texture(TextureRef::channel(rgb.clone(), 1)))
            .unwrap();
        assert_eq!(mt.textures().len(), 1, "one texture read by two bindings is sampled once");
        let mut p = params.clone();
        mt.apply(&[Vec4::new(0.2, 0.9, 0.4, 1.0)], &mut p);
        assert_eq!(p.color("kd"), Vec3::new(0.2, 0.9, 0.4));
        assert_eq!(p.scalar("roughness"), 0.9);
        let e = MaterialTextures::new(params.clone())
            .bind("roughness", ParamSource::Texture(TextureRef::rgb(rgb.clone())))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("roughness: is a scalar parameter"), "{e}");
        let e = MaterialTextures::new(params.clone())
            .bind("distribution", ParamSource::Texture(TextureRef::rgb(grey(0.5))))
            .unwrap_err()
            .to_string();
        assert!(e.contains("only colour and scalar"), "{e}");
        let e = MaterialTextures::new(params.clone())
            .bind("albedo", ParamSource::Texture(TextureRef::rgb(grey(0.5))))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no parameter \"albedo\""), "{e}");
        let e = MaterialTextures::new(params)
            .bind("kd", ParamSource::Texture(TextureRef::channel(rgb, 3)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("channel 3 of a texture with 3"), "{e}");
    }

    #[test]
    fn values_are_clamped_into_the_documented_range_and_gltf_metallic_mixes() {
        let params = Params::resolve(brdf_core::models::spec("cook_torrance").unwrap(), &[]).unwrap();
        let base = TextureRef::constant(Vec3::new(1.0, 0.5, 0.25));
        let metal = TextureRef::rgb(grey(0.5));
        let mt = MaterialTextures::new(params.clone())
            .bind("kd", ParamSource::MetallicDiffuse { base_color: base.clone(), metallic: metal.clone() })
            .unwrap()
            .bind("f0", ParamSource::MetallicF0 { base_color: base, metallic: metal })
            .unwrap()
            .bind("ks", ParamSource::Texture(TextureRef::rgb(grey(3.0))))
            .unwrap();
        let p = mt.mean_params();
        assert_eq!(p.color("kd"), Vec3::new(0.5, 0.25, 0.125));
        assert!((p.color("f0") - Vec3::new(0.52, 0.27, 0.145)).abs().max_element() < 1e-6);
        assert_eq!(p.color("ks"), Vec3::ONE, "3 is clamped to ks's range [0, 1]");
        let half = TextureRef::rgb(grey(0.5)).with_factor(Vec3::splat(0.8));
        let mt = MaterialTextures::new(params).bind("roughness", ParamSource::Squared(half)).unwrap();
        let alpha = mt.mean_params().scalar("roughness");
        assert!((alpha - 0.16).abs() < 1e-7, "glTF: alpha = (0.8 * 0.5)^2, got {alpha}");
    }
}
