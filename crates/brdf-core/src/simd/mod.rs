//! Lanes: one formula, evaluated on one sample (`f32`) or on eight at once.
//!
//! The hot terms of the benchmarked models (GGX `D`, the GGX Smith visibility, Schlick's Fresnel, the
//! Cook–Torrance and Blinn–Phong lobes, normalisation) are written once, generic over [`Lane`], and
//! the scalar API (`ggx::d`, `CookTorrance::specular`, `Bxdf::f`, …) is that same code instantiated
//! with `F = f32`. The batch evaluator ([`crate::batch`]) instantiates it with eight lanes: one AVX
//! register where the CPU has AVX2 (detected at run time; `avx2.rs`, the only `unsafe` code, with its
//! soundness argument), else [`F32x8`] from the `wide` crate (two SSE registers on baseline x86-64).
//!
//! **Bit-identical to the scalar path.** Every lane type does exactly the IEEE-754 operations the
//! scalar code does, lane by lane and in the same order: `+ − × ÷` and `√` are correctly rounded,
//! `min`/`max`/`abs` have `f32`'s semantics (with the sign of a zero result pinned, see [`Lane::min`]),
//! comparisons and [`Lane::select`] are exact, and Rust never contracts `a·b + c` into a fused
//! multiply-add on its own (no fast-math; FMA is not enabled for the AVX2 build either). Terms
//! without a wide form (`exp`, `powf`, `erf`, the exact Fresnel equations, …) run the scalar function
//! on each lane ([`Lane::map`]). A batch therefore gives the same bits as [`crate::Model::eval`] on
//! each sample, on any x86-64 CPU, with or without AVX, for any thread count (the batch tests check
//! every model against the scalar path bit for bit).
//!
//! Branches become selects: the generic code computes both sides and keeps one per lane. Lanes that a
//! select discards may hold anything (NaN, ∞); they never reach a result.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Not, Sub};

use glam::{Vec3, Vec3A};
use wide::{CmpEq, CmpGt, CmpLt, CmpNe};

use crate::Geometry;

#[cfg(target_arch = "x86_64")]
mod avx2;

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::dispatch as dispatch_avx2;

#[cfg(target_arch = "x86_64")]
pub(crate) mod srgb8_avx2;

/// A computation over lanes of any [`Lane`] type (the batch evaluator's chunk loop, the rasterizer's
/// shading queue), so that the lane type can be chosen at run time by [`run_widest`].
pub trait LaneKernel {
    /// Run with lane type `F`. Mark the implementation `#[inline(always)]`: it is then compiled inside
    /// the AVX2-enabled caller and its lane operations become single AVX instructions.
    fn run<F: Lane>(self);
}

/// Run `k` with eight lanes in one AVX register where this CPU has AVX2 (detected at run time), else
/// with [`F32x8`]. Both give the same bits (module docs).
#[inline]
pub fn run_widest<K: LaneKernel>(k: K) {
    #[cfg(target_arch = "x86_64")]
    let Some(k) = dispatch_avx2(k) else { return };
    k.run::<F32x8>();
}

