"""Update latency of the browser explorer (issue 11): ``brdfpy explore`` is started as a user starts it,
Debian's headless Chromium opens the page (Selenium, tests/browser.py), and each of several controls (θ_i,
φ, the roughness parameter, the distribution choice) is changed from the browser ``--count`` times; each
latency is the time from the change in the page until the page holds the redrawn views (the status line
arrives in the same message as the images: lit sphere and lit object at 512 x 512, lobe, polar slice; the
slice and albedo are recomputed when the model changes, cached otherwise) and the browser has painted the
next frame. Median and 95th percentile are reported per control and over all, with the server's own compute
time per frame; the target is 150 ms on the project's 2-core machine. The 1-minute load average before and
after is recorded: with other work on the cores the figures are upper bounds.

Run through ``python benchmarks/run.py explore`` or directly. Needs chromium, chromium-driver and
``brdfpy[explore]`` + selenium.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))


# The controls whose changes are timed: (label, page-model type, values cycled through). Incidence,
# azimuth, a registry parameter (an editable slider: its slider half is moved) and a choice (a new D).
CONTROLS: list[tuple[str, str, list[Any]]] = [
    ("θ_i", "Slider", [15.0 + (k * 37) % 70 for k in range(8)]),
    ("φ", "Slider", [-150.0 + (k * 47) % 300 for k in range(8)]),
    ("roughness", "Slider", [0.1, 0.45, 0.2, 0.7, 0.3, 0.55, 0.15, 0.8]),
    ("distribution", "Select", ["beckmann", "ggx", "gaussian", "ggx", "blinn_phong", "ggx"]),
]


def percentile(sorted_ms: list[float], q: float) -> float:
    return sorted_ms[min(len(sorted_ms) - 1, round(q * (len(sorted_ms) - 1)))]


def main(argv: list[str] | None = None) -> dict[str, Any]:
    import browser as B

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--quick", action="store_true", help="3 changes per control only")
    p.add_argument("--count", type=int, default=20, help="changes per control (default 20)")
    p.add_argument("--models", default="cook_torrance", help="the models the explorer starts with")
    args = p.parse_args(argv)
    missing = B.available()
    if missing:
        print(f"skipped: {missing}")
        return {"benchmark": "explore", "skipped": missing}
    count = 3 if args.quick else args.count
    before = os.getloadavg()[0]
    per_control: dict[str, dict[str, Any]] = {}
    with B.server(args.models) as url, B.browser() as d:
        B.open_page(d, url)
        for k in range(3):  # warm up (first frames, caches)
            B.latency_ms(d, "θ_i", 10.0 + k)
        for label, kind, values in CONTROLS:
            lat, server = [], []
            for k in range(count):
                lat.append(B.latency_ms(d, label, values[k % len(values)], kind))
                status = d.execute_script("return __status()")
                server.append(float(status.split(":")[1].split("ms")[0]))
            lat.sort()
            per_control[label] = {
                "latency_ms": lat,
                "median_ms": statistics.median(lat),
                "p95_ms": percentile(lat, 0.95),
                "server_compute_median_ms": statistics.median(server),
            }
            r = per_control[label]
            print(
                f"{args.models} {label:>12}: latency median {r['median_ms']:.0f} ms, "
                f"p95 {r['p95_ms']:.0f} ms, {count} changes "
                f"(server compute median {r['server_compute_median_ms']:.0f} ms)",
                flush=True,
            )
    after = os.getloadavg()[0]
    every = sorted(x for r in per_control.values() for x in r["latency_ms"])
    med, p95 = statistics.median(every), percentile(every, 0.95)
    worst = max(per_control, key=lambda k: per_control[k]["median_ms"])
    print(
        f"every control: median {med:.0f} ms, p95 {p95:.0f} ms (target 150 ms; slowest control {worst}: "
        f"median {per_control[worst]['median_ms']:.0f} ms); load {before:.1f} -> {after:.1f}"
    )
    return {
        "benchmark": "explore",
        "models": args.models,
        "count_per_control": count,
        "controls": per_control,
        "median_ms": med,
        "p95_ms": p95,
        "loadavg_before": before,
        "loadavg_after": after,
        "target_ms": 150.0,
    }


if __name__ == "__main__":
    main()
