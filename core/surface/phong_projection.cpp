#include "core/surface/phong_projection.h"

#include "core/common/error.h"

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
  C_.resize(14 * nf, D);
  CV_.resize(14 * nf, 3);
  scale_.resize(static_cast<std::size_t>(nf));
  edges_.resize(2 * nf, D);
  gram_.resize(nf, 5);
  auto frame = [&](Index v) {
    Frame T(2, D);
    T.row(0) = frames_.row(v).head(D);
    T.row(1) = frames_.row(v).tail(D);
    return T;
  };
  for (Index f = 0; f < nf; ++f)
  {
    const Frame T1 = frame(F_(f, 0)), T2 = frame(F_(f, 1)), T3 = frame(F_(f, 2));
    scale_[static_cast<std::size_t>(f)] = std::max({ (E_.row(F_(f, 0)) - E_.row(F_(f, 1))).norm(),
      (E_.row(F_(f, 1)) - E_.row(F_(f, 2))).norm(), (E_.row(F_(f, 2)) - E_.row(F_(f, 0))).norm() });
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
    const Frame B = 0.5 * ((A4 + A5) + (A6 + A1) + (A2 + A3));
    {
      const Eigen::RowVectorXd v3 = E_.row(F_(f, 2));
      const Eigen::RowVectorXd e1 = E_.row(F_(f, 0)) - v3, e2 = E_.row(F_(f, 1)) - v3;
      edges_.row(2 * f) = e1;
      edges_.row(2 * f + 1) = e2;
      Eigen::Matrix2d G;
      G << e1.squaredNorm(), e1.dot(e2), e1.dot(e2), e2.squaredNorm();
      const Eigen::Matrix2d Gi = G.inverse();
      gram_.row(f) << Gi(0, 0), Gi(0, 1), Gi(1, 1), e1.dot(v3), e2.dot(v3);
    }
    const Frame* coefficients[7] = { &A1, &A2, &A3, &A4, &A5, &A6, &B };
    for (int m = 0; m < 7; ++m)
      for (int r = 0; r < 2; ++r)
      {
        const Index row = 14 * f + 2 * m + r;
        C_.row(row) = coefficients[m]->row(r);
        for (int k = 0; k < 3; ++k)
          CV_(row, k) = C_.row(row).dot(E_.row(F_(f, k)));
      }
  }
}

Eigen::Vector3d PhongProjection::euclidean_barycentric(Index f, const double* y) const
{
  const double* e1 = edges_.data() + 2 * f * D_;
  const double* e2 = e1 + D_;
  double r1 = 0, r2 = 0;
  for (int d = 0; d < D_; ++d)
  {
    r1 += e1[d] * y[d];
    r2 += e2[d] * y[d];
  }
  const double* g = gram_.data() + 5 * f;
  r1 -= g[3];
  r2 -= g[4];
  const double a = g[0] * r1 + g[1] * r2, b = g[1] * r1 + g[2] * r2;
  return { a, b, 1.0 - a - b };
}

