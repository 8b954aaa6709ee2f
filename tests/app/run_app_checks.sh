#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# End-to-end: run the nacre executable on tests/app/tiny.toml, validate every output, then check
# that a run extended by --restart --extend (to twice the displacement) equals a direct run bit for bit.
#   run_app_checks.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -euo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
sed 's/^final_displacement = .*/final_displacement = 0.024/' "$src/tests/app/tiny.toml" > long.toml
"$exe" "$src/tests/app/tiny.toml" -o short -q
python3 "$src/tests/app/check_outputs.py" short
"$exe" long.toml -o short -q --restart short/checkpoint.h5 --extend
"$exe" long.toml -o direct -q
# Off a terminal (stdout to a file, as in a batch job), [output] heartbeat: plain "in progress"
# lines within a load step (here as often as possible); heartbeat = 0: none. Lines are
# line-buffered, so the file holds them while the run goes on.
sed 's/^DumpInter = .*/DumpInter = 0\nheartbeat = 1e-9\ncharts = false/' "$src/tests/app/tiny.toml" > beat.toml
"$exe" beat.toml -o beat > beat.log 2>&1
grep -q "^  step 1 in progress: D = .* cycles, E = " beat.log || { cat beat.log; echo "FAIL: no heartbeat line"; exit 1; }
sed 's/^heartbeat = .*/heartbeat = 0/' beat.toml > quiet_beat.toml
"$exe" quiet_beat.toml -o beat0 > beat0.log 2>&1
if grep -q "in progress" beat0.log; then echo "FAIL: heartbeat = 0 still wrote heartbeat lines"; exit 1; fi
grep -q "^  step 1: D = " beat0.log || { cat beat0.log; echo "FAIL: no step line"; exit 1; }
echo "heartbeat: $(grep -c 'in progress' beat.log) lines within steps at heartbeat 1e-9, none at 0"
# the run directory keeps the run's log: what it printed (off a terminal, every line), and for a
# quiet run (-q) its log lines all the same; a restart appends to the log it continues
cmp beat.log beat/log.txt || { diff beat.log beat/log.txt; echo "FAIL: log.txt is not what the run printed"; exit 1; }
grep -q "^nacre: .*tiny.toml: .* bricks" short/log.txt && grep -q "^nacre: --- restarted ---" short/log.txt &&
  [ "$(grep -c "^  step 1: D = " short/log.txt)" -eq 1 ] ||
  { cat short/log.txt; echo "FAIL: the quiet run's log.txt (its lines, then the restart's)"; exit 1; }
echo "log.txt: the run's lines ($(wc -l < beat/log.txt) off a terminal), a quiet run's and its restart's"
# every column but the wall time must agree exactly
if ! diff <(cut -d, -f1-12 short/steps.csv) <(cut -d, -f1-12 direct/steps.csv); then
  echo "FAIL: restarted run differs from the direct run"; exit 1
fi
python3 "$src/tests/app/check_outputs.py" short
echo "restart: $(($(wc -l < direct/steps.csv) - 1)) steps identical to the direct run"
# a directory written before mesh.h5 held the interfaces' connectivity: a restart into it
# rewrites the mesh, so its nacre.xdmf resolves again
cp -r short oldmesh
python3 -c "import h5py, sys; f = h5py.File(sys.argv[1], 'r+'); del f['/interfaces/connectivity']; f.close()" oldmesh/mesh.h5
sed 's/^final_displacement = .*/final_displacement = 0.03/' "$src/tests/app/tiny.toml" > longer.toml
"$exe" longer.toml -o oldmesh -q --restart oldmesh/checkpoint.h5 --extend
python3 -c "import h5py, sys; assert '/interfaces/connectivity' in h5py.File(sys.argv[1], 'r')" oldmesh/mesh.h5
# every nacre.xdmf this test wrote, as ParaView's Xdmf3 reader needs it (connectivity per topology)
python3 "$src/tests/app/check_xdmf.py" $(find . -name nacre.xdmf | sort)
# A temperature so high that no step converges: "not converged after N cycles", exit 4, the CSV
# (header only: no step completed) and the checkpoint of the last completed step (0) kept.
sed -e 's/^TEMP = .*/TEMP = 1000.0/' -e 's/^colouring = .*/colouring = "natural"\nmax_cycles = 200\npolish_iterations = 10/' \
  "$src/tests/app/tiny.toml" > hot.toml
