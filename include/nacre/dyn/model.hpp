// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Device-resident deformable model (MODEL.md §5): element types, elements, interfaces.
///
/// One design for UE and BE: an "element" owns its nodes (UE: a fan triangle, 3 nodes; BE: a
/// bolted brick, centre + n corners). Elements never share nodes, so every per-element operation
/// (K p, C v, (M + h/2 C)^-1 r) is independent; the only coupling is the interface force, which
/// acts on two nodes of an edge of each side. UE and BE differ only in what the builder puts in
/// the tables (UE adds the stiff internal joints on the spokes as interfaces of kind 2).
///
/// Layout (ElemLayout below): per-element arrays are View<double**, L> [element][dof], per-interface
/// ones [interface][k], element types [type][row][col], with L the execution space's array_layout
/// (Kokkos' convention): on a GPU LayoutLeft, element index fastest, so consecutive threads (one
/// element each) read consecutive addresses for every dof (coalesced); on a CPU LayoutRight, each
/// element's dofs contiguous, so a thread streams 3 arrays instead of 3 nd columns (the hardware
/// prefetchers follow 3 streams, not 30) and an interface gathers one cache line per side instead
/// of one per dof (measured: the run of ac16330 in perf/results/dyn_step_quiet, in git). With sharing, the type tables are a few
/// KB read from cache on either backend.
#include <nacre/cohesive/law_table.hpp>
#include <nacre/cohesive/quadrature.hpp>
#include <nacre/core/types.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/joint_kind.hpp>
#include <nacre/loading/pattern.hpp>
#include <nacre/loading/ramp.hpp>
#include <nacre/par/decomposition.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace nacre::dyn {

/// Largest element: a bolted 7-gon (centre + 7 corners). Clipped rectangles have at most 6 sides.
inline constexpr int kMaxNodes = 8;
inline constexpr int kMaxDof = 2 * kMaxNodes;
/// Elements per work item of the tiled element apply (ElementApply::tiled) and of BIE's shared
/// J^-1 product: 8 doubles = 4 SSE2 / 2 AVX2 / 1 AVX-512 register per accumulator row.
inline constexpr int kTile = 8;
/// Tiles are cut within windows of this many consecutive elements (a pass touches each cache
/// line of the state once; UE's 4 triangles of a brick are 4 types).
inline constexpr int kTileWindow = 8 * kTile;

/// Gather-list entry: interface i (< kMaxGatherIface), side (0 a, 1 b), the side's local nodes
/// n0, n1 (< 8) in one unsigned 32-bit word: 25 bits of interface, 33.5 M interfaces (UE has 7
/// per brick: 4.8 M bricks; a signed int's 24 bits stopped UE at 2.4 M, seen on an H200).
using GatherEntry = std::uint32_t;
inline constexpr int kMaxGatherIface = 1 << 25;
KOKKOS_INLINE_FUNCTION constexpr GatherEntry gather_entry(int i, int side, int n0, int n1) {
  return (static_cast<GatherEntry>(i) << 7) | (static_cast<GatherEntry>(side) << 6) |
         (static_cast<GatherEntry>(n0) << 3) | static_cast<GatherEntry>(n1);
}
/// \brief The fields of a gather entry (gather_entry's inverse).
struct GatherFields {
  int iface, side, n0, n1;
};
KOKKOS_INLINE_FUNCTION constexpr GatherFields gather_fields(GatherEntry e) {
  return {static_cast<int>(e >> 7), static_cast<int>((e >> 6) & 1u), static_cast<int>((e >> 3) & 7u),
          static_cast<int>(e & 7u)};
}

/// Layout of the per-element, per-interface and per-type arrays (see above): LayoutLeft on a GPU,
/// LayoutRight on a CPU. Checkpoints store the state in LayoutLeft order whatever this is.
template <class MemorySpace>
using ElemLayout = typename MemorySpace::execution_space::array_layout;

template <class MemorySpace = MemSpace>
struct Model {
  static_assert(Kokkos::is_memory_space_v<MemorySpace>, "dyn::Model needs a Kokkos memory space");
  using memory_space = MemorySpace;
  using TypeMat = Kokkos::View<double***, ElemLayout<MemorySpace>, MemorySpace>;  ///< [type][row][col]
  using Dof = Kokkos::View<double**, ElemLayout<MemorySpace>, MemorySpace>;       ///< [element|type][dof]

