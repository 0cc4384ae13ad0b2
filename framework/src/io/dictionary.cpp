// OpenFOAM-syntax dictionary reader (see scree/io/dictionary.hpp for the syntax).
//
// Design
// ------
//   text ──► Lexer ──► Parser ──► Dictionary
//
// * Lexer: turns one file's bytes into tokens ({ } ( ) ; word string number $macro
//   #directive end), skipping whitespace and comments. Every token carries its start
//   location (1-based line and column; columns count UTF-8 code points) and its end, so
//   that "expected ';'" can point just after the value it follows. The lexer alone
//   decides what a number is: a token that starts like one (a digit, or a sign or '.'
//   and some digit) must be a complete number, otherwise it is a "bad number". NUL bytes
//   and control characters are rejected up front with their location (binary input).
//
// * Parser: recursive descent with an explicit scope stack. Each dictionary under
//   construction (the file's top level, every `name { }`, and `{ }` inside lists) is a
//   Scope on the stack; entries go into the innermost scope as soon as they are parsed,
//   so `$macro` lookup sees exactly the entries defined before the point of use,
//   innermost scope first (lexical scoping, OpenFOAM semantics). Values are expanded
//   when they are parsed, so a macro whose value came from other macros needs no
//   further expansion, and recursive definitions cannot exist.
//
// * Includes: `#include "file"` opens a new Lexer on the file (relative to the including
//   file's directory) and parses its entries into the current scope. The stack of open
//   files (by canonical path) detects include cycles; each included file gets its own
//   display name, so locations in it name that file.
//
// * Hostile input: nesting of { } and ( ) (including structure copied in by macros) is
//   limited to kMaxNesting levels, includes to kMaxIncludeDepth, and the total amount
//   of structure copied by macro expansion to kMaxExpandedNodes (so "billion laughs"
//   style definitions fail cleanly instead of exhausting memory). Lookup by key is
//   hashed, so files with very many entries parse in linear time.
//
// Every problem is reported as an InputError located at the offending token (or, for a
// missing ';', just after the value that lacks it).

#include "scree/io/dictionary.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <system_error>
#include <utility>

namespace scree {

namespace fs = std::filesystem;

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

std::string located(const SourceLocation& where, const std::string& message) {
  // Without any location (dictionaries built in code), the message stands alone.
  if (!where.file) return message;
  return where.str() + ": " + message;
}

std::string join_errors(const std::vector<InputError>& errors) {
  std::string s;
  for (const InputError& e : errors) {
    if (!s.empty()) s += '\n';
    s += e.what();
  }
  return s;
}

}  // namespace

InputError::InputError(SourceLocation where, std::string message)
    : std::runtime_error(located(where, message)), where_(std::move(where)), message_(std::move(message)) {}

InputErrors::InputErrors(std::vector<InputError> errors)
    : std::runtime_error(join_errors(errors)), errors_(std::move(errors)) {}

// ---------------------------------------------------------------------------------------
// Character classes, numbers and quoting (shared by the lexer and the writers)
// ---------------------------------------------------------------------------------------

namespace {

constexpr int kMaxNesting = 256;                  // levels of { } and ( )
constexpr int kMaxIncludeDepth = 64;              // files open at once
constexpr std::size_t kMaxExpandedNodes = 1'000'000;  // items/entries copied by macros
constexpr std::size_t kDescribeWidth = 60;        // longest value quoted in a message

bool is_space(unsigned char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}
bool is_control(unsigned char c) { return (c < 0x20 && !is_space(c)) || c == 0x7f; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_delimiter(unsigned char c) {
  return c == ';' || c == '(' || c == ')' || c == '{' || c == '}' || c == '"' || c == '$' || c == '[' || c == ']';
}
/// Bytes that may appear in a word (UTF-8 bytes included); '/' may, but "//" and "/*"
/// start a comment (checked by the callers, which see two bytes).
bool is_word_byte(unsigned char c) { return !is_space(c) && !is_control(c) && !is_delimiter(c); }
/// A word proper starts with a letter, '_' or a non-ASCII byte.
bool starts_word(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c >= 0x80;
}

/// Starts like a number: a digit, or a sign or '.' followed somewhere by a digit
/// (so `-9.81`, `.5` and `--1` are numbers or bad numbers, `-` and `+x` are words).
bool looks_numeric(std::string_view s) {
  if (s.empty()) return false;
  const char c = s[0];
  if (is_digit(c)) return true;
  if (c != '+' && c != '-' && c != '.') return false;
  return std::any_of(s.begin(), s.end(), is_digit);
}

enum class NumberStatus { ok, malformed, overflow };

/// Power of ten of the leading digit of a well-formed number (for telling overflow from
/// underflow when conversion reports out-of-range). The exponent saturates.
long long decimal_magnitude(std::string_view s) {
  std::size_t i = (s[0] == '+' || s[0] == '-') ? 1 : 0;
  long long mag = 0;
  bool found = false;
  long long int_digits = 0;
  for (; i < s.size() && is_digit(s[i]); ++i) {
    if (found) ++int_digits;
    else if (s[i] != '0') found = true, int_digits = 0;
  }
  if (found) mag = int_digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    long long zeros = 0;
    for (; i < s.size() && is_digit(s[i]); ++i) {
      if (!found) {
        if (s[i] == '0') ++zeros;
        else found = true, mag = -zeros - 1;
      }
    }
  }
  long long exp = 0;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    bool neg = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
    for (; i < s.size() && is_digit(s[i]); ++i) exp = std::min<long long>(exp * 10 + (s[i] - '0'), 1'000'000'000);
    if (neg) exp = -exp;
  }
  return mag + exp;
}

/// Strict number syntax: [+-] (digits [. [digits]] | . digits) [(e|E) [+-] digits].
NumberStatus parse_number(std::string_view s, double& value, bool& integral) {
  const std::size_t n = s.size();
  std::size_t i = 0;
  if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < n && is_digit(s[i])) ++i, ++digits;
  bool dot = false, exponent = false;
  if (i < n && s[i] == '.') {
    dot = true;
    ++i;
    while (i < n && is_digit(s[i])) ++i, ++digits;
  }
  if (digits == 0) return NumberStatus::malformed;
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    exponent = true;
    ++i;
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t exp_digits = 0;
    while (i < n && is_digit(s[i])) ++i, ++exp_digits;
    if (exp_digits == 0) return NumberStatus::malformed;
  }
  if (i != n) return NumberStatus::malformed;
  integral = !dot && !exponent;

  std::string_view body = s[0] == '+' ? s.substr(1) : s;  // from_chars takes no '+'
  double v = 0;
  auto [end, ec] = std::from_chars(body.data(), body.data() + body.size(), v);
  if (ec == std::errc::result_out_of_range) {
    if (decimal_magnitude(s) > 0) return NumberStatus::overflow;
    value = s[0] == '-' ? -0.0 : 0.0;  // underflow: as good as zero
    return NumberStatus::ok;
  }
  if (ec != std::errc() || end != body.data() + body.size()) return NumberStatus::malformed;
  value = v;
  return NumberStatus::ok;
}

