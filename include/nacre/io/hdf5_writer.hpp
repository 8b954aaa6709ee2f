// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A thin RAII layer over the HDF5 C API: create a file, groups, 1-D/2-D datasets and
/// scalar attributes. Enough for nacre's dumps and checkpoints, nothing more. Every HDF5 error,
/// the final close included, throws (with the OS error text where there is one).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace nacre::io {

class H5Writer {
public:
  /// \brief Create/truncate; the root gets the attributes nacre_version, nacre_commit and
  /// kokkos_version (core/build_info.hpp).
  explicit H5Writer(const std::string& path);
  /// \brief Whether `name` is one of the root attributes every file gets (readers skip them).
  [[nodiscard]] static bool is_build_attribute(const std::string& name);
  /// \brief Closes without checking (only reached on an error path: call close() to commit).
  ~H5Writer();
  /// \brief Flush and close the file; throws if HDF5 could not write it completely (full disk).
  void close();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  void group(const std::string& name);
  /// \brief Dataset `name` with shape (rows, cols) (cols = 1: a 1-D dataset), row-major data.
  void write(const std::string& name, const std::vector<double>& v, std::size_t cols = 1);
  void write(const std::string& name, const std::vector<std::int32_t>& v, std::size_t cols = 1);
  void write(const std::string& name, const std::vector<std::int64_t>& v, std::size_t cols = 1);
  void write(const std::string& name, const std::vector<std::int8_t>& v, std::size_t cols = 1);
  void attribute(const std::string& name, double v);
  void attribute(const std::string& name, std::int64_t v);
  void attribute(const std::string& name, const std::string& v);

private:
  template <class T>
  void write_impl(const std::string& name, const std::vector<T>& v, std::size_t cols, long type);
  std::string path_;
  long file_ = -1;
};

/// \brief Reads datasets and scalar attributes back (checkpoints, restarts); the file stays open
/// for the reader's lifetime.
class H5Reader {
public:
  explicit H5Reader(const std::string& path);
  ~H5Reader();
  H5Reader(const H5Reader&) = delete;
  H5Reader& operator=(const H5Reader&) = delete;

  [[nodiscard]] bool has(const std::string& dataset) const;
  [[nodiscard]] std::vector<double> doubles(const std::string& dataset) const;
  /// \brief A numeric scalar attribute, converted to double (exact for counts below 2^53).
  [[nodiscard]] double attribute(const std::string& name) const;
  [[nodiscard]] std::string string_attribute(const std::string& name) const;

private:
  std::string path_;
  long file_ = -1;

public:
  /// \brief Kind of a scalar attribute as stored.
  enum class Kind { integer, real, string, other };
  /// \brief Every scalar attribute of the root group with its kind.
  [[nodiscard]] std::map<std::string, Kind> attributes() const;
  [[nodiscard]] std::int64_t integer_attribute(const std::string& name) const;
  /// \brief Names of the datasets directly inside `group` (empty when it does not exist).
  [[nodiscard]] std::vector<std::string> datasets(const std::string& group) const;
};

}  // namespace nacre::io
