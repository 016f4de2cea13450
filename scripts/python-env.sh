#!/usr/bin/env bash
# Creates (once) the project's Python virtual environment `.venv/` and installs
# the build and test requirements from PyPI into it, leaving the machine's
# site-packages untouched. Sourced by scripts/test.sh; run directly by .ci/run.
# Override the interpreter with PYTHON=..., the location with FRAMEDYN_VENV=...
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
FRAMEDYN_VENV="${FRAMEDYN_VENV:-$PWD/.venv}"
# What the build and the Python tests need (dask is optional for users and
# installed here so that the ensemble helper is tested).
REQUIREMENTS=(
  "maturin>=1.9.4,<2" "pytest>=7" "numpy>=1.21" "scipy>=1.9" "hypothesis>=6"
  "matplotlib>=3.5" "mypy>=1.5" "dask[distributed]>=2023.1"
)
stamp="$FRAMEDYN_VENV/.framedyn-requirements"
if [ ! -x "$FRAMEDYN_VENV/bin/python" ]; then
  "${PYTHON:-python3}" -m venv "$FRAMEDYN_VENV"
fi
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "${REQUIREMENTS[*]}" ]; then
  "$FRAMEDYN_VENV/bin/python" -m pip install --quiet --disable-pip-version-check "${REQUIREMENTS[@]}"
  printf '%s' "${REQUIREMENTS[*]}" > "$stamp"
fi
