#!/usr/bin/env bash
# The whole test suite (the README's test command). Rust: every crate of the
# workspace in one shared dev profile (dependencies optimised, see Cargo.toml),
# unit tests, the integration suite, doctests and examples. Python: the
# extension is built by maturin from the same target directory and profile
# (the environment below makes pyo3's build configuration identical, and the
# feature pins in crates/framedyn-py/Cargo.toml the dependency graph, so the
# dependency stack and the core are compiled once), installed into `.venv/`,
# and tested with pytest. docs/development.md: what each step builds and how
# long it takes.
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

# Each step's wall time, printed when it ends (docs/development.md), and the
# CPU time (user + system) of the child processes that ended during it, so
# that runs on a busy and on a quiet machine can be compared in CPU time too
# (the background job's CPU time falls into the step during which it ends).
cpu_file="$(mktemp)"
trap 'rm -f "$cpu_file"' EXIT
# `times` must run in this shell (not in a $(…) subshell) to see its children.
read_cpu() { times > "$cpu_file"; cpu_now=$(awk 'NR == 2 { split($1, u, "m"); split($2, s, "m"); printf "%.0f", u[1] * 60 + u[2] + s[1] * 60 + s[2] }' "$cpu_file"); }
step_start=$SECONDS
read_cpu
step_cpu=$cpu_now
step() {
    read_cpu
    echo "[test.sh] $1: $((SECONDS - step_start)) s (CPU $((cpu_now - step_cpu)) s)"
    step_start=$SECONDS
    step_cpu=$cpu_now
}

./scripts/python-env.sh
step "python environment"
# shellcheck source=scripts/build-env.sh
. scripts/build-env.sh

# Everything below shares one dependency graph, so the core crate is compiled
# once for the Rust tests, the examples and the Python extension (see
# docs/development.md). Every cargo command selects the whole workspace with
# its dev-dependencies (`--workspace` and test or example targets): a command
# on one package (`cargo run -p framedyn-tests --example ...`) resolves fewer
# features in shared dependencies and recompiles the core.
# The core library has no unit-test binary (`test = false`; its internals
# are tested in tests/suite/internals/): a `#[cfg(test)]` there would never
# be compiled, so its tests would silently not run.
if grep -rln --include='*.rs' -e '#\[cfg(test)\]' -e '#\[test\]' crates/framedyn/src; then
    echo "the files above hold tests inside the core library, which has no test binary:" >&2
    echo "move them to tests/suite/internals/ (docs/development.md, \"Why the core has no unit-test binary\")" >&2
    exit 1
fi
# The dev profile's opt-level-0 exceptions must not reach a binary of ours
# (Cargo.toml explains why; a few seconds of `cargo metadata`).
"$PY" scripts/check_profile.py
# The downstream crate's lock file (scripts/release_check.sh builds it with
# --locked, long after this script) must follow the workspace's dependency
# changes: checked here in a second, rather than at the end of CI.
if ! cargo metadata --locked --format-version 1 --manifest-path examples/downstream/Cargo.toml >/dev/null; then
    echo "examples/downstream/Cargo.lock is out of date: run 'cargo metadata --format-version 1 --manifest-path examples/downstream/Cargo.toml >/dev/null' and commit it" >&2
    exit 1
fi
# `--tests --examples`, not `--all-targets`: the test harnesses of every
# library that has tests (the CLI's; the core, the extension and
# framedyn-tests have none, `test = false`), the integration tests and the
# examples (compiled as test harnesses: a compile check). `--all-targets`
# would also compile those three empty library harnesses and the criterion
# bench; the bench harness and the API docs are checked by
# scripts/check_more.sh, which CI runs after this script (docs/development.md,
# "The two commands", has what each costs).
cargo test --workspace --tests --examples
step "cargo test (build and run)"
# maturin builds the extension crate alone; crates/framedyn-py/Cargo.toml
# pins the features that the workspace build turns on, so that the core's
# dependency graph is the same and only the extension crate is compiled.
# If a dependency update breaks that, say so instead of silently doubling
# the build time.
target_dir="${CARGO_TARGET_DIR:-target}"
stamp="$(mktemp)"
beside_log=""
beside_pid=""
trap 'rm -f "$stamp" "$beside_log" "$cpu_file"; if [ -n "$beside_pid" ]; then kill "$beside_pid" 2>/dev/null || true; fi' EXIT
# The extension is an abi3 module (_framedyn.abi3.so); a version-specific
# one left by a build before the switch would shadow it on import.
rm -f python/framedyn/_framedyn.cpython-*.so
"$FRAMEDYN_VENV/bin/maturin" develop --quiet
if [ -n "$(find "$target_dir/debug/deps" -maxdepth 1 -name 'libframedyn-*.rlib' -newer "$stamp")" ]; then
    echo "maturin compiled the core crate a second time: a shared dependency's features differ between" >&2
    echo "'cargo test --workspace' and the extension's build; update the feature pins in" >&2
    echo "crates/framedyn-py/Cargo.toml (docs/development.md explains how to find them)." >&2
    exit 1
fi
step "maturin develop"

# The doctests and the seven checking examples (both cargo, after the last
# build that pytest needs) run in the background, beside pytest, which needs
# no cargo: pytest alone keeps one core busy. Their output is printed, and
# their failure fails the script, when pytest has ended.
# The examples compare what they measure with the paper's closed forms and
# exit with status 1 on a mismatch. `cargo test` compiled them only as test
# harnesses (no `main`); the programs themselves are built here.
examples=(transport_through_pole s2_bodies h2_bodies t2_bodies s3_bodies potential_families user_potential)
beside_log="$(mktemp)"
(
    set -e
    beside_start=$SECONDS
    cargo test --workspace --doc
    echo "[test.sh] doctests (beside pytest): $((SECONDS - beside_start)) s"
    cargo build --quiet --workspace "${examples[@]/#/--example=}"
    for example in "${examples[@]}"; do
        echo "example $example"
        "$target_dir/debug/examples/$example"
    done
    echo "[test.sh] doctests and examples (beside pytest): $((SECONDS - beside_start)) s"
) >"$beside_log" 2>&1 &
beside_pid=$!

# The Agg backend: the plotting tests draw without a display.
MPLBACKEND=Agg "$PY" -m pytest python/tests -q
step "pytest"

beside_status=0
wait "$beside_pid" || beside_status=$?
beside_pid=""
cat "$beside_log"
if [ "$beside_status" -ne 0 ]; then
    echo "the doctests or a checking example failed (exit status $beside_status): see above" >&2
    exit "$beside_status"
fi
step "waiting for the doctests and examples"

