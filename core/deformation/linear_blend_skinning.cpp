#include "core/deformation/linear_blend_skinning.h"

#include "core/detail/parallel_for.h"
#include "core/detail/simd.h"
#include "core/common/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

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
  return dim;
}

using detail::thread_count;

} // namespace

namespace
{

// The skinning kernel. Per point, M = sum_j W(p, j) [A_j | t_j] is accumulated first, then
// x' = M [x; 1]: the flops of Eq. (1) as a matrix product, with no allocation, no per-handle
// matrix-vector product and one pass over the weights. Each transform is packed as D rows of
// four doubles, (A_r0, A_r1, A_r2, t_r) in 3D and (A_r0, A_r1, 0, t_r) in 2D, so a row is one
// 4-wide vector (GCC's vector extension: one AVX2 register, or two SSE2 ones in the portable
// build) and a weight costs D vector multiply-adds; two sets of accumulators (even and odd
// stored weights) keep the multiply-adds independent. Written once as an always-inline
// template, compiled for AVX2+FMA and portably (detail/simd.h); a point's result does not
// depend on the thread that computes it.
using v4d = double __attribute__((vector_size(32)));

/// v += w * (the 4 doubles at p); by reference, so no vector crosses a function boundary.
BARY_ALWAYS_INLINE void add_scaled(v4d& v, double w, const double* p)
{
  v4d t;
  std::memcpy(&t, p, sizeof t);
  v += w * t;
}

/// The transforms packed as D rows of 4 doubles each.
std::vector<double> pack_transforms(const AffineTransforms& transforms, int D)
{
  std::vector<double> T(transforms.size() * static_cast<std::size_t>(4 * D), 0.0);
  for (std::size_t j = 0; j < transforms.size(); ++j)
    for (int r = 0; r < D; ++r)
    {
      double* row = T.data() + j * static_cast<std::size_t>(4 * D) + 4 * r;
      for (int c = 0; c < D; ++c)
        row[c] = transforms[j](r, c);
      row[3] = transforms[j](r, D);
    }
  return T;
}

template <int D>
BARY_ALWAYS_INLINE void apply_blend(const v4d* M0, const v4d* M1, const double* X, Index np,
  Index p, double* Y)
{
  v4d h = { 0.0, 0.0, 0.0, 1.0 };
  for (int d = 0; d < D; ++d)
    h[d] = X[d * np + p];
  for (int r = 0; r < D; ++r)
  {
    const v4d t = (M0[r] + M1[r]) * h;
    Y[r * np + p] = (t[0] + t[1]) + (t[2] + t[3]);
  }
}

template <int D>
BARY_ALWAYS_INLINE void skin_dense(const double* X, Index np, const double* W, Index m,
  const double* T, double* Y, Index begin, Index end)
{
  for (Index p = begin; p < end; ++p)
  {
    v4d M0[D], M1[D];
    for (int r = 0; r < D; ++r)
      M0[r] = M1[r] = v4d{ 0.0, 0.0, 0.0, 0.0 };
    const double* w = W + p * m;
    Index j = 0;
    for (; j + 1 < m; j += 2)
    {
      const double* T0 = T + j * 4 * D;
      const double* T1 = T0 + 4 * D;
      for (int r = 0; r < D; ++r)
      {
        add_scaled(M0[r], w[j], T0 + 4 * r);
        add_scaled(M1[r], w[j + 1], T1 + 4 * r);
      }
    }
    if (j < m)
      for (int r = 0; r < D; ++r)
        add_scaled(M0[r], w[j], T + j * 4 * D + 4 * r);
    apply_blend<D>(M0, M1, X, np, p, Y);
  }
}

template <int D>
BARY_ALWAYS_INLINE void skin_sparse(const double* X, Index np, const SparseWeights& W,
  const double* T, double* Y, Index begin, Index end)
{
  const auto* outer = W.outerIndexPtr();
  const auto* inner = W.innerIndexPtr();
  const double* values = W.valuePtr();
  const auto* nnz = W.innerNonZeroPtr(); // null when compressed
  for (Index p = begin; p < end; ++p)
  {
    v4d M0[D], M1[D];
    for (int r = 0; r < D; ++r)
      M0[r] = M1[r] = v4d{ 0.0, 0.0, 0.0, 0.0 };
    const Index first = outer[p];
    const Index last = nnz ? first + nnz[p] : outer[p + 1];
    Index e = first;
    for (; e + 1 < last; e += 2)
    {
      const double* T0 = T + static_cast<Index>(inner[e]) * 4 * D;
      const double* T1 = T + static_cast<Index>(inner[e + 1]) * 4 * D;
      for (int r = 0; r < D; ++r)
      {
        add_scaled(M0[r], values[e], T0 + 4 * r);
        add_scaled(M1[r], values[e + 1], T1 + 4 * r);
      }
    }
    if (e < last)
      for (int r = 0; r < D; ++r)
        add_scaled(M0[r], values[e], T + static_cast<Index>(inner[e]) * 4 * D + 4 * r);
    apply_blend<D>(M0, M1, X, np, p, Y);
  }
}

template <int D>
BARY_TARGET_AVX2 void skin_dense_avx2(const double* X, Index np, const double* W, Index m,
  const double* T, double* Y, Index begin, Index end)
{
  skin_dense<D>(X, np, W, m, T, Y, begin, end);
}

template <int D>
void skin_dense_portable(const double* X, Index np, const double* W, Index m, const double* T,
  double* Y, Index begin, Index end)
{
  skin_dense<D>(X, np, W, m, T, Y, begin, end);
}

template <int D>
BARY_TARGET_AVX2 void skin_sparse_avx2(const double* X, Index np, const SparseWeights& W,
  const double* T, double* Y, Index begin, Index end)
{
  skin_sparse<D>(X, np, W, T, Y, begin, end);
}

template <int D>
void skin_sparse_portable(const double* X, Index np, const SparseWeights& W, const double* T,
  double* Y, Index begin, Index end)
{
  skin_sparse<D>(X, np, W, T, Y, begin, end);
}

/// Runs body(begin, end) over [0, np) in static blocks, one per thread: every point is written
/// by the thread that computes it (its first touch), and no point depends on another.
template <typename Body>
void for_blocks(Index np, int threads, const Body& body)
{
  const int nt = static_cast<int>(std::min<Index>(thread_count(threads), std::max<Index>(1, np / 1024)));
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const int t = omp_get_thread_num(), count = omp_get_num_threads();
#else
    const int t = 0, count = 1;
#endif
    const Index begin = np * t / count, end = np * (t + 1) / count;
    body(begin, end);
  }
}

