#!/usr/bin/env bash
# cw4d's hot slice against a JavaScript port of Tesserxel's tetrahedral slicing kernel
# (bench/js/tet_slice.mjs), run side by side, interleaved, in one run.
#
#   bench/js/compare_js.sh [ROUNDS] [MIN_TIME]      (defaults: 3, 0.25)
#
# Per model (tesseract, 24-cell, 120-cell, 600-cell, duoprism:32,32): the model's tetrahedra
# as cw4d makes them (`cw4d tetrahedralize MODEL -o mesh.bin`), then in each round, model by
# model, bench_compare's "offsets" case (Slicer::slice, one SliceBuffers, the fixed generic
# normal and 256 offsets inside +-0.95 x the largest vertex norm in turn) and the port slicing
# the tetrahedra with the same planes; the medians over the rounds of ns per slice (CPU time)
# and JS time / cw4d time. First the port is checked against cw4d's own section (the area of
# its triangles against `cw4d slice --triangulate`, 20 slices; CHECK=0 skips it).
#
# BUILD=dir: the build whose bench/bench_compare and apps/cw4d run (default build/).
# OLD_BENCH=path: an older bench_compare (e.g. COMPARE_DIR=/tmp/x bench/compare.sh REF leaves
# one in /tmp/x/build-old/bench), timed in the same rounds as a third column.
# MODELS="tesseract 600-cell": restricts the models.  NODE=path: node (default: node).
set -euo pipefail
rounds=${1:-3}
min_time=${2:-0.25}
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD:-$root/build}
bench="$build/bench/bench_compare"
cli="$build/apps/cw4d"
node=${NODE:-node}
old=${OLD_BENCH:-}
port="$root/bench/js/tet_slice.mjs"
for f in "$bench" "$cli"; do
  [[ -x "$f" ]] || { echo "compare_js.sh: $f missing (build the bench_compare and cw4d targets)" >&2; exit 2; }
done
[[ -z "$old" || -x "$old" ]] || { echo "compare_js.sh: OLD_BENCH=$old is not executable" >&2; exit 2; }
tmp=$(mktemp -d /tmp/cw4d-js.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
models=${MODELS:-tesseract 24-cell 120-cell 600-cell duoprism:32,32}
label() { [[ $1 == duoprism:32,32 ]] && echo duoprism32 || echo "$1"; }
if [[ "${CHECK:-1}" == 1 ]]; then
  echo "checking the port against cw4d slice ..." >&2
  "$node" "$port" check "$cli" | tail -1 >&2
fi
declare -A tets
for m in $models; do
  "$cli" tetrahedralize "$m" -o "$tmp/$(label "$m").bin" >/dev/null
  tets[$m]=$(($(stat -c %s "$tmp/$(label "$m").bin") / 192))
done
for ((r = 1; r <= rounds; ++r)); do
  echo "round $r/$rounds ..." >&2
  for m in $models; do
    l=$(label "$m")
    "$bench" --min-time "$min_time" --filter "$l/offsets" | awk -v m="$m" '$1 == "case" { print "new", m, $3 }' >>"$tmp/runs.txt"
    if [[ -n "$old" ]]; then
      "$old" --min-time "$min_time" --filter "$l/offsets" | awk -v m="$m" '$1 == "case" { print "old", m, $3 }' >>"$tmp/runs.txt"
    fi
    "$node" "$port" time "$tmp/$l.bin" "$min_time" | awk -v m="$m" '$1 == "js" { print "js", m, $2, $3 }' >>"$tmp/runs.txt"
  done
done
echo "# bench/js/compare_js.sh $rounds $min_time  ($(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet || echo '+dirty'), $("$node" --version), $rounds interleaved rounds, medians of ns per slice)"
for m in $models; do echo "tets $m ${tets[$m]}"; done >>"$tmp/runs.txt"
awk -v models="$models" -v has_old="${old:+1}" '
  $1 == "tets" { nt[$2] = $3; next }
  { t[$1, $2] = t[$1, $2] " " $3; if ($1 == "js") tri[$2] = $4 }
  function median(s,   a, k, i, j, x) {
    k = split(s, a, " ")
    for (i = 2; i <= k; ++i) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; --j) a[j + 1] = a[j]; a[j + 1] = x }
    return k % 2 ? a[(k + 1) / 2] : (a[k / 2] + a[k / 2 + 1]) / 2
  }
  END {
    n = split(models, ms, " ")
    if (has_old) printf "%-16s %7s %9s %11s %11s %11s %9s %9s\n", "model", "tets", "triangles", "js ns", "old ns", "new ns", "js/old", "js/new"
    else printf "%-16s %7s %9s %11s %11s %9s\n", "model", "tets", "triangles", "js ns", "cw4d ns", "js/cw4d"
    for (i = 1; i <= n; ++i) {
      m = ms[i]; js = median(t["js", m]); w = median(t["new", m])
      if (has_old) { o = median(t["old", m]); printf "%-16s %7d %9.1f %11.0f %11.0f %11.0f %8.2fx %8.2fx\n", m, nt[m], tri[m], js, o, w, js / o, js / w }
      else printf "%-16s %7d %9.1f %11.0f %11.0f %8.2fx\n", m, nt[m], tri[m], js, w, js / w
    }
  }' "$tmp/runs.txt"
