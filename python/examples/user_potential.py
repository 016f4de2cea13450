"""A user potential as a Python callable ``V(x, e)`` (the Python twin of
``examples/user_potential.rs``).

``x`` is the embedding position (shape ``(E,)``), ``e`` the body frame
(shape ``(N, E)``, the vectors as rows); the callable is added to the
scene's potential and differentiated by finite differences in Rust.

1. The S² Bertrand oscillator (b88) written by hand in ambient coordinates,
   ``(κ/2)R²(x² + y²)/z²``, against the built-in ``oscillator``: same
   energy, same trajectory, and the orbit closes after two radial periods
   ``T_r = π√(mR²/(2E + κR²))``.
2. A dipole ``b⟨e₁, ẑ⟩`` on a gyroscope: energy and ``p_φ`` conserved.

Run: ``python python/examples/user_potential.py`` (exit status 1 if a check fails).
"""

import math

import numpy as np

import framedyn as fd
from _check import drift, finish, le, returned

m, R, kappa = 1.3, 1.2, 0.8


def my_oscillator(x, e):
    return 0.5 * kappa * R * R * (x[0] ** 2 + x[1] ** 2) / x[2] ** 2


def point(t_end, **potential):
    return fd.Scene(
        manifold={"kind": "S2", "radius": R}, body={"kind": "point", "mass": m}, **potential,
        r=0.5, phi=0.0, r_dot=0.0, phi_dot=0.9,
        method="dopri5", rtol=1e-10, atol=1e-10, t_end=t_end, times=[0.0, t_end],
    )


E = float(fd.solve(point(1e-3), user_potential=my_oscillator).energy[0])
E_builtin = float(fd.solve(point(1e-3, potential={"kind": "oscillator", "kappa": kappa})).energy[0])
T_r = math.pi * math.sqrt(m * R * R / (2 * E + kappa * R * R))
mine = fd.solve(point(2 * T_r), user_potential=my_oscillator)
builtin = fd.solve(point(2 * T_r, potential={"kind": "oscillator", "kappa": kappa}))
print(f"S² point, hand-written oscillator (callable): E = {E:.12f}, 2T_r = {2 * T_r:.12f}")
le("|E(callable) − E(built-in)|", abs(E - E_builtin), 1e-13)
le("|x_callable(2T_r) − x_built-in(2T_r)| / R", float(np.linalg.norm(mine.position[-1] - builtin.position[-1])) / R, 1e-7)
le("|x(2T_r) − x(0)| / R (Bertrand: the orbit closes)", returned(mine) / R, 1e-7)

b = 0.4
sol = fd.solve(fd.Scene(
    manifold={"kind": "S2", "radius": R}, body={"kind": "gyroscope", "mass": m, "inertia": 0.25},
    r=0.7, phi=0.0, r_dot=0.2, phi_dot=0.6, alpha=0.0, spin=0.3,
    method="dopri5", rtol=1e-10, atol=1e-10, t_end=2.0, samples=21,
), user_potential=lambda x, e: b * e[0, 2])
print("S² gyroscope with the dipole V = b⟨e₁, ẑ⟩, t ≤ 2:")
le("energy drift", drift(sol, "energy"), 1e-8)
le("p_φ drift", drift(sol, "p_phi"), 1e-8)
finish()