/// A number type the model formulas are written over: `f32` (one sample) or eight lanes.
///
/// Every operation has the semantics of the `f32` operation of the same name, applied lane by lane.
pub trait Lane:
    Copy + Send + Sync + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// A per-lane boolean (`bool` for `f32`).
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask> + Not<Output = Self::Mask>;
    /// Number of samples held.
    const LANES: usize;

    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// Lane `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// The value of lane `i < LANES`.
    fn lane(self, i: usize) -> f32;
    /// `√x` (correctly rounded).
    fn sqrt(self) -> Self;
    /// `f32::min` per lane (the other operand where one is NaN; `self` when equal, so `min(−0, +0)`
    /// is −0).
    fn min(self, o: Self) -> Self;
    /// `f32::max` per lane (as [`Lane::min`]).
    fn max(self, o: Self) -> Self;
    /// `|x|`.
    fn abs(self) -> Self;
    /// `self > o`.
    fn gt(self, o: Self) -> Self::Mask;
    /// `self < o`.
    fn lt(self, o: Self) -> Self::Mask;
    /// `self == o`.
    fn eq(self, o: Self) -> Self::Mask;
    /// `f32::is_finite` per lane.
    fn is_finite(self) -> Self::Mask;
    /// A mask with every lane `b`.
    fn mask_splat(b: bool) -> Self::Mask;
    /// Lane `i` of a mask.
    fn mask_lane(m: Self::Mask, i: usize) -> bool;
    /// `true` when every lane of `m` is set.
    #[inline(always)]
    fn mask_all(m: Self::Mask) -> bool {
        (0..Self::LANES).all(|i| Self::mask_lane(m, i))
    }
    /// `a` where `m`, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;

    /// `f` applied to each lane: how terms without a wide form join a wide computation (bit-identical to
    /// calling `f` on each sample).
    #[inline(always)]
    fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self::from_fn(|i| f(self.lane(i)))
    }

    /// `rows` (exactly `LANES` of them) transposed into lanes: lane `j` of `x` is `rows[j].x`, …
    #[inline(always)]
    fn load_rows(rows: &[Vec3]) -> V3<Self> {
        V3 {
            x: Self::from_fn(|j| rows[j].x),
            y: Self::from_fn(|j| rows[j].y),
            z: Self::from_fn(|j| rows[j].z),
        }
    }

    /// The inverse of [`Lane::load_rows`]: lane `j` of `v` into `rows[j]` (exactly `LANES` rows).
    #[inline(always)]
    fn store_rows(v: V3<Self>, rows: &mut [Vec3]) {
        for (j, r) in rows.iter_mut().enumerate() {
            *r = v.lane(j);
        }
    }

    /// `f32::clamp(lo, hi)` per lane (NaN stays NaN).
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> Self {
        let (lo, hi) = (Self::splat(lo), Self::splat(hi));
        Self::select(self.lt(lo), lo, Self::select(self.gt(hi), hi, self))
    }
}

