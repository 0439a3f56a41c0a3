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

/// A convex polyhedron as its faces, each a polygon ordered counter-clockwise seen from outside,
/// in fixed storage (the clipped tetrahedra below have at most 7 faces of at most 7 points; the
/// capacities leave room, and clip_polyhedron reports an overflow rather than write past them).
struct Polyhedron
{
  static constexpr int max_faces = 10, max_points = 24;
  int faces = 0;
  int size[max_faces] = {};
  Eigen::Vector3d point[max_faces][max_points];

  void add_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
  {
    point[faces][0] = a;
    point[faces][1] = b;
    point[faces][2] = c;
    size[faces++] = 3;
  }
};

/// Volume of a closed polyhedron with outward-oriented faces (divergence theorem, fans from each
/// face's first point; the origin should be near the polyhedron to limit rounding).
double polyhedron_volume(const Polyhedron& P)
{
  double six = 0.0;
  for (int f = 0; f < P.faces; ++f)
    for (int k = 1; k + 1 < P.size[f]; ++k)
      six += P.point[f][0].dot(P.point[f][k].cross(P.point[f][k + 1]));
  return six / 6.0;
}

/// A monotone stand-in for atan2(y, x) (the "diamond angle" in [0, 4)): orders points by angle
/// without a transcendental function.
double pseudo_angle(double y, double x)
{
  const double s = std::abs(x) + std::abs(y);
  if (s == 0.0)
    return 0.0;
  const double r = y / s;
  return x >= 0.0 ? (y >= 0.0 ? r : 4.0 + r) : 2.0 - r;
}

/// P clipped to the half-space n . x <= d (Sutherland-Hodgman on every face, then the cap
/// polygon on the plane, ordered counter-clockwise around n), into @p clipped; @p changed is
/// false (and @p clipped untouched) when P lies in the half-space. Signed distances within
/// @p on_plane of 0 count as on the plane. Returns false if the result would not fit the fixed
/// storage (it always fits for a tetrahedron clipped three times: at most 7 faces; a cap has at
/// most 14 points, each shared one counted twice, and each later clip adds at most one).
bool clip_polyhedron(
  const Polyhedron& P, const Eigen::Vector3d& n, double d, double on_plane, Polyhedron& clipped,
  bool& changed)
{
  bool outside = false;
  for (int f = 0; f < P.faces; ++f)
    for (int k = 0; k < P.size[f]; ++k)
      outside = outside || n.dot(P.point[f][k]) - d > on_plane;
  changed = outside;
  if (!outside)
    return true;
  clipped.faces = 0;
  constexpr int max_cap = 2 * Polyhedron::max_points;
  Eigen::Vector3d cap[max_cap];
  int caps = 0;
  for (int f = 0; f < P.faces; ++f)
  {
    if (clipped.faces == Polyhedron::max_faces)
      return false;
    Eigen::Vector3d* g = clipped.point[clipped.faces];
    int points = 0;
    const int m = P.size[f];
    for (int k = 0; k < m; ++k)
    {
      const Eigen::Vector3d& a = P.point[f][k];
      const Eigen::Vector3d& b = P.point[f][(k + 1) % m];
      const double sa = n.dot(a) - d, sb = n.dot(b) - d;
      if (points + 2 > Polyhedron::max_points || caps + 2 > max_cap)
        return false;
      if (sa <= on_plane)
      {
        g[points++] = a;
        if (sa >= -on_plane)
          cap[caps++] = a;
      }
      if ((sa < -on_plane && sb > on_plane) || (sa > on_plane && sb < -on_plane))
      {
        const Eigen::Vector3d x = a + (sa / (sa - sb)) * (b - a);
        g[points++] = x;
        cap[caps++] = x;
      }
    }
    if (points >= 3)
      clipped.size[clipped.faces++] = points;
  }
  if (caps >= 3)
  {
    if (clipped.faces == Polyhedron::max_faces || caps > Polyhedron::max_points)
      return false;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int k = 0; k < caps; ++k)
      centre += cap[k];
    centre /= static_cast<double>(caps);
    const Eigen::Vector3d axis = n.normalized();
    const Eigen::Vector3d u = (std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                        : Eigen::Vector3d::UnitY())
                                .cross(axis)
                                .normalized();
    const Eigen::Vector3d v = axis.cross(u);
    double angle[max_cap];
    int order[max_cap];
    for (int k = 0; k < caps; ++k)
    {
      angle[k] = pseudo_angle((cap[k] - centre).dot(v), (cap[k] - centre).dot(u));
      order[k] = k;
    }
    // Insertion sort by angle (a handful of points), stable like the points' order.
    for (int k = 1; k < caps; ++k)
      for (int q = k; q > 0 && angle[order[q]] < angle[order[q - 1]]; --q)
        std::swap(order[q], order[q - 1]);
    for (int k = 0; k < caps; ++k)
      clipped.point[clipped.faces][k] = cap[order[k]];
    clipped.size[clipped.faces++] = caps;
  }
  return true;
}

