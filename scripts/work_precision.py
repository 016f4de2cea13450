#!/usr/bin/env python3
"""Work-precision charts of framedyn against scipy — ONE command:

    python3 scripts/work_precision.py            # full run (several minutes)
    python3 scripts/work_precision.py --quick    # smoke run (T = 20, fewer settings)

Steps:
1. `cargo run --profile measure --example work_precision -- --out docs/data` writes the
   Rust results (wp_rust.csv), the references (references.csv), the S²
   gyroscope in the paper's coordinates (s2_problem.csv) and sample values of
   the Rust coordinate form (s2_samples.csv), and defect/energy time series
   (defect_series.csv).
2. The numpy right-hand side below — the Euler–Lagrange equations of the
   Lagrangian (a52) specialised to the S² gyroscope (paper §5.1, (a91)) with
   V = a cos(r/R) — and the map to the ambient observable are checked against
   those samples (relative agreement <= 1e-12) before anything is timed.
3. scipy's solve_ivp (DOP853, RK45, LSODA; numpy RHS, and numba RHS if numba
   imports) integrates the same problem over the same T, timed with
   time.thread_time() (minimum over repeats), errors against the same
   reference observable; written to docs/data/wp_scipy.csv.
4. PNG charts into docs/figures/performance/.

Run it from the repository root with a Python that has numpy, scipy and
matplotlib (e.g. `python3 -m venv .venv && .venv/bin/pip install numpy scipy
matplotlib numba`, then `.venv/bin/python scripts/work_precision.py`).
"""

import argparse
import csv
import math
import os
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "docs", "data")
FIGS = os.path.join(ROOT, "docs", "figures", "performance")


# ---------------------------------------------------------------------------
# The S² gyroscope in the paper's coordinates (q = (r, φ, ψ))
# ---------------------------------------------------------------------------
#
# L = m/2 (ṙ² + R² sin²(r/R) φ̇²) + I/2 ω² − a cos(r/R),  ω = ψ̇ + cos(r/R) φ̇  (a52), (a91)
#
# ψ cyclic: I ω = p_ψ const  ⇒ ψ̈ = (sin/R) ṙ φ̇ − cos φ̈
# φ cyclic: d/dt (m R² sin² φ̇ + I cos ω) = 0
#           ⇒ φ̈ = (I (sin/R) ṙ ω − 2 m R sin cos ṙ φ̇) / (m R² sin²)
# r:        m r̈ = m R sin cos φ̇² − I ω (sin/R) φ̇ + (a/R) sin


def make_rhs(m, R, I, a):
    def rhs(t, y):
        r, _phi, _psi, rd, phd, psd = y
        th = r / R
        s, c = math.sin(th), math.cos(th)
        om = psd + c * phd
        rdd = R * s * c * phd * phd - (I / m) * om * (s / R) * phd + (a / (m * R)) * s
        phdd = (I * (s / R) * rd * om - 2.0 * m * R * s * c * rd * phd) / (m * R * R * s * s)
        psdd = (s / R) * rd * phd - c * phdd
        return np.array([rd, phd, psd, rdd, phdd, psdd])

    return rhs


def make_rhs_numba(m, R, I, a):
    import numba

    @numba.njit(cache=False)
    def rhs(t, y):
        r = y[0]
        rd = y[3]
        phd = y[4]
        psd = y[5]
        th = r / R
        s = math.sin(th)
        c = math.cos(th)
        om = psd + c * phd
        out = np.empty(6)
        out[0] = rd
        out[1] = phd
        out[2] = psd
        out[3] = R * s * c * phd * phd - (I / m) * om * (s / R) * phd + (a / (m * R)) * s
        phdd = (I * (s / R) * rd * om - 2.0 * m * R * s * c * rd * phd) / (m * R * R * s * s)
        out[4] = phdd
        out[5] = (s / R) * rd * phd - c * phdd
        return out

    return rhs


def observable(y, m, R, I):
    """Ambient position, velocity, body frame (e1, e2) and spin s = I ω."""
    r, phi, psi, rd, phd, psd = y
    th = r / R
    s, c = math.sin(th), math.cos(th)
    cp, sp = math.cos(phi), math.sin(phi)
    X = R * np.array([s * cp, s * sp, c])
    Xd = np.array([c * cp * rd - R * s * sp * phd, c * sp * rd + R * s * cp * phd, -s * rd])
    Er = np.array([c * cp, c * sp, -s])
    Ep = np.array([-sp, cp, 0.0])
    e1 = math.cos(psi) * Er + math.sin(psi) * Ep
    e2 = -math.sin(psi) * Er + math.cos(psi) * Ep
    spin = I * (psd + c * phd)
    return np.concatenate([X, Xd, e1, e2, [spin]])


