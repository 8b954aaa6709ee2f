// SPDX-License-Identifier: BSD-3-Clause
// Throughput of nacre's bitsliced AES-128-ECB, OpenSSL's AES-128-ECB and -CTR (EVP) and of
// random-number generators (Random123 Philox, nacre's Philox, AES-CTR and MT+AES sources).
//
//   nacre_aes_bench --mode=nacre   [--min-size=65536] [--max-size=1073741824] [--min-time=0.5]
//   nacre_aes_bench --mode=openssl [same] [--cipher=ecb|ctr]  (AES-NI masked off by
//                                  OPENSSL_ia32cap="~0x200000200000000" in the environment)
//   nacre_aes_bench --mode=rng     [--streams=1048576] [--min-time=0.5]
//   plus --label=NAME (column impl), --kind=NAME (column kind, default cipher / rng),
//   --rep=N (column rep, for interleaved repetitions) and any --kokkos-* option.
//
// Writes CSV rows to stdout:
//   kind,impl,threads,size_bytes,count,seconds,cpu_seconds,rate,rate_per_cpu,unit,rep
// kind = cipher: rate in Gbit/s of plaintext per wall second, rate_per_cpu per CPU second of the
// process (all its threads: the per-core rate, insensitive to time the machine's other users
// take); kind = rng: random doubles per second.
#include <nacre/aes/aes128.hpp>
#include <nacre/rng/aes_sources.hpp>
#include <nacre/rng/registry.hpp>

#include <Random123/philox.h>
#ifdef NACRE_HAVE_OPENSSL  // absent in the GPU runbook's bare build: --mode=openssl says so
#include <openssl/crypto.h>
#include <openssl/evp.h>
#endif

#include <chrono>
#include <ctime>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

struct Options {
  std::string mode = "nacre";
  std::string label;
  std::size_t min_size = 64 * 1024;
  std::size_t max_size = std::size_t(1) << 30;
  double min_time = 0.5;
  std::size_t streams = std::size_t(1) << 20;
  std::string cipher = "ecb";
  std::string kind;
  int rep = 0;
};

Options g_opt;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// CPU time of the whole process (all threads), seconds.
double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Timing {
  long reps;
  double seconds, cpu_seconds;
};

/// Run f repeatedly (after one warm-up call) until min_time has passed; wall and CPU time.
Timing time_it(double min_time, const std::function<void()>& f) {
  f();
  long reps = 0;
  const double t0 = now(), c0 = cpu_now();
  double t = t0;
  do {
    f();
    ++reps;
    t = now();
  } while (t - t0 < min_time);
  return {reps, t - t0, cpu_now() - c0};
}

void row(const char* kind, const std::string& impl, int threads, std::size_t size,
         std::size_t count, const Timing& tm, double amount, const char* unit) {
  const std::string k = g_opt.kind.empty() ? kind : g_opt.kind;
  std::printf("%s,%s,%d,%zu,%zu,%.6f,%.6f,%.6g,%.6g,%s,%d\n", k.c_str(), impl.c_str(), threads,
              size, count, tm.seconds, tm.cpu_seconds, amount / tm.seconds,
              amount / tm.cpu_seconds, unit, g_opt.rep);
  std::fflush(stdout);
}

std::vector<std::size_t> sizes(const Options& o) {
  std::vector<std::size_t> s;
  for (std::size_t n = o.min_size; n <= o.max_size; n *= 2) s.push_back(n);
  return s;
}

void bench_nacre(const Options& o) {
  const int threads = nacre::ExecSpace().concurrency();
  const std::string impl = o.label.empty() ? "nacre" : o.label;
  std::fprintf(stderr, "nacre AES layout: %s, %d threads\n",
               nacre::aes::aes128_layout_description().c_str(), threads);
  nacre::aes::Key128 key{};
  for (int i = 0; i < 16; ++i) key.bytes[i] = std::uint8_t(0x11 * i + 3);
  Kokkos::View<std::uint8_t*, nacre::MemSpace> buf(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "buf"), o.max_size);
  Kokkos::parallel_for("init", Kokkos::RangePolicy<nacre::ExecSpace>(0, o.max_size),
                       KOKKOS_LAMBDA(const std::size_t i) { buf(i) = std::uint8_t(i * 7); });
  for (const std::size_t n : sizes(o)) {
    auto v = Kokkos::subview(buf, std::make_pair(std::size_t(0), n));
    const Timing tm = time_it(o.min_time, [&] {
      nacre::aes::aes128_ecb_encrypt(key, v, v);
      Kokkos::fence();
    });
    row("cipher", impl, threads, n, std::size_t(tm.reps), tm, 8.0 * double(n) * tm.reps / 1e9,
        "Gbit/s");
  }
}

