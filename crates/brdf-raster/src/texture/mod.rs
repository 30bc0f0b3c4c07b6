//! Textures: images of linear texels (1, 3 or 4 channels) with their mip chain, read through a
//! sampler (wrap modes, nearest / bilinear / trilinear filtering) at perspective-correct texture
//! coordinates, and bound to a material's parameters, normals, occlusion and emission
//! ([`binding`]).
//!
//! **Texture coordinates** follow glTF 2.0 (§3.8.4): `(0, 0)` is the top-left corner of the image,
//! `(1, 1)` the bottom-right one, `v` grows downward, and row 0 of the data is the top row of the
//! image. Texel `(i, j)` (column `i`, row `j`) has its centre at `((i + ½)/W, (j + ½)/H)`.
//!
//! **Colour.** Texels are linear values. 8-bit data is decoded by [`ColorSpace`]: sRGB (IEC
//! 61966-2-1, the transfer function of [`brdf_core::tonemap::srgb_decode_f32`]; the default for colour
//! images, as glTF requires for base colour and emissive textures) or linear `x/255` (glTF's
//! metallic-roughness, normal and occlusion textures). 16-bit data is `x/65535` and float data is
//! taken as it is, both linear; the alpha channel is always linear.
//!
//! Files: `image.rs` (texel storage, the box-filtered mip chain), `filter.rs` (nearest, bilinear,
//! trilinear and the level of detail), `sampler.rs` (wrap modes and filters), `binding.rs` (what a
//! material binds to textures), `tangents.rs` (MikkTSpace tangents for normal maps).

pub mod binding;
mod filter;
pub mod image;
pub mod sampler;
pub mod tangents;

use brdf_core::tonemap::srgb_decode_f32;
use glam::Vec4;

use crate::RasterError;
pub use binding::{AlphaMask, Channel, MaterialTextures, ParamSource, TextureRef};
pub use filter::level_of_detail;
pub use image::{Level, MAX_TEXELS, MAX_TEXTURE_SIDE};
pub use sampler::{Filter, Sampler, Wrap};

/// Every texel value finite and ≥ 0, else an error naming the first bad texel and channel.
fn check_texels(width: u32, channels: usize, data: &[f32]) -> Result<(), RasterError> {
    let Some((i, x)) = image::first_bad(data) else { return Ok(()) };
    let texel = i / channels;
    Err(RasterError::arg(
        "texture",
        format!(
            "texel ({}, {}) channel {} is {x}: texels must be finite and ≥ 0",
            texel % width as usize,
            texel / width as usize,
            i % channels
        ),
    ))
}

/// How 8-bit texels encode linear values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorSpace {
    /// sRGB-encoded colour channels (IEC 61966-2-1), decoded to linear; alpha is linear `x/255`.
    #[default]
    Srgb,
    /// Linear `x/255` in every channel.
    Linear,
}

impl ColorSpace {
    /// `"srgb"` or `"linear"`.
    pub fn from_name(name: &str) -> Result<Self, RasterError> {
        match name {
            "srgb" => Ok(Self::Srgb),
            "linear" => Ok(Self::Linear),
            _ => {
                Err(RasterError::arg("colorspace", format!("expected \"srgb\" or \"linear\", got {name:?}")))
            }
        }
    }
}

/// A texture: its mip chain (level 0 the image itself), its channel count and its sampler.
///
/// Invariants (checked by the constructors): 1, 3 or 4 channels; `1 ≤ width, height ≤`
/// [`MAX_TEXTURE_SIDE`], at most [`MAX_TEXELS`] texels; every value finite and ≥ 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    levels: Vec<Level>,
    channels: usize,
    /// How the texture is read.
    pub sampler: Sampler,
    /// The mean of each channel over the image (RGBA as [`Texture::sample`] returns it).
    mean: Vec4,
}

impl Texture {
    /// A texture from linear float texels, row-major from the top row, `channels` values per texel.
    /// The mip chain is built when `sampler.filter` is trilinear.
    ///
    /// Errors ([`RasterError::InvalidArgument`] naming `texture`): a channel count other than 1, 3, 4;
    /// zero size; a side above [`MAX_TEXTURE_SIDE`] or more than [`MAX_TEXELS`] texels; a data length
    /// that is not `width·height·channels`; a NaN, infinite or negative value (the message gives the
    /// texel and channel).
    pub fn new(
        width: u32,
        height: u32,
        channels: usize,
        data: Vec<f32>,
        sampler: Sampler,
    ) -> Result<Self, RasterError> {
        image::validate("texture", width, height, channels, data.len())?;
        check_texels(width, channels, &data)?;
        let base = Level { width, height, data };
        // f64 sums: a 2^26-texel image averages without losing its small values.
        let n = f64::from(width) * f64::from(height);
        let mut sum = [0.0f64; 4];
        for texel in base.data.chunks_exact(channels) {
            for (s, &x) in sum.iter_mut().zip(texel) {
                *s += f64::from(x);
            }
        }
        let m = Vec4::from_array(sum.map(|s| (s / n) as f32));
        let mean = match channels {
            1 => Vec4::new(m.x, m.x, m.x, 1.0),
            3 => m.truncate().extend(1.0),
            _ => m,
        };
        let levels =
            if sampler.filter == Filter::Trilinear { image::mip_chain(base, channels) } else { vec![base] };
        Ok(Self { levels, channels, sampler, mean })
    }

