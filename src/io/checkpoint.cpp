// SPDX-License-Identifier: BSD-3-Clause
// Checkpoint of named arrays: write (atomic, checked close), read back with format and checksum
// verified. Solver-neutral: the solvers translate their state into names.
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/hdf5_writer.hpp>

#include <cstdio>
#include <cstring>

namespace nacre::io {

namespace {
// reserved root attribute names (not entries)
bool reserved(const std::string& n) {
  return n == "format" || n == "fingerprint" || n == "checksum" || H5Writer::is_build_attribute(n);
}

std::string hex(std::uint64_t v) {
  char b[20];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
  return b;
}

struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  }
  void size(std::size_t n) {
    const std::uint64_t v = n;
    bytes(&v, sizeof v);
  }
  void str(const std::string& s) {
    size(s.size());
    bytes(s.data(), s.size());
  }
};
}  // namespace

std::int64_t Checkpoint::integer(const std::string& n) const {
  auto it = integers.find(n);
  if (it == integers.end()) throw CheckpointError("checkpoint lacks the integer '" + n + "'");
  return it->second;
}
double Checkpoint::real(const std::string& n) const {
  auto it = reals.find(n);
  if (it == reals.end()) throw CheckpointError("checkpoint lacks the number '" + n + "'");
  return it->second;
}
const std::string& Checkpoint::string(const std::string& n) const {
  auto it = strings.find(n);
  if (it == strings.end()) throw CheckpointError("checkpoint lacks the string '" + n + "'");
  return it->second;
}
const std::vector<double>& Checkpoint::array(const std::string& n) const {
  auto it = arrays.find(n);
  if (it == arrays.end()) throw CheckpointError("checkpoint lacks the array '" + n + "'");
  return it->second;
}

std::uint64_t checksum(const Checkpoint& c) {
  Fnv f;
  f.str(c.fingerprint);
  f.size(c.integers.size());
  for (const auto& [n, v] : c.integers) f.str(n), f.bytes(&v, sizeof v);
  f.size(c.reals.size());
  for (const auto& [n, v] : c.reals) f.str(n), f.bytes(&v, sizeof v);
  f.size(c.strings.size());
  for (const auto& [n, v] : c.strings) f.str(n), f.str(v);
  f.size(c.arrays.size());
  for (const auto& [n, v] : c.arrays) f.str(n), f.size(v.size()), f.bytes(v.data(), v.size() * sizeof(double));
  return f.h;
}

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c) {
  auto check_name = [&](const std::string& n) {
    if (n.empty() || reserved(n) || n.find('/') != std::string::npos)
      throw std::invalid_argument("checkpoint entry name '" + n + "' is empty, reserved or holds '/'");
  };
  AtomicPath ap(path);
  try {
    H5Writer h(ap.temp().string());
    h.attribute("format", std::string(checkpoint_format));
    h.attribute("fingerprint", c.fingerprint);
    h.attribute("checksum", hex(checksum(c)));
    for (const auto& [n, v] : c.integers) check_name(n), h.attribute(n, v);
    for (const auto& [n, v] : c.reals) check_name(n), h.attribute(n, v);
    for (const auto& [n, v] : c.strings) check_name(n), h.attribute(n, v);
    h.group("/arrays");
    for (const auto& [n, v] : c.arrays) check_name(n), h.write("/arrays/" + n, v);
    h.close();
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const WriteError*>(&e)) throw;
    throw WriteError("cannot write " + path.string() + ": " + e.what() + "; the previous " +
                     path.filename().string() + " (if any) is unchanged");
  }
  ap.commit();
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  const std::string p = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw CheckpointError(p + ": is a directory; expected a checkpoint.h5 file");
  Checkpoint c;
  std::string stored;
  try {
    const H5Reader h(p);
    const auto attrs = h.attributes();
    auto kind = [&](const char* n) { auto it = attrs.find(n); return it == attrs.end() ? H5Reader::Kind::other : it->second; };
    if (kind("format") != H5Reader::Kind::string || h.string_attribute("format") != checkpoint_format)
      throw CheckpointError(p + ": not a nacre checkpoint (no format attribute \"" + std::string(checkpoint_format) +
                            "\"; checkpoints of older nacre versions cannot be restarted)");
    if (kind("fingerprint") != H5Reader::Kind::string || kind("checksum") != H5Reader::Kind::string)
      throw CheckpointError(p + ": checkpoint lacks its fingerprint or checksum");
    c.fingerprint = h.string_attribute("fingerprint");
    stored = h.string_attribute("checksum");
    for (const auto& [n, k] : attrs) {
      if (reserved(n)) continue;
      switch (k) {
        case H5Reader::Kind::integer: c.integers[n] = h.integer_attribute(n); break;
        case H5Reader::Kind::real: c.reals[n] = h.attribute(n); break;
        case H5Reader::Kind::string: c.strings[n] = h.string_attribute(n); break;
        default: throw CheckpointError(p + ": attribute '" + n + "' has an unexpected type");
      }
    }
    for (const auto& n : h.datasets("/arrays")) c.arrays[n] = h.doubles("/arrays/" + n);
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    throw CheckpointError(p + ": unreadable checkpoint (" + e.what() + ")");
  }
  const std::string computed = hex(checksum(c));
  if (stored != computed)
    throw CheckpointError(p + ": checksum mismatch (stored " + stored + ", content gives " + computed +
                          "): the file is corrupt; refusing to restart from it");
  return c;
}

}  // namespace nacre::io