/// True when `s` would be read back as one word token.
bool lexes_as_word(std::string_view s) {
  if (s.empty() || s[0] == '#' || looks_numeric(s)) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!is_word_byte(static_cast<unsigned char>(s[i]))) return false;
    if (s[i] == '/' && i + 1 < s.size() && (s[i + 1] == '/' || s[i + 1] == '*')) return false;
  }
  return true;
}

std::string quote(std::string_view s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  q += '"';
  return q;
}

/// A key or word written so that it reads back the same (quoted when it is not a word).
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

std::string dict_inline(const Dictionary& d);

/// "the word 'ten'", "the number 2.5", ...: what a message says was found.
std::string describe(const Item& item) {
  switch (item.kind) {
    case Item::Kind::word: return "the word '" + shorten(item.text) + "'";
    case Item::Kind::string: return "the string " + shorten(quote(item.text));
    case Item::Kind::number: return "the number " + shorten(item.to_string());
    case Item::Kind::list: return "the list " + shorten(item.to_string());
    case Item::Kind::dict: return "a dictionary " + shorten(item.to_string());
  }
  return "an item";
}

std::string join_items(const std::vector<Item>& items) {
  std::string s;
  for (const Item& it : items) {
    if (!s.empty()) s += ' ';
    s += it.to_string();
  }
  return s;
}

/// `{ key value; sub { ... } }` on one line (dictionaries inside lists, messages).
std::string dict_inline(const Dictionary& d) {
  std::string s = "{";
  for (const Entry& e : d.entries()) {
    s += ' ' + word_text(e.key()) + ' ';
    s += e.is_dict() ? dict_inline(e.dict()) : e.value_string() + ';';
  }
  s += " }";
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Item
// ---------------------------------------------------------------------------------------

std::string Item::kind_name() const {
  switch (kind) {
    case Kind::word: return "a word";
    case Kind::string: return "a string";
    case Kind::number: return "a number";
    case Kind::list: return "a list";
    case Kind::dict: return "a dictionary";
  }
  return "an item";
}

std::string Item::to_string() const {
  switch (kind) {
    case Kind::word: return word_text(text);
    case Kind::string: return quote(text);
    case Kind::number: {
      double ignored = 0;
      bool ignored_integral = false;
      if (!text.empty() && looks_numeric(text) &&
          parse_number(text, ignored, ignored_integral) == NumberStatus::ok)
        return text;
      return format_number(number, integral);
    }
    case Kind::list: return '(' + join_items(list) + ')';
    case Kind::dict: return dict ? dict_inline(*dict) : "{ }";
  }
  return {};
}

// ---------------------------------------------------------------------------------------
// Entry
// ---------------------------------------------------------------------------------------

Entry::Entry(std::string key, SourceLocation where, std::vector<Item> items)
    : key_(std::move(key)), where_(std::move(where)), items_(std::move(items)) {}

Entry::Entry(std::string key, SourceLocation where, std::shared_ptr<const Dictionary> dict)
    : key_(std::move(key)), where_(std::move(where)), dict_(std::move(dict)) {}

namespace {

[[noreturn]] void entry_error(const Entry& e, const std::string& expected, const std::string& found) {
  throw InputError(e.where(), shorten(e.key()) + ": expected " + expected + ", found " + found);
}

/// What a message says was found for the whole entry.
std::string describe_value(const Entry& e) {
  if (e.is_dict()) return "a dictionary " + shorten(dict_inline(e.dict()));
  if (e.items().empty()) return "nothing";
  if (e.items().size() == 1) return describe(e.items().front());
  return std::to_string(e.items().size()) + " values: " + shorten(e.value_string());
}

/// The entry's only item, or an error saying `expected`.
const Item& only_item(const Entry& e, const std::string& expected) {
  if (e.is_dict() || e.items().size() != 1) entry_error(e, expected, describe_value(e));
  return e.items().front();
}

bool in_integer_range(double v) {
  return v >= -9223372036854775808.0 && v < 9223372036854775808.0;
}

}  // namespace

const Dictionary& Entry::dict() const {
  if (!dict_)
    throw InputError(where_, "'" + shorten(key_) + "' must be a dictionary { ... }, found " + describe_value(*this));
  return *dict_;
}

const Item& Entry::single_item() const { return only_item(*this, "a single value"); }

double Entry::as_scalar() const {
  const Item& it = only_item(*this, "a number");
  if (it.kind != Item::Kind::number) entry_error(*this, "a number", describe(it));
  return it.number;
}

long long Entry::as_integer() const {
  const char* expected = "an integer";
  const Item& it = only_item(*this, expected);
  if (it.kind != Item::Kind::number) entry_error(*this, expected, describe(it));
  if (it.integral && !it.text.empty()) {
    std::string_view t = it.text;
    if (t[0] == '+') t.remove_prefix(1);
    long long v = 0;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec == std::errc() && end == t.data() + t.size()) return v;
    if (ec == std::errc::result_out_of_range)
      entry_error(*this, expected, describe(it) + ", which is out of range (the limit is +-9223372036854775807)");
  }
  const double v = it.number;
  if (!std::isfinite(v) || v != std::trunc(v)) entry_error(*this, expected, describe(it));
  if (!in_integer_range(v))
    entry_error(*this, expected, describe(it) + ", which is out of range (the limit is +-9223372036854775807)");
  return static_cast<long long>(v);
}

bool Entry::as_bool() const {
  const char* expected = "a boolean (true/false, yes/no, on/off)";
  const Item& it = only_item(*this, expected);
  if (it.kind == Item::Kind::word) {
    const std::string& w = it.text;
    if (w == "true" || w == "yes" || w == "on") return true;
    if (w == "false" || w == "no" || w == "off") return false;
  }
  entry_error(*this, expected, describe(it));
}

std::string Entry::as_word() const {
  const Item& it = only_item(*this, "a word");
  if (it.kind != Item::Kind::word && it.kind != Item::Kind::string) entry_error(*this, "a word", describe(it));
  return it.text;
}

std::vector<double> Entry::as_scalar_list() const {
  const char* expected = "a list of numbers";
  const Item& it = only_item(*this, expected);
  if (it.kind != Item::Kind::list) entry_error(*this, expected, describe(it));
  std::vector<double> values;
  values.reserve(it.list.size());
  for (std::size_t i = 0; i < it.list.size(); ++i) {
    const Item& el = it.list[i];
    if (el.kind != Item::Kind::number)
      throw InputError(where_, shorten(key_) + ": expected a list of numbers, but element " + std::to_string(i + 1) +
                                   " is " + describe(el));
    values.push_back(el.number);
  }
  return values;
}

