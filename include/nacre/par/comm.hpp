// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The processes a run is spread over: MPI when nacre is built with NACRE_ENABLE_MPI, one
/// process otherwise. Rank and size, the reductions whose results are the bits of the
/// one-process computation, and the exchange of halo buffers with neighbour ranks.
///
/// Why mpi.h stays out of this header: only src/par/comm.cpp includes it, so the solvers, the
/// tests and a build without MPI compile the same code (a Comm of one process then reduces to
/// nothing and exchanges nothing).
#include <nacre/core/deterministic_sum.hpp>

#include <string>
#include <vector>

namespace nacre::par {

/// \brief Whether this build has MPI.
[[nodiscard]] bool has_mpi();

/// \brief Whether this MPI accepts device (GPU) memory in its calls: Open MPI's run-time query
/// (MPIX_Query_cuda_support / MPIX_Query_rocm_support) where its extensions say it has one; false
/// where the MPI cannot tell (then device data is staged through host memory unless asked).
[[nodiscard]] bool mpi_device_aware();

/// \brief The MPI library's name and version ("Open MPI v5.0.7", the first line of
/// MPI_Get_library_version, callable before MPI_Init); "" in a build without MPI.
[[nodiscard]] std::string mpi_library();

/// \brief MPI for the life of the object (MPI_Init_thread with funneled threads when built with
/// MPI and not yet initialised; MPI_Finalize at the end if this object initialised it).
class Environment {
public:
  Environment(int& argc, char**& argv);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

private:
  bool owns_ = false;
};

/// \brief All processes of the run (MPI_COMM_WORLD), or this one alone.
class Comm {
public:
  /// \brief One process (rank 0 of 1): what a solver that is not distributed combines with.
  Comm() = default;
  /// \brief The world (one process in a build without MPI or before MPI is initialised).
  static Comm world();

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }

  [[nodiscard]] double max(double x) const;
  /// \brief The largest x over the ranks and its loc; ties go to the smallest loc (MPI_MAXLOC),
  /// as an arg-max over one process's indices in increasing order.
  void max_loc(double& x, int& loc) const;
  [[nodiscard]] long long sum(long long x) const;
  /// \brief Element-wise sum over ranks of n long longs, in place.
  void sum(long long* x, int n) const;
  /// \brief Element-wise sum over ranks of n doubles that add exactly in any order (the level sums
  /// of deterministic_sum), in place: every rank gets the same bits.
  void sum_exact(double* x, int n) const;

  /// \brief One round of point-to-point messages from two contiguous buffers: neighbour k
  /// (ranks[k]) gets records [send_off[k], send_off[k+1]) of `words` doubles each, and its
  /// message, as many records as it sends, lands at recv_off[k]. Every pair of ranks that
  /// exchanges lists the other (the halo relation is symmetric). The pointers may be device
  /// memory where device_direct() (a GPU-aware MPI).
  void exchange(const std::vector<int>& ranks, const double* send, const std::vector<int>& send_off, double* recv,
                const std::vector<int>& recv_off, int words) const;

  /// \brief Device buffers go to MPI as they are (a GPU-aware MPI) instead of through a host
  /// copy: `nacre --gpu-aware-mpi on|off|auto` (auto: mpi_device_aware()). Host data never needs
  /// staging, whatever this says.
  [[nodiscard]] bool device_direct() const { return device_direct_; }
  void set_device_direct(bool on) { device_direct_ = on; }
  /// \brief Rank 0 receives every rank's `mine` in rank order (others get an empty vector).
  [[nodiscard]] std::vector<std::vector<double>> gather(const std::vector<double>& mine) const;
  [[nodiscard]] std::vector<std::vector<long long>> gather(const std::vector<long long>& mine) const;
  /// \brief The same, `mine` moved into the result on one process (no copy).
  [[nodiscard]] std::vector<std::vector<double>> gather(std::vector<double>&& mine) const;
  [[nodiscard]] std::vector<std::vector<long long>> gather(std::vector<long long>&& mine) const;
  /// \brief The reverse of gather: rank 0's parts[r] lands in rank r's `mine`, which each rank
  /// sizes beforehand to its part's length (parts is read on rank 0 only).
  void scatter(const std::vector<std::vector<double>>& parts, std::vector<double>& mine) const;
  /// \brief Rank 0's n doubles at x to every rank.
  void broadcast(double* x, int n) const;
  /// \brief Every rank receives every rank's `mine` in rank order.
  [[nodiscard]] std::vector<std::vector<double>> allgather(const std::vector<double>& mine) const;
  void barrier() const;
  /// \brief End every rank of the run with exit code `code` (MPI_Abort): what a rank that failed
  /// alone does, since the others would wait for it in the next collective. One process: std::exit.
  [[noreturn]] void abort(int code) const;

private:
  int rank_ = 0, size_ = 1;
  bool device_direct_ = false;
};

