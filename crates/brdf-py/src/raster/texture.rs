//! Textures from Python: `RasterTexture` (an image of linear texels with its mip chain and sampler,
//! built from a NumPy array) and the per-instance texture bindings `render_scene` receives.

use std::sync::Arc;

use brdf_raster::texture::{
    Channel, ColorSpace, Filter, MaterialTextures, ParamSource, Sampler, Texture, TextureRef, Wrap,
};
use glam::{Vec2, Vec3};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use super::raster_err;
use crate::errors::invalid;

/// A texture: linear texels (1, 3 or 4 channels) with their mip chain, a wrap mode and a filter
/// (`brdf_raster::texture::Texture`). Texture coordinates follow glTF: `(0, 0)` is the top-left corner
/// of the image, `v` grows downward.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterTexture {
    pub(crate) inner: Arc<Texture>,
}

/// `(height, width, channels)` of a `(H, W)` or `(H, W, C)` array.
fn dims(shape: &[usize]) -> PyResult<(u32, u32, usize)> {
    let (h, w, c) = match shape {
        [h, w] => (*h, *w, 1),
        [h, w, c] => (*h, *w, *c),
        _ => {
            return Err(invalid(format!(
                "data: expected an array of shape (H, W), (H, W, 3) or (H, W, 4), got {} dimensions",
                shape.len()
            )));
        }
    };
    let side = |n: usize, what: &str| {
        u32::try_from(n).map_err(|_| invalid(format!("data: {what} {n} exceeds the texture limit")))
    };
    Ok((side(h, "height")?, side(w, "width")?, c))
}

fn wrap_name(w: Wrap) -> &'static str {
    match w {
        Wrap::Repeat => "repeat",
        Wrap::ClampToEdge => "clamp",
        Wrap::MirroredRepeat => "mirror",
    }
}

