#pragma once
/// @file local_barycentric_coordinates.h
/// Local barycentric coordinates (LBC: Zhang, Deng, Liu, Patanè, Bouaziz, Hormann & Liu, "Local
/// barycentric coordinates", ACM TOG 33(6), 2014) on a triangulation (2D) or tetrahedralization
/// (3D) of a cage's interior. The weights minimise the (weighted) total variation of every
/// coordinate function subject to the barycentric constraints, the paper's problem (15):
///
///   min_W  sum_s sum_i phi_i^s A_s |G_s W_i + e_i^s|               (Eq. 14)
///   s.t.   W K = B  (partition of unity and reproduction, Eq. 16),  W >= 0,
///
/// W the weights at the interior vertices (#free by #C), G_s the gradient on cell s (area or
/// volume A_s), e_i^s the contribution of the fixed boundary values (the cage's hat functions:
/// linear along 2D cage edges, barycentric on 3D cage triangles: DomainMesh::boundary_weights,
/// the Lagrange and linearity properties), and phi_i^s = tau(D_i) the locality weight of §3.3
/// (Eq. 10-12): D_i the geodesic distance to control point i inside the domain (heat method,
/// geodesic_heat.h), normalised to [0, 1], at the cell's centroid. With relaxed_tv_epsilon > 0
/// the norm is replaced by the C^1 function f_eps of Eq. 7-8 (§3.2: globally C^1 weights, less
/// local).
///
/// Solver: the ADMM of the paper's Appendix B (splitting (17), steps 1-3 with over-relaxation,
/// shrinkage (30), projection (31), the Y-update as solves with one factorisation, residuals
/// (26)-(27)), written as the equivalent relaxed Douglas-Rachford iteration on
/// s = G Y M + J - lambda / mu (with ConstraintScaling::Paper its iterates are Appendix B's:
/// tested against a literal implementation). For speed, without changing the problem or the
/// stopping rule:
/// - constraint scaling (LBCOptions::scaling): the constraints X = G W + E and W = Y M + H are
///   multiplied by diagonal weights (sqrt(A_s) per cell, beta sqrt(m_v) per vertex), an
///   equivalent problem whose Y-system is the stiffness plus lumped mass matrix K + beta^2 M
///   instead of G^T G + I: the iteration count becomes nearly independent of the mesh size;
/// - all #C right-hand sides of a step are solved together (row-major #free by #C blocks: each
///   factor entry updates a whole row of weights), the steps are fused into three sweeps;
/// - optional safeguarded Anderson acceleration (type II, Walker & Ni 2011) with the acceptance
///   test of Zhang, O'Donoghue & Boyd ("Globally convergent type-I Anderson acceleration for
///   nonsmooth fixed-point iterations", SIAM J. Optim. 30(4), 2020): an accelerated point is
///   kept only if its fixed-point residual is below both the last accepted one and
///   D |g_0| (k+1)^-(1+eps), otherwise the plain step is taken, whose residual never increases,
///   so convergence is that of ADMM. Off by default: it did not reduce the iterations here.
/// Stopping (LBCOptions::stopping): the paper's rule is on residuals (26)-(27) measured in the
/// unscaled variables after rescaling the mesh to bounding-box diameter 1, |r_p| <= N_p
/// primal_tolerance and |r_d| <= N_d dual_tolerance with N the residuals' numbers of entries.
/// Its thresholds grow like N, the residuals like sqrt(N), so on 3D meshes it stops while most
/// weights are still significant; LBCStopping::Converged (the default) adds a test on the
/// residuals' root mean square and on the support (see LBCStopping), and balances the penalty
/// mu against the residuals (LBCOptions::adaptive_penalty; Boyd et al. 2011, §3.4.1).
///
/// After the ADMM, its W (>= 0 with exact zeros: the locality) is projected, row by row, onto
/// the exact feasible set {w >= 0, w K = b} keeping its zeros (Y M + H projected onto the whole
/// set where that is impossible): polish, on by default. The returned weights are >= 0 exactly
/// and satisfy partition of unity and reproduction to rounding (~1e-15).
///
/// Properties (discrete): partition of unity, reproduction (linear precision), non-negativity,
/// Lagrange property at the cage vertices, linear on cage edges (2D) / barycentric on cage faces
/// (3D); local: each point depends on few control points (paper Fig. 14-15; see
/// locality_statistics.h); C^1 almost everywhere (relaxed TV: everywhere), not smooth across
/// the boundary of a weight's support. With unconstrained TV (barycentric_constraints = false,
/// tau = 1) a concave cage vertex's weight vanishes inside (§3.2); with the coupling it need not
/// (measured in the docs).
///
/// Threads: results do not depend on the thread count. An iteration has five short parallel
/// loops: on a machine where other processes compete for the cores, libgomp's spin-waiting makes
/// several threads much slower than one (measured 10x); use threads = 1 or
/// OMP_WAIT_POLICY=passive there.
///
/// Measured (Release, one thread of a shared 2-core AMD EPYC; the authors' four reference runs
/// 5.8-13x faster than their solver, with lower objectives): docs/local-barycentric-coordinates.md.

