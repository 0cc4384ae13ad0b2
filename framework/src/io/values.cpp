// The dictionary's values: entries' typed access (as_scalar, as_integer, ...), with the
// messages that say what was expected and what was found, and lookup by key.

#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>
#include <utility>

#include "format.hpp"
#include "scree/io/dictionary.hpp"

namespace scree {

using reader::describe;
using reader::dict_inline;
using reader::shorten;

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

// ---------------------------------------------------------------------------------------
// Dictionary (except reading)
// ---------------------------------------------------------------------------------------

Dictionary::Dictionary(std::string name, SourceLocation where) : name_(std::move(name)), where_(std::move(where)) {}

namespace {

/// Up to this many entries a dictionary is searched by a scan and index_ stays empty:
/// most dictionaries of a case are that small, and a scan of a few keys is as fast as a
/// hash, without a table to keep.
constexpr std::size_t kScanned = 8;

std::size_t key_hash(std::string_view key) noexcept { return std::hash<std::string_view>{}(key); }

}  // namespace

const Entry* Dictionary::find(std::string_view key) const noexcept {
  if (index_.empty()) {
    for (const Entry& e : entries_)
      if (e.key() == key) return &e;
    return nullptr;
  }
  const std::size_t mask = index_.size() - 1;
  for (std::size_t slot = key_hash(key) & mask;; slot = (slot + 1) & mask) {
    const std::uint32_t p = index_[slot];
    if (p == 0) return nullptr;
    if (entries_[p - 1].key() == key) return &entries_[p - 1];
  }
}

/// Slots for all entries at most three quarters full (linear probing stays short).
void Dictionary::rebuild_index() {
  std::size_t slots = 16;
  while (4 * entries_.size() > 3 * slots) slots *= 2;
  std::vector<std::uint32_t>().swap(index_);  // the old table is gone before the new one is made
  index_.assign(slots, 0);
  const std::size_t mask = slots - 1;
  for (std::size_t p = 0; p < entries_.size(); ++p) {
    std::size_t slot = key_hash(entries_[p].key()) & mask;
    while (index_[slot] != 0) slot = (slot + 1) & mask;
    index_[slot] = static_cast<std::uint32_t>(p + 1);
  }
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
  if (Entry* x = const_cast<Entry*>(find(e.key()))) {  // replacement keeps its position
    *x = std::move(e);
    return;
  }
  if (entries_.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
    throw InputError(e.where(), "too many entries in dictionary '" + name_ + "'");
  entries_.push_back(std::move(e));
  if (entries_.size() <= kScanned) return;
  if (index_.empty() || 4 * entries_.size() > 3 * index_.size()) {
    rebuild_index();
    return;
  }
  const std::size_t mask = index_.size() - 1;
  std::size_t slot = key_hash(entries_.back().key()) & mask;
  while (index_[slot] != 0) slot = (slot + 1) & mask;
  index_[slot] = static_cast<std::uint32_t>(entries_.size());
}

}  // namespace scree
