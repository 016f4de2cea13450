"""framedyn.solve: arrays, geometry of the records, invariants, convergence
order, failures with partial solutions, user potentials, Ctrl-C."""

import math
import os
import signal
import threading
import time
import warnings

import numpy as np
import pytest

import framedyn as fd

from conftest import SCENES, gyro_s2


def minkowski(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] - a[..., 2] * b[..., 2]


def test_arrays_and_shapes(any_scene):
    name, scene = any_scene
    sol = fd.solve(scene)
    n = len(sol)
    E = 4 if name.startswith("S3") else 3
    assert n == sol.stats["records"] >= 2
    assert sol.t.shape == (n,) and sol.t[0] == 0.0 and sol.t[-1] == pytest.approx(scene.to_dict()["time"]["t_end"])
    assert sol.position.shape == (n, E) and sol.velocity.shape == (n, E)
    if "point" in name:
        assert sol.frame.shape[1] == 0
    else:
        assert sol.frame.shape == (n, 3 if E == 4 else 2, E)
    assert sol.energy.shape == sol.defect.shape == (n,)
    assert sol.data.shape == (n, len(sol.columns)) and sol.data.dtype == np.float64
    # Views of the one array the core produced (no copies).
    assert np.shares_memory(sol.position, sol.data) and np.shares_memory(sol.energy, sol.data)
    assert sol.stats["stop"] == "finished" and sol.stats["steps"] > 0
    assert sol.stats["max_defect"] < 1e-12
    for k in sol.momentum_maps:
        assert sol.unit(k) == "M L^2/T"


def test_records_lie_on_the_manifold(any_scene):
    name, scene = any_scene
    sol = fd.solve(scene)
    man = scene.to_dict()["manifold"]
    x, f = sol.position, sol.frame
    if man["kind"] in ("S2", "S3"):
        R = man["radius"]
        np.testing.assert_allclose(np.linalg.norm(x, axis=1), R, rtol=1e-12)
        if f.shape[1]:
            # Tangent frames; orthonormal for gyroscopes (e = q·ρ for affine bodies).
            np.testing.assert_allclose(np.einsum("nae,ne->na", f, x), 0.0, atol=1e-12)
            if "gyroscope" in name:
                np.testing.assert_allclose(np.einsum("nae,nbe->nab", f, f), np.broadcast_to(np.eye(f.shape[1]), (len(sol), f.shape[1], f.shape[1])), atol=1e-12)
    elif man["kind"] == "H2":
        R = man["radius"]
        np.testing.assert_allclose(-minkowski(x, x), R**2, rtol=1e-12)
        assert (x[:, 2] > 0).all()
    else:
        L, R = man["L"] if "L" in man else man["major"], man["R"] if "R" in man else man["minor"]
        rho = np.hypot(x[:, 0], x[:, 1])
        np.testing.assert_allclose((rho - L) ** 2 + x[:, 2] ** 2, R**2, rtol=1e-12)
        np.testing.assert_allclose(np.einsum("nae,nbe->nab", f, f), np.broadcast_to(np.eye(2), (len(sol), 2, 2)), atol=1e-12)


def test_paper_coordinates_match_the_embedding():
    """The documented embeddings of the paper's charts (docs/conventions.md)
    applied to the coordinate columns give the position columns."""
    for name in ("S2-gyroscope", "H2-point", "T2-gyroscope", "S3-gyroscope"):
        scene = SCENES[name]()
        sol = fd.solve(scene)
        c, x = sol.coordinates, sol.position
        man = scene.to_dict()["manifold"]
        if man["kind"] == "S2":
            R = man["radius"]
            th = c["r"] / R
            y = R * np.stack([np.sin(th) * np.cos(c["phi"]), np.sin(th) * np.sin(c["phi"]), np.cos(th)], 1)
        elif man["kind"] == "H2":
            R = man["radius"]
            th = c["r"] / R
            y = R * np.stack([np.sinh(th) * np.cos(c["phi"]), np.sinh(th) * np.sin(c["phi"]), np.cosh(th)], 1)
        elif man["kind"] == "T2":
            L, R = man["major"], man["minor"]
            y = np.stack([(L + R * np.cos(c["theta"])) * np.cos(c["phi"]), (L + R * np.cos(c["theta"])) * np.sin(c["phi"]), R * np.sin(c["theta"])], 1)
        else:
            R = man["radius"]
            rv = np.stack([c["r1"], c["r2"], c["r3"]], 1)
            r = np.linalg.norm(rv, axis=1)
            y = np.concatenate([R * np.cos(r / R)[:, None], R * np.sin(r / R)[:, None] * rv / r[:, None]], 1)
        np.testing.assert_allclose(y, x, atol=1e-12, err_msg=name)


