#pragma once
/// @file bbw.h
/// Bounded biharmonic weights (Jacobson, Baran, Popović & Sorkine, "Bounded biharmonic weights
/// for real-time deformation", ACM TOG 30(4), 2011): on a triangle or tetrahedral mesh of the
/// domain, the weights w_j of m handles minimize the Laplacian energy (Eq. 2) subject to the
/// handles' boundary conditions (Eq. 3-4), bounds 0 <= w_j <= 1 (Eq. 6) and, in the coupled
/// mode, partition of unity (Eq. 5).
///
/// Discretization (§3.4, Eq. 8): linear FEM, energy 1/2 sum_j w_j^T Q w_j with
/// Q = K M^-1 K, K the stiffness matrix (fem_operators.h: minus the cotangent Laplacian) and M
/// the lumped mass matrix (BBWOptions::mass_lumping): by default the Voronoi area / volume of
/// each vertex, as §3.4 specifies (MassMatrixType::Voronoi: Meyer et al.'s mixed area for
/// triangles, as libigl; the nearest-corner part of each tetrahedron), or the barycentric
/// lumping (1/3 or 1/4 of the incident element volumes), which libigl's MATLAB reference used
/// for tetrahedra (the knight: 1.3e-6 from it with barycentric lumping, 0.11 with Voronoi;
/// both converge to the same continuous weights). Q is sparse (two-ring
/// stencil) and symmetric positive semidefinite; positive definite once every connected
/// component has a fixed vertex. The optional shape-preservation term (§3.3, Eq. 7/9) adds
/// G^T diag(rho_t vol_t) G = the integral of rho |grad w|^2 for a per-element brush rho.
///
/// Handles become fixed rows (bbw_boundary_conditions): a point handle fixes its mesh vertex to
/// 1 for itself and 0 for the others; a bone fixes the vertices sampled along it (paper §3.1;
/// the mesh must contain samples of the bone, e.g. inserted as Steiner points); a vertex shared
/// by several point/bone handles (a joint) gets 1/k for each of its k handles ("equally
/// distributed between the overlapping bones", §3.1); cage handles and any other boundary
/// condition (e.g. values linear on cage faces, Eq. 4) are given as explicit rows.
///
/// Properties (discrete): Lagrange / interpolation of the fixed rows exactly; 0 <= w <= 1
/// exactly (Eq. 6); partition of unity exact after normalization (fast mode) or to the solver
/// tolerance (coupled mode) and exact after its normalization; smooth (C1 at point handles);
/// local; no linear precision. Local maxima (Table 1 claims none, "only experimental
/// confirmation"): on the paper's Fig. 16 setup (random point handles in a square) w_j has no
/// local maximum away from its handle except small bumps near the boundary behind a handle close
/// to it (prominence up to ~0.03, up to w = 1 in a corner) and, rarely, a shallow bump a few
/// vertices from such a handle, in both modes, always where handle j dominates (bbw_test,
/// Fig16; the study in docs/bounded-biharmonic-weights.md counts them on unstructured meshes).
/// Without the bounds (BBWOptions::bounded = false) the weights go negative and have many
/// local extrema (Figs. 4, 16 left).
///
/// Measured (Release, this 2-core machine shared with other jobs, so CPU time = user + sys is
/// the reliable figure; best of 3): libigl's hand (7,234 vertices, 20 bones), fast mode 5.8 s
/// CPU and 6.0 s wall on one thread (646 active-set iterations: 382 factorizations, 264 row
/// modifications; KKT <= 5e-11), where libigl's active-set BBW takes ~35 s on one thread and
/// this mode took 19.9 s with Eigen's SimplicialLDLT refactoring every iteration; coupled
/// 14 s CPU on one thread (33 coupled active-set iterations, 437 CG iterations; E_mean 0.0024,
/// E_max 0.20 against the normalized fast weights; partition error 1e-11, KKT 5e-11), where
/// the previous augmented Lagrangian did not finish in 25 minutes. libigl's knight (1,822
/// vertices, 7 bones): fast 0.4 s CPU (292 iterations), max |W - W_matlab| = 1.26e-6 against
/// the libigl authors' MATLAB active-set weights (before normalization); coupled 2.2 s CPU
/// (40 iterations; E_mean 0.013, E_max 0.15), previously 17 s. Since then (2026-11-28, an
/// AMD EPYC VM, one thread): the hand fast 3.5-4.7 s, coupled 5.0-6.7 s (33 iterations, 327 CG
/// iterations, no fast phase first), libigl 33-39 s; docs/benchmarks.md has the history.
///
/// Edge cases: every vertex must belong to an element and every connected component must hold
/// a fixed vertex (else Q is singular there: Error(InvalidArgument) naming a vertex); a handle
/// must be fixed to a positive value at some vertex; in fast mode a vertex may get zero weight
/// from every handle (all bounds active there), which cannot be normalized: Error naming it
/// (use the coupled mode).

