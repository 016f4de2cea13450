"""The torus T²(L, R): a point, a gyroscope and an affine body (the Python
twin of ``examples/t2_bodies.rs``; see there for the formulas).

Run: ``python python/examples/t2_bodies.py`` (exit status 1 if a check fails).
"""

import math

import framedyn as fd
from _check import close, drift, finish, le

TORUS = {"kind": "T2", "L": 2.0, "R": 0.7}
L, R, m = 2.0, 0.7, 1.3

# Point: Clairaut's integral p_φ = m(L + R cos θ)² φ̇ and the energy.
theta, theta_dot, phi_dot = 0.4, 0.9, 0.35
sol = fd.solve(fd.Scene(
    manifold=TORUS, body={"kind": "point", "mass": m},
    theta=theta, phi=0.0, theta_dot=theta_dot, phi_dot=phi_dot, method="butcher6", h=0.01, t_end=10.0, every=50,
))
rho = L + R * math.cos(theta)
print("T² point (geodesic), t ≤ 10:")
close("p_φ at t = 0 vs m(L + R cos θ)²φ̇", float(sol["p_phi"][0]), m * rho * rho * phi_dot, 1e-13)
close("E at t = 0 vs (m/2)(R²θ̇² + (L + R cos θ)²φ̇²)", float(sol.energy[0]), 0.5 * m * ((R * theta_dot) ** 2 + (rho * phi_dot) ** 2), 1e-13)
le("p_φ drift (Clairaut)", drift(sol, "p_phi"), 1e-10)
le("energy drift", drift(sol, "energy"), 1e-10)

# Gyroscope, V = 0.3 cos θ (independent of φ): energy, spin, p_φ conserved.
sol = fd.solve(fd.Scene(
    manifold=TORUS, body={"kind": "gyroscope", "mass": m, "inertia": 0.2},
    potential={"kind": "separable", "v_r": {"cos": [[0.3, 1.0]]}},
    theta=0.4, phi=0.0, theta_dot=0.5, phi_dot=0.3, alpha=0.0, spin=0.4,
    method="butcher6", h=0.01, t_end=10.0, every=50,
))
print("T² gyroscope, V = 0.3 cos θ, t ≤ 10:")
le("energy drift", drift(sol, "energy"), 1e-10)
le("spin drift", drift(sol, "spin"), 1e-12)
le("p_φ drift", drift(sol, "p_phi"), 1e-10)

# Affine body, elastic potential (a131).
sol = fd.solve(fd.Scene(
    manifold=TORUS, body={"kind": "affine", "mass": m, "inertia": 0.1}, potential={"kind": "elastic", "kappa": 1.0},
    theta=0.3, phi=0.0, theta_dot=0.2, phi_dot=0.3, rho=[[1.1, 0.0], [0.1, 0.9]],
    method="rk4", h=0.002, t_end=2.0, every=50,
))
print("T² affine body, elastic potential (a131), RKMK4 h = 0.002, t ≤ 2:")
le("relative energy drift", drift(sol, "energy") / abs(sol.energy[0]), 1e-9)
le("p_φ drift", drift(sol, "p_phi"), 1e-10)
le("max constraint defect", float(sol.defect.max()), 1e-12)
finish()
