// SPDX-License-Identifier: BSD-3-Clause
// [load]: the prescribed-displacement pattern and the load-step programme (required section).
#include "../section.hpp"

#include <nacre/loading/ramp.hpp>

#include <cmath>

namespace nacre::deck::detail {

void read_load(Section& top, Deck& d) {
  Section l = top.sub("load");
  if (!l.present()) top.fail("load", "missing section; expected a [load] table");
  auto& L = d.load;
  l.number("tension", {}, L.tension, [](double) { return true; }, "a number");
  l.number("bending", {}, L.bending, [](double) { return true; }, "a number");
  // programme: the targets in order (finite, each different from the one before, starting away
  // from 0); replaces final_displacement, which becomes its last target
  if (const toml::node* n = l.find("programme", {"program"})) {
    const std::string expected = "an array of displacement targets in order, e.g. [0.1, 0.05, 0.2] (at most " +
                                 std::to_string(loading::kMaxTargets) + ")";
    const toml::array* a = n->as_array();
    if (!a || a->empty() || a->size() > std::size_t(loading::kMaxTargets)) l.fail("programme", "expected " + expected);
    double prev = 0;
    for (const auto& e : *a) {
      double v;
      if (auto x = e.value_exact<double>())
        v = *x;
      else if (auto i = e.value_exact<std::int64_t>())
        v = static_cast<double>(*i);
      else
        l.fail("programme", "an entry is not a number; expected " + expected);
      if (!std::isfinite(v) || v == prev)
        l.fail("programme", "entry " + std::to_string(L.programme.size() + 1) +
                                " is not finite or repeats the displacement before it (0 at the start); expected " +
                                expected);
      L.programme.push_back(v);
      prev = v;
    }
    if (l.find("final_displacement", {}))
      l.fail("final_displacement",
             "given with programme; expected one of them (the programme ends at its last target)");
    L.final_displacement = L.programme.back();
  } else {
    l.number("final_displacement", {}, L.final_displacement, positive, "a positive displacement", true);
  }
  l.number("initial_step", {"InitialLoadStepSize"}, L.initial_step, positive, "a positive displacement");
  L.min_step = L.max_step = L.initial_step;
  l.number("min_step", {"MinLoadStepSize"}, L.min_step, positive, "a positive displacement");
  l.number("max_step", {"MaxLoadStepSize"}, L.max_step, positive, "a positive displacement");
  l.boolean("adaptive", L.adaptive);
  // predictor: true (the one suited to the relaxation), false, or "damped" / "secant"
  if (const toml::node* n = l.find("predictor", {})) {
    const std::string expected = "true, false, \"damped\" (eq. 2.11) or \"secant\"";
    if (auto b = n->value_exact<bool>()) {
      L.predictor = *b ? Load::Predictor::automatic : Load::Predictor::none;
    } else if (auto s = n->value_exact<std::string>()) {
      if (*s != "damped" && *s != "secant") l.fail("predictor", "unknown value \"" + *s + "\"; expected " + expected);
      L.predictor = *s == "damped" ? Load::Predictor::damped : Load::Predictor::secant;
    } else {
      l.fail("predictor", "wrong type (" + Section::type_name(*n) + "); expected " + expected);
    }
  }
  l.integer("max_ruptures_per_step", {}, L.max_ruptures_per_step, 0, 1000000000,
            "an interface count >= 0 (0: no snap-back control)");
  // unknown keys first: a misspelt "bendng" is named, not reported as a zero bending
  l.reject_unknown({"tension", "bending", "final_displacement", "programme", "initial_step (InitialLoadStepSize)",
                    "min_step (MinLoadStepSize)", "max_step (MaxLoadStepSize)", "adaptive", "predictor",
                    "max_ruptures_per_step"});
  // damage = "auto": history only where the path unloads (monotonic loading never reads it)
  if (d.mortar.damage_auto)
    d.mortar.damage = L.unloads() ? cohesive::Damage::irreversible : cohesive::Damage::reversible;
  if (L.tension == 0 && L.bending == 0)
    l.fail("tension", "tension and bending are both zero; expected at least one non-zero load component");
  check_bracket(l, "initial_step", L.initial_step, L.min_step, L.max_step, "min_step");
  // (a [dynamics] deck has no load steps; its reader rejects these keys)
  if (!top.table()->contains("dynamics") && L.programme.empty() && L.initial_step > L.final_displacement)
    l.fail("initial_step", "first increment exceeds final_displacement; expected initial_step <= final_displacement");
}

}  // namespace nacre::deck::detail
