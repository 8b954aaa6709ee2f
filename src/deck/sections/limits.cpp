// SPDX-License-Identifier: BSD-3-Clause
// [limits]: what a deck may ask for before it is refused (checked by deck/limits.cpp from
// estimates, before anything is built); each limit is raised explicitly here.
#include "../section.hpp"

namespace nacre::deck::detail {

void read_limits(Section& top, Deck& d) {
  Section lim = top.sub("limits");
  auto& L = d.limits;
  lim.number("max_bricks", {}, L.max_bricks, positive, "a positive brick count");
  lim.number("max_load_steps", {}, L.max_load_steps, positive, "a positive load-step count");
  lim.number("max_time_steps", {}, L.max_time_steps, positive, "a positive time-step count");
  lim.number("max_memory_gib", {}, L.max_memory_gib, positive, "a positive memory size in GiB");
  lim.reject_unknown({"max_bricks", "max_load_steps", "max_time_steps", "max_memory_gib"});
}

}  // namespace nacre::deck::detail
