// SPDX-License-Identifier: BSD-3-Clause
// [mortar]: one cohesive law for every joint, optionally overridden by [mortar.bed] and
// [mortar.head] (required section).
#include "../section.hpp"

namespace nacre::deck::detail {

void read_mortar(Section& top, Deck& d) {
  Section m = top.sub("mortar");
  if (!m.present()) top.fail("mortar", "missing section; expected a [mortar] table with k, x1, x2");
  cohesive::Law common = d.mortar.bed;
  read_law(m, common);
  check_law(m, common);
  d.mortar.bed = d.mortar.head = common;
  Section bed = m.sub("bed"), head = m.sub("head");
  read_law(bed, d.mortar.bed);
  check_law(bed, d.mortar.bed);
  read_law(head, d.mortar.head);
  check_law(head, d.mortar.head);
  bed.reject_unknown({"k", "x1", "x2"});
  head.reject_unknown({"k", "x1", "x2"});
  std::string damage = "auto";
  m.string("damage", damage, {"auto", "reversible", "irreversible"},
           "\"reversible\" (the law alone), \"irreversible\" (unloading along the damaged secant, a history per "
           "Gauss point) or \"auto\" (irreversible when [load] programme unloads)");
  d.mortar.damage_auto = damage == "auto";
  d.mortar.damage = damage == "irreversible" ? cohesive::Damage::irreversible : cohesive::Damage::reversible;
  m.reject_unknown({"k", "x1", "x2", "damage", "bed", "head"});
}

}  // namespace nacre::deck::detail
