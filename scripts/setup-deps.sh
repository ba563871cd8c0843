#!/usr/bin/env bash
# Installs what grainlab needs on Debian 12 and bootstraps Kokkos with OpenMP when none is found.
# Idempotent: a second run only checks and returns in about a second.
#
#   scripts/setup-deps.sh            # apt packages + Kokkos (OpenMP+Serial) into $GRAINLAB_DEPS
#   KOKKOS_ROOT=/path scripts/...    # use your own Kokkos (>= 3.4, 4.x fine); nothing is built
#
# Facts behind the recipe: ../shared/DEPENDENCIES.md (Debian's libtrilinos-kokkos-dev is Serial-only,
# so Kokkos 3.4.01 is taken from Debian's trilinos *source* package and built with OpenMP).
set -euo pipefail

DEPS_DIR="${GRAINLAB_DEPS:-${XDG_CACHE_HOME:-$HOME/.cache}/grainlab}"
KOKKOS_VARIANT="${KOKKOS_VARIANT:-openmp}"          # openmp | cuda (make gpu)
KOKKOS_PREFIX="$DEPS_DIR/kokkos-3.4.01-$KOKKOS_VARIANT"
say() { printf '[setup] %s\n' "$*" >&2; }

# ---- 1. Debian packages ----------------------------------------------------------------------
PKGS=(cmake g++ make patch libeigen3-dev libhdf5-dev hdf5-tools libyaml-cpp-dev libgtest-dev libbenchmark-dev
      dpkg-dev xz-utils python3 python3-numpy python3-matplotlib python3-h5py python3-scipy python3-yaml)
missing=()
if command -v dpkg-query >/dev/null && command -v apt-get >/dev/null; then
  for p in "${PKGS[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
else
  # Not Debian: nothing is installed here; CMake then names what it cannot find.
  debian=no
  say "no dpkg/apt here: not installing packages. grainlab needs the equivalents of: ${PKGS[*]}"
fi
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  say "installing Debian packages: ${missing[*]}"
  # Two setups at once (make test in two clones) used to fail on dpkg's lock ("Could not get lock"): grainlab's
  # own setups queue on a lock file, and apt waits up to 10 minutes for any other holder of dpkg's.
  mkdir -p "$DEPS_DIR"
  exec 8>"$DEPS_DIR/.apt-lock"; flock 8
  APTWAIT=(-o DPkg::Lock::Timeout=600)
  $SUDO apt-get "${APTWAIT[@]}" update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get "${APTWAIT[@]}" install -y -qq --no-install-recommends "${missing[@]}" >&2
  exec 8>&-
fi

# ---- 2. Kokkos -------------------------------------------------------------------------------
# A user-supplied Kokkos wins (KOKKOS_ROOT or Kokkos_ROOT); CMake's find_package checks it.
if [ -n "${KOKKOS_ROOT:-${Kokkos_ROOT:-}}" ]; then
  echo "${KOKKOS_ROOT:-${Kokkos_ROOT:-}}"; exit 0
fi
if [ -f "$KOKKOS_PREFIX/.complete" ]; then
  echo "$KOKKOS_PREFIX"; exit 0
fi

if [ "${debian:-yes}" = no ]; then
  say "error: bootstrapping Kokkos needs Debian's trilinos source package; with a Kokkos >= 3.4 (OpenMP) of"
  say "your own: KOKKOS_ROOT=/path/to/kokkos make test"
  exit 1
fi
mkdir -p "$DEPS_DIR"
# Serialise concurrent bootstraps (two make invocations at once must not build twice).
exec 9>"$DEPS_DIR/.lock"; flock 9
if [ -f "$KOKKOS_PREFIX/.complete" ]; then echo "$KOKKOS_PREFIX"; exit 0; fi

