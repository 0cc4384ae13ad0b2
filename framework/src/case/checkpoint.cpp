// Checkpoint files (see checkpoint.hpp).
#include "scree/case/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "scree/case/case.hpp"
#include "scree/output/writer.hpp"
#include "scree/time/step_control.hpp"

namespace fs = std::filesystem;

namespace scree {

namespace {

constexpr char kMagic[16] = {'S', 'C', 'R', 'E', 'E', '-', 'C', 'H', 'E', 'C', 'K', 'P', 'O', 'I', 'N', 'T'};
constexpr const char* kSuffix = ".ckpt";

/// FNV-1a, 64 bits (Fowler, Noll & Vo): a checksum that finds a torn or altered file.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
};

/// The file's bytes, built in memory (a checkpoint is the size of the particle data: a copy
/// of it on the host is what the writers take at every write too).
class Out {
 public:
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    buf_.insert(buf_.end(), b, b + n);
  }
  template <class T>
  void pod(const T& v) {
    bytes(&v, sizeof v);
  }
  void text(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes(s.data(), s.size());
  }
  template <class T>
  void array(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  std::vector<unsigned char>& buffer() { return buf_; }

 private:
  std::vector<unsigned char> buf_;
};

class In {
 public:
  In(const std::vector<unsigned char>& b, const fs::path& file) : b_(b), file_(file) {}
  void bytes(void* p, std::size_t n) {
    if (n > b_.size() - pos_) fail("it ends early (truncated)");
    if (n == 0) return;  // an empty array's data() may be null: memcpy(null, ..., 0) is undefined
    std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  template <class T>
  T pod() {
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  std::string text() {
    const auto n = count(1);
    std::string s(n, '\0');
    bytes(s.data(), n);
    return s;
  }
  template <class T>
  std::vector<T> array() {
    std::vector<T> v(count(sizeof(T)));
    bytes(v.data(), v.size() * sizeof(T));
    return v;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(file_.string() + ": not a usable checkpoint: " + why);
  }

 private:
  std::size_t count(std::size_t element) {
    const auto n = pod<std::uint64_t>();
    if (n > (b_.size() - pos_) / element) fail("a length field exceeds the file (truncated or corrupt)");
    return static_cast<std::size_t>(n);
  }
  const std::vector<unsigned char>& b_;
  const fs::path& file_;
  std::size_t pos_ = 0;
};

std::string time_text(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", t == 0 ? 0.0 : t);
  return buf;
}


}  // namespace

bool checkpoint_time(const fs::path& file, double& t) {
  const std::string name = file.filename().string();
  if (name.size() <= std::strlen(kSuffix) || name[0] == '.' ||
      name.compare(name.size() - std::strlen(kSuffix), std::string::npos, kSuffix) != 0)
    return false;
  const std::string stem = name.substr(0, name.size() - std::strlen(kSuffix));
  char* end = nullptr;
  t = std::strtod(stem.c_str(), &end);
  return end && *end == '\0' && end != stem.c_str();
}

void Checkpoint::write(const fs::path& file) const {
  Out o;
  o.bytes(kMagic, sizeof kMagic);
  o.pod<std::uint32_t>(kVersion);
  o.pod<std::uint32_t>(sizeof(Real));
  o.pod<std::uint32_t>(sizeof(StepControl));
  o.pod<std::int32_t>(dimension);
  o.pod(time);
  o.pod(step);
  o.pod(sorted_at);
  o.pod(writes);
  o.array(clock);
  o.array(schedule);
  o.pod<std::uint64_t>(bodies.size());
  for (const Body& b : bodies) {
    o.text(b.name);
    o.text(b.material_type);
    o.pod(b.particles);
    o.pod(b.columns);
    o.array(b.data);
  }
  o.array(liquid);
  o.array(decomposition);
  o.pod<std::uint64_t>(physics.size());
  for (const auto& [key, value] : physics) {
    o.text(key);
    o.text(value);
  }
  o.pod<std::uint64_t>(pieces.size());
  for (const std::string& p : pieces) o.text(p);
  Fnv sum;
  sum.add(o.buffer().data(), o.buffer().size());
  o.pod(sum.h);

  write_file_atomically(file, [&](const fs::path& tmp) {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot write the checkpoint " + tmp.string() + ": " + std::strerror(errno));
    const auto& b = o.buffer();
    std::size_t done = 0;
    while (done < b.size()) {
      const ssize_t n = ::write(fd, b.data() + done, b.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int e = errno;
        ::close(fd);
        throw std::runtime_error("error writing the checkpoint " + file.string() + " (" + std::to_string(b.size()) +
                                 " bytes): " + std::strerror(e));
      }
      done += static_cast<std::size_t>(n);
    }
    // On disk before the rename: after a crash of the machine the name holds the whole file.
    if (::fsync(fd) != 0 || ::close(fd) != 0)
      throw std::runtime_error("error writing the checkpoint " + file.string() + ": " + std::strerror(errno));
  });
}

namespace {
Checkpoint read_one(const fs::path& file);
}  // namespace

Checkpoint Checkpoint::read(const fs::path& file, int rank, int ranks) {
  Checkpoint c = read_one(file);
  if (c.pieces.empty()) return c;
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(file.string() + ": " + why + " (the checkpoint of a run over " +
                             std::to_string(c.pieces.size()) + " ranks: a manifest and its pieces in " +
                             checkpoint_piece(file, 0).parent_path().string() + ")");
  };
  // On as many ranks, each reads its own piece; otherwise every piece, in rank order.
  const bool own = ranks > 1 && c.pieces.size() == static_cast<std::size_t>(ranks);
  const std::size_t first = own ? static_cast<std::size_t>(rank) : 0;
  const std::size_t last = own ? first + 1 : c.pieces.size();
  std::vector<Checkpoint> part;
  for (std::size_t r = first; r < last; ++r) {
    const fs::path pf = file.parent_path() / c.pieces[r];
    if (!fs::exists(pf)) fail("its piece " + pf.string() + " is missing");
    part.push_back(read_one(pf));
    const Checkpoint& p = part.back();
    if (p.time != c.time || p.step != c.step || p.bodies.size() != c.bodies.size() || !p.pieces.empty())
      fail("its piece " + pf.string() + " belongs to another checkpoint");
    for (std::size_t b = 0; b < c.bodies.size(); ++b)
      if (p.bodies[b].columns != c.bodies[b].columns)
        fail("body '" + c.bodies[b].name + "' has another number of columns in " + pf.string());
  }
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    Body& body = c.bodies[b];
    std::uint64_t total = 0;
    for (const Checkpoint& p : part) total += p.bodies[b].particles;
    if (!own && total != body.particles)
      fail("its pieces hold " + std::to_string(total) + " points of body '" + body.name + "', the manifest " +
           std::to_string(body.particles));
    // Column by column: every piece's points of the column, in rank order.
    const std::size_t C = static_cast<std::size_t>(body.columns);
    body.data.assign(static_cast<std::size_t>(total) * C, 0.0);
    std::size_t at = 0;
    for (const Checkpoint& p : part) {
      const std::size_t n = static_cast<std::size_t>(p.bodies[b].particles);
      for (std::size_t col = 0; col < C; ++col)
        std::copy_n(p.bodies[b].data.data() + col * n, n, body.data.data() + col * total + at);
      at += n;
    }
  }
  return c;
}

