"""The hyperbolic plane H²(R): a point, the gyroscope (Riemannian (a135) and
Lorentz-type (a138)) and an affine body (the Python twin of
``examples/h2_bodies.rs``; see there for the formulas).

Run: ``python python/examples/h2_bodies.py`` (exit status 1 if a check fails).
"""

import math

import numpy as np

import framedyn as fd
from _check import close, drift, finish, le, returned

# Point: a radial geodesic has r(t) = r0 + ṙ0 t (r is the geodesic distance).
r0, v, t_end = 0.2, 0.7, 3.0
sol = fd.solve(fd.Scene(
    manifold={"kind": "H2", "radius": 1.0}, body="point",
    r=r0, phi=0.5, r_dot=v, phi_dot=0.0, method="butcher6", h=0.01, t_end=t_end, every=100,
))
print("H² point (radial geodesic):")
close("r(T) vs r₀ + ṙ₀T", float(sol["r"][-1]), r0 + v * t_end, 1e-12)


def gyroscope(signature, s, u, t_end):
    return fd.solve(fd.Scene(
        manifold={"kind": "H2", "radius": 1.0},
        body={"kind": "gyroscope", "mass": 1.0, "inertia": 0.3, "signature": signature},
        r=0.4, phi=0.0, r_dot=u, phi_dot=0.0, spin=s,
        method="dopri5", rtol=1e-12, atol=1e-12, t_end=t_end, times=[0.0, t_end],
    ))


# Free gyroscope: Λ(t) = Λ₀ exp(t(h(u₀) + cG)), c = −s/(mR²); elliptic for c² > |u|²/R².
s, u = 0.6, 0.3
T = 2 * math.pi / math.sqrt(s * s - u * u)
sol = gyroscope("riemannian", s, u, T)
print(f"H² gyroscope (a135), free, s = {s}: period 2π/√(c² − |u|²/R²) = {T:.12f}")
le("|x(T) − x(0)| / R (Minkowski components)", returned(sol), 1e-9)
le("|s(T) − s(0)|", drift(sol, "spin"), 1e-12)
le("energy drift", drift(sol, "energy"), 1e-11)

sol = gyroscope("lorentz", s, u, T)
print(f"H² Lorentz-type gyroscope (a138), free, s = {s}:")
close("energy vs (m/2)|u|² − s²/(2I)", float(sol.energy[0]), 0.5 * u * u - s * s / 0.6, 1e-12)
le("|s(T) − s(0)|", drift(sol, "spin"), 1e-12)
le("energy drift", drift(sol, "energy"), 1e-11)

# Affine body, separable potential (b128): p_φ, spin p_α = k12 − k21, energy conserved.
sol = fd.solve(fd.Scene(
    manifold={"kind": "H2", "radius": 1.0}, body={"kind": "affine", "mass": 1.0, "inertia": 0.1},
    potential={"kind": "separable", "v_r": {"poly": [0.0, 0.0, 0.2]}, "v_rho": {"poly": [0.0, 0.0, 0.5]}, "v_eps": {"sec_2x": 2.0}},
    r=0.5, phi=0.0, phi_dot=0.5, rho=[[1.1, 0.1], [0.0, 0.9]], rho_dot=[[0.0, 0.1], [0.0, 0.0]],
    method="dopri5", rtol=1e-11, atol=1e-11, t_end=3.0, samples=31,
))
spin = sol["k_12"] - sol["k_21"]
print("H² affine body, separable potential (b128), t ≤ 3:")
le("relative energy drift", drift(sol, "energy") / abs(sol.energy[0]), 1e-9)
le("p_φ drift", drift(sol, "p_phi"), 1e-9)
le("spin p_α = k₁₂ − k₂₁ drift", float(np.max(np.abs(spin - spin[0]))), 1e-9)
finish()
