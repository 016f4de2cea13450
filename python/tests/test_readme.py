"""The README's Python code runs as written."""

import os
import re

import numpy as np

README = os.path.join(os.path.dirname(__file__), "..", "..", "README.md")


def test_readme_python_example(capsys):
    text = open(README, encoding="utf-8").read()
    blocks = re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)
    assert blocks, "no ```python block in the README"
    ns: dict = {}
    for i, code in enumerate(blocks):
        exec(compile(code, f"README.md (python block {i})", "exec"), ns)
    out = capsys.readouterr().out.split()
    assert float(out[0]) < 1e-8  # the energy drift printed by the quick start
    assert ns["batch"].energy.shape[0] == 8
    assert np.isfinite(ns["sol"].position).all()