def energy(y, m, R, I, a):
    r, _phi, _psi, rd, phd, psd = y
    s, c = math.sin(r / R), math.cos(r / R)
    om = psd + c * phd
    return 0.5 * m * (rd * rd + R * R * s * s * phd * phd) + 0.5 * I * om * om + a * c


def p_phi(y, m, R, I):
    r, _phi, _psi, _rd, phd, psd = y
    s, c = math.sin(r / R), math.cos(r / R)
    return m * R * R * s * s * phd + I * c * (psd + c * phd)


def rel(x, y):
    return abs(x - y) / max(1.0, abs(y))


def check_against_rust(par, samples):
    """Asserts agreement <= 1e-12 (relative) of the numpy RHS, observable,
    energy and p_φ with the Rust coordinate form at the exported samples."""
    m, R, I, a = par["m"], par["R"], par["I"], par["a"]
    rhs = make_rhs(m, R, I, a)
    worst = 0.0
    for row in samples:
        y = np.array([row[k] for k in ("r", "phi", "psi", "rdot", "phidot", "psidot")])
        f = rhs(0.0, y)
        for i in range(3):
            worst = max(worst, rel(f[3 + i], row[f"acc{i}"]))
        o = observable(y, m, R, I)
        for i in range(13):
            worst = max(worst, rel(o[i], row[f"obs{i}"]))
        worst = max(worst, rel(energy(y, m, R, I, a), row["energy"]))
        worst = max(worst, rel(p_phi(y, m, R, I), row["p_phi"]))
    print(f"numpy RHS / observable / energy / p_phi vs framedyn::coords at {len(samples)} states: "
          f"max relative difference {worst:.2e}")
    assert worst <= 1e-12, f"numpy coordinate equations disagree with framedyn::coords: {worst:e}"
    return worst


def read_kv(path):
    with open(path) as f:
        return {r["key"]: float(r["value"]) for r in csv.DictReader(f)}


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def timed(fn):
    """Minimum thread-CPU time over repeats (>= 1 run, until 0.2 s or 5 runs)."""
    best, spent, k, res = math.inf, 0.0, 0, None
    while True:
        t0 = time.thread_time()
        res = fn()
        dt = time.thread_time() - t0
        best, spent, k = min(best, dt), spent + dt, k + 1
        if spent >= 0.2 or k >= 5:
            return best, res


def run_scipy(par, quick):
    m, R, I, a, T = par["m"], par["R"], par["I"], par["a"], par["T"]
    y0 = np.array([par[f"q{i}"] for i in range(3)] + [par[f"v{i}"] for i in range(3)])
    ref = np.array([par[f"ref{i}"] for i in range(13)])
    e0, j0 = energy(y0, m, R, I, a), p_phi(y0, m, R, I)
    rhss = [("numpy", make_rhs(m, R, I, a))]
    try:
        f = make_rhs_numba(m, R, I, a)
        f(0.0, y0)  # compile outside the timing
        rhss.append(("numba", f))
    except Exception as exc:  # numba is optional
        print(f"numba not available ({exc.__class__.__name__}): numpy right-hand side only")
    tols = [10.0 ** (-k / 2) for k in range(6, 25)]
    if quick:
        tols = tols[::4]
    rows = []
    for rhs_name, rhs in rhss:
        # One RHS evaluation, for the record.
        t_eval, _ = timed(lambda: [rhs(0.0, y0) for _ in range(10000)])
        print(f"{rhs_name} RHS: {t_eval / 10000 * 1e6:.2f} us per call (thread CPU)")
        for method in ("DOP853", "RK45", "LSODA"):
            for tol in tols:
                if method == "RK45" and tol < 1e-10 and not quick:
                    continue  # 5th order at 1e-11: minutes per run
                cpu, sol = timed(lambda: solve_ivp(rhs, (0.0, T), y0, method=method, rtol=tol, atol=tol))
                if not sol.success:
                    rows.append(dict(method=f"scipy_{method}_{rhs_name}", tol=tol, error=math.nan, cpu_s=cpu,
                                     rhs_evals=sol.nfev, steps=len(sol.t) - 1, energy_drift=math.nan,
                                     momentum_drift=math.nan, failure=sol.message))
                    continue
                err = float(np.max(np.abs(observable(sol.y[:, -1], m, R, I) - ref)))
                ed = max(abs(energy(sol.y[:, k], m, R, I, a) - e0) for k in range(sol.y.shape[1]))
                md = max(abs(p_phi(sol.y[:, k], m, R, I) - j0) for k in range(sol.y.shape[1]))
                rows.append(dict(method=f"scipy_{method}_{rhs_name}", tol=tol, error=err, cpu_s=cpu,
                                 rhs_evals=sol.nfev, steps=len(sol.t) - 1, energy_drift=ed, momentum_drift=md,
                                 failure=""))
                print(f"  {method:6s} {rhs_name:5s} tol {tol:.0e}: error {err:.2e}, {cpu * 1e3:8.2f} ms, nfev {sol.nfev}")
    return rows


