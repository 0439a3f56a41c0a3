// Landmark selection by halfedge-collapse decimation (core/surface/landmark_decimation.h).
//
// The meshes are made here: geodesic icospheres (each icosahedron face cut into k^2 triangles,
// projected onto the unit sphere: 10 k^2 + 2 vertices), flat and bumpy grids on [0, 1]^2 (with
// an optional square hole), a torus grid; and, when present, wa/3holes.obj of the shared data
// (BARYLAB_SHARED_DIR where the build defines it, else /work/shared/data; genus 3, 3596
// vertices), read by the small OBJ parser below; the tests that need it skip without it. Every
// check of the decimated mesh (edges, orientation, fans, boundary loops, Euler characteristic,
// degenerate faces) is computed here from the faces, without the unit's data structures.
#include "core/common/error.h"
#include "core/surface/landmark_decimation.h"
#include "error_matchers.h"

#include <Eigen/Geometry>
#include "igl_formats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace bary
{
namespace
{

using test::throws_error;

struct Mesh
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
};

Mesh from_lists(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& faces)
{
  Mesh m;
  m.V.resize(static_cast<Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    m.V.row(static_cast<Index>(i)) = points[i].transpose();
  m.F.resize(static_cast<Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      m.F(static_cast<Index>(f), k) = faces[f][k];
  return m;
}

/// Drops the vertices no face uses and renumbers the others in order.
Mesh compact(const Mesh& in)
{
  std::vector<int> index(static_cast<std::size_t>(in.V.rows()), -1);
  for (Index f = 0; f < in.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      index[in.F(f, k)] = 0;
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < index.size(); ++i)
    if (index[i] == 0)
    {
      index[i] = static_cast<int>(points.size());
      points.push_back(in.V.row(static_cast<Index>(i)).transpose());
    }
  Mesh out = from_lists(points, {});
  out.F = in.F;
  for (Index f = 0; f < in.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      out.F(f, k) = index[in.F(f, k)];
  return out;
}

/// Unit sphere: the icosahedron with every face cut into k^2 triangles, outward oriented.
Mesh icosphere(int k)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const std::vector<Eigen::Vector3d> ico = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 },
    { 1, -t, 0 }, { 0, -1, t }, { 0, 1, t }, { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 },
    { t, 0, 1 }, { -t, 0, -1 }, { -t, 0, 1 } };
  const std::vector<std::array<int, 3>> ico_faces = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 },
    { 0, 7, 10 }, { 0, 10, 11 }, { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 },
    { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 },
    { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 } };
  // A point is sum_c (w_c / k) corner_c; its key lists the corners with non-zero weights.
  std::map<std::vector<std::pair<int, int>>, int> ids;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> faces;
  for (const auto& c : ico_faces)
  {
    auto id = [&](int i, int j) {
      std::vector<std::pair<int, int>> key;
      const int w[3] = { k - i - j, i, j };
      for (int a = 0; a < 3; ++a)
        if (w[a] > 0)
          key.emplace_back(c[a], w[a]);
      std::sort(key.begin(), key.end());
      const auto [it, inserted] = ids.emplace(key, static_cast<int>(points.size()));
      if (inserted)
        points.push_back(
          ((w[0] * ico[c[0]] + w[1] * ico[c[1]] + w[2] * ico[c[2]]) / k).normalized());
      return it->second;
    };
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j)
      {
        faces.push_back({ id(i, j), id(i + 1, j), id(i, j + 1) });
        if (i + j + 2 <= k)
          faces.push_back({ id(i + 1, j), id(i + 1, j + 1), id(i, j + 1) });
      }
  }
  return from_lists(points, faces);
}

/// n x n vertices on [0, 1]^2 at height z(x, y), faces oriented towards +z; the cells (i, j)
/// with hole_begin <= i, j < hole_end are left out.
template<class Height>
Mesh grid(int n, Height&& z, int hole_begin = 0, int hole_end = 0)
{
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const double x = static_cast<double>(i) / (n - 1), y = static_cast<double>(j) / (n - 1);
      points.emplace_back(x, y, z(x, y));
    }
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i)
    {
      if (i >= hole_begin && i < hole_end && j >= hole_begin && j < hole_end)
        continue;
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      faces.push_back({ a, b, d });
      faces.push_back({ a, d, c });
    }
  return compact(from_lists(points, faces));
}

Mesh flat_grid(int n, int hole_begin = 0, int hole_end = 0)
{
  return grid(n, [](double, double) { return 0.0; }, hole_begin, hole_end);
}