/// Any other dimension: Eq. (1) term by term (the kernels above cover 2D and 3D).
template <typename Weights>
void skin_generic(const Points& X, const Weights& W, const AffineTransforms& transforms,
  int threads, Points& Y)
{
  const Index np = X.rows(), dim = X.cols();
#pragma omp parallel for schedule(static) num_threads(thread_count(threads))
  for (Index p = 0; p < np; ++p)
  {
    Eigen::VectorXd h(dim + 1);
    h.head(dim) = X.row(p).transpose();
    h(dim) = 1.0;
    Eigen::VectorXd y = Eigen::VectorXd::Zero(dim);
    if constexpr (std::is_same_v<Weights, DenseWeights>)
    {
      for (Index j = 0; j < W.cols(); ++j)
        y.noalias() += W(p, j) * (transforms[static_cast<std::size_t>(j)] * h);
    }
    else
    {
      for (typename Weights::InnerIterator it(W, p); it; ++it)
        y.noalias() += it.value() * (transforms[static_cast<std::size_t>(it.col())] * h);
    }
    Y.row(p) = y.transpose();
  }
}

/// The weights' finiteness is checked only when some deformed point is not finite (a non-finite
/// weight makes its point's result non-finite: every entry of its blended transform is then
/// infinite or NaN, and the last column meets the homogeneous 1): the check names the
/// culprit, and finite inputs that overflow are named as such. The points are checked as a
/// whole (one contiguous pass), the transforms before.
template <typename CheckWeights>
void check_result(const Points& X, const Points& Y, const CheckWeights& check_weights)
{
  if (Y.allFinite() && X.allFinite()) // X too: a point with no stored weight has no term
    return;
  for (Index p = 0; p < X.rows(); ++p)
    if (!X.row(p).allFinite())
      throw Error(ErrorCode::NonFinite, "point " + std::to_string(p) + " is not finite");
  check_weights();
  for (Index p = 0; p < Y.rows(); ++p)
    if (!Y.row(p).allFinite())
      throw Error(ErrorCode::NonFinite,
        "the deformed position of point " + std::to_string(p) +
          " overflows (finite weights and transforms, but too large)");
}

