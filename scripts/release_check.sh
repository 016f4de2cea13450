#!/usr/bin/env bash
# The release check: framedyn as users install it (docs/development.md,
# "Release check"). From the repository root:
#
#     ./scripts/release_check.sh
#
# 1. the release wheel (maturin, abi3 for CPython >= 3.9, manylinux2014
#    linked by zig, checked by maturin's auditwheel) and the sdist;
# 2. a fresh virtual environment that installs the wheel and numpy (binary
#    only) and runs a smoke test with no Rust toolchain on PATH: import,
#    __version__, a solve, a columnar batch, the `framedyn` console script,
#    the type stubs;
# 3. `cargo package` of the two publishable crates, verified (each built from
#    its packaged files), with no warning;
# 4. the downstream crate examples/downstream (outside the workspace, depends
#    on framedyn by path) built and run: it exits 1 when a check fails.
# Exits non-zero on the first failure. Not part of scripts/test.sh; .ci/run
# runs it after the test suite. Output goes to target/release-check/.
set -euo pipefail
cd "$(dirname "$0")/.."

step_start=$SECONDS
step() { echo "[release_check] $1: $((SECONDS - step_start)) s"; step_start=$SECONDS; }
fail() { echo "release_check: $*" >&2; exit 1; }

./scripts/python-env.sh
FRAMEDYN_VENV="${FRAMEDYN_VENV:-$PWD/.venv}"
PY="$FRAMEDYN_VENV/bin/python"
PYTHON="${PYTHON:-python3}"
# The one version: the workspace's (crates inherit it; maturin reads it into
# the wheel's metadata; the CLI's --version and framedyn.__version__ report it).
VERSION="$("$PY" - <<'PYEOF'
import tomllib
with open("Cargo.toml", "rb") as f:
    print(tomllib.load(f)["workspace"]["package"]["version"])
PYEOF
)"
# The manylinux policy of the wheel: manylinux2014 (glibc >= 2.17), as
# polars and pydantic-core ship theirs. Linked on this machine (glibc 2.36)
# the extension needs GLIBC_2.35 symbols, so the wheel is linked by zig
# against glibc 2.17 (`maturin build --zig`; the `ziglang` package from PyPI,
# installed into .venv/ here); it measured as fast as the natively linked
# one (docs/development.md, "manylinux"). FRAMEDYN_MANYLINUX=manylinux_2_35
# builds the native wheel instead, without zig.
MANYLINUX="${FRAMEDYN_MANYLINUX:-manylinux2014}"
zig=()
case "$MANYLINUX" in
    manylinux_2_35|manylinux_2_36) wheel_tag="$MANYLINUX" ;;
    manylinux2014|manylinux_2_17)
        wheel_tag="manylinux2014_$(uname -m).manylinux_2_17"
        zig=(--zig)
        "$PY" -m pip install --quiet --disable-pip-version-check "ziglang>=0.13,<0.18" ;;
    *) fail "FRAMEDYN_MANYLINUX=$MANYLINUX: this script builds manylinux2014 (with zig) or manylinux_2_35 (natively)" ;;
esac
OUT="$PWD/target/release-check"
rm -rf "$OUT"
mkdir -p "$OUT/dist"
echo "release check of framedyn $VERSION"

# --- 1. wheel and sdist ------------------------------------------------------
# PATH starts with .venv/bin: maturin runs zig as `python3 -m ziglang`.
PATH="$FRAMEDYN_VENV/bin:$PATH" "$FRAMEDYN_VENV/bin/maturin" build --release "${zig[@]}" --compatibility "$MANYLINUX" --auditwheel check --out "$OUT/dist"
wheel="$OUT/dist/framedyn-$VERSION-cp39-abi3-${wheel_tag}_$(uname -m).whl"
[ -f "$wheel" ] || fail "expected the wheel $(basename "$wheel"), found: $(ls "$OUT/dist")"
"$FRAMEDYN_VENV/bin/maturin" sdist --out "$OUT/dist"
sdist="$OUT/dist/framedyn-$VERSION.tar.gz"
[ -f "$sdist" ] || fail "expected the sdist $(basename "$sdist"), found: $(ls "$OUT/dist")"
"$PY" - "$wheel" "$sdist" <<'PYEOF'
import sys, tarfile, zipfile
wheel, sdist = sys.argv[1:]
names = zipfile.ZipFile(wheel).namelist()
for want in ("framedyn/__init__.py", "framedyn/py.typed", "framedyn/_framedyn.pyi", "framedyn/_framedyn.abi3.so"):
    if want not in names:
        sys.exit(f"release_check: the wheel lacks {want}")