std::vector<std::string> Entry::as_word_list() const {
  const char* expected = "a list of words";
  const Item& it = only_item(*this, expected);
  if (it.kind != Item::Kind::list) entry_error(*this, expected, describe(it));
  std::vector<std::string> words;
  words.reserve(it.list.size());
  for (std::size_t i = 0; i < it.list.size(); ++i) {
    const Item& el = it.list[i];
    if (el.kind != Item::Kind::word && el.kind != Item::Kind::string)
      throw InputError(where_, shorten(key_) + ": expected a list of words, but element " + std::to_string(i + 1) +
                                   " is " + describe(el));
    words.push_back(el.text);
  }
  return words;
}

std::string Entry::value_string() const {
  if (dict_) return dict_inline(*dict_);
  return join_items(items_);
}

// ---------------------------------------------------------------------------------------
// Dictionary (except reading)
// ---------------------------------------------------------------------------------------

Dictionary::Dictionary(std::string name, SourceLocation where) : name_(std::move(name)), where_(std::move(where)) {}

const Entry* Dictionary::find(std::string_view key) const noexcept {
  auto it = index_.find(key);
  return it == index_.end() ? nullptr : &entries_[it->second];
}

const Entry& Dictionary::at(std::string_view key) const {
  if (const Entry* e = find(key)) return *e;
  throw InputError(where_, "missing required entry '" + shorten(std::string(key)) + "' in dictionary '" + name_ + "'");
}

const Dictionary& Dictionary::sub(std::string_view key) const { return at(key).dict(); }

std::vector<std::string> Dictionary::keys() const {
  std::vector<std::string> k;
  k.reserve(entries_.size());
  for (const Entry& e : entries_) k.push_back(e.key());
  return k;
}

double Dictionary::get_scalar_or(std::string_view key, double def) const {
  const Entry* e = find(key);
  return e ? e->as_scalar() : def;
}

long long Dictionary::get_integer_or(std::string_view key, long long def) const {
  const Entry* e = find(key);
  return e ? e->as_integer() : def;
}

bool Dictionary::get_bool_or(std::string_view key, bool def) const {
  const Entry* e = find(key);
  return e ? e->as_bool() : def;
}

std::string Dictionary::get_word_or(std::string_view key, std::string def) const {
  const Entry* e = find(key);
  return e ? e->as_word() : std::move(def);
}

void Dictionary::set(Entry e) {
  auto it = index_.find(std::string_view(e.key()));
  if (it != index_.end()) {
    entries_[it->second] = std::move(e);
    return;
  }
  index_.emplace(e.key(), entries_.size());
  entries_.push_back(std::move(e));
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

// ---------------------------------------------------------------------------------------
// Lexer
// ---------------------------------------------------------------------------------------

namespace {

// '[' ... ']' (OpenFOAM's dimension sets, `dimensions [0 1 -2 0 0 0 0];`) is a list like
// '(' ... ')'; it must close with the bracket it opened with.
enum class Tok { end, word, string, number, macro, directive, lbrace, rbrace, lparen, rparen, lbracket, rbracket, semicolon };

struct Token {
  Tok kind = Tok::end;
  std::string text;  ///< word, string contents, number as written, macro/directive name
  double number = 0;
  bool integral = false;
  SourceLocation where;
  int end_line = 0, end_column = 0;  ///< just after the token
  bool line_start = false;           ///< no other token before it on its line

  SourceLocation end() const { return {where.file, end_line, end_column}; }
};

/// "the word 'x'", "';'", "the end of the file": what a message says was found.
std::string describe(const Token& t) {
  switch (t.kind) {
    case Tok::end: return "the end of the file";
    case Tok::word: return "the word '" + shorten(t.text) + "'";
    case Tok::string: return "the string " + shorten(quote(t.text));
    case Tok::number: return "the number " + shorten(t.text);
    case Tok::macro: return "the macro '$" + shorten(t.text) + "'";
    case Tok::directive: return "the directive '#" + shorten(t.text) + "'";
    case Tok::lbrace: return "'{'";
    case Tok::rbrace: return "'}'";
    case Tok::lparen: return "'('";
    case Tok::rparen: return "')'";
    case Tok::lbracket: return "'['";
    case Tok::rbracket: return "']'";
    case Tok::semicolon: return "';'";
  }
  return "a token";
}

class Lexer {
 public:
  Lexer(std::string text, std::shared_ptr<const std::string> file) : text_(std::move(text)), file_(std::move(file)) {
    reject_nul();
    if (text_.compare(0, 3, "\xEF\xBB\xBF") == 0) pos_ = 3;  // UTF-8 byte order mark
  }

  const Token& peek() {
    if (!ahead_) ahead_ = lex();
    return *ahead_;
  }

  Token next() {
    Token t = ahead_ ? std::move(*ahead_) : lex();
    ahead_.reset();
    return t;
  }

 private:
  char at(std::size_t offset) const {  // '\0' past the end (NUL cannot occur in text_)
    return pos_ + offset < text_.size() ? text_[pos_ + offset] : '\0';
  }
  bool done() const { return pos_ >= text_.size(); }
  SourceLocation here() const { return {file_, line_, column_}; }

  void advance() {
    const unsigned char c = static_cast<unsigned char>(text_[pos_++]);
    if (c == '\n') {
      ++line_;
      column_ = 1;
    } else if ((c & 0xC0) != 0x80) {  // UTF-8 continuation bytes share their column
      ++column_;
    }
  }

  [[noreturn]] void fail(const SourceLocation& where, std::string message) const {
    throw InputError(where, std::move(message));
  }

  void reject_nul() {
    const std::size_t nul = text_.find('\0');
    if (nul == std::string::npos) return;
    while (pos_ < nul) advance();
    fail(here(), "unexpected NUL byte (is this a binary file?)");
  }

  void skip_space_and_comments() {
    while (!done()) {
      const char c = at(0);
      if (is_space(static_cast<unsigned char>(c))) {
        advance();
      } else if (c == '/' && at(1) == '/') {
        while (!done() && at(0) != '\n') advance();
      } else if (c == '/' && at(1) == '*') {
        const SourceLocation open = here();
        advance(), advance();
        while (!done() && !(at(0) == '*' && at(1) == '/')) advance();
        if (done()) fail(open, "unterminated comment: '/*' has no matching '*/'");
        advance(), advance();
      } else {
        return;
      }
    }
  }

  /// Word bytes up to a delimiter, whitespace or the start of a comment.
  std::string read_word_bytes() {
    const std::size_t begin = pos_;
    while (!done() && is_word_byte(static_cast<unsigned char>(at(0))) &&
           !(at(0) == '/' && (at(1) == '/' || at(1) == '*'))) {
      // A byte order mark is skipped at the start of the file only. Elsewhere (files
      // joined with `cat`, an editor's paste) it is an invisible part of a word:
      // "\uFEFFendTime" would be an unknown key that prints as 'endTime', and a key
      // written back would lose it when read again (the writer's output starts with it).
      if (text_.compare(pos_, 3, "\xEF\xBB\xBF") == 0)
        fail(here(), "invisible character U+FEFF (a byte order mark, allowed only at the start of the file) "
                     "inside a word: delete it");
      advance();
    }
    return text_.substr(begin, pos_ - begin);
  }

  Token lex() {
    skip_space_and_comments();
    Token t;
    t.where = here();
    if (done()) {
      t.kind = Tok::end;
    } else {
      const unsigned char c = static_cast<unsigned char>(at(0));
      switch (c) {
        case '{': t.kind = Tok::lbrace, advance(); break;
        case '}': t.kind = Tok::rbrace, advance(); break;
        case '(': t.kind = Tok::lparen, advance(); break;
        case ')': t.kind = Tok::rparen, advance(); break;
        case '[': t.kind = Tok::lbracket, advance(); break;
        case ']': t.kind = Tok::rbracket, advance(); break;
        case ';': t.kind = Tok::semicolon, advance(); break;
        case '"': lex_string(t); break;
        case '$': lex_macro(t); break;
        case '#': lex_directive(t); break;
        default:
          if (is_control(c)) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "0x%02x", c);
            fail(t.where, std::string("unexpected control character (byte ") + hex + "; is this a binary file?)");
          }
          lex_bare(t);
      }
    }
    t.end_line = line_;
    t.end_column = column_;
    t.line_start = t.where.line > last_end_line_;
    last_end_line_ = line_;
    return t;
  }

  void lex_string(Token& t) {
    t.kind = Tok::string;
    advance();  // opening quote
    for (;;) {
      if (done()) fail(t.where, "unterminated string: no closing '\"' before the end of the file");
      const char c = at(0);
      if (c == '"') {
        advance();
        return;
      }
      if (c == '\n')
        fail(t.where, "unterminated string: no closing '\"' before the end of the line");
      if (c == '\\') {
        const char n = at(1);
        if (n == '"' || n == '\\') {
          t.text += n;
          advance(), advance();
        } else if (n == '\n') {  // line continuation
          advance(), advance();
        } else if (n == '\r' && at(2) == '\n') {
          advance(), advance(), advance();
        } else {  // other escapes are kept as written
          t.text += c;
          advance();
        }
        continue;
      }
      t.text += c;
      advance();
    }
  }

  void lex_macro(Token& t) {
    t.kind = Tok::macro;
    advance();  // '$'
    if (at(0) == '{') {
      advance();
      t.text = read_word_bytes();
      if (at(0) != '}') fail(t.where, "unterminated '${': expected a name and '}', found " + found_here());
      if (t.text.empty()) fail(t.where, "empty macro name '${}'");
      advance();
      return;
    }
    t.text = read_word_bytes();
    if (t.text.empty()) fail(t.where, "expected a macro name after '$', found " + found_here());
  }

  void lex_directive(Token& t) {
    t.kind = Tok::directive;
    advance();  // '#'
    t.text = read_word_bytes();
    if (t.text.empty())
      fail(t.where, "expected a directive name after '#', found " + found_here() +
                        " (supported directives: #include \"file\", #inputMode merge|overwrite)");
  }

  void lex_bare(Token& t) {
    if (at(0) == '*' && at(1) == '/')
      fail(t.where, "unexpected '*/' outside a comment (block comments do not nest)");
    t.text = read_word_bytes();
    const unsigned char c = static_cast<unsigned char>(t.text[0]);
    if (starts_word(c) || !looks_numeric(t.text)) {
      t.kind = Tok::word;
      return;
    }
    t.kind = Tok::number;
    switch (parse_number(t.text, t.number, t.integral)) {
      case NumberStatus::ok: return;
      case NumberStatus::overflow:
        fail(t.where, "number '" + shorten(t.text) + "' is out of range (larger than about 1.8e308)");
      case NumberStatus::malformed:
        fail(t.where, "bad number '" + shorten(t.text) +
                          "': expected a number such as 42, -9.81, .5 or 1e-5 (a word must start with a letter "
                          "or '_')");
    }
  }

  /// What comes next, for lexer messages ("'}'", "the end of the file", "' '").
  std::string found_here() const {
    if (done()) return "the end of the file";
    const unsigned char c = static_cast<unsigned char>(at(0));
    if (c == '\n' || c == '\r') return "the end of the line";
    if (is_space(c)) return "a space";
    if (is_control(c)) return "a control character";
    return std::string("'") + static_cast<char>(c) + "'";
  }

  std::string text_;
  std::shared_ptr<const std::string> file_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
  int last_end_line_ = 0;
  std::optional<Token> ahead_;
};

