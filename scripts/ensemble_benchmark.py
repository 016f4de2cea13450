#!/usr/bin/env python3
"""Ensemble throughput (issue 18 targets) — ONE command, from the repository root:

    .venv/bin/python scripts/ensemble_benchmark.py             # release wheel in a temporary venv, then the baselines
    .venv/bin/python scripts/ensemble_benchmark.py --summary-only

The problem: the S² gyroscope of SPEC §5 (m = 1, R = 1, I = 0.3,
V = 0.5 cos(r/R), start (r, φ, ψ) = (1, 0.3, 0.4), (ṙ, φ̇) = (0.3, 0.6),
ω = 1), with r, ṙ and ω of each member perturbed uniformly by ±10 %
(seeded), T = 20, final state only.

Measured (benchmarks, not tests; the CSV keeps the machine's load):
1. framedyn, columnar ``fd.solve_batch(scene, table, keep="final")`` with
   Blanes–Moan RKN 6 at h = 0.4, N = 10², 10³, 10⁴ (and 10⁵ with
   ``--large``), threads = 1 and 2: members/s of the whole call;
2. the per-member overhead: the same call with ``time.t_end`` = 1e-9 (one
   step of 1e-9), per member;
3. a batch with a Python ``user_potential`` (6 members × 400 RK4 steps)
   against a loop of ``fd.solve`` over the same members, in ``--rounds``
   alternating rounds, and the list-of-dicts form
   ``fd.solve_batch(scene, [dict, …])`` at N = 10³ for comparison;
4. the accuracy of each method on 200 members against a reference
   (scipy DOP853, rtol = atol = 1e-13, in the paper's coordinates): the
   maximal error of the final ambient observable;
5. baselines in this interpreter, when installed: diffrax ``jit(vmap(...))``
   with Dopri8 (JAX on CPU, float64; compile time measured separately and
   excluded from members/s) at a tolerance whose maximal error is ≤ 1e-8,
   and a scipy ``solve_ivp`` loop (DOP853, numba right-hand side when numba
   is installed) at the same error.

Steps 1-4 run in a temporary virtual environment with a release wheel
(``maturin build --release``), as scripts/python_overhead.py does, unless
the installed extension is a release build (or ``--installed``). Output:
docs/data/ensemble_benchmark.csv and a table on stdout.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import shutil
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
CSV_PATH = os.path.join(ROOT, "docs", "data", "ensemble_benchmark.csv")

M, R, I, A = 1.0, 1.0, 0.3, 0.5
Q0 = (1.0, 0.3, 0.4)
V0 = (0.3, 0.6, 1.0)  # ṙ, φ̇, ω
T_END = 20.0
H = 0.4
SEED = 20261127
CHECK = 200  # members whose error is measured
FIELDS = ["tool", "variant", "members", "threads", "wall_s", "members_per_s", "per_member_us", "run_us", "max_error", "compile_s", "load1"]


def members(n, seed=SEED):
    rng = np.random.default_rng(seed)
    f = lambda: 1.0 + rng.uniform(-0.1, 0.1, n)  # noqa: E731
    return Q0[0] * f(), V0[0] * f(), V0[2] * f()


def observable_from_chart(y):
    from work_precision import observable

    return observable(y, M, R, I)


def chart_state(r, rd, om):
    """(r, φ, ψ, ṙ, φ̇, ψ̇) with ψ̇ = ω − cos(r/R) φ̇ (a91)."""
    return np.array([r, Q0[1], Q0[2], rd, V0[1], om - math.cos(r / R) * V0[1]])


def references(r, rd, om):
    from scipy.integrate import solve_ivp
    from work_precision import make_rhs

    rhs = make_rhs(M, R, I, A)
    out = []
    for k in range(min(CHECK, len(r))):
        sol = solve_ivp(rhs, (0.0, T_END), chart_state(r[k], rd[k], om[k]), method="DOP853", rtol=1e-13, atol=1e-13)
        out.append(observable_from_chart(sol.y[:, -1]))
    return np.array(out)


def row(tool, variant, n, threads, wall, err=float("nan"), compile_s=float("nan"), run_s=float("nan")):
    """``run_s``: framedyn's own time inside ``Simulation::run`` per member
    (``stats["wall_time"]``, mean), where measured."""
    return {
        "tool": tool, "variant": variant, "members": n, "threads": threads, "wall_s": f"{wall:.6f}",
        "members_per_s": f"{n / wall:.1f}", "per_member_us": f"{1e6 * wall / n:.3f}", "run_us": f"{1e6 * run_s:.3f}",
        "max_error": f"{err:.3e}", "compile_s": f"{compile_s:.2f}", "load1": f"{os.getloadavg()[0]:.2f}",
    }


# ---------------------------------------------------------------------------
# framedyn (runs in the measuring environment)
# ---------------------------------------------------------------------------


def framedyn_scene(fd, t_end=T_END):
    return fd.Scene(
        manifold={"kind": "S2", "radius": R}, body={"kind": "gyroscope", "mass": M, "inertia": I},
        potential={"kind": "cosine", "alpha_hat": 0.0, "beta_hat": A},
        r=Q0[0], phi=Q0[1], r_dot=V0[0], phi_dot=V0[1], alpha=Q0[2], spin=I * V0[2],
        method={"name": "blanes_moan_rkn6", "h": H}, t_end=t_end,
    )


def framedyn_observable(out):
    """Final ambient observable (position, velocity, e1, e2, spin) per member."""
    f = out.final
    idx = {c: j for j, c in enumerate(out.columns)}
    cols = ["x0", "x1", "x2", "v0", "v1", "v2", "e1_0", "e1_1", "e1_2", "e2_0", "e2_1", "e2_2", "spin"]
    return f[:, [idx[c] for c in cols]]


def best_of(fn, repeats):
    best = float("inf")
    res = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = fn()
        best = min(best, time.perf_counter() - t0)
    return best, res


def measure_framedyn(args):
    import framedyn as fd

    rows = []
    base = framedyn_scene(fd)
    sizes = args.sizes
    r, rd, om = members(max(sizes))
    ref = references(r, rd, om)
    table = lambda n: {"initial.r": r[:n], "initial.r_dot": rd[:n], "initial.spin": I * om[:n]}  # noqa: E731
    check = fd.solve_batch(base, table(CHECK), keep="final")
    err = float(np.max(np.abs(framedyn_observable(check) - ref)))
    print(f"framedyn RKN6 h={H}: max final error over {CHECK} members {err:.2e}", flush=True)
    for n in sizes:
        for threads in (1, 2):
            wall, out = best_of(lambda: fd.solve_batch(base, table(n), keep="final", threads=threads), args.repeats)
            assert (out.status == "finished").all()
            rows.append(row("framedyn", "columnar", n, threads, wall, err))
            print(f"framedyn columnar N={n} threads={threads}: {n / wall:,.0f} members/s", flush=True)
    # One native integration of the same problem (all records, as fd.solve
    # gives them): the cost a batch member is compared with.
    wall, sol = best_of(lambda: fd.solve(base), 20 * args.repeats)
    rows.append(row("framedyn", "single_solve", 1, 1, wall, run_s=sol.stats["wall_time"]))
    print(f"framedyn one fd.solve: {1e6 * wall:.1f} µs ({1e6 * sol.stats['wall_time']:.1f} µs in the run)", flush=True)
    # Members of one step of 1e-9: what a member costs besides its steps
    # (run_us: the part inside Simulation::run, one step and the summary of
    # two states; the rest is building and bookkeeping).
    tiny = framedyn_scene(fd, t_end=1e-9)
    for n in sizes:
        wall, out = best_of(lambda: fd.solve_batch(tiny, table(n), keep="final", threads=1), args.repeats)
        run_s = float(np.mean(out.stats["wall_time"]))
        rows.append(row("framedyn", "overhead", n, 1, wall, run_s=run_s))
        print(f"framedyn per-member overhead N={n}: {1e6 * wall / n:.2f} µs, of which {1e6 * run_s:.2f} µs in the run", flush=True)
    # A Python user potential (V = a z/R, the cosine potential by hand),
    # 6 members × 400 RK4 steps: the batch (members one after another, each
    # call holding the GIL) against a loop of fd.solve over the same members.
    upot = lambda x, e: A * x[2] / R  # noqa: E731
    ubase = fd.Scene(
        manifold={"kind": "S2", "radius": R}, body={"kind": "gyroscope", "mass": M, "inertia": I},
        r=Q0[0], phi=Q0[1], r_dot=V0[0], phi_dot=V0[1], alpha=Q0[2], spin=I * V0[2], method="rk4", h=0.05, t_end=T_END,
    )
    k = 6
    uparams = [{"initial.r": float(r[i]), "initial.r_dot": float(rd[i])} for i in range(k)]
    # Rounds alternate the two (one row each per round: the per-round ratio
    # is robust to the machine's drift), each keeping the best of `repeats`.
    ratios = []
    for _ in range(args.rounds):
        wall_b, ub = best_of(lambda: fd.solve_batch(ubase, {"initial.r": r[:k], "initial.r_dot": rd[:k]}, user_potential=upot, keep="final"), args.repeats)
        wall_l, ul = best_of(lambda: [fd.solve(ubase.with_params(p), user_potential=upot) for p in uparams], args.repeats)
        assert all(np.array_equal(ub.final[i], ul[i].data[-1]) for i in range(k))
        rows.append(row("framedyn", "user_potential_batch", k, 1, wall_b))
        rows.append(row("framedyn", "user_potential_loop", k, 1, wall_l))
        ratios.append(wall_b / wall_l)
        print(f"user potential: batch {wall_b:.3f} s, loop of fd.solve {wall_l:.3f} s, batch/loop {wall_b / wall_l:.3f}", flush=True)
    print(f"user potential: batch/loop over {args.rounds} rounds: median {np.median(ratios):.3f}, max {max(ratios):.3f}", flush=True)
    n = min(1000, max(sizes))
    params = [{"initial.r": float(r[k]), "initial.r_dot": float(rd[k]), "initial.spin": float(I * om[k])} for k in range(n)]
    for threads in (1, 2):
        wall, _ = best_of(lambda: fd.solve_batch(base, params, threads=threads), args.repeats)
        rows.append(row("framedyn", "list_of_dicts", n, threads, wall, err))
    return rows


# ---------------------------------------------------------------------------
# Baselines (this interpreter)
# ---------------------------------------------------------------------------


def measure_diffrax(args):
    # One thread, as framedyn's threads = 1 rows: XLA's CPU backend would
    # otherwise spread vmapped work over every core.
    os.environ.setdefault("XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1")
    try:
        import jax
        import diffrax
    except ImportError:
        print("jax/diffrax not installed: diffrax baseline skipped (pip install 'jax[cpu]' diffrax)")
        return []
    jax.config.update("jax_enable_x64", True)
    jax.config.update("jax_platform_name", "cpu")
    import jax.numpy as jnp

    def f(t, y, _):
        r, _phi, _psi, rd_, phd, psd = y
        s, c = jnp.sin(r / R), jnp.cos(r / R)
        w = psd + c * phd
        rdd = R * s * c * phd * phd - (I / M) * w * (s / R) * phd + (A / (M * R)) * s
        phdd = (I * (s / R) * rd_ * w - 2.0 * M * R * s * c * rd_ * phd) / (M * R * R * s * s)
        return jnp.stack([rd_, phd, psd, rdd, phdd, (s / R) * rd_ * phd - c * phdd])

    def solver(tol):
        def one(y0):
            sol = diffrax.diffeqsolve(
                diffrax.ODETerm(f), diffrax.Dopri8(), 0.0, T_END, 0.05, y0,
                stepsize_controller=diffrax.PIDController(rtol=tol, atol=tol), max_steps=100000,
            )
            return sol.ys[-1]

        return jax.jit(jax.vmap(one))

    sizes = args.sizes
    r, rd, om = members(max(sizes))
    ref = references(r, rd, om)
    y0 = np.array([chart_state(r[k], rd[k], om[k]) for k in range(max(sizes))])
    rows = []
    for tol in (1e-9, 1e-10, 1e-11, 1e-12):
        run = solver(tol)
        t0 = time.perf_counter()
        ys = np.asarray(run(y0[:CHECK]).block_until_ready())
        compile_s = time.perf_counter() - t0
        err = max(float(np.max(np.abs(observable_from_chart(ys[k]) - ref[k]))) for k in range(CHECK))
        print(f"diffrax Dopri8 tol={tol:.0e}: max error {err:.2e} (first call {compile_s:.1f} s)", flush=True)
        if err <= 1e-8:
            break
    for n in sizes:
        run(y0[:n]).block_until_ready()  # compile for this shape
        wall, _ = best_of(lambda: run(y0[:n]).block_until_ready(), args.repeats)
        rows.append(row("diffrax", f"jit_vmap_dopri8_tol{tol:.0e}", n, 1, wall, err, compile_s))
        print(f"diffrax N={n}: {n / wall:,.0f} members/s", flush=True)
    return rows


def measure_scipy(args):
    from scipy.integrate import solve_ivp
    from work_precision import make_rhs, make_rhs_numba

    try:
        rhs, label = make_rhs_numba(M, R, I, A), "numba"
        rhs(0.0, chart_state(*Q0[:1], V0[0], V0[2]))
    except Exception:  # numba is optional
        rhs, label = make_rhs(M, R, I, A), "numpy"
    n = min(CHECK, 200)
    r, rd, om = members(n)
    ref = references(r, rd, om)
    for tol in (1e-9, 1e-10, 1e-11, 1e-12):
        ys = [solve_ivp(rhs, (0.0, T_END), chart_state(r[k], rd[k], om[k]), method="DOP853", rtol=tol, atol=tol).y[:, -1] for k in range(n)]
        err = max(float(np.max(np.abs(observable_from_chart(ys[k]) - ref[k]))) for k in range(n))
        if err <= 1e-8:
            break
    wall, _ = best_of(lambda: [solve_ivp(rhs, (0.0, T_END), chart_state(r[k], rd[k], om[k]), method="DOP853", rtol=tol, atol=tol) for k in range(n)], 1)
    print(f"scipy DOP853 ({label}) tol={tol:.0e}: {n / wall:,.0f} members/s, max error {err:.2e}", flush=True)
    return [row("scipy", f"dop853_{label}_tol{tol:.0e}", n, 1, wall, err)]


# ---------------------------------------------------------------------------


def write_csv(rows, append):
    os.makedirs(os.path.dirname(CSV_PATH), exist_ok=True)
    mode = "a" if append and os.path.exists(CSV_PATH) else "w"
    with open(CSV_PATH, mode, newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if mode == "w":
            w.writeheader()
        w.writerows(rows)


def summary():
    with open(CSV_PATH, newline="") as f:
        rows = list(csv.DictReader(f))
    out = ["| tool | variant | N | threads | members/s | µs/member | µs in the run | max error | compile s | load |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(
            f"| {r['tool']} | {r['variant']} | {r['members']} | {r['threads']} | {float(r['members_per_s']):,.0f} | "
            f"{float(r['per_member_us']):.2f} | {r.get('run_us', 'nan')} | {r['max_error']} | {r['compile_s']} | {r['load1']} |"
        )
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3, help="runs per measurement (the minimum is kept)")
    ap.add_argument("--rounds", type=int, default=5, help="alternating rounds of the user-potential batch and loop")
    ap.add_argument("--large", action="store_true", help="also N = 10^5")
    ap.add_argument("--sizes", default="100,1000,10000", help="ensemble sizes N (comma-separated; default 100,1000,10000)")
    ap.add_argument("--summary-only", action="store_true")
    ap.add_argument("--installed", action="store_true", help="measure the installed extension even if it is a development build")
    ap.add_argument("--wheel", help="a release wheel already built (maturin build --release) to install instead of building one")
    ap.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    args.sizes = sorted({int(x) for x in args.sizes.split(",")} | ({100000} if args.large else set()))
    if max(args.sizes) < CHECK:
        sys.exit(f"--sizes: the largest N must be >= {CHECK} (the members whose error is measured)")
    if args.summary_only:
        print(summary())
        return
    passthrough = ["--repeats", str(args.repeats), "--rounds", str(args.rounds), "--sizes", ",".join(map(str, args.sizes))]
    if args.measure:
        write_csv(measure_framedyn(args), append=False)
        return
    from python_overhead import installed_extension, make_wheel_venv, run

    origin, dev = installed_extension()
    if origin is not None and (not dev or args.installed):
        run([sys.executable, os.path.abspath(__file__), "--measure", *passthrough], cwd=ROOT)
    else:
        tmp = tempfile.mkdtemp(prefix="framedyn-ensemble-")
        try:
            if args.wheel:
                import numpy

                run([sys.executable, "-m", "venv", os.path.join(tmp, "venv")])
                py = os.path.join(tmp, "venv", "bin", "python")
                run([py, "-m", "pip", "install", "--quiet", "--disable-pip-version-check", f"numpy=={numpy.__version__}", os.path.abspath(args.wheel)])
            else:
                py = make_wheel_venv(tmp)
            run([py, "-m", "pip", "install", "--quiet", "--disable-pip-version-check", "scipy"])
            env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "scripts"))
            run([py, os.path.abspath(__file__), "--measure", *passthrough], cwd=tmp, env=env)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    write_csv(measure_diffrax(args) + measure_scipy(args), append=True)
    print(summary())


if __name__ == "__main__":
    main()
