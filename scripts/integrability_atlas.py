#!/usr/bin/env python3
"""Integrability, measured (issue 21): the maximal Lyapunov exponent of the
paper's models, its growth law over a decade of time, the two-trajectory
check, and the cost of carrying tangent vectors; SALI maps over initial
conditions and over parameters, and Poincaré sections.

The table. For each case (an embedded scene, possibly modified, run over
T = 200 or 100 with its own method and fixed step) it records the maximal
exponent λ(T) with its batch-means standard error, the two-trajectory
estimate, and the growth exponent g = Δlog|ξ| / Δlog t of the tangent
vector between t = T/10 and T, the smallest SALI over the run (and when it
fell below 1e-8): g ≈ 1 is the linear shear of an integrable motion (λ(t) ~
log t / t), g ≫ 1 exponential growth. Verdict: "regular" when |g − 1| <
0.3, "chaotic" when g > 3 and λ > 5 standard errors, else "undecided".
Then the cost: wall time of fd.solve (plain run) against fd.lyapunov with
1 and with all tangent vectors, on the same scene (median of 3).

The maps. SALI (stopped at 1e-8) and MEGNO ⟨Y⟩ at T over a grid of
initial conditions, each map one fd.chaos_map call (every grid point in
parallel on Rust threads, results as columns): the S² affine body with
elastic potential over initial deformation a × initial deformation rate s,
general J against isotropic J; the S² gyroscope at fixed energy and spin
over the section plane x₁ = 0 (angle θ along the great circle, velocity
v_θ along it), in the separable α̂cos² + β̂cos potential and with a tilt
ε⟨x, e₀⟩ added; the S³ gyroscope (J = diag(.1, .2, .3), oscillator) over
initial r₁ × the scale s of its initial angular velocity. A point is
"chaotic" when SALI fell below 1e-8 within T, "regular" when it ended at
or above 1e-4, else "undecided"; MEGNO calls it chaotic when ⟨Y⟩(T) > 4
(→ 2 on a quasi-periodic orbit). The maps over parameters, one
fd.chaos_map call each with the parameter a column of the member table
beside the initial values: the affine body's inertia J(δ) = 0.1·1 +
δ·(J₁ − 0.1·1) from the isotropic (δ = 0) to the general J₁ of the map
above (δ = 1) × initial deformation a (`body.J.I.J`), and the gyroscope's
tilt ε × θ at v_θ = 0 (`potential.terms.1.beta_hat`), with the classes per
parameter value, and the smallest parameters again at T = 2000. The floor check: the smallest
SALI that chaotic orbits reach with no threshold, for two perturbations ε
and both difference formulas (until 145caef SALI stopped at a floor
proportional to 1/ε there; --floor-scenes DIR writes these orbits as scene
files for `framedyn sali`). The sections: fd.section of the plane x₁ = 0
for several orbits at equal energy of the point on S² (Kepler, oscillator,
V = r²/2) and of the gyroscope (separable, tilted). The degeneracy table:
GALI₂ and GALI₃ of central-potential orbits in the phase space (modulo the
parallel frame's gauge direction) and on the stored state, whose log–log
slopes tell one drifting direction (a Bertrand orbit: GALI₂ ~ 1/t) from
two (a torus: GALI₂ stays).

Writes docs/data/integrability_atlas.csv, integrability_cost.csv,
integrability_map_s2_affine.csv, integrability_map_s2_gyroscope.csv,
integrability_map_s3_gyroscope.csv, integrability_maps.csv, integrability_sali_floor.csv,
integrability_sections.csv, integrability_params_s2_affine.csv,
integrability_params_s2_gyroscope.csv, integrability_params_summary.csv,
integrability_params_long.csv, integrability_degeneracy.csv,
integrability_leveling.csv (--leveling) and
docs/figures/integrability_*.png, and prints
the tables as Markdown (docs/integrability.md quotes them). Run:
    .venv/bin/python scripts/integrability_atlas.py               # all
    .venv/bin/python scripts/integrability_atlas.py --maps-only   # maps, sections, floor
    .venv/bin/python scripts/integrability_atlas.py --grids-only  # the SALI/MEGNO maps only
    .venv/bin/python scripts/integrability_atlas.py --table-only  # table and cost
    .venv/bin/python scripts/integrability_atlas.py --params-only # the maps over parameters only
    .venv/bin/python scripts/integrability_atlas.py --degeneracy-only  # GALI of the central orbits: maximal degeneracy
    .venv/bin/python scripts/integrability_atlas.py --leveling 1e7     # GALI₂ of V = r²/2 on S² to t = 1e7 (~25 min)
        [--leveling-tol 1e-8] [--leveling-fourth-order]               # other tolerance / tangent differences
    .venv/bin/python scripts/integrability_atlas.py --quick       # small grids, into out/integrability_quick/
    .venv/bin/python scripts/integrability_atlas.py --floor-only  # the SALI floor check only
    .venv/bin/python scripts/integrability_atlas.py --floor-scenes DIR  # its orbits as scenes (JSON)
"""

import argparse
import csv
import math
import os
import sys
import time
from multiprocessing import get_context

import numpy as np

import framedyn as fd

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "docs", "data")
FIGURES = os.path.join(ROOT, "docs", "figures")


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
        r = fd.lyapunov(s, two_trajectory=True, **TANGENTS)
        g = growth(r, t_end)
        lam, se = float(r.exponents[0]), float(r.stderr[0])
        two = r.two_trajectory
        si = fd.sali(s, **TANGENTS)
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
        one, r1 = best(lambda: fd.lyapunov(s, exponents=1, **TANGENTS))
        full, rk = best(lambda: fd.lyapunov(s, exponents="all", **TANGENTS))
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


def table(data):
    rows = atlas()
    write(os.path.join(data, "integrability_atlas.csv"), rows)
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
    write(os.path.join(data, "integrability_cost.csv"), c)
    print()
    print("| scene | dim | plain run | 1 tangent vector | all tangent vectors |")
    print("|---|---|---|---|---|")
    for r in c:
        print(
            f"| {r['scene']} | {r['state_dimension']} | {r['plain_s'] * 1e3:.0f} ms | {r['tangent_1_s'] * 1e3:.0f} ms ({r['ratio_1']:.1f}×; {r['method_steps_1']} steps per step) | "
            f"{r['tangent_all_s'] * 1e3:.0f} ms ({r['ratio_all']:.1f}×; {r['method_steps_all']} steps per step) |"
        )


# ---------------------------------------------------------------- maps

MAP_THRESHOLD = 1e-8  # SALI below this: chaotic (the customary value; meaningful since SALI has no floor, 145caef)
REGULAR_ABOVE = 1e-4  # final SALI at or above this: regular; in between: undecided
MEGNO_CHAOTIC = 4.0  # <Y>(T) above this: chaotic by MEGNO (regular orbits: <Y> -> 2; chaotic: <Y> ~ lambda_1 T/2)

# The affine body of the atlas: ρ = 1 + a·D, ρ̇ = s·Ṙ (a = s = 1: the atlas's
# "large deformation" state), position r = 0.7, φ̇ = 1.5.
GENERAL_J = [[0.1, 0.02], [0.02, 0.05]]
AFFINE_D = np.array([[0.8, 0.3], [0.0, -0.5]])
AFFINE_RDOT = np.array([[0.0, 0.8], [-0.6, 0.0]])
AFFINE_H = 0.005

# The gyroscope of s2-gyroscope-cosine (m = 1, I = 0.3) in
# V = α̂z² + β̂z + εx (x, z embedding components on the unit sphere), spin
# 0.6, translational energy ½|v|² + V = 1.0 (the energy column adds s²/2I).
GYRO_ALPHA_HAT, GYRO_BETA_HAT, GYRO_SPIN, GYRO_E = 0.5, -0.4, 0.6, 1.0
GYRO_EPS = 0.6
GYRO_H = 0.01

# The S³ gyroscope of s3-gyroscope (J = diag(.1, .2, .3), oscillator
# κ = 0.5): initial r₁ (the other initial values of the scene) against the
# scale s of its initial body angular velocity ω = s·(1, 0.5, −0.3).
S3_OMEGA = np.array([1.0, 0.5, -0.3])
S3_H = 0.005

# Initial-energy bands in which the summary counts the chaotic points.
ENERGY_BANDS = {"s2_affine": [(2.0, 3.0), (3.0, 3.5), (3.5, 4.0), (4.0, 5.0)], "s2_gyroscope": [(1.5, 1.7)], "s3_gyroscope": []}


def affine_scene(a, s, general, t_end, h=AFFINE_H):
    changes = {
        "initial.rho": (np.eye(2) + a * AFFINE_D).tolist(),
        "initial.rho_dot": (s * AFFINE_RDOT).tolist(),
        "initial.phi_dot": 1.5,
        "method.h": h,
    }
    if general:
        changes.update({"body.inertia": None, "body.J": GENERAL_J})
    return scene("s2-affine-elastic", t_end, **changes)


