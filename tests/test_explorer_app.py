"""The explorer's app without a browser (as in a notebook: no server, every change redraws at once): controls
generated from the registry, refused values shown on the page, overlays, measured tables, dragging on the
sphere, and ``brdfpy.explore``. The browser tests are in tests/test_explorer.py."""

from __future__ import annotations

import brdfpy
import pytest

pytest.importorskip("panel", reason="brdfpy[explore] (Panel) is not installed")


@pytest.fixture
def app():
    from brdfpy import explorer

    return explorer.Explorer([brdfpy.model("cook_torrance")], size=64)


def test_controls_come_from_the_registry(app) -> None:
    c = app.controls["cook_torrance"]
    spec = {p["name"]: p for p in brdfpy.model_info("cook_torrance")["params"]}
    assert set(c.widgets) == set(spec)
    rough = c.widgets["roughness"]
    assert (rough.start, rough.end, rough.value) == (spec["roughness"]["min"], spec["roughness"]["max"], 0.3)
    assert list(c.widgets["distribution"].options) == list(spec["distribution"]["choices"])
    # A colour picker shows 8-bit sRGB and gives back the linear value: to half an 8-bit step (1/510) times
    # the slope of the sRGB decoding, at most 2.2 (at 1), so within 4.4e-3.
    assert c.params()["kd"] == pytest.approx(list(spec["kd"]["default"]), abs=4.4e-3)


def test_a_refused_value_shows_the_message_and_the_next_good_one_clears_it(app) -> None:
    frame = app.frame
    app.controls["cook_torrance"].widgets["roughness"].value = -1.0
    assert app.error.visible and "roughness" in app.error.object and app.frame == frame + 1
    app.controls["cook_torrance"].widgets["roughness"].value = 0.5
    assert not app.error.visible and app.frame == frame + 2


def test_models_overlay_and_tables_join_the_choices(app) -> None:
    app.w_models.value = ["cook_torrance", "phong"]
    assert app.src_polar.data["label"] == ["cook_torrance", "phong"]
    assert len(set(app.src_polar.data["color"])) == 2
    from brdfpy.measured import Tabulated

    t = Tabulated.from_model(brdfpy.model("lambert"), (8, 8, 16)).as_model()
    app.load_table("measured: lambert.binary", t)
    assert "measured: lambert.binary" in app.w_models.options
    assert app.src_albedo.data["label"][-1] == "measured: lambert.binary"
    app.w_models.value = []
    assert app.error.visible and "at least one model" in app.error.object


def test_a_truncated_uploaded_table_is_refused_on_the_page(app) -> None:
    from brdfpy.measured import Tabulated

    data = Tabulated.from_model(brdfpy.model("lambert"), (8, 8, 16)).to_merl_bytes()
    app.w_upload_table.filename = "cut.binary"
    app.w_upload_table.value = data[:-10]
    assert app.error.visible and "cut.binary" in app.error.object and "bytes" in app.error.object


def test_dragging_on_the_sphere_sets_the_incidence(app) -> None:
    from types import SimpleNamespace

    app._dragged(SimpleNamespace(x=0.5 + 0.5 * 0.5, y=0.5))  # x = 0.5 on the unit disc, to the right
    assert app.w_theta.value == pytest.approx(30.0, abs=0.01) and app.w_phi.value == pytest.approx(0.0)
    app._dragged(SimpleNamespace(x=0.5, y=1.2))  # outside the disc: on the rim, straight up
    assert app.w_theta.value == pytest.approx(90.0) and app.w_phi.value == pytest.approx(90.0)


def test_brdfpy_explore_returns_the_notebook_layout() -> None:
    layout = brdfpy.explore(["lambert", "ward"], size=64)
    assert type(layout).__name__ == "Row"
