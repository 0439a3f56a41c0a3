#pragma once
/// @file format.h
/// Numbers, points and index lists as core's error messages write them. Every formatter writes
/// what std::ostream writes with the given precision (significant digits, "%g" style).

#include "core/common/types.h"

#include <Eigen/Core>

#include <string>

namespace bary::detail
{

/// @p x with @p precision significant digits (6: the stream default), e.g. "0.333333", "1e-12".
std::string format_number(double x, int precision = 6);

/// "(x0, x1, ...)": the @p n doubles at @p x, each with @p precision significant digits.
std::string format_point(const double* x, Index n, int precision = 6);

/// "(x0, x1, ...)": row @p i of @p V, each entry with @p precision significant digits.
std::string format_row(const Eigen::MatrixXd& V, Index i, int precision = 6);

/// "a, b, c": row @p i of the index matrix @p T.
std::string format_index_row(const Eigen::MatrixXi& T, Index i);

} // namespace bary::detail