namespace {
Checkpoint read_one(const fs::path& file) {
  std::vector<unsigned char> buf;
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error(file.string() + ": cannot open the checkpoint: " + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const auto size = in.tellg();
    if (size < 0) throw std::runtime_error(file.string() + ": cannot read the checkpoint");
    in.seekg(0);
    buf.resize(static_cast<std::size_t>(size));
    if (!in.read(reinterpret_cast<char*>(buf.data()), size))
      throw std::runtime_error(file.string() + ": cannot read the checkpoint");
  }
  In in(buf, file);
  char magic[sizeof kMagic];
  if (buf.size() < sizeof kMagic + sizeof(std::uint64_t)) in.fail("it is too short");
  in.bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) in.fail("it does not start with " + std::string(kMagic, 16));
  {  // the checksum over everything before its own 8 bytes
    Fnv sum;
    sum.add(buf.data(), buf.size() - sizeof(std::uint64_t));
    std::uint64_t stored;
    std::memcpy(&stored, buf.data() + buf.size() - sizeof stored, sizeof stored);
    if (stored != sum.h) in.fail("its checksum does not match (the file was altered or cut)");
  }
  const auto version = in.pod<std::uint32_t>();
  if (version < 1 || version > Checkpoint::kVersion)
    in.fail("format version " + std::to_string(version) + ", this scree reads versions 1 to " +
            std::to_string(Checkpoint::kVersion));
  if (in.pod<std::uint32_t>() != sizeof(Real)) in.fail("written with another size of Real");
  if (in.pod<std::uint32_t>() != sizeof(StepControl))
    in.fail("written by a scree with another clock layout (StepControl): restart with the scree that wrote it");
  Checkpoint c;
  c.dimension = in.pod<std::int32_t>();
  c.time = in.pod<double>();
  c.step = in.pod<std::int64_t>();
  c.sorted_at = in.pod<std::int64_t>();
  c.writes = in.pod<std::int64_t>();
  c.clock = in.array<unsigned char>();
  if (c.clock.size() != sizeof(StepControl)) in.fail("its clock has the wrong size");
  c.schedule = in.array<double>();
  const auto nb = in.pod<std::uint64_t>();
  if (nb > buf.size()) in.fail("a body count exceeds the file");
  for (std::uint64_t i = 0; i < nb; ++i) {
    Checkpoint::Body b;
    b.name = in.text();
    b.material_type = in.text();
    b.particles = in.pod<std::uint64_t>();
    b.columns = in.pod<std::uint64_t>();
    b.data = in.array<Real>();
    c.bodies.push_back(std::move(b));
  }
  c.liquid = in.array<Real>();
  if (version >= 5) {
    c.decomposition = in.array<std::int32_t>();
  } else if (version >= 2) {
    // Slabs: node k cuts rank k's slab off the rest (a leaf r is written -(r + 1)).
    const auto axis = in.pod<std::int32_t>();
    const std::vector<std::int32_t> cuts = in.array<std::int32_t>();
    const auto ranks = static_cast<std::int32_t>(cuts.size()) - 1;
    for (std::int32_t k = 0; axis >= 0 && k + 1 < ranks; ++k)
      c.decomposition.insert(c.decomposition.end(),
                             {axis, cuts[static_cast<std::size_t>(k) + 1], -(k + 1), k + 2 < ranks ? k + 1 : -ranks});
  }
  if (version >= 3) {
    const auto n = in.pod<std::uint64_t>();
    if (n > buf.size()) in.fail("an entry count exceeds the file");
    for (std::uint64_t i = 0; i < n; ++i) {
      std::string key = in.text();
      c.physics.emplace_back(std::move(key), in.text());
    }
  }
  if (version >= 4) {
    const auto n = in.pod<std::uint64_t>();
    if (n > buf.size()) in.fail("a piece count exceeds the file");
    for (std::uint64_t i = 0; i < n; ++i) c.pieces.push_back(in.text());
  }
  for (const Checkpoint::Body& b : c.bodies) {  // a manifest's points are in its pieces
    const std::uint64_t n = c.pieces.empty() ? b.particles : 0;
    if (b.columns == 0 || b.data.size() / b.columns != n || b.data.size() % b.columns != 0)
      in.fail("body '" + b.name + "' has " + std::to_string(b.data.size()) + " values, not " +
              std::to_string(b.columns) + " x " + std::to_string(n));
  }
  return c;
}
}  // namespace

