"""The interactive BRDF explorer in the browser, on Panel (the optional extra ``brdfpy[explore]``).

A page in the spirit of Disney's BRDF Explorer (Burley 2012 §3): pick one or several registry models (overlaid
in distinct colours) or a measured MERL table, edit their parameters with controls generated from the registry
(:func:`brdfpy.model_info`: sliders over the documented ranges with their units, choices, colours, flags), set
the incidence by dragging on the lit sphere or with the sliders, and see every view of :mod:`brdfpy.views`
update live: the lit sphere, the in-plane polar slice, the 3D lobe (rendered by brdfpy's rasterizer), the
θ_h/θ_d image slice, the directional albedo, and the "lit object" (a built-in or uploaded mesh rendered by the
rasterizer in the active model).

- ``brdfpy explore`` (:func:`serve`) serves it on ``http://127.0.0.1:PORT`` only and opens the browser;
- ``brdfpy.explore(model)`` in a Jupyter notebook displays the same app inline (Panel's notebook mode).

Every control change is coalesced: while the views of one state are being computed, further changes only
update the state, and the views are redrawn once for the latest one, so dragging never queues stale work.
Invalid values (out of range, not finite, unknown names, a truncated table file) are refused by the library
and its message is shown on the page; the server keeps running. ``GET /api/view`` returns one view of one
model as PNG or JSON for scripts (HTTP 400 with the message for bad input).
"""

from __future__ import annotations

import io
import json
import math
import time
from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from brdfpy import tonemap, views
from brdfpy.camera import Camera
from brdfpy.lights import DirectionalLight
from brdfpy.measured import Tabulated
from brdfpy.mesh import BUILTIN_MESHES, Mesh, builtin_mesh, load_mesh, plane
from brdfpy.models import Model, model_info, models
from brdfpy.scene import Scene

try:
    import panel as _panel
    from bokeh import events as _events
    from bokeh import models as _bokeh_models
    from bokeh import plotting as _bokeh_plotting
    from bokeh.palettes import Category10_10, Magma256
except ImportError as e:  # pragma: no cover - exercised by the packaging
    raise ImportError(
        "the BRDF explorer needs Panel: pip install 'brdfpy[explore]' (or pip install panel)"
    ) from e

__all__ = ["Explorer", "notebook", "serve"]

# Panel's annotations are partial (most constructors are untyped) and Bokeh's property types are not what its
# constructors accept at run time (e.g. numbers for a Range1d), so mypy --strict sees both through Any.
pn: Any = _panel
events: Any = _events
figure: Any = _bokeh_plotting.figure
Range1d: Any = _bokeh_models.Range1d
ColumnDataSource: Any = _bokeh_models.ColumnDataSource

COLORS = list(Category10_10)
# A rotation of +90° about x (y → z): meshes built facing +y turned to the lobe's z-up frame.
_Y_UP_TO_Z_UP = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], dtype=np.float64)
_MAGMA = np.array([[int(c[k : k + 2], 16) for k in (1, 3, 5)] for c in Magma256], dtype=np.uint8)


def _widget(cls: Any, label: str, **params: Any) -> Any:
    """A Panel widget with its label: ``label=`` since Panel 1.9 (``name=`` is deprecated there), ``name=``
    before."""
    params["label" if "label" in cls.param else "name"] = label
    w = cls(**params)
    # Panel waits 50 ms (``Syncable._debounce``) before it processes a change from the browser, to coalesce
    # bursts. The explorer coalesces changes itself (one arriving while a frame is drawn is folded into the
    # next frame), so that wait is pure latency: a third of the 150 ms budget of an update. Composite
    # widgets (the editable slider) hold the widgets that receive the change.
    for x in [w, *w.select(pn.widgets.Widget)]:
        if isinstance(getattr(type(x), "_debounce", None), int):
            x._debounce = 0
    return w


