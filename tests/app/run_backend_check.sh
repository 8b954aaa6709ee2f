#!/usr/bin/env bash
# The run-time backend choice (`--backend`, include/nacre/core/backend.hpp) through the app:
#  1. `nacre --backend list` names this build's backends, the default first;
#  2. the small dynamic deck, BE and BIE, run on every listed backend: series.csv identical in
#     every column but seconds (nacre promises the same bits on every host backend), and
#     summary.json names the backend it ran on;
#  3. an unknown backend is refused (exit 2) naming the enabled ones, and a Monte Carlo deck on a
#     backend other than the default is refused (the rigid family runs on the default one).
#   run_backend_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
. "$src/tests/app/checks_lib.sh"
mapfile -t listed < <("$exe" --backend list)
[ "${#listed[@]}" -ge 1 ] && [[ "${listed[0]}" == *"(default)" ]] && ok "backends: ${listed[*]}" \
  || bad "--backend list printed '${listed[*]}'"
backends=()
for l in "${listed[@]}"; do backends+=("${l%% *}"); done
sed 's/^method = "be"/method = "bie"/' "$src/tests/app/tiny_dynamic.toml" > tiny_bie.toml
for deck in "$src/tests/app/tiny_dynamic.toml" tiny_bie.toml; do
  name=$(basename "$deck" .toml)
  for b in "${backends[@]}"; do
    if "$exe" "$deck" --backend "$b" -o "${name}_$b" -q > "run_${name}_$b.txt" 2>&1; then ok "$name on $b"
    else bad "$name on $b: $(tail -3 "run_${name}_$b.txt")"; fi
  done
  python3 - "$name" "${backends[@]}" <<'PY' && ok "$name: the same series on ${backends[*]}" || bad "$name: backends disagree"
import csv, json, sys
name, backends = sys.argv[1], sys.argv[2:]
tables = {}
for b in backends:
    s = json.load(open(f"{name}_{b}/summary.json"))
    assert s["backend"] == b and s["status"] == "done", (b, s["backend"], s["status"])
    rows = list(csv.DictReader(open(f"{name}_{b}/series.csv")))
    assert len(rows) > 5
    tables[b] = [{k: v for k, v in r.items() if k != "seconds"} for r in rows]
ref = tables[backends[0]]
for b in backends[1:]:
    assert tables[b] == ref, f"{b} differs from {backends[0]}"
PY
done
expect 2 "not a backend of this build; expected one of" "$exe" "$src/tests/app/tiny_dynamic.toml" --backend no-such-backend -o unknown
if [ "${#backends[@]}" -ge 2 ]; then
  expect 2 "Monte Carlo solver runs on the default backend" "$exe" "$src/tests/app/tiny.toml" --backend "${backends[1]}" -o mc_other
else
  ok "one backend in this build: the Monte Carlo refusal of another needs two"
fi
[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "all backend checks passed"
