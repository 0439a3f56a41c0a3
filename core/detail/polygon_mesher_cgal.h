#pragma once
/// @file detail/polygon_mesher_cgal.h
/// The CGAL part of mesh_polygon (domain_mesh.h), kept in one translation unit because CGAL's
/// headers are heavy to compile.

#include "core/common/types.h"

#include <functional>
#include <vector>

namespace bary::detail
{

/// Throws Error(InvalidCage) if the rings (rings[0] the outer polygon, the others holes, each
/// already a valid simple polygon) intersect or touch each other, if a hole is not inside the
/// outer polygon, or if a hole lies inside another hole. Exact predicates.
void check_polygon_rings(const std::vector<Eigen::MatrixXd>& rings);

/// What cgal_mesh_polygon needs.
struct PolygonMesherInput
{
  std::vector<Eigen::MatrixXd> rings; ///< rings[0] the outer polygon, then the holes
  Eigen::MatrixXd steiner;            ///< #S by 2 distinct points strictly inside the domain
  double max_area = 0.0;              ///< > 0: triangle area bound
  double shape_bound = 0.0;           ///< bound on sin^2 of the smallest angle (0 = none)
  /// Called every few hundred refinement steps with the current number of vertices; returning
  /// false stops the refinement (the output is then incomplete and `cancelled` is set).
  std::function<bool(Index)> step;
};

/// Output: V (#V by 2), T (#T by 3, counter-clockwise). Vertex order: the rings' vertices
/// (rings[0] first), then the Steiner points, in input order, then the added vertices.
struct PolygonMesherOutput
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  bool cancelled = false;
};

/// Constrained Delaunay triangulation of the rings and the Steiner points, refined with
/// CGAL::Delaunay_mesher_2 under an area bound and a smallest-angle bound, restricted to the
/// inside of rings[0] minus the holes.
PolygonMesherOutput cgal_mesh_polygon(const PolygonMesherInput& input);

} // namespace bary::detail