namespace {
/// The dictionaries that define what a case computes (case_physics), by their file.
std::vector<std::pair<std::string, const Dictionary*>> physics_files(const Case& c) {
  return {{"system/gridDict", &c.grid()},           {"system/mpmSchemes", &c.schemes()},
          {"constant/g", &c.gravity()},             {"constant/materialProperties", &c.materials()},
          {"constant/bodies", &c.bodies()},         {"constant/boundaryConditions", &c.boundaries()}};
}
/// Every primitive entry of `d`, at any depth, with its dotted key ("soil.E") and value.
void leaves(const Dictionary& d, const std::string& prefix, std::vector<std::pair<std::string, const Entry*>>& out) {
  for (const Entry& e : d.entries()) {
    const std::string key = prefix.empty() ? e.key() : prefix + "." + e.key();
    if (e.is_dict()) leaves(e.dict(), key, out);
    else out.emplace_back(key, &e);
  }
}
}  // namespace

std::vector<std::pair<std::string, std::string>> case_physics(const Case& c) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [file, d] : physics_files(c)) {
    std::vector<std::pair<std::string, const Entry*>> all;
    leaves(*d, "", all);
    for (const auto& [key, e] : all) out.emplace_back(file + "/" + key, e->value_string());
  }
  return out;
}

