# Checks of the perf scripts' environment settings, sourced by race.sh, scaling_peers.sh and results.sh: a bad
# value stops the script at once with one line naming the variable and what is allowed, instead of a run of
# many minutes that fails (or measures the wrong thing) at the end.
# env_check_peers SCRIPT: every word of $PEERS is a known peer ("" = none).
env_check_peers() {
  local p
  for p in $PEERS; do
    case $p in liggghts|lammps|lammpsclassic|yade) ;;
      *) echo "$1: PEERS='$PEERS': unknown peer '$p' (allowed: liggghts lammps lammpsclassic yade, or \"\" for none)"
         return 1 ;;
    esac
  done
}
# env_check_whole SCRIPT VAR...: each named variable holds a whole number >= 1.
env_check_whole() {
  local script=$1 v; shift
  for v in "$@"; do
    case ${!v} in
      ''|*[!0-9]*|0|0*) echo "$script: $v='${!v}' must be a whole number >= 1, without leading zeros"; return 1 ;;
    esac
  done
}
