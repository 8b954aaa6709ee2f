// SPDX-License-Identifier: BSD-3-Clause
// Raw output of nacre's generators on stdout, for dieharder (-g 200 reads raw binary on stdin).
//
//   nacre_rng_stream --gen=aes-ctr|mt-aes|philox|mt [--seed=N] [--streams=S] [--bytes=N]
//
// For draw d = 0, 1, 2, ... and stream s = 0 .. S-1 it writes the four 64-bit words behind the
// stream's four uniforms (block 0 low, high; block 1 low, high; little-endian), i.e. exactly the
// bits the Monte Carlo solver turns into doubles, in the order a sweep consumes them.
//   aes-ctr: AES_k(s || 2d+h)                           (nacre::aes::AesCtrSource)
//   mt-aes:  AES_k(MT_s output) — the dissertation's pipeline (nacre::aes::MtAesSource)
//   philox:  Philox4x32-10, key = seed, counter (s, 2d+h) (nacre::rng::PhiloxSource's mapping)
//   mt:      the raw Mersenne Twister words mt-aes whitens (S <= 1024: 1024 interleaved MTs)
// --bytes=0 (default) streams until the reader closes the pipe.
#include <nacre/rng/aes_sources.hpp>
#include <nacre/rng/philox.hpp>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

int main(int argc, char* argv[]) {
  std::string gen = "aes-ctr";
  std::uint64_t seed = 20170601, bytes = 0;
  std::size_t streams = 1024;
  std::vector<char*> kargs{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (a.starts_with("--kokkos-")) kargs.push_back(argv[i]);
    else if (a.starts_with("--gen=")) gen = std::string(a.substr(6));
    else if (a.starts_with("--seed=")) seed = std::stoull(std::string(a.substr(7)));
    else if (a.starts_with("--streams=")) streams = std::stoull(std::string(a.substr(10)));
    else if (a.starts_with("--bytes=")) bytes = std::stoull(std::string(a.substr(8)));
    else {
      std::fprintf(stderr, "usage: %s --gen=aes-ctr|mt-aes|philox|mt [--seed=N] [--streams=S] "
                           "[--bytes=N]\n", argv[0]);
      return 2;
    }
  }
  if (gen == "mt" && streams > std::size_t(nacre::aes::MtAesSource::kMtStreams)) {
    std::fprintf(stderr, "--gen=mt needs --streams <= %d (one per Mersenne Twister)\n",
                 nacre::aes::MtAesSource::kMtStreams);
    return 2;
  }
  std::signal(SIGPIPE, SIG_DFL);
  int kargc = int(kargs.size());
  Kokkos::ScopeGuard guard(kargc, kargs.data());
  {
    Kokkos::View<std::uint64_t*, nacre::MemSpace> ids("ids", streams);
    Kokkos::parallel_for("ids", Kokkos::RangePolicy<nacre::ExecSpace>(0, streams),
                         KOKKOS_LAMBDA(const std::size_t i) { ids(i) = i; });
    nacre::aes::BitsTable<> bits("bits", streams);
    auto host = Kokkos::create_mirror_view(bits);
    nacre::aes::AesCtrSource ctr(seed);
    nacre::aes::MtAesSource mt(seed);
    std::vector<std::uint64_t> out(4 * streams);
    std::uint64_t written = 0;
    for (std::uint64_t d = 0; bytes == 0 || written < bytes; ++d) {
      if (gen == "aes-ctr") ctr.fill_bits(d, ids, bits);
      else if (gen == "mt-aes") mt.fill_bits(d, ids, bits);
      else if (gen == "mt") mt.fill_plain_bits(d, ids, bits);
      else if (gen == "philox") {
        const std::uint32_t k0 = std::uint32_t(seed), k1 = std::uint32_t(seed >> 32);
        Kokkos::parallel_for(
            "philox_bits", Kokkos::RangePolicy<nacre::ExecSpace>(0, streams),
            KOKKOS_LAMBDA(const std::size_t i) {
              const std::uint64_t s = ids(i);
              for (int h = 0; h < 2; ++h) {
                const std::uint64_t c = 2 * d + std::uint64_t(h);
                const nacre::rng::Block128 ctrb{{std::uint32_t(s), std::uint32_t(s >> 32),
                                                 std::uint32_t(c), std::uint32_t(c >> 32)}};
                const auto r = nacre::rng::philox4x32_10(ctrb, k0, k1);
                bits(i, 2 * h) = (std::uint64_t(r.w[1]) << 32) | r.w[0];
                bits(i, 2 * h + 1) = (std::uint64_t(r.w[3]) << 32) | r.w[2];
              }
            });
      } else {
        std::fprintf(stderr, "unknown generator %s\n", gen.c_str());
        return 2;
      }
      Kokkos::deep_copy(host, bits);
      for (std::size_t i = 0; i < streams; ++i)
        for (int c = 0; c < 4; ++c) out[4 * i + std::size_t(c)] = host(i, c);
      std::size_t n = out.size() * sizeof(std::uint64_t);
      if (bytes && written + n > bytes) n = std::size_t(bytes - written);
      if (std::fwrite(out.data(), 1, n, stdout) != n) break;  // reader closed the pipe
      written += n;
    }
    std::fflush(stdout);
  }
  return 0;
}
