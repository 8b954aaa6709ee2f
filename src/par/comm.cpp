// SPDX-License-Identifier: BSD-3-Clause
// The one file that includes mpi.h (include/nacre/par/comm.hpp says why). Built without MPI
// (NACRE_HAVE_MPI undefined) every call is that of a one-process world.
#include <nacre/par/comm.hpp>

#include <sched.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <cstddef>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#ifdef NACRE_HAVE_MPI
#include <mpi.h>
#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>  // Open MPI's extensions: the GPU-awareness queries
#endif
#endif

namespace nacre::par {

namespace {
#ifdef NACRE_HAVE_MPI
bool mpi_up() {
  int init = 0, fin = 0;
  MPI_Initialized(&init);
  MPI_Finalized(&fin);
  return init && !fin;
}
void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS)
    throw std::runtime_error(std::string("nacre::par: ") + what + " failed (MPI error " + std::to_string(rc) + ")");
}
#endif
}  // namespace

bool has_mpi() {
#ifdef NACRE_HAVE_MPI
  return true;
#else
  return false;
#endif
}

std::string mpi_library() {
#ifdef NACRE_HAVE_MPI
  char text[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  int length = 0;
  if (MPI_Get_library_version(text, &length) != MPI_SUCCESS) return "(version unknown)";
  std::string v(text, static_cast<std::size_t>(length));
  v = v.substr(0, v.find_first_of("\n,"));
  while (!v.empty() && (v.back() == ' ' || v.back() == '\0')) v.pop_back();
  return v;
#else
  return "";
#endif
}

namespace {
/// "0-3,6" of a CPU set
std::string cpu_list(const cpu_set_t& set) {
  std::string out;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (!CPU_ISSET(c, &set)) continue;
    int e = c;
    while (e + 1 < CPU_SETSIZE && CPU_ISSET(e + 1, &set)) ++e;
    out += (out.empty() ? "" : ",") + std::to_string(c) + (e > c ? "-" + std::to_string(e) : std::string());
    c = e;
  }
  return out;
}

}  // namespace

std::vector<int> node_cpu_ids() {
  std::vector<int> ids;
  std::ifstream in("/sys/fs/cgroup/cpuset.cpus.effective");
  std::string text;
  if (in && std::getline(in, text) && !text.empty()) {
    std::stringstream ss(text);
    std::string part;
    while (std::getline(ss, part, ',')) {
      const auto dash = part.find('-');
      const int a = std::atoi(part.c_str()), b = dash == std::string::npos ? a : std::atoi(part.c_str() + dash + 1);
      for (int c = a; c <= b; ++c) ids.push_back(c);
    }
  }
  if (ids.empty())
    for (long c = 0; c < sysconf(_SC_NPROCESSORS_ONLN); ++c) ids.push_back(static_cast<int>(c));
  return ids;
}

namespace {
Placement& last_placement() {
  static Placement p;
  return p;
}
}  // namespace

const Placement& placement() { return last_placement(); }

Placement check_placement([[maybe_unused]] const Comm& comm, [[maybe_unused]] bool fix) {
  Placement& p = last_placement();
  p = Placement{};
  cpu_set_t mine;
  CPU_ZERO(&mine);
  if (sched_getaffinity(0, sizeof mine, &mine) != 0) return p;
  p.cpus = p.cpus_at_start = cpu_list(mine);
  p.rank_cpus = CPU_COUNT(&mine);
  const std::vector<int> node = node_cpu_ids();
  p.node_cpus = static_cast<int>(node.size());
#ifdef NACRE_HAVE_MPI
  if (comm.size() < 2) return p;
  MPI_Comm local = MPI_COMM_NULL;
  check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, comm.rank(), MPI_INFO_NULL, &local),
        "MPI_Comm_split_type");
  int lr = 0, ln = 1;
  MPI_Comm_rank(local, &lr);
  MPI_Comm_size(local, &ln);
  p.node_ranks = ln;
  // every rank's CPU set on the node, as bytes
  std::vector<unsigned char> all(sizeof(cpu_set_t) * static_cast<std::size_t>(ln));
  check(MPI_Allgather(&mine, sizeof(cpu_set_t), MPI_BYTE, all.data(), sizeof(cpu_set_t), MPI_BYTE, local),
        "MPI_Allgather");
  for (int a = 0; a < ln && !p.shared; ++a)
    for (int b = a + 1; b < ln && !p.shared; ++b) {
      cpu_set_t both;
      const auto* sa = reinterpret_cast<const cpu_set_t*>(all.data() + sizeof(cpu_set_t) * static_cast<std::size_t>(a));
      const auto* sb = reinterpret_cast<const cpu_set_t*>(all.data() + sizeof(cpu_set_t) * static_cast<std::size_t>(b));
      CPU_AND(&both, sa, sb);
      p.shared = CPU_COUNT(&both) > 0;
    }
  int ok = 1;
  if (p.shared && fix && ln <= p.node_cpus) {  // rank lr of ln: CPUs [lr n / ln, (lr + 1) n / ln)
    cpu_set_t slice;
    CPU_ZERO(&slice);
    const std::size_t n = node.size(), lo = n * static_cast<std::size_t>(lr) / static_cast<std::size_t>(ln),
                      hi = n * static_cast<std::size_t>(lr + 1) / static_cast<std::size_t>(ln);
    for (std::size_t k = lo; k < hi; ++k) CPU_SET(node[k], &slice);
    ok = sched_setaffinity(0, sizeof slice, &slice) == 0 ? 1 : 0;
  } else {
    ok = 0;
  }
  int all_ok = 0;
  check(MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, local), "MPI_Allreduce");
  if (ok && !all_ok) sched_setaffinity(0, sizeof mine, &mine);  // all or none: back to the start
  p.rebound = all_ok == 1;
  if (sched_getaffinity(0, sizeof mine, &mine) == 0) p.cpus = cpu_list(mine), p.rank_cpus = CPU_COUNT(&mine);
  MPI_Comm_free(&local);
