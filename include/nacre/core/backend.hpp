#pragma once
/// \file
/// \brief The execution spaces a run can choose at run time (`nacre DECK --backend NAME`).
///
/// Why a variant of instances: nacre's models and states live in the default memory space
/// (core/types.hpp MemSpace), so a backend is usable when its execution space can reach that
/// memory: the default space itself, and in a host build every other enabled host space (Serial
/// beside OpenMP). Every kernel launcher is a template on the execution space; a solver that
/// holds a Backend launches through visit(), which instantiates the launch once per enabled
/// space and picks the run's at the call: one binary, every enabled backend, no rebuild.
#include <nacre/core/types.hpp>

#include <Kokkos_Core.hpp>

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
  // E joins when it reaches the default memory space and is not already listed
  static constexpr bool kJoin = Kokkos::SpaceAccessibility<E, MemSpace>::accessible && !(std::is_same_v<E, Ts> || ...);
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
}  // namespace detail

/// \brief One execution-space instance of a backend this build enabled (the default first).
using AnySpace = detail::Spaces2;

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
  /// \brief The instance when this is the default space (std::bad_variant_access otherwise).
  [[nodiscard]] const Kokkos::DefaultExecutionSpace& default_instance() const { return std::get<0>(space_); }
  void fence() const;

  /// \brief f(instance) with the instance's own type: every launch of a run goes through here.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), space_);
  }

private:
  AnySpace space_;
};

}  // namespace nacre
