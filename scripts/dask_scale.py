#!/usr/bin/env python3
"""A columnar ensemble of a million members on a Dask cluster, client memory
flat (issue 18's Dask target) — one command, from the repository root:

    .venv/bin/python scripts/dask_scale.py                    # N = 10^6, 2 workers
    .venv/bin/python scripts/dask_scale.py --members 100000   # a quicker check

Needs ``dask[distributed]`` and ``zarr`` (``pip install 'framedyn[dask]' zarr``)
and the installed framedyn (for the speeds in docs/performance.md, a
release build: ``pip install .``).

The ensemble is the one of ``scripts/ensemble_benchmark.py``: the S²
gyroscope of SPEC §5 with r, ṙ and ω of each member perturbed by ±10 %,
T = 20, Blanes–Moan RKN 6 with h = 0.4, final state only. It runs through
``framedyn.ensemble.solve_table(..., keep="final", store=<zarr>)`` on a
``LocalCluster`` of 2 worker processes with one thread each: each task
integrates its chunk of the table and writes its rows into the Zarr store,
and returns only statuses and summaries.

Measured: wall time and members/s; the client's peak resident memory
(``ru_maxrss`` of this process, which holds the table, the futures and
the per-member statuses and summaries, but never the records) and its
resident memory before the run; the store's size. Checked: every member
finished, and the records of 2,000 members spread over the table equal
``fd.solve_batch`` on this machine bit for bit. One CSV row is appended to
docs/data/dask_scale.csv and printed.
"""

from __future__ import annotations

import argparse
import csv
import os
import resource
import shutil
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
CSV_PATH = os.path.join(ROOT, "docs", "data", "dask_scale.csv")
FIELDS = ["members", "workers", "chunk_size", "wall_s", "members_per_s", "client_rss_before_mb", "client_peak_rss_mb", "store_mb", "checked", "load1"]


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def dir_mb(path: str) -> float:
    total = 0
    for root, _dirs, files in os.walk(path):
        total += sum(os.path.getsize(os.path.join(root, f)) for f in files)
    return total / 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--members", type=int, default=1_000_000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--chunk-size", type=int, default=None, help="members per task (default: solve_table's)")
    ap.add_argument("--store", default=None, help="Zarr path (default: a temporary directory, removed afterwards)")
    args = ap.parse_args()

    import framedyn as fd
    from dask.distributed import Client, LocalCluster
    from ensemble_benchmark import I, framedyn_scene, members
    from framedyn.ensemble import solve_table

    import zarr  # noqa: F401  (fail early if missing)

    n = args.members
    r, rd, om = members(n)
    table = {"initial.r": r, "initial.r_dot": rd, "initial.spin": I * om}
    base = framedyn_scene(fd)
    tmp = tempfile.mkdtemp(prefix="framedyn-dask-")
    store = args.store or os.path.join(tmp, "runs.zarr")
    try:
        with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
            before = rss_mb()
            t0 = time.perf_counter()
            out = solve_table(base, table, client=client, keep="final", store=store, chunk_size=args.chunk_size)
            wall = time.perf_counter() - t0
            peak = peak_rss_mb()
        finished = int(np.sum(out.status == "finished"))
        if finished != n:
            sys.exit(f"{n - finished} members did not finish: {sorted(set(map(str, out.status)))}")
        # Bit-for-bit check of members spread over the table.
        idx = np.unique(np.linspace(0, n - 1, min(n, 2000)).astype(np.int64))
        local = fd.solve_batch(base, {k: v[idx] for k, v in table.items()}, keep="final")
        stored = np.asarray(out.open()["data"].get_orthogonal_selection((idx, slice(None), slice(None))))
        if not np.array_equal(stored, local.data):
            sys.exit("the stored records differ from solve_batch")
        chunk = args.chunk_size or "default"
        row = {
            "members": n, "workers": args.workers, "chunk_size": chunk, "wall_s": f"{wall:.2f}", "members_per_s": f"{n / wall:.0f}",
            "client_rss_before_mb": f"{before:.0f}", "client_peak_rss_mb": f"{peak:.0f}", "store_mb": f"{dir_mb(store):.0f}",
            "checked": len(idx), "load1": f"{os.getloadavg()[0]:.2f}",
        }
    finally:
        if args.store is None:
            shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(os.path.dirname(CSV_PATH), exist_ok=True)
    new = not os.path.exists(CSV_PATH)
    with open(CSV_PATH, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        w.writerow(row)
    print(", ".join(f"{k} = {v}" for k, v in row.items()))


if __name__ == "__main__":
    main()