# ---------------------------------------------------------------------------
# Charts
# ---------------------------------------------------------------------------

STYLE = {
    "lie_euler": ("tab:gray", "v"), "heun": ("tab:olive", "^"), "kutta3": ("tab:cyan", "<"),
    "rkmk4": ("tab:blue", "o"), "dopri5_fixed": ("tab:purple", "s"), "butcher6": ("tab:green", "D"),
    "dopri5": ("tab:red", "*"), "coords_rk4": ("black", "x"),
    # splittings (dotted in the charts), implicit midpoint, library coordinate baselines
    "strang": ("gold", "1"), "yoshida4": ("darkgoldenrod", "2"), "suzuki4": ("peru", "3"),
    "blanes_moan4": ("sienna", "4"), "yoshida6": ("darkkhaki", "h"), "blanes_moan6": ("saddlebrown", "H"),
    "blanes_moan_rkn4": ("orangered", "p"), "blanes_moan_rkn6": ("darkred", "P"),
    "lie_midpoint": ("magenta", "d"), "coords_rk4_lib": ("dimgray", "+"), "coords_dopri5": ("silver", "x"),
}

SPLITTINGS = {"strang", "yoshida4", "suzuki4", "blanes_moan4", "yoshida6", "blanes_moan6", "blanes_moan_rkn4", "blanes_moan_rkn6"}


def style(name):
    if name in STYLE:
        return STYLE[name]
    if name.startswith("scipy_"):
        col = {"DOP853": "tab:brown", "RK45": "tab:pink", "LSODA": "tab:orange"}[name.split("_")[1]]
        return col, ("P" if name.endswith("numba") else "X")
    return None, "."


def series(rows, problem, xkey, ykey):
    out = {}
    for r in rows:
        if r["problem"] != problem:
            continue
        try:
            x, y = float(r[xkey]), float(r[ykey])
        except (KeyError, ValueError):
            continue
        if not (x > 0 and y > 0 and math.isfinite(x) and math.isfinite(y)) or r.get("failure"):
            continue
        out.setdefault(r["method"], []).append((x, y))
    return out