#[pymethods]
impl RasterTexture {
    /// From a C-contiguous array `data` of float32 (linear), uint8 (sRGB-decoded unless `colorspace`
    /// is "linear") or uint16 (linear unless `colorspace` is "srgb"), shape (H, W), (H, W, 3) or
    /// (H, W, 4), row 0 the top of the image. `wrap`: "repeat", "clamp" or "mirror"; `filter`:
    /// "nearest", "bilinear" or "trilinear". `wrap_v`: the wrap mode along `v` (rows, glTF's
    /// `wrapT`) when it differs from `wrap` (along `u`).
    #[new]
    #[pyo3(signature = (data, wrap="repeat", filter="trilinear", colorspace=None, wrap_v=None))]
    fn new(
        py: Python<'_>,
        data: &Bound<'_, PyAny>,
        wrap: &str,
        filter: &str,
        colorspace: Option<&str>,
        wrap_v: Option<&str>,
    ) -> PyResult<Self> {
        let mut sampler = Sampler::new(
            Wrap::from_name(wrap).map_err(raster_err)?,
            Filter::from_name(filter).map_err(raster_err)?,
        );
        if let Some(v) = wrap_v {
            sampler.wrap_v = Wrap::from_name(v).map_err(raster_err)?;
        }
        let cs = colorspace.map(ColorSpace::from_name).transpose().map_err(raster_err)?;
        let contiguous = |ok: bool| {
            if ok { Ok(()) } else { Err(PyTypeError::new_err("data: expected a C-contiguous array")) }
        };
        let texture = if let Ok(a) = data.extract::<PyReadonlyArrayDyn<'_, f32>>() {
            let (h, w, c) = dims(a.shape())?;
            contiguous(a.is_c_contiguous())?;
            let v = a.as_slice()?.to_vec();
            py.detach(|| Texture::from_f32(w, h, c, v, cs.unwrap_or(ColorSpace::Linear), sampler))
        } else if let Ok(a) = data.extract::<PyReadonlyArrayDyn<'_, u8>>() {
            let (h, w, c) = dims(a.shape())?;
            contiguous(a.is_c_contiguous())?;
            let v = a.as_slice()?;
            py.detach(|| Texture::from_u8(w, h, c, v, cs.unwrap_or(ColorSpace::Srgb), sampler))
        } else if let Ok(a) = data.extract::<PyReadonlyArrayDyn<'_, u16>>() {
            let (h, w, c) = dims(a.shape())?;
            contiguous(a.is_c_contiguous())?;
            let v = a.as_slice()?;
            py.detach(|| Texture::from_u16(w, h, c, v, cs.unwrap_or(ColorSpace::Linear), sampler))
        } else {
            return Err(PyTypeError::new_err(format!(
                "data: expected a NumPy array of float32, uint8 or uint16, got {}",
                data.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into())
            )));
        };
        Ok(Self { inner: Arc::new(texture.map_err(raster_err)?) })
    }

    #[getter]
    fn width(&self) -> u32 {
        self.inner.width()
    }
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height()
    }
    #[getter]
    fn channels(&self) -> usize {
        self.inner.channels()
    }
    /// The wrap mode along `u` (columns): "repeat", "clamp" or "mirror".
    #[getter]
    fn wrap(&self) -> &'static str {
        wrap_name(self.inner.sampler.wrap_u)
    }
    /// The wrap mode along `v` (rows).
    #[getter]
    fn wrap_v(&self) -> &'static str {
        wrap_name(self.inner.sampler.wrap_v)
    }
    /// "nearest", "bilinear" or "trilinear".
    #[getter]
    fn filter(&self) -> &'static str {
        match self.inner.sampler.filter {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::Trilinear => "trilinear",
        }
    }
    /// Mean of each channel as RGBA (1 channel → grey, alpha 1 without one).
    #[getter]
    fn mean(&self) -> [f32; 4] {
        self.inner.mean().to_array()
    }
    /// Every mip level (level 0 the image), float32 (h, w, channels).
    fn levels<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, numpy::PyArray3<f32>>>> {
        let c = self.inner.channels();
        self.inner
            .levels()
            .iter()
            .map(|l| PyArray1::from_slice(py, &l.data).reshape([l.height as usize, l.width as usize, c]))
            .collect()
    }
    /// The filtered RGBA at float32 (N, 2) texture coordinates `uv`, with their change per sample
    /// column `duv_dx` and row `duv_dy` (float32 (N, 2) each, for the mip level); float32 (N, 4).
    fn sample<'py>(
        &self,
        py: Python<'py>,
        uv: PyReadonlyArrayDyn<'py, f32>,
        duv_dx: PyReadonlyArrayDyn<'py, f32>,
        duv_dy: PyReadonlyArrayDyn<'py, f32>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
        let rows = |name: &str, a: &PyReadonlyArrayDyn<'py, f32>| -> PyResult<Vec<Vec2>> {
            if a.ndim() != 2 || a.shape()[1] != 2 || !a.is_c_contiguous() {
                return Err(invalid(format!(
                    "{name}: expected a C-contiguous float32 array of shape (N, 2)"
                )));
            }
            let v: Vec<Vec2> = a.as_slice()?.chunks_exact(2).map(Vec2::from_slice).collect();
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(invalid(format!("{name}: row {i} is not finite")));
            }
            Ok(v)
        };
        let (uv, dx, dy) = (rows("uv", &uv)?, rows("duv_dx", &duv_dx)?, rows("duv_dy", &duv_dy)?);
        if dx.len() != uv.len() || dy.len() != uv.len() {
            return Err(invalid(format!(
                "duv_dx, duv_dy: {} and {} rows for {} texture coordinates",
                dx.len(),
                dy.len(),
                uv.len()
            )));
        }
        let t = &self.inner;
        let out: Vec<f32> = py.detach(|| {
            uv.iter().zip(&dx).zip(&dy).flat_map(|((&u, &x), &y)| t.sample(u, x, y).to_array()).collect()
        });
        PyArray1::from_vec(py, out).reshape([uv.len(), 4])
    }

    fn __repr__(&self) -> String {
        format!(
            "brdfpy.Texture({}×{}, {} channel(s), wrap={:?}, filter={:?})",
            self.inner.width(),
            self.inner.height(),
            self.inner.channels(),
            self.wrap(),
            self.filter()
        )
    }
}

