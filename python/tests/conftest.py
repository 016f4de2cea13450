"""Shared scenes for the Python tests."""

from __future__ import annotations

import os

import pytest
from hypothesis import settings

os.environ.setdefault("MPLBACKEND", "Agg")

# Reproducible property tests (as PROPTEST_RNG_SEED for Rust): hypothesis
# derives its examples from the test itself unless FRAMEDYN_HYPOTHESIS_RANDOM=1.
settings.register_profile("framedyn", derandomize=True, database=None)
settings.register_profile("random", derandomize=False)
settings.load_profile("random" if os.environ.get("FRAMEDYN_HYPOTHESIS_RANDOM") == "1" else "framedyn")

import framedyn as fd  # noqa: E402


def pytest_collection_finish(session):
    """Starts test_stubs.py's mypy runs as soon as the tests are collected,
    if any of its tests was selected (they then run beside the others)."""
    for item in session.items:
        if item.module.__name__.endswith("test_stubs") and hasattr(item.module, "start_checks"):
            item.module.start_checks()
            break


def gyro_s2(**kw):
    """A gyroscope on the unit sphere under the cosine potential."""
    d = dict(
        manifold={"kind": "S2", "radius": 1.0},
        body={"kind": "gyroscope", "inertia": 0.2},
        potential={"kind": "cosine", "beta_hat": -0.3},
        r=0.6, phi=0.1, r_dot=-1.0, phi_dot=0.3, spin=0.05,
        method="rk4", h=0.01, t_end=2.0,
    )
    d.update(kw)
    if isinstance(d["method"], dict):
        d.pop("h")
    return fd.Scene(**d)


# One small scene per manifold × a body that lives there.
SCENES = {
    "S2-gyroscope": lambda: gyro_s2(),
    "H2-point": lambda: fd.Scene(
        manifold={"kind": "H2", "radius": 1.5}, body={"kind": "point", "mass": 2.0},
        potential={"kind": "kepler", "alpha": 1.0}, r=1.0, phi=0.0, r_dot=0.1, phi_dot=0.6,
        method="rk4", h=0.005, t_end=2.0,
    ),
    "T2-gyroscope": lambda: fd.Scene(
        manifold={"kind": "T2", "L": 2.0, "R": 0.7}, body={"kind": "gyroscope", "inertia": 0.3},
        theta=0.4, phi=0.0, theta_dot=0.5, phi_dot=0.7, spin=0.1, method="rk4", h=0.005, t_end=2.0,
    ),
    "S3-gyroscope": lambda: fd.Scene(
        manifold={"kind": "S3", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
        potential={"kind": "oscillator", "kappa": 0.5},
        r1=0.2, r2=0.1, r3=-0.3, r1_dot=0.3, r2_dot=0.0, r3_dot=0.2, spin=[0.1, 0.0, 0.2],
        method="rk4", h=0.005, t_end=2.0,
    ),
    "S2-affine": lambda: fd.Scene(
        manifold={"kind": "S2", "radius": 1.0}, body={"kind": "affine", "inertia": 0.1},
        potential={"kind": "elastic", "kappa": 1.0}, r=0.5, phi=0.0, r_dot=0.2, phi_dot=0.4,
        rho=[[1.0, 0.1], [0.0, 0.9]], rho_dot=[[0.0, 0.1], [-0.1, 0.0]],
        method="rk4", h=0.002, t_end=1.0,
    ),
}


@pytest.fixture(params=sorted(SCENES))
def any_scene(request):
    return request.param, SCENES[request.param]()