def gyro_potential(x, eps):
    return GYRO_ALPHA_HAT * x[2] ** 2 + GYRO_BETA_HAT * x[2] + eps * x[0]


def gyro_initial(eps, theta, v_theta):
    """Position and velocity of the gyroscope on the great circle x₁ = 0 at
    angle θ from the north pole towards +x₀, velocity v_θ along the circle
    and v₁ > 0 across it from the energy; None where v_θ is not allowed at
    that energy."""
    x = np.array([math.sin(theta), 0.0, math.cos(theta)])
    k = 2.0 * (GYRO_E - gyro_potential(x, eps)) - v_theta**2
    if k < 0.0:
        return None
    v = v_theta * np.array([math.cos(theta), 0.0, -math.sin(theta)]) + math.sqrt(k) * np.array([0.0, 1.0, 0.0])
    return x, v


def gyro_scene(eps, theta, v_theta, t_end, h=GYRO_H):
    """The gyroscope from gyro_initial(eps, θ, v_θ), or None."""
    xv = gyro_initial(eps, theta, v_theta)
    if xv is None:
        return None
    x, v = xv
    d = fd.Scene.example("s2-gyroscope-cosine").to_dict()
    terms = [{"kind": "cosine", "scale": 1.0, "alpha_hat": GYRO_ALPHA_HAT, "beta_hat": GYRO_BETA_HAT}]
    if eps != 0.0:
        terms.append({"kind": "cosine", "scale": 1.0, "beta_hat": eps, "centre": [1.0, 0.0, 0.0]})
    d["potential"] = {"kind": "sum", "terms": terms}
    d["initial"] = {"position": x.tolist(), "velocity": v.tolist(), "alpha": 0.0, "spin": GYRO_SPIN}
    d["time"]["t_end"] = t_end
    d["method"]["h"] = h
    d.pop("events", None)
    return fd.Scene.from_dict(d)


def s3_scene(t_end, h=S3_H):
    d = fd.Scene.example("s3-gyroscope").to_dict()
    d["time"]["t_end"] = t_end
    d["method"]["h"] = h
    d.pop("output", None)
    return fd.Scene.from_dict(d)


def classify(r):
    if r["chaotic_at"] is not None:
        return "chaotic"
    return "regular" if r["sali"] >= REGULAR_ABOVE else "undecided"


def map_members(model, variant, ps, qs, t_end):
    """The base scene of a map and its member table (the grid points the
    energy allows, p fastest): (scene, table, p of each member, q of each
    member, number of forbidden points)."""
    pp, qq = [float(p) for q in qs for p in ps], [float(q) for q in qs for p in ps]
    if model == "s2_affine":
        base = affine_scene(0.0, 0.0, variant == "general J", t_end)
        rho = [np.eye(2) + p * AFFINE_D for p in pp]
        rdot = [q * AFFINE_RDOT for q in qq]
        table = {f"initial.rho.{i}.{j}": np.array([m[i, j] for m in rho]) for i in range(2) for j in range(2)}
        table.update({f"initial.rho_dot.{i}.{j}": np.array([m[i, j] for m in rdot]) for i in range(2) for j in range(2)})
        return base, table, np.array(pp), np.array(qq), 0
    if model == "s3_gyroscope":
        table = {"initial.r1": np.array(pp), **{f"initial.omega.{k}": np.array(qq) * S3_OMEGA[k] for k in range(3)}}
        return s3_scene(t_end), table, np.array(pp), np.array(qq), 0
    eps = GYRO_EPS if variant == "tilted" else 0.0
    allowed = [(p, q, gyro_initial(eps, p, q)) for p, q in zip(pp, qq)]
    kept = [(p, q, xv) for p, q, xv in allowed if xv is not None]
    base = gyro_scene(eps, kept[0][0], kept[0][1], t_end)
    table = {f"initial.position.{k}": np.array([xv[0][k] for _, _, xv in kept]) for k in range(3)}
    table.update({f"initial.velocity.{k}": np.array([xv[1][k] for _, _, xv in kept]) for k in range(3)})
    return base, table, np.array([p for p, _, _ in kept]), np.array([q for _, q, _ in kept]), len(allowed) - len(kept)


def initial_records(base, table):
    """The first record of every member (energy, momenta): one columnar
    solve_batch of 10 steps each."""
    d = base.to_dict()
    n = len(next(iter(table.values())))
    short = {**table, "time.t_end": np.full(n, d["time"]["t0"] + 10 * d["method"]["h"])}
    out = fd.solve_batch(base, short, keep="all")
    first = out.flat[out.offsets[:-1]]
    return {c: first[:, j] for j, c in enumerate(out.columns)}


def centres(lo, hi, n):
    """n cell centres of [lo, hi] (a grid that avoids its ends)."""
    return lo + (hi - lo) * (np.arange(n) + 0.5) / n


def _set_tangents(tangents):
    """Worker initializer: the parent's TANGENTS (spawned workers start afresh)."""
    TANGENTS.update(tangents)


def pool_map(f, tasks, workers):
    if workers <= 1:
        return [f(t) for t in tasks]
    with get_context("spawn").Pool(workers, initializer=_set_tangents, initargs=(dict(TANGENTS),)) as pool:
        return pool.map(f, tasks, chunksize=1)


def map_grids(quick):
    """(model, variants, p values, q values, T, step, axis names)."""
    if quick:
        a, s, t_aff = np.linspace(0.0, 1.375, 4), np.linspace(0.0, 3.0, 4), 300.0
        th, vt, t_gyro = centres(-math.pi, math.pi, 12), centres(-1.9, 1.9, 6), 300.0
        r1, w, t_s3 = np.linspace(0.1, 1.3, 4), np.linspace(0.0, 6.0, 3), 100.0
    else:
        a, s, t_aff = np.arange(12) * 0.125, np.arange(13) * 0.25, 500.0
        th, vt, t_gyro = centres(-math.pi, math.pi, 30), centres(-1.9, 1.9, 18), 500.0
        r1, w, t_s3 = np.linspace(0.1, 1.4, 12), np.linspace(0.0, 6.0, 10), 300.0
    return [
        ("s2_affine", ("general J", "isotropic J"), a, s, t_aff, AFFINE_H, ("a", "s")),
        ("s2_gyroscope", ("separable", "tilted"), th, vt, t_gyro, GYRO_H, ("theta", "v_theta")),
        ("s3_gyroscope", ("J = diag(.1, .2, .3)",), r1, w, t_s3, S3_H, ("r1", "omega_scale")),
    ]


def run_chaos_map(base, table, what):
    """One fd.chaos_map call at MAP_THRESHOLD: the map, its wall and CPU time,
    and the SALI class ("chaotic" below the threshold within T, "regular" at
    or above REGULAR_ABOVE at T, else "undecided") and MEGNO class (⟨Y⟩ >
    MEGNO_CHAOTIC) of every member. Stops the script if a member did not
    finish (`what` names the map)."""
    w0, c0 = time.perf_counter(), time.process_time()
    m = fd.chaos_map(base, table, threshold=MAP_THRESHOLD, **TANGENTS)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    if not m.ok.all():
        bad = np.flatnonzero(~m.ok)
        raise SystemExit(f"{what}: {bad.size} members not finished, e.g. {m.errors[int(bad[0])]}")
    cls = np.where(np.isfinite(m.chaotic_at), "chaotic", np.where(m.sali >= REGULAR_ABOVE, "regular", "undecided"))
    mcls = np.where(m.megno_mean > MEGNO_CHAOTIC, "chaotic", "regular")
    return m, wall, cpu, cls, mcls


