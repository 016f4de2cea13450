#!/usr/bin/env python3
"""Does pyo3's stable ABI (abi3) cost anything? Compares two wheels of
framedyn in the same run — ONE command, from the repository root:

    python3 scripts/abi3_compare.py NATIVE.whl ABI3.whl [--rounds 5]

Each wheel is installed (with numpy) into its own temporary virtual
environment; then ``--rounds`` alternating rounds run a fresh interpreter
per wheel that times, on the problem of scripts/ensemble_benchmark.py (the
S² gyroscope, Blanes–Moan RKN 6, h = 0.4, T = 20):

* ``solve``: one ``fd.solve(scene)`` (all records), best of 200 calls — the
  call most exposed to the Python boundary (the run itself is ~50 steps);
* ``batch``: ``fd.solve_batch(scene, table, keep="final", threads=1)`` over
  1,000 members whose ``r``, ``ṙ`` and spin are perturbed by ±10 %, best of 3.

Printed: the minimum over the rounds of each timing per wheel and the ratio
second / first. Exit status 0 (a measurement, not a test). docs/development.md
records the result and the choice.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
import venv

HERE = os.path.dirname(os.path.abspath(__file__))


def worker() -> None:
    import numpy as np

    import framedyn as fd

    sys.path.insert(0, HERE)
    from ensemble_benchmark import I, framedyn_scene, members

    scene = framedyn_scene(fd)
    r, rd, om = members(1000)
    table = {"initial.r": r, "initial.r_dot": rd, "initial.spin": I * om}

    def best(fn, repeats):
        fn()  # warm-up
        out = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            fn()
            out = min(out, time.perf_counter() - t0)
        return out

    batch = fd.solve_batch(scene, table, keep="final", threads=1)
    assert (batch.status == "finished").all() and np.isfinite(batch.final).all()
    print(json.dumps({
        "solve": best(lambda: fd.solve(scene), 200),
        "batch": best(lambda: fd.solve_batch(scene, table, keep="final", threads=1), 3),
    }))


def main() -> int:
    args = sys.argv[1:]
    rounds = 5
    if "--rounds" in args:
        i = args.index("--rounds")
        rounds = int(args[i + 1])
        del args[i : i + 2]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    wheels = [os.path.abspath(w) for w in args]
    with tempfile.TemporaryDirectory(prefix="framedyn-abi3-") as tmp:
        pythons = []
        for k, wheel in enumerate(wheels):
            env_dir = os.path.join(tmp, f"venv{k}")
            venv.create(env_dir, with_pip=True)
            py = os.path.join(env_dir, "bin", "python")
            subprocess.run([py, "-m", "pip", "install", "--quiet", "--disable-pip-version-check", wheel, "numpy"], check=True)
            pythons.append(py)
        results = [[], []]
        for _ in range(rounds):
            for k, py in enumerate(pythons):
                out = subprocess.run([py, os.path.abspath(__file__), "--worker"], check=True, capture_output=True, text=True, cwd=tmp)
                results[k].append(json.loads(out.stdout.strip().splitlines()[-1]))
    names = [os.path.basename(w) for w in wheels]
    for key, unit, scale in (("solve", "µs", 1e6), ("batch", "ms", 1e3)):
        a = min(r[key] for r in results[0])
        b = min(r[key] for r in results[1])
        print(f"{key}: {names[0]} {scale * a:.1f} {unit}, {names[1]} {scale * b:.1f} {unit}, ratio second/first {b / a:.3f} (min of {rounds} rounds)")
    return 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        worker()
    else:
        sys.exit(main())
