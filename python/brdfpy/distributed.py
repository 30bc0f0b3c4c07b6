"""brdfpy past one machine: batch evaluation on Dask arrays, many renders and many fits on a Dask cluster.

Needs the optional extra ``brdfpy[dask]`` (``dask[array]`` and ``distributed``); ``import brdfpy`` does not
import this module or Dask. The same calls run on a laptop (a ``distributed.LocalCluster`` of worker
processes, started for the call when no client is given) and on any Dask deployment (pass its ``Client``).

- :func:`eval` / :func:`shade`: ``Model.eval`` / ``Model.shade`` over Dask arrays of rows ``(N, 3)``, lazy and
  chunk by chunk, so inputs and outputs can live in Zarr stores or NumPy memmaps larger than memory. Each
  chunk gives the bits the local call gives for those rows.
- :func:`render_many`: render a list of jobs (scene, camera, options) or a sweep spec on the cluster, write
  each frame (PNG, and EXR or NPZ when asked) and a manifest, resumably.
- :func:`fit_many`: fit one model to each of many measured tables (:func:`brdfpy.measured.fit`) in parallel.

What crosses the network per task (measured by ``benchmarks/bench_dask.py``): a scene is sent to every
worker once (``client.scatter(..., broadcast=True)``), then each render task carries its camera, options,
per-job material overrides and a reference to the scene — a few hundred bytes — and returns its encoded
files to the client, which alone writes the output folder (the workers need no shared file system).

Files are written atomically: to a temporary file in the output folder, flushed to disk, then renamed over
the final name; the manifest likewise. A frame is entered into the manifest only after its file is
complete, so a killed worker (its task is re-run by Dask elsewhere), a killed client or a full disk never
leaves a truncated frame or a manifest naming a missing or different file. Every byte goes through
:func:`_write_bytes`, the one place to inject failures in tests (``tests/test_distributed.py`` simulates a
disk that fills up this way).
"""

# dask and distributed ship partial annotations (many functions untyped): calls into them are allowed here.
# mypy: disallow-untyped-calls=False

from __future__ import annotations

import concurrent.futures
import contextlib
import copy
import dataclasses
import datetime
import functools
import hashlib
import inspect
import io
import json
import math
import os
import pickle
import re
import socket
import threading
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypedDict, Union

import numpy as np

try:
    import dask
    import dask.array as da
    import distributed
    from distributed.diagnostics.plugin import WorkerPlugin
    from distributed.protocol import pickle as dask_pickle
except ImportError as _err:  # pragma: no cover - exercised only without the extra
    raise ImportError(
        "brdfpy.distributed needs the optional extra brdfpy[dask]: pip install 'brdfpy[dask]' "
        f"(dask[array] and distributed); {_err}"
    ) from _err

from brdfpy import __version__, _brdfpy
from brdfpy.camera import Camera
from brdfpy.image import Image
from brdfpy.measured import Tabulated, fit
from brdfpy.models import Model, model, models
from brdfpy.scene import OUTPUTS, SHADING_MODES, TONEMAPS, Scene
from brdfpy.sweep import FORMATS, Sweep, load_spec

if TYPE_CHECKING:
    from numpy.typing import NDArray

__all__ = [
    "FitRow",
    "Job",
    "JobsFailed",
    "RenderReport",
    "eval",
    "fit_many",
    "local_cluster",
    "render_many",
    "shade",
]

#: Rows per chunk when NumPy rows must be cut into chunks (no Dask argument says how).
DEFAULT_CHUNK_ROWS = 1 << 20

#: Name of the manifest in the output folder.
MANIFEST = "manifest.json"

#: Scene.render keyword arguments a job may set (``progress`` runs on the worker: refused).
RENDER_OPTIONS = tuple(
    p for p in inspect.signature(Scene.render).parameters if p not in ("self", "camera", "progress")
)

#: Instance attributes a job may override (on the worker, on a copy of the scene).
INSTANCE_FIELDS = ("material", "ambient", "emission", "transform")

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,199}$")


# -- evaluation on Dask arrays ----------------------------------------------------------------------------


def eval(
    model: Model,
    l: Any,
    v: Any,
    n: Any,
    tangent: Any = None,
    *,
    rechunk: bool = True,
) -> da.Array:
    """:meth:`brdfpy.Model.eval` over Dask arrays: a lazy float32 Dask array of shape ``(N, 3)``.

    Parameters
    ----------
    model : brdfpy.Model
        Sent once into the graph (one task every chunk depends on), not once per chunk.
    l, v, n : dask.array.Array of shape (N, 3), NumPy rows (N, 3), or one direction (3,)
        Dask arrays may have any chunking along the rows but must hold the 3 components in one chunk
        (chunks ``(k, 3)``). A single ``(3,)`` direction is used for every row.
    tangent : like ``l``, optional
        For anisotropic models.
    rechunk : bool
        Dask arguments whose row chunks differ from the first Dask argument's are rechunked to match it
        (default); with ``False`` they are refused.

    Each output chunk is ``model.eval`` of the rows of that chunk, so the result has the bits of the local
    call on the whole arrays. To stream through storage larger than memory, read with
    ``da.from_zarr`` / ``da.from_array(np.memmap(...))`` and write with ``result.to_zarr(...)`` or
    ``da.store(result, np.memmap(..., mode="w+"))`` (a memmap target only with the local schedulers).

    Raises
    ------
    ValueError
        Wrong shapes, components split across chunks, unknown chunk sizes, row counts that differ, or row
        chunks that differ with ``rechunk=False`` (the message names the argument).
    TypeError
        ``model`` not a :class:`brdfpy.Model`.
    """
    return _map_rows(model, l, v, n, tangent, shade=False, rechunk=rechunk)


