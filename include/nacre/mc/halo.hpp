// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The Monte Carlo model of one rank (its owned bricks and their halo) and the exchange of
/// halo poses that keeps a colour-swept cycle on many ranks the cycle of one process.
///
/// Why it gives the same bits: a brick's trial reads only its own pose, its interfaces' cached
/// energies and its neighbours' poses, and draws its uniforms from Philox at (seed, global brick
/// id, cycle). Bricks of one colour share no interface, so a colour's sweep on a rank that holds
/// every neighbour of its owned bricks at their current poses makes the decisions one process
/// makes. After each colour the owners send the poses of that colour's bricks to the ranks that
/// hold them in a halo (all five numbers, the cached rotation included), and the receivers
/// recompute the cached energies of the interfaces those bricks touch (the sweep's own
/// arithmetic, so the bits of the owner's cache). Pack and unpack are Kokkos kernels on the
/// run's execution space; the buffers cross MPI through host copies (no GPU-aware MPI needed).
#include <nacre/mc/kernels.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/par/comm.hpp>
#include <nacre/par/decomposition.hpp>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace nacre::mc {

/// \brief The colouring of a rank's local bricks: owned bricks keep the global colour and tile,
/// halo bricks get colour -1 (not swept here: build_model puts them after the swept bricks).
[[nodiscard]] Colouring local_colouring(const par::Decomposition& d, const Colouring& global);

/// \brief Poses per brick in a halo message (Model::pose's row: x, y, theta, sin, cos - 1).
inline constexpr int kPoseWords = 5;

template <class MemorySpace>
class PoseHalo {
public:
  /// \brief The message lists of rank d.rank's local model m (built from local_specimen,
  /// local_interfaces and local_colouring(d, global)), per colour of the global colouring.
  /// Also sets m.id to the global brick index (the RNG stream of one process).
  template <class ExecutionSpace>
  PoseHalo(const ExecutionSpace& space, const par::Decomposition& d, const Colouring& global, Model<MemorySpace>& m);

  [[nodiscard]] const std::vector<int>& neighbours() const { return neighbours_; }

  /// \brief Per neighbour, the poses of the owned bricks of `colour` (-1: every colour) it holds.
  template <class ExecutionSpace>
  std::vector<std::vector<double>> pack(const ExecutionSpace& space, const Model<MemorySpace>& m, int colour) const;
  /// \brief Sizes of the messages `colour` brings from each neighbour.
  [[nodiscard]] std::vector<std::vector<double>> receive_buffers(int colour) const;
  /// \brief Store received poses; then, if cache is allocated, recompute the cached energies of the
  /// interfaces the received bricks touch.
  template <class ExecutionSpace>
  void unpack(const ExecutionSpace& space, const Model<MemorySpace>& m, int colour,
              const std::vector<std::vector<double>>& recv, Field<double, MemorySpace> cache) const;
  /// \brief One colour's round: the pack kernel into the send buffer, the messages straight from
  /// and into the buffers (host memory, or device memory with comm.device_direct()) or through
  /// their host mirrors, the unpack kernel and the stale energies. No host vector on the way.
  template <class ExecutionSpace>
  void exchange(const ExecutionSpace& space, const par::Comm& comm, const Model<MemorySpace>& m, int colour,
                Field<double, MemorySpace> cache = {}) const;
  /// \brief Every halo row of `rows` (a View with a row per model brick, `words` <= kPoseWords
  /// columns: a vector on the bricks, such as a Newton-CG direction) from its owner; fenced.
  template <class ExecutionSpace, class Rows>
  void exchange_rows(const ExecutionSpace& space, const par::Comm& comm, const Rows& rows, int words) const;
  /// \brief Bytes one full cycle sends (every colour once).
  [[nodiscard]] long long cycle_bytes() const;

  /// (public: nvcc names it in the device lambdas of pack_into / unpack_from)
  struct Lists {
    Kokkos::View<int*, MemorySpace> send, recv, stale;  ///< sweep indices (neighbours concatenated); interfaces
    std::vector<int> send_off, recv_off;                ///< per neighbour: [off[k], off[k+1])
  };

private:
  std::vector<int> neighbours_;
  std::vector<Lists> lists_;  ///< [colour + 1]: 0 = every colour
  /// message buffers, allocated once for the largest list (every colour: list 0) and reused by
  /// every exchange (a device allocation per message would synchronise the device each time)
  using Buffer = Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace>;
  Buffer send_buf_, recv_buf_;
  typename Buffer::host_mirror_type send_host_, recv_host_;
  int n_colours_ = 0;
  [[nodiscard]] const Lists& lists(int colour) const { return lists_.at(static_cast<std::size_t>(colour + 1)); }

