#include "core/analysis/locality_statistics.h"

#include "core/common/error.h"
#include "core/solvers/fem_operators.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace bary
{
namespace
{

double resolve_threshold(double threshold, Index controls)
{
  if (threshold < 0.0)
    return 1e-3 / static_cast<double>(controls);
  if (!(threshold > 0.0) || !std::isfinite(threshold))
    throw Error(ErrorCode::InvalidArgument,
      "the locality threshold must be > 0 (or negative for 1e-3 / #C), got " +
        std::to_string(threshold));
  return threshold;
}

void check_weights(const DenseWeights& W)
{
  if (W.rows() == 0 || W.cols() == 0)
    throw Error(ErrorCode::EmptyInput, "the weight matrix is empty");
  for (Index p = 0; p < W.rows(); ++p)
    if (!W.row(p).allFinite())
      throw Error(ErrorCode::NonFinite,
        "the weights of point " + std::to_string(p) + " hold NaN or infinity");
}

} // namespace

std::vector<double> default_locality_t()
{
  std::vector<double> t{ 0.0 };
  for (int j = 0; j <= 24; ++j)
    t.push_back(std::pow(10.0, -6.0 + j / 4.0));
  t.back() = 1.0;
  return t;
}

Eigen::VectorXd vertex_measures(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  return mass_matrix(V, T, MassMatrixType::Barycentric).diagonal();
}

LocalityStatistics locality_statistics(const DenseWeights& W, double threshold,
  const Eigen::VectorXd& measure, const std::vector<double>& t)
{
  check_weights(W);
  const Index np = W.rows(), nc = W.cols();
  LocalityStatistics s;
  s.threshold = resolve_threshold(threshold, nc);
  Eigen::VectorXd mu;
  if (measure.size() == 0)
    mu = Eigen::VectorXd::Ones(np);
  else
  {
    if (measure.size() != np)
      throw Error(ErrorCode::SizeMismatch,
        "measure has " + std::to_string(measure.size()) + " entries for " + std::to_string(np) +
          " points");
    if (!measure.allFinite())
      throw Error(ErrorCode::NonFinite, "the point measures hold NaN or infinity");
    if (measure.minCoeff() < 0.0)
      throw Error(ErrorCode::InvalidArgument, "point measures must be >= 0");
    mu = measure;
  }
  const double total = mu.sum();
  if (!(total > 0.0))
    throw Error(ErrorCode::InvalidArgument, "the point measures sum to 0");

  s.t = t.empty() ? default_locality_t() : t;
  for (double v : s.t)
    if (!std::isfinite(v))
      throw Error(ErrorCode::NonFinite, "a t value for P(t) is NaN or infinite");
  std::sort(s.t.begin(), s.t.end());
  const std::size_t nt = s.t.size();

  // P(t): histogram of the first t index with |w| <= t, then cumulative sums.
  std::vector<double> bins(nt + 1, 0.0);
  s.influence_fraction.assign(static_cast<std::size_t>(nc), 0.0);
  std::vector<double> support_measure(static_cast<std::size_t>(nc) + 1, 0.0);
  s.max_support = 0.0;
  double mean = 0.0;
  for (Index p = 0; p < np; ++p)
  {
    int sigma = 0;
    for (Index i = 0; i < nc; ++i)
    {
      const double w = W(p, i);
      const std::size_t first =
        static_cast<std::size_t>(std::lower_bound(s.t.begin(), s.t.end(), std::abs(w)) - s.t.begin());
      bins[first] += mu(p);
      if (w > s.threshold)
      {
        ++sigma;
        s.influence_fraction[static_cast<std::size_t>(i)] += mu(p);
      }
    }
    support_measure[static_cast<std::size_t>(sigma)] += mu(p);
    s.max_support = std::max(s.max_support, static_cast<double>(sigma));
    mean += mu(p) * sigma;
  }
  s.P.resize(nt);
  double cumulative = 0.0;
  for (std::size_t j = 0; j < nt; ++j)
  {
    cumulative += bins[j];
    s.P[j] = cumulative / (total * static_cast<double>(nc));
  }
  for (double& f : s.influence_fraction)
    f /= total;
  s.mean_support = mean / total;
  // Q(k) = measure{sigma >= k} / total, k = 1 .. #C
  s.k.resize(static_cast<std::size_t>(nc));
  s.Q.resize(static_cast<std::size_t>(nc));
  double tail = 0.0;
  for (Index k = nc; k >= 1; --k)
  {
    tail += support_measure[static_cast<std::size_t>(k)];
    s.k[static_cast<std::size_t>(k - 1)] = static_cast<int>(k);
    s.Q[static_cast<std::size_t>(k - 1)] = tail / total;
  }
  return s;
}

ReducedWeights reduce_weights(const DenseWeights& W, double threshold, const Points* controls,
  const Points* points, bool renormalize)
{
  return reduce_weights(
    W, threshold, renormalize ? Renormalization::RowSum : Renormalization::None, controls, points);
}

ReducedWeights reduce_weights(const DenseWeights& W, double threshold, Renormalization mode,
  const Points* controls, const Points* points)
{
  check_weights(W);
  const Index np = W.rows(), nc = W.cols();
  ReducedWeights r;
  r.threshold = resolve_threshold(threshold, nc);
  r.renormalization = mode;
  if ((controls == nullptr) != (points == nullptr))
    throw Error(ErrorCode::SizeMismatch,
      "give both the control points and the points (for the reproduction error), or neither");
  const bool geometry = controls != nullptr;
  double diameter = 1.0;
  if (geometry)
  {
    if (controls->rows() != nc)
      throw Error(ErrorCode::SizeMismatch,
        "there are " + std::to_string(controls->rows()) + " control points for " +
          std::to_string(nc) + " weight columns");
    if (points->rows() != np)
      throw Error(ErrorCode::SizeMismatch,
        "there are " + std::to_string(points->rows()) + " points for " + std::to_string(np) +
          " weight rows");
    if (points->cols() != controls->cols())
      throw Error(ErrorCode::SizeMismatch, "points and control points differ in dimension");
    if (!controls->allFinite() || !points->allFinite())
      throw Error(ErrorCode::NonFinite, "the control points or points hold NaN or infinity");
    diameter = (controls->colwise().maxCoeff() - controls->colwise().minCoeff()).norm();
    if (!(diameter > 0.0))
      diameter = 1.0;
  }
  else if (mode == Renormalization::Affine)
    throw Error(ErrorCode::InvalidArgument,
      "Renormalization::Affine needs the control points and the points");

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(np) * 8);
  const Index dim = geometry ? controls->cols() : 0;
  double max_dropped = 0.0;
  for (Index p = 0; p < np; ++p)
  {
    std::vector<int> keep;
    double kept = 0.0, dropped = 0.0;
    for (Index i = 0; i < nc; ++i)
      if (W(p, i) > r.threshold)
      {
        keep.push_back(static_cast<int>(i));
        kept += W(p, i);
      }
      else
        dropped += std::abs(W(p, i));
    max_dropped = std::max(max_dropped, dropped);
    Eigen::VectorXd w(static_cast<Index>(keep.size()));
    for (std::size_t j = 0; j < keep.size(); ++j)
      w(static_cast<Index>(j)) = W(p, keep[j]);
    bool row_sum = mode == Renormalization::RowSum ||
      (mode == Renormalization::Affine && keep.empty());
    if (mode == Renormalization::Affine && !keep.empty())
    {
      // least-norm correction: A^T (w + dw) = b with A = [c_S 1]
      Eigen::MatrixXd A(static_cast<Index>(keep.size()), dim + 1);
      for (std::size_t j = 0; j < keep.size(); ++j)
      {
        A.row(static_cast<Index>(j)).head(dim) = controls->row(keep[j]);
        A(static_cast<Index>(j), dim) = 1.0;
      }
      Eigen::VectorXd b(dim + 1);
      b.head(dim) = points->row(p).transpose();
      b(dim) = 1.0;
      const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A.transpose());
      // rank relative to the controls' extent (A's last column is all ones)
      if (cod.rank() == dim + 1)
        w += cod.solve(Eigen::VectorXd(b - A.transpose() * w));
      else
        row_sum = true;
    }
    if (row_sum)
    {
      if (!(kept > 0.0))
        throw Error(ErrorCode::InvalidArgument,
          "point " + std::to_string(p) + " has no weight above the threshold " +
            std::to_string(r.threshold) + ": its row cannot be renormalised");
      w /= kept;
    }
    for (std::size_t j = 0; j < keep.size(); ++j)
      triplets.emplace_back(static_cast<int>(p), keep[j], w(static_cast<Index>(j)));
  }
  r.W.resize(np, nc);
  r.W.setFromTriplets(triplets.begin(), triplets.end());
  r.W.makeCompressed();
  r.max_dropped = max_dropped;
  r.nonzeros = r.W.nonZeros();
  r.memory_fraction = (static_cast<double>(r.nonzeros) * 12.0 + static_cast<double>(np + 1) * 4.0) /
    (static_cast<double>(np) * static_cast<double>(nc) * 8.0);
  r.min_weight = r.nonzeros ? std::numeric_limits<double>::infinity() : 0.0;
  double partition = 0.0, reproduction = 0.0;
  for (Index p = 0; p < np; ++p)
  {
    double sum = 0.0;
    Eigen::RowVectorXd x = Eigen::RowVectorXd::Zero(dim);
    for (SparseWeights::InnerIterator it(r.W, p); it; ++it)
    {
      sum += it.value();
      r.min_weight = std::min(r.min_weight, it.value());
      if (geometry)
        x += it.value() * controls->row(it.col());
    }
    partition = std::max(partition, std::abs(sum - 1.0));
    if (geometry)
      reproduction = std::max(reproduction, (x - points->row(p)).norm() / diameter);
  }
  r.partition_error = partition;
  r.reproduction_error = geometry ? reproduction : std::numeric_limits<double>::quiet_NaN();
  return r;
}

} // namespace bary
