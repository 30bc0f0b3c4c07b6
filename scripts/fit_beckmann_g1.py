"""Fit the rational approximation of the Beckmann Smith masking term that brdf-core evaluates
(crates/brdf-core/src/microfacet/beckmann.rs, ``G1_P`` and ``G1_Q``), and measure its error.

The exact Smith ``Λ`` of the Beckmann distribution is (B. Walter, S. R. Marschner, H. Li, K. E. Torrance,
"Microfacet Models for Refraction through Rough Surfaces", EGSR 2007, eq. 25)

    Λ(a) = (erf(a) − 1)/2 + exp(−a²)/(2 a √π),   a = 1/(α tan θ),   G1 = 1/(1 + Λ),

which costs an error function and an exponential. G1 is smooth on [0, ∞): 0 at a = 0 with slope 2√π, and
1 − G1 falls like exp(−a²)/(4√π a³), below 2⁻²⁵ (where G1 rounds to 1 in float32) from a ≈ 3.45 on. So
on [0, A] with A = 3.6 (1 − G1(A) = 6.4e-9) it is written ``G1 ≈ a P(a)/Q(a)`` with P, Q of degree 6
(Q(0) = 1), and G1 = 1 beyond. The coefficients minimise the largest relative error of G1 over [0, A]
(Sanathanan–Koerner linearisation with Lawson's reweighting toward the minimax solution, on 3000 Chebyshev
points; the reference is mpmath at 30 digits), are then rounded to float32, and the rounded rational is
evaluated as the Rust code does (Horner's rule in float32, then ``a·P/Q``) on a dense grid.

Run: ``python3 scripts/fit_beckmann_g1.py`` (needs numpy and mpmath; about a minute). It prints the two
coefficient arrays for the Rust file and the errors: float64 fit ≈ 3.9e-9, float32 coefficients in float64
arithmetic ≈ 3.7e-8, float32 evaluation ≈ 4e-7 (a few float32 ulps).
"""

from __future__ import annotations

import mpmath as mp  # type: ignore[import-untyped]
import numpy as np
from numpy.typing import NDArray

A = 3.6
DEG_P = 6
DEG_Q = 6
mp.mp.dps = 30


def g1_exact(a: float) -> float:
    """Walter et al. 2007 eq. 25 through G1 = 1/(1 + Λ), in 30-digit arithmetic."""
    x = mp.mpf(a)
    lam = (mp.exp(-x * x) / (x * mp.sqrt(mp.pi)) - mp.erfc(x)) / 2
    return float(1 / (1 + lam))


def fit(iterations: int = 300) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """(P, Q, max relative error): coefficients in powers of a (a⁰ first), Q[0] = 1."""
    n = 3000
    x = (A / 2) * (1 - np.cos(np.pi * (np.arange(n) + 0.5) / n))
    f = np.array([g1_exact(t) / t for t in x])  # G1/a, smooth with f(0) = 2√π
    t = x / A  # fit in t ∈ [0, 1] for conditioning, convert at the end
    vp = np.vander(t, DEG_P + 1, increasing=True)
    vq = np.vander(t, DEG_Q + 1, increasing=True)
    w = np.full(n, 1.0 / n)
    q = np.ones(n)
    err = np.inf
    p_t = q_t = np.zeros(1)
    for _ in range(iterations):
        # Minimise Σ w ((P − f Q)/(f Q_prev))² over P and Q with Q(0) = 1: linear in the coefficients.
        scale = 1.0 / (f * q)
        m = np.hstack([vp, -f[:, None] * vq[:, 1:]]) * scale[:, None]
        rhs = f * scale
        sw = np.sqrt(w)
        c, *_ = np.linalg.lstsq(m * sw[:, None], rhs * sw, rcond=None)
        p_t, q_t = c[: DEG_P + 1], np.concatenate([[1.0], c[DEG_P + 1 :]])
        q = vq @ q_t
        rel = np.abs((vp @ p_t) / q / f - 1)
        err = float(rel.max())
        w = w * rel  # Lawson: weight grows where the error is large
        w /= w.sum()
    p = p_t / A ** np.arange(DEG_P + 1)
    qa = q_t / A ** np.arange(DEG_Q + 1)
    return p, qa, err


def horner32(c: NDArray[np.float32], x: NDArray[np.float32]) -> NDArray[np.float32]:
    """Horner's rule in float32, highest degree first, as `horner` in beckmann.rs."""
    r = np.full_like(x, c[-1])
    for k in c[-2::-1]:
        r = r * x + k
    return r


def main() -> None:
    p, q, err64 = fit()
    p32, q32 = p.astype(np.float32), q.astype(np.float32)
    xs = np.linspace(0.0, A, 40_001, dtype=np.float32)[1:]
    exact = np.array([g1_exact(float(a)) for a in xs])
    x64 = xs.astype(np.float64)
    p64, q64 = p32[::-1].astype(np.float64), q32[::-1].astype(np.float64)
    rounded = x64 * np.polyval(p64, x64) / np.polyval(q64, x64)
    got = xs * horner32(p32, xs) / horner32(q32, xs)
    rel32 = np.abs(got.astype(np.float64) / exact - 1)
    print(f"fit on [0, {A}], degrees ({DEG_P}, {DEG_Q})")
    print(f"  max relative error, float64 coefficients:         {err64:.2e}")
    print(f"  max relative error, float32 coefficients (f64):    {np.abs(rounded / exact - 1).max():.2e}")
    worst = xs[rel32.argmax()]
    print(f"  max relative error, float32 evaluation:            {rel32.max():.2e} at a = {worst}")
    print(f"  1 − G1({A}) = {1 - g1_exact(A):.2e} (G1 = 1 in float32 from a = {A} on)")

    def rust(name: str, c: NDArray[np.float32]) -> str:
        # str of a float32 is its shortest round-trip form (the digits clippy accepts for an f32).
        return f"const {name}: [f32; {len(c)}] = [{', '.join(str(v) for v in c)}];"

    print(rust("G1_P", p32))
    print(rust("G1_Q", q32))


if __name__ == "__main__":
    main()
