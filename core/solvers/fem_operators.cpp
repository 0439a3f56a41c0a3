#include "core/solvers/fem_operators.h"

#include "core/detail/format.h"
#include "core/common/error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <array>
#include <utility>
#include <vector>

namespace bary
{
namespace
{

/// Geometry of one element: its unsigned volume and the gradients of its barycentric
/// coordinates (column i = grad lambda_i, the first dim rows are used).
struct ElementGeometry
{
  double volume = 0.0;
  Eigen::Matrix<double, 3, 4> grad = Eigen::Matrix<double, 3, 4>::Zero();
};

std::string describe_element(const Eigen::MatrixXi& T, Index t)
{
  return "element " + std::to_string(t) + " (vertices " + detail::format_index_row(T, t) + ")";
}

const char* element_noun(const Eigen::MatrixXi& T)
{
  return T.cols() == 3 ? "triangle" : "tetrahedron";
}

/// Shapes, index ranges and finiteness (see the file comment of fem_operators.h).
void validate_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  if (T.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no elements (T has no rows)");
  if (T.cols() != 3 && T.cols() != 4)
    throw Error(ErrorCode::SizeMismatch,
      "elements must be triangles (T with 3 columns) or tetrahedra (4 columns), got " +
        std::to_string(T.cols()) + " columns");
  if (V.cols() != 2 && V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "mesh vertices must have 2 or 3 coordinates, got " + std::to_string(V.cols()));
  if (T.cols() == 4 && V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "tetrahedra need 3D vertices (V with 3 columns), got " + std::to_string(V.cols()) +
        " columns");
  for (Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite())
    {
      std::ostringstream s;
      s << "mesh vertex " << i << " has a non-finite coordinate (" << V.row(i) << ")";
      throw Error(ErrorCode::NonFinite, s.str());
    }
  const Index n = V.rows();
  for (Index t = 0; t < T.rows(); ++t)
    for (Index k = 0; k < T.cols(); ++k)
      if (T(t, k) < 0 || T(t, k) >= n)
        throw Error(ErrorCode::InvalidArgument,
          describe_element(T, t) + " refers to vertex " + std::to_string(T(t, k)) +
            ", outside [0, " + std::to_string(n) + "): the mesh has " + std::to_string(n) +
            " vertices");
}

[[noreturn]] void throw_degenerate(
  const Eigen::MatrixXi& T, Index t, double volume, double longest_edge)
{
  std::ostringstream s;
  s << describe_element(T, t) << " is a degenerate " << element_noun(T) << ": its "
    << (T.cols() == 3 ? "area" : "volume") << " is " << volume << " for a longest edge of "
    << longest_edge
    << " (collinear/coplanar or repeated vertices); remove it or repair the mesh";
  throw Error(ErrorCode::InvalidArgument, s.str());
}

/// Volume and barycentric gradients of element t. Throws for a degenerate element.
ElementGeometry element_geometry(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t)
{
  const int dim = static_cast<int>(V.cols());
  const int d = static_cast<int>(T.cols()) - 1;
  ElementGeometry g;

  // Edge vectors from vertex 0 (columns of J) and the longest edge, for the degeneracy test.
  Eigen::Matrix<double, 3, 3> J = Eigen::Matrix<double, 3, 3>::Zero();
  const Eigen::RowVectorXd p0 = V.row(T(t, 0));
  for (int i = 1; i <= d; ++i)
    J.col(i - 1).head(dim) = (V.row(T(t, i)) - p0).transpose();
  double h2 = 0.0;
  for (int i = 0; i <= d; ++i)
    for (int j = i + 1; j <= d; ++j)
      h2 = std::max(h2, (V.row(T(t, i)) - V.row(T(t, j))).squaredNorm());
  const double h = std::sqrt(h2);
  const double tolerance = 64.0 * std::numeric_limits<double>::epsilon() * std::pow(h, d);

  if (d == dim)
  {
    // Full-dimensional: grad lambda_i (i >= 1) is row i-1 of J^-1.
    double det = 0.0;
    if (d == 2)
    {
      const Eigen::Matrix2d J2 = J.topLeftCorner<2, 2>();
      det = J2.determinant();
      g.volume = std::abs(det) / 2.0;
      if (!(g.volume > tolerance))
        throw_degenerate(T, t, g.volume, h);
      g.grad.block<2, 2>(0, 1) = J2.inverse().transpose();
    }
    else
    {
      det = J.determinant();
      g.volume = std::abs(det) / 6.0;
      if (!(g.volume > tolerance))
        throw_degenerate(T, t, g.volume, h);
      g.grad.block<3, 3>(0, 1) = J.inverse().transpose();
    }
  }
  else
  {
    // Surface triangle in 3D: intrinsic, through the metric J^T J; det(J^T J) = |e1 x e2|^2
    // (Lagrange's identity) is taken from the cross product, which does not cancel.
    const Eigen::Vector3d e1 = J.col(0), e2 = J.col(1);
    const double cross2 = e1.cross(e2).squaredNorm();
    g.volume = std::sqrt(cross2) / 2.0;
    if (!(g.volume > tolerance))
      throw_degenerate(T, t, g.volume, h);
    const double g11 = e1.squaredNorm(), g12 = e1.dot(e2), g22 = e2.squaredNorm();
    // Columns of J (J^T J)^-1.
    g.grad.col(1) = (g22 * e1 - g12 * e2) / cross2;
    g.grad.col(2) = (g11 * e2 - g12 * e1) / cross2;
  }
  g.grad.col(0) = -g.grad.block(0, 1, 3, d).rowwise().sum();
  return g;
}

/// Meyer et al. 2003's mixed (Voronoi) area of the three corners of triangle t, whose area is
/// @p area (see MassMatrixType::Voronoi). Uses the squared edge lengths only, so planar and
/// surface triangles are treated alike.
std::array<double, 3> mixed_voronoi_areas(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t, double area)
{
  double l2[3]; // squared length of the edge opposite corner i
  for (int i = 0; i < 3; ++i)
    l2[i] = (V.row(T(t, (i + 1) % 3)) - V.row(T(t, (i + 2) % 3))).squaredNorm();
  std::array<double, 3> part{};
  for (int i = 0; i < 3; ++i)
    if (l2[i] > l2[(i + 1) % 3] + l2[(i + 2) % 3]) // obtuse at corner i
    {
      part.fill(area / 4.0);
      part[static_cast<std::size_t>(i)] = area / 2.0;
      return part;
    }
  // cot(angle i) = (l2_j + l2_k - l2_i) / (4 area); corner i's circumcentric part is
  // (|e_ij|^2 cot(angle k) + |e_ik|^2 cot(angle j)) / 8, |e_ij|^2 = l2_k.
  double cot[3];
  for (int i = 0; i < 3; ++i)
    cot[i] = (l2[(i + 1) % 3] + l2[(i + 2) % 3] - l2[i]) / (4.0 * area);
  for (int i = 0; i < 3; ++i)
  {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    part[static_cast<std::size_t>(i)] = (l2[k] * cot[k] + l2[j] * cot[j]) / 8.0;
  }
  return part;
}

/// A convex polyhedron as its faces, each a polygon ordered counter-clockwise seen from outside.
using Polyhedron = std::vector<std::vector<Eigen::Vector3d>>;

/// Volume of a closed polyhedron with outward-oriented faces (divergence theorem, fans from each
/// face's first point; the origin should be near the polyhedron to limit rounding).
double polyhedron_volume(const Polyhedron& P)
{
  double six = 0.0;
  for (const auto& f : P)
    for (std::size_t k = 1; k + 1 < f.size(); ++k)
      six += f[0].dot(f[k].cross(f[k + 1]));
  return six / 6.0;
}

/// P clipped to the half-space n . x <= d (Sutherland-Hodgman on every face, then the cap
/// polygon on the plane, ordered counter-clockwise around n). Signed distances within
/// @p on_plane of 0 count as on the plane.
Polyhedron clip_polyhedron(const Polyhedron& P, const Eigen::Vector3d& n, double d, double on_plane)
{
  bool outside = false;
  for (const auto& f : P)
    for (const auto& p : f)
      outside = outside || n.dot(p) - d > on_plane;
  if (!outside)
    return P;
  Polyhedron clipped;
  std::vector<Eigen::Vector3d> cap;
  for (const auto& f : P)
  {
    std::vector<Eigen::Vector3d> g;
    for (std::size_t k = 0; k < f.size(); ++k)
    {
      const Eigen::Vector3d& a = f[k];
      const Eigen::Vector3d& b = f[(k + 1) % f.size()];
      const double sa = n.dot(a) - d, sb = n.dot(b) - d;
      if (sa <= on_plane)
      {
        g.push_back(a);
        if (sa >= -on_plane)
          cap.push_back(a);
      }
      if ((sa < -on_plane && sb > on_plane) || (sa > on_plane && sb < -on_plane))
      {
        const Eigen::Vector3d x = a + (sa / (sa - sb)) * (b - a);
        g.push_back(x);
        cap.push_back(x);
      }
    }
    if (g.size() >= 3)
      clipped.push_back(std::move(g));
  }
  if (cap.size() >= 3)
  {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& p : cap)
      centre += p;
    centre /= static_cast<double>(cap.size());
    const Eigen::Vector3d axis = n.normalized();
    const Eigen::Vector3d u = (std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                        : Eigen::Vector3d::UnitY())
                                .cross(axis)
                                .normalized();
    const Eigen::Vector3d v = axis.cross(u);
    std::vector<std::pair<double, Eigen::Vector3d>> ordered;
    ordered.reserve(cap.size());
    for (const auto& p : cap)
      ordered.emplace_back(std::atan2((p - centre).dot(v), (p - centre).dot(u)), p);
    std::sort(ordered.begin(), ordered.end(),
      [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Eigen::Vector3d> face;
    face.reserve(ordered.size());
    for (const auto& [angle, p] : ordered)
      face.push_back(p);
    clipped.push_back(std::move(face));
  }
  return clipped;
}

/// The part of tetrahedron t (volume @p volume) nearer to each corner than to its other three
/// corners (see MassMatrixType::Voronoi), scaled so that the four parts sum to @p volume
/// exactly (they do up to rounding).
std::array<double, 4> tetrahedron_voronoi_volumes(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t, double volume)
{
  std::array<Eigen::Vector3d, 4> p;
  for (int i = 0; i < 4; ++i)
    p[static_cast<std::size_t>(i)] = V.row(T(t, i)).transpose();
  std::array<double, 4> part{};
  double sum = 0.0;
  for (std::size_t i = 0; i < 4; ++i)
  {
    // Corners relative to corner i (less rounding in the volume formula).
    std::array<Eigen::Vector3d, 4> q;
    double h = 0.0;
    for (std::size_t k = 0; k < 4; ++k)
    {
      q[k] = p[k] - p[i];
      h = std::max(h, q[k].norm());
    }
    if ((q[1] - q[0]).dot((q[2] - q[0]).cross(q[3] - q[0])) < 0.0)
      std::swap(q[1], q[2]); // positively oriented: the faces below point outwards
    Polyhedron P = { { q[0], q[2], q[1] }, { q[0], q[1], q[3] }, { q[0], q[3], q[2] },
      { q[1], q[2], q[3] } };
    for (std::size_t j = 0; j < 4; ++j)
      if (j != i)
      {
        // Nearer to corner i (the origin) than to corner j: n . x <= |n|^2 / 2, n = p_j - p_i.
        const Eigen::Vector3d n = p[j] - p[i];
        const double on_plane = 64.0 * std::numeric_limits<double>::epsilon() * h * n.norm();
        P = clip_polyhedron(P, n, 0.5 * n.squaredNorm(), on_plane);
      }
    part[i] = std::max(0.0, polyhedron_volume(P));
    sum += part[i];
  }
  for (double& v : part)
    v *= volume / sum;
  return part;
}

} // namespace

Eigen::VectorXd simplex_volumes(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  validate_mesh(V, T);
  Eigen::VectorXd vol(T.rows());
  for (Index t = 0; t < T.rows(); ++t)
    vol(t) = element_geometry(V, T, t).volume;
  return vol;
}

Eigen::SparseMatrix<double> stiffness_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  validate_mesh(V, T);
  const int n = static_cast<int>(T.cols());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(T.rows() * n * n));
  for (Index t = 0; t < T.rows(); ++t)
  {
    const ElementGeometry g = element_geometry(V, T, t);
    double diagonal[4] = { 0.0, 0.0, 0.0, 0.0 };
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
      {
        // The same value goes to (i, j) and (j, i), so K is exactly symmetric.
        const double k = g.volume * g.grad.col(i).dot(g.grad.col(j));
        triplets.emplace_back(T(t, i), T(t, j), k);
        triplets.emplace_back(T(t, j), T(t, i), k);
        diagonal[i] -= k;
        diagonal[j] -= k;
      }
    for (int i = 0; i < n; ++i)
      triplets.emplace_back(T(t, i), T(t, i), diagonal[i]);
  }
  Eigen::SparseMatrix<double> K(V.rows(), V.rows());
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

Eigen::SparseMatrix<double> mass_matrix(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, MassMatrixType type)
{
  validate_mesh(V, T);
  const int n = static_cast<int>(T.cols());
  const int d = n - 1;
  std::vector<Eigen::Triplet<double>> triplets;
  if (type == MassMatrixType::Barycentric)
  {
    triplets.reserve(static_cast<std::size_t>(T.rows() * n));
    for (Index t = 0; t < T.rows(); ++t)
    {
      const double share = element_geometry(V, T, t).volume / n;
      for (int i = 0; i < n; ++i)
        triplets.emplace_back(T(t, i), T(t, i), share);
    }
  }
  else if (type == MassMatrixType::Full)
  {
    // Integral of lambda_i lambda_j over a d-simplex = vol (1 + delta_ij) d! / (d + 2)!.
    const double factor = d == 2 ? 1.0 / 12.0 : 1.0 / 20.0;
    triplets.reserve(static_cast<std::size_t>(T.rows() * n * n));
    for (Index t = 0; t < T.rows(); ++t)
    {
      const double off = element_geometry(V, T, t).volume * factor;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          triplets.emplace_back(T(t, i), T(t, j), i == j ? 2.0 * off : off);
    }
  }
  else if (type == MassMatrixType::Voronoi)
  {
    triplets.reserve(static_cast<std::size_t>(T.rows() * n));
    for (Index t = 0; t < T.rows(); ++t)
    {
      const double volume = element_geometry(V, T, t).volume; // validates the element
      if (n == 3)
      {
        const std::array<double, 3> part = mixed_voronoi_areas(V, T, t, volume);
        for (int i = 0; i < 3; ++i)
          triplets.emplace_back(T(t, i), T(t, i), part[static_cast<std::size_t>(i)]);
      }
      else
      {
        const std::array<double, 4> part = tetrahedron_voronoi_volumes(V, T, t, volume);
        for (int i = 0; i < 4; ++i)
          triplets.emplace_back(T(t, i), T(t, i), part[static_cast<std::size_t>(i)]);
      }
    }
  }
  else
    throw Error(ErrorCode::InvalidArgument, "unknown mass matrix type");
  Eigen::SparseMatrix<double> M(V.rows(), V.rows());
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

Eigen::SparseMatrix<double> gradient_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  validate_mesh(V, T);
  const int n = static_cast<int>(T.cols());
  const Index dim = V.cols();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(T.rows() * n * dim));
  for (Index t = 0; t < T.rows(); ++t)
  {
    const ElementGeometry g = element_geometry(V, T, t);
    for (Index k = 0; k < dim; ++k)
      for (int i = 0; i < n; ++i)
        triplets.emplace_back(t * dim + k, T(t, i), g.grad(k, i));
  }
  Eigen::SparseMatrix<double> G(T.rows() * dim, V.rows());
  G.setFromTriplets(triplets.begin(), triplets.end());
  return G;
}

