"""Regressions of the hostile-input runs over the public API (issue 9): each case once gave a wrong
exception type, a message that named nothing, a silent NaN/inf from finite input, or touched a file
descriptor. The rule each test states is the contract: a clean ``TypeError``/``ValueError`` whose message
names the argument, or a finite result."""

from __future__ import annotations

import io
import math
import os

import brdfpy
import numpy as np
import pytest
from brdfpy import fresnel, measured, microfacet, sh, tonemap, transforms
from brdfpy.scene import ProgressBar


@pytest.fixture(scope="module")
def table() -> measured.Tabulated:
    return measured.Tabulated.from_model(brdfpy.model("lambert"), (4, 4, 8))


@pytest.fixture(scope="module")
def image() -> brdfpy.Image:
    scene = brdfpy.Scene()
    scene.add(brdfpy.cube())
    return scene.render(brdfpy.Camera.framing((0, 0, 0), 2.0), width=8, height=8)


# ------------------------------------------------------------------- integers are not file descriptors


@pytest.mark.parametrize("fd", [0, 1, 3, True, 2.5, None, b"\x00"[0]])
def test_save_merl_refuses_a_non_path_instead_of_writing_to_a_file_descriptor(
    table: measured.Tabulated, fd: object
) -> None:
    with pytest.raises(TypeError, match=r"^path: expected a file path"):
        table.save_merl(fd)  # type: ignore[arg-type]


@pytest.mark.parametrize("fd", [0, 3, 1.0, None, object()])
def test_load_merl_refuses_a_non_path_instead_of_reading_standard_input(fd: object) -> None:
    with pytest.raises(TypeError, match=r"^path: expected a file path"):
        measured.Tabulated.load_merl(fd)  # type: ignore[arg-type]


def test_merl_round_trip_still_takes_str_bytes_and_pathlike(
    table: measured.Tabulated, tmp_path: os.PathLike[str]
) -> None:
    p = os.path.join(os.fspath(tmp_path), "t.binary")
    table.save_merl(p)
    for path in (p, os.fsencode(p), type(tmp_path)(p)):
        assert measured.Tabulated.load_merl(path).shape == table.shape  # type: ignore[arg-type]


@pytest.mark.parametrize("bad", [-1, 10**12, 3.0, None, "abc"])
def test_from_merl_bytes_refuses_what_is_not_bytes(bad: object) -> None:
    # bytes(-1) said "negative count"; bytes(10**12) tried to allocate a terabyte.
    with pytest.raises(TypeError, match=r"^data: expected the bytes of a MERL file"):
        measured.Tabulated.from_merl_bytes(bad)  # type: ignore[arg-type]


def test_a_merl_header_asking_for_terabytes_is_refused_without_allocating_them() -> None:
    header = np.array([4096, 4096, 4096], "<i4").tobytes()
    with pytest.raises(brdfpy.BrdfError, match=r"^merl: the header asks for .* nodes, more than the limit"):
        measured.Tabulated.from_merl_bytes(header + b"\x00" * 64)


@pytest.mark.parametrize("fd", [1, 2.0, None])
def test_image_save_and_load_mesh_refuse_non_paths(image: brdfpy.Image, fd: object) -> None:
    with pytest.raises(TypeError, match=r"^path: expected a file path"):
        image.save(fd)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"^path: expected a file path"):
        brdfpy.load_mesh(fd)  # type: ignore[arg-type]


# ------------------------------------------------------------------ finite in, finite (or refused) out


def test_obscurance_at_vanishing_tau_is_its_linear_limit_not_nan() -> None:
    mesh = brdfpy.torus()
    tiny = mesh.compute_obscurance(tau=1e-45, samples=16)
    small = mesh.compute_obscurance(tau=1e-3, samples=16)
    assert np.all(np.isfinite(tiny)) and np.all((tiny >= 0) & (tiny <= 1))
    # μ(d) → d/d_max as τ → 0: τ = 1e-3 is within 1e-3 of that limit.
    np.testing.assert_allclose(tiny, small, atol=2e-3)


@pytest.mark.parametrize("eta", [1e-45, 1e-30, 1e30, 1e38])
def test_dielectric_refuses_an_index_of_refraction_beyond_float32_arithmetic(eta: float) -> None:
    with pytest.raises(ValueError, match=r"^eta: must be in \[1e-6, 1e6\], got"):
        fresnel.dielectric(1.0, eta)


@pytest.mark.parametrize("eta", [1e-6, 1e-3, 1.5, 1e3, 1e6])
def test_dielectric_is_finite_over_the_whole_accepted_range(eta: float) -> None:
    cos = np.linspace(-1, 1, 101)
    r = fresnel.dielectric(cos, eta)
    assert np.all(np.isfinite(r)) and np.all((r >= 0) & (r <= 1))


@pytest.mark.parametrize("aspect", [1e-45, 0.0, -1.0, math.inf, math.nan, 1e9])
def test_projection_matrix_refuses_an_aspect_that_gave_infinite_entries(aspect: float) -> None:
    with pytest.raises(ValueError, match=r"^aspect: must be a width/height ratio in"):
        brdfpy.Camera().projection_matrix(aspect=aspect)


def test_projection_matrix_is_finite_at_the_extreme_accepted_aspects() -> None:
    for aspect in (1 / 16384, 16384.0):
        assert np.all(np.isfinite(brdfpy.Camera().projection_matrix(aspect=aspect)))


