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
//   #includeEtc "file"            a file shipped with scree (share/scree/etc of the
//                                 installation, or a folder of SCREE_ETC): documented
//                                 parameter sets, `#includeEtc "materials/feng2025/
//                                 table3-columnCollapse"` inside a material's { }
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
#include <iterator>
#include <memory>
#include <optional>
#include <span>
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

/// The same position in 12 bytes, as items and entries keep it (a large file has millions
/// of them): the file is a number in a table of the process's file names, which never
/// shrinks (a program reads a handful of files, each name is stored once).
struct SCREE_API SourcePos {
  std::uint32_t file = 0;  ///< 0: no file
  int line = 0;
  int column = 0;

  /// The position of `where` (its file name entered in the table if new).
  static SourcePos of(const SourceLocation& where);
  /// The number of the file name `file` (0 for none), entered in the table if new.
  static std::uint32_t file_number(const std::shared_ptr<const std::string>& file);
  /// The full location (the file's name shared with the table).
  SourceLocation location() const;
  operator SourceLocation() const { return location(); }  // NOLINT: positions are locations
  std::string str() const { return location().str(); }
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
///
/// 24 bytes (a table of a million rows is millions of items): the position, the kind and,
/// in the remaining 9 bytes, a short text (a number's text packed two characters a byte,
/// so up to 18 of them) or a pointer to the longer text, the list's elements or the
/// dictionary. A number keeps only its text as written; its value is read from it.
class SCREE_API Item {
 public:
  enum class Kind : std::uint8_t { word, string, number, list, dict };

  Item() noexcept = default;  ///< an empty word
  Item(const Item& other);
  Item(Item&& other) noexcept;
  Item& operator=(const Item& other);
  Item& operator=(Item&& other) noexcept;
  ~Item();

  static Item make_word(std::string_view text, SourcePos where = {});
  static Item make_string(std::string_view text, SourcePos where = {});
  /// A number as written: `text` must read as one ("1e6", "-0.5"), and is what
  /// to_string() writes back.
  static Item make_number(std::string_view text, SourcePos where = {});
  /// A number from its value, written back in the shortest form that reads back the same.
  static Item make_number(double value, bool integral, SourcePos where = {});
  static Item make_list(std::vector<Item> elements, SourcePos where = {});
  /// `count` elements moved from `first` into a list of exactly that many.
  static Item make_list(Item* first, std::size_t count, SourcePos where = {});
  static Item make_dict(std::shared_ptr<const Dictionary> dict, SourcePos where = {});

  Kind kind() const noexcept { return kind_; }
  /// word: the word; string: the unquoted contents; number: the text as written.
  std::string text() const;
  /// The value of a number (0 for other kinds).
  double number() const noexcept;
  /// The number was written without '.', 'e' or 'E'.
  bool integral() const noexcept { return (bits_ & kIntegral) != 0; }
  /// The elements of a list (none for other kinds).
  std::span<const Item> list() const noexcept;
  /// The dictionary of a { } inside a list (null for other kinds).
  const Dictionary* dict() const noexcept;
  SourceLocation where() const { return pos_.location(); }
  const SourcePos& pos() const noexcept { return pos_; }

  /// Moves `elements` to the end of this list, which keeps room to grow (a long list is
  /// built in place rather than copied whole when it is complete).
  void append(std::span<Item> elements);

  /// Human-readable description of the kind ("a number", "a word", "a list", ...).
  std::string kind_name() const;
  /// The item written back in dictionary syntax.
  std::string to_string() const;

 private:
  static constexpr std::uint8_t kIntegral = 1;  // a number written without '.', 'e', 'E'
  static constexpr std::uint8_t kHeap = 2;      // word/string/number text behind the pointer
  static constexpr std::size_t kInline = 9;     // bytes of text held in the item

  struct ListBlock;
  void release() noexcept;
  void set_text(std::string_view text);
  void* pointer() const noexcept;
  void set_pointer(const void* p) noexcept;
  ListBlock* block() const noexcept;

  SourcePos pos_;
  Kind kind_ = Kind::word;
  std::uint8_t bits_ = 0;
  std::uint8_t size_ = 0;             ///< inline text: bytes, or characters of a number
  unsigned char bytes_[kInline] = {};  ///< inline text, or a pointer in bytes_[1..8]
};

/// A `key value;` or `key { }` entry.
class SCREE_API Entry {
 public:
  const std::string& key() const noexcept { return key_; }
  SourceLocation where() const { return where_.location(); }
  const SourcePos& pos() const noexcept { return where_; }
  bool is_dict() const noexcept { return shape_ == Shape::dict; }
  /// The sub-dictionary; throws InputError ("'key' must be a dictionary { ... }") otherwise.
  const Dictionary& dict() const;
  /// Items of a primitive entry (empty for a dictionary entry).
  std::span<const Item> items() const noexcept;

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

