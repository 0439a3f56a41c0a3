#include "core/meshing/mesh_point_locator.h"

#include "core/detail/closest_point.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"
#include "core/common/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

namespace bary
{
namespace
{

constexpr int kLeafSize = 4;
// Median splits keep the depth below log2(#T) + 1 (< 32); the stack holds at most depth + 1.
constexpr int kMaxStack = 128;

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x() * b.y() - a.y() * b.x();
}

} // namespace

MeshPointLocator::MeshPointLocator(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, double tolerance)
{
  if (V.cols() != 2 && V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "mesh vertices must have 2 or 3 coordinates, got " + std::to_string(V.cols()));
  dim_ = static_cast<int>(V.cols());
  if (T.rows() == 0 || V.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no elements; mesh the domain first");
  surface_ = dim_ == 3 && T.cols() == 3;
  if (T.cols() != dim_ + 1 && !surface_)
    throw Error(ErrorCode::SizeMismatch,
      "a " + std::to_string(dim_) + "D mesh needs " +
        (dim_ == 2 ? "3 vertices per element (triangles)"
                   : "4 vertices per element (tetrahedra) or 3 (surface triangles)") +
        ", got " + std::to_string(T.cols()));
  if (!(tolerance >= 0.0 && tolerance <= 1e-3))
    throw Error(ErrorCode::InvalidArgument,
      "the locator tolerance must be in [0, 1e-3] (relative to the mesh size), got " +
        std::to_string(tolerance));
  for (Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite())
      throw Error(ErrorCode::NonFinite,
        "mesh vertex " + std::to_string(i) + " has a non-finite coordinate");
  for (Index e = 0; e < T.rows(); ++e)
    for (Index k = 0; k < T.cols(); ++k)
      if (T(e, k) < 0 || T(e, k) >= V.rows())
        throw Error(ErrorCode::InvalidArgument,
          "mesh element " + std::to_string(e) + " refers to vertex " + std::to_string(T(e, k)) +
            " but the mesh has " + std::to_string(V.rows()) + " vertices");
  if (T.rows() > std::numeric_limits<int>::max() / 2)
    throw Error(ErrorCode::InvalidArgument, "the mesh has too many elements for the locator");

  V_ = V;
  T_ = T;
  tol_ = tolerance * (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();

  const Index nt = T.rows();
  box_.resize(nt, 2 * dim_);
  std::vector<double> centroid(static_cast<std::size_t>(nt * dim_));
  for (Index e = 0; e < nt; ++e)
    for (int k = 0; k < dim_; ++k)
    {
      double lo = V_(T_(e, 0), k), hi = lo, sum = 0.0;
      for (int c = 0; c < T_.cols(); ++c)
      {
        const double v = V_(T_(e, c), k);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        sum += v;
      }
      box_(e, k) = lo;
      box_(e, dim_ + k) = hi;
      centroid[static_cast<std::size_t>(e * dim_ + k)] = sum / static_cast<double>(T_.cols());
    }
  order_.resize(static_cast<std::size_t>(nt));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(static_cast<std::size_t>(2 * nt / kLeafSize + 2));
  build(0, static_cast<int>(nt), centroid);
}

int MeshPointLocator::build(int begin, int end, std::vector<double>& centroid)
{
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  for (int k = 0; k < 3; ++k)
  {
    node.lo[k] = std::numeric_limits<double>::infinity();
    node.hi[k] = -std::numeric_limits<double>::infinity();
  }
  double clo[3], chi[3];
  for (int k = 0; k < dim_; ++k)
  {
    clo[k] = std::numeric_limits<double>::infinity();
    chi[k] = -std::numeric_limits<double>::infinity();
  }
  for (int i = begin; i < end; ++i)
  {
    const int e = order_[static_cast<std::size_t>(i)];
    for (int k = 0; k < dim_; ++k)
    {
      node.lo[k] = std::min(node.lo[k], box_(e, k));
      node.hi[k] = std::max(node.hi[k], box_(e, dim_ + k));
      const double c = centroid[static_cast<std::size_t>(e * dim_ + k)];
      clo[k] = std::min(clo[k], c);
      chi[k] = std::max(chi[k], c);
    }
  }
  node.begin = begin;
  node.end = end;
  if (end - begin > kLeafSize)
  {
    int axis = 0;
    for (int k = 1; k < dim_; ++k)
      if (chi[k] - clo[k] > chi[axis] - clo[axis])
        axis = k;
    const int mid = begin + (end - begin) / 2;
    // Ties broken by element index so the tree does not depend on the standard library.
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
      [&](int a, int b) {
        const double ca = centroid[static_cast<std::size_t>(a * dim_ + axis)];
        const double cb = centroid[static_cast<std::size_t>(b * dim_ + axis)];
        return ca < cb || (ca == cb && a < b);
      });
    node.left = build(begin, mid, centroid);
    node.right = build(mid, end, centroid);
  }
  nodes_[static_cast<std::size_t>(id)] = node;
  return id;
}

double MeshPointLocator::box_distance2(const Node& node, const double* x) const
{
  double d2 = 0.0;
  for (int k = 0; k < dim_; ++k)
  {
    const double d = std::max({ node.lo[k] - x[k], x[k] - node.hi[k], 0.0 });
    d2 += d * d;
  }
  return d2;
}

double MeshPointLocator::element_distance(
  Index e, const double* x, Eigen::Vector4d& lambda, bool containment_only) const
{
  lambda.setZero();
  if (dim_ == 2)
  {
    const Eigen::Vector2d p(x[0], x[1]);
    const Eigen::Vector2d v[3] = { V_.row(T_(e, 0)).transpose(), V_.row(T_(e, 1)).transpose(),
      V_.row(T_(e, 2)).transpose() };
    const Eigen::Vector2d e1 = v[1] - v[0], e2 = v[2] - v[0], r = p - v[0];
    const double det = cross2(e1, e2);
    const double scale = std::max({ e1.squaredNorm(), e2.squaredNorm(), (v[2] - v[1]).squaredNorm() });
    if (std::abs(det) > 1e-14 * scale)
    {
      const double l1 = cross2(r, e2) / det, l2 = cross2(e1, r) / det;
      const double l0 = 1.0 - l1 - l2;
      if (l0 >= 0.0 && l1 >= 0.0 && l2 >= 0.0)
      {
        lambda << l0, l1, l2, 0.0;
        return 0.0;
      }
    }
    if (containment_only)
      return std::numeric_limits<double>::infinity();
    // Outside (or degenerate): the closest point lies on an edge.
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k)
    {
      const int k1 = (k + 1) % 3;
      const double t = detail::closest_on_segment(p, v[k], v[k1]);
      const double d = (v[k] + t * (v[k1] - v[k]) - p).norm();
      if (d < best)
      {
        best = d;
        lambda.setZero();
        lambda(k) = 1.0 - t;
        lambda(k1) = t;
      }
    }
    return best;
  }

  const Eigen::Vector3d p(x[0], x[1], x[2]);
  if (surface_)
  {
    // A triangle in space: the closest point (a point counts as on it at distance 0 only when
    // it lies exactly in it, so containment_only never answers).
    if (containment_only)
      return std::numeric_limits<double>::infinity();
    const Eigen::Vector3d a = V_.row(T_(e, 0)).transpose(), b = V_.row(T_(e, 1)).transpose(),
                          c = V_.row(T_(e, 2)).transpose();
    const Eigen::Vector3d l = detail::closest_on_triangle(p, a, b, c);
    lambda << l(0), l(1), l(2), 0.0;
    return (l(0) * a + l(1) * b + l(2) * c - p).norm();
  }
  const Eigen::Vector3d v[4] = { V_.row(T_(e, 0)).transpose(), V_.row(T_(e, 1)).transpose(),
    V_.row(T_(e, 2)).transpose(), V_.row(T_(e, 3)).transpose() };
  const Eigen::Vector3d e1 = v[1] - v[0], e2 = v[2] - v[0], e3 = v[3] - v[0], r = p - v[0];
  const double det = e1.dot(e2.cross(e3));
  double scale = 0.0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      scale = std::max(scale, (v[b] - v[a]).squaredNorm());
  bool check_face[4] = { true, true, true, true };
  if (std::abs(det) > 1e-14 * scale * std::sqrt(scale))
  {
    const double l1 = r.dot(e2.cross(e3)) / det;
    const double l2 = e1.dot(r.cross(e3)) / det;
    const double l3 = e1.dot(e2.cross(r)) / det;
    const double l0 = 1.0 - l1 - l2 - l3;
    if (l0 >= 0.0 && l1 >= 0.0 && l2 >= 0.0 && l3 >= 0.0)
    {
      lambda << l0, l1, l2, l3;
      return 0.0;
    }
    if (containment_only)
      return std::numeric_limits<double>::infinity();
    // The closest point lies on a face whose plane separates p from the tetrahedron.
    const double l[4] = { l0, l1, l2, l3 };
    for (int k = 0; k < 4; ++k)
      check_face[k] = l[k] < 0.0;
  }
  else if (containment_only)
    return std::numeric_limits<double>::infinity();
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) // face opposite vertex k
  {
    if (!check_face[k])
      continue;
    const int a = (k + 1) % 4, b = (k + 2) % 4, c = (k + 3) % 4;
    const Eigen::Vector3d l = detail::closest_on_triangle(p, v[a], v[b], v[c]);
    const double d = (l(0) * v[a] + l(1) * v[b] + l(2) * v[c] - p).norm();
    if (d < best)
    {
      best = d;
      lambda.setZero();
      lambda(a) = l(0);
      lambda(b) = l(1);
      lambda(c) = l(2);
    }
  }
  return best;
}