void bench_openssl(const Options& o) {
#ifndef NACRE_HAVE_OPENSSL
  (void)o;
  throw std::runtime_error("nacre_aes_bench was built without OpenSSL: --mode=openssl is not available");
#else
  const std::string impl = o.label.empty() ? "openssl-" + o.cipher : o.label;
  const char* cap = std::getenv("OPENSSL_ia32cap");
  std::fprintf(stderr, "OpenSSL %s, AES-128-%s, OPENSSL_ia32cap=%s\n",
               OpenSSL_version(OPENSSL_VERSION), o.cipher.c_str(), cap ? cap : "(unset)");
  if (o.cipher != "ecb" && o.cipher != "ctr") throw std::runtime_error("--cipher must be ecb or ctr");
  const EVP_CIPHER* cipher = o.cipher == "ctr" ? EVP_aes_128_ctr() : EVP_aes_128_ecb();
  unsigned char iv[16] = {};
  unsigned char key[16];
  for (int i = 0; i < 16; ++i) key[i] = std::uint8_t(0x11 * i + 3);
  std::vector<unsigned char> buf(o.max_size + 16);
  for (std::size_t i = 0; i < buf.size(); ++i) buf[i] = std::uint8_t(i * 7);
  EVP_CIPHER_CTX* ctx = EVP_CIPHER_CTX_new();
  if (!ctx || EVP_EncryptInit_ex(ctx, cipher, nullptr, key, iv) != 1)
    throw std::runtime_error("EVP init failed");
  EVP_CIPHER_CTX_set_padding(ctx, 0);
  for (const std::size_t n : sizes(o)) {
    const Timing tm = time_it(o.min_time, [&] {
      // EVP_EncryptUpdate takes an int length: feed at most 1 GiB - 16 per call.
      std::size_t done = 0;
      while (done < n) {
        const std::size_t m = std::min<std::size_t>(n - done, (std::size_t(1) << 30) - 16 * 1024);
        int len = 0;
        if (EVP_EncryptUpdate(ctx, buf.data() + done, &len, buf.data() + done, int(m)) != 1)
          throw std::runtime_error("EVP_EncryptUpdate failed");
        done += m;
      }
    });
    row("cipher", impl, 1, n, std::size_t(tm.reps), tm, 8.0 * double(n) * tm.reps / 1e9,
        "Gbit/s");
  }
  EVP_CIPHER_CTX_free(ctx);
#endif
}

/// Random123's Philox4x32-10 with nacre's (stream, 2 draw + half) counter mapping. (A named
/// functor rather than a lambda: device lambdas may not be nested in other lambdas.)
struct Random123Fill {
  nacre::rng::UniformTable<> u;
  std::uint64_t seed, d;
  KOKKOS_INLINE_FUNCTION void operator()(const std::size_t i) const {
    r123::Philox4x32 g;
    const r123::Philox4x32::key_type k = {{std::uint32_t(seed), std::uint32_t(seed >> 32)}};
    for (int h = 0; h < 2; ++h) {
      const std::uint64_t c = 2 * d + std::uint64_t(h);
      const r123::Philox4x32::ctr_type ctr = {{std::uint32_t(i), std::uint32_t(std::uint64_t(i) >> 32),
                                              std::uint32_t(c), std::uint32_t(c >> 32)}};
      const auto r = g(ctr, k);
      u(i, 2 * h) = nacre::rng::to_unit_double((std::uint64_t(r.v[1]) << 32) | r.v[0]);
      u(i, 2 * h + 1) = nacre::rng::to_unit_double((std::uint64_t(r.v[3]) << 32) | r.v[2]);
    }
  }
};

