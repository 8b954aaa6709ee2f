// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A run directory keeps the run's log (log.txt): every line nacre writes to standard output and
// standard error during the run (log lines, heartbeats, warnings, the error that stopped it; not
// the live progress line), held in memory until the output directory exists, then appended to the
// file line by line, so the log of a killed run says where it stopped. A quiet run (-q) still
// logs: its log lines go to the file alone. One per process (rank 0 of an MPI run), installed by
// main() once the command line and the deck have passed; a restart appends to the log it continues.
#include <filesystem>
#include <fstream>
#include <ostream>
#include <streambuf>
#include <string>

namespace nacre::app {

class RunLog {
public:
  /// \brief Tee std::cout and std::cerr into the log (they still print as before).
  RunLog();
  ~RunLog();
  RunLog(const RunLog&) = delete;
  RunLog& operator=(const RunLog&) = delete;

  /// \brief The log installed in this process, or nullptr.
  static RunLog* active();

  /// \brief Write the log to `dir`/log.txt from now on (what was held first): afresh, or appended
  /// to the log of the run a restart continues (`append`). A log that cannot be opened is a
  /// warning; the run goes on.
  void attach(const std::filesystem::path& dir, bool append);

  /// \brief A stream to the log alone (a quiet run's log lines).
  [[nodiscard]] std::ostream& file_only() { return file_only_; }

private:
  class Tee : public std::streambuf {
  public:
    Tee(std::streambuf* terminal, RunLog& log) : terminal_(terminal), log_(log) {}
    [[nodiscard]] std::streambuf* terminal() const { return terminal_; }

  protected:
    int overflow(int c) override;
    std::streamsize xsputn(const char* s, std::streamsize n) override;
    int sync() override;

  private:
    std::streambuf* terminal_;  // nullptr: the log alone
    RunLog& log_;
  };
  void append(const char* s, std::streamsize n);

  Tee out_, err_, alone_;
  std::ostream file_only_;
  std::string held_;  // before attach()
  std::ofstream file_;
  bool attached_ = false;
};

}  // namespace nacre::app
