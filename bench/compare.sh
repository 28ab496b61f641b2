#!/usr/bin/env bash
# Old/new ratios of the section, tet and sweep benchmarks (bench/bench_compare.cpp).
#
#   bench/compare.sh [REF] [ROUNDS] [MIN_TIME]      (defaults: efc0dc1, 3, 0.25)
#
# Builds REF in a temporary git worktree and the working tree (Release, Ninja, ccache), both
# with the working tree's bench_compare.cpp (it uses the API as of efc0dc1, with no feature macros:
# REF must be efc0dc1 or later), runs the two programs
# in alternating rounds (old, new, old, new, ...) and prints per case the median time of each
# and old/new. Nothing outside the checkout and /tmp is written; the worktree is removed.
# BENCH_MODELS="tesseract/ 600-cell/" restricts the models (case name prefixes).
# COUNT=1 prints instructions per operation (bench_instructions under valgrind's callgrind: the
# slice, section, tet, sweep and sweep-slices cases, per layer for the last two, and the new
# tree's 256 x slice / sweep) instead of times: the figure a loaded machine does not move.
# COUNT_MODELS="tesseract 600-cell" restricts its models, COUNT_MODES="tet" its cases.
# COMPARE_DIR=/tmp/somewhere keeps REF's worktree and build there for later runs (only the
# benchmark itself is recompiled); remove it with `git worktree remove --force DIR/old`.
set -euo pipefail
ref=${1:-efc0dc1}
rounds=${2:-3}
min_time=${3:-0.25}
root=$(cd "$(dirname "$0")/.." && pwd)
keep=${COMPARE_DIR:-}
if [[ -n "$keep" ]]; then
  tmp=$keep
  mkdir -p "$tmp"
  rm -f "$tmp/runs.txt"
else
  tmp=$(mktemp -d /tmp/cw4d-compare.XXXXXX)
fi
old_tree="$tmp/old"
cleanup() {
  if [[ -z "$keep" ]]; then
    git -C "$root" worktree remove --force "$old_tree" >/dev/null 2>&1 || true
    rm -rf "$tmp"
  fi
}
trap cleanup EXIT
export CCACHE_NOHASHDIR=1
if [[ ! -d "$old_tree" ]]; then
  git -C "$root" worktree add --detach "$old_tree" "$ref" >/dev/null 2>&1
elif [[ $(git -C "$old_tree" rev-parse HEAD) != $(git -C "$root" rev-parse "$ref^{commit}") ]]; then
  echo "compare.sh: $old_tree holds another commit than $ref" >&2
  exit 2
fi
for prog in bench_compare bench_instructions; do
  cp "$root/bench/$prog.cpp" "$old_tree/bench/"
  if ! grep -q "add_executable($prog " "$old_tree/bench/CMakeLists.txt"; then
    cat >>"$old_tree/bench/CMakeLists.txt" <<CMAKE
add_executable($prog $prog.cpp)
target_link_libraries($prog PRIVATE cw4d_tetrahedralize cw4d_section cw4d_complex
  cw4d_settings)
CMAKE
  fi