MeshPointLocator::Location MeshPointLocator::locate(const double* x) const
{
  Location best;
  best.distance = std::numeric_limits<double>::infinity();
  std::array<int, kMaxStack> stack;
  int top = 0;
  Eigen::Vector4d lambda;

  // 1. Containment (cheap barycentric test) in the elements whose boxes contain x: every
  // element at distance 0 is among them, so the smallest such index is the answer. Surface
  // triangles have no interior: they go straight to the nearest search.
  if (!surface_)
    stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
    if (box_distance2(node, x) > 0.0)
      continue;
    if (node.left >= 0)
    {
      stack[top++] = node.right;
      stack[top++] = node.left;
      continue;
    }
    for (int i = node.begin; i < node.end; ++i)
    {
      const int e = order_[static_cast<std::size_t>(i)];
      if ((best.element < 0 || e < best.element) &&
        element_distance(e, x, lambda, true) == 0.0)
      {
        best.distance = 0.0;
        best.element = e;
        best.barycentric = lambda;
      }
    }
  }
  if (best.element >= 0)
  {
    best.inside = true;
    return best;
  }

  // 2. Nearest element: depth-first, nearer child first, pruned by the best distance so far.
  // Boxes as near as the best are still visited so that ties go to the smallest index.
  stack[top++] = 0;
  auto pruned = [&](double box_d2) {
    const double b = best.distance;
    return box_d2 > b * b * (1.0 + 1e-12) + std::numeric_limits<double>::denorm_min();
  };
  while (top > 0)
  {
    const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
    if (pruned(box_distance2(node, x)))
      continue;
    if (node.left < 0)
    {
      for (int i = node.begin; i < node.end; ++i)
      {
        const int e = order_[static_cast<std::size_t>(i)];
        const double d = element_distance(e, x, lambda);
        if (d < best.distance || (d == best.distance && e < best.element))
        {
          best.distance = d;
          best.element = e;
          best.barycentric = lambda;
        }
      }
      continue;
    }
    const Node& l = nodes_[static_cast<std::size_t>(node.left)];
    const Node& r = nodes_[static_cast<std::size_t>(node.right)];
    const double dl = box_distance2(l, x), dr = box_distance2(r, x);
    // Push the farther child first so the nearer one is visited first.
    if (dl <= dr)
    {
      stack[top++] = node.right;
      stack[top++] = node.left;
    }
    else
    {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  best.inside = best.distance <= tol_;
  return best;
}

MeshPointLocator::Result MeshPointLocator::interpolate(const DenseWeights& mesh_weights,
  const Points& P, OutsidePolicy policy, const ProgressCallback& progress) const
{
  if (mesh_weights.rows() != V_.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the mesh weights have " + std::to_string(mesh_weights.rows()) +
        " rows but the mesh has " + std::to_string(V_.rows()) + " vertices");
  if (P.cols() != dim_)
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(P.cols()) + " coordinates but the mesh is " +
        std::to_string(dim_) + "D");
  for (Index p = 0; p < P.rows(); ++p)
    if (!P.row(p).allFinite())
      throw Error(ErrorCode::NonFinite,
        "point " + std::to_string(p) + " has a non-finite coordinate");

  const Index np = P.rows(), nc = mesh_weights.cols();
  Result result;
  result.W.resize(np, nc);
  std::vector<double> distance(static_cast<std::size_t>(np), 0.0);
  std::vector<char> outside(static_cast<std::size_t>(np), 0);
  const RowMatrixXd X = P;

  // Small chunks in parallel (detail/parallel_for.h); each point's row is written by one thread.
  ProgressReporter reporter(progress, np);
  constexpr Index chunk = 64;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  detail::parallel_for(np, chunk, 0, reporter, "interpolation on the mesh", [&](Index begin, Index end) {
    for (Index p = begin; p < end; ++p)
    {
      const Location loc = locate(X.row(p).data());
      const auto sp = static_cast<std::size_t>(p);
      distance[sp] = loc.distance;
      outside[sp] = loc.inside ? 0 : 1;
      if (!loc.inside && policy != OutsidePolicy::Nearest)
      {
        result.W.row(p).setConstant(nan);
        continue;
      }
      result.W.row(p).setZero();
      for (int k = 0; k < T_.cols(); ++k)
        if (loc.barycentric(k) != 0.0)
          result.W.row(p) += loc.barycentric(k) * mesh_weights.row(T_(loc.element, k));
    }
  });

  for (Index p = 0; p < np; ++p)
    if (outside[static_cast<std::size_t>(p)])
    {
      result.outside.push_back(p);
      result.outside_distance.push_back(distance[static_cast<std::size_t>(p)]);
    }
  if (policy == OutsidePolicy::Error && !result.outside.empty())
  {
    const Index first = result.outside.front();
    std::ostringstream s;
    s.precision(6);
    s << result.outside.size() << " of " << np << " points lie outside the mesh (farther than "
      << tol_ << " from it); the first is point " << first << " at "
      << detail::format_point(X.row(first).data(), dim_, 17) << ", at distance "
      << result.outside_distance.front();
    throw Error(ErrorCode::PointsOutside, s.str(),
      "choose the outside policy OutsidePolicy::Nearest to clamp them to the mesh or "
      "OutsidePolicy::NaN to mark them");
  }
  return result;
}

} // namespace bary