#include "core/meshing/domain_mesh.h"
#include "core/solvers/geodesic_heat.h"
#include "core/common/progress.h"
#include "core/solvers/sparse_cholesky.h"
#include "core/common/types.h"
#include "core/common/weights_result.h"

#include <functional>
#include <memory>
#include <vector>

namespace bary
{

/// tau of §3.3 (Eq. 11): the locality weight phi_i = tau(D_i) as a function of the normalised
/// geodesic distance D_i in [0, 1] to control point i.
enum class LocalityFunction
{
  Squared,  ///< tau(x) = x^2: the paper's choice for all its results (§5). Default.
  Constant, ///< tau = 1: unweighted total variation (problem (5)).
  Linear,   ///< tau(x) = x
  Custom    ///< LBCOptions::custom_locality (must map [0, 1] to [0, 1]; may be decreasing,
            ///< which makes the weights more global, Fig. 6)
};

/// How the geodesic distance g_i is normalised to D_i in [0, 1] (Eq. 12).
enum class DistanceNormalization
{
  /// D_i = g_i / max_y g_i(y): each control point's own maximum (the paper's Eq. 12). Default.
  PerControlPoint,
  /// D_i = g_i / max_j max_y g_j(y): one maximum over all control points (what the authors'
  /// public code does); use it to compare with weights computed by that code.
  Global
};

/// When the ADMM stops.
enum class LBCStopping
{
  /// The paper's rule (Eqs. 26-27, thresholds per residual entry), with a fixed penalty: the
  /// paper's iteration. On 3D meshes it stops while many weights are still significant (1.5-3
  /// times the converged support).
  Paper,
  /// BaryLab's rule: the paper's test and, with the residuals' root mean square per
  /// entry (which does not loosen as the mesh grows) and the targets e = 10^3 tolerance / #C
  /// (10^-3 / #C primal, 10^-2 / #C dual at the defaults: below the threshold at which a
  /// weight counts as significant), either both RMS residuals <= e, or both <= 10 e and the
  /// support (weights above 10^-3 / #C per vertex) within 1% of its value at half the
  /// iterations. Chosen by a convergence study against tight solves (the LBC page): on 3D cages
  /// the paper's rule stops with 1.5-3 times the converged support, this rule within 6% of
  /// it. Default: with residual balancing of the penalty (LBCOptions::adaptive_penalty) it
  /// costs 1-3.5 times the paper's iterations in 3D (without it 10-30 times) and 1-2 times in
  /// 2D, where the penalty is not changed.
  Converged
};

/// How the splitting's two constraints are weighted (see the file comment). Both solve the same
/// problem (15); they differ in speed.
enum class ConstraintScaling
{
  /// As in Appendix B: X = G W + E and W = Y M + H unweighted; Y-system G^T G + I.
  Paper,
  /// sqrt(A_s) on cell s's gradient rows, beta sqrt(m_v) on vertex v's weight row (m_v its
  /// lumped mass, beta = constraint_balance / h_c); Y-system K + beta^2 M. Default (10-25 times
  /// fewer iterations than Paper measured, independent of the mesh size).
  Lumped
};

/// Options of local barycentric coordinates. Defaults: the paper's (Appendix B "Parameters",
/// §5: tau(x) = x^2) but the stopping rule (LBCStopping::Converged), plus acceleration that
/// does not change the solution.
struct LBCOptions
{
  /// ADMM penalty mu (Eq. 25) of ConstraintScaling::Paper, > 0: the paper's 10 (for a model of
  /// bounding-box diameter 1). Also the mu of the dual residual (27) in the stopping rule, with
  /// either scaling. Default 10.
  double penalty = 10.0;
  /// Penalty of ConstraintScaling::Lumped, in units of the mean cage edge length h_c (relative
  /// to the bounding-box diameter): mu = scaled_penalty h_c, > 0. The edges are read from
  /// boundary_weights (pairs of control points sharing a boundary row); without any, h_c is the
  /// mean distance from a control point to its nearest one. The scaling with h_c keeps mu near
  /// the best measured value across cages with few and many control points (0.03 for the
  /// 34-vertex gecko, 0.1 for the 6-vertex logo). Default 0.3.
  double scaled_penalty = 0.3;
  /// Over-relaxation alpha of Appendix B, in (0, 2); the paper uses 1.65 (range [1.5, 1.8]).
  double relaxation = 1.65;
  /// Primal stopping threshold per residual entry: stop when |r_p|_F <= N_p primal_tolerance,
  /// N_p the number of entries of r_p (Eq. 26), measured on the mesh rescaled to bounding-box
  /// diameter 1. The paper's 1e-6. Range (0, 1). With LBCStopping::Converged it also sets the
  /// root-mean-square target 10^3 primal_tolerance / #C.
  double primal_tolerance = 1e-6;
  /// Dual stopping threshold per entry, |r_d|_F <= N_d dual_tolerance (Eq. 27, with mu = the
  /// paper's penalty 10 whatever the internal scaling). The paper's 1e-5. Range (0, 1). With
  /// LBCStopping::Converged it also sets the root-mean-square target 10^3 dual_tolerance / #C.
  double dual_tolerance = 1e-5;
  /// Cap on ADMM iterations (each one Y-solve), >= 1. Default 20000.
  int max_iterations = 20000;
  /// Residuals are checked every check_interval iterations (each check costs one extra solve),
  /// >= 1. Default 10 (as the authors' code).
  int check_interval = 10;
  /// The stopping rule. Default Converged (local weights in 3D too); Paper: the paper's rule.
  LBCStopping stopping = LBCStopping::Converged;

