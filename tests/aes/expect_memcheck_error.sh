#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Run a command (valgrind memcheck --error-exitcode=1 ...) that MUST report secret-dependent
# control flow or addresses: pass only if it exits with 1 and memcheck's report is in the output.
out=$("$@" 2>&1)
rc=$?
printf '%s\n' "$out"
if [ "$rc" -ne 1 ]; then
  echo "FAIL: expected memcheck to report errors (exit code 1), got exit code $rc"
  exit 1
fi
if ! printf '%s\n' "$out" | grep -Eq "Use of uninitialised value|Conditional jump or move depends on uninitialised"; then
  echo "FAIL: exit code 1 but no secret-dependent address or branch in memcheck's report"
  exit 1
fi
echo "OK: memcheck caught the table-based AES"
