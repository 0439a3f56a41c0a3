#include "core/detail/polygon_mesher_cgal.h"

#include "core/common/error.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <deque>
#include <string>
#include <utility>

namespace bary::detail
{
namespace
{

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Segment2 = Kernel::Segment_2;

/// Output index of a triangulation vertex; -1 until assigned.
struct VertexId
{
  int id = -1;
};

using Vbb = CGAL::Triangulation_vertex_base_with_info_2<VertexId, Kernel>;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<Kernel, Vbb>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<int, Kernel>; // nesting level
using Fbc = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbi>;
using Fbd = CGAL::Constrained_Delaunay_triangulation_face_base_2<Kernel, Fbc>;
using Fb = CGAL::Delaunay_mesh_face_base_2<Kernel, Fbd>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds>;
using Face_handle = CDT::Face_handle;
using Vertex_handle = CDT::Vertex_handle;

/// Delaunay refinement criteria with an *area* bound (CGAL's Delaunay_mesh_size_criteria_2
/// bounds the longest edge instead) and CGAL's shape criterion: the squared sine of the
/// smallest angle, (2 area)^2 / (l_max^2 l_mid^2), compared with the bound B. Mirrors
/// Delaunay_mesh_size_criteria_2: too large faces are IMPERATIVELY_BAD (refined even next to
/// small input angles), badly shaped ones BAD; the largest faces, then the worst shaped, first.
class AreaAngleCriteria
{
public:
  using Face_handle = ::bary::detail::Face_handle;

  struct Quality
  {
    double sine = 1.0; ///< squared sine of the smallest angle
    double size = 0.0; ///< area / area bound (0 without bound)
    /// q1 < q2: q1 is refined before q2.
    bool operator<(const Quality& q) const
    {
      if (size > 1.0)
        return q.size > 1.0 ? size > q.size : true;
      if (q.size > 1.0)
        return false;
      return sine < q.sine;
    }
  };

  AreaAngleCriteria(double shape_bound, double max_area)
    : shape_bound_(shape_bound)
    , max_area_(max_area)
  {
  }

  class Is_bad
  {
  public:
    Is_bad(double shape_bound, double max_area)
      : shape_bound_(shape_bound)
      , max_area_(max_area)
    {
    }

    CGAL::Mesh_2::Face_badness operator()(const Quality& q) const
    {
      if (q.size > 1.0)
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      if (q.sine < shape_bound_)
        return CGAL::Mesh_2::BAD;
      return CGAL::Mesh_2::NOT_BAD;
    }

    CGAL::Mesh_2::Face_badness operator()(const Face_handle& fh, Quality& q) const
    {
      const Point2& a = fh->vertex(0)->point();
      const Point2& b = fh->vertex(1)->point();
      const Point2& c = fh->vertex(2)->point();
      const double area = std::abs(CGAL::to_double(CGAL::area(a, b, c)));
      q.size = max_area_ > 0.0 ? area / max_area_ : 0.0;
      if (q.size > 1.0)
      {
        q.sine = 1.0;
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      double l[3] = { CGAL::to_double(CGAL::squared_distance(b, c)),
        CGAL::to_double(CGAL::squared_distance(c, a)),
        CGAL::to_double(CGAL::squared_distance(a, b)) };
      std::sort(l, l + 3);
      q.sine = (l[2] > 0.0 && l[1] > 0.0) ? (4.0 * area * area) / (l[2] * l[1]) : 0.0;
      return (*this)(q);
    }

  private:
    double shape_bound_, max_area_;
  };

