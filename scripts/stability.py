#!/usr/bin/env python3
"""Stability maps of docs/stability.md — ONE command:

    python3 scripts/stability.py            # full run (about 5–8 min on one core)
    python3 scripts/stability.py --quick    # smoke run (fewer settings, 1e5 long steps)

Steps:
1. `cargo run --profile measure -p framedyn-tests --example stability -- --out docs/data` writes
   docs/data/stability_*.csv (largest stable steps, the pole trajectory, H²
   escape against the closed form, the affine-body collapse and bounce, and
   the long-time runs over 1e7 steps).
2. scipy's solve_ivp (RK45, DOP853, LSODA) integrates the pole trajectory in
   the paper's coordinates with the numpy right-hand side of
   scripts/work_precision.py (imported, checked there against
   framedyn::coords), timed with time.thread_time(); written to
   docs/data/stability_pole_scipy.csv.
3. Charts into docs/figures/stability/ and the tables of docs/stability.md
   printed to stdout (`--summary-only` redraws and reprints from the CSVs).
"""

import argparse
import math
import os
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import work_precision as wp  # noqa: E402  (the numpy coordinate RHS, observable, CSV readers)

ROOT = os.path.dirname(HERE)
DATA = os.path.join(ROOT, "docs", "data")
FIGS = os.path.join(ROOT, "docs", "figures", "stability")

STYLE = {
    "lie_euler": ("tab:gray", "v", "-"), "heun": ("tab:olive", "^", "-"), "kutta3": ("tab:cyan", "<", "-"),
    "rkmk4": ("tab:blue", "o", "-"), "dopri5_fixed": ("tab:purple", "s", "-"), "butcher6": ("tab:green", "D", "-"),
    "dopri5": ("tab:red", "*", "-"), "implicit_midpoint": ("black", "h", "-"),
    "strang": ("tab:orange", "o", "--"), "yoshida4": ("gold", "^", "--"), "suzuki4": ("tab:brown", "v", "--"),
    "blanes_moan4": ("tab:red", "s", "--"), "yoshida6": ("tab:pink", "D", "--"), "blanes_moan6": ("darkred", "P", "--"),
    "blanes_moan_rkn4": ("orangered", "p", ":"), "blanes_moan_rkn6": ("maroon", "X", ":"),
    "coords_rk4": ("gray", "x", ":"), "coords_dopri5_fixed": ("dimgray", "+", ":"), "coords_dopri5": ("dimgray", "+", ":"),
    "scipy_RK45": ("tab:pink", "X", ":"), "scipy_DOP853": ("tab:brown", "X", ":"), "scipy_LSODA": ("darkgoldenrod", "X", ":"),
}


def style(name):
    for key in sorted(STYLE, key=len, reverse=True):
        if name.startswith(key):
            return STYLE[key]
    return (None, ".", "-")