  /// tau (§3.3). Default Squared.
  LocalityFunction locality = LocalityFunction::Squared;
  /// tau for LocalityFunction::Custom: called with D in [0, 1], must return a finite value >= 0.
  std::function<double(double)> custom_locality;
  /// Eq. 12's normalisation. Default PerControlPoint.
  DistanceNormalization distance_normalization = DistanceNormalization::PerControlPoint;
  /// Heat-method settings for D_i (not used with LocalityFunction::Constant); threads is
  /// replaced by LBCOptions::threads. Its backend Automatic means Supernodal here (measured, one
  /// thread, the factorisations and 6-8 sources: LBClogo's 1,621 vertices 4.5 ms vs Eigen 4.3,
  /// CHOLMOD 6.7; a 3D cube mesh of 3,127 vertices 0.05 s vs 0.12, 0.13; of 29,903 vertices
  /// 3.8 s vs 25.5, 4.3).
  GeodesicHeatOptions geodesic;

  /// epsilon of the relaxed total variation f_eps (Eq. 7-8), >= 0, in units of 1 / (the
  /// bounding-box diameter): f_eps differs from |u| where the gradient is smaller than that of
  /// a function rising by epsilon over the whole cage. 0 (default): plain TV.
  double relaxed_tv_epsilon = 0.0;

  /// false: drop partition of unity and reproduction (W K = B) and minimise each w_i's
  /// (weighted) total variation under its boundary values and w_i >= 0 alone: §3.2's
  /// "unconstrained TV" (its inset, left), e.g. to see the shape a single coordinate takes
  /// without the coupling. The result is then not a set of barycentric coordinates. Default true.
  bool barycentric_constraints = true;

  /// OpenMP threads; 0 = OpenMP's default. The weights do not depend on it (bitwise).
  int threads = 0;
  /// Throw Error(NotConverged) when max_iterations is reached; false returns the last iterate
  /// (polished) with converged = false. Default true.
  bool require_convergence = true;
  /// Factorisation of the Y-system. Automatic (default): BaryLab's row-major LL^T (Eigen's
  /// simplicial factor with AMD ordering, solved for all #C columns at once in row-major blocks,
  /// each factor entry a contiguous update of a row of weights). Any other value: that
  /// SparseCholesky backend, solved through SparseCholesky::solve on column-major copies (for
  /// comparison). Measured ADMM time, one thread: Gil_Gecko 1.13 s (Automatic) vs 1.47
  /// (Supernodal), 1.84 (Eigen), 2.24 (Cholmod); LBClogo 19 vs 30, 35, 43 ms. The geodesic
  /// distances use geodesic.backend.
  SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic;

