// The dictionary reader's parser, and Dictionary::read_file / Dictionary::parse
// (see scree/io/dictionary.hpp for the syntax).
//
//   text ──► Lexer (lexer.hpp) ──► Parser (here) ──► Dictionary (values.cpp)
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

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "expansion.hpp"
#include "files.hpp"
#include "format.hpp"
#include "lexer.hpp"
#include "scree/io/dictionary.hpp"

namespace scree {

namespace fs = std::filesystem;

namespace reader {
namespace {

constexpr int kMaxNesting = 256;                      // levels of { } and ( )
constexpr int kMaxIncludeDepth = 64;                  // files open at once
constexpr std::size_t kMaxExpandedNodes = 1'000'000;  // items/entries copied by macros
constexpr std::size_t kBufferedElements = 4096;       // longer lists grow in place, this many at a time

/// What a path whose symbolic links go round in a loop is, naming the chain.
std::string link_loop_text(const fs::path& path, const std::string& shown) {
  const std::string chain = link_chain(path, shown);
  if (chain.empty())
    return "the directories of " + absolute_text(path) + " are symbolic links in a loop, which reaches no file";
  return "symbolic links in a loop, which reaches no file: " + chain;
}

/// What a body of entries belongs to.
enum class Level { main_file, included_file, nested };

/// A dictionary under construction.
struct Scope {
  Dictionary* dict;
  std::string path;  ///< dotted path of the dictionary ("" at the top level)
  /// The source that wrote each entry of `dict` (by position): the file being read
  /// (each file read, the main one and every #include, is a source of its own) or a
  /// `$name;` merge (each a source). A key written twice by the same source is a mistake
  /// (a line copied and edited, a value appended); one replacing an included or merged
  /// entry is the intended "base plus changes" of a variant. Where the earlier one was
  /// written is its entry's location.
  std::vector<int> sources = {};
};

class Parser {
 public:
  Parser(Dictionary& top, OpenFile file) : elements_(kMaxNesting + 1) {
    scopes_.push_back({&top, ""});
    files_.push_back(std::move(file));
  }

  void parse_main(Lexer& lx) { parse_entries(lx, Level::main_file, nullptr); }

 private:
  [[noreturn]] static void fail(const SourcePos& where, std::string message) {
    throw InputError(where.location(), std::move(message));
  }

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
  SourcePos parse_entries(Lexer& lx, Level level, const Token* open) {
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
    if (const std::size_t at = scope.dict->position(key.text); at != Dictionary::npos) {
      const Entry* earlier = &scope.dict->entries()[at];
      int& source = scope.sources[at];
      if (source == source_ && !overwrite_)
        fail(key.where, shorten(key.text) + ": duplicate entry, already set at " + earlier->where().str() +
                            " (a key is set once per dictionary: remove one of them, or write "
                            "'#inputMode overwrite' before an intended replacement)");
      source = source_;
    } else {
      scope.sources.push_back(source_);
    }
    scope.dict->set(std::move(e));
  }

  /// An entry copied by a `$name;` merge (source: that merge).
  void add_merged(Entry e, int source) {
    Scope& scope = scopes_.back();
    if (const std::size_t at = scope.dict->position(e.key()); at != Dictionary::npos)
      scope.sources[at] = source;
    else
      scope.sources.push_back(source);
    scope.dict->set(std::move(e));
  }

  void parse_entry(Lexer& lx, const Token& key, Level level) {
    const std::string path = join_path(scopes_.back().path, key.text);
    const bool file_level = level != Level::nested;
    if (lx.peek().kind == Tok::lbrace) {
      Token open = lx.next();
      SourcePos close;
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
    if (items.size() == 1 && items[0].kind() == Item::Kind::dict) {  // `sand2 $sand;`
      add_written(key, Entry(key.text, key.where,
                             std::make_shared<const Dictionary>(renamed(*items[0].dict(), path, key.where))));
      return;
    }
    add_written(key, Entry(key.text, key.where, std::move(items)));
  }

  /// `{ ... }` after its '{'; `close` receives the location just after the '}'.
  Dictionary parse_dict(Lexer& lx, const Token& open, const std::string& path, const SourcePos& where,
                        SourcePos& close) {
    enter(open);
    Dictionary d(path, where);
    scopes_.push_back({&d, path});
    close = parse_entries(lx, Level::nested, &open);
    scopes_.pop_back();
    leave();
    return d;
  }

  // ---- values ----

  [[noreturn]] void missing_semicolon(const Token& key, const SourcePos& after, const Token& found) {
    std::string where_found = describe(found);
    if (found.kind != Tok::end && found.where.line != after.line)
      where_found += " on line " + std::to_string(found.where.line);
    fail(after, "expected ';' after the value of '" + shorten(key.text) + "', found " + where_found);
  }

  /// Items up to and including ';'. A dictionary macro may only be the whole value.
  std::vector<Item> parse_value(Lexer& lx, const Token& key, const std::string& path) {
    std::vector<Item> items;
    SourcePos after;                   // just after the last item
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
      after = parse_item(lx, items, 0, path, false);
      if (macro && items.back().kind() == Item::Kind::dict) dict_macro = std::move(macro);
    }
    if (dict_macro && items.size() > 1)
      fail(dict_macro->where, "'$" + shorten(dict_macro->text) +
                                  "' is a dictionary: it can be the whole value of an entry ('key $" +
                                  shorten(dict_macro->text) + ";') or an element of a list, not one of several values");
    return items;
  }

