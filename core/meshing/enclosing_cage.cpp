#include "core/meshing/enclosing_cage.h"

#include "core/common/error.h"
#include "core/detail/cgal_cage_oracle.h"
#include "core/detail/closest_point.h"
#include "core/detail/format.h"
#include "core/detail/timing.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <unordered_map>
#include <vector>

namespace bary
{
namespace
{
using detail::Point3d;
using Vec3 = Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

Point3d to_p3(const Vec3& v)
{
  return { v.x(), v.y(), v.z() };
}

void check_input(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const EnclosingCageOptions& o)
{
  if (V.rows() == 0 || F.rows() == 0)
    throw Error(ErrorCode::EmptyInput,
      "enclosing cage: the model has no " + std::string(V.rows() == 0 ? "vertices" : "faces"));
  const Index dim = V.cols();
  if (dim != 2 && dim != 3)
    throw Error(ErrorCode::SizeMismatch,
      "enclosing cage: model vertices have " + std::to_string(dim) + " coordinates, not 2 or 3");
  if (F.cols() != 3 && !(F.cols() == 2 && dim == 2))
    throw Error(ErrorCode::SizeMismatch,
      "enclosing cage: model faces have " + std::to_string(F.cols()) +
        " vertices; expected triangles (3) or, in 2D, segments (2)");
  for (Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite())
      throw Error(ErrorCode::NonFinite, "enclosing cage: model vertex " + std::to_string(i) +
          " is not finite: " + detail::format_row(V, i));
  for (Index f = 0; f < F.rows(); ++f)
    for (Index k = 0; k < F.cols(); ++k)
      if (F(f, k) < 0 || F(f, k) >= V.rows())
        throw Error(ErrorCode::SizeMismatch, "enclosing cage: face " + std::to_string(f) +
            " uses vertex " + std::to_string(F(f, k)) + ", out of range [0, " +
            std::to_string(V.rows()) + ")");
  const Index minimum = dim == 3 ? 4 : 3;
  if (o.target_vertices < minimum)
    throw Error(ErrorCode::InvalidArgument,
      "enclosing cage: target of " + std::to_string(o.target_vertices) +
        " vertices is too small: a " + (dim == 3 ? "closed triangle surface" : "polygon") +
        " needs at least " + std::to_string(minimum));
  if (!(o.margin >= 0.0) || !std::isfinite(o.margin))
    throw Error(ErrorCode::InvalidArgument, "enclosing cage: margin " +
        detail::format_number(o.margin) + " is not a positive distance (0 = automatic)");
  if (!(o.margin_fraction > 0.0 && o.margin_fraction <= 1.0))
    throw Error(ErrorCode::InvalidArgument, "enclosing cage: margin fraction " +
        detail::format_number(o.margin_fraction) + " is not in (0, 1]");
  if (!(o.resolution >= 2.0 && o.resolution <= 64.0))
    throw Error(ErrorCode::InvalidArgument, "enclosing cage: resolution " +
        detail::format_number(o.resolution) + " is not in [2, 64] cells per margin");
  if (o.tighten_rounds < 0 || o.tighten_rounds > 1000)
    throw Error(ErrorCode::InvalidArgument, "enclosing cage: tighten_rounds " +
        std::to_string(o.tighten_rounds) + " is not in [0, 1000]");
  if (!(o.clearance >= 0.0 && o.clearance <= 1.0))
    throw Error(ErrorCode::InvalidArgument, "enclosing cage: clearance " +
        detail::format_number(o.clearance) + " is not in [0, 1] margins");
  if (o.max_grid_nodes < 8)
    throw Error(ErrorCode::InvalidArgument, "enclosing cage: max_grid_nodes must be >= 8");
}

// ---------------------------------------------------------------------------------------------
// Step 1: the outer offset surface.

struct Grid
{
  int dim = 3;
  std::array<Index, 3> n{ 1, 1, 1 };
  Vec3 origin = Vec3::Zero();
  double h = 0.0;
  Index size() const { return n[0] * n[1] * n[2]; }
  Index id(Index i, Index j, Index k) const { return i + n[0] * (j + n[1] * k); }
  Vec3 node(Index id) const
  {
    const Index i = id % n[0], j = (id / n[0]) % n[1], k = id / (n[0] * n[1]);
    return origin + h * Vec3(double(i), double(j), double(k));
  }
};

// Model in 3D coordinates (2D: z = 0).
Eigen::MatrixXd lift(const Eigen::MatrixXd& V)
{
  Eigen::MatrixXd V3 = Eigen::MatrixXd::Zero(V.rows(), 3);
  V3.leftCols(V.cols()) = V;
  return V3;
}

// Signed field on the grid's nodes: > 0 outside, < 0 solid.
std::vector<double> offset_field(const Eigen::MatrixXd& V3, const Eigen::MatrixXi& F,
  const Grid& g, double margin, ProgressReporter& progress)
{
  std::vector<double> d(static_cast<std::size_t>(g.size()), kInf);
  const double reach = margin + g.h;
  for (Index f = 0; f < F.rows(); ++f)
  {
    Vec3 lo = V3.row(F(f, 0)).transpose(), hi = lo;
    for (Index k = 1; k < F.cols(); ++k)
    {
      lo = lo.cwiseMin(V3.row(F(f, k)).transpose());
      hi = hi.cwiseMax(V3.row(F(f, k)).transpose());
    }
    std::array<Index, 3> a{ 0, 0, 0 }, b{ 0, 0, 0 };
    for (int c = 0; c < g.dim; ++c)
    {
      a[c] = std::max<Index>(0, Index(std::floor((lo[c] - reach - g.origin[c]) / g.h)));
      b[c] = std::min<Index>(g.n[c] - 1, Index(std::ceil((hi[c] + reach - g.origin[c]) / g.h)));
    }
    const Vec3 p0 = V3.row(F(f, 0)).transpose(), p1 = V3.row(F(f, 1)).transpose();
    const Vec3 p2 = F.cols() == 3 ? Vec3(V3.row(F(f, 2)).transpose()) : p1;
    for (Index k = a[2]; k <= b[2]; ++k)
      for (Index j = a[1]; j <= b[1]; ++j)
        for (Index i = a[0]; i <= b[0]; ++i)
        {
          const Index id = g.id(i, j, k);
          const Vec3 x = g.node(id);
          double dist;
          if (F.cols() == 3)
            dist = detail::point_triangle_distance(x, p0, p1, p2);
          else
          {
            const double t = detail::closest_on_segment(x, p0, p1);
            dist = (x - (p0 + t * (p1 - p0))).norm();
          }
          double& slot = d[static_cast<std::size_t>(id)];
          slot = std::min(slot, dist);
        }
    if (!progress.step())
      progress.throw_if_cancelled("enclosing cage (distance grid)");
  }
  // Outside: d >= margin and reachable from the border (face neighbours).
  std::vector<char> outside(d.size(), 0);
  std::vector<Index> stack;
  auto seed = [&](Index id) {
    if (!outside[static_cast<std::size_t>(id)] && d[static_cast<std::size_t>(id)] >= margin)
    {
      outside[static_cast<std::size_t>(id)] = 1;
      stack.push_back(id);
    }
  };
  for (Index k = 0; k < g.n[2]; ++k)
    for (Index j = 0; j < g.n[1]; ++j)
      for (Index i = 0; i < g.n[0]; ++i)
        if (i == 0 || j == 0 || i == g.n[0] - 1 || j == g.n[1] - 1 ||
          (g.dim == 3 && (k == 0 || k == g.n[2] - 1)))
          seed(g.id(i, j, k));
  while (!stack.empty())
  {
    const Index id = stack.back();
    stack.pop_back();
    const Index i = id % g.n[0], j = (id / g.n[0]) % g.n[1], k = id / (g.n[0] * g.n[1]);
    if (i > 0) seed(id - 1);
    if (i + 1 < g.n[0]) seed(id + 1);
    if (j > 0) seed(id - g.n[0]);
    if (j + 1 < g.n[1]) seed(id + g.n[0]);
    if (g.dim == 3 && k > 0) seed(id - g.n[0] * g.n[1]);
    if (g.dim == 3 && k + 1 < g.n[2]) seed(id + g.n[0] * g.n[1]);
  }
  std::vector<double> field(d.size());
  for (std::size_t id = 0; id < d.size(); ++id)
    field[id] = outside[id] ? std::clamp(d[id] - margin, 1e-3 * g.h, g.h)
                            : (d[id] < margin ? std::min(d[id] - margin, -1e-3 * g.h) : -g.h);
  return field;
}

// Vertices on grid edges, shared between the cells around an edge.
class EdgeVertices
{
public:
  EdgeVertices(const Grid& g, const std::vector<double>& field) : g_(g), field_(field) {}
  int get(Index a, Index b) // a, b: nodes of opposite signs
  {
    const std::uint64_t key =
      std::uint64_t(std::min(a, b)) * std::uint64_t(g_.size()) + std::uint64_t(std::max(a, b));
    const auto [it, inserted] = ids_.emplace(key, int(points_.size()));
    if (inserted)
    {
      const double fa = field_[static_cast<std::size_t>(a)], fb = field_[static_cast<std::size_t>(b)];
      const double t = std::clamp(fa / (fa - fb), 0.05, 0.95);
      points_.push_back((1.0 - t) * g_.node(a) + t * g_.node(b));
    }
    return it->second;
  }
  const std::vector<Vec3>& points() const { return points_; }

private:
  const Grid& g_;
  const std::vector<double>& field_;
  std::unordered_map<std::uint64_t, int> ids_;
  std::vector<Vec3> points_;
};

// Marching tetrahedra: the outward-oriented boundary of the solid nodes.
void march_3d(const Grid& g, const std::vector<double>& field, std::vector<Vec3>& P,
  std::vector<std::array<int, 3>>& T)
{
  EdgeVertices edges(g, field);
  static const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 },
    { 2, 0, 1 }, { 2, 1, 0 } };
  for (Index k = 0; k + 1 < g.n[2]; ++k)
    for (Index j = 0; j + 1 < g.n[1]; ++j)
      for (Index i = 0; i + 1 < g.n[0]; ++i)
      {
        Index corner[8];
        int solid = 0;
        for (int c = 0; c < 8; ++c)
        {
          corner[c] = g.id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          solid += field[static_cast<std::size_t>(corner[c])] < 0.0;
        }
        if (solid == 0 || solid == 8)
          continue;
        for (const auto& perm : perms)
        {
          const Index tet[4] = { corner[0], corner[1 << perm[0]],
            corner[(1 << perm[0]) | (1 << perm[1])], corner[7] };
          std::vector<Index> in, out;
          for (Index n : tet)
            (field[static_cast<std::size_t>(n)] < 0.0 ? in : out).push_back(n);
          if (in.empty() || out.empty())
            continue;
          std::vector<int> poly;
          if (in.size() == 1 || out.size() == 1)
          {
            const bool loneIn = in.size() == 1;
            const Index lone = loneIn ? in[0] : out[0];
            for (Index other : (loneIn ? out : in))
              poly.push_back(edges.get(lone, other));
          }
          else // a quadrilateral, in cyclic order
            poly = { edges.get(in[0], out[0]), edges.get(in[0], out[1]),
              edges.get(in[1], out[1]), edges.get(in[1], out[0]) };
          const auto& pts = edges.points();
          Vec3 area = Vec3::Zero();
          for (std::size_t a = 0; a < poly.size(); ++a)
            area += pts[poly[a]].cross(pts[poly[(a + 1) % poly.size()]]);
          Vec3 dir = Vec3::Zero();
          for (Index n : out)
            dir += g.node(n) / double(out.size());
          for (Index n : in)
            dir -= g.node(n) / double(in.size());
          if (area.dot(dir) < 0.0)
            std::reverse(poly.begin(), poly.end());
          if (poly.size() == 3)
            T.push_back({ poly[0], poly[1], poly[2] });
          else
          {
            // The shorter diagonal.
            if ((pts[poly[0]] - pts[poly[2]]).squaredNorm() <=
              (pts[poly[1]] - pts[poly[3]]).squaredNorm())
            {
              T.push_back({ poly[0], poly[1], poly[2] });
              T.push_back({ poly[0], poly[2], poly[3] });
            }
            else
            {
              T.push_back({ poly[1], poly[2], poly[3] });
              T.push_back({ poly[1], poly[3], poly[0] });
            }
          }
        }
      }
  P = edges.points();
}

