#include "core/meshing/domain_mesh.h"

#include "core/detail/closest_point.h"
#include "core/detail/format.h"
#include "core/detail/polygon_mesher_cgal.h"
#include "core/detail/tetgen_mesher.h"
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/coordinates/harmonic_coordinates.h"
#include "core/detail/timing.h"
#include "core/detail/constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace bary
{
namespace
{


/// The automatic SurfaceMeshOptions::max_added_vertices (TetGen's 'S' switch). Its quality
/// refinement does not end when the radius-edge bound cannot be met (1.0 on the bundled kidney
/// cage ran 4 minutes to 4.8 GB), so the work is bounded.
Index surface_mesh_vertex_cap(double expected_cells, Index faces, Index steiner_points)
{
  const double cap = 20.0 * expected_cells + 100.0 * static_cast<double>(faces) +
    static_cast<double>(steiner_points) + 1e5;
  return static_cast<Index>(std::min(cap, 2147483647.0));
}

[[noreturn]] void throw_invalid(const std::string& message)
{
  throw Error(ErrorCode::InvalidArgument, message);
}

/// Reports @p fraction; throws Error(Cancelled) if the callback asks to stop.
void checkpoint(const ProgressCallback& progress, double fraction, const char* what)
{
  if (progress && !progress(std::clamp(fraction, 0.0, 1.0)))
    throw Error(ErrorCode::Cancelled, std::string(what) + " was cancelled");
}

void check_points(const Eigen::MatrixXd& P, int dim, const std::string& what)
{
  if (P.size() == 0)
    return;
  if (P.cols() != dim)
    throw Error(ErrorCode::SizeMismatch,
      what + " must be #S by " + std::to_string(dim) + ", got " + std::to_string(P.rows()) +
        " by " + std::to_string(P.cols()));
  for (Index i = 0; i < P.rows(); ++i)
    if (!P.row(i).allFinite())
      throw Error(ErrorCode::NonFinite,
        what + ": point " + std::to_string(i) + " has a non-finite coordinate");
}

// --- Steiner points ---------------------------------------------------------------------------

/// Hash of a cell of a uniform grid.
struct CellHash
{
  std::size_t operator()(const std::array<std::int64_t, 3>& c) const noexcept
  {
    std::uint64_t h = 1469598103934665603ULL;
    for (std::int64_t v : c)
    {
      h ^= static_cast<std::uint64_t>(v) + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

/// Keeps the points flagged @p ok, merging each with an earlier kept point within @p tol
/// (exact duplicates always). Returns for every point its row in @p kept, or -1.
std::vector<int> merge_points(const Eigen::MatrixXd& P, const std::vector<char>& ok, double tol,
  double diameter, Eigen::MatrixXd& kept)
{
  const Index n = P.rows();
  const int dim = static_cast<int>(P.cols());
  std::vector<int> index(static_cast<std::size_t>(n), -1);
  if (n == 0)
  {
    kept.resize(0, dim);
    return index;
  }
  // Cells at least tol wide, so a point within tol of another lies in a neighbouring cell;
  // at least 1e-9 of the diameter, so cell indices stay far from overflow.
  const double h = std::max({ tol, 1e-9 * diameter, std::numeric_limits<double>::min() });
  const Eigen::RowVectorXd lo = P.colwise().minCoeff();
  auto cell_of = [&](Index i) {
    std::array<std::int64_t, 3> c{ 0, 0, 0 };
    for (int k = 0; k < dim; ++k)
      c[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(std::floor((P(i, k) - lo(k)) / h));
    return c;
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<int>, CellHash> grid;
  std::vector<Index> rows;
  for (Index i = 0; i < n; ++i)
  {
    if (!ok[static_cast<std::size_t>(i)])
      continue;
    const auto c = cell_of(i);
    int found = -1;
    const int range_z = dim == 3 ? 1 : 0;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -range_z; dz <= range_z && found < 0; ++dz)
        {
          const auto it = grid.find({ c[0] + dx, c[1] + dy, c[2] + dz });
          if (it == grid.end())
            continue;
          for (int r : it->second)
            if ((P.row(rows[static_cast<std::size_t>(r)]) - P.row(i)).norm() <= tol &&
              (found < 0 || r < found))
              found = r;
        }
    if (found >= 0)
    {
      index[static_cast<std::size_t>(i)] = found;
      continue;
    }
    const int r = static_cast<int>(rows.size());
    rows.push_back(i);
    grid[c].push_back(r);
    index[static_cast<std::size_t>(i)] = r;
  }
  kept.resize(static_cast<Index>(rows.size()), dim);
  for (std::size_t r = 0; r < rows.size(); ++r)
    kept.row(static_cast<Index>(r)) = P.row(rows[r]);
  return index;
}

// --- 2D ---------------------------------------------------------------------------------------

double ring_area(const Eigen::MatrixXd& R)
{
  double a = 0.0;
  for (Index i = 0, n = R.rows(); i < n; ++i)
  {
    const Index j = (i + 1) % n;
    a += R(i, 0) * R(j, 1) - R(j, 0) * R(i, 1);
  }
  return 0.5 * a;
}

/// Even-odd rule over all rings: inside the outer polygon and outside every hole.
bool inside_rings(const std::vector<Eigen::MatrixXd>& rings, double x, double y)
{
  bool inside = false;
  for (const Eigen::MatrixXd& R : rings)
    for (Index i = 0, n = R.rows(); i < n; ++i)
    {
      const Index j = (i + 1) % n;
      const double xi = R(i, 0), yi = R(i, 1), xj = R(j, 0), yj = R(j, 1);
      if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi)
        inside = !inside;
    }
  return inside;
}

double rings_distance(const std::vector<Eigen::MatrixXd>& rings, const Eigen::Vector2d& p)
{
  double d = std::numeric_limits<double>::infinity();
  for (const Eigen::MatrixXd& R : rings)
    for (Index i = 0, n = R.rows(); i < n; ++i)
    {
      const Eigen::Vector2d a = R.row(i).transpose(), b = R.row((i + 1) % n).transpose();
      const double t = detail::closest_on_segment(p, a, b);
      d = std::min(d, (a + t * (b - a) - p).norm());
    }
  return d;
}

/// Where each mesh boundary vertex lies: on ring r, on its edge `edge` (from ring vertex `edge`
/// to `edge + 1`), or at ring vertex `edge` (vertex = true).
struct BoundaryPlace
{
  int ring = -1;
  Index edge = -1;
  bool vertex = false;
};

/// Walks the boundary cycles of a 2D mesh whose vertex ring_offset[r] + i is vertex i of ring r,
/// and assigns every boundary vertex its ring edge.
std::vector<BoundaryPlace> locate_boundary_2d(const Eigen::MatrixXi& T, Index nv,
  const std::vector<Eigen::MatrixXd>& rings, const std::vector<int>& ring_offset)
{
  std::vector<std::pair<int, int>> edges;
  edges.reserve(static_cast<std::size_t>(3 * T.rows()));
  for (Index t = 0; t < T.rows(); ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int a = T(t, k), b = T(t, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<int>> adj(static_cast<std::size_t>(nv));
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i])
      ++j;
    if (j - i == 1)
    {
      adj[static_cast<std::size_t>(edges[i].first)].push_back(edges[i].second);
      adj[static_cast<std::size_t>(edges[i].second)].push_back(edges[i].first);
    }
    i = j;
  }
  auto internal = [](const std::string& what) {
    throw Error(ErrorCode::Internal, "2D domain mesh boundary: " + what);
  };
  std::vector<BoundaryPlace> place(static_cast<std::size_t>(nv));
  for (std::size_t r = 0; r < rings.size(); ++r)
  {
    const int o = ring_offset[r];
    const int n = static_cast<int>(rings[r].rows());
    auto ring_vertex = [&](int v) { return v >= o && v < o + n; };
    auto next_of = [&](int prev, int cur) {
      const auto& a = adj[static_cast<std::size_t>(cur)];
      if (a.size() != 2)
        internal("vertex " + std::to_string(cur) + " has " + std::to_string(a.size()) +
          " boundary edges instead of 2");
      return a[0] == prev ? a[1] : a[0];
    };
    const auto& a0 = adj[static_cast<std::size_t>(o)];
    if (a0.size() != 2)
      internal("polygon vertex " + std::to_string(o) + " is not on the mesh boundary");
    // Direction: the walk that reaches ring vertex 1 before any other ring vertex.
    int chosen = -1;
    for (int cand : a0)
    {
      int prev = o, cur = cand;
      for (Index steps = 0; !ring_vertex(cur) && steps <= nv; ++steps)
      {
        const int next = next_of(prev, cur);
        prev = cur;
        cur = next;
      }
      if (cur == o + 1)
        chosen = cand;
    }
    if (chosen < 0)
      internal("the boundary of ring " + std::to_string(r) + " does not follow the polygon");
    place[static_cast<std::size_t>(o)] = { static_cast<int>(r), 0, true };
    int prev = o, cur = chosen;
    Index edge = 0;
    for (Index steps = 0; cur != o; ++steps)
    {
      if (steps > nv)
        internal("the boundary walk does not close");
      if (ring_vertex(cur))
      {
        if (cur != o + edge + 1)
          internal("the boundary of ring " + std::to_string(r) + " visits polygon vertices out of order");
        ++edge;
        place[static_cast<std::size_t>(cur)] = { static_cast<int>(r), edge, true };
      }
      else
        place[static_cast<std::size_t>(cur)] = { static_cast<int>(r), edge, false };
      const int next = next_of(prev, cur);
      prev = cur;
      cur = next;
    }
    if (edge != n - 1)
      internal("the boundary of ring " + std::to_string(r) + " skips polygon vertices");
  }
  for (Index v = 0; v < nv; ++v)
    if (!adj[static_cast<std::size_t>(v)].empty() && place[static_cast<std::size_t>(v)].ring < 0)
      internal("boundary vertex " + std::to_string(v) + " is not on the polygon or a hole");
  return place;
}

// --- 3D ---------------------------------------------------------------------------------------

Eigen::Vector3d row3(const Eigen::MatrixXd& V, Index i)
{
  return V.row(i).transpose();
}

/// Generalized winding number of a closed triangle surface around p (sum of solid angles,
/// Van Oosterom & Strackee 1983, / 4 pi): +-1 inside, 0 outside.
double winding_number(const Cage& cage, const Eigen::Vector3d& p)
{
  double omega = 0.0;
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d a = row3(cage.V, cage.F(f, 0)) - p, b = row3(cage.V, cage.F(f, 1)) - p,
                          c = row3(cage.V, cage.F(f, 2)) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega / (4.0 * kPi);
}

struct FaceBox
{
  double lo[3], hi[3];
};

std::vector<FaceBox> face_boxes(const Cage& cage, double pad)
{
  std::vector<FaceBox> boxes(static_cast<std::size_t>(cage.F.rows()));
  for (Index f = 0; f < cage.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      double lo = cage.V(cage.F(f, 0), k), hi = lo;
      for (int c = 1; c < 3; ++c)
      {
        lo = std::min(lo, cage.V(cage.F(f, c), k));
        hi = std::max(hi, cage.V(cage.F(f, c), k));
      }
      boxes[static_cast<std::size_t>(f)].lo[k] = lo - pad;
      boxes[static_cast<std::size_t>(f)].hi[k] = hi + pad;
    }
  return boxes;
}

/// Distance between the parts of faces f and g that do not meet at shared vertices: the
/// vertices of one not in the other against the other triangle, and the edge pairs with no
/// common vertex. Describes the closest pair in @p what.
double face_pair_distance(const Cage& cage, Index f, Index g, std::string& what)
{
  const Eigen::MatrixXd& V = cage.V;
  const int fa[3] = { cage.F(f, 0), cage.F(f, 1), cage.F(f, 2) };
  const int ga[3] = { cage.F(g, 0), cage.F(g, 1), cage.F(g, 2) };
  auto in = [](const int* s, int v) { return s[0] == v || s[1] == v || s[2] == v; };
  double best = std::numeric_limits<double>::infinity();
  auto vertex_face = [&](const int* s, const int* t, Index tf) {
    for (int k = 0; k < 3; ++k)
    {
      if (in(t, s[k]))
        continue;
      const double d = detail::point_triangle_distance(
        row3(V, s[k]), row3(V, t[0]), row3(V, t[1]), row3(V, t[2]));
      if (d < best)
      {
        best = d;
        what = "vertex " + std::to_string(s[k]) + " is " + detail::format_number(d) + " from face " +
          std::to_string(tf);
      }
    }
  };
  vertex_face(fa, ga, g);
  vertex_face(ga, fa, f);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      const int a = fa[i], b = fa[(i + 1) % 3], c = ga[j], d = ga[(j + 1) % 3];
      if (a == c || a == d || b == c || b == d)
        continue;
      const double dist =
        detail::segment_segment_distance(row3(V, a), row3(V, b), row3(V, c), row3(V, d));
      if (dist < best)
      {
        best = dist;
        what = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ") is " +
          detail::format_number(dist) + " from edge (" + std::to_string(c) + ", " + std::to_string(d) + ")";
      }
    }
  return best;
}

/// Throws Error(InvalidCage) if an edge is shorter than @p min_distance or two faces come
/// closer than it away from their shared vertices. Sweep over x of the padded face boxes.
void check_feature_size(const Cage& cage, double min_distance)
{
  const Index nf = cage.F.rows();
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
    {
      const int a = cage.F(f, k), b = cage.F(f, (k + 1) % 3);
      const double len = (cage.V.row(a) - cage.V.row(b)).norm();
      if (len < min_distance)
        throw Error(ErrorCode::InvalidCage,
          "invalid cage: edge (" + std::to_string(std::min(a, b)) + ", " +
            std::to_string(std::max(a, b)) + ") is only " + detail::format_number(len) +
            " long, below the smallest feature TetGen resolves (" + detail::format_number(min_distance) +
            " for this cage); merge its vertices");
    }
  const std::vector<FaceBox> boxes = face_boxes(cage, 0.5 * min_distance);
  std::vector<Index> order(static_cast<std::size_t>(nf));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Index a, Index b) {
    const double xa = boxes[static_cast<std::size_t>(a)].lo[0];
    const double xb = boxes[static_cast<std::size_t>(b)].lo[0];
    return xa < xb || (xa == xb && a < b);
  });
  Index best_f = -1, best_g = -1;
  std::string best_what;
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    const FaceBox& bf = boxes[static_cast<std::size_t>(order[i])];
    for (std::size_t j = i + 1; j < order.size(); ++j)
    {
      const FaceBox& bg = boxes[static_cast<std::size_t>(order[j])];
      if (bg.lo[0] > bf.hi[0])
        break;
      if (bg.lo[1] > bf.hi[1] || bf.lo[1] > bg.hi[1] || bg.lo[2] > bf.hi[2] || bf.lo[2] > bg.hi[2])
        continue;
      const Index f = std::min(order[i], order[j]), g = std::max(order[i], order[j]);
      std::string what;
      if (face_pair_distance(cage, f, g, what) < min_distance &&
        (best_f < 0 || std::make_pair(f, g) < std::make_pair(best_f, best_g)))
      {
        best_f = f;
        best_g = g;
        best_what = what;
      }
    }
  }
  if (best_f >= 0)
    throw Error(ErrorCode::InvalidCage,
      "invalid cage: faces " + std::to_string(best_f) + " and " + std::to_string(best_g) +
        " nearly touch (" + best_what + "), closer than the smallest feature TetGen resolves (" +
        detail::format_number(min_distance) + " for this cage); separate them");
}

