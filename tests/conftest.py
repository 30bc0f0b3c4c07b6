"""Shared fixtures: the oracle on sys.path, seeded random geometry, and the float32 tolerances.

brdfpy computes in float32; the oracle in float64 on the *same* float32-rounded inputs. What remains is
float32 arithmetic inside brdfpy: each operation is exact to 2^-24 ~ 6e-8 relative, a BRDF evaluation
chains ~10-100 of them, and powers/exponentials amplify an input error by their exponent
(``x^32`` turns 6e-8 into ~2e-6; ``exp(-tan^2/alpha^2)`` with ``tan^2/alpha^2 ~ 100`` into ~1e-5). So:

* ``RTOL = 1e-3`` — two orders above the worst amplified rounding of the well-conditioned samples, two
  orders below any formula slip worth catching (a wrong constant, a missing pi, 0.3 vs 0.33 changes values
  by > 1 %).
* ``ATOL_REL = 1e-5`` — an absolute floor scaled by the largest value in the batch, for samples whose
  value is near zero (e.g. far outside a lobe) where a relative comparison means nothing.
* Samples where the *oracle itself* is ill conditioned are left out (see :func:`well_conditioned`):
  where a relative change of the inputs of ``PERTURB = 1e-6`` (about 16 float32 ulps) moves the oracle by
  more than ``RTOL/4``. That removes threshold jumps (toon bands), cusps and the last fraction of a degree
  before grazing, and keeps everything else, including directions at 89.9 degrees.
* Nearly opposite light and view (``|l + v| < MIN_HALF = 0.25`` for unit l, v: both grazing, on opposite
  sides) are compared like the rest. There the cosine form ``n.h = (n.l + n.v)/sqrt(2 + 2 l.v)``, then
  ``1 - (n.h)^2`` (pbrt's ``Tan2Theta``), cancels twice and was off by 31 % at alpha = 0.05; the models
  build h from ``l + v`` summed component by component (Cook-Torrance keeps it un-normalised and splits it
  along n and the tangent plane, ``brdf_core::microfacet::half``). What is left is the rounding of the
  float32 unit l and v, which turns h by ~1e-7/|l + v| rad (measured: <= 3e-5 relative in Cook-Torrance's D
  for |l + v| >= 0.01 at alpha = 0.05, <= 2e-3 below 0.003), and the PERTURB filter above drops the
  samples where that could reach RTOL/4 (a 1e-6 input change moves the oracle ~10x more than that rounding
  does). ``test_models.py`` checks the region separately for Cook-Torrance, at a tolerance that follows
  that rounding.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Iterator
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable, TypeVar

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

sys.path.insert(0, str(Path(__file__).resolve().parent))

RTOL = 1e-3
ATOL_REL = 1e-5
PERTURB = 1e-6
#: At least this fraction of samples must survive the conditioning filter, so a comparison can't pass
#: by comparing nothing.
MIN_COMPARED = 0.9
#: Unit l, v with |l + v| below this are "nearly opposite" (see the module docstring).
MIN_HALF = 0.25

settings.register_profile(
    "fast", max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("ci", max_examples=300, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "fast"))


@lru_cache(maxsize=16)
def gauss_legendre01(count: int) -> tuple[np.ndarray, np.ndarray]:
    """About ``count`` nodes and weights on [0, 1]: composite Gauss-Legendre, 32-point rule on
    ``count // 32`` equal panels (a single 1000-point rule costs seconds of eigensolve; the panels also
    resolve peaked integrands better)."""
    x, w = np.polynomial.legendre.leggauss(32)
    panels = max(1, count // 32)
    left = np.arange(panels)[:, None] / panels
    nodes = (left + 0.5 * (x + 1) / panels).reshape(-1)
    weights = np.tile(0.5 * w / panels, panels)
    return nodes, weights


def unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


#: One unit in the last place of float32 at 1 (the precision tests' unit of error).
F32_ULP = 2.0**-24


def direction(cos_theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Unit vectors at polar cosine ``cos_theta`` from +z and azimuth ``phi`` (float64)."""
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta**2))
    return np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), cos_theta], axis=-1)


