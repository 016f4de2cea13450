"""The README's Python example runs as written."""

import os
import re

import numpy as np

README = os.path.join(os.path.dirname(__file__), "..", "..", "README.md")


def test_readme_python_example(capsys):
    text = open(README, encoding="utf-8").read()
    section = text.split("## Python", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    ns: dict = {}
    exec(compile(code, "README.md", "exec"), ns)
    out = capsys.readouterr().out.split()
    assert float(out[0]) < 1e-8  # the energy drift printed
    assert ns["batch"].energy.shape[0] == 8
    assert np.isfinite(ns["sol"].position).all()