#endif
  return p;
}

bool mpi_device_aware() {
#if defined(NACRE_HAVE_MPI) && defined(OMPI_HAVE_MPI_EXT_CUDA)
  if (MPIX_Query_cuda_support() == 1) return true;
#endif
#if defined(NACRE_HAVE_MPI) && defined(OMPI_HAVE_MPI_EXT_ROCM)
  if (MPIX_Query_rocm_support() == 1) return true;
#endif
  return false;
}

Environment::Environment([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef NACRE_HAVE_MPI
  int init = 0;
  MPI_Initialized(&init);
  if (!init) {
    int provided = 0;
    check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    owns_ = true;
  }
#endif
}

Environment::~Environment() {
#ifdef NACRE_HAVE_MPI
  if (owns_ && mpi_up()) MPI_Finalize();
#endif
}

Comm Comm::world() {
  Comm c;
#ifdef NACRE_HAVE_MPI
  if (mpi_up()) {
    MPI_Comm_rank(MPI_COMM_WORLD, &c.rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &c.size_);
  }
#endif
  return c;
}

double Comm::max(double x) const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) check(MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce(max)");
#endif
  return x;
}

void Comm::max_loc([[maybe_unused]] double& x, [[maybe_unused]] int& loc) const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) {
    struct {
      double val;
      int loc;
    } v{x, loc};
    check(MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE_INT, MPI_MAXLOC, MPI_COMM_WORLD), "MPI_Allreduce(maxloc)");
    x = v.val, loc = v.loc;
  }
#endif
}

long long Comm::sum(long long x) const {
  sum(&x, 1);
  return x;
}

void Comm::sum([[maybe_unused]] long long* x, [[maybe_unused]] int n) const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) check(MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce(sum)");
#endif
}

