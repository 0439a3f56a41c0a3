#include "core/surface/euclidean_embedding.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/solvers/fem_operators.h"
#include "core/solvers/geodesic_heat.h"
#include "core/solvers/min_quad_with_fixed.h"
#include "core/detail/parallel_for.h"
#include "core/surface/landmark_decimation.h"
#include "core/detail/timing.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>

namespace bary
{
namespace
{

using Clock = std::chrono::steady_clock;

/// Rows @p rows of the heat distances from @p sources (in blocks of 64 sources, so memory stays
/// #V x 64), as a #rows by #sources matrix.
Eigen::MatrixXd heat_distances_at(const GeodesicHeat& heat, const std::vector<int>& sources,
  const std::vector<int>& rows, ProgressReporter& reporter)
{
  const Index ns = static_cast<Index>(sources.size());
  Eigen::MatrixXd R(static_cast<Index>(rows.size()), ns);
  constexpr Index block = 64;
  for (Index b = 0; b < ns; b += block)
  {
    const Index nb = std::min(block, ns - b);
    Eigen::VectorXi s(nb);
    for (Index k = 0; k < nb; ++k)
      s(k) = sources[static_cast<std::size_t>(b + k)];
    const Eigen::MatrixXd D = heat.distances(s);
    for (std::size_t r = 0; r < rows.size(); ++r)
      R.row(static_cast<Index>(r)).segment(b, nb) = D.row(rows[r]);
    if (!reporter.step(nb))
      reporter.throw_if_cancelled("the embedding's geodesic distances");
  }
  return R;
}

/// Stress (14) over the pairs i < j, and its number of pairs.
double stress_of(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Q)
{
  const Index n = X.rows();
  double s = 0;
  for (Index i = 0; i < n; ++i)
    for (Index j = i + 1; j < n; ++j)
    {
      const double r = 1.0 - (X.row(i) - X.row(j)).norm() / Q(i, j);
      s += r * r;
    }
  return s;
}

EmbeddingQuality quality_with(const GeodesicHeat& heat, const SurfaceMesh& mesh,
  const Eigen::MatrixXd& E, const std::vector<int>& sources)
{
  EmbeddingQuality q;
  if (sources.empty())
    return q;
  Eigen::VectorXi s(static_cast<Index>(sources.size()));
  for (std::size_t k = 0; k < sources.size(); ++k)
    s(static_cast<Index>(k)) = sources[k];
  const Eigen::MatrixXd D = heat.distances(s);
  const double min_distance = 3 * mesh.mean_edge_length;
  std::vector<double> errors;
  errors.reserve(static_cast<std::size_t>(D.size()));
  for (Index k = 0; k < s.size(); ++k)
    for (Index v = 0; v < D.rows(); ++v)
    {
      const double g = D(v, k);
      if (!(g > min_distance) || !std::isfinite(g))
        continue;
      errors.push_back(std::abs((E.row(v) - E.row(s(k))).norm() - g) / g);
    }
  q.pairs = static_cast<Index>(errors.size());
  if (errors.empty())
    return q;
  double sum = 0;
  for (const double e : errors)
  {
    sum += e;
    q.max_relative_error = std::max(q.max_relative_error, e);
  }
  q.mean_relative_error = sum / static_cast<double>(errors.size());
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2), errors.end());
  q.median_relative_error = errors[errors.size() / 2];
  return q;
}

} // namespace

void validate_embedding_options(const EmbeddingOptions& o)
{
  auto fail = [](const std::string& what) { throw Error(ErrorCode::InvalidArgument, what); };
  if (o.dimension < 2 || o.dimension > 64)
    fail("the embedding dimension must be in [2, 64], got " + std::to_string(o.dimension));
  if (o.landmarks < o.dimension + 2 || o.landmarks > 100000)
    fail("the number of landmarks must be in [dimension + 2, 100000] = [" +
      std::to_string(o.dimension + 2) + ", 100000], got " + std::to_string(o.landmarks));
  if (!(o.stress_tolerance >= 1e-14 && o.stress_tolerance <= 0.1))
    fail("the stress tolerance must be in [1e-14, 0.1], got " + detail::format_number(o.stress_tolerance));
  if (o.max_iterations < 0 || o.max_iterations > 100000)
    fail("the SMACOF iteration cap must be in [0, 100000], got " + std::to_string(o.max_iterations));
  if (!(o.heat_time_factor > 0 && o.heat_time_factor <= 1e6))
    fail("the heat time factor must be in (0, 1e6], got " + detail::format_number(o.heat_time_factor));
  if (o.quality_sources < 0 || o.quality_sources > 1000)
    fail("the number of quality sources must be in [0, 1000], got " + std::to_string(o.quality_sources));
  if (o.threads < 0 || o.threads > 1024)
    fail("the thread count must be in [0, 1024], got " + std::to_string(o.threads));
}

