"""The sphere S²(R): a point, a gyroscope and an affine body, each checked
against a closed form of the paper (the Python twin of
``examples/s2_bodies.rs``; see there for the formulas).

Run: ``python python/examples/s2_bodies.py`` (exit status 1 if a check fails).
"""

import math

import framedyn as fd
from _check import close, drift, finish, le, returned

# Point: a geodesic of speed |v| returns after 2πR/|v|.
R, r0, r_dot, phi_dot = 1.5, 0.6, 0.3, 0.8
speed = math.hypot(r_dot, R * math.sin(r0 / R) * phi_dot)
T = 2 * math.pi * R / speed
sol = fd.solve(fd.Scene(
    manifold={"kind": "S2", "radius": R}, body="point",
    r=r0, phi=0.0, r_dot=r_dot, phi_dot=phi_dot,
    method="dopri5", rtol=1e-12, atol=1e-12, t_end=T, times=[0.0, T],
))
print(f"S² point (geodesic): period 2πR/|v| = {T:.12f}")
le("|x(T) − x(0)| / R", returned(sol) / R, 1e-9)
le("energy drift", drift(sol, "energy"), 1e-11)

# Gyroscope (free): m u̇ = K s ε u (a59) makes the path a circle of period 2π/√(|u|²/R² + (s/mR²)²).
m, s, u = 1.0, 0.5, 1.0
T = 2 * math.pi / math.sqrt(u**2 + (s / m) ** 2)
sol = fd.solve(fd.Scene(
    manifold={"kind": "S2", "radius": 1.0}, body={"kind": "gyroscope", "mass": m, "inertia": 0.2},
    r=0.3, phi=0.0, r_dot=-u, phi_dot=0.0, alpha=0.0, spin=s,
    method="dopri5", rtol=1e-12, atol=1e-12, t_end=T, samples=201,
))
print(f"S² gyroscope (free, s = {s}): period = {T:.12f}; closest approach to the pole 1 − max z = {1 - sol.position[:, 2].max():.3e} R")
le("|x(T) − x(0)| / R", returned(sol), 1e-9)
le("|s(T) − s(0)| (the spin p_ψ is conserved)", drift(sol, "spin"), 1e-12)
le("energy drift", drift(sol, "energy"), 1e-11)

# Affine body, elastic potential (a131).
sol = fd.solve(fd.Scene(
    manifold={"kind": "S2", "radius": 1.0}, body={"kind": "affine", "mass": 1.0, "inertia": 0.1},
    potential={"kind": "elastic", "kappa": 1.0},
    r=0.7, phi=0.0, phi_dot=0.6, rho=[[1.1, 0.0], [0.0, 0.9]], rho_dot=[[0.0, 0.2], [-0.1, 0.0]],
    method="rk4", h=0.002, t_end=2.0, every=10,
))
print("S² affine body, elastic potential (a131), RKMK4 h = 0.002, t ≤ 2:")
le("relative energy drift", drift(sol, "energy") / abs(sol.energy[0]), 1e-9)
le("p_φ drift", drift(sol, "p_phi"), 1e-10)
le("max constraint defect", float(sol.defect.max()), 1e-12)
finish()
