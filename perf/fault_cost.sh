#!/usr/bin/env bash
# What a page fault costs on this machine: a C program maps 1 GiB of fresh anonymous memory and writes one byte a
# 4 KiB page (each write a minor fault), timed; prints microseconds a fault, median of ROUNDS (default 5). A forked
# figure writer faults its memory in (scripts/grainlab_plot.py, FIGURE_JOBS; perf/NOTES.md session 69), so this price
# decides whether GRAINLAB_FIGURE_JOBS > 1 pays.
#   perf/fault_cost.sh
set -eu
rounds=${ROUNDS:-5}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/f.c" <<'C'
#include <stdio.h>
#include <sys/mman.h>
#include <time.h>
int main(void) {
  const size_t n = (size_t)1 << 30, page = 4096;
  struct timespec a, b;
  clock_gettime(CLOCK_MONOTONIC, &a);
  volatile char* p = mmap(0, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return 1;
  for (size_t i = 0; i < n; i += page) p[i] = 1;
  clock_gettime(CLOCK_MONOTONIC, &b);
  printf("%.3f\n", ((b.tv_sec - a.tv_sec) + (b.tv_nsec - a.tv_nsec) * 1e-9) * 1e6 / (double)(n / page));
  return 0;
}
C
cc -O2 -o "$tmp/f" "$tmp/f.c"
for _ in $(seq 1 "$rounds"); do "$tmp/f"; done | sort -g |
  awk -v r="$rounds" -v c="$(nproc)" '{ v[NR] = $1 }
    END { m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    printf "page fault: %.2f us (median of %d, %d cores; fresh anonymous memory, 4 KiB pages)\n", m, r, c }'