  /// One item (several for a macro holding several values) appended to `out`; returns
  /// the location just after it. `path` names dictionaries in it: the entry's path for a
  /// value, the list's path for list elements (which append "[index]"); `before` is the
  /// number of elements of the list that are not in `out`.
  SourcePos parse_item(Lexer& lx, std::vector<Item>& out, std::size_t before, const std::string& path, bool in_list) {
    Token t = lx.next();
    // The name of a list or dictionary this item is (made only for those: a table's
    // numbers would each pay for a string).
    auto item_path = [&] { return in_list ? index_path(path, before + out.size()) : path; };
    switch (t.kind) {
      case Tok::word: out.push_back(Item::make_word(t.text, t.where)); return t.end();
      case Tok::string: out.push_back(Item::make_string(t.text, t.where)); return t.end();
      case Tok::number: out.push_back(Item::make_number(t.text, t.where)); return t.end();
      case Tok::lparen:
      case Tok::lbracket: return parse_list(lx, t, item_path(), out);
      case Tok::lbrace: {  // only reached inside lists
        SourcePos close;
        auto d = std::make_shared<const Dictionary>(parse_dict(lx, t, item_path(), t.where, close));
        out.push_back(Item::make_dict(std::move(d), t.where));
        return close;
      }
      case Tok::macro: expand_items(t, out, before, path, in_list); break;
      default: fail(t.where, "expected a value, found " + describe(t));  // callers filter these
    }
    return t.end();
  }

  /// "opened at line 3, column 7": where the list that `open` begins was opened, for its
  /// messages (made only when one is needed: a table has a list a row).
  static std::string opened_at(const Token& open) {
    return "opened at line " + std::to_string(open.where.line) + ", column " + std::to_string(open.where.column);
  }