/// Torus with radii 1 and 0.4, n around the axis by m around the tube, outward oriented.
Mesh torus(int n, int m)
{
  const double pi = 3.14159265358979323846;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
    {
      const double u = 2 * pi * i / n, v = 2 * pi * j / m;
      points.emplace_back((1 + 0.4 * std::cos(v)) * std::cos(u),
        (1 + 0.4 * std::cos(v)) * std::sin(u), 0.4 * std::sin(v));
    }
  std::vector<std::array<int, 3>> faces;
  auto id = [&](int i, int j) { return ((i + n) % n) * m + (j + m) % m; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
    {
      faces.push_back({ id(i, j), id(i + 1, j), id(i + 1, j + 1) });
      faces.push_back({ id(i, j), id(i + 1, j + 1), id(i, j + 1) });
    }
  return from_lists(points, faces);
}

/// An OBJ file through the tests' reader (igl_formats.h). False if the file does not exist.
bool read_obj(const std::string& path, Mesh& mesh)
{
  if (!std::ifstream(path))
    return false;
  const bary::test::ObjMesh obj = bary::test::read_obj(path);
  mesh.V = obj.V;
  mesh.F = obj.F;
  return true;
}

/// What the tests check of a triangle mesh, computed from its faces alone (boundary loops and
/// vertex links assume consistently oriented faces).
struct Topology
{
  Index vertices = 0;          ///< distinct vertices used by the faces
  Index edges = 0;
  Index faces = 0;
  bool edge_manifold = true;   ///< every edge in 1 or 2 faces
  bool oriented = true;        ///< no directed edge twice
  bool vertex_manifold = true; ///< every vertex's link is one path or one cycle
  int boundary_loops = 0;
  std::map<int, int> boundary_next; ///< boundary halfedges a -> b
  Index euler() const { return vertices - edges + faces; }
};

Topology topology(const Eigen::MatrixXi& F)
{
  Topology t;
  t.faces = F.rows();
  std::map<std::pair<int, int>, int> directed;
  std::map<int, std::vector<std::pair<int, int>>> link; // x -> link edges (a, b) of faces (x, a, b)
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
      if (++directed[{ a, b }] > 1)
        t.oriented = false;
      link[a].emplace_back(b, c);
    }
  t.vertices = static_cast<Index>(link.size());
  std::map<std::pair<int, int>, int> undirected;
  for (const auto& [e, count] : directed)
    undirected[{ std::min(e.first, e.second), std::max(e.first, e.second) }] += count;
  t.edges = static_cast<Index>(undirected.size());
  for (const auto& [e, count] : undirected)
    if (count > 2)
      t.edge_manifold = false;
  for (const auto& [e, count] : directed)
    if (directed.count({ e.second, e.first }) == 0)
    {
      if (t.boundary_next.count(e.first))
        t.vertex_manifold = false;
      t.boundary_next[e.first] = e.second;
    }
  // Each vertex's link edges must chain into one path or one cycle.
  for (const auto& [x, edges] : link)
  {
    std::map<int, int> next;
    std::set<int> targets;
    for (const auto& [a, b] : edges)
    {
      if (next.count(a))
        t.vertex_manifold = false;
      next[a] = b;
      targets.insert(b);
    }
    int start = edges.front().first;
    for (const auto& [a, b] : edges)
      if (!targets.count(a))
        start = a;
    std::size_t steps = 0;
    for (int y = start; next.count(y) && steps <= edges.size(); y = next[y])
    {
      ++steps;
      if (next[y] == start)
        break;
    }
    if (steps != edges.size())
      t.vertex_manifold = false;
  }
  std::set<int> visited;
  for (const auto& [a, b] : t.boundary_next)
  {
    if (visited.count(a))
      continue;
    ++t.boundary_loops;
    for (int y = a; !visited.count(y) && t.boundary_next.count(y); y = t.boundary_next.at(y))
      visited.insert(y);
  }
  return t;
}

/// Checks every structural property of a decimation of (V, F) to @p expected landmarks.
void expect_valid(const Mesh& mesh, const LandmarkDecimation& d, Index expected)
{
  const Index n = mesh.V.rows();
  ASSERT_EQ(static_cast<Index>(d.landmarks.size()), expected);
  EXPECT_EQ(d.collapses, n - expected);
  EXPECT_TRUE(std::is_sorted(d.landmarks.begin(), d.landmarks.end()));
  EXPECT_TRUE(std::adjacent_find(d.landmarks.begin(), d.landmarks.end()) == d.landmarks.end());
  EXPECT_GE(d.landmarks.front(), 0);
  EXPECT_LT(d.landmarks.back(), n);
  const std::set<int> landmarks(d.landmarks.begin(), d.landmarks.end());
  std::set<int> used;
  ASSERT_EQ(d.faces.cols(), 3);
  for (Index f = 0; f < d.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_TRUE(landmarks.count(d.faces(f, k))) << "face " << f << " uses " << d.faces(f, k);
      used.insert(d.faces(f, k));
    }
  EXPECT_EQ(used, landmarks) << "every landmark is in a face";
  const Topology before = topology(mesh.F), after = topology(d.faces);
  EXPECT_TRUE(after.edge_manifold);
  EXPECT_TRUE(after.oriented);
  EXPECT_TRUE(after.vertex_manifold);
  EXPECT_EQ(after.euler(), before.euler());
  EXPECT_EQ(after.boundary_loops, before.boundary_loops);
  EXPECT_EQ(after.vertices, expected);
  // No face is degenerate (twice its area at most 1e-12 times its longest edge squared, the
  // unit's bound for the faces a collapse changes) unless it is a degenerate input face.
  auto degenerate = [&](int i, int j, int k) {
    const Eigen::Vector3d a = mesh.V.row(i), b = mesh.V.row(j), c = mesh.V.row(k);
    const double longest =
      std::max({ (b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm() });
    return !((b - a).cross(c - a).norm() > 1e-12 * longest);
  };
  std::set<std::array<int, 3>> degenerate_input;
  for (Index f = 0; f < mesh.F.rows(); ++f)
    if (degenerate(mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)))
      degenerate_input.insert({ mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2) });
  for (Index f = 0; f < d.faces.rows(); ++f)
  {
    const std::array<int, 3> t = { d.faces(f, 0), d.faces(f, 1), d.faces(f, 2) };
    EXPECT_TRUE(!degenerate(t[0], t[1], t[2]) || degenerate_input.count(t))
      << "face " << f << " (" << t[0] << ", " << t[1] << ", " << t[2] << ") is degenerate";
  }
}