def chart(plt, rows, problem, xkey, ykey, xlabel, ylabel, title, path):
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    for name, pts in sorted(series(rows, problem, xkey, ykey).items()):
        pts.sort()
        col, mk = style(name)
        ls = "--" if name.startswith("scipy_") else (":" if name in SPLITTINGS else "-")
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], ls, color=col, marker=mk, ms=4, lw=1.2, label=name)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw(rows, defect_rows, problems):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(FIGS, exist_ok=True)
    for p in problems:
        chart(plt, rows, p, "cpu_s", "error", "thread CPU time [s]", "final error (max norm, ambient)",
              f"{p}: error vs CPU time", os.path.join(FIGS, f"{p}_error_vs_cpu.png"))
        chart(plt, rows, p, "rhs_evals", "error", "right-hand-side evaluations", "final error",
              f"{p}: error vs RHS evaluations", os.path.join(FIGS, f"{p}_error_vs_rhs.png"))
        chart(plt, rows, p, "cpu_s", "energy_drift", "thread CPU time [s]", "max |E(t) − E(0)|",
              f"{p}: energy drift vs CPU time", os.path.join(FIGS, f"{p}_energy_vs_cpu.png"))
        chart(plt, rows, p, "cpu_s", "momentum_drift", "thread CPU time [s]", "max |p_φ(t) − p_φ(0)|",
              f"{p}: momentum-map drift vs CPU time", os.path.join(FIGS, f"{p}_momentum_vs_cpu.png"))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    by = {}
    for r in defect_rows:
        by.setdefault(f"{r['method']} h={r['h']}", []).append(
            (float(r["t"]), float(r["defect"]), float(r["energy_error"])))
    for name, pts in by.items():
        col, _ = style(name.split(" ")[0])
        axes[0].semilogy([p[0] for p in pts], [max(p[1], 1e-18) for p in pts], color=col, lw=1, label=name)
        axes[1].semilogy([p[0] for p in pts], [max(p[2], 1e-18) for p in pts], color=col, lw=1, label=name)
    axes[0].set_title("constraint defect vs time (S² gyroscope)", fontsize=10)
    axes[1].set_title("energy error vs time (S² gyroscope)", fontsize=10)
    for ax in axes:
        ax.set_xlabel("t")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("max(|QᵀQ − I|, |det Q − 1|, …)")
    axes[1].set_ylabel("|E(t) − E(0)|")
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "s2_defect_vs_time.png"), dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="smoke run: T = 20 on S², fewer settings")
    ap.add_argument("--no-cargo", action="store_true", help="reuse docs/data/*.csv from a previous cargo run")
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--out", default=None, help="data directory (default docs/data)")
    ap.add_argument("--figs", default=None, help="chart directory (default docs/figures/performance)")
    ap.add_argument("--summary-only", action="store_true",
                    help="only print the tables of docs/performance.md from docs/data/*.csv")
    args = ap.parse_args()
    global DATA, FIGS
    DATA = os.path.abspath(args.out) if args.out else DATA
    FIGS = os.path.abspath(args.figs) if args.figs else FIGS
    os.makedirs(DATA, exist_ok=True)
    if args.summary_only:
        rows = read_rows(os.path.join(DATA, "wp_rust.csv")) + read_rows(os.path.join(DATA, "wp_scipy.csv"))
        summary(rows)
        return 0
    if not args.no_cargo:
        cmd = ["cargo", "run", "--profile", "measure", "-p", "framedyn-tests", "--example", "work_precision", "--", "--out", DATA]
        if args.quick:
            cmd.append("--quick")
        print("+", " ".join(cmd), flush=True)
        subprocess.run(cmd, cwd=ROOT, check=True)
    par = read_kv(os.path.join(DATA, "s2_problem.csv"))
    samples = [{k: float(v) for k, v in r.items()} for r in read_rows(os.path.join(DATA, "s2_samples.csv"))]
    check_against_rust(par, samples)
    sc = run_scipy(par, args.quick)
    with open(os.path.join(DATA, "wp_scipy.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["method", "problem", "kind", "setting", "error", "cpu_s", "rhs_evals",
                                          "steps", "energy_drift", "momentum_drift", "failure"])
        w.writeheader()
        for r in sc:
            w.writerow(dict(method=r["method"], problem="s2_gyro", kind="tol", setting=f"{r['tol']:e}",
                            error=f"{r['error']:e}", cpu_s=f"{r['cpu_s']:e}", rhs_evals=r["rhs_evals"],
                            steps=r["steps"], energy_drift=f"{r['energy_drift']:e}",
                            momentum_drift=f"{r['momentum_drift']:e}", failure=r["failure"]))
    rust = read_rows(os.path.join(DATA, "wp_rust.csv"))
    scipy_rows = read_rows(os.path.join(DATA, "wp_scipy.csv"))
    rows = rust + scipy_rows
    problems = sorted({r["problem"] for r in rust})
    if not args.no_plots:
        draw(rows, read_rows(os.path.join(DATA, "defect_series.csv")), problems)
        print(f"charts: {FIGS}")
    summary(rows)


def runs_by_method(rows, problem):
    """Per method: the (CPU seconds, final error) of its successful runs on
    `problem` with a finite positive error, sorted by CPU time."""
    per = {}
    for r in rows:
        if r["problem"] != problem or r.get("failure"):
            continue
        try:
            err, cpu = float(r["error"]), float(r["cpu_s"])
        except ValueError:
            continue
        if math.isfinite(err) and err > 0 and cpu > 0:
            per.setdefault(r["method"], []).append((cpu, err))
    return {m: sorted(runs) for m, runs in per.items()}


