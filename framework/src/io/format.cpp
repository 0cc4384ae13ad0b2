// The dictionary reader's writing side: locations and errors as text, values written
// back in dictionary syntax (format.hpp), and Dictionary::to_string.

#include "format.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <mutex>
#include <unordered_map>
#include <utility>

#include "lexer.hpp"

namespace scree {

// ---------------------------------------------------------------------------------------
// SourceLocation, InputError, InputErrors
// ---------------------------------------------------------------------------------------

std::string SourceLocation::str() const {
  if (!file) return "<unknown>";
  std::string s = *file;
  if (line > 0) {
    s += ':' + std::to_string(line);
    if (column > 0) s += ':' + std::to_string(column);
  }
  return s;
}

namespace {

/// The file names positions refer to, numbered from 1 in the order first seen.
struct FileTable {
  std::mutex mutex;
  std::vector<std::shared_ptr<const std::string>> names{nullptr};  // 0: no file
  std::unordered_map<std::string, std::uint32_t> numbers;
};

FileTable& file_table() {
  static FileTable* table = new FileTable;  // never destroyed: positions outlive everything
  return *table;
}

}  // namespace

std::uint32_t SourcePos::file_number(const std::shared_ptr<const std::string>& file) {
  if (!file) return 0;
  FileTable& t = file_table();
  std::lock_guard lock(t.mutex);
  auto [it, added] = t.numbers.try_emplace(*file, static_cast<std::uint32_t>(t.names.size()));
  if (added) t.names.push_back(file);
  return it->second;
}

SourcePos SourcePos::of(const SourceLocation& where) { return {file_number(where.file), where.line, where.column}; }

SourceLocation SourcePos::location() const {
  if (file == 0) return {nullptr, line, column};
  FileTable& t = file_table();
  std::lock_guard lock(t.mutex);
  return {t.names[file], line, column};
}

namespace {

std::string located(const SourceLocation& where, const std::string& message) {
  // Without any location (dictionaries built in code), the message stands alone.
  if (!where.file) return message;
  return where.str() + ": " + message;
}

/// The texts of `values` (`text(value)` each) separated by `separator`.
template <class Range, class Text>
std::string join(const Range& values, char separator, Text text) {
  std::string s;
  for (const auto& v : values) {
    if (!s.empty()) s += separator;
    s += text(v);
  }
  return s;
}

std::string join_errors(const std::vector<InputError>& errors) {
  return join(errors, '\n', [](const InputError& e) { return e.what(); });
}

}  // namespace

InputError::InputError(SourceLocation where, std::string message)
    : std::runtime_error(located(where, message)), where_(std::move(where)), message_(std::move(message)) {}

InputErrors::InputErrors(std::vector<InputError> errors)
    : std::runtime_error(join_errors(errors)), errors_(std::move(errors)) {}

// ---------------------------------------------------------------------------------------
// Values written back, and what messages say was found
// ---------------------------------------------------------------------------------------

namespace reader {

namespace {
constexpr std::size_t kDescribeWidth = 60;  // longest value quoted in a message
}  // namespace

std::string quote(std::string_view s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  q += '"';
  return q;
}

std::string word_text(std::string_view s) { return lexes_as_word(s) ? std::string(s) : quote(s); }

std::string format_number(double v, bool integral) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  if (integral && v == std::trunc(v) && std::fabs(v) < 9.0e15) {
    auto r = std::to_chars(buf, buf + sizeof buf, static_cast<long long>(v));
    return std::string(buf, r.ptr);
  }
  auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  std::string s(buf, r.ptr);
  // Keep it a floating-point literal when it was one (1 -> 1.0 would not matter for
  // the value, but keeps `integral` stable across a round trip).
  if (!integral && s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string shorten(std::string s) {
  if (s.size() > kDescribeWidth) {
    s.resize(kDescribeWidth - 3);
    s += "...";
  }
  return s;
}

std::string describe(const Item& item) {
  switch (item.kind()) {
    case Item::Kind::word: return "the word '" + shorten(item.text()) + "'";
    case Item::Kind::string: return "the string " + shorten(quote(item.text()));
    case Item::Kind::number: return "the number " + shorten(item.to_string());
    case Item::Kind::list: return "the list " + shorten(item.to_string());
    case Item::Kind::dict: return "a dictionary " + shorten(item.to_string());
  }
  return "an item";
}

std::string join_items(std::span<const Item> items) {
  return join(items, ' ', [](const Item& it) { return it.to_string(); });
}

std::string dict_inline(const Dictionary& d) {
  std::string s = "{";
  for (const Entry& e : d.entries()) {
    s += ' ' + word_text(e.key()) + ' ';
    s += e.is_dict() ? dict_inline(e.dict()) : e.value_string() + ';';
  }
  s += " }";
  return s;
}

}  // namespace reader

using namespace reader;  // this file is the writing side of the reader

// ---------------------------------------------------------------------------------------
// Item
// ---------------------------------------------------------------------------------------

std::string Item::kind_name() const {
  switch (kind_) {
    case Kind::word: return "a word";
    case Kind::string: return "a string";
    case Kind::number: return "a number";
    case Kind::list: return "a list";
    case Kind::dict: return "a dictionary";
  }
  return "an item";
}

std::string Item::to_string() const {
  switch (kind_) {
    case Kind::word: return word_text(text());
    case Kind::string: return quote(text());
    case Kind::number: return text();  // as written, or as make_number(value) formatted it
    case Kind::list: return '(' + join_items(list()) + ')';
    case Kind::dict: return dict() ? dict_inline(*dict()) : "{ }";
  }
  return {};
}

std::string Entry::value_string() const {
  if (is_dict()) return dict_inline(dict());
  return join_items(items());
}

namespace {

/// `key value;` and `key { ... }` lines; `indent` spaces before each, sub-dictionaries
/// four more. Keys are padded to 16 columns like OpenFOAM's own writer.
void write_entries(std::string& out, const Dictionary& d, int indent) {
  const std::string pad(static_cast<std::size_t>(std::max(indent, 0)), ' ');
  for (const Entry& e : d.entries()) {
    const std::string key = word_text(e.key());
    if (e.is_dict()) {
      out += pad + key + '\n' + pad + "{\n";
      write_entries(out, e.dict(), indent + 4);
      out += pad + "}\n";
    } else {
      out += pad + key;
      out += key.size() < 15 ? std::string(16 - key.size(), ' ') : std::string(" ");
      out += e.value_string() + ";\n";
    }
  }
}

}  // namespace

std::string Dictionary::to_string(int indent) const {
  std::string out;
  if (header_) {
    const std::string pad(static_cast<std::size_t>(std::max(indent, 0)), ' ');
    out += pad + "FoamFile\n" + pad + "{\n";
    write_entries(out, *header_, indent + 4);
    out += pad + "}\n\n";
  }
  write_entries(out, *this, indent);
  return out;
}

}  // namespace scree
