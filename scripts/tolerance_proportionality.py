#!/usr/bin/env python3
"""Tolerance proportionality of framedyn's adaptive methods — ONE command:

    python3 scripts/tolerance_proportionality.py            # about 1 minute (release build)
    python3 scripts/tolerance_proportionality.py --quick    # tol 1e-6, 1e-9, 1e-12 only

For every problem below and tol = 1e-6 … 1e-12 (rtol = atol = tol) it runs
framedyn's DOP853 and DOPRI5 through the Python module and measures their
error against a reference at 161 equally spaced times (dense output), as

    error = max over the times and over the quantities q of ‖δq‖₂ / (1 + ‖q_ref‖₂)

with q the embedded position, the velocity, each body-frame vector and the
internal momenta (spin, hypermomentum): mixed absolute/relative, like
atol = rtol. The reference is framedyn's DOP853 with a *fixed* small step
(no step-size control involved); the script checks it against the run with
twice that step and, for the Kepler problems, against scipy's DOP853 at
rtol = atol = 1e-13 on the paper's coordinate equations (independent code).
Where the coordinates allow (the two Kepler problems, in polar coordinates
about the centre; on S² also in embedding coordinates) scipy's DOP853 and
RK45 run at the same tolerances on the same problem, measured in position
and velocity. Every framedyn run asks for the global-error estimate
(`global_error=True`) and the script compares it with the measured error.
Each framedyn method runs twice, plain and with the energy projection
(`project="energy"`, the rows "+ energy projection"); the script prints
what the projection gains (error / tol) and costs at equal error
(vector-field evaluations, energy evaluations per step, wall time — the
last from the runs' own clocks, noisy at a few milliseconds) and, on the
Kepler problems, at how many tolerances it is further from tol than
scipy. `--no-projection` leaves those runs out (builds before `project`).

Writes docs/data/tolerance_proportionality.csv (one row per problem, solver
and tol) and docs/figures/performance/tolerance_proportionality.png, and
prints the table of docs/performance.md ("Tolerance proportionality").
`--out DIR` writes the CSV to DIR instead (e.g. to compare builds);
`--compare OLD.csv` prints, for every problem and method, the ratio of
vector-field evaluations (new / old) at equal error, interpolated in
log-log between the tolerances (work-precision at equal error);
`--compare-wp OLD_wp_rust.csv NEW_wp_rust.csv` does the same for the
adaptive DOPRI5 rows of two runs of scripts/work_precision.py (final error
at T, evaluations and thread-CPU time), and runs nothing else;
`--diagnose` runs nothing else either but reads the CSV (docs/data or
--out) and, on the Kepler problems, prints framedyn against scipy at each
tol (error / tol and evaluations), the error ratio at equal evaluations,
and for one tol (`--diagnose-tol`, default 1e-10) the energy error after
each pericentre passage, the steps through the passage and the rejections
(why framedyn's DOP853 lands further from tol than scipy's in polar
coordinates; docs/performance.md, "Kepler passages against scipy").

Run it from the repository root with a Python that has numpy, scipy,
matplotlib and a release build of framedyn (`pip install .`).
"""

import argparse
import csv
import math
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

import framedyn as fd

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "docs", "data")
FIGS = os.path.join(ROOT, "docs", "figures", "performance")
SAMPLES = 161
NO_ESTIMATE = False  # --no-estimate: for a build without global_error
PROJECTIONS = (False, True)  # --no-projection: (False,), for a build without `project`
PROJECTED = " + energy projection"

