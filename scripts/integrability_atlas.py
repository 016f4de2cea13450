#!/usr/bin/env python3
"""Integrability, measured (issue 21): the maximal Lyapunov exponent of the
paper's models, its growth law over a decade of time, the two-trajectory
check, and the cost of carrying tangent vectors.

For each case (an embedded scene, possibly modified, run over T = 200 or
100 with its own method and fixed step) it records the maximal exponent
λ(T) with its batch-means standard error, the two-trajectory estimate, and
the growth exponent g = Δlog|ξ| / Δlog t of the tangent vector between
t = T/10 and T, the smallest SALI over the run (and when it fell below
1e-8): g ≈ 1 is the linear shear of an integrable motion (λ(t) ~
log t / t), g ≫ 1 exponential growth. Verdict: "regular" when |g − 1| <
0.3, "chaotic" when g > 3 and λ > 5 standard errors, else "undecided".

Then the cost: wall time of fd.solve (plain run) against fd.lyapunov with
1 and with all tangent vectors, on the same scene (median of 3).

Writes docs/data/integrability_atlas.csv and
docs/data/integrability_cost.csv and prints both as Markdown tables
(docs/integrability.md quotes them). Run:
    .venv/bin/python scripts/integrability_atlas.py
"""

import csv
import math
import os
import sys
import time

import numpy as np

import framedyn as fd

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "docs", "data")


def scene(name, t_end, **changes):
    d = fd.Scene.example(name).to_dict()
    d["time"]["t_end"] = t_end
    d.pop("events", None)
    for path, value in changes.items():
        node = d
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[k]
        if value is None:
            node.pop(keys[-1], None)
        else:
            node[keys[-1]] = value
    return fd.Scene.from_dict(d)


# (case, paper's claim, scene)
CASES = [
    ("S² point, Kepler (Bertrand)", "integrable, maximally degenerate (§5)", lambda: scene("s2-point-kepler", 200.0)),
    ("S² point, oscillator (Bertrand)", "integrable, maximally degenerate (§5)", lambda: scene("s2-point-oscillator", 200.0)),
    ("S² point, V = r²/2 (non-Bertrand central)", "integrable (central), orbits not closed", lambda: scene("s2-point-central", 200.0)),
    ("H² point, Kepler (Bertrand)", "integrable, maximally degenerate (§5)", lambda: scene("h2-point-kepler", 200.0)),
    ("S² gyroscope, α̂cos² + β̂cos", "elementary integrability (l. 3725); integrable (cyclic φ, ψ)", lambda: scene("s2-gyroscope-cosine", 200.0)),
    ("T² gyroscope, V(θ) separable", "integrable (separable, (b128))", lambda: scene("t2-gyroscope-separable", 200.0)),
    ("S³ gyroscope, J = diag(.1,.2,.3), oscillator", "open (§6 treats free motion)", lambda: scene("s3-gyroscope", 100.0)),
    ("S² affine body, elastic, isotropic J", "integrable only for separable V (§5)", lambda: scene("s2-affine-elastic", 100.0)),
    (
        "S² affine body, elastic, general J",
        "\"no hope for integrability\"",
        lambda: scene("s2-affine-elastic", 100.0, **{"body.inertia": None, "body.J": [[0.1, 0.02], [0.02, 0.05]]}),
    ),
    (
        "S² affine body, elastic, general J, large deformation",
        "\"no hope for integrability\"",
        lambda: scene(
            "s2-affine-elastic",
            1000.0,
            **{"body.inertia": None, "body.J": [[0.1, 0.02], [0.02, 0.05]], "initial.rho": [[1.8, 0.3], [0.0, 0.5]], "initial.rho_dot": [[0.0, 0.8], [-0.6, 0.0]], "initial.phi_dot": 1.5},
        ),
    ),
    (
        "S² affine body, elastic, isotropic J, large deformation",
        "integrable only for separable V (§5)",
        lambda: scene("s2-affine-elastic", 1000.0, **{"initial.rho": [[1.8, 0.3], [0.0, 0.5]], "initial.rho_dot": [[0.0, 0.8], [-0.6, 0.0]], "initial.phi_dot": 1.5}),
    ),
    (
        "S³ gyroscope, J = diag(.1,.2,.3), oscillator, fast spin",
        "open (§6 treats free motion)",
        lambda: scene("s3-gyroscope", 100.0, **{"initial.omega": [3.0, 1.0, -2.0]}),
    ),
]