set +e
"$exe" hot.toml -o hot -q 2> hot.err
rc=$?
set -e
cat hot.err
[ "$rc" -eq 4 ] || { echo "FAIL: a run that cannot converge exited $rc, expected 4"; exit 1; }
grep -q "not converged after 200 cycles" hot.err || { echo "FAIL: no 'not converged after 200 cycles' message"; exit 1; }
[ "$(head -1 hot/steps.csv | cut -d, -f1)" = "step" ] || { echo "FAIL: steps.csv not kept"; exit 1; }
[ -f hot/checkpoint.h5 ] || { echo "FAIL: no checkpoint kept"; exit 1; }
[ ! -f hot/summary.json ] || { echo "FAIL: an unfinished run wrote summary.json"; exit 1; }
echo "hot deck: exit 4, steps.csv and checkpoint kept"
# relaxation = "newton" (trust-region Newton, no Monte Carlo) and "auto": every step converged,
# steps.csv names the method and counts the CG iterations; the same deck with a load programme
# that turns back (irreversible damage) is refused for "newton" (exit 2, naming the key)
for r in newton auto; do
  sed "s/^colouring = .*/colouring = \"natural\"\nrelaxation = \"$r\"\nresidual_tolerance = 1e-9/" \
    "$src/tests/app/tiny.toml" > "$r.toml"
  "$exe" "$r.toml" -o "$r" -q
  python3 - "$r" <<'PY'
import csv, sys
r = sys.argv[1]
rows = list(csv.DictReader(open(f"{r}/steps.csv")))
assert len(rows) >= 3, len(rows)
for row in rows:
    assert row["converged"] == "1" and float(row["residual"]) < 1e-9, row
    assert row["method"].startswith("newton"), row["method"]
    assert int(row["cg_iterations"]) > 0 and int(row["polish_iterations"]) > 0, row
    if r == "newton":
        assert row["method"] == "newton" and row["cycles"] == "0", row
print(f"relaxation = {r}: {len(rows)} steps, methods {sorted({x['method'] for x in rows})}, "
      f"{sum(int(x['polish_iterations']) for x in rows)} Newton steps, {sum(int(x['cg_iterations']) for x in rows)} CG iterations")
PY
done
sed 's/^final_displacement = .*/programme = [0.008, 0.004, 0.012]/' newton.toml > newton_cyclic.toml
set +e
"$exe" newton_cyclic.toml -o newton_cyclic -q 2> newton_cyclic.err
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "relaxation: the trust-region Newton method needs the reversible law" newton_cyclic.err ||
  { cat newton_cyclic.err; echo "FAIL: newton with irreversible damage: exit $rc"; exit 1; }
echo "newton with a path that turns back: refused (exit 2)"

# The command line of nacre 1.0: --version, the subcommands in --help, `nacre run` / `nacre check`
# as `nacre DECK` / `--check`, a deck key set for one run (--set, validated as the deck is and
# recorded in the run's deck.toml), a malformed --set refused before anything is written
v=$("$exe" --version)
[ "$(echo "$v" | wc -l)" -eq 3 ] && echo "$v" | head -1 | grep -Eq "^nacre [0-9]+\.[0-9]+\.[0-9]+ \(commit " &&
  echo "$v" | sed -n 2p | grep -q "^Kokkos [0-9]" || { echo "$v"; echo "FAIL: nacre --version"; exit 1; }
h=$("$exe" --help)
for c in run check sweep bench; do
  echo "$h" | grep -q "^  $c " || { echo "$h"; echo "FAIL: nacre --help does not list $c"; exit 1; }
done
"$exe" check "$src/tests/app/tiny.toml" | grep -q "deck is valid" || { echo "FAIL: nacre check"; exit 1; }
sed 's/^\[output\]/[output]\ncharts = false/' "$src/tests/app/tiny.toml" > nc.toml  # (the charts are checked above)
"$exe" run nc.toml -o via_run -q
"$exe" nc.toml -o via_deck -q
diff <(cut -d, -f1-12 via_run/steps.csv) <(cut -d, -f1-12 via_deck/steps.csv) > /dev/null ||
  { echo "FAIL: nacre run DECK differs from nacre DECK"; exit 1; }
cmp -s via_run/deck.toml nc.toml || { echo "FAIL: deck.toml is not the deck as read"; exit 1; }
"$exe" nc.toml --set geometry.angle=5 -o set5 -q
grep -q "^# nacre: .* with --set geometry.angle=5" set5/deck.toml && grep -q "^angle = 5" set5/deck.toml ||
  { cat set5/deck.toml; echo "FAIL: --set not recorded in deck.toml"; exit 1; }
python3 - set5 via_run <<'PY'
import json, sys
a, b = (json.load(open(f"{d}/summary.json")) for d in sys.argv[1:])
assert a["bricks"] != b["bricks"], "--set geometry.angle=5 changed nothing"
assert a["nacre"]["version"] == b["nacre"]["version"] and a["kokkos"]["version"]
PY
set +e
"$exe" nc.toml --set geometry.angle=abc -o setbad -q 2> setbad.err
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "(with --set):.*geometry.angle" setbad.err && [ ! -e setbad ] ||
  { cat setbad.err; echo "FAIL: a bad --set value: exit $rc"; exit 1; }
echo "command line: --version, subcommands, run/check, --set recorded in deck.toml, a bad --set refused (exit 2)"
