#include "core/detail/cgal_cage_oracle.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace bary::detail
{
namespace
{
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = Kernel::Point_3;
using P2 = Kernel::Point_2;
using Triangle3 = Kernel::Triangle_3;
using Segment3 = Kernel::Segment_3;
using Segment2 = Kernel::Segment_2;
using Tetrahedron3 = Kernel::Tetrahedron_3;
using TriangleIt = std::vector<Triangle3>::const_iterator;
using SegmentIt = std::vector<Segment3>::const_iterator;
using TriangleTree =
  CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, TriangleIt>>>;
using SegmentTree =
  CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_segment_primitive<Kernel, SegmentIt>>>;

P3 point(const Point3d& p)
{
  return P3(p[0], p[1], p[2]);
}
} // namespace

struct CageModelOracle::Impl
{
  std::vector<Triangle3> triangles;
  std::vector<Segment3> segments;
  TriangleTree triangle_tree;
  SegmentTree segment_tree;
};

CageModelOracle::CageModelOracle(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
  : impl_(std::make_unique<Impl>())
{
  auto at = [&](int i) { return P3(V(i, 0), V(i, 1), V(i, 2)); };
  if (F.cols() == 3)
  {
    impl_->triangles.reserve(static_cast<std::size_t>(F.rows()));
    for (Eigen::Index f = 0; f < F.rows(); ++f)
    {
      const P3 a = at(F(f, 0)), b = at(F(f, 1)), c = at(F(f, 2));
      if (!CGAL::collinear(a, b, c))
        impl_->triangles.emplace_back(a, b, c);
      else // a degenerate model triangle: its sides
        for (int k = 0; k < 3; ++k)
        {
          const P3 p = at(F(f, k)), q = at(F(f, (k + 1) % 3));
          if (p != q)
            impl_->segments.emplace_back(p, q);
        }
    }
  }
  else
    for (Eigen::Index f = 0; f < F.rows(); ++f)
    {
      const P3 p = at(F(f, 0)), q = at(F(f, 1));
      if (p != q)
        impl_->segments.emplace_back(p, q);
    }
  // Degenerate model triangles (rare) are kept exactly as their sides, in the segment tree.
  impl_->triangle_tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->segment_tree.insert(impl_->segments.begin(), impl_->segments.end());
  if (!impl_->triangles.empty())
  {
    impl_->triangle_tree.build();
    impl_->triangle_tree.accelerate_distance_queries();
  }
  if (!impl_->segments.empty())
  {
    impl_->segment_tree.build();
    impl_->segment_tree.accelerate_distance_queries();
  }
}

CageModelOracle::~CageModelOracle() = default;

namespace
{
template<class Impl, class Query>
bool touches_any(const Impl& impl, const Query& q)
{
  if (!impl.triangles.empty() && impl.triangle_tree.do_intersect(q))
    return true;
  return !impl.segments.empty() && impl.segment_tree.do_intersect(q);
}
} // namespace

bool CageModelOracle::tetrahedra_touch_model(
  const Point3d& apex, const std::vector<std::array<Point3d, 3>>& bases) const
{
  const Impl& m = *impl_;
  const P3 p = point(apex);
  auto triangle = [&](const P3& a, const P3& b, const P3& c) {
    if (!CGAL::collinear(a, b, c))
      return touches_any(m, Triangle3(a, b, c));
    for (const auto& [s, t] : { std::pair(a, b), std::pair(b, c), std::pair(c, a) })
      if (s != t && touches_any(m, Segment3(s, t)))
        return true;
    return (a == b && b == c) && touches_any(m, a);
  };
  for (const auto& base : bases)
  {
    const P3 a = point(base[0]), b = point(base[1]), c = point(base[2]);
    if (CGAL::orientation(p, a, b, c) != CGAL::COPLANAR)
    {
      if (touches_any(m, Tetrahedron3(p, a, b, c)))
        return true;
    }
    else if (triangle(a, b, c) || triangle(p, a, b) || triangle(p, b, c) || triangle(p, c, a))
      return true;
  }
  return false;
}

bool CageModelOracle::triangles_touch_model(
  const Point3d& apex, const std::vector<std::array<Point3d, 2>>& bases) const
{
  const Impl& m = *impl_;
  const P3 p = point(apex);
  for (const auto& base : bases)
  {
    const P3 a = point(base[0]), b = point(base[1]);
    if (!CGAL::collinear(p, a, b))
    {
      if (touches_any(m, Triangle3(p, a, b)))
        return true;
      continue;
    }
    for (const auto& [s, t] : { std::pair(p, a), std::pair(a, b), std::pair(b, p) })
      if (s != t && touches_any(m, Segment3(s, t)))
        return true;
    if (p == a && a == b && touches_any(m, p))
      return true;
  }
  return false;
}

double CageModelOracle::distance(const Point3d& q) const
{
  const Impl& m = *impl_;
  const P3 p = point(q);
  double d2 = std::numeric_limits<double>::infinity();
  if (!m.triangles.empty())
    d2 = std::min(d2, CGAL::to_double(m.triangle_tree.squared_distance(p)));
  if (!m.segments.empty())
    d2 = std::min(d2, CGAL::to_double(m.segment_tree.squared_distance(p)));
  return std::sqrt(d2);
}

Point3d CageModelOracle::closest_point(const Point3d& q) const
{
  const Impl& m = *impl_;
  const P3 p = point(q);
  P3 best = p;
  double d2 = std::numeric_limits<double>::infinity();
  if (!m.triangles.empty())
  {
    best = m.triangle_tree.closest_point(p);
    d2 = CGAL::to_double(CGAL::squared_distance(p, best));
  }
  if (!m.segments.empty())
  {
    const P3 c = m.segment_tree.closest_point(p);
    if (CGAL::to_double(CGAL::squared_distance(p, c)) < d2)
      best = c;
  }
  return { CGAL::to_double(best.x()), CGAL::to_double(best.y()), CGAL::to_double(best.z()) };
}

bool triangles_intersect_improperly(const std::array<Point3d, 3>& A, const std::array<int, 3>& ia,
  const std::array<Point3d, 3>& B, const std::array<int, 3>& ib)
{
  // Which vertices are shared: sa[k] = the position in B of A's vertex k, or -1.
  std::array<int, 3> sa{ -1, -1, -1 };
  int shared = 0;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l)
      if (ia[k] == ib[l])
      {
        sa[k] = l;
        ++shared;
      }
  const Triangle3 ta(point(A[0]), point(A[1]), point(A[2]));
  const Triangle3 tb(point(B[0]), point(B[1]), point(B[2]));
  if (shared == 0)
    return CGAL::do_intersect(ta, tb);
  if (shared >= 3)
    return true;
  if (shared == 1)
  {
    int k = 0;
    while (sa[k] < 0)
      ++k;
    const int l = sa[k];
    const Segment3 oppositeA(point(A[(k + 1) % 3]), point(A[(k + 2) % 3]));
    const Segment3 oppositeB(point(B[(l + 1) % 3]), point(B[(l + 2) % 3]));
    return CGAL::do_intersect(oppositeA, tb) || CGAL::do_intersect(oppositeB, ta);
  }
  // An edge (p, q) shared; r and s the other vertices.
  int r = 0;
  while (sa[r] >= 0)
    ++r;
  int s = 0;
  while (s == sa[(r + 1) % 3] || s == sa[(r + 2) % 3])
    ++s;
  const P3 p = point(A[(r + 1) % 3]), q = point(A[(r + 2) % 3]);
  const P3 pr = point(A[r]), ps = point(B[s]);
  if (CGAL::orientation(p, q, pr, ps) != CGAL::COPLANAR)
    return false;
  return CGAL::coplanar_orientation(p, q, pr, ps) == CGAL::POSITIVE;
}

bool segments_intersect_improperly(const std::array<std::array<double, 2>, 2>& A,
  const std::array<int, 2>& ia, const std::array<std::array<double, 2>, 2>& B,
  const std::array<int, 2>& ib)
{
  const P2 a0(A[0][0], A[0][1]), a1(A[1][0], A[1][1]);
  const P2 b0(B[0][0], B[0][1]), b1(B[1][0], B[1][1]);
  const bool s00 = ia[0] == ib[0], s01 = ia[0] == ib[1], s10 = ia[1] == ib[0],
             s11 = ia[1] == ib[1];
  const int shared = int(s00 || s01) + int(s10 || s11);
  if (shared == 0)
    return CGAL::do_intersect(Segment2(a0, a1), Segment2(b0, b1));
  if (shared == 2)
    return true;
  // One shared end p; the other ends a and b: improper when one lies on the other's segment.
  const P2 p = (s00 || s01) ? a0 : a1;
  const P2 a = (s00 || s01) ? a1 : a0;
  const P2 b = (s00 || s10) ? b1 : b0;
  return Segment2(p, a).has_on(b) || Segment2(p, b).has_on(a);
}

} // namespace bary::detail