  /// `( ... )` after its '('; appends the list to `out`.
  SourcePos parse_list(Lexer& lx, const Token& open, const std::string& path, std::vector<Item>& out) {
    enter(open);
    // The elements are gathered in this level's reused buffer and the list gets exactly
    // as many: a list grown in place keeps up to as much room again unused (a row of
    // three numbers held four), and tables have a list a row. A long list (a table) is
    // then grown in place, a buffer at a time, so that it is never held twice.
    std::vector<Item>& elements = elements_[static_cast<std::size_t>(depth_)];
    elements.clear();
    Item list = Item::make_list({}, open.where);
    std::size_t moved = 0;  // elements already in `list`
    const bool bracket = open.kind == Tok::lbracket;
    const Tok closer = bracket ? Tok::rbracket : Tok::rparen;
    const std::string_view o = bracket ? "'['" : "'('", c = bracket ? "']'" : "')'";
    for (;;) {
      const Token& t = lx.peek();
      if (t.kind == closer) {
        Token close = lx.next();
        list.append(elements);
        elements.clear();
        out.push_back(std::move(list));
        leave();
        return close.end();
      }
      switch (t.kind) {
        case Tok::rparen:
        case Tok::rbracket:
        case Tok::semicolon:
        case Tok::rbrace:
          fail(t.where, "expected " + std::string(c) + " to close the list " + opened_at(open) + ", found " + describe(t));
        case Tok::end:
          fail(t.where, "unterminated list: " + std::string(o) + " " + opened_at(open) + " has no matching " +
                            std::string(c));
        case Tok::directive:
          fail(t.where, "unexpected directive '#" + t.text + "' inside a list (directives stand between entries)");
        default:
          parse_item(lx, elements, moved, path, true);
          if (elements.size() >= kBufferedElements) {
            list.append(elements);
            moved += elements.size();
            elements.clear();
          }
          break;
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
  void expand_items(const Token& macro, std::vector<Item>& out, std::size_t before, const std::string& path,
                    bool in_list) {
    const Entry& e = resolve(macro);
    auto path_of = [&](std::size_t k) { return in_list ? index_path(path, before + out.size() + k) : path; };
    if (e.is_dict()) {
      charge(extent(e.dict()), 1, macro);
      if (in_list) {
        out.push_back(Item::make_dict(
            std::make_shared<const Dictionary>(renamed(e.dict(), path_of(0), e.dict().where())), macro.where));
      } else {
        // The whole value of an entry (`sand2 $sand;`): parse_entry() copies it under the
        // new name right after this value is parsed, and nothing is modified meanwhile,
        // so a non-owning pointer (aliasing an empty shared_ptr) avoids a second copy.
        out.push_back(Item::make_dict(std::shared_ptr<const Dictionary>(std::shared_ptr<const Dictionary>(), &e.dict()),
                                      macro.where));
      }
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
    } else if (d.text == "includeEtc") {
      Token file = lx.next();
      if (file.kind != Tok::string)
        fail(d.where, "expected a quoted file name after '#includeEtc', found " + describe(file));
      if (file.text.empty()) fail(file.where, "empty file name after '#includeEtc'");
      include(d, etc_file(d, file.text).string());
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
                        "' (supported: #include \"file\"; #includeEtc \"file\"; #inputMode overwrite|merge|error)");
    }
    if (lx.peek().kind == Tok::semicolon) lx.next();
  }

  /// `#includeEtc "name"`: the first folder of etc_search_path() that has it.
  fs::path etc_file(const Token& directive, const std::string& name) {
    const std::vector<fs::path> dirs = etc_search_path();
    std::string looked, shipped;
    for (const fs::path& dir : dirs) {
      std::error_code ec;
      if (fs::is_regular_file(dir / name, ec)) return dir / name;
      looked += (looked.empty() ? "" : ", ") + absolute_text(dir / name);
      if (!fs::is_directory(dir, ec)) continue;
      std::vector<std::string> files;
      for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
           it.increment(ec))
        if (it->is_regular_file(ec) && it->path().filename().string().rfind("README", 0) != 0)
          files.push_back(it->path().lexically_relative(dir).string());
      std::sort(files.begin(), files.end());
      for (const std::string& f : files) shipped += (shipped.empty() ? "" : ", ") + f;
    }
    fail(directive.where, "cannot find '#includeEtc' file '" + name + "' (looked for " +
                              (looked.empty() ? std::string("it nowhere: no folder is known") : looked) +
                              "; SCREE_ETC adds folders, separated by ':')" +
                              (shipped.empty() ? std::string() : ". Shipped: " + shipped));
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
      case ReadStatus::link_loop: fail(directive.where, "include loop: " + link_loop_text(actual, display));
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
  /// The elements of the list being read at each level of nesting (sized once: a
  /// reference to a level stays valid while deeper lists are read).
  std::vector<std::vector<Item>> elements_;
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
}  // namespace reader

Dictionary Dictionary::read_file(const fs::path& path, std::optional<std::string> display_name) {
  std::string display = display_name ? std::move(*display_name) : path.string();
  std::string text;
  const SourceLocation where{std::make_shared<const std::string>(display), 0, 0};
  fs::file_type kind = fs::file_type::unknown;
  switch (reader::read_text(path, text, kind)) {
    case reader::ReadStatus::ok: break;
    case reader::ReadStatus::missing:
      throw InputError(where, "cannot open file '" + display + "' (looked for " + reader::absolute_text(path) + ")");
    case reader::ReadStatus::link_loop:
      throw InputError(where, "cannot read '" + display + "': " + reader::link_loop_text(path, display));
    case reader::ReadStatus::directory:
      throw InputError(where, "cannot read '" + display + "': " + reader::absolute_text(path) + " is a directory");
    case reader::ReadStatus::not_regular:
      throw InputError(where, "cannot read '" + display + "': " + reader::absolute_text(path) + " is " +
                                  reader::special_file_kind(kind) + ", not a regular file");
    case reader::ReadStatus::unreadable:
      throw InputError(where, "cannot read file '" + display + "' (" + reader::absolute_text(path) + ")");
  }
  return reader::parse_text(std::move(text), display, path);
}

Dictionary Dictionary::parse(std::string_view text, std::string name) {
  const fs::path actual(name);
  return reader::parse_text(std::string(text), name, actual);
}

}  // namespace scree
