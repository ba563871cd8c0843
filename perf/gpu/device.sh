#!/usr/bin/env bash
# Runs on the lent GPU machine over a copy of the working tree with .gpucarry/ (perf/gpu/pack.sh) carried.
# Everything it measures lands in $OUT (the tool's result folder; ./gpu-out elsewhere).
#   perf/gpu/device.sh tests [REGEX]   the CTest suite on the CUDA backend (or the tests REGEX selects, @unpassed:
#                                      those no earlier call on this machine passed; env
#                                      GPU_TESTS_EXCLUDE, GPU_TESTS_SECONDS, GPU_TESTS_JOBS, GPU_TESTS_GPU_SLOTS: see the verb)
#   perf/gpu/device.sh bench [REPS]    copy bandwidth + race scene 32k .. 11M, rolling on/off (perf/RESULTS.md)
#   perf/gpu/device.sh base [TILES]    the race bench of an older build (pack.sh BASE_BUILD=...) at the tiles
#                                      "TILES" (default "1 4"), rolling on: a baseline on the same card, same call
#   perf/gpu/device.sh ur1 [SECONDS]   configs/paper/UR1.yaml end to end (stopped after SECONDS, default 540)
#   perf/gpu/device.sh memory [COUNTS] device memory of configs/quick.yaml's run at COUNT spheres (default
#                                      "250000 1000000 4000000") and of the race scene at 2M and 11M: the bytes
#                                      per sphere behind the memory check, loose and dense
#   perf/gpu/device.sh profile [TILE]  each kernel's GPU time over 20 race steps (Nsight Compute), next to the
#                                      step's wall time: what the per-step constant is made of (TILE 1 = 32k)
# Several verbs run in order: perf/gpu/device.sh tests bench
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
C="$ROOT/.gpucarry"
OUT=${OUT:-$ROOT/gpu-out}
mkdir -p "$OUT"
cd "$ROOT"
[ -f "$C/build-gpu.tar.xz" ] || { echo "device.sh: $C/build-gpu.tar.xz missing: run perf/gpu/pack.sh and carry .gpucarry" >&2; exit 1; }
[ -x build-gpu/grainlab ] || tar -xJf "$C/build-gpu.tar.xz"
# Only the libraries this machine lacks go on the path (pack.sh's comment says why).
mkdir -p /tmp/gpucarry-lib
for lib in "$C"/lib/*; do
  ldconfig -p | grep -q "^[[:space:]]*$(basename "$lib") " || ln -sf "$lib" /tmp/gpucarry-lib/
done
export LD_LIBRARY_PATH=/tmp/gpucarry-lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
# A Python with numpy, h5py and matplotlib for the CLI's plots and the tests' checks (the GPU image keeps
# them in its PyTorch environment; its /usr/bin/python3 has none): GRAINLAB_PYTHON is honoured by the
# program (src/main.cpp) and by the test scripts.
for py in "${GRAINLAB_PYTHON:-}" /opt/torch/.venv/bin/python3 "$(command -v python3)" /usr/bin/python3; do
  [ -n "$py" ] && [ -x "$py" ] && "$py" -c "import numpy, h5py, matplotlib" 2>/dev/null && { export GRAINLAB_PYTHON=$py; break; }
done
echo "python: ${GRAINLAB_PYTHON:-none with numpy, h5py and matplotlib}"
# The CTest files name the paths of the machine that built them.
old_root=$(sed -n 's/^# Source directory: //p' build-gpu/CTestTestfile.cmake)
# So do the configs CMake writes for the tests (bad_configs/, cyclic.yaml). Only a quoted argument that is a
# python3's path is replaced: cli_plot_no_python's "GRAINLAB_PYTHON=/nonexistent/python3" became the python itself,
# which then ran grainlab as a script (session 47).
# NUL-separated: a test's output left by an earlier call on this machine has paths with spaces (study_prep's
# "Bob's study"), which a word-split list handed to sed in pieces (session 49).
find build-gpu -path build-gpu/CMakeFiles -prune -o \( -name CTestTestfile.cmake -o -name "*.yaml" \) -type f -print0 |
while IFS= read -r -d '' f; do
  sed -i -e "s#$old_root#$ROOT#g" -e "s#\"/usr/bin/cmake\"#\"$(command -v cmake)\"#g" \
         -e "s#\"/[^\"]*/python3\"#\"${GRAINLAB_PYTHON:-python3}\"#g" "$f"
