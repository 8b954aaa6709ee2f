// [load]: the prescribed-displacement pattern and the load-step programme (required section).
#include "../section.hpp"

namespace nacre::deck::detail {

void read_load(Section& top, Deck& d) {
  Section l = top.sub("load");
  if (!l.present()) top.fail("load", "missing section; expected a [load] table");
  auto& L = d.load;
  l.number("tension", {}, L.tension, [](double) { return true; }, "a number");
  l.number("bending", {}, L.bending, [](double) { return true; }, "a number");
  l.number("final_displacement", {}, L.final_displacement, positive, "a positive displacement", true);
  l.number("initial_step", {"InitialLoadStepSize"}, L.initial_step, positive, "a positive displacement");
  L.min_step = L.max_step = L.initial_step;
  l.number("min_step", {"MinLoadStepSize"}, L.min_step, positive, "a positive displacement");
  l.number("max_step", {"MaxLoadStepSize"}, L.max_step, positive, "a positive displacement");
  l.boolean("adaptive", L.adaptive);
  l.boolean("predictor", L.predictor);
  l.integer("max_ruptures_per_step", {}, L.max_ruptures_per_step, 0, 1000000000,
            "an interface count >= 0 (0: no snap-back control)");
  // unknown keys first: a misspelt "bendng" is named, not reported as a zero bending
  l.reject_unknown({"tension", "bending", "final_displacement", "initial_step (InitialLoadStepSize)",
                    "min_step (MinLoadStepSize)", "max_step (MaxLoadStepSize)", "adaptive", "predictor",
                    "max_ruptures_per_step"});
  if (L.tension == 0 && L.bending == 0)
    l.fail("tension", "tension and bending are both zero; expected at least one non-zero load component");
  check_bracket(l, "initial_step", L.initial_step, L.min_step, L.max_step, "min_step");
  // (a [dynamics] deck has no load steps; its reader rejects these keys)
  if (!top.table()->contains("dynamics") && L.initial_step > L.final_displacement)
    l.fail("initial_step", "first increment exceeds final_displacement; expected initial_step <= final_displacement");
}

}  // namespace nacre::deck::detail
