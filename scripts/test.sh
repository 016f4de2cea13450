#!/usr/bin/env bash
# The whole test suite (the README's test command). Rust: every crate of the
# workspace in one shared dev profile (dependencies optimised, see Cargo.toml),
# unit tests, the integration suite, doctests and examples.
set -euo pipefail
cd "$(dirname "$0")/.."
export PROPTEST_CASES="${PROPTEST_CASES:-256}"
cargo test --workspace --all-targets
cargo test --workspace --doc