def maps(quick, data, figures):
    """Each map is one fd.chaos_map call (SALI and MEGNO of every grid point,
    in parallel in Rust) on its base scene and member table."""
    summary, rows_all = [], {}
    for model, variants, ps, qs, t_end, h, (pn, qn) in map_grids(quick):
        rows = []
        for v in variants:
            base, table, mp, mq, forbidden = map_members(model, v, ps, qs, t_end)
            rec = initial_records(base, table)
            m, wall, cpu, cls, mcls = run_chaos_map(base, table, f"map {model} {v}")
            energy = rec["energy"]
            spin = rec["k_12"] - rec["k_21"] if model == "s2_affine" else rec.get("spin", np.full(len(m), np.nan))
            mine = [
                {
                    "model": model,
                    "variant": v,
                    pn: float(mp[i]),
                    qn: float(mq[i]),
                    "T": t_end,
                    "energy": float(energy[i]),
                    "spin": float(spin[i]),
                    "sali": float(m.sali[i]),
                    "sali_min": float(m.sali_min[i]),
                    "chaotic_at": float(m.chaotic_at[i]),
                    "sali_steps": int(m.sali_steps[i]),
                    "class": str(cls[i]),
                    "megno_mean": float(m.megno_mean[i]),
                    "megno_slope": float(m.megno_slope[i]),
                    "lyapunov": float(m.lyapunov[i]),
                    "megno_class": str(mcls[i]),
                }
                for i in range(len(m))
            ]
            rows += mine
            count = {c: int(np.sum(cls == c)) for c in ("chaotic", "undecided", "regular")}
            decided = cls != "undecided"
            reg, cha, und = cls == "regular", cls == "chaotic", cls == "undecided"
            summary.append(
                {
                    "map": model,
                    "variant": v,
                    "grid": f"{len(ps)}x{len(qs)}",
                    "points": len(m),
                    "forbidden": forbidden,
                    "T": t_end,
                    "h": h,
                    "threshold": MAP_THRESHOLD,
                    "chaotic": count["chaotic"],
                    "undecided": count["undecided"],
                    "regular": count["regular"],
                    "chaotic_fraction": count["chaotic"] / len(m),
                    "t_chaos_median": float(np.median(m.chaotic_at[cha])) if cha.any() else float("nan"),
                    "t_chaos_max": float(np.max(m.chaotic_at[cha])) if cha.any() else float("nan"),
                    "regular_sali_min": float(np.min(m.sali[reg])) if reg.any() else float("nan"),
                    "megno_chaotic": int(np.sum(mcls == "chaotic")),
                    "megno_agree": int(np.sum((mcls == cls) & decided)),
                    "decided": int(np.sum(decided)),
                    "megno_regular_range": f"{np.min(m.megno_mean[reg]):.2f} … {np.max(m.megno_mean[reg]):.2f}" if reg.any() else "—",
                    "megno_regular_median": float(np.median(m.megno_mean[reg])) if reg.any() else float("nan"),
                    "megno_undecided_range": f"{np.min(m.megno_mean[und]):.1f} … {np.max(m.megno_mean[und]):.1f}" if und.any() else "—",
                    "megno_only": int(np.sum(reg & (mcls == "chaotic"))),
                    "megno_only_sali_range": f"{np.min(m.sali[reg & (mcls == 'chaotic')]):.1e} … {np.max(m.sali[reg & (mcls == 'chaotic')]):.1e}" if (reg & (mcls == "chaotic")).any() else "—",
                    "megno_only_megno_range": f"{np.min(m.megno_mean[reg & (mcls == 'chaotic')]):.1f} … {np.max(m.megno_mean[reg & (mcls == 'chaotic')]):.1f}" if (reg & (mcls == "chaotic")).any() else "—",
                    "sali_only": int(np.sum(cha & (mcls == "regular"))),
                    "megno_chaotic_range": f"{np.min(m.megno_mean[cha]):.1f} … {np.max(m.megno_mean[cha]):.1f}" if cha.any() else "—",
                    "lyapunov_regular_max": float(np.max(m.lyapunov[reg])) if reg.any() else float("nan"),
                    "lyapunov_chaotic_median": float(np.median(m.lyapunov[cha])) if cha.any() else float("nan"),
                    "chaotic_first_parameter_min": float(np.min(mp[cha])) if cha.any() else float("nan"),
                    "chaotic_energy_min": float(np.min(energy[cha])) if cha.any() else float("nan"),
                    "by_energy": " ".join(f"[{lo:g},{hi:g}):{int(np.sum((lo <= energy) & (energy < hi) & cha))}/{int(np.sum((lo <= energy) & (energy < hi)))}" for lo, hi in ENERGY_BANDS[model]),
                    "energy_min": float(np.min(energy)),
                    "energy_max": float(np.max(energy)),
                    "wall_s": wall,
                    "cpu_s": cpu,
                }
            )
            print(f"map {model} {v}: {count} of {len(m)}, MEGNO chaotic {summary[-1]['megno_chaotic']}, {wall:.0f} s wall, {cpu:.0f} s CPU", file=sys.stderr)
        write(os.path.join(data, f"integrability_map_{model}.csv"), rows)
        plot_map(model, variants, ps, qs, rows, (pn, qn), summary[-len(variants):], figures)
        rows_all[model] = rows
    return summary


def affine_drift(quick):
    """Relative energy drift over T at the maps' most violent corners: the
    affine body at the largest a and s (general J, isotropic J) and the S³
    gyroscope at the largest r₁ and spin."""
    a, s, t_end = 1.375, 3.0, (300.0 if quick else 500.0)
    scenes = [affine_scene(a, s, general, t_end) for general in (True, False)]
    r1, w, t_s3 = map_grids(quick)[2][2][-1], map_grids(quick)[2][3][-1], map_grids(quick)[2][4]
    d = s3_scene(t_s3).to_dict()
    d["initial"]["r1"] = float(r1)
    d["initial"]["omega"] = (w * S3_OMEGA).tolist()
    scenes.append(fd.Scene.from_dict(d))
    out = []
    for sc in scenes:
        e = fd.solve(sc).energy
        out.append(float(np.max(np.abs(e - e[0])) / abs(e[0])))
    return out


