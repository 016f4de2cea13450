"""Columnar batches: ``fd.solve_batch(scene, table)`` equals per-scene
``fd.solve`` bit for bit, bad tables are refused naming the column (and the
member), failures stay with their member, and Ctrl-C stops a batch."""

import os
import signal
import threading
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import framedyn as fd

from conftest import gyro_s2


@settings(max_examples=10, deadline=None)
@given(
    r=st.lists(st.floats(0.1, 2.5), min_size=1, max_size=5),
    spin=st.floats(-0.2, 0.2),
    beta=st.floats(-0.5, 0.5),
)
def test_columnar_members_equal_single_solves_bit_for_bit(r, spin, beta):
    base = gyro_s2(t_end=0.5)
    n = len(r)
    table = {
        "initial.r": np.array(r),
        "initial.spin": np.full(n, spin) + 0.01 * np.arange(n),
        "potential.beta_hat": np.full(n, beta),
    }
    out = fd.solve_batch(base, table, threads=2)
    assert isinstance(out, fd.EnsembleSolution)
    assert len(out) == n and list(out.status) == ["finished"] * n
    for i in range(n):
        p = {k: float(v[i]) for k, v in table.items()}
        single = fd.solve(base.with_params(p))
        assert out.columns == single.columns
        assert np.array_equal(out.data[i], single.data)
        assert np.array_equal(out.member(i).data, single.data)
        assert out.stats["steps"][i] == single.stats["steps"]
        assert out.stats["energy_drift"][i] == single.stats["energy_drift"]


def test_stacked_shapes_keep_and_samples():
    base = gyro_s2(t_end=1.0)
    table = {"initial.r": np.linspace(0.3, 1.2, 4)}
    out = fd.solve_batch(base, table, samples=9)
    assert out.position.shape == (4, 9, 3)
    assert out.frame.shape == (4, 9, 2, 3)
    assert out.t.shape == out.energy.shape == out.defect.shape == (4, 9)
    assert out["spin"].shape == (4, 9)
    np.testing.assert_allclose(out.t[:, 0], 0.0)
    np.testing.assert_allclose(out.t[:, -1], 1.0)
    final = fd.solve_batch(base, table, keep="final")
    assert final.data.shape == (4, 1, len(final.columns))
    full = fd.solve_batch(base, table)
    assert np.array_equal(final.final, full.final)
    assert np.array_equal(full.final, full.data[:, -1, :])
    # A DataFrame is a table too.
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(table)
    assert np.array_equal(fd.solve_batch(base, df, keep="final").final, final.final)


def test_ragged_members_need_flat_access():
    base = gyro_s2(t_end=1.0, method={"name": "dopri5", "rtol": 1e-8, "atol": 1e-10})
    out = fd.solve_batch(base, {"initial.r": np.array([0.3, 1.4])})
    if out.records[0] != out.records[1]:
        with pytest.raises(ValueError, match="different numbers of records"):
            out.position
    assert out.flat.shape[0] == out.offsets[-1] == out.records.sum()
    assert np.array_equal(out.member_index, np.repeat([0, 1], out.records))
    for i in range(2):
        single = fd.solve(base.with_params({"initial.r": [0.3, 1.4][i]}))
        assert np.array_equal(out.member(i).data, single.data)


@pytest.mark.parametrize(
    "table, match",
    [
        ({"initial.r": np.array([0.1, 0.2]), "initial.spin": np.array([0.0])}, r"initial\.spin.*2 members"),
        ({"initial.r": np.array([0.1, np.nan, 0.3])}, r"initial\.r.*member 1.*finite"),
        ({"body.colour": np.array([1.0])}, r"body\.colour"),
        ({"initial.r": np.array(["a", "b"])}, r"initial\.r.*dtype"),
        ({"initial.r": np.array([True, False])}, r"initial\.r.*dtype"),
        ({"initial.r": np.ones((2, 2))}, r"initial\.r.*1-D"),
        ({}, r"no columns"),
        ({"initial.r": np.array([])}, r"0 members"),
        ([1, 2], r"list of dicts|Scene|params"),
    ],
)
def test_bad_tables_are_refused_naming_the_column(table, match):
    with pytest.raises(fd.InvalidInputError, match=match):
        fd.solve_batch(gyro_s2(), table)


def test_invalid_member_raises_or_is_kept():
    table = {"body.inertia": np.array([0.2, -1.0, 0.3])}
    with pytest.raises(fd.InvalidInputError, match=r"body\.inertia.*member 1") as ei:
        fd.solve_batch(gyro_s2(), table)
    assert ei.value.index == 1
    out = fd.solve_batch(gyro_s2(), table, on_error="keep")
    assert list(out.status) == ["finished", "invalid", "finished"]
    assert list(out.ok) == [True, False, True]
    assert out.records[1] == 0 and np.isnan(out.stats["steps"][1])
    assert "member 1" in out.errors[1]


def test_user_potential_error_stays_with_its_member():
    # Only member 2 moves towards the pole, where the potential raises.
    base = gyro_s2(potential=None, t_end=1.0)
    table = {"initial.r_dot": np.array([1.0, 1.0, -1.0, 1.0, 1.0, 1.0])}

    def v(x, e):
        if x[2] > 0.95:
            raise ValueError("outside the potential's domain")
        return -0.3 * x[2]

    out = fd.solve_batch(base, table, user_potential=v, on_error="keep")
    assert list(out.status) == ["finished", "finished", "failed", "finished", "finished", "finished"]
    assert isinstance(out.exceptions[2], ValueError) and "domain" in str(out.exceptions[2])
    assert all(out.exceptions[i] is None for i in (0, 1, 3, 4, 5))
    assert out.records[2] > 0 and out.stats["t_reached"][2] < 1.0
    assert isinstance(out.member(2).error, ValueError)
    for i in (0, 5):
        single = fd.solve(base.with_params({"initial.r_dot": 1.0}), user_potential=v)
        assert np.array_equal(out.member(i).data, single.data)
    with pytest.raises(ValueError, match="domain"):
        fd.solve(base.with_params({"initial.r_dot": -1.0}), user_potential=v)


def test_ctrl_c_stops_a_large_batch_within_a_second():
    base = gyro_s2(t_end=200.0, h=1e-4)
    table = {"initial.r": np.linspace(0.2, 1.5, 64)}
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        fd.solve_batch(base, table, keep="final", threads=2)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 1.5, f"batch took {elapsed:.2f} s to stop after Ctrl-C at 0.5 s"
    # No worker is left running: a new batch gets the threads at once.
    t0 = time.monotonic()
    fd.solve_batch(gyro_s2(t_end=0.1), {"initial.r": np.array([0.5, 0.6])}, threads=2)
    assert time.monotonic() - t0 < 1.0


def test_ctrl_c_stops_a_list_batch_within_a_second():
    scenes = [gyro_s2(t_end=200.0, h=1e-4, output={"samples": 2})] * 8
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        fd.solve_batch(scenes, threads=2)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 1.5, f"batch took {elapsed:.2f} s to stop after Ctrl-C at 0.5 s"