def test_invariants_conserved():
    # Rotationally symmetric potentials: p_phi is conserved; the spin of a
    # gyroscope under a frame-independent potential too.
    for name in ("S2-gyroscope", "H2-point", "T2-gyroscope"):
        sol = fd.solve(SCENES[name]())
        assert sol.drift("p_phi").max() < 1e-9, name
        assert sol.drift("energy").max() < 1e-9, name
    sol = fd.solve(SCENES["S2-gyroscope"]())
    assert sol.drift("spin").max() < 1e-12


def test_rk4_convergence_order():
    """The error at t_end against a 1/16-step reference falls like h^4
    (least-squares slope over four step sizes)."""
    hs = np.array([0.04, 0.02, 0.01, 0.005])
    ref = fd.solve(gyro_s2(h=hs[-1] / 16, output={"samples": 2})).position[-1]
    errs = [np.linalg.norm(fd.solve(gyro_s2(h=h, output={"samples": 2})).position[-1] - ref) for h in hs]
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert 3.7 < slope < 4.3, (slope, errs)


def test_output_sampling():
    sol = fd.solve(gyro_s2(output={"times": [0.5, 1.0, 1.5], "quantities": ["position", "energy"]}))
    np.testing.assert_allclose(sol.t, [0.5, 1.0, 1.5], rtol=0, atol=1e-12)
    assert sol.columns == ["t", "x0", "x1", "x2", "energy"]
    with pytest.raises(KeyError, match="no column 'defect'"):
        sol.defect


def test_adaptive_method():
    sol = fd.solve(gyro_s2(method={"name": "dopri5", "rtol": 1e-10, "atol": 1e-12}))
    # The summary names the method by the registry's display name.
    assert sol.stats["method"] == next(m["display"] for m in fd.methods() if m["name"] == "dopri5")
    ref = fd.solve(gyro_s2(h=0.001, output={"samples": 2})).position[-1]
    assert np.linalg.norm(sol.position[-1] - ref) < 1e-8


def test_integration_failure_carries_partial_solution():
    s = gyro_s2(method={"name": "dopri5", "rtol": 1e-12, "atol": 1e-14, "max_steps": 5})
    with pytest.raises(fd.IntegrationError, match="maximum number of steps") as ei:
        fd.solve(s)
    p = ei.value.partial
    assert isinstance(p, fd.Solution)
    assert 1 <= len(p) and p.t[-1] < 2.0
    assert p.stats["stop"] == "failed"


# -- user potentials ------------------------------------------------------------


def test_user_potential_equals_the_builtin():
    """V = β̂ cos(r/R) = β̂ x₂/R written by hand agrees with the built-in
    cosine potential (the user gradient is by finite differences)."""
    beta = -0.3
    builtin = fd.solve(gyro_s2())
    calls = []

    def V(x, e):
        calls.append((x.shape, e.shape))
        return beta * x[2]

    user = fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=V)
    assert calls[0] == ((3,), (2, 3))
    np.testing.assert_allclose(user.position, builtin.position, atol=1e-8)
    np.testing.assert_allclose(user.energy, builtin.energy, atol=1e-8)


def test_frame_dependent_user_potential_conserves_energy():
    def V(x, e):
        return 0.2 * e[0, 2]  # couples the body frame to the ambient z axis

    sol = fd.solve(gyro_s2(potential={"kind": "none"}, h=0.005), user_potential=V)
    assert sol.drift("energy").max() < 1e-8
    assert sol.drift("spin").max() > 1e-4  # the torque changes the spin


def test_supplied_gradient_equals_the_builtin_to_round_off():
    """With its exact gradient supplied, the hand-written β̂ x₂/R is the
    built-in cosine potential up to round-off (no differencing error), and
    each evaluation calls V and G once instead of ~20 times per coordinate."""
    beta = -0.3
    builtin = fd.solve(gyro_s2())
    n_v, n_g = [0], [0]

    def V(x, e):
        n_v[0] += 1
        return beta * x[2]

    def G(x, e):
        n_g[0] += 1
        assert x.shape == (3,) and e.shape == (2, 3)
        return np.array([0.0, 0.0, beta]), np.zeros((2, 3))

    sol = fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=V, user_gradient=G)
    np.testing.assert_allclose(sol.position, builtin.position, rtol=0, atol=1e-13)
    np.testing.assert_allclose(sol.energy, builtin.energy, rtol=0, atol=1e-13)
    assert n_g[0] >= 4 * sol.stats["steps"]  # RK4: four forces per step
    assert n_v[0] <= 2 * n_g[0]  # no differencing


