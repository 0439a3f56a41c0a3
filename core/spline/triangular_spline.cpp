#include "core/spline/triangular_spline.h"

#include "core/common/error.h"
#include "core/detail/exact_elimination.h"
#include "core/detail/format.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <string>

namespace bary
{

const char* to_string(ControlPointType type) noexcept
{
  switch (type)
  {
    case ControlPointType::Corner:
      return "corner";
    case ControlPointType::EdgeCorner:
      return "edge corner";
    case ControlPointType::Edge:
      return "edge";
    case ControlPointType::InnerCorner:
      return "inner corner";
    case ControlPointType::InnerEdge:
      return "inner edge";
    case ControlPointType::Interior:
      return "interior";
  }
  return "?";
}

namespace
{

double signed_area(const Eigen::MatrixXd& V, int a, int b, int c)
{
  return 0.5 * ((V(b, 0) - V(a, 0)) * (V(c, 1) - V(a, 1)) -
    (V(c, 0) - V(a, 0)) * (V(b, 1) - V(a, 1)));
}

ControlPointType classify(int d, int i, int j, int k)
{
  if (i == d || j == d || k == d)
    return ControlPointType::Corner;
  if ((i == 0 && (j == 1 || k == 1)) || (j == 0 && (i == 1 || k == 1)) ||
    (k == 0 && (i == 1 || j == 1)))
    return ControlPointType::EdgeCorner;
  if (i == 0 || j == 0 || k == 0)
    return ControlPointType::Edge;
  if ((i == 1 && j == 1) || (i == 1 && k == 1) || (j == 1 && k == 1))
    return ControlPointType::InnerCorner;
  if (i == 1 || j == 1 || k == 1)
    return ControlPointType::InnerEdge;
  return ControlPointType::Interior;
}

std::string tri_text(const Eigen::MatrixXi& T, Index t)
{
  return "triangle " + std::to_string(t) + " (" + std::to_string(T(t, 0)) + ", " +
    std::to_string(T(t, 1)) + ", " + std::to_string(T(t, 2)) + ")";
}

} // namespace

SplineNet::SplineNet(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, int degree)
  : d_(degree)
{
  if (degree < kMinSplineDegree || degree > kMaxSplineDegree)
    throw Error(ErrorCode::InvalidArgument,
      "spline degree " + std::to_string(degree) + " is out of range [" +
        std::to_string(kMinSplineDegree) + ", " + std::to_string(kMaxSplineDegree) + "]",
      "C1 splines on a triangulation can be edited locally from degree 5 on");
  if (T.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the spline's domain has no triangle");
  if (T.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "the spline's domain triangles have " + std::to_string(T.cols()) + " columns, not 3");
  if (V.cols() != 2 && V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "the spline's domain vertices have " + std::to_string(V.cols()) + " columns, not 2");
  for (Index v = 0; v < V.rows(); ++v)
  {
    if (!V.row(v).allFinite())
      throw Error(ErrorCode::NonFinite,
        "domain vertex " + std::to_string(v) + " has a non-finite coordinate");
    if (V.cols() == 3 && V(v, 2) != 0.0)
      throw Error(ErrorCode::InvalidArgument,
        "domain vertex " + std::to_string(v) + " has z = " + detail::format_number(V(v, 2)) +
          "; a spline's domain is planar (z = 0)");
  }
  V_ = V.leftCols(2);
  T_ = T;
  const Index nv = V_.rows(), nt = T_.rows();
  for (Index t = 0; t < nt; ++t)
    for (int c = 0; c < 3; ++c)
      if (T_(t, c) < 0 || T_(t, c) >= nv)
        throw Error(ErrorCode::InvalidArgument,
          tri_text(T_, t) + " names vertex " + std::to_string(T_(t, c)) + ", out of range [0, " +
            std::to_string(nv - 1) + "]");

  // Degenerate triangles and orientation.
  const double diag2 = (V_.colwise().maxCoeff() - V_.colwise().minCoeff()).squaredNorm();
  Index ccw = 0, cw = 0, first_ccw = -1, first_cw = -1;
  for (Index t = 0; t < nt; ++t)
  {
    const double a = signed_area(V_, T_(t, 0), T_(t, 1), T_(t, 2));
    if (!(std::abs(a) > 1e-12 * diag2))
      throw Error(ErrorCode::InvalidCage,
        tri_text(T_, t) + " of the spline's domain is degenerate (area " +
          detail::format_number(a) + ")");
    if (a > 0)
    {
      if (first_ccw < 0)
        first_ccw = t;
      ++ccw;
    }
    else
    {
      if (first_cw < 0)
        first_cw = t;
      ++cw;
    }
  }
  if (ccw > 0 && cw > 0)
    throw Error(ErrorCode::InvalidCage,
      tri_text(T_, first_cw) + " of the spline's domain is clockwise and " +
        tri_text(T_, first_ccw) + " counter-clockwise",
      "orient all triangles the same way");
  if (cw > 0)
  {
    T_.col(1).swap(T_.col(2));
    reversed_ = true;
  }

  // Edges: directed half-edges a -> b of each triangle.
  std::map<std::pair<int, int>, std::array<Index, 2>> edge_map; // (min, max) -> (left, right)
  std::vector<char> used(static_cast<size_t>(nv), 0);
  for (Index t = 0; t < nt; ++t)
    for (int c = 0; c < 3; ++c)
    {
      const int a = T_(t, c), b = T_(t, (c + 1) % 3);
      used[static_cast<size_t>(a)] = 1;
      if (a == b)
        throw Error(ErrorCode::InvalidCage, tri_text(T_, t) + " repeats a vertex");
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = edge_map.emplace(key, std::array<Index, 2>{ -1, -1 }).first;
      const int side = a < b ? 0 : 1; // 0: the triangle has min -> max (on its left)
      if (it->second[side] >= 0)
        throw Error(ErrorCode::InvalidCage,
          "edge (" + std::to_string(key.first) + ", " + std::to_string(key.second) +
            ") of the spline's domain is in " + tri_text(T_, it->second[side]) + " and " +
            tri_text(T_, t) +
            " on the same side: the triangles overlap, or the edge is in more than two triangles");
      it->second[side] = t;
    }
  for (Index v = 0; v < nv; ++v)
    if (!used[static_cast<size_t>(v)])
      throw Error(ErrorCode::InvalidCage,
        "vertex " + std::to_string(v) + " of the spline's domain is in no triangle");
  const Index ne = static_cast<Index>(edge_map.size());
  E_.resize(ne, 2);
  ET_.resize(ne, 2);
  {
    Index e = 0;
    for (const auto& [key, tris] : edge_map)
    {
      E_(e, 0) = key.first;
      E_(e, 1) = key.second;
      ET_(e, 0) = static_cast<int>(tris[0]);
      ET_(e, 1) = static_cast<int>(tris[1]);
      ++e;
    }
  }
  // Edge lookups: (key, index) sorted.
  std::vector<std::pair<std::pair<int, int>, Index>> edge_sorted;
  edge_sorted.reserve(static_cast<size_t>(ne));
  for (Index e = 0; e < ne; ++e)
    edge_sorted.push_back({ { E_(e, 0), E_(e, 1) }, e });
  auto find_edge = [&](int a, int b) -> Index {
    const std::pair<int, int> key{ std::min(a, b), std::max(a, b) };
    const auto it = std::lower_bound(edge_sorted.begin(), edge_sorted.end(),
      std::make_pair(key, Index(-1)));
    return it->second;
  };

  // Vertex fans: around v, each triangle (v, a, b) (CCW) links a -> b; one chain (boundary) or
  // one cycle turning once (interior).
  {
    std::vector<std::vector<std::pair<int, int>>> links(static_cast<size_t>(nv));
    for (Index t = 0; t < nt; ++t)
      for (int c = 0; c < 3; ++c)
        links[static_cast<size_t>(T_(t, c))].push_back({ T_(t, (c + 1) % 3), T_(t, (c + 2) % 3) });
    for (Index v = 0; v < nv; ++v)
    {
      auto& L = links[static_cast<size_t>(v)];
      std::map<int, int> next;
      std::map<int, int> in_count;
      for (auto [a, b] : L)
      {
        next[a] = b;
        in_count[b]++;
      }
      int start = L.front().first;
      int starts = 0;
      for (auto [a, b] : L)
        if (!in_count.count(a))
        {
          start = a;
          ++starts;
        }
      size_t visited = 0;
      int cur = start;
      double angle = 0;
      while (next.count(cur) && visited <= L.size())
      {
        const int nxt = next[cur];
        const Eigen::Vector2d p = V_.row(cur) - V_.row(v), q = V_.row(nxt) - V_.row(v);
        angle += std::atan2(p.x() * q.y() - p.y() * q.x(), p.dot(q));
        ++visited;
        cur = nxt;
        if (cur == start)
          break;
      }
      if (starts > 1 || visited != L.size())
        throw Error(ErrorCode::InvalidCage,
          "vertex " + std::to_string(v) +
            " of the spline's domain is not manifold: its triangles do not form one fan");
      if (starts == 0 && std::abs(angle - 2 * M_PI) > 1e-6)
        throw Error(ErrorCode::InvalidCage,
          "the triangles around vertex " + std::to_string(v) + " of the spline's domain turn " +
            detail::format_number(angle / (2 * M_PI)) + " times around it: the domain folds there");
    }
  }

  // Mean edge length.
  double total = 0;
  for (Index e = 0; e < ne; ++e)
    total += (V_.row(E_(e, 0)) - V_.row(E_(e, 1))).norm();
  h_ = total / static_cast<double>(ne);

  // Global numbering.
  const int d = d_;
  const Index per_edge = d - 1, per_tri = (d - 1) * (d - 2) / 2;
  const Index edge_base = nv, tri_base = nv + ne * per_edge;
  n_ = tri_base + nt * per_tri;
  L2G_.resize(nt, bezier_count(d));
  type_.assign(static_cast<size_t>(n_), ControlPointType::Interior);
  near_vertex_.assign(static_cast<size_t>(n_), -1);
  tri_of_.assign(static_cast<size_t>(n_), -1);
  nominal_.resize(n_, 2);
  for (Index t = 0; t < nt; ++t)
  {
    const int tv[3] = { T_(t, 0), T_(t, 1), T_(t, 2) };
    Index interior = 0;
    for (int i = 0; i <= d; ++i)
      for (int j = 0; j <= d - i; ++j)
      {
        const int k = d - i - j;
        const int w[3] = { i, j, k };
        Index g = -1;
        int near = -1;
        int zeros = (i == 0) + (j == 0) + (k == 0);
        if (zeros == 2)
        {
          const int c = i == d ? 0 : (j == d ? 1 : 2);
          g = tv[c];
          near = tv[c];
        }
        else if (zeros == 1)
        {
          const int z = i == 0 ? 0 : (j == 0 ? 1 : 2);
          const int ca = (z + 1) % 3, cb = (z + 2) % 3;
          const int a = tv[ca], b = tv[cb];
          const Index e = find_edge(a, b);
          const int step = E_(e, 0) == a ? w[cb] : w[ca]; // steps from the edge's first vertex
          g = edge_base + e * per_edge + (step - 1);
          if (w[cb] == 1 || w[cb] == 2)
            near = a;
          else if (w[ca] == 1 || w[ca] == 2)
            near = b;
        }
        else
        {
          g = tri_base + t * per_tri + interior++;
          if ((i == 1) + (j == 1) + (k == 1) >= 2)
            near = i > 1 ? tv[0] : (j > 1 ? tv[1] : tv[2]);
        }
        L2G_(t, bezier_index(d, i, j)) = static_cast<int>(g);
        const size_t gs = static_cast<size_t>(g);
        type_[gs] = classify(d, i, j, k);
        near_vertex_[gs] = near;
        if (tri_of_[gs] < 0)
          tri_of_[gs] = t;
        nominal_.row(g) = (i * V_.row(tv[0]) + j * V_.row(tv[1]) + k * V_.row(tv[2])) / d;
      }
  }
  for (Index v = 0; v < nv; ++v)
    nominal_.row(v) = V_.row(v); // exact at the vertices

  // The quadrilateral conditions on interior edges.
  auto global_in = [&](Index t, std::initializer_list<std::pair<int, int>> weights) -> Index {
    int w[3] = { 0, 0, 0 };
    for (auto [vertex, weight] : weights)
      for (int c = 0; c < 3; ++c)
        if (T_(t, c) == vertex)
          w[c] = weight;
    return L2G_(t, bezier_index(d, w[0], w[1]));
  };
  auto third = [&](Index t, int a, int b) {
    for (int c = 0; c < 3; ++c)
      if (T_(t, c) != a && T_(t, c) != b)
        return T_(t, c);
    return -1;
  };
  for (Index e = 0; e < ne; ++e)
  {
    const Index u = ET_(e, 0), v = ET_(e, 1);
    if (u < 0 || v < 0)
      continue;
    const int P = E_(e, 0), Q = E_(e, 1);
    const int u0 = third(u, P, Q), v0 = third(v, P, Q);
    // The betas exactly, then rounded (the same numbers the exact elimination uses).
    auto xy = [&](int w) { return std::array<double, 2>{ V_(w, 0), V_(w, 1) }; };
    const auto beta = detail::exact_barycentric({ xy(u0), xy(P), xy(Q), xy(v0) });
    const double b0 = beta[0], b1 = beta[1], b2 = beta[2];
    for (int t = 0; t < d; ++t)
    {
      const int j = d - 1 - t, k = t;
      QuadCondition c;
      c.point = { global_in(v, { { v0, 1 }, { P, j }, { Q, k } }),
        global_in(u, { { u0, 1 }, { P, j }, { Q, k } }),
        global_in(u, { { P, j + 1 }, { Q, k } }), global_in(u, { { P, j }, { Q, k + 1 } }) };
      c.coefficient = { -1.0, b0, b1, b2 };
      c.edge = e;
      c.t = t;
      c.vertex = { u0, P, Q, v0 };
      conditions_.push_back(c);
    }
  }

  // CSR: point -> conditions.
  {
    std::vector<Index> count(static_cast<size_t>(n_) + 1, 0);
    for (const auto& c : conditions_)
      for (Index p : c.point)
        ++count[static_cast<size_t>(p) + 1];
    for (size_t i = 1; i < count.size(); ++i)
      count[i] += count[i - 1];
    cond_offset_ = count;
    cond_index_.resize(static_cast<size_t>(count.back()));
    std::vector<Index> fill(count.begin(), count.end() - 1);
    for (size_t ci = 0; ci < conditions_.size(); ++ci)
      for (Index p : conditions_[ci].point)
        cond_index_[static_cast<size_t>(fill[static_cast<size_t>(p)]++)] = static_cast<Index>(ci);
  }
  // CSR: net neighbours (edges of every local net, deduplicated).
  {
    std::vector<std::pair<Index, Index>> pairs;
    for (Index t = 0; t < nt; ++t)
      for (int i = 0; i <= d; ++i)
        for (int j = 0; j <= d - i; ++j)
        {
          const Index g = L2G_(t, bezier_index(d, i, j));
          if (i > 0)
          {
            pairs.push_back({ g, L2G_(t, bezier_index(d, i - 1, j + 1)) });
            pairs.push_back({ g, L2G_(t, bezier_index(d, i - 1, j)) });
          }
          if (j > 0)
            pairs.push_back({ g, L2G_(t, bezier_index(d, i, j - 1)) });
        }
    std::vector<std::pair<Index, Index>> both;
    both.reserve(pairs.size() * 2);
    for (auto [a, b] : pairs)
    {
      both.push_back({ a, b });
      both.push_back({ b, a });
    }
    std::sort(both.begin(), both.end());
    both.erase(std::unique(both.begin(), both.end()), both.end());
    nb_offset_.assign(static_cast<size_t>(n_) + 1, 0);
    for (auto [a, b] : both)
      ++nb_offset_[static_cast<size_t>(a) + 1];
    for (size_t i = 1; i < nb_offset_.size(); ++i)
      nb_offset_[i] += nb_offset_[i - 1];
    nb_index_.resize(both.size());
    for (size_t i = 0; i < both.size(); ++i)
      nb_index_[i] = both[i].second;
  }

  // CSR: vertex -> the points near it.
  block_offset_.assign(static_cast<size_t>(nv) + 1, 0);
  for (Index p = 0; p < n_; ++p)
    if (near_vertex_[static_cast<size_t>(p)] >= 0)
      ++block_offset_[static_cast<size_t>(near_vertex_[static_cast<size_t>(p)]) + 1];
  for (size_t i = 1; i < block_offset_.size(); ++i)
    block_offset_[i] += block_offset_[i - 1];
  block_index_.resize(static_cast<size_t>(block_offset_.back()));
  {
    std::vector<Index> fill(block_offset_.begin(), block_offset_.end() - 1);
    for (Index p = 0; p < n_; ++p)
      if (near_vertex_[static_cast<size_t>(p)] >= 0)
        block_index_[static_cast<size_t>(fill[static_cast<size_t>(near_vertex_[static_cast<size_t>(p)])]++)] = p;
  }

  locator_ = std::make_shared<MeshPointLocator>(V_, T_, 1e-10);
}

std::vector<Index> SplineNet::vertex_block(int v) const
{
  const size_t s = static_cast<size_t>(v);
  return std::vector<Index>(block_index_.begin() + block_offset_[s],
    block_index_.begin() + block_offset_[s + 1]);
}

std::vector<Index> SplineNet::conditions_of(Index p) const
{
  const size_t s = static_cast<size_t>(p);
  return std::vector<Index>(cond_index_.begin() + cond_offset_[s],
    cond_index_.begin() + cond_offset_[s + 1]);
}

std::vector<Index> SplineNet::net_neighbours(Index p) const
{
  const size_t s = static_cast<size_t>(p);
  return std::vector<Index>(nb_index_.begin() + nb_offset_[s],
    nb_index_.begin() + nb_offset_[s + 1]);
}

std::vector<int> SplineNet::net_distances(const std::vector<Index>& sources, int max_distance) const
{
  std::vector<int> dist(static_cast<size_t>(n_), -1);
  std::queue<Index> q;
  for (Index s : sources)
    if (dist[static_cast<size_t>(s)] < 0)
    {
      dist[static_cast<size_t>(s)] = 0;
      q.push(s);
    }
  while (!q.empty())
  {
    const Index p = q.front();
    q.pop();
    const int dp = dist[static_cast<size_t>(p)];
    if (dp >= max_distance)
      continue;
    for (Index k = nb_offset_[static_cast<size_t>(p)]; k < nb_offset_[static_cast<size_t>(p) + 1];
         ++k)
    {
      const Index r = nb_index_[static_cast<size_t>(k)];
      if (dist[static_cast<size_t>(r)] < 0)
      {
        dist[static_cast<size_t>(r)] = dp + 1;
        q.push(r);
      }
    }
  }
  return dist;
}

Eigen::Vector3d SplineNet::barycentric(Index t, const Eigen::Vector2d& x) const
{
  const int a = T_(t, 0), b = T_(t, 1), c = T_(t, 2);
  const Eigen::Vector2d pa = V_.row(a), pb = V_.row(b), pc = V_.row(c);
  const double A = (pb - pa).x() * (pc - pa).y() - (pc - pa).x() * (pb - pa).y();
  const double l1 = ((x - pa).x() * (pc - pa).y() - (pc - pa).x() * (x - pa).y()) / A;
  const double l2 = ((pb - pa).x() * (x - pa).y() - (x - pa).x() * (pb - pa).y()) / A;
  return { 1.0 - l1 - l2, l1, l2 };
}

// ---------------------------------------------------------------------------------------------

TriangularSpline::TriangularSpline(std::shared_ptr<const SplineNet> net, Eigen::MatrixXd values)
  : net_(std::move(net))
  , values_(std::move(values))
{
  if (!net_)
    throw Error(ErrorCode::InvalidArgument, "a spline needs a control net");
  if (values_.rows() != net_->num_points() || values_.cols() < 1)
    throw Error(ErrorCode::SizeMismatch,
      "a spline of degree " + std::to_string(net_->degree()) + " on this domain has " +
        std::to_string(net_->num_points()) + " control points; " +
        std::to_string(values_.rows()) + " by " + std::to_string(values_.cols()) +
        " values were given");
  for (Index p = 0; p < values_.rows(); ++p)
    if (!values_.row(p).allFinite())
      throw Error(ErrorCode::NonFinite,
        "control point " + std::to_string(p) + " of the spline has a non-finite value");
}

TriangularSpline TriangularSpline::identity(std::shared_ptr<const SplineNet> net)
{
  Eigen::MatrixXd values = net->nominal();
  return TriangularSpline(std::move(net), std::move(values));
}

TriangularSpline TriangularSpline::constant(std::shared_ptr<const SplineNet> net, double value)
{
  const Index n = net->num_points();
  return TriangularSpline(std::move(net), Eigen::MatrixXd::Constant(n, 1, value));
}

Eigen::MatrixXd TriangularSpline::piece(Index t) const
{
  const int n = bezier_count(net_->degree());
  Eigen::MatrixXd C(n, values_.cols());
  for (int r = 0; r < n; ++r)
    C.row(r) = values_.row(net_->local_to_global()(t, r));
  return C;
}

Eigen::RowVectorXd TriangularSpline::evaluate(Index t, const Eigen::Vector3d& b) const
{
  return bezier_evaluate(piece(t), net_->degree(), b);
}

namespace
{

/// Barycentric directions of the domain's x and y axes in triangle t.
std::pair<Eigen::Vector3d, Eigen::Vector3d> axis_directions(const SplineNet& net, Index t)
{
  const auto& V = net.vertices();
  const auto& T = net.triangles();
  Eigen::Matrix2d M;
  M.col(0) = (V.row(T(t, 1)) - V.row(T(t, 0))).transpose();
  M.col(1) = (V.row(T(t, 2)) - V.row(T(t, 0))).transpose();
  const Eigen::Matrix2d Mi = M.inverse();
  const Eigen::Vector2d ux = Mi.col(0), uy = Mi.col(1);
  return { Eigen::Vector3d(-ux.sum(), ux[0], ux[1]), Eigen::Vector3d(-uy.sum(), uy[0], uy[1]) };
}

} // namespace

Eigen::MatrixXd TriangularSpline::jacobian(Index t, const Eigen::Vector3d& b) const
{
  const int d = net_->degree();
  const Eigen::MatrixXd C = piece(t);
  const auto [ux, uy] = axis_directions(*net_, t);
  Eigen::MatrixXd J(values_.cols(), 2);
  J.col(0) = bezier_evaluate(bezier_derivative(C, d, ux), d - 1, b).transpose();
  J.col(1) = bezier_evaluate(bezier_derivative(C, d, uy), d - 1, b).transpose();
  return J;
}

TriangularSpline::Locations TriangularSpline::locate(const Points& P, OutsidePolicy policy) const
{
  if (P.cols() < 2)
    throw Error(ErrorCode::SizeMismatch,
      "points to deform have " + std::to_string(P.cols()) + " columns, need x and y");
  const Index np = P.rows();
  for (Index p = 0; p < np; ++p)
    if (!P.row(p).allFinite())
      throw Error(ErrorCode::NonFinite, "point " + std::to_string(p) + " is not finite");
  Locations out;
  out.triangle.assign(static_cast<size_t>(np), -1);
  out.barycentric.assign(static_cast<size_t>(np), Eigen::Vector3d::Zero());
  std::vector<char> outside(static_cast<size_t>(np), 0);
  const MeshPointLocator& loc = net_->locator();
#pragma omp parallel for schedule(static)
  for (Index p = 0; p < np; ++p)
  {
    const double x[2] = { P(p, 0), P(p, 1) };
    const auto l = loc.locate(x);
    const size_t s = static_cast<size_t>(p);
    outside[s] = !l.inside;
    if (l.inside || policy == OutsidePolicy::Nearest)
    {
      out.triangle[s] = l.element;
      out.barycentric[s] = l.barycentric.head<3>();
    }
  }
  for (Index p = 0; p < np; ++p)
    if (outside[static_cast<size_t>(p)])
      out.outside.push_back(p);
  if (!out.outside.empty() && policy == OutsidePolicy::Error)
  {
    const Index p = out.outside.front();
    throw Error(ErrorCode::PointsOutside,
      std::to_string(out.outside.size()) + " of " + std::to_string(np) +
        " points lie outside the spline's domain, the first is point " + std::to_string(p) +
        " at " + detail::format_row(P, p),
      "enlarge the domain triangulation so that it covers the model");
  }
  return out;
}

Eigen::MatrixXd TriangularSpline::evaluate(const Locations& where) const
{
  const int d = net_->degree();
  const int nb = bezier_count(d);
  const Index np = static_cast<Index>(where.triangle.size());
  const int m = dimension();
  const Index nt = net_->num_triangles();
  Eigen::MatrixXd out(np, m);
  // Each triangle's coefficients in one contiguous block (component-major), and the basis'
  // multinomials and exponents in row order: per point, the powers of the barycentric
  // coordinates and one pass over the block.
  const auto& L2G = net_->local_to_global();
  std::vector<double> blocks(static_cast<size_t>(nt * nb * m));
  for (Index t = 0; t < nt; ++t)
    for (int c = 0; c < m; ++c)
      for (int r = 0; r < nb; ++r)
        blocks[static_cast<size_t>((t * m + c) * nb + r)] = values_(L2G(t, r), c);
  std::vector<double> mult(static_cast<size_t>(nb));
  std::vector<std::array<int, 3>> expo = bezier_multi_indices(d);
  {
    const Eigen::Vector3d unit(1, 1, 1);
    bernstein_basis(d, unit, mult.data()); // d!/(i!j!k!) times 1
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
#pragma omp parallel for schedule(static)
  for (Index p = 0; p < np; ++p)
  {
    const Index t = where.triangle[static_cast<size_t>(p)];
    if (t < 0)
    {
      for (int c = 0; c < m; ++c)
        out(p, c) = nan;
      continue;
    }
    const Eigen::Vector3d& b = where.barycentric[static_cast<size_t>(p)];
    double pw[3][kMaxSplineDegree + 1];
    for (int k = 0; k < 3; ++k)
    {
      pw[k][0] = 1.0;
      for (int e = 1; e <= d; ++e)
        pw[k][e] = pw[k][e - 1] * b[k];
    }
    double basis[bezier_count(kMaxSplineDegree)];
    for (int r = 0; r < nb; ++r)
    {
      const auto& x = expo[static_cast<size_t>(r)];
      basis[r] = mult[static_cast<size_t>(r)] * pw[0][x[0]] * pw[1][x[1]] * pw[2][x[2]];
    }
    const double* block = blocks.data() + t * m * nb;
    for (int c = 0; c < m; ++c)
    {
      double sum = 0;
      for (int r = 0; r < nb; ++r)
        sum += basis[r] * block[c * nb + r];
      out(p, c) = sum;
    }
  }
  return out;
}

ContinuityReport TriangularSpline::continuity() const
{
  ContinuityReport rep;
  const auto& conds = net_->conditions();
  rep.conditions = static_cast<Index>(conds.size());
  for (const auto& c : conds)
  {
    Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(values_.cols());
    for (int k = 0; k < 4; ++k)
      r += c.coefficient[static_cast<size_t>(k)] * values_.row(c.point[static_cast<size_t>(k)]);
    rep.max_condition_residual = std::max(rep.max_condition_residual, r.cwiseAbs().maxCoeff());
  }
  const int d = net_->degree();
  const auto& E = net_->edges();
  const auto& ET = net_->edge_triangles();
  const auto& V = net_->vertices();
  for (Index e = 0; e < E.rows(); ++e)
  {
    if (ET(e, 0) < 0 || ET(e, 1) < 0)
      continue;
    for (int s = 0; s <= d; ++s)
    {
      const Eigen::Vector2d x =
        V.row(E(e, 0)).transpose() + (double(s) / d) * (V.row(E(e, 1)) - V.row(E(e, 0))).transpose();
      const Eigen::MatrixXd Ju = jacobian(ET(e, 0), net_->barycentric(ET(e, 0), x));
      const Eigen::MatrixXd Jv = jacobian(ET(e, 1), net_->barycentric(ET(e, 1), x));
      rep.max_gradient_jump = std::max(rep.max_gradient_jump, (Ju - Jv).norm());
    }
  }
  return rep;
}

namespace
{

struct JacobianSearch
{
  int degree; // of the determinant
  int max_depth;
  double min_value = std::numeric_limits<double>::infinity();
  Eigen::Vector2d min_point = Eigen::Vector2d::Zero();
  bool folded = false;
  bool undecided = false;
  Eigen::Vector2d fold_point = Eigen::Vector2d::Zero();

  /// J: coefficients over the sub-triangle with domain corners P[0..2].
  void visit(const Eigen::MatrixXd& J, const std::array<Eigen::Vector2d, 3>& P, int depth)
  {
    const int m = degree;
    const double corner[3] = { J(bezier_index(m, m, 0), 0), J(bezier_index(m, 0, m), 0),
      J(bezier_index(m, 0, 0), 0) };
    for (int c = 0; c < 3; ++c)
    {
      if (corner[c] < min_value)
      {
        min_value = corner[c];
        min_point = P[static_cast<size_t>(c)];
      }
      if (corner[c] <= 0 && !folded)
      {
        folded = true;
        fold_point = P[static_cast<size_t>(c)];
      }
    }
    if (folded)
      return;
    if (J.minCoeff() > 0)
      return;
    if (depth >= max_depth)
    {
      undecided = true;
      return;
    }
    const Eigen::Vector3d a(1, 0, 0), b(0, 1, 0), c(0, 0, 1);
    const Eigen::Vector3d ab = (a + b) / 2, bc = (b + c) / 2, ca = (c + a) / 2;
    const Eigen::Vector2d pab = (P[0] + P[1]) / 2, pbc = (P[1] + P[2]) / 2, pca = (P[2] + P[0]) / 2;
    visit(bezier_subtriangle(J, m, a, ab, ca), { P[0], pab, pca }, depth + 1);
    if (folded)
      return;
    visit(bezier_subtriangle(J, m, ab, b, bc), { pab, P[1], pbc }, depth + 1);
    if (folded)
      return;
    visit(bezier_subtriangle(J, m, ca, bc, c), { pca, pbc, P[2] }, depth + 1);
    if (folded)
      return;
    visit(bezier_subtriangle(J, m, ab, bc, ca), { pab, pbc, pca }, depth + 1);
  }
};

} // namespace

JacobianReport TriangularSpline::check_jacobian(int max_depth) const
{
  if (dimension() != 2)
    throw Error(ErrorCode::InvalidArgument,
      "the Jacobian test needs a deformation of the plane (2 values per control point), not " +
        std::to_string(dimension()));
  if (max_depth < 0 || max_depth > 12)
    throw Error(ErrorCode::InvalidArgument,
      "Jacobian subdivision depth " + std::to_string(max_depth) + " is out of range [0, 12]");
  const int d = net_->degree();
  const Index nt = net_->num_triangles();
  const auto& V = net_->vertices();
  const auto& T = net_->triangles();
  JacobianReport rep;
  rep.min_jacobian = std::numeric_limits<double>::infinity();
  rep.lower_bound = std::numeric_limits<double>::infinity();
  std::vector<char> status(static_cast<size_t>(nt), 0); // 0 positive, 1 folded, 2 undecided
  std::vector<double> tmin(static_cast<size_t>(nt)), tlow(static_cast<size_t>(nt));
  std::vector<Eigen::Vector2d> tpoint(static_cast<size_t>(nt)), tfold(static_cast<size_t>(nt));
#pragma omp parallel for schedule(dynamic, 8)
  for (Index t = 0; t < nt; ++t)
  {
    const Eigen::MatrixXd C = piece(t);
    const Eigen::MatrixXd Da = bezier_derivative(C, d, Eigen::Vector3d(-1, 1, 0));
    const Eigen::MatrixXd Db = bezier_derivative(C, d, Eigen::Vector3d(-1, 0, 1));
    const Eigen::Vector2d p0 = V.row(T(t, 0)), p1 = V.row(T(t, 1)), p2 = V.row(T(t, 2));
    const Eigen::Vector2d e1 = p1 - p0, e2 = p2 - p0;
    const double twice_area = e1.x() * e2.y() - e1.y() * e2.x();
    Eigen::MatrixXd J = (bezier_product(Da.col(0), d - 1, Db.col(1), d - 1) -
                          bezier_product(Da.col(1), d - 1, Db.col(0), d - 1)) /
      twice_area;
    JacobianSearch search{ 2 * (d - 1), max_depth };
    search.visit(J, { p0, p1, p2 }, 0);
    const size_t s = static_cast<size_t>(t);
    status[s] = search.folded ? 1 : (search.undecided ? 2 : 0);
    tmin[s] = search.min_value;
    tpoint[s] = search.min_point;
    tfold[s] = search.fold_point;
    tlow[s] = J.minCoeff();
  }
  for (Index t = 0; t < nt; ++t)
  {
    const size_t s = static_cast<size_t>(t);
    if (tmin[s] < rep.min_jacobian)
    {
      rep.min_jacobian = tmin[s];
      rep.min_point = tpoint[s];
    }
    rep.lower_bound = std::min(rep.lower_bound, tlow[s]);
    if (status[s] == 0)
      ++rep.positive;
    else if (status[s] == 1)
    {
      rep.folded.push_back(t);
      rep.fold_points.push_back(tfold[s]);
    }
    else
      rep.undecided.push_back(t);
  }
  return rep;
}

TriangularSpline TriangularSpline::elevated() const
{
  const int d = net_->degree();
  auto net = std::make_shared<SplineNet>(net_->vertices(), net_->triangles(), d + 1);
  Eigen::MatrixXd values(net->num_points(), values_.cols());
  const auto& L2G = net->local_to_global();
  for (Index t = 0; t < net_->num_triangles(); ++t)
  {
    const Eigen::MatrixXd C = bezier_elevate(piece(t), d);
    for (int r = 0; r < C.rows(); ++r)
      values.row(L2G(t, r)) = C.row(r);
  }
  return TriangularSpline(std::move(net), std::move(values));
}

TriangularSpline::Locations edge_sample_locations(const SplineNet& net, int samples)
{
  if (samples < 1)
    throw Error(ErrorCode::InvalidArgument,
      "edge samples " + std::to_string(samples) + " is below 1");
  TriangularSpline::Locations where;
  const Eigen::MatrixXi& E = net.edges();
  const Eigen::MatrixXi& ET = net.edge_triangles();
  const Eigen::MatrixXi& T = net.triangles();
  where.triangle.reserve(static_cast<size_t>(E.rows() * (samples + 1)));
  where.barycentric.reserve(static_cast<size_t>(E.rows() * (samples + 1)));
  for (Index e = 0; e < E.rows(); ++e)
  {
    const Index t = ET(e, 0) >= 0 ? ET(e, 0) : ET(e, 1);
    int a = 0, b = 0;
    for (int k = 0; k < 3; ++k)
    {
      if (T(t, k) == E(e, 0))
        a = k;
      if (T(t, k) == E(e, 1))
        b = k;
    }
    for (int s = 0; s <= samples; ++s)
    {
      Eigen::Vector3d bc = Eigen::Vector3d::Zero();
      const double u = static_cast<double>(s) / samples;
      bc[a] = 1.0 - u;
      bc[b] = u;
      where.triangle.push_back(t);
      where.barycentric.push_back(bc);
    }
  }
  return where;
}

} // namespace bary