// ---------------------------------------------------------------------------------------
// Copying structure (macro expansion): size, depth, renaming
// ---------------------------------------------------------------------------------------

struct Extent {
  std::size_t nodes = 0;  ///< items and entries
  int depth = 0;          ///< levels of ( ) and { }
};

Extent extent(const Dictionary& d);

Extent extent(const Item& item) {
  Extent x{1, 0};
  if (item.kind == Item::Kind::list) {
    for (const Item& el : item.list) {
      Extent e = extent(el);
      x.nodes += e.nodes;
      x.depth = std::max(x.depth, e.depth);
    }
    x.depth += 1;
  } else if (item.kind == Item::Kind::dict && item.dict) {
    Extent e = extent(*item.dict);
    x.nodes += e.nodes;
    x.depth = e.depth + 1;
  }
  return x;
}

Extent extent(const Dictionary& d) {
  Extent x;
  for (const Entry& e : d.entries()) {
    x.nodes += 1;
    if (e.is_dict()) {
      Extent s = extent(e.dict());
      x.nodes += s.nodes;
      x.depth = std::max(x.depth, s.depth + 1);
    }
    for (const Item& it : e.items()) {
      Extent s = extent(it);
      x.nodes += s.nodes;
      x.depth = std::max(x.depth, s.depth);
    }
  }
  return x;
}