/// Distance from p to the cage surface, or a value > limit when it is farther than limit.
double surface_distance_within(const Cage& cage, const std::vector<FaceBox>& boxes,
  const Eigen::Vector3d& p, double limit)
{
  double d = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const FaceBox& b = boxes[static_cast<std::size_t>(f)];
    if (p(0) < b.lo[0] || p(0) > b.hi[0] || p(1) < b.lo[1] || p(1) > b.hi[1] || p(2) < b.lo[2] ||
      p(2) > b.hi[2])
      continue;
    d = std::min(d,
      detail::point_triangle_distance(
        p, row3(cage.V, cage.F(f, 0)), row3(cage.V, cage.F(f, 1)), row3(cage.V, cage.F(f, 2))));
  }
  return std::isfinite(d) ? d : 2.0 * limit + 1.0;
}

} // namespace

// --- mesh_polygon -----------------------------------------------------------------------------

namespace
{

/// mesh_polygon at the scale given (see scale_exponent).
DomainMesh mesh_polygon_as_given(
  const Cage& cage2d, const PolygonMeshOptions& options, const ProgressCallback& progress)
{
  const auto t0 = std::chrono::steady_clock::now();
  const char* what = "meshing the polygon";
  if (cage2d.V.rows() > 0 && cage2d.V.cols() != 2)
    throw Error(ErrorCode::SizeMismatch,
      "mesh_polygon needs a 2D cage (V #C by 2), got " + std::to_string(cage2d.V.cols()) +
        " coordinates per vertex",
      "use mesh_closed_surface for 3D cages");
  validate_cage(cage2d);
  checkpoint(progress, 0.0, what);

  if (!(options.min_angle_degrees >= 0.0 && options.min_angle_degrees <= kMaxMinAngleDegrees))
    throw Error(ErrorCode::InvalidArgument,
      "min_angle_degrees must be in [0, " + detail::format_number(kMaxMinAngleDegrees) +
        "] (CGAL's refinement terminates for sure up to there), got " +
        detail::format_number(options.min_angle_degrees));
  if (!std::isfinite(options.max_area))
    throw Error(ErrorCode::InvalidArgument, "max_area must be finite");
  if (options.max_area <= 0.0 && options.target_cells <= 0)
    throw Error(ErrorCode::InvalidArgument,
      "give a size: max_area > 0 or target_cells > 0 (got max_area " +
        detail::format_number(options.max_area) + ", target_cells " + std::to_string(options.target_cells) + ")");
  if (!(options.steiner_tolerance >= 0.0 && options.steiner_tolerance <= 0.1))
    throw Error(ErrorCode::InvalidArgument,
      "steiner_tolerance must be in [0, 0.1], got " + detail::format_number(options.steiner_tolerance));
  check_points(options.steiner_points, 2, "the Steiner points");

  std::vector<Eigen::MatrixXd> rings{ cage2d.V };
  for (std::size_t h = 0; h < options.holes.size(); ++h)
  {
    const Eigen::MatrixXd& H = options.holes[h];
    const std::string name = "hole " + std::to_string(h);
    if (H.cols() != 2 && H.rows() > 0)
      throw Error(ErrorCode::SizeMismatch,
        name + " must be #H by 2, got " + std::to_string(H.rows()) + " by " + std::to_string(H.cols()));
    try
    {
      Cage hole;
      hole.V = H;
      validate_cage(hole);
    }
    catch (const Error& e)
    {
      throw Error(e.code(), name + ": " + e.what());
    }
    rings.push_back(H);
  }
  detail::check_polygon_rings(rings);

  double area = std::abs(ring_area(cage2d.V));
  for (std::size_t h = 1; h < rings.size(); ++h)
    area -= std::abs(ring_area(rings[h]));
  const double max_area =
    options.max_area > 0.0 ? options.max_area : area / static_cast<double>(options.target_cells);
  if (area / max_area > kMaxRequestedCells)
    throw Error(ErrorCode::InvalidArgument,
      "max_area " + detail::format_number(max_area) + " asks for more than " +
        detail::format_number(area / max_area) + " triangles (area " + detail::format_number(area) +
        "); the limit is " + detail::format_number(kMaxRequestedCells));

  // Steiner points: inside the domain and away from its boundary, merged when close.
  const double diameter = cage2d.diameter();
  const double tol = options.steiner_tolerance * diameter;
  const Eigen::MatrixXd& S = options.steiner_points;
  std::vector<char> ok(static_cast<std::size_t>(S.rows()), 0);
  for (Index s = 0; s < S.rows(); ++s)
  {
    const Eigen::Vector2d p = S.row(s).transpose();
    ok[static_cast<std::size_t>(s)] =
      inside_rings(rings, p(0), p(1)) && rings_distance(rings, p) > tol;
  }
  Eigen::MatrixXd accepted;
  const std::vector<int> steiner_index = merge_points(S, ok, tol, diameter, accepted);
  checkpoint(progress, 0.1, what);

  std::vector<int> ring_offset;
  int ring_vertices = 0;
  for (const Eigen::MatrixXd& R : rings)
  {
    ring_offset.push_back(ring_vertices);
    ring_vertices += static_cast<int>(R.rows());
  }

  detail::PolygonMesherInput input;
  input.rings = rings;
  input.steiner = accepted;
  input.max_area = max_area;
  const double sine = std::sin(options.min_angle_degrees * kPi / 180.0);
  input.shape_bound = sine * sine;
  // Progress estimate: about 0.8 vertices per unit of area / max_area (measured).
  const double expected = std::max(1.0, 0.8 * area / max_area);
  input.step = [&](Index vertices) {
    return !progress || progress(0.1 + 0.85 * std::min(1.0, static_cast<double>(vertices) / expected));
  };
  detail::PolygonMesherOutput out = detail::cgal_mesh_polygon(input);
  if (out.cancelled)
    throw Error(ErrorCode::Cancelled, std::string(what) + " was cancelled");
  checkpoint(progress, 0.95, what);

  DomainMesh mesh;
  mesh.V = std::move(out.V);
  mesh.T = std::move(out.T);
  const Index nc = cage2d.V.rows();
  mesh.control_vertex.resize(nc);
  for (Index i = 0; i < nc; ++i)
    mesh.control_vertex(i) = static_cast<int>(i);
  mesh.steiner_vertex.resize(S.rows());
  for (Index s = 0; s < S.rows(); ++s)
  {
    const int r = steiner_index[static_cast<std::size_t>(s)];
    mesh.steiner_vertex(s) = r < 0 ? -1 : ring_vertices + r;
  }

  const std::vector<BoundaryPlace> place =
    locate_boundary_2d(mesh.T, mesh.V.rows(), rings, ring_offset);
  std::vector<Eigen::Triplet<double>> triplets;
  for (Index v = 0; v < mesh.V.rows(); ++v)
  {
    const BoundaryPlace& b = place[static_cast<std::size_t>(v)];
    if (b.ring < 0)
      continue;
    if (b.ring > 0)
    {
      mesh.hole_boundary_vertices.push_back(static_cast<int>(v));
      continue;
    }
    const Index row = static_cast<Index>(mesh.boundary_vertices.size());
    mesh.boundary_vertices.push_back(static_cast<int>(v));
    if (b.vertex)
    {
      triplets.emplace_back(row, b.edge, 1.0);
      continue;
    }
    const Index i = b.edge, j = (b.edge + 1) % nc;
    const Eigen::Vector2d p = mesh.V.row(v).transpose();
    const double t = detail::closest_on_segment(
      p, Eigen::Vector2d(cage2d.V.row(i).transpose()), Eigen::Vector2d(cage2d.V.row(j).transpose()));
    triplets.emplace_back(row, i, 1.0 - t);
    triplets.emplace_back(row, j, t);
  }
  mesh.boundary_weights.resize(static_cast<Index>(mesh.boundary_vertices.size()), nc);
  mesh.boundary_weights.setFromTriplets(triplets.begin(), triplets.end());
  mesh.seconds = seconds_since(t0);
  checkpoint(progress, 1.0, what);
  return mesh;
}

} // namespace

