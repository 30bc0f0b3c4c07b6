"""Run every benchmark (``benchmarks/bench_*.py``) and write ``benchmarks/results/<name>.json``.

Usage: ``python benchmarks/run.py [--quick] [NAME ...]``; extra options after ``--`` go to every benchmark.
Each benchmark module has ``main(argv) -> dict``, prints its own table and returns what is written.
Benchmarks are never part of the test suite: timings here are reported, not asserted.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("names", nargs="*", help="benchmarks to run (default: all), e.g. eval")
    p.add_argument("--quick", action="store_true", help="tiny sizes, to check that every benchmark runs")
    p.add_argument("--out", default=str(HERE / "results"), help="folder for the JSON files")
    args, extra = p.parse_known_args(argv)
    extra = [x for x in extra if x != "--"]
    files = sorted(HERE.glob("bench_*.py"))
    known = [f.stem.removeprefix("bench_") for f in files]
    unknown = [n for n in args.names if n not in known]
    if unknown:
        p.error(f"unknown benchmark(s) {unknown}; known: {known}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for f in files:
        name = f.stem.removeprefix("bench_")
        if args.names and name not in args.names:
            continue
        spec = importlib.util.spec_from_file_location(f"bench_{name}", f)
        assert spec is not None and spec.loader is not None
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        print(f"== {name}", flush=True)
        t0 = time.perf_counter()
        result = mod.main([*extra, *(["--quick"] if args.quick else [])])
        result["wall_seconds"] = time.perf_counter() - t0
        path = out / f"{name}.json"
        path.write_text(json.dumps(result, indent=2) + "\n")
        print(f"wrote {path} ({result['wall_seconds']:.1f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