bool PhongProjection::project(
  Index f, const double* y, Eigen::Vector3d& xi, const Eigen::Vector3d& start) const
{
  // p_m = C_m y (14 numbers), then H(a, b) = sum_m mono_m (a q_m1 + b q_m2 + c q_m3 - p_m) / s.
  double p[14];
  const double* C = C_.data() + 14 * f * D_;
  for (int r = 0; r < 14; ++r)
  {
    double sum = 0;
    for (int d = 0; d < D_; ++d)
      sum += C[r * D_ + d] * y[d];
    p[r] = sum;
  }
  const double* Q = CV_.data() + 14 * f * 3;
  const double residual_tolerance = 1e-14 * scale_[static_cast<std::size_t>(f)];
  const double tolerance2 = residual_tolerance * residual_tolerance;
  // Start inside the triangle (the blend's denominator vanishes at the corners).
  double a = std::clamp(start(0), 0.02, 0.96), b = std::clamp(start(1), 0.02, 0.96);
  if (a + b > 0.98)
  {
    const double excess = (a + b - 0.98) / 2;
    a -= excess;
    b -= excess;
  }
  for (int it = 0; it < 30; ++it)
  {
    const double c = 1.0 - a - b;
    // Monomials and their partial derivatives with respect to a, b, c.
    const double m[7] = { a * a * b, a * b * b, b * b * c, b * c * c, c * c * a, c * a * a, a * b * c };
    const double ma[7] = { 2 * a * b, b * b, 0, 0, c * c, 2 * c * a, b * c };
    const double mb[7] = { a * a, 2 * a * b, 2 * b * c, c * c, 0, 0, c * a };
    const double mc[7] = { 0, 0, b * b, 2 * b * c, 2 * c * a, a * a, a * b };
    double G[2] = { 0, 0 }, Ga[2] = { 0, 0 }, Gb[2] = { 0, 0 };
    for (int k = 0; k < 7; ++k)
      for (int r = 0; r < 2; ++r)
      {
        const double* q = Q + (2 * k + r) * 3;
        const double g = a * q[0] + b * q[1] + c * q[2] - p[2 * k + r];
        G[r] += m[k] * g;
        // d/da = d/da - d/dc, d/db = d/db - d/dc (c = 1 - a - b)
        Ga[r] += (ma[k] - mc[k]) * g + m[k] * (q[0] - q[2]);
        Gb[r] += (mb[k] - mc[k]) * g + m[k] * (q[1] - q[2]);
      }
    const double s = a * b + b * c + c * a;
    if (!(std::abs(s) > 1e-24))
    {
      // At (or within rounding of) a corner k, where Psi is the corner's basis: accept the
      // corner when y - v_k is orthogonal to it (Property 3).
      const int k = a >= b && a >= c ? 0 : b >= c ? 1 : 2;
      const int corner = 2 * k; // A1, A3, A5: the corner bases among the coefficients
      const double r0 = Q[(2 * corner) * 3 + k] - p[2 * corner],
                   r1 = Q[(2 * corner + 1) * 3 + k] - p[2 * corner + 1];
      if (std::hypot(r0, r1) > 1e3 * residual_tolerance)
        break;
      xi = Eigen::Vector3d::Zero();
      xi(k) = 1.0;
      return true;
    }
    const double sa = (b + c) - (a + b), sb = (a + c) - (a + b);
    // H = G / s; dH = (dG s - G ds) / s^2
    double H[2], Ha[2], Hb[2];
    for (int r = 0; r < 2; ++r)
    {
      H[r] = G[r] / s;
      Ha[r] = (Ga[r] * s - G[r] * sa) / (s * s);
      Hb[r] = (Gb[r] * s - G[r] * sb) / (s * s);
    }
    const double det = Ha[0] * Hb[1] - Ha[1] * Hb[0];
    if (!(std::abs(det) > 0) || !std::isfinite(det))
      break;
    const double da = -(H[0] * Hb[1] - H[1] * Hb[0]) / det;
    const double db = -(Ha[0] * H[1] - Ha[1] * H[0]) / det;
    if (!std::isfinite(da) || !std::isfinite(db))
      break;
    a += da;
    b += db;
    // Converged: the step is at rounding level, or the residual is (near a corner, where
    // Psi's limit depends on the direction, Newton converges only linearly).
    if (std::abs(da) + std::abs(db) < 1e-13 || H[0] * H[0] + H[1] * H[1] <= tolerance2)
    {
      double x[3] = { a, b, 1.0 - a - b };
      constexpr double tolerance = 1e-9;
      if (x[0] < -tolerance || x[1] < -tolerance || x[2] < -tolerance)
      {
        xi = Eigen::Vector3d(x[0], x[1], x[2]);
        return false;
      }
      for (double& v : x)
        v = std::max(v, 0.0);
      const double sum = x[0] + x[1] + x[2];
      xi = Eigen::Vector3d(x[0] / sum, x[1] / sum, x[2] / sum);
      return true;
    }
    // Far outside the triangle: no projection here (Eq. 9 cannot hold).
    if (std::abs(a) > 1e3 || std::abs(b) > 1e3)
      break;
  }
  xi = Eigen::Vector3d(a, b, 1.0 - a - b);
  return false;
}

void PhongProjection::psi(Index f, const Eigen::Vector3d& xi, double* out) const
{
  const double a = xi(0), b = xi(1), c = xi(2);
  const double s = a * b + b * c + c * a;
  const double* C = C_.data() + 14 * f * D_;
  if (!(s > 1e-300))
  {
    const int m = a >= b && a >= c ? 0 : b >= c ? 2 : 4;
    std::copy(C + 2 * m * D_, C + (2 * m + 2) * D_, out);
    return;
  }
  const double mono[7] = { a * a * b, a * b * b, b * b * c, b * c * c, c * c * a, c * a * a, a * b * c };
  std::fill(out, out + 2 * D_, 0.0);
  for (int m = 0; m < 7; ++m)
  {
    const double k = mono[m] / s;
    const double* row = C + 2 * m * D_;
    for (int d = 0; d < 2 * D_; ++d)
      out[d] += k * row[d];
  }
}

Eigen::MatrixXd PhongProjection::psi(Index f, const Eigen::Vector3d& xi) const
{
  const double a = xi(0), b = xi(1), c = xi(2);
  const double s = a * b + b * c + c * a;
  Eigen::MatrixXd P(2, D_);
  if (!(s > 1e-300))
  {
    // At a corner: the coefficient of that corner's basis (A1 at v1, A3 at v2, A5 at v3).
    const int m = a >= b && a >= c ? 0 : b >= c ? 2 : 4;
    for (int r = 0; r < 2; ++r)
      P.row(r) = C_.row(14 * f + 2 * m + r);
    return P;
  }
  const double mono[7] = { a * a * b, a * b * b, b * b * c, b * c * c, c * c * a, c * a * a, a * b * c };
  P.setZero();
  for (int m = 0; m < 7; ++m)
    for (int r = 0; r < 2; ++r)
      P.row(r) += (mono[m] / s) * C_.row(14 * f + 2 * m + r);
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
