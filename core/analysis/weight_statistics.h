#pragma once
/// @file weight_statistics.h
/// Property checks for any weight field: partition of unity, reproduction, range, and how many
/// weights per point are significant (the locality measure of Zhang et al. 2014, Eq. 19–21).

#include "core/common/types.h"

#include <vector>

namespace bary
{

struct WeightStatisticsOptions
{
  /// A weight counts as significant when it is > threshold. A negative value selects the LBC
  /// paper's 1e-3 / #C.
  double threshold = -1.0;
};

struct WeightStatistics
{
  Index points = 0;                ///< #P
  Index controls = 0;              ///< #C
  double threshold = 0.0;          ///< the threshold actually used
  double min_weight = 0.0;         ///< smallest weight (finite entries)
  double max_weight = 0.0;         ///< largest weight (finite entries)
  Index negative_weights = 0;      ///< entries < 0
  Index non_finite_rows = 0;       ///< rows holding NaN/inf (excluded from the errors below)
  double max_partition_error = 0;  ///< max_p |sum_i W(p,i) - 1|
  double mean_partition_error = 0; ///< mean_p |sum_i W(p,i) - 1|
  bool has_reproduction = false;   ///< reproduction errors computed (cage and points given)
  double max_reproduction_error = 0;  ///< max_p |sum_i W(p,i) c_i - x_p| / cage diameter
  double mean_reproduction_error = 0; ///< mean of the same
  std::vector<Index> significant;  ///< #P, count of weights > threshold per point
  double mean_significant = 0;     ///< mean of significant
  Index max_significant = 0;       ///< max of significant
};

/// Statistics of @p W (#P by #C). With @p C (#C by dim control points) and @p P (#P by dim
/// points) also the reproduction error.
/// @throws Error(SizeMismatch) for inconsistent shapes, Error(EmptyInput) for empty W.
WeightStatistics weight_statistics(const DenseWeights& W, const Eigen::MatrixXd* C = nullptr,
  const Points* P = nullptr, const WeightStatisticsOptions& options = {});

} // namespace bary
