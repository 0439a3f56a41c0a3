#include "core/spline/spline_fit.h"

#include "core/common/error.h"
#include "core/detail/exact_elimination.h"

#include <Eigen/SparseLU>

#include <cmath>

namespace bary
{

SplineFit fit_spline(std::shared_ptr<const SplineNet> net, const Points& X,
  const Eigen::MatrixXd& Y, double regularization, const std::vector<Index>& pinned)
{
  if (X.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "no samples to fit a spline to");
  if (X.cols() < 2 || X.rows() != Y.rows() || Y.cols() < 1)
    throw Error(ErrorCode::SizeMismatch,
      "spline fit samples: " + std::to_string(X.rows()) + " points and " +
        std::to_string(Y.rows()) + " values (need the same count, points with x and y)");
  if (!Y.allFinite())
    throw Error(ErrorCode::NonFinite, "a sample value to fit is not finite");
  if (!(regularization >= 0 && regularization <= 1))
    throw Error(ErrorCode::InvalidArgument,
      "spline fit regularization " + std::to_string(regularization) + " is out of range [0, 1]");
  const Index n = net->num_points();
  const int m = static_cast<int>(Y.cols());
  const int d = net->degree();
  const int nb = bezier_count(d);
  // The samples' located pieces: a row of Bernstein values per sample.
  const TriangularSpline probe(net, Eigen::MatrixXd::Zero(n, m));
  const TriangularSpline::Locations where = probe.locate(X.leftCols(2));
  std::vector<Eigen::Triplet<double>> trip;
  std::vector<double> basis(static_cast<size_t>(nb));
  for (Index s = 0; s < X.rows(); ++s)
  {
    const Index t = where.triangle[static_cast<size_t>(s)];
    bernstein_basis(d, where.barycentric[static_cast<size_t>(s)], basis.data());
    for (int r = 0; r < nb; ++r)
      trip.emplace_back(s, net->local_to_global()(t, r), basis[static_cast<size_t>(r)]);
  }
  Eigen::SparseMatrix<double> M(X.rows(), n);
  M.setFromTriplets(trip.begin(), trip.end());
  Eigen::SparseMatrix<double> H = Eigen::SparseMatrix<double>(M.transpose()) * M;
  double scale = 0;
  for (Index k = 0; k < H.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, k); it; ++it)
      if (it.row() == it.col())
        scale = std::max(scale, it.value());
  const double eps = regularization * scale;
  const Eigen::MatrixXd c0 = m == 2 ? Eigen::MatrixXd(net->nominal()) : Eigen::MatrixXd::Zero(n, m);

  // The independent conditions (exact elimination with every control point unknown).
  const auto& conds = net->conditions();
  std::vector<detail::ExactCondition> rows(conds.size());
  for (size_t r = 0; r < conds.size(); ++r)
    for (int k = 0; k < 4; ++k)
    {
      rows[r].column[static_cast<size_t>(k)] = static_cast<int>(conds[r].point[static_cast<size_t>(k)]);
      const int v = conds[r].vertex[static_cast<size_t>(k)];
      rows[r].vertex[static_cast<size_t>(k)] = { net->vertices()(v, 0), net->vertices()(v, 1) };
    }
  // Pinned points are known (at c0, which satisfies every condition): their columns are
  // constants for the elimination, and they get rows c_p = c0_p of their own.
  std::vector<char> is_pinned(static_cast<size_t>(n), 0);
  for (Index p : pinned)
  {
    if (p < 0 || p >= n)
      throw Error(ErrorCode::InvalidArgument,
        "pinned control point " + std::to_string(p) + " is out of range [0, " + std::to_string(n - 1) + "]");
    is_pinned[static_cast<size_t>(p)] = 1;
  }
  for (auto& row : rows)
    for (int k = 0; k < 4; ++k)
      if (row.column[static_cast<size_t>(k)] >= 0 && is_pinned[static_cast<size_t>(row.column[static_cast<size_t>(k)])])
        row.column[static_cast<size_t>(k)] = -1;
  const detail::ExactElimination ex = detail::eliminate_exact(rows, static_cast<int>(n), 0);
  const Index nc = static_cast<Index>(ex.independent.size());
  std::vector<Index> pins;
  for (Index p = 0; p < n; ++p)
    if (is_pinned[static_cast<size_t>(p)])
      pins.push_back(p);
  const Index npin = static_cast<Index>(pins.size());

