// SPDX-License-Identifier: BSD-3-Clause
// nacre's own tables read back by column (io/csv.hpp).
#include <nacre/io/csv.hpp>

#include <cstdlib>
#include <stdexcept>

namespace nacre::io {

namespace {
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> f;
  std::size_t a = 0;
  while (true) {
    const std::size_t b = line.find(',', a);
    f.push_back(line.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) return f;
    a = b + 1;
  }
}
}  // namespace

std::optional<std::size_t> CsvTable::column(const std::string& name) const {
  for (std::size_t k = 0; k < header.size(); ++k)
    if (header[k] == name) return k;
  return std::nullopt;
}

std::vector<double> CsvTable::numbers(const std::string& name) const {
  const auto k = column(name);
  if (!k) throw std::runtime_error("no column '" + name + "'");
  std::vector<double> v;
  v.reserve(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::string& s = rows[r][*k];
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size())
      throw std::runtime_error("column '" + name + "', row " + std::to_string(r + 1) + ": '" + s + "' is not a number");
    v.push_back(x);
  }
  return v;
}

CsvTable parse_csv(const std::string& text, const std::string& what) {
  CsvTable t;
  std::size_t a = 0, line_no = 0;
  while (a < text.size()) {
    std::size_t b = text.find('\n', a);
    if (b == std::string::npos) b = text.size();
    std::string line = text.substr(a, b - a);
    a = b + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (t.header.empty()) {
      t.header = fields(line);
      continue;
    }
    auto f = fields(line);
    if (f.size() != t.header.size())
      throw std::runtime_error(what + ":" + std::to_string(line_no) + ": " + std::to_string(f.size()) +
                               " fields where the header has " + std::to_string(t.header.size()));
    t.rows.push_back(std::move(f));
  }
  return t;
}

}  // namespace nacre::io