if not any(n.endswith("licenses/LICENSE-MIT") for n in names) or not any(n.endswith("licenses/LICENSE-APACHE") for n in names):
    sys.exit("release_check: the wheel lacks the license files")
members = tarfile.open(sdist).getnames()
for want in ("pyproject.toml", "Cargo.toml", "Cargo.lock", "crates/framedyn/src/lib.rs", "crates/framedyn-py/src/lib.rs", "python/framedyn/__init__.py", "LICENSE-MIT", "LICENSE-APACHE"):
    if not any(m.endswith("/" + want) for m in members):
        sys.exit(f"release_check: the sdist lacks {want}")
print(f"wheel: {len(names)} files; sdist: {len(members)} entries")
PYEOF
step "wheel and sdist"

# --- 2. install and smoke-test without a Rust toolchain -----------------------
# PATH without ~/.cargo/bin or any directory holding cargo, rustc or rustup.
clean_path=""
IFS=: read -r -a path_dirs <<< "$PATH"
for d in "${path_dirs[@]}"; do
    case "$d" in *cargo*|*rustup*|"") continue ;; esac
    if [ -e "$d/cargo" ] || [ -e "$d/rustc" ] || [ -e "$d/rustup" ]; then continue; fi
    clean_path="${clean_path:+$clean_path:}$d"
