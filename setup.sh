#!/usr/bin/env bash
# cw4d setup: installs the Debian packages the mode needs, builds Release into build/, then
#   ./setup.sh        runs the main job (a tesseract section written to out/section.obj); installs
#                     only RUN_PACKAGES and builds only the cw4d CLI (and the Python module when
#                     the build directory has it)
#   ./setup.sh test   adds TEST_PACKAGES (the test tooling), reconfigures the same build directory
#                     with the tests, benchmarks and Python module on, and runs the test suite
#                     (ctest), the Python module's tests (pytest), the C++ suite again under
#                     ASan+UBSan in build-asan/, the browser test of the web viewer, then each
#                     libFuzzer target for 30 s (built in build-asan/ too); every stage runs, a
#                     verdict per stage is printed, and the exit status is the first failure's
# Both also build the web viewer (WebAssembly, emscripten) into build-web/ when emscripten is
# installed (CW4D_WEB=0 skips it); `./setup.sh test` installs emscripten, the plain run does only
# with CW4D_WEB=1 (`CW4D_WEB=1 ./setup.sh`: 33 more packages, 185 MB to fetch, 1.2 GB installed).
# Safe to run again, and the modes in either order: only missing packages are installed and the
# build is incremental.
# Environment: CW4D_JOBS (parallel build/test jobs, default 2), CW4D_BUILD_DIR (default build),
# CW4D_WERROR (test mode: 1 = warnings in cw4d's own code are errors, the default; 0 = not).
set -euo pipefail

