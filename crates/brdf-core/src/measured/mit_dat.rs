//! The MIT CSAIL anisotropic `.dat` format (the data of A. Ngan, F. Durand, W. Matusik, "Experimental
//! Analysis of BRDF Models", EGSR 2005), as the BRDF Explorer (B. Burley, Disney, 2012:
//! `src/brdf/BRDFMeasuredAniso.cpp`) reads it: reader and writer of [`AnisotropicTabulated`].
//!
//! ## The file
//! A header of 16 little-endian `int32`:
//! - `[0..4]` the bins of `(θ_in, θ_out, φ_diff, φ_in)`;
//! - `[6]` paramType: 1 = the standard parametrisation (the only one defined; 0 is reserved);
//! - `[7]` binType: 0 = uniform bins (the only one defined);
//! - `[9]` half_data: 0 = `φ_diff` over `[0, 2π)`, 1 = over `[0, π)`;
//! - `[10]` num_channels: 3 (RGB);
//! - `[4]`, `[5]`, `[8]`, `[11..16]` reserved (ignored).
//!
//! Then `3 · n_θin · n_θout · n_φdiff · n_φin` little-endian `float32`, channel-planar (every red
//! value, then every green, then every blue), each block with
//! `index = i_φin + n_φin·(i_φdiff + n_φdiff·(i_θout + n_θout·i_θin))`. Negative values mark bins
//! without a measurement. The angles and bins are those of [`super::anisotropic`].
//!
//! ## Scale
//! The values are kept as stored, times `scale` (1 by default). The Explorer's shader multiplies
//! them by 10 for display: pass 10 to see what it shows. The writer divides by `scale`.
//!
//! ## Checks
//! Every header field is checked before anything is allocated: each dimension in
//! `1..=`[`MAX_NODES_PER_AXIS`], at most [`MAX_NODES`] cells, paramType 1, binType 0, half_data 0
//! or 1, num_channels 3, and the file exactly as long as the header says. Values must not be NaN or
//! infinite.

use glam::Vec3;

use super::anisotropic::{AXES, AnisotropicTabulated, check_aniso_dims};
#[cfg(doc)]
use super::{MAX_NODES, MAX_NODES_PER_AXIS};
use crate::BrdfError;

/// Bytes of the header: 16 `int32`.
pub const MIT_HEADER_BYTES: usize = 64;

fn bad(problem: String) -> BrdfError {
    BrdfError::InvalidInput { name: "data", problem }
}

fn check_scale(scale: f32) -> Result<(), BrdfError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(BrdfError::InvalidInput {
            name: "scale",
            problem: format!("must be finite and > 0, got {scale}"),
        });
    }
    Ok(())
}

