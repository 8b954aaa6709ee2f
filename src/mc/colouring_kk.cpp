// SPDX-License-Identifier: BSD-3-Clause
// Why: Kokkos Kernels' distance-1 graph colouring (KokkosGraph) as a candidate sweep schedule
// beside nacre's own greedy colourings ("kokkos-d1"). It runs in parallel on the execution space
// the sweep uses (OpenMP threads, or the GPU where colouring a million bricks on the host would
// dominate start-up), so it is the natural choice where nacre's serial greedy pass is slow.
// The deterministic vertex-based variant (COLORING_VBD) is used: the default variants resolve
// conflicts in whatever order threads race, and nacre's runs must be reproducible from the
// deck alone, independent of thread count and backend. Compiled only when CMake finds Kokkos
// Kernels (NACRE_HAVE_KOKKOSKERNELS); perf/colouring_compare.cpp measures it against the rest.
#include <nacre/mc/colouring.hpp>

#include <Kokkos_Core.hpp>
#include <Kokkos_Profiling_ScopedRegion.hpp>
#include <KokkosGraph_Distance1Color.hpp>
#include <KokkosKernels_Handle.hpp>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace nacre::mc {

namespace {

/// The free bricks' subgraph (driven bricks neither get a colour nor constrain one) as CRS in
/// wall order, coloured on `space`. Kokkos Kernels' handle (4.7) takes no execution-space
/// instance: the call runs on the space's default instance, hence the fence before returning.
template <class ExecSpace>
Colouring colour_d1(const ExecSpace& space, const geometry::Adjacency& adj, const std::vector<bool>& free,
                    bool deterministic) {
  using Mem = typename ExecSpace::memory_space;
  using Handle = KokkosKernels::Experimental::KokkosKernelsHandle<int, int, double, ExecSpace, Mem, Mem>;
  Kokkos::Profiling::ScopedRegion region("nacre::mc::colour_kokkos_d1");
  const std::size_t n = free.size();
  std::vector<int> local(n, -1), global;
  for (std::size_t i = 0; i < n; ++i)
    if (free[i]) local[i] = static_cast<int>(global.size()), global.push_back(static_cast<int>(i));
  const int nv = static_cast<int>(global.size());
  // CRS of the subgraph, built on the host and copied once (LayoutRight 1-D: plain arrays)
  Kokkos::View<int*, Kokkos::HostSpace> h_row(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::mc::kk_rowmap_h"), nv + 1);
  std::vector<int> entries;
  h_row(0) = 0;
  for (int v = 0; v < nv; ++v) {
    const int i = global[v];
    for (int j = adj.offset[i]; j < adj.offset[i + 1]; ++j)
      if (const int l = local[adj.neighbour[j]]; l >= 0) entries.push_back(l);
    h_row(v + 1) = static_cast<int>(entries.size());
  }
  Kokkos::View<const int*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h_ent(entries.data(), entries.size());
  Kokkos::View<int*, Mem> row(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::kk_rowmap"), nv + 1);
  Kokkos::View<int*, Mem> ent(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::kk_entries"), entries.size());
  Kokkos::deep_copy(space, row, h_row);
  Kokkos::deep_copy(space, ent, h_ent);
  space.fence("nacre::mc::colour_kokkos_d1: upload");

  Handle kh;
  kh.create_graph_coloring_handle(deterministic ? KokkosGraph::COLORING_VBD : KokkosGraph::COLORING_DEFAULT);
  KokkosGraph::Experimental::graph_color(&kh, nv, nv, row, ent);
  auto* ch = kh.get_graph_coloring_handle();
  const auto colours = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, ch->get_vertex_colors());
  Colouring c;
  c.name = deterministic ? "kokkos-d1" : "kokkos-d1-default";
  c.colour.assign(n, -1);
  c.tile.assign(n, -1);
  for (int v = 0; v < nv; ++v) {
    const int col = static_cast<int>(colours(v)) - 1;  // Kokkos Kernels' colours start at 1
    if (col < 0) throw std::logic_error("Kokkos Kernels left brick " + std::to_string(global[v]) + " uncoloured");
    c.colour[global[v]] = col;
    c.n_colours = std::max(c.n_colours, col + 1);
  }
  kh.destroy_graph_coloring_handle();
  return c;
}

}  // namespace

Colouring colour_kokkos_d1(const geometry::Adjacency& adj, const std::vector<bool>& free, bool deterministic) {
  return colour_d1(Kokkos::DefaultExecutionSpace{}, adj, free, deterministic);
}

}  // namespace nacre::mc
