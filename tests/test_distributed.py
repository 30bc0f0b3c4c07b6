"""brdfpy.distributed and ``brdfpy batch`` on a real cluster: a ``distributed.LocalCluster`` of two worker
processes (one thread each), shared by the tests of this module.

What is real and what is simulated: the cluster, the worker processes, killing one by its pid and the
scheduler re-running its tasks are real. A full disk is simulated by replacing
``brdfpy.distributed._write_bytes`` (the one function through which every output byte goes) with one that
raises ``OSError(ENOSPC)`` once a byte budget is spent, as a full file system would.
"""

from __future__ import annotations

import errno
import hashlib
import io
import json
import os
import signal
import subprocess
import sys
import threading
import time
import tracemalloc
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

distributed = pytest.importorskip("distributed", reason="brdfpy[dask] is part of the dev extra")
da = pytest.importorskip("dask.array")

import brdfpy  # noqa: E402
from brdfpy import distributed as bd  # noqa: E402
from brdfpy import measured  # noqa: E402
from brdfpy.cli import main as cli_main  # noqa: E402
from PIL import Image as PILImage  # noqa: E402

pytestmark = pytest.mark.filterwarnings(
    # distributed warns when a worker it was talking to disappears (the kill test does that on purpose).
    "ignore::ResourceWarning",
)


@pytest.fixture(scope="module")
def client() -> Iterator[Any]:
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as c:
        yield c


def _rows(k: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(k, 3)).astype(np.float32)
    l = (rng.normal(size=(k, 3)) + n).astype(np.float32)
    v = (rng.normal(size=(k, 3)) + n).astype(np.float32)
    t = rng.normal(size=(k, 3)).astype(np.float32)
    return l, v, n, t


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# -- importing -------------------------------------------------------------------------------------


def test_importing_brdfpy_imports_no_dask() -> None:
    code = (
        "import sys, brdfpy, brdfpy.sweep, brdfpy.cli\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed'))\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


# -- eval / shade on Dask arrays -------------------------------------------------------------------


@pytest.mark.parametrize(
    "name,params",
    [("cook_torrance", {"roughness": 0.17}), ("ward", {"alpha_x": 0.1, "alpha_y": 0.3}), ("toon", {})],
)
def test_eval_and_shade_on_the_cluster_give_the_bits_of_the_local_call(
    client: Any, name: str, params: dict[str, Any]
) -> None:
    m = brdfpy.model(name, **params)
    l, v, n, t = _rows(50_003)
    tangent = t if m.anisotropic else None
    for chunks in ((7_000, 3), (50_003, 3), (1, 3)) if name == "toon" else ((6_151, 3),):
        if chunks[0] == 1:
            l_, v_, n_ = l[:40], v[:40], n[:40]
            t_ = None if tangent is None else tangent[:40]
        else:
            l_, v_, n_, t_ = l, v, n, tangent
        dl = da.from_array(l_, chunks=chunks)
        dt = None if t_ is None else da.from_array(t_, chunks=chunks)
        for fn, local in ((bd.eval, m.eval), (bd.shade, m.shade)):
            got = fn(m, dl, v_, n_, dt).compute()
            assert same_bits(got, local(l_, v_, n_, t_))


def test_mismatched_row_chunks_are_rechunked_or_refused() -> None:
    m = brdfpy.model("lambert")
    l, v, n, _ = _rows(1000)
    dl, dv = da.from_array(l, chunks=(300, 3)), da.from_array(v, chunks=(170, 3))
    r = bd.eval(m, dl, dv, da.from_array(n, chunks=(1000, 3)))
    assert r.chunks[0] == dl.chunks[0]
    assert same_bits(r.compute(scheduler="threads"), m.eval(l, v, n))
    with pytest.raises(ValueError, match=r"v: row chunks \(170, 170, 170, 170\)\.\.\. differ from l's"):
        bd.eval(m, dl, dv, n, rechunk=False)


def test_different_evaluations_in_one_graph_do_not_share_keys() -> None:
    # Each result's keys hash its model and inputs: two evaluations computed together stay two.
    import dask

    l, v, n, _ = _rows(500)
    dl = da.from_array(l, chunks=(100, 3))
    a, b = brdfpy.model("lambert", kd=0.2), brdfpy.model("lambert", kd=0.7)
    ea, eb, sa = dask.compute(
        bd.eval(a, dl, v, n), bd.eval(b, dl, v, n), bd.shade(a, dl, v, n), scheduler="threads"
    )
    assert (
        same_bits(ea, a.eval(l, v, n)) and same_bits(eb, b.eval(l, v, n)) and same_bits(sa, a.shade(l, v, n))
    )
    assert bd.eval(a, dl, v, n).name != bd.eval(b, dl, v, n).name
    assert bd.eval(a, dl, v, n).name == bd.eval(a, dl, v, n).name  # and the same evaluation is one


def test_bad_dask_inputs_are_refused_naming_the_argument() -> None:
    m = brdfpy.model("lambert")
    l, v, n, _ = _rows(100)
    dl = da.from_array(l, chunks=(10, 3))
    with pytest.raises(ValueError, match=r"v: each chunk must hold whole rows of 3 components .* \(2, 1\)"):
        bd.eval(m, dl, da.from_array(v, chunks=(10, 2)), n)
    with pytest.raises(ValueError, match=r"n: expected a Dask array of shape \(N, 3\), got shape \(100, 4\)"):
        bd.eval(m, dl, v, da.zeros((100, 4), chunks=(10, 4)))
    with pytest.raises(ValueError, match="v: has 99 rows, l has 100"):
        bd.eval(m, dl, da.from_array(v[:99], chunks=(10, 3)), n)
    with pytest.raises(ValueError, match="v: has 99 rows, l has 100"):
        bd.eval(m, dl, v[:99], n)
    with pytest.raises(ValueError, match=r"l: has unknown chunk sizes"):
        bd.eval(m, dl[dl[:, 0] > 0], v[0], n[0])
    with pytest.raises(TypeError, match="model: expected a brdfpy"):
        bd.eval("lambert", dl, v, n)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"n: expected shape \(N, 3\) or \(3,\)"):
        bd.eval(m, dl, v, [0, 1])
    # Bad values are found where they are, on the worker, by the library's own check.
    bad = l.copy()
    bad[57, 1] = np.nan
    with pytest.raises(ValueError, match=r"l: contains a non-finite value .* at l\[57\]"):
        bd.eval(m, da.from_array(bad, chunks=(10, 3)), v, n).compute(scheduler="threads")