def test_supplied_frame_gradient_matches_the_differenced_one():
    """A frame-dependent V = 0.2 e₁ᶻ + 0.1 (e₂ᶻ)² with its gradient gives the
    trajectory of the differenced gradient (to the differences' accuracy),
    conserves energy, and a wrong gradient (sign flipped in ∂V/∂e) is seen
    in the energy drift."""

    def V(x, e):
        return 0.2 * e[0, 2] + 0.1 * e[1, 2] ** 2

    def G(x, e):
        de = np.zeros((2, 3))
        de[0, 2] = 0.2
        de[1, 2] = 0.2 * e[1, 2]
        return np.zeros(3), de

    def G_wrong(x, e):
        dx, de = G(x, e)
        return dx, -de

    scene = gyro_s2(potential={"kind": "none"}, h=0.005)
    fdiff = fd.solve(scene, user_potential=V)
    exact = fd.solve(scene, user_potential=V, user_gradient=G)
    np.testing.assert_allclose(exact.frame, fdiff.frame, rtol=0, atol=1e-9)
    assert exact.drift("energy").max() < 1e-8
    # A wrong gradient breaks energy conservation, and the quality check says so.
    with pytest.warns(fd.QualityWarning, match="energy drift"):
        wrong = fd.solve(scene, user_potential=V, user_gradient=G_wrong)
    assert wrong.drift("energy").max() > 1e-4


def test_supplied_gradient_in_batch_and_stepper():
    beta = -0.3

    def V(x, e):
        return beta * x[2]

    def G(x, e):
        return [0.0, 0.0, beta], [[0, 0, 0], [0, 0, 0]]  # lists and ints are accepted

    scenes = [gyro_s2(potential={"kind": "none"}, r=r) for r in (0.4, 0.7)]
    batch = fd.solve_batch(scenes, user_potential=V, user_gradient=G, threads=2)
    for s, b in zip(scenes, batch):
        np.testing.assert_array_equal(b.data, fd.solve(s, user_potential=V, user_gradient=G).data)
    st = fd.Stepper(scenes[0], user_potential=V, user_gradient=G)
    st.advance(0.005, 10)
    ref = fd.Stepper(gyro_s2(r=0.4))
    ref.advance(0.005, 10)
    assert abs(st.energy - ref.energy) < 1e-13


@pytest.mark.parametrize(
    "G, match",
    [
        (lambda x, e: np.zeros(3), r"pair"),
        (lambda x, e: (np.zeros(2), np.zeros((2, 3))), r"dV/dx has shape \[2\].*shape \[3\]"),
        (lambda x, e: (np.zeros(3), np.zeros(6)), r"dV/de has shape \[6\].*shape \[2, 3\]"),
        (lambda x, e: (np.zeros(3), "abc"), r"dV/de has no numeric array form"),
    ],
)
def test_supplied_gradient_wrong_shapes_name_the_argument(G, match):
    with pytest.raises(fd.InvalidInputError, match=match) as ei:
        fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=lambda x, e: 0.0, user_gradient=G)
    assert "user_gradient" in str(ei.value)
    assert isinstance(ei.value.partial, fd.Solution)


def test_supplied_gradient_needs_the_potential_and_must_be_callable():
    with pytest.raises(fd.InvalidInputError, match="user_gradient given without user_potential"):
        fd.solve(gyro_s2(), user_gradient=lambda x, e: (np.zeros(3), np.zeros((2, 3))))
    with pytest.raises(fd.InvalidInputError, match="user_gradient: a float is not callable"):
        fd.solve(gyro_s2(), user_potential=lambda x, e: 0.0, user_gradient=1.5)


def test_supplied_gradient_exception_propagates():
    class Boom(Exception):
        pass

    def G(x, e):
        raise Boom("from the gradient")

    with pytest.raises(Boom, match="from the gradient") as ei:
        fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=lambda x, e: 0.0, user_gradient=G)
    assert isinstance(ei.value.partial, fd.Solution)


def test_user_potential_exception_propagates():
    class Boom(Exception):
        pass

    n = [0]

    def V(x, e):
        n[0] += 1
        if n[0] > 50:
            raise Boom("from the user potential")
        return 0.0

    with pytest.raises(Boom, match="from the user potential") as ei:
        fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=V)
    assert isinstance(ei.value.partial, fd.Solution)