def plot_map(model, variants, ps, qs, rows, names, summary, figures):
    """SALI at the end (top row) and MEGNO ⟨Y⟩ at T (bottom row) over the
    grid, one column per variant."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pn, qn = names
    fig, axes = plt.subplots(2, len(variants), figsize=(6.2 * len(variants), 9.4), constrained_layout=True, squeeze=False)
    dp, dq = (ps[1] - ps[0]) if len(ps) > 1 else 1.0, (qs[1] - qs[0]) if len(qs) > 1 else 1.0
    extent = [ps[0] - dp / 2, ps[-1] + dp / 2, qs[0] - dq / 2, qs[-1] + dq / 2]
    for k, (v, summ) in enumerate(zip(variants, summary)):
        z = np.full((len(qs), len(ps)), np.nan)
        y = np.full((len(qs), len(ps)), np.nan)
        e = np.full((len(qs), len(ps)), np.nan)
        for r in rows:
            if r["variant"] != v:
                continue
            i, j = int(np.argmin(np.abs(qs - r[qn]))), int(np.argmin(np.abs(ps - r[pn])))
            z[i, j] = math.log10(max(r["sali"], 1e-12))
            y[i, j] = r["megno_mean"]
            e[i, j] = r["energy"]
        for row, (values, cmap_name, lo, hi, what) in enumerate(
            [
                (z, "magma", math.log10(MAP_THRESHOLD), 0.0, f"SALI: chaotic {summ['chaotic']}/{summ['points']} ({100 * summ['chaotic_fraction']:.0f} %), undecided {summ['undecided']}"),
                (y, "viridis", 0.0, 2.0 * MEGNO_CHAOTIC, f"MEGNO: ⟨Y⟩ > {MEGNO_CHAOTIC:g} at {summ['megno_chaotic']}/{summ['points']}; agrees with SALI at {summ['megno_agree']}/{summ['decided']}"),
            ]
        ):
            ax = axes[row, k]
            cmap = plt.get_cmap(cmap_name).copy()
            cmap.set_bad("0.85")
            im = ax.imshow(np.ma.masked_invalid(values), origin="lower", extent=extent, aspect="auto", cmap=cmap, vmin=lo, vmax=hi, interpolation="nearest")
            if model == "s2_affine":
                cs = ax.contour(ps, qs, e, levels=6, colors="white", linewidths=0.6, alpha=0.8)
                ax.clabel(cs, fmt="E=%.1f", fontsize=7)
                ax.plot([1.0], [1.0], marker="*", ms=12, mfc="none", mec="cyan", mew=1.5)
                ax.set_xlabel(r"initial deformation $a$ ($\rho = 1 + a D$)")
                ax.set_ylabel(r"initial rate $s$ ($\dot\rho = s\,\dot R$)")
                ax.set_title(f"S² affine body, elastic, {v}\n{what}", fontsize=9)
            elif model == "s2_gyroscope":
                ax.set_xlabel(r"$\theta$ on the circle $x_1 = 0$ (0: north pole, $\pm\pi$: south)")
                ax.set_ylabel(r"$v_\theta$")
                pot = r"$\hat\alpha z^2 + \hat\beta z$" if v == "separable" else rf"$\hat\alpha z^2 + \hat\beta z + {GYRO_EPS}\,x$"
                ax.set_title(f"S² gyroscope, {pot}\n{what}", fontsize=9)
            else:
                ax.set_xlabel(r"initial $r_1$")
                ax.set_ylabel(r"$s$: initial $\omega = s\,(1, 0.5, -0.3)$")
                ax.set_title(f"S³ gyroscope, oscillator, {v}\n{what}", fontsize=9)
            if k == len(variants) - 1:
                label = rf"$\log_{{10}}$ SALI at the end (runs stop at $10^{{{int(math.log10(MAP_THRESHOLD))}}}$)" if row == 0 else r"MEGNO $\langle Y\rangle$ at $T$ (2: quasi-periodic)"
                fig.colorbar(im, ax=axes[row, :].tolist(), label=label, shrink=0.9)
    fig.savefig(os.path.join(figures, f"integrability_map_{model}.png"), dpi=110)
    plt.close(fig)


# ------------------------------------------------------ maps over parameters

# The affine body's inertia along the straight line from the isotropic J of
# map (a) to its general J: J(δ) = J₀ + δ·(J₁ − J₀), J₀ = 0.1·1 (δ = 0, the
# isotropic body), J₁ = GENERAL_J (δ = 1); positive definite up to δ ≈ 1.9.
# Against the initial deformation a at the fixed rate s = PARAM_AFFINE_S
# (the row of map (a) with chaos at a ≥ 1 and none below), other initial
# values those of map (a).
ISOTROPIC_J = 0.1 * np.eye(2)
PARAM_AFFINE_S = 2.0


def affine_j(delta):
    return ISOTROPIC_J + delta * (np.array(GENERAL_J) - ISOTROPIC_J)


def param_grids(quick):
    """(model, parameter name, parameter values, initial-condition name, its
    values, T, step): the parameter on the horizontal axis, p below, one
    initial-condition coordinate q on the vertical one."""
    if quick:
        delta, a, t_aff = np.linspace(0.0, 1.2, 4), np.linspace(0.0, 1.5, 4), 300.0
        eps, th, t_gyro = np.linspace(0.0, 1.2, 4), centres(-math.pi, math.pi, 8), 300.0
    else:
        delta, a, t_aff = np.arange(25) * 0.05, np.arange(13) * 0.125, 500.0
        eps, th, t_gyro = np.arange(25) * 0.05, centres(-math.pi, math.pi, 36), 500.0
    return [
        ("s2_affine", "delta", delta, "a", a, t_aff, AFFINE_H),
        ("s2_gyroscope", "eps", eps, "theta", th, t_gyro, GYRO_H),
    ]


def param_members(model, ps, qs, t_end):
    """The base scene of a parameter map and its member table (p fastest):
    (scene, table, p of each member, q of each member, number of points the
    energy forbids). The parameter is a table column like the initial
    values: `body.J.I.J` for the affine body, `potential.terms.1.beta_hat`
    (the tilt ε) for the gyroscope."""
    pp, qq = [float(p) for q in qs for p in ps], [float(q) for q in qs for p in ps]
    if model == "s2_affine":
        base = affine_scene(0.0, PARAM_AFFINE_S, True, t_end)
        rho = [np.eye(2) + q * AFFINE_D for q in qq]
        js = [affine_j(p) for p in pp]
        table = {f"initial.rho.{i}.{j}": np.array([m[i, j] for m in rho]) for i in range(2) for j in range(2)}
        table.update({f"body.J.{i}.{j}": np.array([m[i, j] for m in js]) for i in range(2) for j in range(2)})
        return base, table, np.array(pp), np.array(qq), 0
    # The tilt term is in the base scene (gyro_scene adds it for ε ≠ 0), so
    # that its beta_hat can be a column; at ε = 0 it adds 0·x to V.
    allowed = [(p, q, gyro_initial(p, q, 0.0)) for p, q in zip(pp, qq)]
    kept = [(p, q, xv) for p, q, xv in allowed if xv is not None]
    base = gyro_scene(GYRO_EPS, kept[0][1], 0.0, t_end)
    table = {"potential.terms.1.beta_hat": np.array([p for p, _, _ in kept])}
    table.update({f"initial.position.{k}": np.array([xv[0][k] for _, _, xv in kept]) for k in range(3)})
    table.update({f"initial.velocity.{k}": np.array([xv[1][k] for _, _, xv in kept]) for k in range(3)})
    return base, table, np.array([p for p, _, _ in kept]), np.array([q for _, q, _ in kept]), len(allowed) - len(kept)


def param_maps(quick, data, figures):
    """One fd.chaos_map call per map, the parameter a column of the member
    table; per-member rows in integrability_params_<model>.csv, the classes
    per parameter value in integrability_params_summary.csv."""
    summary = []
    for model, pn, ps, qn, qs, t_end, h in param_grids(quick):
        base, table, mp, mq, forbidden = param_members(model, ps, qs, t_end)
        rec = initial_records(base, table)
        m, wall, cpu, cls, mcls = run_chaos_map(base, table, f"parameter map {model}")
        energy = rec["energy"]
        rows = [
            {
                "model": model,
                pn: float(mp[i]),
                qn: float(mq[i]),
                "T": t_end,
                "h": h,
                "energy": float(energy[i]),
                "sali": float(m.sali[i]),
                "sali_min": float(m.sali_min[i]),
                "chaotic_at": float(m.chaotic_at[i]),
                "class": str(cls[i]),
                "megno_mean": float(m.megno_mean[i]),
                "lyapunov": float(m.lyapunov[i]),
                "megno_class": str(mcls[i]),
            }
            for i in range(len(m))
        ]
        write(os.path.join(data, f"integrability_params_{model}.csv"), rows)
        mine = []
        for p in ps:
            at = np.isclose(mp, p)
            n = int(np.sum(at))
            count = {c: int(np.sum(at & (cls == c))) for c in ("chaotic", "undecided", "regular")}
            cha, reg = at & (cls == "chaotic"), at & (cls == "regular")
            mine.append(
                {
                    "map": model,
                    "parameter": pn,
                    "value": float(p),
                    "points": n,
                    "forbidden": len(qs) - n,
                    "T": t_end,
                    "chaotic": count["chaotic"],
                    "undecided": count["undecided"],
                    "regular": count["regular"],
                    "chaotic_fraction": count["chaotic"] / n if n else float("nan"),
                    "regular_fraction": count["regular"] / n if n else float("nan"),
                    "megno_chaotic": int(np.sum(at & (mcls == "chaotic"))),
                    "megno_agree": int(np.sum(at & (mcls == cls))),
                    "decided": int(np.sum(at & (cls != "undecided"))),
                    "initial_condition": qn,
                    "smallest_chaotic_initial": float(np.min(mq[cha])) if cha.any() else float("nan"),
                    "regular_sali_min": float(np.min(m.sali[reg])) if reg.any() else float("nan"),
                    "megno_regular_max": float(np.max(m.megno_mean[reg])) if reg.any() else float("nan"),
                    "energy_min": float(np.min(energy[at])) if n else float("nan"),
                    "energy_max": float(np.max(energy[at])) if n else float("nan"),
                    "wall_s": wall,
                    "cpu_s": cpu,
                }
            )
        summary += mine
        total = {c: int(np.sum(cls == c)) for c in ("chaotic", "undecided", "regular")}
        print(f"parameter map {model}: {total} of {len(m)} ({forbidden} forbidden), MEGNO chaotic {int(np.sum(mcls == 'chaotic'))}, {wall:.0f} s wall, {cpu:.0f} s CPU", file=sys.stderr)
        plot_param_map(model, (pn, ps), (qn, qs), rows, mine, figures)
    write(os.path.join(data, "integrability_params_summary.csv"), summary)
    return summary


# The small parameters again with a run four times as long: is the absence
# of chaos there a matter of T? (parameter values, T) per model.
PARAM_LONG = {"s2_affine": ((0.1, 0.3, 0.5), 2000.0), "s2_gyroscope": ((0.1, 0.2), 2000.0)}
PARAM_LABEL = {"delta": "δ", "eps": "ε", "a": "a", "theta": "θ"}


def param_long(quick):
    """The members of PARAM_LONG's parameter values (every initial condition
    of the map), one fd.chaos_map call per model at the longer T: the
    classes per parameter value."""
    out = []
    for model, pn, _, qn, qs, t_map, _ in param_grids(quick):
        values, t_end = PARAM_LONG[model]
        if quick:
            values, t_end = values[-1:], 2.0 * t_map
        base, table, mp, mq, _ = param_members(model, np.array(values), qs, t_end)
        m, wall, _, cls, _ = run_chaos_map(base, table, f"long parameter map {model}")
        for p in values:
            at = np.isclose(mp, p)
            reg = at & (cls == "regular")
            out.append(
                {
                    "map": model,
                    "parameter": pn,
                    "value": float(p),
                    "T": t_end,
                    "points": int(np.sum(at)),
                    "chaotic": int(np.sum(at & (cls == "chaotic"))),
                    "undecided": int(np.sum(at & (cls == "undecided"))),
                    "regular": int(np.sum(reg)),
                    "megno_chaotic": int(np.sum(at & (m.megno_mean > MEGNO_CHAOTIC))),
                    "chaotic_" + "initial": " ".join(f"{q:.3g}" for q in mq[at & (cls == "chaotic")]),
                    "regular_sali_min": float(np.min(m.sali[reg])) if reg.any() else float("nan"),
                    "megno_regular_max": float(np.max(m.megno_mean[reg])) if reg.any() else float("nan"),
                    "wall_s": wall,
                }
            )
        print(f"long parameter map {model}: T = {t_end:g}, {len(m)} members, {wall:.0f} s wall", file=sys.stderr)
    return out


def param_drift(quick):
    """Relative energy drift over T at the most violent corner of each
    parameter map: the affine body at the largest δ and a, the gyroscope at
    the largest ε on the first allowed θ of the grid."""
    out = []
    for model, _, ps, _, qs, t_end, _ in param_grids(quick):
        if model == "s2_affine":
            d = affine_scene(float(qs[-1]), PARAM_AFFINE_S, True, t_end).to_dict()
            d["body"]["J"] = affine_j(float(ps[-1])).tolist()
            s = fd.Scene.from_dict(d)
        else:
            s = next(sc for sc in (gyro_scene(float(ps[-1]), float(q), 0.0, t_end) for q in qs) if sc is not None)
        e = fd.solve(s).energy
        out.append((model, float(np.max(np.abs(e - e[0])) / abs(e[0]))))
    return out


def compare_with_initial_maps(quick):
    """The members of the affine parameter map at δ = 1 (general J) and
    δ = 0 (isotropic J, here as body.J = 0.1·1 rather than body.inertia =
    0.1) against the points of map (a) at the same (a, s), read from
    docs/data/integrability_map_s2_affine.csv: the number of equal classes
    and the largest relative difference of the final SALI."""
    if quick:
        return []
    path = os.path.join(DATA, "integrability_map_s2_affine.csv")
    mine = os.path.join(DATA, "integrability_params_s2_affine.csv")
    if not (os.path.exists(path) and os.path.exists(mine)):
        return []
    with open(path) as f:
        old = {(r["variant"], round(float(r["a"]), 6)): r for r in csv.DictReader(f) if abs(float(r["s"]) - PARAM_AFFINE_S) < 1e-9}
    with open(mine) as f:
        new = list(csv.DictReader(f))
    out = []
    for delta, variant in ((1.0, "general J"), (0.0, "isotropic J")):
        pairs = [(r, old[(variant, round(float(r["a"]), 6))]) for r in new if abs(float(r["delta"]) - delta) < 1e-9 and (variant, round(float(r["a"]), 6)) in old]
        same = sum(r["class"] == o["class"] for r, o in pairs)
        rel = max(abs(float(r["sali"]) - float(o["sali"])) / float(o["sali"]) for r, o in pairs)
        out.append((delta, variant, same, len(pairs), rel))
    return out


def plot_param_map(model, pars, ics, rows, summary, figures):
    """SALI at the end and MEGNO ⟨Y⟩ at T over (parameter, initial
    condition), and the fractions of chaotic, undecided and regular members
    against the parameter."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (pn, ps), (qn, qs) = pars, ics
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.0), constrained_layout=True)
    dp, dq = ps[1] - ps[0], qs[1] - qs[0]
    extent = [ps[0] - dp / 2, ps[-1] + dp / 2, qs[0] - dq / 2, qs[-1] + dq / 2]
    z = np.full((len(qs), len(ps)), np.nan)
    y = np.full((len(qs), len(ps)), np.nan)
    for r in rows:
        i, j = int(np.argmin(np.abs(qs - r[qn]))), int(np.argmin(np.abs(ps - r[pn])))
        z[i, j] = math.log10(max(r["sali"], 1e-12))
        y[i, j] = r["megno_mean"]
    if model == "s2_affine":
        xlabel = r"$\delta$: $J = 0.1\cdot 1 + \delta\,(J_1 - 0.1\cdot 1)$, $J_1 = [[0.1, 0.02], [0.02, 0.05]]$"
        ylabel = r"initial deformation $a$ ($\rho = 1 + a D$)"
        title = f"S² affine body, elastic, ρ̇₀ = {PARAM_AFFINE_S:g}·Ṙ, T = {rows[0]['T']:g}"
    else:
        xlabel = r"tilt $\varepsilon$: $V = \hat\alpha z^2 + \hat\beta z + \varepsilon x$"
        ylabel = r"$\theta$ on the circle $x_1 = 0$, $v_\theta = 0$"
        title = f"S² gyroscope, spin {GYRO_SPIN}, ½|v|² + V = {GYRO_E:g}, T = {rows[0]['T']:g}"
    for ax, values, cmap_name, lo, hi, label in (
        (axes[0], z, "magma", math.log10(MAP_THRESHOLD), 0.0, rf"$\log_{{10}}$ SALI at the end (runs stop at $10^{{{int(math.log10(MAP_THRESHOLD))}}}$)"),
        (axes[1], y, "viridis", 0.0, 2.0 * MEGNO_CHAOTIC, r"MEGNO $\langle Y\rangle$ at $T$ (2: quasi-periodic)"),
    ):
        cmap = plt.get_cmap(cmap_name).copy()
        cmap.set_bad("0.85")
        im = ax.imshow(np.ma.masked_invalid(values), origin="lower", extent=extent, aspect="auto", cmap=cmap, vmin=lo, vmax=hi, interpolation="nearest")
        fig.colorbar(im, ax=ax, label=label, shrink=0.9)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=9)
    ax = axes[2]
    x = [r["value"] for r in summary]
    ax.plot(x, [100 * r["chaotic_fraction"] for r in summary], "o-", color="black", label=f"chaotic (SALI < {MAP_THRESHOLD:g})")
    ax.plot(x, [100 * r["undecided"] / r["points"] for r in summary], "s-", color="0.6", label="undecided")
    ax.plot(x, [100 * r["regular_fraction"] for r in summary], "^-", color="tab:blue", label=f"regular (SALI ≥ {REGULAR_ABOVE:g})")
    ax.plot(x, [100 * r["megno_chaotic"] / r["points"] for r in summary], "x--", color="tab:red", label=f"MEGNO ⟨Y⟩ > {MEGNO_CHAOTIC:g}")
    ax.set_xlabel(xlabel, fontsize=8)
    ax.set_ylabel(f"% of the allowed members at that {PARAM_LABEL[pn]}")
    ax.set_ylim(-3, 103)
    ax.legend(fontsize=8)
    ax.set_title(f"classes against {PARAM_LABEL[pn]} (at most {len(qs)} values of {PARAM_LABEL[qn]} each)", fontsize=9)
    fig.savefig(os.path.join(figures, f"integrability_params_{model}.png"), dpi=110)
    plt.close(fig)