/// Largest distance from a vertex of V to its nearest landmark.
double covering_radius(const Eigen::MatrixXd& V, const std::vector<int>& landmarks)
{
  double radius = 0.0;
  for (Index i = 0; i < V.rows(); ++i)
  {
    double nearest = std::numeric_limits<double>::infinity();
    for (int l : landmarks)
      nearest = std::min(nearest, (V.row(i) - V.row(l)).norm());
    radius = std::max(radius, nearest);
  }
  return radius;
}

/// The cost of every legal collapse u -> v of the undecimated mesh, by the header's definition
/// (each face's cone is its own normal, each boundary edge's its own direction), written
/// independently of the unit: the key is (u, v).
std::map<std::pair<int, int>, double> first_collapse_costs(const Mesh& mesh)
{
  auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));
  };
  const Eigen::MatrixXd& V = mesh.V;
  const Eigen::MatrixXi& F = mesh.F;
  auto P = [&](int i) -> Eigen::Vector3d { return V.row(i).transpose(); };
  auto normal = [&](int a, int b, int c) -> Eigen::Vector3d {
    return (P(b) - P(a)).cross(P(c) - P(a));
  };
  std::vector<std::vector<int>> faces_of(static_cast<std::size_t>(V.rows()));
  std::vector<std::set<int>> neighbours(static_cast<std::size_t>(V.rows()));
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      faces_of[F(f, k)].push_back(static_cast<int>(f));
      neighbours[F(f, k)].insert(F(f, (k + 1) % 3));
      neighbours[F(f, k)].insert(F(f, (k + 2) % 3));
    }
  const Topology t = topology(F);
  std::map<int, int> previous;
  for (const auto& [a, b] : t.boundary_next)
    previous[b] = a;
  auto has = [&](int f, int x) { return F(f, 0) == x || F(f, 1) == x || F(f, 2) == x; };

  std::map<std::pair<int, int>, double> costs;
  for (int u = 0; u < V.rows(); ++u)
    for (int v : neighbours[u])
    {
      const bool boundary = t.boundary_next.count(u) > 0;
      if (boundary && v != t.boundary_next.at(u) && v != previous.at(u))
        continue;
      std::vector<int> removed, opposite;
      for (int f : faces_of[u])
        if (has(f, v))
        {
          removed.push_back(f);
          for (int k = 0; k < 3; ++k)
            if (F(f, k) != u && F(f, k) != v)
              opposite.push_back(F(f, k));
        }
      int common = 0;
      for (int w : neighbours[u])
        common += static_cast<int>(neighbours[v].count(w));
      if (common != static_cast<int>(removed.size()))
        continue;
      bool legal = true;
      double cost = 0.0;
      for (int f : faces_of[u])
      {
        if (has(f, v))
          continue;
        std::array<int, 3> g = { F(f, 0), F(f, 1), F(f, 2) };
        for (int& x : g)
          if (x == u)
            x = v;
        const Eigen::Vector3d before = normal(F(f, 0), F(f, 1), F(f, 2));
        const Eigen::Vector3d after = normal(g[0], g[1], g[2]);
        const double longest = std::max({ (P(g[1]) - P(g[0])).squaredNorm(),
          (P(g[2]) - P(g[1])).squaredNorm(), (P(g[0]) - P(g[2])).squaredNorm() });
        if (after.norm() <= 1e-12 * longest || after.dot(before) <= 0.0)
        {
          legal = false;
          break;
        }
        cost = std::max(cost, angle(after, before));
        for (std::size_t k = 0; k < removed.size(); ++k)
          if (has(f, opposite[k]))
          {
            const int r = removed[k];
            cost = std::max(cost, angle(after, normal(F(r, 0), F(r, 1), F(r, 2))));
          }
      }
      if (!legal)
        continue;
      if (boundary)
      {
        const bool forward = v == t.boundary_next.at(u);
        const int from = forward ? previous.at(u) : v;
        const int to = forward ? v : t.boundary_next.at(u);
        const Eigen::Vector3d direction = P(to) - P(from);
        cost = std::max({ cost, angle(direction, P(u) - P(from)), angle(direction, P(to) - P(u)) });
      }
      costs[{ u, v }] = cost;
    }
  return costs;
}

