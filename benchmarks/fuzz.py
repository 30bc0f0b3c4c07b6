"""The long hostile-input campaign over brdfpy's public API, in subprocesses.

Usage: ``python benchmarks/fuzz.py [--calls N] [--workers W] [--chunk C] [--timeout S] [--seed K]
[--only SUBSTRING] [--out DIR] [--json FILE]``

Call ``i`` of the campaign is target ``i mod T`` of ``tests/fuzzing/api.targets()`` (every public function,
class and method, round robin) with arguments drawn from ``random.Random(f"{seed}:{i}")``: a pure function
of ``(seed, i)``, so any call is replayed by ``--replay i``. Workers run chunks of consecutive calls
under a memory ceiling, writing the index of the call in progress to a shared page; when a worker dies
(segfault, abort, out of memory) or stops making progress for ``--timeout`` seconds (a hang), the
parent records the call at that index as a crash or a hang, saves a reproducer
(``<out>/reproducers/<kind>-<index>.py``) and resumes the chunk after it. Failures that a worker
classifies itself (wrong exception type, a message naming nothing, NaN from finite input) are saved
the same way.

Prints calls, outcome classes (ok / clean / failure / crash / hang) and rates per target, and writes
JSON (default ``benchmarks/results/fuzz.json``). Exit status 1 if anything failed.
"""

from __future__ import annotations

import argparse
import collections
import json
import mmap
import os
import random
import resource
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "tests"))

#: Address space a worker may use (an absurd size must be refused, not allocated).
WORKER_MEMORY = 6 << 30
KINDS = ("ok", "clean", "failure", "crash", "hang")


def _rng(seed: int, index: int) -> random.Random:
    return random.Random(f"{seed}:{index}")


def _targets(only: str | None) -> list[Any]:
    from fuzzing import api

    ts = list(api.targets())
    return [t for t in ts if only in t.qualname] if only else ts


def _describe(seed: int, index: int, only: str | None) -> tuple[str, str]:
    """(target, call text) of call ``index`` without running it."""
    from fuzzing import api

    ts = _targets(only)
    t = ts[index % len(ts)]
    r = _rng(seed, index)
    try:
        t.get(r)
        args, kwargs = api.draw(t, r, 0.35)
        shown = ", ".join([api._short(a) for a in args] + [f"{k}={api._short(v)}" for k, v in kwargs.items()])
        return t.qualname, f"{t.qualname}({shown})"
    except Exception as e:
        return t.qualname, f"{t.qualname}(<arguments could not be drawn again: {e}>)"


def _reproducer(out: Path, kind: str, seed: int, index: int, only: str | None, detail: str) -> Path:
    qualname, text = _describe(seed, index, only)
    d = out / "reproducers"
    d.mkdir(parents=True, exist_ok=True)
    p = d / f"{kind}-{qualname.replace('brdfpy.', '')}-{seed}-{index}.py"
    only_arg = f" --only {only!r}" if only else ""
    p.write_text(
        f'"""{kind}: {detail}\n\ncall: {text}\n\n'
        f"Replay: python benchmarks/fuzz.py --seed {seed} --replay {index}{only_arg}\n" + '"""\n\n'
        "import random\nimport sys\n\nsys.path.insert(0, 'tests')\nfrom fuzzing import api\n\n"
        f"targets = [t for t in api.targets() if {only!r} in t.qualname]"
        f" if {only!r} else list(api.targets())\n"
        f"target = targets[{index} % len(targets)]\n"
        f"print(api.call(target, random.Random('{seed}:{index}')))\n"
    )
    return p


# ------------------------------------------------------------------------------------------ worker


