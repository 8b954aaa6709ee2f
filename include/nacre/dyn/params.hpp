// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The choices of a dynamic run, defined once: the deck reads them (deck/dynamics.hpp
/// names these types), the app maps the deck onto dyn::Params with them, the solver dispatches on
/// them. Plain enums, no Kokkos: the deck reader includes this header and nothing else of dyn.
#include <cstdint>

namespace nacre::dyn {

/// \brief Time integrators: UE = unbolted explicit (eq. 4.4, each triangle its own element, stiff
/// internal joints on the diagonals), BE = bolted explicit (eq. 4.5, one (n+1)-node element per
/// brick), BIE = bolted implicit-explicit (eq. 4.6/4.7: implicit midpoint for the element terms,
/// explicit Verlet for the interface forces, constant per-type Jacobian; docs/methods.md).
enum class Method : std::uint8_t { ue, be, bie };

/// \brief How BIE applies J^-1 to every element's residual (docs/methods.md, perf/dyn_bie):
/// row = row-by-row matvec per element; reordered = blocks of Params::bie_block rows with the
/// columns accumulated in registers (dissertation §4.3); batched = KokkosBatched::SerialGemv per
/// element (only where Kokkos Kernels is available); shared_gemm = one J^-1 x [residuals of all
/// elements of the type] product per element type, tiled (compute-bound). Same result to rounding.
enum class BieSolve : std::uint8_t { row, reordered, batched, shared_gemm };

/// \brief The reordered matvec's rows per block (Params::bie_block): the deck reader and the
/// solver check it with this one rule.
constexpr bool valid_bie_block(long nb) { return nb == 2 || nb == 4 || nb == 5 || nb == 10; }
inline constexpr const char* kBieBlockExpected = "2, 4, 5 or 10 (rows per block of the reordered matvec)";

/// \brief How the per-element terms (K p, C v, (M + h/2 C)^-1 r) of the explicit integrators and
/// BIE's residuals are applied: per_element = one element per work item, the type's matrices read
/// row by row (a GPU thread per element, coalesced with the element index fastest); tiled = up to
/// kTile consecutive free elements of one type per work item, each matrix entry loaded once and
/// applied to the tile's elements in the innermost (SIMD) loop, so the apply is compute-throughput
/// bound instead of latency bound (a CPU core); automatic = tiled for BE and BIE where the backend's
/// layout is LayoutRight (CPU), per_element on a GPU and for UE (6-dof triangles: no gain, measured). Same sums in the same order: bit-identical results.
enum class ElementApply : std::uint8_t { automatic, per_element, tiled };

/// \brief BIE's step (docs/methods.md "The split step"): iterate = eq. 4.6, Params::bie_iterations
/// Newton iterations with the constant J of eq. 4.7 (the dissertation); split = the same partition
/// (implicit midpoint for the element terms K, C; explicit for the interface, thermal and applied
/// forces) as a Strang splitting: half kick with the explicit forces at p_n, one implicit-midpoint
/// step of the linear element part (one J^-1 apply solves it exactly), half kick with the explicit
/// forces at p_{n+1}. With C = 0 both give the same step (to rounding); with damping the split is
/// unconditionally stable in K and C, its step set by the interface (Verlet) limit alone, at one
/// J^-1 apply and one interface evaluation per step.
enum class BieScheme : std::uint8_t { iterate, split };

/// \brief Time step control (docs/dynamics.md "Stability monitor"): fixed = the step set at the
/// start for the whole run (the run stops when the estimated critical step falls below it);
/// adaptive = the step follows the estimated critical step down (and back up to its start
/// value) at the checks, keeping the start's ratio dt / estimate.
enum class DtMode : std::uint8_t { fixed, adaptive };

/// \brief Time profile of the prescribed opening D(t).
enum class Ramp : std::uint8_t { linear, smooth };

}  // namespace nacre::dyn
