#!/usr/bin/env bash
# Builds tools/pinocchio_bench/main.cpp against the `pin` wheel (Pinocchio's C++ libraries and
# headers; Eigen's and urdfdom's headers from cmeel-eigen and cmeel-urdfdom-headers) into
# tools/.build/pinocchio_bench, then runs tools/benchmarks.py, which interleaves it with
# `hya bench` and writes BENCHMARKS.md. Options are passed to benchmarks.py.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="${HYA_VENV:-$here/.venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q pin numpy cmeel-eigen cmeel-urdfdom-headers
prefix="$("$venv/bin/python" -c 'import cmeel; print(cmeel.__path__[0])' 2>/dev/null || true)"
[ -d "$prefix/include/pinocchio" ] || prefix="$(find "$venv" -maxdepth 5 -type d -name cmeel.prefix | head -n 1)"
mkdir -p "$here/.build"
binary="$here/.build/pinocchio_bench"
# Flags: -march=native like hya's release build here; EIGEN_MAX_ALIGN_BYTES=16 and
# EIGEN_MALLOC_ALREADY_ALIGNED=1 because the model is built by the wheel's baseline-x86-64
# parser library (else freeing it crashes); the Boost limits are those Pinocchio's CMake exports;
# OpenMP for rneaInParallel (header-only in the wheel).
flags=(-O3 -march=native -DNDEBUG -std=c++17 -w -fopenmp
  -DEIGEN_MAX_ALIGN_BYTES=16 -DEIGEN_MALLOC_ALREADY_ALIGNED=1
  -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS
  -DBOOST_FUSION_INVOKE_MAX_ARITY=12 -DPINOCCHIO_WITH_URDFDOM)
if [ ! -x "$binary" ] || [ "$here/pinocchio_bench/main.cpp" -nt "$binary" ]; then
  echo "building $binary (a few minutes: Pinocchio is template-heavy)" >&2
  g++ "${flags[@]}" -I"$prefix/include" -I"$prefix/include/eigen3" -I"$prefix/include/urdfdom_headers" \
    -I"$prefix/include/urdfdom" "$here/pinocchio_bench/main.cpp" -o "$binary" \
    -L"$prefix/lib" -lpinocchio_parsers -lpinocchio_default -Wl,-rpath,"$prefix/lib"
fi
PINOCCHIO_VERSION="$("$venv/bin/python" -c 'import pinocchio; print(pinocchio.__version__)')" \
PINOCCHIO_FLAGS="${flags[*]}" python3 "$here/benchmarks.py" --pinocchio "$binary" "$@"