  /// one round of l's rows: pack, MPI (direct or staged), unpack; not fenced after the unpack
  template <class ExecutionSpace, class Rows>
  void round(const ExecutionSpace& space, const par::Comm& comm, const Rows& rows, const Lists& l, int words) const;

public:  // (nvcc: the enclosing function of a device lambda must be public)
  /// the first `words` columns of l's send rows into send_buf_, `words` doubles a record (no fence)
  template <class ExecutionSpace, class Rows>
  void pack_into(const ExecutionSpace& space, const Rows& rows, const Lists& l, int words) const;
  /// recv_buf_'s records to l's receive rows (no fence)
  template <class ExecutionSpace, class Rows>
  void unpack_from(const ExecutionSpace& space, const Rows& rows, const Lists& l, int words) const;
  /// the poses' round's end: the stale cached energies recomputed (if cache), fenced
  template <class ExecutionSpace>
  void after_poses(const ExecutionSpace& space, const Model<MemorySpace>& m, const Lists& l,
                   Field<double, MemorySpace> cache) const;
};

template <class MemorySpace>
template <class ExecutionSpace>
PoseHalo<MemorySpace>::PoseHalo(const ExecutionSpace& space, const par::Decomposition& d, const Colouring& global,
                                Model<MemorySpace>& m)
    : neighbours_(d.neighbours), n_colours_(global.n_colours) {
  check_access<ExecutionSpace, MemorySpace>();
  const int nl = static_cast<int>(d.bricks.size());
  std::vector<int> sweep_of(nl);
  for (int k = 0; k < nl; ++k) sweep_of[m.perm[k]] = k;
  // global ids: the RNG streams of one process
  auto hid = Kokkos::create_mirror_view(m.id);
  for (int k = 0; k < nl; ++k) hid(k) = static_cast<std::uint64_t>(d.bricks[m.perm[k]]);
  Kokkos::deep_copy(space, m.id, hid);
  // the model's interfaces of each local brick (ends are sweep indices)
  std::vector<std::vector<int>> touching(nl);
  {
    auto hends = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.ends);
    for (int i = 0; i < m.n_interfaces; ++i)
      touching[m.perm[hends(i, 0)]].push_back(i), touching[m.perm[hends(i, 1)]].push_back(i);
  }
  auto upload = [&](const std::vector<int>& v, const char* label) {
    Kokkos::View<int*, MemorySpace> out(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, std::string(label)),
                                        v.size());
    auto h = Kokkos::create_mirror_view(out);
    for (std::size_t k = 0; k < v.size(); ++k) h(k) = v[k];
    Kokkos::deep_copy(space, out, h);
    return out;
  };
  for (int c = -1; c < global.n_colours; ++c) {
    const auto in_colour = [&](int local) { return c < 0 || global.colour[d.bricks[local]] == c; };
    std::vector<int> send, recv, stale;
    Lists l;
    l.send_off.push_back(0), l.recv_off.push_back(0);
    std::vector<char> seen(m.n_interfaces, 0);
    for (std::size_t q = 0; q < d.neighbours.size(); ++q) {
      for (int b : d.send[q])
        if (in_colour(b)) send.push_back(sweep_of[b]);
      for (int b : d.recv[q])
        if (in_colour(b)) {
          recv.push_back(sweep_of[b]);
          for (int i : touching[b])
            if (!seen[i]) seen[i] = 1, stale.push_back(i);
        }
      l.send_off.push_back(static_cast<int>(send.size())), l.recv_off.push_back(static_cast<int>(recv.size()));
    }
    std::sort(stale.begin(), stale.end());
    l.send = upload(send, "nacre::mc::halo_send"), l.recv = upload(recv, "nacre::mc::halo_recv");
    l.stale = upload(stale, "nacre::mc::halo_stale");
    lists_.push_back(std::move(l));
  }
  const auto rows = [](const Kokkos::View<int*, MemorySpace>& v) { return std::max<std::size_t>(v.extent(0), 1); };
  send_buf_ = Buffer(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::halo_send_buffer"),
                     rows(lists_[0].send), kPoseWords);
  recv_buf_ = Buffer(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::halo_recv_buffer"),
                     rows(lists_[0].recv), kPoseWords);
  send_host_ = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, send_buf_);
  recv_host_ = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, recv_buf_);
  space.fence("nacre::mc::PoseHalo");
}

