// SPDX-License-Identifier: BSD-3-Clause
// Atomic file commits: temporary + close + fsync + rename + directory fsync, each step checked;
// a failure removes the temporary and names the file and errno text.
#include <nacre/io/atomic_file.hpp>

#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sstream>
#include <string_view>
#include <sys/stat.h>
#include <unistd.h>

namespace nacre::io {

namespace {
std::filesystem::path temp_name(const std::filesystem::path& target) {
  return target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
}

/// \brief fsync a file (or directory) by path; returns 0 or the errno of the failing call.
int fsync_path(const std::filesystem::path& p, bool directory) {
  const int fd = ::open(p.empty() ? "." : p.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return errno;
  int err = 0;
  if (::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  // Directories on some file systems do not support fsync; that is not a data loss.
  if (directory && (err == EINVAL || err == EROFS || err == EBADF)) err = 0;
  return err;
}
}  // namespace

std::string write_error_message(const std::filesystem::path& target, int err, const std::string& what) {
  std::string m = "cannot write " + target.string() + ": ";
  if (!what.empty()) m += what + ": ";
  m += err ? std::strerror(err) : "unknown error";
  m += "; the previous " + target.filename().string() + " (if any) is unchanged";
  return m;
}

int injected_write_failure(const std::filesystem::path& target) {
  const char* env = std::getenv("NACRE_INJECT_WRITE_FAILURE");
  if (!env || !*env) return 0;
  const std::string name = target.filename().string();
  std::string_view list(env);
  while (!list.empty()) {
    const auto comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    if (item == "*" || item == name) return ENOSPC;
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return 0;
}

void injected_kill_after_commit(const std::filesystem::path& target) {
  static int seen = 0;  // commits of the named file so far
  const char* env = std::getenv("NACRE_INJECT_KILL_AFTER");
  if (!env || !*env) return;
  const std::string_view spec(env);
  const auto colon = spec.find(':');
  if (spec.substr(0, colon) != target.filename().string()) return;
  const int n = colon == std::string_view::npos ? 1 : std::atoi(std::string(spec.substr(colon + 1)).c_str());
  if (++seen >= n) ::kill(::getpid(), SIGKILL);
}

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  AtomicPath ap(path);
  const int fd = ::open(ap.temp().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(write_error_message(path, errno, "cannot create " + ap.temp().filename().string()));
  std::size_t done = 0;
  int err = 0;
  while (done < content.size()) {
    const ssize_t w = ::write(fd, content.data() + done, content.size() - done);
    if (w < 0) {
      if (errno == EINTR) continue;
      err = errno;
      break;
    }
    done += static_cast<std::size_t>(w);
  }
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err) throw WriteError(write_error_message(path, err));  // ~AtomicPath removes the temporary
  ap.commit();
}

AtomicPath::AtomicPath(std::filesystem::path target) : target_(std::move(target)), temp_(temp_name(target_)) {}

AtomicPath::~AtomicPath() {
  if (!done_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicPath::commit() {
  int err = injected_write_failure(target_);
  if (!err) err = fsync_path(temp_, false);
  if (err) throw WriteError(write_error_message(target_, err));  // the destructor removes temp_
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) throw WriteError(write_error_message(target_, ec.value(), "rename"));
  done_ = true;
  // The rename is durable once the directory entry is; an error here leaves the new file in place.
  if (const int derr = fsync_path(target_.parent_path(), true))
    throw WriteError(write_error_message(target_.parent_path(), derr, "directory sync after renaming " +
                                                                          target_.filename().string()));
  injected_kill_after_commit(target_);
}

int remove_stale_temporaries(const std::filesystem::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    // ".NAME.tmpPID" with PID all digits
    const auto pos = n.rfind(".tmp");
    if (n.size() < 6 || n[0] != '.' || pos == std::string::npos || pos == 0 || pos + 4 >= n.size()) continue;
    long pid = 0;
    const char* b = n.data() + pos + 4;
    const char* end = n.data() + n.size();
    const auto [p, perr] = std::from_chars(b, end, pid);
    if (perr != std::errc() || p != end || pid <= 0) continue;
    // a live writer (another nacre on the same directory) keeps its temporary
    if (pid != ::getpid() && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM)) continue;
    std::error_code rec;
    if (e.is_regular_file(rec) && std::filesystem::remove(e.path(), rec)) ++removed;
  }
  return removed;
}

}  // namespace nacre::io