  // --- acceleration (none of these changes the problem or the stopping rule) ----------------
  /// See ConstraintScaling. Default Lumped.
  ConstraintScaling scaling = ConstraintScaling::Lumped;
  /// beta of ConstraintScaling::Lumped in units of 1 / h_c (the weight rows are scaled by
  /// constraint_balance sqrt(m_v) / h_c), > 0. Default 7 (measured; 4 to 8 were as good).
  double constraint_balance = 7.0;
  /// Safeguarded Anderson acceleration (file comment). Default false: on the reference cages
  /// it reached a given objective in as many iterations as the plain step (the residual of
  /// this nonsmooth fixed-point map is not explained by its recent history) at up to twice
  /// the cost per iteration.
  bool anderson = false;
  /// Anderson history length, in [1, 50]. Default 5.
  int anderson_history = 5;
  /// Residual balancing of the penalty (Boyd et al. 2011, §3.4.1) with LBCStopping::Converged
  /// (with Paper the iteration is the paper's, fixed mu): the residuals' root mean squares are
  /// measured against the converged rule's targets (10^3 primal_tolerance / #C, 10^3
  /// dual_tolerance / #C); when one ratio exceeds the other by more than a factor 2, mu is
  /// doubled (primal larger) or halved (dual larger), at least 3 residual checks apart and at
  /// most 20 times, so mu is eventually fixed and convergence is that of ADMM. The multipliers
  /// are kept and nothing is refactored (the Y-system does not depend on mu). Same problem,
  /// same stopping test: on the 3D study cases it cut the converged rule's iterations 4-10
  /// times (kidney 8,660 to 1,460, icosphere42 4,020 to 400); on the 2D ones it never changed
  /// mu. Not with anderson. Default true.
  bool adaptive_penalty = true;
  /// Project every row onto {w >= 0, w K = b} at the end (file comment). Default true.
  bool polish = true;
};

/// What a computation did. Times are wall-clock seconds. WeightsResult's fields: W (#V by #C
/// weights, mesh vertex order, columns in cage order), no location, no undefined rows,
/// converged (both residuals below their thresholds) and the statistics, in this order:
/// iterations, primal_residual, dual_residual, primal_threshold, dual_threshold, objective,
/// converged (1 or 0), partition_error, reproduction_error, min_weight, threads (the OpenMP
/// threads used), geodesic_seconds, factor_seconds, admm_seconds, solve_seconds (seconds).
struct LBCResult : WeightsResult
{
  int iterations = 0;      ///< fixed-point (ADMM) iterations = Y-solves of the iteration proper
  double primal_residual = 0; ///< |r_p|_F of Eq. 26 at the last check (diameter-1 units)
  double dual_residual = 0;   ///< |r_d|_F of Eq. 27 at the last check
  double primal_threshold = 0; ///< N_p primal_tolerance
  double dual_threshold = 0;   ///< N_d dual_tolerance
  double objective = 0;    ///< Eq. 14 (Eq. 7 with relaxed TV) of W, in the mesh's own units
  // Acceleration and polishing diagnostics.
  int anderson_accepted = 0; ///< accelerated points kept
  int anderson_rejected = 0; ///< accelerated points refused by the safeguard (each cost one
                             ///< extra iteration, counted in iterations)
  int penalty_updates = 0;     ///< changes of mu by residual balancing (adaptive_penalty)
  double penalty_factor = 1.0; ///< the final mu over the initial one
  double max_polish_change = 0; ///< max |W - (Y M + H)| over the free entries made by polishing
  Index polish_failures = 0;    ///< rows the polish could not project (left clamped)
  double partition_error = 0;    ///< max_v |sum_i W(v,i) - 1|
  double reproduction_error = 0; ///< max_v |sum_i W(v,i) c_i - x_v| / bounding-box diameter
  double min_weight = 0;         ///< smallest entry of W
  /// |r_p|, |r_d| at every check (for convergence plots and tests).
  std::vector<double> primal_history, dual_history;
  /// At every check: the mean number of weights above 10^-3 / #C per free vertex in the
  /// iterate W^k (>= 0, the projection (31)): the support that LBCStopping::Converged watches.
  std::vector<double> support_history;
  double geodesic_seconds = 0; ///< heat-method distances (constructor)
  double factor_seconds = 0;   ///< operators, SVD of K, factorisation (constructor)
  double admm_seconds = 0;     ///< the iteration
  double polish_seconds = 0;   ///< projection and objective
  double seconds = 0;          ///< constructor + compute
};

/// Precompute once per mesh and options (geodesic distances, operators, the factorisation),
/// then compute().
class LocalBarycentricCoordinates
{
public:
  /// Meshes nothing: takes the domain mesh of a cage (mesh_polygon / mesh_closed_surface output,
  /// or any DomainMesh: V, T, control_vertex, boundary_vertices, boundary_weights are used; see
  /// domain_mesh_from_simplices and domain_mesh_for_cage (domain_mesh.h) for a mesh read from
  /// files).
  /// @throws Error(InvalidArgument) for options out of range (named), a control vertex or
  ///   boundary vertex out of range, a control vertex that is not a boundary vertex, control
  ///   points that do not span the space (collinear / coplanar), a mesh without interior
  ///   vertices; Error(SizeMismatch) for inconsistent shapes; the errors of the finite-element
  ///   operators (degenerate elements, non-finite vertices) and of the factorisations;
  ///   Error(Cancelled) when @p progress returns false.
  explicit LocalBarycentricCoordinates(const DomainMesh& mesh, const LBCOptions& options = {},
    const ProgressCallback& progress = {});
  ~LocalBarycentricCoordinates();
  LocalBarycentricCoordinates(LocalBarycentricCoordinates&&) noexcept;
  LocalBarycentricCoordinates& operator=(LocalBarycentricCoordinates&&) noexcept;

