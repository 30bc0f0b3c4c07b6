"""brdfpy on a Dask cluster against local loops, on this machine: a ``distributed.LocalCluster`` of 2 worker
processes with 1 thread each (brdfpy's own pool set to 1 thread per worker by ``brdfpy.distributed``).

What is measured:

- ``render_many``: ``--frames`` frames (default 200) of a sweep at 640×480 (Garland's cow on a floor,
  Cook-Torrance roughness sweep × turntable, hard shadows), rendered, PNG-encoded and written with the
  manifest, against a local loop doing the same (render, encode, write) with brdfpy on 1 thread, and on
  all threads. Target: the cluster ≥ 1.6× the 1-thread loop. The cluster's start-up is reported apart.
- per-task overhead: the same with 8×6-pixel frames (the work per task is ~0): wall time per task.
- bytes per task: the pickled arguments the scheduler sends with each render task (what crosses the
  network per task), with the scene scattered to the workers once (a reference) and without (the scene,
  mesh arrays included, in every task).
- ``eval``: ``brdfpy.distributed.eval`` of Cook-Torrance on ``--rows`` rows (default 10^8) held by the
  workers (persisted Dask arrays) against ``Model.eval`` on the same number of rows in this process (all
  threads). Target: ≤ 1.3× the local time. Also the threaded scheduler in this process, from an in-memory
  array into a preallocated one (``da.store``).

The machine is shared: ``uptime`` (load averages) is recorded with each figure; compare figures from a
quiet window. Run: ``python benchmarks/run.py dask`` (``--quick`` for tiny sizes).
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np


def _load() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def _sweep_spec(frames: int, width: int, height: int) -> dict[str, Any]:
    per = 20 if frames >= 20 else frames
    steps = max(1, frames // per)
    return {
        "mesh": "cow",
        "models": [
            {"name": "cook_torrance", "params": {"roughness": {"range": [0.05, 0.7], "steps": steps}}}
        ],
        "camera": {"frames": per, "elevation": 20},
        "size": [width, height],
        "shadows": True,
        "name": "bench",
    }


def _local_loop(sweep: Any, out: Path, threads: int | None) -> float:
    import brdfpy
    from brdfpy import distributed as bd

    brdfpy.set_num_threads(threads)
    try:
        t0 = time.perf_counter()
        for job in bd.sweep_jobs(sweep):
            res = bd._render_job(job.scene, job.camera, dict(job.options), dict(job.instances), ("png",))
            bd._write_bytes(out / f"{job.name}.png", res["files"]["png"])
        return time.perf_counter() - t0
    finally:
        brdfpy.set_num_threads(None)


def _task_bytes(job: Any, scene_arg: Any) -> int:
    from brdfpy import distributed as bd
    from distributed.protocol import pickle as dask_pickle

    args = (scene_arg, job.camera, bd._check_options("o", job.options), dict(job.instances), ("png",))
    buffers: list[Any] = []
    data = dask_pickle.dumps(args, buffer_callback=buffers.append)
    return len(data) + sum(memoryview(b).nbytes for b in buffers)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--quick", action="store_true", help="tiny sizes (checks that the benchmark runs)")
    p.add_argument("--frames", type=int, default=200)
    p.add_argument("--rows", type=int, default=100_000_000)
    p.add_argument("--repeat", type=int, default=3, help="eval timings: best of N")
    args = p.parse_args(argv)
    frames, rows, width, height = args.frames, args.rows, 640, 480
    if args.quick:
        frames, rows, width, height = 20, 1_000_000, 160, 120

    import brdfpy
    import dask.array as da
    import distributed
    from brdfpy import distributed as bd
    from brdfpy.sweep import load_spec

    result: dict[str, Any] = {"machine": {"cpus": os.cpu_count(), "platform": sys.platform}}
    tmp = Path(tempfile.mkdtemp(prefix="bench-dask-"))
    try:
        t0 = time.perf_counter()
        cluster = bd.local_cluster(2, dashboard_address=None)
        client = distributed.Client(cluster)
        startup = time.perf_counter() - t0
        result["cluster"] = {"workers": 2, "threads_per_worker": 1, "startup_s": round(startup, 2)}
        with cluster, client:
            # -- render_many
            sweep = load_spec(_sweep_spec(frames, width, height))
            n = len(sweep.jobs)
            load0 = _load()
            bd.render_many(load_spec(_sweep_spec(4, 32, 24)), client, tmp / "warm", progress=False)  # imports
            t0 = time.perf_counter()
            rep = bd.render_many(sweep, client, tmp / "cluster", progress=False, resume=False)
            t_cluster = time.perf_counter() - t0
            load1 = _load()
            (tmp / "local1").mkdir()
            (tmp / "localN").mkdir()
            t_local1 = _local_loop(sweep, tmp / "local1", 1)
            load2 = _load()
            t_localn = _local_loop(sweep, tmp / "localN", None)
            tiny = load_spec(_sweep_spec(frames, 8, 6))
            t0 = time.perf_counter()
            bd.render_many(tiny, client, tmp / "tiny", progress=False, resume=False)
            t_tiny = time.perf_counter() - t0
            assert len(rep.rendered) == n
            same = all(
                (tmp / "cluster" / f"{j.name}.png").read_bytes()
                == (tmp / "local1" / f"{j.name}.png").read_bytes()
                for j in sweep.jobs
            )
            result["render_many"] = {
                "frames": n,
                "size": [width, height],
                "cluster_s": round(t_cluster, 3),
                "local_1_thread_s": round(t_local1, 3),
                "local_all_threads_s": round(t_localn, 3),
                "speedup_vs_1_thread": round(t_local1 / t_cluster, 3),
                "speedup_vs_all_threads": round(t_localn / t_cluster, 3),
                "target_speedup_vs_1_thread": 1.6,
                "ms_per_frame_cluster": round(1e3 * t_cluster / n, 2),
                "ms_per_frame_local_1_thread": round(1e3 * t_local1 / n, 2),
                "pngs_identical_to_local": same,
                "overhead_ms_per_task": round(1e3 * t_tiny / n, 2),
                "uptime": {"before": load0, "after_cluster": load1, "after_local": load2},
            }
            # -- bytes per task
            job = bd.sweep_jobs(sweep)[0]
            ref = client.scatter(sweep.scene, broadcast=True, hash=False)
            result["bytes_per_task"] = {
                "scattered_scene": _task_bytes(job, ref),
                "scene_in_every_task": _task_bytes(job, sweep.scene),
                "mesh_faces": sweep.scene.instances[0].mesh.n_faces,
                "note": "pickled task arguments (out-of-band buffers included) sent with each render task",
            }
            del ref
            # -- eval
            m = brdfpy.model("cook_torrance", roughness=0.3)
            chunk = min(rows, 4_000_000)
            v, nn = np.array([0.0, 0.6, 0.8], np.float32), np.array([0.0, 0.0, 1.0], np.float32)
            rng = np.random.default_rng(0)
            l_np = rng.random((rows, 3), dtype=np.float32) - np.float32(0.5)
            l_np[:, 2] = np.abs(l_np[:, 2])
            load3 = _load()
            local = []
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                ref_out = m.eval(l_np, v, nn)
                local.append(time.perf_counter() - t0)
            del ref_out
            # The same rows on the workers (made there: shipping 1.2 GB through the scheduler is not the
            # case being measured), results kept there.
            dl = da.from_array(l_np, chunks=(chunk, 3)) if args.quick else None
            if dl is None:
                dl = (
                    da.random.default_rng(0).random((rows, 3), chunks=(chunk, 3), dtype=np.float32) - 0.5
                ).astype(np.float32)
            dl = client.persist(dl)
            distributed.wait(dl)
            dask_times = []
            for k in range(args.repeat):
                # Another view direction each time: the same evaluation twice is one graph key (cached).
                vk = np.array([0.0, 0.6, 0.8 + 1e-3 * k], np.float32)
                t0 = time.perf_counter()
                r = client.persist(bd.eval(m, dl, vk, nn))
                distributed.wait(r)
                dask_times.append(time.perf_counter() - t0)
                del r
            del dl
            load4 = _load()
            out = np.empty((rows, 3), np.float32)
            thr = []
            for k in range(args.repeat):
                vk = np.array([0.0, 0.6, 0.8 + 1e-3 * k], np.float32)
                t0 = time.perf_counter()
                da.store(
                    bd.eval(m, da.from_array(l_np, chunks=(chunk, 3)), vk, nn),
                    out,
                    lock=False,
                    scheduler="threads",
                )
                thr.append(time.perf_counter() - t0)
            local_s, cluster_s, threads_s = min(local), min(dask_times), min(thr)
            result["eval"] = {
                "model": "cook_torrance",
                "rows": rows,
                "chunk_rows": chunk,
                "local_s": round(local_s, 3),
                "cluster_s": round(cluster_s, 3),
                "threads_scheduler_s": round(threads_s, 3),
                "cluster_over_local": round(cluster_s / local_s, 3),
                "threads_over_local": round(threads_s / local_s, 3),
                "target_over_local": 1.3,
                "local_all_s": [round(x, 3) for x in local],
                "cluster_all_s": [round(x, 3) for x in dask_times],
                "uptime": {"before": load3, "after": load4, "end": _load()},
            }
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    rm, bt, ev = result["render_many"], result["bytes_per_task"], result["eval"]
    print(
        f"render_many {rm['frames']} x {width}x{height}: cluster {rm['cluster_s']} s, "
        f"local 1 thread {rm['local_1_thread_s']} s ({rm['speedup_vs_1_thread']}x), "
        f"all threads {rm['local_all_threads_s']} s ({rm['speedup_vs_all_threads']}x); "
        f"overhead {rm['overhead_ms_per_task']} ms/task; load {rm['uptime']}"
    )
    print(f"bytes per task: scattered {bt['scattered_scene']}, in every task {bt['scene_in_every_task']}")
    print(
        f"eval {rows} rows: local {ev['local_s']} s, cluster {ev['cluster_s']} s "
        f"({ev['cluster_over_local']}x), threads scheduler {ev['threads_scheduler_s']} s "
        f"({ev['threads_over_local']}x); load {ev['uptime']}"
    )
    print(f"median local eval {statistics.median(ev['local_all_s'])} s")
    return result


if __name__ == "__main__":
    main()
