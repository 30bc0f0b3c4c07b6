"""A real headless browser on the explorer: start ``brdfpy explore`` as a subprocess on 127.0.0.1, drive
Debian's Chromium through chromedriver with Selenium, and read and change the page's Bokeh models from
JavaScript the way the page's own widgets do (a slider drag sets the slider model's ``value``, which the
browser sends to the server). Used by tests/test_explorer.py and benchmarks/bench_explore.py.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

CHROMIUM = next((p for p in ("/usr/bin/chromium", "/usr/bin/chromium-browser") if os.path.exists(p)), None)
DRIVER = shutil.which("chromedriver") or (
    "/usr/bin/chromedriver" if os.path.exists("/usr/bin/chromedriver") else None
)

# Helpers injected into the page: find Bokeh models by a property, read the status line.
JS = r"""
window.__models = () => Array.from(Bokeh.documents[0].all_models);
window.__title = (m) => { try { return m.title; } catch (e) { return undefined; } };
window.__by_title = (t) => __models().filter(m => __title(m) !== undefined
                                               && String(__title(m)).startsWith(t));
window.__text = (m) => { try { return m.text; } catch (e) { return undefined; } };
window.__texts = () => __models().map(__text).filter(t => typeof t === 'string');
window.__status = () => (__texts().find(s => s.includes('frame ')) || '');
window.__frame = () => { const m = /frame (\d+)/.exec(__status()); return m ? Number(m[1]) : -1; };
// A control of an EditableFloatSlider: its label is a Div, its box a Spinner, both in one small layout.
window.__kids = (m) => { try { return Array.from(m.children || []).map(c => Array.isArray(c) ? c[0] : c); }
                         catch (e) { return []; } };
window.__tree = (m, d) => d < 0 ? [] : [m, ...__kids(m).flatMap(c => __tree(c, d - 1))];
window.__control = (label, type) => {
  for (const m of __models()) {
    const sub = __tree(m, 3);
    const hasLabel = sub.some(x => typeof x.text === 'string' && x.text.startsWith(label));
    const target = sub.find(x => String(x.type).includes(type));
    if (__kids(m).length && hasLabel && target) return target;
  }
  return null;
};
window.__figure = (title) => __models().find(m => m.title && m.title.text !== undefined
                                               && String(m.title.text).startsWith(title));