done
smoke="$OUT/smoke"
"$PYTHON" -m venv "$smoke/venv"
(
    cd "$smoke"
    export PATH="$smoke/venv/bin:$clean_path"
    unset CARGO_HOME RUSTUP_HOME RUSTC CARGO VIRTUAL_ENV PYO3_PYTHON PYTHONPATH
    ! command -v cargo >/dev/null || fail "cargo is still on PATH: $(command -v cargo)"
    # Binary only: pip must not fall back to building anything from source.
    python -m pip install --quiet --disable-pip-version-check --only-binary :all: "$wheel" "numpy>=1.21"
    python - "$VERSION" <<'PYEOF'
import os, pathlib, shutil, subprocess, sys, warnings

version = sys.argv[1]
assert shutil.which("cargo") is None and shutil.which("rustc") is None, "a Rust toolchain is on PATH"
import numpy as np
import framedyn as fd

pkg = pathlib.Path(fd.__file__).parent
assert pathlib.Path(sys.prefix) in pkg.parents, f"framedyn imported from {pkg}, not from the fresh environment"
assert fd.__version__ == version, (fd.__version__, version)
for stub in ("py.typed", "_framedyn.pyi"):
    assert (pkg / stub).is_file(), f"{stub} not installed"

sol = fd.solve(fd.Scene.example("s2-gyroscope-pole"))
assert sol.t[-1] > 0 and np.isfinite(sol.energy).all(), sol.stats
assert sol.stats["energy_drift"] < 1e-8 and sol.position[:, 2].max() > 0.999, sol.stats
scene = fd.Scene(
    manifold={"kind": "S2", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
    potential={"kind": "cosine", "beta_hat": -0.3},
    r=0.6, phi=0.0, r_dot=-1.0, spin=0.02, method="rk4", h=0.005, t_end=4.0,
)
batch = fd.solve_batch(scene, {"initial.r": np.linspace(0.2, 1.0, 8)}, keep="final")
assert (batch.status == "finished").all() and batch.final.shape[0] == 8 and np.isfinite(batch.final).all()
try:
    fd.Scene.from_toml("format = 2\n" + fd.Scene.example("s2-gyroscope-pole").to_toml())
except fd.InvalidInputError as e:
    assert "format" in str(e), e
else:
    raise AssertionError("a scene of format 2 was accepted")

exe = shutil.which("framedyn")
assert exe is not None and pathlib.Path(exe).parent == pathlib.Path(sys.prefix) / "bin", exe
out = subprocess.run([exe, "--version"], capture_output=True, text=True, check=True).stdout
assert out.strip() == f"framedyn {version}", out
run = subprocess.run([exe, "run", "--output", "x.csv", "--quiet"], capture_output=True, text=True)
assert run.returncode == 0, (run.returncode, run.stdout, run.stderr)
header = pathlib.Path("x.csv").read_text().splitlines()[0].split(",")
assert header[0] == "t" and "energy" in header, header
print(f"smoke test passed: framedyn {fd.__version__} from {pkg}, {len(sol.t)} records, batch of 8, console script {exe}")
PYEOF
)
step "wheel smoke test without a Rust toolchain"

# --- 3. the publishable crates ------------------------------------------------
# Packaged together: framedyn-cli's dependency on the unpublished framedyn is
# resolved from a local registry overlay of the package just made. Any
# warning (missing metadata, files left out of a target) fails the check.
#
# Cargo treats a registry package as immutable: it extracts the overlay's
# framedyn-$VERSION into $CARGO_HOME/registry/src/-<hash of the overlay path>/
# once and compiles it once per target directory, keyed by name and version
# only. A second check at the same path (CI checks out to a fixed directory)
# would therefore verify framedyn-cli against the framedyn of an earlier
# commit. So the stale extraction is removed, and the verification builds in
# a target directory of its own whose framedyn artifacts are cleaned, which
# leaves the test build in target/ alone.
PKG_TARGET="$PWD/target/package-verify"
cargo_home="${CARGO_HOME:-$HOME/.cargo}"
for crate in framedyn framedyn-cli; do
    rm -rf "$cargo_home"/registry/src/-*/"$crate-$VERSION"
done
if [ -d "$PKG_TARGET" ]; then
    cargo clean --quiet --target-dir "$PKG_TARGET" -p framedyn -p framedyn-cli
fi
dirty=()
if [ -n "$(git status --porcelain -- crates Cargo.toml Cargo.lock README.md LICENSE-MIT LICENSE-APACHE)" ]; then
    echo "note: uncommitted changes in the packaged files, packaging with --allow-dirty"
    dirty=(--allow-dirty)
fi
cargo package -p framedyn -p framedyn-cli --locked --target-dir "$PKG_TARGET" "${dirty[@]}" \
    2> >(tee "$OUT/package.log" >&2)
if grep -n "^warning" "$OUT/package.log"; then
    fail "cargo package warned (above; full log in $OUT/package.log)"
fi
for crate in framedyn framedyn-cli; do
    listing="$(tar -tzf "$PKG_TARGET/package/$crate-$VERSION.crate")"
    for want in Cargo.toml README.md LICENSE-MIT LICENSE-APACHE src/lib.rs; do
        grep -qx "$crate-$VERSION/$want" <<< "$listing" || fail "the $crate package lacks $want"
    done
done
step "cargo package (verified)"

# --- 4. a downstream crate ----------------------------------------------------
# Its own workspace and lock file; it builds in the verification's target
# directory (same profile, so the dependencies build once). Its framedyn is a
# path dependency, a different package from the overlay's, so it is rebuilt
# from the working tree.
CARGO_TARGET_DIR="$PKG_TARGET" cargo run --locked --manifest-path examples/downstream/Cargo.toml
step "downstream crate (build and run)"
echo "release check passed: $(basename "$wheel"), $(basename "$sdist"), framedyn and framedyn-cli $VERSION packaged"