def _rgba(rgb: NDArray[np.uint8]) -> NDArray[np.uint32]:
    """(H, W, 3) uint8 → Bokeh's packed RGBA (H, W) uint32, flipped so that row 0 is the bottom."""
    h, w, _ = rgb.shape
    out = np.empty((h, w, 4), dtype=np.uint8)
    out[..., :3] = rgb[::-1]
    out[..., 3] = 255
    return out.view(np.uint32).reshape(h, w)


def _hex(linear: Sequence[float]) -> str:
    c = tonemap.srgb_encode(np.clip(np.asarray(linear, dtype=np.float32), 0, 1))
    return "#" + "".join(f"{round(255 * float(x)):02x}" for x in c)


def _linear(hex_color: str) -> list[float]:
    s = hex_color.lstrip("#")
    if len(s) != 6:
        raise ValueError(f"colour: expected #rrggbb, got {hex_color!r}")
    srgb = np.array([int(s[k : k + 2], 16) / 255.0 for k in (0, 2, 4)], dtype=np.float32)
    return [round(float(x), 6) for x in tonemap.srgb_decode(srgb)]


class _Controls:
    """The parameter widgets of one model, generated from the registry."""

    def __init__(self, m: Model, on_change: Callable[[], None]) -> None:
        self.name = m.name
        self.widgets: dict[str, Any] = {}
        self.kinds: dict[str, str] = {}
        if m.name == "measured":
            return
        current = m.params
        for p in model_info(m.name)["params"]:
            name, kind, unit = p["name"], p["kind"], p["unit"]
            label = f"{name} [{unit}]" if unit and unit != "1" else name
            value = current.get(name, p["default"])
            w: Any
            if kind == "scalar":
                lo, hi = float(p["min"] or 0.0), float(p["max"] or 1.0)
                # A huge documented range (shininess to 10^4, Ashikhmin-Shirley exponents to 10^6) would make
                # the slider useless: it spans a practical range, and the box accepts any value (the library
                # refuses what is outside the documented range, and the page shows its message).
                end = hi if hi - lo <= 1000 else max(1000.0, 10 * float(value))
                end = min(end, hi)
                w = _widget(
                    pn.widgets.EditableFloatSlider,
                    label,
                    start=lo,
                    end=end,
                    value=float(value),
                    step=(end - lo) / 500 or 0.001,
                )
            elif kind == "color" and (p["max"] or 1.0) <= 1.0:
                w = _widget(pn.widgets.ColorPicker, f"{name} (sRGB picker, linear value)", value=_hex(value))
            elif kind in ("color", "array"):
                w = _widget(pn.widgets.TextInput, f"{label} (comma-separated)", value=json.dumps(value)[1:-1])
            elif kind == "choice":
                w = _widget(pn.widgets.Select, name, options=list(p["choices"] or ()), value=str(value))
            elif kind == "bool":
                w = _widget(pn.widgets.Checkbox, name, value=bool(value))
            else:  # pragma: no cover - a new kind in the registry
                continue
            w.param.watch(lambda _e: on_change(), "value")
            self.widgets[name] = w
            self.kinds[name] = kind

    def params(self) -> dict[str, Any]:
        """The widgets' values as model parameters (raises ValueError with the parameter named)."""
        out: dict[str, Any] = {}
        for name, w in self.widgets.items():
            kind, v = self.kinds[name], w.value
            if isinstance(w, pn.widgets.ColorPicker):
                out[name] = _linear(v)
            elif isinstance(w, pn.widgets.TextInput):
                try:
                    out[name] = json.loads(f"[{v}]")
                except json.JSONDecodeError:
                    raise ValueError(
                        f"parameter {name!r}: expected comma-separated numbers, got {v!r}"
                    ) from None
                if kind == "color" and len(out[name]) == 1:
                    out[name] = out[name][0]
            else:
                out[name] = v
        return out