namespace
{

/// A size bound (area, volume) times 2^@p exponent: it stays positive and finite where it was,
/// so an absurd one is still refused by the mesher's request limit rather than read as "none".
double scaled_size_bound(double bound, int exponent)
{
  if (!(bound > 0.0) || !std::isfinite(bound))
    return bound;
  return std::clamp(std::ldexp(bound, exponent), std::numeric_limits<double>::min(),
    std::numeric_limits<double>::max());
}

/// @p mesh_as_given run on @p cage at a normalised scale (scale_exponent, cage.h), the mesh
/// scaled back: the cage, the Steiner points, the holes (2D) and the size bound (its @p dim-th
/// power) are scaled by 2^k, which is exact.
template <class Options>
DomainMesh mesh_at_normalised_scale(const Cage& cage, int dim, const Options& options,
  double Options::*size_bound,
  DomainMesh (*mesh_as_given)(const Cage&, const Options&, const ProgressCallback&),
  const ProgressCallback& progress)
{
  const int k = cage.V.cols() == dim ? scale_exponent(bounding_box_extent(cage.V)) : 0;
  if (k == 0)
    return mesh_as_given(cage, options, progress);
  validate_cage(cage); // its errors in the caller's units
  const double s = std::ldexp(1.0, k);
  Cage scaled_cage = cage;
  scaled_cage.V *= s;
  Options scaled = options;
  scaled.steiner_points *= s;
  if constexpr (std::is_same_v<Options, PolygonMeshOptions>)
    for (Eigen::MatrixXd& hole : scaled.holes)
      hole *= s;
  scaled.*size_bound = scaled_size_bound(options.*size_bound, dim * k);
  DomainMesh mesh = mesh_as_given(scaled_cage, scaled, progress);
  mesh.V *= std::ldexp(1.0, -k);
  return mesh;
}

} // namespace

