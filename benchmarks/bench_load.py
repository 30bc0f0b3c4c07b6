"""Scene-file loading: the time to load a ~1M-triangle glTF (``.glb``) and binary STL with brdfpy against
trimesh loading the same file, in the same run.

The files are written by trimesh (``trimesh.creation.icosphere(8)``, 1,310,720 triangles, 655,362 vertices;
``--subdivisions`` changes it, ``--quick`` uses 5) into a temporary folder. Timed, alternating the two
loaders, median of ``--repeat`` loads each:

- glTF: ``brdfpy.load_scene(path)`` (decode in Rust, build the ``Scene``, its materials and a framing
  camera) and ``brdfpy._brdfpy.load_gltf(path)`` (the decode alone) against ``trimesh.load(path)`` (a
  ``trimesh.Scene``, with trimesh's default processing);
- STL: ``brdfpy.load_mesh(path)`` (parse and weld the corners by position, normals computed) and
  ``brdfpy.load_scene(path)`` against ``trimesh.load(path)`` (which also merges vertices).

The ratio is brdfpy's time over trimesh's (< 1: brdfpy is faster). The machine's load average is recorded
before and after (it is shared: a busy machine inflates both sides, the ratio less so).

Run through ``python benchmarks/run.py load`` or directly; ``--quick`` checks that it runs. Needs trimesh.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import tempfile
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any


def _time(fn: Callable[[], Any]) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def bench(subdivisions: int, repeat: int) -> dict[str, Any]:
    import brdfpy
    import trimesh
    from brdfpy import _brdfpy

    load_before = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions)
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp:
        glb, stl = Path(tmp) / "sphere.glb", Path(tmp) / "sphere.stl"
        mesh.export(glb)
        mesh.export(stl)
        cases: dict[str, tuple[Path, dict[str, Callable[[], Any]]]] = {
            "glb": (
                glb,
                {
                    "brdfpy.load_scene": lambda: brdfpy.load_scene(glb),
                    "brdfpy decode (_brdfpy.load_gltf)": lambda: _brdfpy.load_gltf(str(glb)),
                    "trimesh.load": lambda: trimesh.load(glb),
                },
            ),
            "stl": (
                stl,
                {
                    "brdfpy.load_mesh": lambda: brdfpy.load_mesh(stl, orient="keep"),
                    "brdfpy.load_scene": lambda: brdfpy.load_scene(stl),
                    "trimesh.load": lambda: trimesh.load(stl),
                },
            ),
        }
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for fmt, (path, loaders) in cases.items():
                times: dict[str, list[float]] = {k: [] for k in loaders}
                for fn in loaders.values():  # one warm-up each (file cache, imports)
                    fn()
                for _ in range(repeat):
                    for k, fn in loaders.items():
                        times[k].append(_time(fn))
                base = statistics.median(times["trimesh.load"])
                for k, ts in times.items():
                    med = statistics.median(ts)
                    rows.append(
                        {
                            "format": fmt,
                            "loader": k,
                            "seconds": med,
                            "ratio_to_trimesh": med / base,
                            "bytes": path.stat().st_size,
                        }
                    )
    return {
        "machine": {
            "platform": platform.platform(),
            "cpus": os.cpu_count(),
            "threads": brdfpy.get_num_threads(),
            "brdfpy": brdfpy.__version__,
            "trimesh": trimesh.__version__,
            "loadavg_before": load_before,
            "loadavg_after": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
        "triangles": len(mesh.faces),
        "vertices": len(mesh.vertices),
        "repeat": repeat,
        "rows": rows,
    }


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--subdivisions", type=int, default=8, help="icosphere subdivisions (8: 1.3M triangles)")
    p.add_argument("--repeat", type=int, default=3, help="loads per loader, median time (default 3)")
    p.add_argument("--quick", action="store_true", help="a small mesh: checks that the benchmark runs")
    p.add_argument("--json", default=None, help="also write the results to this file")
    a = p.parse_args(argv)
    if a.quick:
        a.subdivisions, a.repeat = 5, 1
    result = bench(a.subdivisions, a.repeat)
    m = result["machine"]
    print(
        f"{result['triangles']:,} triangles, median of {result['repeat']} loads, load average "
        f"{m['loadavg_before']} -> {m['loadavg_after']}"
    )
    for row in result["rows"]:
        print(
            f"  {row['format']:4s} {row['loader']:36s} {row['seconds']:8.3f} s  "
            f"{row['ratio_to_trimesh']:6.2f} x trimesh  ({row['bytes'] / 1e6:.1f} MB)"
        )
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
