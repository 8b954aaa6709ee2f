// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A CSV table as nacre writes it (steps.csv, series.csv: a header line, then rows of
/// comma-separated fields without quoting), read back by name: the R-curve and `nacre sweep`'s
/// sweep.csv are computed from the tables the runs wrote.
#include <optional>
#include <string>
#include <vector>

namespace nacre::io {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  ///< each as long as the header

  /// \brief The column's index, or nullopt.
  [[nodiscard]] std::optional<std::size_t> column(const std::string& name) const;
  /// \brief The column as numbers (strtod; "nan" and "inf" read as such); throws
  /// std::runtime_error naming the column and row when a field is not a number or the column is absent.
  [[nodiscard]] std::vector<double> numbers(const std::string& name) const;
};

/// \brief Parse `text` (`what` names it in errors: a file path). A row with another field count
/// than the header throws std::runtime_error naming the line.
[[nodiscard]] CsvTable parse_csv(const std::string& text, const std::string& what);

}  // namespace nacre::io