void Comm::sum_exact([[maybe_unused]] double* x, [[maybe_unused]] int n) const {
#ifdef NACRE_HAVE_MPI
  // exact in any order (the caller's promise), so MPI's reduction tree cannot change the bits
  if (size_ > 1) check(MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce(sum)");
#endif
}

void Comm::exchange(const std::vector<int>& ranks, [[maybe_unused]] const double* send,
                    const std::vector<int>& send_off, [[maybe_unused]] double* recv, const std::vector<int>& recv_off,
                    [[maybe_unused]] int words) const {
  if (send_off.size() != ranks.size() + 1 || recv_off.size() != ranks.size() + 1)
    throw std::logic_error("nacre::par::Comm::exchange: one send and one receive range per neighbour");
#ifdef NACRE_HAVE_MPI
  if (ranks.empty()) return;
  std::vector<MPI_Request> req(2 * ranks.size());
  constexpr int kTag = 17;
  const auto count = [&](const std::vector<int>& off, std::size_t k) { return (off[k + 1] - off[k]) * words; };
  for (std::size_t k = 0; k < ranks.size(); ++k)
    check(MPI_Irecv(recv + static_cast<std::ptrdiff_t>(recv_off[k]) * words, count(recv_off, k), MPI_DOUBLE, ranks[k],
                    kTag, MPI_COMM_WORLD, &req[k]),
          "MPI_Irecv");
  for (std::size_t k = 0; k < ranks.size(); ++k)
    check(MPI_Isend(send + static_cast<std::ptrdiff_t>(send_off[k]) * words, count(send_off, k), MPI_DOUBLE, ranks[k],
                    kTag, MPI_COMM_WORLD, &req[ranks.size() + k]),
          "MPI_Isend");
  check(MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
#else
  if (!ranks.empty()) throw std::logic_error("nacre::par::Comm::exchange: neighbours in a one-process build");
#endif
}

namespace {
template <class T>
std::vector<std::vector<T>> gather_impl([[maybe_unused]] const Comm& c, const std::vector<T>& mine) {
  std::vector<std::vector<T>> all;
#ifdef NACRE_HAVE_MPI
  if (c.size() > 1) {
    const MPI_Datatype type = std::is_same_v<T, double> ? MPI_DOUBLE : MPI_LONG_LONG;
    int n = static_cast<int>(mine.size());
    std::vector<int> counts(c.size()), displs(c.size());
    check(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    std::vector<T> flat;
    if (c.rank() == 0) {
      for (int r = 1; r < c.size(); ++r) displs[r] = displs[r - 1] + counts[r - 1];
      flat.resize(static_cast<std::size_t>(displs.back()) + counts.back());
    }
    check(MPI_Gatherv(mine.data(), n, type, flat.data(), counts.data(), displs.data(), type, 0, MPI_COMM_WORLD),
          "MPI_Gatherv");
    if (c.rank() == 0)
      for (int r = 0; r < c.size(); ++r)
        all.emplace_back(flat.begin() + displs[r], flat.begin() + displs[r] + counts[r]);
    return all;
  }
#endif
  all.push_back(mine);
  return all;
}
}  // namespace

std::vector<std::vector<double>> Comm::gather(const std::vector<double>& mine) const {
  return gather_impl(*this, mine);
}
std::vector<std::vector<long long>> Comm::gather(const std::vector<long long>& mine) const {
  return gather_impl(*this, mine);
}
std::vector<std::vector<double>> Comm::gather(std::vector<double>&& mine) const {
  if (size_ > 1) return gather_impl(*this, mine);
  std::vector<std::vector<double>> all;
  all.push_back(std::move(mine));
  return all;
}
std::vector<std::vector<long long>> Comm::gather(std::vector<long long>&& mine) const {
  if (size_ > 1) return gather_impl(*this, mine);
  std::vector<std::vector<long long>> all;
  all.push_back(std::move(mine));
  return all;
}

std::vector<std::vector<double>> Comm::allgather(const std::vector<double>& mine) const {
  std::vector<std::vector<double>> all;
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) {
    int n = static_cast<int>(mine.size());
    std::vector<int> counts(size_), displs(size_);
    check(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    std::vector<double> flat(static_cast<std::size_t>(displs.back()) + counts.back());
    check(MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, flat.data(), counts.data(), displs.data(), MPI_DOUBLE,
                         MPI_COMM_WORLD),
          "MPI_Allgatherv");
    for (int r = 0; r < size_; ++r) all.emplace_back(flat.begin() + displs[r], flat.begin() + displs[r] + counts[r]);
    return all;
  }
#endif
  all.push_back(mine);
  return all;
}

void Comm::scatter(const std::vector<std::vector<double>>& parts, std::vector<double>& mine) const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) {
    std::vector<int> counts(size_), displs(size_);
    std::vector<double> flat;
    if (rank_ == 0) {
      if (parts.size() != static_cast<std::size_t>(size_))
        throw std::logic_error("nacre::par::Comm::scatter: one part per rank");
      for (int r = 0; r < size_; ++r) counts[r] = static_cast<int>(parts[r].size());
      for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + counts[r - 1];
      flat.reserve(static_cast<std::size_t>(displs.back()) + counts.back());
      for (const auto& p : parts) flat.insert(flat.end(), p.begin(), p.end());
    }
    check(MPI_Scatterv(flat.data(), counts.data(), displs.data(), MPI_DOUBLE, mine.data(),
                       static_cast<int>(mine.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD),
          "MPI_Scatterv");
    return;
  }
#endif
  if (parts.size() != 1 || parts[0].size() != mine.size())
    throw std::logic_error("nacre::par::Comm::scatter: one part, of the receiver's length");
  mine = parts[0];
}

void Comm::broadcast([[maybe_unused]] double* x, [[maybe_unused]] int n) const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) check(MPI_Bcast(x, n, MPI_DOUBLE, 0, MPI_COMM_WORLD), "MPI_Bcast");
#endif
}

void Comm::barrier() const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

void Reduce::combine(sum::Scan& s, long long& n) const {
  long long c[4] = {owned, s.pos_inf, s.neg_inf, s.nan};
  comm->sum(c, 4);
  n = c[0], s.pos_inf = c[1], s.neg_inf = c[2], s.nan = c[3];
  s.amax = comm->max(s.amax);
}

void Reduce::combine(sum::Levels& l) const { comm->sum_exact(l.s, sum::kFolds); }

void process_grid(int size, double width, double height, int dims[2]) {
  // the factor pair of `size` closest to the specimen's aspect ratio (MPI_Dims_create's balanced
  // pair is the special case of a square specimen), the larger factor along the longer side
  int best = 1;
  double best_err = 1e300;
  const double aspect = width > 0 && height > 0 ? width / height : 1.0;
  for (int a = 1; a <= size; ++a) {
    if (size % a) continue;
    const double cell = (static_cast<double>(a) * a) / size;  // (a / (size / a)): columns over rows
    const double err = std::abs(std::log(cell / aspect));
    if (err < best_err - 1e-12) best_err = err, best = a;
  }
  dims[0] = best, dims[1] = size / best;
}

void Comm::abort(int code) const {
#ifdef NACRE_HAVE_MPI
  if (size_ > 1 && mpi_up()) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace nacre::par