def test_an_evaluation_streams_between_memmaps_in_bounded_memory(tmp_path: Path) -> None:
    # 10^7 rows: 120 MB per array on disk. Evaluated chunk by chunk from a memmap into a memmap, the
    # memory NumPy allocates stays near a few chunks (4 threads x 250k rows x 12 bytes x ~3 buffers),
    # where the local call allocates the 120 MB result at once.
    rows, chunk = 10_000_000, 250_000
    m = brdfpy.model("blinn_phong", shininess=40)
    lpath, opath = tmp_path / "l.f32", tmp_path / "out.f32"
    l_mm = np.memmap(lpath, dtype=np.float32, mode="w+", shape=(rows, 3))
    for i in range(0, rows, 1_000_000):  # written in pieces too
        block = np.random.default_rng(i).normal(size=(1_000_000, 3)).astype(np.float32)
        block[:, 2] = np.abs(block[:, 2])
        l_mm[i : i + 1_000_000] = block
    l_mm.flush()
    del l_mm
    src = np.memmap(lpath, dtype=np.float32, mode="r", shape=(rows, 3))
    out = np.memmap(opath, dtype=np.float32, mode="w+", shape=(rows, 3))
    lazy = bd.shade(m, da.from_array(src, chunks=(chunk, 3)), [0.0, 0.6, 0.8], [0.0, 0.0, 1.0])
    tracemalloc.start()
    try:
        da.store(lazy, out, lock=False, scheduler="threads", num_workers=4)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    out.flush()
    assert peak < 40e6, f"peak {peak / 1e6:.0f} MB"
    # Same bits as the local call, compared a slice at a time (the whole would need the 120 MB again).
    for i in range(0, rows, 2_000_000):
        local = m.shade(src[i : i + 2_000_000], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0])
        assert same_bits(np.asarray(out[i : i + 2_000_000]), local)