def worker(seed: int, start: int, count: int, only: str | None, progress_path: str) -> None:
    """Run calls ``start .. start+count``; one JSON line of counts (and failures) on stdout at the end."""
    hard = resource.getrlimit(resource.RLIMIT_AS)[1]
    resource.setrlimit(resource.RLIMIT_AS, (WORKER_MEMORY, hard))
    from fuzzing import api

    ts = _targets(only)
    with open(progress_path, "r+b") as f:
        page = mmap.mmap(f.fileno(), 8)
    counts: dict[str, collections.Counter[str]] = collections.defaultdict(collections.Counter)
    failures: list[dict[str, Any]] = []
    seconds: collections.Counter[str] = collections.Counter()
    for i in range(start, start + count):
        page[:8] = struct.pack("<q", i)
        t = ts[i % len(ts)]
        t0 = time.perf_counter()
        o = api.call(t, _rng(seed, i))
        seconds[t.qualname] += time.perf_counter() - t0
        counts[t.qualname][o.kind] += 1
        if o.kind == "clean":
            counts[t.qualname][f"exc:{o.exception}"] += 1
        if o.kind == "failure" and len(failures) < 200:
            failures.append({"index": i, "target": t.qualname, "detail": o.detail, "call": o.call})
    page[:8] = struct.pack("<q", start + count)
    print(
        json.dumps(
            {
                "counts": {k: dict(v) for k, v in counts.items()},
                "seconds": dict(seconds),
                "failures": failures,
            }
        )
    )


# ------------------------------------------------------------------------------------------ parent


