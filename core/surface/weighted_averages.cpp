#include "core/surface/weighted_averages.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace bary
{

struct WeightedAverages::Workspace
{
  std::vector<int> stamp;  ///< per triangle: the query that last visited it
  std::vector<int> queue;  ///< breadth-first queue of triangles
  std::vector<std::pair<double, int>> ring; ///< the start vertex's triangles, with their order
  int query = 0;
  Index tried = 0;         ///< Phong projections attempted
  Eigen::VectorXd ybar, point;
};

namespace
{

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr Index kChunk = 256; // queries per chunk: the unit of warm starts and of parallelism

double squared_distance(const double* a, const double* b, int D)
{
  if (D == 8) // the default dimension: a fixed-length loop the compiler vectorises
  {
    double s = 0;
    for (int d = 0; d < 8; ++d)
    {
      const double t = a[d] - b[d];
      s += t * t;
    }
    return s;
  }
  double s = 0;
  for (int d = 0; d < D; ++d)
  {
    const double t = a[d] - b[d];
    s += t * t;
  }
  return s;
}

/// lambda = M^+ b for the symmetric positive semidefinite 3 x 3 M of the inverse problem,
/// b = (0, 0, 1): equilibrated to a unit diagonal, Cholesky when it is well conditioned (the
/// usual case), else the eigen-decomposition's pseudo-inverse (directions below 1e-14 of the
/// largest eigenvalue dropped: anchors that do not span the tangent plane); then one step of
/// iterative refinement with the residual b - A w that @p residual(lambda) returns.
template<class Residual>
Eigen::Vector3d solve_constraints(const Eigen::Matrix3d& M, Residual&& residual)
{
  const Eigen::Vector3d scale = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::Matrix3d Ms = scale.asDiagonal() * M * scale.asDiagonal();
  const Eigen::LLT<Eigen::Matrix3d> llt(Ms);
  const Eigen::Matrix3d L = llt.matrixL();
  const bool cholesky = llt.info() == Eigen::Success && L.diagonal().minCoeff() > 1e-6;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  if (!cholesky)
    eig.compute(Ms);
  auto solve = [&](const Eigen::Vector3d& rhs) {
    const Eigen::Vector3d r = scale.asDiagonal() * rhs;
    Eigen::Vector3d y;
    if (cholesky)
      y = llt.solve(r);
    else
    {
      y.setZero();
      const Eigen::Vector3d ev = eig.eigenvalues();
      const double cutoff = 1e-14 * ev.cwiseAbs().maxCoeff();
      for (int k = 0; k < 3; ++k)
        if (ev(k) > cutoff)
          y += eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(r) / ev(k));
    }
    return Eigen::Vector3d(scale.asDiagonal() * y);
  };
  Eigen::Vector3d lambda = solve(Eigen::Vector3d(0, 0, 1));
  lambda += solve(residual(lambda));
  return lambda;
}

/// The corner of a surface point with the largest barycentric coordinate.
int nearest_corner(const Eigen::MatrixXi& F, const SurfacePoint& p)
{
  Index k;
  p.barycentric.maxCoeff(&k);
  return F(p.face, k);
}

} // namespace

void validate_forward_options(const ForwardOptions& options)
{
  if (options.max_triangles < 0 || options.max_triangles > std::numeric_limits<int>::max())
    throw Error(ErrorCode::InvalidArgument, "the triangle cap must be in [0, 2^31), got " +
        std::to_string(options.max_triangles));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
}

void validate_round_trip_tolerance(double tolerance)
{
  if (!(tolerance > 0 && tolerance <= 1e6))
    throw Error(ErrorCode::InvalidArgument, "the round-trip tolerance must be in (0, 1e6] (times "
        "the mean edge length), got " + detail::format_number(tolerance));
}

void validate_inverse_options(const InverseOptions& options)
{
  if (!(options.gamma >= 1.0 && options.gamma <= 1e6))
    throw Error(ErrorCode::InvalidArgument,
      "gamma must be in [1, 1e6], got " + detail::format_number(options.gamma));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
}