def shade(
    model: Model,
    l: Any,
    v: Any,
    n: Any,
    tangent: Any = None,
    *,
    rechunk: bool = True,
) -> da.Array:
    """:meth:`brdfpy.Model.shade` over Dask arrays; arguments and errors as for :func:`eval`."""
    return _map_rows(model, l, v, n, tangent, shade=True, rechunk=rechunk)


def _eval_block(
    m: Model,
    shade: bool,
    l: NDArray[Any],
    v: NDArray[Any],
    n: NDArray[Any],
    t: NDArray[Any] | None,
    block_info: dict[Any, Any] | None = None,
) -> NDArray[np.float32]:
    try:
        return m.shade(l, v, n, t) if shade else m.eval(l, v, n, t)
    except ValueError as err:
        # The library names the row within this chunk; say which row of the whole array that is.
        start = int(block_info[None]["array-location"][0][0]) if block_info else 0
        msg = re.sub(r"\b(l|v|n|tangent)\[(\d+)\]", lambda g: f"{g[1]}[{start + int(g[2])}]", str(err))
        raise ValueError(msg) from None


def _map_rows(model: Any, l: Any, v: Any, n: Any, tangent: Any, *, shade: bool, rechunk: bool) -> da.Array:
    if not isinstance(model, _brdfpy.Model):
        raise TypeError(
            f"model: expected a brdfpy.Model (from brdfpy.model(...)), got {type(model).__name__}"
        )
    named = {"l": l, "v": v, "n": n, "tangent": tangent}
    ref: tuple[str, int, tuple[int, ...]] | None = None  # name, rows, row chunks of the first Dask argument
    rows_np: list[tuple[str, NDArray[Any]]] = []
    for name, x in named.items():
        if x is None:
            continue
        if isinstance(x, da.Array):
            if x.ndim != 2 or x.shape[1] != 3:
                raise ValueError(f"{name}: expected a Dask array of shape (N, 3), got shape {x.shape}")
            if any(math.isnan(c) for c in x.chunks[0]):
                raise ValueError(f"{name}: has unknown chunk sizes; call {name}.compute_chunk_sizes() first")
            if x.chunks[1] != (3,):
                raise ValueError(
                    f"{name}: each chunk must hold whole rows of 3 components (chunks (k, 3)), got chunks "
                    f"{x.chunks[1]} along the last axis; use {name}.rechunk({{1: 3}})"
                )
            if ref is None:
                ref = (name, int(x.shape[0]), tuple(int(c) for c in x.chunks[0]))
            elif x.shape[0] != ref[1]:
                raise ValueError(f"{name}: has {x.shape[0]} rows, {ref[0]} has {ref[1]}")
        else:
            a = np.asarray(x)
            if a.dtype.kind not in "fiu":
                raise TypeError(f"{name}: expected real numbers, got dtype {a.dtype}")
            if a.shape != (3,) and (a.ndim != 2 or a.shape[1] != 3):
                raise ValueError(f"{name}: expected shape (N, 3) or (3,), got {a.shape}")
            if a.ndim == 2:
                rows_np.append((name, a))
    if ref is None:
        if not rows_np:
            raise ValueError("l, v, n: no argument has rows; use Model.eval for single directions")
        first_name, first = rows_np[0]
        k = first.shape[0]
        chunks = tuple(min(DEFAULT_CHUNK_ROWS, k - i) for i in range(0, k, DEFAULT_CHUNK_ROWS))
        ref = (first_name, k, chunks)
    ref_name, n_rows, ref_chunks = ref
    args: list[Any] = []
    for name, x in named.items():
        if x is None:
            args.append(None)
        elif isinstance(x, da.Array):
            if tuple(x.chunks[0]) != ref_chunks:
                if not rechunk:
                    raise ValueError(
                        f"{name}: row chunks {x.chunks[0][:4]}... differ from {ref_name}'s "
                        f"{ref_chunks[:4]}...; "
                        f"rechunk them alike or pass rechunk=True"
                    )
                x = x.rechunk({0: ref_chunks})
            args.append(x)
        else:
            a = np.asarray(x)
            if a.ndim == 2:
                if a.shape[0] != n_rows:
                    raise ValueError(f"{name}: has {a.shape[0]} rows, {ref_name} has {n_rows}")
                args.append(da.from_array(a, chunks=(ref_chunks, 3)))
            else:
                args.append(a.astype(np.float32))
    # The model enters the graph once as its own task; every chunk depends on it (Dask ships it to each
    # worker once, not once per chunk).
    m = dask.delayed(model, pure=True, traverse=False)  # type: ignore[attr-defined]  # lazily exported
    out: da.Array = da.map_blocks(
        _eval_block,
        m,
        shade,
        *args,
        dtype=np.float32,
        chunks=(ref_chunks, (3,)),
        meta=np.empty((0, 3), dtype=np.float32),
        token=f"brdfpy-{'shade' if shade else 'eval'}",  # a prefix: the key gets a hash of the inputs
    )
    return out


# -- clients and workers ---------------------------------------------------------------------------


