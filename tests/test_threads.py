"""Results are bit-identical whatever the thread count (every output element depends only on its own
inputs; batch.rs splits work into fixed chunks)."""

from __future__ import annotations

from typing import Any

import brdfpy
import numpy as np
import pytest

BATCH = 120_000  # above the size at which brdfpy starts using its pool

CASES: list[tuple[str, dict[str, Any]]] = [
    ("lambert", {}),
    ("lambert_classic", {}),
    ("oren_nayar", {}),
    ("oren_nayar_full", {}),
    ("toon", {}),
    ("phong_classic", {}),
    ("blinn_phong_classic", {}),
    ("phong", {}),
    ("blinn_phong", {}),
    ("cook_torrance", {}),
    ("cook_torrance", {"distribution": "beckmann", "masking": "smith", "fresnel": "conductor"}),
    ("strauss", {}),
    ("ward", {}),
    ("ashikhmin_shirley", {}),
    ("lafortune", {}),
]


@pytest.fixture(scope="module")
def batch() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(2024)
    n = rng.normal(size=(BATCH, 3))
    return {
        "l": (rng.normal(size=(BATCH, 3)) + n).astype(np.float32),
        "v": (rng.normal(size=(BATCH, 3)) + n).astype(np.float32),
        "n": n.astype(np.float32),
        "tangent": rng.normal(size=(BATCH, 3)).astype(np.float32),
    }


@pytest.mark.parametrize("case", CASES, ids=[c[0] + "".join(f"-{v}" for v in c[1].values()) for c in CASES])
def test_thread_count_does_not_change_a_bit(
    case: tuple[str, dict[str, Any]], batch: dict[str, np.ndarray], restore_threads: None
) -> None:
    m = brdfpy.model(case[0], **case[1])
    results = {}
    for threads in (1, 2, 4):
        brdfpy.set_num_threads(threads)
        results[threads] = (m.eval(**batch), m.shade(**batch))
    for threads in (2, 4):
        for a, b in zip(results[1], results[threads]):
            assert a.tobytes() == b.tobytes(), f"{case[0]}: {threads} threads differ from 1"
    assert np.any(results[1][0] > 0)


def test_thread_count_must_be_positive() -> None:
    with pytest.raises((ValueError, TypeError)):
        brdfpy.set_num_threads(-1)
