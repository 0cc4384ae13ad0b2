// OpenFOAM-syntax dictionaries with source locations.
//
// Syntax (a superset of what cases use):
//   FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }  (header)
//   key value;                    primitive entry: one or more items before ';'
//   key value1 value2;            several items (e.g. `region box (0 0) (1 1);`)
//   name { ... }                  sub-dictionary (no ';' needed after '}')
//   key ( 1 2.5 word "str" (0 1) );  list: numbers, words, strings, nested lists,
//                                    and { } dictionaries inside lists
//   // line comment, /* block comment */
//   $name, $a.b.c                 macro: the value of an entry found by scope lookup
//                                 (current dictionary, then its parents); a dotted name
//                                 walks sub-dictionaries from the first match;
//                                 `$:a.b` starts at the top-level dictionary.
//                                 As a whole entry (`$defaults;`) inside a dictionary,
//                                 a sub-dictionary's entries are merged in.
//                                 `${name}` is the same as `$name`.
//   #include "file"               file relative to the including file's directory
//   #inputMode overwrite|merge|error   how the rest of this file treats a repeated key
//
// A key may be set once per dictionary by the file that writes it: a second `endTime`
// in the same controlDict (a value appended, a line copied and edited) is an error that
// names both lines. A key may replace one that came from an `#include` or a `$name;`
// merge: a variant that includes its base case's file and then sets `cellSize 0.01;`
// changes that entry, as in OpenFOAM. `#inputMode overwrite` (or `merge`) makes later
// entries of the rest of the current file replace earlier ones silently; `#inputMode
// error` is the default. (`merge` does not merge sub-dictionaries: the later one
// replaces the earlier one whole.) A replacement keeps the position of the first entry
// and the location of the one that wins. A file must be a regular file: a named pipe, a
// device or a socket is an error naming the path, reported without opening it.
//
// Every entry, item and dictionary keeps file, line and column (1-based). Every error
// is an InputError whose what() reads `file:line:col: message`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "scree/core/config.hpp"

namespace scree {

/// Position in an input file. `file` is the path as it was opened (callers open
/// case files relative to the case directory, so messages read `system/controlDict:12:5`).
struct SCREE_API SourceLocation {
  std::shared_ptr<const std::string> file;
  int line = 0;
  int column = 0;
  /// "file:line:col", or "file" when line is 0, or "<unknown>" when there is no file.
  std::string str() const;
};

/// An error a user can cause, located in an input file.
class SCREE_API InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string message);
  const SourceLocation& where() const noexcept { return where_; }
  /// The message without the location prefix.
  const std::string& message() const noexcept { return message_; }

 private:
  SourceLocation where_;
  std::string message_;
};

/// Several input errors reported together; what() lists them one per line.
class SCREE_API InputErrors : public std::runtime_error {
 public:
  explicit InputErrors(std::vector<InputError> errors);
  const std::vector<InputError>& errors() const noexcept { return errors_; }

 private:
  std::vector<InputError> errors_;
};

class Dictionary;

/// One item of a primitive entry's value.
struct SCREE_API Item {
  enum class Kind { word, string, number, list, dict };
  Kind kind = Kind::word;
  /// word: the word; string: the unquoted contents; number: the text as written.
  std::string text;
  double number = 0;        ///< number value (Kind::number)
  bool integral = false;    ///< the number was written without '.', 'e' or 'E'
  std::vector<Item> list;   ///< Kind::list
  std::shared_ptr<const Dictionary> dict;  ///< Kind::dict (a { } inside a list)
  SourceLocation where;

  /// Human-readable description of the kind ("a number", "a word", "a list", ...).
  std::string kind_name() const;
  /// The item written back in dictionary syntax.
  std::string to_string() const;
};

/// A `key value;` or `key { }` entry.
class SCREE_API Entry {
 public:
  const std::string& key() const noexcept { return key_; }
  const SourceLocation& where() const noexcept { return where_; }
  bool is_dict() const noexcept { return dict_ != nullptr; }
  /// The sub-dictionary; throws InputError ("'key' must be a dictionary { ... }") otherwise.
  const Dictionary& dict() const;
  /// Items of a primitive entry (empty for a dictionary entry).
  const std::vector<Item>& items() const noexcept { return items_; }

