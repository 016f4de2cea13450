"""Every script in python/examples runs and its checks against the paper
pass (exit status 0), and every ```python block of docs/guide.md runs as
written."""

import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EXAMPLES = os.path.join(ROOT, "python", "examples")
SCRIPTS = sorted(f for f in os.listdir(EXAMPLES) if f.endswith(".py") and not f.startswith("_") and f != "readme_figure.py")


def python_blocks(path):
    text = open(path, encoding="utf-8").read()
    return re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)


@pytest.mark.parametrize("script", SCRIPTS)
def test_example_script(script):
    r = subprocess.run([sys.executable, os.path.join(EXAMPLES, script)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, f"{script} failed:\n{r.stdout}\n{r.stderr}"
    assert "all checks passed" in r.stdout


def test_readme_figure_script(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "figure.png"
    r = subprocess.run([sys.executable, os.path.join(EXAMPLES, "readme_figure.py"), str(out)], capture_output=True, text=True, timeout=600,
                       env={**os.environ, "MPLBACKEND": "Agg"})
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 10_000


GUIDE_BLOCKS = python_blocks(os.path.join(ROOT, "docs", "guide.md"))


def test_guide_has_python_blocks():
    assert len(GUIDE_BLOCKS) >= 3


@pytest.mark.parametrize("index", range(len(GUIDE_BLOCKS)))
def test_guide_python_block(index, capsys):
    ns: dict = {"__name__": f"guide_block_{index}"}
    exec(compile(GUIDE_BLOCKS[index], f"docs/guide.md (python block {index})", "exec"), ns)
