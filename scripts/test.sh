#!/usr/bin/env bash
# Every test of brdfpy, from a fresh clone: needs only Rust (cargo), Python >= 3.9 with pip, and the package
# registries. Installs what the tests need from the project's own files (pyproject.toml), then runs
#   cargo fmt --check, cargo clippy -D warnings (whole workspace), cargo doc -D warnings (whole workspace:
#   broken intra-doc links, e.g. a unit written [rad] instead of \[rad\]), cargo test (brdf-core, brdf-raster),
#   ruff check, ruff format --check, mypy --strict (python/brdfpy), mypy.stubtest (the compiled module's
#   stub), pytest (tests/).
# Every step runs even after a failure, so one run shows every problem; the exit status is non-zero if any
# step failed. CI (`.ci/run`) runs exactly this.
set -uo pipefail
cd "$(dirname "$0")/.."

export PIP_ROOT_USER_ACTION=ignore PIP_DISABLE_PIP_VERSION_CHECK=1
# The interpreter to install into and test with: $PYTHON, else python3, else python. Tools run as modules of
# it (python -m ruff, ...), so nothing depends on where pip puts console scripts.
PY="${PYTHON:-$(command -v python3 || command -v python)}"
# Thorough property tests in CI (tests/conftest.py defines the profiles); quick ones locally.
if [[ "${CI:-}" == "true" ]]; then export HYPOTHESIS_PROFILE="${HYPOTHESIS_PROFILE:-ci}"; fi

failed=()
step() {
    local name="$1"
    shift
    printf '\n==> %s\n' "$name"
    local t0=$SECONDS
    if "$@"; then
        printf '<== %s: ok (%ds)\n' "$name" $((SECONDS - t0))
    else
        printf '<== %s: FAILED (%ds)\n' "$name" $((SECONDS - t0))
        failed+=("$name")
    fi
}

install() {
    "$PY" -m pip install -q 'maturin>=1.9,<2' &&
        # --no-build-isolation: build with the maturin just installed rather than fetching another copy.
        "$PY" -m pip install -q --no-build-isolation -e '.[dev]'
}

step "install (maturin release build of the extension, test tools)" install
step "cargo fmt --check" cargo fmt --all --check
step "cargo clippy -D warnings" cargo clippy --workspace --all-targets -- -D warnings
step "cargo doc -D warnings" env RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace
step "cargo test" cargo test
step "ruff check" "$PY" -m ruff check .
step "ruff format --check" "$PY" -m ruff format --check .
step "mypy --strict" "$PY" -m mypy
step "stubtest" "$PY" -m mypy.stubtest brdfpy._brdfpy --allowlist python/stubtest-allowlist.txt
step "pytest" "$PY" -m pytest

if ((${#failed[@]})); then
    printf '\nFAILED steps: %s\n' "$(IFS=,; echo "${failed[*]}")"
    exit 1
fi
printf '\nall steps passed\n'
