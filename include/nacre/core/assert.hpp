// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief NACRE_ASSERT(cond, "what was expected"): a precondition of nacre's own code (a View's
/// extent, a size two arguments must share) checked in every build, on the host before a kernel
/// is launched or inside one. A failure is a bug in nacre or in a caller of its library, not bad
/// input (decks and checkpoints get named errors, exit 2): it aborts through Kokkos::abort with
/// "nacre: FILE:LINE: COND: WHAT", which every backend supports (device code may not throw or
/// print). The message is one string literal, assembled at compile time.
#include <Kokkos_Core.hpp>

#define NACRE_ASSERT_STR2(x) #x
#define NACRE_ASSERT_STR(x) NACRE_ASSERT_STR2(x)
#define NACRE_ASSERT(cond, what)                                                                          \
  do {                                                                                                    \
    if (!(cond)) ::Kokkos::abort("nacre: " __FILE__ ":" NACRE_ASSERT_STR(__LINE__) ": " #cond ": " what); \
  } while (false)
