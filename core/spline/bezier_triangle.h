#pragma once
/// @file bezier_triangle.h
/// Polynomials on a triangle in Bernstein-Bézier form (Rodrigues, Stolfi, Gomide, "Editing
/// C1-continuous 2D spline deformations by constrained least squares", 2014, §3.1; Lai and
/// Schumaker, "Spline functions on triangulations", 2007, ch. 2): the basis
/// B_ijk = d!/(i! j! k!) b0^i b1^j b2^k over barycentric coordinates (b0, b1, b2), i + j + k = d,
/// and the operations the spline family needs on a piece: evaluation, directional derivatives,
/// degree elevation, products (the Jacobian determinant), and the coefficients over a
/// sub-triangle (subdivision, for the positivity test of §3.4).
///
/// Coefficients of one piece are stored as the rows of a matrix (bezier_count(d) rows, one
/// column per component: 1 for a scalar spline, 2 for a deformation of the plane), row
/// bezier_index(d, i, j) holding c_ijk (k = d - i - j): i ascending, then j ascending.

#include <Eigen/Core>

#include <array>
#include <vector>

namespace bary
{

/// Number of Bézier coefficients of a piece of degree @p d: (d + 1)(d + 2) / 2.
constexpr int bezier_count(int d) noexcept
{
  return (d + 1) * (d + 2) / 2;
}

/// Row of c_ijk (k = d - i - j) in a piece's coefficient matrix: i ascending, then j ascending.
constexpr int bezier_index(int d, int i, int j) noexcept
{
  return i * (d + 1) - i * (i - 1) / 2 + j;
}

/// The multi-indices (i, j, k) of degree @p d in row order.
std::vector<std::array<int, 3>> bezier_multi_indices(int d);

/// The bezier_count(d) Bernstein polynomials B_ijk at barycentric coordinates @p b, in row order
/// (written to @p out). Sums to 1 when b does.
void bernstein_basis(int d, const Eigen::Vector3d& b, double* out);

/// The piece's value at barycentric coordinates @p b (de Casteljau's algorithm).
/// @param C bezier_count(d) by m coefficients
Eigen::RowVectorXd bezier_evaluate(const Eigen::MatrixXd& C, int d, const Eigen::Vector3d& b);

/// Coefficients (degree d - 1) of the derivative along a barycentric direction @p u
/// (u = the barycentric coordinates of a vector: u0 + u1 + u2 = 0):
/// D_u f = d sum_{|a| = d-1} (u0 c_{a+e0} + u1 c_{a+e1} + u2 c_{a+e2}) B_a.
Eigen::MatrixXd bezier_derivative(const Eigen::MatrixXd& C, int d, const Eigen::Vector3d& u);

/// The same polynomial with degree d + 1 (degree elevation):
/// c'_a = (a0 c_{a-e0} + a1 c_{a-e1} + a2 c_{a-e2}) / (d + 1).
Eigen::MatrixXd bezier_elevate(const Eigen::MatrixXd& C, int d);

/// The product of two scalar pieces of degrees @p m and @p n (column vectors), degree m + n:
/// coefficient of B_g is sum_{a + b = g} C(m, a) C(n, b) / C(m + n, g) p_a q_b.
Eigen::VectorXd bezier_product(const Eigen::VectorXd& p, int m, const Eigen::VectorXd& q, int n);

/// Coefficients of the same polynomial over the sub-triangle whose corners have barycentric
/// coordinates @p a, @p b, @p c in the piece's triangle (blossoming: c'_ijk is the blossom at
/// a (i times), b (j times), c (k times)).
Eigen::MatrixXd bezier_subtriangle(const Eigen::MatrixXd& C, int d, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c);

} // namespace bary
