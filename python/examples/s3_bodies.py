"""The three-sphere S³(R): a point, a gyroscope and an affine body (the
Python twin of ``examples/s3_bodies.rs``; see there for the formulas).

Run: ``python python/examples/s3_bodies.py`` (exit status 1 if a check fails).
"""

import math

import numpy as np

import framedyn as fd
from _check import drift, finish, le, returned

m, R, kappa = 1.3, 1.2, 0.8


def point(t_end):
    return fd.solve(fd.Scene(
        manifold={"kind": "S3", "radius": R}, body={"kind": "point", "mass": m},
        potential={"kind": "oscillator", "kappa": kappa},
        r1=0.5, r2=0.0, r3=0.1, r1_dot=0.1, r2_dot=0.6, r3_dot=0.0,
        method="dopri5", rtol=1e-12, atol=1e-12, t_end=t_end, times=[0.0, t_end],
    ))


# Bertrand oscillator: the state returns after two radial periods T_r = π√(mR²/(2E + κR²)).
E = float(point(1e-3).energy[0])
T_r = math.pi * math.sqrt(m * R * R / (2 * E + kappa * R * R))
sol = point(2 * T_r)
print(f"S³ point, Bertrand oscillator: E = {E:.12f}, T_r = {T_r:.12f}")
le("|x(2T_r) − x(0)| / R", returned(sol) / R, 1e-9)
le("|J_12(2T_r) − J_12(0)| (rotations fixing the centre)", drift(sol, "J_12"), 1e-11)

J_AB = ["J_01", "J_02", "J_03", "J_12", "J_13", "J_23"]

# Free gyroscope, J = (I/2)δ: the SO(4) momentum map and |S_rl|² are conserved.
sol = fd.solve(fd.Scene(
    manifold={"kind": "S3", "radius": 1.0}, body={"kind": "gyroscope", "mass": 1.0, "J": 0.25 * np.eye(3)},
    r1=0.5, r2=0.0, r3=0.2, r1_dot=0.0, r2_dot=0.7, r3_dot=0.0,
    orientation=[0.1, 0.2, 0.3], omega=[1.0, 0.5, -0.3],
    method="butcher6", h=0.01, t_end=5.0, every=20,
))
spin2 = sum(sol[f"spin_{k}"] ** 2 for k in (1, 2, 3))
print("S³ gyroscope, free, J = (I/2)δ with I = 0.5, t ≤ 5:")
le("max over J_ab of the drift (SO(4) momentum map)", max(drift(sol, j) for j in J_AB), 1e-10)
le("drift of |spin|² (body components)", float(np.max(np.abs(spin2 - spin2[0]))), 1e-10)
le("energy drift", drift(sol, "energy"), 1e-10)

# Affine body, neo-Hookean energy of the Green tensor.
sol = fd.solve(fd.Scene(
    manifold={"kind": "S3", "radius": 1.0}, body={"kind": "affine", "mass": 1.0, "inertia": 0.1},
    potential={"kind": "neo_hookean", "lambda": 1.0, "mu": 1.0},
    r1=0.4, r2=0.0, r3=0.0, r2_dot=0.5,
    rho=[[1.1, 0.0, 0.0], [0.0, 0.95, 0.0], [0.0, 0.05, 1.0]], rho_dot=[[0.0, 0.1, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.1]],
    method="rk4", h=0.002, t_end=1.0, every=50,
))
print("S³ affine body, neo-Hookean, RKMK4 h = 0.002, t ≤ 1:")
le("relative energy drift", drift(sol, "energy") / abs(sol.energy[0]), 1e-9)
le("max over J_ab of the drift", max(drift(sol, j) for j in J_AB), 1e-9)
finish()