def test_user_potential_nan_is_an_integration_error():
    with pytest.raises(fd.IntegrationError, match="non-finite"):
        fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=lambda x, e: float("nan"))


def test_user_potential_wrong_return_type():
    with pytest.raises(TypeError, match=r"user_potential\(x, e\) returned a str; it must return a float"):
        fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=lambda x, e: "zero")
    with pytest.raises(TypeError, match="user_potential.*returned a NoneType"):
        fd.solve(gyro_s2(potential={"kind": "none"}), user_potential=lambda x, e: None)
    with pytest.raises(TypeError, match="event function.*returned a str"):
        fd.solve(gyro_s2(), events=[lambda t, state: "up"])


def test_user_potential_not_callable():
    with pytest.raises(fd.InvalidInputError, match="user_potential"):
        fd.solve(gyro_s2(), user_potential=3.0)


def test_solve_rejects_non_scenes():
    with pytest.raises(fd.InvalidInputError, match="scene"):
        fd.solve(42)
    assert len(fd.solve(gyro_s2().to_dict())) == len(fd.solve(gyro_s2()))


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals go to the main thread")
def test_ctrl_c_stops_a_long_run():
    s = gyro_s2(h=1e-3, t_end=1e5, output={"every": 10_000_000})  # ~1e8 steps: minutes
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    # A process started in the background by a non-interactive shell
    # (`cmd &`) inherits SIGINT ignored, and Python then installs no handler:
    # the signal would be dropped before framedyn could see it. Install
    # Python's own handler for the test (what an interactive session has).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    t0 = time.monotonic()
    timer.start()
    try:
        sol = fd.solve(s)
    except KeyboardInterrupt:
        pass
    else:
        pytest.fail(f"no KeyboardInterrupt: solve returned after {time.monotonic() - t0:.2f} s, stats {sol.stats}")
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.monotonic() - t0 < 10.0


def test_quality_warning_on_a_crude_run():
    d = fd.Scene.example("s2-gyroscope-pole").to_dict()
    d["method"] = {"name": "lie_euler", "h": 0.05}
    with pytest.warns(fd.QualityWarning, match="energy drift .* exceeds quality.energy_drift"):
        sol = fd.solve(d)
    assert len(sol) == 21 and sol.stats["warnings"] and "energy drift" in sol.stats["warnings"][0]
    with pytest.warns(fd.QualityWarning, match="solve_batch: 2 of 2 members failed the quality check .* member 0: the energy drift"):
        out = fd.solve_batch(fd.Scene.from_dict(d), {"initial.r": np.array([0.6, 0.61])}, keep="final")
    assert all(w and "energy drift" in w[0] for w in out.warnings) and out.warnings.flagged.tolist() == [0, 1]
    d["quality"] = {"energy_drift": 1.0}
    with warnings.catch_warnings():
        warnings.simplefilter("error", fd.QualityWarning)
        assert fd.solve(d).stats["warnings"] == []
    assert fd.solve(fd.Scene.example("s2-gyroscope-pole")).stats["warnings"] == []


def test_global_error_estimate_only_when_asked():
    """`global_error=True` puts an estimate of the run's error into the stats
    (max over the records, and at the last one), within a factor 3 of the
    error against a fixed-step reference; without it there is none and the
    run is the same."""
    kw = dict(manifold="H2", body={"kind": "gyroscope", "inertia": 0.2}, potential={"kind": "kepler", "alpha": 1.0},
              r=1.0, phi=0.0, r_dot=0.0, phi_dot=0.3, spin=0.1, t_end=8.0, samples=81)
    ref = fd.solve(fd.Scene(**kw, method="dop853", h=1e-4))
    plain = fd.solve(fd.Scene(**kw, method="dop853", rtol=1e-8, atol=1e-8))
    sol = fd.solve(fd.Scene(**kw, method="dop853", rtol=1e-8, atol=1e-8, global_error=True))
    assert "global_error" not in plain.stats
    np.testing.assert_array_equal(plain.data, sol.data)
    rel = lambda a, b: np.linalg.norm(a - b, axis=-1) / (1 + np.linalg.norm(b, axis=-1))
    err = np.max([rel(sol.position, ref.position), rel(sol.velocity, ref.velocity),
                  rel(sol.frame[:, 0], ref.frame[:, 0]), rel(sol.frame[:, 1], ref.frame[:, 1]),
                  np.abs(sol.momenta["spin"] - ref.momenta["spin"]) / (1 + np.abs(ref.momenta["spin"]))], axis=0)
    assert 1 / 3 <= sol.stats["global_error"] / err.max() <= 3
    assert 1 / 3 <= sol.stats["global_error_final"] / err[-1] <= 3
    assert sol.stats["global_error_rhs_evals"] > sol.stats["rhs_evals"]