/// Edit distance counting insertions, deletions, substitutions and transpositions of
/// neighbours (optimal string alignment). Long strings count as far apart.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  if (a.size() > 64 || b.size() > 64) return std::numeric_limits<std::size_t>::max();
  const std::size_t w = b.size() + 1;
  std::vector<std::size_t> d((a.size() + 1) * w);
  for (std::size_t i = 0; i <= a.size(); ++i) d[i * w] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t& x = d[i * w + j];
      x = std::min({d[(i - 1) * w + j] + 1, d[i * w + j - 1] + 1,
                    d[(i - 1) * w + j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        x = std::min(x, d[(i - 2) * w + j - 2] + 1);
    }
  return d[a.size() * w + b.size()];
}

/// The key of `dicts` closest to `word` (a likely typo), or "" when none is close:
/// one edit for names of 3 to 5 characters, two from 6, and so on.
std::string nearest_key(std::string_view word, const std::vector<const Dictionary*>& dicts) {
  const std::size_t limit = word.size() / 3;
  if (limit == 0) return {};
  std::string best;
  std::size_t best_distance = limit + 1;
  for (const Dictionary* d : dicts)
    for (const Entry& e : d->entries()) {
      const std::size_t distance = edit_distance(word, e.key());
      if (distance < best_distance) best_distance = distance, best = e.key();
    }
  return best;
}

std::string join_path(const std::string& path, const std::string& key) { return path.empty() ? key : path + '.' + key; }
std::string index_path(const std::string& path, std::size_t i) { return path + '[' + std::to_string(i) + ']'; }

Dictionary renamed(const Dictionary& src, const std::string& name, const SourceLocation& where);

bool holds_dictionary(const Item& item) {
  if (item.kind == Item::Kind::dict) return true;
  return item.kind == Item::Kind::list && std::any_of(item.list.begin(), item.list.end(), holds_dictionary);
}

/// A copy of `item` whose dictionaries are named after their new place (`path`).
Item renamed(const Item& item, const std::string& path) {
  if (!holds_dictionary(item)) return item;  // nothing to rename: a plain copy
  Item copy;
  copy.kind = item.kind;
  copy.text = item.text;
  copy.number = item.number;
  copy.integral = item.integral;
  copy.where = item.where;
  if (item.kind == Item::Kind::list) {
    copy.list.reserve(item.list.size());
    for (std::size_t i = 0; i < item.list.size(); ++i) {
      const Item& el = item.list[i];
      copy.list.push_back(holds_dictionary(el) ? renamed(el, index_path(path, i)) : el);
    }
  } else if (item.kind == Item::Kind::dict && item.dict) {
    copy.dict = std::make_shared<const Dictionary>(renamed(*item.dict, path, item.dict->where()));
  }
  return copy;
}

/// A copy of entry `e` placed in the dictionary named `parent`.
Entry renamed(const Entry& e, const std::string& parent) {
  if (e.is_dict()) {
    const std::string path = join_path(parent, e.key());
    return Entry(e.key(), e.where(), std::make_shared<const Dictionary>(renamed(e.dict(), path, e.dict().where())));
  }
  if (std::none_of(e.items().begin(), e.items().end(), holds_dictionary)) return e;  // nothing to rename
  const std::string path = join_path(parent, e.key());
  std::vector<Item> items;
  items.reserve(e.items().size());
  for (const Item& it : e.items()) items.push_back(renamed(it, path));
  return Entry(e.key(), e.where(), std::move(items));
}

Dictionary renamed(const Dictionary& src, const std::string& name, const SourceLocation& where) {
  Dictionary d(name, where);
  for (const Entry& e : src.entries()) d.set(renamed(e, name));
  return d;
}

// ---------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------

enum class ReadStatus { ok, missing, directory, not_regular, unreadable };

/// What a path that is neither a regular file nor a directory is ("a named pipe").
std::string special_file_kind(fs::file_type t) {
  switch (t) {
    case fs::file_type::fifo: return "a named pipe (FIFO)";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::block: return "a block device";
    case fs::file_type::character: return "a character device";
    default: return "not a regular file";
  }
}

fs::file_type file_type_of_mode(mode_t m) {
  if (S_ISFIFO(m)) return fs::file_type::fifo;
  if (S_ISSOCK(m)) return fs::file_type::socket;
  if (S_ISBLK(m)) return fs::file_type::block;
  if (S_ISCHR(m)) return fs::file_type::character;
  if (S_ISDIR(m)) return fs::file_type::directory;
  return fs::file_type::unknown;
}

/// Read a whole regular file. Anything else (a named pipe, a device, a socket) is refused
/// before it is opened: reading a FIFO blocks until a writer appears, a device may never
/// end. The file is then opened without blocking and checked again, so that a path
/// replaced in between cannot block either. `kind` receives the type of a refused path.
ReadStatus read_text(const fs::path& path, std::string& out, fs::file_type& kind) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) return ReadStatus::missing;
  if (fs::is_directory(st)) return ReadStatus::directory;
  if (!fs::is_regular_file(st)) {
    kind = st.type();
    return ReadStatus::not_regular;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return ReadStatus::unreadable;
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat opened {};
  if (::fstat(fd, &opened) != 0) return ReadStatus::unreadable;
  if (!S_ISREG(opened.st_mode)) {
    kind = file_type_of_mode(opened.st_mode);
    return kind == fs::file_type::directory ? ReadStatus::directory : ReadStatus::not_regular;
  }
  std::string text;
  if (opened.st_size > 0) text.reserve(static_cast<std::size_t>(opened.st_size));
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      return ReadStatus::unreadable;
    }
    text.append(buf, static_cast<std::size_t>(n));
  }
  out = std::move(text);
  return ReadStatus::ok;
}

std::string absolute_text(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal().string();
}

fs::path identity_of(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  if (ec || c.empty()) return fs::path(absolute_text(p));
  return c;
}

/// A file being read: for include cycles, relative includes and display names.
struct OpenFile {
  fs::path path;        ///< as opened
  std::string display;  ///< name in messages
  std::optional<fs::path> canonical = {};  ///< computed when an #include needs it

  const fs::path& identity() {
    if (!canonical) canonical = identity_of(path);
    return *canonical;
  }
};

// ---------------------------------------------------------------------------------------
// Parser
// ---------------------------------------------------------------------------------------

/// What a body of entries belongs to.
enum class Level { main_file, included_file, nested };

/// Which source wrote an entry, and where: the file being read (each file read, the main
/// one and every #include, is a source of its own) or a `$name;` merge (each a source).
struct Origin {
  int source = 0;
  SourceLocation where;
};

/// A dictionary under construction.
struct Scope {
  Dictionary* dict;
  std::string path;  ///< dotted path of the dictionary ("" at the top level)
  /// key -> the source of its entry: a key written twice by the same source is a mistake
  /// (a line copied and edited, a value appended), one replacing an included or merged
  /// entry is the intended "base plus changes" of a variant.
  std::unordered_map<std::string, Origin> origins = {};
};

class Parser {
 public:
  Parser(Dictionary& top, OpenFile file) {
    scopes_.push_back({&top, ""});
    files_.push_back(std::move(file));
  }

  void parse_main(Lexer& lx) { parse_entries(lx, Level::main_file, nullptr); }

 private:
  [[noreturn]] static void fail(const SourceLocation& where, std::string message) {
    throw InputError(where, std::move(message));
  }

  Dictionary& current() { return *scopes_.back().dict; }

  // ---- nesting and expansion limits ----

  void enter(const Token& open) {
    if (++depth_ > kMaxNesting)
      fail(open.where, "nesting too deep: more than " + std::to_string(kMaxNesting) +
                           " levels of '{ }' and '( )' (is a closing bracket missing?)");
  }
  void leave() { --depth_; }

  /// Account for structure copied by a macro (size and resulting depth).
  void charge(const Extent& x, int extra_depth, const Token& macro) {
    expanded_ += x.nodes;
    if (expanded_ > kMaxExpandedNodes)
      fail(macro.where, "macro expansion too large: more than " + std::to_string(kMaxExpandedNodes) +
                            " values copied by macros (macros nested exponentially?)");
    if (depth_ + extra_depth + x.depth > kMaxNesting)
      fail(macro.where, "nesting too deep after expanding '$" + shorten(macro.text) + "': more than " +
                            std::to_string(kMaxNesting) + " levels of '{ }' and '( )'");
  }