#include "core/solvers/box_constrained_qp.h"
#include "core/common/progress.h"
#include "core/solvers/sparse_cholesky.h"
#include "core/common/types.h"
#include "core/common/weights_result.h"

#include <vector>

namespace bary
{

/// Handles as boundary conditions at mesh vertices. Handles are numbered: the point handles
/// first (in order), then the bones, then the `extra_handles` handles that exist only through
/// explicit rows (cage vertices, painted regions, ...). Any combination of the three kinds
/// (paper Eq. 3-4) is allowed; bbw_boundary_conditions() turns them into fixed rows.
struct BBWHandles
{
  /// #P: the mesh vertex of each point handle.
  Eigen::VectorXi point_vertex;
  /// #B lists: the mesh vertices sampled along each bone (its end points included). A vertex
  /// in several lists (a joint), or both a point handle's and a bone's, is shared equally.
  std::vector<std::vector<int>> bone_vertices;
  /// Number of handles defined only through fixed_values (e.g. cage vertices); they are
  /// numbered after the bones. Default 0.
  Index extra_handles = 0;
  /// #F mesh vertices with explicit values for every handle, e.g. the mesh vertices on a cage's
  /// faces with the values of the cage vertices' linear hat functions there (Eq. 4; see
  /// cage_boundary_values in harmonic_coordinates.h). A vertex listed here must not also be a
  /// point or bone vertex: merge such rows yourself.
  Eigen::VectorXi fixed_vertices;
  /// #F by handle_count(): the explicit rows; entries in [0, 1], each row summing to 1.
  DenseWeights fixed_values;

