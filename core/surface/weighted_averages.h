#pragma once
/// @file weighted_averages.h
/// Weighted averages of points on a surface and their inverse (Panozzo et al., "Weighted
/// averages on surfaces", ACM TOG 32(4), 2013, §3.3-3.4), on a surface with a Euclidean
/// embedding (euclidean_embedding.h) and its Phong projection (phong_projection.h).
///
/// **Forward problem** (§3.3): anchors x_i on the surface and weights w_i (summing to 1) give
/// ybar = sum_i w_i e(x_i) in R^D, whose Phong projection onto the embedded mesh is the average.
/// The search is the paper's: a greedy walk on the edge graph towards ybar until no neighbour
/// is closer to ybar, then a breadth-first search over triangles from that vertex's triangles,
/// stopping at the first triangle where a Phong projection exists. The walk starts from the
/// vertex of the previous query's result (warm start), a hint, or else from the vertex a grid
/// over three coordinates of the embedding holds for ybar's cell (built once; the vertex
/// nearest to the cell's centre) unless that is farther than two cells from ybar, when the
/// nearest corner of the anchor nearest to ybar in R^D is also considered (the paper starts from
/// the heaviest anchor when nothing better is known; a nearer start shortens the walk). The
/// walk's distances are in single precision (they only choose where the search starts; it
/// ends at a vertex nearer to ybar than its neighbours all the same), and the vertex's triangles
/// are tried in order of the smallest Euclidean barycentric coordinate of ybar in them, the
/// largest first. A query whose search finds none (within max_triangles) is reported as failed,
/// never returned as a point. Search::BruteForce projects onto every triangle and keeps the
/// projection closest to ybar (Definition 2), for validation. Queries go four at a time
/// through each stage (their walks in turns, their first Phong projections in one vector
/// iteration) so that their latencies overlap; a warm start makes them go one at a time.
/// A row of weights that is not an average's is found while its query runs and the first such
/// row is reported after all of them (the same row whatever the thread count).
///
/// **Inverse problem** (§3.4): for a point xhat on triangle t with barycentric coordinates xi,
/// the weights minimise |D w|^2 subject to Psi(xi) (yhat - sum_i w_i y_i) = 0 and sum_i w_i = 1
/// (Eq. 13), with D_ii = |v_T|^2 + gamma |v_O|^2, v_T and v_O the parts of y_i - yhat in and
/// orthogonal to the tangent plane Psi(xi) (gamma = 10, the paper's). The solution is
/// w = D^-2 A^T (A D^-2 A^T)^+ b with A = [P Y^T; 1^T], b = [P yhat; 1], P an orthonormal basis
/// of Psi's rows (A D^-2 A^T, 3 by 3, is inverted by cofactors when its equilibrated Cholesky
/// pivots are above 1e-6, else by the pseudo-inverse that drops directions below 1e-14 of its
/// largest eigenvalue; then one step of iterative refinement; where that leaves the partition
/// of unity inexact, the row is scaled to sum to 1, which keeps the homogeneous tangential
/// constraint; a row summing to 0 falls back to the anchor with the smallest D_ii). When xhat
/// is an anchor (D_ii = 0, up to 1e-24 of the squared embedding extent) its weight is 1 and the
/// others 0: the weights interpolate. The sums over anchors run four anchors at a time.
///
/// Both are per-query: OpenMP over queries in fixed chunks; results do not depend on the
/// thread count (a warm start only follows the previous query of the same chunk). The
/// per-query kernels run in an AVX2 + FMA instantiation where the CPU has both and a portable one
/// otherwise (core/detail/simd.h; BARYLAB_SIMD=0 forces the portable one); their results agree
/// to rounding. No allocation per query.

#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/surface/phong_projection.h"
#include "core/surface/surface_mesh.h"

#include <memory>
#include <vector>

namespace bary
{

namespace detail
{
struct SurfaceSearch;
}

/// Options of the forward problem.
struct ForwardOptions
{
  enum class Search
  {
    Local,     ///< the paper's greedy walk and breadth-first search (default)
    BruteForce ///< every triangle, the closest Phong projection (validation; O(#F) per query)
  };
  Search search = Search::Local;
  /// Each query starts from the previous query's result (curves, animations: queries in an
  /// order where consecutive ones are close); otherwise from the anchor nearest to the average
  /// in R^D. Default off.
  bool warm_start = false;
  /// Triangles the breadth-first search may try per query before it reports a failure;
  /// 0 = every triangle. Range [0, 2^31). Default 0.
  Index max_triangles = 0;
  /// OpenMP threads (0 = OpenMP's default). Results do not depend on it. Default 0.
  int threads = 0;
};

/// Options of the inverse problem.
struct InverseOptions
{
  /// gamma of D_ii = |v_T|^2 + gamma |v_O|^2: how much more anchors off the tangent plane are
  /// penalised. Range [1, 1e6]. Default 10 (the paper's, "for all examples").
  double gamma = 10.0;
  /// OpenMP threads (0 = OpenMP's default). Results do not depend on it. Default 0.
  int threads = 0;
};

/// Result of WeightedAverages::round_trip (§4.4: a point whose forward(inverse) does not
/// return to it is not a weighted average of the anchors; its weights are meaningless there).
struct RoundTrip
{
  std::vector<double> error;  ///< per point: distance from forward(inverse(x)) to x (NaN: failed)
  std::vector<char> returned; ///< per point: 1 when the error is within the tolerance
  Index failures = 0;         ///< forward problems without a projection
  Index not_returned = 0;     ///< points with returned = 0 (failures included)
  double median_error = 0, max_error = 0; ///< over the points whose forward problem succeeded
};

/// Default round-trip tolerance, relative to the surface's mean edge length.
inline constexpr double kDefaultRoundTripTolerance = 1e-6;

/// Result of a forward problem.
struct ForwardResult
{
  std::vector<SurfacePoint> points; ///< per query: the triangle and barycentric coordinates
  std::vector<char> valid;          ///< per query: 1 when a Phong projection was found
  Eigen::MatrixXd positions;        ///< #queries by 3 points on the surface (NaN rows: failed)
  Index failures = 0;               ///< queries without a projection
  Index triangles_tried = 0;        ///< Phong projections attempted, all queries together
  double seconds = 0;
};

/// A surface with its embedding, ready for forward and inverse problems. Copies share the
/// precomputation; const methods are thread-safe.
class WeightedAverages
{
public:
  /// @param mesh the validated surface
  /// @param E #V by D embedding of its vertices (euclidean_embedding, a file, or the vertices
  ///   themselves for D = 3)
  /// @throws the errors of PhongProjection (sizes, a non-finite entry, a degenerate one-ring)
  WeightedAverages(SurfaceMesh mesh, const Eigen::MatrixXd& E);

