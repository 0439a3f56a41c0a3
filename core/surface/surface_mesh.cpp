#include "core/surface/surface_mesh.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/meshing/mesh_point_locator.h"
#include "core/solvers/fem_operators.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace bary
{
namespace
{

std::string edge_name(int a, int b)
{
  return "(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

} // namespace

SurfaceMesh::SurfaceMesh(const Eigen::MatrixXd& V_in, const Eigen::MatrixXi& F_in)
  : V(V_in), F(F_in)
{
  if (V.rows() == 0 || F.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the surface has no " +
        std::string(V.rows() == 0 ? "vertices" : "triangles"));
  if (V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "surface vertices must have 3 coordinates, got " + std::to_string(V.cols()));
  if (F.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "surface faces must be triangles (3 vertices each), got " + std::to_string(F.cols()));
  if (V.rows() > std::numeric_limits<int>::max() / 4 || F.rows() > std::numeric_limits<int>::max() / 4)
    throw Error(ErrorCode::InvalidArgument, "the surface has too many vertices or triangles");
  const Index nv = V.rows(), nf = F.rows();
  for (Index i = 0; i < nv; ++i)
    if (!V.row(i).allFinite())
      throw Error(ErrorCode::NonFinite, "surface vertex " + std::to_string(i) +
          " has a non-finite coordinate " + detail::format_row(V, i));
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= nv)
        throw Error(ErrorCode::InvalidArgument, "triangle " + std::to_string(f) + " " +
            detail::format_index_row(F, f) + " refers to vertex " + std::to_string(F(f, k)) +
            " but the surface has " + std::to_string(nv) + " vertices");
  double edge_sum = 0;
  for (Index f = 0; f < nf; ++f)
  {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double l0 = (c - b).norm(), l1 = (a - c).norm(), l2 = (b - a).norm();
    edge_sum += l0 + l1 + l2;
    const double h = std::max({ l0, l1, l2 });
    const double area2 = (b - a).cross(c - a).norm();
    if (!(area2 > 128 * std::numeric_limits<double>::epsilon() * h * h))
      throw Error(ErrorCode::InvalidArgument, "triangle " + std::to_string(f) + " " +
          detail::format_index_row(F, f) + " is degenerate (zero area or a repeated vertex)",
        "remove it or merge its vertices before computing weighted averages");
  }

  // Vertex -> triangles.
  face_offsets.assign(static_cast<std::size_t>(nv + 1), 0);
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      ++face_offsets[static_cast<std::size_t>(F(f, k) + 1)];
  for (Index v = 0; v < nv; ++v)
  {
    if (face_offsets[static_cast<std::size_t>(v + 1)] == 0)
      throw Error(ErrorCode::InvalidArgument, "surface vertex " + std::to_string(v) +
          " belongs to no triangle", "remove unreferenced vertices");
    face_offsets[static_cast<std::size_t>(v + 1)] += face_offsets[static_cast<std::size_t>(v)];
  }
  vertex_faces.resize(static_cast<std::size_t>(3 * nf));
  {
    std::vector<int> fill(face_offsets.begin(), face_offsets.end() - 1);
    for (Index f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        vertex_faces[static_cast<std::size_t>(fill[static_cast<std::size_t>(F(f, k))]++)] =
          static_cast<int>(f);
  }

  // Edges: sort the 3 #F half-edges by their undirected key.
  struct HalfEdge
  {
    long long key;
    int face, corner; // the edge opposite `corner`
  };
  std::vector<HalfEdge> half(static_cast<std::size_t>(3 * nf));
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
    {
      const long long a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      half[static_cast<std::size_t>(3 * f + k)] = { std::min(a, b) * nv + std::max(a, b),
        static_cast<int>(f), k };
    }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key < y.key || (x.key == y.key && (x.face < y.face || (x.face == y.face && x.corner < y.corner)));
  });
  face_neighbors.setConstant(nf, 3, -1);
  boundary.assign(static_cast<std::size_t>(nv), 0);
  edges = 0;
  Index boundary_edges = 0;
  std::vector<std::pair<int, int>> boundary_list;
  for (std::size_t i = 0; i < half.size();)
  {
    std::size_t j = i + 1;
    while (j < half.size() && half[j].key == half[i].key)
      ++j;
    ++edges;
    const int a = static_cast<int>(half[i].key / nv), b = static_cast<int>(half[i].key % nv);
    if (j - i > 2)
      throw Error(ErrorCode::InvalidArgument, "edge " + edge_name(a, b) + " is shared by " +
          std::to_string(j - i) + " triangles (a non-manifold edge)",
        "weighted averages need a manifold surface: every edge in one or two triangles");
    if (j - i == 2)
    {
      if (half[i].face == half[i + 1].face)
        throw Error(ErrorCode::InvalidArgument, "triangle " + std::to_string(half[i].face) +
            " uses edge " + edge_name(a, b) + " twice");
      face_neighbors(half[i].face, half[i].corner) = half[i + 1].face;
      face_neighbors(half[i + 1].face, half[i + 1].corner) = half[i].face;
    }
    else
    {
      ++boundary_edges;
      boundary[static_cast<std::size_t>(a)] = boundary[static_cast<std::size_t>(b)] = 1;
      boundary_list.emplace_back(a, b);
    }
    i = j;
  }

  // One-rings in fan order: the link of v (the edges opposite v in its triangles) must be one
  // path (boundary vertex) or one cycle (interior vertex).
  ring_offsets.assign(static_cast<std::size_t>(nv + 1), 0);
  ring.clear();
  ring.reserve(static_cast<std::size_t>(3 * nf + boundary_edges));
  std::vector<std::pair<int, int>> link;
  std::vector<int> order;
  for (Index v = 0; v < nv; ++v)
  {
    link.clear();
    for (int i = face_offsets[static_cast<std::size_t>(v)]; i < face_offsets[static_cast<std::size_t>(v + 1)]; ++i)
    {
      const int f = vertex_faces[static_cast<std::size_t>(i)];
      const int k = F(f, 0) == v ? 0 : F(f, 1) == v ? 1 : 2;
      link.emplace_back(F(f, (k + 1) % 3), F(f, (k + 2) % 3));
    }
    // Walk the link: start at an endpoint (a neighbour in one link edge) when there is one.
    auto count_of = [&](int u) {
      int c = 0;
      for (const auto& e : link)
        c += (e.first == u) + (e.second == u);
      return c;
    };
    int start = link.front().first;
    for (const auto& e : link)
    {
      if (count_of(e.first) == 1) { start = e.first; break; }
      if (count_of(e.second) == 1) { start = e.second; break; }
    }
    std::vector<char> used(link.size(), 0);
    order.assign(1, start);
    int current = start;
    for (std::size_t step = 0; step < link.size(); ++step)
    {
      int next = -1;
      for (std::size_t e = 0; e < link.size(); ++e)
        if (!used[e] && (link[e].first == current || link[e].second == current))
        {
          used[e] = 1;
          next = link[e].first == current ? link[e].second : link[e].first;
          break;
        }
      if (next < 0)
        break;
      if (next != start)
        order.push_back(next);
      current = next;
    }
    if (std::find(used.begin(), used.end(), 0) != used.end())
      throw Error(ErrorCode::InvalidArgument, "the triangles around surface vertex " +
          std::to_string(v) + " do not form one fan (surface sheets touch at this vertex)",
        "weighted averages need a manifold surface; split the vertex");
    ring.insert(ring.end(), order.begin(), order.end());
    ring_offsets[static_cast<std::size_t>(v + 1)] = static_cast<int>(ring.size());
  }

  // Connected pieces (union-find over the triangles' vertices).
  const Eigen::VectorXi component = connected_components(nv, F);
  if (component.maxCoeff() > 0)
    throw Error(ErrorCode::InvalidArgument, "the surface has " +
        std::to_string(component.maxCoeff() + 1) +
        " connected pieces (vertex 0 and vertex " +
        std::to_string(std::find(component.data(), component.data() + nv, 1) - component.data()) +
        " are on different ones)",
      "weighted averages need one connected surface; split it into one file per piece");

  // Boundary loops: components of the boundary edge graph (each boundary vertex of a manifold
  // surface has exactly two boundary edges).
  boundary_loops = 0;
  if (!boundary_list.empty())
  {
    std::vector<int> parent(static_cast<std::size_t>(nv));
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
      while (parent[static_cast<std::size_t>(x)] != x)
        x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      return x;
    };
    for (const auto& [a, b] : boundary_list)
      parent[static_cast<std::size_t>(find(a))] = find(b);
    for (Index v = 0; v < nv; ++v)
      if (boundary[static_cast<std::size_t>(v)] && find(static_cast<int>(v)) == v)
        ++boundary_loops;
  }
  mean_edge_length = edge_sum / static_cast<double>(3 * nf);
}

