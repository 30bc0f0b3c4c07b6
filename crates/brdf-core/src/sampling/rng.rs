//! The counter-based random numbers of the samplers: `u[row][d]` is a pure function of
//! `(seed, row, d)`, so a batch gives the same numbers however it is split into chunks, threads or
//! lanes, and any row can be regenerated on its own.
//!
//! ```text
//! key        = mix(seed)
//! u[row][d]  = top 24 bits of mix(key + (3·row + d + 1)·γ) · 2⁻²⁴,      d = 0, 1, 2
//! mix(z)     = SplitMix64's output function: z ^= z >> 30; z *= 0xBF58476D1CE4E5B9;
//!              z ^= z >> 27; z *= 0x94D049BB133111EB; z ^= z >> 31      (wrapping u64 arithmetic)
//! γ          = 0x9E3779B97F4A7C15 (the golden-ratio increment)
//! ```
//!
//! That is the `(3·row + d)`-th output of SplitMix64 (Steele, Lea & Flood 2014, "Fast splittable
//! pseudorandom number generators", OOPSLA) started from the state `key`: a Weyl sequence through a
//! bijective 64-bit mixer, which passes BigCrush, so consecutive rows and dimensions are independent
//! for all practical purposes. Hashing the seed first keeps the streams of nearby seeds (0, 1, 2, …)
//! far apart. The 24 bits fill an `f32` mantissa exactly: every value is a multiple of 2⁻²⁴ in
//! `[0, 1 − 2⁻²⁴]`, never 1.

/// SplitMix64's golden-ratio increment.
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Dimensions drawn per row: one to select a lobe, two for the direction ([`super::Sampler`]).
pub const DIMS: u64 = 3;

/// SplitMix64's output function (a bijection of `u64`).
#[inline(always)]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The stream key of a seed, `mix(seed)`.
#[inline(always)]
pub fn key(seed: u64) -> u64 {
    mix64(seed)
}

/// `u[row][d]` of the module docs for the stream `key` ([`key`] of the seed), in `[0, 1)`.
#[inline(always)]
pub fn uniform_keyed(key: u64, row: u64, d: u64) -> f32 {
    let z = mix64(key.wrapping_add(row.wrapping_mul(DIMS).wrapping_add(d + 1).wrapping_mul(GAMMA)));
    (z >> 40) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The three numbers of row `row` for `seed`: `[u[row][0], u[row][1], u[row][2]]`.
#[inline]
pub fn uniform3(seed: u64, row: u64) -> [f32; 3] {
    let k = key(seed);
    [uniform_keyed(k, row, 0), uniform_keyed(k, row, 1), uniform_keyed(k, row, 2)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::properties::SplitMix64;

    #[test]
    fn rows_are_the_documented_splitmix64_stream_started_at_the_hashed_seed() {
        for seed in [0u64, 1, 42, u64::MAX] {
            let mut r = SplitMix64::new(key(seed));
            for row in 0..50u64 {
                let want: [f32; 3] =
                    std::array::from_fn(|_| (r.next_u64() >> 40) as f32 * (1.0 / 16_777_216.0));
                assert_eq!(uniform3(seed, row), want, "seed {seed} row {row}");
            }
        }
    }

    #[test]
    fn numbers_lie_in_the_half_open_unit_interval_and_look_uniform() {
        let n = 200_000u64;
        let mut sums = [0.0f64; 3];
        let mut bins = [0u32; 16];
        for row in 0..n {
            let u = uniform3(7, row);
            for (d, x) in u.iter().enumerate() {
                assert!((0.0..1.0).contains(x));
                sums[d] += f64::from(*x);
            }
            bins[(u[1] * 16.0) as usize] += 1;
        }
        for s in sums {
            // Mean 1/2 with standard error 1/√(12 n) ≈ 6.5e-4.
            assert!((s / n as f64 - 0.5).abs() < 4e-3, "{s}");
        }
        let expected = n as f64 / 16.0;
        let chi2: f64 = bins.iter().map(|&b| (f64::from(b) - expected).powi(2) / expected).sum();
        assert!(chi2 < 40.0, "chi2 {chi2} over 15 dof"); // p ≈ 5e-4
    }
}