# -- render_many -----------------------------------------------------------------------------------


def _scene(level: int = 3) -> brdfpy.Scene:
    scene = brdfpy.Scene(ambient_light=0.2, background=(0.05, 0.05, 0.08))
    scene.add(brdfpy.icosphere(level), brdfpy.model("cook_torrance", roughness=0.25), ambient=0.05)
    scene.add(brdfpy.plane(6, 4), brdfpy.model("lambert", kd=0.5), brdfpy.transforms.translate(0, -1, 0))
    scene.add_light(brdfpy.DirectionalLight((-0.5, -1, -0.4), 2.0))
    scene.add_light(brdfpy.PointLight((2, 2, 2), 10))
    return scene


def _cameras(k: int) -> list[brdfpy.Camera]:
    return [
        brdfpy.Camera.perspective((3 * np.sin(a), 0.8, 3 * np.cos(a)), (0, -0.2, 0))
        for a in np.linspace(0, 2 * np.pi, k, endpoint=False)
    ]


def _jobs(k: int, scene: brdfpy.Scene | None = None, **options: Any) -> list[bd.Job]:
    scene = scene or _scene()
    opts = {"width": 64, "height": 48, "shadows": True, **options}
    mats = [brdfpy.model("cook_torrance", roughness=r) for r in (0.1, 0.4)]
    return [
        bd.Job(scene, cam, opts, params={"i": i}, instances={0: {"material": mats[i % 2]}})
        for i, cam in enumerate(_cameras(k))
    ]


def _manifest(out: Path) -> dict[str, Any]:
    data: dict[str, Any] = json.loads((out / "manifest.json").read_text())
    return data


def _assert_complete(out: Path, names: list[str], formats: tuple[str, ...] = ("png",)) -> dict[str, Any]:
    """Every frame is in the manifest once, its files on disk with their checksums, no temporary files."""
    man = _manifest(out)
    assert sorted(man["frames"]) == sorted(names)
    for name in names:
        files = man["frames"][name]["files"]
        assert sorted(files) == sorted(formats)
        for fmt, info in files.items():
            data = (out / info["file"]).read_bytes()
            assert info["file"] == f"{name}.{fmt}"
            assert hashlib.sha256(data).hexdigest() == info["sha256"] and len(data) == info["bytes"]
            if fmt == "png":
                with PILImage.open(io.BytesIO(data)) as im:
                    im.load()  # a truncated PNG fails here
    assert not [p for p in out.iterdir() if ".tmp-" in p.name]
    on_disk = sorted(p.stem for p in out.glob("*.png") if p.stem != "contact_sheet")
    assert on_disk == sorted(names)
    return man


def test_render_many_writes_the_frames_of_local_renders_and_a_manifest(client: Any, tmp_path: Path) -> None:
    jobs = _jobs(6, samples=4, outputs="all")
    report = bd.render_many(jobs, client, tmp_path, formats=("png", "npz", "exr"), progress=False)
    names = [f"frame_{i:05d}" for i in range(6)]
    assert sorted(report.rendered) == names and not report.skipped and not report.failed
    man = _assert_complete(tmp_path, names, ("png", "npz", "exr"))
    for i, job in enumerate(jobs):
        scene = _scene()
        scene.instances[0].material = job.instances[0]["material"]
        local = scene.render(job.camera, **job.options)
        with PILImage.open(tmp_path / f"frame_{i:05d}.png") as im:
            assert same_bits(np.asarray(im), local.rgb)
        with np.load(tmp_path / f"frame_{i:05d}.npz") as z:
            for name in ("hdr", "depth", "normal", "triangle_id"):
                assert same_bits(z[name], np.asarray(getattr(local, name))), name
        entry = man["frames"][f"frame_{i:05d}"]
        assert entry["params"] == {"i": i} and entry["size"] == [64, 48] and entry["render_s"] > 0
    import OpenEXR

    with OpenEXR.File(str(tmp_path / "frame_00002.exr")) as f:
        rgb = f.channels()["RGB"].pixels
    hdr = np.asarray(_scene_with(jobs[2]).render(jobs[2].camera, **jobs[2].options).hdr)
    assert same_bits(rgb, hdr.astype(np.float16))


