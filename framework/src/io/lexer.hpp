// The dictionary reader's lexer: one file's bytes into tokens (private to the reader).
//
// Tokens are { } ( ) [ ] ; word string number $macro #directive and the end, with
// whitespace and comments skipped. Every token carries its start location (1-based line
// and column; columns count UTF-8 code points) and its end, so that "expected ';'" can
// point just after the value it follows. The lexer alone decides what a number is: a
// token that starts like one (a digit, or a sign or '.' and some digit) must be a
// complete number, otherwise it is a "bad number". NUL bytes and control characters are
// rejected with their location (binary input).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "scree/io/dictionary.hpp"

namespace scree::reader {

// ---- character classes and number syntax (shared with the writers) ----

inline bool is_space(unsigned char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}
inline bool is_control(unsigned char c) { return (c < 0x20 && !is_space(c)) || c == 0x7f; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline bool is_delimiter(unsigned char c) {
  return c == ';' || c == '(' || c == ')' || c == '{' || c == '}' || c == '"' || c == '$' || c == '[' || c == ']';
}
/// Bytes that may appear in a word (UTF-8 bytes included); '/' may, but "//" and "/*"
/// start a comment (checked by the callers, which see two bytes).
inline bool is_word_byte(unsigned char c) { return !is_space(c) && !is_control(c) && !is_delimiter(c); }
/// A word proper starts with a letter, '_' or a non-ASCII byte.
inline bool starts_word(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c >= 0x80;
}

/// Starts like a number: a digit, or a sign or '.' followed somewhere by a digit
/// (so `-9.81`, `.5` and `--1` are numbers or bad numbers, `-` and `+x` are words).
bool looks_numeric(std::string_view s);

enum class NumberStatus { ok, malformed, overflow };

/// Strict number syntax: [+-] (digits [. [digits]] | . digits) [(e|E) [+-] digits].
NumberStatus parse_number(std::string_view s, double& value, bool& integral);

/// True when `s` would be read back as one word token.
bool lexes_as_word(std::string_view s);

// ---- tokens ----

// '[' ... ']' (OpenFOAM's dimension sets, `dimensions [0 1 -2 0 0 0 0];`) is a list like
// '(' ... ')'; it must close with the bracket it opened with.
enum class Tok { end, word, string, number, macro, directive, lbrace, rbrace, lparen, rparen, lbracket, rbracket, semicolon };

struct Token {
  Tok kind = Tok::end;
  std::string text;  ///< word, string contents, number as written, macro/directive name
  double number = 0;
  bool integral = false;
  SourcePos where;
  int end_line = 0, end_column = 0;  ///< just after the token
  bool line_start = false;           ///< no other token before it on its line

  SourcePos end() const { return {where.file, end_line, end_column}; }
};

/// "the word 'x'", "';'", "the end of the file": what a message says was found.
std::string describe(const Token& t);

class Lexer {
 public:
  Lexer(std::string text, std::shared_ptr<const std::string> file);

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
  SourcePos here() const { return {file_, line_, column_}; }

  void advance() {
    const unsigned char c = static_cast<unsigned char>(text_[pos_++]);
    if (c == '\n') {
      ++line_;
      column_ = 1;
    } else if ((c & 0xC0) != 0x80) {  // UTF-8 continuation bytes share their column
      ++column_;
    }
  }

  [[noreturn]] void fail(const SourcePos& where, std::string message) const;
  void reject_nul();
  void skip_space_and_comments();
  std::string read_word_bytes();
  Token lex();
  void lex_string(Token& t);
  void lex_macro(Token& t);
  void lex_directive(Token& t);
  void lex_bare(Token& t);
  std::string found_here() const;

  std::string text_;
  std::uint32_t file_;  ///< SourcePos::file_number of the file's name
  std::size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
  int last_end_line_ = 0;
  std::optional<Token> ahead_;
};

}  // namespace scree::reader
