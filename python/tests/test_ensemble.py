"""framedyn.ensemble on a local Dask cluster on loopback: the same results
as solve_batch (skipped when dask.distributed is not installed)."""

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

import framedyn as fd  # noqa: E402
from framedyn.ensemble import solve_ensemble  # noqa: E402

from conftest import gyro_s2  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None, protocol="tcp"
    )
    c = distributed.Client(cluster)
    try:
        yield c
    finally:
        c.close()
        cluster.close()


def test_ensemble_equals_batch(client):
    assert all(addr.startswith("tcp://127.0.0.1") for addr in client.scheduler_info()["workers"])
    base = gyro_s2(output={"samples": 21})
    params = [{"initial.r": r, "potential.beta_hat": b} for r in (0.3, 0.6, 0.9) for b in (-0.3, 0.2)]
    ens = solve_ensemble(base, params, client=client, chunk_size=2)
    local = fd.solve_batch(base, params)
    assert len(ens) == len(params)
    assert np.array_equal(ens.data, local.data)
    assert ens.position.shape == (6, 21, 3)


def test_ensemble_with_user_potential_and_failures(client):
    scenes = [gyro_s2(potential={"kind": "none"}), gyro_s2(method={"name": "dopri5", "rtol": 1e-12, "max_steps": 3})]
    V = lambda x, e: -0.3 * x[2]  # noqa: E731  (pickled to the workers)
    kept = solve_ensemble(scenes, client=client, user_potential=V, on_error="keep")
    assert kept.errors[0] is None and isinstance(kept.errors[1], fd.IntegrationError)
    assert np.array_equal(kept[0].data, fd.solve(scenes[0], user_potential=V).data)
    with pytest.raises(fd.IntegrationError) as ei:
        solve_ensemble(scenes, client=client, user_potential=V)
    assert ei.value.index == 1


def test_ensemble_argument_errors(client):
    with pytest.raises(fd.InvalidInputError, match="chunk_size"):
        solve_ensemble([gyro_s2()], client=client, chunk_size=0)
    with pytest.raises(fd.InvalidInputError, match="on_error"):
        solve_ensemble([gyro_s2()], client=client, on_error="x")


def test_columnar_ensemble_equals_solve_batch(client):
    from framedyn.ensemble import solve_table

    base = gyro_s2(t_end=1.0)
    table = {"initial.r": np.linspace(0.2, 1.4, 7), "body.inertia": np.array([0.2, 0.3, -1.0, 0.2, 0.25, 0.3, 0.35])}
    for kw in ({"keep": "final"}, {"samples": 5}):
        ens = solve_table(base, table, client=client, chunk_size=3, **kw)
        local = fd.solve_batch(base, table, on_error="keep", **kw)
        assert list(ens.status) == list(local.status)
        assert ens.status[2] == "invalid" and "body.inertia" in ens.errors[2]
        assert np.array_equal(ens.flat, local.flat) and np.array_equal(ens.offsets, local.offsets)
        for k in ("steps", "energy_drift", "t_reached"):
            assert np.array_equal(ens.stats[k], local.stats[k], equal_nan=True)


def test_back_to_back_calls_on_an_equal_scene(client):
    """Calls in quick succession on equal scenes: with the scene scattered
    under its content hash, each call reuses the previous call's key, and
    when that call's future is released during the next call's replication,
    the scheduler loses the key ("lost dependencies"); 60 calls make that
    likely."""
    from framedyn.ensemble import solve_table

    import threading

    table = {"initial.r": np.linspace(0.2, 1.4, 4)}
    local = fd.solve_batch(gyro_s2(t_end=0.1), table, keep="final")
    # In a thread of its own: a lost key can also leave `gather` waiting
    # forever, which must fail the test, not hang it.
    done, failure = [], []

    def calls():
        try:
            for _ in range(60):
                ens = solve_table(gyro_s2(t_end=0.1), table, client=client, chunk_size=1, keep="final")
                assert np.array_equal(ens.flat, local.flat)
                done.append(1)
        except BaseException as e:  # re-raised below, in the test's thread
            failure.append(e)

    worker = threading.Thread(target=calls, daemon=True)
    worker.start()
    worker.join(120)
    assert not worker.is_alive(), f"solve_table did not return after {len(done)} calls"
    if failure:
        raise failure[0]
    assert len(done) == 60


