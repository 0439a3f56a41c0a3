#include "core/analysis/weight_statistics.h"

#include "core/common/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace bary
{

WeightStatistics weight_statistics(const DenseWeights& W, const Eigen::MatrixXd* C,
  const Points* P, const WeightStatisticsOptions& options)
{
  if (W.rows() == 0 || W.cols() == 0)
    throw Error(ErrorCode::EmptyInput, "the weight matrix is empty");
  if ((C == nullptr) != (P == nullptr))
    throw Error(ErrorCode::InvalidArgument,
      "reproduction needs both the control points and the points");
  if (C && C->rows() != W.cols())
    throw Error(ErrorCode::SizeMismatch,
      "the weights have " + std::to_string(W.cols()) + " components but the cage has " +
        std::to_string(C->rows()) + " control points");
  if (P && P->rows() != W.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the weights have " + std::to_string(W.rows()) + " rows but there are " +
        std::to_string(P->rows()) + " points");
  if (C && P && C->cols() != P->cols())
    throw Error(ErrorCode::SizeMismatch, "control points and points differ in dimension");

  WeightStatistics s;
  s.points = W.rows();
  s.controls = W.cols();
  s.threshold = options.threshold >= 0.0 ? options.threshold : 1e-3 / static_cast<double>(W.cols());
  s.significant.assign(static_cast<std::size_t>(W.rows()), 0);
  s.min_weight = std::numeric_limits<double>::infinity();
  s.max_weight = -std::numeric_limits<double>::infinity();
  s.has_reproduction = C != nullptr;
  double diameter = 1.0;
  if (C)
  {
    diameter = (C->colwise().maxCoeff() - C->colwise().minCoeff()).norm();
    if (diameter <= 0.0)
      diameter = 1.0;
  }
  Index finite_rows = 0;
  double sum_partition = 0.0, sum_reproduction = 0.0, sum_significant = 0.0;
  for (Index p = 0; p < W.rows(); ++p)
  {
    if (!W.row(p).allFinite())
    {
      ++s.non_finite_rows;
      continue;
    }
    ++finite_rows;
    const double row_min = W.row(p).minCoeff(), row_max = W.row(p).maxCoeff();
    s.min_weight = std::min(s.min_weight, row_min);
    s.max_weight = std::max(s.max_weight, row_max);
    Index count = 0;
    for (Index i = 0; i < W.cols(); ++i)
    {
      s.negative_weights += W(p, i) < 0.0;
      count += W(p, i) > s.threshold;
    }
    s.significant[static_cast<std::size_t>(p)] = count;
    s.max_significant = std::max(s.max_significant, count);
    sum_significant += static_cast<double>(count);
    const double e = std::abs(W.row(p).sum() - 1.0);
    s.max_partition_error = std::max(s.max_partition_error, e);
    sum_partition += e;
    if (C)
    {
      const double r = (W.row(p) * (*C) - P->row(p)).norm() / diameter;
      s.max_reproduction_error = std::max(s.max_reproduction_error, r);
      sum_reproduction += r;
    }
  }
  if (finite_rows > 0)
  {
    const double n = static_cast<double>(finite_rows);
    s.mean_partition_error = sum_partition / n;
    s.mean_reproduction_error = sum_reproduction / n;
    s.mean_significant = sum_significant / n;
  }
  else
  {
    s.min_weight = s.max_weight = std::numeric_limits<double>::quiet_NaN();
  }
  return s;
}

} // namespace bary
