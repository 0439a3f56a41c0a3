#pragma once
/// @file detail/cgal_intersections.h
/// Exact intersection tests (CGAL, exact predicates) used by cage validation. Kept in one
/// translation unit because CGAL headers are heavy to compile.

#include "core/common/types.h"

#include <utility>
#include <vector>

namespace bary::detail
{

/// Pairs (i, j), i < j, of polygon edges that intersect although they should not: non-adjacent
/// edges that touch or cross, and adjacent edges that overlap along a segment. Edge i joins
/// V(i) and V((i+1) % n). At most @p max_pairs pairs are returned.
std::vector<std::pair<Index, Index>> polygon_self_intersections(
  const Eigen::MatrixXd& V, std::size_t max_pairs);

/// Pairs of faces of a closed, manifold, consistently oriented triangle mesh that intersect
/// other than along shared edges/vertices. At most @p max_pairs pairs are returned.
std::vector<std::pair<Index, Index>> triangle_mesh_self_intersections(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, std::size_t max_pairs);

} // namespace bary::detail
