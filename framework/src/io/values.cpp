// The dictionary's values: items' compact storage, entries' typed access (as_scalar,
// as_integer, ...), with the messages that say what was expected and what was found, and
// lookup by key.

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "format.hpp"
#include "lexer.hpp"
#include "scree/io/dictionary.hpp"

namespace scree {

using reader::describe;
using reader::dict_inline;
using reader::shorten;

// ---------------------------------------------------------------------------------------
// Item
// ---------------------------------------------------------------------------------------

static_assert(sizeof(Item) == 24, "an item is 24 bytes: tables hold millions of them");

/// A list's elements: how many, room for how many, then the elements.
struct Item::ListBlock {
  std::uint32_t size;
  std::uint32_t capacity;
  Item* items() noexcept { return reinterpret_cast<Item*>(this + 1); }
};
static_assert(sizeof(Item) % alignof(Item) == 0 && alignof(Item) <= 8);

namespace {

/// A number's text packed two characters a byte: its characters are digits, '+', '-',
/// '.', 'e' and 'E', each a code below 16.
constexpr char kNumberChars[] = "0123456789+-.eE";

int number_code(char c) {
  const char* p = std::strchr(kNumberChars, c);
  return c != '\0' && p ? static_cast<int>(p - kNumberChars) : -1;
}

/// Heap text: its length, then its bytes.
char* new_text(std::string_view text) {
  char* p = static_cast<char*>(::operator new(sizeof(std::size_t) + text.size()));
  const std::size_t n = text.size();
  std::memcpy(p, &n, sizeof n);
  if (n) std::memcpy(p + sizeof n, text.data(), n);
  return p;
}
std::string_view heap_text(const char* p) {
  std::size_t n = 0;
  std::memcpy(&n, p, sizeof n);
  return {p + sizeof n, n};
}

}  // namespace

void* Item::pointer() const noexcept {
  void* p = nullptr;
  std::memcpy(&p, bytes_ + 1, sizeof p);
  return p;
}

void Item::set_pointer(const void* p) noexcept { std::memcpy(bytes_ + 1, &p, sizeof p); }

Item::ListBlock* Item::block() const noexcept { return static_cast<ListBlock*>(pointer()); }

void Item::release() noexcept {
  switch (kind_) {
    case Kind::word:
    case Kind::string:
    case Kind::number:
      if (bits_ & kHeap) ::operator delete(pointer());
      break;
    case Kind::list:
      if (ListBlock* b = block()) {
        for (std::uint32_t i = 0; i < b->size; ++i) b->items()[i].~Item();
        ::operator delete(b);
      }
      break;
    case Kind::dict: delete static_cast<std::shared_ptr<const Dictionary>*>(pointer()); break;
  }
  kind_ = Kind::word;
  bits_ = 0;
  size_ = 0;
}

void Item::set_text(std::string_view text) {
  if (kind_ == Kind::number && text.size() <= 2 * kInline) {
    bool packed = true;
    unsigned char b[kInline] = {};
    for (std::size_t i = 0; i < text.size() && packed; ++i) {
      const int code = number_code(text[i]);
      if (code < 0) packed = false;
      else b[i / 2] |= static_cast<unsigned char>(i % 2 ? code << 4 : code);
    }
    if (packed) {
      std::memcpy(bytes_, b, kInline);
      size_ = static_cast<std::uint8_t>(text.size());
      return;
    }
  } else if (kind_ != Kind::number && text.size() <= kInline) {
    if (!text.empty()) std::memcpy(bytes_, text.data(), text.size());
    size_ = static_cast<std::uint8_t>(text.size());
    return;
  }
  set_pointer(new_text(text));
  bits_ |= kHeap;
}

std::string Item::text() const {
  switch (kind_) {
    case Kind::word:
    case Kind::string:
      if (bits_ & kHeap) return std::string(heap_text(static_cast<const char*>(pointer())));
      return std::string(reinterpret_cast<const char*>(bytes_), size_);
    case Kind::number: {
      if (bits_ & kHeap) return std::string(heap_text(static_cast<const char*>(pointer())));
      std::string s(size_, '\0');
      for (std::size_t i = 0; i < size_; ++i) s[i] = kNumberChars[(bytes_[i / 2] >> (i % 2 ? 4 : 0)) & 0xF];
      return s;
    }
    case Kind::list:
    case Kind::dict: break;
  }
  return {};
}

double Item::number() const noexcept {
  if (kind_ != Kind::number) return 0;
  char packed[2 * kInline];
  std::string_view t;
  if (bits_ & kHeap) {
    t = heap_text(static_cast<const char*>(pointer()));
  } else {
    for (std::size_t i = 0; i < size_; ++i) packed[i] = kNumberChars[(bytes_[i / 2] >> (i % 2 ? 4 : 0)) & 0xF];
    t = std::string_view(packed, size_);
  }
  double v = 0;
  bool integral = false;
  if (reader::parse_number(t, v, integral) == reader::NumberStatus::ok) return v;
  // Written by make_number(value) for a value no number text reads as.
  if (t == "inf") return std::numeric_limits<double>::infinity();
  if (t == "-inf") return -std::numeric_limits<double>::infinity();
  return std::numeric_limits<double>::quiet_NaN();
}

std::span<const Item> Item::list() const noexcept {
  if (kind_ != Kind::list) return {};
  const ListBlock* b = block();
  return b ? std::span<const Item>(const_cast<ListBlock*>(b)->items(), b->size) : std::span<const Item>();
}

const Dictionary* Item::dict() const noexcept {
  if (kind_ != Kind::dict) return nullptr;
  return static_cast<const std::shared_ptr<const Dictionary>*>(pointer())->get();
}

Item::Item(const Item& other) : pos_(other.pos_), kind_(other.kind_), bits_(other.bits_), size_(other.size_) {
  std::memcpy(bytes_, other.bytes_, kInline);
  switch (kind_) {
    case Kind::word:
    case Kind::string:
    case Kind::number:
      if (bits_ & kHeap) set_pointer(new_text(heap_text(static_cast<const char*>(other.pointer()))));
      break;
    case Kind::list: {
      set_pointer(nullptr);
      const std::span<const Item> from = other.list();
      if (from.empty()) break;
      auto* b = static_cast<ListBlock*>(::operator new(sizeof(ListBlock) + from.size() * sizeof(Item)));
      b->size = 0;
      b->capacity = static_cast<std::uint32_t>(from.size());
      try {
        for (const Item& el : from) {
          new (b->items() + b->size) Item(el);
          ++b->size;
        }
      } catch (...) {  // this item is not constructed: its destructor will not run
        for (std::uint32_t i = 0; i < b->size; ++i) b->items()[i].~Item();
        ::operator delete(b);
        throw;
      }
      set_pointer(b);
      break;
    }
    case Kind::dict:
      set_pointer(new std::shared_ptr<const Dictionary>(*static_cast<const std::shared_ptr<const Dictionary>*>(other.pointer())));
      break;
  }
}

Item::Item(Item&& other) noexcept : pos_(other.pos_), kind_(other.kind_), bits_(other.bits_), size_(other.size_) {
  std::memcpy(bytes_, other.bytes_, kInline);
  other.kind_ = Kind::word;  // the storage is ours now
  other.bits_ = 0;
  other.size_ = 0;
}

Item& Item::operator=(const Item& other) {
  if (this != &other) *this = Item(other);
  return *this;
}

Item& Item::operator=(Item&& other) noexcept {
  if (this != &other) {
    release();
    pos_ = other.pos_;
    kind_ = other.kind_;
    bits_ = other.bits_;
    size_ = other.size_;
    std::memcpy(bytes_, other.bytes_, kInline);
    other.kind_ = Kind::word;
    other.bits_ = 0;
    other.size_ = 0;
  }
  return *this;
}

Item::~Item() { release(); }

Item Item::make_word(std::string_view text, SourcePos where) {
  Item it;
  it.pos_ = where;
  it.set_text(text);
  return it;
}

Item Item::make_string(std::string_view text, SourcePos where) {
  Item it;
  it.kind_ = Kind::string;
  it.pos_ = where;
  it.set_text(text);
  return it;
}

Item Item::make_number(std::string_view text, SourcePos where) {
  Item it;
  it.kind_ = Kind::number;
  it.pos_ = where;
  double v = 0;
  bool integral = false;
  if (reader::parse_number(text, v, integral) != reader::NumberStatus::ok)
    throw std::invalid_argument("Item::make_number: '" + std::string(text) + "' is not a number");
  if (integral) it.bits_ |= kIntegral;
  it.set_text(text);
  return it;
}

Item Item::make_number(double value, bool integral, SourcePos where) {
  Item it;
  it.kind_ = Kind::number;
  it.pos_ = where;
  if (integral) it.bits_ |= kIntegral;
  it.set_text(reader::format_number(value, integral));
  return it;
}

Item Item::make_list(Item* first, std::size_t count, SourcePos where) {
  Item it;
  it.kind_ = Kind::list;
  it.pos_ = where;
  it.set_pointer(nullptr);
  it.append(std::span<Item>(first, count));
  return it;
}

Item Item::make_list(std::vector<Item> elements, SourcePos where) {
  return make_list(elements.data(), elements.size(), where);
}

Item Item::make_dict(std::shared_ptr<const Dictionary> dict, SourcePos where) {
  Item it;
  it.kind_ = Kind::dict;
  it.pos_ = where;
  it.set_pointer(new std::shared_ptr<const Dictionary>(std::move(dict)));
  return it;
}

void Item::append(std::span<Item> elements) {
  if (kind_ != Kind::list) throw std::logic_error("Item::append: not a list");
  if (elements.empty()) return;
  ListBlock* b = block();
  const std::size_t size = b ? b->size : 0, capacity = b ? b->capacity : 0;
  const std::size_t needed = size + elements.size();
  if (needed > std::numeric_limits<std::uint32_t>::max()) throw std::length_error("list too long");
  if (needed > capacity) {
    // An empty list gets exactly what it is given (most lists are complete when made);
    // one that grows gets room for as much again.
    std::size_t room = size == 0 ? needed : std::max(needed, 2 * capacity);
    room = std::min<std::size_t>(room, std::numeric_limits<std::uint32_t>::max());
    auto* grown = static_cast<ListBlock*>(::operator new(sizeof(ListBlock) + room * sizeof(Item)));
    grown->size = static_cast<std::uint32_t>(size);
    grown->capacity = static_cast<std::uint32_t>(room);
    for (std::size_t i = 0; i < size; ++i) {
      new (grown->items() + i) Item(std::move(b->items()[i]));
      b->items()[i].~Item();
    }
    if (b) ::operator delete(b);
    b = grown;
    set_pointer(b);
  }
  for (Item& el : elements) {
    new (b->items() + b->size) Item(std::move(el));
    ++b->size;
  }
}

// ---------------------------------------------------------------------------------------
// Entry
// ---------------------------------------------------------------------------------------

Entry::Entry(std::string key, SourcePos where, std::vector<Item> items) : key_(std::move(key)), where_(where) {
  if (items.size() == 1) {
    shape_ = Shape::one;
    value_ = std::move(items.front());
  } else {
    shape_ = Shape::items;
    value_ = Item::make_list(std::move(items), where);
  }
}

Entry::Entry(std::string key, SourcePos where, std::shared_ptr<const Dictionary> dict)
    : key_(std::move(key)), where_(where), shape_(Shape::dict), value_(Item::make_dict(std::move(dict), where)) {}

std::span<const Item> Entry::items() const noexcept {
  switch (shape_) {
    case Shape::one: return {&value_, 1};
    case Shape::items: return value_.list();
    case Shape::dict: break;
  }
  return {};
}

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
  if (shape_ != Shape::dict || !value_.dict())
    throw InputError(where_, "'" + shorten(key_) + "' must be a dictionary { ... }, found " + describe_value(*this));
  return *value_.dict();
}

