"""One trajectory per manifold against scipy's solve_ivp on the paper's
coordinate equations: Euler–Lagrange equations of the chart Lagrangians
L = (m/2) g_ij(q) q̇^i q̇^j − V, written out here by hand (independent of
the Rust code), integrated with DOP853 at tight tolerances."""

import math

import numpy as np
import pytest

scipy_integrate = pytest.importorskip("scipy.integrate")

import framedyn as fd  # noqa: E402

TIMES = [0.25, 0.5, 1.0, 1.5, 2.0]


def reference(rhs, y0):
    sol = scipy_integrate.solve_ivp(rhs, (0.0, TIMES[-1]), y0, method="DOP853", rtol=1e-12, atol=1e-13, t_eval=TIMES)
    assert sol.success
    return sol.y.T


def run(scene):
    sol = fd.solve(scene)
    np.testing.assert_allclose(sol.t, TIMES, atol=1e-12)
    return sol


def common(**kw):
    return dict(method={"name": "dopri5", "rtol": 1e-11, "atol": 1e-13}, t_end=TIMES[-1], output={"times": TIMES}, **kw)


def test_s2_point_oscillator():
    # L = (m/2)(ṙ² + R² sin²(r/R) φ̇²) − V,  V = (κ/2) R² tan²(r/R)  (paper (b88))
    m, R, k = 1.3, 2.0, 0.7

    def rhs(t, y):
        r, phi, rd, phid = y
        f, fp = R * math.sin(r / R), math.cos(r / R)
        dV = k * R * math.tan(r / R) / math.cos(r / R) ** 2
        return [rd, phid, f * fp * phid**2 - dV / m, -2 * fp / f * rd * phid]

    y0 = [0.8, 0.3, 0.2, 0.9]
    ref = reference(rhs, y0)
    sol = run(fd.Scene({"kind": "S2", "radius": R}, {"kind": "point", "mass": m}, potential={"kind": "oscillator", "kappa": k},
                       r=y0[0], phi=y0[1], r_dot=y0[2], phi_dot=y0[3], **common()))
    c = sol.coordinates
    np.testing.assert_allclose(np.c_[c["r"], c["r_dot"], c["phi_dot"]], ref[:, [0, 2, 3]], atol=1e-8)
    np.testing.assert_allclose(np.remainder(c["phi"] - ref[:, 1] + math.pi, 2 * math.pi) - math.pi, 0.0, atol=1e-8)


def test_h2_point_kepler():
    # L = (m/2)(ṙ² + R² sinh²(r/R) φ̇²) − V,  V = −(α/R) coth(r/R)  (paper (b133))
    m, R, a = 0.8, 1.5, 0.6

    def rhs(t, y):
        r, phi, rd, phid = y
        f, fp = R * math.sinh(r / R), math.cosh(r / R)
        dV = (a / R**2) / math.sinh(r / R) ** 2
        return [rd, phid, f * fp * phid**2 - dV / m, -2 * fp / f * rd * phid]

    y0 = [1.2, -0.4, 0.1, 0.5]
    ref = reference(rhs, y0)
    sol = run(fd.Scene({"kind": "H2", "radius": R}, {"kind": "point", "mass": m}, potential={"kind": "kepler", "alpha": a},
                       r=y0[0], phi=y0[1], r_dot=y0[2], phi_dot=y0[3], **common()))
    c = sol.coordinates
    np.testing.assert_allclose(np.c_[c["r"], c["phi"], c["r_dot"], c["phi_dot"]], ref, atol=1e-8)


def test_t2_point_geodesic():
    # L = (m/2)(R² θ̇² + (L + R cos θ)² φ̇²): geodesics of the torus.
    Lm, R = 2.0, 0.7

    def rhs(t, y):
        th, phi, thd, phid = y
        rho = Lm + R * math.cos(th)
        return [thd, phid, -rho * math.sin(th) * phid**2 / R, 2 * R * math.sin(th) * thd * phid / rho]

    y0 = [0.4, 0.0, 1.1, 0.6]
    ref = reference(rhs, y0)
    sol = run(fd.Scene({"kind": "T2", "L": Lm, "R": R}, "point",
                       theta=y0[0], phi=y0[1], theta_dot=y0[2], phi_dot=y0[3], **common()))
    c = sol.coordinates
    wrap = lambda d: np.remainder(d + math.pi, 2 * math.pi) - math.pi  # noqa: E731
    np.testing.assert_allclose(wrap(c["theta"] - ref[:, 0]), 0.0, atol=1e-8)
    np.testing.assert_allclose(wrap(c["phi"] - ref[:, 1]), 0.0, atol=1e-8)
    np.testing.assert_allclose(np.c_[c["theta_dot"], c["phi_dot"]], ref[:, 2:], atol=1e-8)


def test_s3_point_oscillator():
    # Hyperspherical coordinates (χ, ϑ, φ): L = (m R²/2)(χ̇² + sin²χ (ϑ̇² + sin²ϑ φ̇²)) − V(Rχ),
    # V = (κ/2) R² tan²(χ); the paper's chart is r̄ = Rχ·n(ϑ, φ) (§6).
    m, R, k = 1.0, 1.2, 0.4

    def rhs(t, y):
        chi, th, phi, chid, thd, phid = y
        s, c = math.sin(chi), math.cos(chi)
        dV = k * R * math.tan(chi) / math.cos(chi) ** 2  # dV/dr
        return [
            chid, thd, phid,
            s * c * (thd**2 + math.sin(th) ** 2 * phid**2) - dV / (m * R),
            math.sin(th) * math.cos(th) * phid**2 - 2 * c / s * chid * thd,
            -2 * c / s * chid * phid - 2 * math.cos(th) / math.sin(th) * thd * phid,
        ]

    def rbar(chi, th, phi, chid, thd, phid):
        n = np.array([math.sin(th) * math.cos(phi), math.sin(th) * math.sin(phi), math.cos(th)])
        dn = np.array([
            math.cos(th) * math.cos(phi) * thd - math.sin(th) * math.sin(phi) * phid,
            math.cos(th) * math.sin(phi) * thd + math.sin(th) * math.cos(phi) * phid,
            -math.sin(th) * thd,
        ])
        return R * chi * n, R * chid * n + R * chi * dn

    y0 = [0.5, 1.0, 0.3, 0.2, -0.3, 0.8]
    ref = reference(rhs, y0)
    r0, rd0 = rbar(*y0)
    sol = run(fd.Scene({"kind": "S3", "radius": R}, "point", potential={"kind": "oscillator", "kappa": k},
                       r1=r0[0], r2=r0[1], r3=r0[2], r1_dot=rd0[0], r2_dot=rd0[1], r3_dot=rd0[2], **common()))
    c = sol.coordinates
    got = np.c_[c["r1"], c["r2"], c["r3"], c["r1_dot"], c["r2_dot"], c["r3_dot"]]
    want = np.array([np.concatenate(rbar(*row)) for row in ref])
    np.testing.assert_allclose(got, want, atol=1e-8)
    # And in the embedding ℝ⁴: x = R(cos χ, sin χ n).
    n = want[:, :3] / np.linalg.norm(want[:, :3], axis=1)[:, None]
    x = np.c_[R * np.cos(ref[:, 0]), R * np.sin(ref[:, 0])[:, None] * n]
    np.testing.assert_allclose(sol.position, x, atol=1e-8)
