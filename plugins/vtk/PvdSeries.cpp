// PvdSeries (see PvdSeries.hpp).
#include "PvdSeries.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "scree/output/writer.hpp"

namespace scree::vtkio {

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

std::string xml_unescape(const std::string& text) {
  static const std::pair<const char*, char> entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    if (text[i] == '&') {
      for (const auto& [ent, ch] : entities) {
        if (text.compare(i, std::char_traits<char>::length(ent), ent) == 0) {
          out += ch;
          i += std::char_traits<char>::length(ent);
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out += text[i++];
  }
  return out;
}

}  // namespace

std::string time_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (v == 0) v = 0;  // no "-0"
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

void PvdSeries::truncate_from(double t) {
  const double eps = 1e-9 * std::max(1.0, std::fabs(t));
  std::erase_if(entries_, [&](const PvdEntry& e) { return e.time >= t - eps; });
}

void PvdSeries::put(double time, std::string relative_file) {
  const double eps = 1e-9 * std::max(1.0, std::fabs(time));
  std::erase_if(entries_, [&](const PvdEntry& e) { return e.file == relative_file || std::fabs(e.time - time) <= eps; });
  const auto at = std::upper_bound(entries_.begin(), entries_.end(), time,
                                   [](double t, const PvdEntry& e) { return t < e.time; });
  entries_.insert(at, {time, std::move(relative_file)});
}

void PvdSeries::load() {
  entries_.clear();
  std::ifstream in(file_);
  if (!in) return;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (text.find("type=\"Collection\"") == std::string::npos)
    throw std::runtime_error(file_.string() + ": not a ParaView data collection (.pvd)");
  static const std::regex dataset(R"(<DataSet\s([^>]*)/?>)");
  static const std::regex timestep(R"re(timestep\s*=\s*"([^"]*)")re");
  static const std::regex file(R"re(file\s*=\s*"([^"]*)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset); it != std::sregex_iterator(); ++it) {
    const std::string attrs = (*it)[1];
    std::smatch t, f;
    if (!std::regex_search(attrs, t, timestep) || !std::regex_search(attrs, f, file))
      throw std::runtime_error(file_.string() + ": a DataSet without timestep or file: " + it->str());
    PvdEntry e;
    try {
      e.time = std::stod(t[1]);
    } catch (const std::exception&) {
      throw std::runtime_error(file_.string() + ": bad timestep '" + t[1].str() + "'");
    }
    e.file = xml_unescape(f[1]);
    entries_.push_back(std::move(e));
  }
}

void PvdSeries::save() const {
  write_file_atomically(file_, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open " + tmp.string() + " for writing");
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        << "  <Collection>\n";
    for (const auto& e : entries_)
      out << "    <DataSet timestep=\"" << time_text(e.time) << "\" group=\"\" part=\"0\" file=\""
          << xml_escape(e.file) << "\"/>\n";
    out << "  </Collection>\n</VTKFile>\n";
    out.close();
    if (!out) throw std::runtime_error("error writing " + tmp.string() + " (disk full?)");
  });
}

}  // namespace scree::vtkio