class _Threads(WorkerPlugin):
    """Gives each worker process as many brdfpy threads as it runs tasks at once (default: the machine's
    cores in every process, which oversubscribes a machine running one worker process per core)."""

    name = "brdfpy-threads"

    def setup(self, worker: Any) -> None:
        import brdfpy

        brdfpy.set_num_threads(max(1, int(worker.state.nthreads)))


def local_cluster(
    workers: int | None = None, *, threads_per_worker: int = 1, **kwargs: Any
) -> distributed.LocalCluster:
    """A ``distributed.LocalCluster`` of ``workers`` worker **processes** (default: one per core) with
    ``threads_per_worker`` threads each; extra keyword arguments go to ``LocalCluster``."""
    n = (os.cpu_count() or 1) if workers is None else workers
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValueError(f"workers: expected a positive integer, got {workers!r}")
    kwargs.setdefault("dashboard_address", ":0")
    return distributed.LocalCluster(
        n_workers=n, threads_per_worker=threads_per_worker, processes=True, **kwargs
    )


@contextlib.contextmanager
def _client(client: distributed.Client | None) -> Iterator[distributed.Client]:
    """``client``, else the default client, else a temporary local cluster of processes for this call."""
    if client is not None:
        yield client
        return
    try:
        yield distributed.default_client()
        return
    except ValueError:
        pass
    with local_cluster(dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def _prepare_workers(client: distributed.Client) -> None:
    client.register_plugin(_Threads(), name=_Threads.name)


def _check_picklable(where: str, obj: Any) -> bytes:
    """``obj`` as Dask will send it (cloudpickle), or a ``TypeError`` naming ``where``."""
    try:
        data: bytes = dask_pickle.dumps(obj)
    except Exception as err:
        raise TypeError(
            f"{where}: cannot be sent to a worker ({type(err).__name__}: {err}); use objects that pickle "
            "(module-level functions, no open files, locks or generators in closures)"
        ) from None
    return data


# -- writing files ---------------------------------------------------------------------------------


def _write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically: a temporary file next to it, flushed to disk, renamed over
    ``path`` (readers see the old file or the new one, never a part). Every file this module writes goes
    through here."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}-{threading.get_ident()}")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def _check_folder(out: str | os.PathLike[str]) -> Path:
    path = Path(out)
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".brdfpy-write-test-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as err:
        raise OSError(f"out: cannot write in {str(path)!r}: {err.strerror or err}") from None
    # Temporary files of an earlier run that was killed mid-write.
    for stale in path.glob(".*.tmp-*"):
        with contextlib.suppress(OSError):
            stale.unlink()
    return path


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


# -- render_many -----------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Job:
    """One frame to render.

    Attributes
    ----------
    scene : Scene, or a callable returning one
        A callable (module-level function or any picklable callable) builds the scene on the worker.
    camera : Camera
    options : dict
        Keyword arguments of :meth:`brdfpy.Scene.render` (``width``, ``height``, ``shading``, ``samples``,
        ``ao``, ``shadows``, ``tonemap``, ...; not ``progress``).
    name : str, optional
        File name without extension (letters, digits, ``.``, ``_``, ``-``); default ``frame_00000``...
    params : dict
        What the manifest records for this frame (JSON values).
    instances : dict
        Per-instance overrides ``{index: {"material": Model, "ambient": ..., "emission": ..., "transform":
        ...}}``, applied on the worker to a copy of the scene: many jobs can share one scene (sent once)
        and differ in materials or placement.
    """

    scene: Scene | Callable[[], Scene]
    camera: Camera
    options: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    name: str | None = None
    params: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    instances: Mapping[int, Mapping[str, Any]] = dataclasses.field(default_factory=dict)


JobLike = Union[Job, Mapping[str, Any], Sequence[Any]]


@dataclasses.dataclass
class RenderReport:
    """What :func:`render_many` did: the frames ``rendered`` now, ``skipped`` (already in the manifest with
    the right files), ``failed`` (name → reason), the ``manifest`` path and the wall time ``seconds``."""

    out: Path
    manifest: Path
    rendered: list[str]
    skipped: list[str]
    failed: dict[str, str]
    seconds: float


class JobsFailed(RuntimeError):
    """Some jobs raised; the others finished and are in the manifest. ``report`` (render) or ``results``
    (fits) holds everything."""

    def __init__(self, message: str, report: Any) -> None:
        super().__init__(message)
        self.report = report


def _as_job(i: int, j: Any) -> Job:
    where = f"jobs[{i}]"
    if isinstance(j, Job):
        return j
    if isinstance(j, Mapping):
        unknown = set(j) - {f.name for f in dataclasses.fields(Job)}
        if unknown:
            raise ValueError(
                f"{where}: unknown field {sorted(unknown)[0]!r}; a job has scene, camera, options, name, "
                "params, instances"
            )
        if "scene" not in j or "camera" not in j:
            raise ValueError(f"{where}: needs 'scene' and 'camera'")
        return Job(**j)
    if isinstance(j, Sequence) and not isinstance(j, str) and len(j) in (2, 3):
        return Job(j[0], j[1], j[2] if len(j) == 3 else {})
    raise TypeError(
        f"{where}: expected a Job, a dict or a (scene, camera, options) tuple, got {type(j).__name__}"
    )