DomainMesh mesh_polygon(
  const Cage& cage2d, const PolygonMeshOptions& options, const ProgressCallback& progress)
{
  return mesh_at_normalised_scale(
    cage2d, 2, options, &PolygonMeshOptions::max_area, mesh_polygon_as_given, progress);
}

// --- mesh_closed_surface ----------------------------------------------------------------------

namespace
{

/// mesh_closed_surface at the scale given (see scale_exponent).
DomainMesh mesh_closed_surface_as_given(
  const Cage& cage3d, const SurfaceMeshOptions& options, const ProgressCallback& progress)
{
  const auto t0 = std::chrono::steady_clock::now();
  const char* what = "meshing the closed surface";
  if (cage3d.V.rows() > 0 && cage3d.V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "mesh_closed_surface needs a 3D cage (V #C by 3, F #F by 3), got " +
        std::to_string(cage3d.V.cols()) + " coordinates per vertex",
      "use mesh_polygon for 2D cages");
  validate_cage(cage3d);
  checkpoint(progress, 0.0, what);

  if (!std::isfinite(options.max_volume))
    throw Error(ErrorCode::InvalidArgument, "max_volume must be finite");
  if (options.target_cells < 0)
    throw Error(ErrorCode::InvalidArgument,
      "target_cells must be >= 0 (0 = no volume bound), got " + std::to_string(options.target_cells));
  if (!(options.radius_edge_ratio <= 0.0 ||
        (options.radius_edge_ratio >= kMinRadiusEdgeRatio &&
          options.radius_edge_ratio <= kMaxRadiusEdgeRatio)))
    throw Error(ErrorCode::InvalidArgument,
      "radius_edge_ratio must be <= 0 (no quality refinement) or in [" +
        detail::format_number(kMinRadiusEdgeRatio) + ", " + detail::format_number(kMaxRadiusEdgeRatio) +
        "] (TetGen's refinement may not terminate below " + detail::format_number(kMinRadiusEdgeRatio) +
        "), got " + detail::format_number(options.radius_edge_ratio));
  if (!(options.steiner_tolerance >= 1e-7 && options.steiner_tolerance <= 0.1))
    throw Error(ErrorCode::InvalidArgument,
      "steiner_tolerance must be in [1e-7, 0.1] in 3D (TetGen merges closer points itself), got " +
        detail::format_number(options.steiner_tolerance));
  check_points(options.steiner_points, 3, "the Steiner points");

  const double diameter = cage3d.diameter();
  check_feature_size(cage3d, kMinSurfaceFeatureSize * diameter);

  const double volume = std::abs(signed_measure(cage3d));
  double max_volume = 0.0;
  if (options.max_volume > 0.0)
    max_volume = options.max_volume;
  else if (options.target_cells > 0)
    max_volume = volume / static_cast<double>(options.target_cells);
  if (max_volume > 0.0 && volume / max_volume > kMaxRequestedCells)
    throw Error(ErrorCode::InvalidArgument,
      "max_volume " + detail::format_number(max_volume) + " asks for more than " +
        detail::format_number(volume / max_volume) + " tetrahedra (volume " + detail::format_number(volume) +
        "); the limit is " + detail::format_number(kMaxRequestedCells));

  // Steiner points: inside and away from the surface, merged when close.
  const double tol = options.steiner_tolerance * diameter;
  const Eigen::MatrixXd& S = options.steiner_points;
  std::vector<char> ok(static_cast<std::size_t>(S.rows()), 0);
  if (S.rows() > 0)
  {
    const std::vector<FaceBox> boxes = face_boxes(cage3d, tol);
    const Eigen::RowVector3d lo = cage3d.V.colwise().minCoeff(), hi = cage3d.V.colwise().maxCoeff();
#pragma omp parallel for schedule(dynamic, 16)
    for (Index s = 0; s < S.rows(); ++s)
    {
      const Eigen::Vector3d p = S.row(s).transpose();
      const bool in_box = (p.transpose().array() > lo.array()).all() &&
        (p.transpose().array() < hi.array()).all();
      ok[static_cast<std::size_t>(s)] = in_box &&
        surface_distance_within(cage3d, boxes, p, tol) > tol &&
        std::abs(winding_number(cage3d, p)) > 0.5;
    }
  }
  Eigen::MatrixXd accepted;
  const std::vector<int> steiner_index = merge_points(S, ok, tol, diameter, accepted);
  checkpoint(progress, 0.1, what);

  std::string switches = "pzQ";
  if (options.preserve_boundary)
    switches += "Y";
  if (options.radius_edge_ratio > 0.0)
    switches += "q" + detail::format_number(options.radius_edge_ratio, 17); // digits and '.' only
  if (max_volume > 0.0)
    switches += "a" + detail::format_number(max_volume, 17);
  if (options.max_added_vertices < 0)
    throw_invalid("max_added_vertices must be >= 0 (0: automatic), got " +
      std::to_string(options.max_added_vertices));
  const Index added_cap = options.max_added_vertices > 0
    ? std::min<Index>(options.max_added_vertices, 2147483647)
    : surface_mesh_vertex_cap(
        max_volume > 0.0 ? volume / max_volume : 0.0, cage3d.F.rows(), accepted.rows());
  switches += "S" + std::to_string(added_cap);
  detail::TetgenOutput out = detail::tetgen_tetrahedralize(cage3d.V, cage3d.F, accepted, switches);
  checkpoint(progress, 0.9, what);

  const Index nc = cage3d.V.rows();
  const Index ntg = out.V.rows();
  if (options.radius_edge_ratio > 0.0 && ntg - nc - accepted.rows() >= added_cap)
    throw Error(ErrorCode::NotConverged,
      "TetGen's quality refinement to radius-edge ratio " +
        detail::format_number(options.radius_edge_ratio) + " was still adding vertices after " +
        std::to_string(added_cap) + " (the limit for this cage and size bound): the bound cannot be "
        "met on this cage",
      "raise radius_edge_ratio (1.414 meshes every test cage), or 0 for no quality refinement");
  if (ntg < nc || out.T.rows() == 0)
    throw Error(ErrorCode::Internal,
      "TetGen returned " + std::to_string(ntg) + " vertices and " + std::to_string(out.T.rows()) +
        " tetrahedra for a cage of " + std::to_string(nc) + " vertices");
  for (Index i = 0; i < nc; ++i)
    if (out.V.row(i) != cage3d.V.row(i))
      throw Error(ErrorCode::Internal,
        "TetGen moved or dropped cage vertex " + std::to_string(i) + " " + detail::format_row(cage3d.V, i, 17));

  // New numbering: cage vertices, Steiner points, then TetGen's other used vertices.
  std::vector<int> new_id(static_cast<std::size_t>(ntg), -1);
  std::vector<char> used(static_cast<std::size_t>(ntg), 0);
  for (Index t = 0; t < out.T.rows(); ++t)
    for (int k = 0; k < 4; ++k)
    {
      const int v = out.T(t, k);
      if (v < 0 || v >= ntg)
        throw Error(ErrorCode::Internal, "TetGen returned a tetrahedron with an invalid vertex");
      used[static_cast<std::size_t>(v)] = 1;
    }
  int next = 0;
  for (Index i = 0; i < nc; ++i)
  {
    if (!used[static_cast<std::size_t>(i)])
      throw Error(ErrorCode::Internal,
        "TetGen left cage vertex " + std::to_string(i) + " out of the tetrahedralization");
    new_id[static_cast<std::size_t>(i)] = next++;
  }
  std::unordered_map<std::array<std::int64_t, 3>, int, CellHash> by_coordinates;
  auto key_of = [](const double* x) {
    std::array<std::int64_t, 3> k{};
    for (int c = 0; c < 3; ++c)
    {
      const double v = x[c] == 0.0 ? 0.0 : x[c]; // -0 == +0
      std::int64_t bits;
      static_assert(sizeof bits == sizeof v, "64-bit doubles");
      std::memcpy(&bits, &v, sizeof v);
      k[static_cast<std::size_t>(c)] = bits;
    }
    return k;
  };
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> VT = out.V;
  for (Index i = nc; i < ntg; ++i)
    if (used[static_cast<std::size_t>(i)])
      by_coordinates.emplace(key_of(VT.row(i).data()), static_cast<int>(i));
  std::vector<int> accepted_vertex(static_cast<std::size_t>(accepted.rows()), -1);
  for (Index a = 0; a < accepted.rows(); ++a)
  {
    const Eigen::RowVector3d x = accepted.row(a);
    const auto it = by_coordinates.find(key_of(x.data()));
    if (it == by_coordinates.end() || new_id[static_cast<std::size_t>(it->second)] >= 0)
      continue; // TetGen did not insert it (within its own tolerance of another vertex)
    new_id[static_cast<std::size_t>(it->second)] = next;
    accepted_vertex[static_cast<std::size_t>(a)] = next++;
  }
  for (Index i = nc; i < ntg; ++i)
    if (used[static_cast<std::size_t>(i)] && new_id[static_cast<std::size_t>(i)] < 0)
      new_id[static_cast<std::size_t>(i)] = next++;

  DomainMesh mesh;
  mesh.V.resize(next, 3);
  for (Index i = 0; i < ntg; ++i)
    if (new_id[static_cast<std::size_t>(i)] >= 0)
      mesh.V.row(new_id[static_cast<std::size_t>(i)]) = out.V.row(i);
  mesh.T.resize(out.T.rows(), 4);
  for (Index t = 0; t < out.T.rows(); ++t)
  {
    for (int k = 0; k < 4; ++k)
      mesh.T(t, k) = new_id[static_cast<std::size_t>(out.T(t, k))];
    const Eigen::Vector3d a = row3(mesh.V, mesh.T(t, 0));
    const double det = (row3(mesh.V, mesh.T(t, 1)) - a)
                         .dot((row3(mesh.V, mesh.T(t, 2)) - a).cross(row3(mesh.V, mesh.T(t, 3)) - a));
    if (det < 0.0)
      std::swap(mesh.T(t, 2), mesh.T(t, 3));
  }
  mesh.control_vertex.resize(nc);
  for (Index i = 0; i < nc; ++i)
    mesh.control_vertex(i) = static_cast<int>(i);
  mesh.steiner_vertex.resize(S.rows());
  for (Index s = 0; s < S.rows(); ++s)
  {
    const int r = steiner_index[static_cast<std::size_t>(s)];
    mesh.steiner_vertex(s) = r < 0 ? -1 : accepted_vertex[static_cast<std::size_t>(r)];
  }

  // Boundary vertices and their cage face (TetGen's face markers).
  std::vector<Index> face_of(static_cast<std::size_t>(next), -1);
  std::vector<char> on_boundary(static_cast<std::size_t>(next), 0);
  for (Index f = 0; f < out.boundary_faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      const int old = out.boundary_faces(f, k);
      if (old < 0 || old >= ntg || new_id[static_cast<std::size_t>(old)] < 0)
        throw Error(ErrorCode::Internal, "TetGen returned a boundary face with an invalid vertex");
      const auto v = static_cast<std::size_t>(new_id[static_cast<std::size_t>(old)]);
      on_boundary[v] = 1;
      if (face_of[v] < 0)
        face_of[v] = out.boundary_face_input(f);
    }
  std::vector<Eigen::Triplet<double>> triplets;
  for (int v = 0; v < next; ++v)
  {
    if (!on_boundary[static_cast<std::size_t>(v)])
      continue;
    const Index row = static_cast<Index>(mesh.boundary_vertices.size());
    mesh.boundary_vertices.push_back(v);
    if (v < nc)
    {
      triplets.emplace_back(row, v, 1.0);
      continue;
    }
    const Eigen::Vector3d p = row3(mesh.V, v);
    Index face = face_of[static_cast<std::size_t>(v)];
    if (face < 0) // no marker: the closest cage face
    {
      double best = std::numeric_limits<double>::infinity();
      for (Index f = 0; f < cage3d.F.rows(); ++f)
      {
        const double d = detail::point_triangle_distance(p, row3(cage3d.V, cage3d.F(f, 0)),
          row3(cage3d.V, cage3d.F(f, 1)), row3(cage3d.V, cage3d.F(f, 2)));
        if (d < best)
        {
          best = d;
          face = f;
        }
      }
    }
    Eigen::Vector3d l = detail::closest_on_triangle(p, row3(cage3d.V, cage3d.F(face, 0)),
      row3(cage3d.V, cage3d.F(face, 1)), row3(cage3d.V, cage3d.F(face, 2)));
    l = l.cwiseMax(0.0); // 1 - v - w may round to -1e-16
    l /= l.sum();
    for (int k = 0; k < 3; ++k)
      if (l(k) != 0.0)
        triplets.emplace_back(row, cage3d.F(face, k), l(k));
  }
  for (Index i = 0; i < nc; ++i)
    if (!on_boundary[static_cast<std::size_t>(i)])
      throw Error(ErrorCode::Internal,
        "cage vertex " + std::to_string(i) + " is not on TetGen's boundary faces");
  mesh.boundary_weights.resize(static_cast<Index>(mesh.boundary_vertices.size()), nc);
  mesh.boundary_weights.setFromTriplets(triplets.begin(), triplets.end());
  mesh.seconds = seconds_since(t0);
  checkpoint(progress, 1.0, what);
  return mesh;
}

} // namespace