void bench_rng(const Options& o) {
  const int threads = nacre::ExecSpace().concurrency();
  const std::size_t n = o.streams;
  Kokkos::View<std::uint64_t*, nacre::MemSpace> ids("ids", n);
  Kokkos::parallel_for("ids", Kokkos::RangePolicy<nacre::ExecSpace>(0, n),
                       KOKKOS_LAMBDA(const std::size_t i) { ids(i) = i; });
  nacre::rng::UniformTable<> u("u", n);
  const std::size_t numbers = 4 * n;
  const std::uint64_t seed = 12345;

  {  // Random123's Philox4x32-10 (the reference implementation), 4 doubles per stream and draw.
    std::uint64_t draw = 0;
    const Timing tm = time_it(o.min_time, [&] {
      Kokkos::parallel_for("random123_philox", Kokkos::RangePolicy<nacre::ExecSpace>(0, n),
                           Random123Fill{u, seed, draw++});
      Kokkos::fence();
    });
    row("rng", "random123-philox", threads, 0, numbers * tm.reps, tm, double(numbers) * tm.reps,
        "numbers/s");
  }
  for (const char* kind : {"philox", "aes-ctr", "mt-aes"}) {
    auto src = nacre::rng::make_uniform_source(kind, seed);
    std::uint64_t draw = 0;
    const Timing tm = time_it(o.min_time, [&] {
      src->fill(draw++, ids, u);
      Kokkos::fence();
    });
    row("rng", std::string("nacre-") + kind, threads, 0, numbers * tm.reps, tm,
        double(numbers) * tm.reps, "numbers/s");
  }
}

std::size_t parse_size(std::string_view s) {
  std::size_t mult = 1;
  if (!s.empty() && (s.back() == 'K' || s.back() == 'k')) mult = 1024;
  if (!s.empty() && (s.back() == 'M' || s.back() == 'm')) mult = 1024 * 1024;
  if (!s.empty() && (s.back() == 'G' || s.back() == 'g')) mult = std::size_t(1) << 30;
  if (mult != 1) s.remove_suffix(1);
  return std::stoull(std::string(s)) * mult;
}

}  // namespace

int main(int argc, char* argv[]) {
  std::vector<char*> kargs{argv[0]};
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    auto val = [&](std::string_view key) -> std::string_view {
      return a.starts_with(key) ? a.substr(key.size()) : std::string_view();
    };
    if (a.starts_with("--kokkos-")) kargs.push_back(argv[i]);
    else if (a.starts_with("--mode=")) o.mode = val("--mode=");
    else if (a.starts_with("--label=")) o.label = val("--label=");
    else if (a.starts_with("--min-size=")) o.min_size = parse_size(val("--min-size="));
    else if (a.starts_with("--max-size=")) o.max_size = parse_size(val("--max-size="));
    else if (a.starts_with("--min-time=")) o.min_time = std::stod(std::string(val("--min-time=")));
    else if (a.starts_with("--streams=")) o.streams = parse_size(val("--streams="));
    else if (a.starts_with("--cipher=")) o.cipher = val("--cipher=");
    else if (a.starts_with("--kind=")) o.kind = val("--kind=");
    else if (a.starts_with("--rep=")) o.rep = std::stoi(std::string(val("--rep=")));
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  if (o.min_size % 16 || o.max_size % 16 || o.min_size == 0 || o.min_size > o.max_size) {
    std::fprintf(stderr, "sizes must be positive multiples of 16 with min <= max\n");
    return 2;
  }
  g_opt = o;
  int kargc = int(kargs.size());
  Kokkos::ScopeGuard guard(kargc, kargs.data());
  if (o.mode == "nacre") bench_nacre(o);
  else if (o.mode == "openssl") bench_openssl(o);
  else if (o.mode == "rng") bench_rng(o);
  else {
    std::fprintf(stderr, "unknown mode %s\n", o.mode.c_str());
    return 2;
  }
  return 0;
}
