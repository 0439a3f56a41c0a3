#pragma once
/// @file mean_value_coordinates.h
/// Mean value coordinates.
/// - 2D: Hormann & Floater, "Mean value coordinates for arbitrary planar polygons", ACM TOG
///   25(4), 2006 — w_i = (tan(a_{i-1}/2) + tan(a_i/2)) / r_i, normalised, with tan(a/2)
///   evaluated as sin(a)/(1+cos(a)) for a < pi/2 and (1-cos(a))/sin(a) otherwise, so neither
///   form cancels; on an edge the coordinates are the linear interpolant of its end points.
/// - 3D: Ju, Schaefer & Warren, "Mean value coordinates for closed triangular meshes", ACM TOG
///   24(3), 2005 — the per-triangle formula of its Sect. 3.2 / Fig. 4, rewritten so that nothing
///   cancels near the cage: the sine of the spherical angle comes from det[u0,u1,u2] instead of
///   sqrt(1 - c^2), which keeps full accuracy down to ~1e-15 of the cage size from a face or
///   edge (see mean_value_coordinates.cpp); points at a vertex, on an edge or on a face (within
///   the boundary tolerance) get the exact linear/barycentric interpolant.
///
/// Properties (inside the cage): partition of unity, linear reproduction, Lagrange property at
/// the cage vertices, linear on cage edges (2D) and faces (3D), smooth (C-infinity) away from the
/// cage, may be negative for non-convex cages. Outside the cage they are still defined (and
/// still reproduce linear functions) wherever the denominator does not vanish.

#include "core/common/cage.h"
#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/common/weights_result.h"

#include <array>
#include <vector>

namespace bary
{

/// Options for mean value coordinates.
struct MeanValueOptions
{
  /// Points closer to the cage than this (relative to the cage's bounding-box diagonal) are
  /// treated as lying on the cage: their weights are the exact linear (2D edge) or barycentric
  /// (3D face) interpolant, which is the limit of the coordinates there. Range [0, 1e-3].
  double boundary_tolerance = 1e-10;
  /// Validate the cage (validate_cage) when the evaluator is built.
  bool validate = true;
  /// Options passed to validate_cage.
  CageValidationOptions validation;
  /// Number of threads for batch evaluation; 0 = all cores (OpenMP's default). The result does not depend
  /// on it: every point is computed independently and written to its own row.
  int threads = 0;
};

/// Result of a batch evaluation. WeightsResult's fields: W (#P by #C), location (#P: Inside
/// for |winding number| = 1, either cage orientation; Outside for winding number 0; Boundary
/// on a cage vertex, edge or face within the boundary tolerance), undefined (points whose
/// weights could not be normalised, sum of raw weights ~ 0, which can only happen outside the
/// cage: their rows are NaN), no statistics, converged always true.
struct MeanValueResult : WeightsResult
{
  Index inside = 0, outside = 0, boundary = 0; ///< counts of each location
};

/// Precomputes what a cage needs once and evaluates mean value coordinates at many points.
///
/// Thread-safe for concurrent const calls.
class MeanValueCoordinates
{
public:
  /// Validates the cage (unless options.validate is false) and keeps a copy.
  /// @throws Error(InvalidCage | EmptyInput | NonFinite | SizeMismatch | InvalidArgument)
  explicit MeanValueCoordinates(Cage cage, const MeanValueOptions& options = {});

  const Cage& cage() const noexcept { return cage_; }
  int dimension() const noexcept { return cage_.dimension(); }
  Index num_controls() const noexcept { return cage_.num_controls(); }

  /// Weights at one point @p x (dimension() doubles) written to @p w (num_controls() doubles).
  /// Returns where x lies. If the weights are undefined there (sum ~ 0, outside only), @p w is
  /// filled with NaN. Does not allocate (beyond a thread-local scratch buffer); pure.
  PointLocation evaluate(const double* x, double* w) const;

  /// Weights at the rows of @p P (#P by dimension()), in parallel.
  /// @throws Error(SizeMismatch) if P has the wrong number of columns, Error(NonFinite) naming
  /// the first non-finite point, Error(Cancelled) if @p progress returned false.
  MeanValueResult evaluate(const Points& P, const ProgressCallback& progress = {}) const;

  /// The same into @p result, every field overwritten, reusing the storage of its W and location
  /// where they already have the points' shape: repeated evaluations (a moving probe, frames of
  /// points against one cage) then neither allocate nor first-touch #P x #C doubles (at 20,000
  /// points and 642 controls, 103 MB: page faults and zeroing cost ~10% of the call).
  /// @throws as above; @p result is then unspecified.
  void evaluate(const Points& P, MeanValueResult& result, const ProgressCallback& progress = {}) const;

private:
  PointLocation evaluate_2d(const double* x, double* w) const;
  PointLocation evaluate_3d(const double* x, double* w) const;

  Cage cage_;
  MeanValueOptions options_;
  double tolerance_ = 0.0;          // absolute boundary tolerance
  // 3D: per face 1 / (2 area) and its three edges (edge index << 1 | reversed), and the edges
  // (vertex pairs, smaller index first); arc quantities are computed once per edge.
  std::vector<double> inv_twice_area_;
  std::vector<unsigned> face_edges_;
  std::vector<std::array<int, 2>> edges_;
};

/// One-call form: the #P by #C mean value coordinates of the rows of @p P w.r.t. @p cage.
DenseWeights mean_value_coordinates(
  const Cage& cage, const Points& P, const MeanValueOptions& options = {});

} // namespace bary
