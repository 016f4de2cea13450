"""The type stubs match the extension module (mypy's stubtest), the package
type-checks against them (mypy), and ``py.typed`` ships with it."""

import os
import subprocess
import sys

import pytest

import framedyn

pytest.importorskip("mypy")
PACKAGE = os.path.dirname(framedyn.__file__)


# The two mypy runs are among the slowest tests; `start_checks` (called by conftest.py
# when collection ends, if a test below is selected) starts both as
# subprocesses, so that they run beside the rest of the suite and the tests
# below only wait for their results.
_CHECKS = {
    "stubtest": [sys.executable, "-m", "mypy.stubtest", "framedyn._framedyn"],
    "mypy": [sys.executable, "-m", "mypy", "--no-incremental", PACKAGE],
}
_RUNNING: dict = {}


def start_checks():
    for name, cmd in _CHECKS.items():
        if name not in _RUNNING:
            _RUNNING[name] = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=os.path.dirname(PACKAGE))


def _result(name):
    start_checks()
    out, _ = _RUNNING[name].communicate()
    return _RUNNING[name].returncode, out


def test_stubtest_extension_module():
    code, out = _result("stubtest")
    assert code == 0, out


def test_package_typechecks():
    code, out = _result("mypy")
    assert code == 0, out


def test_py_typed_and_exports():
    assert os.path.exists(os.path.join(PACKAGE, "py.typed"))
    assert os.path.exists(os.path.join(PACKAGE, "_framedyn.pyi"))
    for name in framedyn.__all__:
        assert hasattr(framedyn, name), name
