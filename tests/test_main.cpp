// SPDX-License-Identifier: BSD-3-Clause
// Catch2 main for every nacre test: Kokkos is initialised once per test process, and any
// --kokkos-* arguments (e.g. --kokkos-num-threads=2) reach Kokkos, not Catch2. Built with
// NACRE_TEST_MPI (tests/par: mpiexec starts one per rank) MPI comes first; every rank runs every
// case (they call collectives in the same order) and a failure on any rank fails the run.
#ifdef NACRE_TEST_MPI
#include <nacre/par/comm.hpp>
#endif
#include <catch2/catch_session.hpp>
#include <Kokkos_Core.hpp>

#include <string_view>
#include <vector>

int main(int argc, char* argv[]) {
#ifdef NACRE_TEST_MPI
  nacre::par::Environment mpi(argc, argv);
#endif
  std::vector<char*> kokkos_args{argv[0]}, catch_args{argv[0]};
  for (int i = 1; i < argc; ++i)
    (std::string_view(argv[i]).starts_with("--kokkos-") ? kokkos_args : catch_args).push_back(argv[i]);
  // argv[argc] == nullptr, as Kokkos (and C convention) expect of an argument vector
  kokkos_args.push_back(nullptr);
  catch_args.push_back(nullptr);
  int kargc = static_cast<int>(kokkos_args.size()) - 1;
  Kokkos::ScopeGuard guard(kargc, kokkos_args.data());
  return Catch::Session().run(static_cast<int>(catch_args.size()) - 1, catch_args.data());
}
