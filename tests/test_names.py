"""One name per concept across the API: a count of random samples is ``samples=`` everywhere (``n`` is the
normal), in the checks and in the sampling checks they re-export."""

from __future__ import annotations

import brdfpy
import pytest
from brdfpy import checks


def test_the_sampling_checks_count_samples_with_samples() -> None:
    m = brdfpy.model("lambert", kd=0.5)
    r = checks.albedo_by_sampling(m, [1.0], samples=4096)
    assert r["albedo"].shape[0] == 1 and abs(float(r["albedo"][0][0]) - 0.5) < 0.02
    assert checks.chi2(m, (0.0, 0.0, 1.0), samples=20_000, n_theta=8, n_phi=16)["passed"]


@pytest.mark.parametrize(
    ("call", "old"),
    [
        (lambda m: checks.albedo_by_sampling(m, [1.0], n_samples=100), "n_samples"),
        (lambda m: checks.chi2(m, (0.0, 0.0, 1.0), sample_count=100), "sample_count"),
        (lambda m: checks.positivity(m, n=100), "n"),
        (lambda m: checks.reciprocity_error(m, n=100), "n"),
    ],
)
def test_the_old_spellings_are_refused_naming_samples(call, old) -> None:
    with pytest.raises(TypeError, match=rf"{old}= is now samples="):
        call(brdfpy.model("lambert"))