def test_energy_projection_when_asked():
    """`project="energy"` puts every accepted step back on the initial
    energy: on the H² gyroscope's Kepler passage DOP853 at tol 1e-8 lands
    within 30 × tol of a fixed-step reference instead of hundreds of times
    tol; the energy at the step ends holds to round-off; the stats count the
    projections; a batch projects each member as `fd.solve` does; any other
    value is a ValueError naming `method.project`."""
    kw = dict(manifold="H2", body={"kind": "gyroscope", "inertia": 0.2}, potential={"kind": "kepler", "alpha": 1.0},
              r=1.0, phi=0.0, r_dot=0.0, phi_dot=0.3, spin=0.1, t_end=8.0, method="dop853")
    ref = fd.solve(fd.Scene(**kw, h=1e-4, samples=81))
    rel = lambda a, b: np.linalg.norm(a - b, axis=-1) / (1 + np.linalg.norm(b, axis=-1))

    def error(sol):
        return np.max([rel(sol.position, ref.position), rel(sol.velocity, ref.velocity),
                       rel(sol.frame[:, 0], ref.frame[:, 0]), rel(sol.frame[:, 1], ref.frame[:, 1])])

    tol = dict(rtol=1e-8, atol=1e-8)
    projected = fd.solve(fd.Scene(**kw, **tol, samples=81, project="energy"))
    plain = fd.solve(fd.Scene(**kw, **tol, samples=81))
    assert error(projected) < 30e-8 and error(plain) > 300e-8
    assert "projected_steps" not in plain.stats
    steps = fd.solve(fd.Scene(**kw, **tol, project="energy"))  # records at the step ends
    assert steps.stats["relative_energy_drift"] < 1e-13
    assert steps.stats["projected_steps"] == steps.stats["steps"] and steps.stats["projection_skipped"] == 0
    assert steps.stats["energy_evals"] > steps.stats["steps"]
    assert steps.stats["warnings"] == []
    rs = np.array([0.8, 1.0])
    batch = fd.solve_batch(fd.Scene(**kw, **tol, samples=5, project="energy"), {"initial.r": rs}, threads=1)
    for i, r in enumerate(rs):
        one = fd.solve(fd.Scene(**{**kw, "r": r}, **tol, samples=5, project="energy"))
        np.testing.assert_array_equal(batch.position[i], one.position)
    for bad in ["momentum", "Energy", 1, True]:
        with pytest.raises(ValueError, match="method.project"):
            fd.solve(fd.Scene(**kw, **tol, project=bad))
    # The stepping API projects as a run does, back to the initial energy.
    st = fd.Stepper(fd.Scene(**{**kw, "method": "rk4"}, h=0.01, project="energy"))
    plain = fd.Stepper(fd.Scene(**{**kw, "method": "rk4"}, h=0.01))
    e0 = st.energy
    for _ in range(20):
        st.step(0.01)
        plain.step(0.01)
    st.advance(0.01, 100)
    plain.advance(0.01, 100)
    assert abs(st.energy - e0) < 1e-12 * abs(e0) and abs(plain.energy - e0) > 1e-9 * abs(e0)


def test_ensemble_members_carry_their_global_error_estimate():
    """A batch whose scene asks for the estimate reports each member's in its
    stats, equal to the member's own `fd.solve`; a batch that does not ask
    has NaN there."""
    kw = dict(manifold="S2", body={"kind": "gyroscope", "inertia": 0.2}, potential={"kind": "cosine", "beta_hat": -0.3},
              r=0.6, phi=0.0, r_dot=-1.0, spin=0.02, method="dopri5", rtol=1e-7, atol=1e-7, t_end=3.0, samples=11)
    rs = np.array([0.4, 0.6, 0.8])
    asked = fd.solve_batch(fd.Scene(**kw, global_error=True), {"initial.r": rs}, threads=1)
    for i, r in enumerate(rs):
        one = fd.solve(fd.Scene(**{**kw, "r": r}, global_error=True))
        assert asked.stats["global_error"][i] == one.stats["global_error"]
        assert asked.stats["global_error_final"][i] == one.stats["global_error_final"]
    assert (asked.stats["global_error"] > 0).all()
    plain = fd.solve_batch(fd.Scene(**kw), {"initial.r": rs}, threads=1)
    assert np.isnan(plain.stats["global_error"]).all() and np.isnan(plain.stats["global_error_final"]).all()
