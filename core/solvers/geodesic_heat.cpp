#include "core/solvers/geodesic_heat.h"

#include "core/detail/parallel_for.h"
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/detail/timing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace bary
{
namespace
{

/// Mean length of the mesh's edges, each edge counted once.
double average_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  std::vector<std::pair<int, int>> edges;
  edges.reserve(static_cast<std::size_t>(T.rows() * T.cols() * (T.cols() - 1) / 2));
  for (Index t = 0; t < T.rows(); ++t)
    for (Index a = 0; a < T.cols(); ++a)
      for (Index b = a + 1; b < T.cols(); ++b)
        edges.emplace_back(std::min(T(t, a), T(t, b)), std::max(T(t, a), T(t, b)));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  double sum = 0.0;
  for (const auto& [a, b] : edges)
    sum += (V.row(a) - V.row(b)).norm();
  return edges.empty() ? 0.0 : sum / static_cast<double>(edges.size());
}

void check_cancel(const ProgressCallback& progress, double fraction)
{
  if (progress && !progress(fraction))
    throw Error(ErrorCode::Cancelled, "the heat-method geodesic distances were cancelled");
}

} // namespace

void GeodesicHeat::check_options(const GeodesicHeatOptions& options)
{
  if (!(options.time_factor > 0.0 && options.time_factor <= 1e6))
    throw Error(ErrorCode::InvalidArgument,
      "GeodesicHeatOptions::time_factor must be in (0, 1e6], got " +
        std::to_string(options.time_factor));
  if (options.threads < 0)
    throw Error(ErrorCode::InvalidArgument,
      "GeodesicHeatOptions::threads must be >= 0 (0 = OpenMP's default), got " +
        std::to_string(options.threads));
}

GeodesicHeat::GeodesicHeat(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, const GeodesicHeatOptions& options)
  : options_(options)
  , V_(V)
  , T_(T)
{
  check_options(options);
  const auto t0 = std::chrono::steady_clock::now();
  // gradient_operator validates the mesh (shapes, indices, degenerate elements, finiteness).
  Eigen::SparseMatrix<double> G = gradient_operator(V, T);
  Eigen::VectorXd volume = simplex_volumes(V, T);
  factor(std::move(G), std::move(volume), t0);
}

GeodesicHeat::GeodesicHeat(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  Eigen::SparseMatrix<double> G, Eigen::VectorXd volumes, const GeodesicHeatOptions& options)
  : options_(options)
  , V_(V)
  , T_(T)
{
  check_options(options);
  if (T.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no elements (T has no rows)");
  if (G.rows() != T.rows() * V.cols() || G.cols() != V.rows() || volumes.size() != T.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the gradient operator must be (#T dim) by #V and the volumes #T long for this mesh");
  factor(std::move(G), std::move(volumes), std::chrono::steady_clock::now());
}

void GeodesicHeat::factor(Eigen::SparseMatrix<double> G, Eigen::VectorXd volume,
  std::chrono::steady_clock::time_point t0)
{
  const Eigen::MatrixXd& V = V_;
  const Eigen::MatrixXi& T = T_;
  const GeodesicHeatOptions& options = options_;
  G_ = std::move(G);
  volume_ = std::move(volume);
  // K = G^T diag(vol) G (the stiffness matrix), M lumped: 1/(d+1) of the incident volumes.
  const Index dim = V.cols();
  Eigen::VectorXd weights(T.rows() * dim);
  for (Index t = 0; t < T.rows(); ++t)
    weights.segment(t * dim, dim).setConstant(volume_(t));
  const Eigen::SparseMatrix<double> K =
    Eigen::SparseMatrix<double>(G_.transpose() * weights.asDiagonal() * G_);
  Eigen::VectorXd lumped = Eigen::VectorXd::Zero(V.rows());
  for (Index t = 0; t < T.rows(); ++t)
    for (Index k = 0; k < T.cols(); ++k)
      lumped(T(t, k)) += volume_(t) / static_cast<double>(T.cols());
  Eigen::SparseMatrix<double> M(V.rows(), V.rows());
  M.reserve(Eigen::VectorXi::Ones(V.rows()));
  for (Index v = 0; v < V.rows(); ++v)
    M.insert(v, v) = lumped(v);
  const Index n = V.rows();
  {
    std::vector<char> used(static_cast<std::size_t>(n), 0);
    for (Index t = 0; t < T.rows(); ++t)
      for (Index k = 0; k < T.cols(); ++k)
        used[static_cast<std::size_t>(T(t, k))] = 1;
    for (Index v = 0; v < n; ++v)
      if (!used[static_cast<std::size_t>(v)])
        throw Error(ErrorCode::InvalidArgument,
          "mesh vertex " + std::to_string(v) +
            " belongs to no element: remove unreferenced vertices before computing distances");
  }
  h_ = average_edge_length(V, T);
  t_ = options.time_factor * h_ * h_;

  // I. heat flow matrix, Neumann boundary.
  heat_ = SparseCholesky(options.backend);
  heat_.compute(Eigen::SparseMatrix<double>(M + t_ * K));

  // III. Poisson matrix with the first vertex of every connected component pinned to 0.
  component_ = connected_components(n, T);
  const int components = component_.size() ? component_.maxCoeff() + 1 : 0;
  std::vector<char> pinned_component(static_cast<std::size_t>(components), 0);
  pinned_index_.resize(n);
  std::vector<int> free_ids;
  free_ids.reserve(static_cast<std::size_t>(n));
  for (Index v = 0; v < n; ++v)
  {
    char& pinned = pinned_component[static_cast<std::size_t>(component_(v))];
    if (!pinned)
    {
      pinned = 1;
      pinned_index_(v) = -1;
    }
    else
    {
      pinned_index_(v) = static_cast<int>(free_ids.size());
      free_ids.push_back(static_cast<int>(v));
    }
  }
  poisson_ = SparseCholesky(options.backend);
  if (!free_ids.empty())
  {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(K.nonZeros()));
    for (Index j = 0; j < K.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, j); it; ++it)
      {
        const int r = pinned_index_(it.row()), c = pinned_index_(it.col());
        if (r >= 0 && c >= 0)
          triplets.emplace_back(r, c, it.value());
      }
    Eigen::SparseMatrix<double> Kf(
      static_cast<Index>(free_ids.size()), static_cast<Index>(free_ids.size()));
    Kf.setFromTriplets(triplets.begin(), triplets.end());
    poisson_.compute(Kf, Eigen::Map<const Eigen::VectorXi>(
                           free_ids.data(), static_cast<Index>(free_ids.size())));
  }
  factor_seconds_ = seconds_since(t0);
}

Eigen::MatrixXd GeodesicHeat::potential(
  const Eigen::MatrixXd& U, const ProgressCallback& progress, Index* zero_gradient_elements) const
{
  const Index n = V_.rows(), k = U.cols(), cells = T_.rows();
  const Index dim = V_.cols();
  // II. X = -grad u / |grad u| per element, times the element's volume: G^T (A X) is then the
  // integrated divergence (weak form).
  Eigen::MatrixXd X = G_ * U;
  Index zero = 0;
  const int threads = detail::thread_count(options_.threads);
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : zero)
  for (Index t = 0; t < cells; ++t)
    for (Index j = 0; j < k; ++j)
    {
      auto g = X.col(j).segment(t * dim, dim);
      const double norm = g.norm();
      if (norm > 0.0 && std::isfinite(norm))
        g *= -volume_(t) / norm;
      else
      {
        g.setZero();
        ++zero;
      }
    }
  if (zero_gradient_elements)
    *zero_gradient_elements = zero;
  check_cancel(progress, 0.7);
  const Eigen::MatrixXd B = G_.transpose() * X;

  // III. K phi = B on the free vertices, 0 at the pinned ones.
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(n, k);
  if (poisson_.computed())
  {
    Eigen::MatrixXd Bf(poisson_.rows(), k);
    for (Index v = 0; v < n; ++v)
      if (pinned_index_(v) >= 0)
        Bf.row(pinned_index_(v)) = B.row(v);
    const Eigen::MatrixXd Pf = poisson_.solve(Bf);
    for (Index v = 0; v < n; ++v)
      if (pinned_index_(v) >= 0)
        phi.row(v) = Pf.row(pinned_index_(v));
  }
  return phi;
}