def _check_options(where: str, opts: Mapping[str, Any]) -> dict[str, Any]:
    if not isinstance(opts, Mapping):
        raise TypeError(f"{where}: expected a dict of Scene.render options, got {type(opts).__name__}")
    out = dict(opts)
    for key in out:
        if key == "progress":
            raise ValueError(
                f"{where}.progress: a progress callback would run on the worker; render_many shows Dask's "
                "progress bar"
            )
        if key not in RENDER_OPTIONS:
            raise ValueError(f"{where}.{key}: unknown option; Scene.render takes {', '.join(RENDER_OPTIONS)}")
    for key in ("width", "height"):
        x = out.get(key, 1)
        if isinstance(x, bool) or not isinstance(x, (int, np.integer)) or not 1 <= int(x) <= 16384:
            raise ValueError(f"{where}.{key}: expected an integer in [1, 16384], got {x!r}")
    if out.get("shading", "phong") not in SHADING_MODES:
        raise ValueError(
            f"{where}.shading: expected one of {', '.join(SHADING_MODES)}, got {out['shading']!r}"
        )
    tm = out.get("tonemap", "clamp")
    if not isinstance(tm, str) or tm.lower() not in TONEMAPS:
        raise ValueError(f"{where}.tonemap: expected one of {', '.join(TONEMAPS)}, got {tm!r}")
    if out.get("samples", 1) not in (1, 4, 9, 16):
        raise ValueError(f"{where}.samples: expected 1, 4, 9 or 16, got {out['samples']!r}")
    return out


def _check_overrides(
    where: str, scene: Any, inst: Mapping[int, Mapping[str, Any]]
) -> dict[int, dict[str, Any]]:
    out: dict[int, dict[str, Any]] = {}
    for k, fields in inst.items():
        if isinstance(k, bool) or not isinstance(k, int) or k < 0:
            raise ValueError(f"{where}: instance index must be an integer >= 0, got {k!r}")
        if isinstance(scene, Scene) and k >= len(scene.instances):
            raise ValueError(f"{where}[{k}]: the scene has {len(scene.instances)} instances")
        bad = set(fields) - set(INSTANCE_FIELDS)
        if bad:
            raise ValueError(
                f"{where}[{k}].{sorted(bad)[0]}: unknown; an instance override sets "
                f"{', '.join(INSTANCE_FIELDS)}"
            )
        mat = fields.get("material")
        if mat is not None and not isinstance(mat, _brdfpy.Model):
            raise TypeError(f"{where}[{k}].material: expected a brdfpy.Model, got {type(mat).__name__}")
        out[k] = dict(fields)
    return out


def _outputs_for(formats: Sequence[str], options: Mapping[str, Any]) -> list[str]:
    asked = options.get("outputs")
    own: list[str] = (
        list(OUTPUTS) if asked == "all" else [asked] if isinstance(asked, str) else list(asked or [])
    )
    need = {"rgb"}
    if "exr" in formats:
        need.add("hdr")
    if "npz" in formats:
        need.update(own or OUTPUTS)
    return [o for o in OUTPUTS if o in need or o in own]


def _encode(img: Image, fmt: str) -> bytes:
    buf = io.BytesIO()
    if fmt == "png":
        img.to_pil().save(buf, format="PNG")
    elif fmt == "npz":
        arrays: dict[str, Any] = {name: np.asarray(getattr(img, name)) for name in img.outputs}
        np.savez_compressed(buf, **arrays)
    else:  # exr
        import OpenEXR  # type: ignore[import-not-found,unused-ignore]  # optional, ships no stubs

        hdr = np.ascontiguousarray(img.hdr, dtype=np.float16)
        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        with OpenEXR.File(header, {"RGB": hdr}) as f:
            f.write(buf)
    return buf.getvalue()


def _render_job(
    scene: Scene | Callable[[], Scene],
    camera: Camera,
    options: dict[str, Any],
    overrides: dict[int, dict[str, Any]],
    formats: tuple[str, ...],
) -> dict[str, Any]:
    """The task: render one frame on a worker and return its encoded files (the client writes them)."""
    t0 = time.perf_counter()
    s = scene if isinstance(scene, Scene) else scene()
    if not isinstance(s, Scene):
        raise TypeError(f"scene: the scene callable returned {type(s).__name__}, not a brdfpy.Scene")
    if overrides:
        # The worker keeps one copy of a scattered scene for all its tasks (which may run in threads at
        # once): change a shallow copy, never the shared scene.
        s = copy.copy(s)
        s.instances = [copy.copy(inst) for inst in s.instances]
        for k, fields in overrides.items():
            for attr, value in fields.items():
                setattr(s.instances[k], attr, value)
    opts = dict(options)
    opts["outputs"] = _outputs_for(formats, options)
    img = s.render(camera, **opts)
    t1 = time.perf_counter()
    files = {fmt: _encode(img, fmt) for fmt in formats}
    t2 = time.perf_counter()
    return {
        "files": files,
        "render_s": t1 - t0,
        "encode_s": t2 - t1,
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "size": [img.width, img.height],
    }


def _now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def _read_manifest(path: Path) -> dict[str, Any]:
    if not path.exists():
        return {"frames": {}}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as err:
        raise ValueError(
            f"out: {path} is not a brdfpy manifest ({err}); move it away to start afresh"
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("frames"), dict):
        raise ValueError(f"out: {path} is not a brdfpy manifest (no 'frames'); move it away to start afresh")
    return data


def _complete(out: Path, entry: Mapping[str, Any], fingerprint: str) -> bool:
    """``entry`` is this job's (same fingerprint) and every file it lists is on disk with its checksum."""
    if entry.get("fingerprint") != fingerprint:
        return False
    files = entry.get("files")
    if not isinstance(files, dict) or not files:
        return False
    for info in files.values():
        try:
            data = (out / info["file"]).read_bytes()
        except (OSError, KeyError, TypeError):
            return False
        if _sha256(data) != info.get("sha256"):
            return False
    return True


