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


@pytest.mark.skipif(HAS_CLI, reason="the command-line tool is bound")
def test_without_the_cli_it_says_so(capsys):
    assert cli.main(["scenes"]) == 2
    assert "framedyn_cli::main_with_args" in capsys.readouterr().err


@pytest.mark.skipif(not HAS_CLI, reason="the command-line tool is not bound into this build")
def test_scenes_and_validate(tmp_path):
    exe = shutil.which("framedyn", path=sys.prefix + "/bin")
    out = subprocess.run([exe, "scenes"], capture_output=True, text=True)
    assert out.returncode == 0 and "s2-gyroscope-pole" in out.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text("[manifold]\nkind = 'S4'\n")
    out = subprocess.run([exe, "validate", str(bad)], capture_output=True, text=True)
    assert out.returncode != 0 and "manifold" in out.stderr
