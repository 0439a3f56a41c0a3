#pragma once
/// @file celestial_coordinates.h
/// T-Celestial and S-Celestial coordinates: Cerveró, Vinacua & Brunet, "3D Model Deformations
/// With Arbitrary Control Points" (shared/papers/celestial-coordinates-cervero.md). Cage-free
/// generalized barycentric coordinates w.r.t. free control points v_1..v_n (no connectivity),
/// defined on their convex hull, in 2D and 3D (the paper is 3D; the 2D scheme is the same
/// equations with 2-vectors). Documentation with measured accuracy and speed:
/// docs/celestial-coordinates.md.
///
/// For a point p, with d_i = |v_i - p| and the unit vectors q_i = (v_i - p) / d_i (the
/// controls projected on the "celestial sphere" of p, Sect. 3), both schemes find positive
/// beta_i with sum_i beta_i q_i = 0 (Eq. 4) and return alpha_i = (beta_i / d_i) /
/// sum_j (beta_j / d_j) (Eq. 3), which then reproduce p: sum_i alpha_i v_i = p.
/// - T scheme (TCC, Sect. 4): beta_i = s_i + exp(psi . q_i) (Eq. 8) with user weights s_i >= 0;
///   psi solves sum_i exp(psi . q_i) q_i = r, r = -sum_i s_i q_i (Eq. 9). Newton from the
///   linearised guess of Sect. 4.2.
/// - S scheme (SCC, Sect. 5): beta_i = mu_i^2, mu_i = q_i . c + sqrt((q_i . c)^2 + lambda^2 +
///   2 lambda |c|) (Eq. 15), where the centre c solves sum_i mu_i^2 q_i = 0 (Eq. 11/18). Newton
///   from c = -l, l the centre of mass of Sect. 5.3.
///
/// How it is solved (details and the reasons in celestial_coordinates.cpp and
/// docs/celestial-coordinates.md):
/// - Both systems are the gradient of a strictly convex potential, so the Jacobian is symmetric
///   positive definite and the solution is unique. For TCC the potential is
///   sum_i exp(psi . q_i) - r . psi. For SCC, mu_i = lambda m(|y|) m(q_i . y) with
///   y = c / sqrt(lambda^2 + 2 lambda |c|) and m(a) = a + sqrt(a^2 + 1), so Eq. (11) reads
///   sum_i m(q_i . y)^2 q_i = 0, the gradient of sum_i (m_i^3 / 6 + m_i / 2). BaryLab runs
///   Newton in y and reports c = lambda m(|y|) y. (In c the Jacobian is not symmetric, has a
///   kink at c = 0 and is singular where |F(c)| has minima that are not solutions: Newton in c
///   stalled on 19.5% of random interior points in our measurement; in y on none.)
/// - Newton is safeguarded by a backtracking (Armijo) line search on that potential (also on
///   the residual norm once the residual is below 1e-6) and capped by max_iterations.
/// - Points are solved in neighbour order (Hilbert curve, or breadth-first over mesh edges)
///   with warm starts, in fixed chunks of 256 points run in parallel: bitwise independent of
///   the number of threads.
/// - Where the CPU has AVX2 and FMA (chosen at run time), the per-point work runs in vector
///   kernels and SCC's warm starts are moved by a first-order prediction (dy/dp); elsewhere
///   the portable code. Both converge to the same solutions to the tolerance.
///
/// Measured (docs/celestial-coordinates.md; AMD EPYC, 2 shared cores, SSE2): 1e6 points with
/// 30 controls in 3D, SCC: 1.7 s, 3.4 Newton iterations per point (6.3 cold); partition of
/// unity <= 3e-15, reproduction <= 5e-13 of the diameter with the default tolerance. With the
/// AVX2 kernels on a loaded Intel Xeon: 1.9x less CPU time, 2.5 iterations per point.
///
/// Properties (measured values in docs/celestial-coordinates.md): inside the convex hull the
/// weights are positive, sum to 1, reproduce p up to tolerance times the hull's diameter, are
/// smooth, global (every control influences every point), invariant under similarity
/// transformations (rotation, translation, uniform scale) of controls and points together —
/// for both schemes, see the docs for why the paper's claim that TCC is not rotation invariant
/// does not hold — but not under affine maps. SCC does not depend on lambda (mu_i is
/// homogeneous of degree 1 in (c, lambda)). On the hull boundary the weights of the controls
/// off the face containing p vanish; for TCC with s = 0 and for SCC the coordinates there are
/// the same scheme in the face (the limit from inside: TCC approaches it like O(h), SCC like
/// O(sqrt(h)) at distance h); for TCC with s != 0 there is no such limit (see
/// CelestialOptions::user_weights).