def growth(r, t_hi):
    times, run = r.times, r.running[:, 0]
    t_lo = t_hi / 10.0

    def log_xi(t):
        i = int(np.argmin(np.abs(times - t)))
        return run[i] * times[i], times[i]

    (a, ta), (b, tb) = log_xi(t_lo), log_xi(t_hi)
    return (b - a) / math.log(tb / ta)


def atlas():
    rows = []
    for name, claim, make in CASES:
        s = make()
        t_end = s.to_dict()["time"]["t_end"]
        r = fd.lyapunov(s, two_trajectory=True)
        g = growth(r, t_end)
        lam, se = float(r.exponents[0]), float(r.stderr[0])
        two = r.two_trajectory
        si = fd.sali(s)
        if abs(g - 1.0) < 0.3:
            verdict = "regular"
        elif g > 3.0 and lam > 5.0 * se:
            verdict = "chaotic"
        else:
            verdict = "undecided"
        rows.append(
            {
                "case": name,
                "paper": claim,
                "T": t_end,
                "h": s.to_dict()["method"]["h"],
                "lambda": lam,
                "stderr": se,
                "lambda_T_over_10": float(r.running[np.argmin(np.abs(r.times - t_end / 10.0)), 0]),
                "growth": g,
                "two_trajectory": float(two["exponent"]),
                "two_stderr": float(two["stderr"]),
                "sali_min": si["min"],
                "sali_below_1e-8_at": si["chaotic_at"] if si["chaotic_at"] is not None else float("nan"),
                "verdict": verdict,
            }
        )
        print(f"{name}: λ = {lam:.4f} ± {se:.4f}, growth {g:.2f}, two-trajectory {two['exponent']:.4f}: {verdict}", file=sys.stderr)
    return rows


def cost():
    rows = []
    for name, make in [("s2-gyroscope-cosine (T = 200)", lambda: scene("s2-gyroscope-cosine", 200.0)), ("s2-affine-elastic (T = 100)", lambda: scene("s2-affine-elastic", 100.0))]:
        s = make()

        def best(f):
            ts = []
            for _ in range(3):
                t0 = time.perf_counter()
                out = f()
                ts.append(time.perf_counter() - t0)
            return float(np.median(ts)), out

        plain, _ = best(lambda: fd.solve(s))
        one, r1 = best(lambda: fd.lyapunov(s, exponents=1))
        full, rk = best(lambda: fd.lyapunov(s, exponents="all"))
        rows.append(
            {
                "scene": name,
                "state_dimension": rk.state_dimension,
                "plain_s": plain,
                "tangent_1_s": one,
                "ratio_1": one / plain,
                "method_steps_1": r1.steps_per_step,
                "tangent_all_s": full,
                "ratio_all": full / plain,
                "method_steps_all": rk.steps_per_step,
            }
        )
    return rows


def write(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def main():
    rows = atlas()
    write(os.path.join(DATA, "integrability_atlas.csv"), rows)
    print("| case | the paper | T | λ(T/10) | λ(T) ± stderr | two trajectories | growth g | SALI: min (< 1e-8 at t) | verdict |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['case']} | {r['paper']} | {r['T']:g} | {r['lambda_T_over_10']:.4f} | {r['lambda']:.4f} ± {r['stderr']:.4f} | "
            f"{r['two_trajectory']:.4f} ± {r['two_stderr']:.4f} | {r['growth']:.2f} | {r['sali_min']:.1e}"
            + ("" if math.isnan(r["sali_below_1e-8_at"]) else f" (t = {r['sali_below_1e-8_at']:.0f})")
            + f" | {r['verdict']} |"
        )
    c = cost()
    write(os.path.join(DATA, "integrability_cost.csv"), c)
    print()
    print("| scene | dim | plain run | 1 tangent vector | all tangent vectors |")
    print("|---|---|---|---|---|")
    for r in c:
        print(
            f"| {r['scene']} | {r['state_dimension']} | {r['plain_s'] * 1e3:.0f} ms | {r['tangent_1_s'] * 1e3:.0f} ms ({r['ratio_1']:.1f}×; {r['method_steps_1']} steps per step) | "
            f"{r['tangent_all_s'] * 1e3:.0f} ms ({r['ratio_all']:.1f}×; {r['method_steps_all']} steps per step) |"
        )


if __name__ == "__main__":
    main()