def best_cpu_at(rows, problem, target):
    """Per method: the least CPU time among runs with error <= target."""
    best = {}
    for m, runs in runs_by_method(rows, problem).items():
        ok = [c for c, e in runs if e <= target]
        if ok:
            best[m] = min(ok)
    return best


def cpu_at_error(rows, problem, target):
    """Per method: the thread-CPU time at final error exactly `target`,
    interpolated linearly in (log error, log CPU) between two runs of the
    method that bracket it (consecutive in CPU time, the cheaper one above
    the target, the dearer one at or below it); the least such estimate,
    or the least CPU time of a run at or below the target if that is less.
    Methods that never reach the target are absent."""
    per = runs_by_method(rows, problem)
    out = {}
    for m, runs in per.items():
        best = min((c for c, e in runs if e <= target), default=math.inf)
        for (c0, e0), (c1, e1) in zip(runs, runs[1:]):
            if e0 > target >= e1:
                f = math.log(e0 / target) / math.log(e0 / e1)
                best = min(best, math.exp(math.log(c0) + f * math.log(c1 / c0)))
        if math.isfinite(best):
            out[m] = best
    return out


def summary(rows):
    problems = sorted({r["problem"] for r in rows})
    print("\nLeast thread-CPU time [ms] to reach a final error <= 1e-6 / 1e-8 (— : not reached)")
    methods = sorted({r["method"] for r in rows if not r["method"].startswith("scipy_")})
    print("| problem | " + " | ".join(methods) + " |")
    print("|---" * (len(methods) + 1) + "|")
    for p in problems:
        cells = []
        for m in methods:
            c = []
            for target in (1e-6, 1e-8):
                b = best_cpu_at([r for r in rows if r["method"] == m], p, target)
                c.append(f"{b[m] * 1e3:.2f}" if m in b else "—")
            cells.append(" / ".join(c))
        print(f"| {p} | " + " | ".join(cells) + " |")
    print("\nLargest energy / momentum-map drift among runs with final error <= 1e-6")
    for p in problems:
        worst = {}
        for r in rows:
            if r["problem"] != p or r.get("failure"):
                continue
            try:
                err, ed, md = float(r["error"]), float(r["energy_drift"]), float(r["momentum_drift"])
            except ValueError:
                continue
            if err <= 1e-6:
                a, b = worst.get(r["method"], (0.0, 0.0))
                worst[r["method"]] = (max(a, ed), max(b, md))
        print(f"  {p}: " + ", ".join(f"{m} {a:.1e}/{b:.1e}" for m, (a, b) in sorted(worst.items())))
    for target in (1e-4, 1e-6, 1e-8):
        best = best_cpu_at(rows, "s2_gyro", target)
        if not best:
            continue
        ranked = sorted(best.items(), key=lambda kv: kv[1])
        print(f"S² gyroscope, error <= {target:.0e}: least thread-CPU time per method")
        for name, cpu in ranked:
            print(f"  {name:22s} {cpu * 1e3:10.3f} ms")
        fd = [c for n, c in ranked if not n.startswith("scipy_")]
        sp = [c for n, c in ranked if n.startswith("scipy_")]
        if fd and sp:
            ratio = min(sp) / min(fd)
            print(f"  best scipy / best framedyn = {ratio:.1f}x")
            if target == 1e-8:
                print(f"  issue target (>= 100x at 1e-8), least CPU on the sampled ladders: {'met' if ratio >= 100 else 'NOT met'}")
        # At equal error: each method's CPU time interpolated to the target.
        eq = cpu_at_error(rows, "s2_gyro", target)
        fd = {n: c for n, c in eq.items() if not n.startswith("scipy_")}
        sp = {n: c for n, c in eq.items() if n.startswith("scipy_")}
        if fd and sp:
            (nf, cf), (ns, cs) = min(fd.items(), key=lambda kv: kv[1]), min(sp.items(), key=lambda kv: kv[1])
            print(f"  at equal error {target:.0e} (interpolated): {nf} {cf * 1e3:.3f} ms, {ns} {cs * 1e3:.3f} ms, "
                  f"ratio {cs / cf:.1f}x")
            if target == 1e-8:
                print(f"  issue target (>= 100x at equal error 1e-8): {'met' if cs / cf >= 100 else 'NOT met'}")


if __name__ == "__main__":
    sys.exit(main())
