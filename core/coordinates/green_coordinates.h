#pragma once
/// @file green_coordinates.h
/// Green coordinates: Lipman, Levin & Cohen-Or, "Green Coordinates", ACM TOG 27(3) (SIGGRAPH
/// 2008). A point x inside the cage is written as
///
///   x = sum_i phi_i(x) v_i + sum_j psi_j(x) n(t_j),
///
/// with v_i the cage vertices and n(t_j) the unit normals of the cage faces t_j (edges in 2D),
/// from Green's third identity applied to the linear function x (the paper's derivation):
///
///   phi_i(x) = integral over the faces around v_i of Gamma_i(xi) dG/dn(xi, x),
///   psi_j(x) = - integral over t_j of G(xi, x),
///
/// Gamma_i the hat function of v_i, G the fundamental solution of the Laplacian (2D:
/// log(r) / (2 pi); 3D: -1 / (4 pi r)), n the outward normal. A deformed cage (v'_i, t'_j) moves x
/// to
///
///   x' = sum_i phi_i(x) v'_i + sum_j psi_j(x) s_j n(t'_j),
///
/// with the stretch factors s_j of the paper (2D |e'_j| / |e_j|; 3D the paper's formula from
/// the edge vectors of t_j and t'_j): conformal in 2D, quasi-conformal in 3D, and exact under
/// similarities of the cage (bary::deform_points_green, core/deformation/cage_deformation.h).
///
/// Closed forms (derived in green_coordinates.cpp; the same integrals as the paper's Algorithm 1
/// and its appendix's GCTriInt, arranged for accuracy; checked against a quadrature in the tests):
/// - 2D, per edge: the angle the edge subtends at x, a log of the distance ratio of its ends
///   and their product with the edge's geometry (no arctangent of a ratio that overflows near
///   the edge's line);
/// - 3D, per triangle: the signed solid angle (van Oosterom & Strackee), the three edge
///   integrals of 1/r, and the single-layer integral of 1/r over the triangle from the
///   divergence theorem in its plane; phi of the triangle's vertices comes from one vector w
///   without dividing by x's height over the triangle, so nothing blows up near its plane.
///
/// Orientation: either cage orientation is accepted (validate_cage). psi is the coefficient of
/// each face's normal *as its vertex order orients it* (2D: edge j's direction e_j rotated
/// clockwise, (e_y, -e_x) / |e|, outward for a counter-clockwise polygon; 3D: the right-hand
/// normal of (V(F(j,0)), V(F(j,1)), V(F(j,2))), outward for outward-oriented faces), so that
/// x = phi V + psi N holds for both orientations and the deformation uses the deformed faces'
/// normals by the same rule.
///
/// Points on the cage (within the boundary tolerance) get the limits from inside: the
/// single-layer part psi is continuous there; the double-layer part phi jumps across the
/// boundary, and its interior limit is the principal value plus the faces' share of the solid
/// angle, 2 pi (4 pi) minus what the other faces subtend, spread over the point's face, edge or
/// vertex with its barycentric coordinates.
///
/// Points outside the cage: the integrals there give sum phi = 0 and phi V + psi N = 0 (Green's
/// identity outside), so the paper's extension beyond the cage is applied by default: a point
/// that left the cage through face t_j (taken as the face nearest to it) is written as
/// x = sum_k alpha_k v_k + beta n(t_j) over that face's vertices (alpha the affine coordinates
/// of x's projection onto the face's plane, beta its height), and alpha_k is added to phi_k,
/// beta to psi_j. Coordinates and deformation then continue across the interior
/// of t_j (the limits from both sides agree); they jump where the nearest face changes outside
/// the cage (near convex corners), as the paper's piecewise extension does.
///
/// Properties (inside the cage): sum phi_i = 1, linear reproduction x = phi V + psi N (with the
/// extension, outside too), smooth (harmonic) inside, not interpolating (a cage vertex is not
/// mapped to its moved position), phi may be negative, psi of either sign (2D: scale dependent).

