#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# build-deps.sh — build Kokkos / Kokkos Kernels from the carried tarballs into versioned prefixes.
#
# Why: Debian ships Kokkos 5.2.2 (OpenMP only) and no Kokkos Kernels; nacre also has to be
# tested against an older Kokkos (4.6.01, OpenMP+Serial) and linked against a CUDA Kokkos. Each
# recipe builds once into a prefix whose name carries every version that matters, and leaves a
# stamp (.nacre-ready, holding the recipe) only after a complete install: a changed recipe
# rebuilds, an interrupted build starts over, two callers at once wait on a lock.
#
# Runs inside the dev root (devenv/nacre-env deps ... calls it) or on any machine with CMake,
# Ninja and a C++20 compiler (perf/gpu/runbook.sh calls it with NACRE_OPT set):
#   build-deps.sh RECIPE...    recipes: kk-dev kokkos-host kk-host kokkos-cuda kk-cuda kokkos-serial
#   build-deps.sh prefix RECIPE   print the prefix of RECIPE
# Environment: NACRE_DEPS  folder with the tarballs (default /opt/nacre/src, bound by nacre-env)
#              NACRE_OPT   where prefixes go (default /opt/nacre)
#              NACRE_JOBS  parallel compile jobs (default 2)
#              NACRE_NICE  niceness of the builds (default 19: they yield to interactive work)
#              NACRE_CUDA_ARCH  Kokkos arch option for CUDA (default HOPPER90)
#              NACRE_CUDA_HOME  CUDA toolkit (default /usr/local/cuda)
# Kokkos Kernels is installed header-only (no explicit instantiation): nacre calls a handful of
# kernels, and the minimal ETI set costs 17-44 CPU-minutes per build (see shared/deps/README.md).
set -euo pipefail

DEPS="${NACRE_DEPS:-/opt/nacre/src}"
OPT="${NACRE_OPT:-/opt/nacre}"
JOBS="${NACRE_JOBS:-2}"
NICE="${NACRE_NICE:-19}"
ARCH="${NACRE_CUDA_ARCH:-HOPPER90}"
CUDA_HOME="${NACRE_CUDA_HOME:-/usr/local/cuda}"
arch_tag=$(echo "$ARCH" | tr 'A-Z' 'a-z')

K46=kokkos-4.6.01
KK47=kokkos-kernels-4.7.00
KKDEV=kokkos-kernels-4.7.99-2fc2af19

say() { printf '[build-deps] %s\n' "$*" >&2; }

# Kokkos Kernels components nacre uses: graph (distance-1 colouring) and batched (small dense
# kernels); sparse stays off (it drags in every solver), so do blas/lapack beyond what batched
# needs. No TPLs: nacre's matrices are tiny and the GPU machines have no BLAS.
KK_OPTS=(-DKokkosKernels_ENABLE_ALL_COMPONENTS=OFF -DKokkosKernels_ENABLE_COMPONENT_BATCHED=ON
  -DKokkosKernels_ENABLE_COMPONENT_BLAS=ON -DKokkosKernels_ENABLE_COMPONENT_GRAPH=ON
  -DKokkosKernels_ENABLE_TESTS=OFF -DKokkosKernels_ENABLE_EXAMPLES=OFF
  -DKokkosKernels_ENABLE_PERFTESTS=OFF -DKokkosKernels_ENABLE_TPL_BLAS=OFF
  -DKokkosKernels_ENABLE_TPL_LAPACK=OFF -DKokkosKernels_ADD_DEFAULT_ETI=OFF)
KK_CUDA_OPTS=(-DKokkosKernels_ENABLE_TPL_CUBLAS=OFF -DKokkosKernels_ENABLE_TPL_CUSPARSE=OFF
  -DKokkosKernels_ENABLE_TPL_CUSOLVER=OFF)
COMMON=(-G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_STANDARD=20)
K_OFF=(-DKokkos_ENABLE_TESTS=OFF -DKokkos_ENABLE_EXAMPLES=OFF)

