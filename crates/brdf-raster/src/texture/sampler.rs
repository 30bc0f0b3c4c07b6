//! How texture coordinates outside `[0, 1)` map to texels (glTF 2.0's three wrap modes, §5.26
//! "sampler"; the same as OpenGL 4.6 §8.14.2) and which filter reads them.

use crate::RasterError;

/// What happens to a texel index outside `0..n` (glTF's `wrapS` / `wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    /// The image tiles: index `i mod n` (glTF `REPEAT`, 10497; the default).
    #[default]
    Repeat,
    /// The edge texel repeats outward: `clamp(i, 0, n − 1)` (glTF `CLAMP_TO_EDGE`, 33071).
    ClampToEdge,
    /// The image tiles with every other copy mirrored: `k = i mod 2n`, then `k` or `2n − 1 − k`
    /// (glTF `MIRRORED_REPEAT`, 33648).
    MirroredRepeat,
}

impl Wrap {
    /// Every name [`Wrap::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["repeat", "clamp", "mirror"];

    /// `"repeat"`, `"clamp"` (to edge) or `"mirror"` (mirrored repeat).
    pub fn from_name(name: &str) -> Result<Self, RasterError> {
        match name {
            "repeat" => Ok(Self::Repeat),
            "clamp" | "clamp_to_edge" => Ok(Self::ClampToEdge),
            "mirror" | "mirrored_repeat" => Ok(Self::MirroredRepeat),
            _ => {
                Err(RasterError::arg("wrap", format!("expected one of repeat, clamp, mirror, got {name:?}")))
            }
        }
    }

    /// `u` moved by whole periods of the wrap (1 for repeat, 2 for mirror; exact in f64) into
    /// `[0, period)`, so that the texel indices of a filter footprint fall in or next to `0..n` and
    /// [`Wrap::index`] takes its branch-only path instead of an integer division; clamp keeps `u`.
    #[inline(always)]
    pub fn reduce(self, u: f64) -> f64 {
        match self {
            Self::Repeat => u - u.floor(),
            Self::MirroredRepeat => u - 2.0 * (0.5 * u).floor(),
            Self::ClampToEdge => u,
        }
    }

    /// The texel index in `0..n` that index `i` reads.
    #[inline(always)]
    pub fn index(self, i: i64, n: u32) -> u32 {
        if (0..i64::from(n)).contains(&i) {
            return i as u32;
        }
        let n = i64::from(n);
        // Within one period of `0..n` (what a reduced coordinate's footprint reaches) without a division.
        let near = (-n..2 * n).contains(&i);
        (match self {
            Self::Repeat if near => {
                if i < 0 {
                    i + n
                } else {
                    i - n
                }
            }
            Self::Repeat => i.rem_euclid(n),
            Self::ClampToEdge => i.clamp(0, n - 1),
            Self::MirroredRepeat if near => {
                if i < 0 {
                    -i - 1
                } else {
                    2 * n - 1 - i
                }
            }
            Self::MirroredRepeat => {
                let k = i.rem_euclid(2 * n);
                if k >= n { 2 * n - 1 - k } else { k }
            }
        }) as u32
    }
}

/// How a texture is read between and across texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filter {
    /// The texel whose square holds the point, of the full-resolution image (no mip-mapping).
    Nearest,
    /// Bilinear interpolation of the four nearest texel centres of the full-resolution image.
    Bilinear,
    /// Mip-mapped: bilinear in the two levels around the level of detail λ, linearly blended
    /// (OpenGL's `LINEAR_MIPMAP_LINEAR`; Williams 1983, "Pyramidal Parametrics"); the default.
    #[default]
    Trilinear,
}

impl Filter {
    /// Every name [`Filter::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["nearest", "bilinear", "trilinear"];

    /// `"nearest"`, `"bilinear"` or `"trilinear"`.
    pub fn from_name(name: &str) -> Result<Self, RasterError> {
        match name {
            "nearest" => Ok(Self::Nearest),
            "bilinear" | "linear" => Ok(Self::Bilinear),
            "trilinear" => Ok(Self::Trilinear),
            _ => Err(RasterError::arg(
                "filter",
                format!("expected one of nearest, bilinear, trilinear, got {name:?}"),
            )),
        }
    }
}

/// A texture's sampler state: wrap modes along `u` and `v` and the filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Sampler {
    /// Wrap along `u` (columns; glTF `wrapS`).
    pub wrap_u: Wrap,
    /// Wrap along `v` (rows; glTF `wrapT`).
    pub wrap_v: Wrap,
    /// Filter.
    pub filter: Filter,
}

impl Sampler {
    /// The same wrap mode along both axes.
    pub fn new(wrap: Wrap, filter: Filter) -> Self {
        Self { wrap_u: wrap, wrap_v: wrap, filter }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes_follow_the_gl_definitions() {
        let idx = |w: Wrap| (-5..9).map(|i| w.index(i, 3)).collect::<Vec<_>>();
        assert_eq!(idx(Wrap::Repeat), vec![1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2]);
        assert_eq!(idx(Wrap::ClampToEdge), vec![0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2, 2]);
        // Period 6 from index 0: 0 1 2 2 1 0 | 0 1 2 ...; index −1 reads 0 (mirrored about the edge).
        assert_eq!(idx(Wrap::MirroredRepeat), vec![1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1, 2]);
    }

    #[test]
    fn reducing_by_whole_periods_reads_the_same_texels() {
        for w in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
            for k in -400..400 {
                let u = f64::from(k) * 0.0173 + 0.001;
                for n in [1u32, 3, 8] {
                    let (a, b) =
                        ((u * f64::from(n)).floor() as i64, (w.reduce(u) * f64::from(n)).floor() as i64);
                    assert_eq!(w.index(a, n), w.index(b, n), "{w:?} u={u} n={n}");
                    assert_eq!(w.index(a - 1, n), w.index(b - 1, n), "{w:?} u={u} n={n}: the left neighbour");
                }
            }
        }
    }
}