// Marching triangles: the counter-clockwise boundary of the solid nodes, as next[] links.
void march_2d(const Grid& g, const std::vector<double>& field, std::vector<Vec3>& P,
  std::vector<std::array<int, 2>>& S)
{
  EdgeVertices edges(g, field);
  for (Index j = 0; j + 1 < g.n[1]; ++j)
    for (Index i = 0; i + 1 < g.n[0]; ++i)
    {
      const Index c[4] = { g.id(i, j, 0), g.id(i + 1, j, 0), g.id(i, j + 1, 0),
        g.id(i + 1, j + 1, 0) };
      static const int tris[2][3] = { { 0, 1, 3 }, { 0, 3, 2 } };
      for (const auto& tri : tris)
      {
        std::vector<Index> in, out;
        for (int v : tri)
          (field[static_cast<std::size_t>(c[v])] < 0.0 ? in : out).push_back(c[v]);
        if (in.empty() || out.empty())
          continue;
        const bool loneIn = in.size() == 1;
        const Index lone = loneIn ? in[0] : out[0];
        const auto& others = loneIn ? out : in;
        std::array<int, 2> s{ edges.get(lone, others[0]), edges.get(lone, others[1]) };
        const auto& pts = edges.points();
        const Vec3 d = pts[s[1]] - pts[s[0]];
        Vec3 dir = Vec3::Zero();
        for (Index n : out)
          dir += g.node(n) / double(out.size());
        for (Index n : in)
          dir -= g.node(n) / double(in.size());
        // Counter-clockwise: the outward normal (d.y, -d.x) points to the outside nodes.
        if (d.y() * dir.x() - d.x() * dir.y() < 0.0)
          std::swap(s[0], s[1]);
        S.push_back(s);
      }
    }
  P = edges.points();
}