double seconds(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

#ifdef BARYLAB_SHARED_DIR
const std::string three_holes_path = std::string(BARYLAB_SHARED_DIR) + "/wa/3holes.obj";
#else
const std::string three_holes_path = "/work/shared/data/wa/3holes.obj";
#endif

TEST(LandmarkDecimation, IcosphereReachesTheTargetAndStaysASphere)
{
  const Mesh sphere = icosphere(8); // 642 vertices
  ASSERT_EQ(sphere.V.rows(), 642);
  for (Index target : { 4, 100, 641 })
  {
    SCOPED_TRACE("target " + std::to_string(target));
    const LandmarkDecimation d = decimation_landmarks(sphere.V, sphere.F, { target });
    expect_valid(sphere, d, target);
    EXPECT_EQ(topology(d.faces).euler(), 2);
    EXPECT_EQ(topology(d.faces).boundary_loops, 0);
  }
}

TEST(LandmarkDecimation, SphereLandmarksAreSpread)
{
  // 200 landmarks evenly spread on the unit sphere leave every point within about 0.15-0.2 of
  // one (a cap of area 4 pi / 200 has chord radius 0.14); 200 vertices bunched in one region
  // leave points up to 2 away. Measured: 0.222 (target 200), 0.126 (target 800).
  const Mesh sphere = icosphere(16); // 2562 vertices, spacing about 0.08
  ASSERT_EQ(sphere.V.rows(), 2562);
  const LandmarkDecimation d200 = decimation_landmarks(sphere.V, sphere.F, { 200 });
  expect_valid(sphere, d200, 200);
  const double r200 = covering_radius(sphere.V, d200.landmarks);
  std::cout << "[ covering radius ] 200 landmarks: " << r200;
  EXPECT_LT(r200, 0.3);
  const LandmarkDecimation d800 = decimation_landmarks(sphere.V, sphere.F, { 800 });
  const double r800 = covering_radius(sphere.V, d800.landmarks);
  std::cout << ", 800 landmarks: " << r800 << "\n";
  EXPECT_LT(r800, 0.16);
  // On a sphere every collapse bends faces: the cost is positive but small.
  EXPECT_GT(d200.max_normal_deviation, 0.0);
  EXPECT_LT(d200.max_normal_deviation, 1.0);
}

TEST(LandmarkDecimation, TorusKeepsGenusOne)
{
  const Mesh t = torus(48, 16); // 768 vertices
  const LandmarkDecimation d = decimation_landmarks(t.V, t.F, { 60 });
  expect_valid(t, d, 60);
  EXPECT_EQ(topology(d.faces).euler(), 0);
}

TEST(LandmarkDecimation, ThreeHolesModelKeepsGenusThree)
{
  Mesh m;
  if (!read_obj(three_holes_path, m))
    GTEST_SKIP() << three_holes_path << " is not present";
  ASSERT_EQ(m.V.rows(), 3596);
  ASSERT_EQ(topology(m.F).euler(), -4); // genus 3
  const auto t0 = std::chrono::steady_clock::now();
  const LandmarkDecimation d = decimation_landmarks(m.V, m.F); // default target: 1000
  std::cout << "[ 3holes ] 3596 -> 1000 in " << seconds(t0) << " s, max deviation "
            << d.max_normal_deviation << " rad\n";
  expect_valid(m, d, 1000);
  EXPECT_EQ(topology(d.faces).euler(), -4);
}

TEST(LandmarkDecimation, FlatGridHasZeroDeviationAndKeepsItsCorners)
{
  const Mesh g = flat_grid(21); // 441 vertices
  const Index target = 40;
  const LandmarkDecimation d = decimation_landmarks(g.V, g.F, { target });
  expect_valid(g, d, target);
  EXPECT_EQ(d.max_normal_deviation, 0.0);
  for (int corner : { 0, 20, 420, 440 })
    EXPECT_TRUE(std::binary_search(d.landmarks.begin(), d.landmarks.end(), corner)) << corner;
  // No face folds over: all still face +z and tile the unit square exactly.
  double area = 0.0;
  for (Index f = 0; f < d.faces.rows(); ++f)
  {
    const Eigen::Vector3d a = g.V.row(d.faces(f, 0)), b = g.V.row(d.faces(f, 1)),
                          c = g.V.row(d.faces(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    EXPECT_GT(n.z(), 0.0) << "face " << f;
    area += 0.5 * n.z();
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
}

TEST(LandmarkDecimation, FlatGridDecimatesToItsCorners)
{
  // Every vertex but the corners goes at zero cost (straight boundary, flat interior); the
  // corners cost pi/2 each and are never needed.
  const Mesh g = flat_grid(8); // 64 vertices
  const LandmarkDecimation d = decimation_landmarks(g.V, g.F, { 4 });
  expect_valid(g, d, 4);
  EXPECT_EQ(d.landmarks, (std::vector<int>{ 0, 7, 56, 63 }));
  EXPECT_EQ(d.faces.rows(), 2);
  EXPECT_EQ(d.max_normal_deviation, 0.0);
}

TEST(LandmarkDecimation, RotatedFlatGridGetsNoSlivers)
{
  // The flat grid turned by 0.3 rad in its plane: points on a grid line are then collinear only
  // up to rounding, so the zero-cost collapses include many that would leave a sliver of area
  // ~1e-17 with its normal still up. The degeneracy bound refuses them (expect_valid checks
  // every face); costs stay at rounding level, the corners stay.
  Mesh g = flat_grid(21);
  const double c = std::cos(0.3), s = std::sin(0.3);
  for (Index i = 0; i < g.V.rows(); ++i)
  {
    const double x = g.V(i, 0), y = g.V(i, 1);
    g.V(i, 0) = c * x - s * y;
    g.V(i, 1) = s * x + c * y;
  }
  for (Index target : { 100, 20 })
  {
    SCOPED_TRACE("target " + std::to_string(target));
    const LandmarkDecimation d = decimation_landmarks(g.V, g.F, { target });
    expect_valid(g, d, target);
    EXPECT_LT(d.max_normal_deviation, 1e-12);
    for (int corner : { 0, 20, 420, 440 })
      EXPECT_TRUE(std::binary_search(d.landmarks.begin(), d.landmarks.end(), corner)) << corner;
  }
}

TEST(LandmarkDecimation, BoundaryLoopsKeepTheirVerticesInOrder)
{
  // A bumpy grid with a square hole (two boundary loops): collapses along the boundary cost
  // something here, so boundary vertices do go. The decimated boundary must be the original
  // boundary with vertices left out: its vertices are original boundary vertices and each
  // boundary edge a -> b joins a to the next surviving vertex of a's original loop.
  const Mesh g = grid(
    25, [](double x, double y) { return 0.1 * std::sin(6 * x) * std::cos(5 * y); }, 9, 15);
  const Topology before = topology(g.F);
  ASSERT_EQ(before.boundary_loops, 2);
  ASSERT_EQ(before.euler(), 0);
  for (Index target : { 150, 40, 12 })
  {
    SCOPED_TRACE("target " + std::to_string(target));
    const LandmarkDecimation d = decimation_landmarks(g.V, g.F, { target });
    expect_valid(g, d, target);
    const std::set<int> landmarks(d.landmarks.begin(), d.landmarks.end());
    const Topology after = topology(d.faces);
    EXPECT_EQ(after.boundary_loops, 2);
    for (const auto& [a, b] : after.boundary_next)
    {
      ASSERT_TRUE(before.boundary_next.count(a)) << a << " was not on the boundary";
      int y = before.boundary_next.at(a);
      while (!landmarks.count(y))
        y = before.boundary_next.at(y);
      EXPECT_EQ(y, b) << "boundary edge " << a << " -> " << b;
    }
    // Surviving boundary vertices stay on the boundary.
    for (const auto& [a, b] : before.boundary_next)
      EXPECT_TRUE(!landmarks.count(a) || after.boundary_next.count(a)) << a;
  }
}

TEST(LandmarkDecimation, CurvedRegionsKeepMoreLandmarks)
{
  // A flat square with a bump of radius ~0.15 around (0.7, 0.7): the collapses of least normal
  // change take the flat part first, so the disc of radius 0.25 around the bump (20% of the
  // square) keeps most landmarks (measured: 76 of 80).
  const Mesh g = grid(41, [](double x, double y) {
    return 0.15 * std::exp(-((x - 0.7) * (x - 0.7) + (y - 0.7) * (y - 0.7)) / 0.01);
  });
  const LandmarkDecimation d = decimation_landmarks(g.V, g.F, { 80 });
  expect_valid(g, d, 80);
  int near_bump = 0;
  for (int l : d.landmarks)
    if (std::hypot(g.V(l, 0) - 0.7, g.V(l, 1) - 0.7) < 0.25)
      ++near_bump;
  std::cout << "[ bump ] " << near_bump << " of 80 landmarks near the bump\n";
  EXPECT_GT(near_bump, 40);
}

TEST(LandmarkDecimation, DecimatingAsFarAsPossibleKeepsTopologyAndOrientation)
{
  // Target 4 cannot be reached on a torus or a surface with holes: the decimation stops when
  // no legal collapse is left, with the topology intact and no face folded over.
  {
    const Mesh t = torus(24, 8);
    const LandmarkDecimation d = decimation_landmarks(t.V, t.F, { 4 });
    std::cout << "[ torus ] stopped at " << d.landmarks.size() << " vertices\n";
    EXPECT_GE(d.landmarks.size(), 7u); // the smallest torus triangulation has 7 vertices
    expect_valid(t, d, static_cast<Index>(d.landmarks.size()));
    EXPECT_EQ(topology(d.faces).euler(), 0);
  }
  {
    // A gentle height field over the square with a hole: every face keeps facing up.
    const Mesh g = grid(
      25, [](double x, double y) { return 0.05 * std::sin(7 * x + 1) * std::cos(4 * y); }, 7, 13);
    const LandmarkDecimation d = decimation_landmarks(g.V, g.F, { 4 });
    std::cout << "[ grid with hole ] stopped at " << d.landmarks.size() << " vertices\n";
    expect_valid(g, d, static_cast<Index>(d.landmarks.size()));
    EXPECT_EQ(topology(d.faces).boundary_loops, 2);
    for (Index f = 0; f < d.faces.rows(); ++f)
    {
      const Eigen::Vector3d a = g.V.row(d.faces(f, 0)), b = g.V.row(d.faces(f, 1)),
                            c = g.V.row(d.faces(f, 2));
      EXPECT_GT((b - a).cross(c - a).z(), 0.0) << "face " << f;
    }
  }
  {
    // The sphere goes down to a tetrahedron whose faces all face outwards.
    const Mesh sphere = icosphere(6);
    const LandmarkDecimation d = decimation_landmarks(sphere.V, sphere.F, { 4 });
    expect_valid(sphere, d, 4);
    for (Index f = 0; f < d.faces.rows(); ++f)
    {
      const Eigen::Vector3d a = sphere.V.row(d.faces(f, 0)), b = sphere.V.row(d.faces(f, 1)),
                            c = sphere.V.row(d.faces(f, 2));
      EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0.0) << "face " << f;
    }
  }
  Mesh m;
  if (read_obj(three_holes_path, m))
  {
    const LandmarkDecimation d = decimation_landmarks(m.V, m.F, { 4 });
    std::cout << "[ 3holes ] stopped at " << d.landmarks.size() << " vertices\n";
    expect_valid(m, d, static_cast<Index>(d.landmarks.size()));
    EXPECT_EQ(topology(d.faces).euler(), -4);
  }
}

TEST(LandmarkDecimation, FirstCollapseIsTheCheapestByTheDefinition)
{
  // One collapse (target #V - 1) against first_collapse_costs(): the collapse done (u is the
  // vertex missing from the landmarks, v the vertex that replaces it in the faces) must have
  // the least cost of all legal collapses, and max_normal_deviation must be that cost.
  std::vector<std::pair<std::string, Mesh>> meshes = {
    { "bumpy grid with a hole",
      grid(
        12, [](double x, double y) { return 0.2 * std::sin(5 * x + 2 * y) * std::cos(3 * y); },
        4, 7) },
    { "torus", torus(12, 7) },
    { "icosphere", icosphere(3) },
  };
  Mesh m;
  if (read_obj(three_holes_path, m))
    meshes.emplace_back("3holes", m);
  for (const auto& [name, mesh] : meshes)
  {
    SCOPED_TRACE(name);
    const Index n = mesh.V.rows();
    const LandmarkDecimation d = decimation_landmarks(mesh.V, mesh.F, { n - 1 });
    expect_valid(mesh, d, n - 1);
    int u = 0;
    while (u < n - 1 && d.landmarks[u] == u)
      ++u;
    // v: the neighbour for which "remove the faces holding u and v, put v for u" gives d.faces.
    int v = -1;
    for (int candidate = 0; candidate < n && v < 0; ++candidate)
    {
      std::vector<std::array<int, 3>> expected;
      for (Index f = 0; f < mesh.F.rows(); ++f)
      {
        std::array<int, 3> t = { mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2) };
        const bool holds_u = std::count(t.begin(), t.end(), u) > 0;
        if (holds_u && std::count(t.begin(), t.end(), candidate) > 0)
          continue;
        for (int& x : t)
          if (x == u)
            x = candidate;
        expected.push_back(t);
      }
      bool same = static_cast<Index>(expected.size()) == d.faces.rows();
      for (std::size_t f = 0; same && f < expected.size(); ++f)
        for (int k = 0; k < 3; ++k)
          same = same && expected[f][k] == d.faces(static_cast<Index>(f), k);
      if (same && candidate != u)
        v = candidate;
    }
    ASSERT_GE(v, 0) << "the faces are not those of one collapse of vertex " << u;
    const auto costs = first_collapse_costs(mesh);
    ASSERT_TRUE(costs.count({ u, v })) << u << " -> " << v << " is not a legal collapse";
    double least = std::numeric_limits<double>::infinity();
    for (const auto& [uv, cost] : costs)
      least = std::min(least, cost);
    std::cout << "[ first collapse ] " << name << ": " << u << " -> " << v << ", cost "
              << costs.at({ u, v }) << " (least " << least << ")\n";
    EXPECT_NEAR(costs.at({ u, v }), least, 1e-12);
    EXPECT_NEAR(d.max_normal_deviation, costs.at({ u, v }), 1e-12);
    EXPECT_GT(least, 0.0);
  }
}

TEST(LandmarkDecimation, IsDeterministic)
{
  Mesh m;
  if (!read_obj(three_holes_path, m))
    m = torus(60, 20);
  const LandmarkDecimationOptions options{ 500 };
  const LandmarkDecimation a = decimation_landmarks(m.V, m.F, options);
  const LandmarkDecimation b = decimation_landmarks(m.V, m.F, options);
  EXPECT_EQ(a.landmarks, b.landmarks);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.collapses, b.collapses);
  EXPECT_EQ(a.max_normal_deviation, b.max_normal_deviation);
}

TEST(LandmarkDecimation, AcceptsZeroAreaFaces)
{
  // (1) Vertex a of one face moved to the middle of the opposite edge: that face has (up to
  // rounding) zero area. (2) Vertex a moved onto its neighbour b: the two faces on edge ab have
  // exactly zero area. Degenerate faces have no normal; the decimation goes on around them and
  // makes no new ones (expect_valid).
  for (int variant : { 1, 2 })
  {
    SCOPED_TRACE("variant " + std::to_string(variant));
    Mesh sphere = icosphere(8);
    const int a = sphere.F(100, 0), b = sphere.F(100, 1), c = sphere.F(100, 2);
    sphere.V.row(a) = variant == 1 ? Eigen::RowVector3d(0.5 * (sphere.V.row(b) + sphere.V.row(c)))
                                   : Eigen::RowVector3d(sphere.V.row(b));
    for (Index target : { 600, 100 })
    {
      const LandmarkDecimation d = decimation_landmarks(sphere.V, sphere.F, { target });
      expect_valid(sphere, d, target);
      EXPECT_EQ(topology(d.faces).euler(), 2);
    }
  }
}

TEST(LandmarkDecimation, InconsistentOrientationGivesTheSameLandmarks)
{
  // Every third face of the sphere turned over (and, second, all of them): the mesh is
  // oriented internally, so the landmarks, the costs and the faces are those of the consistent
  // sphere, each face keeping the orientation of its input face.
  const Mesh sphere = icosphere(8); // 642 vertices
  const LandmarkDecimation reference = decimation_landmarks(sphere.V, sphere.F, { 400 });
  auto as_set = [](const Eigen::MatrixXi& F) {
    std::set<std::array<int, 3>> s;
    for (Index f = 0; f < F.rows(); ++f)
    {
      std::array<int, 3> t = { F(f, 0), F(f, 1), F(f, 2) };
      std::sort(t.begin(), t.end());
      s.insert(t);
    }
    return s;
  };
  for (int every : { 3, 1 })
  {
    SCOPED_TRACE("every " + std::to_string(every));
    Mesh mixed = sphere;
    std::set<std::array<int, 3>> turned; // the input faces turned over, as written in mixed.F
    for (Index f = 0; f < mixed.F.rows(); f += every)
    {
      std::swap(mixed.F(f, 1), mixed.F(f, 2));
      turned.insert({ mixed.F(f, 0), mixed.F(f, 1), mixed.F(f, 2) });
    }
    ASSERT_FALSE(every == 3 && topology(mixed.F).oriented);
    const LandmarkDecimation d = decimation_landmarks(mixed.V, mixed.F, { 400 });
    EXPECT_EQ(d.landmarks, reference.landmarks);
    EXPECT_EQ(d.max_normal_deviation, reference.max_normal_deviation);
    EXPECT_EQ(as_set(d.faces), as_set(reference.faces));
    // Faces that are input faces unchanged keep the way the input wrote them.
    std::set<std::array<int, 3>> input;
    for (Index f = 0; f < mixed.F.rows(); ++f)
      input.insert({ mixed.F(f, 0), mixed.F(f, 1), mixed.F(f, 2) });
    Index kept = 0, kept_turned = 0;
    for (Index f = 0; f < d.faces.rows(); ++f)
    {
      std::array<int, 3> t = { d.faces(f, 0), d.faces(f, 1), d.faces(f, 2) };
      std::array<int, 3> other = { t[0], t[2], t[1] };
      for (int r = 0; r < 3; ++r) // the same face written the other way round is not an input
      {
        EXPECT_FALSE(input.count(other) && !input.count(t)) << "face " << f << " turned over";
        std::rotate(other.begin(), other.begin() + 1, other.end());
      }
      for (int r = 0; r < 3; ++r)
      {
        kept += static_cast<Index>(input.count(t));
        kept_turned += static_cast<Index>(turned.count(t));
        std::rotate(t.begin(), t.begin() + 1, t.end());
      }
    }
    EXPECT_GT(kept, 0);
    EXPECT_GT(kept_turned, 0);
  }
}

TEST(LandmarkDecimation, TargetOfAllVerticesChangesNothing)
{
  const Mesh sphere = icosphere(3);
  const LandmarkDecimation d =
    decimation_landmarks(sphere.V, sphere.F, { sphere.V.rows() });
  ASSERT_EQ(static_cast<Index>(d.landmarks.size()), sphere.V.rows());
  for (Index i = 0; i < sphere.V.rows(); ++i)
    EXPECT_EQ(d.landmarks[i], i);
  EXPECT_EQ(d.faces, sphere.F);
  EXPECT_EQ(d.collapses, 0);
  EXPECT_EQ(d.max_normal_deviation, 0.0);
}

TEST(LandmarkDecimation, ComponentsStopAtFourVertices)
{
  // An icosahedron (12 vertices) and a far-away octahedron (6): target 4 cannot be reached,
  // each component ends as a tetrahedron and 8 landmarks are returned.
  const Mesh ico = icosphere(1);
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> faces;
  for (Index i = 0; i < ico.V.rows(); ++i)
    points.push_back(ico.V.row(i).transpose());
  for (Index f = 0; f < ico.F.rows(); ++f)
    faces.push_back({ ico.F(f, 0), ico.F(f, 1), ico.F(f, 2) });
  const int o = static_cast<int>(points.size());
  for (const Eigen::Vector3d& p : { Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0),
         Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, 1),
         Eigen::Vector3d(0, 0, -1) })
    points.push_back(p + Eigen::Vector3d(10, 0, 0));
  for (const auto& t : std::vector<std::array<int, 3>>{ { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 },
         { 3, 0, 4 }, { 2, 0, 5 }, { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } })
    faces.push_back({ o + t[0], o + t[1], o + t[2] });
  const Mesh two = from_lists(points, faces);
  ASSERT_TRUE(topology(two.F).oriented);
  const LandmarkDecimation d = decimation_landmarks(two.V, two.F, { 4 });
  expect_valid(two, d, 8);
  EXPECT_EQ(d.faces.rows(), 8);
  EXPECT_EQ(std::count_if(d.landmarks.begin(), d.landmarks.end(), [&](int l) { return l < o; }), 4);
  EXPECT_EQ(topology(d.faces).euler(), 4);
}

