// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The nacre command line: parse, validate, run a deck, write outputs.

namespace nacre::app {

/// \brief main() of the nacre executable; returns the process exit code
/// (0 success, 1 runtime failure, 2 bad command line or deck, 3 dynamic run stopped unstable).
int main(int argc, char* argv[]);

}  // namespace nacre::app
