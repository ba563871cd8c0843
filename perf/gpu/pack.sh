#!/usr/bin/env bash
# Packs the CUDA build (make gpu) for a GPU machine that has the CUDA driver but none of our build
# dependencies: the executables and CTest files of build-gpu/, the shared libraries they load beyond the
# C runtime (HDF5, yaml-cpp, cudart, ...), and the race scene. Output: .gpucarry/ (git-ignored), which
# the lent-GPU tool carries with the working tree; perf/gpu/device.sh unpacks and runs it there.
#   make gpu && perf/gpu/pack.sh
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
GPU_BUILD=${GPU_BUILD:-build-gpu}
PEERS_DIR=${PEERS_DIR:-$ROOT/../shared/bench/peers}
C="$ROOT/.gpucarry"
cd "$ROOT"
[ -x "$GPU_BUILD/grainlab" ] || { echo "pack.sh: $GPU_BUILD/grainlab not found: run 'make gpu' first" >&2; exit 1; }
rm -rf "$C"; mkdir -p "$C/lib" "$C/scene"
mapfile -t exes < <(find "$GPU_BUILD" -path "$GPU_BUILD/CMakeFiles" -prune -o -type f -perm -u+x -print)
mapfile -t extra < <(find "$GPU_BUILD" -path "$GPU_BUILD/CMakeFiles" -prune -o \
                       \( -name CTestTestfile.cmake -o -path "*/bad_configs/*" \) -type f -print)
# The configs CMake writes beside the tests (tests/cyclic.yaml); not the outputs of a test run there.
mapfile -t -O "${#extra[@]}" extra < <(find "$GPU_BUILD/tests" -maxdepth 1 -name "*.yaml" -type f)
# xz: the fat binaries (sm_80 + sm_90 machine code + PTX) shrink ~5x, which keeps the carry under its limit.
tar -cf - "${exes[@]}" "${extra[@]}" | xz -T0 -6 > "$C/build-gpu.tar.xz"
# Libraries: everything ldd resolves except the C runtime. device.sh puts on the library path only those
# the GPU machine lacks, so that its own (newer) libstdc++ or libssl is never shadowed by ours.
for e in "${exes[@]}"; do ldd "$e"; done | awk '/=> \//{print $3}' | sort -u | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libdl.so*|libpthread.so*|librt.so*|ld-linux*|libresolv.so*) ;;
    *) cp -L "$lib" "$C/lib/" ;;
  esac
done
git -C "$ROOT" describe --always --dirty > "$C/commit.txt"  # the tree the binaries were built from
# BASE_BUILD=<an older build-gpu>: its race_bench rides along (device.sh base), so that a change is timed
# against its base on the same card in the same call, not against numbers from another machine.
if [ -n "${BASE_BUILD:-}" ]; then
  xz -T0 -6 -c "$BASE_BUILD/perf/race_bench" > "$C/race_bench_base.xz"
  git -C "$BASE_BUILD/.." describe --always --dirty > "$C/base_commit.txt"
fi
# CTest's cost data of the CPU build (build/, `make test`), the gtests renamed to their one CUDA entry: a fresh
# GPU machine then orders them longest first (study_quick) instead of as they are declared.
if [ -f "${BUILD:-build}/Testing/Temporary/CTestCostData.txt" ]; then
  awk '$0 == "---" {exit} / /{n = split($1, a, ".")} a[n] == "omp1" {next} {sub(/\.omp2$/, ".cuda", $1)} NF == 3; END {print "---"}' \
    "${BUILD:-build}/Testing/Temporary/CTestCostData.txt" > "$C/CTestCostData.txt"
fi
cp "$PEERS_DIR/scene_32k.txt" "$PEERS_DIR/scene_32k_box.txt" "$C/scene/"
echo "pack.sh: $(du -sh "$C" | cut -f1) in $C (${#exes[@]} executables, $(ls "$C/lib" | wc -l) libraries)"