  // Construction (used by the parser and by code that builds dictionaries; a
  // SourceLocation becomes a position with SourcePos::of).
  Entry(std::string key, SourcePos where, std::vector<Item> items);
  Entry(std::string key, SourcePos where, std::shared_ptr<const Dictionary> dict);

 private:
  /// one: value_ is the only item (most entries); items: value_ is a list of the items
  /// (none or several); dict: value_ holds the sub-dictionary.
  enum class Shape : std::uint8_t { one, items, dict };
  std::string key_;
  SourcePos where_;
  Shape shape_ = Shape::items;
  Item value_;
};

/// The entries of a dictionary, in order. The first kSmall are held as a vector holds them
/// (a dictionary of a few entries costs what a vector costs); beyond, in blocks of
/// kSmall, 2 kSmall, 4 kSmall, ... entries that never move once made, so that a dictionary
/// of millions of entries grows without copying them: its peak memory is its size, not the
/// twice its size of a vector that reallocates.
class SCREE_API EntryList {
 public:
  EntryList() = default;
  EntryList(const EntryList& other);
  EntryList(EntryList&& other) noexcept;
  EntryList& operator=(const EntryList& other);
  EntryList& operator=(EntryList&& other) noexcept;
  ~EntryList();

  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  const Entry& operator[](std::size_t i) const noexcept { return *slot(i); }
  Entry& operator[](std::size_t i) noexcept { return *slot(i); }
  const Entry& front() const noexcept { return *slot(0); }
  const Entry& back() const noexcept { return *slot(size_ - 1); }
  void push_back(Entry e);

  template <class E, class L>
  class basic_iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Entry;
    using difference_type = std::ptrdiff_t;
    using pointer = E*;
    using reference = E&;
    basic_iterator() = default;
    basic_iterator(L* list, std::size_t i) : list_(list), i_(i) {}
    reference operator*() const { return (*list_)[i_]; }
    pointer operator->() const { return &(*list_)[i_]; }
    basic_iterator& operator++() {
      ++i_;
      return *this;
    }
    basic_iterator operator++(int) {
      basic_iterator t = *this;
      ++i_;
      return t;
    }
    bool operator==(const basic_iterator& o) const { return i_ == o.i_; }
    bool operator!=(const basic_iterator& o) const { return i_ != o.i_; }

   private:
    L* list_ = nullptr;
    std::size_t i_ = 0;
  };
  using iterator = basic_iterator<Entry, EntryList>;
  using const_iterator = basic_iterator<const Entry, const EntryList>;
  iterator begin() noexcept { return {this, 0}; }
  iterator end() noexcept { return {this, size_}; }
  const_iterator begin() const noexcept { return {this, 0}; }
  const_iterator end() const noexcept { return {this, size_}; }

 private:
  static constexpr int kSmallBits = 12;
  static constexpr std::size_t kSmall = std::size_t(1) << kSmallBits;
  Entry* slot(std::size_t i) const noexcept;
  void clear() noexcept;
  Entry* small_ = nullptr;      // entries 0 .. kSmall - 1 (capacity small_capacity_)
  std::size_t small_capacity_ = 0;
  std::vector<Entry*> blocks_;  // block b holds entries 2^(b + kSmallBits) .. 2^(b + kSmallBits + 1) - 1
  std::size_t size_ = 0;
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
  const EntryList& entries() const noexcept { return entries_; }
  /// The FoamFile header, if the file had one.
  const Dictionary* header() const noexcept { return header_.get(); }

  const Entry* find(std::string_view key) const noexcept;
  /// The index of `key` in entries(), or npos.
  std::size_t position(std::string_view key) const noexcept;
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
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
  EntryList entries_;
  std::shared_ptr<const Dictionary> header_;
  /// Open addressing over entries_' keys (find() and set() in constant time, even for
  /// huge files): a power-of-two number of slots, each 0 (free) or a position + 1; empty
  /// while the dictionary is small enough to scan.
  std::vector<std::uint32_t> index_;
};

}  // namespace scree