    /// A texture from 8-bit texels, decoded by `colorspace` (alpha always linear).
    pub fn from_u8(
        width: u32,
        height: u32,
        channels: usize,
        data: &[u8],
        colorspace: ColorSpace,
        sampler: Sampler,
    ) -> Result<Self, RasterError> {
        image::validate("texture", width, height, channels, data.len())?;
        let mut table = [0.0f32; 256];
        for (i, t) in table.iter_mut().enumerate() {
            *t = i as f32 / 255.0;
        }
        let mut srgb = table;
        if colorspace == ColorSpace::Srgb {
            for (i, t) in srgb.iter_mut().enumerate() {
                *t = srgb_decode_f32(i as f32 / 255.0);
            }
        }
        let alpha = channels == 4;
        let f = data
            .iter()
            .enumerate()
            .map(|(i, &x)| if alpha && i % 4 == 3 { table[x as usize] } else { srgb[x as usize] })
            .collect();
        Self::new(width, height, channels, f, sampler)
    }

    /// A texture from 16-bit texels, `x/65535`, then decoded by `colorspace` (16-bit images are
    /// normally linear: pass [`ColorSpace::Linear`]).
    pub fn from_u16(
        width: u32,
        height: u32,
        channels: usize,
        data: &[u16],
        colorspace: ColorSpace,
        sampler: Sampler,
    ) -> Result<Self, RasterError> {
        image::validate("texture", width, height, channels, data.len())?;
        let f = data.iter().map(|&x| f32::from(x) / 65535.0).collect();
        Self::from_f32(width, height, channels, f, colorspace, sampler)
    }

    /// A texture from float texels decoded by `colorspace` ([`ColorSpace::Linear`]: as they are,
    /// [`Texture::new`]; [`ColorSpace::Srgb`]: the colour channels through the sRGB decoding, alpha
    /// kept).
    pub fn from_f32(
        width: u32,
        height: u32,
        channels: usize,
        mut data: Vec<f32>,
        colorspace: ColorSpace,
        sampler: Sampler,
    ) -> Result<Self, RasterError> {
        image::validate("texture", width, height, channels, data.len())?;
        // Checked before decoding: the sRGB curve clamps, it would hide a NaN or a negative value.
        check_texels(width, channels, &data)?;
        if colorspace == ColorSpace::Srgb {
            for (i, x) in data.iter_mut().enumerate() {
                if !(channels == 4 && i % 4 == 3) {
                    *x = srgb_decode_f32(*x);
                }
            }
        }
        Self::new(width, height, channels, data, sampler)
    }

    /// A 1×1 texture of one value (a constant; no filtering changes it).
    pub fn constant(value: &[f32]) -> Result<Self, RasterError> {
        Self::new(1, 1, value.len(), value.to_vec(), Sampler::new(Wrap::Repeat, Filter::Nearest))
    }

    /// Width of the image (level 0), in texels.
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    /// Height of the image (level 0), in texels.
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// Values per texel (1, 3 or 4).
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The mip chain, level 0 first (one level unless the filter is trilinear).
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// The mean over the image of each channel, as RGBA in the form [`Texture::sample`] returns.
    pub fn mean(&self) -> Vec4 {
        self.mean
    }

