#include "core/common/cage.h"

#include "core/detail/cgal_intersections.h"
#include "core/detail/format.h"
#include "core/common/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

namespace bary
{
namespace
{

[[noreturn]] void fail(const std::string& what)
{
  throw Error(ErrorCode::InvalidCage, "invalid cage: " + what);
}

void check_common(const Cage& cage)
{
  const Index n = cage.V.rows();
  if (n == 0)
    throw Error(ErrorCode::EmptyInput, "the cage has no vertices");
  if (cage.V.cols() != 2 && cage.V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "cage vertices must have 2 or 3 coordinates, got " + std::to_string(cage.V.cols()));
  for (Index i = 0; i < n; ++i)
    if (!cage.V.row(i).allFinite())
      throw Error(ErrorCode::NonFinite,
        "cage vertex " + std::to_string(i) + " has a non-finite coordinate " +
          detail::format_row(cage.V, i));
}

void validate_polygon(const Cage& cage, const CageValidationOptions& options)
{
  const Eigen::MatrixXd& V = cage.V;
  const Index n = V.rows();
  if (cage.F.size() != 0)
    throw Error(ErrorCode::SizeMismatch,
      "a 2D cage is a polygon given by its vertices in order; it must not have faces");
  if (n < 3)
    fail("a polygon needs at least 3 vertices, got " + std::to_string(n));
  const double tol = options.degenerate_tolerance * cage.diameter();
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1) % n;
    if ((V.row(j) - V.row(i)).norm() <= tol)
      fail("polygon vertices " + std::to_string(i) + " and " + std::to_string(j) +
        " coincide at " + detail::format_row(V, i) + " (zero-length edge " + std::to_string(i) +
        "); remove the duplicate vertex");
  }
  // All vertices on one line: nothing is enclosed (reported as such, not as the edge overlap
  // it also is).
  double fan = 0.0;
  for (Index i = 1; i + 1 < n; ++i)
    fan += std::abs((V(i, 0) - V(0, 0)) * (V(i + 1, 1) - V(0, 1)) -
      (V(i, 1) - V(0, 1)) * (V(i + 1, 0) - V(0, 0)));
  if (0.5 * fan <= tol * cage.diameter())
    fail("the polygon encloses zero area (all its vertices lie on one line)");
  if (options.check_self_intersections)
  {
    const auto pairs = detail::polygon_self_intersections(V, 1);
    if (!pairs.empty())
    {
      const auto [a, b] = pairs.front();
      fail("the polygon is not simple: edge " + std::to_string(a) + " (vertices " +
        std::to_string(a) + "-" + std::to_string((a + 1) % n) + ") intersects edge " +
        std::to_string(b) + " (vertices " + std::to_string(b) + "-" +
        std::to_string((b + 1) % n) + ")");
    }
  }
  const double area = signed_measure(cage);
  if (std::abs(area) <= tol * cage.diameter())
    fail("the polygon encloses zero area");
}