  int n_elem = 0, nd = 0, n_types = 0, n_iface = 0, n_mortar = 0;

  // ---- element types (shared matrices)
  TypeMat K;       ///< stiffness
  TypeMat Ainv;    ///< (M + h/2 C)^-1 = ((1 + h alpha/2) M + h beta/2 K)^-1
  Dof mass;        ///< lumped mass per dof
  /// [type] largest eigenvalue of M_e^-1 K_e: the element's part of the step bound (monitor.hpp;
  /// elements share no nodes, so the elements' part of M^-1 K is block diagonal and this is exact)
  Kokkos::View<double*, MemorySpace> klam;
  Dof theta;       ///< thermal load Theta for the run's eigenstrain
  Dof node_x, node_y;  ///< [type][node] node positions relative to the brick centroid
  Kokkos::View<int*, MemorySpace> type_nodes;

  // ---- elements
  Kokkos::View<int*, MemorySpace> type;
  /// Reference centroid of a driven element's brick (only the prescribed motion needs it), at the
  /// element's index in `driven`: driven_index(e) (-1 for a free element).
  Kokkos::View<int*, MemorySpace> driven_index;
  Field<double, MemorySpace> cx, cy;
  Kokkos::View<std::int8_t*, MemorySpace> drive;  ///< -1 bottom, 0 free, +1 top (whole element prescribed)
  Dof fp;          ///< [element][dof] prescribed nodal forces (extent 0 when none)
  /// Gather list (CSR): the interface sides acting on element e are gent[goff[e] .. goff[e+1]),
  /// in increasing interface order (no atomics, same bits on any thread count); each entry packs
  /// (interface, side, the side's two local nodes) (gather_entry), so the gather reads the
  /// interface's force row and nothing else of it.
  Kokkos::View<int*, MemorySpace> goff;
  Kokkos::View<GatherEntry*, MemorySpace> gent;
  /// Tiled element apply: work item w < n_tiles covers the free elements
  /// tile_elem[tile_start(w) .. tile_start(w + 1)): at most kTile, one type, increasing, within
  /// one window of kTileWindow elements; the windows in order, in a window the types in order;
  /// work item n_tiles + k the driven element driven(k) (per element: prescribed motion).
  Kokkos::View<int*, MemorySpace> tile_start, tile_elem, driven;
  int n_tiles = 0, n_driven = 0;
  bool ainv_diagonal = false;  ///< every type's (M + h/2 C)^-1 is diagonal (beta_d = 0): skip its zeros

  // ---- interfaces (first the geometry's bed/head interfaces in element order: sorted by their
  // first element, the geometry's order within; HostMap::iface_geom maps back; then internal joints)
  Kokkos::View<int* [2], ElemLayout<MemorySpace>, MemorySpace> ielem;          ///< element of side a, b
  /// Interface shapes, shared as element types are ("model no more than the scene needs"): the
  /// geometry of interface i is shape ishape(i); interfaces with bitwise-equal geometry (local
  /// nodes, normal, length, edge parameters, kind) share one, so a running bond needs a handful.
  Kokkos::View<int*, MemorySpace> ishape;
  int n_shapes = 0;
  Kokkos::View<std::int8_t* [4], ElemLayout<MemorySpace>, MemorySpace> inode;  ///< [shape] local nodes a0 a1 b0 b1
  Kokkos::View<double* [4], ElemLayout<MemorySpace>, MemorySpace> ixi;  ///< [shape] edge parameter of the segment ends a0 a1 b0 b1
  Field<double, MemorySpace> inx, iny, ilen;                              ///< [shape] unit normal a -> b, length
  Kokkos::View<std::uint8_t*, MemorySpace> ikind;  ///< [shape] geometry::JointKind (bed, head, internal)
  cohesive::LawTable laws;  ///< one law per joint kind
  cohesive::Quadrature quad;
  /// Damage history (cohesive/damage.hpp, [mortar] damage = "irreversible"): hist(i, p) is the
  /// largest separation bed/head interface i (< n_mortar) has seen at quad's point p, raised after
  /// every step. State, not geometry: it lives here so that every interface operator sees it.
  /// Empty with the reversible law (and internal joints, which never leave the elastic range,
  /// have no row). LayoutRight: an interface's few points are read together.
  Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace> hist;
  bool irreversible = false;  ///< the run keeps the history (on ranks: even where this rank's part has no row)