def _scene_with(job: bd.Job) -> brdfpy.Scene:
    scene = _scene()
    scene.instances[0].material = job.instances[0]["material"]
    return scene


def test_a_resumed_run_renders_only_the_missing_and_damaged_frames(client: Any, tmp_path: Path) -> None:
    jobs = _jobs(8)
    bd.render_many(jobs, client, tmp_path, progress=False)
    (tmp_path / "frame_00003.png").unlink()
    damaged = tmp_path / "frame_00006.png"
    damaged.write_bytes(damaged.read_bytes()[:100])  # as if an editor had truncated it
    again = bd.render_many(jobs, client, tmp_path, progress=False)
    assert sorted(again.rendered) == ["frame_00003", "frame_00006"]
    assert len(again.skipped) == 6
    _assert_complete(tmp_path, [f"frame_{i:05d}" for i in range(8)])
    # A changed job (another camera) is not taken for the old frame.
    jobs[1] = bd.Job(jobs[1].scene, _cameras(9)[4], jobs[1].options, instances=jobs[1].instances)
    third = bd.render_many(jobs, client, tmp_path, progress=False)
    assert third.rendered == ["frame_00001"]
    fresh = bd.render_many(jobs, client, tmp_path, progress=False, resume=False)
    assert len(fresh.rendered) == 8


def test_a_worker_killed_mid_run_loses_no_frame_and_duplicates_none(client: Any, tmp_path: Path) -> None:
    # Frames of ~50-100 ms each; one worker process is killed (SIGKILL, by its pid) once a few frames are
    # on disk. The scheduler re-runs its tasks on the other worker (and the nanny restarts it).
    jobs = _jobs(40, scene=_scene(5), ao={"samples": 16}, width=160, height=120)
    result: dict[str, Any] = {}

    def run() -> None:
        try:
            result["report"] = bd.render_many(jobs, client, tmp_path, progress=False)
        except BaseException as err:  # re-raised in the test's thread
            result["error"] = err

    t = threading.Thread(target=run)
    t.start()
    deadline = time.monotonic() + 60
    while len(list(tmp_path.glob("frame_*.png"))) < 4 and time.monotonic() < deadline:
        time.sleep(0.01)
    pids = client.run(os.getpid)
    victim = next(iter(pids.values()))
    os.kill(victim, signal.SIGKILL)
    at_kill = len(list(tmp_path.glob("frame_*.png")))
    assert at_kill < 40, "the run ended before the kill: make the frames slower"
    t.join(120)
    assert not t.is_alive()
    if "error" in result:
        raise result["error"]
    report = result["report"]
    names = [f"frame_{i:05d}" for i in range(40)]
    assert sorted(report.rendered) == names  # each once
    _assert_complete(tmp_path, names)
    assert len(client.run(os.getpid)) >= 1
    # The worker that died rendered some frames first: both processes appear in the manifest.
    workers = {e["worker"] for e in _manifest(tmp_path)["frames"].values()}
    assert any(w.endswith(f":{victim}") for w in workers), (victim, workers)
    client.wait_for_workers(2, timeout=60)
    assert victim not in client.run(os.getpid).values()  # the nanny started a new process


def test_a_job_that_raises_is_reported_by_name_and_the_others_finish(client: Any, tmp_path: Path) -> None:
    jobs = _jobs(5)
    # Passes the checks made before sending (they do not estimate AO); the renderer refuses it.
    jobs[3] = bd.Job(jobs[3].scene, jobs[3].camera, {**jobs[3].options, "ao": {"samples": 0}}, name="bad-one")
    with pytest.raises(
        bd.JobsFailed, match=r"1 of 5 jobs failed[\s\S]*jobs\[3\] 'bad-one': .*ao samples"
    ) as e:
        bd.render_many(jobs, client, tmp_path, progress=False)
    report = e.value.report
    assert sorted(report.rendered) == ["frame_00000", "frame_00001", "frame_00002", "frame_00004"]
    man = _assert_complete(tmp_path, report.rendered)
    assert "bad-one" in man["failed"]
    assert bd.render_many(jobs, client, tmp_path, progress=False, errors="report").failed.keys() == {
        "bad-one"
    }


