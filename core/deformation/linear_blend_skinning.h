#pragma once
/// @file linear_blend_skinning.h
/// Linear blend skinning (Magnenat-Thalmann et al. 1988), Eq. (1) of Jacobson et al. 2011:
///
///   x'_p = sum_j W(p, j) (A_j x_p + t_j),
///
/// each handle j carrying an affine transform [A_j | t_j] (dim by dim+1). With weights that sum
/// to 1 the same transform on every handle moves every point by it (partition of unity).
/// Also the paper's §3.4 rotations inferred from translations through pseudo-edges.

#include "core/common/types.h"

#include <vector>

namespace bary
{

/// One affine transform per handle, each dim by dim+1: [A | t], x' = A x + t.
using AffineTransforms = std::vector<Eigen::MatrixXd>;

/// Deforms the rows of @p X (#P by dim) by Eq. (1) with dense weights @p W (#P by #handles).
/// In 2D and 3D a vector kernel (AVX2+FMA where the CPU has it, chosen at run time) blends the
/// transforms per point, sum_j W(p, j) [A_j | t_j], and applies the blend once; other
/// dimensions are summed term by term. Points are independent: computed in parallel with
/// @p threads OpenMP threads (0 = OpenMP's default; sets under 2,048 points use one), in blocks
/// of consecutive points; the result does not depend on the thread count.
/// @throws Error(SizeMismatch) when W has not #P rows or not one column per transform, or a
///   transform is not dim by dim+1 (named); Error(NonFinite) for NaN / infinity in X, W or a
///   transform, or a deformed point that overflows (named); Error(InvalidArgument) for
///   threads < 0.
Points linear_blend_skinning(const Points& X, const DenseWeights& W,
  const AffineTransforms& transforms, int threads = 0);

/// Same with sparse weights (#P by #handles, row-major): only stored entries contribute.
Points linear_blend_skinning(const Points& X, const SparseWeights& W,
  const AffineTransforms& transforms, int threads = 0);

/// A 2D affine transform [A | t] (2 by 3) lifted to 3 by 4 (z kept: A_zz = 1, t_z = 0), the
/// form the VTK filters and pose files use; a 3 by 4 transform is returned as is.
/// @throws Error(SizeMismatch) for any other shape.
Eigen::MatrixXd lift_transform(const Eigen::MatrixXd& T);

/// §3.4, "Specifying handle transforms": the rotation of each point handle is the average of
/// the smallest rotations that take each incident pseudo-edge from its rest direction to its
/// posed direction (2D: the mean of the signed angles; 3D: the normalized sum of the unit
/// quaternions, each sign-aligned with the sum so far), and its translation maps the handle's rest
/// position onto its posed position: t_j = posed_j - R_j rest_j. Handles with no pseudo-edge
/// get the identity rotation (a pure translation).
/// @param rest #H by dim (2 or 3) handle positions at rest
/// @param posed #H by dim their posed positions
/// @param pseudo_edges #E by 2 pairs of handle indices (any order, no self-loops)
/// @return #H transforms, dim by dim+1
/// @throws Error(SizeMismatch) for shapes that differ or dim not 2/3, pseudo_edges not #E by 2;
///   Error(InvalidArgument) naming a pseudo-edge with an index outside [0, #H), a self-loop, or
///   zero length at rest or when posed; Error(NonFinite) for NaN / infinite positions.
AffineTransforms transforms_from_pseudo_edges(
  const Points& rest, const Points& posed, const Eigen::MatrixXi& pseudo_edges);

} // namespace bary
