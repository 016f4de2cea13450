#!/usr/bin/env python3
"""Does a way of building the wheel cost anything? Compares the speed of two
wheels of framedyn in the same run — ONE command, from the repository root:

    python3 scripts/abi3_compare.py FIRST.whl SECOND.whl [--rounds 5] [--examples]

Written for pyo3's stable ABI (a cp311 wheel against an abi3 one); also
used for the manylinux policy (a wheel linked on this machine, manylinux_2_35,
against one linked by zig for manylinux2014, which binds libm's exp, log and
pow to their glibc 2.2.5 versions instead of the 2.29 ones).

Each wheel is installed (with numpy) into its own temporary virtual
environment; then ``--rounds`` alternating rounds run a fresh interpreter
per wheel that times, on the problem of scripts/ensemble_benchmark.py (the
S² gyroscope, Blanes–Moan RKN 6, h = 0.4, T = 20):

* ``solve``: one ``fd.solve(scene)`` (all records), best of 200 calls — the
  call most exposed to the Python boundary (the run itself is ~50 steps);
* ``batch``: ``fd.solve_batch(scene, table, keep="final", threads=1)`` over
  1,000 members whose ``r``, ``ṙ`` and spin are perturbed by ±10 %, best of 3.

With ``--examples``, also ``fd.solve`` of every embedded example scene
(best of 5 calls each): the scenes cover every manifold × body, with the
exp/log/pow-heavy hyperbolic functions of H² and the potentials' powers.

Printed: the minimum over the rounds of each timing per wheel and the ratio
second / first (for the examples: each scene's ratio, then their geometric
mean and range). Exit status 0 (a measurement, not a test). docs/development.md
records the result and the choice.
"""

from __future__ import annotations

import json
import math
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
    out = {
        "solve": best(lambda: fd.solve(scene), 200),
        "batch": best(lambda: fd.solve_batch(scene, table, keep="final", threads=1), 3),
    }
    if "--examples" in sys.argv:
        for name in fd.Scene.examples():
            example = fd.Scene.example(name)
            out[f"example:{name}"] = best(lambda: fd.solve(example), 5)
    print(json.dumps(out))


def main() -> int:
    args = sys.argv[1:]
    rounds = 5
    examples = "--examples" in args
    if examples:
        args.remove("--examples")
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
                cmd = [py, os.path.abspath(__file__), "--worker"] + (["--examples"] if examples else [])
                out = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=tmp)
                results[k].append(json.loads(out.stdout.strip().splitlines()[-1]))
    names = [os.path.basename(w) for w in wheels]
    for key, unit, scale in (("solve", "µs", 1e6), ("batch", "ms", 1e3)):
        a = min(r[key] for r in results[0])
        b = min(r[key] for r in results[1])
        print(f"{key}: {names[0]} {scale * a:.1f} {unit}, {names[1]} {scale * b:.1f} {unit}, ratio second/first {b / a:.3f} (min of {rounds} rounds)")
    if examples:
        ratios = []
        for key in sorted(k for k in results[0][0] if k.startswith("example:")):
            a = min(r[key] for r in results[0])
            b = min(r[key] for r in results[1])
            ratios.append(b / a)
            print(f"{key[8:]}: {1e3 * a:.2f} ms, {1e3 * b:.2f} ms, ratio {b / a:.3f}")
        gmean = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
        print(f"examples: geometric mean of {len(ratios)} ratios second/first {gmean:.3f}, range {min(ratios):.3f} … {max(ratios):.3f}")
    return 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["--worker"]:
        worker()
    else:
        sys.exit(main())
