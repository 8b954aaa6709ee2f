// SPDX-License-Identifier: BSD-3-Clause
// The bare bitsliced AES core on one thread, without the Kokkos kernel: where the time goes.
//
//   nacre_aes_core_bench [--rounds=5] [--min-time=0.3]
//
// Compiled like src/aes (-march=native under NACRE_AES_NATIVE). For the host word it times, per
// CPU second and interleaved over --rounds rounds: the whole cipher on the build's path
// (encrypt_blocks_io: the GFNI transposition where available), the whole cipher on the portable
// SWAPMOVE transposition with the same rounds, and the phases (each transposition pair alone, the
// rounds alone). Buffer: 64 chunks of 512 blocks (512 KiB, L2-resident). Prints CSV:
//   what,round,ns_per_chunk,gbit_per_cpu_s
// and checks both paths against each other first (nonzero exit on a mismatch).
#include <nacre/aes/bitsliced.hpp>

#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace bs = nacre::aes::bitslice;
using W = bs::HostWord;
using L = bs::WordTraits<W>::lane;
constexpr int kB = bs::kBlocks<W>;
constexpr int kChunks = 64;

double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

__attribute__((noinline)) void portable_cipher(const L* masks, L* blocks) {
  alignas(64) W a[128], b[128];
  bs::load_state<W>(blocks, a);
  bs::encrypt_state<W>(a, b, masks);
  bs::store_state<W>(a, blocks);
}

__attribute__((noinline)) void build_cipher(const L* masks, L* blocks) {
  if constexpr (bs::kDirectIO<W>) {
    bs::encrypt_blocks_io<W>(masks, reinterpret_cast<const unsigned char*>(blocks),
                             reinterpret_cast<unsigned char*>(blocks));
  } else {
    bs::encrypt_blocks<W>(masks, blocks);
  }
}

__attribute__((noinline)) void portable_transpose(const L*, L* blocks) {
  alignas(64) W a[128];
  bs::load_state<W>(blocks, a);
  bs::store_state<W>(a, blocks);
}

#ifdef NACRE_AES_GFNI_TRANSPOSE
__attribute__((noinline)) void gfni_transpose(const L*, L* blocks) {
  alignas(64) W a[128], t[128];
  bs::gfni::load_state(blocks, reinterpret_cast<__m512i*>(a), reinterpret_cast<__m512i*>(t));
  bs::gfni::store_state(reinterpret_cast<const __m512i*>(a), blocks,
                        reinterpret_cast<__m512i*>(t));
}
#endif

W g_state[128];
__attribute__((noinline)) void rounds_only(const L* masks, L*) {
  alignas(64) W b[128];
  bs::encrypt_state<W>(g_state, b, masks);
}

}  // namespace

int main(int argc, char* argv[]) {
  int rounds = 5;
  double min_time = 0.3;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (a.starts_with("--rounds=")) rounds = std::stoi(std::string(a.substr(9)));
    else if (a.starts_with("--min-time=")) min_time = std::stod(std::string(a.substr(11)));
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  nacre::aes::Key128 key{};
  for (int i = 0; i < 16; ++i) key.bytes[i] = std::uint8_t(0x11 * i + 3);
  std::vector<L> masks(bs::kMaskCount);
  bs::round_key_masks<L>(nacre::aes::expand_key(key), masks.data());
  const std::size_t lanes = std::size_t(kChunks) * kB * bs::kLanesPerBlock<W>;
  std::vector<L> buf(lanes + 8), ref(lanes);
  L* b = reinterpret_cast<L*>((reinterpret_cast<std::uintptr_t>(buf.data()) + 63) & ~std::uintptr_t(63));
  for (std::size_t i = 0; i < lanes; ++i) b[i] = L(i * 0x9E3779B97F4A7C15ull);
  std::memcpy(ref.data(), b, lanes * sizeof(L));
  for (int c = 0; c < kChunks; ++c) build_cipher(masks.data(), b + std::size_t(c) * lanes / kChunks);
  for (int c = 0; c < kChunks; ++c) portable_cipher(masks.data(), ref.data() + std::size_t(c) * lanes / kChunks);
  if (std::memcmp(ref.data(), b, lanes * sizeof(L)) != 0) {
    std::fprintf(stderr, "mismatch between the build's path and the portable path\n");
    return 1;
  }
  struct Case {
    const char* name;
    void (*f)(const L*, L*);
  };
  std::vector<Case> cases = {{"cipher (build path)", build_cipher},
                             {"cipher (portable transposition)", portable_cipher},
                             {"transposition pair (portable)", portable_transpose},
                             {"rounds only", rounds_only}};
#ifdef NACRE_AES_GFNI_TRANSPOSE
  cases.insert(cases.begin() + 3, {"transposition pair (GFNI)", gfni_transpose});
#endif
  std::fprintf(stderr, "word %s, %d blocks per chunk, GFNI transposition %s\n",
               bs::WordTraits<W>::name, kB, bs::kGfniTranspose<W> ? "yes" : "no");
  std::printf("what,round,ns_per_chunk,gbit_per_cpu_s\n");
  for (int r = 1; r <= rounds; ++r)
    for (const Case& c : cases) {
      long n = 0;
      const double t0 = cpu_now();
      double t = t0;
      do {
        for (int k = 0; k < kChunks; ++k) c.f(masks.data(), b + std::size_t(k) * lanes / kChunks);
        n += kChunks;
        t = cpu_now();
      } while (t - t0 < min_time);
      const double per = (t - t0) / double(n);
      std::printf("%s,%d,%.1f,%.3f\n", c.name, r, per * 1e9, 128.0 * kB / per / 1e9);
    }
  return 0;
}
