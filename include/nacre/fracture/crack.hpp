// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The crack as a fracture scientist reads it: the ruptured interfaces connected to the
/// notch (a walk over the mortar network), its tip, extension, length along the path, deflection,
/// the bed and head joints on it, and the process zone ahead of it. Both solver families give
/// their per-interface states (0 elastic, 1 softening, 2 ruptured, in the geometry's order);
/// this file depends on the specimen only (no solver), so MC and dynamics share it.
///
/// Definitions (docs/fracture.md):
/// - The mortar network: nodes are interface end points (merged within 1e-6 of a brick height),
///   edges are interfaces. The notch is the slit y = notch_y from x = 0 to its tip, the right end
///   of its free faces (brick edges on the line that no interface covers: notch_length on an
///   unrotated wall, the end of the last split brick on a rotated one); network nodes on it are
///   the crack's roots.
/// - The crack: the ruptured interfaces reachable from a root through ruptured interfaces.
/// - Its tip: the crack node furthest along the ligament (largest x; the notch runs along +x).
///   Extension = tip x - notch tip x (the projected crack length, >= 0). Path length = the
///   shortest distance from a root to the tip through the crack (Dijkstra). Deflection = path
///   length / extension (1 for a straight crack along the ligament; 0 when there is no extension).
/// - The process zone: the softening interfaces reachable from the crack's nodes (or from the
///   notch tip when nothing has ruptured) through softening interfaces; its extent is how far its
///   nodes reach beyond the tip along the ligament.
#include <nacre/deck/deck.hpp>
#include <nacre/geometry/specimen.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace nacre::fracture {

/// \brief One reading of the crack (lengths in the specimen's unit, mm).
struct CrackReading {
  int interfaces = 0;              ///< ruptured interfaces connected to the notch
  int bed = 0, head = 0;           ///< of those, bed and head joints
  double tip_x = 0, tip_y = 0;     ///< the tip (the notch tip while nothing is connected)
  double extension = 0;            ///< tip_x - notch tip x (projected crack length)
  double path_length = 0;          ///< shortest distance from the notch to the tip along the crack
  double deflection = 0;           ///< path_length / extension (0 when extension is 0)
  int process_zone = 0;            ///< softening interfaces connected to the crack (or the notch tip)
  double process_zone_extent = 0;  ///< how far they reach beyond the tip along the ligament
  /// Energy of fracture: the cohesive energy of every softening and ruptured joint (the reversible
  /// law's stand-in for the work dissipated; docs/fracture.md), N mm (MC: per unit depth); 0
  /// when no energies were given.
  double fracture_energy = 0;
};

/// \brief The mortar network of one specimen, built once; measure() reads a state vector.
class CrackTracker {
public:
  CrackTracker(const geometry::Specimen& s, const geometry::Interfaces& f, const deck::Geometry& g);

  /// \brief Read the crack from per-interface states (geometry order; 0 elastic, 1 softening,
  /// 2 ruptured). Throws std::invalid_argument when the size is not the interface count.
  /// `energy` (optional, same order): each joint's cohesive energy, for fracture_energy.
  [[nodiscard]] CrackReading measure(std::span<const int> state, std::span<const double> energy = {}) const;
  /// \brief The same from the 8-bit states the Monte Carlo output keeps.
  [[nodiscard]] CrackReading measure(std::span<const std::int8_t> state, std::span<const double> energy = {}) const;

  /// \brief The interfaces of the crack (geometry indices, ascending) for these states.
  [[nodiscard]] std::vector<int> crack_interfaces(std::span<const int> state) const;
  /// \brief Per interface 1 on the crack, else 0: the dumps' interface field "crack" (ParaView
  /// draws the path by a threshold on it over the interface polylines).
  [[nodiscard]] std::vector<std::int8_t> crack_mask(std::span<const int> state) const;
  [[nodiscard]] std::vector<std::int8_t> crack_mask(std::span<const std::int8_t> state) const;

  [[nodiscard]] double notch_tip_x() const { return notch_tip_x_; }
  [[nodiscard]] double notch_y() const { return notch_y_; }
  [[nodiscard]] std::size_t nodes() const { return node_x_.size(); }

private:
  template <class T>
  CrackReading measure_impl(std::span<const T> state, std::span<const double> energy, std::vector<int>* members) const;
  template <class T>
  std::vector<std::int8_t> mask_impl(std::span<const T> state) const;

  std::vector<double> node_x_, node_y_;
  std::vector<int> end0_, end1_;  ///< per interface: its two nodes
  std::vector<double> length_;    ///< per interface
  std::vector<geometry::JointKind> kind_;
  std::vector<int> adj_offset_, adj_iface_;  ///< node -> incident interfaces (CSR)
  std::vector<int> roots_;                   ///< nodes on the notch
  double notch_tip_x_ = 0, notch_y_ = 0;
};

/// \brief The reading's CSV columns, shared by steps.csv and series.csv: the header names
/// ("crack_interfaces,...,process_zone_extent", no newline) and one row's values, reals to `digits`.
[[nodiscard]] std::string csv_header();
[[nodiscard]] std::string csv_columns(const CrackReading& c, int digits);

/// \brief The reading as members of a JSON object (summary.json's "crack" of both families);
/// a template so this file needs no JSON library.
template <class Json>
void put_json(Json& j, const CrackReading& c, double notch_tip_x) {
  j["interfaces"] = c.interfaces, j["bed"] = c.bed, j["head"] = c.head;
  j["tip_x"] = c.tip_x, j["tip_y"] = c.tip_y, j["notch_tip_x"] = notch_tip_x;
  j["extension"] = c.extension, j["path_length"] = c.path_length, j["deflection"] = c.deflection;
  j["process_zone"] = c.process_zone, j["process_zone_extent"] = c.process_zone_extent;
  j["fracture_energy"] = c.fracture_energy;
}

/// \brief The run's damage model and load path as summary.json members ("damage", "programme",
/// and crack.fracture_energy_is: what the crack's fracture_energy measures).
template <class Json>
void put_damage_json(Json& j, const deck::Deck& d) {
  const bool irr = d.mortar.damage == cohesive::Damage::irreversible;
  j["damage"] = irr ? "irreversible" : "reversible";
  j["damage_rule"] = d.mortar.damage_auto ? "auto" : "deck";
  j["programme"] = d.load.targets();
  j["crack"]["fracture_energy_is"] =
      irr ? "dissipated" : "cohesive energy of softening and ruptured joints (reversible law)";
}

/// \brief Rayleigh wave speed of an isotropic elastic solid in plane stress (the bricks'
/// in-plane model): the root xi in (0, 1) of (2 - xi^2)^2 = 4 sqrt(1 - xi^2 k^2) sqrt(1 - xi^2),
/// k = c_s / c_p with c_p^2 = E / (rho (1 - nu^2)), c_s^2 = E / (2 rho (1 + nu)); returns xi c_s.
[[nodiscard]] double rayleigh_speed_plane_stress(double youngs_modulus, double poisson, double density);

}  // namespace nacre::fracture
