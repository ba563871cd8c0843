# shellcheck shell=bash
# Sourced by perf/race.sh and perf/scaling_peers.sh: the peers named in $PEERS installed from Debian when
# missing (apt-get, as root or through sudo), unless SKIP_INSTALL=1. $1: the calling script's name for
# messages, $2: the folder for apt's log. Returns non-zero (after saying why) when a peer cannot be had.
install_peers() {
  local who=$1 logdir=$2 need="" p SUDO=""
  for p in $PEERS; do
    case $p in
      liggghts) command -v liggghts >/dev/null || need="$need liggghts openmpi-bin" ;;
      lammps|lammpsclassic) command -v lmp >/dev/null || need="$need lammps openmpi-bin" ;;
      yade) command -v yade >/dev/null || need="$need yade" ;;
      *) echo "$who: unknown peer '$p' (liggghts lammps lammpsclassic yade)"; return 1 ;;
    esac
  done
  [ -n "$need" ] || return 0
  [ "${SKIP_INSTALL:-0}" = 1 ] && { echo "$who: missing peers ($need) and SKIP_INSTALL=1"; return 1; }
  echo ">>> installing from Debian:$need"
  [ "$(id -u)" = 0 ] || SUDO=sudo
  # apt's chatter (it names the archive hosts) goes to the log only; $need is a list of packages
  # shellcheck disable=SC2086
  { $SUDO apt-get update && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y $need python3-numpy; } \
    > "$logdir/apt.log" 2>&1 || { echo "$who: apt-get failed, see $logdir/apt.log"; return 1; }
}
