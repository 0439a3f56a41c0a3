#include "core/surface/weighted_averages.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"

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
  double s = 0;
  for (int d = 0; d < D; ++d)
  {
    const double t = a[d] - b[d];
    s += t * t;
  }
  return s;
}

/// The corner of a surface point with the largest barycentric coordinate.
int nearest_corner(const Eigen::MatrixXi& F, const SurfacePoint& p)
{
  Index k;
  p.barycentric.maxCoeff(&k);
  return F(p.face, k);
}

} // namespace

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
  for (int i = mesh.face_offsets[static_cast<std::size_t>(v)]; i < mesh.face_offsets[static_cast<std::size_t>(v + 1)]; ++i)
  {
    const int f = mesh.vertex_faces[static_cast<std::size_t>(i)];
    ws.stamp[static_cast<std::size_t>(f)] = query;
    ws.queue.push_back(f);
  }
  const Index cap = max_triangles > 0 ? max_triangles : mesh.face_count();
  Eigen::Vector3d xi;
  for (std::size_t head = 0; head < ws.queue.size() && static_cast<Index>(head) < cap; ++head)
  {
    const int f = ws.queue[head];
    ++ws.tried;
    if (phong.project(f, ybar, xi))
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
  const auto t0 = std::chrono::steady_clock::now();
  if (anchors.empty())
    throw Error(ErrorCode::EmptyInput, "no anchors: a weighted average needs at least one");
  validate_surface_points(*mesh_, anchors, "anchor");
  if (W.cols() != static_cast<Index>(anchors.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.cols()) +
        " columns but there are " + std::to_string(anchors.size()) + " anchors",
      "give one weight per anchor in every row");
  if (options.max_triangles < 0 || options.max_triangles > std::numeric_limits<int>::max())
    throw Error(ErrorCode::InvalidArgument, "the triangle cap must be in [0, 2^31), got " +
        std::to_string(options.max_triangles));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
  for (Index q = 0; q < W.rows(); ++q)
  {
    if (!W.row(q).allFinite())
      throw Error(ErrorCode::NonFinite, "weights row " + std::to_string(q) + " has a non-finite weight");
    const double sum = W.row(q).sum(), magnitude = W.row(q).cwiseAbs().sum();
    if (!(std::abs(sum - 1.0) <= 1e-9 * std::max(1.0, magnitude)))
      throw Error(ErrorCode::InvalidArgument, "weights row " + std::to_string(q) + " sums to " +
          detail::format_number(sum, 15) + ", not 1", "weights of an average must sum to 1");
  }

  const int D = dimension();
  const RowMatrix Y = embed(anchors);
  const Index nq = W.rows();
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
      ws.ybar.noalias() = (W.row(q) * Y).transpose();
      SurfacePoint& out = result.points[static_cast<std::size_t>(q)];
      bool ok;
      if (options.search == ForwardOptions::Search::BruteForce)
        ok = forward_brute(ws.ybar.data(), ws, out);
      else
      {
        Index start;
        if (options.warm_start && q > begin && result.valid[static_cast<std::size_t>(q - 1)])
          start = nearest_corner(mesh_->F, result.points[static_cast<std::size_t>(q - 1)]);
        else
        {
          Index heaviest;
          W.row(q).maxCoeff(&heaviest);
          start = nearest_corner(mesh_->F, anchors[static_cast<std::size_t>(heaviest)]);
        }
        ok = forward_local(ws.ybar.data(), start, options.max_triangles, ws, out);
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
  if (!(options.gamma >= 1.0 && options.gamma <= 1e6))
    throw Error(ErrorCode::InvalidArgument,
      "gamma must be in [1, 1e6], got " + detail::format_number(options.gamma));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
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
    Eigen::VectorXd yhat, Dii, d;
    Eigen::MatrixXd A;
  };
  auto make_state = [&] {
    State s;
    s.yhat.resize(D);
    s.Dii.resize(n);
    s.d.resize(D);
    s.A.resize(3, n);
    return s;
  };
  auto body = [&](State& s, Index begin, Index end) {
    for (Index q = begin; q < end; ++q)
    {
      const SurfacePoint& p = points[static_cast<std::size_t>(q)];
      phong_->position(p.face, p.barycentric, s.yhat.data());
      // Orthonormal basis of the interpolated tangent plane.
      Eigen::MatrixXd P = phong_->psi(p.face, p.barycentric);
      P.row(0).normalize();
      P.row(1) -= P.row(1).dot(P.row(0)) * P.row(0);
      P.row(1).normalize();
      double smallest = std::numeric_limits<double>::infinity();
      for (Index i = 0; i < n; ++i)
      {
        s.d = Y.row(i).transpose() - s.yhat;
        const Eigen::Vector2d t = P * s.d;
        const double n2 = s.d.squaredNorm(), t2 = t.squaredNorm();
        s.Dii(i) = t2 + options.gamma * std::max(0.0, n2 - t2);
        s.A(0, i) = t(0);
        s.A(1, i) = t(1);
        s.A(2, i) = 1.0;
        smallest = std::min(smallest, s.Dii(i));
      }
      auto w = W.row(q);
      if (smallest <= coincide)
      {
        // The point is an anchor: interpolation (split evenly among coinciding anchors).
        w.setZero();
        Index count = 0;
        for (Index i = 0; i < n; ++i)
          if (s.Dii(i) <= coincide)
            ++count;
        for (Index i = 0; i < n; ++i)
          if (s.Dii(i) <= coincide)
            w(i) = 1.0 / static_cast<double>(count);
        continue;
      }
      // w = D^-2 A^T (A D^-2 A^T)^+ b, b = (0, 0, 1): the tangential constraint is written on
      // y_i - yhat, which is equivalent given sum w = 1 and better conditioned.
      const Eigen::ArrayXd inv = s.Dii.array().square().inverse();
      const Eigen::MatrixXd AD = s.A.array().rowwise() * inv.transpose();
      const Eigen::Matrix3d M = AD * s.A.transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
      const Eigen::Vector3d ev = eig.eigenvalues();
      const double cutoff = 1e-12 * ev.cwiseAbs().maxCoeff();
      Eigen::Vector3d lambda = Eigen::Vector3d::Zero();
      const Eigen::Vector3d b(0, 0, 1);
      for (int k = 0; k < 3; ++k)
        if (ev(k) > cutoff)
          lambda += eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(b) / ev(k));
      w = (AD.transpose() * lambda).transpose();
    }
  };
  detail::parallel_for(np, kChunk, options.threads, reporter, "the inverse weighted averages",
    make_state, body, [](State&) {});
  return W;
}

} // namespace bary