def print_param_long(rows):
    print()
    print(
        f"| map | parameter | T | members | chaotic (SALI < {MAP_THRESHOLD:g}) | undecided | regular | ⟨Y⟩ > {MEGNO_CHAOTIC:g} | initial condition of the chaotic | "
        "smallest final SALI of the regular | largest ⟨Y⟩ of the regular | wall |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['map']} | {PARAM_LABEL[r['parameter']]} = {r['value']:g} | {r['T']:g} | {r['points']} | {r['chaotic']} | {r['undecided']} | {r['regular']} | "
            f"{r['megno_chaotic']} | {r['chaotic_initial'] or '—'} | {r['regular_sali_min']:.1e} | {r['megno_regular_max']:.2f} | {r['wall_s']:.0f} s |"
        )


def print_params(summary, drift, checks):
    for model in dict.fromkeys(r["map"] for r in summary):
        mine = [r for r in summary if r["map"] == model]
        pn = mine[0]["parameter"]
        qn = mine[0]["initial_condition"]
        print()
        print(
            f"| {pn} | members | chaotic (SALI < {MAP_THRESHOLD:g}) | undecided | regular | chaotic fraction | ⟨Y⟩ > {MEGNO_CHAOTIC:g} | MEGNO agrees (of the decided) | "
            f"smallest {qn} of a chaotic member | smallest final SALI of the regular | largest ⟨Y⟩ of the regular | initial energy |"
        )
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in mine:
            first = r["smallest_chaotic_initial"]
            print(
                f"| {r['value']:g} | {r['points']} | {r['chaotic']} | {r['undecided']} | {r['regular']} | {100 * r['chaotic_fraction']:.1f} % | {r['megno_chaotic']} | "
                f"{r['megno_agree']}/{r['decided']} | {'—' if math.isnan(first) else f'{first:.3g}'} | {r['regular_sali_min']:.1e} | {r['megno_regular_max']:.2f} | "
                f"{r['energy_min']:.2f} … {r['energy_max']:.2f} |"
            )
        total = {k: sum(r[k] for r in mine) for k in ("points", "forbidden", "chaotic", "undecided", "regular", "megno_chaotic", "megno_agree", "decided")}
        print(
            f"\n{model}: T = {mine[0]['T']:g}, in all {total['chaotic']} chaotic, {total['undecided']} undecided, {total['regular']} regular of {total['points']} "
            f"({total['forbidden']} forbidden by the energy); ⟨Y⟩ > {MEGNO_CHAOTIC:g} at {total['megno_chaotic']}, MEGNO agrees with SALI at {total['megno_agree']}/{total['decided']} "
            f"of the decided; one fd.chaos_map call: {mine[0]['wall_s']:.0f} s wall, {mine[0]['cpu_s']:.0f} s CPU"
        )
    for model, d in drift:
        print(f"{model} parameter map, most violent corner: relative energy drift over T {d:.1e}")
    for delta, variant, same, n, rel in checks:
        print(f"affine parameter map at delta = {delta:g} against map (a), {variant}, s = {PARAM_AFFINE_S:g}: {same}/{n} classes equal, largest relative difference of the final SALI {rel:.1e}")