// ---------------------------------------------------------------------------------------------
// Step 2: decimation.

// Uniform grid of boxes (cells clamped to the grid, so far boxes land in border cells).
class BoxGrid
{
public:
  BoxGrid(const Vec3& lo, const Vec3& hi, int dim, double cell)
    : lo_(lo), cell_(cell), dim_(dim)
  {
    for (int c = 0; c < 3; ++c)
      n_[c] = c < dim ? std::max<Index>(1, Index(std::ceil((hi[c] - lo[c]) / cell))) : 1;
    cells_.resize(static_cast<std::size_t>(n_[0] * n_[1] * n_[2]));
  }
  template<class Fn>
  void for_cells(const Vec3& lo, const Vec3& hi, Fn&& fn) const
  {
    Index a[3], b[3];
    for (int c = 0; c < 3; ++c)
    {
      a[c] = c < dim_ ? clampi(Index(std::floor((lo[c] - lo_[c]) / cell_)), c) : 0;
      b[c] = c < dim_ ? clampi(Index(std::floor((hi[c] - lo_[c]) / cell_)), c) : 0;
    }
    for (Index k = a[2]; k <= b[2]; ++k)
      for (Index j = a[1]; j <= b[1]; ++j)
        for (Index i = a[0]; i <= b[0]; ++i)
          fn(static_cast<std::size_t>(i + n_[0] * (j + n_[1] * k)));
  }
  void insert(int id, const Vec3& lo, const Vec3& hi)
  {
    for_cells(lo, hi, [&](std::size_t c) { cells_[c].push_back(id); });
  }
  void erase(int id, const Vec3& lo, const Vec3& hi)
  {
    for_cells(lo, hi, [&](std::size_t c) {
      auto& v = cells_[c];
      v.erase(std::find(v.begin(), v.end(), id));
    });
  }
  const std::vector<int>& cell(std::size_t c) const { return cells_[c]; }

private:
  Index clampi(Index v, int c) const { return std::clamp<Index>(v, 0, n_[c] - 1); }
  Vec3 lo_;
  double cell_;
  int dim_;
  Index n_[3] = { 1, 1, 1 };
  std::vector<std::vector<int>> cells_;
};

struct Candidate
{
  double cost;
  int u, v;
  unsigned su, sv;
  bool operator<(const Candidate& o) const // for a min-queue through std::priority_queue
  {
    if (cost != o.cost)
      return cost > o.cost;
    if (u != o.u)
      return u > o.u;
    return v > o.v;
  }
};

using Quadric = Eigen::Matrix4d;

double quadric_cost(const Quadric& Q, const Vec3& p)
{
  const Eigen::Vector4d x(p.x(), p.y(), p.z(), 1.0);
  return std::max(0.0, x.dot(Q * x));
}