def campaign(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    ts = _targets(args.only)
    counts: dict[str, collections.Counter[str]] = collections.defaultdict(collections.Counter)
    seconds: collections.Counter[str] = collections.Counter()
    failures: list[dict[str, Any]] = []
    seen_failures: set[tuple[str, str]] = set()
    t0 = time.perf_counter()
    load0 = os.getloadavg()
    # Chunks of consecutive indices; a list of (start, count) still to run.
    todo = [(s, min(args.chunk, args.calls - s)) for s in range(0, args.calls, args.chunk)]
    running: list[tuple[subprocess.Popen[str], int, int, str, float, int]] = []
    me = [sys.executable, str(Path(__file__).resolve())]
    done_calls = 0
    last_report = time.perf_counter()

    def start(s: int, c: int) -> None:
        fd, progress = tempfile.mkstemp(prefix="brdfpy-fuzz-progress-")
        os.write(fd, struct.pack("<q", s))
        os.close(fd)
        cmd = [
            *me,
            "--worker",
            "--seed",
            str(args.seed),
            "--start",
            str(s),
            "--count",
            str(c),
            "--progress",
            progress,
        ]
        if args.only:
            cmd += ["--only", args.only]
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
        running.append((p, s, c, progress, time.perf_counter(), s))

    def position(progress: str) -> int:
        with open(progress, "rb") as f:
            return int(struct.unpack("<q", f.read(8))[0])

    while todo or running:
        while todo and len(running) < args.workers:
            start(*todo.pop(0))
        time.sleep(0.2)
        for entry in list(running):
            p, s, c, progress, last_t, last_i = entry
            i = position(progress)
            now = time.perf_counter()
            if i != last_i:
                # Replace the entry (and keep the name on the new one: it is removed below when done).
                k = running.index(entry)
                entry = running[k] = (p, s, c, progress, now, i)
                last_t = now
            code = p.poll()
            hung = code is None and now - last_t > args.timeout
            if code is None and not hung:
                continue
            running.remove(entry)
            if hung:
                p.kill()
            stdout, stderr = p.communicate()
            os.unlink(progress)
            if code == 0 and stdout.strip():
                report = json.loads(stdout.strip().splitlines()[-1])
                for target, cs in report["counts"].items():
                    counts[target].update(cs)
                seconds.update(report["seconds"])
                for f in report["failures"]:
                    done_key = (f["target"], f["detail"][:80])
                    if done_key not in seen_failures:
                        seen_failures.add(done_key)
                        f["reproducer"] = str(
                            _reproducer(out, "failure", args.seed, f["index"], args.only, f["detail"])
                        )
                        failures.append(f)
                done_calls += c
                continue
            # A crash or a hang at index i: record it, resume after it.
            kind = "hang" if hung else "crash"
            target = ts[i % len(ts)].qualname
            counts[target][kind] += 1
            detail = f"exit status {code}" if not hung else f"no progress for {args.timeout} s"
            tail = (stderr or "").strip().splitlines()[-5:]
            f = {"index": i, "target": target, "detail": f"{kind}: {detail}; stderr: {' | '.join(tail)}"}
            f["reproducer"] = str(_reproducer(out, kind, args.seed, i, args.only, f["detail"]))
            f["call"] = _describe(args.seed, i, args.only)[1]
            failures.append(f)
            print(f"  {kind} at call {i} ({target}): {f['reproducer']}", flush=True)
            done_calls += i - s + 1
            if s + c > i + 1:
                todo.insert(0, (i + 1, s + c - i - 1))
        if time.perf_counter() - last_report > 60:
            last_report = time.perf_counter()
            rate = done_calls / (last_report - t0)
            print(f"  {done_calls} calls done, {rate:.0f} calls/s, load {os.getloadavg()[0]:.1f}", flush=True)

    wall = time.perf_counter() - t0
    totals: collections.Counter[str] = collections.Counter()
    for cs in counts.values():
        totals.update({k: v for k, v in cs.items() if k in KINDS})
    calls = sum(totals.values())
    head = ("calls", "ok", "clean", "fail", "crash", "hang")
    print(f"\n{'target':52} " + " ".join(f"{h:>6}" for h in head) + f" {'calls/s':>8}")
    for target in sorted(counts):
        cs = counts[target]
        n = sum(cs[k] for k in KINDS)
        rate = n / seconds[target] if seconds[target] else 0.0
        row = (n, cs["ok"], cs["clean"], cs["failure"], cs["crash"], cs["hang"])
        print(f"{target:52} " + " ".join(f"{x:6}" for x in row) + f" {rate:8.0f}")
    print(
        f"\n{calls} calls over {len(counts)} targets in {wall:.0f} s "
        f"({calls / wall:.0f} calls/s, {args.workers} workers): "
        + ", ".join(f"{k} {totals[k]} ({100 * totals[k] / max(calls, 1):.2f} %)" for k in KINDS)
    )
    print(f"load average at start {load0[0]:.1f}, at end {os.getloadavg()[0]:.1f}")
    for f in failures[:40]:
        print(f"  FAILURE {f['target']}: {f['detail'][:300]}")
        print(f"    {f.get('call', '')[:300]}\n    {f.get('reproducer', '')}")
    result = {
        "command": " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]),
        "seed": args.seed,
        "calls": calls,
        "targets": len(counts),
        "wall_seconds": wall,
        "calls_per_second": calls / wall if wall else 0.0,
        "workers": args.workers,
        "load_average_start": load0,
        "load_average_end": os.getloadavg(),
        "outcomes": {k: totals[k] for k in KINDS},
        "per_target": {t: dict(cs) for t, cs in sorted(counts.items())},
        "failures": failures,
    }
    path = Path(args.json) if args.json else HERE / "results" / "fuzz.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {path}")
    return 1 if totals["failure"] + totals["crash"] + totals["hang"] else 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("--calls", type=int, default=100_000, help="calls in all (default 100000)")
    p.add_argument("--workers", type=int, default=1, help="worker processes at once (default 1)")
    p.add_argument("--chunk", type=int, default=5000, help="calls per worker process (default 5000)")
    p.add_argument(
        "--timeout", type=float, default=120.0, help="seconds without progress = a hang (default 120)"
    )
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--only", help="only targets whose name contains this")
    p.add_argument(
        "--out", default=str(Path(tempfile.gettempdir()) / "brdfpy-fuzz"), help="reproducers folder"
    )
    p.add_argument("--json", help="result file (default benchmarks/results/fuzz.json)")
    p.add_argument("--replay", type=int, help="run call number REPLAY in this process and print its outcome")
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--start", type=int, default=0, help=argparse.SUPPRESS)
    p.add_argument("--count", type=int, default=0, help=argparse.SUPPRESS)
    p.add_argument("--progress", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        worker(args.seed, args.start, args.count, args.only, args.progress)
        return 0
    if args.replay is not None:
        from fuzzing import api

        ts = _targets(args.only)
        o = api.call(ts[args.replay % len(ts)], _rng(args.seed, args.replay))
        print(f"{o.kind}: {o.detail}\n  call: {o.call}")
        return 0 if o.kind != "failure" else 1
    return campaign(args)


if __name__ == "__main__":
    sys.exit(main())