done
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv | tee "$OUT/device.txt"
echo "carried libraries used: $(ls /tmp/gpucarry-lib | tr '\n' ' ')" | tee -a "$OUT/device.txt"
{ sed "s/^/binaries built at commit /" "$C/commit.txt"; cp "$C/commit.txt" "$OUT/commit.txt"; } 2>/dev/null | tee -a "$OUT/device.txt"

S="$C/scene"
PASSED_ALL=/tmp/gpu_tests_passed_all.txt  # the entries passed by every `tests` call on this machine so far
status=0
while [ $# -gt 0 ]; do
  case "$1" in
    tests)  # tests [REGEX]: all of them, or those CTest's -R selects
      regex=""; if [ $# -gt 1 ] && [[ "$2" != tests && "$2" != bench && "$2" != base && "$2" != ur1 && "$2" != profile && "$2" != memory ]]; then regex=$2; shift
        # @FILE: the regex a first call wrote (tests_rest.txt, copied into the tree). An empty regex is refused: CTest
        # would run every entry, and a "$(cat FILE)" of a file that is not there says nothing else (session 43 lost
        # a call's 240 s so, to study_quick).
        # @unpassed: every entry no call has passed yet on this machine (PASSED_ALL, kept across the calls of one warm
        # machine): a first call runs what matters most by its REGEX, a second everything else (session 49 built
        # that regex by hand in the call's command).
        if [[ "$regex" == @unpassed ]]; then
          (cd build-gpu && ctest -N) | sed -n 's/^ *Test *#[0-9]*: //p' | sort > /tmp/tests_all.txt
          regex=$(comm -23 /tmp/tests_all.txt <(sort -u "$PASSED_ALL" 2> /dev/null) | sed 's/[.+]/\\&/g' | paste -sd'|')
          [ -n "$regex" ] || { echo "device.sh tests @unpassed: every entry has passed on this machine"; shift; continue; }
          regex="^($regex)\$"
        elif [[ "$regex" == @* ]]; then
          [ -s "${regex#@}" ] || { echo "device.sh tests: ${regex#@}: no such file, or empty (copy the first call's tests_rest.txt there)" >&2; exit 2; }
          regex=$(cat "${regex#@}")
        fi
        [ -n "$regex" ] || { echo "device.sh tests: the REGEX given is empty (a missing tests_rest.txt?); run nothing" >&2; exit 2; }
      fi
      # -j 6: the tests are small; several share the GPU (and its 16 host cores) and none is timed.
      # GPU_TESTS_EXCLUDE: a CTest -E regex; GPU_TESTS_SECONDS: stop every test that long from now (CTest's
      # --stop-time), so that a call's time limit ends the suite with its summary written, not mid-log.
      # The CPU suite's test times (pack.sh), unless this machine has timed its own: longest first.
      [ -f build-gpu/Testing/Temporary/CTestCostData.txt ] || { [ -f "$C/CTestCostData.txt" ] && \
        mkdir -p build-gpu/Testing/Temporary && cp "$C/CTestCostData.txt" build-gpu/Testing/Temporary/; }
      stop=(); [ -n "${GPU_TESTS_SECONDS:-}" ] && stop=(--stop-time "$(date -d "+${GPU_TESTS_SECONDS} seconds" +%H:%M:%S)")
      # The GPU in GPU_TESTS_GPU_SLOTS slots (default 1: tests/CMakeLists.txt says why the engine's tests take it in
      # turn); the config checks and the rest of the -j slots run beside.
      spec=(); if ctest --help | grep -q resource-spec-file; then
        printf '{"version": {"major": 1, "minor": 0}, "local": [{"gpus": [{"id": "0", "slots": %d}]}]}\n' \
          "${GPU_TESTS_GPU_SLOTS:-1}" > /tmp/gpu_resources.json
        spec=(--resource-spec-file /tmp/gpu_resources.json)
      fi
      # Each gtest's cases with their times (GTEST_OUTPUT: one XML an executable): CTest's log gives an entry's total
      # only, and test_lab.cuda's doubled (91 s at 71e7563, 181 s at 9d55af7) could not be split by case (session 51).
      rm -rf "$OUT/gtest"; export GTEST_OUTPUT="xml:$OUT/gtest/"
      (cd build-gpu && ctest --output-on-failure -j "${GPU_TESTS_JOBS:-6}" --timeout 500 ${regex:+-R "$regex"} \
        ${GPU_TESTS_EXCLUDE:+-E "$GPU_TESTS_EXCLUDE"} "${stop[@]}" "${spec[@]}") > "$OUT/ctest.log" 2>&1 || status=1
      tail -n 25 "$OUT/ctest.log"
      unset GTEST_OUTPUT
      if ls "$OUT"/gtest/*.xml > /dev/null 2>&1; then
        echo "the slowest gtest cases (all in $OUT/gtest/cases.txt):"
        awk 'match($0, /<testcase name="[^"]*"/) { n = substr($0, RSTART + 16, RLENGTH - 17); t = ""; c = ""
               if (match($0, / time="[^"]*"/)) t = substr($0, RSTART + 7, RLENGTH - 8)
               if (match($0, /classname="[^"]*"/)) c = substr($0, RSTART + 11, RLENGTH - 12)
               print t " s", c "." n }' "$OUT"/gtest/*.xml | sort -rn > "$OUT/gtest/cases.txt"
        head -n 8 "$OUT/gtest/cases.txt"
      fi
      # The entries of this selection that did not pass (stopped by GPU_TESTS_SECONDS, not reached, or failed), as
      # a -R regex in $OUT/tests_rest.txt: on one GPU slot the whole suite is ~620 s of GPU time on an H200
      # (RESULTS_GPU.md, session 41), more than one call, so a second call runs `device.sh tests @.gpucarry/tests_rest.txt` after
      # `cp <the first call's files>/tests_rest.txt .gpucarry/`.
      (cd build-gpu && ctest -N ${regex:+-R "$regex"} ${GPU_TESTS_EXCLUDE:+-E "$GPU_TESTS_EXCLUDE"}) \
        | sed -n 's/^ *Test *#[0-9]*: //p' | sort > /tmp/tests_selected.txt
      sed -n -E 's/^ *[0-9]+\/[0-9]+ Test +#[0-9]+: ([^ ]+) .* Passed .*/\1/p' "$OUT/ctest.log" | sort > /tmp/tests_passed.txt
      sort -u /tmp/tests_passed.txt "$PASSED_ALL" -o "$PASSED_ALL" 2> /dev/null || cp /tmp/tests_passed.txt "$PASSED_ALL"
      rest=$(comm -23 /tmp/tests_selected.txt /tmp/tests_passed.txt | sed 's/[.+]/\\&/g' | paste -sd'|')
      if [ -n "$rest" ]; then
        echo "^($rest)\$" > "$OUT/tests_rest.txt"
        echo "not passed: $(comm -23 /tmp/tests_selected.txt /tmp/tests_passed.txt | wc -l) entries; the rest's -R regex is in tests_rest.txt"
      else echo "every selected entry passed"; fi ;;
    bench)
      reps=3; if [[ "${2:-}" =~ ^[0-9]+$ ]]; then reps=$2; shift; fi
      # Sizes: the race scene tiled K^3 (32k x K^3): 32k, 256k, 2.05M, 11.0M. Rolling on and off, double
      # precision, the race's 200 warm-up + 2 000 timed steps, the engine's default lists.
      build-gpu/perf/race_bench --generate 2000 --copy 1 --warmup 0 --steps 1 | tee "$OUT/bench.txt"
      for tile in 1 2 4 7; do
        for rolling in 1 0; do
          build-gpu/perf/race_bench --scene "$S/scene_32k.txt" --box "$S/scene_32k_box.txt" --tile $tile \
            --rolling $rolling --reps "$reps" | sed "s/^/tile=$tile /" | tee -a "$OUT/bench.txt" || status=1
        done
      done
      # The Verlet list itself (--inner 0), the list the CPU race's headline row streams, at 32k and 2M.
      for tile in 1 4; do
        build-gpu/perf/race_bench --scene "$S/scene_32k.txt" --box "$S/scene_32k_box.txt" --tile $tile \
          --rolling 1 --inner 0 --reps "$reps" | sed "s/^/tile=$tile /" | tee -a "$OUT/bench.txt" || status=1
      done ;;
    base)  # base [TILES]: the race bench of an older build (pack.sh with BASE_BUILD) on this same GPU, rolling on
      tiles="1 4"; if [[ "${2:-}" =~ ^[0-9\ ]+$ ]]; then tiles=$2; shift; fi
      [ -f "$C/race_bench_base.xz" ] || { echo "device.sh: no base binary: pack with BASE_BUILD=<older build-gpu>" >&2; exit 1; }
      xz -dc "$C/race_bench_base.xz" > /tmp/race_bench_base && chmod +x /tmp/race_bench_base
      sed "s/^/base binary built at commit /" "$C/base_commit.txt" | tee "$OUT/bench_base.txt"
      for tile in $tiles; do
        /tmp/race_bench_base --scene "$S/scene_32k.txt" --box "$S/scene_32k_box.txt" --tile "$tile" \
          --rolling 1 --reps 3 | sed "s/^/tile=$tile /" | tee -a "$OUT/bench_base.txt" || status=1
      done ;;
    ur1)
      secs=540; if [[ "${2:-}" =~ ^[0-9]+$ ]]; then secs=$2; shift; fi
      rm -rf /tmp/ur1
      start=$(date +%s.%N)
      timeout --signal=INT "$secs" build-gpu/grainlab run configs/paper/UR1.yaml --out /tmp/ur1 > "$OUT/ur1.log" 2>&1
      rc=$?
      end=$(date +%s.%N)
      echo "ur1 rc=$rc wall_s=$(echo "$end - $start" | bc -l 2>/dev/null || python3 -c "print($end-$start)")" | tee -a "$OUT/ur1.log"
      cp /tmp/ur1/series.csv "$OUT/ur1_series.csv" 2>/dev/null
      # The small files that say what happened (the checkpoints and snapshots, ~170 MB, stay there).
      for f in blowup.txt run.h5; do cp "/tmp/ur1/$f" "$OUT/ur1_$f" 2>/dev/null; done
      ls -la /tmp/ur1 >> "$OUT/ur1.log"
      tail -n 15 "$OUT/ur1.log" ;;
    profile)
      tile=1; if [[ "${2:-}" =~ ^[0-9]+$ ]]; then tile=$2; shift; fi
      args=(--scene "$S/scene_32k.txt" --box "$S/scene_32k_box.txt" --tile "$tile" --rolling 1)
      # The wall time per step without the profiler, then the kernels' own times (ncu serialises the
      # launches, so only its per-kernel durations are used, never its wall time). --clock-control none
      # leaves the GPU's clocks as they are (the device tool's METHOD.md).
      # With a base binary carried (pack.sh BASE_BUILD=...), it is profiled the same way after the current one
      # (files *_base_t*): a step time that changed between the two is then read kernel by kernel.
      bins=("build-gpu/perf/race_bench:"); if [ -f "$C/race_bench_base.xz" ]; then
        xz -dc "$C/race_bench_base.xz" > /tmp/race_bench_base && chmod +x /tmp/race_bench_base
        bins+=("/tmp/race_bench_base:_base"); fi
      ncu=$(command -v ncu || ls /opt/nvidia/nsight-compute/*/ncu 2>/dev/null | head -n 1)
      for b in "${bins[@]}"; do
        bin=${b%%:*} tag=${b#*:}
        if [ -n "$tag" ]; then sed "s/^/base binary built at commit /" "$C/base_commit.txt"; fi > "$OUT/profile${tag}_t$tile.txt"
        "$bin" "${args[@]}" --reps 3 | tee -a "$OUT/profile${tag}_t$tile.txt" || status=1
        "${ncu:-ncu}" --clock-control none --metrics gpu__time_duration.sum --csv --print-units base \
          "$bin" "${args[@]}" --warmup 10 --steps 20 > "$OUT/ncu${tag}_t$tile.csv" 2> "$OUT/ncu${tag}_t$tile.err" || status=1
        python3 perf/gpu/kernels.py "$OUT/ncu${tag}_t$tile.csv" 30 | tee -a "$OUT/profile${tag}_t$tile.txt"
      done ;;
    memory)  # memory [COUNTS]: the device memory a lab run holds, per sphere (the memory check's 1.5 kB, measured)
      counts="250000 1000000 4000000"; if [[ "${2:-}" =~ ^[0-9\ ]+$ ]]; then counts=$2; shift; fi
      # configs/quick.yaml at COUNT spheres, generated, listed and stepped 300 times (--stop-after-steps): the
      # peak of nvidia-smi's memory.used, sampled every 20 ms, above the idle GPU's. The slope between counts is
      # the per-sphere figure (the CUDA context and Kokkos's own buffers are the intercept).
      idle=$(nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits | head -n 1)
      echo "idle_MiB=$idle" | tee "$OUT/memory.txt"
      for count in $counts; do
        sed -e "s/count: 3000/count: $count/" configs/quick.yaml > /tmp/mem_$count.yaml
        rm -rf /tmp/mem_out
        nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -lms 20 > /tmp/mem_$count.txt &
        smi=$!
        start=$(date +%s.%N)
        build-gpu/grainlab run /tmp/mem_$count.yaml --out /tmp/mem_out --stop-after-steps 300 --quiet > /tmp/mem_run.log 2>&1
        rc=$?
        end=$(date +%s.%N)
        kill $smi; wait $smi 2>/dev/null
        peak=$(sort -n /tmp/mem_$count.txt | tail -n 1)
        echo "count=$count rc=$rc peak_MiB=$peak above_idle_MiB=$((peak - idle)) wall_s=$(python3 -c "print(round($end - $start, 1))")" | tee -a "$OUT/memory.txt"
        [ $rc -eq 0 ] || [ $rc -eq 130 ] || { tail -n 5 /tmp/mem_run.log; status=1; }
      done
      # The densest state a run meets: the race scene (5.4 contacts a sphere) tiled to 2.05M and 11.0M spheres, 400 steps.
      for tile in 4 7; do
        nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -lms 20 > /tmp/mem_t$tile.txt &
        smi=$!
        build-gpu/perf/race_bench --scene "$S/scene_32k.txt" --box "$S/scene_32k_box.txt" --tile $tile --rolling 1 \
          --reps 1 --warmup 200 --steps 200 > /tmp/mem_race.txt 2>&1 || { tail -n 3 /tmp/mem_race.txt; status=1; }
        kill $smi; wait $smi 2>/dev/null
        peak=$(sort -n /tmp/mem_t$tile.txt | tail -n 1)
        n=$(sed -n 's/.* particles=\([0-9]*\) .*/\1/p' /tmp/mem_race.txt | head -n 1)
        echo "race count=${n:-0} peak_MiB=$peak above_idle_MiB=$((peak - idle))" | tee -a "$OUT/memory.txt"
      done
      python3 - "$OUT/memory.txt" <<'PY' | tee -a "$OUT/memory.txt"
import re, sys
text = open(sys.argv[1]).read()
for what, pattern in (("lab run, loose", r"^count=(\d+) rc=\d+ peak_MiB=\d+ above_idle_MiB=(-?\d+)"),
                      ("race scene, dense", r"^race count=(\d+) peak_MiB=\d+ above_idle_MiB=(-?\d+)")):
    rows = [(int(a), int(b)) for a, b in re.findall(pattern, text, re.M)]
    if len(rows) >= 2 and rows[-1][0] != rows[0][0]:
        (n0, m0), (n1, m1) = rows[0], rows[-1]
        print(f"{what}: device_bytes_per_sphere={(m1 - m0) * 2**20 / (n1 - n0):.0f} (slope {n0}..{n1}) "
              f"intercept_MiB={m0 - (m1 - m0) * n0 / (n1 - n0):.0f}")
PY
      ;;
    *) echo "device.sh: unknown verb '$1' (allowed: tests, bench [REPS], base [TILES], ur1 [SECONDS], profile [TILE], memory [COUNTS])" >&2; exit 2 ;;
  esac
  shift
done
exit $status