void validate_surface_tolerance(double tolerance)
{
  if (!(tolerance >= 0 && tolerance <= 1))
    throw Error(ErrorCode::InvalidArgument, "the surface tolerance must be in [0, 1] (a fraction "
        "of the surface's bounding-box diagonal), got " + detail::format_number(tolerance));
}

std::vector<SurfacePoint> closest_surface_points(
  const SurfaceMesh& mesh, const Eigen::MatrixXd& P, std::vector<double>* distance)
{
  if (P.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "points on a surface need 3 coordinates, got " + std::to_string(P.cols()));
  for (Index i = 0; i < P.rows(); ++i)
    if (!P.row(i).allFinite())
      throw Error(ErrorCode::NonFinite,
        "point " + std::to_string(i) + " has a non-finite coordinate " + detail::format_row(P, i));
  const MeshPointLocator locator(mesh.V, mesh.F, 0.0);
  std::vector<SurfacePoint> result(static_cast<std::size_t>(P.rows()));
  if (distance)
    distance->assign(static_cast<std::size_t>(P.rows()), 0.0);
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> X = P;
#pragma omp parallel for schedule(dynamic, 64)
  for (Index i = 0; i < X.rows(); ++i)
  {
    const MeshPointLocator::Location loc = locator.locate(X.row(i).data());
    auto& r = result[static_cast<std::size_t>(i)];
    r.face = loc.element;
    r.barycentric = loc.barycentric.head<3>();
    if (distance)
      (*distance)[static_cast<std::size_t>(i)] = loc.distance;
  }
  return result;
}

Eigen::MatrixXd surface_point_positions(
  const Eigen::MatrixXi& F, const Eigen::MatrixXd& X, const std::vector<SurfacePoint>& points)
{
  Eigen::MatrixXd R(static_cast<Index>(points.size()), X.cols());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const SurfacePoint& p = points[i];
    R.row(static_cast<Index>(i)) = p.barycentric(0) * X.row(F(p.face, 0)) +
      p.barycentric(1) * X.row(F(p.face, 1)) + p.barycentric(2) * X.row(F(p.face, 2));
  }
  return R;
}

} // namespace bary