# name -> (scene keywords, t_end, reference step, amplifying?, scipy kind or None)
PROBLEMS = {
    # The reference problems of the test suite that the Python module runs.
    "s2_gyro": (dict(manifold={"kind": "S2", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
                     potential={"kind": "cosine", "alpha_hat": 0.0, "beta_hat": -0.3},
                     r=0.6, phi=0.0, r_dot=0.3, phi_dot=0.8, spin=0.2), 10.0, 2e-3, False, None),
    "h2_gyro": (dict(manifold={"kind": "H2", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
                     potential={"kind": "cosine", "alpha_hat": 0.0, "beta_hat": 0.3},
                     r=0.6, phi=0.0, r_dot=0.0, phi_dot=0.8, spin=0.2), 10.0, 2e-3, False, None),
    "t2_gyro": (dict(manifold={"kind": "T2", "L": 2.0, "R": 0.7}, body={"kind": "gyroscope", "inertia": 0.3},
                     potential={"kind": "cosine", "alpha_hat": 0.0, "beta_hat": 0.8},
                     theta=0.3, phi=0.0, theta_dot=0.5, phi_dot=0.4, spin=0.3), 10.0, 2e-3, False, None),
    "s3_gyro": (dict(manifold={"kind": "S3", "radius": 1.0}, body={"kind": "gyroscope", "J": [[0.2, 0, 0], [0, 0.35, 0], [0, 0, 0.5]]},
                     potential={"kind": "cosine", "alpha_hat": 0.0, "beta_hat": 0.5},
                     r1=0.3, r2=0.2, r3=0.1, r1_dot=0.3, r2_dot=-0.2, r3_dot=0.4, orientation=[0.1, 0.2, 0.3], omega=[1.0, 0.5, -0.3]), 10.0, 2e-3, False, None),
    "s2_affine": (dict(manifold={"kind": "S2", "radius": 1.0}, body={"kind": "affine", "mass": 1.0, "inertia": 0.1},
                       potential={"kind": "elastic", "kappa": 1.0},
                       r=0.7, phi=0.0, r_dot=0.0, phi_dot=0.6, rho=[[1.1, 0.0], [0.0, 0.9]], rho_dot=[[0.0, 0.2], [-0.1, 0.0]]),
                  10.0, 1e-3, False, None),
    "h2_affine": (dict(manifold={"kind": "H2", "radius": 1.0}, body={"kind": "affine", "mass": 1.0, "inertia": 0.1},
                       potential={"kind": "elastic", "kappa": 1.0},
                       r=0.5, phi=0.0, r_dot=0.2, phi_dot=0.5, rho=[[1.1, 0.0], [0.0, 0.9]], rho_dot=[[0.0, 0.2], [-0.1, 0.0]]),
                  10.0, 1e-3, False, None),
    # Harder problems.
    "s2_pole": (dict(manifold={"kind": "S2", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
                          potential={"kind": "cosine", "alpha_hat": 0.0, "beta_hat": -0.3},
                     r=0.6, phi=0.0, r_dot=-1.0, phi_dot=1e-7, alpha=0.3, spin=0.0), 4.0, 1e-3, False, None),
    "h2_escape_r17": (dict(manifold={"kind": "H2", "radius": 1.0}, body={"kind": "point"},
                           potential={"kind": "oscillator", "kappa": 1.0},
                           r=0.5, phi=0.0, r_dot=1.2, phi_dot=0.1), 20.0, 2e-3, False, None),
    "s2_affine_k100": (dict(manifold={"kind": "S2", "radius": 1.0}, body={"kind": "affine", "mass": 1.0, "inertia": 0.1},
                            potential={"kind": "elastic", "kappa": 100.0},
                            r=0.7, phi=0.0, r_dot=0.0, phi_dot=0.6, rho=[[1.1, 0.0], [0.0, 0.9]], rho_dot=[[0.0, 0.2], [-0.1, 0.0]]),
                       4.0, 1e-4, False, None),
    # Kepler-type pericentre passages (sensitive flows).
    "s2_kepler_point": (dict(manifold={"kind": "S2", "radius": 1.0}, body={"kind": "point", "mass": 1.0},
                             potential={"kind": "kepler", "alpha": 1.0},
                             r=1.0, phi=0.0, r_dot=0.0, phi_dot=0.3), 8.0, 5e-5, True, "S2"),
    "h2_kepler_point": (dict(manifold={"kind": "H2", "radius": 1.0}, body={"kind": "point", "mass": 1.0},
                             potential={"kind": "kepler", "alpha": 1.0},
                             r=1.0, phi=0.0, r_dot=0.0, phi_dot=0.3), 8.0, 5e-5, True, "H2"),
    "h2_kepler_gyro": (dict(manifold={"kind": "H2", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
                            potential={"kind": "kepler", "alpha": 1.0},
                            r=1.0, phi=0.0, r_dot=0.0, phi_dot=0.3, spin=0.1), 8.0, 1e-4, True, None),
}


def groups(sol, position_velocity_only=False):
    """The measured vectors of a solution, each an (n, k) array."""
    gs = [sol.position, sol.velocity]
    if position_velocity_only:
        return gs
    try:
        f = sol.frame
    except Exception:  # a point has no frame
        f = None
    if f is not None:
        gs.extend(f[:, a, :] for a in range(f.shape[1]))
    m = sol.momenta
    if m:
        n = len(sol.t)
        gs.append(np.hstack([np.asarray(m[k]).reshape(n, -1) for k in m]))
    return gs


def error(gs, ref_gs):
    """max over times and quantities of ‖δ‖₂/(1 + ‖ref‖₂); and at the last time."""
    per = np.max([np.linalg.norm(a - b, axis=1) / (1.0 + np.linalg.norm(b, axis=1)) for a, b in zip(gs, ref_gs)], axis=0)
    return float(per.max()), float(per[-1])


def scene(kw, t_end, **method):
    return fd.Scene(**kw, t_end=t_end, samples=SAMPLES, max_steps=10**8, **method)


# ---------------------------------------------------------------------------
# The Kepler problem of a point on S² / H² in polar coordinates about the
# centre, V = −(α/R) cot(r/R) (coth on H²):
#   m r̈ = m R s c φ̇² − α/(R² s²),   φ̈ = −2 c ṙ φ̇ /(R s)
# with s, c = sin, cos (sinh, cosh on H²) of r/R.
# ---------------------------------------------------------------------------

def kepler_polar(kind, m, R, alpha):
    hyp = kind == "H2"

    def rhs(t, y):
        r, _ph, rd, phd = y
        th = r / R
        s, c = (math.sinh(th), math.cosh(th)) if hyp else (math.sin(th), math.cos(th))
        return [rd, phd, R * s * c * phd * phd - alpha / (m * R * R * s * s), -2.0 * c / (R * s) * rd * phd]

    def ambient(Y):
        r, ph, rd, phd = Y
        th = r / R
        s, c = (np.sinh(th), np.cosh(th)) if hyp else (np.sin(th), np.cos(th))
        ds, dc = (c, s) if hyp else (c, -s)
        x = R * np.array([s * np.cos(ph), s * np.sin(ph), c])
        v = np.array([ds * rd * np.cos(ph) - R * s * np.sin(ph) * phd, ds * rd * np.sin(ph) + R * s * np.cos(ph) * phd, dc * rd])
        return [x.T, v.T]

    return rhs, ambient


def kepler_s2_cartesian(m, R, alpha):
    """The same S² problem in embedding coordinates (x, ẋ) ∈ ℝ⁶:
    ẍ = P(−∇V/m) − |ẋ|² x/R², V = −(α/R) z/√(x² + y²), P the tangent projection."""

    def rhs(t, u):
        x, v = u[:3], u[3:]
        rho = math.hypot(x[0], x[1])
        g = np.array([alpha / R * x[2] * x[0] / rho**3, alpha / R * x[2] * x[1] / rho**3, -alpha / R / rho])
        f = -g / m
        f = f - x * np.dot(x, f) / R**2
        return np.concatenate([v, f - np.dot(v, v) / R**2 * x])

    return rhs


def scipy_runs(name, kw, t_end, ts, ref_pv, tols, rows):
    kind = PROBLEMS[name][4]
    m, R, alpha = kw["body"].get("mass", 1.0), kw["manifold"]["radius"], kw["potential"]["alpha"]
    rhs, ambient = kepler_polar(kind, m, R, alpha)
    y0 = [kw["r"], kw["phi"], kw["r_dot"], kw["phi_dot"]]
    # Independent check of the fixed-step framedyn reference.
    chk = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-13, t_eval=ts, dense_output=True)
    diff, _ = error(ambient(chk.y), ref_pv)
    r_min = chk.sol(np.linspace(0.0, t_end, 400001))[0].min() / R
    print(f"  {name}: framedyn fixed-step reference vs scipy DOP853 (tol 1e-13, polar coordinates): {diff:.1e}; pericentre r_min = {r_min:.3f} R")
    variants = [("polar", rhs, y0, lambda Y: ambient(Y))]
    if kind == "S2":
        x0, v0 = ambient(np.array(y0).reshape(4, 1))
        variants.append(("embedding", kepler_s2_cartesian(m, R, alpha), np.concatenate([x0[0], v0[0]]), lambda Y: [Y[:3].T, Y[3:].T]))
    for coords, f, u0, obs in variants:
        for method in ("DOP853", "RK45"):
            for tol in tols:
                out = solve_ivp(f, (0.0, t_end), u0, method=method, rtol=tol, atol=tol, t_eval=ts)
                e, e_last = error(obs(out.y), ref_pv)
                rows.append(dict(problem=name, solver=f"scipy {method} ({coords})", tol=tol, max_error=e, final_error=e_last,
                                 max_over_tol=e / tol, rhs_evals=out.nfev, steps="", estimate="", estimate_over_error="",
                                 estimate_final_over_error="", estimate_rhs_evals="", energy_evals="", projection_skipped="",
                                 wall_time=""))


def measure(names, tols):
    rows = []
    summary = {}
    for name in names:
        kw, t_end, h_ref, amplifying, scipy_kind = PROBLEMS[name]
        ts = np.linspace(0.0, t_end, SAMPLES)
        ref = fd.solve(scene(kw, t_end, method="dop853", h=h_ref))
        coarse = fd.solve(scene(kw, t_end, method="dop853", h=2 * h_ref))
        ref_gs = groups(ref)
        ref_err, _ = error(groups(coarse), ref_gs)
        x = ref.position
        # Distance from the chart pole / from the Kepler centre (0, 0, R) in units of R.
        dist = np.arctan2(np.hypot(x[:, 0], x[:, 1]), x[:, 2]) if kw["manifold"]["kind"] == "S2" else np.arccosh(np.maximum(x[:, 2], 1.0))
        note = f"r ∈ [{dist.min():.3g}, {dist.max():.3g}] R (at the samples)" if kw["manifold"]["kind"] in ("S2", "H2") else ""
        if name.startswith("s2_pole"):
            # The closest approach to the pole: below any sampling's
            # resolution, so from the conserved p_φ = m sin²(r/R) R² φ̇ (the
            # spin is 0): r_min ≈ |p_φ|/(m |v|) at the pole (sin r ≈ r).
            i = int(np.argmin(dist))
            p_phi = abs(float(ref.momentum_maps["p_phi"][0]))
            note += f"; closest approach to the pole ≈ |p_φ|/(m|v|) = {p_phi / np.linalg.norm(ref.velocity[i]):.1e} R"
        print(f"{name}: reference h = {h_ref} differs from h = {2 * h_ref} by {ref_err:.1e}; {note}")
        # With 2h the error of an 8th-order method is 2⁸ times that with h:
        # the reference's own error is about ref_err/255 (the Kepler runs
        # are checked against scipy below as well).
        assert ref_err < (1e-10 if amplifying else 1e-12), f"{name}: reference not converged"
        for projection in PROJECTIONS:
            for method in ("dop853", "dopri5"):
                for tol in tols:
                    extra = {} if NO_ESTIMATE else {"global_error": True}
                    if projection:
                        extra["project"] = "energy"
                    sol = fd.solve(scene(kw, t_end, method=method, rtol=tol, atol=tol, **extra))
                    e, e_last = error(groups(sol), ref_gs)
                    est = sol.stats.get("global_error", float("nan"))
                    rows.append(dict(problem=name, solver=f"framedyn {method}{PROJECTED if projection else ''}", tol=tol, max_error=e,
                                     final_error=e_last, max_over_tol=e / tol,
                                     rhs_evals=sol.stats["rhs_evals"], steps=sol.stats["steps"], estimate=est, estimate_over_error=est / e,
                                     estimate_final_over_error=sol.stats.get("global_error_final", float("nan")) / e_last,
                                     estimate_rhs_evals=sol.stats.get("global_error_rhs_evals", float("nan")),
                                     energy_evals=sol.stats.get("energy_evals", 0), projection_skipped=sol.stats.get("projection_skipped", 0),
                                     wall_time=sol.stats["wall_time"]))
        if scipy_kind:
            scipy_runs(name, kw, t_end, ts, groups(ref, position_velocity_only=True), tols, rows)
        summary[name] = (amplifying, note)
    return rows, summary


def slope(rows):
    x = np.log([r["tol"] for r in rows])
    y = np.log([r["max_error"] for r in rows])
    return float(np.polyfit(x, y, 1)[0])


def table(rows, summary):
    print()
    print("| problem | solver | max error / tol over tol = 1e-6 … 1e-12 | slope | global-error estimate / error (max and final) |")
    print("|---|---|---|---|---|")
    for name, (amplifying, note) in summary.items():
        for solver in sorted({r["solver"] for r in rows if r["problem"] == name}, key=lambda s: (not s.startswith("framedyn"), s)):
            rs = [r for r in rows if r["problem"] == name and r["solver"] == solver]
            q = [r["max_over_tol"] for r in rs]
            est = [r[k] for r in rs for k in ("estimate_over_error", "estimate_final_over_error")
                   if r[k] != "" and not math.isnan(r[k])]
            est_s = f"{min(est):.2f} – {max(est):.2f}" if est else "—"
            label = f"{name}{' (amplifying)' if amplifying else ''}"
            print(f"| {label} | {solver} | {min(q):.3g} – {max(q):.3g} | {slope(rs):.2f} | {est_s} |")


def chart(rows, summary, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [(method, p) for p in PROJECTIONS for method in ("dop853", "dopri5")]
    fig, axes = plt.subplots(len(PROJECTIONS), 2, figsize=(13, 5.5 * len(PROJECTIONS)), sharey=True, squeeze=False)
    for ax, (method, projected) in zip(axes.flat, panels):
        solver = f"framedyn {method}{PROJECTED if projected else ''}"
        for name, (amplifying, _) in summary.items():
            rs = [r for r in rows if r["problem"] == name and r["solver"] == solver]
            ax.loglog([r["tol"] for r in rs], [r["max_over_tol"] for r in rs], "o-" if not amplifying else "s--", label=name, ms=4)
        sm = "DOP853" if method == "dop853" else "RK45"
        for name, (amplifying, _) in summary.items():
            rs = [r for r in rows if r["problem"] == name and r["solver"] == f"scipy {sm} (polar)"]
            if rs:
                ax.loglog([r["tol"] for r in rs], [r["max_over_tol"] for r in rs], "x:", color="grey", label=f"{name}: scipy {sm} (polar)")
        ax.axhline(20 if method == "dop853" else 50, color="k", lw=0.8, ls="--")
        ax.set_xlabel("tol (rtol = atol)")
        ax.set_title(f"{solver}: max error / tol", fontsize=10)
        ax.invert_xaxis()
        ax.grid(True, which="major", alpha=0.3)
    for row in axes:
        row[0].set_ylabel("max error / tol")
    axes[0][1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def estimate_cost(rows):
    ratios = {}
    for r in rows:
        if r["solver"].startswith("framedyn") and r["estimate_rhs_evals"] != "" and not math.isnan(r["estimate_rhs_evals"]):
            ratios.setdefault(r["solver"], []).append(r["estimate_rhs_evals"] / r["rhs_evals"])
    for solver, q in ratios.items():
        print(f"global-error estimate, {solver}: the reference run costs {min(q):.2f} – {max(q):.2f} × the run (median {np.median(q):.2f})")


def projection_report(rows, summary):
    """The energy projection against the plain method: error / tol, cost at
    equal error, and (Kepler problems) against scipy at each tol."""
    print("\nenergy projection: max error / tol (plain -> projected); vector-field evaluations, energy evaluations")
    print("per step and wall time of the projected run at equal max error, projected / plain (log-log interpolation):")
    for name in summary:
        for method in ("dop853", "dopri5"):
            plain = [r for r in rows if r["problem"] == name and r["solver"] == f"framedyn {method}"]
            proj = [r for r in rows if r["problem"] == name and r["solver"] == f"framedyn {method}{PROJECTED}"]
            if not plain or not proj:
                continue
            q0, q1 = [r["max_over_tol"] for r in plain], [r["max_over_tol"] for r in proj]
            old = [(r["max_error"], r["rhs_evals"], r["wall_time"]) for r in plain]
            new = [(r["max_error"], r["rhs_evals"], r["wall_time"]) for r in proj]
            ratios = interpolated_ratios(old, new)
            per_step = [r["energy_evals"] / max(r["steps"], 1) for r in proj]
            skipped = sum(int(r["projection_skipped"]) for r in proj)
            cost = (f"evals {min(x[0] for x in ratios):.2f} – {max(x[0] for x in ratios):.2f}, "
                    f"wall {min(x[1] for x in ratios):.2f} – {max(x[1] for x in ratios):.2f} ({len(ratios)} points)") if ratios else "no common error range"
            print(f"  {name:18s} {method}: {min(q0):.3g} – {max(q0):.3g} -> {min(q1):.3g} – {max(q1):.3g}; "
                  f"{min(per_step):.1f} – {max(per_step):.1f} energy evals/step; skipped {skipped}; at equal error: {cost}")
    for name in summary:
        for method, refs in (("dop853", ("DOP853",)), ("dopri5", ("RK45",))):
            proj = {r["tol"]: r["max_over_tol"] for r in rows if r["problem"] == name and r["solver"] == f"framedyn {method}{PROJECTED}"}
            for ref in refs:
                for coords in ("polar", "embedding"):
                    sc = {r["tol"]: r["max_over_tol"] for r in rows if r["problem"] == name and r["solver"] == f"scipy {ref} ({coords})"}
                    common = sorted(set(proj) & set(sc))
                    if not common:
                        continue
                    worse = [t for t in common if proj[t] > sc[t]]
                    ratio = [proj[t] / sc[t] for t in common]
                    print(f"  {name:18s} {method} + projection vs scipy {ref} ({coords}): further from tol at {len(worse)} of {len(common)} "
                          f"tolerances; error ratio {min(ratio):.3g} – {max(ratio):.3g}")


def compare(rows, old_path):
    with open(old_path) as f:
        old = list(csv.DictReader(f))
    print("\nvector-field evaluations at equal max error, new / old (log-log interpolation between tolerances):")
    for name in dict.fromkeys(r["problem"] for r in rows):
        for method in ("framedyn dop853", "framedyn dopri5"):
            new = [(r["max_error"], r["rhs_evals"]) for r in rows if r["problem"] == name and r["solver"] == method]
            prev = [(float(r["max_error"]), float(r["rhs_evals"])) for r in old if r["problem"] == name and r["solver"] == method]
            if not new or not prev:
                continue
            ratios = []
            pe, pc = np.log([p[0] for p in prev]), np.log([p[1] for p in prev])
            order = np.argsort(pe)
            for e, c in new:
                le = math.log(e)
                if pe.min() <= le <= pe.max():
                    ratios.append(c / math.exp(np.interp(le, pe[order], pc[order])))
            if ratios:
                print(f"  {name:18s} {method}: {min(ratios):.2f} – {max(ratios):.2f} (median {np.median(ratios):.2f}, {len(ratios)} points)")


def interpolated_ratios(old, new):
    """old, new: lists of (error, cost...) tuples; for each new point inside
    the old error range, new cost / old cost at equal error (log-log)."""
    oe = np.log([o[0] for o in old])
    order = np.argsort(oe)
    out = []
    for point in new:
        le = math.log(point[0])
        if oe[order[0]] <= le <= oe[order[-1]]:
            out.append([c / math.exp(np.interp(le, oe[order], np.log([o[k] for o in old])[order]))
                        for k, c in enumerate(point) if k > 0])
    return out


def compare_wp(old_path, new_path):
    def load(p):
        with open(p) as f:
            return [r for r in csv.DictReader(f) if r["method"] == "dopri5" and r["kind"] == "tol" and not r["failure"]
                    and float(r["error"]) > 0]
    old, new = load(old_path), load(new_path)
    print(f"adaptive DOPRI5 of scripts/work_precision.py at equal final error, {new_path} / {old_path}:")
    for prob in sorted({r["problem"] for r in new}):
        pick = lambda rows: [(float(r["error"]), float(r["rhs_evals"]), float(r["cpu_s"])) for r in rows if r["problem"] == prob]
        q = interpolated_ratios(pick(old), pick(new))
        if q:
            rhs, cpu = np.array(q).T
            print(f"  {prob:12s} evaluations median {np.median(rhs):.2f} [{rhs.min():.2f}, {rhs.max():.2f}], "
                  f"thread-CPU median {np.median(cpu):.2f} [{cpu.min():.2f}, {cpu.max():.2f}] ({len(q)} points)")


def kepler_energy(kind, m, R, alpha, Y):
    r, _ph, rd, phd = Y
    th = r / R
    s, c = (np.sinh(th), np.cosh(th)) if kind == "H2" else (np.sin(th), np.cos(th))
    return 0.5 * m * (rd**2 + R * R * s * s * phd**2) - alpha / R * c / s


def at_equal_work(points, evals):
    """log-log interpolation of (evals, error) points at `evals` (None outside)."""
    pts = sorted(points)
    xs, ys = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    le = math.log(evals)
    return math.exp(np.interp(le, xs, ys)) if xs[0] <= le <= xs[-1] else None


def diagnose(csv_path, tol):
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    pairs = (("dop853", "DOP853"), ("dopri5", "RK45"))
    print(f"from {csv_path}: framedyn against scipy in polar coordinates, error / tol (rhs evaluations)")
    for name in ("s2_kepler_point", "h2_kepler_point", "h2_kepler_gyro"):
        if PROBLEMS[name][4] is None:
            print(f"  {name}: no scipy formulation in this script (the spin couples to the orbit), no head-to-head")
            continue
        for fm, sm in pairs:
            fr = [r for r in rows if r["problem"] == name and r["solver"] == f"framedyn {fm}"]
            for coords in ("polar", "embedding"):
                sr = {r["tol"]: r for r in rows if r["problem"] == name and r["solver"] == f"scipy {sm} ({coords})"}
                if not sr:
                    continue
                cells, worse, eq = [], 0, []
                for r in fr:
                    q = sr.get(r["tol"])
                    if q is None:
                        continue
                    a, b = float(r["max_over_tol"]), float(q["max_over_tol"])
                    worse += a > b
                    cells.append(f"{float(r['tol']):.0e} {a:.0f}/{b:.0f}")
                    e = at_equal_work([(float(x["rhs_evals"]), float(x["max_error"])) for x in sr.values()], float(r["rhs_evals"]))
                    if e is not None:
                        eq.append(float(r["max_error"]) / e)
                eq_s = f"; error at equal evaluations framedyn / scipy {min(eq):.2g} – {max(eq):.2g} (median {np.median(eq):.2g})" if eq else ""
                print(f"  {name} {fm} vs scipy {sm} ({coords}): further from tol at {worse} of {len(cells)} tols{eq_s}")
                print("     " + " | ".join(cells))
    print(f"\nat tol {tol:g}: energy error |E − E0| after each pericentre passage, steps through it, rejections")
    for name in ("s2_kepler_point", "h2_kepler_point"):
        kw, t_end, _h, _a, kind = PROBLEMS[name]
        m, R, alpha = kw["body"].get("mass", 1.0), kw["manifold"]["radius"], kw["potential"]["alpha"]
        rhs, _amb = kepler_polar(kind, m, R, alpha)
        y0 = [kw["r"], kw["phi"], kw["r_dot"], kw["phi_dot"]]
        dense = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-13, dense_output=True)
        tt = np.linspace(0.0, t_end, 80001)
        rr = dense.sol(tt)[0]
        peri = [tt[i] for i in range(1, len(tt) - 1) if rr[i] < rr[i - 1] and rr[i] <= rr[i + 1]]
        r_min = rr.min()
        # the passage: r < 3 r_min; the energy is read halfway to the next apocentre
        after = [p + 0.5 * (peri[1] - peri[0] if len(peri) > 1 else 1.0) for p in peri]
        after = [a for a in after if a < t_end]
        print(f"  {name}: pericentres at t = {', '.join(f'{p:.3f}' for p in peri)} (r_min = {r_min:.3f} R); energy read at t = {', '.join(f'{a:.2f}' for a in after)}")
        for fm, sm in pairs:
            # every step saved: no dense output, so the evaluations compare with scipy's
            sol = fd.solve(fd.Scene(**kw, t_end=t_end, every=1, max_steps=10**8, method=fm, rtol=tol, atol=tol))
            t = np.asarray(sol.t)
            x = sol.position
            dist = np.arctan2(np.hypot(x[:, 0], x[:, 1]), x[:, 2]) if kind == "S2" else np.arccosh(np.maximum(x[:, 2], 1.0))
            E = np.asarray(sol.energy)
            fe = [abs(np.interp(a, t, E) - E[0]) for a in after]
            h = np.diff(t)
            inside = dist[:-1] < 3 * r_min
            # steps and evaluations from a run without dense output (scipy's
            # DOP853 spends 3 more evaluations per step on it), energies from one with
            out = solve_ivp(rhs, (0.0, t_end), y0, method=sm, rtol=tol, atol=tol)
            out2 = solve_ivp(rhs, (0.0, t_end), y0, method=sm, rtol=tol, atol=tol, dense_output=True)
            se = np.abs(kepler_energy(kind, m, R, alpha, out2.sol(np.array(after))) - kepler_energy(kind, m, R, alpha, np.array(y0)))
            st, sr_ = out.t, out.y[0]
            sh = np.diff(st)
            sin_ = sr_[:-1] < 3 * r_min
            # attempts = (evaluations − 2 for the first step) / new evaluations per step (FSAL)
            per = 12 if sm == "DOP853" else 6
            s_rej = round((out.nfev - 2) / per) - (len(st) - 1)
            print(f"    framedyn {fm}: energy error {', '.join(f'{v:.2e}' for v in fe)}; {int(inside.sum())} steps with r < 3 r_min, "
                  f"smallest {h.min():.2e}; {sol.stats['steps']} steps, {sol.stats['rejected']} rejected, {sol.stats['rhs_evals']} evaluations")
            print(f"    scipy {sm} (polar): energy error {', '.join(f'{v:.2e}' for v in se)}; {int(sin_.sum())} steps with r < 3 r_min, "
                  f"smallest {sh.min():.2e}; {len(st) - 1} steps, about {s_rej} rejected, {out.nfev} evaluations")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="tol 1e-6, 1e-9, 1e-12 only")
    ap.add_argument("--out", default=DATA, help="directory of the CSV (default docs/data)")
    ap.add_argument("--problems", default=",".join(PROBLEMS), help="comma-separated subset")
    ap.add_argument("--compare", help="an earlier CSV: work at equal error, new / old")
    ap.add_argument("--no-chart", action="store_true")
    ap.add_argument("--no-estimate", action="store_true", help="do not ask for the global-error estimate (builds before it existed)")
    ap.add_argument("--no-projection", action="store_true", help="no energy-projection runs (builds before `project` existed)")
    ap.add_argument("--compare-wp", nargs=2, metavar=("OLD", "NEW"), help="two wp_rust.csv of scripts/work_precision.py")
    ap.add_argument("--diagnose", action="store_true", help="Kepler rows against scipy, from the CSV; runs nothing else")
    ap.add_argument("--diagnose-tol", type=float, default=1e-10)
    args = ap.parse_args()
    if args.diagnose:
        diagnose(os.path.join(args.out, "tolerance_proportionality.csv"), args.diagnose_tol)
        return 0
    if args.compare_wp:
        compare_wp(*args.compare_wp)
        return 0
    global NO_ESTIMATE, PROJECTIONS
    NO_ESTIMATE = args.no_estimate
    if args.no_projection:
        PROJECTIONS = (False,)
    tols = [1e-6, 1e-9, 1e-12] if args.quick else [10.0**-k for k in range(6, 13)]
    names = args.problems.split(",")
    rows, summary = measure(names, tols)
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "tolerance_proportionality.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")
    table(rows, summary)
    estimate_cost(rows)
    projection_report(rows, summary)
    if not args.no_chart:
        os.makedirs(FIGS, exist_ok=True)
        chart(rows, summary, os.path.join(FIGS, "tolerance_proportionality.png"))
    if args.compare:
        compare(rows, args.compare)
    return 0


if __name__ == "__main__":
    sys.exit(main())
