#include "core/surface/phong_projection.h"

#include "core/common/error.h"
#include "core/detail/phong_kernel.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>

namespace bary
{
namespace
{

using Mat2 = Eigen::Matrix2d;
using Frame = Eigen::Matrix<double, 2, Eigen::Dynamic>;

/// Ort(A) = argmin over O(2) of |B - A|_F = U V^T of A's SVD (Eq. 10).
Mat2 ort(const Mat2& A)
{
  const Eigen::JacobiSVD<Mat2> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

/// Two orthonormal rows spanning t1, t2 (Gram-Schmidt); false when they span less than a plane.
bool orthonormalize(Eigen::VectorXd t1, Eigen::VectorXd t2, double scale, Frame& T)
{
  const double n1 = t1.norm();
  if (!(n1 > 1e-12 * scale))
    return false;
  t1 /= n1;
  t2 -= t2.dot(t1) * t1;
  const double n2 = t2.norm();
  if (!(n2 > 1e-12 * scale))
    return false;
  T.resize(2, t1.size());
  T.row(0) = t1.transpose();
  T.row(1) = (t2 / n2).transpose();
  return true;
}

} // namespace

Eigen::MatrixXd tangent_frames(const SurfaceMesh& mesh, const Eigen::MatrixXd& E)
{
  const Index nv = mesh.vertex_count();
  if (E.rows() != nv)
    throw Error(ErrorCode::SizeMismatch, "the embedding has " + std::to_string(E.rows()) +
        " rows but the surface has " + std::to_string(nv) + " vertices");
  if (E.cols() < 2)
    throw Error(ErrorCode::SizeMismatch,
      "the embedding needs at least 2 dimensions, got " + std::to_string(E.cols()));
  const Index D = E.cols();
  Eigen::MatrixXd frames(nv, 2 * D);
  const double pi = std::acos(-1.0);
  for (Index v = 0; v < nv; ++v)
  {
    const int begin = mesh.ring_offsets[static_cast<std::size_t>(v)];
    const int k = mesh.ring_offsets[static_cast<std::size_t>(v + 1)] - begin;
    auto p = [&](int i) { return E.row(mesh.ring[static_cast<std::size_t>(begin + i)]).transpose(); };
    const Eigen::VectorXd x = E.row(v).transpose();
    Eigen::VectorXd t1 = Eigen::VectorXd::Zero(D), t2 = Eigen::VectorXd::Zero(D);
    double scale = 0;
    for (int i = 0; i < k; ++i)
      scale = std::max(scale, (p(i) - x).norm());
    if (!mesh.boundary[static_cast<std::size_t>(v)])
    {
      for (int i = 0; i < k; ++i)
      {
        t1 += std::cos(2 * pi * i / k) * (p(i) - x);
        t2 += std::sin(2 * pi * i / k) * (p(i) - x);
      }
    }
    else
    {
      t1 = p(k - 1) - p(0);
      if (k == 2)
        t2 = p(0) + p(1) - 2 * x;
      else
        for (int i = 1; i <= k - 2; ++i)
          t2 += std::sin(i * pi / (k - 1)) * (p(i) - x);
    }
    Frame T;
    if (!orthonormalize(t1, t2, scale, T))
    {
      // Fallback: the best-fitting plane of the one-ring's edge vectors.
      Eigen::MatrixXd R(D, k);
      for (int i = 0; i < k; ++i)
        R.col(i) = p(i) - x;
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeThinU);
      if (svd.singularValues().size() < 2 || !(svd.singularValues()(1) > 1e-12 * scale) ||
        !orthonormalize(svd.matrixU().col(0), svd.matrixU().col(1), 1.0, T))
        throw Error(ErrorCode::InvalidArgument, "the embedded one-ring of vertex " +
            std::to_string(v) + " spans less than a plane (a degenerate embedding)");
    }
    frames.row(v).head(D) = T.row(0);
    frames.row(v).tail(D) = T.row(1);
  }
  return frames;
}

PhongProjection::PhongProjection(const SurfaceMesh& mesh, const Eigen::MatrixXd& E)
{
  if (!E.allFinite())
    throw Error(ErrorCode::NonFinite, "the embedding has a non-finite entry");
  frames_ = tangent_frames(mesh, E);
  D_ = static_cast<int>(E.cols());
  F_ = mesh.F;
  E_ = E;
  const Index nf = F_.rows();
  const Index D = D_;
  static_assert(kData == detail::kPhongData, "the kernel's layout");
  data_.assign(static_cast<std::size_t>(nf * kData), 0.0);
  frame_rows_.resize(static_cast<std::size_t>(frames_.rows() * 2 * D));
  for (Index v = 0; v < frames_.rows(); ++v)
    for (Index d = 0; d < 2 * D; ++d)
      frame_rows_[static_cast<std::size_t>(v * 2 * D + d)] = frames_(v, d);
  auto frame = [&](Index v) {
    Frame T(2, D);
    T.row(0) = frames_.row(v).head(D);
    T.row(1) = frames_.row(v).tail(D);
    return T;
  };
  for (Index f = 0; f < nf; ++f)
  {
    const Frame T1 = frame(F_(f, 0)), T2 = frame(F_(f, 1)), T3 = frame(F_(f, 2));
    const Mat2 R12 = ort(T2 * T1.transpose()), R23 = ort(T3 * T2.transpose()),
               R31 = ort(T1 * T3.transpose());
    const Frame P12 = R12 * T1 + T2, P23 = R23 * T2 + T3, P31 = R31 * T3 + T1;
    Mat2 E12 = Mat2::Identity(), E23 = Mat2::Identity(), E31 = Mat2::Identity();
    // Maximise <E12 P12, E23 P23> + <E23 P23, E31 P31> + <E31 P31, E12 P12> (Eq. 12: the
    // within-pair terms do not depend on the E's), one E at a time.
    auto energy = [&] {
      const Frame a = E12 * P12, b = E23 * P23, c = E31 * P31;
      return (a.cwiseProduct(b).sum() + b.cwiseProduct(c).sum() + c.cwiseProduct(a).sum());
    };
    double e = energy();
    for (int round = 0; round < 100; ++round)
    {
      E12 = ort((E23 * P23 + E31 * P31) * P12.transpose());
      E23 = ort((E31 * P31 + E12 * P12) * P23.transpose());
      E31 = ort((E12 * P12 + E23 * P23) * P31.transpose());
      const double en = energy();
      const bool done = !(en - e > 1e-15 * std::abs(en));
      e = en;
      if (done)
        break;
    }
    const Frame A1 = E12 * R12 * T1, A2 = E12 * T2, A3 = E23 * R23 * T2, A4 = E23 * T3,
                A5 = E31 * R31 * T3, A6 = E31 * T1;
    const Eigen::RowVectorXd v3 = E_.row(F_(f, 2));
    const Eigen::RowVectorXd e1 = E_.row(F_(f, 0)) - v3, e2 = E_.row(F_(f, 1)) - v3;
    Eigen::Matrix2d G;
    G << e1.squaredNorm(), e1.dot(e2), e1.dot(e2), e2.squaredNorm();
    const Eigen::Matrix2d Gi = G.inverse();
    using P = detail::PhongData;
    double* data = data_.data() + f * kData;
    const Frame* coefficients[6] = { &A1, &A2, &A3, &A4, &A5, &A6 };
    const Mat2 M[6] = { E12 * R12, E12, E23 * R23, E23, E31 * R31, E31 };
    for (int m = 0; m < 6; ++m)
      for (int r = 0; r < 2; ++r)
      {
        const int row = 2 * m + r;
        data[P::q1 + row] = coefficients[m]->row(r).dot(e1);
        data[P::q2 + row] = coefficients[m]->row(r).dot(e2);
        data[P::col0 + row] = M[m](r, 0);
        data[P::col1 + row] = M[m](r, 1);
      }
    data[P::gram] = Gi(0, 0);
    data[P::gram + 1] = Gi(0, 1);
    data[P::gram + 2] = Gi(1, 1);
    data[P::scale] = std::max({ e1.norm(), e2.norm(), (e1 - e2).norm() });
  }
}

Eigen::Vector3d PhongProjection::euclidean_barycentric(Index f, const double* y) const
{
  const double* v1 = vertex(F_(f, 0));
  const double* v2 = vertex(F_(f, 1));
  const double* v3 = vertex(F_(f, 2));
  double r1 = 0, r2 = 0;
  for (int d = 0; d < D_; ++d)
  {
    const double w = y[d] - v3[d];
    r1 += (v1[d] - v3[d]) * w;
    r2 += (v2[d] - v3[d]) * w;
  }
  const double* g = data(f) + detail::PhongData::gram;
  const double a = g[0] * r1 + g[1] * r2, b = g[1] * r1 + g[2] * r2;
  return { a, b, 1.0 - a - b };
}

namespace
{

/// The arguments of the kernels for triangle f.
struct Triangle
{
  const double *data, *T1, *T2, *T3, *v1, *v2, *v3;
};

template<int kD>
BARY_ALWAYS_INLINE bool project_impl(const Triangle& t, int D, const double* y, double a0,
  double b0, double* xi)
{
  return detail::phong_project<kD>(
    t.data, t.T1, t.T2, t.T3, t.v1, t.v2, t.v3, D, y, false, a0, b0, xi);
}

bool project_portable(const Triangle& t, int D, const double* y, double a0, double b0, double* xi)
{
  return D == 8 ? project_impl<8>(t, D, y, a0, b0, xi) : project_impl<0>(t, D, y, a0, b0, xi);
}

BARY_TARGET_AVX2 bool project_avx2(
  const Triangle& t, int D, const double* y, double a0, double b0, double* xi)
{
  return D == 8 ? project_impl<8>(t, D, y, a0, b0, xi) : project_impl<0>(t, D, y, a0, b0, xi);
}

} // namespace

bool PhongProjection::project(
  Index f, const double* y, Eigen::Vector3d& xi, const Eigen::Vector3d& start) const
{
  const Triangle t{ data(f), frame(F_(f, 0)), frame(F_(f, 1)), frame(F_(f, 2)),
    vertex(F_(f, 0)), vertex(F_(f, 1)), vertex(F_(f, 2)) };
  double x[3];
  const bool ok = detail::simd_level() == detail::SimdLevel::AVX2
    ? project_avx2(t, D_, y, start(0), start(1), x)
    : project_portable(t, D_, y, start(0), start(1), x);
  xi = Eigen::Vector3d(x[0], x[1], x[2]);
  return ok;
}

void PhongProjection::psi(Index f, const Eigen::Vector3d& xi, double* out) const
{
  detail::phong_psi<0>(data(f), frame(F_(f, 0)), frame(F_(f, 1)), frame(F_(f, 2)), D_, xi(0),
    xi(1), xi(2), out);
}

Eigen::MatrixXd PhongProjection::psi(Index f, const Eigen::Vector3d& xi) const
{
  Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor> P(2, D_);
  psi(f, xi, P.data());
  return P;
}

void PhongProjection::position(Index f, const Eigen::Vector3d& xi, double* out) const
{
  const double* v0 = vertex(F_(f, 0));
  const double* v1 = vertex(F_(f, 1));
  const double* v2 = vertex(F_(f, 2));
  for (int d = 0; d < D_; ++d)
    out[d] = xi(0) * v0[d] + xi(1) * v1[d] + xi(2) * v2[d];
}

} // namespace bary
