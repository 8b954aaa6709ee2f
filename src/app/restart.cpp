// Checkpoint fingerprints and their comparison with the deck (issue 6 point 2).
#include <nacre/app/restart.hpp>

#include <Kokkos_Core.hpp>

#include <cstdio>
#include <sstream>
#include <vector>

#ifndef NACRE_VERSION
#define NACRE_VERSION "unknown"
#endif

namespace nacre::app {

std::string physics_text(const deck::Deck& d) {
  return d.canonical + "nacre.version = \"" NACRE_VERSION "\"\nnacre.backend = \"" +
         std::string(Kokkos::DefaultExecutionSpace::name()) + "\"\n";
}

std::string fingerprint(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  char b[20];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

namespace {
std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}
std::string key_of(const std::string& line) { return line.substr(0, line.find(" = ")); }
}  // namespace

void check_fingerprint(const io::Checkpoint& c, const deck::Deck& d, const std::string& path) {
  const std::string mine = physics_text(d);
  if (c.fingerprint == fingerprint(mine)) return;
  std::string diff;
  const auto it = c.strings.find("deck");
  if (it != c.strings.end()) {
    // first key whose line differs, reported with both values
    const auto a = lines_of(it->second), b = lines_of(mine);
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
      if (i < a.size() && j < b.size() && a[i] == b[j]) {
        ++i, ++j;
        continue;
      }
      if (i < a.size() && j < b.size() && key_of(a[i]) == key_of(b[j])) {
        diff = a[i] + " in the checkpoint, " + b[j].substr(b[j].find(" = ") + 3) + " in " + d.path;
      } else if (j >= b.size() || (i < a.size() && key_of(a[i]) < key_of(b[j]))) {
        diff = a[i] + " in the checkpoint, not set in " + d.path;
      } else {
        diff = b[j] + " in " + d.path + ", not set in the checkpoint's deck";
      }
      break;
    }
  }
  throw io::CheckpointError(path + ": written by a different deck or build (fingerprint " + c.fingerprint +
                            ", this deck and build give " + fingerprint(mine) + ")" +
                            (diff.empty() ? "" : ": " + diff) +
                            "; restart with the deck that made it (output keys may differ)");
}

}  // namespace nacre::app