  // ---- entries ----

  /// Entries into the current scope until the '}' matching `open`, or until the end of
  /// the file when `open` is null. Returns the location just after the '}'.
  SourceLocation parse_entries(Lexer& lx, Level level, const Token* open) {
    for (;;) {
      Token t = lx.next();
      switch (t.kind) {
        case Tok::end:
          if (open)
            fail(t.where, "unterminated block: '{' opened at line " + std::to_string(open->where.line) +
                              " has no matching '}'" + block_name_hint());
          return t.end();
        case Tok::rbrace:
          if (!open)
            fail(t.where, level == Level::included_file
                              ? "unexpected '}': no '{' is open in this included file"
                              : "unexpected '}': no '{' is open");
          return t.end();
        case Tok::word:
        case Tok::string: parse_entry(lx, t, level); break;
        case Tok::macro: merge_macro(lx, t); break;
        case Tok::directive: parse_directive(lx, t); break;
        case Tok::number:
          fail(t.where, "expected a key, found the number " + shorten(t.text) +
                            " (a key must start with a letter or '_')");
        case Tok::semicolon: fail(t.where, "unexpected ';' with no key or value before it");
        case Tok::lparen: fail(t.where, "expected a key, found '(' (a list is written 'key (1 2 3);')");
        case Tok::rparen: fail(t.where, "unmatched ')'");
        case Tok::lbracket: fail(t.where, "expected a key, found '[' (a dimension set is written 'key [0 1 -2 0 0 0 0];')");
        case Tok::rbracket: fail(t.where, "unmatched ']'");
        case Tok::lbrace: fail(t.where, "expected a key before '{' (a sub-dictionary is written 'name { ... }')");
      }
    }
  }

  std::string block_name_hint() const {
    const std::string& path = scopes_.back().path;
    return path.empty() ? std::string() : " (dictionary '" + shorten(path) + "')";
  }

  /// An entry written in the file being read, at `key`. A key the same file already set
  /// in this dictionary is an error naming both places, unless '#inputMode overwrite' (or
  /// merge) is in force in this file; a key set by an included file or a `$name;` merge
  /// is replaced (a variant includes its base and changes a few entries).
  void add_written(const Token& key, Entry e) {
    Scope& scope = scopes_.back();
    auto [it, fresh] = scope.origins.try_emplace(key.text, Origin{source_, key.where});
    if (!fresh) {
      if (it->second.source == source_ && !overwrite_)
        fail(key.where, shorten(key.text) + ": duplicate entry, already set at " + it->second.where.str() +
                            " (a key is set once per dictionary: remove one of them, or write "
                            "'#inputMode overwrite' before an intended replacement)");
      it->second = Origin{source_, key.where};
    }
    scope.dict->set(std::move(e));
  }

  /// An entry copied by a `$name;` merge (source: that merge).
  void add_merged(Entry e, int source) {
    scopes_.back().origins[e.key()] = Origin{source, e.where()};
    current().set(std::move(e));
  }

  void parse_entry(Lexer& lx, const Token& key, Level level) {
    const std::string path = join_path(scopes_.back().path, key.text);
    const bool file_level = level != Level::nested;
    if (lx.peek().kind == Tok::lbrace) {
      Token open = lx.next();
      SourceLocation close;
      auto d = std::make_shared<const Dictionary>(parse_dict(lx, open, path, key.where, close));
      if (lx.peek().kind == Tok::semicolon) lx.next();  // `name { ... };` is tolerated
      if (file_level && key.text == "FoamFile") {
        if (level == Level::main_file) scopes_.front().dict->set_header(std::move(d));
        return;  // the header of an included file is ignored
      }
      add_written(key, Entry(key.text, key.where, std::move(d)));
      return;
    }
    std::vector<Item> items = parse_value(lx, key, path);
    if (file_level && key.text == "FoamFile")
      fail(key.where, "the FoamFile header must be a dictionary 'FoamFile { ... }', found " +
                          (items.size() == 1 ? describe(items[0]) : std::to_string(items.size()) + " values"));
    if (items.size() == 1 && items[0].kind == Item::Kind::dict) {  // `sand2 $sand;`
      add_written(key, Entry(key.text, key.where,
                             std::make_shared<const Dictionary>(renamed(*items[0].dict, path, key.where))));
      return;
    }
    add_written(key, Entry(key.text, key.where, std::move(items)));
  }

  /// `{ ... }` after its '{'; `close` receives the location just after the '}'.
  Dictionary parse_dict(Lexer& lx, const Token& open, const std::string& path, const SourceLocation& where,
                        SourceLocation& close) {
    enter(open);
    Dictionary d(path, where);
    scopes_.push_back({&d, path});
    close = parse_entries(lx, Level::nested, &open);
    scopes_.pop_back();
    leave();
    return d;
  }

  // ---- values ----

  [[noreturn]] void missing_semicolon(const Token& key, const SourceLocation& after, const Token& found) {
    std::string where_found = describe(found);
    if (found.kind != Tok::end && found.where.line != after.line)
      where_found += " on line " + std::to_string(found.where.line);
    fail(after, "expected ';' after the value of '" + shorten(key.text) + "', found " + where_found);
  }

  /// Items up to and including ';'. A dictionary macro may only be the whole value.
  std::vector<Item> parse_value(Lexer& lx, const Token& key, const std::string& path) {
    std::vector<Item> items;
    SourceLocation after;              // just after the last item
    std::optional<Token> dict_macro;   // a macro that gave a dictionary
    for (;;) {
      const Token& t = lx.peek();
      if (t.kind == Tok::semicolon) {
        if (items.empty()) fail(t.where, "expected a value for '" + shorten(key.text) + "', found ';'");
        lx.next();
        break;
      }
      if (t.kind == Tok::end || t.kind == Tok::rbrace) {
        if (items.empty()) fail(t.where, "expected a value for '" + shorten(key.text) + "', found " + describe(t));
        missing_semicolon(key, after, t);
      }
      // A word, macro or directive that begins a new line after a complete value is
      // almost certainly the next entry: report the missing ';' rather than merging it.
      if (!items.empty() && t.line_start && (t.kind == Tok::word || t.kind == Tok::macro || t.kind == Tok::directive))
        missing_semicolon(key, after, t);
      if (t.kind == Tok::rparen) fail(t.where, "unmatched ')' in the value of '" + shorten(key.text) + "'");
      if (t.kind == Tok::rbracket) fail(t.where, "unmatched ']' in the value of '" + shorten(key.text) + "'");
      if (t.kind == Tok::lbrace)
        fail(t.where, "unexpected '{' in the value of '" + shorten(key.text) +
                          "' (a sub-dictionary is written 'name { ... }'; is a ';' missing?)");
      if (t.kind == Tok::directive)
        fail(t.where, "unexpected directive '#" + t.text + "' in the value of '" + shorten(key.text) +
                          "' (directives stand on their own, between entries)");
      std::optional<Token> macro;
      if (t.kind == Tok::macro) macro = t;
      after = parse_item(lx, items, path, false);
      if (macro && items.back().kind == Item::Kind::dict) dict_macro = std::move(macro);
    }
    if (dict_macro && items.size() > 1)
      fail(dict_macro->where, "'$" + shorten(dict_macro->text) +
                                  "' is a dictionary: it can be the whole value of an entry ('key $" +
                                  shorten(dict_macro->text) + ";') or an element of a list, not one of several values");
    return items;
  }