void GeodesicHeat::check_sources(const int* sources, Index count) const
{
  const Index n = V_.rows();
  for (Index j = 0; j < count; ++j)
    if (sources[j] < 0 || sources[j] >= n)
      throw Error(ErrorCode::InvalidArgument,
        "source " + std::to_string(j) + " is vertex " + std::to_string(sources[j]) +
          ", outside [0, " + std::to_string(n) + ")");
}

Eigen::MatrixXd GeodesicHeat::distances(
  const Eigen::VectorXi& sources, const ProgressCallback& progress, Index* zero_gradient_elements) const
{
  const Index n = V_.rows();
  check_sources(sources.data(), sources.size());
  if (zero_gradient_elements)
    *zero_gradient_elements = 0;
  if (sources.size() == 0)
    return Eigen::MatrixXd(n, 0);
  check_cancel(progress, 0.0);
  Eigen::MatrixXd delta = Eigen::MatrixXd::Zero(n, sources.size());
  for (Index j = 0; j < sources.size(); ++j)
    delta(sources(j), j) = 1.0;
  const Eigen::MatrixXd U = heat_.solve(delta);
  check_cancel(progress, 0.4);
  Eigen::MatrixXd phi = potential(U, progress, zero_gradient_elements);
  // Shift: 0 at the source; +infinity outside the source's component.
  const double inf = std::numeric_limits<double>::infinity();
  for (Index j = 0; j < sources.size(); ++j)
  {
    const double shift = phi(sources(j), j);
    const int c = component_(sources(j));
    for (Index v = 0; v < n; ++v)
      phi(v, j) = component_(v) == c ? phi(v, j) - shift : inf;
  }
  check_cancel(progress, 1.0);
  return phi;
}

Eigen::VectorXd GeodesicHeat::distance_to_set(const std::vector<int>& sources) const
{
  const Index n = V_.rows();
  if (sources.empty())
    throw Error(ErrorCode::InvalidArgument, "distance_to_set needs at least one source vertex");
  check_sources(sources.data(), static_cast<Index>(sources.size()));
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
  for (int s : sources)
    delta(s) = 1.0;
  const Eigen::MatrixXd U = heat_.solve(delta);
  Eigen::VectorXd phi = potential(U, {}, nullptr).col(0);
  // Per component: shift so that the smallest value over its sources is 0; +infinity in
  // components without a source.
  const double inf = std::numeric_limits<double>::infinity();
  const int components = component_.maxCoeff() + 1;
  std::vector<double> shift(static_cast<std::size_t>(components), inf);
  for (int s : sources)
  {
    double& m = shift[static_cast<std::size_t>(component_(s))];
    m = std::min(m, phi(s));
  }
  for (Index v = 0; v < n; ++v)
  {
    const double m = shift[static_cast<std::size_t>(component_(v))];
    phi(v) = m < inf ? phi(v) - m : inf;
  }
  return phi;
}

Eigen::MatrixXd heat_geodesic_distances(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const Eigen::VectorXi& sources, const GeodesicHeatOptions& options,
  const ProgressCallback& progress)
{
  return GeodesicHeat(V, T, options).distances(sources, progress);
}

} // namespace bary
