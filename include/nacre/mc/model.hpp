// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Device-resident rigid-brick model: brick poses and interface geometry as Views, in
/// sweep order (free bricks grouped by colour, each colour contiguous, then driven bricks).
#include <nacre/cohesive/law_table.hpp>
#include <nacre/cohesive/quadrature.hpp>
#include <nacre/kinematics/rigid.hpp>
#include <nacre/core/backend.hpp>
#include <nacre/core/types.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/mc/colouring.hpp>

#include <vector>

namespace nacre::mc {

/// Columns of Model::seg, one per Segment field. Scoped: short names such as nx or length must
/// not leak into nacre::mc, where a second model (or a loop variable) may want them.
enum class SegCol : int { ra0x, ra0y, ra1x, ra1y, rb0x, rb0y, rb1x, rb1y, nx, ny, length, count };

/// \brief Column index of a SegCol (for View access: seg(i, col(SegCol::length))).
KOKKOS_INLINE_FUNCTION constexpr int col(SegCol c) { return static_cast<int>(c); }

/// Columns of Model::slot: an interface seen from one of its bricks ("own"), the other brick's
/// segment ends, the normal pointing from own to other, and the length.
enum class SlotCol : int { r0x, r0y, r1x, r1y, o0x, o0y, o1x, o1y, nx, ny, length, count };

/// \brief Column index of a SlotCol.
KOKKOS_INLINE_FUNCTION constexpr int col(SlotCol c) { return static_cast<int>(c); }

template <class MemorySpace = MemSpace>
struct Model {
  static_assert(Kokkos::is_memory_space_v<MemorySpace>, "Model needs a Kokkos memory space");
  using memory_space = MemorySpace;

  /// \brief Pose per brick: x, y, theta and, cached, sin(theta) and cos(theta) - 1 (a
  /// kinematics::Frame). The sweep gathers ~6 neighbour poses per trial; with the rotation cached
  /// it needs 2 sines per trial (the proposal) instead of 16. Every writer goes through
  /// store_frame(). LayoutRight keeps a brick's five numbers together, so a gather touches one
  /// or two cache lines (CPU) / 32-byte sectors (GPU) instead of five.
  using PoseView = Kokkos::View<double* [5], Kokkos::LayoutRight, MemorySpace>;

  // ---- bricks (structure of arrays for everything read per brick in sweep order)
  PoseView pose;
  Field<double, MemorySpace> cx, cy;   ///< reference centroid (where the load is evaluated)
  Kokkos::View<std::int8_t*, MemorySpace> drive;   ///< -1 bottom, 0 free, +1 top
  Kokkos::View<std::uint64_t*, MemorySpace> id;    ///< original brick index = RNG stream id
  Kokkos::View<int*, MemorySpace> adj_offset, adj_iface;  ///< CSR brick -> interfaces
  Field<double, MemorySpace> phi0;     ///< energy of all the brick's interfaces at x1 (predictor)

  // ---- interfaces. LayoutRight: the sweep, where the time goes, gathers the interfaces of a
  // brick by index, so an interface's 11 numbers should share two cache lines rather than sit
  // in 11 columns (LayoutLeft would coalesce only the rarely called loop over all interfaces).
  Kokkos::View<int* [2], Kokkos::LayoutRight, MemorySpace> ends;       ///< bricks a, b
  Kokkos::View<double* [col(SegCol::count)], Kokkos::LayoutRight, MemorySpace> seg;
  Kokkos::View<std::uint8_t*, MemorySpace> kind;  ///< geometry::JointKind (bed or head): selects the law

  // ---- the sweep's view of the interfaces: one record per adjacency slot j (brick b's
  // interface adj_iface(j)), oriented from b's side, so a trial reads its brick's records as one
  // contiguous stream (no gather by interface index, no test of which side b is on). The gap
  // other - own and the normal own -> other are, for b on side b, the negatives of the
  // interface's; every term of the energy is a product of two of them, so it has the same bits.
  // A derived copy of seg (twice its size): kept because the sweep is where the time goes.
  // LayoutRight: a slot's 11 numbers are read together, and a brick's slots are adjacent.
  Kokkos::View<double* [col(SlotCol::count)], Kokkos::LayoutRight, MemorySpace> slot;
  Kokkos::View<int* [2], Kokkos::LayoutRight, MemorySpace> slot_link;  ///< other brick, interface
  Kokkos::View<std::uint8_t*, MemorySpace> slot_kind;                  ///< joint kind (law)

  cohesive::LawTable laws;     ///< one law per joint kind, shared by all interfaces of the kind
  cohesive::Quadrature quad;

  /// \brief Damage history (cohesive/damage.hpp): hist(i, p) is the largest separation interface
  /// i has seen at quad's point p, in the interfaces' order (a slot's segment runs the same way,
  /// so both of its bricks read the same row). Empty with the reversible law (damage =
  /// "reversible"), which keeps the exact integral and pays nothing. LayoutRight: the sweep reads
  /// an interface's few values together, beside its slot record.
  Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace> hist;

  // ---- host-side bookkeeping
  /// \brief Work items (tiles) in sweep order: bricks of tile w are [tile_offset(w), tile_offset(w+1)).
  Kokkos::View<int*, MemorySpace> tile_offset;

  std::vector<int> colour_offset;  ///< bricks of colour c: [colour_offset[c], colour_offset[c+1])
  std::vector<int> colour_tiles;   ///< tiles of colour c: [colour_tiles[c], colour_tiles[c+1])
  std::vector<int> perm;           ///< perm[sweep index] = original brick index
  std::vector<int> iface_perm;     ///< iface_perm[model interface] = original interface index
  int n_free = 0, n_bricks = 0, n_interfaces = 0;
  std::string colouring_name;
};

/// \brief The sweep order of a colouring's bricks (Model::perm: perm[k] = the brick at sweep index
/// k): the free bricks by (colour, tile, wall order), then the driven ones.
[[nodiscard]] std::vector<int> sweep_order(const Colouring& colouring);

/// \brief Build the model for a given colouring in the memory space of `space` (an instance of an
/// enabled space): reorders bricks (free by colour, then driven) and uploads everything on that
/// instance (fenced before returning). Poses start at zero.
template <class ExecutionSpace, class = std::enable_if_t<Kokkos::is_execution_space_v<ExecutionSpace>>>
Model<MemOf<ExecutionSpace>> build_model(const ExecutionSpace& space, const geometry::Specimen& s,
                                         const geometry::Interfaces& f, const geometry::Adjacency& adj,
                                         const Colouring& colouring, const deck::Mortar& mortar, int quadrature_points);
/// \brief The same in the default memory space, on a backend that reaches it.
Model<> build_model(const Backend& backend, const geometry::Specimen& s, const geometry::Interfaces& f,
                    const geometry::Adjacency& adj, const Colouring& colouring, const deck::Mortar& mortar,
                    int quadrature_points);

/// \brief Segment i of the model (a handful of coalesced loads).
template <class SegView>
KOKKOS_INLINE_FUNCTION kinematics::Segment load_segment(const SegView& seg, int i) {
  using C = SegCol;
  return kinematics::Segment{seg(i, col(C::ra0x)), seg(i, col(C::ra0y)), seg(i, col(C::ra1x)),
                             seg(i, col(C::ra1y)), seg(i, col(C::rb0x)), seg(i, col(C::rb0y)),
                             seg(i, col(C::rb1x)), seg(i, col(C::rb1y)), seg(i, col(C::nx)),
                             seg(i, col(C::ny)),   seg(i, col(C::length))};
}

}  // namespace nacre::mc
