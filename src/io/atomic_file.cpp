#include <nacre/io/atomic_file.hpp>

#include <cstdio>
#include <fcntl.h>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace nacre::io {

namespace {
std::filesystem::path temp_name(const std::filesystem::path& target) {
  return target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
}
void fsync_path(const std::filesystem::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}
}  // namespace

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  AtomicPath ap(path);
  std::FILE* f = std::fopen(ap.temp().c_str(), "wb");
  if (!f) throw std::system_error(errno, std::generic_category(), "cannot write " + ap.temp().string());
  const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() && std::fflush(f) == 0;
  std::fclose(f);
  if (!ok) throw std::runtime_error("write failed: " + ap.temp().string());
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
  fsync_path(temp_);
  std::filesystem::rename(temp_, target_);
  done_ = true;
}

}  // namespace nacre::io