  /// m = #P + #B + extra_handles.
  Index handle_count() const noexcept
  {
    return point_vertex.size() + static_cast<Index>(bone_vertices.size()) + extra_handles;
  }
};

/// Fixed rows of the weights: vertices (ascending, no repeats) and their values.
struct BBWBoundaryConditions
{
  Eigen::VectorXi vertices; ///< #known mesh vertices
  Eigen::MatrixXd values;   ///< #known by #handles, rows in [0, 1] summing to 1
};

/// Maps handles to fixed rows (see the file comment) on a mesh with @p vertex_count vertices.
/// @throws Error(EmptyInput) for no handle; Error(InvalidArgument) naming the handle or vertex
///   for an index outside [0, vertex_count), an empty bone, a vertex listed twice in
///   fixed_vertices or both there and as a point/bone vertex, a value outside [0, 1], a row not
///   summing to 1 (within 1e-9), a negative extra_handles, or a handle that is fixed to a
///   positive value nowhere; Error(SizeMismatch) if fixed_values is not #F by handle_count();
///   Error(NonFinite) for NaN / infinite values.
BBWBoundaryConditions bbw_boundary_conditions(const BBWHandles& handles, Index vertex_count);

/// Handles of a skeleton with libigl's rule (boundary_conditions): point handle p is the mesh
/// vertex nearest to C(P(p)); bone b gets every mesh vertex within @p tolerance of the segment
/// C(BE(b,0)) - C(BE(b,1)).
/// @param V #V by dim mesh vertices; @param C #C by dim joint positions; @param P #P indices into
///   C of the point handles; @param BE #B by 2 indices into C of the bones' end points.
/// @param tolerance absolute distance; <= 0 selects 1e-6 times V's bounding-box diagonal.
/// @throws Error(InvalidArgument) for an index outside C, or naming a point handle or bone with
///   no mesh vertex within the tolerance (mesh the domain with the skeleton sampled: its joints
///   and points along each bone must be mesh vertices); Error(SizeMismatch) when C and V differ
///   in dimension or BE is not #B by 2.
BBWHandles handles_from_skeleton(const Eigen::MatrixXd& V, const Eigen::MatrixXd& C,
  const Eigen::VectorXi& P, const Eigen::MatrixXi& BE, double tolerance = -1.0);

/// The lumped mass matrix M of the discrete Laplacian M^-1 L (§3.4).
enum class BBWMassLumping
{
  /// Each element's area / volume split equally among its vertices.
  Barycentric,
  /// The Voronoi area / volume of each vertex (§3.4's choice).
  Voronoi
};

/// How the handles' problems are coupled.
enum class BBWMode
{
  /// Each handle's weights solved independently (Eq. 8 subject to Eq. 3, 4, 6 without Eq. 5:
  /// a bound-constrained QP of #V unknowns per handle, BoxConstrainedQP), handles in parallel,
  /// then every row normalized to sum to 1: the paper's §3.4 speed-up ("50 times faster"
  /// for the Gargoyle). Cost: one shared factorization of Q on the unknowns (the unconstrained
  /// biharmonic start of every handle), then per handle 20-50 active-set iterations, each a
  /// factorization of Q on the handle's support or a few row modifications of the last one
  /// (box_constrained_qp.h).
  Fast,
  /// The full problem (Eq. 8 subject to Eq. 3-6) with partition of unity enforced, by a
  /// primal-dual active-set method on the coupled KKT conditions
  ///   Q w_j + mu = lambda_j (on the unknown vertices), sum_j w_j = 1,
  ///   lambda_j >= 0 where w_j = 0, <= 0 where w_j = 1, = 0 where 0 < w_j < 1,
  /// started from every handle solved alone once on the active sets of the unconstrained
  /// biharmonic weights (the Fast mode's first iteration: weights <= 0 on the lower bound, >= 1
  /// on the upper), clamped onto [0, 1] and normalized, keeping those factorizations. Not from
  /// the converged Fast weights: they cost about as much as the coupled solve itself and save
  /// it few iterations (libigl's hand: 29 instead of 33 iterations, 9.0-11.9 s instead of
  /// 5.0-6.7 s in all, side by side). Each iteration, for the current active sets F_j (free
  /// weights of handle j):
  ///  1. per handle, the factorization of Q on F_j is updated (FreeSetFactor: refactored, or
  ///     modified by row additions / deletions when few weights changed) and
  ///     a_j(mu) = Q(F_j, F_j)^-1 (-Q(F_j, N_j) w_j(N_j) - mu(F_j)), the free weights for the
  ///     last iteration's mu (0 at the start);
  ///  2. the multiplier mu of Eq. 5 on the vertices V with a free weight solves the Schur
  ///     complement system S mu = sum_j a_j(0) - (1 - sum of the bounded weights), S = sum_j
  ///     E_j^T Q(F_j, F_j)^-1 E_j (E_j: F_j's rows of V), by conjugate gradients preconditioned
  ///     with Q(V, V) / #handles (exactly S^-1 where every handle is free; 10-40 iterations),
  ///     started from the last mu (its residual is the partition residual of the a_j(mu)), to a
  ///     tolerance 0.1 x the largest violation (0.1 x partition_tolerance once no violator is
  ///     left: a final iteration confirms); each iteration one solve per handle, whose result
  ///     also moves a_j along with mu;
  ///  3. w_j(F_j) = a_j(mu), then lambda_j = Q w_j + mu (mu where no weight is free: the middle
  ///     of the interval that signs the multipliers correctly);
  ///  4. the violators (free weights outside [0, 1] by more than min(tolerance,
  ///     partition_tolerance / #handles) / 2, multipliers of the wrong sign beyond tolerance / 2
  ///     relative to max_i sum_j |Q_ij|) change sets by a block step, with BoxConstrainedQP's
  ///     safeguard (single steps after block_attempts steps without a new best count of
  ///     violators, or when the step returns to an active set already solved); a vertex left
  ///     with no free weight whose bounds do not sum to 1 gets its largest weight freed.
  /// Converged when no violator is left, the KKT residual of the coupled problem (stationarity,
  /// sign and complementarity as in box_constrained_qp.h, on the clamped weights) is <=
  /// tolerance and max |sum_j w_j - 1| <= partition_tolerance. Cost: per iteration one factor
  /// update per handle (as in the Fast mode) and (#CG iterations + 1) solves per handle; the
  /// handles' factorizations and solves run in parallel, summed in handle order (the weights do
  /// not depend on the thread count). 30-45 iterations on the knight and the hand.
  Coupled
};

/// Options of bounded biharmonic weights. Defaults are the paper's problem solved to tight
/// tolerances.
struct BBWOptions
{
  /// Fast (per handle, then normalized) or Coupled (partition of unity enforced). Default Fast.
  BBWMode mode = BBWMode::Fast;
  /// Divide every row of the weights by its sum at the end (both modes; in the coupled mode
  /// the sums are already 1 to partition_tolerance). Keeps 0 <= w <= 1 and the fixed rows.
  /// false returns the raw per-handle weights (what libigl's bbw returns). Default true.
  bool normalize = true;
  /// Relative KKT tolerance of every QP (BoxQPOptions::tolerance), in (0, 1). Default 1e-10.
  double tolerance = 1e-10;
  /// Active-set iterations allowed per QP, >= 1. Default 1000.
  int max_iterations = 1000;
  /// Coupled: max |sum_j w_ij - 1| at convergence, > 0. Default 1e-10.
  double partition_tolerance = 1e-10;
  /// Coupled: active-set iterations of the coupled solver allowed, >= 1. Default 1000.
  int max_outer_iterations = 1000;
  /// Coupled: also solve the Fast mode's per-handle QPs, to report how far the coupled weights
  /// are from the fast ones (the paper's Table 2: BBWResult::fast_difference_mean / _max and
  /// the fast phase's counts). It does not change the coupled weights (the coupled solver does
  /// not start from the fast ones) and roughly doubles the time. Default false.
  bool compare_with_fast = false;
  /// Unused since the coupled mode is an active-set method (it was the augmented Lagrangian's
  /// penalty factor); kept so that code setting it compiles. Must be finite and > 0.
  double penalty = 1e3;
  /// Throw Error(NotConverged) when a QP or the coupled iteration does not converge within its
  /// caps; false returns the unconverged weights with converged = false. Default true.
  bool require_convergence = true;
  /// OpenMP threads for the per-handle solves (both modes); 0 = OpenMP's default. The weights
  /// do not depend on it. Default 0.
  int threads = 0;
  /// Factorization backend of every QP. Default Supernodal: the QPs factor many mid-size
  /// matrices (one per active-set iteration, or a few row modifications of the last one), where
  /// BaryLab's supernodal LL^T on Eigen's dense kernels is 2-4x faster than Eigen's simplicial
  /// LDL^T and CHOLMOD's supernodal LL^T with the reference BLAS; only it supports the row
  /// modifications (with CHOLMOD). Eigen and Cholmod give the same weights to the tolerance.
  SparseCholesky::Backend backend = SparseCholesky::Backend::Supernodal;
  /// Shape preservation (§3.3): a brush rho >= 0 per element (#T), adding
  /// 1/2 sum_j integral rho |grad w_j|^2 (Eq. 7, discretized as Eq. 9) to the energy, so that
  /// the painted region follows the handles nearly rigidly. Its magnitude trades off against Q
  /// (both scale as 1/length^2 relative to each other: a brush of ~1/h^2, h the edge length,
  /// is strong). Empty (default): no term.
  Eigen::VectorXd shape_preservation;
  /// The lumped mass matrix M of the Laplacian M^-1 K (fem_operators.h, MassMatrixType).
  /// Default Voronoi, as §3.4 specifies (2D and 3D).
  BBWMassLumping mass_lumping = BBWMassLumping::Voronoi;
  /// false: drop the bounds 0 <= w <= 1 (Eq. 6): unbounded biharmonic weights (Botsch & Kobbelt
  /// 2004; the paper's Figs. 4 and 16 left), a comparison that shows what the bounds buy. The
  /// weights are then the minimizer of Eq. 8 subject to Eq. 3-4, one sparse Cholesky
  /// factorization of Q on the unknowns for all handles (MinQuadWithFixed). Both modes give
  /// them: with Eq. 5 added, the KKT conditions Q w_j + mu = 0, sum_j w_j = 1 are solved by
  /// mu = 0, because the fixed rows sum to 1 and Q annihilates constants, so the per-handle
  /// solutions already sum to 1 (to rounding; normalize divides by those sums). They are smooth
  /// and sum to 1, but go negative and have local extrema away from the handles.
  /// max_bound_violation reports how far they leave [0, 1]. Default true.
  bool bounded = true;
};

/// What a computation did. Times in seconds. WeightsResult's fields: W (#V by #handles), no
/// location, no undefined rows, converged (every QP and the coupled iteration converged) and
/// the statistics, in this order: mesh_vertices, mesh_cells, handles, fixed_vertices, coupled
/// (1 or 0), fast_iterations and fast_factorizations (summed over the handles; 0 in the coupled
/// mode unless compare_with_fast), max_fast_iterations_per_handle, in the coupled mode
/// outer_iterations, coupled_iterations, coupled_factorizations, coupled_kkt_residual, and with
/// compare_with_fast fast_difference_mean, fast_difference_max, then max_kkt_residual, max_bound_violation, partition_error,
/// partition_error_before_normalization, converged (1 or 0), solve_seconds (seconds).
struct BBWResult : WeightsResult
{
  BBWMode mode = BBWMode::Fast;
  // Fast phase (the fast mode; the coupled mode with compare_with_fast): one entry per handle,
  // empty when it did not run.
  std::vector<int> iterations;      ///< active-set iterations of handle j's QP
  std::vector<int> factorizations;  ///< factorizations of handle j's QP
  std::vector<int> modifications;   ///< row modifications of its factorization (the other
                                    ///< iterations, BoxQPResult::modifications)
  std::vector<double> kkt_residual; ///< relative KKT residual of handle j's QP
  // Coupled phase.
  int outer_iterations = 0;          ///< active-set iterations of the coupled solver
  int coupled_iterations = 0;        ///< conjugate-gradient iterations summed over them
  int coupled_factorizations = 0;    ///< factorizations in them, summed over the handles
  int coupled_modifications = 0;     ///< factor modifications in them, summed over the handles
  double coupled_kkt_residual = 0;   ///< relative KKT residual of the coupled problem
  double fast_difference_mean = 0;   ///< coupled, compare_with_fast: Table 2's E_mean, mean |W_fast - W|
  double fast_difference_max = 0;    ///< coupled, compare_with_fast: Table 2's E_max, max |W_fast - W|
  // Both.
  double max_kkt_residual = 0;       ///< max over the QPs of the mode (fast: per handle)
  double max_bound_violation = 0;    ///< max over entries of max(-w, w - 1, 0): exactly 0
                                     ///< (bounded), how far unbounded weights leave [0, 1]
  double partition_error = 0;        ///< max_i |sum_j W(i,j) - 1| of W as returned
  double partition_error_before_normalization = 0; ///< the same before normalizing
  Index fixed_vertices = 0;          ///< #known rows
  double operator_seconds = 0;       ///< assembling Q (done once per BoundedBiharmonicWeights)
  double unconstrained_seconds = 0;  ///< the shared unconstrained biharmonic solve
  double fast_seconds = 0;           ///< the per-handle QPs (wall clock; 0 when not run)
  double coupled_seconds = 0;        ///< the coupled active-set phase
  double seconds = 0;                ///< compute() in total (wall clock)
};

/// Mean and max absolute difference of two weight matrices of the same shape (the paper's
/// Table 2 E_mean / E_max between the coupled and the fast weights).
struct WeightDifference
{
  double mean = 0;
  double max = 0;
};
/// @throws Error(SizeMismatch) when the shapes differ; Error(EmptyInput) when they are empty.
WeightDifference weight_difference(const DenseWeights& a, const DenseWeights& b);

/// Precompute once per mesh (and energy options), bind many handle sets.
class BoundedBiharmonicWeights
{
public:
  /// Validates the mesh and assembles Q (Eq. 8, plus Eq. 9 when options.shape_preservation is
  /// set). @p options are kept for compute().
  /// @param V #V by dim (2: planar triangles; 3: tetrahedra, or a triangle surface)
  /// @param T #T by 3 triangles or #T by 4 tetrahedra
  /// @throws the errors of stiffness_matrix (fem_operators.h); Error(InvalidArgument) naming a
  ///   vertex that belongs to no element, or for options out of range (named);
  ///   Error(SizeMismatch) / Error(NonFinite) for a shape_preservation of the wrong size or
  ///   holding NaN / infinity / negative values.
  BoundedBiharmonicWeights(
    const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, const BBWOptions& options = {});