# Debian packages. Add new dependencies here only, to the list of the mode that needs them.
# RUN_PACKAGES: building the cw4d CLI and running the main job.
RUN_PACKAGES=(
  g++
  cmake
  ninja-build
  ccache
  pkg-config
  libeigen3-dev
  libcli11-dev
  nlohmann-json3-dev
  libcgal-dev
  libgmp-dev
  libmpfr-dev
  libopenmesh-dev
  libtinygltf-dev
  libstb-dev
  libglm-dev
  libwebp-dev
  libgif-dev
  libtet1.5-dev
)
# WEB_PACKAGES: the web viewer's compiler (it pulls in clang/LLVM 14, binaryen and nodejs).
# Always installed by `./setup.sh test`; by the plain run only with CW4D_WEB=1.
RUN_WITH_WEB=0
[[ "${CW4D_WEB:-}" == 1 ]] && RUN_WITH_WEB=1
WEB_PACKAGES=(
  emscripten
)
# TEST_PACKAGES: the test tooling `./setup.sh test` adds (Catch2, Google Benchmark, the
# sanitizer and fuzzing runtimes, the readers and checkers the tests use, the Python module's
# build and test dependencies, the browser of the browser test). npm is added when the `npm`
# command is missing (Debian's nodejs has none; NodeSource's bundles it and conflicts with npm).
TEST_PACKAGES=(
  catch2
  libbenchmark-dev
  libtbb-dev
  assimp-utils
  python3-vtk9
  nodejs
  clang
  lld
  clang-format
  libclang-rt-14-dev
  libosmesa6-dev
  python3-dev
  pybind11-dev
  python3-pybind11
  python3-numpy
  python3-pytest
  python3-meshio
  python3-jsonschema
  python3-scipy
  python3-matplotlib
  python3-mypy
  chromium
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
# ccache (when installed) keys objects by paths relative to the checkout, so a fresh clone in
# another folder reuses what an earlier build on this machine compiled.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
JOBS="${CW4D_JOBS:-2}"
BUILD_DIR="${CW4D_BUILD_DIR:-build}"
[[ "$JOBS" =~ ^[1-9][0-9]*$ ]] || die "CW4D_JOBS must be a positive integer, got '$JOBS'"

# --- (a) packages -------------------------------------------------------------------------------
PACKAGES=("${RUN_PACKAGES[@]}")
if [[ "$MODE" == test || "$RUN_WITH_WEB" == 1 ]]; then PACKAGES+=("${WEB_PACKAGES[@]}"); fi
if [[ "$MODE" == test ]]; then PACKAGES+=("${TEST_PACKAGES[@]}"); fi

missing_packages() {  # PACKAGE...: prints those not installed, one a line
  local pkg status
  for pkg in "$@"; do
    status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
    [[ "$status" == "install ok installed" ]] || printf '%s\n' "$pkg"
  done
}

install_missing_packages() {
  local missing=()
  mapfile -t missing < <(missing_packages "${PACKAGES[@]}")
  if [[ "$MODE" == test ]] && ! command -v npm >/dev/null 2>&1; then missing+=(npm); fi
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
  # Test mode (and so CI) turns the tests, benchmarks and Python module on and builds cw4d's own
  # code with -Werror (CW4D_WERROR=0 turns it off). The plain run keeps what the build directory
  # has (so switching back from test mode rebuilds nothing) and builds only the CLI (and the
  # Python module if it is on); without the test tooling it turns them off, since tests/ needs
  # Catch2, assimp and node and the module pybind11 (a new build directory starts so). The first
  # test run after a plain one recompiles the libraries once (-Werror, and -fPIC for the module).
  local opts=() targets=()
  if [[ "$MODE" == test ]]; then
    # (the tests' own files at -O1: a fifth less to compile, the suite's time is in the libraries)
    opts=(-DCW4D_BUILD_TESTS=ON -DCW4D_BUILD_BENCH=ON -DCW4D_BUILD_PYTHON=ON
      -DCW4D_TEST_COMPILE_OPTIONS=-O1)
    if [[ "${CW4D_WERROR:-1}" != 0 ]]; then opts+=(-DCW4D_WERROR=ON); else opts+=(-DCW4D_WERROR=OFF); fi
  elif [[ -n "$(missing_packages "${TEST_PACKAGES[@]}")" ]]; then
    opts=(-DCW4D_BUILD_TESTS=OFF -DCW4D_BUILD_BENCH=OFF -DCW4D_BUILD_PYTHON=OFF)
  fi
  mapfile -t -O "${#opts[@]}" opts < <(web_options)
  log "configuring Release in $BUILD_DIR/"
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "${opts[@]}" >&2
  if [[ "$MODE" != test ]]; then
    targets=(--target cw4d)
    if [[ "$(sed -n 's/^CW4D_BUILD_PYTHON:BOOL=//p' "$BUILD_DIR/CMakeCache.txt")" == ON ]]; then
      targets+=(cw4d_python)
    fi
  fi
  log "building ${targets[*]:+${targets[*]:1} }with $JOBS jobs"
  cmake --build "$BUILD_DIR" -j "$JOBS" "${targets[@]}" >&2
}

# --- (c) test mode only: the suite under ASan+UBSan, and short libFuzzer runs ---------------------
# One instrumented clang build in build-asan/ (CW4D_ASAN_DIR) serves both: the test suite and the
# libFuzzer targets of fuzz/ (-DCW4D_BUILD_FUZZ=ON: every library also carries libFuzzer's 8-bit
# edge counters), so the libraries are compiled once, not twice. Linked by lld.
# CW4D_SANITIZE=0 skips the sanitizer suite, CW4D_FUZZ_SECONDS=0 the fuzz runs (default 30 s per
# target, nine targets, CW4D_JOBS of them at a time).
# UBSan without the checks ASan already makes or that cost compile time for little here (null,
# object-size, pointer-overflow: ASan reports the bad access; alignment: x86 loads misaligned
# data, and the binary readers copy bytes with memcpy; vptr, function, nonnull-attribute,
# returns-nonnull-attribute: casts and calls between polymorphic or C types, which cw4d hardly
# has). With them the library files took 1.3-1.7x as long to compile as with the rest of UBSan,
# which keeps signed overflow, shifts, division by zero, float-to-integer overflow, array bounds,
# bool and enum values, and missing returns.
UBSAN_SKIPPED="null,object-size,pointer-overflow,alignment,vptr,function,nonnull-attribute,returns-nonnull-attribute"
SANITIZE_FLAGS="-fsanitize=address,undefined -fno-sanitize=$UBSAN_SKIPPED -fno-sanitize-recover=all -fno-omit-frame-pointer"
ASAN_DIR="${CW4D_ASAN_DIR:-build-asan}"
FUZZ_TARGETS=(off g4mf scene spec nesting wythoff cli texture view)

discard_stale_cache() {  # DIR [COMPILER]: drop a CMake cache made elsewhere or with another compiler
  local cache="$1/CMakeCache.txt" gen home cxx
  [[ -f "$cache" ]] || return 0
  gen="$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$cache")"
  home="$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cache")"
  cxx="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$cache")"
  if [[ "$gen" != "Ninja" || "$home" != "$PWD" || ( -n "${2:-}" && "$cxx" != *"$2" ) ]]; then
    log "discarding stale CMake cache in $1/"
    rm -rf "$cache" "$1/CMakeFiles"
  fi
}

