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