const Item& Entry::single_item() const { return only_item(*this, "a single value"); }

double Entry::as_scalar() const {
  const Item& it = only_item(*this, "a number");
  if (it.kind() != Item::Kind::number) entry_error(*this, "a number", describe(it));
  return it.number();
}

long long Entry::as_integer() const {
  const char* expected = "an integer";
  const Item& it = only_item(*this, expected);
  if (it.kind() != Item::Kind::number) entry_error(*this, expected, describe(it));
  const std::string text = it.text();
  if (it.integral() && !text.empty()) {
    std::string_view t = text;
    if (t[0] == '+') t.remove_prefix(1);
    long long v = 0;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec == std::errc() && end == t.data() + t.size()) return v;
    if (ec == std::errc::result_out_of_range)
      entry_error(*this, expected, describe(it) + ", which is out of range (the limit is +-9223372036854775807)");
  }
  const double v = it.number();
  if (!std::isfinite(v) || v != std::trunc(v)) entry_error(*this, expected, describe(it));
  if (!in_integer_range(v))
    entry_error(*this, expected, describe(it) + ", which is out of range (the limit is +-9223372036854775807)");
  return static_cast<long long>(v);
}

bool Entry::as_bool() const {
  const char* expected = "a boolean (true/false, yes/no, on/off)";
  const Item& it = only_item(*this, expected);
  if (it.kind() == Item::Kind::word) {
    const std::string w = it.text();
    if (w == "true" || w == "yes" || w == "on") return true;
    if (w == "false" || w == "no" || w == "off") return false;
  }
  entry_error(*this, expected, describe(it));
}

