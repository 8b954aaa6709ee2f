#pragma once
/// \file
/// \brief Atomic outputs: write beside the target, flush, then rename over it, so a reader (or
/// a crash) never sees a half-written file.
#include <filesystem>
#include <string>

namespace nacre::io {

/// \brief Write `content` to `path` atomically.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

/// \brief A temporary sibling path for writers that need a file name (HDF5): write there, then
/// commit() renames it onto the target; destroyed uncommitted, the temporary is removed.
class AtomicPath {
public:
  explicit AtomicPath(std::filesystem::path target);
  ~AtomicPath();
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;
  [[nodiscard]] const std::filesystem::path& temp() const { return temp_; }
  void commit();

private:
  std::filesystem::path target_, temp_;
  bool done_ = false;
};

}  // namespace nacre::io