class Explorer:
    """The explorer's state, widgets and views; :meth:`panel` is the page (served or shown in a notebook).

    Parameters
    ----------
    initial : models to start with (registry models, or measured tables as models)
    size : pixels of the square views (lit sphere, lit object, lobe, slice)
    """

    def __init__(self, initial: Sequence[Model] = (), *, size: int = 512) -> None:
        self.size = int(size)
        self.frame = 0
        self.last_ms = 0.0
        self.push_ms = 0.0
        self.tables: dict[str, Model] = {}
        self.controls: dict[str, _Controls] = {}
        self._pending = False
        self._busy = False
        self._cache: dict[Any, Any] = {}
        self._sent_albedo: dict[str, Any] = {}
        start = list(initial) or [Model("cook_torrance")]
        for m in start:
            if m.name == "measured":
                self.tables["measured"] = m
        names = [m.name for m in start]
        options = [*models(), *self.tables]
        self.w_models = _widget(pn.widgets.MultiChoice, "models (overlaid)", options=options, value=names)
        self.w_active = _widget(
            pn.widgets.Select, "active model (sphere, slice, object)", options=names, value=names[0]
        )
        self.w_theta = _widget(
            pn.widgets.FloatSlider, "θ_i [°] (incidence)", start=0.0, end=90.0, value=45.0, step=0.5
        )
        self.w_phi = _widget(
            pn.widgets.FloatSlider, "φ [°] (azimuth)", start=-180.0, end=180.0, value=0.0, step=1.0
        )
        self.w_cosine = _widget(pn.widgets.Checkbox, "polar and lobe × cos θ_o", value=True)
        self.w_log = _widget(pn.widgets.Checkbox, "polar: log radius", value=False)
        self.w_phi_d = _widget(
            pn.widgets.FloatSlider, "slice φ_d [°]", start=0.0, end=180.0, value=90.0, step=1.0
        )
        self.w_mesh = _widget(
            pn.widgets.Select,
            "lit object",
            options=list(BUILTIN_MESHES),
            value="garland_cow" if "garland_cow" in BUILTIN_MESHES else BUILTIN_MESHES[0],
        )
        self.w_upload_mesh = _widget(pn.widgets.FileInput, "your mesh", accept=".obj,.ply")
        self.w_upload_table = _widget(pn.widgets.FileInput, "measured table", accept=".binary")
        self.error = pn.pane.Alert("", alert_type="danger", visible=False, sizing_mode="stretch_width")
        self.status = pn.pane.Str("", name="status", css_classes=["brdfpy-status"])
        self.params_box = pn.Column(sizing_mode="stretch_width")
        self._mesh: Mesh = builtin_mesh(self.w_mesh.value)
        for m in start:
            self.controls[m.name] = _Controls(m, self.schedule)
        self._build_figures()
        for w in (self.w_theta, self.w_phi, self.w_cosine, self.w_log, self.w_phi_d, self.w_active):
            w.param.watch(lambda _e: self.schedule(), "value")
        self.w_models.param.watch(self._models_changed, "value")
        self.w_mesh.param.watch(self._mesh_changed, "value")
        self.w_upload_mesh.param.watch(self._mesh_uploaded, "value")
        self.w_upload_table.param.watch(self._table_uploaded, "value")
        self._refresh_params()
        self.update()

    # --- layout ---------------------------------------------------------------------------------------

    def _square(self, title: str, *, tools: str = "") -> Any:
        f = figure(
            title=title,
            frame_width=self.size,
            frame_height=self.size,
            tools=tools,
            toolbar_location=None,
            x_range=Range1d(0, 1, bounds=(0, 1)),
            y_range=Range1d(0, 1, bounds=(0, 1)),
            match_aspect=True,
        )
        f.axis.visible = False
        f.grid.visible = False
        f.min_border = 0
        return f

    def _build_figures(self) -> None:
        blank = np.zeros((2, 2), dtype=np.uint32)
        self.src_sphere = ColumnDataSource({"image": [blank]})
        self.fig_sphere = self._square("lit sphere (drag to move the light)", tools="pan,tap")
        self.fig_sphere.image_rgba("image", source=self.src_sphere, x=0, y=0, dw=1, dh=1)
        self.fig_sphere.on_event(events.Pan, self._dragged)
        self.fig_sphere.on_event(events.Tap, self._dragged)
        self.src_object = ColumnDataSource({"image": [blank]})
        self.fig_object = self._square("lit object (brdfpy rasterizer)")
        self.fig_object.image_rgba("image", source=self.src_object, x=0, y=0, dw=1, dh=1)
        self.src_lobe = ColumnDataSource({"image": [blank]})
        self.fig_lobe = self._square("3D lobe (brdfpy rasterizer)")
        self.fig_lobe.image_rgba("image", source=self.src_lobe, x=0, y=0, dw=1, dh=1)
        self.src_slice = ColumnDataSource({"image": [blank]})
        self.fig_slice = figure(
            title="θ_h/θ_d slice (log f_r)",
            width=self.size,
            height=self.size,
            tools="",
            toolbar_location=None,
            x_range=(0, 90),
            y_range=(0, 90),
        )
        self.fig_slice.image_rgba("image", source=self.src_slice, x=0, y=0, dw=90, dh=90)
        self.fig_slice.xaxis.axis_label = "θ_h [°]"
        self.fig_slice.yaxis.axis_label = "θ_d [°]"
        line: dict[str, list[Any]] = {"xs": [], "ys": [], "color": [], "label": []}
        self.src_polar = ColumnDataSource(dict(line))
        self.src_polar_dirs = ColumnDataSource({"xs": [], "ys": []})
        self.fig_polar = figure(
            title="in-plane slice",
            width=self.size,
            height=self.size // 2 + 60,
            tools="",
            toolbar_location=None,
            match_aspect=True,
        )
        self.fig_polar.multi_line(
            "xs", "ys", color="color", legend_field="label", source=self.src_polar, line_width=2
        )
        self.fig_polar.multi_line("xs", "ys", source=self.src_polar_dirs, color="grey", line_dash="dashed")
        self.fig_polar.xaxis.axis_label = "f_r sin θ_o [1/sr] (mirror side right)"
        self.fig_polar.yaxis.axis_label = "f_r cos θ_o [1/sr]"
        self.fig_polar.legend.location = "top_left"
        self.src_albedo = ColumnDataSource(dict(line))
        self.fig_albedo = figure(
            title="directional albedo",
            width=self.size,
            height=self.size // 2 + 60,
            tools="",
            toolbar_location=None,
            x_range=(0, 90),
        )
        self.fig_albedo.multi_line(
            "xs", "ys", color="color", legend_field="label", source=self.src_albedo, line_width=2
        )
        self.fig_albedo.xaxis.axis_label = "θ_i [°]"
        self.fig_albedo.yaxis.axis_label = "E(θ_i) [1]"
        self.fig_albedo.legend.location = "bottom_left"

    def panel(self) -> Any:
        """The page as a Panel layout (serve it, or display it in a notebook)."""
        sidebar = pn.Column(
            "## brdfpy explorer",
            self.w_models,
            self.w_active,
            self.w_theta,
            self.w_phi,
            self.w_cosine,
            self.w_log,
            self.w_phi_d,
            self.w_mesh,
            pn.Row("mesh:", self.w_upload_mesh),
            pn.Row("table:", self.w_upload_table),
            "### parameters",
            self.params_box,
            width=340,
        )
        views_ = pn.Column(
            self.error,
            pn.Row(pn.pane.Bokeh(self.fig_sphere), pn.pane.Bokeh(self.fig_object)),
            pn.Row(
                pn.Column(pn.pane.Bokeh(self.fig_polar), pn.pane.Bokeh(self.fig_albedo)),
                pn.pane.Bokeh(self.fig_lobe),
            ),
            pn.Row(pn.pane.Bokeh(self.fig_slice)),
            self.status,
        )
        return pn.Row(sidebar, views_)

    # --- events ---------------------------------------------------------------------------------------

    def _dragged(self, event: Any) -> None:
        # The point under the pointer on the sphere is where the light comes from (the brightest diffuse
        # point): l = (x, y, sqrt(1 − x² − y²)) in view space; outside the disc, on the rim.
        x, y = 2 * float(event.x) - 1, 2 * float(event.y) - 1
        r = math.hypot(x, y)
        if r > 1:
            x, y, r = x / r, y / r, 1.0
        theta = math.degrees(math.asin(min(r, 1.0)))
        phi = math.degrees(math.atan2(y, x)) if r > 0 else self.w_phi.value
        # One redraw for both (the watchers would schedule two otherwise; schedule() coalesces anyway).
        self.w_theta.value, self.w_phi.value = round(theta, 2), round(phi, 1)

    def _models_changed(self, _e: Any) -> None:
        names = list(self.w_models.value)
        for n in names:
            if n not in self.controls:
                self.controls[n] = _Controls(self.tables.get(n) or Model(n), self.schedule)
        self.w_active.options = names
        if names and self.w_active.value not in names:
            self.w_active.value = names[0]
        self._refresh_params()
        self.schedule()

    def _refresh_params(self) -> None:
        cards: list[Any] = []
        for n in self.w_models.value:
            c = self.controls.get(n)
            if c is None:
                continue
            body = list(c.widgets.values()) or [pn.pane.Markdown("(a measured table: no parameters)")]
            cards.append(pn.Card(*body, title=n, collapsed=len(cards) > 0, sizing_mode="stretch_width"))
        self.params_box.objects = cards

    def _mesh_changed(self, _e: Any) -> None:
        try:
            self._mesh = builtin_mesh(self.w_mesh.value)
        except ValueError as e:
            self._show_error(str(e))
            return
        self.schedule()

    def _mesh_uploaded(self, _e: Any) -> None:
        import os
        import tempfile

        data, name = self.w_upload_mesh.value, self.w_upload_mesh.filename or "mesh.obj"
        if not data:
            return
        suffix = os.path.splitext(name)[1].lower() or ".obj"
        try:
            with tempfile.NamedTemporaryFile(suffix=suffix, delete=False) as f:
                f.write(data)
            self._mesh = load_mesh(f.name)
        except (ValueError, OSError) as e:
            self._show_error(f"{name}: {e}")
            return
        finally:
            os.unlink(f.name)
        self.schedule()

    def _table_uploaded(self, _e: Any) -> None:
        data, name = self.w_upload_table.value, self.w_upload_table.filename or "table.binary"
        if not data:
            return
        try:
            m = Tabulated.from_merl_bytes(bytes(data)).as_model()
        except ValueError as e:
            self._show_error(f"{name}: {e}")
            return
        key = f"measured: {name}"
        self.tables[key] = m
        self.controls[key] = _Controls(m, self.schedule)
        self.w_models.options = [*models(), *self.tables]
        self.w_models.value = [*self.w_models.value, key]

    def load_table(self, key: str, m: Model) -> None:
        """Add a measured table (as a model) to the choices and select it."""
        self.tables[key] = m
        self.controls[key] = _Controls(m, self.schedule)
        self.w_models.options = [*models(), *self.tables]
        self.w_models.value = [*self.w_models.value, key]

    def _show_error(self, msg: str) -> None:
        self.error.object = msg
        self.error.visible = True

    # --- updates --------------------------------------------------------------------------------------

    def schedule(self) -> None:
        """Redraw for the current state: at once when idle, else once the running redraw has finished (the
        changes made meanwhile are coalesced into that one redraw)."""
        if self._busy:
            self._pending = True
            return
        doc = pn.state.curdoc
        if doc is not None and getattr(doc, "session_context", None) is not None and not self._pending:
            self._pending = True
            doc.add_next_tick_callback(self._tick)
        elif doc is None or getattr(doc, "session_context", None) is None:
            self.update()

    def _tick(self) -> None:
        self._pending = False
        self.update()
        if self._pending:  # changed while drawing
            self._pending = False
            doc = pn.state.curdoc
            if doc is not None:
                self._pending = True
                doc.add_next_tick_callback(self._tick)

    def current_models(self) -> list[Model]:
        """The selected models with the controls' parameters (ValueError with the library's message)."""
        out = []
        for n in self.w_models.value:
            if n in self.tables:
                out.append(self.tables[n])
            else:
                out.append(Model(n, **self.controls[n].params()))
        if not out:
            raise ValueError("models: select at least one model")
        return out

    def update(self) -> None:
        """Compute every view for the current state and push them to the page."""
        self._busy = True
        t0 = time.perf_counter()
        try:
            ms = self.current_models()
            names = list(self.w_models.value)
            active = ms[names.index(self.w_active.value)] if self.w_active.value in names else ms[0]
            data = self._compute(ms, names, active)
        except (ValueError, TypeError) as e:
            self._show_error(str(e))
            self.frame += 1
            self.status.object = f"frame {self.frame}: refused ({e})"
            self._busy = False
            return
        # One message to the browser for all the views (Panel's hold batches the model changes).
        with pn.io.hold():
            self.error.visible = False
            self.src_sphere.data = {"image": [data["sphere"]]}
            self.src_object.data = {"image": [data["object"]]}
            self.src_lobe.data = {"image": [data["lobe"]]}
            # Unchanged (cached) images are not sent again.
            if self.src_slice.data["image"][0] is not data["slice"]:
                self.src_slice.data = {"image": [data["slice"]]}
            self.src_polar.data = data["polar"]
            self.src_polar_dirs.data = data["polar_dirs"]
            if data["albedo"] != self._sent_albedo:
                self.src_albedo.data = data["albedo"]
                self._sent_albedo = data["albedo"]
            self.last_ms = 1e3 * (time.perf_counter() - t0)
            self.frame += 1
            self.status.object = (
                f"frame {self.frame}: {self.last_ms:.0f} ms (sending the previous one: {self.push_ms:.0f} ms)"
            )
        # Leaving hold() serialises the changes and hands them to the websocket.
        self.push_ms = 1e3 * (time.perf_counter() - t0) - self.last_ms
        self._busy = False

    def _compute(self, ms: list[Model], names: list[str], active: Model) -> dict[str, Any]:
        t, p = float(self.w_theta.value), float(self.w_phi.value)
        cosine = bool(self.w_cosine.value)
        colors = [COLORS[k % len(COLORS)] for k in range(len(ms))]
        out: dict[str, Any] = {}
        img = views.lit_sphere(active, theta_i=t, phi=p, size=self.size, background=0.02)
        out["sphere"] = _rgba(img.rgb)
        polars = views.polar(ms, t, phi=p, n=361, cosine=cosine)
        xs, ys = [], []
        top = max(float(pl.luminance[np.abs(pl.theta_o) <= 85].max()) for pl in polars) or 1.0
        for pl in polars:
            r = pl.luminance.astype(np.float64)
            if self.w_log.value:
                floor = top * 1e-4
                r = np.log10(np.maximum(r, floor) / floor) / 4 * top
            r = np.minimum(r, 1.5 * top)
            th = np.radians(pl.theta_o)
            xs.append((r * np.sin(th)).tolist())
            ys.append((r * np.cos(th)).tolist())
        out["polar"] = {"xs": xs, "ys": ys, "color": colors, "label": names}
        ti = math.radians(t)
        out["polar_dirs"] = {
            "xs": [[0.0, -top * math.sin(ti)], [0.0, top * math.sin(ti)]],
            "ys": [[0.0, top * math.cos(ti)], [0.0, top * math.cos(ti)]],
        }
        # The albedo curves and the slice do not depend on the incidence: computed once per model state.
        keys = [f"{n}:{m!r}" for n, m in zip(names, ms)]
        grid = np.linspace(0.0, 88.0, 23)
        alb = [self._cached(("albedo", k), partial(views.albedo, m, grid)) for k, m in zip(keys, ms)]
        out["albedo"] = {
            "xs": [a.theta_i.tolist() for a in alb],
            "ys": [a.luminance.tolist() for a in alb],
            "color": colors,
            "label": names,
        }
        phi_d = float(self.w_phi_d.value)
        akey = keys[ms.index(active)] if active in ms else repr(active)
        out["slice"] = self._cached(("slice", akey, phi_d), partial(self._slice_image, active, phi_d))
        out["lobe"] = self._lobe_image(ms, t, p, cosine, colors)
        out["object"] = self._object_image(active, t, p)
        return out

    def _slice_image(self, m: Model, phi_d: float) -> NDArray[np.uint32]:
        s = views.half_diff_slice(m, phi_d=phi_d, size=self.size // 2)
        lum = s.luminance
        lo, hi = s.log_range(lum)
        if hi > 0:
            k = np.clip(np.log10(np.maximum(lum, lo) / lo) / math.log10(hi / lo), 0, 1)
        else:
            k = np.zeros_like(lum)
        rgb = _MAGMA[(k * 255).astype(np.int64)]
        rgb[~s.valid] = 150
        return _rgba(rgb[::-1])  # _rgba flips for Bokeh; the slice's row 0 is already θ_d = 0

    def _cached(self, key: Any, make: Callable[[], Any]) -> Any:
        if key not in self._cache:
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[key] = make()
        return self._cache[key]

    def _lobe_image(
        self, ms: list[Model], t: float, p: float, cosine: bool, colors: list[str]
    ) -> NDArray[np.uint32]:
        lobes = views.lobe(ms, t, phi=p, n_theta=48, n_phi=96, radius="f_cos" if cosine else "f")
        # As in the polar plot, the scale comes from directions at least 5° above the horizon, and radii
        # beyond 1.5 times it are cut (Ward's f_r grows without bound toward grazing).
        above = lobes[0].directions[:, 2] >= math.cos(math.radians(85.0))
        extent = max(float(lb.radii[above].max()) for lb in lobes) or 1.0
        scene = Scene(ambient_light=0.12, background=0.02)
        # The surface the lobe stands on (plane() faces +y: turned to face +z), for a sense of up and scale.
        scene.add(plane(2.0).transformed(_Y_UP_TO_Z_UP), Model("lambert", kd=0.12), ambient=0.12)
        for lb, c in zip(lobes, colors):
            albedo = _linear(c)
            r = np.minimum(lb.radii, 1.5 * extent) / extent
            mesh = Mesh(lb.directions * r[:, None], lb.mesh.faces)
            scene.add(mesh, Model("lambert", kd=albedo))  # ambient: its albedo under the sky
        # A key light from the upper left of the camera: a light from behind the camera left the lobes
        # evenly lit, flat discs of colour with no sense of their shape.
        scene.add_light(DirectionalLight((1.0, 1.0, -1.2), color=2.2))
        cam = Camera.perspective((1.6, -2.6, 1.5), (0.0, 0.0, 0.35), up=(0, 0, 1), fovy=40)
        size = self.size * 3 // 4
        img = scene.render(cam, size, size, cull_back_faces=False)
        return _rgba(img.rgb)

    def _object_image(self, m: Model, t: float, p: float) -> NDArray[np.uint32]:
        mesh = self._mesh
        centre, radius = mesh.bounding_sphere()
        cam = Camera.framing(centre, radius, direction=(0.0, 0.3, 1.0))
        # The light in view space (as on the sphere), turned into world space with the camera's basis.
        view = np.asarray(cam.view_matrix(), dtype=np.float64)[:3, :3]
        l_view = np.array(
            [
                math.sin(math.radians(t)) * math.cos(math.radians(p)),
                math.sin(math.radians(t)) * math.sin(math.radians(p)),
                math.cos(math.radians(t)),
            ]
        )
        l_world = view.T @ l_view
        scene = Scene(ambient_light=0.05, background=0.02)
        # The sky of the lit sphere: what the model reflects under uniform radiance 0.05 (its white-sky
        # albedo), so metals keep their colour on the unlit side.
        scene.add(mesh, m)
        scene.add_light(DirectionalLight(-l_world, color=math.pi if m.physical else 1.0))
        img = scene.render(cam, self.size, self.size, outputs=("hdr", "depth"))
        # The views' "auto" tone map: extended Reinhard, white point at the object's peak (at least 1).
        lit = img.hdr[img.mask]
        white = max(1.0, float(lit.max()) if lit.size else 1.0)
        return _rgba(img.tonemapped("reinhard_extended", white=white))


def _api_handler() -> Any:
    """``GET /api/view?model=NAME&view=sphere|polar|albedo|slice&theta_i=DEG&phi=DEG&KEY=VALUE...``: one view
    of one model, PNG for images and JSON for curves; HTTP 400 with ``{"error": message}`` for bad input."""
    from tornado.web import RequestHandler

    from brdfpy.render_cmd import parse_value

    class ViewHandler(RequestHandler):
        def get(self) -> None:
            args = {k: self.get_argument(k) for k in self.request.arguments}
            try:
                name = args.pop("model", "cook_torrance")
                view = args.pop("view", "sphere")
                theta = float(args.pop("theta_i", "45"))
                phi = float(args.pop("phi", "0"))
                size = int(args.pop("size", "256"))
                m = Model(name, **{k: parse_value(v) for k, v in args.items()})
                if view == "sphere":
                    img = views.lit_sphere(m, theta_i=theta, phi=phi, size=size)
                    buf = io.BytesIO()
                    img.to_pil().save(buf, format="PNG")
                    self.set_header("Content-Type", "image/png")
                    self.write(buf.getvalue())
                    return
                if view == "polar":
                    pl = views.polar(m, theta, phi=phi)
                    body = {"theta_o": pl.theta_o.tolist(), "values": pl.values.tolist()}
                elif view == "albedo":
                    a = views.albedo(m)
                    body = {"theta_i": a.theta_i.tolist(), "values": a.values.tolist()}
                elif view == "slice":
                    s = views.half_diff_slice(m, size=min(size, 256))
                    body = {
                        "theta_h": s.theta_h.tolist(),
                        "theta_d": s.theta_d.tolist(),
                        "luminance": s.luminance.tolist(),
                    }
                else:
                    raise ValueError(f"view: expected sphere, polar, albedo or slice, got {view!r}")
                self.set_header("Content-Type", "application/json")
                self.write(json.dumps(body))
            except (ValueError, TypeError) as e:
                self.set_status(400)
                self.set_header("Content-Type", "application/json")
                self.write(json.dumps({"error": str(e)}))

    return ViewHandler


def free_port() -> int:
    """A TCP port on 127.0.0.1 that is free now."""
    import socket

    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def serve(initial: Sequence[Model] = (), *, port: int = 0, show: bool = True, size: int = 512) -> Any:
    """Serve the explorer on ``http://127.0.0.1:port`` (0: a free port) until interrupted; every browser
    session gets its own :class:`Explorer`. Returns when the server stops."""
    port = port or free_port()

    def app() -> Any:
        return Explorer(initial, size=size).panel()

    return pn.serve(
        {"/": app},
        address="127.0.0.1",
        port=port,
        show=show,
        title="brdfpy explorer",
        websocket_origin=[f"127.0.0.1:{port}", f"localhost:{port}"],
        extra_patterns=[(r"/api/view", _api_handler())],
        threaded=False,
        print_url=True,
    )


def notebook(initial: Sequence[Model] = (), *, size: int = 512) -> Any:
    """The explorer as a Panel layout for a Jupyter notebook (display it, e.g. as a cell's last value)."""
    pn.extension()
    return Explorer(initial, size=size).panel()