def in_random_frame(rng: np.random.Generator, l: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
    """Local-frame ``l``, ``v`` (normal +z; rows with both above the surface kept) turned to a random world
    frame: ``{"l", "v", "n", "tangent"}`` in float64."""
    keep = (l[:, 2] > 0) & (v[:, 2] > 0)
    l, v = l[keep], v[keep]
    n = unit(rng.normal(size=l.shape))
    t = unit(np.cross(n, rng.normal(size=l.shape)))
    b = np.cross(n, t)

    def world(w: np.ndarray) -> np.ndarray:
        return w[:, :1] * t + w[:, 1:2] * b + w[:, 2:3] * n

    return {"l": world(l), "v": world(v), "n": n, "tangent": t}


def log_uniform(rng: np.random.Generator, lo: float, hi: float, count: int) -> np.ndarray:
    """``count`` numbers spread evenly in ``log`` over ``[lo, hi]``."""
    return np.exp(rng.uniform(np.log(lo), np.log(hi), count))


def _orthonormal(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t = unit(np.cross(helper, n))
    return t, np.cross(n, t)


def hemisphere(rng: np.random.Generator, n: np.ndarray, cos_theta: np.ndarray) -> np.ndarray:
    """Unit directions at the given cos(theta) from the unit normals ``n`` and uniform azimuth."""
    t, b = _orthonormal(n)
    phi = rng.uniform(0, 2 * np.pi, len(n))
    s = np.sqrt(np.maximum(0.0, 1 - cos_theta**2))
    return (s * np.cos(phi))[:, None] * t + (s * np.sin(phi))[:, None] * b + cos_theta[:, None] * n


def random_geometry(rng: np.random.Generator, count: int, below: float = 0.0) -> dict[str, np.ndarray]:
    """``count`` (l, v, n, tangent) configurations, float32, with random normals (not only +z):

    * 60 % uniform over the hemisphere (cos theta uniform in (0, 1]);
    * 20 % grazing: one or both of l, v at 80..89.9 degrees from the normal;
    * 20 % near the mirror configuration (v close to reflect(l)), where specular lobes peak;
    * a fraction ``below`` of l or v flipped below the horizon.

    Vectors are deliberately not normalised (lengths 0.5..2) so normalisation is part of the contract;
    the tangent is a random vector, not orthogonal to n (the model must Gram-Schmidt it).
    """
    n = unit(rng.normal(size=(count, 3)))
    cl = rng.uniform(1e-3, 1, count)
    cv = rng.uniform(1e-3, 1, count)
    kind = rng.uniform(size=count)
    graze = (kind >= 0.6) & (kind < 0.8)
    graze_cos = np.cos(np.deg2rad(rng.uniform(80, 89.9, count)))
    which = rng.integers(0, 3, count)  # 0: l grazes, 1: v grazes, 2: both
    cl = np.where(graze & (which != 1), graze_cos, cl)
    cv = np.where(graze & (which != 0), np.cos(np.deg2rad(rng.uniform(80, 89.9, count))), cv)
    l = hemisphere(rng, n, cl)
    v = hemisphere(rng, n, cv)
    mirror = kind >= 0.8
    r = 2 * np.sum(n * l, axis=1, keepdims=True) * n - l
    jitter = rng.normal(scale=rng.choice([0.01, 0.05, 0.2], count)[:, None], size=(count, 3))
    v_m = unit(r + jitter)
    v = np.where(mirror[:, None] & (np.sum(v_m * n, axis=1, keepdims=True) > 1e-3), v_m, v)
    flip = rng.uniform(size=count) < below
    which_flip = rng.integers(0, 2, count)
    l = np.where((flip & (which_flip == 0))[:, None], l - 2 * np.sum(l * n, 1, keepdims=True) * n, l)
    v = np.where((flip & (which_flip == 1))[:, None], v - 2 * np.sum(v * n, 1, keepdims=True) * n, v)
    scale = rng.uniform(0.5, 2.0, (3, count, 1))
    tangent = rng.normal(size=(count, 3))
    return {
        "l": (l * scale[0]).astype(np.float32),
        "v": (v * scale[1]).astype(np.float32),
        "n": (n * scale[2]).astype(np.float32),
        "tangent": tangent.astype(np.float32),
    }


def well_conditioned(
    fn: Callable[..., np.ndarray], geo: dict[str, np.ndarray], rng: np.random.Generator, reference: np.ndarray
) -> np.ndarray:
    """Rows where the oracle ``fn(l, v, n, tangent)`` moves by less than RTOL/4 (relative, with the
    ATOL floor) under two random relative perturbations of size PERTURB of every input."""
    scale = np.max(np.abs(reference)) if reference.size else 1.0
    ok = np.ones(len(reference), bool)
    for _ in range(2):
        pert = {
            k: a.astype(np.float64) * (1 + PERTURB * rng.choice([-1.0, 1.0], a.shape)) for k, a in geo.items()
        }
        moved = fn(**pert)
        err = np.abs(moved - reference)
        ok &= np.all(err <= RTOL / 4 * np.abs(reference) + ATOL_REL * scale / 4, axis=-1)
    return ok


def assert_close(got: Any, want: np.ndarray, mask: np.ndarray | None = None, what: str = "") -> None:
    """float32 result vs float64 oracle at the suite's tolerances (on the ``mask`` rows)."""
    got = np.asarray(got, dtype=np.float64)
    want = np.asarray(want, dtype=np.float64)
    assert got.shape == want.shape, f"{what}: shape {got.shape} != {want.shape}"
    if mask is not None:
        got, want = got[mask], want[mask]
    scale = np.max(np.abs(want)) if want.size else 0.0
    np.testing.assert_allclose(got, want, rtol=RTOL, atol=ATOL_REL * scale + 1e-30, err_msg=what)


@pytest.fixture
def rng(request: pytest.FixtureRequest) -> np.random.Generator:
    """A generator seeded from the test's name: reproducible, but different per test."""
    seed = sum(request.node.nodeid.encode()) * 7919 % (2**32)
    return np.random.default_rng(seed)


@pytest.fixture
def restore_threads() -> Iterator[None]:
    """Put brdfpy's thread count back after a test that changes it."""
    import brdfpy

    before = brdfpy.get_num_threads()
    yield
    brdfpy.set_num_threads(before)


@pytest.fixture
def one_thread(restore_threads: None) -> None:
    """brdfpy on one thread, leaving the second core to a Python thread (GIL tests)."""
    import brdfpy

    brdfpy.set_num_threads(1)


T = TypeVar("T")


def _spin_until(done: threading.Event) -> int:
    count = 0
    while not done.is_set():
        count += 1
    return count


def python_spins_during(work: Callable[[], T]) -> tuple[float, T]:
    """Run ``work`` on another thread while a pure-Python loop spins on this one, and return the loop's
    speed meanwhile **as a fraction of its speed alone** (measured just before, same loop), with ``work``'s
    result.

    If ``work`` releases the GIL the loop keeps running: a fraction near 1 (less on a loaded machine, where
    the two threads share cores with other processes). If ``work`` holds the GIL, the loop cannot run at
    all while the C or Rust code runs, only before and after it (interpreter switch intervals are 5 ms and
    only apply between bytecodes): a fraction near 0 for a call of ~0.1 s or more. An absolute iteration
    count would not separate the two: it depends on the machine's speed and load.
    ``test_raster_gil.py`` shows that a GIL-holding call of the same length scores near 0.
    """

    def speed_alone() -> float:
        alone = threading.Event()
        timer = threading.Timer(0.15, alone.set)
        t0 = time.perf_counter()
        timer.start()
        free_count = _spin_until(alone)
        return free_count / (time.perf_counter() - t0)

    done = threading.Event()
    result: list[T] = []

    def run() -> None:
        try:
            result.append(work())
        finally:
            done.set()

    # The clock starts before the thread: waiting for it to signal that it started would need the GIL,
    # which a GIL-holding call gives back only when it is finished (the loop would time only the end).
    before = speed_alone()
    t = threading.Thread(target=run)
    t1 = time.perf_counter()
    t.start()
    count = _spin_until(done)
    elapsed = time.perf_counter() - t1
    t.join()
    if not result:
        raise RuntimeError("the work raised on its thread (see the thread's traceback above)")
    # The loop's best speed alone, before and after: other processes on a busy machine slow it at times.
    free_rate = max(before, speed_alone())
    return count / (free_rate * elapsed), result[0]


#: A call that releases the GIL lets the spinning loop keep at least this fraction of its speed: measured at
#: load 25-30 on 2 cores, 0.7-0.8 for ``time.sleep`` and 0.28 for a debug-build render (which converts the
#: scene under the GIL first), while a GIL-holding call of 0.5 s scored 0.05-0.13 (see
#: :func:`python_spins_during` and ``test_raster_gil.py``).
GIL_RELEASED_FRACTION = 0.2


def model_defaults(name: str) -> dict[str, Any]:
    """Resolved default parameters of a model, read from the registry (the API, not the Rust code)."""
    import brdfpy

    return {p["name"]: p["default"] for p in brdfpy.model_info(name)["params"]}


#: Every model the registry must contain (SPEC rows 1-12), in registry order: tests parametrise over it,
#: not over `brdfpy.models()`, so a model that goes missing fails instead of silently dropping its tests.
REGISTRY_MODELS = [
    "lambert",
    "lambert_classic",
    "oren_nayar",
    "oren_nayar_full",
    "toon",
    "phong_classic",
    "blinn_phong_classic",
    "phong",
    "blinn_phong",
    "cook_torrance",
    "strauss",
    "ward",
    "ashikhmin_shirley",
    "lafortune",
]
