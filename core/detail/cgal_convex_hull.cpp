#include "core/detail/cgal_convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>

#include <iterator>
#include <map>

namespace bary::detail
{
namespace
{
using HullKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
}

std::vector<int> convex_hull_2d(const std::vector<std::array<double, 2>>& points)
{
  using P2 = HullKernel::Point_2;
  std::vector<P2> pts;
  std::map<std::array<double, 2>, int> where;
  pts.reserve(points.size());
  for (std::size_t j = 0; j < points.size(); ++j)
  {
    pts.emplace_back(points[j][0], points[j][1]);
    where.emplace(points[j], static_cast<int>(j));
  }
  std::vector<P2> hull;
  CGAL::convex_hull_2(pts.begin(), pts.end(), std::back_inserter(hull)); // counterclockwise
  std::vector<int> ids;
  ids.reserve(hull.size());
  for (const P2& p : hull)
    ids.push_back(where.at({ p.x(), p.y() }));
  return ids;
}

std::vector<std::array<int, 3>> convex_hull_3d(const std::vector<std::array<double, 3>>& points)
{
  using P3 = HullKernel::Point_3;
  std::vector<P3> pts;
  std::map<std::array<double, 3>, int> where;
  pts.reserve(points.size());
  for (std::size_t j = 0; j < points.size(); ++j)
  {
    pts.emplace_back(points[j][0], points[j][1], points[j][2]);
    where.emplace(points[j], static_cast<int>(j));
  }
  CGAL::Surface_mesh<P3> hull;
  CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
  std::vector<std::array<int, 3>> faces;
  faces.reserve(hull.number_of_faces());
  for (auto f : hull.faces())
  {
    std::array<int, 3> t{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull))
    {
      const P3& p = hull.point(v);
      if (c < 3)
        t[static_cast<std::size_t>(c)] = where.at({ p.x(), p.y(), p.z() });
      ++c;
    }
    faces.push_back(t);
  }
  return faces;
}

} // namespace bary::detail