  /// Runs the ADMM and polishes. Thread-safe for concurrent calls (const, no shared state).
  /// @throws Error(NotConverged) if max_iterations is reached and options.require_convergence;
  ///   Error(Cancelled) when @p progress returns false (checked every check_interval
  ///   iterations).
  LBCResult compute(const ProgressCallback& progress = {}) const;

  /// Eq. 14 (Eq. 7 with relaxed TV) of any #V by #C weights on this mesh with these options'
  /// locality weights, in the mesh's units (rows of fixed vertices are used as given).
  /// @throws Error(SizeMismatch) for a wrong shape.
  double objective(const DenseWeights& W) const;

  /// #V by #C normalised geodesic distances D_i (Eq. 12) at the mesh vertices (zero columns
  /// with LocalityFunction::Constant, where they are not computed).
  const Eigen::MatrixXd& normalized_distances() const noexcept;
  /// #T by #C locality weights phi_i^s = tau(D_i(centroid of s)).
  const Eigen::MatrixXd& locality_weights() const noexcept;
  const LBCOptions& options() const noexcept;
  Index free_vertex_count() const noexcept;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-call form: LocalBarycentricCoordinates(mesh, options, progress).compute(progress)
/// (progress: 0-0.1 set-up, 0.1-1 solve).
LBCResult local_barycentric_coordinates(const DomainMesh& mesh, const LBCOptions& options = {},
  const ProgressCallback& progress = {});

/// f_eps of Eq. 8 at |u| = r >= 0: r for r >= eps (and for eps = 0), otherwise
/// -r^3 / (3 eps^2) + r^2 / eps + eps / 3 (C^1, convex, >= r, at most eps / 3 above it).
double relaxed_tv(double r, double eps);

/// The proximal step of the (relaxed) total variation on one gradient, as the solver takes it:
/// prox_{kappa f}(a) = rho a / |a| with rho = relaxed_tv_prox_radius(|a|, kappa, eps) the
/// minimiser over [0, r] of 1/2 (rho - r)^2 + kappa f_eps(rho), r = |a|, kappa >= 0:
/// - eps = 0 (plain TV): the shrinkage of Eq. 30, rho = max(0, r - kappa);
/// - r >= eps + kappa: rho = r - kappa (the minimiser lies where f_eps = |.|);
/// - otherwise rho = 2 r / (c + sqrt(c^2 - 4 kappa r / eps^2)), c = 1 + 2 kappa / eps, the
///   smaller root of rho - r + kappa (2 rho / eps - rho^2 / eps^2) = 0 (f_eps' on [0, eps)),
///   written without cancellation; it is < eps, positive for r > 0 (no exact zeros: the
///   relaxed weights are less local). Derivation in docs/local-barycentric-coordinates.md.
double relaxed_tv_prox_radius(double r, double kappa, double eps);

} // namespace bary