#include "core/common/cage.h"
#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/common/weights_result.h"

#include <vector>

namespace bary
{

/// Options for Green coordinates.
struct GreenOptions
{
  /// Points closer to the cage than this (relative to the cage's bounding-box diagonal) are
  /// treated as lying on it and get the limits from inside (see the file comment). Range
  /// [0, 1e-3]. The formulas are accurate right up to the cage, so this only decides which
  /// points are *reported* and evaluated as boundary points.
  double boundary_tolerance = 1e-10;
  /// Points outside the cage get the paper's extension through their nearest face:
  /// the deformation continues across the cage. Off: the raw integrals (sum phi = 0 and
  /// phi V + psi N = 0 outside, a deformation that collapses outside points towards 0).
  bool extend_outside = true;
  /// Validate the cage (validate_cage) when the evaluator is built.
  bool validate = true;
  /// Options passed to validate_cage.
  CageValidationOptions validation;
  /// Number of threads for batch evaluation; 0 = all cores. The result does not depend on it.
  int threads = 0;
};

/// Result of a batch evaluation. WeightsResult's fields: W = phi (#P by #C), face_weights = psi
/// (#P by #F: 3D the triangles of Cage::F, 2D edge j from V(j) to V(j+1)), location (#P:
/// Inside / Outside by the winding number, Boundary within the tolerance), undefined (always
/// empty: Green coordinates are defined everywhere), no statistics, converged always true.
struct GreenResult : WeightsResult
{
  Index inside = 0, outside = 0, boundary = 0; ///< counts of each location
};

/// Precomputes a cage's faces (normals, areas, edge normals) once and evaluates Green
/// coordinates at many points. Thread-safe for concurrent const calls.
class GreenCoordinates
{
public:
  /// Validates the cage (unless options.validate is false) and keeps a copy.
  /// @throws Error(InvalidCage | EmptyInput | NonFinite | SizeMismatch | InvalidArgument)
  explicit GreenCoordinates(Cage cage, const GreenOptions& options = {});

  const Cage& cage() const noexcept { return cage_; }
  int dimension() const noexcept { return cage_.dimension(); }
  Index num_controls() const noexcept { return cage_.num_controls(); }
  /// Number of faces: #F in 3D, #C (edges) in 2D.
  Index num_faces() const noexcept { return dimension() == 2 ? cage_.num_controls() : cage_.F.rows(); }

  /// Coordinates at one point @p x (dimension() doubles): @p phi (num_controls() doubles) and
  /// @p psi (num_faces() doubles). Returns where x lies. Pure; no allocation beyond a
  /// thread-local scratch buffer.
  PointLocation evaluate(const double* x, double* phi, double* psi) const;

  /// Coordinates at the rows of @p P (#P by dimension()), in parallel.
  /// @throws Error(SizeMismatch) if P has the wrong number of columns, Error(NonFinite) naming
  /// the first non-finite point, Error(Cancelled) if @p progress returned false.
  GreenResult evaluate(const Points& P, const ProgressCallback& progress = {}) const;

private:
  PointLocation evaluate_2d(const double* x, double* phi, double* psi) const;
  PointLocation evaluate_3d(const double* x, double* phi, double* psi) const;
  void extend_2d(const double* x, double* phi, double* psi) const;
  void extend_3d(const double* x, double* phi, double* psi) const;

  Cage cage_;
  GreenOptions options_;
  double tolerance_ = 0.0; // absolute boundary tolerance
  double sigma_ = 1.0;     // +1 for a counter-clockwise polygon / outward faces, -1 otherwise
  // 3D, per face: unit normal (3), twice the area, and per edge the in-plane outward normal
  // and the unit tangent (9 each)
  std::vector<double> normal_, twice_area_, edge_normal_, edge_tangent_;
};

/// One-call form: Green coordinates (phi in W, psi in face_weights) of the rows of @p P.
GreenResult green_coordinates(const Cage& cage, const Points& P, const GreenOptions& options = {});

} // namespace bary
