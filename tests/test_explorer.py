"""The explorer in a real headless browser (Debian's Chromium through Selenium, tests/browser.py) against
``brdfpy explore`` run as a user runs it: the page loads, lists every model, moving a slider changes the
image, an out-of-range value shows the library's message, two models overlay, and the server survives bad
input (HTTP 400 from its view endpoint, the page still served).

On CI (``CI=true``) these must run: scripts/test.sh installs Chromium, chromium-driver and the extras.
Elsewhere they are skipped, with the reason, when the browser or the extras are missing.
"""

from __future__ import annotations

import json
import os
import urllib.error
import urllib.request

import brdfpy
import pytest

import browser as B

_missing = B.available()
if _missing and os.environ.get("CI") == "true":
    raise RuntimeError(f"the browser tests must run on CI, but {_missing}; see scripts/test.sh")
pytestmark = pytest.mark.skipif(_missing is not None, reason=f"browser tests skipped: {_missing}")


@pytest.fixture(scope="module")
def page():
    with B.server("lambert") as url, B.browser() as driver:
        B.open_page(driver, url)
        yield url, driver


def _frame(driver) -> int:
    return int(driver.execute_script("return __frame()"))


def _wait_frame_after(driver, before: int) -> None:
    B.wait_for(driver, f"return __frame() > {before}", 30)


def test_the_page_loads_and_lists_every_model(page) -> None:
    _, d = page
    assert d.title == "brdfpy explorer"
    options = d.execute_script("return __by_title('models')[0].options")
    names = [o if isinstance(o, str) else o[0] for o in options]
    assert set(brdfpy.models()) <= set(names)
    assert "frame" in d.execute_script("return __status()")


def test_moving_a_slider_changes_the_image(page) -> None:
    _, d = page
    before = d.execute_script("return __image_sum('lit sphere')")
    frame = _frame(d)
    B.set_value(d, "θ_i", 70.0, "Slider")
    _wait_frame_after(d, frame)
    after = d.execute_script("return __image_sum('lit sphere')")
    assert after != before
    frame = _frame(d)
    B.set_value(d, "φ", -120.0, "Slider")
    _wait_frame_after(d, frame)
    assert d.execute_script("return __image_sum('lit sphere')") != after


def test_dragging_on_the_lit_sphere_moves_the_light(page) -> None:
    _, d = page
    frame = _frame(d)
    # From the centre to half-way to the right rim: the light at x = 0.5 on the unit disc, θ_i = 30°, φ = 0.
    B.drag(d, "lit sphere", (0.5, 0.5), (0.75, 0.5))
    _wait_frame_after(d, frame)
    B.wait_for(d, "return Math.abs(__by_title('θ_i')[0].value - 30) < 1.5", 10)
    assert abs(d.execute_script("return __by_title('φ')[0].value")) < 2


def test_an_out_of_range_value_shows_the_librarys_message_and_the_page_recovers(page) -> None:
    _, d = page
    frame = _frame(d)
    B.set_value(d, "models", ["lambert", "cook_torrance"])
    _wait_frame_after(d, frame)
    frame = _frame(d)
    # The box of the roughness slider accepts any number; the library refuses 5 (range [0, 2]).
    B.set_value(d, "roughness [", 5.0, "Spinner")
    _wait_frame_after(d, frame)
    B.wait_for(d, "return __texts().some(t => t.includes('roughness') && t.includes('[0, 2]'))", 10)
    assert "refused" in d.execute_script("return __status()")
    frame = _frame(d)
    B.set_value(d, "roughness [", 0.2, "Spinner")
    _wait_frame_after(d, frame)
    assert "refused" not in d.execute_script("return __status()")


def test_two_models_overlay_in_distinct_colours(page) -> None:
    _, d = page
    frame = _frame(d)
    B.set_value(d, "models", ["lambert", "phong"])
    _wait_frame_after(d, frame)
    data = d.execute_script(
        "const f = __figure('in-plane slice'); const s = f.renderers[0].data_source.data;"
        "return {labels: Array.from(s.label), colors: Array.from(s.color), n: s.xs.length};"
    )
    assert data["labels"] == ["lambert", "phong"] and data["n"] == 2
    assert len(set(data["colors"])) == 2


def test_the_server_refuses_bad_requests_and_stays_up(page) -> None:
    url, _ = page
    for query, words in [
        ("model=nope", "unknown model"),
        ("model=lambert&view=polar&theta_i=95", "theta_i"),
        ("model=cook_torrance&roughness=nan", "roughness"),
        ("model=lambert&view=radar", "view"),
    ]:
        with pytest.raises(urllib.error.HTTPError) as e:
            urllib.request.urlopen(f"{url}/api/view?{query}", timeout=30)
        assert e.value.code == 400
        assert words in json.loads(e.value.read())["error"]
    with urllib.request.urlopen(f"{url}/api/view?model=phong&view=polar&theta_i=30", timeout=30) as r:
        body = json.loads(r.read())
    assert len(body["theta_o"]) == 360
    with urllib.request.urlopen(url, timeout=30) as r:
        assert r.status == 200