void validate_surface_points(
  const SurfaceMesh& mesh, const std::vector<SurfacePoint>& points, const char* what)
{
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const SurfacePoint& p = points[i];
    const std::string name = std::string(what) + " " + std::to_string(i);
    if (p.face < 0 || p.face >= mesh.face_count())
      throw Error(ErrorCode::InvalidArgument, name + " is on triangle " + std::to_string(p.face) +
          " but the surface has " + std::to_string(mesh.face_count()) + " triangles");
    if (!p.barycentric.allFinite() || (p.barycentric.array() < -1e-9).any() ||
      std::abs(p.barycentric.sum() - 1.0) > 1e-9)
      throw Error(ErrorCode::InvalidArgument, name + " has barycentric coordinates " +
          detail::format_point(p.barycentric.data(), 3) +
          " (they must be finite, >= 0 and sum to 1)");
  }
}

WeightedAverages::WeightedAverages(SurfaceMesh mesh, const Eigen::MatrixXd& E)
  : mesh_(std::make_shared<const SurfaceMesh>(std::move(mesh)))
  , phong_(std::make_shared<const PhongProjection>(*mesh_, E))
  , E_(E)
{
}

Eigen::MatrixXd WeightedAverages::embed(const std::vector<SurfacePoint>& points) const
{
  return surface_point_positions(mesh_->F, E_, points);
}

bool WeightedAverages::forward_local(const double* ybar, Index start, Index max_triangles,
  Workspace& ws, SurfacePoint& out) const
{
  const int D = dimension();
  const PhongProjection& phong = *phong_;
  const SurfaceMesh& mesh = *mesh_;
  // Greedy walk on the edge graph.
  Index v = start;
  double best = squared_distance(phong.vertex(v), ybar, D);
  for (;;)
  {
    Index next = -1;
    for (int i = mesh.ring_offsets[static_cast<std::size_t>(v)]; i < mesh.ring_offsets[static_cast<std::size_t>(v + 1)]; ++i)
    {
      const int u = mesh.ring[static_cast<std::size_t>(i)];
      const double d = squared_distance(phong.vertex(u), ybar, D);
      if (d < best)
      {
        best = d;
        next = u;
      }
    }
    if (next < 0)
      break;
    v = next;
  }
  // Breadth-first search over triangles from v's triangles.
  const int query = ++ws.query;
  ws.queue.clear();
  // v's triangles are tried in order of how far inside them the Euclidean projection of ybar
  // onto their planes falls (the Phong projection is near it), ties by triangle index.
  ws.ring.clear();
  for (int i = mesh.face_offsets[static_cast<std::size_t>(v)]; i < mesh.face_offsets[static_cast<std::size_t>(v + 1)]; ++i)
  {
    const int f = mesh.vertex_faces[static_cast<std::size_t>(i)];
    ws.stamp[static_cast<std::size_t>(f)] = query;
    ws.ring.emplace_back(-phong.euclidean_barycentric(f, ybar).minCoeff(), f);
  }
  std::sort(ws.ring.begin(), ws.ring.end());
  for (const auto& [score, f] : ws.ring)
    ws.queue.push_back(f);
  const Index cap = max_triangles > 0 ? max_triangles : mesh.face_count();
  Eigen::Vector3d xi;
  for (std::size_t head = 0; head < ws.queue.size() && static_cast<Index>(head) < cap; ++head)
  {
    const int f = ws.queue[head];
    ++ws.tried;
    // Newton starts at the Euclidean projection (clamped into the triangle).
    if (phong.project(f, ybar, xi, phong.euclidean_barycentric(f, ybar)))
    {
      out.face = f;
      out.barycentric = xi;
      return true;
    }
    for (int k = 0; k < 3; ++k)
    {
      const int g = mesh.face_neighbors(f, k);
      if (g >= 0 && ws.stamp[static_cast<std::size_t>(g)] != query)
      {
        ws.stamp[static_cast<std::size_t>(g)] = query;
        ws.queue.push_back(g);
      }
    }
  }
  return false;
}