  Is_bad is_bad_object() const { return Is_bad(shape_bound_, max_area_); }

private:
  double shape_bound_, max_area_;
};

std::string ring_name(std::size_t r)
{
  return r == 0 ? std::string("the cage") : "hole " + std::to_string(r - 1);
}

std::vector<Point2> ring_points(const Eigen::MatrixXd& R)
{
  std::vector<Point2> pts;
  pts.reserve(static_cast<std::size_t>(R.rows()));
  for (Index i = 0; i < R.rows(); ++i)
    pts.emplace_back(R(i, 0), R(i, 1));
  return pts;
}

/// Nesting level of every face: 0 for the faces reachable from the infinite face without
/// crossing a constraint, +1 for each constraint crossed (CGAL's "polygon with holes" example).
/// The domain is the faces at odd levels.
void mark_nesting_levels(CDT& cdt)
{
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    f->info() = -1;
  std::deque<std::pair<Face_handle, int>> seeds;
  seeds.emplace_back(cdt.infinite_face(), 0);
  while (!seeds.empty())
  {
    const auto [start, level] = seeds.front();
    seeds.pop_front();
    if (start->info() != -1)
      continue;
    std::deque<Face_handle> queue{ start };
    start->info() = level;
    while (!queue.empty())
    {
      const Face_handle fh = queue.front();
      queue.pop_front();
      for (int i = 0; i < 3; ++i)
      {
        const Face_handle n = fh->neighbor(i);
        if (n->info() != -1)
          continue;
        if (cdt.is_constrained(CDT::Edge(fh, i)))
          seeds.emplace_back(n, level + 1);
        else
        {
          n->info() = level;
          queue.push_back(n);
        }
      }
    }
  }
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    f->set_in_domain(!cdt.is_infinite(f) && f->info() % 2 == 1);
}

} // namespace

void check_polygon_rings(const std::vector<Eigen::MatrixXd>& rings)
{
  if (rings.size() < 2)
    return;
  struct Edge
  {
    Segment2 s;
    std::size_t ring;
    Index index;
    double xmin, xmax;
  };
  std::vector<Edge> edges;
  for (std::size_t r = 0; r < rings.size(); ++r)
  {
    const Eigen::MatrixXd& R = rings[r];
    for (Index i = 0, n = R.rows(); i < n; ++i)
    {
      const Index j = (i + 1) % n;
      edges.push_back({ Segment2(Point2(R(i, 0), R(i, 1)), Point2(R(j, 0), R(j, 1))), r, i,
        std::min(R(i, 0), R(j, 0)), std::max(R(i, 0), R(j, 0)) });
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.xmin < b.xmin || (a.xmin == b.xmin && (a.ring < b.ring || (a.ring == b.ring && a.index < b.index)));
  });
  // Sweep over x; within one ring the edges were checked by validate_cage. The first pair (by
  // ring, then edge index) is reported.
  using Key = std::pair<std::size_t, Index>;
  std::vector<std::pair<Key, Key>> pairs;
  for (std::size_t a = 0; a < edges.size(); ++a)
    for (std::size_t b = a + 1; b < edges.size() && edges[b].xmin <= edges[a].xmax; ++b)
    {
      const Edge& e = edges[a];
      const Edge& f = edges[b];
      if (e.ring == f.ring || !CGAL::do_intersect(e.s, f.s))
        continue;
      const Key ke{ e.ring, e.index }, kf{ f.ring, f.index };
      pairs.emplace_back(std::min(ke, kf), std::max(ke, kf));
    }
  if (!pairs.empty())
  {
    const auto [lo, hi] = *std::min_element(pairs.begin(), pairs.end());
    throw Error(ErrorCode::InvalidCage,
      "invalid holes: edge " + std::to_string(lo.second) + " of " + ring_name(lo.first) +
        " touches or crosses edge " + std::to_string(hi.second) + " of " + ring_name(hi.first) +
        "; holes must lie strictly inside the cage and must not touch each other");
  }

  const std::vector<Point2> outer = ring_points(rings[0]);
  for (std::size_t h = 1; h < rings.size(); ++h)
  {
    const Point2 p(rings[h](0, 0), rings[h](0, 1));
    if (CGAL::bounded_side_2(outer.begin(), outer.end(), p, Kernel()) != CGAL::ON_BOUNDED_SIDE)
      throw Error(ErrorCode::InvalidCage,
        "invalid holes: " + ring_name(h) + " lies outside the cage; holes must lie strictly "
        "inside the cage");
  }
  for (std::size_t h = 1; h < rings.size(); ++h)
  {
    const std::vector<Point2> hole = ring_points(rings[h]);
    for (std::size_t g = 1; g < rings.size(); ++g)
    {
      if (g == h)
        continue;
      const Point2 p(rings[g](0, 0), rings[g](0, 1));
      if (CGAL::bounded_side_2(hole.begin(), hole.end(), p, Kernel()) == CGAL::ON_BOUNDED_SIDE)
        throw Error(ErrorCode::InvalidCage,
          "invalid holes: " + ring_name(g) + " lies inside " + ring_name(h) +
            "; nested holes are not supported (remove the inner one)");
    }
  }
}

PolygonMesherOutput cgal_mesh_polygon(const PolygonMesherInput& input)
{
  PolygonMesherOutput out;
  CDT cdt;
  int next_id = 0;
  std::vector<std::vector<Vertex_handle>> ring_handles;
  try
  {
    for (const Eigen::MatrixXd& R : input.rings)
    {
      std::vector<Vertex_handle> handles;
      for (Index i = 0; i < R.rows(); ++i)
      {
        Vertex_handle vh = cdt.insert(Point2(R(i, 0), R(i, 1)));
        if (vh->info().id != -1)
          throw Error(ErrorCode::Internal, "two polygon vertices coincide after validation");
        vh->info().id = next_id++;
        handles.push_back(vh);
      }
      ring_handles.push_back(std::move(handles));
    }
    for (Index s = 0; s < input.steiner.rows(); ++s)
    {
      Vertex_handle vh = cdt.insert(Point2(input.steiner(s, 0), input.steiner(s, 1)));
      if (vh->info().id != -1)
        throw Error(ErrorCode::Internal, "a Steiner point coincides with another vertex after filtering");
      vh->info().id = next_id++;
    }
    for (const auto& handles : ring_handles)
      for (std::size_t i = 0; i < handles.size(); ++i)
        cdt.insert_constraint(handles[i], handles[(i + 1) % handles.size()]);

    mark_nesting_levels(cdt);
    CGAL::Delaunay_mesher_2<CDT, AreaAngleCriteria> mesher(
      cdt, AreaAngleCriteria(input.shape_bound, input.max_area));
    mesher.init(true); // the domain is marked (in_domain) already
    long long steps = 0;
    while (mesher.step_by_step_refine_mesh())
    {
      if (++steps % 512 == 0 && input.step &&
        !input.step(static_cast<Index>(cdt.number_of_vertices())))
      {
        out.cancelled = true;
        return out;
      }
    }
  }
  catch (const Error&)
  {
    throw;
  }
  catch (const std::exception& e) // CGAL::Failure_exception, intersection of constraints
  {
    throw Error(ErrorCode::Internal,
      std::string("the CGAL 2D mesher failed: ") + e.what() + "; please report it with the cage");
  }

  // Number the other vertices used by domain faces in the triangulation's order.
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain())
      for (int k = 0; k < 3; ++k)
        if (f->vertex(k)->info().id == -1)
          f->vertex(k)->info().id = -2;
  const int fixed = next_id;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (v->info().id == -2)
      v->info().id = next_id++;
  out.V.resize(next_id, 2);
  std::vector<char> used(static_cast<std::size_t>(next_id), 0);
  Index nt = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    nt += f->is_in_domain() ? 1 : 0;
  out.T.resize(nt, 3);
  Index t = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
  {
    if (!f->is_in_domain())
      continue;
    for (int k = 0; k < 3; ++k)
    {
      const int id = f->vertex(k)->info().id;
      out.T(t, k) = id;
      used[static_cast<std::size_t>(id)] = 1;
    }
    ++t;
  }
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
  {
    const int id = v->info().id;
    if (id < 0)
      continue;
    out.V(id, 0) = v->point().x();
    out.V(id, 1) = v->point().y();
  }
  for (int id = 0; id < fixed; ++id)
    if (!used[static_cast<std::size_t>(id)])
      throw Error(ErrorCode::Internal,
        "the CGAL 2D mesher left input vertex " + std::to_string(id) + " out of the mesh");
  return out;
}

} // namespace bary::detail
