#pragma once
/// @file cage_deformation.h
/// Linear deformation by weights: x'_p = sum_i W(p, i) c'_i. The building block every
/// coordinate-based deformation reuses (cages, point handles, control points).

#include "core/common/types.h"

namespace bary
{

/// Deformed points: @p W (#P by #C) times @p C (#C by dim, the moved control points).
/// @throws Error(SizeMismatch) if W.cols() != C.rows(), Error(EmptyInput) if #C == 0,
/// Error(NonFinite) if C holds NaN/inf.
Points deform_points(const DenseWeights& W, const Eigen::MatrixXd& C);
/// Same with sparse weights (only the stored entries contribute).
Points deform_points(const SparseWeights& W, const Eigen::MatrixXd& C);

/// Keeps the entries of @p W whose value is strictly greater than @p threshold and stores them
/// sparsely. If @p renormalize, each row is rescaled to sum to one (rows left with no entry are
/// kept empty and counted in @p empty_rows when given).
SparseWeights sparsify_weights(const DenseWeights& W, double threshold, bool renormalize,
  Index* empty_rows = nullptr);

} // namespace bary