template <class MemorySpace>
template <class ExecutionSpace, class Rows>
void PoseHalo<MemorySpace>::pack_into(const ExecutionSpace& space, const Rows& rows, const Lists& l, int words) const {
  const int n = static_cast<int>(l.send.extent(0));
  // the records packed at `words` doubles each (the buffer holds kPoseWords a record at most)
  const Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> buf(
      send_buf_.data(), n, words);
  auto idx = l.send;
  Kokkos::parallel_for(
      "nacre::mc::halo_pack", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n), KOKKOS_LAMBDA(const int k) {
        for (int w = 0; w < words; ++w) buf(k, w) = rows(idx(k), w);
      });
}

template <class MemorySpace>
template <class ExecutionSpace, class Rows>
void PoseHalo<MemorySpace>::unpack_from(const ExecutionSpace& space, const Rows& rows, const Lists& l,
                                        int words) const {
  const int n = static_cast<int>(l.recv.extent(0));
  const Kokkos::View<const double**, Kokkos::LayoutRight, MemorySpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> buf(
      recv_buf_.data(), n, words);
  auto idx = l.recv;
  Kokkos::parallel_for(
      "nacre::mc::halo_unpack", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n), KOKKOS_LAMBDA(const int k) {
        for (int w = 0; w < words; ++w) rows(idx(k), w) = buf(k, w);
      });
}

template <class MemorySpace>
template <class ExecutionSpace>
void PoseHalo<MemorySpace>::after_poses(const ExecutionSpace& space, const Model<MemorySpace>& m, const Lists& l,
                                        Field<double, MemorySpace> cache) const {
  if (cache.data())
    interface_energies(space, m, cache, Kokkos::View<const int*, MemorySpace>(l.stale),
                       static_cast<int>(l.stale.extent(0)));
  space.fence("nacre::mc::halo_unpack");  // the buffers are reused by the next exchange
}

template <class MemorySpace>
template <class ExecutionSpace, class Rows>
void PoseHalo<MemorySpace>::round(const ExecutionSpace& space, const par::Comm& comm, const Rows& rows, const Lists& l,
                                  int words) const {
  const int ns = static_cast<int>(l.send.extent(0)), nr = static_cast<int>(l.recv.extent(0));
  const auto cells = [&](int n) { return Kokkos::make_pair(std::size_t{0}, static_cast<std::size_t>(n) * words); };
  const auto flat = [](const auto& b) {  // a buffer as one run of doubles (LayoutRight: contiguous)
    return Kokkos::View<double*, typename std::decay_t<decltype(b)>::memory_space,
                        Kokkos::MemoryTraits<Kokkos::Unmanaged>>(b.data(), b.size());
  };
  pack_into(space, rows, l, words);
  // Host memory goes to MPI as it is; device memory too where the MPI is GPU-aware
  // (comm.device_direct()), else through the host mirrors (send_host_ is send_buf_ on the host).
  constexpr bool host = Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible;
  const bool direct = host || comm.device_direct();
  if (!direct)
    Kokkos::deep_copy(space, Kokkos::subview(flat(send_host_), cells(ns)), Kokkos::subview(flat(send_buf_), cells(ns)));
  space.fence("nacre::mc::halo_pack");  // MPI reads the buffer
  comm.exchange(neighbours_, direct ? send_buf_.data() : send_host_.data(), l.send_off,
                direct ? recv_buf_.data() : recv_host_.data(), l.recv_off, words);
  if (!direct)
    Kokkos::deep_copy(space, Kokkos::subview(flat(recv_buf_), cells(nr)), Kokkos::subview(flat(recv_host_), cells(nr)));
  unpack_from(space, rows, l, words);
}

template <class MemorySpace>
template <class ExecutionSpace>
void PoseHalo<MemorySpace>::exchange(const ExecutionSpace& space, const par::Comm& comm, const Model<MemorySpace>& m,
                                     int colour, Field<double, MemorySpace> cache) const {
  const Lists& l = lists(colour);
  round(space, comm, m.pose, l, kPoseWords);
  after_poses(space, m, l, cache);
}