impl AnisotropicTabulated {
    /// Read a MIT CSAIL `.dat` file from its bytes (module docs), values multiplied by `scale`. A cell
    /// any of whose channels is negative has no data. Errors name `data` and the header field.
    pub fn read_mit(bytes: &[u8], scale: f32) -> Result<Self, BrdfError> {
        check_scale(scale)?;
        if bytes.len() < MIT_HEADER_BYTES {
            return Err(bad(format!(
                "truncated header: {} bytes, a MIT .dat header is {MIT_HEADER_BYTES} (16 int32)",
                bytes.len()
            )));
        }
        let h: Vec<i32> = bytes[..MIT_HEADER_BYTES]
            .chunks_exact(4)
            .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let mut dims = [0usize; 4];
        for (k, d) in dims.iter_mut().enumerate() {
            if h[k] < 1 {
                return Err(bad(format!("header[{k}] (bins of {}) is {}, must be >= 1", AXES[k], h[k])));
            }
            *d = h[k] as usize;
        }
        let cells = check_aniso_dims("data", dims)?;
        if h[6] != 1 {
            return Err(bad(format!(
                "header[6] (paramType) is {}; only 1 (the standard parametrisation) is defined",
                h[6]
            )));
        }
        if h[7] != 0 {
            return Err(bad(format!("header[7] (binType) is {}; only 0 (uniform bins) is defined", h[7])));
        }
        let half_data = match h[9] {
            0 => false,
            1 => true,
            x => {
                return Err(bad(format!(
                    "header[9] (half_data) is {x}; expected 0 (phi_diff over [0, 2pi)) or 1 ([0, pi))"
                )));
            }
        };
        if h[10] != 3 {
            return Err(bad(format!("header[10] (num_channels) is {}; expected 3 (RGB)", h[10])));
        }
        // cells ≤ MAX_NODES (2²⁶): no overflow.
        let expected = MIT_HEADER_BYTES + 3 * 4 * cells;
        if bytes.len() != expected {
            return Err(bad(format!(
                "the header asks for {}x{}x{}x{} bins x 3 channels of float32, {expected} bytes in all; the data are {} bytes ({})",
                dims[0],
                dims[1],
                dims[2],
                dims[3],
                bytes.len(),
                if bytes.len() > expected { "trailing bytes" } else { "truncated" }
            )));
        }
        let body = &bytes[MIT_HEADER_BYTES..];
        let mut data = vec![Vec3::ZERO; cells];
        let mut valid = vec![true; cells];
        for c in 0..3 {
            for (i, (out, ok)) in data.iter_mut().zip(valid.iter_mut()).enumerate() {
                let o = 4 * (c * cells + i);
                let x = f32::from_le_bytes([body[o], body[o + 1], body[o + 2], body[o + 3]]);
                if !x.is_finite() {
                    return Err(bad(format!("value {i} of channel {c} is not finite ({x})")));
                }
                if x < 0.0 {
                    *ok = false;
                }
                let y = x * scale;
                if !y.is_finite() {
                    return Err(bad(format!(
                        "value {i} of channel {c} ({x}) is beyond float32 once multiplied by scale = {scale}"
                    )));
                }
                out[c] = y;
            }
        }
        Self::new(dims, half_data, data, Some(valid))
    }