#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/common/weights_result.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace bary
{

/// Which celestial scheme.
enum class CelestialScheme
{
  T, ///< T-Celestial coordinates (Sect. 4): beta_i = s_i + exp(psi . q_i)
  S, ///< S-Celestial coordinates (Sect. 5): beta_i = mu_i^2 of the wrapping sphere
};

/// What to do with query points outside the convex hull of the controls (where celestial
/// coordinates are not defined: no positive beta with sum beta_i q_i = 0 exists there).
enum class CelestialOutsidePolicy
{
  Error, ///< throw Error(InvalidArgument) with the count and the first ids (before any solve)
  Flag,  ///< give them NaN rows and list them in CelestialResult::outside
};

/// Control points added so that the query points are strictly inside the controls' convex
/// hull (§6: "which can always be ensured adding, if necessary, more control points"). The
/// values are stable (the filters store them by value).
enum class CelestialHullPoints
{
  None = 0,  ///< the controls as given
  Auto = 1,  ///< hull points added only when needed: some query point is not strictly inside
  Always = 2 ///< hull points always added (the same columns whatever the points)
};

/// Where a query point lies relative to the hull, finer than PointLocation (which maps Inside
/// to Inside, Outside to Outside, Boundary and AtControl to Boundary). Decided before solving,
/// with the hull's facet planes.
enum class CelestialLocation : unsigned char
{
  Inside = 0,    ///< strictly inside the hull (more than boundary_tolerance from it): full solve
  Boundary = 1,  ///< on the hull (within boundary_tolerance): solved in the face containing it
  AtControl = 2, ///< within boundary_tolerance of a control point: exact unit row (Lagrange)
  Outside = 3,   ///< outside the hull by more than boundary_tolerance: NaN row or error
};

/// Options for celestial coordinates.
struct CelestialOptions
{
  /// T (Sect. 4) or S (Sect. 5). The paper recommends S (Sect. 6: faster, and TCC is claimed
  /// not to be rotation invariant; in BaryLab both are, see the docs).
  CelestialScheme scheme = CelestialScheme::S;
  /// SCC: the wrapping sphere's radius is lambda + |c| (Sect. 5); the paper only requires
  /// lambda > 1 and gives no value. The coordinates do not depend on it (mu_i is homogeneous
  /// of degree 1 in (c, lambda)); it only scales CelestialResult::solution. Range (1, 1e6].
  double lambda = 2.0;
  /// TCC: the user weights s_i >= 0 of Eq. (8), one per control point (#C). Empty = all zero,
  /// which is the paper's Eq. (7). With s != 0 the coordinates have no limit at the hull's
  /// boundary (near a face psi grows like 1 / distance and the weights drift towards a
  /// piecewise-linear interpolant); points on the boundary get the TCC of the face with the
  /// face's s_i, which is then not the limit from inside. Must be empty for the S scheme.
  Eigen::VectorXd user_weights;
  /// Newton stops when the relative residual rho = |sum_i beta_i q_i| / sum_i beta_i
  /// (CelestialResult::residual) is <= max(tolerance, 4 u (|x|_1 + #C)), u = 2^-53, x the
  /// unknown (psi, or y for SCC). The reproduction error |sum_i alpha_i v_i - p| is at most
  /// rho * max_i d_i <= rho * (hull diameter). The second term is the rounding floor of
  /// evaluating the sum at x; it exceeds 1e-12 only within ~1e-9 of the hull's diameter from its
  /// boundary, where |x| grows (SCC: |y| ~ distance^-1/2; TCC with s != 0: |psi| ~ 1 /
  /// distance). The paper stops at an absolute 1e-6. Range [1e-15, 1e-3].
  double tolerance = 1e-12;
  /// Cap on Newton iterations per point (and per face solve). Range [1, 10000]. A cold start
  /// needs 3-8 iterations inside, up to ~35 within 1e-12 of the boundary.
  int max_iterations = 100;
  /// Start each point's Newton from the solution of an already solved neighbour (Sect. 4.2 and
  /// 5.3) instead of the cold initial guess. The order: a space-filling (Hilbert) curve through
  /// the points, or breadth-first over the mesh edges when given; cut into fixed-size chunks
  /// solved in parallel, warm starts only inside a chunk. A warm start that fails is retried
  /// cold. Changes the iteration counts, not the weights (beyond the tolerance).
  bool warm_start = true;
  /// Policy for points outside the convex hull.
  CelestialOutsidePolicy outside = CelestialOutsidePolicy::Error;
  /// Hull points (§6: "which can always be ensured adding, if necessary, more control
  /// points"; the paper's organs use "eight external points"). With Auto, when some query point
  /// is not strictly inside the controls' hull (outside it, or on it within boundary_tolerance;
  /// points at a control do not count), compute() adds the 2^dim corners of an oriented box
  /// around the query points and the controls (hull_points_for), enlarged by hull_margin times
  /// its diagonal on every side, as controls #C .. #C + 2^dim - 1
  /// (CelestialResult::added_controls), and solves with all of them: every query point is then
  /// strictly inside and gets positive weights. When every point is strictly inside, nothing is
  /// added and the result is bitwise that of None. Always adds the corners in any case. The box
  /// is placed from the points alone (no coordinate axes), so the weights stay invariant under
  /// rotations, translations and uniform scaling of the whole scene. The corners stay where
  /// they are when the user's controls move. With Auto or Always the controls may also be fewer
  /// than dim + 1 or flat (a line, a plane): the corners are then always added. TCC gives them
  /// s_i = 0. Default None here (the paper's domain: points outside are an error or NaN rows,
  /// see outside); the front ends' default is Auto (core/coordinates/weight_methods.h).
  CelestialHullPoints hull_points = CelestialHullPoints::None;
  /// Margin of the added hull points, relative to the diagonal of the oriented box around the
  /// query points and the controls (hull_points_for), in [1e-6, 10] (> 0, so that every point
  /// is strictly inside the added corners' box). Default 0.1.
  double hull_margin = 0.1;
  /// With Auto or Always: the points from which the hull points are decided and placed, when
  /// the query points are a part of them (a distributed run's piece; non-owning, #R by dim,
  /// must outlive compute()). Null (default): the query points. Every part then gets the
  /// whole's columns: Auto adds the corners when some reference point needs them.
  const Points* hull_reference = nullptr;
  /// If true, compute() throws Error(NotConverged) naming the points that did not converge and
  /// their residuals; if false they get NaN rows and are listed in CelestialResult::not_converged.
  bool require_convergence = true;
  /// Distance (relative to the bounding-box diagonal of the controls) under which a point
  /// counts as lying on the hull's boundary or on a control point, and two controls count as
  /// coincident. Points within it of the hull get the coordinates of the face (reproducing
  /// their projection on it, so the reproduction error there is at most this times the
  /// diagonal). Range [1e-15, 1e-6].
  double boundary_tolerance = 1e-12;
  /// Number of threads; 0 = OpenMP's default. The result does not depend on it (bitwise): the
  /// order, the chunks and the warm starts do not depend on the thread count.
  int threads = 0;
};

/// Result of compute(). WeightsResult's fields: W (#P by #C + #A, #A the added hull points
/// of CelestialHullPoints::Auto / Always in added_controls, their columns last; rows of outside and
/// non-converged points are NaN), location (#P: hull_location as a PointLocation), undefined
/// (outside and not_converged, merged, ascending), converged (not_converged is empty) and the
/// statistics, in this order: hull_facets, newton_iterations (total_iterations),
/// mean_newton_iterations (per point), max_newton_iterations, warm_starts, cold_restarts,
/// max_residual (over the finite residuals), at_control, not_converged (how many),
/// solve_seconds (seconds), hull_points_added (#A).
struct CelestialResult : WeightsResult
{
  /// #P, where each point lies relative to the hull.
  std::vector<CelestialLocation> hull_location;
  /// Ids (ascending) of the points outside the controls' convex hull.
  std::vector<Index> outside;
  /// Ids (ascending) of the points whose Newton did not reach the tolerance.
  std::vector<Index> not_converged;
  /// #P, Newton iterations per point (of the last attempt; 0 at a control and outside).
  Eigen::VectorXi iterations;
  /// #P, final relative residual |sum beta_i q_i| / sum beta_i per point (of the face solve
  /// for Boundary points; 0 at a control, NaN outside). See CelestialOptions::tolerance.
  Eigen::VectorXd residual;
  /// #P by dim, the paper's unknown for Inside points: psi (TCC) or the centre c of the
  /// wrapping sphere relative to p, in the units of the celestial sphere (SCC). NaN rows for
  /// the other locations (on a face the unknown lives in the face; at a control there is none).
  Points solution;
  /// Locations are relative to the hull actually used (the user's controls and, when some were
  /// added, the hull points: WeightsResult::added_controls).
  Index inside = 0, boundary = 0, at_control = 0; ///< counts of each location (outside: .size())
  long long total_iterations = 0; ///< sum of iterations (including failed warm attempts)
  Index warm_starts = 0;          ///< points started from a neighbour's solution
  Index cold_restarts = 0;        ///< warm-started points that failed and were solved again cold
  double seconds = 0.0;           ///< wall-clock time of compute()
};

/// Precomputes the convex hull of the control points (its facets and, recursively, the faces'
/// own hulls) and evaluates celestial coordinates at many points.
///
/// Thread-safe for concurrent const calls.
class CelestialCoordinates
{
public:
  /// Validates the controls (#C by dim, dim = 2 or 3) and the options and builds the hull.
  /// @throws Error(EmptyInput) without controls; Error(SizeMismatch) if dim is not 2 or 3 or
  /// user_weights has the wrong size; Error(NonFinite) naming a non-finite control;
  /// Error(InvalidArgument) for options out of range, fewer than dim + 1 controls, coincident
  /// controls (naming the pair) or controls on one line (2D) / one plane (3D).
  explicit CelestialCoordinates(Points controls, const CelestialOptions& options = {});
  ~CelestialCoordinates();
  CelestialCoordinates(CelestialCoordinates&&) noexcept;
  CelestialCoordinates& operator=(CelestialCoordinates&&) noexcept;

  /// Coordinates of the rows of @p X (#P by dim). Points are ordered along a Hilbert curve for
  /// the warm starts.
  /// @throws Error(SizeMismatch) if X has the wrong number of columns, Error(NonFinite) naming
  /// the first non-finite point, Error(InvalidArgument) for points outside the hull under
  /// CelestialOutsidePolicy::Error, Error(NotConverged) under require_convergence,
  /// Error(Cancelled) if @p progress returned false.
  CelestialResult compute(const Points& X, const ProgressCallback& progress = {}) const;

  /// Same, into @p result, reusing the storage of its arrays (W, hull_location, iterations,
  /// residual, solution) where their sizes match, e.g. across the frames of an animation: every
  /// field is overwritten, and the result equals compute(X)'s bit for bit. Saves allocating
  /// and first touching #P x #C doubles a call (240 MB at 10^6 points and 30 controls).
  /// @throws as compute(X); for bad points (wrong dimension, non-finite) before @p result is
  /// touched; after that (points outside, not converged, cancelled) @p result is left valid
  /// but unspecified.
  void compute(const Points& X, CelestialResult& result, const ProgressCallback& progress = {}) const;

  /// Same, with the warm starts ordered breadth-first over the mesh @p edges (#E by 2, indices
  /// into the rows of X; neighbours visited nearest first, as in Sect. 4.2), each point started
  /// from its nearest already solved neighbour. Points without edges are visited in Hilbert
  /// order. @throws as above, and Error(SizeMismatch | InvalidArgument) for bad edges.
  CelestialResult compute(
    const Points& X, const Eigen::MatrixXi& edges, const ProgressCallback& progress = {}) const;

  /// Same, each Inside point's Newton started from row p of @p initial (#P by dim, in the form
  /// of CelestialResult::solution: psi for TCC, c for SCC) where that row is finite, instead of
  /// a neighbour's solution; e.g. the solution of the same points before a control point was
  /// added or removed (an interactive edit: the solution moves little). A start that fails is
  /// retried cold; the weights are the same as compute()'s up to the tolerance.
  /// @throws as compute(), and Error(SizeMismatch) if initial is not #P by dim.
  CelestialResult compute_from(const Points& X, const Points& initial,
    const ProgressCallback& progress = {}) const;

  Index num_controls() const noexcept;
  int dimension() const noexcept;
  const Points& controls() const noexcept;
  const CelestialOptions& options() const noexcept;
  /// Number of facets (distinct supporting planes) of the controls' convex hull (0 when the
  /// controls span no interior, allowed with CelestialHullPoints::Auto or Always only).
  Index num_hull_facets() const noexcept;
  /// The hull points CelestialHullPoints::Auto / Always add for the query points @p X (#P by
  /// dim), whether or not compute() needs them: the 2^dim corners of a box around the controls
  /// and X, in a frame built from these points alone. With P the controls then X and c their
  /// centroid: axis e1 points from c to the point farthest from c; in 3D e2 points to the point
  /// farthest from the line (c, e1), made orthogonal to e1, and e3 = e1 x e2; in 2D e2 is e1
  /// turned by +90 degrees. Ties (distances within a relative 1e-9 of the largest) go to the
  /// lowest index, so that symmetric sets (a cube's corners) give the same frame after a
  /// rotation. The box spans P's extent along each axis, enlarged on every side by hull_margin
  /// times its diagonal; corner k lies at the maximum along e_j iff bit j of k is set. The
  /// corners therefore rotate, translate and scale with the scene, and so the weights do not
  /// change. Exception: 3D points all on one line get e2 from the coordinate axis least aligned
  /// with e1 (any roll about the line encloses them).
  /// @throws Error(SizeMismatch) for X not #P by dim, Error(NonFinite) for a non-finite
  ///   coordinate, Error(InvalidArgument) when the controls and X all coincide (no box).
  Points hull_points_for(const Points& X) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-call form: the #P by #C celestial coordinates of the rows of @p X w.r.t. @p controls
/// (throws as CelestialCoordinates and its compute()).
CelestialResult celestial_coordinates(const Points& controls, const Points& X,
  const CelestialOptions& options = {}, const ProgressCallback& progress = {});

} // namespace bary