def floor_cases(t_end):
    """The chaotic orbits of the floor check: (file stem, name, h, scene)."""
    return [
        ("gyro_h0.005", "S² gyroscope, tilted, θ = −3.0, v_θ = 0", 0.005, gyro_scene(GYRO_EPS, -3.0, 0.0, t_end, 0.005)),
        ("gyro_h0.01", "S² gyroscope, tilted, θ = −3.0, v_θ = 0", 0.01, gyro_scene(GYRO_EPS, -3.0, 0.0, t_end, 0.01)),
        ("gyro_h0.02", "S² gyroscope, tilted, θ = −3.0, v_θ = 0", 0.02, gyro_scene(GYRO_EPS, -3.0, 0.0, t_end, 0.02)),
        ("affine_h0.005", "S² affine body, general J, a = 1, s = 1", 0.005, affine_scene(1.0, 1.0, True, t_end, 0.005)),
        ("affine_h0.002", "S² affine body, general J, a = 1, s = 1", 0.002, affine_scene(1.0, 1.0, True, t_end, 0.002)),
    ]


# Keyword arguments of every analysis call: {"differenced": True} with
# --differenced (set before any worker process is forked).
TANGENTS: dict = {}

# The linearisations of the floor check: (difference formula, ε); "exact"
# is the method on the tangent group (ε unused).
FLOOR_LINEARISATIONS = [("central2", 1e-5), ("central2", 1e-3), ("central4", 1e-3), ("exact", float("nan"))]


def sali_floor(quick):
    """The smallest SALI chaotic orbits reach with no threshold, for each
    linearisation: no floor (until 145caef there was one, proportional to
    1/ε: docs/integrability.md)."""
    t_end = 300.0 if quick else 1000.0
    rows = []
    for _, name, h, s in floor_cases(t_end):
        for formula, eps in FLOOR_LINEARISATIONS:
            if formula == "exact":
                r = fd.sali(s, threshold=1e-300)
                assert r["exact_tangents"], "the floor cases have exact tangent maps"
            else:
                r = fd.sali(s, threshold=1e-300, eps=eps, fourth_order=formula == "central4", differenced=True)
            rows.append({"case": name, "h": h, "T": t_end, "difference": formula, "eps": eps, "sali_min": r["min"], "sali_end": r["sali"], "below_1e-8": r["min"] < 1e-8})
            print(f"floor {name} h = {h} {formula} eps = {eps:g}: min {r['min']:.2e}", file=sys.stderr)
    return rows


def print_floor(floor):
    print("| SALI floor: case | h | T | difference, ε | smallest SALI (no threshold) | SALI at T |")
    print("|---|---|---|---|---|---|")
    for r in floor:
        print(f"| {r['case']} | {r['h']:g} | {r['T']:g} | {r['difference']}, {r['eps']:g} | {r['sali_min']:.1e} | {r['sali_end']:.1e} |")


# Sections of the point on S² at equal energy: (scene, V(r), energy).
POINT_MODELS = [
    ("S² point, Kepler (Bertrand)", "s2-point-kepler", lambda r: -1.0 / math.tan(r), -0.5),
    ("S² point, oscillator (Bertrand)", "s2-point-oscillator", lambda r: 0.5 * math.tan(r) ** 2, 0.5),
    ("S² point, V = r²/2 (non-Bertrand)", "s2-point-central", lambda r: 0.5 * r * r, 0.5),
]


def r_max(v, energy):
    lo, hi = 1e-3, math.pi / 2 - 1e-3
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if v(mid) < energy else (lo, mid)
    return lo


POINT_SECTION_H = 0.001  # RK4's error precesses the eccentric Kepler orbits at the scenes' h = 0.005 (see kepler_steps)


def point_orbit(task, h=POINT_SECTION_H):
    """One orbit of a point model at its energy: r₀ = f·(largest r allowed),
    ṙ₀ = g·(largest ṙ there), φ̇₀ > 0 from the energy; its section (at step
    h) and SALI (at the scene's step)."""
    name, example, k, f, g, t_end = task
    v, energy = POINT_MODELS[k][2], POINT_MODELS[k][3]
    r0 = f * r_max(v, energy)
    kinetic = 2.0 * (energy - v(r0))
    rdot0 = g * math.sqrt(kinetic)
    phi_dot = math.sqrt(kinetic - rdot0**2) / math.sin(r0)
    initial = {"initial.r": r0, "initial.r_dot": rdot0, "initial.phi": 0.0, "initial.phi_dot": phi_dot}
    sec = fd.section(scene(example, t_end, **initial, **{"method.h": h}), plane=[0.0, 1.0, 0.0], direction="rising")
    r = fd.sali(scene(example, t_end, **initial), threshold=MAP_THRESHOLD, **TANGENTS)
    return orbit_row(name, sec, r0, rdot0, sec.column("r"), sec.column("r_dot"), r)


def orbit_row(model, sec, q0, p0, q, p, r):
    """One orbit of a section plot: its start (q0, p0), its crossings in the
    section's coordinates (q, p) with their spread, and its SALI verdict."""
    return {
        "model": model,
        "energy": float(np.mean(sec.column("energy"))),
        "q0": q0,
        "p0": p0,
        "crossings": len(sec),
        "spread_q": float(np.ptp(q)),
        "spread_p": float(np.ptp(p)),
        "sali": r["sali"],
        "class": classify(r),
        "points_q": q,
        "points_p": p,
    }


def gyro_orbit(task):
    eps, theta, v_theta, t_end = task
    s = gyro_scene(eps, theta, v_theta, t_end)
    if s is None:
        return None
    sec = fd.section(s, plane=[0.0, 1.0, 0.0], direction="rising")
    x0, x2, v0, v2 = (sec.column(c) for c in ("x0", "x2", "v0", "v2"))
    q, p = np.arctan2(x0, x2), x2 * v0 - x0 * v2
    r = fd.sali(gyro_scene(eps, theta, v_theta, min(t_end, 500.0)), threshold=MAP_THRESHOLD, **TANGENTS)
    model = "S² gyroscope, separable" if eps == 0.0 else f"S² gyroscope, tilted (ε = {eps})"
    return orbit_row(model, sec, theta, v_theta, q, p, r)


def kepler_steps(quick):
    """The most eccentric Kepler orbit of the section at three steps: the
    spread of its crossings is RK4's error, not the dynamics."""
    t_end = 100.0 if quick else 300.0
    name, example = POINT_MODELS[0][0], POINT_MODELS[0][1]
    return [{"h": h, "spread_r": point_orbit((name, example, 0, 0.9, 0.5, t_end), h)["spread_q"]} for h in (0.005, 0.002, 0.001)]