def _jsonable(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.generic, np.ndarray)):
        return _jsonable(x.tolist())
    if isinstance(x, _brdfpy.Model):
        return {"model": x.name, **_jsonable(x.params)} if x.name != "measured" else {"model": "measured"}
    if x is None or isinstance(x, (bool, int, float, str)):
        return x
    return repr(x)


class _Progress:
    """Dask's text progress bar over the futures, in a thread (the caller's thread writes the files)."""

    def __init__(self, futures: list[Any], enabled: bool) -> None:
        self.thread: threading.Thread | None = None
        if not enabled or not futures:
            return
        self.thread = threading.Thread(target=self._run, args=(futures,), name="brdfpy-progress", daemon=True)
        self.thread.start()

    @staticmethod
    def _run(futures: list[Any]) -> None:
        with contextlib.suppress(Exception):
            distributed.progress(futures, notebook=False)

    def close(self, timeout: float = 2.0) -> None:
        if self.thread is not None:
            self.thread.join(timeout)


def render_many(
    jobs: Sequence[JobLike] | Sweep | Mapping[str, Any] | str | os.PathLike[str],
    client: distributed.Client | None = None,
    out: str | os.PathLike[str] = "frames",
    *,
    formats: Sequence[str] = ("png",),
    resume: bool = True,
    scatter: bool = True,
    progress: bool = True,
    errors: str = "raise",
    manifest_interval: float = 1.0,
) -> RenderReport:
    """Render many frames on a Dask cluster into the folder ``out``, with a manifest; resumable.

    Parameters
    ----------
    jobs : list of Job, dicts or (scene, camera, options) tuples; or a sweep spec (dict, JSON path, Sweep)
        See :class:`Job` and :func:`brdfpy.sweep.load_spec`. A sweep's scene is shared by its jobs, which
        override the material of its first instance.
    client : distributed.Client, optional
        Default: the current default client, else a ``LocalCluster`` of one worker process per core,
        started for this call.
    out : path
        Output folder (created). Frame ``NAME`` is written as ``NAME.png`` (and ``NAME.exr``, ``NAME.npz``);
        ``manifest.json`` lists, per frame, its parameters, files with SHA-256 checksums and sizes, render
        and encode times, the worker and when it finished.
    formats : sequence of "png", "exr", "npz"
        ``exr``: half-float linear HDR (needs the ``OpenEXR`` package on the workers); ``npz``: every
        buffer the job's ``outputs=`` asks for (default all), as NumPy arrays.
    resume : bool
        Skip frames already in the manifest for the same job (same scene, camera, options and formats) whose
        files are on disk with their checksums; ``False`` renders everything again.
    scatter : bool
        Send each distinct scene to every worker once (default); ``False`` puts the scene into every task
        (for measuring what scattering saves).
    progress : bool
        Show Dask's progress bar (text, on stdout).
    errors : "raise" or "report"
        A job that raises never stops the others; at the end ``"raise"`` raises :class:`JobsFailed` naming
        each failed job and why, ``"report"`` only lists them in the returned report.
    manifest_interval : float
        Seconds between rewrites of the manifest while frames arrive (it is always written at the end);
        frames finished after the last rewrite are on disk and are re-rendered by a resumed run.

    Returns
    -------
    RenderReport

    Raises
    ------
    ValueError, TypeError
        A bad job (unknown option or instance field, duplicate names, unpicklable scene callables...) or spec,
        before any task is sent; the message names the job and field.
    OSError
        ``out`` cannot be written (checked before any task is sent), or a write failed mid-run (e.g. the
        disk is full): the remaining tasks are cancelled, the manifest lists exactly the complete frames.
    JobsFailed
        With ``errors="raise"``, when some jobs raised.
    """
    t_start = time.perf_counter()
    if errors not in ("raise", "report"):
        raise ValueError(f"errors: expected 'raise' or 'report', got {errors!r}")
    if isinstance(jobs, (Sweep, Mapping, str, os.PathLike)):
        sweep = jobs if isinstance(jobs, Sweep) else load_spec(jobs)
        job_list = sweep_jobs(sweep)
        formats = sweep.formats
    else:
        if isinstance(jobs, (bytes, bytearray)) or not isinstance(jobs, Sequence):
            raise TypeError(f"jobs: expected a list of jobs or a sweep spec, got {type(jobs).__name__}")
        job_list = [_as_job(i, j) for i, j in enumerate(jobs)]
    fmts = tuple(dict.fromkeys(formats))
    if not fmts or any(f not in FORMATS for f in fmts):
        raise ValueError(f"formats: expected some of {', '.join(FORMATS)}, got {list(formats)!r}")
    if "exr" in fmts:
        try:
            import OpenEXR  # type: ignore[import-not-found,unused-ignore]  # noqa: F401
        except ImportError:
            raise ImportError("formats: 'exr' needs the OpenEXR package (pip install OpenEXR)") from None
    if not job_list:
        raise ValueError("jobs: is empty")

    # Everything is checked before anything is sent.
    digits = len(str(len(job_list) - 1))
    names: list[str] = []
    prepared: list[tuple[Job, dict[str, Any], dict[int, dict[str, Any]]]] = []
    scene_bytes: dict[int, bytes] = {}
    for i, job in enumerate(job_list):
        where = f"jobs[{i}]"
        name = job.name if job.name is not None else f"frame_{i:0{max(digits, 5)}d}"
        if not isinstance(name, str) or not _NAME.match(name):
            raise ValueError(f"{where}.name: expected letters, digits, '.', '_' and '-', got {name!r}")
        names.append(name)
        if not isinstance(job.camera, Camera):
            raise TypeError(f"{where}.camera: expected a brdfpy.Camera, got {type(job.camera).__name__}")
        if not isinstance(job.scene, Scene) and not callable(job.scene):
            raise TypeError(
                f"{where}.scene: expected a brdfpy.Scene or a callable returning one, got "
                f"{type(job.scene).__name__}"
            )
        if isinstance(job.scene, Scene) and not job.scene.instances:
            raise ValueError(f"{where}.scene: has no meshes")
        opts = _check_options(f"{where}.options", job.options)
        over = _check_overrides(f"{where}.instances", job.scene, job.instances)
        if id(job.scene) not in scene_bytes:
            scene_bytes[id(job.scene)] = _check_picklable(f"{where}.scene", job.scene)
        _check_picklable(f"{where}.options", opts)
        _check_picklable(f"{where}.instances", over)
        prepared.append((job, opts, over))
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise ValueError(
            f"jobs: names must be unique; {sorted(dup)[0]!r} appears {names.count(sorted(dup)[0])} times"
        )
    folder = _check_folder(out)
    manifest_path = folder / MANIFEST
    manifest = _read_manifest(manifest_path) if resume else {"frames": {}}
    frames: dict[str, Any] = dict(manifest["frames"])

    scene_digest = {k: _sha256(b) for k, b in scene_bytes.items()}
    todo: list[int] = []
    skipped: list[str] = []
    fingerprints: list[str] = []
    for i, (job, opts, over) in enumerate(prepared):
        h = hashlib.sha256()
        h.update(scene_digest[id(job.scene)].encode())
        h.update(pickle.dumps(job.camera, protocol=5))
        h.update(json.dumps(_jsonable(opts), sort_keys=True).encode())
        h.update(pickle.dumps(over, protocol=5))
        h.update(",".join(fmts).encode())
        fp = h.hexdigest()
        fingerprints.append(fp)
        entry = frames.get(names[i])
        if resume and isinstance(entry, Mapping) and _complete(folder, entry, fp):
            skipped.append(names[i])
        else:
            todo.append(i)

    rendered: list[str] = []
    failed: dict[str, str] = {}
    state = {"last": 0.0}

    def save_manifest(force: bool) -> None:
        now = time.perf_counter()
        if not force and now - state["last"] < manifest_interval:
            return
        order = {n: k for k, n in enumerate(names)}
        doc = {
            "brdfpy": __version__,
            "updated": _now(),
            "frames": dict(sorted(frames.items(), key=lambda kv: (order.get(kv[0], len(order)), kv[0]))),
            "failed": failed,
        }
        _write_bytes(manifest_path, json.dumps(doc, indent=1).encode())
        state["last"] = now

    if todo:
        with _client(client) as c:
            _prepare_workers(c)
            refs: dict[int, Any] = {}
            for i in todo:
                sc = prepared[i][0].scene
                if id(sc) not in refs:
                    refs[id(sc)] = c.scatter(sc, broadcast=True, hash=False) if scatter else sc
            index: dict[Any, int] = {}
            futures = []
            for i in todo:
                job, opts, over = prepared[i]
                key = f"brdfpy-render-{names[i]}-{fingerprints[i][:16]}"
                fut = c.submit(
                    _render_job, refs[id(job.scene)], job.camera, opts, over, fmts, key=key, pure=False
                )
                index[fut.key] = i
                futures.append(fut)
            bar = _Progress(futures, progress)

            def write_frame(i: int, res: dict[str, Any]) -> tuple[int, dict[str, Any]]:
                files = {}
                for fmt, data in res["files"].items():
                    fname = f"{names[i]}.{fmt}"
                    _write_bytes(folder / fname, data)
                    files[fmt] = {"file": fname, "sha256": _sha256(data), "bytes": len(data)}
                return i, {
                    "job": i,
                    "params": _jsonable(prepared[i][0].params),
                    "options": _jsonable(prepared[i][1]),
                    "files": files,
                    "fingerprint": fingerprints[i],
                    "size": res["size"],
                    "render_s": round(res["render_s"], 6),
                    "encode_s": round(res["encode_s"], 6),
                    "worker": res["worker"],
                    "finished": _now(),
                }

            # Files are written by a few threads (each write is flushed to disk, which waits on the
            # device; the threads overlap those waits); the manifest only by this thread, and only with
            # frames whose files are complete.
            pending: set[concurrent.futures.Future[tuple[int, dict[str, Any]]]] = set()

            def collect(block: bool) -> None:
                nonlocal pending
                done, pending = concurrent.futures.wait(
                    pending, timeout=None if block else 0, return_when=concurrent.futures.ALL_COMPLETED
                )
                for w in done:
                    i, entry = w.result()  # re-raises a write's OSError
                    frames[names[i]] = entry
                    failed.pop(names[i], None)
                    rendered.append(names[i])
                if done:
                    save_manifest(block)

            with concurrent.futures.ThreadPoolExecutor(4, thread_name_prefix="brdfpy-write") as writers:
                try:
                    for fut, res in distributed.as_completed(futures, with_results=True, raise_errors=False):
                        i = index[fut.key]
                        ok = fut.status == "finished"
                        fut.release()
                        if not ok:
                            exc = res[1] if isinstance(res, tuple) else res
                            failed[names[i]] = f"jobs[{i}] {names[i]!r}: {type(exc).__name__}: {exc}"
                        else:
                            pending.add(writers.submit(write_frame, i, res))
                        collect(False)
                    collect(True)
                except OSError as err:
                    c.cancel(futures)
                    for w in pending:
                        w.cancel()
                    # Frames whose files were completed still enter the manifest.
                    for w in concurrent.futures.wait(pending).done:
                        if not w.cancelled() and w.exception() is None:
                            i, entry = w.result()
                            frames[names[i]] = entry
                    with contextlib.suppress(OSError):
                        save_manifest(True)
                    raise OSError(
                        err.errno,
                        f"out: writing in {str(folder)!r} failed ({err.strerror or err}); {len(frames)} "
                        f"frames are complete and listed in {MANIFEST} (the others will be rendered by a "
                        "resumed run); free space and run again to render the rest",
                    ) from err
                finally:
                    bar.close()
    save_manifest(True)
    report = RenderReport(folder, manifest_path, rendered, skipped, failed, time.perf_counter() - t_start)
    if failed and errors == "raise":
        lines = "\n  ".join(failed.values())
        raise JobsFailed(
            f"{len(failed)} of {len(todo)} jobs failed (the others are in {manifest_path}):\n  {lines}",
            report,
        )
    return report


