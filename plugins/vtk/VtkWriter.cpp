// VtkWriter (see VtkWriter.hpp).
#include "VtkWriter.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkTypeInt64Array.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

namespace fs = std::filesystem;

namespace scree::vtkio {

namespace {

/// Location of `key` in the writer's dictionary (the dictionary itself when defaulted).
SourceLocation where_of(const ParamReader& r, const char* key) {
  if (const Entry* e = r.dict().find(key)) return e->where();
  return r.dict().where();
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

/// Whether `s` is non-empty and all digits.
bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// The index of a series file "<prefix><index><suffix>", or -1 if `file` is not one.
std::int64_t series_index(const std::string& file, const std::string& prefix, const std::string& suffix) {
  if (file.size() <= prefix.size() + suffix.size()) return -1;
  if (file.compare(0, prefix.size(), prefix) != 0) return -1;
  if (file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0) return -1;
  const std::string_view mid(file.data() + prefix.size(), file.size() - prefix.size() - suffix.size());
  if (!all_digits(mid) || mid.size() > 15) return -1;
  return std::stoll(std::string(mid));
}

/// The index of a particle frame of the series: <prefix><k>.vtp (one file) or
/// <prefix><k>.pvtp (the pieces of a decomposed run); -1 for any other name.
std::int64_t frame_index(const std::string& file, const std::string& prefix) {
  return std::max(series_index(file, prefix, ".vtp"), series_index(file, prefix, ".pvtp"));
}

/// VTK component names: vectors X Y Z; symmetric tensors in VTK's order XX YY ZZ XY YZ XZ
/// (the snapshot's Voigt order xx yy zz xy yz zx, with zx = xz).
void name_components(vtkDataArray* a, int components) {
  static const char* vec[] = {"X", "Y", "Z"};
  static const char* sym[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  if (components == 3)
    for (int c = 0; c < 3; ++c) a->SetComponentName(c, vec[c]);
  if (components == 6)
    for (int c = 0; c < 6; ++c) a->SetComponentName(c, sym[c]);
}

vtkSmartPointer<vtkDataArray> new_real_array(bool single) {
  if (single) return vtkSmartPointer<vtkFloatArray>::New();
  return vtkSmartPointer<vtkDoubleArray>::New();
}

/// Typed pointer to the values of a float or double array of `count` values.
template <class F>
void with_values(vtkDataArray* a, vtkIdType count, F&& f) {
  if (auto* d = vtkDoubleArray::SafeDownCast(a))
    f(d->WritePointer(0, count));
  else if (auto* s = vtkFloatArray::SafeDownCast(a))
    f(s->WritePointer(0, count));
  else
    throw std::logic_error("vtk writer: unexpected array type");
}

void add_string_array(vtkFieldData* fd, const char* name, const std::vector<std::string>& lines) {
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->SetNumberOfValues(static_cast<vtkIdType>(lines.size()));
  for (std::size_t i = 0; i < lines.size(); ++i) a->SetValue(static_cast<vtkIdType>(i), lines[i]);
  fd->AddArray(a);
}

/// TimeValue (what ParaView shows as the time of a lone file) and the step.
void add_time(vtkFieldData* fd, const Snapshot& s) {
  vtkNew<vtkDoubleArray> t;
  t->SetName("TimeValue");
  t->InsertNextValue(s.time);
  fd->AddArray(t);
  vtkNew<vtkTypeInt64Array> step;
  step->SetName("step");
  step->InsertNextValue(s.step);
  fd->AddArray(step);
}

/// Settings shared by the .vtp and .vti writers: appended raw binary (optionally
/// compressed) or ASCII, 64-bit headers and ids (arrays beyond 4 GiB, > 2^31 particles).
template <class W>
void configure(W* w, bool ascii, const std::string& compression, int level) {
  w->SetHeaderTypeToUInt64();
  w->SetIdTypeToInt64();
  if (ascii) {
    w->SetDataModeToAscii();
    w->SetCompressorTypeToNone();
    return;
  }
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();  // raw bytes, not base64
  if (compression == "zlib")
    w->SetCompressorTypeToZLib();
  else if (compression == "lz4")
    w->SetCompressorTypeToLZ4();
  else
    w->SetCompressorTypeToNone();
  if (compression != "none") w->SetCompressionLevel(level);
}

template <class W>
void run_writer(W* w, const fs::path& tmp, const fs::path& target) {
  w->SetFileName(tmp.c_str());
  const int ok = w->Write();
  const unsigned long code = w->GetErrorCode();
  if (ok != 1 || code != 0) {
    std::string why = code ? vtkErrorCode::GetStringFromErrorCode(code) : "VTK reported a failure";
    if (code == vtkErrorCode::CannotOpenFileError || code == vtkErrorCode::OutOfDiskSpaceError) {
      const int err = errno;
      if (err) why += " (" + std::system_category().message(err) + ")";
    }
    throw std::runtime_error("cannot write " + target.string() + ": " + why);
  }
}

const char* kConventions[] = {
    "stress: Cauchy stress [Pa], tension positive; components XX YY ZZ XY YZ XZ (symmetric)",
    "pressure: mean stress p = -trace(stress)/3 [Pa], compression positive",
    "deviatoricStress: von Mises stress q = sqrt(3/2 s:s) [Pa], s = deviator of stress",
    "2D cases: plane strain in the x-y plane; z = 0; mass and volume are per metre of thickness",
    "particleId: unique particle id over the case, stable in time",
    "bodyId: index of the body in constant/bodies (its name: bodyNames[bodyId])",
    "a field that a body does not have is NaN on that body's particles",
};

}  // namespace

// ------------------------------------------------------------------ spec / construction

ParamSpec VtkWriter::spec() {
  ParamSpec s(type_name,
              "particles as VTK XML PolyData (<directory>/<name>_<index>.vtp) at every write time, with a "
              "ParaView time series <directory>/<name>.pvd; optionally the grid as image data (.vti)");
  s.word_list("fields",
              "particle fields to write, e.g. (velocity stress pressure); (all): every field of every body. "
              "Positions, particleId and bodyId are always written; unknown names are reported at the first "
              "write and skipped")
      .default_value("(all)");
  s.word_list("bodies", "bodies to write (default: all bodies)").optional();
  s.word("directory", "output directory, relative to the case directory").default_value("VTK");
  s.word("format", "binary: appended raw binary data (compact, fast); ascii: readable XML text")
      .choices({"binary", "ascii"})
      .default_value("binary");
  s.word("compression", "compression of binary data (ignored for ascii)")
      .choices({"zlib", "lz4", "none"})
      .default_value("zlib");
  s.integer("compressionLevel",
            "zlib/lz4 level: 1 (fastest) to 9 (smallest files); higher levels are much slower for "
            "files only slightly smaller")
      .range(1, 9)
      .default_value(1.0);
  s.word("precision", "floating-point arrays: double (Float64) or single (Float32, half the size)")
      .choices({"double", "single"})
      .default_value("double");
  s.boolean("grid",
            "also write the background grid (nodal mass and velocity) as image data "
            "<directory>/<name>_grid_<index>.vti with its own series <name>_grid.pvd")
      .default_value("no");
  return s;
}

VtkWriter::VtkWriter(const ParamReader& r, const SolverContext& ctx)
    : name_(ctx.name.empty() ? type_name : ctx.name),
      start_time_(ctx.start_time),
      ascii_(r.word("format") == "ascii"),
      compression_(r.word("compression")),
      level_(static_cast<int>(r.integer("compressionLevel"))),
      single_(r.word("precision") == "single"),
      grid_(r.boolean("grid")) {
  for (const auto& f : r.words("fields")) {
    if (f == "all") continue;
    if (std::find(requested_fields_.begin(), requested_fields_.end(), f) == requested_fields_.end())
      requested_fields_.push_back(f);
  }
  const auto fw = r.words("fields");
  all_fields_ = fw.empty() || std::find(fw.begin(), fw.end(), "all") != fw.end();

  if (r.has("bodies")) {
    bodies_ = r.words("bodies");
    for (const auto& b : bodies_) {
      if (ctx.body_names.empty() ||
          std::find(ctx.body_names.begin(), ctx.body_names.end(), b) != ctx.body_names.end())
        continue;
      std::string msg = "bodies: unknown body '" + b + "'";
      const std::string near = nearest_name(b, ctx.body_names);
      if (!near.empty()) msg += " (did you mean '" + near + "'?)";
      throw InputError(where_of(r, "bodies"), msg + "; the bodies of this case are: " + join(ctx.body_names));
    }
  }

  // The output directory: checked now, so that an unwritable place fails before the run,
  // and made at the first write, so that a user error found in a plugin constructed
  // after this one leaves the case as it was. Checked: the directory, or its nearest
  // existing ancestor, is a writable directory.
  const std::string dir_text = r.word("directory");
  if (dir_text.empty()) throw InputError(where_of(r, "directory"), "directory: must not be empty");
  dir_ = ctx.case_dir / dir_text;
  std::error_code ec;
  fs::path p = dir_;
  while (!p.empty() && !fs::exists(p, ec) && p.has_relative_path() && p != p.parent_path()) p = p.parent_path();
  if (p.empty()) p = ".";
  if (!fs::is_directory(p, ec))
    throw InputError(where_of(r, "directory"), "cannot create the output directory " + dir_.string() + ": " +
                                                   p.string() + " is a file, not a directory");
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError(where_of(r, "directory"),
                     "the output directory " + dir_.string() + " cannot be made or written: " + p.string() + ": " +
                         std::system_category().message(errno));
  where_ = where_of(r, "directory");
}

VtkWriter::~VtkWriter() = default;

bool VtkWriter::body_selected(const BodySnapshot& b) const {
  return bodies_.empty() || std::find(bodies_.begin(), bodies_.end(), b.name) != bodies_.end();
}

// ------------------------------------------------------------------ the series

void VtkWriter::start_series() {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw InputError(where_, "cannot create the output directory " + dir_.string() + ": " +
                                 (ec ? ec.message() : "a file of that name exists"));
  particles_ = PvdSeries(dir_ / (name_ + ".pvd"));
  grid_series_ = PvdSeries(dir_ / (name_ + "_grid.pvd"));
  const std::string vtp_prefix = name_ + "_", grid_prefix = name_ + "_grid_";
  if (start_time_ > 0) {
    // A run from a later time (a restart) continues the series. Its frames are numbered
    // after the entries before its time (it writes again the same frames under the same
    // names, PvdSeries::put); later entries, frames of the run it continues, stay listed
    // until it writes them again, so that a restart killed early unlists nothing.
    particles_.load();
    grid_series_.load();
    const double eps = 1e-9 * std::max(1.0, start_time_);
    for (const auto& e : particles_.entries())
      if (e.time < start_time_ - eps) index_ = std::max(index_, frame_index(e.file, vtp_prefix) + 1);
    for (const auto& e : grid_series_.entries())
      if (e.time < start_time_ - eps) index_ = std::max(index_, series_index(e.file, grid_prefix, ".vti") + 1);
    // A run killed between a frame's rename and the rewrite of the .pvd left that frame
    // complete but unlisted: list it (its time is the TimeValue in its header).
    list_unlisted_frame(particles_, vtp_prefix, ".vtp");
    list_unlisted_frame(grid_series_, grid_prefix, ".vti");
  }
  // This writer's files that its series does not list: from t = 0 every old one (files of a
  // longer earlier run would otherwise sit beside the new ones), on a restart those no
  // series lists; and the temporaries of a killed run. From t = 0 the series files go
  // first: a run killed while it removes the old frames then leaves unlisted frames (the
  // next run's clean-up), never a .pvd that lists a frame already removed.
  if (start_time_ <= 0) {
    fs::remove(particles_.path(), ec);
    fs::remove(grid_series_.path(), ec);
  }
  std::set<std::string> listed;
  for (const auto& e : particles_.entries()) listed.insert(e.file);
  for (const auto& e : grid_series_.entries()) listed.insert(e.file);
  ec.clear();
  for (const auto& de : fs::directory_iterator(dir_, ec)) {
    std::string f = de.path().filename().string();
    bool temporary = false;
    if (!f.empty() && f[0] == '.') {
      f = atomic_temporary_target(f);
      if (f.empty()) continue;
      temporary = true;
    }
    const bool series = f == name_ + ".pvd" || f == name_ + "_grid.pvd";
    // A decomposed run's frame: <name>_<k>.pvtp and the folder <name>_<k>/ of its pieces.
    const bool pieces = !temporary && series_index(f, vtp_prefix, "") >= 0 && de.is_directory(ec);
    const bool frame = frame_index(f, vtp_prefix) >= 0 || series_index(f, grid_prefix, ".vti") >= 0 || pieces;
    if (!series && !frame) continue;
    const std::string listed_as = pieces ? f + ".pvtp" : f;
    const bool stale = temporary || (start_time_ > 0 ? frame && !listed.count(listed_as) : true);
    if (stale) fs::remove_all(de.path(), ec);
  }
  started_ = true;
}

void VtkWriter::list_unlisted_frame(PvdSeries& series, const std::string& prefix, const std::string& suffix) {
  std::int64_t last = -1;
  for (const auto& e : series.entries())
    last = std::max(last, suffix == ".vtp" ? frame_index(e.file, prefix) : series_index(e.file, prefix, suffix));
  const std::string file = prefix + std::to_string(last + 1) + suffix;
  std::ifstream in(dir_ / file, std::ios::binary);
  if (!in) return;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  // Complete (it was renamed into place whole) and stamped with its time.
  static const std::regex time_value(R"re(Name="TimeValue"[^>]*RangeMin="\s*([^"\s]+))re");
  std::smatch m;
  const auto tail = text.find_last_not_of(" \n\r");
  const std::string header = text.substr(0, 8192);  // the FieldData comes first: no regex over the data
  if (tail == std::string::npos || tail + 1 < 10 || text.compare(tail + 1 - 10, 10, "</VTKFile>") != 0 ||
      !std::regex_search(header, m, time_value))
    return;
  double t = 0;
  try {
    t = std::stod(m[1]);
  } catch (const std::exception&) {
    return;
  }
  series.put(t, file);
  series.save();
}

void VtkWriter::resolve_fields(const Snapshot& s) {
  struct Available {
    Column col;
    std::string body;
    bool conflict = false;
  };
  std::vector<Available> avail;
  for (const auto& b : s.bodies) {
    if (!body_selected(b)) continue;
    for (const auto& f : b.fields) {
      if (f.name == "bodyId") continue;  // written as an integer array
      auto it = std::find_if(avail.begin(), avail.end(), [&](const Available& a) { return a.col.name == f.name; });
      if (it == avail.end()) {
        avail.push_back({{f.name, f.components, f.unit, f.doc}, b.name, false});
      } else if (it->col.components != f.components && !it->conflict) {
        it->conflict = true;
        std::cerr << "warning: vtk writer '" << name_ << "': field '" << f.name << "' has " << it->col.components
                  << " component(s) in body '" << it->body << "' but " << f.components << " in body '" << b.name
                  << "'; it is not written\n";
      }
    }
  }
  std::vector<std::string> valid;
  for (const auto& a : avail)
    if (!a.conflict) valid.push_back(a.col.name);
  columns_.clear();
  if (all_fields_) {
    for (const auto& a : avail)
      if (!a.conflict) columns_.push_back(a.col);
  }
  std::vector<std::string> unknown;
  for (const auto& name : requested_fields_) {
    if (name == "bodyId" || name == "particleId" || name == "position") continue;  // always written
    auto it = std::find_if(avail.begin(), avail.end(), [&](const Available& a) { return a.col.name == name; });
    if (it == avail.end()) {
      unknown.push_back(name);
    } else if (!it->conflict &&
               std::none_of(columns_.begin(), columns_.end(), [&](const Column& c) { return c.name == name; })) {
      columns_.push_back(it->col);
    }
  }
  for (const auto& name : unknown) {
    std::cerr << "warning: vtk writer '" << name_ << "': '" << name << "' is not a particle field of ";
    std::cerr << (bodies_.empty() ? "any body" : "the selected bodies") << "; it is not written";
    const std::string near = nearest_name(name, valid);
    if (!near.empty()) std::cerr << " (did you mean '" << near << "'?)";
    std::cerr << ". Valid fields: " << join(valid) << " (and particleId, bodyId)\n";
  }
  resolved_ = true;
}

// ------------------------------------------------------------------ writing

void VtkWriter::write(const Snapshot& s) {
  if (index_ > 0 && s.step == last_step_) return;  // the same state again (the final write)
  try {
    if (!started_) start_series();
    if (!resolved_) resolve_fields(s);
    const std::string base = name_ + "_" + std::to_string(index_);
    const fs::path vtp = dir_ / (base + ".vtp");
    write_file_atomically(vtp, [&](const fs::path& tmp) { write_particles(s, tmp, vtp); });
    particles_.put(s.time, vtp.filename().string());
    particles_.save();
    write_grid_frame(s);
  } catch (const std::exception& e) {
    throw std::runtime_error("vtk writer '" + name_ + "': " + e.what());
  }
  ++index_;
  last_step_ = s.step;
}

void VtkWriter::write_grid_frame(const Snapshot& s) {
  if (!grid_ || !s.has_grid) return;
  const fs::path vti = dir_ / (name_ + "_grid_" + std::to_string(index_) + ".vti");
  write_file_atomically(vti, [&](const fs::path& tmp) { write_grid(s, tmp, vti); });
  grid_series_.put(s.time, vti.filename().string());
  grid_series_.save();
}

// ------------------------------------------------------------------ pieces (decomposed runs)

std::string VtkWriter::begin_frame(const Snapshot& header) {
  if (index_ > 0 && header.step == last_step_) return {};  // the same state again (the final write)
  try {
    if (!started_) start_series();
    if (!resolved_) resolve_fields(header);
    const std::string frame = name_ + "_" + std::to_string(index_);
    // A frame written again (a restart) starts from an empty folder: the pieces of another
    // rank count must not stay beside the new ones.
    std::error_code ec;
    fs::remove_all(dir_ / frame, ec);
    fs::create_directories(dir_ / frame, ec);
    if (ec) throw std::runtime_error("cannot make " + (dir_ / frame).string() + ": " + ec.message());
    return frame;
  } catch (const std::exception& e) {
    throw std::runtime_error("vtk writer '" + name_ + "': " + e.what());
  }
}

void VtkWriter::write_piece(const Snapshot& local, const std::string& frame, int rank) {
  if (frame.empty()) return;
  try {
    if (!resolved_) resolve_fields(local);
    const fs::path piece = dir_ / frame / piece_name(frame, rank);
    write_file_atomically(piece, [&](const fs::path& tmp) { write_particles(local, tmp, piece); });
  } catch (const std::exception& e) {
    throw std::runtime_error("vtk writer '" + name_ + "': rank " + std::to_string(rank) + ": " + e.what());
  }
}

void VtkWriter::end_frame(const Snapshot& header, const std::string& frame, int ranks) {
  if (frame.empty()) return;
  try {
    const fs::path pvtp = dir_ / (frame + ".pvtp");
    write_file_atomically(pvtp, [&](const fs::path& tmp) { write_pieces_file(tmp, frame, ranks); });
    particles_.put(header.time, pvtp.filename().string());
    particles_.save();
    write_grid_frame(header);
  } catch (const std::exception& e) {
    throw std::runtime_error("vtk writer '" + name_ + "': " + e.what());
  }
  ++index_;
  last_step_ = header.step;
}

std::string VtkWriter::piece_name(const std::string& frame, int rank) {
  return frame + "_" + std::to_string(rank) + ".vtp";
}

void VtkWriter::write_pieces_file(const fs::path& tmp, const std::string& frame, int ranks) const {
  // ParaView's parallel PolyData: the arrays every piece has (as write_particles makes
  // them), then one Piece per rank, relative to this file.
  const char* real = single_ ? "Float32" : "Float64";
  auto has = [&](const char* n) {
    return std::any_of(columns_.begin(), columns_.end(), [&](const Column& c) { return c.name == n; });
  };
  std::ofstream out(tmp);
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <PPolyData GhostLevel=\"0\">\n"
      << "    <PPointData" << (has("velocity") ? " Vectors=\"velocity\"" : "")
      << (has("stress") ? " Tensors=\"stress\"" : "") << ">\n"
      << "      <PDataArray type=\"Int64\" Name=\"particleId\"/>\n"
      << "      <PDataArray type=\"Int32\" Name=\"bodyId\"/>\n";
  for (const Column& c : columns_)
    out << "      <PDataArray type=\"" << real << "\" Name=\"" << xml_escape(c.name) << "\" NumberOfComponents=\""
        << c.components << "\"/>\n";
  out << "    </PPointData>\n"
      << "    <PPoints>\n"
      << "      <PDataArray type=\"" << real << "\" NumberOfComponents=\"3\"/>\n"
      << "    </PPoints>\n";
  for (int r = 0; r < ranks; ++r)
    out << "    <Piece Source=\"" << xml_escape(frame + "/" + piece_name(frame, r)) << "\"/>\n";
  out << "  </PPolyData>\n</VTKFile>\n";
  out.close();
  if (!out) throw std::runtime_error("cannot write " + tmp.string());
}

void VtkWriter::write_particles(const Snapshot& s, const fs::path& tmp, const fs::path& target) const {
  std::vector<const BodySnapshot*> bodies;
  vtkIdType n = 0;
  for (const auto& b : s.bodies) {
    if (!body_selected(b)) continue;
    if (b.position.size() != static_cast<std::size_t>(3 * b.n) || b.id.size() != static_cast<std::size_t>(b.n))
      throw std::runtime_error("body '" + b.name + "': inconsistent snapshot (positions or ids do not match n)");
    bodies.push_back(&b);
    n += static_cast<vtkIdType>(b.n);
  }

  vtkNew<vtkPolyData> pd;
  // Points.
  vtkNew<vtkPoints> points;
  points->SetDataType(single_ ? VTK_FLOAT : VTK_DOUBLE);
  points->SetNumberOfPoints(n);
  with_values(points->GetData(), 3 * n, [&](auto* dst) {
    using T = std::remove_pointer_t<decltype(dst)>;
    for (const auto* b : bodies) dst = std::transform(b->position.begin(), b->position.end(), dst,
                                                      [](Real v) { return static_cast<T>(v); });
  });
  pd->SetPoints(points);
  // One vertex cell per particle.
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) {
    offsets->SetValue(i, i);
    connectivity->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> verts;
  verts->SetData(offsets, connectivity);
  pd->SetVerts(verts);

  // Point data: ids, body ids, then the chosen fields.
  vtkPointData* point_data = pd->GetPointData();
  vtkNew<vtkTypeInt64Array> ids;
  ids->SetName("particleId");
  ids->SetNumberOfValues(n);
  vtkNew<vtkIntArray> body_ids;
  body_ids->SetName("bodyId");
  body_ids->SetNumberOfValues(n);
  {
    vtkIdType k = 0;
    for (const auto* b : bodies)
      for (Index p = 0; p < b->n; ++p, ++k) {
        ids->SetValue(k, b->id[p]);
        body_ids->SetValue(k, b->body_id);
      }
  }
  point_data->AddArray(ids);
  point_data->AddArray(body_ids);

  std::vector<std::string> descriptions = {"particleId [-]: unique particle id",
                                           "bodyId [-]: index of the body in constant/bodies"};
  for (const auto& col : columns_) {
    auto a = new_real_array(single_);
    a->SetName(col.name.c_str());
    a->SetNumberOfComponents(col.components);
    a->SetNumberOfTuples(n);
    name_components(a, col.components);
    const std::size_t c = static_cast<std::size_t>(col.components);
    with_values(a, n * col.components, [&](auto* dst) {
      using T = std::remove_pointer_t<decltype(dst)>;
      for (const auto* b : bodies) {
        const FieldData* f = b->find(col.name);
        const std::size_t count = c * static_cast<std::size_t>(b->n);
        if (f && f->components == col.components && f->values.size() == count)
          dst = std::transform(f->values.begin(), f->values.end(), dst, [](Real v) { return static_cast<T>(v); });
        else
          dst = std::fill_n(dst, count, std::numeric_limits<T>::quiet_NaN());
      }
    });
    point_data->AddArray(a);
    descriptions.push_back(col.name + " [" + (col.unit.empty() ? "-" : col.unit) + "]: " + col.doc);
  }
  if (point_data->HasArray("velocity")) point_data->SetActiveVectors("velocity");
  if (point_data->HasArray("stress")) point_data->SetActiveTensors("stress");

  // Field data: time, body names, conventions, descriptions.
  vtkFieldData* fd = pd->GetFieldData();
  add_time(fd, s);
  int max_id = -1;
  for (const auto& b : s.bodies) max_id = std::max(max_id, b.body_id);
  std::vector<std::string> names(static_cast<std::size_t>(max_id + 1));
  for (const auto& b : s.bodies)
    if (b.body_id >= 0) names[static_cast<std::size_t>(b.body_id)] = b.name;
  add_string_array(fd, "bodyNames", names);
  add_string_array(fd, "conventions", std::vector<std::string>(std::begin(kConventions), std::end(kConventions)));
  add_string_array(fd, "fieldDescriptions", descriptions);

  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetInputData(pd);
  configure(w.Get(), ascii_, compression_, level_);
  run_writer(w.Get(), tmp, target);
}

void VtkWriter::write_grid(const Snapshot& s, const fs::path& tmp, const fs::path& target) const {
  const GridSnapshot& g = s.grid;
  vtkNew<vtkImageData> img;
  img->SetDimensions(g.n[0], g.n[1], g.n[2]);
  img->SetOrigin(g.origin[0], g.origin[1], g.origin[2]);
  img->SetSpacing(g.h, g.h, g.h);
  const vtkIdType nn = static_cast<vtkIdType>(g.n[0]) * g.n[1] * g.n[2];
  for (const auto& f : g.fields) {
    if (f.values.size() != static_cast<std::size_t>(nn * f.components))
      throw std::runtime_error("grid field '" + f.name + "' has " + std::to_string(f.values.size()) +
                               " values, expected " + std::to_string(nn * f.components));
    auto a = new_real_array(single_);
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    a->SetNumberOfTuples(nn);
    name_components(a, f.components);
    with_values(a, nn * f.components, [&](auto* dst) {
      using T = std::remove_pointer_t<decltype(dst)>;
      std::transform(f.values.begin(), f.values.end(), dst, [](Real v) { return static_cast<T>(v); });
    });
    img->GetPointData()->AddArray(a);
  }
  if (img->GetPointData()->HasArray("velocity")) img->GetPointData()->SetActiveVectors("velocity");
  add_time(img->GetFieldData(), s);

  vtkNew<vtkXMLImageDataWriter> w;
  w->SetInputData(img);
  configure(w.Get(), ascii_, compression_, level_);
  run_writer(w.Get(), tmp, target);
}

}  // namespace scree::vtkio