def test_columnar_ensemble_into_a_zarr_store(client, tmp_path):
    zarr = pytest.importorskip("zarr")
    from framedyn.ensemble import StoredEnsemble, solve_table

    base = gyro_s2(t_end=1.0)
    table = {"initial.r": np.linspace(0.2, 1.4, 10), "initial.spin": np.linspace(0.0, 0.1, 10)}
    table["initial.r"][4] = -2.0  # an invalid member: NaN rows in the store
    path = str(tmp_path / "runs.zarr")
    out = solve_table(base, table, client=client, chunk_size=4, samples=6, store=path)
    assert isinstance(out, StoredEnsemble) and len(out) == 10
    local = fd.solve_batch(base, table, samples=6, on_error="keep")
    assert list(out.status) == list(local.status)
    g = zarr.open_group(path, mode="r")
    data = g["data"][:]
    assert data.shape == (10, 6, len(local.columns)) and list(g.attrs["columns"]) == local.columns
    for i in range(10):
        if local.status[i] == "invalid":
            assert np.isnan(data[i]).all()
        else:
            assert np.array_equal(data[i], local.member(i).data)
    assert np.array_equal(g["steps"][:], local.stats["steps"], equal_nan=True)
    with pytest.raises(fd.InvalidInputError, match="keep='final' or samples"):
        solve_table(base, table, client=client, store=path, keep="all")


def test_stored_ensemble_carries_the_quality_warnings(client, tmp_path):
    zarr = pytest.importorskip("zarr")
    from framedyn.ensemble import MemberWarnings, StoredEnsemble, _table_chunk, solve_table

    # A tiny energy-drift limit: the members with a coarse step fail the
    # quality check, those with a fine step pass; member 2 is invalid.
    d = gyro_s2(t_end=1.0).to_dict()
    d["quality"] = {"energy_drift": 1e-9}
    base = fd.Scene.from_dict(d)
    table = {"method.h": np.array([0.002, 0.1, 0.002, 0.2, 0.001, 0.1, 0.002]),
             "initial.r": np.array([0.5, 0.6, -2.0, 0.7, 0.8, 0.9, 1.0])}
    with pytest.warns(fd.QualityWarning, match="solve_batch: 3 of 7 members failed the quality check"):
        local = fd.solve_batch(base, table, samples=6, on_error="keep")
    flagged = [i for i, w in enumerate(local.warnings) if w]
    assert flagged == [1, 3, 5] and all("energy drift" in local.warnings[i][0] for i in flagged)

    path = str(tmp_path / "runs.zarr")
    with pytest.warns(fd.QualityWarning, match="solve_table: 3 of 7 members failed the quality check .* member 1: the energy drift"):
        out = solve_table(base, table, client=client, chunk_size=3, samples=6, store=path)
    assert isinstance(out, StoredEnsemble) and isinstance(out.warnings, MemberWarnings)
    assert len(out.warnings) == 7 and list(out.warnings) == local.warnings and out.warnings == local.warnings
    assert out.warnings.flagged.tolist() == flagged
    for i in range(7):
        assert out.warnings[i] == local.warnings[i]
    assert out.warnings[-2] == local.warnings[5] and out.warnings[1:4] == local.warnings[1:4]
    with pytest.raises(IndexError):
        out.warnings[7]
    # In the store: the findings joined by "; ", empty for sound members.
    g = zarr.open_group(path, mode="r")
    assert [str(s) for s in g["warnings"][:]] == ["; ".join(w) for w in local.warnings]
    # Without a store, the gathered ensemble has them too.
    with pytest.warns(fd.QualityWarning):
        mem = solve_table(base, table, client=client, chunk_size=3, samples=6)
    assert mem.warnings == local.warnings
    # A chunk sends the findings of its flagged members only.
    part = _table_chunk(base, list(table), list(table.values()), "all", 6, 1, None, 0, None, None)
    assert "warnings" not in part and part["warned"].tolist() == flagged and part["warned_texts"] == [local.warnings[i] for i in flagged]