/// One read of a texture as Python passes it: the texture and the channel (`None`: RGB).
pub type TextureReadArgs<'py> = (PyRef<'py, RasterTexture>, Option<u8>);

/// One read of a bound parameter's source: the texture (`None`: the constant `factor`), the channel
/// (`None`: RGB) and the factor multiplying what is read.
pub type SourceReadArgs<'py> = (Option<PyRef<'py, RasterTexture>>, Option<u8>, [f32; 3]);

/// A bound parameter as Python passes it: `(name, kind, reads)`, `kind` one of "texture" and "squared"
/// (one read) or "metallic_diffuse" and "metallic_f0" (two: the base colour, then the metalness), the
/// core's [`ParamSource`] variants.
pub type BoundParamArgs<'py> = (String, String, Vec<SourceReadArgs<'py>>);

/// An instance's textures as Python passes them: `(params, normal_map, normal_scale, occlusion_map,
/// occlusion_strength, emission_map, alpha_mask)`, `params` the bound parameters, `alpha_mask` a read
/// of one channel and the cutoff.
pub type InstanceTextureArgs<'py> = (
    Vec<BoundParamArgs<'py>>,
    Option<TextureReadArgs<'py>>,
    f32,
    Option<TextureReadArgs<'py>>,
    f32,
    Option<TextureReadArgs<'py>>,
    Option<(SourceReadArgs<'py>, f32)>,
);

fn read(t: &RasterTexture, channel: Option<u8>) -> TextureRef {
    let r = TextureRef::rgb(Arc::clone(&t.inner));
    match channel {
        None => r,
        Some(k) => TextureRef { channel: Channel::One(k), ..r },
    }
}

fn source_read((t, channel, factor): &SourceReadArgs<'_>) -> TextureRef {
    let factor = Vec3::from_array(*factor);
    match t {
        Some(t) => read(t, *channel).with_factor(factor),
        None => TextureRef::constant(factor),
    }
}

/// The core's [`ParamSource`] of a bound parameter `(name, kind, reads)`.
fn param_source((name, kind, reads): &BoundParamArgs<'_>) -> PyResult<ParamSource> {
    let want = match kind.as_str() {
        "texture" | "squared" => 1,
        "metallic_diffuse" | "metallic_f0" => 2,
        _ => {
            return Err(invalid(format!(
                "{name}: unknown texture source {kind:?} (expected texture, squared, metallic_diffuse or \
                 metallic_f0)"
            )));
        }
    };
    if reads.len() != want {
        return Err(invalid(format!("{name}: a {kind} source reads {want} texture(s), got {}", reads.len())));
    }
    let r = |i: usize| source_read(&reads[i]);
    Ok(match kind.as_str() {
        "texture" => ParamSource::Texture(r(0)),
        "squared" => ParamSource::Squared(r(0)),
        "metallic_diffuse" => ParamSource::MetallicDiffuse { base_color: r(0), metallic: r(1) },
        _ => ParamSource::MetallicF0 { base_color: r(0), metallic: r(1) },
    })
}

/// The core's [`MaterialTextures`] over `params` (the model's, at the textures' means) from what
/// Python passed.
pub fn material_textures(
    params: &brdf_core::params::Params,
    args: &InstanceTextureArgs<'_>,
) -> PyResult<MaterialTextures> {
    let (bound, normal, scale, occlusion, strength, emission, alpha) = args;
    let mut mt = MaterialTextures::new(params.clone());
    for b in bound {
        mt = mt.bind(&b.0, param_source(b)?).map_err(raster_err)?;
    }
    if let Some((t, c)) = normal {
        mt = mt.with_normal_map(read(t, *c), *scale).map_err(raster_err)?;
    }
    if let Some((t, c)) = occlusion {
        mt = mt.with_occlusion_map(read(t, c.or(Some(0))), *strength).map_err(raster_err)?;
    }
    if let Some((t, c)) = emission {
        mt = mt.with_emission_map(read(t, *c).with_factor(Vec3::ONE)).map_err(raster_err)?;
    }
    if let Some((r, cutoff)) = alpha {
        mt = mt.with_alpha_mask(source_read(r), *cutoff).map_err(raster_err)?;
    }
    Ok(mt)
}
