# Sourced by the study_*.sh tests (after `bin=$1; src=$2; work=$3`): `study_setup NAME STUDY BASE` makes a fresh $work
# holding tests/data's STUDY and BASE, goes there, and validates STUDY into $plan; `fail MESSAGE` ends the test,
# prefixed by NAME.
fail() { echo "$test_name: $*"; exit 1; }
study_setup() {
  test_name=$1
  rm -rf "$work" && mkdir -p "$work" || exit 1
  cp "$src/$2" "$src/$3" "$work"/ || exit 1
  cd "$work" || exit 1
  plan=$("$bin" validate "$2" 2>&1) || fail "validate failed: $plan"
}
