#!/usr/bin/env bash
# Configures and builds the float-storage variant (per-pair history and forces in float, arithmetic in
# double: -DGRAINLAB_PAIR_FLOAT=ON) next to the default build, with the same Kokkos. Used by
# perf/speed_vs_error and perf/results.sh; targets default to the two they need.
#   BUILD (default build) must be configured; BUILD_FLOAT (default build-float) is created.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD=${BUILD:-$ROOT/build}
BUILD_FLOAT=${BUILD_FLOAT:-$ROOT/build-float}
[ -f "$BUILD/CMakeCache.txt" ] || { echo "build_float.sh: $BUILD is not configured: run \`make build\` first" >&2; exit 1; }
kokkos=$(sed -n 's/^Kokkos_DIR:[A-Z]*=//p' "$BUILD/CMakeCache.txt")
cmake -S "$ROOT" -B "$BUILD_FLOAT" -DCMAKE_BUILD_TYPE=Release -DGRAINLAB_PAIR_FLOAT=ON -DGRAINLAB_BUILD_TESTS=OFF \
  ${kokkos:+-DKokkos_DIR="$kokkos"} > /dev/null
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(grainlab energy_drift bench_kernels)
cmake --build "$BUILD_FLOAT" -j "$(nproc)" --target "${targets[@]}" > /dev/null
