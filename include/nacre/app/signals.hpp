// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief SIGINT / SIGTERM: the handler only records the signal in a lock-free atomic; the run
/// checks it between MC cycles, finishes the write in progress, writes a checkpoint of the last
/// completed step and exits 128 + signal (130, 143). The handler resets to the default action,
/// so a second Ctrl-C ends the process at once (outputs are atomic, nothing half-written).
namespace nacre::app {

/// \brief Installs the handlers for its lifetime (restores the previous ones after).
class SignalGuard {
public:
  SignalGuard();
  ~SignalGuard();
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;
};

/// \brief The first SIGINT/SIGTERM received while a SignalGuard lives, or 0.
[[nodiscard]] int pending_signal();

/// \brief "SIGINT" / "SIGTERM".
[[nodiscard]] const char* signal_name(int sig);

}  // namespace nacre::app
