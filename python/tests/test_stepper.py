"""framedyn.Stepper: the stepping API agrees with a run, resets, errors."""

import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import framedyn as fd

from conftest import SCENES, gyro_s2


def test_stepper_reaches_the_run_final_state(any_scene):
    name, scene = any_scene
    d = scene.to_dict()
    h, t_end = d["method"]["h"], d["time"]["t_end"]
    n = round(t_end / h)
    st = fd.Stepper(scene)
    assert st.span == (0.0, t_end) and st.t == 0.0
    st.advance(h, n)
    assert st.t == pytest.approx(t_end, abs=1e-9)
    sol = fd.solve(scene)
    row = st.row()
    assert row.shape == (len(sol.columns),) and st.columns == sol.columns
    # Same method, same steps (the run may split the span into equal steps).
    np.testing.assert_allclose(row[1:], sol.data[-1, 1:], rtol=0, atol=1e-9)
    assert st.energy == pytest.approx(sol.energy[-1], abs=1e-9)
    assert st.defect < 1e-12


def test_step_and_reset():
    st = fd.Stepper(gyro_s2())
    s0 = st.state()
    st.step(0.01)
    st.step(0.01)
    assert st.t == pytest.approx(0.02)
    assert st.state() != s0
    st.reset()
    assert st.t == 0.0 and st.state() == s0
    st.step(-0.01)  # backwards
    assert st.t == pytest.approx(-0.01)
    assert st.method == {m["name"]: m for m in fd.methods()}["rk4"]["display"]
    assert "Stepper" in repr(st)


@pytest.mark.parametrize("h", [0.0, math.nan, math.inf])
def test_bad_step_sizes(h):
    st = fd.Stepper(gyro_s2())
    with pytest.raises(fd.InvalidInputError, match="h"):
        st.step(h)


def test_bad_arguments():
    st = fd.Stepper(gyro_s2())
    with pytest.raises(fd.InvalidInputError, match="`h`"):
        st.step("0.1")
    with pytest.raises(fd.InvalidInputError, match="`n`"):
        st.advance(0.1, -1)
    with pytest.raises(fd.InvalidInputError, match="`n`"):
        st.advance(0.1, 2.5)
    with pytest.raises(fd.InvalidInputError, match="scene"):
        fd.Stepper(None)
    with pytest.raises(fd.InvalidInputError, match="body"):
        fd.Stepper(gyro_s2().with_params({"body.mass": 0.0}))


def test_stepper_with_user_potential():
    V = lambda x, e: -0.3 * x[2]  # noqa: E731
    a = fd.Stepper(gyro_s2(potential={"kind": "none"}), user_potential=V)
    b = fd.Stepper(gyro_s2())
    a.advance(0.01, 100)
    b.advance(0.01, 100)
    np.testing.assert_allclose(a.row(), b.row(), atol=1e-8)


def test_stepper_user_potential_error_propagates():
    def V(x, e):
        raise ZeroDivisionError("in V")

    with pytest.raises(ZeroDivisionError, match="in V"):
        st = fd.Stepper(gyro_s2(potential={"kind": "none"}), user_potential=V)
        st.step(0.01)


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals go to the main thread")
def test_ctrl_c_stops_advance_and_keeps_the_steps_done():
    st = fd.Stepper(gyro_s2(h=1e-3, t_end=1e5))
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    # A background process inherits SIGINT ignored (see test_solve.py).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    t0 = time.monotonic()
    timer.start()
    try:
        st.advance(1e-5, 10**9)  # 1e9 steps: about an hour
    except KeyboardInterrupt:
        pass
    else:
        pytest.fail("no KeyboardInterrupt")
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.monotonic() - t0 < 1.3, "KeyboardInterrupt later than 1 s after the signal"
    # The steps done before the interrupt stay done, on the step grid.
    k = round(st.t / 1e-5)
    assert k > 0 and abs(st.t - k * 1e-5) < 1e-9
    assert math.isfinite(st.energy)


def test_stepper_keeps_a_drift_record_and_judges_it():
    st = fd.Stepper(gyro_s2(h=1e-3, t_end=10.0))
    assert st.energy_drift == 0.0 and st.warnings == []
    e0 = st.energy
    for _ in range(5):
        st.advance(1e-3, 200)
    assert 0.0 < st.energy_drift < 1e-9 and st.max_defect < 1e-12 and st.warnings == []
    assert st.energy_drift >= abs(st.energy - e0)
    # Lie-Euler with a large step gains energy: the record and the check show it.
    d = gyro_s2(h=0.05, t_end=10.0).to_dict()
    d["method"] = {"name": "lie_euler", "h": 0.05}
    crude = fd.Stepper(d)
    crude.advance(0.05, 80)
    assert crude.energy_drift > 1e-3 * abs(crude.energy)
    assert crude.warnings and "energy drift" in crude.warnings[0]
    crude.reset()
    assert crude.energy_drift == 0.0 and crude.warnings == []
