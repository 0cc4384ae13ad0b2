// vtk: particles (and optionally the grid) as VTK XML files for ParaView.
//
//   writers { vtk { type vtk; fields (velocity stress pressure); grid no; } }
//
// Each write time gives one PolyData file <directory>/<name>_<index>.vtp (index = 0, 1,
// 2, ... in time order) holding the particles of every selected body as vertices, and
// rewrites the time series <directory>/<name>.pvd, which ParaView opens directly (also
// mid-run). Bodies share one file: the point array bodyId (names in the field-data array
// bodyNames) tells them apart. With `grid yes`, the background grid goes to
// <name>_grid_<index>.vti (image data: nodal mass and velocity) and <name>_grid.pvd.
//
// A run decomposed over several ranks writes, at each write time, one piece per rank,
// <directory>/<name>_<index>/<name>_<index>_<rank>.vtp (the points that rank holds, every
// array as above), and <directory>/<name>_<index>.pvtp that lists them; the .pvd lists the
// .pvtp files, so ParaView opens the series as one dataset. The grid is gathered and
// written whole, as above.
//
// Every file is written under a temporary name and renamed into place, so the output
// directory never holds a half-written file. Point arrays carry the snapshot's fields
// with their component counts (symmetric tensors: 6 components named XX YY ZZ XY YZ XZ,
// which ParaView shows as a tensor); field data carries TimeValue, the step, the body
// names, the sign conventions and a one-line description with unit of every array.
//
// Field names are known only once bodies exist (materials declare their own), so names
// in `fields` are checked at the first write: an unknown name is reported once on stderr
// (with the valid names) and skipped.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "PvdSeries.hpp"
#include "scree/output/writer.hpp"
#include "scree/plugin/context.hpp"

namespace scree::vtkio {

class VtkWriter final : public Writer {
 public:
  static constexpr const char* type_name = "vtk";
  static ParamSpec spec();
  VtkWriter(const ParamReader& r, const SolverContext& ctx);
  ~VtkWriter() override;

  void write(const Snapshot& s) override;
  bool wants_grid() const override { return grid_; }
  bool writes_pieces() const override { return true; }
  std::string begin_frame(const Snapshot& header) override;
  void write_piece(const Snapshot& local, const std::string& frame, int rank) override;
  void end_frame(const Snapshot& header, const std::string& frame, int ranks) override;

  /// A particle field chosen for output (resolved at the first write).
  struct Column {
    std::string name;
    int components = 1;
    std::string unit, doc;
  };

 private:
  void start_series();                       // first write: clean up or continue the series
  /// A restart's repair: the frame after the last one `series` lists, complete on disk but
  /// never listed (a kill between its rename and the .pvd's rewrite), listed and saved.
  void list_unlisted_frame(PvdSeries& series, const std::string& prefix, const std::string& suffix);
  void resolve_fields(const Snapshot& s);    // first write: the arrays to write
  /// `tmp`: the file written; `target`: the name it will have (for messages).
  void write_particles(const Snapshot& s, const std::filesystem::path& tmp, const std::filesystem::path& target) const;
  void write_grid(const Snapshot& s, const std::filesystem::path& tmp, const std::filesystem::path& target) const;
  void write_grid_frame(const Snapshot& s);  // <name>_grid_<index>.vti and its series, when asked
  /// <frame>_<rank>.vtp, in the folder <frame>/ beside the frame's .pvtp.
  static std::string piece_name(const std::string& frame, int rank);
  void write_pieces_file(const std::filesystem::path& tmp, const std::string& frame, int ranks) const;
  bool body_selected(const BodySnapshot& b) const;

  std::string name_;            // the writer's name in controlDict (file prefix)
  std::filesystem::path dir_;   // output directory (absolute or relative to the cwd); made at the first write
  SourceLocation where_;        // of the `directory` entry (messages at the first write)
  double start_time_ = 0;
  bool all_fields_ = true;
  std::vector<std::string> requested_fields_;
  std::vector<std::string> bodies_;  // empty: all
  bool ascii_ = false;
  std::string compression_ = "zlib";
  int level_ = 1;
  bool single_ = false;
  bool grid_ = false;

  bool started_ = false;
  bool resolved_ = false;
  std::vector<Column> columns_;
  std::int64_t index_ = 0;         // index of the next file
  std::int64_t last_step_ = -1;    // step of the last write (the final state may come twice)
  PvdSeries particles_, grid_series_;
};

}  // namespace scree::vtkio
