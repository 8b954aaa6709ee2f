// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A solver-neutral checkpoint: named arrays of doubles plus integer, real and string
/// attributes, a fingerprint of what fixes the physics and a checksum over all of it. io knows
/// no solver: the Monte Carlo solver (mc/checkpoint_arrays.hpp) and the dynamics solver
/// (dyn::StateArrays) translate their state to and from this form, and the caller compares the
/// fingerprint with its own (a mismatch is refused with a message naming the difference).
///
/// File layout (HDF5): root attributes `format`, `fingerprint`, `checksum` (16 hex digits,
/// FNV-1a 64 of the content, see checksum()), and one attribute per entry of integers / reals /
/// strings; one 1-D dataset per array under /arrays.
#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace nacre::io {

/// \brief A checkpoint that cannot be used (unreadable, corrupt, wrong kind, out of range, or a
/// different deck); what() names the file and what is wrong. The app exits 2 on it.
class CheckpointError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

struct Checkpoint {
  std::string fingerprint;  ///< what fixes the physics (deck, version, backend); compared by the caller
  std::map<std::string, std::int64_t> integers;
  std::map<std::string, double> reals;
  std::map<std::string, std::string> strings;
  std::map<std::string, std::vector<double>> arrays;

  /// \brief Accessors that throw CheckpointError naming the missing entry.
  [[nodiscard]] std::int64_t integer(const std::string& name) const;
  [[nodiscard]] double real(const std::string& name) const;
  [[nodiscard]] const std::string& string(const std::string& name) const;
  [[nodiscard]] const std::vector<double>& array(const std::string& name) const;
};

/// \brief FNV-1a 64 over the fingerprint and every entry (name, size, bytes) in name order: any
/// changed, added or removed byte changes it.
[[nodiscard]] std::uint64_t checksum(const Checkpoint& c);

/// \brief Write atomically (see atomic_file.hpp); throws WriteError.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c);

/// \brief Read and verify format and checksum; throws CheckpointError (never returns a
/// checkpoint whose bytes differ from what was written).
[[nodiscard]] Checkpoint read_checkpoint(const std::filesystem::path& path);

/// \brief The format tag written into every checkpoint.
inline constexpr const char* checkpoint_format = "nacre-checkpoint-1";

}  // namespace nacre::io
