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

/// Largest side of the bounding box of the rows of @p V: 0 for no rows, NaN when an entry is not
/// finite.
double bounding_box_extent(const Eigen::MatrixXd& V);

/// Extreme scales are normalised by a power of two: cage validation, meshing (CGAL, TetGen) and
/// the weights computations (compute_weights) run on the geometry times 2^k, k =
/// scale_exponent(extent), and scale their results back. This is exact (a power of two changes
/// no digit of a double) and changes no weights (every method is invariant under uniform
/// scaling; sizes such as max_cell_size are scaled with the geometry). Untreated, a cube of side
/// 1e75 crashed TetGen's predicates, one of 1e-50 made its refinement run out of memory, and the
/// mean value coordinates of a 1e100 cube were NaN.
/// @return 0 for extents in [kScaleBandMin, kScaleBandMax] (the geometry is used as given) and
///   for 0 or non-finite extents (refused later by validation); otherwise the k that puts
///   2^k x extent in [0.5, 1).
int scale_exponent(double extent);
constexpr double kScaleBandMin = 1.0 / 65536.0; ///< 2^-16, about 1.5e-5
constexpr double kScaleBandMax = 65536.0;       ///< 2^16

/// Area of a 2D polygon cage / volume of a closed 3D cage, whatever its orientation:
/// |signed_measure(cage)|. Used to turn a target number of mesh cells into a size bound.
double enclosed_measure(const Cage& cage);

/// True if the faces (3D) are oriented outward, or the polygon (2D) is counter-clockwise.
bool is_positively_oriented(const Cage& cage);

} // namespace bary