# spec NAME: sets P (the prefix's folder name, every version that matters) and R (the source
# tarball and the CMake arguments, on one line: also the stamp's content) for each recipe
spec() {
  case "$1" in
    kk-dev)        P="${KKDEV}_kokkos-5.2.2-debian"
                   R="$KKDEV -DKokkos_ROOT=/usr ${KK_OPTS[*]}" ;;
    kokkos-host)   P="${K46}_openmp-serial"
                   R="$K46 -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_SERIAL=ON ${K_OFF[*]}" ;;
    kokkos-serial) P="${K46}_serial"
                   R="$K46 -DKokkos_ENABLE_SERIAL=ON ${K_OFF[*]}" ;;
    kk-host)       P="${KK47}_${K46}_openmp-serial"
                   R="$KK47 -DKokkos_ROOT=$(prefix kokkos-host) ${KK_OPTS[*]}" ;;
    kokkos-cuda)   P="${K46}-cuda13_${arch_tag}-openmp-serial"
                   R="$K46 -DCMAKE_CXX_COMPILER=@SRC@/bin/nvcc_wrapper -DKokkos_ENABLE_CUDA=ON -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_SERIAL=ON -DKokkos_ARCH_${ARCH}=ON -DCUDAToolkit_ROOT=$CUDA_HOME ${K_OFF[*]}" ;;
    kk-cuda)       P="${KK47}_${K46}-cuda13_${arch_tag}-openmp-serial"
                   R="$KK47 -DCMAKE_CXX_COMPILER=$(prefix kokkos-cuda)/bin/nvcc_wrapper -DKokkos_ROOT=$(prefix kokkos-cuda) ${KK_OPTS[*]} ${KK_CUDA_OPTS[*]}" ;;
    *) say "unknown recipe '$1'"; exit 2 ;;
  esac
}
prefix() { spec "$1"; echo "$OPT/$P"; }
recipe() { spec "$1"; echo "$R"; }
needs() { case "$1" in kk-host) echo kokkos-host ;; kk-cuda) echo kokkos-cuda ;; esac; }

build_one() {
  local name="$1" pre rec src args stamp t0
  local dep; dep=$(needs "$name"); [ -n "$dep" ] && build_one "$dep"
  pre=$(prefix "$name"); rec=$(recipe "$name"); stamp="$pre/.nacre-ready"
  if [ -f "$stamp" ] && [ "$(head -n1 "$stamp")" = "$rec" ]; then return 0; fi
  mkdir -p "$OPT"
  exec 9>"$OPT/.lock-$name"
  flock 9
  if [ -f "$stamp" ] && [ "$(head -n1 "$stamp")" = "$rec" ]; then exec 9>&-; return 0; fi
  src=${rec%% *}; args=${rec#* }
  [ -f "$DEPS/$src.tar.gz" ] || { say "error: $DEPS/$src.tar.gz not found (set NACRE_DEPS)"; exit 1; }
  case "$name" in kokkos-cuda|kk-cuda)
    [ -x "$CUDA_HOME/bin/nvcc" ] || { say "error: no nvcc in $CUDA_HOME/bin (set NACRE_CUDA_HOME)"; exit 1; }
    export PATH="$CUDA_HOME/bin:$PATH" ;;
  esac
  local work="$OPT/.build-$name"
  rm -rf "$work" "$pre"; mkdir -p "$work"
  say "$name: building $src into $pre"
  t0=$(date +%s)
  tar xzf "$DEPS/$src.tar.gz" -C "$work"
  if [ "$name" = kokkos-cuda ]; then
    # patch(1) where present, else git apply (the dev root has git, not patch)
    if command -v patch >/dev/null; then (cd "$work/$src" && patch -s -p1 < "$DEPS/kokkos-cuda13.patch")
    else (cd "$work/$src" && git apply -p1 "$DEPS/kokkos-cuda13.patch"); fi
  fi
  args=${args//@SRC@/$work/$src}
  # shellcheck disable=SC2086  # args is a list of -D options without spaces inside
  nice -n "$NICE" cmake -S "$work/$src" -B "$work/build" "${COMMON[@]}" -DCMAKE_INSTALL_PREFIX="$pre" $args \
    > "$work/configure.log" 2>&1 || { tail -n 30 "$work/configure.log" >&2; say "$name: configure failed"; exit 1; }
  nice -n "$NICE" cmake --build "$work/build" -j "$JOBS" > "$work/build.log" 2>&1 \
    || { tail -n 40 "$work/build.log" >&2; say "$name: build failed"; exit 1; }
  cmake --install "$work/build" > "$work/install.log" 2>&1 \
    || { tail -n 20 "$work/install.log" >&2; say "$name: install failed"; exit 1; }
  printf '%s\nbuilt %s in %d s (-j%s)\n' "$rec" "$(date -u +%FT%TZ)" $(( $(date +%s) - t0 )) "$JOBS" > "$stamp"
  rm -rf "$work"
  say "$name: done in $(( $(date +%s) - t0 )) s"
  exec 9>&-
}

if [ "${1:-}" = prefix ]; then prefix "$2"; exit 0; fi
[ $# -gt 0 ] || { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
for r in "$@"; do build_one "$r"; done
