// SPDX-License-Identifier: BSD-3-Clause
// [output]: where and what a run writes.
#include "../section.hpp"

namespace nacre::deck::detail {

void read_output(Section& top, Deck& d) {
  Section o = top.sub("output");
  auto& O = d.output;
  o.string("directory", O.directory, {}, "a non-empty path");
  o.integer("dump_interval", {"DumpInter"}, O.dump_interval, 0, 100000000, "a load-step count >= 0");
  o.boolean("hdf5", O.hdf5);
  o.boolean("charts", O.charts);
  o.boolean("progress", O.progress);
  o.number("heartbeat", {}, O.heartbeat, [](double v) { return v >= 0 && v <= 1e9; }, "seconds >= 0 (0: none)");
  o.reject_unknown({"directory", "dump_interval (DumpInter)", "hdf5", "charts", "progress", "heartbeat"});
}

}  // namespace nacre::deck::detail
