#!/usr/bin/env bash
# The slower checks that the README's test command leaves out and CI runs
# right after it (.ci/run), in the same dev profile and target directory,
# so that after ./scripts/test.sh only the bench itself is compiled:
#
# 1. the criterion bench `step_cost` as a test harness (`cargo test --bench`
#    runs each of its benchmarks once: a check that every benchmark builds
#    and runs, not a measurement);
# 2. the API docs without warnings (`cargo doc -D warnings`: broken
#    intra-doc links, missing docs).
#
# docs/development.md, "The two commands", says why these are not in
# test.sh and what they cost.
set -euo pipefail
cd "$(dirname "$0")/.."

step_start=$SECONDS
step() { echo "[check_more.sh] $1: $((SECONDS - step_start)) s"; step_start=$SECONDS; }

./scripts/python-env.sh
# shellcheck source=scripts/build-env.sh
. scripts/build-env.sh

cargo test --workspace --bench step_cost
step "bench harness (build and run once)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
step "cargo doc"