def sections(quick, workers, data, figures):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t_point, t_gyro = (100.0, 400.0) if quick else (300.0, 1500.0)
    point_tasks = [(name, ex, k, f, g, t_point) for k, (name, ex, _, _) in enumerate(POINT_MODELS) for f, g in ((0.3, 0.0), (0.5, 0.0), (0.7, 0.0), (0.9, 0.0), (0.5, 0.5), (0.7, 0.5), (0.9, 0.5))]
    thetas = np.linspace(-3.0, 3.0, 7 if quick else 13)
    gyro_tasks = [(eps, float(th), vt, t_gyro) for eps in (0.0, GYRO_EPS) for th, vt in [(t, 0.0) for t in thetas] + [(-1.0, 1.0), (1.0, 1.0), (-2.2, 1.2), (2.2, 1.2)]]
    points = pool_map(point_orbit, point_tasks, workers)
    gyros = [o for o in pool_map(gyro_orbit, gyro_tasks, workers) if o is not None]

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    for ax, (name, _, _, energy) in zip(axes, POINT_MODELS):
        mine = [o for o in points if o["model"] == name]
        for o in mine:
            ax.plot(o["points_q"], o["points_p"], ".", ms=3 if o["spread_q"] < 1e-3 else 1.2)
        worst = max(o["spread_q"] for o in mine)
        ax.set_title(f"{name}, E = {energy:g}\n{len(mine)} orbits, largest spread of r over its crossings: {worst:.1e}", fontsize=9)
        ax.set_xlabel("r at the crossing of x₁ = 0 (rising)")
        ax.set_ylabel("ṙ")
    fig.savefig(os.path.join(figures, "integrability_sections_s2_point.png"), dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), constrained_layout=True, sharey=True)
    colours = plt.get_cmap("tab20")
    for ax, eps in zip(axes, (0.0, GYRO_EPS)):
        mine = [o for o in gyros if (o["model"] == "S² gyroscope, separable") == (eps == 0.0)]
        for i, o in enumerate(mine):
            if o["class"] == "chaotic":
                ax.plot(o["points_q"], o["points_p"], ".", ms=1.5, color="black")
            else:
                ax.plot(o["points_q"], o["points_p"], ".", ms=1.5, color=colours(i % 20) if o["class"] == "regular" else "0.55")
        n_chaotic = sum(o["class"] == "chaotic" for o in mine)
        pot = "α̂z² + β̂z" if eps == 0.0 else f"α̂z² + β̂z + {eps}·x"
        ax.set_title(f"S² gyroscope, V = {pot}, E = {mine[0]['energy']:.2f}, spin {GYRO_SPIN}\n{len(mine)} orbits, {n_chaotic} chaotic by SALI (black), undecided grey", fontsize=9)
        ax.set_xlabel("θ at the crossing of x₁ = 0 (rising)")
    axes[0].set_ylabel("v_θ")
    fig.savefig(os.path.join(figures, "integrability_sections_s2_gyroscope.png"), dpi=110)
    plt.close(fig)

    rows = [{k: v for k, v in o.items() if not k.startswith("points_")} for o in points + gyros]
    write(os.path.join(data, "integrability_sections.csv"), rows)
    return rows


