#include "core/deformation/linear_blend_skinning.h"

#include "core/detail/parallel_for.h"
#include "core/common/error.h"

#include <Eigen/Geometry>

#include <cmath>
#include <string>

namespace bary
{
namespace
{

/// Validates the points, the transforms and the weights' shape; returns dim.
Index validate(const Points& X, Index weight_rows, Index weight_cols, const AffineTransforms& transforms,
  int threads)
{
  const Index dim = X.cols();
  if (threads < 0)
    throw Error(ErrorCode::InvalidArgument,
      "threads must be >= 0 (0 = OpenMP's default), got " + std::to_string(threads));
  if (weight_rows != X.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the weights have " + std::to_string(weight_rows) + " rows but there are " +
        std::to_string(X.rows()) + " points");
  if (weight_cols != static_cast<Index>(transforms.size()))
    throw Error(ErrorCode::SizeMismatch,
      "the weights have " + std::to_string(weight_cols) + " columns but there are " +
        std::to_string(transforms.size()) + " transforms (one per handle)");
  for (std::size_t j = 0; j < transforms.size(); ++j)
  {
    const Eigen::MatrixXd& T = transforms[j];
    if (T.rows() != dim || T.cols() != dim + 1)
      throw Error(ErrorCode::SizeMismatch,
        "transform " + std::to_string(j) + " is " + std::to_string(T.rows()) + " by " +
          std::to_string(T.cols()) + ", expected " + std::to_string(dim) + " by " +
          std::to_string(dim + 1) + " ([A | t] for " + std::to_string(dim) + "D points)");
    if (!T.allFinite())
      throw Error(ErrorCode::NonFinite, "transform " + std::to_string(j) + " is not finite");
  }
  for (Index p = 0; p < X.rows(); ++p)
    if (!X.row(p).allFinite())
      throw Error(ErrorCode::NonFinite, "point " + std::to_string(p) + " is not finite");
  return dim;
}

using detail::thread_count;

} // namespace

Points linear_blend_skinning(
  const Points& X, const DenseWeights& W, const AffineTransforms& transforms, int threads)
{
  const Index dim = validate(X, W.rows(), W.cols(), transforms, threads);
  for (Index p = 0; p < W.rows(); ++p)
    if (!W.row(p).allFinite())
      throw Error(ErrorCode::NonFinite, "the weights of point " + std::to_string(p) + " are not finite");
  const Index np = X.rows(), m = W.cols();
  Points Y = Points::Zero(np, dim);
#pragma omp parallel for schedule(static) num_threads(thread_count(threads))
  for (Index p = 0; p < np; ++p)
  {
    Eigen::VectorXd h(dim + 1);
    h.head(dim) = X.row(p).transpose();
    h(dim) = 1.0;
    Eigen::VectorXd y = Eigen::VectorXd::Zero(dim);
    for (Index j = 0; j < m; ++j)
      if (W(p, j) != 0.0)
        y.noalias() += W(p, j) * (transforms[static_cast<std::size_t>(j)] * h);
    Y.row(p) = y.transpose();
  }
  return Y;
}

Points linear_blend_skinning(
  const Points& X, const SparseWeights& W, const AffineTransforms& transforms, int threads)
{
  const Index dim = validate(X, W.rows(), W.cols(), transforms, threads);
  for (Index p = 0; p < W.outerSize(); ++p)
    for (SparseWeights::InnerIterator it(W, p); it; ++it)
      if (!std::isfinite(it.value()))
        throw Error(ErrorCode::NonFinite, "the weights of point " + std::to_string(p) + " are not finite");
  const Index np = X.rows();
  Points Y = Points::Zero(np, dim);
#pragma omp parallel for schedule(static) num_threads(thread_count(threads))
  for (Index p = 0; p < np; ++p)
  {
    Eigen::VectorXd h(dim + 1);
    h.head(dim) = X.row(p).transpose();
    h(dim) = 1.0;
    Eigen::VectorXd y = Eigen::VectorXd::Zero(dim);
    for (SparseWeights::InnerIterator it(W, p); it; ++it)
      y.noalias() += it.value() * (transforms[static_cast<std::size_t>(it.col())] * h);
    Y.row(p) = y.transpose();
  }
  return Y;
}

AffineTransforms transforms_from_pseudo_edges(
  const Points& rest, const Points& posed, const Eigen::MatrixXi& pseudo_edges)
{
  const Index dim = rest.cols(), nh = rest.rows();
  if (dim != 2 && dim != 3)
    throw Error(ErrorCode::SizeMismatch,
      "the handle positions must be 2D or 3D, got " + std::to_string(dim) + " columns");
  if (posed.rows() != nh || posed.cols() != dim)
    throw Error(ErrorCode::SizeMismatch,
      "the posed positions are " + std::to_string(posed.rows()) + " by " +
        std::to_string(posed.cols()) + " but the rest positions are " + std::to_string(nh) +
        " by " + std::to_string(dim));
  if (pseudo_edges.rows() > 0 && pseudo_edges.cols() != 2)
    throw Error(ErrorCode::SizeMismatch,
      "the pseudo-edges must be #E by 2, got " + std::to_string(pseudo_edges.rows()) + " by " +
        std::to_string(pseudo_edges.cols()));
  if (!rest.allFinite() || !posed.allFinite())
    throw Error(ErrorCode::NonFinite, "the handle positions contain NaN or infinity");

  // Per handle: the sum of signed angles (2D) or of aligned quaternions (3D), and the count.
  std::vector<double> angle_sum(static_cast<std::size_t>(nh), 0.0);
  std::vector<Eigen::Vector4d> quaternion_sum(static_cast<std::size_t>(nh), Eigen::Vector4d::Zero());
  std::vector<int> count(static_cast<std::size_t>(nh), 0);
  for (Index e = 0; e < pseudo_edges.rows(); ++e)
  {
    const int a = pseudo_edges(e, 0), b = pseudo_edges(e, 1);
    const std::string name = "pseudo-edge " + std::to_string(e) + " (" + std::to_string(a) +
      ", " + std::to_string(b) + ")";
    if (a < 0 || a >= nh || b < 0 || b >= nh)
      throw Error(ErrorCode::InvalidArgument,
        name + " refers to a handle outside [0, " + std::to_string(nh) + ")");
    if (a == b)
      throw Error(ErrorCode::InvalidArgument, name + " connects a handle to itself");
    const Eigen::VectorXd r = (rest.row(b) - rest.row(a)).transpose();
    const Eigen::VectorXd q = (posed.row(b) - posed.row(a)).transpose();
    if (!(r.norm() > 0.0) || !(q.norm() > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        name + " has zero length " + (r.norm() > 0.0 ? "when posed" : "at rest") +
          ", so it defines no direction");
    for (const int h : { a, b })
    {
      const auto k = static_cast<std::size_t>(h);
      ++count[k];
      if (dim == 2)
        angle_sum[k] += std::atan2(r(0) * q(1) - r(1) * q(0), r.dot(q));
      else
      {
        const Eigen::Quaterniond rotation =
          Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(r), Eigen::Vector3d(q));
        Eigen::Vector4d v = rotation.coeffs();
        if (count[k] > 1 && v.dot(quaternion_sum[k]) < 0.0)
          v = -v; // q and -q are the same rotation: average on one hemisphere
        quaternion_sum[k] += v;
      }
    }
  }

  AffineTransforms transforms(static_cast<std::size_t>(nh));
  for (Index h = 0; h < nh; ++h)
  {
    const auto k = static_cast<std::size_t>(h);
    Eigen::MatrixXd R = Eigen::MatrixXd::Identity(dim, dim);
    if (count[k] > 0 && dim == 2)
    {
      const double theta = angle_sum[k] / count[k];
      R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
    }
    else if (count[k] > 0)
    {
      Eigen::Quaterniond q;
      q.coeffs() = quaternion_sum[k].normalized();
      R = q.toRotationMatrix();
    }
    Eigen::MatrixXd T(dim, dim + 1);
    T.leftCols(dim) = R;
    T.col(dim) = posed.row(h).transpose() - R * rest.row(h).transpose();
    transforms[k] = T;
  }
  return transforms;
}

Eigen::MatrixXd lift_transform(const Eigen::MatrixXd& T)
{
  if (T.rows() == 3 && T.cols() == 4)
    return T;
  if (T.rows() != 2 || T.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "a transform is 2 by 3 (2D) or 3 by 4 (3D), not " + std::to_string(T.rows()) + " by " +
        std::to_string(T.cols()));
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(3, 4);
  L.topLeftCorner(2, 2) = T.leftCols(2);
  L.block(0, 3, 2, 1) = T.col(2);
  L(2, 2) = 1.0;
  return L;
}

} // namespace bary