template <class MemorySpace>
template <class ExecutionSpace, class Rows>
void PoseHalo<MemorySpace>::exchange_rows(const ExecutionSpace& space, const par::Comm& comm, const Rows& rows,
                                          int words) const {
  static_assert(Kokkos::SpaceAccessibility<MemorySpace, typename Rows::memory_space>::accessible,
                "PoseHalo::exchange_rows: the rows must live in the halo's memory space");
  if (words < 1 || words > kPoseWords) throw std::logic_error("nacre::mc::PoseHalo::exchange_rows: 1 to 5 words");
  round(space, comm, rows, lists(-1), words);
  space.fence("nacre::mc::halo_rows");
}

template <class MemorySpace>
template <class ExecutionSpace>
std::vector<std::vector<double>> PoseHalo<MemorySpace>::pack(const ExecutionSpace& space, const Model<MemorySpace>& m,
                                                             int colour) const {
  const Lists& l = lists(colour);
  const int n = static_cast<int>(l.send.extent(0));
  pack_into(space, m.pose, l, kPoseWords);
  const auto h = Kokkos::subview(send_host_, Kokkos::make_pair(0, n), Kokkos::ALL);
  Kokkos::deep_copy(space, h, Kokkos::subview(send_buf_, Kokkos::make_pair(0, n), Kokkos::ALL));
  space.fence("nacre::mc::halo_pack");
  std::vector<std::vector<double>> out(neighbours_.size());
  for (std::size_t q = 0; q < neighbours_.size(); ++q)
    out[q].assign(h.data() + static_cast<std::size_t>(l.send_off[q]) * kPoseWords,
                  h.data() + static_cast<std::size_t>(l.send_off[q + 1]) * kPoseWords);
  return out;
}

template <class MemorySpace>
std::vector<std::vector<double>> PoseHalo<MemorySpace>::receive_buffers(int colour) const {
  const Lists& l = lists(colour);
  std::vector<std::vector<double>> out(neighbours_.size());
  for (std::size_t q = 0; q < neighbours_.size(); ++q)
    out[q].resize(static_cast<std::size_t>(l.recv_off[q + 1] - l.recv_off[q]) * kPoseWords);
  return out;
}

template <class MemorySpace>
template <class ExecutionSpace>
void PoseHalo<MemorySpace>::unpack(const ExecutionSpace& space, const Model<MemorySpace>& m, int colour,
                                   const std::vector<std::vector<double>>& recv,
                                   Field<double, MemorySpace> cache) const {
  const Lists& l = lists(colour);
  const int n = static_cast<int>(l.recv.extent(0));
  const auto h = Kokkos::subview(recv_host_, Kokkos::make_pair(0, n), Kokkos::ALL);
  for (std::size_t q = 0; q < neighbours_.size(); ++q)
    std::copy(recv[q].begin(), recv[q].end(), h.data() + static_cast<std::size_t>(l.recv_off[q]) * kPoseWords);
  Kokkos::deep_copy(space, Kokkos::subview(recv_buf_, Kokkos::make_pair(0, n), Kokkos::ALL), h);
  unpack_from(space, m.pose, l, kPoseWords);
  after_poses(space, m, l, cache);
}

/// \brief A Monte Carlo solver's share of a specimen spread over the ranks of `comm` (mc::Solver
/// with a communicator of more than one rank): what it needs beside its local model.
template <class MemorySpace>
struct Distribution {
  par::Comm comm;
  par::Decomposition d;
  std::unique_ptr<PoseHalo<MemorySpace>> halo;
  Kokkos::View<std::uint8_t*, MemorySpace> iface_owned;  ///< per model interface: 1 where this rank owns it
  long long n_free = 0;                                  ///< free bricks of the whole specimen
  std::size_t n_interfaces = 0;                          ///< interfaces of the whole specimen
  int n_colours = 0;                                     ///< colours of the whole specimen's colouring
  /// per model brick: 1 where its pose is an unknown of the whole specimen (owned or halo free
  /// bricks: hessian.hpp's FreeMask)
  Kokkos::View<std::uint8_t*, MemorySpace> brick_free;
  /// per model brick: its index among the free bricks of one process (that process's sweep
  /// order), -1 for a driven brick: the unknowns' numbering of the Newton preconditioner's factor
  std::vector<int> global_free;

  /// \brief deterministic_sum's combine for a sum of which this rank holds `owned` terms.
  [[nodiscard]] par::Reduce reduce(long long owned) const { return par::Reduce{&comm, owned}; }
  /// \brief Every halo pose from its owner (after any move of all bricks: load, predictor, polish, restore).
  template <class ExecutionSpace>
  void refresh(const ExecutionSpace& space, const Model<MemorySpace>& m) const {
    halo->exchange(space, comm, m, -1);
  }
};

