// Catch2 main of the decomposition tests: MPI first (when built with it; mpiexec starts one of
// these per rank), then Kokkos, as in tests/test_main.cpp. Every rank runs every case (they
// call collectives in the same order); a failure on any rank fails the run.
#include <nacre/par/comm.hpp>

#include <catch2/catch_session.hpp>
#include <Kokkos_Core.hpp>

#include <string_view>
#include <vector>

int main(int argc, char* argv[]) {
  nacre::par::Environment mpi(argc, argv);
  std::vector<char*> kokkos_args{argv[0]}, catch_args{argv[0]};
  for (int i = 1; i < argc; ++i)
    (std::string_view(argv[i]).starts_with("--kokkos-") ? kokkos_args : catch_args).push_back(argv[i]);
  kokkos_args.push_back(nullptr);
  catch_args.push_back(nullptr);
  int kargc = static_cast<int>(kokkos_args.size()) - 1;
  Kokkos::ScopeGuard guard(kargc, kokkos_args.data());
  return Catch::Session().run(static_cast<int>(catch_args.size()) - 1, catch_args.data());
}