  // Typed access to a primitive entry holding exactly one item. Each throws an
  // InputError at the entry's location naming the key, what was expected and what
  // was found, e.g. "endTime: expected a number, found the word 'ten'".
  double as_scalar() const;
  long long as_integer() const;
  /// true/false, yes/no, on/off.
  bool as_bool() const;
  /// A word (unquoted) or a string (quoted).
  std::string as_word() const;
  /// A list of numbers, e.g. (0 -9.81).
  std::vector<double> as_scalar_list() const;
  /// A list of words or strings.
  std::vector<std::string> as_word_list() const;
  /// The single item; throws if the entry is a dictionary or has several items.
  const Item& single_item() const;

  /// The value written back in dictionary syntax (for messages and --list-plugins).
  std::string value_string() const;

  // Construction (used by the parser and by code that builds dictionaries).
  Entry(std::string key, SourceLocation where, std::vector<Item> items);
  Entry(std::string key, SourceLocation where, std::shared_ptr<const Dictionary> dict);

 private:
  std::string key_;
  SourceLocation where_;
  std::vector<Item> items_;
  std::shared_ptr<const Dictionary> dict_;
};

class SCREE_API Dictionary {
 public:
  Dictionary() = default;
  Dictionary(std::string name, SourceLocation where);

  /// Read a file. `display_name` is the path used in messages (defaults to `path` as
  /// given). Throws InputError for any syntax error, a missing file or one that is not a
  /// regular file (a named pipe would block), a key set twice, an unknown macro, an
  /// include cycle or a missing include; never hangs or crashes on malformed input.
  static Dictionary read_file(const std::filesystem::path& path,
                              std::optional<std::string> display_name = std::nullopt);
  /// Parse text; `name` is used as the file name in locations.
  static Dictionary parse(std::string_view text, std::string name);

  /// Dotted path from the top ("materials.sand"), or the file name at the top level.
  const std::string& name() const noexcept { return name_; }
  const SourceLocation& where() const noexcept { return where_; }

  /// Entries in file order (the FoamFile header is not among them).
  const std::vector<Entry>& entries() const noexcept { return entries_; }
  /// The FoamFile header, if the file had one.
  const Dictionary* header() const noexcept { return header_.get(); }

  const Entry* find(std::string_view key) const noexcept;
  bool has(std::string_view key) const noexcept { return find(key) != nullptr; }
  /// The entry; throws InputError at this dictionary's location:
  /// "missing required entry 'key' in dictionary 'name'".
  const Entry& at(std::string_view key) const;
  /// The sub-dictionary `key`; throws when missing or not a dictionary.
  const Dictionary& sub(std::string_view key) const;
  std::vector<std::string> keys() const;

  // Convenience: typed getters (at(key).as_...()) and defaults when absent.
  double get_scalar(std::string_view key) const { return at(key).as_scalar(); }
  long long get_integer(std::string_view key) const { return at(key).as_integer(); }
  bool get_bool(std::string_view key) const { return at(key).as_bool(); }
  std::string get_word(std::string_view key) const { return at(key).as_word(); }
  double get_scalar_or(std::string_view key, double def) const;
  long long get_integer_or(std::string_view key, long long def) const;
  bool get_bool_or(std::string_view key, bool def) const;
  std::string get_word_or(std::string_view key, std::string def) const;

  /// Add or replace an entry (replacement keeps the position of the first one).
  void set(Entry e);
  void set_header(std::shared_ptr<const Dictionary> h) { header_ = std::move(h); }
  void set_name(std::string name) { name_ = std::move(name); }

  /// The dictionary written back in dictionary syntax.
  std::string to_string(int indent = 0) const;

 private:
  void rebuild_index();
  std::string name_;
  SourceLocation where_;
  std::vector<Entry> entries_;
  std::shared_ptr<const Dictionary> header_;
  /// Open addressing over entries_' keys (find() and set() in constant time, even for
  /// huge files): a power-of-two number of slots, each 0 (free) or a position + 1; empty
  /// while the dictionary is small enough to scan.
  std::vector<std::uint32_t> index_;
};

}  // namespace scree
