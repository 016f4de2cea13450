#!/usr/bin/env bash
# The cost of compiling our own crates for test.sh's `cargo test`, with the
# dependency stack already built: the part of a fresh build that changes
# with our code and our profile (docs/development.md, "Measured times").
#
#     ./scripts/build_cost.sh [LABEL]
#
# Builds the dependencies first if they are missing (not timed), then
# deletes our crates' artifacts and incremental caches and times
# `cargo test --workspace --tests --examples --no-run`: prints
# `LABEL: wall W s, CPU C s (user U s, system S s)`. Environment variables
# reach cargo, so `CARGO_INCREMENTAL=0 ./scripts/build_cost.sh no-incremental`
# or `CARGO_PROFILE_DEV_DEBUG=line-tables-only ./scripts/build_cost.sh`
# measure an alternative. It spends several minutes of both cores: run it
# with nothing else building, and compare labels measured in one session.
set -euo pipefail
cd "$(dirname "$0")/.."
label="${1:-build}"
./scripts/python-env.sh >/dev/null
# shellcheck source=scripts/build-env.sh
. scripts/build-env.sh
target_dir="${CARGO_TARGET_DIR:-target}"
cargo test --workspace --tests --examples --no-run --quiet >/dev/null 2>&1
cargo clean --quiet -p framedyn -p framedyn-tests -p framedyn-cli -p framedyn-py
rm -rf "$target_dir/debug/incremental"
times_file="$(mktemp)"
trap 'rm -f "$times_file"' EXIT
/usr/bin/time -o "$times_file" -f "%e %U %S" cargo test --workspace --tests --examples --no-run --quiet >/dev/null
read -r wall user sys <"$times_file"
awk -v l="$label" -v w="$wall" -v u="$user" -v s="$sys" \
    'BEGIN { printf "%s: wall %.0f s, CPU %.0f s (user %.0f s, system %.0f s)\n", l, w, u + s, u, s }'
