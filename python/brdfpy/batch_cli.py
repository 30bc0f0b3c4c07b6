"""``brdfpy batch SPEC.json -o DIR``: render a sweep spec (:mod:`brdfpy.sweep`) on a Dask cluster into a
folder, with a manifest and a contact sheet (see :func:`brdfpy.distributed.render_many`).

Without ``--scheduler`` it starts a ``distributed.LocalCluster`` of worker processes on this machine; with
it, it connects to a running scheduler and fails within ``--timeout`` seconds if none answers. The whole
spec and the output folder are checked before the cluster is touched.
"""

# distributed.Client is not annotated.
# mypy: disallow-untyped-calls=False

from __future__ import annotations

import argparse
import contextlib
import sys
import textwrap
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> argparse.ArgumentParser:
    p: argparse.ArgumentParser = sub.add_parser(
        "batch",
        help="render a sweep spec (models x parameter ranges x turntable frames) on a Dask cluster",
        description=textwrap.fill(
            "Render a sweep spec (a JSON file: a mesh, models with parameter values or ranges, a camera "
            "turntable, size, shading, AO and shadows; see the README, 'Batches on a Dask cluster') into "
            "the folder DIR: one PNG per frame (and EXR/NPZ if the spec asks), manifest.json (parameters, "
            "files, SHA-256 checksums, times) and contact_sheet.png. A run that was interrupted resumes: "
            "frames already in the manifest with the right files are skipped. Needs brdfpy[dask].",
            width=78,
        ),
        epilog="Examples:\n"
        "  brdfpy batch sweep.json -o frames                     # a local cluster, one process per core\n"
        "  brdfpy batch sweep.json -o frames --workers 2\n"
        "  brdfpy batch sweep.json -o frames --scheduler tcp://10.0.0.5:8786",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("spec", metavar="SPEC.json", help="the sweep spec")
    p.add_argument("-o", "--out", required=True, metavar="DIR", help="output folder (created)")
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="a running Dask scheduler, e.g. tcp://host:8786 (default: start a local cluster)",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="local worker processes (default: one per core)",
    )
    p.add_argument(
        "--timeout",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="how long to wait for --scheduler to answer (default 10)",
    )
    p.add_argument("--no-resume", action="store_true", help="render every frame again")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    return p


def run(args: argparse.Namespace) -> int:
    from brdfpy.sweep import load_spec

    sweep = load_spec(args.spec)  # every field checked before anything else happens
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers: expected a positive integer, got {args.workers}")
    if not args.timeout > 0:
        raise ValueError(f"--timeout: expected a positive number of seconds, got {args.timeout}")
    try:
        import distributed

        from brdfpy import distributed as bd
    except ImportError as err:
        raise ImportError(f"needs the optional extra brdfpy[dask] ({err})") from None
    folder = bd._check_folder(args.out)
    with contextlib.ExitStack() as stack:
        if args.scheduler is not None:
            try:
                client = stack.enter_context(distributed.Client(args.scheduler, timeout=args.timeout))
            except (OSError, TimeoutError) as err:
                raise OSError(
                    f"--scheduler {args.scheduler}: no Dask scheduler answered within {args.timeout:g} s "
                    f"({err})"
                ) from None
        else:
            cluster = stack.enter_context(bd.local_cluster(args.workers))
            client = stack.enter_context(distributed.Client(cluster))
        n = len(client.scheduler_info(n_workers=-1)["workers"])
        print(f"{len(sweep.jobs)} frames on {n} workers; dashboard: {client.dashboard_link}", file=sys.stderr)
        report = bd.render_many(
            sweep, client, folder, resume=not args.no_resume, progress=not args.no_progress, errors="report"
        )
    sheet = bd.contact_sheet(sweep, folder)
    print(
        f"{len(report.rendered)} rendered, {len(report.skipped)} already done, {len(report.failed)} failed "
        f"in {report.seconds:.1f} s: {report.manifest}, {sheet}"
    )
    for reason in report.failed.values():
        print(f"brdfpy batch: failed: {reason}", file=sys.stderr)
    return 1 if report.failed else 0