// Positions to try, best first: the quadric's optimum (when well posed and near the edge), the
// midpoint, the ends.
std::vector<std::pair<double, Vec3>> positions(const Quadric& Q, const Vec3& a, const Vec3& b,
  int dim)
{
  std::vector<std::pair<double, Vec3>> out;
  const Vec3 mid = 0.5 * (a + b);
  const double len = (a - b).norm();
  const Eigen::Matrix3d A = Q.topLeftCorner<3, 3>();
  const Vec3 rhs = -Q.topRightCorner<3, 1>();
  if (dim == 3)
  {
    Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
    lu.setThreshold(1e-8);
    if (lu.isInvertible())
    {
      const Vec3 x = lu.solve(rhs);
      if (x.allFinite() && (x - mid).norm() <= len)
        out.emplace_back(quadric_cost(Q, x), x);
    }
  }
  else
  {
    Eigen::FullPivLU<Eigen::Matrix2d> lu(A.topLeftCorner<2, 2>());
    lu.setThreshold(1e-8);
    if (lu.isInvertible())
    {
      const Eigen::Vector2d x2 = lu.solve(rhs.head<2>());
      const Vec3 x(x2.x(), x2.y(), 0.0);
      if (x.allFinite() && (x - mid).norm() <= len)
        out.emplace_back(quadric_cost(Q, x), x);
    }
  }
  out.emplace_back(quadric_cost(Q, mid), mid);
  out.emplace_back(quadric_cost(Q, a), a);
  out.emplace_back(quadric_cost(Q, b), b);
  std::stable_sort(out.begin(), out.end(),
    [](const auto& x, const auto& y) { return x.first < y.first; });
  return out;
}

Quadric plane_quadric(const Vec3& n, const Vec3& p, double weight)
{
  const Eigen::Vector4d q(n.x(), n.y(), n.z(), -n.dot(p));
  return weight * q * q.transpose();
}

double triangle_quality(const Vec3& a, const Vec3& b, const Vec3& c)
{
  const double area2 = (b - a).cross(c - a).norm(); // twice the area
  const double sum = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return sum > 0.0 ? 2.0 * std::sqrt(3.0) * area2 / sum : 0.0; // 1 for equilateral
}

constexpr double kMinQuality = 0.05;
constexpr double kMinNormalCos = 0.2;

class SurfaceDecimator
{
public:
  SurfaceDecimator(std::vector<Vec3> P, const std::vector<std::array<int, 3>>& T,
    const detail::CageModelOracle& oracle, double cell)
    : pos_(std::move(P)), faces_(T), oracle_(oracle), face_alive_(T.size(), 1),
      vertex_alive_(pos_.size(), 1), stamp_(pos_.size(), 0), vf_(pos_.size()),
      Q_(pos_.size(), Quadric::Zero()), grid_(lower(), upper(), 3, cell)
  {
    for (std::size_t f = 0; f < faces_.size(); ++f)
    {
      const auto& t = faces_[f];
      const Vec3 n = (pos_[t[1]] - pos_[t[0]]).cross(pos_[t[2]] - pos_[t[0]]);
      const double area2 = n.norm();
      for (int v : t)
      {
        vf_[v].push_back(int(f));
        if (area2 > 0.0)
          Q_[v] += plane_quadric(n / area2, pos_[t[0]], 0.5 * area2);
      }
      Vec3 lo, hi;
      box(t, lo, hi);
      grid_.insert(int(f), lo, hi);
    }
    alive_ = Index(pos_.size());
  }

  // Collapses until @p target vertices remain or no collapse is valid.
  void run(Index target, ProgressReporter& progress, Index& collapses, Index& rejected)
  {
    std::priority_queue<Candidate> queue;
    for (std::size_t f = 0; f < faces_.size(); ++f)
      for (int k = 0; k < 3; ++k)
      {
        const int a = faces_[f][k], b = faces_[f][(k + 1) % 3];
        if (a < b)
          push(queue, a, b);
      }
    while (alive_ > target && !queue.empty())
    {
      const Candidate c = queue.top();
      queue.pop();
      if (!vertex_alive_[c.u] || !vertex_alive_[c.v] || stamp_[c.u] != c.su ||
        stamp_[c.v] != c.sv)
        continue;
      bool done = false;
      for (const auto& [cost, p] : positions(Q_[c.u] + Q_[c.v], pos_[c.u], pos_[c.v], 3))
        if (try_collapse(c.u, c.v, p))
        {
          done = true;
          break;
        }
        else
          ++rejected;
      if (!done)
        continue; // refused: retried when its neighbourhood changes
      ++collapses;
      // Edges around the changed faces get new costs and another chance.
      std::vector<int> touched = neighbours(c.u);
      touched.push_back(c.u);
      std::sort(touched.begin(), touched.end());
      for (int w : touched)
        ++stamp_[w];
      for (int w : touched)
        for (int x : neighbours(w))
          if (w < x || !std::binary_search(touched.begin(), touched.end(), x))
            push(queue, std::min(w, x), std::max(w, x));
      if (!progress.step())
        progress.throw_if_cancelled("enclosing cage (decimation)");
    }
  }

  Index alive() const { return alive_; }

  // Moves each vertex toward its closest model point, to @p clearance from it, halving the step
  // up to 4 times when a check fails; @p rounds sweeps over the vertices in index order.
  Index tighten(int rounds, double clearance)
  {
    Index moves = 0;
    for (int round = 0; round < rounds; ++round)
    {
      Index moved = 0;
      for (std::size_t v = 0; v < pos_.size(); ++v)
      {
        if (!vertex_alive_[v])
          continue;
        const Point3d c = oracle_.closest_point(to_p3(pos_[v]));
        const Vec3 to = Vec3(c[0], c[1], c[2]) - pos_[v];
        const double d = to.norm();
        if (!(d > 1.01 * clearance))
          continue;
        double step = d - clearance;
        for (int attempt = 0; attempt < 5; ++attempt, step *= 0.5)
          if (try_collapse(int(v), -1, pos_[v] + (step / d) * to))
          {
            ++moved;
            break;
          }
      }
      moves += moved;
      if (moved == 0)
        break;
    }
    return moves;
  }

