// A ParaView data collection (.pvd): the time series of one writer's files.
//
//   <?xml version="1.0"?>
//   <VTKFile type="Collection" version="1.0" byte_order="LittleEndian">
//     <Collection>
//       <DataSet timestep="0.1" group="" part="0" file="vtk_1.vtp"/>
//       ...
//
// File names are relative to the .pvd's directory. save() rewrites the whole file
// atomically (temporary + rename), so ParaView can open the series while the run goes
// on and never sees a half-written collection. load() reads back a collection written by
// save() (used to continue a series when a run restarts from a later time).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace scree::vtkio {

struct PvdEntry {
  double time = 0;
  std::string file;  ///< relative to the .pvd's directory
};

class PvdSeries {
 public:
  PvdSeries() = default;
  explicit PvdSeries(std::filesystem::path file) : file_(std::move(file)) {}

  const std::filesystem::path& path() const { return file_; }
  const std::vector<PvdEntry>& entries() const { return entries_; }
  void clear() { entries_.clear(); }
  void add(double time, std::string relative_file) { entries_.push_back({time, std::move(relative_file)}); }
  /// Add an entry in time order, replacing one of the same file or the same time (a
  /// restart writing again a frame the series lists).
  void put(double time, std::string relative_file);
  /// Drop the entries at times >= t (a restart at t rewrites them).
  void truncate_from(double t);

  /// Replace the entries by those of the file on disk (none when it does not exist).
  /// Throws std::runtime_error when the file exists but is not a collection.
  void load();
  /// Write the collection (atomically). Throws std::runtime_error on I/O failure.
  void save() const;

 private:
  std::filesystem::path file_;
  std::vector<PvdEntry> entries_;
};

/// `text` with XML's special characters (& < > " ') replaced by entities.
std::string xml_escape(const std::string& text);
/// A time as written in the collection: 15 significant digits, so that accumulated
/// round-off does not show ("0.3", not "0.30000000000000004").
std::string time_text(double v);

}  // namespace scree::vtkio