class _RecordGraphs(distributed.diagnostics.plugin.SchedulerPlugin):  # type: ignore[misc]
    """Counts the render tasks the scheduler receives."""

    def __init__(self) -> None:
        self.keys: list[str] = []

    def update_graph(self, scheduler: Any, *, keys: set[Any], **kwargs: Any) -> None:
        self.keys += [str(k) for k in keys if str(k).startswith("brdfpy-")]


def _graph_keys(dask_scheduler: Any) -> list[str]:
    return list(dask_scheduler.plugins["record-graphs"].keys)


def test_bad_jobs_and_specs_fail_before_any_task_is_sent(client: Any, tmp_path: Path) -> None:
    client.register_plugin(_RecordGraphs(), name="record-graphs")
    scene, cam = _scene(), _cameras(1)[0]
    a_file = tmp_path / "a-file"
    a_file.write_text("")
    cases: list[tuple[Any, dict[str, Any], type[BaseException], str]] = [
        ([(scene, cam, {"shadow": True})], {}, ValueError, r"jobs\[0\]\.options\.shadow: unknown option"),
        ([(scene, cam, {"width": 0})], {}, ValueError, r"jobs\[0\]\.options\.width: expected an integer"),
        ([(scene, cam, {"shading": "fancy"})], {}, ValueError, r"jobs\[0\]\.options\.shading"),
        ([(scene, cam, {"progress": print})], {}, ValueError, r"jobs\[0\]\.options\.progress: a progress"),
        ([(scene, "cam", {})], {}, TypeError, r"jobs\[0\]\.camera: expected a brdfpy.Camera"),
        (
            [bd.Job(scene, cam, instances={5: {"material": brdfpy.model("lambert")}})],
            {},
            ValueError,
            r"jobs\[0\]\.instances\[5\]: the scene has 2 instances",
        ),
        (
            [bd.Job(scene, cam, instances={0: {"colour": 1}})],
            {},
            ValueError,
            r"instances\[0\]\.colour: unknown",
        ),
        (
            [bd.Job(scene, cam, name="a"), bd.Job(scene, cam, name="a")],
            {},
            ValueError,
            "names must be unique",
        ),
        ([bd.Job(scene, cam, name="../up")], {}, ValueError, r"jobs\[0\]\.name"),
        ([(scene, cam, {})], {"out": a_file / "sub"}, OSError, "out: cannot write in"),
        ([(scene, cam, {})], {"formats": ("png", "tiff")}, ValueError, "formats: expected some of"),
        ({"models": [{"name": "cook_torrans"}]}, {}, ValueError, r"models\[0\]\.name: unknown model"),
        (
            {"models": [{"name": "ward", "params": {"alpha_x": {"range": [0.5, 0.1]}}}]},
            {},
            ValueError,
            r"models\[0\]\.params\.alpha_x\.range: low 0.5 is above high 0.1",
        ),
        (
            {"models": [{"name": "ward", "params": {"alpha_x": {"range": [0.1, 5.0], "steps": 3}}}]},
            {},
            ValueError,
            r'models\[0\]\.params: parameter "alpha_x": must be in \[0, 2\]',
        ),
        ({"models": ["lambert"], "camera": {"frames": 0}}, {}, ValueError, r"camera\.frames: must be"),
        ({"models": ["lambert"], "sizes": [3, 3]}, {}, ValueError, "sizes: unknown field"),
        ({"models": ["lambert"], "mesh": "teapot.obj"}, {}, ValueError, "mesh: no such file"),
    ]
    for jobs, kwargs, exc, message in cases:
        kwargs = {"out": tmp_path / "out", "progress": False, **kwargs}
        with pytest.raises(exc, match=message):
            bd.render_many(jobs, client, **kwargs)
    assert client.run_on_scheduler(_graph_keys) == []
    assert not (tmp_path / "out" / "manifest.json").exists()