done
build() {  # source dir, build dir
  CCACHE_BASEDIR="$1" cmake -S "$1" -B "$2" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  CCACHE_BASEDIR="$1" cmake --build "$2" -j2 --target bench_compare bench_instructions >/dev/null
}
echo "building $ref ..." >&2
build "$old_tree" "$tmp/build-old"
echo "building the working tree ..." >&2
new_build=${NEW_BUILD:-$root/build}
build "$root" "$new_build"
old_bin="$tmp/build-old/bench/bench_compare"
new_bin="$new_build/bench/bench_compare"
if [[ "${COUNT:-0}" == 1 ]]; then
  # Instructions per operation instead of times: (count at 3 rounds - count at 1) / 512.
  command -v valgrind >/dev/null || { echo "compare.sh: COUNT=1 needs valgrind" >&2; exit 2; }
  count() {  # program mode model rounds: the instructions of the whole run
    local err n
    if ! err=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null); then
      printf 'compare.sh: %s failed:\n%s\n' "$*" "$err" >&2
      exit 2
    fi
    n=$(awk '/ refs:/ { gsub(",", "", $NF); print $NF }' <<<"$err")
    [[ -n "$n" ]] || { printf 'compare.sh: no instruction count from %s\n' "$*" >&2; exit 2; }
    echo "$n"
  }
  echo "# COUNT=1 bench/compare.sh $ref  ($(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet || echo '+dirty') vs $(git -C "$root" rev-parse --short "$ref"), instructions per operation, callgrind)"
  printf "%-28s %12s %12s %9s\n" "case" "old" "new" "old/new"
  cmodels=${COUNT_MODELS:-tesseract 24-cell 120-cell 600-cell duoprism:32,32}
  declare -A newc
  for mode in ${COUNT_MODES:-slice section tet sweep sweep-slices}; do
    for m in $cmodels; do
      per=()
      for side in old new; do
        bin="$tmp/build-old/bench/bench_instructions"
        [[ $side == new ]] && bin="$new_build/bench/bench_instructions"
        one=$(count "$bin" "$mode" "$m" 1)
        three=$(count "$bin" "$mode" "$m" 3)
        per+=($(( (three - one) / 512 )))
      done
      newc[$mode/$m]=${per[1]}
      awk -v c="$mode/$m" -v o="${per[0]}" -v w="${per[1]}" \
        'BEGIN { printf "%-28s %12d %12d %8.2fx\n", c, o, w, o / w }'
    done
  done
  for m in $cmodels; do
    [[ -n "${newc[sweep-slices/$m]:-}" && -n "${newc[sweep/$m]:-}" ]] || continue
    awk -v c="$m" -v s="${newc[sweep-slices/$m]}" -v w="${newc[sweep/$m]}" \
      'BEGIN { printf "new %-24s 256 x slice / sweep %.2fx\n", c, s / w }'
  done
  exit 0
fi
# Alternating per model (the load of a shared machine drifts within a run): old, new, old, ...
models=${BENCH_MODELS:-"tesseract/ 24-cell/ 120-cell/ 600-cell/ duoprism32/ omni120/"}
for ((r = 1; r <= rounds; ++r)); do
  echo "round $r/$rounds ..." >&2
  for m in $models; do
    "$old_bin" --min-time "$min_time" --filter "$m" | sed 's/^/old /' >>"$tmp/runs.txt"
    "$new_bin" --min-time "$min_time" --filter "$m" | sed 's/^/new /' >>"$tmp/runs.txt"
  done
done
echo "# bench/compare.sh $ref $rounds $min_time  ($(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet || echo '+dirty') vs $(git -C "$root" rev-parse --short "$ref"), $rounds alternating rounds, medians)"
awk '
  $2 == "case" { t[$1, $3] = t[$1, $3] " " $4; u[$3] = $5; if (!($3 in seen)) { seen[$3] = 1; order[n++] = $3 } }
  $2 == "fallback" && $1 == "new" { fb[$3] = $0 }
  function median(s,   a, k, i, j, x) {
    k = split(s, a, " ")
    for (i = 2; i <= k; ++i) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; --j) a[j + 1] = a[j]; a[j + 1] = x }
    return k % 2 ? a[(k + 1) / 2] : (a[k / 2] + a[k / 2 + 1]) / 2
  }
  function fmt(ns) { return ns >= 1e6 ? sprintf("%.3g ms", ns / 1e6) : ns >= 1e3 ? sprintf("%.3g us", ns / 1e3) : sprintf("%.3g ns", ns) }
  END {
    printf "%-22s %12s %12s %9s %s\n", "case", "old", "new", "old/new", "new per unit"
    for (i = 0; i < n; ++i) {
      c = order[i]; o = median(t["old", c]); w = median(t["new", c])
      printf "%-22s %12s %12s %8.2fx %s\n", c, fmt(o), fmt(w), o / w, (u[c] > 1 ? fmt(w / u[c]) : "")
    }
    for (c in fb) { sub(/^new fallback /, "", fb[c]); print "fallback (new) " fb[c] }
  }' "$tmp/runs.txt"
