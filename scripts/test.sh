#!/usr/bin/env bash
# The whole test suite (the README's test command). Rust: every crate of the
# workspace in one shared dev profile (dependencies optimised, see Cargo.toml),
# unit tests, the integration suite, doctests and examples. Python: the
# extension is built by maturin from the same target directory and profile
# (the environment below makes pyo3's build configuration identical, so the
# dependency stack is compiled once), installed into `.venv/`, and tested with
# pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each property test runs its own case count: 256 (proptest's default)
# unless the test sets fewer — those that integrate trajectories or refine
# step sizes per case set 12–64. PROPTEST_CASES=N, if set, overrides every
# test's count (proptest reads it over the test's own configuration); it is
# not set here: at 256 for every test the integration suite took 150 s of
# the CI run instead of 36 s.
# Reproducible property tests in CI; set PROPTEST_RNG_SEED=random (or any
# other number) to explore new cases.
if [ "${PROPTEST_RNG_SEED:-}" = random ]; then unset PROPTEST_RNG_SEED; else export PROPTEST_RNG_SEED="${PROPTEST_RNG_SEED:-20261122}"; fi

./scripts/python-env.sh
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

cargo test --workspace --all-targets
cargo test --workspace --doc
# The API docs build without warnings (broken intra-doc links, missing docs).
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
# The examples compare what they measure with the paper's closed forms and
# exit with status 1 on a mismatch.
for example in transport_through_pole s2_bodies h2_bodies t2_bodies s3_bodies potential_families user_potential; do
    cargo run --quiet -p framedyn --example "$example"
done

"$FRAMEDYN_VENV/bin/maturin" develop --quiet
# The Agg backend: the plotting tests draw without a display.
MPLBACKEND=Agg "$PY" -m pytest python/tests -q
