// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/app/run.hpp>

int main(int argc, char* argv[]) { return nacre::app::main(argc, argv); }
