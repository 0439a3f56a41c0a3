#pragma once
/// @file types.h
/// Matrix types shared by every method.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace bary
{

using Index = Eigen::Index;

/// Dense weights, #P by #C, row-major: row p holds the weights of point p, column i belongs to
/// control point i. Row-major so a row is contiguous, which is both how per-point methods fill
/// it and how VTK stores a multi-component point-data array.
using DenseWeights = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Sparse weights, #P by #C, row-major compressed (CSR).
using SparseWeights = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// Points, #P by dim (dim = 2 or 3), one point per row.
using Points = Eigen::MatrixXd;

} // namespace bary