TEST(LandmarkDecimation, LargeIcosphere)
{
  const Mesh sphere = icosphere(100); // 100002 vertices
  ASSERT_EQ(sphere.V.rows(), 100002);
  const auto t0 = std::chrono::steady_clock::now();
  const LandmarkDecimation d = decimation_landmarks(sphere.V, sphere.F, { 1000 });
  std::cout << "[ icosphere ] 100002 -> 1000 in " << seconds(t0) << " s\n";
  ASSERT_EQ(d.landmarks.size(), 1000u);
  const Topology after = topology(d.faces);
  EXPECT_TRUE(after.edge_manifold && after.oriented && after.vertex_manifold);
  EXPECT_EQ(after.euler(), 2);
  EXPECT_EQ(after.vertices, 1000);
  const double radius = covering_radius(sphere.V, d.landmarks);
  std::cout << "[ icosphere ] covering radius of the 1000 landmarks: " << radius << "\n";
  EXPECT_LT(radius, 0.15); // 1000 caps of area 4 pi / 1000 have chord radius 0.063
}

TEST(LandmarkDecimation, RefusesBadInput)
{
  const Mesh g = flat_grid(4); // 16 vertices
  auto run = [](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Index target = 4) {
    return [V, F, target] { decimation_landmarks(V, F, { target }); };
  };
  EXPECT_TRUE(
    throws_error(run(Eigen::MatrixXd(0, 3), g.F), ErrorCode::EmptyInput, { "no vertices" }));
  EXPECT_TRUE(throws_error(run(g.V, Eigen::MatrixXi(0, 3)), ErrorCode::EmptyInput, { "no faces" }));
  EXPECT_TRUE(throws_error(
    run(g.V.leftCols(2), g.F), ErrorCode::SizeMismatch, { "3 coordinates", "got 2" }));
  Eigen::MatrixXi F4(g.F.rows(), 4);
  F4 << g.F, g.F.col(0);
  EXPECT_TRUE(throws_error(run(g.V, F4), ErrorCode::SizeMismatch, { "got 4 columns" }));

  Eigen::MatrixXi F = g.F;
  F(3, 1) = 16;
  EXPECT_TRUE(throws_error(
    run(g.V, F), ErrorCode::InvalidArgument, { "face 3", "refers to vertex 16", "[0, 16)" }));
  F(3, 1) = -1;
  EXPECT_TRUE(throws_error(run(g.V, F), ErrorCode::InvalidArgument, { "refers to vertex -1" }));
  F = g.F;
  F(2, 2) = F(2, 0);
  EXPECT_TRUE(throws_error(run(g.V, F), ErrorCode::InvalidArgument, { "face 2", "repeats" }));

  Eigen::MatrixXd V = g.V;
  V(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error(run(V, g.F), ErrorCode::NonFinite, { "vertex 5" }));
  V(5, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error(run(V, g.F), ErrorCode::NonFinite, { "vertex 5" }));

  EXPECT_TRUE(throws_error(run(g.V, g.F, 3), ErrorCode::InvalidArgument,
    { "target_vertices", "[4, 16]", "got 3" }));
  EXPECT_TRUE(throws_error(run(g.V, g.F, 17), ErrorCode::InvalidArgument, { "got 17" }));
  EXPECT_TRUE(throws_error(run(g.V, g.F, -1), ErrorCode::InvalidArgument, { "got -1" }));
}

