"""Speed of ``brdfpy.measured.fit`` (issue 14): fitting Cook-Torrance (GGX) with every continuous parameter
free and no start (multi-start, finite-difference Jacobian) to

- a full-resolution MERL-layout table (90 x 90 x 180 = 1.46 M cells) made from a model, sampled by the
  default strategy (20 000 cosine-distributed pairs below 80°; the time includes drawing the samples), and
- 10 000 scattered samples given as arrays,

on 1 and 2 threads, with the analytic Jacobian (``jacobian="auto"``) and with central differences in the same
run. Each figure is the best of ``--repeat`` runs (wall clock; the median is in the JSON). The
machine may be shared: the 1-minute load average before and after is recorded.

Run through ``python benchmarks/run.py fit`` or directly (``python benchmarks/bench_fit.py``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from typing import Any, Callable


def _time(f: Callable[[], Any], repeat: int) -> tuple[float, float, Any]:
    ts, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t0)
    return min(ts), statistics.median(ts), out


def main(argv: list[str] | None = None) -> dict[str, Any]:
    import brdfpy
    import numpy as np
    from brdfpy import measured

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--quick", action="store_true", help="a small table, one repeat (checks that it runs)")
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args(argv)
    repeat = 1 if args.quick else args.repeat
    res = (16, 16, 32) if args.quick else measured.MERL_RESOLUTION
    truth = brdfpy.model("cook_torrance", roughness=0.2, kd=(0.5, 0.3, 0.1), f0=(0.04, 0.05, 0.06))
    t0 = time.perf_counter()
    table = measured.Tabulated.from_model(truth, res)
    tabulate_s = time.perf_counter() - t0
    rng = np.random.default_rng(0)
    count = 1000 if args.quick else 10_000

    def hemi(k: int) -> Any:
        z = rng.uniform(np.cos(np.radians(80)), 1, k)
        phi = rng.uniform(0, 2 * np.pi, k)
        s = np.sqrt(1 - z * z)
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)

    l, v = hemi(count), hemi(count)
    values = truth.eval(l, v, [0, 0, 1])
    before = os.getloadavg()[0]
    threads_before = brdfpy.get_num_threads()
    rows = []
    try:
        cases = [
            (f"table {res[0]}x{res[1]}x{res[2]}, 20000 samples", jac, (table,))
            for jac in ("auto", "finite_difference")
        ] + [
            (f"{count} scattered samples", jac, (l, v, [0, 0, 1], values))
            for jac in ("auto", "finite_difference")
        ]
        for threads in (1, 2):
            brdfpy.set_num_threads(threads)
            for case, jac, data in cases:

                def run(data: Any = data, jac: str = jac) -> Any:
                    return measured.fit("cook_torrance", *data, jacobian=jac)

                best, median, rep = _time(run, repeat)
                err = max(
                    abs(rep.params["roughness"] - 0.2),
                    *(abs(a - b) for a, b in zip(rep.params["kd"], (0.5, 0.3, 0.1))),
                )
                rows.append(
                    {
                        "case": case,
                        "jacobian": rep.jacobian,
                        "threads": threads,
                        "best_s": best,
                        "median_s": median,
                        "iterations": rep.iterations,
                        "starts": rep.starts,
                        "converged": rep.converged,
                        "max_param_error": err,
                    }
                )
                print(
                    f"{case:<40} {rep.jacobian:<17} {threads} thread(s): {best:7.3f} s (median {median:.3f}) "
                    f"{rep.iterations} iterations, {rep.starts} starts, max |param error| {err:.1e}",
                    flush=True,
                )
    finally:
        brdfpy.set_num_threads(threads_before)
    return {
        "tabulate_seconds": tabulate_s,
        "rows": rows,
        "load_before": before,
        "load_after": os.getloadavg()[0],
        "cpus": os.cpu_count(),
    }


if __name__ == "__main__":
    main()