/// \brief The CPUs the node offers this process: its cgroup's effective cpuset, else every online
/// CPU (not the affinity mask: an OpenMP runtime with OMP_PLACES or OMP_PROC_BIND set binds the
/// initial thread to the first place as the program starts).
[[nodiscard]] std::vector<int> node_cpu_ids();

/// \brief Where the ranks of a run sit on their node's CPUs (par/comm.cpp check_placement).
struct Placement {
  int node_ranks = 1;     ///< ranks on this rank's node
  int node_cpus = 0;      ///< CPUs the node offers (its cgroup's cpuset, else the online CPUs)
  bool shared = false;    ///< at start, ranks of one node could run on the same CPU
  bool rebound = false;   ///< nacre gave each rank of the node CPUs of its own
  int rank_cpus = 0;      ///< CPUs this rank may run on now
  std::string cpus;       ///< this rank's CPUs now ("0-1,4")
  std::string cpus_at_start;  ///< and at start
};

/// \brief Checks, before Kokkos starts its threads, whether ranks of one node share CPUs (an
/// unbound launch: `mpirun --oversubscribe`, many containers and schedulers; with OMP_PROC_BIND
/// set, every unbound rank's OpenMP binds its first thread to the first CPU, so all ranks share
/// one core and MPI's busy polling starves them). Where they share and `fix`, each rank of the
/// node is bound to its own contiguous slice of the node's CPUs (what `--bind-to core` does), when
/// there are at least as many CPUs as ranks. Collective over `comm`; one process: nothing shared.
[[nodiscard]] Placement check_placement(const Comm& comm, bool fix);

/// \brief The result of the last check_placement (a one-process default before any): what
/// summary.json records as "placement".
[[nodiscard]] const Placement& placement();

/// \brief More threads than CPUs: the node's ranks' threads over the node's CPUs. (Not a rank's
/// threads over its own CPU set: with OMP_PROC_BIND set, OpenMP narrows the first thread's set to
/// one CPU at start, and places its other threads beside it.)
[[nodiscard]] inline bool oversubscribed(int threads_per_rank) {
  const Placement& p = placement();
  return p.node_cpus > 0 && p.node_ranks * threads_per_rank > p.node_cpus;
}

/// \brief The placement as summary.json members of j["placement"] (template: no JSON library here).
template <class Json>
void put_placement_json(Json& j, int threads_per_rank) {
  const Placement& p = placement();
  auto& o = j["placement"];
  o["node_ranks"] = p.node_ranks;
  o["node_cpus"] = p.node_cpus;
  o["threads_per_rank"] = threads_per_rank;
  o["rank_cpus"] = p.rank_cpus;
  o["oversubscribed"] = oversubscribed(threads_per_rank);
  o["shared_at_start"] = p.shared;
  o["rebound"] = p.rebound;
  o["cpus_at_start"] = p.cpus_at_start;
  o["cpus"] = p.cpus;
}

/// \brief deterministic_sum's combine for a sum shared by the ranks of `comm`: each rank sums its
/// own terms (the others' indices give 0) and `owned` is how many it owns, so the fold's grids
/// are those of the one-process sum over all owned terms and the result has its bits.
struct Reduce {
  const Comm* comm;
  long long owned;
  void combine(sum::Scan& s, long long& n) const;
  void combine(sum::Levels& l) const;
};

/// \brief Process grid for `size` ranks over a width x height specimen (MPI_Dims_create's
/// factors, the larger along the longer side): dims[0] columns along x, dims[1] rows along y.
void process_grid(int size, double width, double height, int dims[2]);

}  // namespace nacre::par