def fnum(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


# ---------------------------------------------------------------------------
# scipy on the pole trajectory
# ---------------------------------------------------------------------------

class GaveUp(Exception):
    pass


def run_scipy_pole(quick):
    par = wp.read_kv(os.path.join(DATA, "stability_pole_problem.csv"))
    m, R, I, a, T = par["m"], par["R"], par["I"], par["a"], par["T"]
    y0 = np.array([par[f"q{i}"] for i in range(3)] + [par[f"v{i}"] for i in range(3)])
    ref = np.array([par[f"ref{i}"] for i in range(13)])
    base = wp.make_rhs(m, R, I, a)
    limit = 200_000
    rows = []
    tols = [10.0 ** -k for k in range(4, 13)]
    if quick:
        tols = tols[::4]
    for method in ("RK45", "DOP853", "LSODA"):
        for tol in tols:
            if method == "RK45" and tol < 1e-10:
                continue  # 5th order at 1e-11: minutes per run
            count = [0]

            def rhs(t, y):
                count[0] += 1
                if count[0] > limit:
                    raise GaveUp()
                return base(t, y)

            def go():
                count[0] = 0
                try:
                    return solve_ivp(rhs, (0.0, T), y0, method=method, rtol=tol, atol=tol)
                except GaveUp:
                    return None

            t0 = time.thread_time()
            sol = go()
            cpu = time.thread_time() - t0
            if cpu < 0.2 and sol is not None:
                cpu, sol = wp.timed(go)
            nfev = count[0]
            if sol is None:
                row = dict(method=f"scipy_{method}", tol=tol, error=math.nan, cpu_s=cpu, rhs_evals=nfev, steps=-1,
                           min_r=math.nan, failure=f"gave up after {limit} RHS evaluations")
            elif not sol.success:
                row = dict(method=f"scipy_{method}", tol=tol, error=math.nan, cpu_s=cpu, rhs_evals=sol.nfev,
                           steps=len(sol.t) - 1, min_r=float(np.min(np.abs(sol.y[0]))),
                           failure=f"{sol.message} (t = {sol.t[-1]:.6g})")
            else:
                err = float(np.max(np.abs(wp.observable(sol.y[:, -1], m, R, I) - ref)))
                row = dict(method=f"scipy_{method}", tol=tol, error=err, cpu_s=cpu, rhs_evals=sol.nfev,
                           steps=len(sol.t) - 1, min_r=float(np.min(np.abs(sol.y[0]))), failure="")
            rows.append(row)
            print(f"  scipy {method:6s} tol {tol:.0e}: error {row['error']:.2e}, {cpu * 1e3:9.2f} ms, "
                  f"nfev {row['rhs_evals']}, steps {row['steps']}, min r {row['min_r']:.2e} {row['failure']}", flush=True)
    path = os.path.join(DATA, "stability_pole_scipy.csv")
    with open(path, "w") as f:
        f.write("method,kind,setting,error,cpu_s,rhs_evals,steps,min_r,failure\n")
        for r in rows:
            f.write(f"{r['method']},tol,{r['tol']:e},{r['error']:e},{r['cpu_s']:e},{r['rhs_evals']},{r['steps']},"
                    f"{r['min_r']:e},{r['failure'].replace(',', ';')}\n")


# ---------------------------------------------------------------------------
# Charts
# ---------------------------------------------------------------------------

def plt_module():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def chart_steps(plt):
    rows = wp.read_rows(os.path.join(DATA, "stability_steps.csv"))
    sweeps = [("kappa", "elastic stiffness κ (S² affine body)"), ("spin_omega", "angular velocity ω (S² gyroscope)"),
              ("radius", "curvature radius R (S² gyroscope)")]
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2))
    for ax, (key, label) in zip(axes, sweeps):
        by = {}
        for r in rows:
            if r["sweep"] == key:
                by.setdefault(r["method"], []).append((fnum(r["param"]), fnum(r["h_max_stable"])))
        for name, pts in by.items():
            col, mk, ls = style(name)
            pts = [(x, y) for x, y in sorted(pts) if math.isfinite(y)]
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], ls, color=col, marker=mk, ms=4, lw=1.1, label=name)
        ax.set_xlabel(label)
        ax.set_ylabel("largest stable h (T = 10; grid capped at h = 1)")
        ax.grid(True, alpha=0.3)
    axes[1].legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "stability_steps.png"), dpi=100)
    plt.close(fig)


def chart_pole(plt):
    rows = wp.read_rows(os.path.join(DATA, "stability_pole.csv"))
    sc = os.path.join(DATA, "stability_pole_scipy.csv")
    if os.path.exists(sc):
        rows += wp.read_rows(sc)
    fig, ax = plt.subplots(figsize=(8, 5.5))
    by = {}
    for r in rows:
        e, c = fnum(r["error"]), fnum(r["cpu_s"])
        if math.isfinite(e) and e > 0 and c > 0 and not r.get("failure"):
            by.setdefault(r["method"], []).append((c, e))
    for name, pts in sorted(by.items()):
        pts.sort()
        col, mk, ls = style(name)
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], ls, color=col, marker=mk, ms=4, label=name)
    ax.set_xlabel("thread CPU time [s]")
    ax.set_ylabel("final error (max norm, ambient observable)")
    ax.set_title("S² gyroscope through the pole (T = 20): group methods vs the paper's coordinates", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "stability_pole.png"), dpi=100)
    plt.close(fig)


