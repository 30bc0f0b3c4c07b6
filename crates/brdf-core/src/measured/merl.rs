//! The MERL `.binary` file format (Matusik, Pfister, Brand, McMillan 2003, "A Data-Driven Reflectance
//! Model"; the database's `BRDFRead.cpp`): reader and writer of [`Tabulated`].

use std::io::{Read, Write};

use glam::Vec3;

use super::{MAX_NODES, MAX_NODES_PER_AXIS, Tabulated};
use crate::BrdfError;

/// MERL's channel scale factors (`BRDFRead.cpp`: `RED_SCALE = 1.0/1500`, `GREEN_SCALE = 1.15/1500`,
/// `BLUE_SCALE = 1.66/1500`): the file stores `f_r / scale` per channel.
pub const MERL_SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];

impl Tabulated {
    /// Read a MERL `.binary` file: three little-endian `int32` dimensions `(n_th, n_td, n_pd)`, then
    /// `n_th·n_td·n_pd` little-endian `f64` per channel, red block, green block, blue block, each value
    /// `f_r / MERL_SCALE[c]`. Negative values (MERL's marker for unmeasured configurations) become 0.
    pub fn read_merl(mut r: impl Read) -> Result<Self, BrdfError> {
        let bad = |problem: String| BrdfError::InvalidInput { name: "merl", problem };
        let mut header = [0u8; 12];
        r.read_exact(&mut header).map_err(|e| bad(format!("cannot read the 12-byte header: {e}")))?;
        let mut dims = [0usize; 3];
        for (c, d) in dims.iter_mut().enumerate() {
            let x =
                i32::from_le_bytes([header[4 * c], header[4 * c + 1], header[4 * c + 2], header[4 * c + 3]]);
            if !(2..=MAX_NODES_PER_AXIS as i32).contains(&x) {
                return Err(bad(format!(
                    "dimension {c} in the header is {x}, expected 2..={MAX_NODES_PER_AXIS}"
                )));
            }
            *d = x as usize;
        }
        let count = dims[0] * dims[1] * dims[2];
        if count > MAX_NODES {
            return Err(bad(format!(
                "the header asks for {}x{}x{} = {count} nodes, more than the limit of {MAX_NODES}",
                dims[0], dims[1], dims[2]
            )));
        }
        let expected = 3 * count * 8;
        // Read what is there (at most one byte more than the header asks for) instead of allocating
        // what the header asks for: 12 corrupt bytes could otherwise claim gigabytes.
        let mut bytes = Vec::new();
        r.take(expected as u64 + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| bad(format!("cannot read the data: {e}")))?;
        if bytes.len() != expected {
            return Err(bad(format!(
                "expected {expected} bytes of data for {}x{}x{} samples x 3 channels, {}",
                dims[0],
                dims[1],
                dims[2],
                if bytes.len() > expected {
                    "found more (trailing bytes after the data)".to_string()
                } else {
                    format!("found {}", bytes.len())
                }
            )));
        }
        let mut data = vec![Vec3::ZERO; count];
        for c in 0..3 {
            for (i, out) in data.iter_mut().enumerate() {
                let o = (c * count + i) * 8;
                let mut b = [0u8; 8];
                b.copy_from_slice(&bytes[o..o + 8]);
                let x = f64::from_le_bytes(b);
                if !x.is_finite() {
                    return Err(bad(format!("value {i} of channel {c} is not finite ({x})")));
                }
                let v = (x * MERL_SCALE[c]).max(0.0) as f32;
                if !v.is_finite() {
                    return Err(bad(format!(
                        "value {i} of channel {c} ({x}) is beyond float32 once scaled by {}",
                        MERL_SCALE[c]
                    )));
                }
                out[c] = v;
            }
        }
        Self::new((dims[0], dims[1], dims[2]), data)
    }

    /// Write the table in the MERL `.binary` layout (see [`Tabulated::read_merl`]).
    pub fn write_merl(&self, mut w: impl Write) -> Result<(), BrdfError> {
        let io = |e: std::io::Error| BrdfError::InvalidInput { name: "merl", problem: e.to_string() };
        let mut out = Vec::with_capacity(12 + self.data.len() * 24);
        for d in [self.n_th, self.n_td, self.n_pd] {
            out.extend_from_slice(&(d as i32).to_le_bytes());
        }
        for c in 0..3 {
            for v in &self.data {
                out.extend_from_slice(&(f64::from(v[c]) / MERL_SCALE[c]).to_le_bytes());
            }
        }
        w.write_all(&out).map_err(io)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Model;
    use crate::params::Input;

    fn ct() -> Model {
        Model::build(
            "cook_torrance",
            &[
                ("roughness".into(), Input::Number(0.3)),
                ("kd".into(), Input::Numbers(vec![0.5, 0.3, 0.2])),
                ("ks".into(), Input::Number(0.5)),
            ],
        )
        .unwrap()
    }

    #[test]
    fn merl_binary_round_trips_and_has_the_documented_layout() {
        let t = Tabulated::from_model(&ct(), (6, 5, 8)).unwrap();
        let mut bytes = Vec::new();
        t.write_merl(&mut bytes).unwrap();
        assert_eq!(bytes.len(), 12 + 6 * 5 * 8 * 3 * 8);
        assert_eq!(&bytes[0..12], &[6, 0, 0, 0, 5, 0, 0, 0, 8, 0, 0, 0]);
        // Green value of node (i, j, k) = (2, 3, 4) sits in the second block at (2*5 + 3)*8 + 4.
        let idx = (2 * 5 + 3) * 8 + 4;
        let o = 12 + (6 * 5 * 8 + idx) * 8;
        let g = f64::from_le_bytes(bytes[o..o + 8].try_into().unwrap());
        assert!((g * 1.15 / 1500.0 - f64::from(t.at(2, 3, 4).y)).abs() < 1e-9);
        let back = Tabulated::read_merl(bytes.as_slice()).unwrap();
        assert_eq!(back.dims(), t.dims());
        for (a, b) in back.data().iter().zip(t.data()) {
            assert!((*a - *b).abs().max_element() <= 1e-7 * a.max_element().max(1.0));
        }
    }

    #[test]
    fn merl_reader_refuses_truncated_or_corrupt_files() {
        let t = Tabulated::from_model(&ct(), (4, 4, 4)).unwrap();
        let mut bytes = Vec::new();
        t.write_merl(&mut bytes).unwrap();
        let e = Tabulated::read_merl(&bytes[..bytes.len() - 3]).unwrap_err().to_string();
        assert!(e.contains("expected") && e.contains("bytes"), "{e}");
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(Tabulated::read_merl(longer.as_slice()).unwrap_err().to_string().contains("trailing"));
        let mut bad = bytes.clone();
        bad[0..4].copy_from_slice(&(-90i32).to_le_bytes());
        assert!(Tabulated::read_merl(bad.as_slice()).unwrap_err().to_string().contains("-90"));
        let mut neg = bytes.clone();
        neg[12..20].copy_from_slice(&(-1.0f64).to_le_bytes());
        assert_eq!(Tabulated::read_merl(neg.as_slice()).unwrap().data()[0].x, 0.0);
    }
}
