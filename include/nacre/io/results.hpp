#pragma once
/// \file
/// \brief Everything a run writes into its output directory, each file atomically. Solver-neutral:
/// a solver hands over a Snapshot of named brick / vertex / element / interface fields and CSV
/// rows it formatted itself; io knows no solver.
///  steps.csv          one row per load step (rewritten after each step)
///  mesh.h5            static data: polygon topology, reference geometry, ids (written once)
///  dump_NNNNN.h5      the snapshot's fields (per dump)
///  nacre.xdmf         ParaView index of all dumps (rewritten after each dump)
///  summary.json       the solver's summary (at the end)
///  checkpoint.h5      see checkpoint.hpp (written by the caller through write_checkpoint)
#include <nacre/geometry/specimen.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace nacre::io {

/// \brief Where a field lives: per brick (polygon cell), per vertex of the brick polygons, per
/// element (dynamics: triangles), per interface.
enum class Centre : std::uint8_t { brick, vertex, element, interface };

using FieldData = std::variant<std::vector<double>, std::vector<std::int32_t>, std::vector<std::int8_t>>;

/// \brief A named field. Stored at /bricks/NAME (brick and vertex fields), /elements/NAME or
/// /interfaces/NAME with shape (size / components, components). Reserved names: vertex field
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
  int step = 0;
  double time = 0;
  std::map<std::string, double> reals;
  std::map<std::string, std::int64_t> integers;
  std::vector<Field> fields;
};

/// \brief A dump file name "dump_NNNNN.h5" (digits only, at least one) gives its step; any other
/// name (dump_final.h5, dump_-3.h5, dump_7.h5.bak) gives nothing.
[[nodiscard]] std::optional<int> dump_step(const std::string& file_name);

class RunWriter {
public:
  struct Options {
    std::filesystem::path directory;
    bool hdf5 = true;
    std::string csv_header;  ///< first line of steps.csv, with its newline
  };
  /// \brief Continue an earlier run after `step` (restart): rows and dumps up to it are kept
  /// when `source_directory` is this directory; another directory is set up as for a new run
  /// (its own mesh.h5), and receives the source's rows up to `step`.
  struct Resume {
    int step = 0;
    std::filesystem::path source_directory;
  };

  /// \brief Creates the directory, removes stale temporaries and writes mesh.h5 (call only
  /// after the deck, and for a restart the checkpoint, validated: a new run removes the
  /// directory's earlier nacre files, a restart the dumps after its step).
  RunWriter(Options o, const geometry::Specimen& s, const geometry::Interfaces& f,
            const std::optional<Resume>& resume = std::nullopt);

  /// \brief Append one row (formatted by the solver, with its newline) for load step `step`.
  void row(int step, const std::string& csv_line);
  /// \brief HDF5 dump of a snapshot; nacre.xdmf is rewritten to include it.
  void dump(const Snapshot& snap);
  void summary(const std::string& json);

  [[nodiscard]] const std::filesystem::path& directory() const { return o_.directory; }
  [[nodiscard]] int last_step() const { return last_step_; }
  [[nodiscard]] int stale_temporaries_removed() const { return stale_removed_; }

private:
  void write_mesh() const;
  void write_xdmf() const;

  Options o_;
  const geometry::Specimen& s_;
  const geometry::Interfaces& f_;
  std::string csv_;
  struct DumpInfo {
    int step;
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
  int last_step_ = 0;
  int stale_removed_ = 0;
};

}  // namespace nacre::io
