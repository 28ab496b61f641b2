#!/usr/bin/env bash
# ctest view_installed: `cw4d view` of an installed cw4d, away from the source and build trees.
#   view_installed.sh BUILD_DIR SITE_DIR BINDIR SHAREDIR
# installs BUILD_DIR (the default component: the executable, the viewer page and the site folder
# SITE_DIR of the web build) into a scratch prefix outside both trees, moves the prefix elsewhere,
# and from a third folder runs PREFIX/BINDIR/cw4d view tesseract --normal 0,0,0,1: the page must be written with the
# model in it. Then, with the installed page removed, cw4d view must fail with one error line
# naming where it looked (the build tree's page is not a fallback for an installed executable).
set -euo pipefail

fail() { printf 'view_installed: FAILED: %s\n' "$*" >&2; exit 1; }
(($# == 4)) || fail "usage: view_installed.sh BUILD_DIR SITE_DIR BINDIR SHAREDIR"
build="$1" site="$2" bindir="$3" sharedir="$4"

[[ -f "$site/cw4d-view.html" ]] ||
  fail "no web build: $site/cw4d-view.html is missing. Build the viewer first (./setup.sh does;" \
    "or NODE_PATH=/usr/share/nodejs emcmake cmake -S . -B build-web -G Ninja && cmake --build" \
    "build-web), point -DCW4D_WEB_SITE_DIR at its web/site, or configure with -DCW4D_WEB=OFF"

scratch="$(mktemp -d "${TMPDIR:-/tmp}/cw4d-view-installed.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT
case "$scratch/" in
  "$(cd "$build" && pwd -P)/"*) fail "the scratch folder $scratch lies in the build tree" ;;
esac

# The default component only: the python component installs into the interpreter's own folder.
cmake --install "$build" --prefix "$scratch/prefix" --component Unspecified >"$scratch/install.log" ||
  { cat "$scratch/install.log" >&2; fail "cmake --install $build failed"; }
for f in "$sharedir/cw4d-view.html" "$sharedir/site/index.html" "$sharedir/site/cw4d_wasm.js" \
  "$sharedir/site/js/viewer.js"; do
  [[ -f "$scratch/prefix/$f" ]] || fail "the install has no $f"
done

mkdir "$scratch/moved" "$scratch/work"
mv "$scratch/prefix" "$scratch/moved/prefix"
cw4d="$scratch/moved/prefix/$bindir/cw4d"
cd "$scratch/work"
"$cw4d" view tesseract --normal 0,0,0,1 -o out.html >wrote.txt 2>stderr.txt ||
  fail "$cw4d view tesseract -o out.html exited $?: $(cat stderr.txt)"
[[ -s out.html ]] || fail "cw4d view wrote no out.html"
grep -q '/\*cw4d:config\*/{}' out.html && fail "out.html still holds the empty configuration marker"
grep -q 'start(createCw4d, {"off":"4OFF' out.html || fail "out.html has no configuration passed to start()"
grep -q '"name":"tesseract' out.html || fail "out.html does not name the model"
grep -q '"off":"4OFF' out.html || fail "out.html does not hold the model as 4OFF"
grep -q 'createCw4d' out.html && grep -q 'WebAssembly' out.html ||
  fail "out.html does not include the WebAssembly core"
cmp -s <(head -c 200 out.html) <(head -c 200 "$site/cw4d-view.html") ||
  fail "out.html does not start as the viewer page"

# Without the installed page: one error line, exit 1 (usage), naming the installed path.
rm "$scratch/moved/prefix/$sharedir/cw4d-view.html"
rc=0
"$cw4d" view tesseract --normal 0,0,0,1 -o missing.html >stdout.txt 2>stderr.txt || rc=$?
[[ $rc == 1 ]] || fail "without the page, cw4d view exited $rc (expected 1): $(cat stderr.txt)"
[[ $(wc -l <stderr.txt) == 1 ]] || fail "without the page, stderr is not one line: $(cat stderr.txt)"
grep -qF "$scratch/moved/prefix/$sharedir/cw4d-view.html" stderr.txt ||
  fail "the error does not name the installed page's path: $(cat stderr.txt)"
[[ ! -e missing.html ]] || fail "cw4d view wrote a file without a page"
echo "view_installed: passed: $(head -n 1 wrote.txt)"