@pytest.mark.parametrize("ev", [1e38, 200.0, -1e38, -200.0])
def test_exposure_saturates_instead_of_overflowing_to_inf_or_nan(ev: float) -> None:
    x = np.array([0.0, 1e-30, 0.5, -2.0, 3e38], np.float32)
    y = tonemap.exposure(x, ev=ev)
    assert np.all(np.isfinite(y))
    assert y[0] == 0.0
    if ev > 0:
        assert y[2] == np.finfo(np.float32).max and y[3] == -np.finfo(np.float32).max
    else:
        assert np.all(y[1:4] == 0) or np.all(np.abs(y[1:4]) < 1e-30)
    # Where 2^ev overflows float32 but the product does not, the product is exact.
    assert tonemap.exposure(np.float32(2.0**-100), ev=200.0) == np.float32(2.0**100)


@pytest.mark.parametrize("distribution", ["ggx", "beckmann"])
def test_lambda_is_finite_above_the_surface_even_at_grazing_angles(distribution: str) -> None:
    n = [0.0, 0.0, 1.0]
    w = np.array([[0.3, 0.0, 0.9], [1.0, 0.0, 1e-20], [1.0, 1.0, 1e-38], [0.0, 1.0, 1e-30]], np.float32)
    for alpha in (1e-4, 0.5, 1e3, 1e4):
        lam = microfacet.lambda_(w, n, alpha, distribution=distribution)
        assert np.all(np.isfinite(lam)) and np.all(lam >= 0), (alpha, lam)
    # Below the surface Λ is +∞ by definition (G1 = 0).
    assert microfacet.lambda_([1.0, 0.0, -0.5], n, 0.5, distribution=distribution) == np.inf


def test_lambda_refuses_absurd_roughness() -> None:
    pattern = r'^parameter "alpha": must be finite and in \(0, 10000\], got 1000000000'
    with pytest.raises(ValueError, match=pattern):
        microfacet.lambda_([0.3, 0.0, 0.9], [0, 0, 1], 1e9)


# ------------------------------------------------------------------------------ the right exception type


def test_image_save_names_a_bad_format(image: brdfpy.Image, tmp_path: os.PathLike[str]) -> None:
    p = os.path.join(os.fspath(tmp_path), "x.png")
    with pytest.raises(TypeError, match=r"^format: expected an image format name"):
        image.save(p, format=3)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^format: Pillow cannot write 'abc'"):
        image.save(p, format="abc")
    with pytest.raises(ValueError, match=r"^path: Pillow cannot write files with the extension '.xyz'"):
        image.save(os.path.join(os.fspath(tmp_path), "x.xyz"))
    image.save(p)
    image.save(os.path.join(os.fspath(tmp_path), "y.data"), format="png")
    assert os.path.getsize(p) > 0


def test_sh_project_names_a_quad_that_is_not_a_quadrature() -> None:
    with pytest.raises(TypeError, match=r"^quad: expected a Quadrature"):
        sh.project(lambda d: d[:, 2], 2, quad=3)  # type: ignore[arg-type]


@pytest.mark.parametrize(("l", "m", "name"), [(1, None, "m"), (None, 0, "l"), (1.0, 0, "l"), (2, "1", "m")])
def test_sh_index_names_an_argument_that_is_not_an_int(l: object, m: object, name: str) -> None:
    with pytest.raises(TypeError, match=rf"^{name}: expected an int"):
        sh.index(l, m)  # type: ignore[arg-type]


def test_the_light_base_class_cannot_be_made() -> None:
    with pytest.raises(TypeError, match=r"^Light is the base class: create a DirectionalLight"):
        brdfpy.Light()
    assert brdfpy.PointLight((0, 1, 0)).incident((0, 0, 0)) is not None


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"aspect": 0}, r"^aspect: must be a width/height ratio"),
        ({"aspect": -math.inf}, r"^aspect: must be a width/height ratio"),
        ({"aspect": 1e-45}, r"^aspect: must be a width/height ratio"),
        ({"fovy": 180.0}, r"^fovy: must lie in \(0, 180\) degrees"),
        ({"fovy": -math.inf}, r"^fovy: must lie in \(0, 180\) degrees"),
        ({"margin": math.nan}, r"^margin: must be finite and > 0"),
    ],
)
def test_camera_framing_names_the_bad_argument(kwargs: dict[str, float], pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        brdfpy.Camera.framing((0, 0, 0), 1.0, **kwargs)


def test_camera_framing_refuses_a_radius_too_large_to_place_the_eye() -> None:
    with pytest.raises(ValueError, match=r"^radius: .* too large to frame"):
        brdfpy.Camera.framing((0, 0, 0), 1.7e308)


@pytest.mark.parametrize("fraction", [math.inf, 1e9, -0.5, math.nan])
def test_progress_bar_refuses_a_fraction_outside_0_1(fraction: float) -> None:
    # inf gave OverflowError, 1e9 a MemoryError (a bar of 3e10 characters).
    with pytest.raises(ValueError, match=r"^fraction: expected a number in \[0, 1\]"):
        ProgressBar(stream=io.StringIO())(fraction)


def test_progress_bar_still_draws_fractions_in_range() -> None:
    out = io.StringIO()
    bar = ProgressBar(stream=out)
    for f in (0.0, 0.5, 1.0):
        bar(f)
    assert "100 %" in out.getvalue()


# -------------------------------------------------------------------------- messages that name nothing


@pytest.mark.parametrize("degrees", [-math.inf, math.inf, math.nan])
def test_rotate_names_non_finite_degrees(degrees: float) -> None:
    # math.cos(inf) said "math domain error".
    with pytest.raises(ValueError, match=r"^degrees: must be finite"):
        transforms.rotate([0, 0, 1], degrees=degrees)


def test_rotate_names_degrees_of_the_wrong_type() -> None:
    with pytest.raises(TypeError, match=r"^degrees: expected a number, got str"):
        transforms.rotate([0, 0, 1], degrees="90")  # type: ignore[arg-type]