    /// The table as a MIT CSAIL `.dat` file (module docs): values divided by `scale`, cells without
    /// data written as −1 in every channel; reserved header fields 0.
    pub fn write_mit(&self, scale: f32) -> Result<Vec<u8>, BrdfError> {
        check_scale(scale)?;
        let dims = self.dims();
        let mut header = [0i32; 16];
        for (h, d) in header.iter_mut().zip(dims) {
            // At most 4096 (checked when the table was made).
            *h = d as i32;
        }
        header[6] = 1;
        header[7] = 0;
        header[9] = i32::from(self.half_data());
        header[10] = 3;
        let cells = self.data().len();
        let mut out = Vec::with_capacity(MIT_HEADER_BYTES + 12 * cells);
        for x in header {
            out.extend_from_slice(&x.to_le_bytes());
        }
        for c in 0..3 {
            for (v, &ok) in self.data().iter().zip(self.valid()) {
                let x = if ok { v[c] / scale } else { -1.0 };
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Model;
    use crate::params::Input;

    /// A file built from the published layout, field by field (not through the writer).
    fn by_hand(dims: [i32; 4], half: i32, value: impl Fn(usize, usize) -> f32) -> Vec<u8> {
        let mut h = [0i32; 16];
        h[..4].copy_from_slice(&dims);
        h[6] = 1;
        h[9] = half;
        h[10] = 3;
        h[12] = 77; // reserved: ignored
        let cells = dims.iter().product::<i32>() as usize;
        let mut b: Vec<u8> = h.iter().flat_map(|x| x.to_le_bytes()).collect();
        for c in 0..3 {
            for i in 0..cells {
                b.extend_from_slice(&value(c, i).to_le_bytes());
            }
        }
        b
    }

    #[test]
    fn a_file_built_by_hand_reads_to_its_values_at_its_bins() {
        let dims = [3, 4, 6, 8];
        let val = |c: usize, i: usize| (c * 1000 + i) as f32 * 1e-3;
        let bytes = by_hand(dims, 0, |c, i| if i == 5 { -2.0 } else { val(c, i) });
        let t = AnisotropicTabulated::read_mit(&bytes, 1.0).unwrap();
        assert_eq!(t.dims(), [3, 4, 6, 8]);
        assert!(!t.half_data());
        // Bin (1, 2, 3, 4): index 4 + 8·(3 + 6·(2 + 4·1)) = 316.
        let i = t.index([1, 2, 3, 4]);
        assert_eq!(i, 316);
        assert_eq!(t.data()[i], Vec3::new(val(0, 316), val(1, 316), val(2, 316)));
        assert!(!t.valid()[5] && t.data()[5] == Vec3::ZERO);
        let t10 = AnisotropicTabulated::read_mit(&bytes, 10.0).unwrap();
        assert_eq!(t10.data()[i], Vec3::new(val(0, 316), val(1, 316), val(2, 316)) * 10.0);
    }

    #[test]
    fn the_writer_round_trips_bit_for_bit() {
        let ward = Model::build(
            "ward",
            &[("alpha_x".into(), Input::Number(0.2)), ("alpha_y".into(), Input::Number(0.4))],
        )
        .unwrap();
        let t = AnisotropicTabulated::from_model(&ward, [4, 3, 8, 6], true).unwrap();
        let bytes = t.write_mit(1.0).unwrap();
        assert_eq!(bytes.len(), 64 + 12 * 4 * 3 * 8 * 6);
        let back = AnisotropicTabulated::read_mit(&bytes, 1.0).unwrap();
        assert_eq!(back, t);
        assert_eq!(back.write_mit(1.0).unwrap(), bytes);
        // A hand-made file with holes round-trips too (holes are written as −1).
        let mut hand = by_hand([2, 2, 2, 2], 1, |c, i| if i % 5 == 0 { -1.0 } else { (c + i) as f32 });
        // The writer writes the reserved fields as 0.
        hand[48..52].fill(0);
        let t = AnisotropicTabulated::read_mit(&hand, 1.0).unwrap();
        assert!(t.half_data());
        assert_eq!(t.write_mit(1.0).unwrap(), hand);
    }

    #[test]
    fn corrupt_headers_and_wrong_lengths_are_refused_naming_the_field() {
        let good = by_hand([2, 2, 2, 2], 0, |_, _| 0.5);
        let err = |b: &[u8]| AnisotropicTabulated::read_mit(b, 1.0).unwrap_err().to_string();
        assert!(err(&good[..10]).contains("truncated header"), "{}", err(&good[..10]));
        assert!(err(&good[..good.len() - 1]).contains("truncated"));
        let mut longer = good.clone();
        longer.push(0);
        assert!(err(&longer).contains("trailing"));
        let set = |k: usize, x: i32| {
            let mut b = good.clone();
            b[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
            b
        };
        for (k, x, what) in [
            (0, 0, "header[0] (bins of theta_in)"),
            (3, -5, "header[3] (bins of phi_in)"),
            (6, 0, "paramType"),
            (7, 1, "binType"),
            (9, 2, "half_data"),
            (10, 1, "num_channels"),
        ] {
            let e = err(&set(k, x));
            assert!(e.starts_with("data") && e.contains(what), "{e}");
        }
        // Absurd dimensions are refused before any allocation.
        let e = err(&set(1, i32::MAX));
        assert!(e.contains("theta_out") && e.contains("4096"), "{e}");
        let mut huge = good.clone();
        for k in 0..4 {
            huge[4 * k..4 * k + 4].copy_from_slice(&4000i32.to_le_bytes());
        }
        assert!(err(&huge).contains("exceed"));
        let mut nan = good.clone();
        nan[64 + 4 * 7..64 + 4 * 8].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(err(&nan).contains("value 7 of channel 0"));
        let e = AnisotropicTabulated::read_mit(&good, 0.0).unwrap_err().to_string();
        assert!(e.starts_with("scale"), "{e}");
    }
}
