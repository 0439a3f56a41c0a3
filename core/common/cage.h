#pragma once
/// @file cage.h
/// Cages: closed polygons (2D) and closed triangle meshes (3D), and their validation.

#include "core/common/types.h"

#include <string>
#include <vector>

namespace bary
{

/// A cage.
/// - 2D: V is #C by 2, the vertices of one closed simple polygon in order (either orientation);
///   F is empty. Edge i joins V(i) and V((i+1) % #C).
/// - 3D: V is #C by 3; F is #F by 3, the triangles of a closed, manifold, consistently oriented
///   surface (outward or inward) that uses every vertex.
struct Cage
{
  Eigen::MatrixXd V; ///< #C by dim control points
  Eigen::MatrixXi F; ///< #F by 3 triangles (3D only)

  int dimension() const noexcept { return static_cast<int>(V.cols()); }
  Index num_controls() const noexcept { return V.rows(); }
  /// Length of the bounding-box diagonal (0 for an empty cage).
  double diameter() const;
};

/// What validate_cage checks; all on by default.
struct CageValidationOptions
{
  /// Reject self-intersecting cages (2D: edges crossing; 3D: faces intersecting anywhere but
  /// along shared edges and vertices). Exact predicates (CGAL), O(#F log #F) typical.
  bool check_self_intersections = true;
  /// Relative tolerance (times the cage diameter) below which two vertices are "coincident"
  /// and a face or edge is "degenerate".
  double degenerate_tolerance = 1e-12;
};

/// Checks that @p cage is usable by cage-based coordinates and throws Error(InvalidCage) with a
/// message that names the first problem found (which vertex, edge or face), Error(EmptyInput)
/// for an empty cage, Error(NonFinite) for NaN/inf coordinates and Error(SizeMismatch) for bad
/// shapes.
///
/// 2D: at least 3 vertices, finite, no two consecutive vertices coincident, no zero-length
/// edges, a non-zero area, simple (no two edges intersect except consecutive ones at their
/// shared vertex).
/// 3D: triangles only, indices in range, no degenerate (zero-area) face, every edge shared by
/// exactly two faces (closed, edge-manifold), each directed edge used once (consistently
/// oriented), vertex-manifold (the faces around a vertex form one fan), every vertex used,
/// non-zero enclosed volume, no self-intersections.
void validate_cage(const Cage& cage, const CageValidationOptions& options = {});

/// Signed area (2D, positive for counter-clockwise) or signed volume (3D, positive for outward
/// normals) enclosed by the cage.
double signed_measure(const Cage& cage);

/// Area of a 2D polygon cage / volume of a closed 3D cage, whatever its orientation:
/// |signed_measure(cage)|. Used to turn a target number of mesh cells into a size bound.
double enclosed_measure(const Cage& cage);

/// True if the faces (3D) are oriented outward, or the polygon (2D) is counter-clockwise.
bool is_positively_oriented(const Cage& cage);

} // namespace bary