def print_map_summary(summary):
    print()
    print(
        f"| map | variant | grid (points) | T | chaotic (SALI < {MAP_THRESHOLD:g}) | undecided | regular | chaotic fraction | t at {MAP_THRESHOLD:g}: median, max | "
        "smallest final SALI of the regular | initial energy | wall, CPU |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in summary:
        times = "—" if math.isnan(r["t_chaos_median"]) else f"{r['t_chaos_median']:.0f}, {r['t_chaos_max']:.0f}"
        print(
            f"| {r['map']} | {r['variant']} | {r['grid']} ({r['points']}) | {r['T']:g} | {r['chaotic']} | {r['undecided']} | {r['regular']} | "
            f"{100 * r['chaotic_fraction']:.1f} % | {times} | {r['regular_sali_min']:.1e} | {r['energy_min']:.2f} … {r['energy_max']:.2f} | {r['wall_s']:.0f} s, {r['cpu_s']:.0f} s |"
        )
    print()
    print(
        f"| map | variant | ⟨Y⟩ > {MEGNO_CHAOTIC:g} | agrees with SALI (of the decided) | ⟨Y⟩ of the SALI-regular: range, median | ⟨Y⟩ of the SALI-undecided | ⟨Y⟩ of the SALI-chaotic | "
        f"SALI-regular with ⟨Y⟩ > {MEGNO_CHAOTIC:g}: count, their final SALI, their ⟨Y⟩ | SALI-chaotic with ⟨Y⟩ ≤ {MEGNO_CHAOTIC:g} | finite-time λ: largest regular, median chaotic |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in summary:
        print(
            f"| {r['map']} | {r['variant']} | {r['megno_chaotic']} | {r['megno_agree']}/{r['decided']} | {r['megno_regular_range']}, {r['megno_regular_median']:.2f} | "
            f"{r['megno_undecided_range']} | {r['megno_chaotic_range']} | {r['megno_only']}, {r['megno_only_sali_range']}, {r['megno_only_megno_range']} | {r['sali_only']} | "
            f"{r['lyapunov_regular_max']:.3f}, {r['lyapunov_chaotic_median']:.3f} |"
        )
    print()
    for r in summary:
        if r["map"] == "s2_affine":
            print(f"{r['map']} {r['variant']}: chaotic by initial energy (band: chaotic/points) {r['by_energy']}; smallest a of a chaotic point {r['chaotic_first_parameter_min']:g}, lowest initial energy {r['chaotic_energy_min']:.2f}")


def print_drift(drift):
    print(f"\naffine map corner (a = 1.375, s = 3) relative energy drift over T: general J {drift[0]:.1e}, isotropic J {drift[1]:.1e}; S³ map corner (largest r1 and spin) {drift[2]:.1e}")


def print_maps(summary, drift, floor, sec_rows, kepler):
    print_map_summary(summary)
    if drift is not None:
        print_drift(drift)
    print()
    print_floor(floor)
    print()
    print("most eccentric Kepler orbit of the section, spread of r over its crossings: " + ", ".join(f"{r['spread_r']:.1e} at h = {r['h']:g}" for r in kepler))
    print()
    print("| section: model | E | orbits | crossings per orbit | largest spread of q over an orbit's crossings | SALI classes |")
    print("|---|---|---|---|---|---|")
    for m in dict.fromkeys(r["model"] for r in sec_rows):
        mine = [r for r in sec_rows if r["model"] == m]
        classes = {c: sum(r["class"] == c for r in mine) for c in ("chaotic", "undecided", "regular")}
        print(
            f"| {m} | {mine[0]['energy']:.3f} | {len(mine)} | {min(r['crossings'] for r in mine)} … {max(r['crossings'] for r in mine)} | "
            + (f"{max(r['spread_q'] for r in mine):.1e}" if m.startswith("S² point") else "—")
            + " | "
            + ", ".join(f"{n} {c}" for c, n in classes.items() if n) + " |"
        )


# (case, paper's claim, scene name, changes) for the degeneracy table.
DEGENERACY_CASES = [
    ("S² point, Kepler (Bertrand)", "maximally degenerate (§5)", "s2-point-kepler", {}),
    ("S² point, oscillator (Bertrand)", "maximally degenerate (§5)", "s2-point-oscillator", {}),
    ("H² point, Kepler (Bertrand)", "maximally degenerate (§5)", "h2-point-kepler", {}),
    ("S² point, Kepler + 0.2 cos r (non-Bertrand)", "integrable (central), orbits not closed", "s2-point-sum", {}),
    ("S² point, V = r²/2 (non-Bertrand)", "integrable (central), orbits not closed", "s2-point-central", {}),
    ("S³ point, Kepler (Bertrand)", "maximally degenerate ((c88) on S³)", "s3-point-kepler", {}),
    ("S³ point, oscillator (Bertrand)", "maximally degenerate", "s3-point-oscillator", {}),
    (
        "S³ point, Kepler + 0.2 cos r (non-Bertrand)",
        "integrable (central), orbits not closed",
        "s3-point-kepler",
        {"potential": {"kind": "sum", "terms": [{"kind": "kepler", "alpha": 1.0}, {"kind": "cosine", "beta_hat": 0.2, "scale": 1.0}]}, "initial.r1_dot": 0.1},
    ),
]


def window_slope(g, lo, hi):
    """Log–log slope of GALI over [lo, hi] from its means over [lo/2, lo]
    and [hi/2, hi] (the index swings within each period)."""

    def mean(a, b):
        m = (g.times >= a) & (g.times <= b)
        return float(np.mean(g.running_log10[m]))

    return (mean(hi / 2, hi) - mean(lo / 2, lo)) / math.log10(hi / lo)


def degeneracy(quick, data):
    """GALI₂ and GALI₃ of the central-potential orbits, in the phase space
    (the default: modulo the parallel frame's gauge direction) and on the
    stored state, with DOP853 at tol 1e-10: log–log slopes over the decades
    t = 100 … 1000 and 1000 … 10⁴ (window means). One drifting direction
    (a Bertrand orbit: closed) gives GALI₂ ~ 1/t, two (a torus) keep it."""
    t_end = 2000.0 if quick else 10_000.0
    rows = []
    for case, claim, name, changes in DEGENERACY_CASES:
        sc = scene(name, t_end, **{"method.name": "dop853", "method.h": None, "method.rtol": 1e-10, "method.atol": 1e-10, **changes})
        row = {"case": case, "paper": claim, "T": t_end}
        for k, quotient in ((2, True), (3, True), (2, False)):
            g = fd.gali(sc, k=k, threshold=1e-300, quotient=quotient, **TANGENTS)
            key = f"gali{k}_{'phase' if quotient else 'stored'}"
            row[f"{key}_slope_100_1000"] = window_slope(g, 100.0, 1000.0)
            row[f"{key}_slope_1000_T"] = window_slope(g, 1000.0, t_end)
            row[f"{key}_log10_T"] = g.log10
            row["steps"] = g.steps
        rows.append(row)
    write(os.path.join(data, "integrability_degeneracy.csv"), rows)
    print(f"\nGALI in the phase space and on the stored state (DOP853, tol 1e-10, T = {t_end:g}); log–log slopes from window means:\n")
    print("| case | the paper | GALI₂ phase space: slope 10²…10³ / 10³…T, value at T | GALI₃ phase space: slope 10²…10³ / 10³…T | GALI₂ stored state: slope 10²…10³ / 10³…T | GALI₂ in the phase space says |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        s2 = r["gali2_phase_slope_100_1000"], r["gali2_phase_slope_1000_T"]
        verdict = "one drifting direction up to T" if max(s2) < -0.8 else ("two drifting directions (a torus)" if abs(s2[1]) < 0.25 else "undecided")
        print(
            f"| {r['case']} | {r['paper']} | {s2[0]:.2f} / {s2[1]:.2f}, 10^{r['gali2_phase_log10_T']:.2f} | {r['gali3_phase_slope_100_1000']:.2f} / {r['gali3_phase_slope_1000_T']:.2f} | "
            f"{r['gali2_stored_slope_100_1000']:.2f} / {r['gali2_stored_slope_1000_T']:.2f} | {verdict} |"
        )
    return rows


def leveling(t_end, data, tol=1e-10, tangents="exact"):
    """How long the weak twist of V = r²/2 on S² (the scene s2-point-central,
    not a Bertrand potential) keeps GALI₂ falling like 1/t: GALI₂ in the
    phase space to `t_end` (DOP853, tol 1e-10), its log–log slope over each
    decade and its mean over each half-decade window [t/2, t]. A torus with
    twist keeps GALI₂ at a constant once the two drifts separate; a closed
    orbit (Bertrand) keeps it falling like 1/t. `tangents`: "exact" (the
    method on the tangent group), "central2" or "central4" (differences of
    the step map)."""
    sc = scene("s2-point-central", t_end, **{"method.name": "dop853", "method.h": None, "method.rtol": tol, "method.atol": tol})
    if tangents == "exact":
        g = fd.gali(sc, k=2, threshold=1e-300, quotient=True)
        assert g.exact_tangents
    else:
        g = fd.gali(sc, k=2, threshold=1e-300, quotient=True, fourth_order=tangents == "central4", differenced=True)
    rows = []
    t = 10.0 ** 2.5
    while t <= t_end * (1 + 1e-12):
        m = (g.times >= t / 2) & (g.times <= t)
        row = {"t": t, "mean_log10_gali2_over_t_half_to_t": float(np.mean(g.running_log10[m]))}
        if t >= 1000.0 and abs(math.log10(t) - round(math.log10(t))) < 1e-9:
            row["slope_over_the_decade_to_t"] = window_slope(g, t / 10.0, t)
        else:
            row["slope_over_the_decade_to_t"] = float("nan")
        rows.append(row)
        t *= 10.0 ** 0.5
    suffix = ("" if tol == 1e-10 else f"_tol{tol:g}") + {"central2": "", "central4": "_fourth_order", "exact": "_exact"}[tangents]
    write(os.path.join(data, f"integrability_leveling{suffix}.csv"), rows)
    lin = {"central2": "second-order differences", "central4": "fourth-order differences", "exact": "exact tangent maps"}[tangents]
    print(f"\nGALI₂ (phase space) of V = r²/2 on S² (s2-point-central), DOP853 tol {tol:g}, {lin}, T = {t_end:g}, {g.steps} steps:\n")
    print("| t | mean log10 GALI₂ over [t/2, t] | slope over the decade to t |")
    print("|---|---|---|")
    for r in rows:
        sl = r["slope_over_the_decade_to_t"]
        print(f"| {r['t']:.3g} | {r['mean_log10_gali2_over_t_half_to_t']:.2f} | {'' if math.isnan(sl) else f'{sl:.2f}'} |")
    return rows


def run_params(quick, data, figures):
    summary = param_maps(quick, data, figures)
    print_params(summary, param_drift(quick), compare_with_initial_maps(quick))
    long = param_long(quick)
    write(os.path.join(data, "integrability_params_long.csv"), long)
    print_param_long(long)


def main():
    ap = argparse.ArgumentParser(description="Integrability atlas (issue 21): the table of exponents, its cost, SALI maps and Poincaré sections.")
    ap.add_argument("--quick", action="store_true", help="small grids and short runs, written to out/integrability_quick/")
    ap.add_argument("--maps-only", action="store_true", help="maps, sections and the SALI floor only (not the table and cost)")
    ap.add_argument("--table-only", action="store_true", help="the table and cost only (not the maps)")
    ap.add_argument("--floor-only", action="store_true", help="the SALI floor check only")
    ap.add_argument("--grids-only", action="store_true", help="the SALI/MEGNO maps over initial conditions only (not the floor check and sections)")
    ap.add_argument("--params-only", action="store_true", help="the maps over parameters only (the affine body's J anisotropy, the gyroscope's tilt)")
    ap.add_argument("--degeneracy-only", action="store_true", help="the GALI table of maximal degeneracy only (central potentials, phase space against stored state)")
    ap.add_argument("--leveling", type=float, metavar="T", help="GALI₂ of V = r²/2 on S² to T (e.g. 1e7: about 25 minutes), per decade, and stop")
    ap.add_argument("--leveling-tol", type=float, default=1e-10, help="DOP853 tolerance of --leveling (default 1e-10)")
    ap.add_argument(
        "--leveling-tangents",
        choices=["exact", "central2", "central4"],
        default="exact",
        help="tangent maps of --leveling: exact (default; CSV integrability_leveling_exact.csv), or second- / fourth-order differences of the step (integrability_leveling.csv, ..._fourth_order.csv)",
    )
    ap.add_argument(
        "--differenced",
        action="store_true",
        help="every analysis with second-order differences of the step map instead of the exact tangent maps (how the pages' numbers measured before the exact maps were made)",
    )
    ap.add_argument("--floor-scenes", metavar="DIR", help="write the floor check's orbits as scene files (JSON) into DIR and stop")
    ap.add_argument("--workers", type=int, default=2, help="worker processes for the sections (1 or 2); the maps run on the Rust threads of fd.chaos_map")
    args = ap.parse_args()
    if args.differenced:
        TANGENTS["differenced"] = True
    workers = max(1, min(2, args.workers))
    data, figures = DATA, FIGURES
    if args.quick:
        data = figures = os.path.join(ROOT, "out", "integrability_quick")
        os.makedirs(data, exist_ok=True)
    t0 = time.perf_counter()
    if args.floor_scenes:
        os.makedirs(args.floor_scenes, exist_ok=True)
        for stem, _, _, s in floor_cases(300.0 if args.quick else 1000.0):
            with open(os.path.join(args.floor_scenes, stem + ".json"), "w") as f:
                f.write(s.to_json())
        return
    if args.floor_only:
        floor = sali_floor(args.quick)
        write(os.path.join(data, "integrability_sali_floor.csv"), floor)
        print_floor(floor)
        print(f"\nwall time {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        return
    if args.leveling:
        leveling(args.leveling, data, args.leveling_tol, args.leveling_tangents)
        print(f"\nwall time {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        return
    if args.degeneracy_only:
        degeneracy(args.quick, data)
        print(f"\nwall time {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        return
    if args.params_only:
        run_params(args.quick, data, figures)
        print(f"\nwall time {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        return
    if args.grids_only:
        summary = maps(args.quick, data, figures)
        write(os.path.join(data, "integrability_maps.csv"), summary)
        print_map_summary(summary)
        print_drift(affine_drift(args.quick))
        print(f"\nwall time {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        return
    if not args.maps_only:
        table(data)
    if not args.maps_only:
        degeneracy(args.quick, data)
    if not args.table_only:
        summary = maps(args.quick, data, figures)
        write(os.path.join(data, "integrability_maps.csv"), summary)
        drift = affine_drift(args.quick)
        floor = sali_floor(args.quick)
        write(os.path.join(data, "integrability_sali_floor.csv"), floor)
        sec_rows = sections(args.quick, workers, data, figures)
        kepler = kepler_steps(args.quick)
        print_maps(summary, drift, floor, sec_rows, kepler)
    if not args.table_only and not args.maps_only:
        run_params(args.quick, data, figures)
    print(f"\nwall time {time.perf_counter() - t0:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
