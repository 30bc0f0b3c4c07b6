"""brdfpy.plot on the Agg backend: every kind of plot for every registry model and a measured table, with
assertions on the data drawn (the lines, images and surfaces hold the views' numbers), the labels, and the
optional dependency staying optional."""

from __future__ import annotations

import subprocess
import sys

import brdfpy
import numpy as np
import pytest
from brdfpy import views
from brdfpy.measured import Tabulated

from conftest import REGISTRY_MODELS

mpl = pytest.importorskip("matplotlib", reason="brdfpy[plot] (matplotlib) is not installed")
mpl.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from brdfpy import plot  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def measured() -> brdfpy.Model:
    m = brdfpy.model("cook_torrance", roughness=0.3, kd=(0.4, 0.2, 0.1))
    return Tabulated.from_model(m, (24, 24, 48)).as_model()


def _lum(values: np.ndarray) -> np.ndarray:
    return values.astype(np.float64) @ np.array(views.LUMINANCE)


@pytest.mark.parametrize("name", [*REGISTRY_MODELS, "measured"])
def test_every_plot_draws_the_views_data(name: str, measured: brdfpy.Model) -> None:
    m = measured if name == "measured" else brdfpy.model(name)
    ax = plot.polar(m, 30.0, n=91)
    want = _lum(views.polar(m, 30.0, n=91).values)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), want, rtol=1e-6)
    np.testing.assert_allclose(ax.lines[0].get_xdata(), np.radians(np.linspace(-90, 90, 91)))
    assert "[1/sr]" in ax.get_title()

    ax = plot.albedo(m, theta_i=[0.0, 45.0])
    np.testing.assert_allclose(ax.lines[0].get_ydata(), _lum(views.albedo(m, [0.0, 45.0]).values), rtol=1e-6)
    assert "[°]" in ax.get_xlabel() and "E(θ_i)" in ax.get_ylabel()

    ax = plot.half_diff_slice(m, size=32, log=False)
    s = views.half_diff_slice(m, size=32)
    drawn = ax.images[0].get_array()
    np.testing.assert_array_equal(np.ma.getmaskarray(drawn), ~s.valid)
    np.testing.assert_allclose(drawn.compressed(), s.luminance[s.valid], rtol=1e-6)
    assert ax.get_xlabel() == "θ_h [°]" and ax.get_ylabel() == "θ_d [°]"

    axes = plot.lit_sphere(m, size=32)
    np.testing.assert_array_equal(axes[0].images[0].get_array(), views.lit_sphere(m, size=32, samples=2).rgb)

    ax3 = plot.lobe(m, 30.0, n_theta=8, n_phi=16)
    assert len(ax3.collections) == 1 + 1  # one surface, one light arrow
    assert "[1/sr]" in ax3.get_zlabel()
    ax3.figure.canvas.draw()


def test_several_models_overlay_in_distinct_colours() -> None:
    names = ["lambert", "phong", "cook_torrance"]
    ax = plot.polar(names, 20.0)
    lines = ax.lines[: len(names)]
    assert [ln.get_label() for ln in lines] == names
    assert len({ln.get_color() for ln in lines}) == len(names)
    ax = plot.albedo(names)
    assert [ln.get_label() for ln in ax.lines[: len(names)]] == names


def test_log_polar_plots_decades_below_the_peak() -> None:
    ax = plot.polar("phong", 30.0, log=True, decades=3.0)
    r = ax.lines[0].get_ydata()
    assert r.min() >= 0 and r.max() == pytest.approx(3.0, abs=1e-6)


def test_albedo_table_draws_one_curve_per_parameter_value() -> None:
    ax = plot.albedo_table("cook_torrance", "roughness", [0.1, 0.4, 0.9], theta_i=[0, 30, 60])
    t = views.albedo_table("cook_torrance", "roughness", [0.1, 0.4, 0.9], [0, 30, 60])
    for line, row in zip(ax.lines, t.luminance):
        np.testing.assert_allclose(line.get_ydata(), row, rtol=1e-6)
    assert len({tuple(ln.get_color()) for ln in ax.lines[:3]}) == 3


def test_the_dashboard_has_every_view_of_every_model() -> None:
    fig = plot.dashboard(["lambert", "ward"], 40.0)
    titles = [ax.get_title() for ax in fig.axes]
    for want in ["in-plane slice", "lobe", "energy reflected", "lambert: lit sphere", "ward: θ_h/θ_d slice"]:
        assert any(want in t for t in titles), (want, titles)
    fig.canvas.draw()
    fig = plot.dashboard("lambert", views_=["polar", "albedo"])
    assert len(fig.axes) == 2
    with pytest.raises(ValueError, match="views"):
        plot.dashboard("lambert", views_=["radar"])


def test_plots_refuse_bad_input_with_the_views_messages() -> None:
    with pytest.raises(ValueError, match="theta_i"):
        plot.polar("lambert", 91.0)
    with pytest.raises(ValueError, match="unknown model"):
        plot.albedo(["lambert", "nope"])
    with pytest.raises(ValueError, match="models: is empty"):
        plot.polar([])
    with pytest.raises(ValueError, match="polar Axes"):
        plot.polar("lambert", ax=plt.figure().add_subplot())
    with pytest.raises(ValueError, match="channel"):
        plot.albedo("lambert", channel="alpha")  # type: ignore[arg-type]


def test_importing_brdfpy_does_not_import_matplotlib() -> None:
    code = "import sys, brdfpy, brdfpy.views; print('matplotlib' in sys.modules, 'panel' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_the_log_slice_spends_its_colours_on_the_values_the_slice_holds() -> None:
    # A diffuse term under a highlight spans about one decade: a scale fixed at four decades below the top
    # drew the whole slice in its top quarter, one flat colour.
    m = brdfpy.model("blinn_phong")
    s = views.half_diff_slice(m, size=64)
    lum = s.luminance[s.valid]
    ax = plot.half_diff_slice(m, size=64)
    norm = ax.images[0].norm
    assert norm.vmin == pytest.approx(np.percentile(lum, 0.5), rel=1e-6)
    assert norm.vmax == pytest.approx(np.percentile(lum, 99.5), rel=1e-6)
    assert norm.vmax / norm.vmin < 1e3  # well inside the four decades allowed
    # A slice wider than the allowed decades is cut at that many decades below the top.
    wide = np.geomspace(1e-9, 1.0, s.valid.size).reshape(s.valid.shape)
    low, high = s.log_range(np.where(s.valid, wide, 0))
    assert low == pytest.approx(high * 1e-4)
    # A constant slice (white Lambert) gets a decade below its value, not a zero-width range.
    flat = views.half_diff_slice("lambert", size=16)
    low, high = flat.log_range()
    assert high == pytest.approx(float(flat.luminance[flat.valid][0])) and low == pytest.approx(high / 10)