  /// One item (several for a macro holding several values) appended to `out`; returns
  /// the location just after it. `path` names dictionaries in it: the entry's path for a
  /// value, the list's path for list elements (which append "[index]").
  SourceLocation parse_item(Lexer& lx, std::vector<Item>& out, const std::string& path, bool in_list) {
    Token t = lx.next();
    const std::string item_path = in_list ? index_path(path, out.size()) : path;
    switch (t.kind) {
      case Tok::word: out.push_back(simple_item(Item::Kind::word, t)); break;
      case Tok::string: out.push_back(simple_item(Item::Kind::string, t)); break;
      case Tok::number: {
        Item it = simple_item(Item::Kind::number, t);
        it.number = t.number;
        it.integral = t.integral;
        out.push_back(std::move(it));
        break;
      }
      case Tok::lparen:
      case Tok::lbracket: return parse_list(lx, t, item_path, out);
      case Tok::lbrace: {  // only reached inside lists
        Item it;
        it.kind = Item::Kind::dict;
        it.where = t.where;
        SourceLocation close;
        it.dict = std::make_shared<const Dictionary>(parse_dict(lx, t, item_path, t.where, close));
        out.push_back(std::move(it));
        return close;
      }
      case Tok::macro: expand_items(t, out, path, in_list); break;
      default: fail(t.where, "expected a value, found " + describe(t));  // callers filter these
    }
    return t.end();
  }

  static Item simple_item(Item::Kind kind, const Token& t) {
    Item it;
    it.kind = kind;
    it.text = t.text;
    it.where = t.where;
    return it;
  }

  /// `( ... )` after its '('; appends the list to `out`.
  SourceLocation parse_list(Lexer& lx, const Token& open, const std::string& path, std::vector<Item>& out) {
    enter(open);
    Item list;
    list.kind = Item::Kind::list;
    list.where = open.where;
    const std::string opened =
        "opened at line " + std::to_string(open.where.line) + ", column " + std::to_string(open.where.column);
    const bool bracket = open.kind == Tok::lbracket;
    const Tok closer = bracket ? Tok::rbracket : Tok::rparen;
    const std::string o = bracket ? "'['" : "'('", c = bracket ? "']'" : "')'";
    for (;;) {
      const Token& t = lx.peek();
      if (t.kind == closer) {
        Token close = lx.next();
        leave();
        out.push_back(std::move(list));
        return close.end();
      }
      switch (t.kind) {
        case Tok::rparen:
        case Tok::rbracket: fail(t.where, "expected " + c + " to close the list " + opened + ", found " + describe(t));
        case Tok::end: fail(t.where, "unterminated list: " + o + " " + opened + " has no matching " + c);
        case Tok::semicolon:
        case Tok::rbrace: fail(t.where, "expected " + c + " to close the list " + opened + ", found " + describe(t));
        case Tok::directive:
          fail(t.where, "unexpected directive '#" + t.text + "' inside a list (directives stand between entries)");
        default: parse_item(lx, list.list, path, true); break;
      }
    }
  }

  // ---- macros ----

