// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Atomic outputs: write a temporary beside the target, close and fsync it with every
/// error checked, and only then rename it over the target (and fsync the directory), so a reader,
/// a crash or a full disk never leaves a half-written file under a final name. A failed write
/// removes the temporary, leaves the previous file untouched and throws WriteError naming the
/// file and the OS error.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace nacre::io {

/// \brief An output could not be written; what() names the file and the OS error (errno text).
class WriteError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// \brief "cannot write PATH: STRERROR(err); the previous PATH (if any) is unchanged".
[[nodiscard]] std::string write_error_message(const std::filesystem::path& target, int err,
                                              const std::string& what = "");

/// \brief Write `content` to `path` atomically. Throws WriteError.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

/// \brief A temporary sibling path for writers that need a file name (HDF5): write there, close
/// the file (checking the close), then commit() syncs and renames it onto the target; destroyed
/// uncommitted (or after a failed commit), the temporary is removed.
class AtomicPath {
public:
  explicit AtomicPath(std::filesystem::path target);
  ~AtomicPath();
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;
  [[nodiscard]] const std::filesystem::path& temp() const { return temp_; }
  [[nodiscard]] const std::filesystem::path& target() const { return target_; }
  /// \brief fsync the temporary, rename it onto the target, fsync the directory. Throws
  /// WriteError (temporary removed, target untouched) on any failure.
  void commit();

private:
  std::filesystem::path target_, temp_;
  bool done_ = false;
};

/// \brief Temporaries are named ".NAME.tmpPID". Removes those in `dir` whose process is gone
/// (a run killed mid-write); returns how many were removed.
int remove_stale_temporaries(const std::filesystem::path& dir);

/// \brief Test hook: when the environment variable NACRE_INJECT_WRITE_FAILURE holds a
/// comma-separated list of file names (or "*"), committing a file of that name fails as a full
/// disk would (ENOSPC at fsync). Returns the injected errno, or 0.
[[nodiscard]] int injected_write_failure(const std::filesystem::path& target);

/// \brief Test hook: NACRE_INJECT_KILL_AFTER="NAME:N" kills the process (SIGKILL) right after
/// the N-th commit of a file NAME, to test what a restart finds after a crash at that point.
void injected_kill_after_commit(const std::filesystem::path& target);

}  // namespace nacre::io
