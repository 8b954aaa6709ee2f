// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/io/hdf5_writer.hpp>

#include <nacre/core/build_info.hpp>

#include <hdf5.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace nacre::io {

namespace {
void check(herr_t e, const std::string& what) {
  if (e < 0) throw std::runtime_error("HDF5: " + what);
}
/// \brief The OS error behind the HDF5 call that just failed: HDF5's file driver records it in
/// its error stack ("..., errno = 28, error message = ..."); errno itself as a fallback.
int failed_errno(int fallback) {
  int found = 0;
  auto walk = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    if (e && e->desc)
      if (const char* p = std::strstr(e->desc, "errno = ")) *static_cast<int*>(data) = std::atoi(p + 8);
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk, &found);
  return found ? found : fallback;
}
std::string os_error(int err) { return err ? std::string(": ") + std::strerror(err) : std::string(); }
}  // namespace

H5Writer::H5Writer(const std::string& path) : path_(path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become exceptions, not stderr noise
  errno = 0;
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw std::runtime_error("HDF5: cannot create " + path + os_error(failed_errno(errno)));
  // every file names the code that wrote it (core/build_info.hpp)
  const BuildInfo& b = build_info();
  attribute("nacre_version", b.version);
  attribute("nacre_commit", b.commit);
  attribute("kokkos_version", b.kokkos_version);
}

bool H5Writer::is_build_attribute(const std::string& name) {
  return name == "nacre_version" || name == "nacre_commit" || name == "kokkos_version";
}

H5Writer::~H5Writer() {
  if (file_ >= 0) H5Fclose(file_);
}

void H5Writer::close() {
  if (file_ < 0) return;
  errno = 0;
  const herr_t f = H5Fflush(file_, H5F_SCOPE_LOCAL);
  const int err_flush = f < 0 ? failed_errno(errno) : 0;
  errno = 0;
  const herr_t c = H5Fclose(file_);
  const int err_close = c < 0 ? failed_errno(errno) : 0;
  file_ = -1;
  if (f < 0 || c < 0)
    throw std::runtime_error("HDF5: cannot complete " + path_ + os_error(f < 0 ? err_flush : err_close));
}

void H5Writer::group(const std::string& name) {
  const hid_t g = H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (g < 0) throw std::runtime_error("HDF5: cannot create group " + name);
  H5Gclose(g);
}

template <class T>
void H5Writer::write_impl(const std::string& name, const std::vector<T>& v, std::size_t cols, long type) {
  const hsize_t dims[2] = {cols ? v.size() / cols : 0, cols};
  const hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  const hid_t ds = H5Dcreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds < 0) {
    const int err = failed_errno(errno);
    H5Sclose(space);
    throw std::runtime_error("HDF5: cannot create dataset " + name + " of " + path_ + os_error(err));
  }
  errno = 0;
  herr_t e = v.empty() ? 0 : H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  int err = e < 0 ? failed_errno(errno) : 0;
  if (H5Dclose(ds) < 0) {
    if (e >= 0) err = failed_errno(errno);
    e = -1;
  }
  H5Sclose(space);
  check(e, "cannot write dataset " + name + " of " + path_ + (e < 0 ? os_error(err) : ""));
}

void H5Writer::write(const std::string& n, const std::vector<double>& v, std::size_t c) { write_impl(n, v, c, H5T_NATIVE_DOUBLE); }
void H5Writer::write(const std::string& n, const std::vector<std::int32_t>& v, std::size_t c) { write_impl(n, v, c, H5T_NATIVE_INT32); }
void H5Writer::write(const std::string& n, const std::vector<std::int64_t>& v, std::size_t c) { write_impl(n, v, c, H5T_NATIVE_INT64); }
void H5Writer::write(const std::string& n, const std::vector<std::int8_t>& v, std::size_t c) { write_impl(n, v, c, H5T_NATIVE_INT8); }

namespace {
void scalar_attribute(hid_t file, const std::string& name, hid_t type, const void* v) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t e = a < 0 ? -1 : H5Awrite(a, type, v);
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  check(e, "attribute " + name);
}
}  // namespace

void H5Writer::attribute(const std::string& name, double v) { scalar_attribute(file_, name, H5T_NATIVE_DOUBLE, &v); }
void H5Writer::attribute(const std::string& name, std::int64_t v) { scalar_attribute(file_, name, H5T_NATIVE_INT64, &v); }