/// Eq. (1) with either kind of weights: kernel(avx2, dim, packed transforms, Y, begin, end)
/// over blocks of points in 2D and 3D, term by term in any other dimension, then the result's
/// check (check_weights names a non-finite weight).
template <typename Weights, typename Kernel, typename CheckWeights>
Points skin(const Points& X, const Weights& W, const AffineTransforms& transforms, int threads,
  const Kernel& kernel, const CheckWeights& check_weights)
{
  const Index dim = validate(X, W.rows(), W.cols(), transforms, threads);
  Points Y(X.rows(), dim);
  if (dim == 2 || dim == 3)
  {
    const bool avx2 = detail::simd_level() == detail::SimdLevel::AVX2;
    const std::vector<double> T = pack_transforms(transforms, static_cast<int>(dim));
    for_blocks(X.rows(), threads,
      [&](Index begin, Index end) { kernel(avx2, dim, T.data(), Y.data(), begin, end); });
  }
  else
    skin_generic(X, W, transforms, threads, Y);
  check_result(X, Y, check_weights);
  return Y;
}

} // namespace

Points linear_blend_skinning(
  const Points& X, const DenseWeights& W, const AffineTransforms& transforms, int threads)
{
  const auto kernel = [&](bool avx2, Index dim, const double* T, double* Y, Index begin, Index end) {
    if (dim == 2)
      (avx2 ? skin_dense_avx2<2> : skin_dense_portable<2>)(
        X.data(), X.rows(), W.data(), W.cols(), T, Y, begin, end);
    else
      (avx2 ? skin_dense_avx2<3> : skin_dense_portable<3>)(
        X.data(), X.rows(), W.data(), W.cols(), T, Y, begin, end);
  };
  return skin(X, W, transforms, threads, kernel, [&] {
    for (Index p = 0; p < W.rows(); ++p)
      if (!W.row(p).allFinite())
        throw Error(ErrorCode::NonFinite,
          "the weights of point " + std::to_string(p) + " are not finite");
  });
}

Points linear_blend_skinning(
  const Points& X, const SparseWeights& W, const AffineTransforms& transforms, int threads)
{
  const auto kernel = [&](bool avx2, Index dim, const double* T, double* Y, Index begin, Index end) {
    if (dim == 2)
      (avx2 ? skin_sparse_avx2<2> : skin_sparse_portable<2>)(X.data(), X.rows(), W, T, Y, begin, end);
    else
      (avx2 ? skin_sparse_avx2<3> : skin_sparse_portable<3>)(X.data(), X.rows(), W, T, Y, begin, end);
  };
  return skin(X, W, transforms, threads, kernel, [&] {
    for (Index p = 0; p < W.outerSize(); ++p)
      for (SparseWeights::InnerIterator it(W, p); it; ++it)
        if (!std::isfinite(it.value()))
          throw Error(ErrorCode::NonFinite,
            "the weights of point " + std::to_string(p) + " are not finite");
  });
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