fuzz_enabled() { [[ "${CW4D_FUZZ_SECONDS:-30}" != 0 ]]; }

# Configures build-asan/ and builds TARGET... (nothing: everything). The fuzz targets and the
# coverage instrumentation are in only when the fuzz runs are on.
build_instrumented() {
  local web=() fuzz=OFF link="$SANITIZE_FLAGS -fuse-ld=lld"
  mapfile -t web < <(web_options)
  # (-DCW4D_BUILD_FUZZ=ON adds coverage counters to the libraries and the fuzz targets)
  fuzz_enabled && fuzz=ON
  discard_stale_cache "$ASAN_DIR" clang++
  log "configuring the AddressSanitizer + UndefinedBehaviorSanitizer build (clang) in $ASAN_DIR/"
  # -g1 (line tables only): sanitizer reports keep function names and file:line, while each
  # object is ~3.5x smaller and compiles ~1.6x faster than with -g (bench/RESULTS.md, CI time).
  # These flags replace CMake's RelWithDebInfo default (-O2 -g -DNDEBUG): without NDEBUG the
  # assert()s on cw4d's internal invariants (and Eigen's index checks) are on in this build.
  # clang, not g++: g++ 12 compiles this instrumented build about twice as slowly (the
  # Release build stays on g++, so both compilers see the code); clang is also what libFuzzer needs.
  # The tests' own files leave UBSan out (-fno-sanitize=undefined, after the flags above): its
  # checks doubled their compile time; ASan still checks them, and both check the libraries.
  cmake -S . -B "$ASAN_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DCW4D_BUILD_BENCH=OFF -DCW4D_BUILD_PYTHON=OFF -DCW4D_BUILD_FUZZ=$fuzz "${web[@]}" \
    -DCW4D_TEST_COMPILE_OPTIONS=-fno-sanitize=undefined \
    "-DCMAKE_CXX_FLAGS=$SANITIZE_FLAGS" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
    "-DCMAKE_EXE_LINKER_FLAGS=$link" "-DCMAKE_SHARED_LINKER_FLAGS=$link" >&2 ||
    return 1
  local targets=()
  (($# > 0)) && targets=(--target "$@")
  cmake --build "$ASAN_DIR" -j "$JOBS" "${targets[@]}" >&2
}

run_sanitizer_suite() {
  local status=0
  build_instrumented || return 1
  # The degeneracy stress tests run 5% of their planes here (each section costs ~10x under ASan),
  # and the hull tests every fourth Wythoff polychoron and Miratope file; the normal suite above
  # runs all of them.
  log "testing under ASan+UBSan"
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1" \
    UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" CW4D_STRESS_FRACTION=0.05 \
    ctest --test-dir "$ASAN_DIR" --output-on-failure -j "$JOBS" || status=$?
  if ((status == 0)); then log "sanitizer tests passed"; else log "sanitizer tests FAILED (ctest exit $status)"; fi
  return "$status"
}

fuzz_one() {  # TARGET SECONDS: one libFuzzer run, its log in build-asan/fuzz/fuzz_TARGET.log
  local target="$1" seconds="$2" dir="$ASAN_DIR/fuzz" timeout=10
  # New inputs go to a scratch directory: the seed corpus in fuzz/corpus/ stays as committed.
  mkdir -p "$dir/corpus-$target"
  # (a command line may legitimately run for seconds, and far slower instrumented: `info` of an
  # 8-dimensional built-in such as cube:8 loads, validates and measures 5 x 80640 simplices,
  # 9-15 s per run here, 0.4 s in a release build; so 60 s for cli, room for a loaded machine)
  [[ "$target" == cli ]] && timeout=60
  "$dir/fuzz_$target" -max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$dir/crash-$target-" "$dir/corpus-$target" \
    "fuzz/corpus/$target" 2>"$dir/fuzz_$target.log"
}

run_fuzz_smoke() {
  local seconds="${CW4D_FUZZ_SECONDS:-30}" target status=0 running=0 failed=()
  [[ "$seconds" =~ ^[1-9][0-9]*$ ]] || die "CW4D_FUZZ_SECONDS must be a positive integer, got '$seconds'"
  # After the sanitizer suite this only links what is missing; without it (CW4D_SANITIZE=0) it
  # builds the fuzz targets and the libraries they need.
  build_instrumented "${FUZZ_TARGETS[@]/#/fuzz_}" || return 1
  log "fuzzing ${FUZZ_TARGETS[*]} for ${seconds}s each, $JOBS at a time"
  for target in "${FUZZ_TARGETS[@]}"; do
    if ((running >= JOBS)); then wait -n || true; running=$((running - 1)); fi
    rm -f "$ASAN_DIR/fuzz/fuzz_$target.rc"
    (
      rc=0
      fuzz_one "$target" "$seconds" || rc=$?
      echo "$rc" >"$ASAN_DIR/fuzz/fuzz_$target.rc"
    ) &
    running=$((running + 1))
  done
  wait
  for target in "${FUZZ_TARGETS[@]}"; do
    if [[ "$(cat "$ASAN_DIR/fuzz/fuzz_$target.rc" 2>/dev/null)" == 0 ]]; then
      grep -E '^stat::number_of_executed_units' "$ASAN_DIR/fuzz/fuzz_$target.log" |
        sed "s/^/cw4d: fuzz_$target /" >&2
    else
      failed+=("$target")
      tail -n 40 "$ASAN_DIR/fuzz/fuzz_$target.log" >&2
    fi
  done
  if ((${#failed[@]} > 0)); then
    log "fuzzing FAILED: ${failed[*]} (logs and crash inputs in $ASAN_DIR/fuzz/)"
    status=1
  else
    log "fuzz runs clean"
  fi
  return "$status"
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

# --- (c') test mode only: the Python module's pytest suite -------------------------------------
# Runs with the interpreter the module was built for (Python3_EXECUTABLE in the CMake cache,
# /usr/bin/python3 by default), against build/python. pytest's exit 5 (no test collected) is a
# failure here, like every other non-zero status.
run_python_tests() {
  local cache="$BUILD_DIR/CMakeCache.txt" python status=0
  if [[ "$(sed -n 's/^CW4D_BUILD_PYTHON:BOOL=//p' "$cache")" != ON ]]; then
    log "the Python module is not built (CW4D_BUILD_PYTHON is off in $BUILD_DIR/): no pytest run"
    return 1
  fi
  python="$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$cache")"
  [[ -x "$python" ]] || { log "the Python interpreter '$python' of $cache is missing"; return 1; }
  log "testing the Python module with $python -m pytest"
  PYTHONPATH="$PWD/$BUILD_DIR/python${PYTHONPATH:+:$PYTHONPATH}" CW4D_CLI="$PWD/$BUILD_DIR/apps/cw4d" \
    MPLBACKEND=Agg "$python" -m pytest -q -p no:cacheprovider python/tests || status=$?
  case "$status" in
    0) log "Python tests passed" ;;
    5) log "Python tests FAILED: pytest collected no tests (exit 5)" ;;
    *) log "Python tests FAILED (pytest exit $status)" ;;
  esac
  return "$status"
}

# --- (b'') the web viewer: complex/ and section/ compiled to WebAssembly in build-web/ ----------
# Optional: skipped (with a note) when emscripten is not installed, or with CW4D_WEB=0.
WEB_DIR="${CW4D_WEB_DIR:-build-web}"
# Where the web build's site is, for `cmake --install` and the installed `cw4d view` test;
# without a web build that test is left out (CW4D_WEB=OFF). Given to every native build.
web_options() {
  local site="$WEB_DIR/web/site"
  [[ "$site" == /* ]] || site="$PWD/$site"
  if web_enabled; then printf '%s\n' -DCW4D_WEB=ON "-DCW4D_WEB_SITE_DIR=$site"; else echo -DCW4D_WEB=OFF; fi
}
web_enabled() {
  [[ "${CW4D_WEB:-1}" != 0 ]] && command -v emcmake >/dev/null 2>&1 && command -v em++ >/dev/null 2>&1
}
build_web() {
  if ! web_enabled; then
    if [[ "${CW4D_WEB:-1}" == 0 ]]; then
      log "web viewer skipped (CW4D_WEB=0)"
    else
      log "web viewer not built: emscripten is not installed (CW4D_WEB=1 ./setup.sh installs" \
        "it, 185 MB to fetch, and builds the viewer; ./setup.sh test does too)"
    fi
    return 0
  fi
  # emscripten's JavaScript tools need the acorn parser of Debian's node-acorn.
  export NODE_PATH="${NODE_PATH:+$NODE_PATH:}/usr/share/nodejs"
  discard_stale_cache "$WEB_DIR"
  log "configuring the web viewer (emscripten) in $WEB_DIR/"
  emcmake cmake -S . -B "$WEB_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
  cmake --build "$WEB_DIR" -j "$JOBS" >&2
}

run_browser_test() {
  if ! web_enabled; then
    log "browser test skipped (no web build)"
    return 0
  fi
  command -v chromium >/dev/null 2>&1 || die "chromium is missing (Debian package chromium)"
  log "testing the web viewer in headless Chromium"
  local status=0 rc
  python3 web/test/browser_test.py --site "$WEB_DIR/web/site" --cw4d "$BUILD_DIR/apps/cw4d" \
    --samples tests/data/miratope || status=$?
  # The page driven as a person would (pointer, wheel, keys, touch, downloads, the phone
  # layout), its screenshots and frame times in $WEB_DIR/viewer-test/.
  log "driving the viewer page as a user (web/test/viewer_test.mjs)"
  node web/test/viewer_test.mjs --site "$WEB_DIR/web/site" --cw4d "$BUILD_DIR/apps/cw4d" \
    --out "$WEB_DIR/viewer-test" --screenshots "$WEB_DIR/viewer-test" --bench-seconds 20 || { rc=$?; ((status)) || status=$rc; }
  return "$status"
}

# --- (c'') test mode only: every C++ file is formatted by .clang-format ---------------------------
# Lists the files `clang-format` would change (Debian's clang-format 14) and fails if there is one;
# `clang-format -i FILE` fixes it. Only files tracked by git are checked.
check_format() {
  local file bad=()
  command -v clang-format >/dev/null 2>&1 || die "clang-format is missing (Debian package clang-format)"
  git rev-parse --is-inside-work-tree >/dev/null 2>&1 || { log "not a git checkout: format check skipped"; return 0; }
  while IFS= read -r file; do
    clang-format --dry-run --Werror "$file" >/dev/null 2>&1 || bad+=("$file")
  done < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.cc')
  if ((${#bad[@]} > 0)); then
    log "not formatted by .clang-format (fix with clang-format -i): ${bad[*]}"
    return 1
  fi
  log "every C++ file is formatted"
}

install_missing_packages
configure_and_build
build_web

# --- the job ------------------------------------------------------------------------------------
if [[ "$MODE" == test ]]; then
  check_format || exit 1
  install_test_tools
  log "testing"
  # Every stage runs even when an earlier one failed, so one run reports each verdict (a failing
  # browser test does not hide what the sanitizers say); the exit status is the first failure's.
  status=0 verdicts=()
  stage() {  # NAME COMMAND...: run one stage, record its verdict
    local name="$1" rc=0
    shift
    "$@" || rc=$?
    if ((rc == 0)); then verdicts+=("$name: passed"); else verdicts+=("$name: FAILED ($rc)"); fi
    if ((rc != 0 && status == 0)); then status=$rc; fi
  }
  stage "ctest" ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS"
  stage "pytest" run_python_tests
  if [[ "${CW4D_SANITIZE:-1}" != 0 ]]; then stage "ASan+UBSan ctest" run_sanitizer_suite; fi
  stage "browser test" run_browser_test
  if fuzz_enabled; then stage "fuzz" run_fuzz_smoke; fi
  for verdict in "${verdicts[@]}"; do log "$verdict"; done
  if ((status == 0)); then log "every test passed"; else log "tests FAILED"; fi
  exit "$status"
fi

log "slicing the rotated tesseract into out/section.obj"
"$BUILD_DIR/apps/cw4d" slice tesseract --rotate xw:30 --rotate yw:25 --rotate zw:20 \
  --normal 0,0,0,1 --offset 0.25 -o out/section.obj
[[ -s out/section.obj ]] || die "cw4d slice did not write out/section.obj"
if compgen -G "$BUILD_DIR/python/cw4d/_cw4d*.so" >/dev/null; then
  python="$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$BUILD_DIR/CMakeCache.txt")"
  log "the Python module: PYTHONPATH=$BUILD_DIR/python ${python:-python3} -c 'import cw4d' (docs/python.md)"
fi
if web_enabled; then
  log "web viewer: serve $WEB_DIR/web/site/ (python3 -m http.server -d $WEB_DIR/web/site --bind 127.0.0.1 8000)"
  log "  and open http://127.0.0.1:8000/ ; or write one file that opens from disk:"
  log "  $BUILD_DIR/apps/cw4d view 120-cell --normal 0,0,0,1 -o out/view.html"
fi