  /// The weights of @p handles (see BBWHandles and BBWMode).
  /// @throws the errors of bbw_boundary_conditions(); Error(InvalidArgument) naming a vertex of
  ///   a connected component that holds no fixed vertex; Error(InvalidArgument) naming a vertex
  ///   whose fast-mode weights are all 0 (normalize = true); Error(NotConverged) when a solve
  ///   hits its cap and options.require_convergence; Error(Cancelled) when @p progress returns
  ///   false.
  BBWResult compute(const BBWHandles& handles, const ProgressCallback& progress = {}) const;

  /// Q, #V by #V, the energy matrix of Eq. 8 (+ Eq. 9).
  const Eigen::SparseMatrix<double>& energy_matrix() const noexcept { return Q_; }
  const BBWOptions& options() const noexcept { return options_; }
  Index vertex_count() const noexcept { return Q_.rows(); }

private:
  BBWOptions options_;
  Eigen::SparseMatrix<double> Q_;
  Eigen::VectorXi component_; ///< connected component of every vertex
  Index cell_count_ = 0;      ///< #T
  double operator_seconds_ = 0;
};

/// One-call form: BoundedBiharmonicWeights(V, T, options).compute(handles, progress).
BBWResult bounded_biharmonic_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const BBWHandles& handles, const BBWOptions& options = {}, const ProgressCallback& progress = {});

} // namespace bary
