#pragma once
/// @file cage_deformation.h
/// Linear deformation by weights: x'_p = sum_i W(p, i) c'_i. The building block every
/// coordinate-based deformation reuses (cages, point handles, control points).

#include "core/common/cage.h"
#include "core/common/types.h"

namespace bary
{

/// Deformed points: @p W (#P by #C) times @p C (#C by dim, the moved control points).
/// @throws Error(SizeMismatch) if W.cols() != C.rows(), Error(EmptyInput) if #C == 0,
/// Error(NonFinite) if C holds NaN/inf.
Points deform_points(const DenseWeights& W, const Eigen::MatrixXd& C);
/// Same with sparse weights (only the stored entries contribute).
Points deform_points(const SparseWeights& W, const Eigen::MatrixXd& C);

/// Green coordinates' normal terms of a deformed cage (Lipman et al. 2008): row j is s_j n(t'_j),
/// the unit normal of the deformed face (2D: edge) j as its vertex order orients it (the
/// convention of GreenResult::face_weights) times the paper's stretch factor: 2D
/// s_j = |e'_j| / |e_j| (so the row is (e'_y, -e'_x) / |e_j|); 3D, with u, v the edge vectors
/// V1 - V0, V2 - V0 of the rest face and u', v' those of the deformed one,
/// s_j = sqrt(|u'|^2 |v|^2 - 2 (u'.v')(u.v) + |v'|^2 |u|^2) / (sqrt(8) area(t_j)) (the affine
/// map's Frobenius norm over sqrt 2: s_j = lambda for a face scaled by lambda). A deformed 3D
/// face of zero area has no normal: its row is 0.
/// @param rest the rest cage (#C by dim vertices; 3D: its triangles F)
/// @param deformed #C by dim, the moved vertices in the same order
/// @throws Error(SizeMismatch) on shapes that do not match, Error(NonFinite) for NaN/inf.
Eigen::MatrixXd green_face_terms(const Cage& rest, const Eigen::MatrixXd& deformed);

/// Green coordinates' deformation (Lipman et al. 2008):
/// x' = sum_i phi(p, i) v'_i + sum_j psi(p, j) s_j n(t'_j), i.e. phi V' + psi green_face_terms.
/// @param phi #P by #C vertex coordinates (WeightsResult::W of the Green method)
/// @param psi #P by #F face coefficients (WeightsResult::face_weights)
/// @throws Error(SizeMismatch) on shapes that do not match, Error(NonFinite) for NaN/inf in the
/// deformed cage.
Points deform_points_green(const DenseWeights& phi, const DenseWeights& psi, const Cage& rest,
  const Eigen::MatrixXd& deformed);

/// Keeps the entries of @p W whose value is strictly greater than @p threshold and stores them
/// sparsely. If @p renormalize, each row is rescaled to sum to one (rows left with no entry are
/// kept empty and counted in @p empty_rows when given).
SparseWeights sparsify_weights(const DenseWeights& W, double threshold, bool renormalize,
  Index* empty_rows = nullptr);

} // namespace bary
