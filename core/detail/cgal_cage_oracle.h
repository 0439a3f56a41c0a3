#pragma once
/// @file detail/cgal_cage_oracle.h
/// Exact geometric tests of the enclosing-cage generator (core/meshing/enclosing_cage.h): does a
/// region swept by an edge collapse touch the model, do two cage faces (or polygon edges)
/// intersect other than along what they share. CGAL's exact predicates (Epick); in a
/// translation unit of its own, with the other CGAL files (barylab_core_cgal), so that CGAL's
/// headers and -frounding-math reach no other core file.

#include <Eigen/Core>

#include <array>
#include <memory>
#include <vector>

namespace bary::detail
{

using Point3d = std::array<double, 3>;

/// The model, as an AABB tree of its triangles (#F by 3) or segments (#F by 2; 2D polygons).
/// 2D models are given with z = 0. Thread-safe for concurrent const calls.
class CageModelOracle
{
public:
  /// @param V #V by 3 positions; @param F #F by 3 triangles or #F by 2 segments (non-empty).
  CageModelOracle(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  ~CageModelOracle();
  CageModelOracle(const CageModelOracle&) = delete;
  CageModelOracle& operator=(const CageModelOracle&) = delete;

  /// True when some model element meets (touches or crosses) one of the closed tetrahedra
  /// (apex, b[0], b[1], b[2]); a flat tetrahedron is tested as its four triangles (a triangle
  /// degenerate to a segment as its segments). Exact.
  bool tetrahedra_touch_model(const Point3d& apex, const std::vector<std::array<Point3d, 3>>& bases) const;
  /// Same for closed triangles (apex, b[0], b[1]) (2D: all in z = 0; a collinear triangle is
  /// tested as its segments). Exact.
  bool triangles_touch_model(const Point3d& apex, const std::vector<std::array<Point3d, 2>>& bases) const;
  /// Distance from @p p to the model (rounded constructions).
  double distance(const Point3d& p) const;
  /// The model's point closest to @p p (rounded constructions).
  Point3d closest_point(const Point3d& p) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// True when triangles A and B intersect other than in what they share: @p ia and @p ib are
/// their vertex ids (equal ids = the same point). Sharing nothing: any contact; a vertex: any
/// other contact; an edge: the two faces coplanar and on the same side of it; all three: true.
/// Exact. Triangles must not be degenerate.
bool triangles_intersect_improperly(const std::array<Point3d, 3>& A, const std::array<int, 3>& ia,
  const std::array<Point3d, 3>& B, const std::array<int, 3>& ib);

/// 2D: true when segments A and B (x, y; ids as above) intersect other than at a shared end.
bool segments_intersect_improperly(const std::array<std::array<double, 2>, 2>& A,
  const std::array<int, 2>& ia, const std::array<std::array<double, 2>, 2>& B,
  const std::array<int, 2>& ib);

} // namespace bary::detail