    /// Bytes held by the texels of every level.
    pub fn heap_bytes(&self) -> usize {
        self.levels.iter().map(|l| l.data.len() * 4).sum()
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;

    fn tex(w: u32, h: u32, c: usize, data: Vec<f32>, wrap: Wrap, filter: Filter) -> Texture {
        Texture::new(w, h, c, data, Sampler::new(wrap, filter)).unwrap()
    }

    #[test]
    fn bad_textures_are_refused_naming_the_problem() {
        let s = Sampler::default();
        let e = Texture::new(0, 4, 1, vec![], s).unwrap_err().to_string();
        assert!(e.contains("texture") && e.contains("zero size"), "{e}");
        let e = Texture::new(2, 1, 1, vec![0.5, f32::NAN], s).unwrap_err().to_string();
        assert!(e.contains("texel (1, 0) channel 0 is NaN"), "{e}");
        let e = Texture::new(1, 1, 3, vec![0.5, -1.0, 0.0], s).unwrap_err().to_string();
        assert!(e.contains("channel 1 is -1"), "{e}");
        let e = Texture::new(1, 1, 3, vec![0.5, f32::INFINITY, 0.0], s).unwrap_err().to_string();
        assert!(e.contains("inf"), "{e}");
        let e = Texture::new(1, 1, 2, vec![0.5, 0.5], s).unwrap_err().to_string();
        assert!(e.contains("1, 3 or 4 channels"), "{e}");
        let e = Texture::new(2, 2, 3, vec![0.5; 11], s).unwrap_err().to_string();
        assert!(e.contains("11 values"), "{e}");
        // An absurd size is refused before anything is allocated for it.
        let e = Texture::from_u8(100_000, 100_000, 3, &[], ColorSpace::Srgb, s).unwrap_err().to_string();
        assert!(e.contains("exceed the limit"), "{e}");
    }

    #[test]
    fn eight_bit_texels_decode_srgb_or_linear_and_alpha_stays_linear() {
        let s = Sampler::new(Wrap::Repeat, Filter::Nearest);
        let t = Texture::from_u8(1, 1, 4, &[188, 188, 255, 128], ColorSpace::Srgb, s).unwrap();
        let v = t.sample(Vec2::splat(0.5), Vec2::ZERO, Vec2::ZERO);
        // sRGB 188/255 = 0.7373 → ((0.7373 + 0.055)/1.055)^2.4 = 0.5029.
        assert!((v.x - 0.50289).abs() < 1e-4 && v.z == 1.0 && (v.w - 128.0 / 255.0).abs() < 1e-7, "{v}");
        let t = Texture::from_u8(1, 1, 1, &[188], ColorSpace::Linear, s).unwrap();
        assert_eq!(t.sample(Vec2::ZERO, Vec2::ZERO, Vec2::ZERO).x, 188.0 / 255.0);
        let t = Texture::from_u16(1, 1, 1, &[65535], ColorSpace::Linear, s).unwrap();
        assert_eq!(t.sample(Vec2::ZERO, Vec2::ZERO, Vec2::ZERO), Vec4::ONE);
    }

    #[test]
    fn nearest_and_bilinear_follow_the_gltf_texel_centres() {
        // 2×2 grey: row 0 (top) = 0, 1; row 1 = 2, 3.
        let data = vec![0.0, 1.0, 2.0, 3.0];
        let n = tex(2, 2, 1, data.clone(), Wrap::ClampToEdge, Filter::Nearest);
        let at = |t: &Texture, u: f32, v: f32| t.sample(Vec2::new(u, v), Vec2::ZERO, Vec2::ZERO).x;
        assert_eq!(at(&n, 0.1, 0.1), 0.0);
        assert_eq!(at(&n, 0.9, 0.1), 1.0);
        assert_eq!(at(&n, 0.1, 0.9), 2.0);
        let b = tex(2, 2, 1, data, Wrap::ClampToEdge, Filter::Bilinear);
        // Texel centres give the texels; the image centre the mean.
        assert_eq!(at(&b, 0.25, 0.25), 0.0);
        assert_eq!(at(&b, 0.75, 0.75), 3.0);
        assert_eq!(at(&b, 0.5, 0.5), 1.5);
        // Clamped beyond the edge.
        assert_eq!(at(&b, -3.0, 0.25), 0.0);
    }

    #[test]
    fn trilinear_reads_the_level_its_footprint_asks_for() {
        // A 4×4 checker of 0/1: level 0 alternates, level 1 (2×2) and below are 0.5 everywhere.
        let data: Vec<f32> = (0..16).map(|i| ((i % 4 + i / 4) % 2) as f32).collect();
        let t = tex(4, 4, 1, data, Wrap::Repeat, Filter::Trilinear);
        assert_eq!(t.levels().len(), 3);
        let uv = Vec2::new(0.125, 0.125);
        // One texel per sample: λ = 0, the base level.
        let d = Vec2::new(0.25, 0.0);
        assert_eq!(t.sample(uv, d, d.perp()).x, 0.0);
        // Two texels per sample: λ = 1.
        let d = Vec2::new(0.5, 0.0);
        assert_eq!(t.sample(uv, d, d.perp()).x, 0.5);
        // √2 texels: λ = ½, half way.
        let d = Vec2::new(0.25 * 2f32.sqrt(), 0.0);
        assert!((t.sample(uv, d, d.perp()).x - 0.25).abs() < 1e-6);
        assert_eq!(level_of_detail(4, 4, Vec2::new(0.0, 0.5), Vec2::new(0.25, 0.0)), 1.0);
    }
}
