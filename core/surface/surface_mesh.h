#pragma once
/// @file surface_mesh.h
/// A triangle surface in space as the weighted-averages methods need it (Panozzo et al.,
/// "Weighted averages on surfaces", ACM TOG 32(4), 2013): validated (finite, every vertex used,
/// no degenerate triangle, an edge-manifold and vertex-manifold surface, one connected piece;
/// closed or with boundary, any genus), with the adjacency its algorithms walk:
///
/// - the one-ring of every vertex in fan order (the Loop tangent stencils of §3.2),
/// - the edge graph (the greedy walk of the forward problem, §3.3),
/// - the triangles around every vertex and across every edge (the breadth-first search over
///   triangles, §3.3).
///
/// Orientation is not required to be consistent (the methods use unsigned quantities).

#include "core/common/types.h"

#include <vector>

namespace bary
{

/// Adjacency of a validated triangle surface. Built once by SurfaceMesh's constructor.
struct SurfaceMesh
{
  /// Validates the surface and builds the adjacency.
  /// @param V #V by 3 vertex positions
  /// @param F #F by 3 triangles (indices into V)
  /// @throws Error(EmptyInput) for no vertex or no triangle; Error(SizeMismatch) when V does not
  ///   have 3 columns or F does not have 3; Error(NonFinite) naming a vertex with a NaN or
  ///   infinite coordinate; Error(InvalidArgument) naming: an index out of range, a degenerate
  ///   triangle (area <= 64 eps h^2, h its longest edge; a repeated vertex), a vertex no
  ///   triangle uses, an edge shared by more than two triangles, a vertex whose triangles do not
  ///   form one fan (two surface sheets touching at a point), a surface in several connected
  ///   pieces.
  SurfaceMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

  Eigen::MatrixXd V; ///< #V by 3
  Eigen::MatrixXi F; ///< #F by 3

  /// One-ring of vertex v in fan order: ring[ring_offsets[v] .. ring_offsets[v + 1]). For a
  /// boundary vertex the fan starts and ends at its two boundary neighbours.
  std::vector<int> ring_offsets, ring;
  /// Triangles around vertex v: vertex_faces[face_offsets[v] .. face_offsets[v + 1]).
  std::vector<int> face_offsets, vertex_faces;
  /// #F by 3: the triangle across the edge opposite corner k of triangle f (the edge
  /// F(f, k+1), F(f, k+2)), -1 on the boundary.
  Eigen::MatrixXi face_neighbors;
  /// Per vertex: 1 on the boundary.
  std::vector<char> boundary;
  Index boundary_loops = 0; ///< number of boundary curves (0: closed)
  Index edges = 0;          ///< number of edges
  double mean_edge_length = 0;

  Index vertex_count() const noexcept { return V.rows(); }
  Index face_count() const noexcept { return F.rows(); }
  /// Euler characteristic #V - #E + #F.
  Index euler_characteristic() const noexcept { return V.rows() - edges + F.rows(); }
  /// Genus of the surface (2 - chi - boundary loops) / 2.
  Index genus() const noexcept { return (2 - euler_characteristic() - boundary_loops) / 2; }
};

/// A point on a triangle surface: a triangle and the barycentric coordinates of the point in it
/// (in the order of the triangle's corners; each >= 0, summing to 1).
struct SurfacePoint
{
  Index face = -1;
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
};

/// Default tolerance for points given on a surface (anchors, query points): farther than this
/// fraction of the surface's bounding-box diagonal from it, a point is refused as off the
/// surface.
inline constexpr double kDefaultSurfaceTolerance = 1e-3;

/// Checks a surface tolerance: range [0, 1]. @throws Error(InvalidArgument) naming the value.
void validate_surface_tolerance(double tolerance);

/// The closest point of the surface to each row of @p P (#P by 3), by MeshPointLocator's
/// bounding-volume hierarchy; @p distance (optional) receives each point's distance to it.
/// @throws Error(SizeMismatch) when P does not have 3 columns; Error(NonFinite) naming a
///   non-finite point.
std::vector<SurfacePoint> closest_surface_points(
  const SurfaceMesh& mesh, const Eigen::MatrixXd& P, std::vector<double>* distance = nullptr);

/// Position of surface points on a mesh's vertices (or on any per-vertex quantity X: #V by k):
/// row i = sum_k barycentric_k X.row(F(face, k)). #points by X.cols().
Eigen::MatrixXd surface_point_positions(
  const Eigen::MatrixXi& F, const Eigen::MatrixXd& X, const std::vector<SurfacePoint>& points);

} // namespace bary
