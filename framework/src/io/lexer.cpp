// The dictionary reader's lexer (lexer.hpp).

#include "lexer.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <system_error>
#include <utility>

#include "format.hpp"

namespace scree::reader {

// ---- numbers ----

bool looks_numeric(std::string_view s) {
  if (s.empty()) return false;
  const char c = s[0];
  if (is_digit(c)) return true;
  if (c != '+' && c != '-' && c != '.') return false;
  return std::any_of(s.begin(), s.end(), is_digit);
}

namespace {

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

}  // namespace

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

bool lexes_as_word(std::string_view s) {
  if (s.empty() || s[0] == '#' || looks_numeric(s)) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!is_word_byte(static_cast<unsigned char>(s[i]))) return false;
    if (s[i] == '/' && i + 1 < s.size() && (s[i + 1] == '/' || s[i + 1] == '*')) return false;
  }
  return true;
}

// ---- tokens ----

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

Lexer::Lexer(std::string text, std::shared_ptr<const std::string> file)
    : text_(std::move(text)), file_(SourcePos::file_number(file)) {
  reject_nul();
  if (text_.compare(0, 3, "\xEF\xBB\xBF") == 0) pos_ = 3;  // UTF-8 byte order mark
}

void Lexer::fail(const SourcePos& where, std::string message) const {
  throw InputError(where, std::move(message));
}

void Lexer::reject_nul() {
  const std::size_t nul = text_.find('\0');
  if (nul == std::string::npos) return;
  while (pos_ < nul) advance();
  fail(here(), "unexpected NUL byte (is this a binary file?)");
}

void Lexer::skip_space_and_comments() {
  while (!done()) {
    const char c = at(0);
    if (is_space(static_cast<unsigned char>(c))) {
      advance();
    } else if (c == '/' && at(1) == '/') {
      while (!done() && at(0) != '\n') advance();
    } else if (c == '/' && at(1) == '*') {
      const SourcePos open = here();
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
std::string Lexer::read_word_bytes() {
  const std::size_t begin = pos_;
  while (!done() && is_word_byte(static_cast<unsigned char>(at(0))) &&
         !(at(0) == '/' && (at(1) == '/' || at(1) == '*'))) {
    // A byte order mark is skipped at the start of the file only. Elsewhere (files
    // joined with `cat`, an editor's paste) it is an invisible part of a word:
    // "\uFEFFendTime" would be an unknown key that prints as 'endTime', and a key
    // written back would lose it when read again (the writer's output starts with it).
    if (static_cast<unsigned char>(at(0)) == 0xEF && text_.compare(pos_, 3, "\xEF\xBB\xBF") == 0)
      fail(here(), "invisible character U+FEFF (a byte order mark, allowed only at the start of the file) "
                   "inside a word: delete it");
    advance();
  }
  return text_.substr(begin, pos_ - begin);
}

Token Lexer::lex() {
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

void Lexer::lex_string(Token& t) {
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

void Lexer::lex_macro(Token& t) {
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

void Lexer::lex_directive(Token& t) {
  t.kind = Tok::directive;
  advance();  // '#'
  t.text = read_word_bytes();
  if (t.text.empty())
    fail(t.where, "expected a directive name after '#', found " + found_here() +
                      " (supported directives: #include \"file\", #inputMode merge|overwrite)");
}

void Lexer::lex_bare(Token& t) {
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
std::string Lexer::found_here() const {
  if (done()) return "the end of the file";
  const unsigned char c = static_cast<unsigned char>(at(0));
  if (c == '\n' || c == '\r') return "the end of the line";
  if (is_space(c)) return "a space";
  if (is_control(c)) return "a control character";
  return std::string("'") + static_cast<char>(c) + "'";
}

}  // namespace scree::reader