void H5Writer::attribute(const std::string& name, const std::string& v) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, v.size() + 1);
  scalar_attribute(file_, name, type, v.c_str());
  H5Tclose(type);
}

H5Reader::H5Reader(const std::string& path) : path_(path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) throw std::runtime_error("HDF5: cannot open " + path);
}

H5Reader::~H5Reader() {
  if (file_ >= 0) H5Fclose(file_);
}

namespace {
herr_t collect_attribute(hid_t loc, const char* name, const H5A_info_t*, void* op) {
  auto& out = *static_cast<std::map<std::string, H5Reader::Kind>*>(op);
  H5Reader::Kind k = H5Reader::Kind::other;
  const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  if (a >= 0) {
    const hid_t t = H5Aget_type(a);
    const hid_t s = H5Aget_space(a);
    if (H5Sget_simple_extent_type(s) == H5S_SCALAR) {
      switch (H5Tget_class(t)) {
        case H5T_INTEGER: k = H5Reader::Kind::integer; break;
        case H5T_FLOAT: k = H5Reader::Kind::real; break;
        case H5T_STRING: k = H5Reader::Kind::string; break;
        default: break;
      }
    }
    H5Sclose(s);
    H5Tclose(t);
    H5Aclose(a);
  }
  out[name] = k;
  return 0;
}
herr_t collect_dataset(hid_t group, const char* name, const H5L_info2_t*, void* op) {
  H5O_info2_t info;
  if (H5Oget_info_by_name3(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 && info.type == H5O_TYPE_DATASET)
    static_cast<std::vector<std::string>*>(op)->emplace_back(name);
  return 0;
}
}  // namespace

std::map<std::string, H5Reader::Kind> H5Reader::attributes() const {
  std::map<std::string, Kind> out;
  hsize_t idx = 0;
  check(H5Aiterate2(file_, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_attribute, &out), "cannot list attributes of " + path_);
  return out;
}

std::int64_t H5Reader::integer_attribute(const std::string& name) const {
  const hid_t a = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
  std::int64_t v = 0;
  const herr_t e = a < 0 ? -1 : H5Aread(a, H5T_NATIVE_INT64, &v);
  if (a >= 0) H5Aclose(a);
  check(e, "cannot read attribute " + name + " in " + path_);
  return v;
}

std::vector<std::string> H5Reader::datasets(const std::string& group) const {
  std::vector<std::string> out;
  if (H5Lexists(file_, group.c_str(), H5P_DEFAULT) <= 0) return out;
  const hid_t g = H5Gopen2(file_, group.c_str(), H5P_DEFAULT);
  if (g < 0) return out;
  hsize_t idx = 0;
  const herr_t e = H5Literate2(g, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_dataset, &out);
  H5Gclose(g);
  check(e, "cannot list " + group + " in " + path_);
  return out;
}

bool H5Reader::has(const std::string& dataset) const { return H5Lexists(file_, dataset.c_str(), H5P_DEFAULT) > 0; }

std::vector<double> H5Reader::doubles(const std::string& dataset) const {
  const hid_t ds = H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT);
  if (ds < 0) throw std::runtime_error("HDF5: no dataset " + dataset + " in " + path_);
  const hid_t space = H5Dget_space(ds);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<double> v(static_cast<std::size_t>(n));
  const herr_t e = n ? H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) : 0;
  H5Sclose(space);
  H5Dclose(ds);
  check(e, "cannot read " + dataset + " in " + path_);
  return v;
}

double H5Reader::attribute(const std::string& name) const {
  const hid_t a = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
  double v = 0;
  const herr_t e = a < 0 ? -1 : H5Aread(a, H5T_NATIVE_DOUBLE, &v);
  if (a >= 0) H5Aclose(a);
  check(e, "cannot read attribute " + name + " in " + path_);
  return v;
}

std::string H5Reader::string_attribute(const std::string& name) const {
  const hid_t a = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
  std::string v;
  herr_t e = -1;
  if (a >= 0) {
    const hid_t type = H5Aget_type(a);
    std::vector<char> buf(H5Tget_size(type) + 1, '\0');
    e = H5Aread(a, type, buf.data());
    v = buf.data();
    H5Tclose(type);
    H5Aclose(a);
  }
  check(e, "cannot read attribute " + name + " in " + path_);
  return v;
}

}  // namespace nacre::io