  /// Weighted averages of @p anchors, one query per row of @p W (#queries by #anchors).
  /// @throws Error(EmptyInput) for no anchor; Error(SizeMismatch) when W's columns are not the
  ///   anchors; Error(NonFinite) naming a row with a non-finite weight; Error(InvalidArgument)
  ///   naming a row whose weights do not sum to 1 (within 1e-9 of the sum of their magnitudes),
  ///   an anchor that is not a point of the surface, or an option out of range;
  ///   Error(Cancelled) when @p progress returns false.
  ForwardResult forward(const std::vector<SurfacePoint>& anchors, const DenseWeights& W,
    const ForwardOptions& options = {}, const ProgressCallback& progress = {}) const;

  /// The same with sparse weights (only the nonzeros are read: averages of a few anchors among
  /// many, as in subdivision). Without a warm start, a query starts from @p hints (optional, one
  /// surface point per row, face -1 for none: e.g. where the point was before a smoothing step)
  /// or else from the nearest of its row's anchors.
  /// @throws as above; Error(SizeMismatch) when @p hints does not have one entry per row.
  ForwardResult forward(const std::vector<SurfacePoint>& anchors, const SparseWeights& W,
    const ForwardOptions& options, const ProgressCallback& progress = {},
    const std::vector<SurfacePoint>* hints = nullptr) const;

  /// Weights of @p points (#points by #anchors) w.r.t. @p anchors, each row summing to 1.
  /// @throws Error(EmptyInput) for no anchor; Error(InvalidArgument) naming an anchor or point
  ///   that is not a point of the surface, or an option out of range; Error(Cancelled).
  DenseWeights inverse(const std::vector<SurfacePoint>& anchors,
    const std::vector<SurfacePoint>& points, const InverseOptions& options = {},
    const ProgressCallback& progress = {}) const;

  /// The round trip of §4.4 for @p points with weights @p W (from inverse()): forward problems
  /// with W, compared with the points. @p tolerance is relative to the mean edge length,
  /// range (0, 1e6]. @throws the errors of forward(); Error(SizeMismatch) when W does not have
  /// a row per point.
  RoundTrip round_trip(const std::vector<SurfacePoint>& anchors,
    const std::vector<SurfacePoint>& points, const DenseWeights& W,
    double tolerance = kDefaultRoundTripTolerance, const ForwardOptions& options = {},
    const ProgressCallback& progress = {}) const;

  /// Embedded positions of surface points (#points by D).
  Eigen::MatrixXd embed(const std::vector<SurfacePoint>& points) const;

  const SurfaceMesh& mesh() const noexcept { return *mesh_; }
  const PhongProjection& phong() const noexcept { return *phong_; }
  const Eigen::MatrixXd& embedding() const noexcept { return E_; }
  int dimension() const noexcept { return static_cast<int>(E_.cols()); }

private:
  /// Both forward problems: the rows of weights, dense (#queries by #anchors, row-major) or
  /// sparse (compressed row storage: outer, inner, values).
  ForwardResult forward_rows(const std::vector<SurfacePoint>& anchors, Index queries,
    const double* dense, const int* outer, const int* inner, const double* values,
    const ForwardOptions& options, const ProgressCallback& progress,
    const std::vector<SurfacePoint>* hints) const;

  std::shared_ptr<const SurfaceMesh> mesh_;
  std::shared_ptr<const PhongProjection> phong_;
  std::shared_ptr<const detail::SurfaceSearch> search_; ///< the greedy walk's and fans' tables
  Eigen::MatrixXd E_;
};

/// Checks the options' ranges (as forward() and inverse() do first).
/// @throws Error(InvalidArgument) naming the option, its value and its range.
void validate_forward_options(const ForwardOptions& options);
void validate_inverse_options(const InverseOptions& options);
/// Round-trip tolerance: range (0, 1e6] (relative to the mean edge length).
void validate_round_trip_tolerance(double tolerance);

/// Checks surface points against a mesh: a face in range, finite barycentric coordinates, each
/// >= -1e-9, summing to 1 within 1e-9. @p what names them in the message ("anchor", "point").
/// @throws Error(InvalidArgument) naming the first bad one.
void validate_surface_points(
  const SurfaceMesh& mesh, const std::vector<SurfacePoint>& points, const char* what);

} // namespace bary
