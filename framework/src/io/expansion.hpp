// Structure copied by macro expansion (private to the dictionary reader): how big and how
// deep it is (so that expansion can be bounded), copies named after their new place, the
// dotted paths that name dictionaries, and the nearest key for "did you mean".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "scree/io/dictionary.hpp"

namespace scree::reader {

struct Extent {
  std::size_t nodes = 0;  ///< items and entries
  int depth = 0;          ///< levels of ( ) and { }
};

Extent extent(const Item& item);
Extent extent(const Dictionary& d);

/// The key of `dicts` closest to `word` (a likely typo), or "" when none is close:
/// one edit for names of 3 to 5 characters, two from 6, and so on.
std::string nearest_key(std::string_view word, const std::vector<const Dictionary*>& dicts);

/// "a.b" from "a" and "b" ("b" at the top level, where the path is "").
std::string join_path(const std::string& path, const std::string& key);
/// "a.b[3]": element `i` of the list at `path`.
std::string index_path(const std::string& path, std::size_t i);

/// A copy of `item` whose dictionaries are named after their new place (`path`).
Item renamed(const Item& item, const std::string& path);
/// A copy of entry `e` placed in the dictionary named `parent`.
Entry renamed(const Entry& e, const std::string& parent);
/// A copy of `src` named `name`, located at `where`.
Dictionary renamed(const Dictionary& src, const std::string& name, const SourceLocation& where);

}  // namespace scree::reader
