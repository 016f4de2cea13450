#!/usr/bin/env python3
"""Python overhead and batch scaling (issue 7 targets) — ONE command, from
the repository root:

    .venv/bin/python scripts/python_overhead.py            # about 1 minute once built (the first
                                                           # release builds take 5-10 minutes more)
    .venv/bin/python scripts/python_overhead.py --summary-only   # the table from the CSV

Targets measured (benchmarks, not tests):
  (a) from Python, a single 1e5-step trajectory costs <= 1.1x the same run
      from Rust;
  (b) a 1000-trajectory batch scales >= 1.8x on 2 cores.

Steps:
1. `cargo build --release -p framedyn-tests --example scene_timing` (the Rust side).
2. The Python extension must be an optimised build too. If the one this
   interpreter imports is a development build (`maturin develop`: the dev
   profile, whose debug assertions the extension reports as
   `framedyn._framedyn._debug_assertions`), a release wheel is
   built (`maturin build --release -o <tmp>/wheels`) and installed, with
   numpy from PyPI (the version of this interpreter's numpy), into a
   temporary virtual environment (no system site-packages) that is deleted
   afterwards; steps 3-4 run there. The project's `.venv` is never touched.
3. (a) The scene `scripts/data/overhead_scene.toml` (S² gyroscope through
   the pole, RK4, exactly 1e5 steps, one record per step, every column
   group: 100,001 x 22 values) is run from Rust (the example, which clones,
   builds and runs the scene into a `MemorySink`, and into the
   Python module's `FlatSink`) and from Python (`fd.solve(scene)`, which runs
   the same engine with the GIL released on the calling thread and hands
   the flat buffer to numpy without a copy), interleaved in rounds with the
   order alternating. Per round, each side keeps the minimum of `--repeats`
   runs; wall time and thread-CPU time (`CLOCK_THREAD_CPUTIME_ID` in Rust,
   `time.thread_time()` in Python — the same clock; the Rust work of
   `fd.solve` runs on the calling thread, so it is counted). Before timing,
   the records are checked to be bit-identical between Rust and Python
   (same checksum, steps, records, columns).
4. (b) `fd.solve_batch(base, params, threads=n)` over 1000 members (initial
   r from 0.3 to 1.2; 4000 RK4 steps each, one record every 40 steps),
   n = 1 and 2, interleaved over rounds (order alternating); wall time of
   the whole call (including the serial Python part: one `with_params`
   scene per member, and wrapping the results), process CPU time (all
   threads) and, separately, the time of the serial scene preparation. The
   members' records are checked to be bit-identical between thread counts.
5. Writes docs/data/python_overhead.csv (one row per measurement, with
   os.getloadavg() before and after and the CPU used by other processes
   during it — /proc/stat busy time minus our own, in cores — since the
   machine is shared) and prints the table.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scripts", "data", "overhead_scene.toml")
CSV_PATH = os.path.join(ROOT, "docs", "data", "python_overhead.csv")
EXAMPLE = os.path.join(ROOT, "target", "release", "examples", "scene_timing")

# (b): the batch.
BATCH_MEMBERS = 1000
BATCH_T_END = 4000 * 2.0**-10  # 4000 steps of h = 2^-10 (the scene's h)
BATCH_EVERY = 40  # 101 records per member

FIELDS = [
    "benchmark",  # a (single trajectory) or b (batch)
    "round",
    "variant",  # a: rust_memory, rust_flat, python, python_engine_run (stats['wall_time'] of those runs); b: threads1, threads2, prep
    "repeats",  # runs in this measurement (the minimum is kept)
    "wall_s",  # minimum wall time over the repeats
    "cpu_s",  # a: minimum thread-CPU time (nan for python_engine_run); b: process CPU time (all threads)
    "load1_before",
    "load1_after",
    "load5_before",
    "load5_after",
    "other_cores",  # CPU used by other processes during the measurement, in cores (/proc/stat minus our own CPU)
    "python_ext",  # which extension the Python side ran
]

TARGET_A = 1.1
TARGET_B = 1.8


def run(cmd, **kw):
    print("+", " ".join(cmd), flush=True)
    return subprocess.run(cmd, check=True, **kw)


# ---------------------------------------------------------------------------
# Build and environment
# ---------------------------------------------------------------------------


def installed_extension():
    """Path of the framedyn extension this interpreter imports, and whether
    it is a development build (debug assertions on: the dev profile)."""
    import importlib.util

    spec = importlib.util.find_spec("framedyn._framedyn")
    if spec is None or spec.origin is None:
        return None, True
    from framedyn import _framedyn

    return spec.origin, bool(getattr(_framedyn, "_debug_assertions", True))


def make_wheel_venv(tmp):
    """Builds a release wheel and installs it with numpy (from PyPI) into a
    fresh virtual environment under `tmp`; returns its python."""
    import numpy

    wheels = os.path.join(tmp, "wheels")
    run([os.path.join(os.path.dirname(sys.executable), "maturin"), "build", "--release", "--interpreter", sys.executable, "-o", wheels], cwd=ROOT)
    found = [w for w in os.listdir(wheels) if w.endswith(".whl")]
    if len(found) != 1:
        sys.exit(f"expected one wheel in {wheels}, found {found}")
    venv = os.path.join(tmp, "venv")
    run([sys.executable, "-m", "venv", venv])
    py = os.path.join(venv, "bin", "python")
    run([py, "-m", "pip", "install", "--quiet", "--disable-pip-version-check", f"numpy=={numpy.__version__}", os.path.join(wheels, found[0])])
    return py


# ---------------------------------------------------------------------------
# Measurements
# ---------------------------------------------------------------------------


def machine_busy():
    """Non-idle CPU seconds of the whole machine since boot (Linux /proc/stat;
    nan elsewhere)."""
    try:
        with open("/proc/stat", encoding="ascii") as f:
            v = [int(x) for x in f.readline().split()[1:]]
    except (OSError, ValueError):
        return float("nan")
    idle = v[3] + (v[4] if len(v) > 4 else 0)  # idle + iowait
    return (sum(v[:8]) - idle) / os.sysconf("SC_CLK_TCK")


def load():
    """A snapshot around a measurement: load averages, wall clock, machine
    busy CPU seconds, and this process's plus its waited-for children's CPU
    seconds (so that the CPU used by *other* processes can be told apart)."""
    t = os.times()
    return {"avg": os.getloadavg(), "wall": time.perf_counter(), "busy": machine_busy(), "own": t.user + t.system + t.children_user + t.children_system}


def checksum(data):
    """Σ bits(x_i)·(2i+1) mod 2^64 over the row-major values (as the Rust example)."""
    import numpy as np

    bits = np.ascontiguousarray(data, dtype=np.float64).reshape(-1).view(np.uint64)
    weights = 2 * np.arange(bits.size, dtype=np.uint64) + np.uint64(1)
    with np.errstate(over="ignore"):
        return f"{int(np.sum(bits * weights, dtype=np.uint64)):016x}"


def rust_times(repeats):
    out = subprocess.run([EXAMPLE, SCENE, str(repeats), "--sink", "both"], check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def python_times(fd, scene, repeats):
    walls, cpus, engine = [], [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.thread_time()
        sol = fd.solve(scene)
        c1, w1 = time.thread_time(), time.perf_counter()
        walls.append(w1 - w0)
        cpus.append(c1 - c0)
        engine.append(sol.stats["wall_time"])  # the engine's own clock around Simulation::run
        del sol  # the records are freed outside the clock (as in the Rust example)
    return min(walls), min(cpus), min(engine)


def other_cores(before, after):
    """Cores' worth of CPU used by other processes between two snapshots
    (machine busy time minus our own; 1 tick of /proc/stat resolution)."""
    return (after["busy"] - before["busy"] - (after["own"] - before["own"])) / max(after["wall"] - before["wall"], 1e-9)


def row(benchmark, rnd, variant, repeats, wall, cpu, before, after, ext):
    return {
        "benchmark": benchmark,
        "round": rnd,
        "variant": variant,
        "repeats": repeats,
        "wall_s": f"{wall:.6f}",
        "cpu_s": f"{cpu:.6f}",
        "load1_before": f"{before['avg'][0]:.2f}",
        "load1_after": f"{after['avg'][0]:.2f}",
        "load5_before": f"{before['avg'][1]:.2f}",
        "load5_after": f"{after['avg'][1]:.2f}",
        "other_cores": f"{other_cores(before, after):.2f}",
        "python_ext": ext,
    }


def measure(args):
    import numpy as np

    import framedyn as fd

    origin, dev = installed_extension()
    ext = "release-wheel-tmp-venv" if args.ext_label == "wheel" else ("installed-dev" if dev else "installed-release")
    print(f"framedyn {fd.__version__} from {os.path.dirname(fd.__file__)} (extension: {ext}; debug info: {dev})")
    if args.ext_label == "wheel" and os.path.commonpath([os.path.abspath(fd.__file__), ROOT]) == ROOT:
        sys.exit("the temporary venv imported framedyn from the repository, not from the wheel")
    rows = []

    # -- (a) one 1e5-step trajectory -----------------------------------------
    scene = fd.Scene.load(SCENE)
    sol = fd.solve(scene)
    ref = rust_times(1)
    py_sum = checksum(sol.data)
    print(
        f"(a) scene: {ref['steps']} steps of {ref['method']}, {ref['records']} records x {ref['columns']} columns; "
        f"checksum Rust {ref['checksum']}, Python {py_sum}"
    )
    if (sol.stats["steps"], sol.data.shape[0], sol.data.shape[1], py_sum) != (ref["steps"], ref["records"], ref["columns"], ref["checksum"]):
        sys.exit("Rust and Python runs differ (steps, records, columns or checksum): not the same run")
    if ref["steps"] != 100_000:
        sys.exit(f"the scene has {ref['steps']} steps, not 1e5")
    del sol
    for r in range(args.rounds):
        order = ("rust", "python") if r % 2 == 0 else ("python", "rust")
        for side in order:
            before = load()
            if side == "rust":
                res = rust_times(args.repeats)
                after = load()
                for sink in ("memory", "flat"):
                    s = res["sinks"][sink]
                    rows.append(row("a", r, f"rust_{sink}", args.repeats, s["wall_min_s"], s["cpu_min_s"], before, after, ext))
            else:
                wall, cpu, engine = python_times(fd, scene, args.repeats)
                after = load()
                rows.append(row("a", r, "python", args.repeats, wall, cpu, before, after, ext))
                rows.append(row("a", r, "python_engine_run", args.repeats, engine, float("nan"), before, after, ext))
        print(f"  round {r}: " + ", ".join(f"{x['variant']} {float(x['wall_s']) * 1e3:.2f} ms" for x in rows if x["benchmark"] == "a" and x["round"] == r), flush=True)

    # -- (b) a 1000-trajectory batch -------------------------------------------
    base = scene.with_params({"time.t_end": BATCH_T_END, "output.every": BATCH_EVERY})
    params = [{"initial.r": float(r)} for r in np.linspace(0.3, 1.2, BATCH_MEMBERS)]
    for r in range(args.batch_rounds):
        before = load()
        w0, c0 = time.perf_counter(), time.process_time()
        prepared = [base.with_params(p) for p in params]
        c1, w1 = time.process_time(), time.perf_counter()
        rows.append(row("b", r, "prep", 1, w1 - w0, c1 - c0, before, load(), ext))
        del prepared
        results = {}
        for n in ((1, 2) if r % 2 == 0 else (2, 1)):
            before = load()
            w0, c0 = time.perf_counter(), time.process_time()
            batch = fd.solve_batch(base, params, threads=n)
            c1, w1 = time.process_time(), time.perf_counter()
            rows.append(row("b", r, f"threads{n}", 1, w1 - w0, c1 - c0, before, load(), ext))
            results[n] = batch
        one, two = results[1], results[2]
        if len(one) != BATCH_MEMBERS or len(two) != BATCH_MEMBERS:
            sys.exit("batch: wrong number of members")
        for i, (s1, s2) in enumerate(zip(one, two)):
            if s1.stats["stop"] != "finished" or s1.stats["steps"] != 4000:
                sys.exit(f"batch member {i}: {s1.stats['stop']} after {s1.stats['steps']} steps")
            if s1.data.shape != s2.data.shape or s1.data.tobytes() != s2.data.tobytes() or s1.columns != s2.columns:
                sys.exit(f"batch member {i}: records differ between threads=1 and threads=2")
        b = [x for x in rows if x["benchmark"] == "b" and x["round"] == r]
        print(
            "  batch round %d: %s (identical records)"
            % (r, ", ".join(f"{x['variant']} {float(x['wall_s']):.2f} s (other processes: {x['other_cores']} cores)" for x in b)),
            flush=True,
        )
        del results, one, two, batch
    return rows


# ---------------------------------------------------------------------------
# Summary
# ---------------------------------------------------------------------------


def summary(rows):
    def sel(bm, variant):
        return [x for x in rows if x["benchmark"] == bm and x["variant"] == variant]

    def col(xs, key):
        return [float(x[key]) for x in xs]

    loads = [float(x[k]) for x in rows for k in ("load1_before", "load1_after")]
    ext = sorted({x["python_ext"] for x in rows})
    lines = [f"Python extension: {', '.join(ext)}; load average (1 min) during the run: {min(loads):.2f} - {max(loads):.2f} on {os.cpu_count()} CPUs"]
    for bm in ("a", "b"):
        oc = sorted(float(x["other_cores"]) for x in rows if x["benchmark"] == bm and x["variant"] != "python_engine_run")
        lines.append(f"CPU used by other processes during ({bm}) (cores, /proc/stat): median {statistics.median(oc):.2f}, range {oc[0]:.2f} - {oc[-1]:.2f}")
    lines.append("")

    py, rm, rf = sel("a", "python"), sel("a", "rust_memory"), sel("a", "rust_flat")
    rounds = len(py)
    lines.append(f"(a) one 1e5-step trajectory, {rounds} rounds x {py[0]['repeats']} runs per side (ms: minimum over all runs; ratio: of minima / median of per-round ratios)")
    lines.append("| clock | Python fd.solve | Rust MemorySink | Rust flat sink | Python / Rust MemorySink | Python / Rust flat sink |")
    lines.append("|---|---|---|---|---|---|")
    verdict_a = []
    for key, name in (("wall_s", "wall"), ("cpu_s", "thread CPU")):
        p, m, f = col(py, key), col(rm, key), col(rf, key)
        rm_ratio, rf_ratio = min(p) / min(m), min(p) / min(f)
        med_m = statistics.median(a / b for a, b in zip(p, m))
        med_f = statistics.median(a / b for a, b in zip(p, f))
        verdict_a += [rm_ratio, med_m]
        lines.append(
            f"| {name} | {min(p) * 1e3:.1f} ms | {min(m) * 1e3:.1f} ms | {min(f) * 1e3:.1f} ms | "
            f"{rm_ratio:.3f} / {med_m:.3f} | {rf_ratio:.3f} / {med_f:.3f} |"
        )
    eng = col(sel("a", "python_engine_run"), "wall_s")
    lines.append(
        f"inside fd.solve, Simulation::run itself (the engine's wall clock, stats['wall_time']) took {min(eng) * 1e3:.2f} ms: "
        f"everything else fd.solve does (argument checks, scene clone and build, numpy/dict conversion, Solution) "
        f"costs {statistics.median(a - b for a, b in zip(col(py, 'wall_s'), eng)) * 1e3:.2f} ms per call (median over rounds of the per-round minima)"
    )
    worst = max(verdict_a)
    lines.append(f"target (a) <= {TARGET_A}x: {'MET' if worst <= TARGET_A else 'NOT MET'} (largest ratio against the MemorySink run: {worst:.3f})")
    lines.append("")

    t1, t2, prep = sel("b", "threads1"), sel("b", "threads2"), sel("b", "prep")
    w1, w2 = col(t1, "wall_s"), col(t2, "wall_s")
    speed = min(w1) / min(w2)
    med = statistics.median(a / b for a, b in zip(w1, w2))
    lines.append(f"(b) {BATCH_MEMBERS}-member batch (4000 RK4 steps each), {len(t1)} rounds, wall time of fd.solve_batch")
    lines.append("| threads | wall (min) | wall (all rounds) | process CPU / wall |")
    lines.append("|---|---|---|---|")
    for n, xs in ((1, t1), (2, t2)):
        w = col(xs, "wall_s")
        c = col(xs, "cpu_s")
        lines.append(f"| {n} | {min(w):.3f} s | {', '.join(f'{v:.2f}' for v in w)} | {min(a / b for a, b in zip(c, w)):.2f} - {max(a / b for a, b in zip(c, w)):.2f} |")
    lines.append(f"speed-up threads=1 / threads=2: {speed:.3f} (of minima), {med:.3f} (median of per-round ratios)")
    c1, c2 = col(t1, "cpu_s"), col(t2, "cpu_s")
    cores = [c / w for c, w in zip(c2, w2)]
    lines.append(
        f"cores obtained by threads=2 (process CPU / wall, per round): {', '.join(f'{c:.2f}' for c in cores)}; "
        f"CPU time threads=2 / threads=1 (extra work of the parallel run): {statistics.median(b / a for a, b in zip(c1, c2)):.3f} (median)"
    )
    o1, o2 = col(t1, "other_cores"), col(t2, "other_cores")
    lines.append(f"CPU used by other processes (cores) during threads=1: {', '.join(f'{c:.2f}' for c in o1)}; during threads=2: {', '.join(f'{c:.2f}' for c in o2)}")
    quiet = [a / b for a, b, p, q in zip(w1, w2, o1, o2) if max(p, q) < 0.2]
    lines.append(
        "speed-up in the rounds where other processes used < 0.2 cores during both calls: "
        + (f"{statistics.median(quiet):.3f} (median of {len(quiet)} of {len(w1)} rounds)" if quiet else f"no such round of {len(w1)}")
    )
    lines.append(f"serial part: scene preparation (one with_params per member) {min(col(prep, 'wall_s')):.3f} s of the {min(w2):.3f} s threads=2 call")
    lines.append(f"target (b) >= {TARGET_B}x: {'MET' if min(speed, med) >= TARGET_B else 'NOT MET'}")
    return "\n".join(lines)


def write_csv(rows):
    os.makedirs(os.path.dirname(CSV_PATH), exist_ok=True)
    with open(CSV_PATH, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {os.path.relpath(CSV_PATH, ROOT)}")


def read_csv():
    with open(CSV_PATH, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=15, help="rounds of (a) (default 15)")
    ap.add_argument("--repeats", type=int, default=5, help="runs per side and round in (a) (default 5)")
    ap.add_argument("--batch-rounds", type=int, default=7, help="rounds of (b) (default 7)")
    ap.add_argument("--summary-only", action="store_true", help="print the table from docs/data/python_overhead.csv")
    ap.add_argument("--no-build", action="store_true", help="skip the cargo build of the example")
    ap.add_argument("--installed", action="store_true", help="measure the installed extension even if it is a development build")
    ap.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)  # internal: the measuring process
    ap.add_argument("--ext-label", default="installed", help=argparse.SUPPRESS)
    args = ap.parse_args()

    if args.summary_only:
        print(summary(read_csv()))
        return
    if args.measure:
        rows = measure(args)
        write_csv(rows)
        print()
        print(summary(rows))
        return

    t_start = time.perf_counter()
    if not args.no_build:
        run(["cargo", "build", "--release", "-p", "framedyn-tests", "--example", "scene_timing"], cwd=ROOT)
    if not os.path.exists(EXAMPLE):
        sys.exit(f"{EXAMPLE} missing: build it with cargo build --release -p framedyn-tests --example scene_timing")
    origin, dev = installed_extension()
    passthrough = ["--rounds", str(args.rounds), "--repeats", str(args.repeats), "--batch-rounds", str(args.batch_rounds)]
    if origin is not None and (not dev or args.installed):
        print(f"measuring the installed extension {origin} ({'development' if dev else 'release'} build)")
        run([sys.executable, os.path.abspath(__file__), "--measure", "--ext-label", "installed", *passthrough], cwd=ROOT)
    else:
        print(f"the installed extension {origin} is a development build: measuring a release wheel in a temporary venv")
        tmp = tempfile.mkdtemp(prefix="framedyn-overhead-")
        try:
            py = make_wheel_venv(tmp)
            t_meas = time.perf_counter()
            print(f"build and venv: {t_meas - t_start:.0f} s", flush=True)
            # Run from the temporary directory so that nothing from the repository's
            # python/ shadows the installed wheel.
            run([py, os.path.abspath(__file__), "--measure", "--ext-label", "wheel", *passthrough], cwd=tmp)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    print(f"total: {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