/// The circumcentric parts of a well-centred tetrahedron @p p (its circumcentre inside or on
/// it, every face's circumcentre inside or on the face: then the part nearest to each corner is
/// its circumcentric part), in closed form: corner i's part is bounded by the three faces
/// through p_i and by a quadrilateral (m_ij, c_ijk, c, c_ijl) in the bisector plane of each edge
/// ij (edge midpoint, the circumcentres of the two faces on ij, the tetrahedron's
/// circumcentre), |p_j - p_i| / 2 from p_i, so by the divergence theorem it is the sum over j of
/// |p_j - p_i| / 6 times that quadrilateral's area. Returns false, and leaves @p part alone,
/// when the tetrahedron is not well-centred (the caller clips instead).
bool well_centred_voronoi_volumes(const std::array<Eigen::Vector3d, 4>& p, std::array<double, 4>& part)
{
  // Every face non-obtuse (contains its circumcentre): at each corner of each face the two
  // edges make a non-negative dot product.
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      for (std::size_t k = j + 1; k < 4; ++k)
        if (j != i && k != i && (p[j] - p[i]).dot(p[k] - p[i]) < 0.0)
          return false;
  // The circumcentre c, relative to p_0: 2 (p_k - p_0) . c = |p_k - p_0|^2, k = 1, 2, 3.
  const Eigen::Vector3d a = p[1] - p[0], b = p[2] - p[0], d = p[3] - p[0];
  const double six = a.dot(b.cross(d)); // 6 x the signed volume
  if (six == 0.0)
    return false;
  const Eigen::Vector3d c = p[0] +
    (a.squaredNorm() * b.cross(d) + b.squaredNorm() * d.cross(a) + d.squaredNorm() * a.cross(b)) /
      (2.0 * six);
  // Inside or on: on the inner side of every face plane, as the opposite corner is.
  for (std::size_t l = 0; l < 4; ++l)
  {
    const std::size_t i = (l + 1) % 4, j = (l + 2) % 4, k = (l + 3) % 4;
    const Eigen::Vector3d normal = (p[j] - p[i]).cross(p[k] - p[i]);
    if (normal.dot(c - p[i]) * normal.dot(p[l] - p[i]) < 0.0)
      return false;
  }
  // Circumcentre of face (i, j, k), relative to p_i: ((|u|^2 v - |v|^2 u) x (u x v)) / (2 |u x v|^2).
  auto face_centre = [&p](std::size_t i, std::size_t j, std::size_t k) {
    const Eigen::Vector3d u = p[j] - p[i], v = p[k] - p[i], w = u.cross(v);
    return Eigen::Vector3d(
      p[i] + (u.squaredNorm() * v - v.squaredNorm() * u).cross(w) / (2.0 * w.squaredNorm()));
  };
  std::array<double, 4> result{};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
    {
      if (j == i)
        continue;
      // The two other corners k, l: the faces (i, j, k) and (i, j, l) share the edge ij.
      std::size_t k = 0;
      while (k == i || k == j)
        ++k;
      const std::size_t l = 6 - i - j - k;
      const Eigen::Vector3d m = 0.5 * (p[i] + p[j]);
      const Eigen::Vector3d ck = face_centre(i, j, k) - m, cl = face_centre(i, j, l) - m;
      const Eigen::Vector3d cm = c - m;
      const double area = 0.5 * (ck.cross(cm).norm() + cm.cross(cl).norm());
      result[i] += (p[j] - p[i]).norm() / 6.0 * area;
    }
  part = result;
  return true;
}

/// The part of tetrahedron t (volume @p volume) nearer to each corner than to its other three
/// corners (see MassMatrixType::Voronoi), scaled so that the four parts sum to @p volume
/// exactly (they do up to rounding): in closed form when the tetrahedron is well-centred, else
/// by clipping it with the bisector planes.
std::array<double, 4> tetrahedron_voronoi_volumes(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t, double volume)
{
  std::array<Eigen::Vector3d, 4> p;
  for (int i = 0; i < 4; ++i)
    p[static_cast<std::size_t>(i)] = V.row(T(t, i)).transpose();
  std::array<double, 4> part{};
  double sum = 0.0;
  if (well_centred_voronoi_volumes(p, part))
  {
    for (const double v : part)
      sum += v;
    for (double& v : part)
      v *= volume / sum;
    return part;
  }
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
    Polyhedron buffer[2];
    int current = 0;
    buffer[0].add_triangle(q[0], q[2], q[1]);
    buffer[0].add_triangle(q[0], q[1], q[3]);
    buffer[0].add_triangle(q[0], q[3], q[2]);
    buffer[0].add_triangle(q[1], q[2], q[3]);
    for (std::size_t j = 0; j < 4; ++j)
      if (j != i)
      {
        // Nearer to corner i (the origin) than to corner j: n . x <= |n|^2 / 2, n = p_j - p_i.
        const Eigen::Vector3d n = p[j] - p[i];
        const double on_plane = 64.0 * std::numeric_limits<double>::epsilon() * h * n.norm();
        bool changed = false;
        if (!clip_polyhedron(buffer[current], n, 0.5 * n.squaredNorm(), on_plane,
              buffer[1 - current], changed))
          throw Error(ErrorCode::Internal,
            "clipping tetrahedron " + std::to_string(t) + " for its Voronoi volumes overflowed");
        if (changed)
          current = 1 - current;
      }
    part[i] = std::max(0.0, polyhedron_volume(buffer[current]));
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
