#!/usr/bin/env bash
# Every test of brdfpy, from a fresh clone: needs only Rust (cargo), Python >= 3.9 with pip, and the package
# registries. Installs what the tests need from the project's own files, then runs, in order:
#   cargo fmt --check, cargo clippy -D warnings (whole workspace), cargo test (brdf-core, brdf-raster),
#   ruff check, ruff format --check, mypy --strict (python/brdfpy), pytest (tests/).
# Stops at the first failure. CI (`.ci/run`) runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."

export PIP_ROOT_USER_ACTION=ignore PIP_DISABLE_PIP_VERSION_CHECK=1
# Deterministic, thorough property tests in CI; quick ones locally.
if [[ "${CI:-}" == "true" ]]; then export HYPOTHESIS_PROFILE="${HYPOTHESIS_PROFILE:-ci}"; fi

step() { printf '\n==> %s\n' "$*"; }

step "install: build the Rust extension (maturin, release) and the test tools"
python -m pip install -q 'maturin>=1.9,<2'
# --no-build-isolation: use the maturin just installed instead of fetching a second copy per build.
python -m pip install -q --no-build-isolation -e '.[dev]'

step "cargo fmt --check"
cargo fmt --all --check

step "cargo clippy --workspace --all-targets -D warnings"
cargo clippy --workspace --all-targets -- -D warnings

step "cargo test (brdf-core, brdf-raster: the crates without Python)"
cargo test

step "ruff check"
ruff check .

step "ruff format --check"
ruff format --check .

step "mypy --strict (python/brdfpy)"
mypy

step "pytest"
python -m pytest
