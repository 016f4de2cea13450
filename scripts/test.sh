#!/usr/bin/env bash
# The whole test suite (the README's test command). Rust: every crate of the
# workspace in one shared dev profile (dependencies optimised, see Cargo.toml),
# unit tests, the integration suite, doctests and examples.
set -euo pipefail
cd "$(dirname "$0")/.."
export PROPTEST_CASES="${PROPTEST_CASES:-256}"
# Reproducible property tests in CI; set PROPTEST_RNG_SEED=random (or any
# other number) to explore new cases.
if [ "${PROPTEST_RNG_SEED:-}" = random ]; then unset PROPTEST_RNG_SEED; else export PROPTEST_RNG_SEED="${PROPTEST_RNG_SEED:-20261122}"; fi
cargo test --workspace --all-targets
cargo test --workspace --doc
