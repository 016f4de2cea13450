"""framedyn.solve_batch: parallel runs identical to single runs, parameter
sets, stacked arrays, failures per member, and the GIL released."""

import threading
import time

import numpy as np
import pytest

import framedyn as fd

from conftest import SCENES, gyro_s2


def test_batch_equals_loop_of_single_runs():
    scenes = [SCENES[k]() for k in sorted(SCENES)] * 2
    batch = fd.solve_batch(scenes, threads=2)
    assert len(batch) == len(scenes)
    for s, b in zip(scenes, batch):
        single = fd.solve(s)
        assert b.columns == single.columns
        # Bit for bit: the same deterministic computation on another thread.
        assert np.array_equal(b.data, single.data)
        assert b.stats["steps"] == single.stats["steps"]


def test_parameter_sets_and_stacking():
    base = gyro_s2(output={"samples": 11})
    params = [{"initial.r": r, "initial.spin": s} for r in (0.3, 0.6, 0.9) for s in (0.0, 0.1)]
    batch = fd.solve_batch(base, params)
    assert batch.position.shape == (6, 11, 3)
    assert batch.frame.shape == (6, 11, 2, 3)
    assert batch.energy.shape == batch.t.shape == batch.defect.shape == (6, 11)
    assert batch.data.shape[:2] == (6, 11)
    assert batch.stack("spin").shape == (6, 11)
    for p, b in zip(params, batch):
        assert b.coordinates["r"][0] == pytest.approx(p["initial.r"], abs=1e-12)
        assert np.array_equal(b.data, fd.solve(base.with_params(p)).data)
    assert batch.errors == [None] * 6


def test_stacking_needs_equal_records():
    batch = fd.solve_batch([gyro_s2(t_end=1.0), gyro_s2(t_end=2.0)])
    with pytest.raises(ValueError, match="different numbers of records"):
        batch.position


def test_default_threads_and_single_scene():
    s = gyro_s2()
    assert np.array_equal(fd.solve_batch(s)[0].data, fd.solve(s).data)
    assert np.array_equal(fd.solve_batch([s, s]).data[1], fd.solve(s).data)


def test_failures_raise_or_are_kept():
    good = gyro_s2()
    bad = gyro_s2(method={"name": "dopri5", "rtol": 1e-12, "atol": 1e-14, "max_steps": 5})
    with pytest.raises(fd.IntegrationError) as ei:
        fd.solve_batch([good, bad, good])
    assert ei.value.index == 1
    assert isinstance(ei.value.partial, fd.Solution)
    kept = fd.solve_batch([good, bad, good], on_error="keep")
    assert kept.errors[0] is None and kept.errors[2] is None
    assert isinstance(kept.errors[1], fd.IntegrationError)
    assert kept[1].stats["stop"] == "failed" and len(kept[1]) >= 1


def test_invalid_member_names_its_index():
    with pytest.raises(fd.InvalidInputError, match=r"scenes\[1\]"):
        fd.solve_batch([gyro_s2(), "not a scene"])
    with pytest.raises(fd.InvalidInputError, match="threads"):
        fd.solve_batch([gyro_s2()], threads=0)
    with pytest.raises(fd.InvalidInputError, match="on_error"):
        fd.solve_batch([gyro_s2()], on_error="ignore")
    with pytest.raises(fd.InvalidInputError, match="params"):
        fd.solve_batch([gyro_s2()], params=[{}])
    # One dict is a columnar table: its values must be 1-D arrays.
    with pytest.raises(fd.InvalidInputError, match=r"initial\.r.*1-D"):
        fd.solve_batch(gyro_s2(), params={"initial.r": 0.1})
    with pytest.raises(fd.InvalidInputError, match="body"):
        fd.solve_batch(gyro_s2(), params=[{"body.mass": -1.0}]).position


def test_user_potential_in_a_batch():
    V = lambda x, e: -0.3 * x[2]  # noqa: E731  (the cosine potential by hand)
    scenes = [gyro_s2(potential={"kind": "none"}, r=r) for r in (0.3, 0.5)]
    batch = fd.solve_batch(scenes, user_potential=V, threads=2)
    for s, b in zip(scenes, batch):
        np.testing.assert_array_equal(b.data, fd.solve(s, user_potential=V).data)


def test_user_potential_exception_is_reported_on_its_member_only():
    # Only member 3 moves towards the pole, where the potential raises.
    scenes = [gyro_s2(potential={"kind": "none"}, r_dot=(-1.0 if i == 3 else 1.0), t_end=1.0) for i in range(6)]

    def V(x, e):
        if x[2] > 0.95:
            raise ValueError("outside the potential's domain")
        return -0.3 * x[2]

    kept = fd.solve_batch(scenes, user_potential=V, threads=2, on_error="keep")
    assert [e is None for e in kept.errors] == [True, True, True, False, True, True]
    assert isinstance(kept.errors[3], ValueError)
    with pytest.raises(ValueError, match="domain") as ei:
        fd.solve_batch(scenes, user_potential=V)
    assert ei.value.index == 3


def test_gil_is_released_during_a_long_batch():
    """A Python thread keeps counting while the batch runs."""
    scenes = [gyro_s2(h=1e-4, t_end=60.0, output={"samples": 2})] * 2  # ≈ 0.6 s in the dev build
    counts = []
    stop = threading.Event()

    def count():
        n = 0
        while not stop.is_set():
            n += 1
            if n % 1000 == 0:
                counts.append((time.monotonic(), n))

    th = threading.Thread(target=count)
    th.start()
    try:
        t0 = time.monotonic()
        fd.solve_batch(scenes, threads=1)
        t1 = time.monotonic()
    finally:
        stop.set()
        th.join()
    during = [n for (t, n) in counts if t0 < t < t1]
    assert t1 - t0 > 0.2, "the batch should take a while for this test to mean anything"
    # Counting went on during the batch (not just before and after it).
    assert len(during) >= 10 and during[-1] > during[0]


def test_threads_are_capped_at_members_and_cores():
    # 5000 threads for one member start one worker (was 20 s of thread start-up).
    scene = fd.Scene.example("s2-gyroscope-pole")
    t0 = time.monotonic()
    out = fd.solve_batch(scene, {"initial.r": np.array([0.6])}, threads=1024, keep="final")
    assert out.ok.all() and time.monotonic() - t0 < 5.0
    sols = fd.solve_batch([scene, scene], threads=1024)
    assert len(sols) == 2
    # Oversubscribing is allowed when asked, with the same results.
    a = fd.solve_batch(scene, {"initial.r": np.array([0.6, 0.7, 0.8])}, threads=3, oversubscribe=True, keep="final")
    b = fd.solve_batch(scene, {"initial.r": np.array([0.6, 0.7, 0.8])}, threads=1, keep="final")
    np.testing.assert_array_equal(a.final, b.final)
    with pytest.raises(fd.InvalidInputError, match="oversubscribe"):
        fd.solve_batch(scene, {"initial.r": np.array([0.6])}, oversubscribe="yes")  # type: ignore[arg-type]