impl Lane for f32 {
    type Mask = bool;
    const LANES: usize = 1;

    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _i: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    // `f32::min`/`max` leave the sign of a zero result unspecified; these pin it (the first operand
    // on ties) so that the scalar and wide forms agree bit for bit.
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        if o < self || self.is_nan() { o } else { self }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        if o > self || self.is_nan() { o } else { self }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self == o
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn mask_splat(b: bool) -> bool {
        b
    }
    #[inline(always)]
    fn mask_lane(m: bool, _i: usize) -> bool {
        m
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
}

/// Eight `f32` lanes ([`wide::f32x8`]: one AVX register where the crate is compiled for AVX, two SSE
/// registers otherwise).
pub type F32x8 = wide::f32x8;

/// Four `f32` lanes ([`wide::f32x4`]: one SSE register; VEX-encoded in the batch evaluator's AVX2 build).
pub type F32x4 = wide::f32x4;

/// Lane masks of [`F32x8`] (all bits set for `true`, the layout of SSE/AVX compare results).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct M32x8(pub F32x8);

/// Lane masks of [`F32x4`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct M32x4(pub F32x4);

/// `Lane` for a `wide` float vector: every operation used is a correctly rounded IEEE operation or
/// an exact bitwise one.
macro_rules! wide_lane {
    ($f:ty, $m:ident, $n:literal) => {
        impl BitAnd for $m {
            type Output = Self;
            #[inline(always)]
            fn bitand(self, o: Self) -> Self {
                Self(self.0 & o.0)
            }
        }
        impl BitOr for $m {
            type Output = Self;
            #[inline(always)]
            fn bitor(self, o: Self) -> Self {
                Self(self.0 | o.0)
            }
        }
        impl Not for $m {
            type Output = Self;
            #[inline(always)]
            fn not(self) -> Self {
                Self(!self.0)
            }
        }

        impl Lane for $f {
            type Mask = $m;
            const LANES: usize = $n;

            #[inline(always)]
            fn splat(x: f32) -> Self {
                <$f>::splat(x)
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
                <$f>::new(std::array::from_fn(f))
            }
            #[inline(always)]
            fn lane(self, i: usize) -> f32 {
                self.as_array_ref()[i]
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$f>::sqrt(self)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                // f32::min: the smaller, or the other operand where one is NaN (see `impl Lane for f32`).
                Self::select($m(o.cmp_lt(self) | self.cmp_ne(self)), o, self)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                Self::select($m(o.cmp_gt(self) | self.cmp_ne(self)), o, self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$f>::abs(self)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> $m {
                $m(self.cmp_gt(o))
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $m {
                $m(self.cmp_lt(o))
            }
            #[inline(always)]
            fn eq(self, o: Self) -> $m {
                $m(self.cmp_eq(o))
            }
            #[inline(always)]
            fn is_finite(self) -> $m {
                // `x · 0 = 0` exactly when x is finite (∞ · 0 and NaN · 0 are NaN).
                $m((self * <$f>::ZERO).cmp_eq(<$f>::ZERO))
            }
            #[inline(always)]
            fn mask_splat(b: bool) -> $m {
                $m(<$f>::splat(f32::from_bits(if b { u32::MAX } else { 0 })))
            }
            #[inline(always)]
            fn mask_lane(m: $m, i: usize) -> bool {
                m.0.as_array_ref()[i].to_bits() != 0
            }
            #[inline(always)]
            fn mask_all(m: $m) -> bool {
                m.0.all()
            }
            #[inline(always)]
            fn select(m: $m, a: Self, b: Self) -> Self {
                // A blend on whole-lane masks: exact for every value, NaN payloads included.
                m.0.blend(a, b)
            }
        }
    };
}
wide_lane!(F32x8, M32x8, 8);
wide_lane!(F32x4, M32x4, 4);

/// A 3-vector (an RGB colour or a direction) whose components are lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V3<F> {
    /// First component (x or red).
    pub x: F,
    /// Second component (y or green).
    pub y: F,
    /// Third component (z or blue).
    pub z: F,
}

impl<F: Lane> V3<F> {
    /// The vector `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        Self { x: F::splat(v.x), y: F::splat(v.y), z: F::splat(v.z) }
    }

    /// Lane `i` is `f(i)`; `f` is called once per lane.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> Vec3) -> Self {
        // Lane counts are tiny (1 or 8): collect into a fixed buffer of the largest.
        let mut buf = [Vec3::ZERO; 8];
        for (i, b) in buf.iter_mut().enumerate().take(F::LANES) {
            *b = f(i);
        }
        Self { x: F::from_fn(|i| buf[i].x), y: F::from_fn(|i| buf[i].y), z: F::from_fn(|i| buf[i].z) }
    }

    /// Lane `i` as a `Vec3`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> Vec3 {
        Vec3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }

    /// `x·x' + y·y' + z·z'`, summed left to right like glam's `Vec3A::dot`.
    #[inline(always)]
    pub fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Each component multiplied by the per-lane factor `s`.
    #[inline(always)]
    pub fn scale(self, s: F) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }

    /// `a` where `m`, else `b`, per lane.
    #[inline(always)]
    pub fn select(m: F::Mask, a: Self, b: Self) -> Self {
        Self { x: F::select(m, a.x, b.x), y: F::select(m, a.y, b.y), z: F::select(m, a.z, b.z) }
    }

    /// Lanes where all three components are finite.
    #[inline(always)]
    pub fn is_finite(self) -> F::Mask {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }

    /// `v / |v|`, or zero where `|v|²` is 0 or not finite; the mask tells which lanes were normalised.
    /// Operation for operation [`crate::vector::normalize_or_zero`]: three divisions by the length, not
    /// one reciprocal and three products — that would save ~5 % of a Cook–Torrance batch but add an
    /// ulp to every direction, which the sharp GGX peak (α = 0.08) amplifies past the test suite's
    /// 1e-3 tolerance near grazing half vectors.
    #[inline(always)]
    pub fn normalize_or_zero(self) -> (Self, F::Mask) {
        let len2 = self.dot(self);
        let ok = len2.gt(F::splat(0.0)) & len2.is_finite();
        let zero = Self { x: F::splat(0.0), y: F::splat(0.0), z: F::splat(0.0) };
        (Self::select(ok, self / len2.sqrt(), zero), ok)
    }
}