bool WeightedAverages::forward_brute(const double* ybar, Workspace& ws, SurfacePoint& out) const
{
  const int D = dimension();
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d xi;
  for (Index f = 0; f < mesh_->face_count(); ++f)
  {
    ++ws.tried;
    if (!phong_->project(f, ybar, xi))
      continue;
    phong_->position(f, xi, ws.point.data());
    const double d = squared_distance(ws.point.data(), ybar, D);
    if (d < best)
    {
      best = d;
      out.face = f;
      out.barycentric = xi;
    }
  }
  return best < std::numeric_limits<double>::infinity();
}

ForwardResult WeightedAverages::forward(const std::vector<SurfacePoint>& anchors,
  const DenseWeights& W, const ForwardOptions& options, const ProgressCallback& progress) const
{
  if (W.cols() != static_cast<Index>(anchors.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.cols()) +
        " columns but there are " + std::to_string(anchors.size()) + " anchors",
      "give one weight per anchor in every row");
  return forward_rows(anchors, W.rows(),
    [&W](Index q, auto&& visit) {
      for (Index i = 0; i < W.cols(); ++i)
        visit(i, W(q, i));
    },
    false, options, progress, nullptr);
}

ForwardResult WeightedAverages::forward(const std::vector<SurfacePoint>& anchors,
  const SparseWeights& W, const ForwardOptions& options, const ProgressCallback& progress,
  const std::vector<SurfacePoint>* hints) const
{
  if (W.cols() != static_cast<Index>(anchors.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.cols()) +
        " columns but there are " + std::to_string(anchors.size()) + " anchors",
      "give one weight per anchor in every row");
  if (hints && static_cast<Index>(hints->size()) != W.rows())
    throw Error(ErrorCode::SizeMismatch, "there are " + std::to_string(hints->size()) +
        " start hints for " + std::to_string(W.rows()) + " queries");
  return forward_rows(anchors, W.rows(),
    [&W](Index q, auto&& visit) {
      for (SparseWeights::InnerIterator it(W, q); it; ++it)
        visit(it.col(), it.value());
    },
    true, options, progress, hints);
}

