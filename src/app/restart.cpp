// SPDX-License-Identifier: BSD-3-Clause
// Checkpoint fingerprints and their comparison with the deck.
#include <nacre/app/restart.hpp>
#include <nacre/core/build_info.hpp>

#include <Kokkos_Core.hpp>

#include <cstdio>
#include <map>
#include <sstream>

namespace nacre::app {

std::string physics_text(const deck::Deck& d) {
  return d.canonical + "nacre.version = \"" + build_info().version + "\"\nnacre.backend = \"" +
         std::string(Kokkos::DefaultExecutionSpace::name()) + "\"\n";
}

void check_restart_backend(const std::string& checkpoint_path, const std::string& written_on, const std::string& here) {
  // (a checkpoint older than the record was written on the build's default backend: its
  // fingerprint names the build's default space)
  const std::string on = written_on.empty() ? Backend::names().front() : written_on;
  if (Backend::bit_compatible(here, on)) return;
  throw io::CheckpointError(checkpoint_path + ": written on " + on + ", whose results are not bit for bit " + here +
                            "'s (a device's arithmetic differs from the host's), so the run would not " +
                            "continue as it began; restart it with --backend " + on + ", or start afresh on " + here);
}

std::string fingerprint(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  char b[20];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

namespace {
/// \brief "key = value" lines as an ordered map (keys are unique in a physics text).
std::map<std::string, std::string> entries(const std::string& s) {
  std::map<std::string, std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) {
    const auto eq = l.find(" = ");
    if (eq != std::string::npos) out[l.substr(0, eq)] = l.substr(eq + 3);
  }
  return out;
}
}  // namespace

void check_fingerprint(const io::Checkpoint& c, const deck::Deck& d, const std::string& path) {
  const std::string mine = physics_text(d);
  if (c.fingerprint == fingerprint(mine)) return;
  std::string diff;
  if (const auto it = c.strings.find("deck"); it != c.strings.end()) {
    // the first key (in name order) whose value differs or that only one side sets
    const auto a = entries(it->second), b = entries(mine);
    auto ia = a.begin();
    auto ib = b.begin();
    while (ia != a.end() || ib != b.end()) {
      if (ia != a.end() && ib != b.end() && ia->first == ib->first) {
        if (ia->second != ib->second) {
          diff = ia->first + " = " + ia->second + " in the checkpoint, " + ib->second + " in " + d.path;
          break;
        }
        ++ia, ++ib;
      } else if (ib == b.end() || (ia != a.end() && ia->first < ib->first)) {
        diff = ia->first + " = " + ia->second + " in the checkpoint, not set in " + d.path;
        break;
      } else {
        diff = ib->first + " = " + ib->second + " in " + d.path + ", not set in the checkpoint's deck";
        break;
      }
    }
  }
  throw io::CheckpointError(path + ": written by a different deck or build (fingerprint " + c.fingerprint +
                            ", this deck and build give " + fingerprint(mine) + ")" +
                            (diff.empty() ? "" : ": " + diff) +
                            "; restart with the deck that made it (output keys may differ)");
}

void check_state_arrays(const io::Checkpoint& c, const std::vector<std::string>& names,
                        const std::string& checkpoint_path) {
  for (const auto& name : names)
    if (!c.arrays.count(name))
      throw io::CheckpointError(checkpoint_path + ": array '" + name +
                                "' missing: the checkpoint was written by an older nacre, whose state lacks it; "
                                "run the deck again from the start (without --restart)");
}

}  // namespace nacre::app