std::vector<int> farthest_point_landmarks(const SurfaceMesh& mesh, Index count)
{
  const Index nv = mesh.vertex_count();
  if (count >= nv)
  {
    std::vector<int> all(static_cast<std::size_t>(nv));
    for (Index v = 0; v < nv; ++v)
      all[static_cast<std::size_t>(v)] = static_cast<int>(v);
    return all;
  }
  std::vector<double> d(static_cast<std::size_t>(nv), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  // Lowers d by the distances from `source`; returns the farthest vertex (smallest id on ties).
  auto relax_from = [&](int source) {
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    d[static_cast<std::size_t>(source)] = 0;
    heap.emplace(0.0, source);
    while (!heap.empty())
    {
      const auto [dv, v] = heap.top();
      heap.pop();
      if (dv > d[static_cast<std::size_t>(v)])
        continue;
      for (int i = mesh.ring_offsets[static_cast<std::size_t>(v)]; i < mesh.ring_offsets[static_cast<std::size_t>(v + 1)]; ++i)
      {
        const int u = mesh.ring[static_cast<std::size_t>(i)];
        const double du = dv + (mesh.V.row(u) - mesh.V.row(v)).norm();
        if (du < d[static_cast<std::size_t>(u)])
        {
          d[static_cast<std::size_t>(u)] = du;
          heap.emplace(du, u);
        }
      }
    }
    return static_cast<int>(std::max_element(d.begin(), d.end()) - d.begin());
  };
  std::vector<int> chosen;
  chosen.reserve(static_cast<std::size_t>(count));
  int next = relax_from(0);
  std::fill(d.begin(), d.end(), std::numeric_limits<double>::infinity());
  while (static_cast<Index>(chosen.size()) < count)
  {
    chosen.push_back(next);
    next = relax_from(next);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

EmbeddingQuality embedding_quality(const SurfaceMesh& mesh, const Eigen::MatrixXd& E,
  const std::vector<int>& sources, double heat_time_factor)
{
  if (E.rows() != mesh.vertex_count())
    throw Error(ErrorCode::SizeMismatch, "the embedding has " + std::to_string(E.rows()) +
        " rows but the surface has " + std::to_string(mesh.vertex_count()) + " vertices");
  for (const int s : sources)
    if (s < 0 || s >= mesh.vertex_count())
      throw Error(ErrorCode::InvalidArgument, "quality source " + std::to_string(s) +
          " is not a vertex of the surface");
  GeodesicHeatOptions heat_options;
  heat_options.time_factor = heat_time_factor;
  const GeodesicHeat heat(mesh.V, mesh.F, heat_options);
  return quality_with(heat, mesh, E, sources);
}

EmbeddingResult euclidean_embedding(
  const SurfaceMesh& mesh, const EmbeddingOptions& options, const ProgressCallback& progress)
{
  validate_embedding_options(options);
  EmbeddingResult result;
  const Index nv = mesh.vertex_count();
  const int D = options.dimension;
  if (nv < D + 2)
    throw Error(ErrorCode::InvalidArgument, "the surface has " + std::to_string(nv) +
        " vertices; an embedding in R^" + std::to_string(D) + " needs at least " +
        std::to_string(D + 2));

  // 1. Landmarks.
  auto t0 = Clock::now();
  const Index nl = std::min(options.landmarks, nv);
  if (nl == nv)
    result.landmarks = farthest_point_landmarks(mesh, nv);
  else if (options.landmark_method == LandmarkMethod::FarthestPoint)
    result.landmarks = farthest_point_landmarks(mesh, nl);
  else
  {
    LandmarkDecimationOptions decimation;
    decimation.target_vertices = nl;
    result.landmarks = decimation_landmarks(mesh.V, mesh.F, decimation,
      [&](double f) { return progress ? progress(0.1 * f) : true; }).landmarks;
  }
  const Index L = static_cast<Index>(result.landmarks.size());
  result.seconds.emplace_back("landmarks", seconds_since(t0));

  // 2. Geodesic distances between landmarks.
  t0 = Clock::now();
  GeodesicHeatOptions heat_options;
  heat_options.time_factor = options.heat_time_factor;
  heat_options.threads = options.threads;
  const GeodesicHeat heat(mesh.V, mesh.F, heat_options);
  {
    ProgressReporter reporter(progress, L, 0.1, 0.5);
    Eigen::MatrixXd Q = heat_distances_at(heat, result.landmarks, result.landmarks, reporter);
    Q = 0.5 * (Q + Q.transpose()).eval();
    for (Index i = 0; i < L; ++i)
      for (Index j = 0; j < L; ++j)
        if (i != j && !(Q(i, j) > 0 && std::isfinite(Q(i, j))))
          throw Error(ErrorCode::NotConverged, "the heat-method distance between landmark vertices " +
              std::to_string(result.landmarks[static_cast<std::size_t>(i)]) + " and " +
              std::to_string(result.landmarks[static_cast<std::size_t>(j)]) + " is " +
              detail::format_number(Q(i, j)),
            "raise the heat time factor (the mesh is too fine for the default time step)");
    Q.diagonal().setZero();
    result.seconds.emplace_back("geodesics", seconds_since(t0));

    // 3a. Classical MDS: X = U_D Lambda_D^1/2 of B = -1/2 J (Q o Q) J.
    t0 = Clock::now();
    Eigen::MatrixXd B = Q.cwiseAbs2();
    const Eigen::VectorXd row_mean = B.rowwise().mean();
    const double mean = row_mean.mean();
    B = -0.5 * ((B.colwise() - row_mean).rowwise() - row_mean.transpose()).array() - 0.5 * mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(B);
    if (eig.info() != Eigen::Success)
      throw Error(ErrorCode::NotConverged, "the eigensolver of classical MDS did not converge");
    Eigen::MatrixXd X(L, D);
    for (int k = 0; k < D; ++k)
    {
      const Index c = L - 1 - k; // eigenvalues ascend
      X.col(k) = eig.eigenvectors().col(c) * std::sqrt(std::max(0.0, eig.eigenvalues()(c)));
    }
    const double pairs = 0.5 * static_cast<double>(L) * static_cast<double>(L - 1);
    double s = stress_of(X, Q);
    result.initial_stress = s / pairs;
    result.seconds.emplace_back("mds", seconds_since(t0));
    if (progress && !progress(0.55))
      throw Error(ErrorCode::Cancelled, "the embedding was cancelled");

    // 3b. SMACOF on the weighted stress, weights w_ij = 1 / Q_ij^2, dissimilarities Q_ij:
    // X <- V^+ B(X) X with V = sum w_ij (e_i - e_j)(e_i - e_j)^T; since the columns of B(X) X
    // sum to zero, V^+ B(X) X = (V + 1 1^T)^-1 B(X) X.
    t0 = Clock::now();
    result.smacof_converged = options.max_iterations == 0;
    if (options.max_iterations > 0)
    {
      Eigen::MatrixXd W = Q.cwiseAbs2().cwiseInverse();
      W.diagonal().setZero();
      Eigen::MatrixXd Vm = -W;
      Vm.diagonal() = W.rowwise().sum();
      Vm.array() += 1.0;
      const Eigen::LLT<Eigen::MatrixXd> vinv(Vm);
      if (vinv.info() != Eigen::Success)
        throw Error(ErrorCode::Internal, "the SMACOF matrix is not positive definite");
      // One pass over the pairs per iteration gives both the stress of X and B(X) X, whose row
      // i is sum_j (x_i - x_j) / (Q_ij d_ij(X)); no L x L matrix is formed.
      using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
      RowMatrix Xr = X, BX(L, D);
      Eigen::VectorXd row_stress(L);
      ProgressReporter smacof_reporter(progress, options.max_iterations, 0.55, 0.85);
      double previous = s;
      for (int it = 0; it <= options.max_iterations; ++it)
      {
        // Per-row stress summed in order afterwards: the stopping test does not depend on the
        // thread count.
#pragma omp parallel for schedule(dynamic, 16) num_threads(detail::thread_count(options.threads))
        for (Index i = 0; i < L; ++i)
        {
          double stress = 0;
          double acc[64] = { 0 };
          const double* xi = Xr.data() + i * D;
          const double* qi = Q.data() + i * L; // column i = row i (Q is symmetric)
          for (Index j = 0; j < L; ++j)
          {
            if (j == i)
              continue;
            const double* xj = Xr.data() + j * D;
            double d2 = 0;
            for (int k = 0; k < D; ++k)
            {
              const double t = xi[k] - xj[k];
              d2 += t * t;
            }
            const double d = std::sqrt(d2);
            if (j > i)
            {
              const double r = 1.0 - d / qi[j];
              stress += r * r;
            }
            if (d > 0)
            {
              const double c = 1.0 / (qi[j] * d);
              for (int k = 0; k < D; ++k)
                acc[k] += c * (xi[k] - xj[k]);
            }
          }
          for (int k = 0; k < D; ++k)
            BX(i, k) = acc[k];
          row_stress(i) = stress;
        }
        const double stress = row_stress.sum();
        if (it == 0)
          previous = stress; // = s, recomputed in the pass
        else
        {
          result.smacof_iterations = it;
          const bool small_step = !(previous - stress > options.stress_tolerance * previous);
          previous = stress;
          if (small_step)
          {
            result.smacof_converged = true;
            break;
          }
          if (!smacof_reporter.step())
            smacof_reporter.throw_if_cancelled("the embedding's SMACOF iterations");
        }
        if (it == options.max_iterations)
          break;
        Xr = vinv.solve(Eigen::MatrixXd(BX));
      }
      X = Xr;
      s = previous;
    }
    result.stress = s / pairs;
    result.seconds.emplace_back("smacof", seconds_since(t0));

    // 4. Least-squares mesh: min tr(v^T K M^-1 K v) with the landmarks fixed.
    t0 = Clock::now();
    if (L == nv)
    {
      result.E.resize(nv, D);
      for (Index i = 0; i < L; ++i)
        result.E.row(result.landmarks[static_cast<std::size_t>(i)]) = X.row(i);
    }
    else
    {
      const Eigen::SparseMatrix<double> K = stiffness_matrix(mesh.V, mesh.F);
      const Eigen::SparseMatrix<double> M = mass_matrix(mesh.V, mesh.F);
      Eigen::SparseMatrix<double> Minv = M;
      for (Index k = 0; k < Minv.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(Minv, k); it; ++it)
          it.valueRef() = 1.0 / it.value();
      const Eigen::SparseMatrix<double> A = K * Minv * K;
      Eigen::VectorXi known(L);
      for (Index i = 0; i < L; ++i)
        known(i) = result.landmarks[static_cast<std::size_t>(i)];
      MinQuadWithFixed solver;
      solver.precompute(A, known);
      result.E = solver.solve(Eigen::MatrixXd(), X);
    }
    result.seconds.emplace_back("upsampling", seconds_since(t0));
    if (progress && !progress(0.95))
      throw Error(ErrorCode::Cancelled, "the embedding was cancelled");
  }

  // 5. Quality against heat-method geodesics from evenly spread sources.
  t0 = Clock::now();
  if (options.quality_sources > 0)
    result.quality = quality_with(heat, mesh, result.E,
      farthest_point_landmarks(mesh, std::min<Index>(options.quality_sources, nv)));
  result.seconds.emplace_back("quality", seconds_since(t0));
  if (progress && !progress(1.0))
    throw Error(ErrorCode::Cancelled, "the embedding was cancelled");
  return result;
}

} // namespace bary
