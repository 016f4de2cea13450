"""The type stubs match the extension module (mypy's stubtest), the package
type-checks against them (mypy), and ``py.typed`` ships with it."""

import os
import subprocess
import sys

import pytest

import framedyn

pytest.importorskip("mypy")
PACKAGE = os.path.dirname(framedyn.__file__)


def test_stubtest_extension_module():
    out = subprocess.run([sys.executable, "-m", "mypy.stubtest", "framedyn._framedyn"], capture_output=True, text=True, cwd=os.path.dirname(PACKAGE))
    assert out.returncode == 0, out.stdout + out.stderr


def test_package_typechecks():
    out = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", PACKAGE], capture_output=True, text=True, cwd=os.path.dirname(PACKAGE))
    assert out.returncode == 0, out.stdout + out.stderr


def test_py_typed_and_exports():
    assert os.path.exists(os.path.join(PACKAGE, "py.typed"))
    assert os.path.exists(os.path.join(PACKAGE, "_framedyn.pyi"))
    for name in framedyn.__all__:
        assert hasattr(framedyn, name), name