def chart_h2(plt):
    rows = wp.read_rows(os.path.join(DATA, "stability_h2.csv"))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4))
    by = {}
    for r in rows:
        by.setdefault(r["method"], []).append((fnum(r["t"]), fnum(r["distance"]), fnum(r["position_rel_error"]),
                                               fnum(r["relative_energy_error"]), fnum(r["defect"])))
    for name, pts in by.items():
        col, mk, ls = style(name)
        axes[0].semilogy([p[1] for p in pts], [max(p[2], 1e-18) for p in pts], ls, color=col, label=name)
        axes[1].semilogy([p[1] for p in pts], [max(p[3], 1e-18) for p in pts], ls, color=col, label=name)
        axes[2].semilogy([p[1] for p in pts], [max(p[4], 1e-18) for p in pts], ls, color=col, label=name)
    axes[0].set_ylabel("|x − x_exact| / |x_exact| (closed-form free motion)")
    axes[1].set_ylabel("|E(t) − E(0)| / E(0)")
    axes[2].set_ylabel("constraint defect of Λ ∈ SO⁺(1,2)")
    for ax in axes:
        ax.set_xlabel("geodesic distance from the origin r / R")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("free H² gyroscope escaping to infinity", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "stability_h2_escape.png"), dpi=100)
    plt.close(fig)


