#!/usr/bin/env bash
# How long a study's report takes to make (scripts/grainlab_plot.py study DIR: report.md and every figure), at this
# checkout and at an earlier commit, in alternating rounds on the same study directory; prints each one's median of
# ROUNDS (default 5) in seconds and whether both wrote the same report.md. The study directory is any finished study
# (e.g. build/tests/study, which `make test` leaves: configs/quick-study.yaml's 12 jobs). Its report.md and figures are
# rewritten by each round, as `grainlab study` rewrites them.
#   perf/report_time.sh STUDY_DIR [BASE_COMMIT]        (BASE_COMMIT default HEAD~1)
#   perf/report_time.sh STUDY_DIR formats              (this checkout's report with GRAINLAB_FIGURE_FORMATS png,pdf (the
#                                                       default), png, pdf and svg, in alternating rounds)
set -eu
study=$1; base=${2:-HEAD~1}; rounds=${ROUNDS:-5}
here=$(cd "$(dirname "$0")/.." && pwd)
[ -f "$study/study.json" ] || { echo "perf/report_time.sh: $study: not a study directory (no study.json)"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
py=/usr/bin/python3
median() {
  sort -g "$1" | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
if [ "$base" = formats ]; then
  cp -r "$study" "$tmp/study"  # a copy: the study's own figures/ keeps its formats (no SVG left in it)
  for _ in $(seq 1 "$rounds"); do
    for f in png,pdf png pdf svg; do
      t0=$(date +%s.%N)
      GRAINLAB_FIGURE_FORMATS=$f "$py" "$here/scripts/grainlab_plot.py" study "$tmp/study" > /dev/null
      echo "$(date +%s.%N) - $t0" | bc >> "$tmp/$f.t"
    done
  done
  for f in png,pdf png pdf svg; do
    echo "report of $study, $rounds rounds, $(nproc) cores, figures as $f: $(median "$tmp/$f.t") s (median)"
  done
  exit 0
fi
mkdir "$tmp/base"
git -C "$here" archive "$base" scripts | tar -x -C "$tmp/base"
run() {  # $1: scripts directory; prints the seconds the report took
  local t0 t1
  t0=$(date +%s.%N); "$py" "$1/grainlab_plot.py" study "$study" > /dev/null; t1=$(date +%s.%N)
  echo "$t1 - $t0" | bc
}
: > "$tmp/now.t"; : > "$tmp/base.t"
for _ in $(seq 1 "$rounds"); do
  run "$tmp/base/scripts" >> "$tmp/base.t"; cp "$study/report.md" "$tmp/base.md"
  run "$here/scripts" >> "$tmp/now.t"; cp "$study/report.md" "$tmp/now.md"
done
same=$(cmp -s "$tmp/base.md" "$tmp/now.md" && echo yes || echo no)
echo "report of $study, $rounds rounds, $(nproc) cores: $base $(median "$tmp/base.t") s, this checkout" \
     "$(median "$tmp/now.t") s (median); the same report.md: $same"