def sweep_jobs(sweep: Sweep) -> list[Job]:
    """The render jobs of a checked sweep: one shared scene, the material of its first instance replaced
    per job."""
    return [
        Job(
            scene=sweep.scene,
            camera=j.camera,
            options=sweep.options,
            name=j.name,
            params=j.params,
            instances={
                0: {
                    "material": sweep.materials[j.material],
                    "ambient": None,  # the new material's white-sky albedo
                }
            },
        )
        for j in sweep.jobs
    ]


# -- fit_many --------------------------------------------------------------------------------------


class FitRow(TypedDict):
    """One row of :func:`fit_many`'s table."""

    index: int
    name: str
    model: str
    values: dict[str, Any]
    rms_log_error: float
    epsilon: float
    iterations: int
    converged: bool
    samples_used: int
    seconds: float
    error: str | None


TableLike = Union[Tabulated, Model, str, "os.PathLike[str]"]


@functools.lru_cache(maxsize=8)
def _fit_directions(samples: int, seed: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """``samples`` light and view directions, cosine-distributed over the upper hemisphere (z up), the same
    on every machine for the same seed (NumPy's PCG64)."""
    rng = np.random.default_rng(seed)

    def hemi() -> NDArray[np.float32]:
        u1, u2 = rng.random(samples), rng.random(samples)
        r, phi = np.sqrt(u1), 2 * np.pi * u2
        z = np.sqrt(np.maximum(1 - u1, 1e-6))
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)

    return hemi(), hemi()


