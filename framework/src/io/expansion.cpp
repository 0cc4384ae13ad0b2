// Structure copied by macro expansion (expansion.hpp).

#include "expansion.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <span>

namespace scree::reader {

Extent extent(const Item& item) {
  Extent x{1, 0};
  if (item.kind() == Item::Kind::list) {
    for (const Item& el : item.list()) {
      Extent e = extent(el);
      x.nodes += e.nodes;
      x.depth = std::max(x.depth, e.depth);
    }
    x.depth += 1;
  } else if (item.kind() == Item::Kind::dict && item.dict()) {
    Extent e = extent(*item.dict());
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

namespace {

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

}  // namespace

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

namespace {

bool holds_dictionary(const Item& item) {
  if (item.kind() == Item::Kind::dict) return true;
  const std::span<const Item> list = item.list();
  return std::any_of(list.begin(), list.end(), holds_dictionary);
}

}  // namespace

Item renamed(const Item& item, const std::string& path) {
  if (!holds_dictionary(item)) return item;  // nothing to rename: a plain copy
  if (item.kind() == Item::Kind::list) {
    const std::span<const Item> list = item.list();
    std::vector<Item> elements;
    elements.reserve(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Item& el = list[i];
      elements.push_back(holds_dictionary(el) ? renamed(el, index_path(path, i)) : el);
    }
    return Item::make_list(std::move(elements), item.pos());
  }
  if (!item.dict()) return item;
  return Item::make_dict(std::make_shared<const Dictionary>(renamed(*item.dict(), path, item.dict()->where())),
                         item.pos());
}

Entry renamed(const Entry& e, const std::string& parent) {
  if (e.is_dict()) {
    const std::string path = join_path(parent, e.key());
    return Entry(e.key(), e.pos(), std::make_shared<const Dictionary>(renamed(e.dict(), path, e.dict().where())));
  }
  if (std::none_of(e.items().begin(), e.items().end(), holds_dictionary)) return e;  // nothing to rename
  const std::string path = join_path(parent, e.key());
  std::vector<Item> items;
  items.reserve(e.items().size());
  for (const Item& it : e.items()) items.push_back(renamed(it, path));
  return Entry(e.key(), e.pos(), std::move(items));
}

Dictionary renamed(const Dictionary& src, const std::string& name, const SourceLocation& where) {
  Dictionary d(name, where);
  for (const Entry& e : src.entries()) d.set(renamed(e, name));
  return d;
}


}  // namespace scree::reader
