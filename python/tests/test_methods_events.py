"""Method selection (splittings, implicit midpoint) and events from Python:
built-in ``[[events]]`` kinds, user callables, their errors, and
``solve(save=True)`` / ``Solution.save``."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

import framedyn as fd


def geodesic(**kw):
    """A meridian geodesic on S²(R = 2): r(t) = 0.3 + 0.7 t."""
    d = dict(
        manifold={"kind": "S2", "radius": 2.0},
        body="point",
        r=0.3, phi=0.5, r_dot=0.7,
        method="rk4", h=0.1, t_end=6.0,
    )
    d.update(kw)
    if isinstance(d["method"], dict) and "rtol" in d["method"]:
        d.pop("h")  # adaptive: a fixed h beside rtol is refused
    return fd.Scene(**d)


T_EQUATOR = (math.pi / 2 * 2.0 - 0.3) / 0.7


@pytest.mark.parametrize("method", ["strang", "yoshida4", "suzuki4", "blanes_moan4", "yoshida6", "blanes_moan6", "blanes_moan_rkn4", "blanes_moan_rkn6", "implicit_midpoint"])
def test_new_methods_run_and_conserve(method):
    sol = fd.solve(fd.Scene.example("s2-gyroscope-cosine").replace(method={"name": method, "h": 0.01}, time={"t0": 0.0, "t_end": 1.0}))
    assert sol.stats["stop"] == "finished"
    assert np.max(sol.drift("energy")) < 1e-6
    assert np.max(sol.defect) < 1e-12


def test_splitting_refused_for_affine_body_at_validation():
    scene = fd.Scene.example("s2-affine-elastic").replace(method={"name": "strang", "h": 0.01})
    with pytest.raises(fd.InvalidInputError) as e:
        scene.validate()
    msg = str(e.value)
    assert "method.name" in msg and "strang" in msg and "implicit_midpoint" in msg


def test_newton_options_checked():
    with pytest.raises(fd.InvalidInputError, match="method.newton_tol"):
        fd.Scene.example("t2-point").replace(method={"name": "implicit_midpoint", "newton_tol": 1.0}).validate()
    with pytest.raises(fd.InvalidInputError, match="implicit_midpoint"):
        fd.Scene.example("t2-point").replace(method={"name": "rk4", "newton_max_iter": 5}).validate()


def test_builtin_event_located_to_1e_10():
    d = geodesic().to_dict()
    d["events"] = [{"kind": "plane", "name": "equator", "normal": [0, 0, 1], "terminal": True}]
    sol = fd.solve(fd.Scene.from_dict(d))
    assert sol.events.name == ["equator"]
    assert abs(sol.events.t[0] - T_EQUATOR) < 1e-10
    assert sol.stats["stop"] == "event" and sol.stats["events"] == 1
    assert abs(sol.t[-1] - T_EQUATOR) < 1e-10
    assert sol.events.data.shape == (1, len(sol.columns))
    assert abs(sol.events.data[0, sol.columns.index("x2")]) < 1e-12
    back = pickle.loads(pickle.dumps(sol))
    assert back.events.name == ["equator"] and np.array_equal(back.events.t, sol.events.t)


@pytest.mark.parametrize("method", ["rk4", "strang", "dopri5"])
def test_user_event_located_to_1e_10(method):
    kw = {"method": {"name": method, "rtol": 1e-10}} if method == "dopri5" else {"method": method}
    calls = []

    def equator(t, state):
        calls.append(t)
        return state["x2"]

    sol = fd.solve(geodesic(**kw), events=[fd.Event(equator, "eq", direction="falling"), fd.Event(lambda t, s: s["r"] - 2.0, "r2", direction="rising")])
    assert sol.events.name == ["r2", "eq"]
    assert abs(sol.events.times("eq")[0] - T_EQUATOR) < 1e-10
    assert abs(sol.events.times("r2")[0] - (2.0 - 0.3) / 0.7) < 1e-10
    assert list(sol.events.rising) == [True, False]
    assert calls, "the callable was called"
    # A bare callable is an event too; the falling direction filters it.
    sol = fd.solve(geodesic(**kw), events=lambda t, s: s["x2"])
    assert len(sol.events) == 1 and sol.events.name == ["user0"]
    sol = fd.solve(geodesic(**kw), events=[fd.Event(lambda t, s: s["x2"], direction="rising")])
    assert len(sol.events) == 0


def test_bad_events_are_typed_errors():
    with pytest.raises(fd.InvalidInputError, match="callable"):
        fd.Event(3.0)  # type: ignore[arg-type]
    with pytest.raises(fd.InvalidInputError, match="direction"):
        fd.Event(lambda t, s: 0.0, direction="up")
    with pytest.raises(fd.InvalidInputError, match=r"events\[0\]"):
        fd.solve(geodesic(), events=[3.0])  # type: ignore[list-item]
    d = geodesic().to_dict()
    d["events"] = [{"kind": "column", "column": "nope", "value": 1.0}]
    with pytest.raises(fd.InvalidInputError, match=r"events\[0\]\.column"):
        fd.Scene.from_dict(d).validate()
    d["events"] = [{"kind": "plane", "normal": [0, 1]}]
    with pytest.raises(fd.InvalidInputError, match=r"events\[0\]\.normal"):
        fd.Scene.from_dict(d).validate()


def test_event_returning_nan_or_raising_stops_the_run():
    with pytest.raises(fd.IntegrationError) as e:
        fd.solve(geodesic(), events=[lambda t, s: float("nan")])
    assert "event" in str(e.value)
    assert isinstance(e.value.partial, fd.Solution)

    class Boom(Exception):
        pass

    def boom(t, s):
        if t > 1.0:
            raise Boom("no")
        return s["x2"]

    with pytest.raises(Boom):
        fd.solve(geodesic(), events=[boom])
    with pytest.raises(TypeError):
        fd.solve(geodesic(), events=[lambda t, s: "x"])


def test_solve_save_writes_the_scene_output(tmp_path):
    path = tmp_path / "out.csv"
    scene = geodesic(path=str(path), every=10)
    sol = fd.solve(scene)
    assert not path.exists(), "solve writes nothing unless save=True"
    sol = fd.solve(scene, save=True)
    back = np.loadtxt(path, delimiter=",", skiprows=1)
    header = path.read_text().splitlines()[0].split(",")
    assert header == sol.columns
    np.testing.assert_array_equal(back, sol.data)
    npz = tmp_path / "out.npz"
    sol.save(npz)
    with np.load(npz) as z:
        np.testing.assert_array_equal(z["data"], sol.data)
        assert list(z["columns"]) == sol.columns
    with pytest.raises(fd.InvalidInputError, match="format"):
        sol.save(tmp_path / "x", format="xls")
    with pytest.raises(fd.OutputError):
        sol.save(tmp_path / "missing" / "x.csv")
    with pytest.raises(fd.InvalidInputError, match="save"):
        fd.solve(scene, save="yes")  # type: ignore[arg-type]
