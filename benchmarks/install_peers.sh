#!/usr/bin/env bash
# The optional peers of the benchmarks: Mitsuba 3 (bench_models.py, part b) and its LLVM back end.
#   - Debian's libllvm19 (Debian 12 bookworm main): Dr.Jit's llvm_* variants JIT-compile through libLLVM, and
#     Debian 12's default LLVM 15 aborts Dr.Jit's microfacet kernels. bench_models.py finds
#     /usr/lib/*/libLLVM-19.so itself (or set DRJIT_LIBLLVM_PATH to another LLVM >= 16).
#   - mitsuba==3.9.1 and drjit==1.5.0 from PyPI (the extra brdfpy[bench]), into $PYTHON (default python3).
# llvmpipe for bench_render.py is the system's Mesa (see that file). Needs root for apt-get.
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${PYTHON:-$(command -v python3 || command -v python)}"
if ! ls /usr/lib/*/libLLVM-19.so* >/dev/null 2>&1; then
    sudo_=""
    if [[ $(id -u) -ne 0 ]]; then sudo_="sudo"; fi
    $sudo_ apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_ apt-get install -y -qq libllvm19
fi
"$PY" -m pip install -q 'mitsuba==3.9.1' 'drjit==1.5.0'
DRJIT_LIBLLVM_PATH="$(ls /usr/lib/*/libLLVM-19.so* | head -n 1)" "$PY" -c \
    'import mitsuba as mi; mi.set_variant("llvm_ad_rgb"); print("mitsuba", mi.__version__, "llvm_ad_rgb ready")'
