"""Error mapping: Rust errors arrive as ValueError / RuntimeError / OSError
subclasses with the Rust message; a Rust panic never crosses the boundary."""

import errno
import os
import sys

import numpy as np
import pytest

import framedyn as fd
from framedyn import _framedyn


def test_hierarchy():
    assert issubclass(fd.InvalidInputError, ValueError)
    assert issubclass(fd.InvalidInputError, fd.FramedynError)
    assert issubclass(fd.IntegrationError, RuntimeError)
    assert issubclass(fd.IntegrationError, fd.FramedynError)
    assert issubclass(fd.OutputError, OSError)
    assert issubclass(fd.InternalError, RuntimeError)


@pytest.mark.parametrize(
    "kind, cls",
    [("invalid", fd.InvalidInputError), ("integration", fd.IntegrationError), ("io", fd.OutputError), ("internal", fd.InternalError)],
)
def test_each_kind_maps_to_its_class(kind, cls):
    with pytest.raises(cls, match="the Rust message"):
        _framedyn._raise_for_test(kind, "the Rust message")


def test_panic_becomes_internal_error():
    with pytest.raises(fd.InternalError, match="Rust panic.*boom"):
        _framedyn._raise_for_test("panic", "boom")


def test_unknown_kind_is_invalid_input():
    with pytest.raises(fd.InvalidInputError, match="kind"):
        _framedyn._raise_for_test("nope", "x")


def test_integration_error_has_partial_default():
    e = fd.IntegrationError("x")
    assert e.partial is None


def test_scene_load_names_the_file_and_the_problem(tmp_path):
    with pytest.raises(fd.OutputError, match="Scene.load.*missing.toml") as e:
        fd.Scene.load(tmp_path / "missing.toml")
    assert isinstance(e.value, OSError) and e.value.errno == errno.ENOENT
    with pytest.raises(fd.OutputError, match="Scene.load") as e:
        fd.Scene.load(tmp_path)
    assert e.value.errno == errno.EISDIR
    (tmp_path / "bin.toml").write_bytes(b"name = \"x\"\n\xd0\x00")
    with pytest.raises(fd.InvalidInputError, match="not UTF-8 text.*offset 11"):
        fd.Scene.load(tmp_path / "bin.toml")
    with pytest.raises(fd.InvalidInputError, match="`path`"):
        fd.Scene.load(3)  # type: ignore[arg-type]


def test_bad_events_and_batches_name_the_argument():
    scene = fd.Scene.example("s2-gyroscope-pole")
    with pytest.raises(fd.InvalidInputError, match="`events`.*int"):
        fd.solve(scene, events=1)  # type: ignore[arg-type]
    with pytest.raises(fd.InvalidInputError, match="`scenes`.*NoneType"):
        fd.solve_batch(None)  # type: ignore[arg-type]
    with pytest.raises(fd.InvalidInputError, match="`threads`"):
        fd.solve_batch(scene, {"initial.r": [0.5]}, threads=2**64)


def test_save_follows_the_output_policy(tmp_path):
    sol = fd.solve(fd.Scene.example("s2-gyroscope-pole"))
    (tmp_path / "real.csv").write_text("OLD")
    os.symlink("real.csv", tmp_path / "link.csv")
    sol.save(tmp_path / "link.csv")
    assert os.path.islink(tmp_path / "link.csv")
    assert (tmp_path / "real.csv").read_text().startswith("t,")
    ro = tmp_path / "ro.csv"
    ro.write_text("KEEP")
    ro.chmod(0o444)
    with pytest.raises(OSError, match="read-only"):
        sol.save(ro)
    assert ro.read_text() == "KEEP"


def test_records_that_cannot_fit_in_memory_are_refused_before_the_run():
    # 1e9 fixed steps, every one recorded: ~200 GB of records.
    d = fd.Scene.example("s2-gyroscope-pole").to_dict()
    d["method"] = {"name": "rk4", "h": 4e-9}
    d["output"] = {"every": 1}
    with pytest.raises(fd.InvalidInputError, match=r"output\.every.*GB in memory.*available"):
        fd.solve(d)
    # Adaptive steps: the record count is not known in advance, so the run
    # is not refused on the bound that method.max_steps would give.
    d["method"] = {"name": "dop853", "rtol": 1e-8, "atol": 1e-8}
    assert len(fd.solve(d)) >= 2


