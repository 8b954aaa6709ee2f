// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Everything a run of either solver family writes into its output directory, each file
/// atomically. Solver-neutral: a solver hands over a Snapshot of named brick / vertex / element /
/// interface fields, CSV rows it formatted itself and an io::Checkpoint; io knows no solver.
///  steps.csv | series.csv  one row per load step (Monte Carlo) or per csv_interval time steps
///  mesh.h5            static data: brick polygons, reference geometry, ids; the triangle mesh of
///                     a run with deformable bricks (written once)
///  dump_NNNNN.h5      the snapshot's fields (per dump; at least dump_digits digits)
///  nacre.xdmf         ParaView index of all dumps (rewritten after each dump)
///  summary.json       the solver's summary
///  checkpoint.h5      see checkpoint.hpp, through checkpoint()
/// Commit order, which a restart relies on: rows, then the dump and nacre.xdmf, then the
/// checkpoint; every file a checkpoint refers to is durable before it.
#include <nacre/geometry/specimen.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/names.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace nacre::io {

/// \brief Where a field lives: per brick (polygon cell), per vertex (of the brick polygons, or the
/// nodes of the triangle mesh), per element (triangles), per interface.
enum class Centre : std::uint8_t { brick, vertex, element, interface };

using FieldData = std::variant<std::vector<double>, std::vector<std::int32_t>, std::vector<std::int8_t>>;

/// \brief A named field. Stored at /bricks/NAME (brick fields; vertex fields without a triangle
/// mesh), /nodes/NAME and /triangles/NAME (vertex and element fields with one) or /interfaces/NAME with shape (size / components, components). Reserved names: vertex field
/// "points" (2 components) is the displaced brick geometry; interface field "points"
/// (2 components, two ends per interface) the interface geometry.
struct Field {
  Centre centre = Centre::brick;
  std::string name;
  FieldData data;
  std::size_t components = 1;
};

/// \brief One dump: its step, its time in the viewer (the MC solver uses the displacement D),
/// scalar attributes and fields in viewer order.
struct Snapshot {
  long step = 0;
  double time = 0;
  std::map<std::string, double> reals;
  std::map<std::string, std::int64_t> integers;
  std::vector<Field> fields;
};

/// \brief A dump file name "dump_NNNNN.h5" (digits only, at least one) gives its step; any other
/// name (dump_final.h5, dump_-3.h5, dump_7.h5.bak) gives nothing.
[[nodiscard]] std::optional<long> dump_step(const std::string& file_name);

/// \brief The triangle mesh of deformable bricks: node reference positions (x, y per node),
/// 3 node indices per triangle, the brick of each triangle.
struct TriangleMesh {
  std::vector<double> reference;
  std::vector<std::int32_t> connectivity;
  std::vector<std::int32_t> brick;
  [[nodiscard]] std::size_t nodes() const { return reference.size() / 2; }
  [[nodiscard]] std::size_t triangles() const { return brick.size(); }
};

class RunWriter {
public:
  struct Options {
    std::filesystem::path directory;
    bool hdf5 = true;
    std::string csv_header;              ///< first line of the table, with its newline
    std::string csv_name{names::mc_table};  ///< the table's file name
    int dump_digits = 5;                 ///< dump_%0*ld.h5: enough digits that names sort by step
    std::optional<TriangleMesh> elements;  ///< deformable bricks: their triangle mesh
  };
  /// \brief Continue an earlier run after `step` (restart): rows and dumps up to it are kept
  /// when `source_directory` is this directory; another directory is set up as for a new run
  /// (its own mesh.h5), and receives the source's rows up to `step`.
  struct Resume {
    long step = 0;
    std::filesystem::path source_directory;
  };

  /// \brief Creates the directory, removes stale temporaries and writes mesh.h5 (call only
  /// after the deck, and for a restart the checkpoint, validated: a new run removes the
  /// directory's earlier nacre files, a restart the dumps after its step).
  RunWriter(Options o, const geometry::Specimen& s, const geometry::Interfaces& f,
            const std::optional<Resume>& resume = std::nullopt);

  /// \brief Append one row (formatted by the solver, with its newline) for step `step`; the
  /// table is rewritten now (`durable`) or at the next flush_rows(), dump or checkpoint.
  void row(long step, const std::string& csv_line, bool durable = true);
  /// \brief Rewrite the table with every row so far (when a row is pending).
  void flush_rows();
  /// \brief HDF5 dump of a snapshot (rows first); nacre.xdmf is rewritten to include it.
  void dump(const Snapshot& snap);
  /// \brief checkpoint.h5, after the rows and dumps it refers to are durable.
  void checkpoint(const Checkpoint& c);
  void summary(const std::string& json);

  [[nodiscard]] const std::filesystem::path& directory() const { return o_.directory; }
  [[nodiscard]] std::filesystem::path checkpoint_path() const { return o_.directory / names::checkpoint; }
  [[nodiscard]] long last_step() const { return last_step_; }
  [[nodiscard]] long rows() const { return rows_; }
  /// \brief The table as written so far (header and every row, those of a resumed run included).
  [[nodiscard]] const std::string& table() const { return csv_; }
  [[nodiscard]] const std::string& table_name() const { return o_.csv_name; }
  [[nodiscard]] long last_dump_step() const { return dumps_.empty() ? -1 : dumps_.back().step; }
  [[nodiscard]] int stale_temporaries_removed() const { return stale_removed_; }

private:
  void keep_rows(const std::filesystem::path& table, long up_to);
  void write_mesh() const;
  void write_xdmf() const;

  Options o_;
  const geometry::Specimen& s_;
  const geometry::Interfaces& f_;
  std::string csv_;
  struct DumpInfo {
    long step;
    double time;
    std::string file;
  };
  std::vector<DumpInfo> dumps_;
  struct Layout {
    Centre centre;
    std::string name;
    std::size_t index;  ///< variant index: 0 double, 1 int32, 2 int8
    std::size_t components;
    std::size_t rows;
  };
  std::vector<Layout> layout_;  ///< fields of the latest dump (every dump of a run has the same)
  long last_step_ = 0;
  long rows_ = 0;
  bool pending_ = false;  ///< rows not yet in the table file
  int stale_removed_ = 0;
};

}  // namespace nacre::io