/// Each component divided by the per-lane divisor.
impl<F: Lane> Div<F> for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: F) -> Self {
        Self { x: self.x / s, y: self.y / s, z: self.z / s }
    }
}

/// Component-wise product (colour × colour).
impl<F: Lane> Mul for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Self { x: self.x * o.x, y: self.y * o.y, z: self.z * o.z }
    }
}

impl<F: Lane> Sub for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl<F: Lane> Add for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl From<V3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Vec3 {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl From<Vec3A> for V3<f32> {
    #[inline(always)]
    fn from(v: Vec3A) -> Self {
        Self { x: v.x, y: v.y, z: v.z }
    }
}

/// [`Geometry`] for `F::LANES` samples: unit `l`, `v`, `n`, the optional tangent and the cosines.
#[derive(Debug, Clone, Copy)]
pub struct LaneGeometry<F: Lane> {
    /// Unit direction toward the light.
    pub l: V3<F>,
    /// Unit direction toward the viewer.
    pub v: V3<F>,
    /// Unit surface normal.
    pub n: V3<F>,
    /// Unit tangent hint, where given; lanes where it had zero length have `tangent_ok` false.
    pub tangent: Option<V3<F>>,
    /// Lanes whose tangent is usable.
    pub tangent_ok: F::Mask,
    /// cos θ_l = n·l.
    pub nl: F,
    /// cos θ_v = n·v.
    pub nv: F,
}

impl<F: Lane> LaneGeometry<F> {
    /// Normalise the inputs as [`Geometry::new`] does, lane by lane. The mask is false in the lanes
    /// where `Geometry::new` returns `None` (zero-length or non-finite `l`, `v` or `n`).
    #[inline(always)]
    pub fn new(l: V3<F>, v: V3<F>, n: V3<F>, tangent: Option<V3<F>>) -> (Self, F::Mask) {
        let (l, ok_l) = l.normalize_or_zero();
        let (v, ok_v) = v.normalize_or_zero();
        let (n, ok_n) = n.normalize_or_zero();
        let (tangent, tangent_ok) = match tangent.map(V3::normalize_or_zero) {
            Some((t, ok)) => (Some(t), ok),
            None => (None, F::mask_splat(false)),
        };
        let g = Self { l, v, n, tangent, tangent_ok, nl: n.dot(l), nv: n.dot(v) };
        (g, ok_l & ok_v & ok_n)
    }

    /// Lanes where both the light and the viewer are strictly above the surface
    /// ([`Geometry::both_above`]).
    #[inline(always)]
    pub fn both_above(&self) -> F::Mask {
        let zero = F::splat(0.0);
        self.nl.gt(zero) & self.nv.gt(zero)
    }

