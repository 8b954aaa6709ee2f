// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The execution spaces a run can choose at run time (`nacre DECK --backend NAME`).
///
/// Why a variant of instances: every kernel launcher is a template on the execution space; a
/// solver that holds a Backend launches through visit(), which instantiates the launch once per
/// enabled space and picks the run's at the call: one binary, every enabled backend, no rebuild.
/// Every enabled space is listed (a CUDA build with Serial and OpenMP lists all three): a solver
/// built for a backend keeps its model and state in that backend's memory space (MemOf<E>), so the
/// host backends of a CUDA build run on host memory. Code whose data lives in one given memory
/// space launches through visit_in<Mem>(), which instantiates only the spaces that reach it.
#include <nacre/core/types.hpp>

#include <Kokkos_Core.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace nacre {

namespace detail {
template <class Variant, class E>
struct AppendSpace;
template <class... Ts, class E>
struct AppendSpace<std::variant<Ts...>, E> {
  static constexpr bool kJoin = !(std::is_same_v<E, Ts> || ...);  // each space once
  using type = std::conditional_t<kJoin, std::variant<Ts..., E>, std::variant<Ts...>>;
};
using Spaces0 = std::variant<Kokkos::DefaultExecutionSpace>;
#ifdef KOKKOS_ENABLE_SERIAL
using Spaces1 = typename AppendSpace<Spaces0, Kokkos::Serial>::type;
#else
using Spaces1 = Spaces0;
#endif
#ifdef KOKKOS_ENABLE_OPENMP
using Spaces2 = typename AppendSpace<Spaces1, Kokkos::OpenMP>::type;
#else
using Spaces2 = Spaces1;
#endif

/// The alternatives of a variant of spaces that reach memory space Mem (in order).
template <class Variant, class Mem, class Out = std::variant<>>
struct Reaching;
template <class Mem, class Out>
struct Reaching<std::variant<>, Mem, Out> {
  using type = Out;
};
template <class E, class... Rest, class Mem, class... Os>
struct Reaching<std::variant<E, Rest...>, Mem, std::variant<Os...>> {
  using type = typename Reaching<std::variant<Rest...>, Mem,
                                 std::conditional_t<Kokkos::SpaceAccessibility<E, Mem>::accessible,
                                                    std::variant<Os..., E>, std::variant<Os...>>>::type;
};

/// The memory spaces of a variant's spaces, each once: std::variant<Batch<M>...> for Batch.
template <class Variant, template <class> class Of, class Out = std::variant<>>
struct MemoryOf;
template <template <class> class Of, class Out>
struct MemoryOf<std::variant<>, Of, Out> {
  using type = Out;
};
template <class E, class... Rest, template <class> class Of, class... Os>
struct MemoryOf<std::variant<E, Rest...>, Of, std::variant<Os...>> {
  using M = Of<MemOf<E>>;
  using type = typename MemoryOf<
      std::variant<Rest...>, Of,
      std::conditional_t<(std::is_same_v<M, Os> || ...), std::variant<Os...>, std::variant<Os..., M>>>::type;
};

template <class E, class Variant>
struct IndexOf;
template <class E, class... Ts>
struct IndexOf<E, std::variant<Ts...>> {
  static constexpr std::size_t value = [] {
    constexpr bool is[] = {std::is_same_v<E, Ts>...};
    for (std::size_t i = 0; i < sizeof...(Ts); ++i)
      if (is[i]) return i;
    return sizeof...(Ts);
  }();
};
}  // namespace detail

/// \brief One execution-space instance of a backend this build enabled (the default first).
using AnySpace = detail::Spaces2;
/// \brief std::variant<Of<M>...> over the distinct memory spaces M of the enabled spaces (one in
/// a host build, the device's and the host's in a CUDA build with host backends).
template <template <class> class Of>
using PerMemorySpace = typename detail::MemoryOf<AnySpace, Of>::type;
/// \brief Index of space E among AnySpace's alternatives.
template <class E>
inline constexpr std::size_t space_index_v = detail::IndexOf<E, AnySpace>::value;

/// \brief A run's backend: the instance its kernels go to.
class Backend {
public:
  /// \brief The default execution space (a default instance).
  Backend() = default;
  /// \brief An instance of an enabled space (e.g. the caller's own).
  template <class ExecutionSpace>
  explicit Backend(const ExecutionSpace& s) : space_(s) {}

  /// \brief The backend named `name` (case-insensitive: "serial", "openmp", "cuda", ...; Kokkos
  /// initialised); std::invalid_argument naming the enabled ones otherwise.
  static Backend parse(const std::string& name);
  /// \brief Names of the backends this build can run (the default first), lower case (no
  /// initialised Kokkos needed).
  static std::vector<std::string> names();
  /// \brief `name` as names() spells it when it names a backend of this build (case-insensitive),
  /// else "" (no initialised Kokkos needed).
  static std::string canonical(const std::string& name);
  /// \brief names() joined by ", " (for the messages that list what is expected).
  static std::string names_list();

  /// \brief Lower-case name ("openmp"), and Kokkos' name of the space ("OpenMP").
  [[nodiscard]] std::string name() const;
  [[nodiscard]] const char* kokkos_name() const;
  [[nodiscard]] int concurrency() const;
  [[nodiscard]] bool is_default() const { return space_.index() == 0; }
  /// \brief True when a run on this backend continues one written on backend `name` bit for bit:
  /// the same backend, or both on the host (Serial, OpenMP and Threads run the same instructions
  /// on the same memory: nacre's kernels and sums give the same bits at any thread count). A
  /// device's arithmetic differs (fused multiply-adds, its own math library): cuda and a host
  /// backend are not.
  [[nodiscard]] bool bit_compatible(const std::string& name) const { return bit_compatible(this->name(), name); }
  /// \brief The same for two backends' names (case-insensitive; no initialised Kokkos needed).
  [[nodiscard]] static bool bit_compatible(const std::string& a, const std::string& b);
  /// \brief The instance when this is the default space (std::bad_variant_access otherwise).
  [[nodiscard]] const Kokkos::DefaultExecutionSpace& default_instance() const { return std::get<0>(space_); }
  void fence() const;

  /// \brief f(instance) with the instance's own type: every launch of a run goes through here.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), space_);
  }
  /// \brief True when this backend's kernels reach memory space Mem.
  template <class Mem>
  [[nodiscard]] bool reaches() const {
    return visit(
        [](const auto& e) -> bool { return Kokkos::SpaceAccessibility<std::decay_t<decltype(e)>, Mem>::accessible; });
  }
  /// \brief visit() for data that lives in memory space Mem: f is instantiated only for the
  /// spaces that reach Mem; on another backend std::logic_error (callers check reaches<Mem>()
  /// first: a model is built in its backend's memory space).
  template <class Mem, class F>
  decltype(auto) visit_in(F&& f) const {
    using Reach = typename detail::Reaching<AnySpace, Mem>::type;
    static_assert(std::variant_size_v<Reach> > 0, "nacre::Backend::visit_in: no enabled space reaches Mem");
    using First = std::variant_alternative_t<0, Reach>;
    using R = decltype(f(std::declval<const First&>()));
    return std::visit(
        [&](const auto& e) -> R {
          using E = std::decay_t<decltype(e)>;
          if constexpr (Kokkos::SpaceAccessibility<E, Mem>::accessible)
            return f(e);
          else
            throw std::logic_error(std::string("nacre::Backend::visit_in: backend ") + E::name() +
                                   " does not reach memory space " + Mem::name());
        },
        space_);
  }

private:
  AnySpace space_;
};

}  // namespace nacre
