#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# An installed nacre works from its prefix alone:
#  1. cmake --install puts bin/nacre, the Python package, the decks, the headers and the CMake
#     package under the prefix;
#  2. a code links nacre::nacre through find_package(nacre) and runs;
#  3. with the source and build trees hidden (an empty file system mounted over them), the
#     installed nacre prints its version, runs the installed default deck and draws its charts
#     with the installed Python package, and the package reads the run back.
#   run_install_check.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build="$1"; src="$2"; work="$3"
if ! unshare -m --propagation unchanged true 2> /dev/null; then
  echo "SKIP: no mount namespace here (run as root, as CI does, to hide the trees)"; exit 77
fi
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
cmake --install "$build" --prefix "$work/prefix" > install.log || { cat install.log; fail "cmake --install"; }
for f in bin/nacre share/nacre/python/nacre/__init__.py share/nacre/python/nacre/charts/mc.py \
         share/nacre/inputs/default.toml include/nacre/core/build_info.hpp lib/cmake/nacre/nacreConfig.cmake; do
  [ -e "prefix/$f" ] || fail "prefix/$f not installed"
done
echo "installed: $(find prefix -type f | wc -l) files"
gen=(); command -v ninja > /dev/null && gen=(-G Ninja)
cmake -S "$src/tests/install" -B consumer "${gen[@]}" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release > consumer.log 2>&1 || { cat consumer.log; fail "find_package(nacre)"; }
cmake --build consumer >> consumer.log 2>&1 || { cat consumer.log; fail "building against nacre::nacre"; }
./consumer/consumer | grep -q "^nacre 1\." || fail "the consumer did not print nacre's version"
echo "find_package(nacre) -> nacre::nacre: linked and ran"
# the prefix outside both trees, then both trees hidden
p=$(mktemp -d /tmp/nacre-prefix.XXXXXX)
trap 'rm -rf "$p"' EXIT
cp -a prefix/. "$p/"
unshare -m --propagation unchanged env -u NACRE_PYTHON_DIR -u PYTHONPATH bash -c '
  set -euo pipefail
  trap '\''echo "FAIL: line $LINENO of the hidden-tree check exited with $?"'\'' ERR
  p="$1"; src="$2"; build="$3"
  mount -t tmpfs none "$src"
  case "$build" in "$src"/*) ;; *) mount -t tmpfs none "$build" ;; esac
  [ ! -e "$src/python" ] || { echo "FAIL: the source tree is still visible"; exit 1; }
  cd "$p"
  # (not piped into head: head exits after one line and nacre, still writing, dies of SIGPIPE)
  bin/nacre --version > version.txt
  head -n 1 version.txt
  bin/nacre share/nacre/inputs/default.toml -o run -q 2> err.txt || { cat err.txt; echo "FAIL: the run failed"; exit 1; }
  ! grep -q "warning" err.txt || { cat err.txt; echo "FAIL: the installed run warned (charts?)"; exit 1; }
  for f in steps.csv summary.json r_curve.csv deck.toml energy_force.png crack.png r_curve.png; do
    [ -s "run/$f" ] || { echo "FAIL: run/$f missing"; exit 1; }
  done
  PYTHONPATH="$p/share/nacre/python" python3 -c "
import nacre
r = nacre.Run(\"run\")
t = r.table()
assert t[\"method\"].dtype.kind == \"U\" and len(t[\"step\"]) > 10, t.keys()
assert r.summary[\"nacre\"][\"version\"].startswith(\"1.\")
assert r.r_curve() is not None
print(\"the installed package reads the run:\", len(t[\"step\"]), \"steps, toughening ratio\", r.summary[\"crack\"][\"toughening_ratio\"])
"
' bash "$p" "$src" "$build"
echo "the installed nacre ran the default deck with its charts, the source and build trees hidden"