std::vector<InputError> physics_changes(const std::vector<std::pair<std::string, std::string>>& then,
                                        const Case& now) {
  std::vector<InputError> out;
  if (then.empty()) return out;
  std::vector<std::string> seen;
  for (const auto& [file, d] : physics_files(now)) {
    std::vector<std::pair<std::string, const Entry*>> all;
    leaves(*d, "", all);
    for (const auto& [key, e] : all) {
      const std::string full = file + "/" + key;
      seen.push_back(full);
      const auto was = std::find_if(then.begin(), then.end(), [&](const auto& kv) { return kv.first == full; });
      if (was == then.end())
        out.emplace_back(e->where(), "'" + key + "' was added since the checkpoint was written");
      else if (was->second != e->value_string())
        out.emplace_back(e->where(), "'" + key + "' changed since the checkpoint was written: " + was->second +
                                         " then, " + e->value_string() + " now");
    }
    for (const auto& [full, value] : then)
      if (full.rfind(file + "/", 0) == 0 && std::find(seen.begin(), seen.end(), full) == seen.end())
        out.emplace_back(d->where(), "'" + full.substr(file.size() + 1) + "' (" + value +
                                         ") was removed since the checkpoint was written");
  }
  return out;
}

fs::path checkpoint_dir(const fs::path& case_dir) { return case_dir / "checkpoints"; }

namespace {
constexpr const char* kPieces = ".ranks";
}  // namespace

fs::path checkpoint_piece(const fs::path& file, int rank) {
  return file.parent_path() / checkpoint_piece_relative(file, rank);
}

std::string checkpoint_piece_relative(const fs::path& file, int rank) {
  const std::string name = file.filename().string();
  const std::string stem = name.ends_with(kSuffix) ? name.substr(0, name.size() - std::strlen(kSuffix)) : name;
  return stem + kPieces + "/" + std::to_string(rank) + kSuffix;
}

fs::path checkpoint_file(const fs::path& case_dir, double t) {
  return checkpoint_dir(case_dir) / (time_text(t) + kSuffix);
}

std::vector<fs::path> list_checkpoints(const fs::path& case_dir) {
  std::vector<std::pair<double, fs::path>> found;
  std::error_code ec;
  for (const auto& de : fs::directory_iterator(checkpoint_dir(case_dir), ec)) {
    double t = 0;
    if (checkpoint_time(de.path(), t) && de.is_regular_file(ec)) found.emplace_back(t, de.path());
  }
  std::sort(found.begin(), found.end());
  std::vector<fs::path> out;
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

void purge_checkpoints(const fs::path& case_dir, std::size_t keep) {
  const auto all = list_checkpoints(case_dir);
  std::error_code ec;
  for (std::size_t i = 0; i + keep < all.size(); ++i) {
    fs::remove(all[i], ec);
    fs::remove_all(checkpoint_piece(all[i], 0).parent_path(), ec);
  }
  // Pieces whose manifest is gone, or was never written (a run killed in between), up to the
  // newest manifest kept: a later checkpoint's pieces may be being written now. keep 0
  // clears them all.
  double newest = -1;
  if (keep > 0 && !all.empty()) checkpoint_time(all.back(), newest);
  for (const auto& de : fs::directory_iterator(checkpoint_dir(case_dir), ec)) {
    const std::string name = de.path().filename().string();
    if (!name.ends_with(kPieces) || !de.is_directory(ec)) continue;
    const fs::path manifest = de.path().parent_path() / (name.substr(0, name.size() - std::strlen(kPieces)) + kSuffix);
    double t = 0;
    if (!checkpoint_time(manifest, t)) continue;
    if (keep == 0 || (!fs::exists(manifest) && t < newest)) fs::remove_all(de.path(), ec);
  }
  // Temporaries of a killed run: ".<time>.ckpt.tmp<pid>_<n>" (write_file_atomically).
  for (const auto& de : fs::directory_iterator(checkpoint_dir(case_dir), ec)) {
    const std::string target = atomic_temporary_target(de.path().filename().string());
    if (target.size() > std::strlen(kSuffix) && target.ends_with(kSuffix)) fs::remove(de.path(), ec);
  }
}

}  // namespace scree