  /// The entry `$name` refers to (see the header for the lookup rules).
  const Entry& resolve(const Token& macro) {
    std::string_view name = macro.text;
    const bool from_top = !name.empty() && name[0] == ':';
    if (from_top) name.remove_prefix(1);
    std::vector<std::string_view> parts;
    for (std::size_t start = 0;;) {
      const std::size_t dot = name.find('.', start);
      parts.push_back(name.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
      if (dot == std::string_view::npos) break;
      start = dot + 1;
    }
    const std::string shown = "'$" + shorten(macro.text) + "'";
    for (std::string_view p : parts)
      if (p.empty())
        fail(macro.where, "malformed macro name " + shown + " (expected names separated by single dots, "
                          "e.g. '$a.b' or '$:a.b')");

    // First component: innermost scope outwards (or the top level only, for `$:`).
    const Entry* e = nullptr;
    const std::size_t lowest = 0, highest = from_top ? 1 : scopes_.size();
    for (std::size_t i = highest; i-- > lowest && !e;) e = scopes_[i].dict->find(parts[0]);
    if (!e && parts.size() > 1) {  // a key that itself contains dots
      for (std::size_t i = highest; i-- > lowest && !e;) e = scopes_[i].dict->find(name);
      if (e) return *e;
    }
    if (!e) {
      std::vector<const Dictionary*> visible;
      for (std::size_t i = lowest; i < highest; ++i) visible.push_back(scopes_[i].dict);
      const std::string near = nearest_key(parts[0], visible);
      fail(macro.where, "unknown macro " + shown + " (no entry '" + std::string(parts[0]) +
                            (from_top ? "' at the top level" : "' in scope") +
                            (near.empty() ? ")" : "; did you mean '$" + std::string(from_top ? ":" : "") + near + "'?)"));
    }

    std::string walked(parts[0]);
    for (std::size_t i = 1; i < parts.size(); ++i) {
      if (!e->is_dict())
        fail(macro.where, "unknown macro " + shown + " ('" + walked + "' is not a dictionary)");
      const Entry* next = e->dict().find(parts[i]);
      if (!next) {
        const std::string near = nearest_key(parts[i], {&e->dict()});
        fail(macro.where, "unknown macro " + shown + " (dictionary '" + walked + "' has no entry '" +
                              std::string(parts[i]) + "'" +
                              (near.empty() ? ")" : "; did you mean '" + near + "'?)"));
      }
      e = next;
      walked += '.';
      walked += parts[i];
    }
    return *e;
  }

  /// `$name` as a value: the entry's items, or its dictionary as one item.
  void expand_items(const Token& macro, std::vector<Item>& out, const std::string& path, bool in_list) {
    const Entry& e = resolve(macro);
    auto path_of = [&](std::size_t k) { return in_list ? index_path(path, out.size() + k) : path; };
    if (e.is_dict()) {
      charge(extent(e.dict()), 1, macro);
      Item it;
      it.kind = Item::Kind::dict;
      it.where = macro.where;
      if (in_list) {
        it.dict = std::make_shared<const Dictionary>(renamed(e.dict(), path_of(0), e.dict().where()));
      } else {
        // The whole value of an entry (`sand2 $sand;`): parse_entry() copies it under the
        // new name right after this value is parsed, and nothing is modified meanwhile,
        // so a non-owning pointer (aliasing an empty shared_ptr) avoids a second copy.
        it.dict = std::shared_ptr<const Dictionary>(std::shared_ptr<const Dictionary>(), &e.dict());
      }
      out.push_back(std::move(it));
      return;
    }
    for (const Item& it : e.items()) charge(extent(it), 0, macro);
    std::vector<Item> copies;
    for (const Item& it : e.items()) copies.push_back(renamed(it, path_of(copies.size())));
    for (Item& it : copies) out.push_back(std::move(it));
  }

  /// `$name;` as an entry: merge that dictionary's entries into the current one.
  void merge_macro(Lexer& lx, const Token& macro) {
    const Entry& e = resolve(macro);
    if (!e.is_dict())
      fail(macro.where, "'$" + shorten(macro.text) + "' stands where an entry is expected, so it must name a "
                        "dictionary whose entries are merged here, but '" + shorten(macro.text) + "' holds the value " +
                        shorten(e.value_string()) + " (to copy a value, write 'key $" + shorten(macro.text) + ";')");
    charge(extent(e.dict()), 0, macro);
    // Copy first: merging may replace the very entry that owns the source dictionary.
    std::vector<Entry> copies;
    for (const Entry& src : e.dict().entries()) copies.push_back(renamed(src, scopes_.back().path));
    const int source = sources_++;
    for (Entry& c : copies) add_merged(std::move(c), source);
    if (lx.peek().kind == Tok::semicolon) lx.next();
  }

  // ---- directives ----

  void parse_directive(Lexer& lx, const Token& d) {
    if (d.text == "include") {
      Token file = lx.next();
      if (file.kind != Tok::string)
        fail(d.where, "expected a quoted file name after '#include', found " + describe(file));
      if (file.text.empty()) fail(file.where, "empty file name after '#include'");
      include(d, file.text);
    } else if (d.text == "inputMode") {
      Token mode = lx.next();
      if (mode.kind != Tok::word || (mode.text != "merge" && mode.text != "overwrite" && mode.text != "error"))
        fail(mode.kind == Tok::end ? d.where : mode.where,
             "expected 'overwrite', 'merge' or 'error' after '#inputMode', found " + describe(mode) +
                 " (overwrite and merge: later entries of this file replace earlier ones; error, the default: "
                 "a key set twice is an error)");
      overwrite_ = mode.text != "error";
    } else {
      fail(d.where, "unknown directive '#" + shorten(d.text) +
                        "' (supported: #include \"file\"; #inputMode overwrite|merge|error)");
    }
    if (lx.peek().kind == Tok::semicolon) lx.next();
  }

  void include(const Token& directive, const std::string& name) {
    const OpenFile& includer = files_.back();
    const fs::path rel(name);
    const fs::path actual = rel.is_absolute() ? rel : includer.path.parent_path() / rel;
    const std::string display =
        rel.is_absolute() ? rel.string() : (fs::path(includer.display).parent_path() / rel).lexically_normal().string();
    OpenFile file{actual, display};

    for (std::size_t i = 0; i < files_.size(); ++i) {
      if (files_[i].identity() != file.identity()) continue;
      std::string chain = files_[i].display;
      for (std::size_t j = i + 1; j < files_.size(); ++j)
        chain += (j == i + 1 ? " includes " : " which includes ") + files_[j].display;
      chain += (files_.size() - i == 1 ? " includes " : " which includes ") + display;
      fail(directive.where, "include cycle: " + chain);
    }
    if (files_.size() >= static_cast<std::size_t>(kMaxIncludeDepth))
      fail(directive.where, "includes nested too deeply (more than " + std::to_string(kMaxIncludeDepth) + " files)");

    std::string text;
    fs::file_type kind = fs::file_type::unknown;
    switch (read_text(actual, text, kind)) {
      case ReadStatus::ok: break;
      case ReadStatus::missing:
        fail(directive.where, "cannot open include file '" + name + "' (looked for " + absolute_text(actual) + ")");
      case ReadStatus::directory:
        fail(directive.where, "cannot include '" + name + "': " + absolute_text(actual) + " is a directory");
      case ReadStatus::not_regular:
        fail(directive.where, "cannot include '" + name + "': " + absolute_text(actual) + " is " +
                                  special_file_kind(kind) + ", not a regular file");
      case ReadStatus::unreadable:
        fail(directive.where, "cannot read include file '" + name + "' (" + absolute_text(actual) + ")");
    }
    files_.push_back(std::move(file));
    Lexer sub(std::move(text), std::make_shared<const std::string>(display));
    // The included file is a source of its own, in the default mode until it says otherwise.
    const int includer_source = source_;
    const bool includer_overwrite = overwrite_;
    source_ = sources_++;
    overwrite_ = false;
    parse_entries(sub, Level::included_file, nullptr);
    source_ = includer_source;
    overwrite_ = includer_overwrite;
    files_.pop_back();
  }

  std::vector<Scope> scopes_;
  std::vector<OpenFile> files_;
  int source_ = 0;         // the source of entries written now (the file being read)
  int sources_ = 1;        // the next unused source number
  bool overwrite_ = false; // '#inputMode overwrite' (or merge) in force in the file being read
  int depth_ = 0;
  std::size_t expanded_ = 0;
};

Dictionary parse_text(std::string text, const std::string& display, const fs::path& actual) {
  auto file = std::make_shared<const std::string>(display);
  Dictionary top(display, SourceLocation{file, 0, 0});
  Lexer lx(std::move(text), file);
  Parser parser(top, OpenFile{actual, display});
  parser.parse_main(lx);
  return top;
}

}  // namespace

Dictionary Dictionary::read_file(const fs::path& path, std::optional<std::string> display_name) {
  std::string display = display_name ? std::move(*display_name) : path.string();
  std::string text;
  const SourceLocation where{std::make_shared<const std::string>(display), 0, 0};
  fs::file_type kind = fs::file_type::unknown;
  switch (read_text(path, text, kind)) {
    case ReadStatus::ok: break;
    case ReadStatus::missing:
      throw InputError(where, "cannot open file '" + display + "' (looked for " + absolute_text(path) + ")");
    case ReadStatus::directory:
      throw InputError(where, "cannot read '" + display + "': " + absolute_text(path) + " is a directory");
    case ReadStatus::not_regular:
      throw InputError(where, "cannot read '" + display + "': " + absolute_text(path) + " is " +
                                  special_file_kind(kind) + ", not a regular file");
    case ReadStatus::unreadable:
      throw InputError(where, "cannot read file '" + display + "' (" + absolute_text(path) + ")");
  }
  return parse_text(std::move(text), display, path);
}

Dictionary Dictionary::parse(std::string_view text, std::string name) {
  const fs::path actual(name);
  return parse_text(std::string(text), name, actual);
}

}  // namespace scree