window.__image_sum = (title) => {
  const f = __figure(title);
  const r = f.renderers[0];
  const img = r.data_source.data.image[0];
  let s = 0; const a = img.length !== undefined ? img : img.flat();
  for (let i = 0; i < a.length; i += 7) s = (s + a[i] * (i % 13 + 1)) % 1000000007;
  return s;
};
"""


def available() -> str | None:
    """Why the browser tests cannot run here, or ``None`` when they can."""
    if CHROMIUM is None or DRIVER is None:
        return "Debian's chromium and chromium-driver are missing (apt-get install chromium chromium-driver)"
    try:
        import panel  # noqa: F401
        import selenium  # noqa: F401
    except ImportError as e:
        return f"{e.name} is not installed (pip install 'brdfpy[explore]' selenium)"
    return None


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def server(models: str = "lambert", *, timeout: float = 60.0) -> Iterator[str]:
    """``brdfpy explore MODELS`` on a free port; yields its URL and stops it afterwards."""
    import tempfile

    port = free_port()
    cmd = [sys.executable, "-m", "brdfpy", "explore", models, "--port", str(port), "--no-browser"]
    # The server's log goes to a file (a pipe nobody reads would fill up and stall the server).
    log = tempfile.TemporaryFile(mode="w+")
    proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, text=True)
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout:
            if proc.poll() is not None:
                log.seek(0)
                raise RuntimeError(f"brdfpy explore exited: {log.read()}")
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=0.5):
                    break
            except OSError:
                time.sleep(0.2)
        else:
            raise RuntimeError("brdfpy explore did not start listening in time")
        yield f"http://127.0.0.1:{port}"
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(10)
        log.close()


@contextmanager
def browser(width: int = 1500, height: int = 1600) -> Iterator[Any]:
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service

    opts = Options()
    for a in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        f"--window-size={width},{height}",
    ):
        opts.add_argument(a)
    opts.binary_location = CHROMIUM or ""
    driver = webdriver.Chrome(service=Service(DRIVER or ""), options=opts)
    try:
        yield driver
    finally:
        driver.quit()


def open_page(driver: Any, url: str, timeout: float = 60.0) -> None:
    """Load the page and wait until the explorer has drawn its first frame."""
    driver.get(url)
    wait_for(
        driver,
        "return !!(window.Bokeh && Bokeh.documents.length && Bokeh.documents[0].roots().length)",
        timeout,
    )
    driver.execute_script(JS)
    wait_for(driver, "return __frame() >= 1", timeout)


def wait_for(driver: Any, script: str, timeout: float = 30.0) -> Any:
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        try:
            v = driver.execute_script(script)
        except Exception:  # the page is still loading its scripts
            v = None
        if v:
            return v
        time.sleep(0.02)
    raise TimeoutError(f"timed out waiting for: {script}")


def set_value(driver: Any, title: str, value: Any, kind: str | None = None) -> None:
    """Set the ``value`` of the first page model whose title starts with ``title`` (and, if given, whose
    type name contains ``kind``), as the widget itself does when it is moved; failing that, of the ``kind``
    control next to a label starting with ``title`` (a parameter's box)."""
    ok = driver.execute_script(
        "let ms = __by_title(arguments[0])"
        "  .filter(m => !arguments[2] || String(m.type).includes(arguments[2]));"
        "if (!ms.length && arguments[2]) {"
        "  const c = __control(arguments[0], arguments[2]); ms = c ? [c] : []; }"
        "if (!ms.length) return false; ms[0].value = arguments[1]; return true;",
        title,
        value,
        kind,
    )
    if not ok:
        raise LookupError(f"no page model titled {title!r}" + (f" of type {kind}" if kind else ""))


LATENCY_JS = r"""
const [title, value, kind] = [arguments[0], arguments[1], arguments[2]];
const done = arguments[arguments.length - 1];
let ms = __by_title(title).filter(m => String(m.type).includes(kind));
if (!ms.length) { const c = __control(title, kind); ms = c ? [c] : []; }
if (!ms.length) { done(-1); return; }
const sm = __models().find(m => typeof __text(m) === 'string' && __text(m).includes('frame '));
const frame = () => { const r = /frame (\d+)/.exec(sm.text); return r ? Number(r[1]) : -1; };
const before = frame();
const t0 = performance.now();
ms[0].value = value;
const poll = () => {
  if (frame() > before) { requestAnimationFrame(() => done(performance.now() - t0)); }
  else { setTimeout(poll, 1); }
};
poll();
"""


def latency_ms(driver: Any, title: str, value: Any, kind: str = "Slider") -> float:
    """Milliseconds from setting a control in the browser (the first page model titled ``title`` whose type
    contains ``kind``, else the ``kind`` control next to a label starting with ``title``, as
    :func:`set_value` finds it) until the page holds the redrawn views (the status line changes in the same
    message as the images) and the browser has painted the next frame."""
    driver.set_script_timeout(30)
    ms = float(driver.execute_async_script(LATENCY_JS, title, value, kind))
    if ms < 0:
        raise LookupError(f"no control {title!r} of type {kind}")
    return ms


BOX_JS = r"""
const f = __figure(arguments[0]);
let found = null;
const walk = (v) => { if (!v || found) return; if (v.model === f) { found = v; return; }
                      for (const c of (v.child_views || [])) walk(c); };
for (const v of Bokeh.index.all_views()) walk(v);
if (!found) return null;
const b = found.el.getBoundingClientRect();
return [b.left, b.top, b.width, b.height];
"""


def drag(driver: Any, figure_title: str, start: tuple[float, float], end: tuple[float, float]) -> None:
    """Drag the mouse over the plot area of the figure titled ``figure_title`` (its last ``width`` pixels of
    height are the square plot frame) from ``start`` to ``end``, in plot coordinates [0, 1]² (y up), through
    real pointer events."""
    from selenium.webdriver.common.actions.action_builder import ActionBuilder

    box = driver.execute_script(BOX_JS, figure_title)
    if box is None:
        raise LookupError(f"no figure titled {figure_title!r}")
    left, top, width, height = box
    frame_top = top + height - width

    def at(p: tuple[float, float]) -> tuple[int, int]:
        return round(left + p[0] * width), round(frame_top + (1 - p[1]) * width)

    actions = ActionBuilder(driver)
    actions.pointer_action.move_to_location(*at(start)).pointer_down()
    for k in range(1, 9):
        t = k / 8
        actions.pointer_action.move_to_location(
            *at((start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1])))
        )
    actions.pointer_action.pointer_up()
    actions.perform()
