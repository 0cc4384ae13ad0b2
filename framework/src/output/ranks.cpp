// Ranks (see scree/output/ranks.hpp).
#include "scree/output/ranks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace scree {

void Ranks::sum(std::vector<double>& v) const {
  if (size() > 1 && !v.empty()) comm_->sum(v.data(), static_cast<int>(v.size()));
}

void Ranks::max(std::vector<double>& v) const {
  if (size() > 1 && !v.empty()) comm_->max(v.data(), static_cast<int>(v.size()));
}

void Ranks::min(std::vector<double>& v) const {
  if (size() == 1 || v.empty()) return;
  for (double& x : v) x = -x;
  comm_->max(v.data(), static_cast<int>(v.size()));
  for (double& x : v) x = -x;
}

void Ranks::sum(std::vector<std::int64_t>& v) const {
  if (size() == 1 || v.empty()) return;
  // Two's complement: the sum of the unsigned images is the image of the sum.
  std::vector<std::uint64_t> u(v.size());
  std::memcpy(u.data(), v.data(), v.size() * sizeof(std::uint64_t));
  comm_->sum(u.data(), static_cast<int>(u.size()));
  std::memcpy(v.data(), u.data(), v.size() * sizeof(std::uint64_t));
}

double Ranks::sum(double v) const {
  std::vector<double> x{v};
  sum(x);
  return x[0];
}

double Ranks::max(double v) const {
  std::vector<double> x{v};
  max(x);
  return x[0];
}

double Ranks::min(double v) const {
  std::vector<double> x{v};
  min(x);
  return x[0];
}

std::int64_t Ranks::sum(std::int64_t v) const {
  std::vector<std::int64_t> x{v};
  sum(x);
  return x[0];
}

namespace {
/// An integer image of a double that orders as the doubles do (-0 just below +0).
std::uint64_t order_key(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return (b >> 63) ? ~b : (b | (std::uint64_t(1) << 63));
}
double from_key(std::uint64_t k) {
  const std::uint64_t b = (k >> 63) ? (k & ~(std::uint64_t(1) << 63)) : ~k;
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}
}  // namespace

double Ranks::quantile(std::vector<double>& v, double q) const {
  const auto n = static_cast<std::uint64_t>(sum(static_cast<std::int64_t>(v.size())));
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  auto k = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(n) - 1e-9));
  k = std::clamp<std::uint64_t>(k, 1, n);
  if (size() == 1) {
    const auto at = v.begin() + static_cast<std::ptrdiff_t>(k - 1);
    std::nth_element(v.begin(), at, v.end());
    return *at;
  }
  // The k-th smallest of the values of every rank: the least key K with at least k values
  // at or below it, found by bisecting the 64-bit keys (64 rounds of one sum each).
  std::vector<std::uint64_t> keys(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) keys[i] = order_key(v[i]);
  std::sort(keys.begin(), keys.end());
  std::uint64_t lo = 0, hi = std::numeric_limits<std::uint64_t>::max();
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    std::uint64_t at_or_below = static_cast<std::uint64_t>(std::upper_bound(keys.begin(), keys.end(), mid) - keys.begin());
    comm_->sum(&at_or_below, 1);
    if (at_or_below >= k)
      hi = mid;
    else
      lo = mid + 1;
  }
  return from_key(lo);
}

}  // namespace scree
