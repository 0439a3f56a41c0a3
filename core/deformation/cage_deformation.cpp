#include "core/deformation/cage_deformation.h"

#include "core/common/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace bary
{
namespace
{
void check(Index weight_cols, const Eigen::MatrixXd& C)
{
  if (C.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the deformed control points are empty");
  if (weight_cols != C.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the weights have " + std::to_string(weight_cols) + " columns (control points) but " +
        std::to_string(C.rows()) + " deformed control points were given");
  if (!C.allFinite())
    throw Error(ErrorCode::NonFinite, "the deformed control points contain NaN or infinity");
}
} // namespace

Points deform_points(const DenseWeights& W, const Eigen::MatrixXd& C)
{
  check(W.cols(), C);
  return W * C;
}

Points deform_points(const SparseWeights& W, const Eigen::MatrixXd& C)
{
  check(W.cols(), C);
  return W * C;
}

Eigen::MatrixXd green_face_terms(const Cage& rest, const Eigen::MatrixXd& deformed)
{
  const int dim = rest.dimension();
  if (dim != 2 && dim != 3)
    throw Error(ErrorCode::SizeMismatch, "the rest cage must be 2D or 3D");
  check(rest.V.rows(), deformed);
  if (deformed.cols() != dim)
    throw Error(ErrorCode::SizeMismatch,
      "the deformed cage has " + std::to_string(deformed.cols()) + " coordinates but the rest cage is " +
        std::to_string(dim) + "D");
  const Index n = rest.V.rows();
  if (dim == 2)
  {
    Eigen::MatrixXd N(n, 2);
    for (Index j = 0; j < n; ++j)
    {
      const Index k = j + 1 == n ? 0 : j + 1;
      const double len = (rest.V.row(k) - rest.V.row(j)).stableNorm(); // no overflow at 1e300
      const Eigen::RowVector2d e = deformed.row(k) - deformed.row(j);
      N(j, 0) = e(1) / len;
      N(j, 1) = -e(0) / len;
    }
    return N;
  }
  const Index nf = rest.F.rows();
  if (rest.F.cols() != 3 || (nf > 0 && (rest.F.minCoeff() < 0 || rest.F.maxCoeff() >= n)))
    throw Error(ErrorCode::SizeMismatch, "the rest cage's faces must be triangles of its vertices");
  Eigen::MatrixXd N(nf, 3);
  for (Index f = 0; f < nf; ++f)
  {
    const Eigen::Vector3d a = rest.V.row(rest.F(f, 0)), b = rest.V.row(rest.F(f, 1)),
                          c = rest.V.row(rest.F(f, 2));
    const Eigen::Vector3d a2 = deformed.row(rest.F(f, 0)), b2 = deformed.row(rest.F(f, 1)),
                          c2 = deformed.row(rest.F(f, 2));
    // edge vectors divided by their largest coordinate, so that no square over- or
    // underflows at extreme scales (s is a ratio of lengths: the scales come back as L2 / L)
    Eigen::Vector3d u = b - a, v = c - a, u2 = b2 - a2, v2 = c2 - a2;
    const double L = std::max(u.lpNorm<Eigen::Infinity>(), v.lpNorm<Eigen::Infinity>());
    const double L2 = std::max(u2.lpNorm<Eigen::Infinity>(), v2.lpNorm<Eigen::Infinity>());
    if (!(L > 0.0) || !(L2 > 0.0))
    {
      N.row(f).setZero();
      continue;
    }
    u /= L;
    v /= L;
    u2 /= L2;
    v2 /= L2;
    const Eigen::Vector3d cross2 = u2.cross(v2);
    const double area = 0.5 * u.cross(v).norm(), len2 = cross2.norm();
    if (!(len2 > 0.0) || !(area > 0.0))
    {
      N.row(f).setZero();
      continue;
    }
    const double s2 = u2.squaredNorm() * v.squaredNorm() - 2.0 * u2.dot(v2) * u.dot(v) +
      v2.squaredNorm() * u.squaredNorm();
    const double s = std::sqrt(std::max(0.0, s2)) / (std::sqrt(8.0) * area) * (L2 / L);
    N.row(f) = (s / len2) * cross2.transpose();
  }
  return N;
}

Points deform_points_green(const DenseWeights& phi, const DenseWeights& psi, const Cage& rest,
  const Eigen::MatrixXd& deformed)
{
  check(phi.cols(), deformed);
  const Eigen::MatrixXd N = green_face_terms(rest, deformed);
  if (psi.rows() != phi.rows() || psi.cols() != N.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the face coefficients are " + std::to_string(psi.rows()) + " by " + std::to_string(psi.cols()) +
        " but " + std::to_string(phi.rows()) + " points and " + std::to_string(N.rows()) +
        " cage faces need " + std::to_string(phi.rows()) + " by " + std::to_string(N.rows()));
  return phi * deformed + psi * N;
}

SparseWeights sparsify_weights(const DenseWeights& W, double threshold, bool renormalize,
  Index* empty_rows)
{
  std::vector<Eigen::Triplet<double>> entries;
  Index empty = 0;
  for (Index p = 0; p < W.rows(); ++p)
  {
    double sum = 0.0;
    const std::size_t first = entries.size();
    for (Index i = 0; i < W.cols(); ++i)
      if (W(p, i) > threshold)
      {
        entries.emplace_back(static_cast<int>(p), static_cast<int>(i), W(p, i));
        sum += W(p, i);
      }
    if (entries.size() == first)
      ++empty;
    else if (renormalize)
      for (std::size_t k = first; k < entries.size(); ++k)
        entries[k] = Eigen::Triplet<double>(entries[k].row(), entries[k].col(), entries[k].value() / sum);
  }
  SparseWeights S(W.rows(), W.cols());
  S.setFromTriplets(entries.begin(), entries.end());
  if (empty_rows)
    *empty_rows = empty;
  return S;
}

} // namespace bary