def _fit_job(
    table: Any,
    model_name: str,
    start: dict[str, Any],
    fixed: dict[str, Any],
    samples: int,
    seed: int,
    max_iterations: int,
) -> dict[str, Any]:
    t0 = time.perf_counter()
    if isinstance(table, (str, os.PathLike)):
        table = Tabulated.load_merl(table)
    m = table.as_model() if isinstance(table, Tabulated) else table
    l, v = _fit_directions(samples, seed)
    n = np.array([0.0, 0.0, 1.0], dtype=np.float32)
    values = m.eval(l, v, n)
    res = fit(model_name, l, v, n, values, start=start, fixed=fixed, max_iterations=max_iterations)
    out = dict(res)
    out.pop("model")
    out["seconds"] = time.perf_counter() - t0
    return out


def fit_many(
    tables: Sequence[TableLike],
    model_name: str,
    *,
    start: Mapping[str, Any],
    fixed: Mapping[str, Any] | None = None,
    names: Sequence[str] | None = None,
    samples: int = 20_000,
    seed: int = 0,
    max_iterations: int = 200,
    client: distributed.Client | None = None,
    progress: bool = False,
    errors: str = "raise",
) -> list[FitRow]:
    """Fit registry model ``model_name`` to each measured table, in parallel on a Dask cluster.

    Each table is sampled at the same ``samples`` pairs of light and view directions (cosine-distributed
    over the hemisphere, from ``seed``) and fitted by :func:`brdfpy.measured.fit` (``start``, ``fixed``,
    ``max_iterations`` as there).

    Parameters
    ----------
    tables : sequence of Tabulated, measured Model, or MERL ``.binary`` paths
        Paths are read by the workers (they must see the files); tables and models are sent with their task.
    names : sequence of str, optional
        A name per table for the result rows (default: the path, else ``table_<i>``).
    client : distributed.Client, optional
        As for :func:`render_many`.
    errors : "raise" or "report"
        A table that fails never stops the others; ``"raise"`` raises :class:`JobsFailed` at the end (its
        ``report`` holds every row), ``"report"`` returns the rows with ``error`` set and NaN figures.

    Returns
    -------
    list of FitRow
        In the order of ``tables``: ``index``, ``name``, ``model``, the fitted ``values``, ``rms_log_error``,
        ``epsilon``, ``iterations``, ``converged``, ``samples_used``, ``seconds``, ``error`` (None).
    """
    if errors not in ("raise", "report"):
        raise ValueError(f"errors: expected 'raise' or 'report', got {errors!r}")
    if not isinstance(model_name, str) or model_name not in models():
        raise ValueError(f"model_name: unknown model {model_name!r}; known: {', '.join(models())}")
    if isinstance(tables, (str, os.PathLike)) or not isinstance(tables, Sequence) or not tables:
        raise TypeError("tables: expected a non-empty list of Tabulated, measured models or MERL file paths")
    start_d, fixed_d = dict(start), dict(fixed or {})
    if not start_d:
        raise ValueError("start: name at least one parameter to fit")
    try:
        model(model_name, **fixed_d, **start_d)
    except (ValueError, TypeError) as err:
        raise ValueError(f"start, fixed: {err}") from None
    if isinstance(samples, bool) or not isinstance(samples, int) or not 16 <= samples <= 10_000_000:
        raise ValueError(f"samples: expected an integer in [16, 10^7], got {samples!r}")
    row_names: list[str] = []
    for i, t in enumerate(tables):
        where = f"tables[{i}]"
        if isinstance(t, (str, os.PathLike)):
            if not Path(t).is_file():
                raise FileNotFoundError(f"{where}: no such file: {os.fspath(t)!r}")
            default = os.fspath(t)
        elif isinstance(t, Tabulated) or (isinstance(t, _brdfpy.Model) and t.name == "measured"):
            default = f"table_{i}"
        else:
            raise TypeError(
                f"{where}: expected a Tabulated, a measured Model or a file path, got {type(t).__name__}"
            )
        row_names.append(default)
    if names is not None:
        if len(names) != len(tables):
            raise ValueError(f"names: {len(names)} names for {len(tables)} tables")
        row_names = [str(n) for n in names]
    with _client(client) as c:
        _prepare_workers(c)
        futures = [
            c.submit(
                _fit_job,
                t,
                model_name,
                start_d,
                fixed_d,
                samples,
                seed,
                max_iterations,
                key=f"brdfpy-fit-{i}-{os.urandom(4).hex()}",
                pure=False,
            )
            for i, t in enumerate(tables)
        ]
        bar = _Progress(futures, progress)
        rows: list[FitRow] = []
        try:
            distributed.wait(futures)
        finally:
            bar.close()
        for i, fut in enumerate(futures):
            base: FitRow = {
                "index": i,
                "name": row_names[i],
                "model": model_name,
                "values": {},
                "rms_log_error": math.nan,
                "epsilon": math.nan,
                "iterations": 0,
                "converged": False,
                "samples_used": 0,
                "seconds": math.nan,
                "error": None,
            }
            if fut.status == "finished":
                r = fut.result()
                for k in ("values", "rms_log_error", "epsilon", "iterations", "converged", "samples_used"):
                    base[k] = r[k]  # the keys of FitRow
                base["seconds"] = r["seconds"]
            else:
                exc = fut.exception()
                base["error"] = f"tables[{i}] {row_names[i]!r}: {type(exc).__name__}: {exc}"
            rows.append(base)
    bad = [r["error"] for r in rows if r["error"]]
    if bad and errors == "raise":
        lines = "\n  ".join(str(b) for b in bad)
        raise JobsFailed(f"{len(bad)} of {len(rows)} fits failed (the others finished):\n  {lines}", rows)
    return rows


