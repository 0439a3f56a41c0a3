#pragma once
/// @file geodesic_heat.h
/// Geodesic distances by the heat method (Crane, Weischedel & Wardetzky, "Geodesics in heat: a
/// new approach to computing distance based on heat flow", ACM TOG 32(5), 2013), Algorithm 1 with
/// linear finite elements on a triangle mesh (planar, or a surface in space) or a tetrahedral
/// mesh:
///
///   I.   integrate the heat flow for a time t:  (M + t K) u = delta_source       (their Eq. 7)
///   II.  normalise its gradient per element:    X = -grad u / |grad u|
///   III. solve the Poisson equation:            K phi = G^T A X, i.e. "Delta phi = div X"
///
/// then shift phi so that it is 0 at the source. K is the stiffness matrix (minus the cotangent
/// Laplacian, fem_operators.h), M the lumped (barycentric) mass matrix, G the per-element
/// gradient and A the element areas/volumes, so G^T A X is the integrated divergence of X with
/// the sign of the weak form (int grad phi . grad v = int X . grad v). The heat flow uses the
/// natural (Neumann) boundary condition, the one that works for sources on the boundary (the
/// LBC use: the sources are cage vertices). t = time_factor h^2 with h the mean edge length
/// (the paper's §3.2.4 choice, time_factor = 1).
///
/// K is singular (constants); the Poisson solve pins one vertex of each connected component to
/// 0, which is exact because the right-hand side sums to zero over every component. Each matrix
/// (M + t K and the pinned K) is factored ONCE, in the constructor; distances() solves all
/// sources together (one multi-column solve per matrix). Vertices in another connected
/// component than the source get +infinity.
///
/// Accuracy (measured by geodesic_heat_test): the error is O(h) (first order) away from the
/// source, largest near the source and near the boundary; on a flat square from a corner the
/// max error relative to the exact distance fell 0.046 -> 0.026 -> 0.014 for 500 -> 2000 -> 8000
/// triangles. Inside non-convex domains the distance goes around reflex corners.
///
/// @warning The heat kernel decays like exp(-d / sqrt(t)), i.e. like exp(-d / h): on meshes more
/// than ~700 edges across, u underflows to 0 far from the source and the direction of its gradient
/// is lost there (those elements get X = 0; distances() can count them).
/// Raise time_factor for such meshes (smoother, less accurate distances).

#include "core/common/progress.h"
#include "core/solvers/sparse_cholesky.h"
#include "core/common/types.h"

#include <chrono>
#include <vector>

namespace bary
{

/// Options of the heat method.
struct GeodesicHeatOptions
{
  /// t = time_factor x h^2, h the mean edge length of the mesh (Crane et al. §3.2.4: m = 1).
  /// Larger values smooth the distance (and blur it near the source); range (0, 1e6].
  /// Default 1.
  double time_factor = 1.0;
  /// Factorization backend of both matrices. Default Automatic (CHOLMOD when available).
  SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic;
  /// OpenMP threads for the gradient normalisation; 0 = OpenMP's default. The distances do not
  /// depend on it. Default 0.
  int threads = 0;
};

/// Heat-method distances on one mesh: factor once, then distances from any sources.
/// Copies share the factorizations; const methods are thread-safe.
class GeodesicHeat
{
public:
  /// Validates the mesh and factors M + t K and the pinned K.
  /// @param V #V by dim vertices (dim 2: triangles; dim 3: tetrahedra or surface triangles)
  /// @param T #T by 3 triangles or #T by 4 tetrahedra
  /// @throws the errors of stiffness_matrix (fem_operators.h: empty, wrong shapes, indices out of
  ///   range, degenerate elements, non-finite vertices); Error(InvalidArgument) for options out of
  ///   range (named) or a vertex that belongs to no element (named).
  GeodesicHeat(
    const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, const GeodesicHeatOptions& options = {});

  /// The same with the mesh's gradient operator and element volumes already computed (as
  /// gradient_operator(V, T) and simplex_volumes(V, T) return them, e.g. by a caller that needs
  /// them too): the mesh is then not validated again.
  /// @throws Error(SizeMismatch) when G or volumes do not fit the mesh; Error(EmptyInput) for no
  ///   element; the other errors as above.
  GeodesicHeat(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Eigen::SparseMatrix<double> G,
    Eigen::VectorXd volumes, const GeodesicHeatOptions& options = {});

  /// Distances from every vertex to each source: column j is the distance to vertex
  /// sources(j) (0 there, >= 0 up to the method's error elsewhere: values within O(h) of the
  /// source can be slightly negative; they are returned as computed). #V by #sources.
  /// @param zero_gradient_elements optional: receives the number of (element, source) pairs
  ///   whose heat gradient was exactly zero or not finite (see the warning in the file comment).
  /// @throws Error(InvalidArgument) naming a source outside [0, #V); Error(Cancelled) when
  ///   @p progress returns false.
  Eigen::MatrixXd distances(const Eigen::VectorXi& sources, const ProgressCallback& progress = {},
    Index* zero_gradient_elements = nullptr) const;

  /// Distance to a set of vertices (one heat solve with all of them as sources, Crane et al.
  /// §3.2.5): shifted so that its smallest value on the set is 0 (in each connected component
  /// holding a source; +infinity in the others). #V by 1.
  /// @throws Error(InvalidArgument) for an empty set or a vertex outside [0, #V).
  Eigen::VectorXd distance_to_set(const std::vector<int>& sources) const;

  double time_step() const noexcept { return t_; }           ///< t
  double mean_edge_length() const noexcept { return h_; }    ///< h
  double factor_seconds() const noexcept { return factor_seconds_; } ///< both factorizations
  Index vertex_count() const noexcept { return V_.rows(); }

private:
  /// Steps II and III for the heat solutions U (#V by k): the potential, 0 at the pinned vertices
  /// (not yet shifted).
  Eigen::MatrixXd potential(
    const Eigen::MatrixXd& U, const ProgressCallback& progress, Index* zero_gradient_elements) const;
  void check_sources(const int* sources, Index count) const;
  static void check_options(const GeodesicHeatOptions& options);
  void factor(Eigen::SparseMatrix<double> G, Eigen::VectorXd volume,
    std::chrono::steady_clock::time_point t0);

  GeodesicHeatOptions options_;
  Eigen::MatrixXd V_;
  Eigen::MatrixXi T_;
  Eigen::SparseMatrix<double> G_;  ///< (#T dim) by #V gradient
  Eigen::VectorXd volume_;         ///< #T element areas/volumes
  Eigen::VectorXi component_;      ///< connected component of every vertex
  Eigen::VectorXi pinned_index_;   ///< #V: row in the pinned system, -1 for a pinned vertex
  SparseCholesky heat_;            ///< M + t K
  SparseCholesky poisson_;         ///< K without one vertex per component
  double t_ = 0, h_ = 0, factor_seconds_ = 0;
};

/// One-call form: GeodesicHeat(V, T, options).distances(sources, progress).
Eigen::MatrixXd heat_geodesic_distances(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const Eigen::VectorXi& sources, const GeodesicHeatOptions& options = {},
  const ProgressCallback& progress = {});

} // namespace bary