def chart_long(plt):
    rows = wp.read_rows(os.path.join(DATA, "stability_long.csv"))
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    by = {}
    for r in rows:
        by.setdefault(f"{r['problem']} {r['method']} h={r['h']}", []).append(
            (fnum(r["t"]), fnum(r["rel_energy_error"]), fnum(r["momentum_error"]), fnum(r["defect"])))
    for name, pts in by.items():
        col, mk, ls = style(name.split(" ")[1])
        if name.startswith("t2"):
            ls = "-."
        for k, ax in enumerate(axes):
            ax.loglog([p[0] for p in pts], [max(p[k + 1], 1e-18) for p in pts], ls, color=col, lw=1.2, label=name)
    axes[0].set_ylabel("|E(t) − E(0)| / |E(0)|")
    axes[1].set_ylabel("|p_φ(t) − p_φ(0)|")
    axes[2].set_ylabel("constraint defect")
    for ax in axes:
        ax.set_xlabel("t")
        ax.grid(True, which="major", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("long-time behaviour, fixed h = 0.05 (values at log-spaced steps, floored at 1e-18)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "stability_long.png"), dpi=100)
    plt.close(fig)


def chart_collapse(plt):
    rows = wp.read_rows(os.path.join(DATA, "stability_collapse_steps.csv"))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    by = {}
    for r in rows:
        by.setdefault(f"dopri5 tol {fnum(r['setting']):.0e}", []).append(
            (fnum(r["t_star_minus_t"]), fnum(r["h"]), fnum(r["det_rel_error"])))
    for name, pts in by.items():
        pts = [p for p in pts if p[0] > 0]
        axes[0].loglog([p[0] for p in pts], [p[1] for p in pts], ".-", ms=3, lw=0.8, label=name)
        axes[1].loglog([p[0] for p in pts], [max(p[2], 1e-18) for p in pts], ".-", ms=3, lw=0.8, label=name)
    for ax in axes:
        ax.set_xlabel("t* − t (time left to the collapse)")
        ax.invert_xaxis()
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("accepted step h")
    axes[1].set_ylabel("relative error of det ρ (exact: det(I + tρ̇₀))")
    fig.suptitle("adaptive DOPRI5 approaching the collapse of the affine body", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "stability_collapse.png"), dpi=100)
    plt.close(fig)


# ---------------------------------------------------------------------------
# Tables for docs/stability.md
# ---------------------------------------------------------------------------

def g3(x):
    if not math.isfinite(x):
        return "—"
    if x >= 1.0:
        return "≥ 1"
    return f"{x:.2g}" if x >= 0.01 else f"{x:.1e}"


def tables():
    rows = wp.read_rows(os.path.join(DATA, "stability_steps.csv"))
    for sweep in ("kappa", "spin_omega", "radius"):
        sel = [r for r in rows if r["sweep"] == sweep]
        methods = list(dict.fromkeys(r["method"] for r in sel))
        params = sorted({fnum(r["param"]) for r in sel})
        print(f"\n### largest stable h: {sweep}\n")
        print(f"| {sweep} | " + " | ".join(methods) + " |")
        print("|---" * (len(methods) + 1) + "|")
        for p in params:
            cells = [g3(fnum(r["h_max_stable"])) for m in methods for r in sel if r["method"] == m and fnum(r["param"]) == p]
            print(f"| {p:g} | " + " | ".join(cells) + " |")
        print("\nwhy the next larger grid step failed:")
        for p in params:
            reasons = {}
            for r in sel:
                if fnum(r["param"]) == p and r.get("failure_above"):
                    reasons.setdefault(r["failure_above"].split(" at t =")[0], []).append(r["method"])
            print(f"  {sweep} = {p:g}: " + "; ".join(f"{k}: {', '.join(v)}" for k, v in reasons.items()))

    print("\n### pole trajectory (error, CPU ms, RHS evaluations, failure)\n")
    rows = wp.read_rows(os.path.join(DATA, "stability_pole.csv"))
    sc = os.path.join(DATA, "stability_pole_scipy.csv")
    if os.path.exists(sc):
        rows += wp.read_rows(sc)
    print("| method | setting | error | CPU [ms] | RHS evals | steps | note |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        note = r.get("failure", "")
        if r.get("min_distance_to_pole"):
            note = (note + f" closest approach {fnum(r['min_distance_to_pole']):.1e} R").strip()
        if r.get("min_r"):
            note = (note + f" min r {fnum(r['min_r']):.1e}").strip()
        print(f"| {r['method']} | {r['kind']} {fnum(r['setting']):.1e} | {fnum(r['error']):.1e} | "
              f"{fnum(r['cpu_s']) * 1e3:.2f} | {r['rhs_evals']} | {r['steps']} | {note} |")

    print("\n### H² escape (last row per method)\n")
    last = {}
    worst = {}
    for r in wp.read_rows(os.path.join(DATA, "stability_h2.csv")):
        last[r["method"]] = r
        w = worst.setdefault(r["method"], [0.0, 0.0])
        w[0] = max(w[0], fnum(r["defect"]))
        w[1] = max(w[1], fnum(r["position_rel_error"]))
    print("| method | t | r | r exact | position rel. error at end | max position rel. error | max defect | rel. energy error |")
    print("|---|---|---|---|---|---|---|---|")
    for name, r in last.items():
        print(f"| {name} | {fnum(r['t']):.4g} | {fnum(r['distance']):.4f} | {fnum(r['distance_exact']):.4f} | "
              f"{fnum(r['position_rel_error']):.1e} | {worst[name][1]:.1e} | {worst[name][0]:.1e} | "
              f"{fnum(r['relative_energy_error']):.1e} |")

    print("\n### long-time runs\n")
    print("| problem | method | h | steps | T | CPU [s] | max rel. energy error | max p_φ error | max defect | failure |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in wp.read_rows(os.path.join(DATA, "stability_long_summary.csv")):
        print(f"| {r['problem']} | {r['method']} | {r['h']} | {int(r['steps']):.1e} | {int(r['steps']) * fnum(r['h']):.2g} | "
              f"{fnum(r['cpu_s']):.1f} | {fnum(r['max_rel_energy_error']):.1e} | {fnum(r['max_momentum_error']):.1e} | "
              f"{fnum(r['max_defect']):.1e} | {r['failure']} |")
    # energy error at decades of t
    rows = wp.read_rows(os.path.join(DATA, "stability_long.csv"))
    print("\nrelative energy error at t ≈ 10^k (first sample at or after):")
    by = {}
    for r in rows:
        by.setdefault((r["problem"], r["method"]), []).append((fnum(r["t"]), fnum(r["rel_energy_error"])))
    for key, pts in by.items():
        cells = []
        for k in range(0, 7):
            hit = next((e for t, e in pts if t >= 10 ** k), None)
            if hit is not None:
                cells.append(f"1e{k}: {hit:.1e}")
        print(f"  {key[0]} {key[1]}: " + ", ".join(cells))

    print("\n### collapse\n")
    print("| method | setting | outcome | in the step from t | h | t* − t | h‖Ω̂‖ there | steps | rejected | det ρ off by > 10 % from t | detail |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in wp.read_rows(os.path.join(DATA, "stability_collapse.csv")):
        print(f"| {r['method']} | {r['setting']} | {r['outcome']} | {fnum(r['t_stop']):.6f} | {fnum(r['h_stop']):.1e} | "
              f"{fnum(r['t_star_minus_t']):.1e} | {fnum(r['h_omega_last']):.2g} | {r['steps']} | {r['rejected']} | "
              f"{fnum(r['t_det_off_10pct']):.4f} | {r['detail']} |")
    p = os.path.join(DATA, "stability_bounce.csv")
    if os.path.exists(p):
        rows = wp.read_rows(p)
        methods = list(dict.fromkeys(r["method"] for r in rows))
        print("\n### bounce off the elastic barrier (largest stable h)\n")
        print("| compression rate | smallest stretch | DOPRI5 1e-10 steps / h_min | " + " | ".join(methods) + " |")
        print("|---" * (len(methods) + 3) + "|")
        for r in rows:
            if r["method"] == methods[0] and r.get("adaptive_failure"):
                print(f"(rate {r['rate']}: adaptive DOPRI5 stopped: {r['adaptive_failure']})")
        for c in dict.fromkeys(r["rate"] for r in rows):
            sel = [r for r in rows if r["rate"] == c]
            cells = [g3(fnum(r["h_max_stable"])) for m in methods for r in sel if r["method"] == m]
            print(f"| {c} | {fnum(sel[0]['min_stretch']):.2e} | {sel[0]['adaptive_steps']} / {fnum(sel[0]['adaptive_h_min']):.1e} | "
                  + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="smoke run: fewer settings, 1e5 long-time steps")
    ap.add_argument("--no-cargo", action="store_true", help="reuse docs/data/stability_*.csv of a previous cargo run")
    ap.add_argument("--no-scipy", action="store_true")
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--summary-only", action="store_true", help="only redraw the charts and print the tables")
    ap.add_argument("--out", default=None, help="data directory (default docs/data)")
    ap.add_argument("--figs", default=None, help="chart directory (default docs/figures/stability)")
    args = ap.parse_args()
    global DATA, FIGS
    DATA = os.path.abspath(args.out) if args.out else DATA
    FIGS = os.path.abspath(args.figs) if args.figs else FIGS
    os.makedirs(DATA, exist_ok=True)
    os.makedirs(FIGS, exist_ok=True)
    t0 = time.time()
    if not args.summary_only:
        if not args.no_cargo:
            cmd = ["cargo", "run", "--profile", "measure", "-p", "framedyn-tests", "--example", "stability", "--", "--out", DATA]
            if args.quick:
                cmd.append("--quick")
            print("+", " ".join(cmd), flush=True)
            subprocess.run(cmd, cwd=ROOT, check=True)
        if not args.no_scipy:
            run_scipy_pole(args.quick)
    if not args.no_plots:
        plt = plt_module()
        chart_steps(plt)
        chart_pole(plt)
        chart_h2(plt)
        chart_long(plt)
        chart_collapse(plt)
        print(f"charts: {FIGS}")
    tables()
    print(f"\nwall time {time.time() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