  // ---- a rank's part of the specimen (MPI runs; empty in one process): 1 where this rank owns
  // the element / the interface (by its side a) / the driven row, the rows its sums count (each
  // row of the whole model is owned by exactly one rank, so the combined sums have the one-process
  // terms). The others are the halo: elements whose displacement an owned interface reads, held
  // at their owner's values (halo.hpp), and interfaces of an owned element owned by the neighbour.
  Kokkos::View<std::uint8_t*, MemorySpace> elem_owned, iface_owned, driven_owned;

  // ---- run constants
  double h = 0, alpha = 0, beta = 0, thickness = 1, eps_th = 0;
  loading::Pattern pattern;                    ///< prescribed displacement of the driven edges
  bool top_prescribed = true;                  ///< false when force_top loads the top instead
  double brick_height = 0;                     ///< height of a whole brick (internal joints, docs)
  double step_estimate = 0;  ///< the elastic start's StepBound (monitor.hpp), computed on the host: start of the bisection
  int sliver_elements = 0;     ///< elements mass-scaled (Params::sliver_step_ratio)
  double sliver_mass_added = 0;              ///< mass they gained, relative to the specimen's
  double sliver_step_gain = 1;               ///< the elements' step bound after / before the scaling
};

/// \brief Host bookkeeping that maps the model back to bricks and triangles (outputs). The
/// per-element and per-triangle arrays below number the whole specimen's elements (every rank
/// holds them: they serve rank 0's outputs); a rank's model rows map into them by the
/// *_global arrays at the end (the identity in one process).
struct HostMap {
  std::vector<int> brick_elem;       ///< CSR: elements of brick b are [brick_elem[b], brick_elem[b+1])
  std::vector<int> tri_elem, tri_brick;        ///< per output triangle: element, brick
  std::vector<std::array<int, 3>> tri_local;   ///< per output triangle: local nodes in its element
  std::vector<int> elem_brick, elem_type;
  std::vector<int> type_nodes;
  std::vector<double> type_x, type_y;          ///< [type * kMaxNodes + node]
  std::vector<double> cx, cy;                  ///< per brick centroid
  std::vector<int> iface_geom;                 ///< whole-model interface i < n_mortar -> the geometry's interface index

  // ---- this rank's model rows in the whole model's numbering, and which it owns (all in one process)
  int n_elem = 0, n_iface = 0, n_mortar = 0, n_driven = 0;    ///< the whole model's counts
  std::vector<int> elem_global, iface_global, driven_global;  ///< model row -> the whole model's row
  std::vector<char> elem_owned, iface_owned, driven_owned;    ///< model row: this rank owns it
};

/// \brief Build the model of `p.method` for a specimen (host assembly, then upload). With a
/// decomposition `part` (MPI runs) the model holds the elements of that rank's owned and halo
/// bricks and the interfaces with an owned element, in the whole model's order (so an element's
/// gather adds its interfaces' rows in the one-process order: the same bits); the whole model is
/// assembled on the host first, so element types, sliver scaling, the step estimate and the
/// interface order are the one-process ones.
/// The model lives in memory space Mem: the default one, or (a CUDA build's host backends) the host's.
template <class Mem = MemSpace>
Model<Mem> build_model(const Params& p, const geometry::Specimen& s, const geometry::Interfaces& f,
                       const deck::Mortar& mortar, HostMap& map, const par::Decomposition* part = nullptr);

/// \brief Cauchy stress (xx, yy, xy) of a CST with nodes (x, y), CCW, nodal displacements u
/// (6), plane stress E, nu, isotropic eigenstrain eps_th (host; element.cpp). Plain arrays so
/// that the kernel sources stay free of Eigen (nvcc warns on Eigen's headers).
void triangle_stress(const double x[3], const double y[3], const double u[6], double E, double nu,
                     double eps_th, double sig[3], double& area);

/// \brief A new time step for the model's step-dependent tables, (M + h/2 C)^-1 per type (the
/// adaptive step; BIE's J^-1 is rebuilt from the model by build_bie_tables).
template <class Mem>
void set_model_step(Model<Mem>& m, double h);

/// \brief Bytes held by the model's views.
template <class Mem>
std::size_t model_bytes(const Model<Mem>& m);

/// \brief Height of a whole brick: the shortest edge among bricks of full area (rectangles of
/// the running bond; sqrt(full area) when no whole brick exists).
double whole_brick_height(const geometry::Specimen& s);

}  // namespace nacre::dyn