def test_unpicklable_scene_callbacks_are_refused_clearly(client: Any, tmp_path: Path) -> None:
    lock = threading.Lock()

    def build() -> brdfpy.Scene:
        with lock:  # a closure over a lock: cloudpickle cannot send it
            return _scene()

    with pytest.raises(TypeError, match=r"jobs\[0\]\.scene: cannot be sent to a worker \(TypeError: .*lock"):
        bd.render_many([(build, _cameras(1)[0], {})], client, tmp_path, progress=False)
    # A picklable callable is fine: the scene is built on the worker.
    report = bd.render_many(
        [(_scene, _cameras(1)[0], {"width": 32, "height": 24})], client, tmp_path, progress=False
    )
    assert report.rendered == ["frame_00000"]


def test_a_disk_that_fills_up_mid_run_leaves_a_consistent_manifest(
    client: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Simulated (see the module docstring): writes fail with ENOSPC once 60 kB are written, frames and
    # manifest alike, as on a full file system.
    real = bd._write_bytes
    budget = {"left": 60_000}

    def full_disk(path: Path, data: bytes) -> None:
        if len(data) > budget["left"]:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        budget["left"] -= len(data)
        real(path, data)

    monkeypatch.setattr(bd, "_write_bytes", full_disk)
    jobs = _jobs(30)
    with pytest.raises(OSError, match="No space left on device") as e:
        bd.render_many(jobs, client, tmp_path, progress=False, manifest_interval=0.0)
    assert e.value.errno == errno.ENOSPC
    man = _manifest(tmp_path)
    done = sorted(man["frames"])
    assert 0 < len(done) < 30
    on_disk = {p.stem for p in tmp_path.glob("*.png")}
    assert set(done) <= on_disk  # a frame may be on disk and not yet listed: it is rendered again
    _assert_complete_subset(tmp_path, man)
    monkeypatch.setattr(bd, "_write_bytes", real)
    report = bd.render_many(jobs, client, tmp_path, progress=False)
    assert sorted(report.skipped) == done and len(report.rendered) == 30 - len(done)
    _assert_complete(tmp_path, [f"frame_{i:05d}" for i in range(30)])


def _assert_complete_subset(out: Path, man: dict[str, Any]) -> None:
    for entry in man["frames"].values():
        info = entry["files"]["png"]
        assert hashlib.sha256((out / info["file"]).read_bytes()).hexdigest() == info["sha256"]
    assert not [p for p in out.iterdir() if ".tmp-" in p.name]


# -- fit_many --------------------------------------------------------------------------------------


def test_fit_many_fits_each_table_as_a_local_fit_does(client: Any, tmp_path: Path) -> None:
    truths = [brdfpy.model("cook_torrance", roughness=r, kd=kd) for r, kd in ((0.15, 0.3), (0.35, 0.6))]
    tables = [measured.Tabulated.from_model(m, (24, 24, 48)) for m in truths]
    path = tmp_path / "second.binary"
    tables[1].save_merl(path)
    corrupt = tmp_path / "corrupt.binary"
    corrupt.write_bytes(b"\x01\x00\x00\x00" * 5)
    start = {"roughness": 0.5, "kd": 0.4}
    fixed = {"ks": 1.0}
    rows = bd.fit_many(
        [tables[0], str(path), corrupt],
        "cook_torrance",
        start=start,
        fixed=fixed,
        samples=3000,
        client=client,
        errors="report",
    )
    assert [r["index"] for r in rows] == [0, 1, 2]
    assert rows[1]["name"] == str(path)
    assert rows[2]["error"] is not None and "tables[2]" in rows[2]["error"]
    assert np.isnan(rows[2]["rms_log_error"])
    l, v = bd._fit_directions(3000, 0)
    for i, t in enumerate(tables):
        local = measured.fit(
            "cook_torrance", l, v, [0, 0, 1], t.as_model().eval(l, v, [0, 0, 1]), start=start, fixed=fixed
        )
        assert rows[i]["values"] == local["values"] and rows[i]["error"] is None
        assert rows[i]["rms_log_error"] == local["rms_log_error"]
        assert rows[i]["values"]["roughness"] == pytest.approx(truths[i].params["roughness"], abs=0.02)
    with pytest.raises(bd.JobsFailed, match=r"1 of 2 fits failed[\s\S]*tables\[1\]"):
        bd.fit_many([tables[0], corrupt], "cook_torrance", start=start, samples=500, client=client)
    with pytest.raises(ValueError, match="model_name: unknown model"):
        bd.fit_many(tables, "cook", start=start, client=client)
    with pytest.raises(ValueError, match=r"start, fixed: .*roughnes"):
        bd.fit_many(tables, "cook_torrance", start={"roughnes": 0.1}, client=client)
    with pytest.raises(FileNotFoundError, match=r"tables\[0\]: no such file"):
        bd.fit_many([tmp_path / "nope.binary"], "cook_torrance", start=start, client=client)


# -- brdfpy batch ----------------------------------------------------------------------------------


SPEC = {
    "mesh": "icosphere:3",
    "models": [
        {
            "name": "cook_torrance",
            "params": {"roughness": {"range": [0.1, 0.5], "steps": 2}, "kd": [0.5, 0.1, 0.1]},
        },
        {"name": "lambert", "params": {"kd": {"values": [0.2, 0.8]}}},
    ],
    "camera": {"frames": 3, "elevation": 25},
    "size": [64, 48],
    "shadows": True,
    "ao": {"samples": 8},
    "name": "demo",
}


def test_the_batch_command_renders_a_spec_on_a_running_scheduler(client: Any, tmp_path: Path) -> None:
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps(SPEC))
    out = tmp_path / "frames"
    argv = ["batch", str(spec), "-o", str(out), "--scheduler", client.scheduler.address, "--no-progress"]
    assert cli_main(argv) == 0
    names = [f"demo_m{m}_f{k}" for m in range(4) for k in range(3)]
    man = _assert_complete(out, names)
    assert man["frames"]["demo_m1_f2"]["params"] == {
        "model": "cook_torrance",
        "roughness": 0.5,
        "kd": [0.5, 0.1, 0.1],
        "frame": 2,
        "azimuth": 240.0,
    }
    with PILImage.open(out / "contact_sheet.png") as im:
        assert im.size == (4 + 3 * (160 + 4), 4 + 4 * (14 + 120 + 4))
    # Again: nothing left to do.
    assert cli_main(argv) == 0
    assert _manifest(out)["frames"] == man["frames"] | {k: man["frames"][k] for k in man["frames"]}