std::string Entry::as_word() const {
  const Item& it = only_item(*this, "a word");
  if (it.kind() != Item::Kind::word && it.kind() != Item::Kind::string) entry_error(*this, "a word", describe(it));
  return it.text();
}

std::vector<double> Entry::as_scalar_list() const {
  const char* expected = "a list of numbers";
  const Item& it = only_item(*this, expected);
  if (it.kind() != Item::Kind::list) entry_error(*this, expected, describe(it));
  std::vector<double> values;
  values.reserve(it.list().size());
  for (std::size_t i = 0; i < it.list().size(); ++i) {
    const Item& el = it.list()[i];
    if (el.kind() != Item::Kind::number)
      throw InputError(where_, shorten(key_) + ": expected a list of numbers, but element " + std::to_string(i + 1) +
                                   " is " + describe(el));
    values.push_back(el.number());
  }
  return values;
}

std::vector<std::string> Entry::as_word_list() const {
  const char* expected = "a list of words";
  const Item& it = only_item(*this, expected);
  if (it.kind() != Item::Kind::list) entry_error(*this, expected, describe(it));
  std::vector<std::string> words;
  words.reserve(it.list().size());
  for (std::size_t i = 0; i < it.list().size(); ++i) {
    const Item& el = it.list()[i];
    if (el.kind() != Item::Kind::word && el.kind() != Item::Kind::string)
      throw InputError(where_, shorten(key_) + ": expected a list of words, but element " + std::to_string(i + 1) +
                                   " is " + describe(el));
    words.push_back(el.text());
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

// ---------------------------------------------------------------------------------------

Entry* EntryList::slot(std::size_t i) const noexcept {
  if (i < kSmall) return small_ + i;
  // Block b holds the items from index 2^(b + kSmallBits) on: the bit length of i names it.
  const int b = static_cast<int>(std::bit_width(i)) - 1;
  return blocks_[static_cast<std::size_t>(b - kSmallBits)] + (i - (std::size_t(1) << b));
}

void EntryList::push_back(Entry e) {
  if (size_ < kSmall) {
    if (size_ == small_capacity_) {  // grown as a vector grows: moved into twice the room
      const std::size_t room = std::min(kSmall, std::max<std::size_t>(1, 2 * small_capacity_));
      auto* grown = static_cast<Entry*>(::operator new(room * sizeof(Entry)));
      for (std::size_t k = 0; k < size_; ++k) {
        new (grown + k) Entry(std::move(small_[k]));
        small_[k].~Entry();
      }
      ::operator delete(small_);
      small_ = grown;
      small_capacity_ = room;
    }
    new (small_ + size_) Entry(std::move(e));
  } else {
    const int b = static_cast<int>(std::bit_width(size_)) - 1;
    if (static_cast<std::size_t>(b - kSmallBits) == blocks_.size())  // a new block: its pages touched as filled
      blocks_.push_back(static_cast<Entry*>(::operator new(sizeof(Entry) << b)));
    new (blocks_.back() + (size_ - (std::size_t(1) << b))) Entry(std::move(e));
  }
  ++size_;
}

void EntryList::clear() noexcept {
  for (std::size_t i = 0; i < size_; ++i) slot(i)->~Entry();
  ::operator delete(small_);
  for (Entry* b : blocks_) ::operator delete(b);
  small_ = nullptr;
  small_capacity_ = 0;
  blocks_.clear();
  size_ = 0;
}

EntryList::~EntryList() { clear(); }

EntryList::EntryList(const EntryList& other) {
  for (const Entry& e : other) push_back(e);
}

EntryList::EntryList(EntryList&& other) noexcept
    : small_(std::exchange(other.small_, nullptr)),
      small_capacity_(std::exchange(other.small_capacity_, 0)),
      blocks_(std::move(other.blocks_)),
      size_(std::exchange(other.size_, 0)) {
  other.blocks_.clear();
}

EntryList& EntryList::operator=(const EntryList& other) {
  if (this != &other) {
    EntryList copy(other);
    *this = std::move(copy);
  }
  return *this;
}

EntryList& EntryList::operator=(EntryList&& other) noexcept {
  if (this != &other) {
    clear();
    small_ = std::exchange(other.small_, nullptr);
    small_capacity_ = std::exchange(other.small_capacity_, 0);
    blocks_ = std::move(other.blocks_);
    other.blocks_.clear();
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

std::size_t Dictionary::position(std::string_view key) const noexcept {
  if (index_.empty()) {
    for (std::size_t p = 0; p < entries_.size(); ++p)
      if (entries_[p].key() == key) return p;
    return npos;
  }
  const std::size_t mask = index_.size() - 1;
  for (std::size_t slot = key_hash(key) & mask;; slot = (slot + 1) & mask) {
    const std::uint32_t p = index_[slot];
    if (p == 0) return npos;
    if (entries_[p - 1].key() == key) return p - 1;
  }
}

const Entry* Dictionary::find(std::string_view key) const noexcept {
  const std::size_t p = position(key);
  return p == npos ? nullptr : &entries_[p];
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
