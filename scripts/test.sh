#!/usr/bin/env bash
# Every test of brdfpy, from a fresh clone: needs only Rust (cargo), Python >= 3.9 with pip, and the package
# registries. Installs what the tests need from the project's own files (pyproject.toml), then runs
#   cargo fmt --check, cargo clippy -D warnings (whole workspace), cargo doc -D warnings (whole workspace:
#   broken intra-doc links, e.g. a unit written [rad] instead of \[rad\]), cargo test (brdf-core, brdf-raster),
#   ruff check, ruff format --check, mypy --strict (python/brdfpy), mypy.stubtest (the compiled module's
#   stub), pytest (tests/), and the wheel: `maturin build` (abi3, checked against the manylinux
#   policy by maturin's auditwheel), installed into a fresh venv with cargo and rustc off the PATH, where
#   the tests of the compiled module run against that install (tests/test_packaging.py checks where
#   brdfpy was imported from). The explorer's tests drive a real headless browser: on CI (CI=true) Debian's
#   chromium and chromium-driver are installed here (apt-get, about two minutes) and those tests must run;
#   elsewhere they are skipped, saying why, when the browser is missing.
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

# The cargo profile of the extension the tests import, of `cargo test` and of the wheel checked: ci (the
# release code generation without link-time optimisation, with debug assertions and overflow checks in
# brdfpy's own crates, Cargo.toml) builds in about half the time of release on two cores, and `cargo test`
# reuses its compiled dependencies; BRDFPY_PROFILE=release tests the exact build a release ships.
PROFILE="${BRDFPY_PROFILE:-ci}"

install() {
    "$PY" -m pip install -q 'maturin>=1.9,<2' &&
        # --no-build-isolation: build with the maturin just installed rather than fetching another copy.
        MATURIN_PEP517_ARGS="--profile $PROFILE" "$PY" -m pip install -q --no-build-isolation -e '.[dev]'
}

browser() {
    if command -v chromium >/dev/null && command -v chromedriver >/dev/null; then
        echo "chromium and chromedriver present"
    elif [[ "${CI:-}" == "true" ]]; then
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null
    else
        echo "chromium / chromedriver missing: the browser tests (tests/test_explorer.py) will be skipped;" \
            "apt-get install chromium chromium-driver to run them"
    fi
}

# The manylinux policy the wheel is checked against and tagged with; empty: the highest policy maturin's
# audit finds the extension complies with (which one depends on the build host's glibc).
WHEEL_POLICY="${WHEEL_POLICY:-}"
# Tests run against the installed wheel: every test of the compiled module that needs only the [test] extra.
WHEEL_TESTS=(tests/test_packaging.py tests/test_bindings_smoke.py tests/test_errors.py tests/test_scene_api.py
    tests/test_cli.py tests/test_cli_render.py tests/test_light_convention.py tests/test_pickle.py)

wheel() {
    local work dist venv whl clean_path d
    work="$(mktemp -d)" && dist="$work/dist" && venv="$work/venv" || return 1
    # Profile and target dir of the install step: cargo reuses what that build compiled.
    "$PY" -m maturin build --profile "$PROFILE" --locked ${WHEEL_POLICY:+--compatibility "$WHEEL_POLICY"} \
        --out "$dist" || return 1
    whl="$(ls "$dist"/brdfpy-*.whl)" && echo "built $(basename "$whl")" || return 1
    [[ "$whl" == *-abi3-"${WHEEL_POLICY:-manylinux}"_* ]] || { echo "not an abi3 manylinux wheel: $whl"; return 1; }
    "$PY" -m venv "$venv" || return 1
    # PATH without any folder that holds cargo or rustc: the install must not need a Rust toolchain.
    clean_path="$venv/bin"
    local IFS=:
    for d in $PATH; do
        [[ -x "$d/cargo" || -x "$d/rustc" ]] || clean_path="$clean_path:$d"
    done
    unset IFS
    (
        export PATH="$clean_path" BRDFPY_EXPECT_WHEEL="$whl"
        unset VIRTUAL_ENV PYTHONPATH
        if command -v cargo || command -v rustc; then echo "cargo/rustc still on the PATH"; exit 1; fi
        "$venv/bin/python" -m pip install -q "$whl[test]" &&
            "$venv/bin/python" -m pytest -q -p no:cacheprovider "${WHEEL_TESTS[@]}"
    )
    local status=$?
    rm -rf "$work"
    return $status
}

step "install ($PROFILE build of the extension, test tools)" install
step "headless browser for the explorer tests (Debian chromium, chromium-driver)" browser
step "cargo fmt --check" cargo fmt --all --check
step "cargo clippy -D warnings" cargo clippy --workspace --all-targets -- -D warnings
step "cargo doc -D warnings" env RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace
step "cargo test" cargo test --workspace --profile "$PROFILE" --locked
step "ruff check" "$PY" -m ruff check .
step "ruff format --check" "$PY" -m ruff format --check .
step "mypy --strict" "$PY" -m mypy
step "stubtest" "$PY" -m mypy.stubtest brdfpy._brdfpy --allowlist python/stubtest-allowlist.txt
step "pytest" "$PY" -m pytest
# The wheel step's `maturin build` reuses the install step's build (same profile, target dir and flags:
# measured, 0.1 s of cargo, about 40 s for the step with the clean venv and its tests).
# BRDFPY_WHEEL_CHECK=0 skips it.
if [[ "${BRDFPY_WHEEL_CHECK:-1}" == "1" ]]; then
    step "wheel: maturin build, clean venv without cargo, tests against the install" wheel
else
    printf '\n==> wheel: skipped (BRDFPY_WHEEL_CHECK=0)\n'
fi

if ((${#failed[@]})); then
    printf '\nFAILED steps: %s\n' "$(IFS=,; echo "${failed[*]}")"
    exit 1
fi
printf '\nall steps passed\n'