  Cage cage() const
  {
    std::vector<int> remap(pos_.size(), -1);
    Cage cage;
    cage.V.resize(alive_, 3);
    int n = 0;
    for (std::size_t v = 0; v < pos_.size(); ++v)
      if (vertex_alive_[v])
      {
        remap[v] = n;
        cage.V.row(n++) = pos_[v].transpose();
      }
    Index nf = 0;
    for (char a : face_alive_)
      nf += a;
    cage.F.resize(nf, 3);
    Index r = 0;
    for (std::size_t f = 0; f < faces_.size(); ++f)
      if (face_alive_[f])
      {
        for (int k = 0; k < 3; ++k)
          cage.F(r, k) = remap[faces_[f][k]];
        ++r;
      }
    return cage;
  }

private:
  Vec3 lower() const
  {
    Vec3 lo = Vec3::Constant(kInf);
    for (const Vec3& p : pos_)
      lo = lo.cwiseMin(p);
    return lo;
  }
  Vec3 upper() const
  {
    Vec3 hi = Vec3::Constant(-kInf);
    for (const Vec3& p : pos_)
      hi = hi.cwiseMax(p);
    return hi;
  }
  void box(const std::array<int, 3>& t, Vec3& lo, Vec3& hi) const
  {
    lo = pos_[t[0]].cwiseMin(pos_[t[1]]).cwiseMin(pos_[t[2]]);
    hi = pos_[t[0]].cwiseMax(pos_[t[1]]).cwiseMax(pos_[t[2]]);
  }