    /// Lane `i` as a scalar [`Geometry`] (bit-identical to `Geometry::new` on that sample's inputs).
    #[inline]
    pub fn lane(&self, i: usize) -> Geometry {
        let a = |w: &V3<F>| Vec3A::new(w.x.lane(i), w.y.lane(i), w.z.lane(i));
        let tangent = self.tangent.as_ref().filter(|_| F::mask_lane(self.tangent_ok, i)).map(a);
        Geometry {
            l: a(&self.l),
            v: a(&self.v),
            n: a(&self.n),
            tangent,
            nl: self.nl.lane(i),
            nv: self.nv.lane(i),
        }
    }
}

impl From<&Geometry> for LaneGeometry<f32> {
    #[inline(always)]
    fn from(g: &Geometry) -> Self {
        Self {
            l: g.l.into(),
            v: g.v.into(),
            n: g.n.into(),
            tangent: g.tangent.map(Into::into),
            tangent_ok: g.tangent.is_some(),
            nl: g.nl,
            nv: g.nv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward values: signed zeros, subnormals, huge, tiny, NaN, ±∞, ordinary.
    const SPECIALS: [f32; 12] = [
        0.0,
        -0.0,
        1e-40,
        -3e-39,
        3.0e38,
        -1.0e-30,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.5,
        -1.25,
        7.0,
    ];

    fn lanes(base: usize) -> F32x8 {
        F32x8::from_fn(|i| SPECIALS[(base + 5 * i) % SPECIALS.len()])
    }

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn every_lane_operation_equals_the_f32_operation_bit_for_bit() {
        for s in 0..SPECIALS.len() {
            for t in 0..SPECIALS.len() {
                let (a, b) = (lanes(s), lanes(t));
                for i in 0..8 {
                    let (x, y) = (a.lane(i), b.lane(i));
                    assert!(same((a + b).lane(i), x + y));
                    assert!(same((a - b).lane(i), x - y));
                    assert!(same((a * b).lane(i), x * y));
                    assert!(same((a / b).lane(i), x / y));
                    assert!(same(a.sqrt().lane(i), x.sqrt()));
                    assert!(same(Lane::min(a, b).lane(i), Lane::min(x, y)), "min {x} {y}");
                    assert!(same(Lane::max(a, b).lane(i), Lane::max(x, y)), "max {x} {y}");
                    // As values (−0 = +0), the f32 methods' results.
                    let eqv = |p: f32, q: f32| p == q || (p.is_nan() && q.is_nan());
                    assert!(eqv(Lane::min(x, y), x.min(y)), "min {x} {y}");
                    assert!(eqv(Lane::max(x, y), x.max(y)), "max {x} {y}");
                    assert!(same(a.abs().lane(i), x.abs()));
                    assert!(same(a.clamp(-1.0, 1.0).lane(i), Lane::clamp(x, -1.0, 1.0)));
                    assert!(same(Lane::clamp(x, -1.0, 1.0), x.clamp(-1.0, 1.0)));
                    assert_eq!(F32x8::mask_lane(a.gt(b), i), x > y);
                    assert_eq!(F32x8::mask_lane(a.lt(b), i), x < y);
                    assert_eq!(F32x8::mask_lane(a.eq(b), i), x == y);
                    assert_eq!(F32x8::mask_lane(Lane::is_finite(a), i), x.is_finite());
                    let m = a.gt(b);
                    assert!(same(F32x8::select(m, a, b).lane(i), if x > y { x } else { y }));
                }
            }
        }
    }

    #[test]
    fn lane_geometry_equals_scalar_geometry_bit_for_bit() {
        let mut rows = Vec::new();
        for k in 0..64u32 {
            let f = |j: u32| ((k * 7 + j * 13) as f32 * 0.618).sin() * 2.0;
            rows.push(Vec3::new(f(0), f(1), f(2)));
        }
        rows.extend([
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(1e30, 1e30, 0.0),
            Vec3::splat(1e-30),
        ]);
        for base in 0..rows.len() {
            let pick = |off: usize| V3::<F32x8> {
                x: F32x8::from_fn(|i| rows[(base + off + 3 * i) % rows.len()].x),
                y: F32x8::from_fn(|i| rows[(base + off + 3 * i) % rows.len()].y),
                z: F32x8::from_fn(|i| rows[(base + off + 3 * i) % rows.len()].z),
            };
            let (l, v, n, t) = (pick(0), pick(1), pick(2), pick(5));
            let (g, ok) = LaneGeometry::new(l, v, n, Some(t));
            for i in 0..8 {
                let scalar = Geometry::new(l.lane(i), v.lane(i), n.lane(i), Some(t.lane(i)));
                assert_eq!(F32x8::mask_lane(ok, i), scalar.is_some());
                if let Some(s) = scalar {
                    let w = g.lane(i);
                    assert_eq!(w, s);
                    assert_eq!(w.nl.to_bits(), s.nl.to_bits());
                    assert_eq!(w.nv.to_bits(), s.nv.to_bits());
                }
            }
        }
    }
}
