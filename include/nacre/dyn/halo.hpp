// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The exchange that keeps a rank's halo elements at their owners' displacements: what
/// makes a dynamic run on many ranks the run of one process, bit for bit.
///
/// Why one array and one exchange per interface-force pass: elements share no nodes (model.hpp),
/// every per-element operation reads only its own rows, and the only coupling is the interface
/// force, which reads the displacement u of the elements at its two ends. A rank holds its owned
/// elements, the elements of the bricks that share an interface with them (the halo,
/// par::Decomposition's one-brick halo) and every interface with an owned end, in the whole
/// model's order. So if the halo rows of u are the owners' before each force pass, every owned
/// interface force row, every owned element's gather (in the one-process order) and so every
/// owned element's step are the one-process arithmetic. The halo's own v and a go stale (their
/// gathers miss the interfaces of the neighbour's side) and are never read for an owned row.
/// Velocity Verlet exchanges once a step; BIE once per interface evaluation (its iterations).
/// Pack and unpack are Kokkos kernels on the run's execution space; device buffers go to MPI
/// directly where it is GPU-aware (Comm::device_direct), else through host mirrors.
#include <nacre/dyn/model.hpp>
#include <nacre/par/comm.hpp>
#include <nacre/par/decomposition.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace nacre::dyn {

template <class MemorySpace>
class ElementHalo {
public:
  using Rows = typename Model<MemorySpace>::Dof;                            ///< [element][dof]: the displacement u
  using Buffer = Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace>;  ///< [record][dof]: contiguous messages

  /// \brief The lists of rank d.rank's model (built by build_model with &d, its host map `map`):
  /// per neighbour, the owned elements it holds in its halo and the halo elements it owns, both in
  /// the specimen's brick order and each brick's element order (so the two sides of a message list
  /// the same elements). `u`: the rows every exchange refreshes.
  ElementHalo(const par::Comm& comm, const par::Decomposition& d, const HostMap& map, const Rows& u)
      : comm_(comm), neighbours_(d.neighbours), u_(u), words_(static_cast<int>(u.extent(1))) {
    std::vector<int> local(static_cast<std::size_t>(map.n_elem), -1);
    for (std::size_t e = 0; e < map.elem_global.size(); ++e) local[map.elem_global[e]] = static_cast<int>(e);
    auto elements = [&](const std::vector<std::vector<int>>& bricks, std::vector<int>& off) {
      std::vector<int> out;
      off.assign(1, 0);
      for (const auto& list : bricks) {
        for (int lb : list) {
          const int b = d.bricks[lb];
          for (int g = map.brick_elem[b]; g < map.brick_elem[b + 1]; ++g) {
            if (local[g] < 0)
              throw std::logic_error("dyn::ElementHalo: element " + std::to_string(g) + " of a halo brick is not held");
            out.push_back(local[g]);
          }
        }
        off.push_back(static_cast<int>(out.size()));
      }
      return out;
    };
    const auto send = elements(d.send, send_off_), recv = elements(d.recv, recv_off_);
    auto upload = [](const char* label, const std::vector<int>& x) {
      Kokkos::View<int*, MemorySpace> v(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string("nacre::dyn::") + label), x.size());
      auto h = Kokkos::create_mirror_view(v);
      for (std::size_t k = 0; k < x.size(); ++k) h(k) = x[k];
      Kokkos::deep_copy(v, h);
      return v;
    };
    send_ = upload("halo_send", send), recv_ = upload("halo_recv", recv);
    send_buf_ = Buffer(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::halo_send_buf"),
                       std::max<std::size_t>(send.size(), 1), words_);
    recv_buf_ = Buffer(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::halo_recv_buf"),
                       std::max<std::size_t>(recv.size(), 1), words_);
    send_host_ = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, send_buf_);
    recv_host_ = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, recv_buf_);
  }

  /// \brief Every halo row of u from its owner, on `space`; fenced (the buffers are reused).
  template <class ExecutionSpace>
  void exchange(const ExecutionSpace& space) const {
    static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, MemorySpace>::accessible,
                  "dyn::ElementHalo: the run's execution space must reach the model's memory");
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::halo_exchange");
    copy_rows(space, "nacre::dyn::halo_pack", send_, send_buf_, true);
    constexpr bool host = Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible;
    const bool direct = host || comm_.device_direct();
    if (!direct) Kokkos::deep_copy(space, send_host_, send_buf_);
    space.fence("nacre::dyn::halo_pack");  // MPI reads the buffer
    comm_.exchange(neighbours_, direct ? send_buf_.data() : send_host_.data(), send_off_,
                   direct ? recv_buf_.data() : recv_host_.data(), recv_off_, words_);
    if (!direct) Kokkos::deep_copy(space, recv_buf_, recv_host_);
    copy_rows(space, "nacre::dyn::halo_unpack", recv_, recv_buf_, false);
    space.fence("nacre::dyn::halo_unpack");
    ++exchanges_;
  }

  /// \brief Bytes one exchange sends from this rank, and the exchanges made so far.
  [[nodiscard]] long long bytes() const {
    return static_cast<long long>(send_off_.back()) * words_ * static_cast<long long>(sizeof(double));
  }
  [[nodiscard]] long long exchanges() const { return exchanges_; }

  // (public: nvcc names it in a device lambda)
  /// u's rows idx(k) into buf(k, :) (to_buffer: the pack) or back (the unpack); no fence
  template <class ExecutionSpace>
  void copy_rows(const ExecutionSpace& space, const char* label, const Kokkos::View<int*, MemorySpace>& idx,
                 const Buffer& buf, bool to_buffer) const {
    const auto u = u_;
    const int words = words_;
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecutionSpace>(space, 0, static_cast<int>(idx.extent(0))),
        KOKKOS_LAMBDA(const int k) {
          for (int w = 0; w < words; ++w) {
            if (to_buffer)
              buf(k, w) = u(idx(k), w);
            else
              u(idx(k), w) = buf(k, w);
          }
        });
  }

private:
  par::Comm comm_;
  std::vector<int> neighbours_, send_off_, recv_off_;
  Rows u_;
  int words_;
  mutable long long exchanges_ = 0;
  Kokkos::View<int*, MemorySpace> send_, recv_;  ///< model elements, neighbours concatenated
  Buffer send_buf_, recv_buf_;
  typename Buffer::host_mirror_type send_host_, recv_host_;
};

}  // namespace nacre::dyn
