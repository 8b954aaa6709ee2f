#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Helpers of the end-to-end shell tests (sourced): one ok:/FAIL: line per case, a count of
# failures, an expected exit code and message, and a directory's state to show nothing changed.
fails=0
ok() { echo "ok: $*"; }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
# expect RC PATTERN CMD...: exit code and a stderr line matching PATTERN
expect() {
  local rc="$1" pat="$2"; shift 2
  "$@" > out.txt 2> err.txt; local got=$?
  if [ "$got" -ne "$rc" ]; then bad "$* -> exit $got, expected $rc: $(tr '\n' ' ' < err.txt | head -c 400)"; return 1; fi
  if [ -n "$pat" ] && ! grep -Eq -- "$pat" err.txt; then bad "$* -> message lacks /$pat/: $(tr '\n' ' ' < err.txt | head -c 400)"; return 1; fi
  ok "$* -> $rc${pat:+: $(grep -E -- "$pat" err.txt | head -1 | head -c 240)}"
}
# a directory's state: names and checksums (to show nothing was deleted or changed)
state() { (cd "$1" && find . -type f | sort | xargs md5sum); }