# -- contact sheet ---------------------------------------------------------------------------------


def contact_sheet(
    sweep: Sweep, out: str | os.PathLike[str], path: str | os.PathLike[str] | None = None
) -> Path:
    """A PNG of every material of a rendered sweep (one row each, labelled with its parameters) at up to
    ``contact_sheet.columns`` turntable frames (evenly spaced), from the PNGs in ``out``; written
    atomically to ``path`` (default ``out/contact_sheet.png``). Frames missing from the folder are drawn
    as empty cells."""
    from PIL import Image as PILImage
    from PIL import ImageDraw

    folder = Path(out)
    thumb, columns = sweep.sheet.get("thumb", 160), sweep.sheet.get("columns", 8)
    w, h = int(sweep.options["width"]), int(sweep.options["height"])
    tw, th = thumb, max(1, round(thumb * h / w))
    cols = min(columns, sweep.frames)
    frames = sorted({round(k * sweep.frames / cols) for k in range(cols)})
    label_h, pad = 14, 4
    rows = len(sweep.materials)
    sheet = PILImage.new(
        "RGB", (pad + len(frames) * (tw + pad), pad + rows * (label_h + th + pad)), (24, 24, 28)
    )
    draw = ImageDraw.Draw(sheet)
    by_key = {(j.material, j.frame): j.name for j in sweep.jobs}
    for m in range(rows):
        y = pad + m * (label_h + th + pad)
        draw.text((pad, y + 1), sweep.material_labels[m], fill=(230, 230, 230))
        for c, k in enumerate(frames):
            x = pad + c * (tw + pad)
            png = folder / f"{by_key[(m, k)]}.png"
            try:
                with PILImage.open(png) as im:
                    cell = im.convert("RGB").resize((tw, th), PILImage.Resampling.LANCZOS)
            except (OSError, ValueError):
                cell = PILImage.new("RGB", (tw, th), (60, 20, 20))
            sheet.paste(cell, (x, y + label_h))
    buf = io.BytesIO()
    sheet.save(buf, format="PNG")
    target = Path(path) if path is not None else folder / "contact_sheet.png"
    _write_bytes(target, buf.getvalue())
    return target
