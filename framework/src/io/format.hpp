// The dictionary reader's writing side (private): values written back in dictionary
// syntax, and the words messages use for what was found.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "scree/io/dictionary.hpp"

namespace scree::reader {

/// `s` in double quotes, with '"' and '\' escaped.
std::string quote(std::string_view s);
/// A key or word written so that it reads back the same (quoted when it is not a word).
std::string word_text(std::string_view s);
/// The shortest text that reads back as `v` (integral numbers without a '.').
std::string format_number(double v, bool integral);
/// `s` cut to the width a message quotes ("..." at the end when cut).
std::string shorten(std::string s);
/// "the word 'ten'", "the number 2.5", ...: what a message says was found.
std::string describe(const Item& item);
/// The items separated by spaces.
std::string join_items(std::span<const Item> items);
/// `{ key value; sub { ... } }` on one line (dictionaries inside lists, messages).
std::string dict_inline(const Dictionary& d);

}  // namespace scree::reader
