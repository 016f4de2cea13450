# Sourced (not run) by scripts/test.sh and scripts/check_more.sh, after
# scripts/python-env.sh has created `.venv/`: the environment under which
# cargo and maturin build the same dependency graph, so that the core is
# compiled once for the Rust tests, the examples, the bench and the Python
# extension (docs/development.md, "Why the core is compiled once").
export FRAMEDYN_VENV="${FRAMEDYN_VENV:-$PWD/.venv}"
PY="$FRAMEDYN_VENV/bin/python"
# What maturin sets when it builds the extension; set for cargo too, so that
# pyo3's build script sees the same configuration and nothing is rebuilt.
export VIRTUAL_ENV="$FRAMEDYN_VENV"
export PYO3_PYTHON="$PY"
export PYTHON_SYS_EXECUTABLE="$PY"
export PYO3_BUILD_EXTENSION_MODULE=1
PYO3_ENVIRONMENT_SIGNATURE="$("$PY" - <<'PYEOF'
import platform, struct
impl = platform.python_implementation().lower()
major, minor = platform.python_version_tuple()[:2]
print(f"{impl}-{major}.{minor}-{struct.calcsize('P') * 8}bit")
PYEOF
)"
export PYO3_ENVIRONMENT_SIGNATURE