TEST(LandmarkDecimation, RefusesNonManifoldAndNonOrientableMeshes)
{
  // Three triangles on the edge (0, 1).
  Eigen::MatrixXd V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  Eigen::MatrixXi F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  EXPECT_TRUE(throws_error([&] { decimation_landmarks(V, F, { 4 }); }, ErrorCode::InvalidArgument,
    { "edge (0, 1)", "3 faces", "edge-manifold" }));

  // A Moebius strip (12 quads, a half twist) cannot be oriented.
  {
    const double pi = 3.14159265358979323846;
    const int n = 12;
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < n; ++i)
      for (double w : { 1.0, -1.0 }) // vertex 2 i on one side, 2 i + 1 on the other
      {
        const double t = 2 * pi * i / n, r = 1 + 0.3 * w * std::cos(t / 2);
        points.emplace_back(r * std::cos(t), r * std::sin(t), 0.3 * w * std::sin(t / 2));
      }
    std::vector<std::array<int, 3>> faces;
    for (int i = 0; i + 1 < n; ++i)
    {
      faces.push_back({ 2 * i, 2 * i + 1, 2 * i + 3 });
      faces.push_back({ 2 * i, 2 * i + 3, 2 * i + 2 });
    }
    faces.push_back({ 2 * n - 2, 2 * n - 1, 0 }); // the twist: side 1 meets side 0
    faces.push_back({ 2 * n - 2, 0, 1 });
    const Mesh moebius = from_lists(points, faces);
    ASSERT_TRUE(topology(moebius.F).edge_manifold);
    EXPECT_TRUE(throws_error([&] { decimation_landmarks(moebius.V, moebius.F, { 4 }); },
      ErrorCode::InvalidArgument, { "not orientable", "edge (" }));
  }

  // Two triangles meeting only at vertex 0 (a pinch).
  Eigen::MatrixXd W(5, 3);
  W << 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0;
  Eigen::MatrixXi H(2, 3);
  H << 0, 1, 2, 0, 3, 4;
  EXPECT_TRUE(throws_error([&] { decimation_landmarks(W, H, { 4 }); }, ErrorCode::InvalidArgument,
    { "vertex 0", "non-manifold" }));

  // A vertex in no face.
  const Mesh g = flat_grid(3);
  Eigen::MatrixXd extra(g.V.rows() + 1, 3);
  extra << g.V, Eigen::RowVector3d(5, 5, 5);
  EXPECT_TRUE(throws_error([&] { decimation_landmarks(extra, g.F, { 4 }); },
    ErrorCode::InvalidArgument, { "vertex 9", "no face" }));
}

TEST(LandmarkDecimation, ReportsProgressAndCanBeCancelled)
{
  const Mesh sphere = icosphere(16); // 2562 vertices
  std::vector<double> fractions;
  const LandmarkDecimation d = decimation_landmarks(sphere.V, sphere.F, { 100 }, [&](double f) {
    fractions.push_back(f);
    return true;
  });
  EXPECT_EQ(d.landmarks.size(), 100u);
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_GE(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  // About once per percent of each phase (queueing, collapsing).
  EXPECT_GE(fractions.size(), 100u);
  EXPECT_LE(fractions.size(), 250u);

  EXPECT_TRUE(throws_error(
    [&] { decimation_landmarks(sphere.V, sphere.F, { 100 }, [](double) { return false; }); },
    ErrorCode::Cancelled, { "landmark decimation", "cancelled" }));
  double last = -1.0;
  EXPECT_TRUE(throws_error(
    [&] {
      decimation_landmarks(sphere.V, sphere.F, { 100 }, [&](double f) {
        last = f;
        return f < 0.5;
      });
    },
    ErrorCode::Cancelled));
  EXPECT_GE(last, 0.5);
  EXPECT_LT(last, 0.6); // stopped at the first report past one half
}

} // namespace
} // namespace bary
