"""The `framedyn` console script installed by the wheel."""

import shutil
import subprocess
import sys

import pytest

from framedyn import _framedyn, cli

HAS_CLI = hasattr(_framedyn, "cli_main")


def test_console_script_is_installed():
    exe = shutil.which("framedyn", path=sys.prefix + "/bin")
    assert exe is not None


def test_the_cli_is_bound_into_the_extension():
    assert HAS_CLI


def test_run_writes_a_trajectory(tmp_path):
    exe = shutil.which("framedyn", path=sys.prefix + "/bin")
    scene = tmp_path / "scene.toml"
    out = subprocess.run([exe, "scenes", "show", "s2-gyroscope-pole"], capture_output=True, text=True)
    assert out.returncode == 0
    scene.write_text(out.stdout)
    csv = tmp_path / "traj.csv"
    out = subprocess.run([exe, "run", str(scene), "--output", str(csv), "--quiet"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    lines = csv.read_text().splitlines()
    assert lines[0].startswith("t,") and len(lines) > 10


def test_scenes_and_validate(tmp_path):
    exe = shutil.which("framedyn", path=sys.prefix + "/bin")
    out = subprocess.run([exe, "scenes"], capture_output=True, text=True)
    assert out.returncode == 0 and "s2-gyroscope-pole" in out.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text("[manifold]\nkind = 'S4'\n")
    out = subprocess.run([exe, "validate", str(bad)], capture_output=True, text=True)
    assert out.returncode != 0 and "manifold" in out.stderr


def test_sweep_output_round_trips_through_numpy(tmp_path):
    import numpy as np

    import framedyn as fd

    exe = shutil.which("framedyn", path=sys.prefix + "/bin")
    r = np.array([0.4, 0.8, 1.2])
    np.savez(tmp_path / "members.npz", **{"initial.r": r, "initial.spin": np.array([0, 1, 2])})
    out = subprocess.run([exe, "sweep", "s2-gyroscope-pole", "--table", str(tmp_path / "members.npz"), "--output", str(tmp_path / "s.npz"), "--samples", "5"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    with np.load(tmp_path / "s.npz") as z:
        assert list(z["status"]) == ["finished"] * 3
        assert list(z["offsets"]) == [0, 5, 10, 15]
        assert np.array_equal(z["table.initial.r"], r)
        here = fd.solve_batch(fd.Scene.example("s2-gyroscope-pole"), {"initial.r": r, "initial.spin": np.array([0.0, 1.0, 2.0])}, samples=5)
        assert list(z["columns"]) == here.columns
        assert np.array_equal(z["data"], here.flat)
        assert np.array_equal(z["steps"], here.stats["steps"])