Eigen::VectorXi connected_components(Index n, const Eigen::MatrixXi& T)
{
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&parent](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
    {
      parent[static_cast<std::size_t>(v)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
      v = parent[static_cast<std::size_t>(v)];
    }
    return v;
  };
  for (Index t = 0; t < T.rows(); ++t)
    for (Index k = 1; k < T.cols(); ++k)
    {
      const int a = find(T(t, 0)), b = find(T(t, k));
      if (a != b)
        parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  Eigen::VectorXi component(n);
  std::vector<int> id(static_cast<std::size_t>(n), -1);
  int next = 0;
  for (Index v = 0; v < n; ++v)
  {
    const int root = find(static_cast<int>(v));
    if (id[static_cast<std::size_t>(root)] < 0)
      id[static_cast<std::size_t>(root)] = next++;
    component(v) = id[static_cast<std::size_t>(root)];
  }
  return component;
}

std::vector<int> boundary_vertices(const Eigen::MatrixXi& T)
{
  const Index corners = T.cols();
  if (T.rows() > 0 && (corners < 2 || corners > 4))
    throw Error(ErrorCode::SizeMismatch,
      "the elements have " + std::to_string(corners) +
        " vertices; a simplicial mesh has 3 (triangles) or 4 (tetrahedra)");
  // every facet of every element, its vertices sorted; a boundary facet occurs once
  std::vector<std::array<int, 3>> facets;
  facets.reserve(static_cast<std::size_t>(T.rows() * corners));
  for (Index t = 0; t < T.rows(); ++t)
    for (Index skip = 0; skip < corners; ++skip)
    {
      std::array<int, 3> f{ -1, -1, -1 };
      int c = 0;
      for (Index k = 0; k < corners; ++k)
        if (k != skip)
          f[static_cast<std::size_t>(c++)] = T(t, k);
      // sort the c vertices (a network: std::sort on the array trips GCC 12's -Warray-bounds)
      if (c >= 2 && f[0] > f[1])
        std::swap(f[0], f[1]);
      if (c == 3)
      {
        if (f[1] > f[2])
          std::swap(f[1], f[2]);
        if (f[0] > f[1])
          std::swap(f[0], f[1]);
      }
      facets.push_back(f);
    }
  std::sort(facets.begin(), facets.end());
  std::vector<int> boundary;
  for (std::size_t i = 0; i < facets.size();)
  {
    std::size_t j = i;
    while (j < facets.size() && facets[j] == facets[i])
      ++j;
    if (j - i == 1)
      for (int v : facets[i])
        if (v >= 0)
          boundary.push_back(v);
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
  return boundary;
}

} // namespace bary
