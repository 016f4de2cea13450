"""Error mapping: Rust errors arrive as ValueError / RuntimeError / OSError
subclasses with the Rust message; a Rust panic never crosses the boundary."""

import errno
import os

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
