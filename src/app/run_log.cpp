// SPDX-License-Identifier: BSD-3-Clause
// The run's log.txt (run_log.hpp): a tee under std::cout and std::cerr.
#include "run_log.hpp"

#include <nacre/io/names.hpp>

#include <iostream>

namespace nacre::app {

namespace {
RunLog* g_active = nullptr;
}

RunLog::RunLog()
    : out_(std::cout.rdbuf(), *this), err_(std::cerr.rdbuf(), *this), alone_(nullptr, *this), file_only_(&alone_) {
  std::cout.flush();
  std::cout.rdbuf(&out_);
  std::cerr.rdbuf(&err_);
  g_active = this;
}

RunLog::~RunLog() {
  std::cout.flush();
  std::cerr.flush();
  std::cout.rdbuf(out_.terminal());
  std::cerr.rdbuf(err_.terminal());
  if (g_active == this) g_active = nullptr;
}

RunLog* RunLog::active() { return g_active; }

void RunLog::attach(const std::filesystem::path& dir, bool append_to) {
  if (attached_) return;
  attached_ = true;
  file_.open(dir / io::names::log, append_to ? std::ios::app : std::ios::trunc);
  if (!file_) {
    held_.clear();
    std::cerr << "nacre: warning: cannot write " << (dir / io::names::log).string() << "; the run goes on without it\n";
    return;
  }
  if (append_to) file_ << "nacre: --- restarted ---\n";
  file_ << held_;
  file_.flush();
  held_.clear();
}

void RunLog::append(const char* s, std::streamsize n) {
  if (!attached_) {
    held_.append(s, static_cast<std::size_t>(n));
    return;
  }
  if (!file_) return;
  file_.write(s, n);
  for (std::streamsize k = 0; k < n; ++k)
    if (s[k] == '\n') {
      file_.flush();  // line by line: a killed run's log ends at its last line
      break;
    }
}

int RunLog::Tee::overflow(int c) {
  if (c == traits_type::eof()) return traits_type::not_eof(c);
  const char ch = traits_type::to_char_type(c);
  return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
}

std::streamsize RunLog::Tee::xsputn(const char* s, std::streamsize n) {
  if (terminal_) terminal_->sputn(s, n);
  log_.append(s, n);
  return n;
}

int RunLog::Tee::sync() {
  if (terminal_) terminal_->pubsync();
  return 0;
}

}  // namespace nacre::app
