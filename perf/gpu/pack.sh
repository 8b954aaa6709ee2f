#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# pack.sh — bundle everything perf/gpu/runbook.sh needs on a machine without network access:
# nacre's sources (this checkout's committed state), the Kokkos / Kokkos Kernels tarballs and
# the CUDA-13 patch (the dependency sources, NACRE_DEPS: see docs/ci.md / devenv/nacre-env), and the header-only libraries the benchmarks use (CLI11,
# Random123, Eigen's core headers), taken from the dev root. Run on the development machine:
#   perf/gpu/pack.sh [OUT.tar.gz]        (default nacre-gpu-bundle.tar.gz)
# Copy the tarball to the GPU machine, then: tar xzf nacre-gpu-bundle.tar.gz &&
#   nacre-gpu-bundle/nacre/perf/gpu/runbook.sh OUTDIR
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd -P)"
OUT="$(realpath -m "${1:-nacre-gpu-bundle.tar.gz}")"
# The dependency sources: NACRE_DEPS, else the nearest shared/deps beside the repository or beside
# one of its parent directories (found as devenv/nacre-env finds them).
DEPS="${NACRE_DEPS:-}"
if [ -z "$DEPS" ] || [ ! -d "$DEPS" ]; then
  DEPS="$REPO/../shared/deps"; d="$REPO/.."
  while :; do
    if [ -d "$d/shared/deps" ]; then DEPS="$d/shared/deps"; break; fi
    if [ ! -d "$d" ] || [ "$d" -ef / ]; then break; fi
    d="$d/.."
  done
fi
ROOT="$("$REPO/devenv/nacre-env" path 2>/dev/null || echo /var/cache/nacre/devroot-v1)"
INC="${NACRE_VENDOR_INCLUDE:-$ROOT/usr/include}"   # where CLI/ and Random123/ are
stage="$(mktemp -d)"; trap 'rm -rf "$stage"' EXIT
b="$stage/nacre-gpu-bundle"; mkdir -p "$b/deps" "$b/vendor/include"
git -C "$REPO" archive --format=tar --prefix=nacre/ HEAD | tar x -C "$b"
git -C "$REPO" rev-parse HEAD > "$b/nacre/REVISION"
for f in kokkos-4.6.01.tar.gz kokkos-cuda13.patch kokkos-kernels-4.7.00.tar.gz SHA256SUMS README.md; do
  cp "$DEPS/$f" "$b/deps/"
done
for d in CLI Random123 eigen3/Eigen; do
  [ -d "$INC/$d" ] || { echo "pack.sh: $INC/$d not found (set NACRE_VENDOR_INCLUDE)" >&2; exit 1; }
  mkdir -p "$b/vendor/include/$(dirname "$d")"; cp -r "$INC/$d" "$b/vendor/include/$d"
done
tar czf "$OUT" -C "$stage" nacre-gpu-bundle
echo "pack.sh: wrote $OUT ($(du -h "$OUT" | cut -f1))"
