#!/usr/bin/env bash
# `grainlab validate RUN/config.yaml` of a run started from a sample file that has since gone (its preparation run
# cleaned up or moved): one error line that says the file is missing and that the run itself resumes without it (its
# checkpoints record the sample: Lab.AResumeDoesNotNeedItsSampleFile), where it said "no such file" alone. A config
# outside a run directory keeps the plain message.
set -u
bin=$1; sample=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "validate_gone_sample: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
cp "$sample" gone.h5 || fail "no sample to copy: $sample"
printf 'sample: {file: gone.h5}\nstages:\n  - {name: shear, type: triaxial, axial_strain_rate: 1.0, max_axial_strain: 0.0005}\noutput: {every: 100}\n' > c.yaml
out=$("$bin" run c.yaml --out run --threads 1 2>&1) || fail "the run failed: $out"
rm gone.h5
"$here"/expect_error.sh "^grainlab: error: run/config.yaml: .*/gone.h5: no such file; the run in run recorded that sample in its checkpoints, so \`grainlab run run/config.yaml --resume\` goes on without it \(a fresh run needs the file\)$" \
  "$bin" validate run/config.yaml || exit 1
"$here"/expect_error.sh "^grainlab: error: c.yaml: .*/gone.h5: no such file$" "$bin" validate c.yaml || exit 1
"$bin" run run/config.yaml --resume --threads 1 > resume.txt 2>&1 || fail "the resume failed: $(cat resume.txt)"
echo "validate_gone_sample: ok"
