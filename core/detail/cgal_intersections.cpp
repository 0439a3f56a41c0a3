#include "core/detail/cgal_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <iterator>

namespace bary::detail
{
namespace
{
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Segment2 = Kernel::Segment_2;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
namespace PMP = CGAL::Polygon_mesh_processing;
} // namespace

std::vector<std::pair<Index, Index>> polygon_self_intersections(
  const Eigen::MatrixXd& V, std::size_t max_pairs)
{
  const Index n = V.rows();
  std::vector<Segment2> edges;
  edges.reserve(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1) % n;
    edges.emplace_back(Point2(V(i, 0), V(i, 1)), Point2(V(j, 0), V(j, 1)));
  }
  // Sweep over x-intervals: sort edges by their left end, test only overlapping intervals.
  std::vector<Index> order(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
    order[static_cast<std::size_t>(i)] = i;
  auto xmin = [&](Index i) { return std::min(edges[i].source().x(), edges[i].target().x()); };
  auto xmax = [&](Index i) { return std::max(edges[i].source().x(), edges[i].target().x()); };
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return xmin(a) < xmin(b); });

  std::vector<std::pair<Index, Index>> pairs;
  for (std::size_t a = 0; a < order.size() && pairs.size() < max_pairs; ++a)
  {
    const Index i = order[a];
    for (std::size_t b = a + 1; b < order.size() && pairs.size() < max_pairs; ++b)
    {
      const Index j = order[b];
      if (xmin(j) > xmax(i))
        break;
      const Index lo = std::min(i, j), hi = std::max(i, j);
      const bool adjacent = (hi == lo + 1) || (lo == 0 && hi == n - 1);
      if (!adjacent)
      {
        if (CGAL::do_intersect(edges[lo], edges[hi]))
          pairs.emplace_back(lo, hi);
        continue;
      }
      // Adjacent edges share one vertex; they are bad only if they overlap beyond it, i.e. they
      // are collinear and fold back onto each other.
      const Segment2& e0 = edges[lo];
      const Segment2& e1 = edges[hi];
      const Point2 shared = (hi == lo + 1) ? e0.target() : e0.source();
      const Point2 p = (hi == lo + 1) ? e0.source() : e0.target();
      const Point2 q = (hi == lo + 1) ? e1.target() : e1.source();
      if (CGAL::collinear(p, shared, q) && !CGAL::collinear_are_strictly_ordered_along_line(p, shared, q))
        pairs.emplace_back(lo, hi);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<std::pair<Index, Index>> triangle_mesh_self_intersections(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, std::size_t max_pairs)
{
  std::vector<Point3> points;
  points.reserve(static_cast<std::size_t>(V.rows()));
  for (Index i = 0; i < V.rows(); ++i)
    points.emplace_back(V(i, 0), V(i, 1), V(i, 2));
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(static_cast<std::size_t>(F.rows()));
  for (Index f = 0; f < F.rows(); ++f)
    faces.push_back({ static_cast<std::size_t>(F(f, 0)), static_cast<std::size_t>(F(f, 1)),
      static_cast<std::size_t>(F(f, 2)) });

  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  // Surface_mesh keeps the soup's face order, so face descriptors map back to rows of F.
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> found;
  PMP::self_intersections(mesh, std::back_inserter(found));
  std::vector<std::pair<Index, Index>> pairs;
  for (const auto& [a, b] : found)
  {
    const Index i = static_cast<Index>(a.idx()), j = static_cast<Index>(b.idx());
    pairs.emplace_back(std::min(i, j), std::max(i, j));
  }
  std::sort(pairs.begin(), pairs.end());
  if (pairs.size() > max_pairs)
    pairs.resize(max_pairs);
  return pairs;
}

} // namespace bary::detail
