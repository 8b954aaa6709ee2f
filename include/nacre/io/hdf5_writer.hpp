#pragma once
/// \file
/// \brief A thin RAII layer over the HDF5 C API: create a file, groups, 1-D/2-D datasets and
/// scalar attributes. Enough for nacre's dumps and checkpoints, nothing more.
#include <cstdint>
#include <string>
#include <vector>

namespace nacre::io {

class H5Writer {
public:
  explicit H5Writer(const std::string& path);  ///< create/truncate
  ~H5Writer();
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
  long file_ = -1;
};

/// \brief Read back a dataset (for checkpoints and tests).
std::vector<double> h5_read_doubles(const std::string& path, const std::string& name);
double h5_read_attribute(const std::string& path, const std::string& name);
bool h5_has_dataset(const std::string& path, const std::string& name);
std::string h5_read_string_attribute(const std::string& path, const std::string& name);

}  // namespace nacre::io