  std::vector<int> neighbours(int v) const
  {
    std::vector<int> out;
    for (int f : vf_[v])
      for (int w : faces_[f])
        if (w != v)
          out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  void push(std::priority_queue<Candidate>& queue, int u, int v) const
  {
    const auto best = positions(Q_[u] + Q_[v], pos_[u], pos_[v], 3).front();
    queue.push({ best.first, u, v, stamp_[u], stamp_[v] });
  }

  // Collapses the edge (u, v) into u at p; v < 0: moves u to p. Returns false (and changes
  // nothing) when a check fails.
  bool try_collapse(int u, int v, const Vec3& p)
  {
    std::vector<int> edge_faces, star; // faces with both; all faces of u or v
    for (int f : vf_[u])
    {
      star.push_back(f);
      if (v >= 0 && std::find(faces_[f].begin(), faces_[f].end(), v) != faces_[f].end())
        edge_faces.push_back(f);
    }
    if (v >= 0)
    {
      for (int f : vf_[v])
        if (std::find(faces_[f].begin(), faces_[f].end(), u) == faces_[f].end())
          star.push_back(f);
      // Link condition: the common neighbours of u and v are the two apexes of the edge's faces.
      const std::vector<int> nu = neighbours(u), nv = neighbours(v);
      std::vector<int> common;
      std::set_intersection(
        nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
      if (edge_faces.size() != 2 || common.size() != 2)
        return false;
      if (nu.size() + nv.size() - 4 < 3) // degree of the merged vertex
        return false;
    }
    // The new faces, their shape and orientation.
    std::vector<std::array<int, 3>> fresh;
    double worst_old = 1.0;
    for (int f : star)
    {
      const auto& t = faces_[f];
      worst_old = std::min(worst_old, triangle_quality(pos_[t[0]], pos_[t[1]], pos_[t[2]]));
      if (std::find(edge_faces.begin(), edge_faces.end(), f) != edge_faces.end())
        continue;
      std::array<int, 3> nt = t;
      for (int& w : nt)
        if (w == v)
          w = u;
      auto at = [&](int w) { return w == u ? p : pos_[w]; };
      const Vec3 n_old = (pos_[t[1]] - pos_[t[0]]).cross(pos_[t[2]] - pos_[t[0]]);
      const Vec3 n_new = (at(nt[1]) - at(nt[0])).cross(at(nt[2]) - at(nt[0]));
      const double nn = n_new.norm(), no = n_old.norm();
      if (!(nn > 0.0) || n_new.dot(n_old) < kMinNormalCos * nn * no)
        return false;
      if (triangle_quality(at(nt[0]), at(nt[1]), at(nt[2])) < std::min(kMinQuality, worst_old))
        return false;
      fresh.push_back(nt);
    }
    // The model: no element may meet the cone from p over the old faces.
    std::vector<std::array<Point3d, 3>> bases;
    for (int f : star)
      bases.push_back({ to_p3(pos_[faces_[f][0]]), to_p3(pos_[faces_[f][1]]),
        to_p3(pos_[faces_[f][2]]) });
    if (oracle_.tetrahedra_touch_model(to_p3(p), bases))
      return false;
    // Self-intersections: the new faces against each other and the rest of the cage.
    auto corners = [&](const std::array<int, 3>& t) {
      std::array<Point3d, 3> c;
      for (int k = 0; k < 3; ++k)
        c[k] = to_p3(t[k] == u ? p : pos_[t[k]]);
      return c;
    };
    for (std::size_t a = 0; a < fresh.size(); ++a)
      for (std::size_t b = a + 1; b < fresh.size(); ++b)
        if (detail::triangles_intersect_improperly(corners(fresh[a]), fresh[a], corners(fresh[b]), fresh[b]))
          return false;
    std::sort(star.begin(), star.end());
    std::vector<int> seen;
    for (const auto& nt : fresh)
    {
      const auto cn = corners(nt);
      Vec3 lo(cn[0][0], cn[0][1], cn[0][2]), hi = lo;
      for (int k = 1; k < 3; ++k)
      {
        const Vec3 q(cn[k][0], cn[k][1], cn[k][2]);
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      seen.clear();
      bool hit = false;
      grid_.for_cells(lo, hi, [&](std::size_t cell) {
        if (hit)
          return;
        for (int f : grid_.cell(cell))
        {
          if (std::binary_search(star.begin(), star.end(), f) ||
            std::find(seen.begin(), seen.end(), f) != seen.end())
            continue;
          seen.push_back(f);
          Vec3 flo, fhi;
          box(faces_[f], flo, fhi);
          if ((flo.array() > hi.array()).any() || (fhi.array() < lo.array()).any())
            continue;
          if (detail::triangles_intersect_improperly(cn, nt, corners(faces_[f]), faces_[f]))
          {
            hit = true;
            return;
          }
        }
      });
      if (hit)
        return false;
    }
    // Apply.
    for (int f : star)
    {
      Vec3 lo, hi;
      box(faces_[f], lo, hi);
      grid_.erase(f, lo, hi);
    }
    for (int f : edge_faces)
    {
      face_alive_[f] = 0;
      for (int w : faces_[f])
        if (w != u && w != v)
          vf_[w].erase(std::find(vf_[w].begin(), vf_[w].end(), f));
    }
    pos_[u] = p;
    std::vector<int> uf;
    for (int f : star)
    {
      if (!face_alive_[f])
        continue;
      for (int& w : faces_[f])
        if (w == v)
          w = u;
      uf.push_back(f);
      Vec3 lo, hi;
      box(faces_[f], lo, hi);
      grid_.insert(f, lo, hi);
    }
    vf_[u] = uf;
    if (v >= 0)
    {
      vf_[v].clear();
      vertex_alive_[v] = 0;
      Q_[u] += Q_[v];
      --alive_;
    }
    return true;
  }

  std::vector<Vec3> pos_;
  std::vector<std::array<int, 3>> faces_;
  const detail::CageModelOracle& oracle_;
  std::vector<char> face_alive_, vertex_alive_;
  std::vector<unsigned> stamp_;
  std::vector<std::vector<int>> vf_;
  std::vector<Quadric> Q_;
  BoxGrid grid_;
  Index alive_ = 0;
};

class PolygonDecimator
{
public:
  PolygonDecimator(std::vector<Vec3> P, const std::vector<int>& loop,
    const detail::CageModelOracle& oracle, double cell)
    : pos_(std::move(P)), oracle_(oracle), next_(pos_.size(), -1), prev_(pos_.size(), -1),
      alive_flag_(pos_.size(), 0), stamp_(pos_.size(), 0), Q_(pos_.size(), Quadric::Zero()),
      grid_(lower(loop), upper(loop), 2, cell)
  {
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      next_[a] = b;
      prev_[b] = a;
      alive_flag_[a] = 1;
    }
    for (int a : loop)
    {
      const int b = next_[a];
      const Vec3 d = pos_[b] - pos_[a];
      const double len = d.norm();
      if (len > 0.0)
      {
        const Vec3 n(d.y() / len, -d.x() / len, 0.0);
        const Quadric q = plane_quadric(n, pos_[a], len);
        Q_[a] += q;
        Q_[b] += q;
      }
      insert_edge(a);
    }
    alive_ = Index(loop.size());
    start_ = loop.front();
  }

  void run(Index target, ProgressReporter& progress, Index& collapses, Index& rejected)
  {
    std::priority_queue<Candidate> queue;
    for (std::size_t a = 0; a < pos_.size(); ++a)
      if (alive_flag_[a])
        push(queue, int(a));
    while (alive_ > target && alive_ > 3 && !queue.empty())
    {
      const Candidate c = queue.top();
      queue.pop();
      if (!alive_flag_[c.u] || !alive_flag_[c.v] || next_[c.u] != c.v || stamp_[c.u] != c.su ||
        stamp_[c.v] != c.sv)
        continue;
      bool done = false;
      for (const auto& [cost, p] : positions(Q_[c.u] + Q_[c.v], pos_[c.u], pos_[c.v], 2))
        if (try_collapse(c.u, p))
        {
          done = true;
          break;
        }
        else
          ++rejected;
      if (!done)
        continue;
      ++collapses;
      const int a = prev_[c.u], b = next_[c.u];
      for (int w : { a, c.u, b })
        ++stamp_[w];
      for (int w : { prev_[a], a, c.u, b })
        push(queue, w);
      if (!progress.step())
        progress.throw_if_cancelled("enclosing cage (decimation)");
    }
  }

  Index alive() const { return alive_; }

  // As SurfaceDecimator::tighten.
  Index tighten(int rounds, double clearance)
  {
    Index moves = 0;
    for (int round = 0; round < rounds; ++round)
    {
      Index moved = 0;
      for (std::size_t v = 0; v < pos_.size(); ++v)
      {
        if (!alive_flag_[v])
          continue;
        const Point3d c = oracle_.closest_point(to_p3(pos_[v]));
        const Vec3 to = Vec3(c[0], c[1], 0.0) - pos_[v];
        const double d = to.norm();
        if (!(d > 1.01 * clearance))
          continue;
        double step = d - clearance;
        for (int attempt = 0; attempt < 5; ++attempt, step *= 0.5)
          if (try_collapse(int(v), pos_[v] + (step / d) * to, true))
          {
            ++moved;
            break;
          }
      }
      moves += moved;
      if (moved == 0)
        break;
    }
    return moves;
  }

  Cage cage() const
  {
    Cage cage;
    cage.V.resize(alive_, 2);
    int v = start_;
    for (Index k = 0; k < alive_; ++k, v = next_[v])
      cage.V.row(k) = pos_[v].head<2>().transpose();
    return cage;
  }

private:
  Vec3 lower(const std::vector<int>& loop) const
  {
    Vec3 lo = Vec3::Constant(kInf);
    for (int v : loop)
      lo = lo.cwiseMin(pos_[v]);
    return lo;
  }
  Vec3 upper(const std::vector<int>& loop) const
  {
    Vec3 hi = Vec3::Constant(-kInf);
    for (int v : loop)
      hi = hi.cwiseMax(pos_[v]);
    return hi;
  }
  void edge_box(int a, Vec3& lo, Vec3& hi) const
  {
    lo = pos_[a].cwiseMin(pos_[next_[a]]);
    hi = pos_[a].cwiseMax(pos_[next_[a]]);
  }
  void insert_edge(int a)
  {
    Vec3 lo, hi;
    edge_box(a, lo, hi);
    grid_.insert(a, lo, hi);
  }
  void erase_edge(int a)
  {
    Vec3 lo, hi;
    edge_box(a, lo, hi);
    grid_.erase(a, lo, hi);
  }
  void push(std::priority_queue<Candidate>& queue, int a) const
  {
    const int b = next_[a];
    const auto best = positions(Q_[a] + Q_[b], pos_[a], pos_[b], 2).front();
    queue.push({ best.first, a, b, stamp_[a], stamp_[b] });
  }

  // Collapses the edge (i, next(i)) into i at p; with @p move, moves i to p instead.
  bool try_collapse(int i, const Vec3& p, bool move = false)
  {
    const int j = move ? i : next_[i], a = prev_[i], b = next_[j];
    if (p == pos_[a] || p == pos_[b])
      return false;
    std::vector<std::array<Point3d, 2>> bases = { { to_p3(pos_[a]), to_p3(pos_[i]) },
      { to_p3(pos_[j]), to_p3(pos_[b]) } };
    if (!move)
      bases.push_back({ to_p3(pos_[i]), to_p3(pos_[j]) });
    if (oracle_.triangles_touch_model(to_p3(p), bases))
      return false;
    using S2 = std::array<std::array<double, 2>, 2>;
    auto xy = [](const Vec3& q) { return std::array<double, 2>{ q.x(), q.y() }; };
    const S2 e1{ xy(pos_[a]), xy(p) }, e2{ xy(p), xy(pos_[b]) };
    const std::array<int, 2> i1{ a, i }, i2{ i, b };
    if (detail::segments_intersect_improperly(e1, i1, e2, i2))
      return false;
    for (const auto& [e, ids] : { std::pair(e1, i1), std::pair(e2, i2) })
    {
      Vec3 lo(std::min(e[0][0], e[1][0]), std::min(e[0][1], e[1][1]), 0.0);
      Vec3 hi(std::max(e[0][0], e[1][0]), std::max(e[0][1], e[1][1]), 0.0);
      bool hit = false;
      grid_.for_cells(lo, hi, [&](std::size_t cell) {
        if (hit)
          return;
        for (int k : grid_.cell(cell))
        {
          if (k == a || k == i || k == j)
            continue; // the edges being replaced
          const S2 other{ xy(pos_[k]), xy(pos_[next_[k]]) };
          if (detail::segments_intersect_improperly(e, ids, other, { k, next_[k] }))
          {
            hit = true;
            return;
          }
        }
      });
      if (hit)
        return false;
    }
    if (move)
    {
      erase_edge(a);
      erase_edge(i);
      pos_[i] = p;
      insert_edge(a);
      insert_edge(i);
      return true;
    }
    erase_edge(a);
    erase_edge(i);
    erase_edge(j);
    pos_[i] = p;
    next_[i] = b;
    prev_[b] = i;
    alive_flag_[j] = 0;
    insert_edge(a);
    insert_edge(i);
    Q_[i] += Q_[j];
    if (start_ == j)
      start_ = i;
    --alive_;
    return true;
  }

  std::vector<Vec3> pos_;
  const detail::CageModelOracle& oracle_;
  std::vector<int> next_, prev_;
  std::vector<char> alive_flag_;
  std::vector<unsigned> stamp_;
  std::vector<Quadric> Q_;
  BoxGrid grid_;
  Index alive_ = 0;
  int start_ = 0;
};

// Number of connected components of a triangle set (by shared vertices).
Index components(Index nv, const std::vector<std::array<int, 3>>& T)
{
  std::vector<int> parent(static_cast<std::size_t>(nv));
  for (Index v = 0; v < nv; ++v)
    parent[v] = int(v);
  auto find = [&](int v) {
    while (parent[v] != v)
      v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& t : T)
    for (int k = 1; k < 3; ++k)
      parent[find(t[k])] = find(t[0]);
  Index count = 0;
  for (Index v = 0; v < nv; ++v)
    count += parent[v] == v;
  return count;
}

double model_measure(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
{
  if (V.cols() == 2)
  {
    double area = 0.0;
    if (F.cols() == 3)
    {
      for (Index f = 0; f < F.rows(); ++f)
      {
        const Eigen::Vector2d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
        const Eigen::Vector2d e = b - a, g = c - a;
        area += 0.5 * std::abs(e.x() * g.y() - e.y() * g.x());
      }
      return area;
    }
    for (Index f = 0; f < F.rows(); ++f) // closed polygons: the shoelace formula
      area += V(F(f, 0), 0) * V(F(f, 1), 1) - V(F(f, 1), 0) * V(F(f, 0), 1);
    return 0.5 * std::abs(area);
  }
  // 3D: closed and consistently oriented (each directed edge once, its reverse once).
  std::unordered_map<std::uint64_t, int> directed;
  const auto key = [&](int a, int b) { return std::uint64_t(a) * std::uint64_t(V.rows()) + std::uint64_t(b); };
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      ++directed[key(F(f, k), F(f, (k + 1) % 3))];
  for (const auto& [k, count] : directed)
  {
    const auto a = int(k / std::uint64_t(V.rows())), b = int(k % std::uint64_t(V.rows()));
    const auto r = directed.find(key(b, a));
    if (count != 1 || r == directed.end() || r->second != 1)
      return std::numeric_limits<double>::quiet_NaN();
  }
  double volume = 0.0;
  for (Index f = 0; f < F.rows(); ++f)
  {
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return std::abs(volume);
}

} // namespace

EnclosingCageResult enclosing_cage(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
  const EnclosingCageOptions& options, const ProgressCallback& progress)
{
  const auto start = std::chrono::steady_clock::now();
  check_input(V, F, options);
  const int dim = int(V.cols());
  EnclosingCageResult result;
  const Eigen::MatrixXd V3 = lift(V);
  const Vec3 lo = V3.colwise().minCoeff(), hi = V3.colwise().maxCoeff();
  result.diagonal = (hi - lo).norm();
  if (!(result.diagonal > 0.0))
    throw Error(ErrorCode::InvalidArgument,
      "enclosing cage: the model has no extent (all its vertices coincide)");
  result.margin = options.margin > 0.0 ? options.margin : options.margin_fraction * result.diagonal;
  const double h = result.margin / options.resolution;
  result.cell_size = h;

  Grid g;
  g.dim = dim;
  g.h = h;
  const double pad = result.margin + 2.0 * h;
  g.origin = lo - Vec3::Constant(pad);
  if (dim == 2)
    g.origin.z() = 0.0;
  double nodes = 1.0;
  for (int c = 0; c < dim; ++c)
  {
    const double count = std::ceil((hi[c] - lo[c] + 2.0 * pad) / h) + 1.0;
    nodes *= count;
    g.n[c] = nodes <= double(options.max_grid_nodes) ? Index(count) : 0;
  }
  if (nodes > double(options.max_grid_nodes))
    throw Error(ErrorCode::InvalidArgument,
      "enclosing cage: the distance grid would have " + detail::format_number(nodes, 3) +
        " nodes, more than the limit of " + std::to_string(options.max_grid_nodes),
      "raise the margin (" + detail::format_number(result.margin) +
        ") or lower the resolution (" + detail::format_number(options.resolution) + ")");
  result.grid_nodes = g.size();

  const Index target = options.target_vertices;
  ProgressReporter grid_progress(progress, std::max<Index>(1, F.rows()), 0.0, 0.3);
  const std::vector<double> field = offset_field(V3, F, g, result.margin, grid_progress);
  const detail::CageModelOracle oracle(V3, F);
  const double cell = 2.0 * h;

  std::vector<Vec3> P;
  if (dim == 3)
  {
    std::vector<std::array<int, 3>> T;
    march_3d(g, field, P, T);
    result.offset_vertices = Index(P.size());
    result.offset_faces = Index(T.size());
    const Index parts = components(Index(P.size()), T);
    if (parts != 1)
      throw Error(ErrorCode::InvalidArgument,
        "enclosing cage: the offset surface has " + std::to_string(parts) +
          " components: parts of the model lie farther apart than twice the margin (" +
          detail::format_number(result.margin) + ")",
        "raise the margin");
    // The construction guarantees it; checked exactly all the same.
    for (const auto& t : T)
      if (oracle.tetrahedra_touch_model(to_p3(P[t[0]]), { { to_p3(P[t[0]]), to_p3(P[t[1]]), to_p3(P[t[2]]) } }))
        throw Error(ErrorCode::Internal, "enclosing cage: the offset surface touches the model");
    result.offset_seconds = seconds_since(start);
    SurfaceDecimator decimator(std::move(P), T, oracle, cell);
    ProgressReporter dec_progress(
      progress, std::max<Index>(1, result.offset_vertices - target), 0.3, 1.0);
    decimator.run(target, dec_progress, result.collapses, result.rejected);
    if (options.tighten_rounds > 0)
      result.tighten_moves =
        decimator.tighten(options.tighten_rounds, options.clearance * result.margin);
    result.cage = decimator.cage();
  }
  else
  {
    std::vector<std::array<int, 2>> S;
    march_2d(g, field, P, S);
    result.offset_vertices = Index(P.size());
    result.offset_faces = Index(S.size());
    if (S.empty())
      throw Error(ErrorCode::Internal, "enclosing cage: empty offset curve");
    std::vector<int> next(P.size(), -1);
    for (const auto& s : S)
      next[s[0]] = s[1];
    std::vector<int> loop;
    for (int v = S.front()[0]; loop.empty() || v != S.front()[0]; v = next[v])
    {
      if (v < 0 || loop.size() > S.size())
        throw Error(ErrorCode::Internal, "enclosing cage: the offset polygon is not closed");
      loop.push_back(v);
    }
    if (loop.size() != S.size())
      throw Error(ErrorCode::InvalidArgument,
        "enclosing cage: the offset curve has several components: parts of the model lie "
        "farther apart than twice the margin (" + detail::format_number(result.margin) + ")",
        "raise the margin");
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      if (oracle.triangles_touch_model(to_p3(P[a]), { { to_p3(P[a]), to_p3(P[b]) } }))
        throw Error(ErrorCode::Internal, "enclosing cage: the offset polygon touches the model");
    }
    result.offset_seconds = seconds_since(start);
    PolygonDecimator decimator(std::move(P), loop, oracle, cell);
    ProgressReporter dec_progress(
      progress, std::max<Index>(1, result.offset_vertices - target), 0.3, 1.0);
    decimator.run(target, dec_progress, result.collapses, result.rejected);
    if (options.tighten_rounds > 0)
      result.tighten_moves =
        decimator.tighten(options.tighten_rounds, options.clearance * result.margin);
    result.cage = decimator.cage();
  }
  const Index n = result.cage.num_controls();
  result.reached_target = n <= target;
  result.stop_reason = n <= target
    ? (result.offset_vertices <= target ? "the offset surface already had no more vertices"
                                        : "target reached")
    : "no valid collapse left";
  try
  {
    validate_cage(result.cage);
  }
  catch (const Error& e)
  {
    throw Error(ErrorCode::Internal, "enclosing cage: the generated cage is invalid: " + e.message());
  }
  result.model_measure = model_measure(V, F);
  result.cage_measure = enclosed_measure(result.cage);
  result.measure_ratio = result.cage_measure / result.model_measure;
  double sum = 0.0;
  for (Index v = 0; v < n; ++v)
  {
    Point3d q{ result.cage.V(v, 0), result.cage.V(v, 1), dim == 3 ? result.cage.V(v, 2) : 0.0 };
    const double d = oracle.distance(q);
    result.max_distance = std::max(result.max_distance, d);
    sum += d;
  }
  result.mean_distance = n > 0 ? sum / double(n) : 0.0;
  result.seconds = seconds_since(start);
  return result;
}

} // namespace bary