def test_the_batch_command_without_a_scheduler_starts_local_worker_processes(tmp_path: Path) -> None:
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps({**SPEC, "models": ["lambert"], "camera": {"frames": 2}}))
    out = tmp_path / "frames"
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "brdfpy",
            "batch",
            str(spec),
            "-o",
            str(out),
            "--workers",
            "2",
            "--no-progress",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    assert "2 frames on 2 workers" in r.stderr
    _assert_complete(out, ["demo_m0_f0", "demo_m0_f1"])
    workers = {e["worker"] for e in _manifest(out)["frames"].values()}
    assert str(os.getpid()) not in {w.rsplit(":", 1)[1] for w in workers}  # rendered in other processes


def test_the_batch_command_fails_clearly_on_a_bad_spec_or_a_silent_scheduler(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps({**SPEC, "models": [{"name": "ward", "params": {"alpha_x": -1}}]}))
    # The spec is checked first: the scheduler (which would time out) is never contacted.
    t0 = time.monotonic()
    assert cli_main(["batch", str(spec), "-o", str(tmp_path / "o"), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    assert time.monotonic() - t0 < 5
    assert (
        'brdfpy batch: error: models[0].params: parameter "alpha_x": must be in [0, 2]'
        in capsys.readouterr().err
    )
    spec.write_text(json.dumps(SPEC))
    t0 = time.monotonic()
    argv = [
        "batch",
        str(spec),
        "-o",
        str(tmp_path / "o"),
        "--scheduler",
        "tcp://127.0.0.1:9",
        "--timeout",
        "2",
    ]
    assert cli_main(argv) == 2
    assert time.monotonic() - t0 < 15
    err = capsys.readouterr().err
    assert "--scheduler tcp://127.0.0.1:9: no Dask scheduler answered within 2 s" in err
    spec.write_text("{not json")
    assert cli_main(["batch", str(spec), "-o", str(tmp_path / "o")]) == 2
    assert "spec: spec.json is not valid JSON" in capsys.readouterr().err