void validate_triangles(const Cage& cage, const CageValidationOptions& options)
{
  const Eigen::MatrixXd& V = cage.V;
  const Eigen::MatrixXi& F = cage.F;
  const Index n = V.rows();
  if (F.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the 3D cage has no faces");
  if (F.cols() != 3)
    fail("3D cage faces must be triangles, got faces with " + std::to_string(F.cols()) +
      " vertices; triangulate the cage first");
  const std::string face = "face ";
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= n)
        throw Error(ErrorCode::InvalidCage,
          "invalid cage: " + face + std::to_string(f) + " refers to vertex " +
            std::to_string(F(f, k)) + " but the cage has " + std::to_string(n) + " vertices");

  const double diam = cage.diameter();
  const double tol = options.degenerate_tolerance * diam;
  for (Index f = 0; f < F.rows(); ++f)
  {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double twice_area = (b - a).cross(c - a).norm();
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2) || twice_area <= tol * diam)
      fail(face + std::to_string(f) + " (vertices " + std::to_string(F(f, 0)) + ", " +
        std::to_string(F(f, 1)) + ", " + std::to_string(F(f, 2)) +
        ") is degenerate (zero area)");
  }

  // Edges: undirected key -> faces using it, with the direction each face uses.
  struct Use
  {
    Index face;
    bool forward; // face walks the edge from the smaller to the larger vertex index
  };
  std::map<std::pair<int, int>, std::vector<Use>> edges;
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      edges[{ std::min(a, b), std::max(a, b) }].push_back({ f, a < b });
    }
  for (const auto& [key, uses] : edges)
  {
    const std::string edge =
      "edge (" + std::to_string(key.first) + ", " + std::to_string(key.second) + ")";
    if (uses.size() == 1)
      fail("the cage is not closed: " + edge + " belongs to face " +
        std::to_string(uses[0].face) + " only (a hole in the surface)");
    if (uses.size() > 2)
      fail("the cage is not manifold: " + edge + " is shared by " +
        std::to_string(uses.size()) + " faces (" + std::to_string(uses[0].face) + ", " +
        std::to_string(uses[1].face) + ", " + std::to_string(uses[2].face) + ", ...)");
    if (uses[0].forward == uses[1].forward)
      fail("the cage is not consistently oriented: faces " + std::to_string(uses[0].face) +
        " and " + std::to_string(uses[1].face) + " traverse " + edge +
        " in the same direction; flip one of them");
  }

  // Every vertex used, and the faces around each vertex form a single fan (vertex-manifold).
  std::vector<std::vector<std::pair<int, int>>> link(static_cast<std::size_t>(n));
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      link[F(f, k)].emplace_back(F(f, (k + 1) % 3), F(f, (k + 2) % 3));
  for (Index v = 0; v < n; ++v)
  {
    auto& ring = link[static_cast<std::size_t>(v)];
    if (ring.empty())
      fail("vertex " + std::to_string(v) + " " + detail::format_row(V, v) +
        " is not used by any face; remove it or connect it");
    // Walk the oriented link cycle starting at the first face's edge.
    std::map<int, int> next;
    for (const auto& [a, b] : ring)
      next[a] = b;
    std::size_t steps = 0;
    const int start = ring.front().first;
    int cur = start;
    do
    {
      cur = next.at(cur);
      ++steps;
    } while (cur != start && steps <= ring.size());
    if (steps != ring.size())
      fail("the cage is not manifold at vertex " + std::to_string(v) + " " + detail::format_row(V, v) +
        ": its faces form more than one fan (two surface sheets touch there)");
  }

  const double volume = signed_measure(cage);
  if (std::abs(volume) <= tol * diam * diam)
    fail("the cage encloses zero volume");

  if (options.check_self_intersections)
  {
    const auto pairs = detail::triangle_mesh_self_intersections(V, F, 1);
    if (!pairs.empty())
      fail("the cage self-intersects: face " + std::to_string(pairs[0].first) +
        " intersects face " + std::to_string(pairs[0].second));
  }
}

} // namespace

double Cage::diameter() const
{
  if (V.rows() == 0)
    return 0.0;
  // stableNorm: the squared sides of a cage near 1e200 overflow
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).stableNorm();
}

double bounding_box_extent(const Eigen::MatrixXd& V)
{
  if (V.rows() == 0 || V.cols() == 0)
    return 0.0;
  if (!V.allFinite())
    return std::numeric_limits<double>::quiet_NaN();
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
}

int scale_exponent(double extent)
{
  if (!(extent > 0.0) || !std::isfinite(extent) ||
    (extent >= kScaleBandMin && extent <= kScaleBandMax))
    return 0;
  int e = 0;
  std::frexp(extent, &e); // extent = m 2^e, m in [0.5, 1)
  return -e;
}

double signed_measure(const Cage& cage)
{
  const Eigen::MatrixXd& V = cage.V;
  if (cage.dimension() == 2)
  {
    double a = 0.0;
    for (Index i = 0, n = V.rows(); i < n; ++i)
    {
      const Index j = (i + 1) % n;
      a += V(i, 0) * V(j, 1) - V(j, 0) * V(i, 1);
    }
    return 0.5 * a;
  }
  double vol = 0.0;
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d a = V.row(cage.F(f, 0)), b = V.row(cage.F(f, 1)),
                          c = V.row(cage.F(f, 2));
    vol += a.dot(b.cross(c));
  }
  return vol / 6.0;
}

double enclosed_measure(const Cage& cage)
{
  return std::abs(signed_measure(cage));
}

bool is_positively_oriented(const Cage& cage)
{
  return signed_measure(cage) > 0.0;
}

void validate_cage(const Cage& cage, const CageValidationOptions& options)
{
  check_common(cage);
  if (const int k = scale_exponent(bounding_box_extent(cage.V)); k != 0)
  {
    Cage scaled = cage;
    scaled.V *= std::ldexp(1.0, k);
    validate_cage(scaled, options);
    return;
  }
  if (cage.dimension() == 2)
    validate_polygon(cage, options);
  else
    validate_triangles(cage, options);
}

} // namespace bary