DomainMesh mesh_closed_surface(
  const Cage& cage3d, const SurfaceMeshOptions& options, const ProgressCallback& progress)
{
  return mesh_at_normalised_scale(cage3d, 3, options, &SurfaceMeshOptions::max_volume,
    mesh_closed_surface_as_given, progress);
}

DomainMesh domain_mesh_from_simplices(const Cage& cage, const Eigen::MatrixXd& V,
  const Eigen::MatrixXi& T, const Eigen::VectorXi& control_vertex, double tolerance)
{
  const int D = static_cast<int>(V.cols());
  if (D != cage.dimension())
    throw Error(ErrorCode::SizeMismatch,
      "mesh vertices have " + std::to_string(D) + " coordinates but the cage is " +
        std::to_string(cage.dimension()) + "D");
  if (T.cols() != D + 1)
    throw Error(ErrorCode::SizeMismatch,
      "a " + std::to_string(D) + "D mesh needs " + std::to_string(D + 1) +
        " vertices per element, got " + std::to_string(T.cols()));
  if (control_vertex.size() != cage.num_controls())
    throw Error(ErrorCode::SizeMismatch,
      "control_vertex has " + std::to_string(control_vertex.size()) +
        " entries but the cage has " + std::to_string(cage.num_controls()) + " vertices");
  const Index nv = V.rows();
  for (Index t = 0; t < T.rows(); ++t)
    for (Index k = 0; k < T.cols(); ++k)
      if (T(t, k) < 0 || T(t, k) >= nv)
        throw_invalid("element " + std::to_string(t) + " refers to vertex " + std::to_string(T(t, k)) +
          ", outside [0, " + std::to_string(nv) + ")");
  const double diameter = cage.diameter();
  for (Index i = 0; i < control_vertex.size(); ++i)
  {
    const int v = control_vertex(i);
    if (v < 0 || v >= nv)
      throw_invalid("control vertex " + std::to_string(i) + " is mesh vertex " + std::to_string(v) +
        ", outside [0, " + std::to_string(nv) + ")");
    if ((V.row(v) - cage.V.row(i)).norm() > tolerance * diameter)
      throw_invalid("mesh vertex " + std::to_string(v) + " is not at cage vertex " + std::to_string(i));
  }
  const std::vector<int> boundary = boundary_vertices(T);
  DomainMesh mesh;
  mesh.V = V;
  mesh.T = T;
  mesh.control_vertex = control_vertex;
  mesh.boundary_vertices = boundary;
  const DenseWeights values = cage_boundary_values(cage, V, boundary, tolerance);
  mesh.boundary_weights = values.sparseView();
  return mesh;
}