template<class Rows>
ForwardResult WeightedAverages::forward_rows(const std::vector<SurfacePoint>& anchors, Index nq,
  Rows&& rows, bool sparse, const ForwardOptions& options, const ProgressCallback& progress,
  const std::vector<SurfacePoint>* hints) const
{
  const auto t0 = std::chrono::steady_clock::now();
  if (anchors.empty())
    throw Error(ErrorCode::EmptyInput, "no anchors: a weighted average needs at least one");
  validate_surface_points(*mesh_, anchors, "anchor");
  validate_forward_options(options);
  for (Index q = 0; q < nq; ++q)
  {
    double sum = 0, magnitude = 0;
    bool finite = true;
    rows(q, [&](Index, double w) {
      finite = finite && std::isfinite(w);
      sum += w;
      magnitude += std::abs(w);
    });
    if (!finite)
      throw Error(ErrorCode::NonFinite, "weights row " + std::to_string(q) + " has a non-finite weight");
    if (!(std::abs(sum - 1.0) <= 1e-9 * std::max(1.0, magnitude)))
      throw Error(ErrorCode::InvalidArgument, "weights row " + std::to_string(q) + " sums to " +
          detail::format_number(sum, 15) + ", not 1", "weights of an average must sum to 1");
  }

  const int D = dimension();
  const RowMatrix Y = embed(anchors);
  std::vector<Index> anchor_corners(anchors.size());
  for (std::size_t i = 0; i < anchors.size(); ++i)
    anchor_corners[i] = nearest_corner(mesh_->F, anchors[i]);
  ForwardResult result;
  result.points.assign(static_cast<std::size_t>(nq), SurfacePoint{});
  result.valid.assign(static_cast<std::size_t>(nq), 0);
  ProgressReporter reporter(progress, std::max<Index>(nq, 1));
  auto make_state = [&] {
    Workspace ws;
    ws.stamp.assign(static_cast<std::size_t>(mesh_->face_count()), 0);
    ws.ybar.resize(D);
    ws.point.resize(D);
    return ws;
  };
  auto body = [&](Workspace& ws, Index begin, Index end) {
    for (Index q = begin; q < end; ++q)
    {
      ws.ybar.setZero();
      rows(q, [&](Index i, double w) {
        if (w != 0.0)
          ws.ybar += w * Y.row(i).transpose();
      });
      SurfacePoint& out = result.points[static_cast<std::size_t>(q)];
      bool ok;
      if (options.search == ForwardOptions::Search::BruteForce)
        ok = forward_brute(ws.ybar.data(), ws, out);
      else
      {
        Index start = -1;
        if (options.warm_start && q > begin && result.valid[static_cast<std::size_t>(q - 1)])
          start = nearest_corner(mesh_->F, result.points[static_cast<std::size_t>(q - 1)]);
        else if (hints && (*hints)[static_cast<std::size_t>(q)].face >= 0)
          start = nearest_corner(mesh_->F, (*hints)[static_cast<std::size_t>(q)]);
        else
        {
          // The anchor nearest to ybar in R^D (among the row's anchors for sparse weights; the
          // paper starts from the heaviest anchor "if a better initial guess is not
          // available": this one is closer, so the walk is shorter).
          double best = std::numeric_limits<double>::infinity();
          auto consider = [&](Index i) {
            const double d = squared_distance(Y.data() + i * D, ws.ybar.data(), D);
            if (d < best)
            {
              best = d;
              start = anchor_corners[static_cast<std::size_t>(i)];
            }
          };
          if (sparse)
            rows(q, [&](Index i, double) { consider(i); });
          else
            for (Index i = 0; i < Y.rows(); ++i)
              consider(i);
        }
        ok = start >= 0 && forward_local(ws.ybar.data(), start, options.max_triangles, ws, out);
      }
      result.valid[static_cast<std::size_t>(q)] = ok ? 1 : 0;
      if (!ok)
        out = SurfacePoint{};
    }
  };
  Index tried = 0;
  detail::parallel_for(nq, kChunk, options.threads, reporter, "the weighted averages", make_state,
    body, [&](Workspace& ws) { tried += ws.tried; });
  result.triangles_tried = tried;
  result.positions.resize(nq, 3);
  for (Index q = 0; q < nq; ++q)
  {
    const SurfacePoint& p = result.points[static_cast<std::size_t>(q)];
    if (!result.valid[static_cast<std::size_t>(q)])
    {
      ++result.failures;
      result.positions.row(q).setConstant(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    result.positions.row(q) = p.barycentric(0) * mesh_->V.row(mesh_->F(p.face, 0)) +
      p.barycentric(1) * mesh_->V.row(mesh_->F(p.face, 1)) +
      p.barycentric(2) * mesh_->V.row(mesh_->F(p.face, 2));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

DenseWeights WeightedAverages::inverse(const std::vector<SurfacePoint>& anchors,
  const std::vector<SurfacePoint>& points, const InverseOptions& options,
  const ProgressCallback& progress) const
{
  if (anchors.empty())
    throw Error(ErrorCode::EmptyInput, "no anchors: weights need at least one");
  validate_surface_points(*mesh_, anchors, "anchor");
  validate_surface_points(*mesh_, points, "point");
  validate_inverse_options(options);
  const int D = dimension();
  const Index n = static_cast<Index>(anchors.size());
  const RowMatrix Y = embed(anchors);
  const double extent2 = (E_.colwise().maxCoeff() - E_.colwise().minCoeff()).squaredNorm();
  const double coincide = 1e-24 * extent2;
  const Index np = static_cast<Index>(points.size());
  DenseWeights W(np, n);
  ProgressReporter reporter(progress, std::max<Index>(np, 1));
  struct State
  {
    std::vector<double> yhat, P, t0, t1, Dii, x;
  };
  auto make_state = [&] {
    State s;
    s.yhat.resize(static_cast<std::size_t>(D));
    s.P.resize(static_cast<std::size_t>(2 * D));
    for (auto* v : { &s.t0, &s.t1, &s.Dii, &s.x })
      v->resize(static_cast<std::size_t>(n));
    return s;
  };
  const double gamma = options.gamma;
  auto body = [&](State& s, Index begin, Index end) {
    double* yhat = s.yhat.data();
    double* P0 = s.P.data();
    double* P1 = P0 + D;
    for (Index q = begin; q < end; ++q)
    {
      const SurfacePoint& p = points[static_cast<std::size_t>(q)];
      phong_->position(p.face, p.barycentric, yhat);
      // Orthonormal basis of the interpolated tangent plane.
      phong_->psi(p.face, p.barycentric, P0);
      double n0 = 0;
      for (int d = 0; d < D; ++d)
        n0 += P0[d] * P0[d];
      n0 = 1.0 / std::sqrt(n0);
      double dot = 0;
      for (int d = 0; d < D; ++d)
      {
        P0[d] *= n0;
        dot += P0[d] * P1[d];
      }
      double n1 = 0;
      for (int d = 0; d < D; ++d)
      {
        P1[d] -= dot * P0[d];
        n1 += P1[d] * P1[d];
      }
      n1 = 1.0 / std::sqrt(n1);
      for (int d = 0; d < D; ++d)
        P1[d] *= n1;
      // D_ii = |v_T|^2 + gamma |v_O|^2 and the tangential coordinates of y_i - yhat.
      double smallest = std::numeric_limits<double>::infinity();
      for (Index i = 0; i < n; ++i)
      {
        const double* y = Y.data() + i * D;
        double a0 = 0, a1 = 0, n2 = 0;
        for (int d = 0; d < D; ++d)
        {
          const double v = y[d] - yhat[d];
          a0 += P0[d] * v;
          a1 += P1[d] * v;
          n2 += v * v;
        }
        const double t2 = a0 * a0 + a1 * a1;
        s.t0[static_cast<std::size_t>(i)] = a0;
        s.t1[static_cast<std::size_t>(i)] = a1;
        const double dii = t2 + gamma * std::max(0.0, n2 - t2);
        s.Dii[static_cast<std::size_t>(i)] = dii;
        smallest = std::min(smallest, dii);
      }
      auto w = W.row(q);
      if (smallest <= coincide)
      {
        // The point is an anchor: interpolation (split evenly among coinciding anchors).
        w.setZero();
        Index count = 0;
        for (Index i = 0; i < n; ++i)
          count += s.Dii[static_cast<std::size_t>(i)] <= coincide;
        for (Index i = 0; i < n; ++i)
          if (s.Dii[static_cast<std::size_t>(i)] <= coincide)
            w(i) = 1.0 / static_cast<double>(count);
        continue;
      }
      // w = D^-2 A^T (A D^-2 A^T)^+ b with A's rows (t0, t1, 1) and b = (0, 0, 1): the
      // tangential constraint written on y_i - yhat (equivalent given sum w = 1, better
      // conditioned). D^-2 is scaled to a largest entry of 1.
      double largest = 0;
      for (Index i = 0; i < n; ++i)
      {
        double& v = s.x[static_cast<std::size_t>(i)];
        const double dii = s.Dii[static_cast<std::size_t>(i)];
        v = 1.0 / (dii * dii);
        largest = std::max(largest, v);
      }
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      for (Index i = 0; i < n; ++i)
      {
        double& v = s.x[static_cast<std::size_t>(i)];
        v /= largest; // now the weights of D^-2
        const double a0 = s.t0[static_cast<std::size_t>(i)], a1 = s.t1[static_cast<std::size_t>(i)];
        M(0, 0) += v * a0 * a0;
        M(0, 1) += v * a0 * a1;
        M(0, 2) += v * a0;
        M(1, 1) += v * a1 * a1;
        M(1, 2) += v * a1;
        M(2, 2) += v;
      }
      M(1, 0) = M(0, 1);
      M(2, 0) = M(0, 2);
      M(2, 1) = M(1, 2);
      const Eigen::Vector3d lambda = solve_constraints(M, [&](const Eigen::Vector3d& l) {
        // residual b - A w for w = D^-2 A^T l
        Eigen::Vector3d r(0, 0, 1);
        for (Index i = 0; i < n; ++i)
        {
          const double a0 = s.t0[static_cast<std::size_t>(i)], a1 = s.t1[static_cast<std::size_t>(i)];
          const double wi = s.x[static_cast<std::size_t>(i)] * (a0 * l(0) + a1 * l(1) + l(2));
          r(0) -= a0 * wi;
          r(1) -= a1 * wi;
          r(2) -= wi;
        }
        return r;
      });
      double sum = 0;
      for (Index i = 0; i < n; ++i)
      {
        const double a0 = s.t0[static_cast<std::size_t>(i)], a1 = s.t1[static_cast<std::size_t>(i)];
        w(i) = s.x[static_cast<std::size_t>(i)] * (a0 * lambda(0) + a1 * lambda(1) + lambda(2));
        sum += w(i);
      }
      // Partition of unity exactly: the tangential constraint sum w_i (y_i - yhat) = 0 is
      // homogeneous, so scaling the row keeps it. It matters where the anchors do not span the
      // tangent plane and the pseudo-inverse satisfies the constraints only in the least-squares
      // sense. A row that sums to (almost) 0 has no such scaling: it falls back to the anchor
      // nearest in the metric of D (the round trip then tells whether the point is reached).
      if (std::abs(sum) > 1e-12)
        w /= sum;
      else
      {
        Index nearest = 0;
        for (Index i = 1; i < n; ++i)
          if (s.Dii[static_cast<std::size_t>(i)] < s.Dii[static_cast<std::size_t>(nearest)])
            nearest = i;
        w.setZero();
        w(nearest) = 1.0;
      }
    }
  };
  detail::parallel_for(np, kChunk, options.threads, reporter, "the inverse weighted averages",
    make_state, body, [](State&) {});
  return W;
}

RoundTrip WeightedAverages::round_trip(const std::vector<SurfacePoint>& anchors,
  const std::vector<SurfacePoint>& points, const DenseWeights& W, double tolerance,
  const ForwardOptions& options, const ProgressCallback& progress) const
{
  if (W.rows() != static_cast<Index>(points.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.rows()) +
        " rows but there are " + std::to_string(points.size()) + " points");
  validate_round_trip_tolerance(tolerance);
  validate_surface_points(*mesh_, points, "point");
  const ForwardResult f = forward(anchors, W, options, progress);
  const Eigen::MatrixXd X = surface_point_positions(mesh_->F, mesh_->V, points);
  RoundTrip r;
  r.error.resize(points.size());
  r.returned.assign(points.size(), 0);
  r.failures = f.failures;
  const double limit = tolerance * mesh_->mean_edge_length;
  std::vector<double> finite;
  for (std::size_t p = 0; p < points.size(); ++p)
  {
    if (!f.valid[p])
    {
      r.error[p] = std::numeric_limits<double>::quiet_NaN();
      ++r.not_returned;
      continue;
    }
    r.error[p] = (f.positions.row(static_cast<Index>(p)) - X.row(static_cast<Index>(p))).norm();
    finite.push_back(r.error[p]);
    r.returned[p] = r.error[p] <= limit ? 1 : 0;
    if (!r.returned[p])
      ++r.not_returned;
  }
  if (!finite.empty())
  {
    r.max_error = *std::max_element(finite.begin(), finite.end());
    std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(finite.size() / 2), finite.end());
    r.median_error = finite[finite.size() / 2];
  }
  return r;
}

} // namespace bary
