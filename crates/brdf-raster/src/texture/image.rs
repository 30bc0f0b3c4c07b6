//! Texel storage and the mip chain: linear float texels, 1, 3 or 4 channels, row 0 at the top of the
//! image, and the box-filtered pyramid of half-size levels under it.

use glam::Vec4;

use crate::RasterError;

/// Largest width or height of a texture, in texels (glTF and GPUs stop at 16384 too).
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Largest texel count of a texture's first level (`width·height`; 2²⁶ texels = 1 GiB of RGBA f32).
pub const MAX_TEXELS: u64 = 1 << 26;

/// One level of a texture: `width × height` texels of `channels` linear floats, row-major, row 0 at the
/// top of the image (the row `v ∈ [0, 1/height)` reads).
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width·height·channels` values.
    pub data: Vec<f32>,
}

impl Level {
    /// Texel `(x, y)` (column, row; in range) of a `channels`-channel level as RGBA: one channel is
    /// grey `(c, c, c, 1)`, three get `a = 1`.
    #[inline(always)]
    pub fn texel(&self, channels: usize, x: u32, y: u32) -> Vec4 {
        let i = (y as usize * self.width as usize + x as usize) * channels;
        match channels {
            1 => {
                let c = self.data[i];
                Vec4::new(c, c, c, 1.0)
            }
            3 => Vec4::new(self.data[i], self.data[i + 1], self.data[i + 2], 1.0),
            _ => Vec4::from_slice(&self.data[i..i + 4]),
        }
    }
}

/// Check a texture's size and texels (every value finite and ≥ 0), naming the argument `name`.
pub(super) fn validate(
    name: &'static str,
    width: u32,
    height: u32,
    channels: usize,
    len: usize,
) -> Result<(), RasterError> {
    if !matches!(channels, 1 | 3 | 4) {
        return Err(RasterError::arg(name, format!("must have 1, 3 or 4 channels, got {channels}")));
    }
    if width == 0 || height == 0 {
        return Err(RasterError::arg(name, format!("has zero size ({width}×{height})")));
    }
    if width > MAX_TEXTURE_SIDE
        || height > MAX_TEXTURE_SIDE
        || u64::from(width) * u64::from(height) > MAX_TEXELS
    {
        return Err(RasterError::arg(
            name,
            format!(
                "{width}×{height} texels exceed the limit ({MAX_TEXTURE_SIDE} per side, {MAX_TEXELS} in all)"
            ),
        ));
    }
    let want = width as usize * height as usize * channels;
    if len != want {
        return Err(RasterError::arg(
            name,
            format!("{len} values for {width}×{height} texels of {channels} channels (expected {want})"),
        ));
    }
    Ok(())
}

/// The index and the value of the first texel value that is not finite or is negative.
pub(super) fn first_bad(data: &[f32]) -> Option<(usize, f32)> {
    data.iter().position(|x| !(x.is_finite() && *x >= 0.0)).map(|i| (i, data[i]))
}

/// Box-filter weights from `n` source texels to `m = max(1, ⌊n/2⌋)`: output texel `i` covers
/// `[i·n/m, (i+1)·n/m)` of the source, and each source texel weighs by its overlap with that
/// interval over the interval's length (an exact area average, also for odd `n`). Returns, per output
/// texel, `(first source texel, weights)`.
fn box_weights(n: u32) -> Vec<(u32, Vec<f32>)> {
    let m = (n / 2).max(1);
    let scale = f64::from(n) / f64::from(m);
    (0..m)
        .map(|i| {
            let (lo, hi) = (f64::from(i) * scale, f64::from(i + 1) * scale);
            let first = lo.floor() as u32;
            let last = (hi.ceil() as u32).min(n);
            let w = (first..last)
                .map(|k| {
                    let overlap = (f64::from(k + 1)).min(hi) - f64::from(k).max(lo);
                    (overlap / scale) as f32
                })
                .collect();
            (first, w)
        })
        .collect()
}

/// The next, half-size level of `level` (`max(1, ⌊w/2⌋) × max(1, ⌊h/2⌋)`), each texel the area
/// average of the source texels under it ([`box_weights`], separable: rows, then columns).
pub(super) fn downsample(level: &Level, channels: usize) -> Level {
    let (w, h) = (level.width, level.height);
    let (wx, wy) = (box_weights(w), box_weights(h));
    let (nw, nh) = (wx.len() as u32, wy.len() as u32);
    // Horizontal pass: h rows of nw texels.
    let mut tmp = vec![0.0f32; h as usize * nw as usize * channels];
    for y in 0..h as usize {
        let src = &level.data[y * w as usize * channels..(y + 1) * w as usize * channels];
        for (i, (first, ws)) in wx.iter().enumerate() {
            let out = &mut tmp[(y * nw as usize + i) * channels..][..channels];
            for (k, &wk) in ws.iter().enumerate() {
                let s = &src[(*first as usize + k) * channels..][..channels];
                for (o, &v) in out.iter_mut().zip(s) {
                    *o += wk * v;
                }
            }
        }
    }
    // Vertical pass.
    let row = nw as usize * channels;
    let mut data = vec![0.0f32; nh as usize * row];
    for (j, (first, ws)) in wy.iter().enumerate() {
        let out = &mut data[j * row..(j + 1) * row];
        for (k, &wk) in ws.iter().enumerate() {
            let s = &tmp[(*first as usize + k) * row..][..row];
            for (o, &v) in out.iter_mut().zip(s) {
                *o += wk * v;
            }
        }
    }
    Level { width: nw, height: nh, data }
}

/// The whole chain from `base` down to 1×1 (`1 + ⌊log2 max(w, h)⌋` levels).
pub(super) fn mip_chain(base: Level, channels: usize) -> Vec<Level> {
    let mut levels = vec![base];
    loop {
        let last = levels.last().expect("the chain starts with its base");
        if last.width == 1 && last.height == 1 {
            return levels;
        }
        let next = downsample(last, channels);
        levels.push(next);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_weights_are_an_area_average_also_for_odd_sizes() {
        // 4 → 2: pairs.
        assert_eq!(box_weights(4), vec![(0, vec![0.5, 0.5]), (2, vec![0.5, 0.5])]);
        // 5 → 2: texel 2 is split between both outputs; every output's weights sum to 1.
        let w = box_weights(5);
        assert_eq!(w.len(), 2);
        assert_eq!(w[0].0, 0);
        assert!((w[0].1[0] - 0.4).abs() < 1e-6 && (w[0].1[2] - 0.2).abs() < 1e-6, "{w:?}");
        for (_, ws) in &w {
            assert!((ws.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        }
        assert_eq!(box_weights(1), vec![(0, vec![1.0])]);
    }

    #[test]
    fn the_chain_preserves_the_mean_and_ends_at_one_texel() {
        let (w, h) = (7u32, 3u32);
        let data: Vec<f32> = (0..w * h).map(|i| (i * 37 % 11) as f32).collect();
        let mean = data.iter().sum::<f32>() / data.len() as f32;
        let chain = mip_chain(Level { width: w, height: h, data }, 1);
        assert_eq!(
            chain.iter().map(|l| (l.width, l.height)).collect::<Vec<_>>(),
            vec![(7, 3), (3, 1), (1, 1)]
        );
        for l in &chain {
            let m = l.data.iter().sum::<f32>() / l.data.len() as f32;
            assert!((m - mean).abs() < 1e-4, "{} vs {mean}", m);
        }
    }
}