/// \brief What a solver that may be spread over ranks (d) or not (null: one process) sums with:
/// the combine for `owned` terms of this rank; the owned-interface mask (empty: every interface
/// is this process's); how many of m's interfaces this rank sums.
template <class MemorySpace>
par::Reduce reduce_over(const Distribution<MemorySpace>* d, long long owned) {
  static const par::Comm one{};  // one process: combines nothing
  return d ? d->reduce(owned) : par::Reduce{&one, owned};
}
template <class MemorySpace>
Kokkos::View<const std::uint8_t*, MemorySpace> owned_mask(const Distribution<MemorySpace>* d) {
  return d ? Kokkos::View<const std::uint8_t*, MemorySpace>(d->iface_owned)
           : Kokkos::View<const std::uint8_t*, MemorySpace>();
}
template <class MemorySpace>
long long owned_interfaces(const Distribution<MemorySpace>* d, long long all) {
  return d ? d->d.owned_interfaces : all;
}
template <class MemorySpace>
long long owned_interfaces(const Distribution<MemorySpace>* d, const Model<MemorySpace>& m) {
  return owned_interfaces(d, static_cast<long long>(m.n_interfaces));
}
/// \brief The largest x over the ranks (x itself in one process): a residual.
template <class MemorySpace>
double max_over(const Distribution<MemorySpace>* d, double x) {
  return d ? d->comm.max(x) : x;
}

/// \brief The distribution of rank comm.rank()'s part of a specimen whose whole colouring is
/// `global`: its decomposition, and the local model built from it into m.
template <class ExecutionSpace, class MemorySpace>
std::unique_ptr<Distribution<MemorySpace>> distribute(const ExecutionSpace& space, const par::Comm& comm,
                                                      const geometry::Specimen& s, const geometry::Interfaces& f,
                                                      const geometry::Adjacency& adj, const Colouring& global,
                                                      const deck::Mortar& mortar, int quadrature_points,
                                                      Model<MemorySpace>& m) {
  auto dist = std::make_unique<Distribution<MemorySpace>>();
  dist->comm = comm;
  dist->d = par::decompose(comm.rank(), comm.size(), s, f, adj, global.tile);
  const auto ls = par::local_specimen(dist->d, s);
  const auto lf = par::local_interfaces(dist->d, f);
  m = build_model(space, ls, lf, geometry::build_adjacency(ls.size(), lf), local_colouring(dist->d, global), mortar,
                  quadrature_points);
  dist->halo = std::make_unique<PoseHalo<MemorySpace>>(space, dist->d, global, m);
  dist->iface_owned = Kokkos::View<std::uint8_t*, MemorySpace>(
      Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::iface_owned"), std::max(m.n_interfaces, 1));
  auto h = Kokkos::create_mirror_view(dist->iface_owned);
  for (int i = 0; i < m.n_interfaces; ++i) h(i) = dist->d.iface_owned[m.iface_perm[i]];
  Kokkos::deep_copy(space, dist->iface_owned, h);
  for (int c : global.colour) dist->n_free += c >= 0;
  {
    std::vector<int> free_index(global.colour.size(), -1);  // original brick -> one-process free index
    const auto order = sweep_order(global);
    for (std::size_t k = 0; k < order.size(); ++k)
      if (global.colour[order[k]] >= 0) free_index[order[k]] = static_cast<int>(k);
    dist->global_free.resize(static_cast<std::size_t>(m.n_bricks));
    dist->brick_free = Kokkos::View<std::uint8_t*, MemorySpace>(
        Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::brick_free"), m.n_bricks);
    auto hf = Kokkos::create_mirror_view(dist->brick_free);
    for (int k = 0; k < m.n_bricks; ++k) {
      dist->global_free[k] = free_index[dist->d.bricks[m.perm[k]]];
      hf(k) = dist->global_free[k] >= 0;
    }
    Kokkos::deep_copy(space, dist->brick_free, hf);
  }
  dist->n_interfaces = f.size();
  dist->n_colours = global.n_colours;
  space.fence("nacre::mc::distribute");
  return dist;
}

template <class MemorySpace>
long long PoseHalo<MemorySpace>::cycle_bytes() const {
  long long n = 0;
  for (int c = 0; c < n_colours_; ++c) n += static_cast<long long>(lists(c).send.extent(0));
  return n * kPoseWords * static_cast<long long>(sizeof(double));
}

}  // namespace nacre::mc