  // KKT: [H + eps I, C^T; C, 0] [c; lambda] = [M^T Y + eps c0; 0].
  std::vector<Eigen::Triplet<double>> kt;
  for (Index k = 0; k < H.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, k); it; ++it)
      kt.emplace_back(it.row(), it.col(), it.value());
  // Membrane energy of the displacement c - c0 over the edges of the Bézier net (plus 1e-6 of it
  // on the diagonal, for uniqueness where nothing else decides): away from the samples the
  // displacement decays smoothly instead of jumping back to c0.
  Eigen::MatrixXd Lc0 = Eigen::MatrixXd::Zero(n, m);
  for (Index p = 0; p < n; ++p)
  {
    const std::vector<Index> nb_p = net->net_neighbours(p);
    kt.emplace_back(p, p, eps * (static_cast<double>(nb_p.size()) + 1e-6));
    Lc0.row(p) += eps * (static_cast<double>(nb_p.size()) + 1e-6) * c0.row(p);
    for (Index q : nb_p)
    {
      kt.emplace_back(p, q, -eps);
      Lc0.row(p) -= eps * c0.row(q);
    }
  }
  for (Index r = 0; r < nc; ++r)
  {
    const QuadCondition& q = conds[static_cast<size_t>(ex.independent[static_cast<size_t>(r)])];
    for (int k = 0; k < 4; ++k)
    {
      kt.emplace_back(n + r, q.point[static_cast<size_t>(k)], q.coefficient[static_cast<size_t>(k)]);
      kt.emplace_back(q.point[static_cast<size_t>(k)], n + r, q.coefficient[static_cast<size_t>(k)]);
    }
  }
  for (Index r = 0; r < npin; ++r)
  {
    kt.emplace_back(n + nc + r, pins[static_cast<size_t>(r)], 1.0);
    kt.emplace_back(pins[static_cast<size_t>(r)], n + nc + r, 1.0);
  }
  Eigen::SparseMatrix<double> K(n + nc + npin, n + nc + npin);
  K.setFromTriplets(kt.begin(), kt.end());
  K.makeCompressed();
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(K);
  if (lu.info() != Eigen::Success)
    throw Error(ErrorCode::NotConverged,
      "the spline fit's system is singular: too few samples where the regularization is 0",
      "give samples in every triangle or a positive regularization");
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n + nc + npin, m);
  b.topRows(n) = Eigen::MatrixXd(M.transpose() * Y) + Lc0;
  for (Index r = 0; r < npin; ++r)
    b.row(n + nc + r) = c0.row(pins[static_cast<size_t>(r)]);
  const Eigen::MatrixXd sol = lu.solve(b);
  if (!sol.allFinite())
    throw Error(ErrorCode::NotConverged, "the spline fit's solve failed");
  SplineFit out;
  out.spline.emplace(net, sol.topRows(n));
  out.conditions = static_cast<Index>(conds.size());
  out.independent_conditions = nc;
  const Eigen::MatrixXd fitted = out.spline->evaluate(where);
  double sum = 0;
  for (Index s = 0; s < X.rows(); ++s)
  {
    const double e = (fitted.row(s) - Y.row(s)).norm();
    sum += e * e;
    out.max_error = std::max(out.max_error, e);
  }
  out.rms_error = std::sqrt(sum / static_cast<double>(X.rows()));
  return out;
}

} // namespace bary