DomainMesh domain_mesh_for_cage(const Cage& cage, const Eigen::MatrixXd& V,
  const Eigen::MatrixXi& T, const ProgressCallback& progress)
{
  const int dim = cage.dimension();
  if (T.cols() != dim + 1 || V.cols() != dim)
    throw Error(ErrorCode::InvalidArgument,
      std::string("the domain mesh is made of ") + (T.cols() == 4 ? "tetrahedra" : "triangles") +
        " but the cage is " + std::to_string(dim) + "D: give " +
        (dim == 2 ? "a triangulation of the cage's interior, in its plane"
                  : "a tetrahedralization of the cage's interior"));
  // Each cage vertex is the mesh's boundary vertex at its coordinates.
  constexpr double kMatchTolerance = 1e-6; // relative to the cage diameter
  const double diameter = cage.diameter();
  const double tolerance = kMatchTolerance * diameter;
  const std::vector<int> boundary = boundary_vertices(T);
  const Index nc = cage.num_controls();
  const char* what = "matching the domain mesh to the cage";
  Eigen::VectorXi control(nc);
  for (Index i = 0; i < nc; ++i)
  {
    double best = std::numeric_limits<double>::infinity();
    int at = -1;
    for (int v : boundary)
    {
      const double d = (V.row(v) - cage.V.row(i)).norm();
      if (d < best)
      {
        best = d;
        at = v;
      }
    }
    if (!(best <= tolerance))
    {
      throw Error(ErrorCode::InvalidArgument,
        "the domain mesh does not fit the cage: cage vertex " + std::to_string(i) + " at " +
          detail::format_row(cage.V, i, 7) +
          " is not a boundary vertex of the mesh (the nearest one is " +
          detail::format_number(best / diameter, 3) +
          " x the cage diameter away, allowed 1e-6): give a mesh of this cage's interior that "
          "has the cage vertices as vertices");
    }
    control(i) = at;
    checkpoint(progress, 0.5 * static_cast<double>(i + 1) / static_cast<double>(nc), what);
  }
  DomainMesh mesh = domain_mesh_from_simplices(cage, V, T, control, kMatchTolerance);
  checkpoint(progress, 1.0, what);
  return mesh;
}

} // namespace bary
