// Ranks: the statistics of a function object combined over the ranks of a decomposed run.
//
// A decomposed run (case/decomposition.hpp) spreads a case's points over its ranks. A
// function object that reduces over ranks (function_object.hpp) is executed on every rank
// with the points that rank holds, and combines what it measures through these calls:
// every call is collective (each rank makes the same calls in the same order) and leaves
// the result on every rank. On one rank each call returns its argument: the arithmetic
// is the single-process run's, operation for operation.
//
// Sums combine each rank's partial sum, so a decomposed sum differs from the one-rank sum
// by round-off (a relative 1e-16 per point); maxima, minima, counts and quantiles are the
// one-rank values exactly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "scree/comm/comm.hpp"
#include "scree/core/config.hpp"

namespace scree {

class SCREE_API Ranks {
 public:
  /// One rank (no messages).
  Ranks() = default;
  /// The ranks of `comm` (a plugin's SolverContext::comm; one rank where it is null).
  explicit Ranks(std::shared_ptr<Comm> comm) : comm_(std::move(comm)) {}

  int rank() const { return comm_ ? comm_->rank() : 0; }
  int size() const { return comm_ ? comm_->size() : 1; }
  /// The rank that writes the files (rank 0).
  bool root() const { return rank() == 0; }

  /// Element-wise over the ranks, in place.
  void sum(std::vector<double>& v) const;
  void max(std::vector<double>& v) const;
  void min(std::vector<double>& v) const;
  void sum(std::vector<std::int64_t>& v) const;
  double sum(double v) const;
  double max(double v) const;
  double min(double v) const;
  std::int64_t sum(std::int64_t v) const;

  /// The q-quantile (0 < q <= 1) of every rank's values together: the k-th smallest with
  /// k = ceil(q n), n the number of values over all ranks, so q = 1 is the maximum; NaN
  /// when no rank has a value. Reorders `v`. The values must not be NaN.
  double quantile(std::vector<double>& v, double q) const;

  /// Every rank's `v` concatenated in rank order, on the root (empty elsewhere).
  template <class T>
  std::vector<T> gather(const std::vector<T>& v) const {
    if (size() == 1) return v;
    return comm_->gather_vector(v, 0);
  }

 private:
  std::shared_ptr<Comm> comm_;
};

}  // namespace scree
