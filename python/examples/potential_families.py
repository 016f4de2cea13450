"""One check per potential family of the paper, each against a closed form
(the Python twin of ``examples/potential_families.rs``; see there for the
formulas): Bertrand oscillator (b88) and Kepler (c88)/(b133) periods, the
cosine family of §5.1, separable (b128), elastic (a131) and St
Venant–Kirchhoff small-oscillation periods.

Run: ``python python/examples/potential_families.py`` (exit status 1 if a check fails).
"""

import math

import numpy as np

import framedyn as fd
from _check import drift, finish, le, returned

M, R = 1.3, 1.2


def point(manifold, potential, start, t_end):
    r0, rd, pd = start
    return fd.solve(fd.Scene(
        manifold={"kind": manifold, "radius": R}, body={"kind": "point", "mass": M}, potential=potential,
        r=r0, phi=0.0, r_dot=rd, phi_dot=pd,
        method="dopri5", rtol=1e-12, atol=1e-12, t_end=t_end, times=[0.0, t_end],
    ))


def closes(what, manifold, potential, start, periods, period):
    E = float(point(manifold, potential, start, 1e-3).energy[0])
    T_r = period(E)
    sol = point(manifold, potential, start, periods * T_r)
    print(f"{what}: E = {E:.12f}, T_r = {T_r:.12f}")
    le(f"|x({periods:g}·T_r) − x(0)| / R", returned(sol) / R, 1e-9)


kappa, alpha = 0.8, 0.7
closes("S² Bertrand oscillator (b88)", "S2", {"kind": "oscillator", "kappa": kappa}, (0.5, 0.0, 0.9), 2,
       lambda E: math.pi * math.sqrt(M * R * R / (2 * E + kappa * R * R)))


def kepler_period(E, sign):
    # S² (sign = +1): n² = mR(RE + √(R²E² + α²)); H² (sign = −1): n² = mR(−RE − √(R²E² − α²)).
    n2 = M * R * sign * (R * E + math.sqrt(R * R * E * E + sign * alpha * alpha))
    n = math.sqrt(n2)
    return 2 * math.pi / (M * alpha * alpha / n**3 + sign * n / (M * R * R))


closes("S² Bertrand Kepler (c88)", "S2", {"kind": "kepler", "alpha": alpha}, (0.8, 0.3, 0.5), 1, lambda E: kepler_period(E, 1.0))
closes("H² Bertrand Kepler (b133)", "H2", {"kind": "kepler", "alpha": alpha}, (0.5, 0.0, 0.5), 1, lambda E: kepler_period(E, -1.0))

sol = fd.solve(fd.Scene(
    manifold="S2", body={"kind": "gyroscope", "mass": 1.0, "inertia": 0.2},
    potential={"kind": "cosine", "alpha_hat": 0.4, "beta_hat": -0.3},
    r=0.6, phi=0.0, r_dot=-0.5, phi_dot=0.8, spin=0.3, method="butcher6", h=0.01, t_end=10.0, every=50,
))
print("S² gyroscope in the cosine family α̂cos² + β̂cos (§5.1), t ≤ 10:")
le("energy drift", drift(sol, "energy"), 1e-10)
le("spin drift", drift(sol, "spin"), 1e-12)
le("p_φ drift", drift(sol, "p_phi"), 1e-10)

sol = fd.solve(fd.Scene(
    manifold="S2", body={"kind": "affine", "mass": 1.0, "inertia": 0.35},
    potential={"kind": "separable", "v_r": {"cos": [[0.4, 1.0]]}, "v_rho": {"poly": [0.0, 0.0, 0.45, 0.0, 0.05]}, "v_eps": {"sec_2x": 1.8}},
    r=0.5, phi=0.0, r_dot=0.2, phi_dot=0.5, rho=[[1.1, 0.1], [0.0, 0.9]], rho_dot=[[0.0, 0.1], [-0.2, 0.05]],
    method="dopri5", rtol=1e-11, atol=1e-11, t_end=5.0, samples=51,
))
spin = sol["k_12"] - sol["k_21"]
print("S² affine body, separable potential (b128), t ≤ 5:")
le("relative energy drift", drift(sol, "energy") / abs(sol.energy[0]), 1e-9)
le("p_φ drift", drift(sol, "p_phi"), 1e-9)
le("spin p_α = k₁₂ − k₂₁ drift", float(np.max(np.abs(spin - spin[0]))), 1e-9)

# Small oscillations about the natural state: |e₁| is 1 + ε at t = 0 and T, 1 − ε at T/2.
eps, inertia = 1e-4, 0.35


def oscillation(what, manifold, potential, rho, omega2):
    T = 2 * math.pi / math.sqrt(omega2)
    chart = {"r1": 0.3, "r2": 0.0, "r3": 0.0} if manifold == "S3" else {"r": 0.3, "phi": 0.0}
    sol = fd.solve(fd.Scene(
        manifold=manifold, body={"kind": "affine", "mass": 1.0, "inertia": inertia}, potential=potential,
        rho=rho, method="dopri5", rtol=1e-13, atol=1e-13, t_end=T, samples=5, quantities=["frame"], **chart,
    ))
    e1 = np.linalg.norm(sol.frame[:, 0, :], axis=1)
    print(f"{what}: period 2π/ω = {T:.12f}")
    le("| |e₁|(T/2) − (1 − ε)| / ε", abs(e1[2] - (1 - eps)) / eps, 1e-3)
    le("| |e₁|(T) − (1 + ε)| / ε", abs(e1[4] - (1 + eps)) / eps, 1e-3)


kappa = 0.9
elastic = {"kind": "elastic", "kappa": kappa}
oscillation("S² elastic (a131), dilatation ω² = 4κ/I", "S2", elastic, (1 + eps) * np.eye(2), 4 * kappa / inertia)
oscillation("S² elastic (a131), shear ω² = 2κ/I", "S2", elastic, np.diag([1 + eps, 1 - eps]), 2 * kappa / inertia)
lam, mu = 1.1, 0.7
oscillation("S³ St Venant–Kirchhoff, dilatation ω² = (3λ + 2μ)/I", "S3",
            {"kind": "st_venant_kirchhoff", "lambda": lam, "mu": mu}, (1 + eps) * np.eye(3), (3 * lam + 2 * mu) / inertia)
finish()