def _integer_cases():
    """(call, bad values, argument, allowed range as a regex) for every
    public integer argument that reaches the Rust core."""
    scene = fd.Scene.example("s2-gyroscope-pole")
    table = {"initial.r": [0.5, 0.6]}
    usize = r"\[0, 2\*\*64 - 1\]" if sys.maxsize > 2**32 else r"\[0, 2\*\*32 - 1\]"
    common = [2**64, 2**63, -1, True, False, 1.5, "3", np.float64(2.0)]
    yield lambda v: fd.solve_batch([scene], threads=v), common + [0, 1025], "threads", r"\[1, 1024\]"
    yield lambda v: fd.solve_batch(scene, table, threads=v, keep="final"), common + [0, 1025], "threads", r"\[1, 1024\]"
    yield lambda v: fd.solve_batch(scene, table, samples=v), common + [0, 1, 10**8 + 1], "samples", r"\[2, 100_000_000\]"
    yield lambda v: fd.Stepper(scene).advance(0.01, v), [2**64, 2**65, -1, True, 1.5, "3", None], "n", usize
    every = r"1 \.\.= 2\^64 − 1|must be ≥ 1"
    scene_bad = [2**64, 2**70, -1, -(2**63), True, 1.5, "3", [1]]
    plain = scene.with_params({"output": {}})  # no sampling given: every field can be set
    for field, extra, allowed in [
        ("output.every", [0], every),
        ("output.samples", [0, 1, 10**9, 2**63], r"2 \.\.= 1e8"),
        ("method.max_steps", [0], every),
    ]:
        yield (lambda f: lambda v: plain.with_params({f: v}).validate())(field), scene_bad + extra, field, allowed
        key = field.split(".")[1]
        yield (lambda k: lambda v: fd.Scene(manifold="S2", body="point", r=0.5, phi=0.0, r_dot=0.1, h=0.01, t_end=1.0, **{k: v}).validate())(key), \
            scene_bad + extra, field, allowed
    implicit = scene.with_params({"method.name": "implicit_midpoint"})
    yield lambda v: implicit.with_params({"method.newton_max_iter": v}).validate(), scene_bad + [0, 1001, 2**32, 2**40], \
        "method.newton_max_iter", r"1 \.\.= 1000"
    try:
        from framedyn.ensemble import solve_ensemble, solve_table
    except ImportError:  # pragma: no cover - dask is installed by the test environment
        return
    # Checked on the client, before any cluster is needed.
    yield lambda v: solve_table(scene, table, threads_per_task=v), common + [0], "threads_per_task", r"\[1, 1024\]"
    yield lambda v: solve_ensemble([scene], threads_per_task=v), common + [0], "threads_per_task", r"\[1, 1024\]"
    yield lambda v: solve_table(scene, table, samples=v), common + [1], "samples", r"\[2, 100_000_000\]"


def test_integer_arguments_are_bounded_with_a_named_range():
    """Every integer that crosses into Rust, out of its range, of the wrong
    type or beyond 64 bits, raises InvalidInputError naming the argument and
    the range it takes: never OverflowError, a panic or a run."""
    import re

    count = 0
    for call, values, name, allowed in _integer_cases():
        for v in values:
            with pytest.raises(fd.InvalidInputError) as ei:
                call(v)
            msg = str(ei.value)
            assert f"`{name}`" in msg and re.search(allowed, msg), f"{name} = {v!r}: {msg}"
            count += 1
    assert count > 100
    # In range, Python and numpy integers pass.
    scene = fd.Scene.example("s2-gyroscope-pole")
    assert len(fd.solve_batch(scene, {"initial.r": [0.5]}, threads=np.int64(1), samples=np.uint64(3))) == 1
    st = fd.Stepper(scene)
    st.advance(0.01, np.uint64(3))
    st.advance(0.01, 0)
    assert st.t == pytest.approx(0.03)
    assert scene.with_params({"output.every": 2**64 - 1}).validate() is not None


@pytest.mark.parametrize(
    "rtol, atol, field",
    [(1e-300, 1e-300, "method.rtol"), (0.0, 1e-8, "method.rtol"), (float("nan"), 1e-8, "method.rtol"),
     (1e-8, 0.0, "method.atol"), (1e-8, -1e-8, "method.atol"), (1e-8, float("inf"), "method.atol")],
)
def test_tolerances_out_of_range_name_the_field(rtol, atol, field):
    scene = fd.Scene.example("s2-gyroscope-pole")
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        fd.solve(scene.replace(method={"name": "dop853", "rtol": rtol, "atol": atol}))


def test_extreme_values_are_shown_in_scientific_notation():
    """An error message quotes 1e-300 as 1e-300, not as 300 decimals."""
    scene = fd.Scene.example("s2-point-kepler")
    cases = [
        (lambda: fd.solve(scene.replace(method={"name": "dop853", "rtol": 1e-300, "atol": 1e-300})), "`method.rtol` = 1e-300"),
        (lambda: fd.solve(scene.replace(method={"name": "rk4", "h": 1e-320})), "`method.h` = 1e-320"),
        (lambda: fd.sali(scene, threshold=1e300), "threshold = 1e300"),
    ]
    for call, shown in cases:
        with pytest.raises(ValueError) as info:
            call()
        assert shown in str(info.value) and len(str(info.value)) < 250, str(info.value)
