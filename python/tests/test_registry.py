"""What the Python package reads from the core instead of copying: the
method registry (every method runs from Python), the manifolds and their
coordinate names (the ``initial`` keywords), the column groups, and the one
writer of record files (``Solution.save`` writes exactly what ``framedyn
run`` writes)."""

from __future__ import annotations

import shutil
import subprocess
import sys

import warnings

import numpy as np
import pytest

import framedyn as fd

from conftest import gyro_s2


def away_from_pole(method, h):
    """The S² gyroscope away from the chart's pole (so that the coordinate
    methods apply), run to t = 1."""
    return gyro_s2(r=1.2, phi=0.3, r_dot=0.4, phi_dot=0.5, method={"name": method, "h": h}, t_end=1.0, every=1000000)


def test_methods_are_the_registry():
    ms = fd.methods()
    names = [m["name"] for m in ms]
    assert len(set(names)) == len(names) and "rk4" in names and "coordinate_rk4" in names
    for m in ms:
        assert set(m) == {"name", "display", "family", "order", "embedded_order", "adaptive", "needs", "needs_text", "params", "summary"}
        assert m["adaptive"] == (m["embedded_order"] is not None)
        assert m["family"] in ("RKMK", "splitting", "implicit", "coordinate")


@pytest.mark.parametrize("method", [m["name"] for m in fd.methods()])
def test_every_registry_method_runs_from_python(method):
    entry = {m["name"]: m for m in fd.methods()}[method]
    ref = fd.solve(away_from_pole("butcher6", 1e-3)).position[-1]
    h = 0.01
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", fd.QualityWarning)
        sol = fd.solve(away_from_pole(method, h))
    # A warning exactly when the relative energy drift exceeds the default limit.
    assert bool(caught) == (sol.stats["relative_energy_drift"] > 1e-3), (method, sol.stats["relative_energy_drift"])
    assert sol.stats["method"] == entry["display"]
    assert sol.stats["stop"] == "finished"
    err = np.linalg.norm(sol.position[-1] - ref)
    assert err <= max(10.0 * h ** entry["order"], 1e-12), f"{method}: {err:e}"
    st = fd.Stepper(away_from_pole(method, h))
    assert st.method == entry["display"]
    st.advance(h, 3)
    assert st.t == pytest.approx(3 * h)


def test_coordinate_methods_fail_at_the_pole_with_the_partial_records():
    # A geodesic of S² passing 1e-6 from the pole at t ≈ 1.
    r0, lz = 1.0, 1e-6
    phi_dot = lz / np.sin(r0) ** 2
    r_dot = -np.sqrt(1.0 - (np.sin(r0) * phi_dot) ** 2)
    scene = fd.Scene(
        manifold={"kind": "S2", "radius": 1.0}, body="point",
        r=r0, phi=0.0, r_dot=r_dot, phi_dot=phi_dot, method="coordinate_rk4", h=0.01, t_end=2.0,
    )
    with pytest.raises(fd.IntegrationError, match="chart") as e:
        fd.solve(scene)
    part = e.value.partial
    assert isinstance(part, fd.Solution) and 0.9 < part.t[-1] < 1.1
    assert np.all(np.isfinite(part.position))
    # The group method on the same scene goes through.
    sol = fd.solve(scene.replace(method={"name": "rk4", "h": 0.01}))
    assert sol.stats["stop"] == "finished"


def test_manifolds_and_initial_fields_come_from_the_core():
    ms = fd.manifolds()
    assert ms["S2"]["coordinates"] == ["r", "phi"]
    assert ms["T2"]["coordinates"] == ["theta", "phi"]
    assert ms["S3"]["coordinates"] == ["r1", "r2", "r3"]
    for spec in ms.values():
        for c in spec["coordinates"]:
            assert c in fd.INITIAL_FIELDS and f"{c}_dot" in fd.INITIAL_FIELDS
    for f in ("position", "velocity", "frame", "alpha", "spin", "rho", "rho_dot"):
        assert f in fd.INITIAL_FIELDS


def test_column_groups_come_from_the_core(any_scene):
    _, scene = any_scene
    sol = fd.solve(scene)
    assert len(sol.groups) == len(sol.columns) and sol.groups[0] is None
    n, e = sol.frame_shape
    assert sol.position.shape == (len(sol), e)
    assert sol.velocity.shape == (len(sol), e)
    if n:
        assert sol.frame.shape == (len(sol), n, e)
        np.testing.assert_array_equal(sol.frame[:, 0, :], np.stack([sol[f"e1_{i}"] for i in range(e)], axis=1))
    for name in sol.coordinates:
        assert sol.groups[sol.columns.index(name)] == "coordinates"
    assert set(sol.momentum_maps) <= {c for c, g in zip(sol.columns, sol.groups) if g == "momentum_map"}


@pytest.mark.parametrize("fmt", ["csv", "npz"])
def test_save_writes_the_bytes_the_cli_writes(tmp_path, fmt):
    exe = shutil.which("framedyn", path=sys.prefix + "/bin")
    scene = fd.Scene.example("h2-gyroscope")
    path = tmp_path / f"scene.toml"
    path.write_text(scene.to_toml())
    cli_out = tmp_path / f"cli.{fmt}"
    out = subprocess.run([exe, "run", str(path), "--output", str(cli_out), "--quiet"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    py_out = tmp_path / f"py.{fmt}"
    fd.solve(scene).save(py_out)
    assert py_out.read_bytes() == cli_out.read_bytes()


def test_frame_rate_is_the_tangential_rate_of_the_frame():
    scene = fd.Scene(
        manifold={"kind": "S2", "radius": 1.0}, body={"kind": "affine", "inertia": 0.1},
        potential={"kind": "elastic", "kappa": 1.0}, r=0.5, phi=0.0, r_dot=0.2, phi_dot=0.4,
        rho=[[1.0, 0.1], [0.0, 0.9]], rho_dot=[[0.0, 0.1], [-0.1, 0.0]],
        method="rk4", h=1e-3, t_end=0.2,
    )
    sol = fd.solve(scene)
    de, e, x = sol.frame_rate, sol.frame, sol.position
    assert de.shape == e.shape == (len(sol), 2, 3)
    # Tangent to the unit sphere: x·De/Dt = 0.
    assert np.max(np.abs(np.einsum("ni,nai->na", x, de))) < 1e-12
    # The tangential part of the central difference of e, to O(h²).
    dt = sol.t[1] - sol.t[0]
    fd_rate = (e[2:] - e[:-2]) / (2 * dt)
    xm = x[1:-1]
    tangential = fd_rate - np.einsum("ni,nai->na", xm, fd_rate)[:, :, None] * xm[:, None, :]
    assert np.max(np.abs(tangential - de[1:-1])) < 1e-5 * np.max(np.abs(de))
    assert fd.solve(fd.Scene.example("s2-gyroscope-pole")).frame_rate.shape[1] == 0