SRC_DIR="$DEPS_DIR/src"
KOKKOS_SRC="$SRC_DIR/kokkos-3.4.01"
if [ ! -f "$KOKKOS_SRC/CMakeLists.txt" ]; then
  APTDIR="$DEPS_DIR/apt-src"
  mkdir -p "$APTDIR/lists/partial" "$APTDIR/cache/archives/partial" "$SRC_DIR"
  # The system's own sources, re-typed as deb-src, in a private directory: no system file is edited
  # and no archive host is written into this repository.
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    sed 's/^Types:.*/Types: deb-src/' /etc/apt/sources.list.d/debian.sources > "$APTDIR/debian.sources"
  elif [ -f /etc/apt/sources.list ]; then
    sed -n 's/^deb /deb-src /p' /etc/apt/sources.list > "$APTDIR/debian.list"
  else
    say "error: no apt sources found to derive a deb-src entry from"; exit 1
  fi
  APTOPT=(-o Dir::Etc::SourceList=/dev/null -o Dir::Etc::SourceParts="$APTDIR"
          -o Dir::State::Lists="$APTDIR/lists" -o Dir::Cache="$APTDIR/cache")
  say "fetching Debian's trilinos source package (~166 MB, once)"
  APTOPT+=(-o APT::Sandbox::User=root)  # the private lists directory is root's
  apt-get "${APTOPT[@]}" update -qq
  ( cd "$SRC_DIR" && apt-get "${APTOPT[@]}" source --download-only -qq trilinos >&2 )
  tarball=$(ls "$SRC_DIR"/trilinos_*.orig.tar.* | head -n1)
  say "extracting packages/kokkos from $(basename "$tarball")"
  rm -rf "$SRC_DIR/extract"; mkdir -p "$SRC_DIR/extract"
  tar -xf "$tarball" -C "$SRC_DIR/extract" --wildcards '*/packages/kokkos/*'
  rm -rf "$KOKKOS_SRC"
  mv "$SRC_DIR"/extract/*/packages/kokkos "$KOKKOS_SRC"
  rm -rf "$SRC_DIR/extract"
fi

EXTRA=()
SRC_USE="$KOKKOS_SRC"
case "$KOKKOS_VARIANT" in
  openmp) EXTRA=(-DKokkos_ENABLE_OPENMP=ON) ;;
  cuda)
    # CUDA 13 + Kokkos 3.4.01 on Ampere/Hopper needs four small source fixes (../shared/DEPENDENCIES.md),
    # kept as patches in patches/kokkos-3.4.01-cuda13/ and applied to a private copy of the source.
    command -v nvcc >/dev/null || { say "error: nvcc not found (the CUDA build needs the CUDA toolkit)"; exit 1; }
    SRC_USE="$SRC_DIR/kokkos-3.4.01-cuda13"
    rm -rf "$SRC_USE"; cp -r "$KOKKOS_SRC" "$SRC_USE"
    for p in "$(cd "$(dirname "$0")/.." && pwd)"/patches/kokkos-3.4.01-cuda13/*.patch; do
      patch -s -p1 -d "$SRC_USE" < "$p" || { say "error: patch $p does not apply"; exit 1; }
    done
    EXTRA=(-DKokkos_ENABLE_CUDA=ON -DKokkos_ENABLE_CUDA_LAMBDA=ON -DKokkos_ARCH_AMPERE80=ON
           -DCMAKE_CXX_COMPILER="$SRC_USE/bin/nvcc_wrapper" -DCMAKE_POLICY_VERSION_MINIMUM=3.5) ;;
  *) say "error: KOKKOS_VARIANT=$KOKKOS_VARIANT is not supported (allowed: openmp, cuda)"; exit 1 ;;
esac
BUILD="$DEPS_DIR/build-kokkos-$KOKKOS_VARIANT"
rm -rf "$BUILD" "$KOKKOS_PREFIX"
say "building Kokkos 3.4.01 ($KOKKOS_VARIANT + Serial) into $KOKKOS_PREFIX"
cmake -S "$SRC_USE" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$KOKKOS_PREFIX" \
  -DCMAKE_CXX_STANDARD=17 -DKokkos_CXX_STANDARD=17 -DKokkos_ENABLE_SERIAL=ON "${EXTRA[@]}" \
  -DKokkos_ENABLE_TESTS=OFF -DBUILD_SHARED_LIBS=OFF -DCMAKE_POSITION_INDEPENDENT_CODE=ON >/dev/null
cmake --build "$BUILD" -j "$(nproc)" >/dev/null
cmake --install "$BUILD" >/dev/null
rm -rf "$BUILD"
touch "$KOKKOS_PREFIX/.complete"
say "Kokkos ready"
echo "$KOKKOS_PREFIX"
