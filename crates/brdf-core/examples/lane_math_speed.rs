//! Throughput of the lane math functions, in M evaluations/s on one thread, for each lane type:
//! `cargo run --release -p brdf-core --example lane_math_speed`.
//!
//! The timed loops are written out by a macro inside the kernel's `run` (no closures): a closure is
//! compiled without the AVX2 target feature of `run_widest`, and its lane operations would be calls.

use std::hint::black_box;
use std::time::Instant;

use brdf_core::simd::{F32x8, Lane, LaneKernel, run_widest};

struct Speed(&'static str);

/// Time `$e` (an expression of the lane `$x`) over the inputs and print M evaluations/s.
macro_rules! time {
    ($label:expr, $name:expr, $xs:expr, |$x:ident| $e:expr) => {{
        let reps = 40;
        let mut acc = F::splat(0.0);
        let t0 = Instant::now();
        for _ in 0..reps {
            for c in $xs.chunks_exact(F::LANES) {
                let $x = black_box(F::from_fn(|i| c[i]));
                acc = acc + $e;
            }
        }
        black_box(acc.lane(0));
        let dt = t0.elapsed().as_secs_f64();
        println!("{:6} {:8} {:8.1} M/s", $label, $name, (reps * $xs.len()) as f64 / dt / 1e6);
    }};
}

impl LaneKernel for Speed {
    #[inline(always)]
    fn run<F: Lane>(self) {
        let xs: Vec<f32> = (0..1 << 16).map(|i| (i as f32 / 65536.0) * 0.98 + 0.01).collect();
        let l = self.0;
        time!(l, "sqrt", xs, |x| x.sqrt());
        time!(l, "exp", xs, |x| (-x * F::splat(30.0)).exp());
        time!(l, "ln", xs, |x| x.ln());
        time!(l, "powf", xs, |x| x.powf(F::splat(37.5)));
        time!(l, "sin", xs, |x| (x * F::splat(6.0)).sin());
        time!(l, "acos", xs, |x| x.acos());
        time!(l, "atan2", xs, |x| x.atan2(F::splat(0.3)));
        time!(l, "erf", xs, |x| (x * F::splat(4.0)).erf());
        time!(l, "erfc", xs, |x| (x * F::splat(4.0)).erfc());
    }
}

fn main() {
    run_widest(Speed("widest"));
    Speed("F32x8").run::<F32x8>();
    Speed("f32").run::<f32>();
    println!("(widest = one AVX register where the CPU has AVX2)");
}
