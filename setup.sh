#!/usr/bin/env bash
# cw4d setup: installs the Debian packages the build needs, builds Release into build/, then
#   ./setup.sh        runs the main job (a tesseract section written to out/section.obj)
#   ./setup.sh test   runs the test suite (ctest) and exits with its status
# Safe to run again: only missing packages are installed and the build is incremental.
# Environment: CW4D_JOBS (parallel build/test jobs, default 2), CW4D_BUILD_DIR (default build).
set -euo pipefail

# Debian packages needed to build, test and benchmark cw4d. Add new dependencies here only.
PACKAGES=(
  g++
  cmake
  ninja-build
  ccache
  pkg-config
  libeigen3-dev
  libcli11-dev
  nlohmann-json3-dev
  catch2
  libbenchmark-dev
  libcgal-dev
  libgmp-dev
  libmpfr-dev
  libopenmesh-dev
  libtinygltf-dev
  libstb-dev
  libglm-dev
  libtet1.5-dev
  libtbb-dev
  assimp-utils
  python3-vtk9
  nodejs
  clang
  libclang-rt-14-dev
  libosmesa6-dev
)

log() { printf 'cw4d: %s\n' "$*" >&2; }
die() { printf 'cw4d: error: %s\n' "$*" >&2; exit 1; }

usage() {
  cat >&2 <<'EOF'
usage: ./setup.sh [test]
  (no argument)  install missing packages, build, and write out/section.obj
  test           install missing packages, build, and run the test suite
EOF
}

MODE="run"
case "$#" in
  0) ;;
  1)
    case "$1" in
      test) MODE="test" ;;
      -h|--help) usage; exit 0 ;;
      *) log "unknown argument: $1"; usage; exit 1 ;;
    esac
    ;;
  *) usage; exit 1 ;;
esac

cd "$(dirname "${BASH_SOURCE[0]}")"
JOBS="${CW4D_JOBS:-2}"
BUILD_DIR="${CW4D_BUILD_DIR:-build}"
[[ "$JOBS" =~ ^[1-9][0-9]*$ ]] || die "CW4D_JOBS must be a positive integer, got '$JOBS'"

# --- (a) packages -------------------------------------------------------------------------------
install_missing_packages() {
  local missing=() pkg status
  for pkg in "${PACKAGES[@]}"; do
    status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
    [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
  done
  if ((${#missing[@]} == 0)); then
    return 0
  fi
  log "installing ${missing[*]}"
  local -a as_root=()
  if [[ "$(id -u)" -ne 0 ]]; then
    command -v sudo >/dev/null 2>&1 ||
      die "not root and sudo is missing: install ${missing[*]} by hand"
    as_root=(sudo)
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q >&2
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
}

# --- (b) configure and build --------------------------------------------------------------------
configure_and_build() {
  local cache="$BUILD_DIR/CMakeCache.txt"
  if [[ -f "$cache" ]]; then
    # A build dir made by another generator or for another source tree (e.g. a copied
    # checkout) cannot be reconfigured in place: drop its cache, keep nothing stale.
    local gen home
    gen="$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$cache")"
    home="$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cache")"
    if [[ "$gen" != "Ninja" || "$home" != "$PWD" ]]; then
      log "discarding stale CMake cache in $BUILD_DIR/ (generator '$gen', source '$home')"
      rm -rf "$cache" "$BUILD_DIR/CMakeFiles"
    fi
  fi
  log "configuring Release in $BUILD_DIR/"
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
  log "building with $JOBS jobs"
  cmake --build "$BUILD_DIR" -j "$JOBS" >&2
}

# --- (b') test mode only: readers the tests open exported files with ----------------------------
# The Khronos glTF-Validator from the npm registry, pinned by tests/tools/package-lock.json and
# installed into tests/tools/node_modules/ (ignored by git), shared by every build directory.
install_test_tools() {
  if [[ -f tests/tools/node_modules/gltf-validator/package.json ]] &&
     cmp -s tests/tools/package-lock.json tests/tools/node_modules/.package-lock.json.cw4d; then
    return 0
  fi
  command -v npm >/dev/null 2>&1 || die "npm is missing (Debian package nodejs)"
  log "installing the glTF-Validator (npm ci in tests/tools/)"
  (cd tests/tools && npm ci --no-audit --no-fund --loglevel=error >&2)
  cp tests/tools/package-lock.json tests/tools/node_modules/.package-lock.json.cw4d
}

install_missing_packages
configure_and_build

# --- the job ------------------------------------------------------------------------------------
if [[ "$MODE" == test ]]; then
  install_test_tools
  log "testing"
  status=0
  ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" || status=$?
  if ((status == 0)); then log "tests passed"; else log "tests FAILED (ctest exit $status)"; fi
  exit "$status"
fi

log "slicing the rotated tesseract into out/section.obj"
"$BUILD_DIR/apps/cw4d" slice tesseract --rotate xw:30 --rotate yw:25 --rotate zw:20 \
  --normal 0,0,0,1 --offset 0.25 -o out/section.obj
[[ -s out/section.obj ]] || die "cw4d slice did not write out/section.obj"
