// Tests of core/surface/phong_projection: the five properties of Panozzo et al. 2013 §3.2, the
// continuity of the interpolated tangent planes, and the tangent frames.
#include "core/detail/simd.h"
#include "core/surface/phong_projection.h"
#include "error_matchers.h"
#include "surface_catalogue.h"

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include <random>

using namespace bary;
using bary::test::throws_error;

namespace
{

/// Largest principal angle (sine) between the row spaces of two 2 by D matrices.
double plane_distance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B)
{
  auto basis = [](const Eigen::MatrixXd& M) {
    Eigen::MatrixXd Q = M.transpose();
    Q.col(0).normalize();
    Q.col(1) -= Q.col(1).dot(Q.col(0)) * Q.col(0);
    Q.col(1).normalize();
    return Q;
  };
  const Eigen::MatrixXd QA = basis(A), QB = basis(B);
  // |(I - QB QB^T) QA|_2 is the sine of the largest principal angle.
  const Eigen::MatrixXd R = QA - QB * (QB.transpose() * QA);
  return Eigen::JacobiSVD<Eigen::MatrixXd>(R).singularValues()(0);
}

/// A vector orthogonal to the rows of P (2 by D), random, of length len.
Eigen::VectorXd normal_offset(const Eigen::MatrixXd& P, double len, std::mt19937& rng)
{
  std::normal_distribution<double> g;
  Eigen::VectorXd n(P.cols());
  for (Index d = 0; d < n.size(); ++d)
    n(d) = g(rng);
  Eigen::MatrixXd Q = P.transpose();
  Q.col(0).normalize();
  Q.col(1) -= Q.col(1).dot(Q.col(0)) * Q.col(0);
  Q.col(1).normalize();
  n -= Q * (Q.transpose() * n);
  return len * n.normalized();
}

struct Case
{
  const char* name;
  test::Surface surface;
  bool lift;
};

std::vector<Case> cases()
{
  return { { "sphere R3", test::icosphere(2), false }, { "sphere R8", test::icosphere(2), true },
    { "torus R8", test::torus(16, 10), true } };
}

} // namespace

TEST(PhongProjection, FramesAreOrthonormalAndTangent)
{
  const auto s = test::icosphere(3);
  const SurfaceMesh m(s.V, s.F);
  const Eigen::MatrixXd T = tangent_frames(m, m.V);
  for (Index v = 0; v < m.vertex_count(); ++v)
  {
    const Eigen::Vector3d t1 = T.row(v).head(3), t2 = T.row(v).tail(3);
    EXPECT_NEAR(t1.norm(), 1, 1e-12);
    EXPECT_NEAR(t2.norm(), 1, 1e-12);
    EXPECT_NEAR(t1.dot(t2), 0, 1e-12);
    // On a fine sphere the Loop tangent plane is close to the true one (normal = position).
    EXPECT_LT(std::abs(t1.dot(m.V.row(v).normalized())), 0.02);
    EXPECT_LT(std::abs(t2.dot(m.V.row(v).normalized())), 0.02);
  }
}

// Property 1: every point of the mesh is its own Phong projection.
TEST(PhongProjection, PointsOnTheMeshProjectToThemselves)
{
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& c : cases())
  {
    const SurfaceMesh m(c.surface.V, c.surface.F);
    const Eigen::MatrixXd E = c.lift ? test::lift8(m.V) : m.V;
    const PhongProjection phong(m, E);
    for (int t = 0; t < 300; ++t)
    {
      const Index f = static_cast<Index>(u(rng) * m.face_count());
      Eigen::Vector3d xi(u(rng), u(rng), u(rng));
      if (t % 10 == 0)
        xi(t % 3) = 0; // on an edge
      xi /= xi.sum();
      Eigen::VectorXd y(E.cols());
      phong.position(f, xi, y.data());
      Eigen::Vector3d found;
      ASSERT_TRUE(phong.project(f, y.data(), found)) << c.name << " face " << f;
      EXPECT_LT((found - xi).cwiseAbs().maxCoeff(), 1e-10) << c.name;
    }
  }
}

// Property 2: on a plane Phong projection is the Euclidean projection.
TEST(PhongProjection, OnAPlaneItIsTheEuclideanProjection)
{
  const auto g = test::flat_grid(8);
  const SurfaceMesh m(g.V, g.F);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  // The plane z = 0 embedded in R^3, and rotated into R^8 (a random isometry).
  Eigen::MatrixXd Q = Eigen::MatrixXd::Random(8, 8);
  Q = Eigen::HouseholderQR<Eigen::MatrixXd>(Q).householderQ();
  Eigen::MatrixXd E8 = Eigen::MatrixXd::Zero(m.vertex_count(), 8);
  E8.leftCols(3) = m.V;
  E8 = (E8 * Q.transpose()).eval();
  for (const Eigen::MatrixXd& E : { m.V, E8 })
  {
    const PhongProjection phong(m, E);
    // Psi spans the plane everywhere.
    const Eigen::MatrixXd plane = (Eigen::MatrixXd(2, E.cols()) << (E.row(1) - E.row(0)), (E.row(9) - E.row(0))).finished();
    for (int t = 0; t < 200; ++t)
    {
      const Index f = static_cast<Index>(u(rng) * m.face_count());
      Eigen::Vector3d xi(u(rng), u(rng), u(rng));
      xi /= xi.sum();
      EXPECT_LT(plane_distance(phong.psi(f, xi), plane), 1e-12);
      Eigen::VectorXd y(E.cols());
      phong.position(f, xi, y.data());
      // Move off the plane along its normal space: the projection is the foot point.
      Eigen::VectorXd offset = Eigen::VectorXd::Random(E.cols());
      const Eigen::MatrixXd B = plane.transpose().householderQr().householderQ() * Eigen::MatrixXd::Identity(E.cols(), 2);
      offset -= B * (B.transpose() * offset);
      y += offset;
      Eigen::Vector3d found;
      ASSERT_TRUE(phong.project(f, y.data(), found));
      EXPECT_LT((found - xi).cwiseAbs().maxCoeff(), 1e-10);
    }
  }
}

// Property 3: if y projects (Euclidean) onto vertex v's tangent plane at v, v is a Phong
// projection of y on each of v's triangles.
TEST(PhongProjection, VertexIsAProjectionOfPointsAlongItsNormalSpace)
{
  std::mt19937 rng(3);
  for (const auto& c : cases())
  {
    const SurfaceMesh m(c.surface.V, c.surface.F);
    const Eigen::MatrixXd E = c.lift ? test::lift8(m.V) : m.V;
    const PhongProjection phong(m, E);
    const Index D = E.cols();
    for (Index v = 0; v < m.vertex_count(); v += 7)
    {
      Eigen::MatrixXd T(2, D);
      T.row(0) = phong.frames().row(v).head(D);
      T.row(1) = phong.frames().row(v).tail(D);
      const Eigen::VectorXd y = E.row(v).transpose() + normal_offset(T, 0.3 * m.mean_edge_length, rng);
      for (int i = m.face_offsets[v]; i < m.face_offsets[v + 1]; ++i)
      {
        const int f = m.vertex_faces[i];
        Eigen::Vector3d found;
        ASSERT_TRUE(phong.project(f, y.data(), found)) << c.name << " vertex " << v << " face " << f;
        const int k = m.F(f, 0) == v ? 0 : m.F(f, 1) == v ? 1 : 2;
        EXPECT_NEAR(found(k), 1.0, 1e-7) << c.name << " vertex " << v;
      }
    }
  }
}

// Property 4 (and the continuity of Psi it rests on): on an edge shared by two triangles both
// interpolate the same tangent plane, so a projection on the edge is one from both sides.
TEST(PhongProjection, EdgeProjectionsAgreeAcrossTheEdge)
{
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (const auto& c : cases())
  {
    const SurfaceMesh m(c.surface.V, c.surface.F);
    const Eigen::MatrixXd E = c.lift ? test::lift8(m.V) : m.V;
    const PhongProjection phong(m, E);
    for (Index f = 0; f < m.face_count(); f += 5)
      for (int k = 0; k < 3; ++k)
      {
        const int g = m.face_neighbors(f, k);
        const int a = m.F(f, (k + 1) % 3), b = m.F(f, (k + 2) % 3);
        const double t = u(rng);
        Eigen::Vector3d xf = Eigen::Vector3d::Zero(), xg = Eigen::Vector3d::Zero();
        xf((k + 1) % 3) = 1 - t;
        xf((k + 2) % 3) = t;
        for (int j = 0; j < 3; ++j)
          xg(j) = m.F(g, j) == a ? 1 - t : m.F(g, j) == b ? t : 0.0;
        const Eigen::MatrixXd Pf = phong.psi(f, xf), Pg = phong.psi(g, xg);
        EXPECT_LT(plane_distance(Pf, Pg), 1e-12) << c.name;
        Eigen::VectorXd y(E.cols());
        phong.position(f, xf, y.data());
        y += normal_offset(Pf, 0.2 * m.mean_edge_length, rng);
        Eigen::Vector3d found_f, found_g;
        ASSERT_TRUE(phong.project(f, y.data(), found_f));
        ASSERT_TRUE(phong.project(g, y.data(), found_g));
        EXPECT_LT((found_f - xf).cwiseAbs().maxCoeff(), 1e-8) << c.name;
        EXPECT_LT((found_g - xg).cwiseAbs().maxCoeff(), 1e-8) << c.name;
      }
  }
}

// At a corner, Psi tends to the corner's tangent plane from every direction.
TEST(PhongProjection, PsiTendsToTheVertexPlanes)
{
  const auto s = test::torus(16, 10);
  const SurfaceMesh m(s.V, s.F);
  const Eigen::MatrixXd E = test::lift8(m.V);
  const PhongProjection phong(m, E);
  for (Index f = 0; f < m.face_count(); f += 3)
    for (int k = 0; k < 3; ++k)
    {
      Eigen::MatrixXd T(2, 8);
      T.row(0) = phong.frames().row(m.F(f, k)).head(8);
      T.row(1) = phong.frames().row(m.F(f, k)).tail(8);
      for (const double along : { 0.1, 0.5, 0.9 })
      {
        Eigen::Vector3d xi;
        xi(k) = 1 - 1e-7;
        xi((k + 1) % 3) = 1e-7 * along;
        xi((k + 2) % 3) = 1e-7 * (1 - along);
        EXPECT_LT(plane_distance(phong.psi(f, xi), T), 1e-5);
      }
      Eigen::Vector3d corner = Eigen::Vector3d::Zero();
      corner(k) = 1;
      EXPECT_LT(plane_distance(phong.psi(f, corner), T), 1e-12);
    }
}

// Property 5: the points with a given Phong projection form an affine subspace.
TEST(PhongProjection, PreimagesAreAffine)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.1, 1);
  const auto s = test::icosphere(2);
  const SurfaceMesh m(s.V, s.F);
  const Eigen::MatrixXd E = test::lift8(m.V);
  const PhongProjection phong(m, E);
  for (Index f = 0; f < m.face_count(); f += 11)
  {
    Eigen::Vector3d xi(u(rng), u(rng), u(rng));
    xi /= xi.sum();
    Eigen::VectorXd x(8);
    phong.position(f, xi, x.data());
    const Eigen::MatrixXd P = phong.psi(f, xi);
    const Eigen::VectorXd n1 = normal_offset(P, 0.1 * m.mean_edge_length, rng);
    const Eigen::VectorXd n2 = normal_offset(P, 0.1 * m.mean_edge_length, rng);
    for (const double alpha : { -0.5, 0.0, 0.3, 1.0, 1.5 })
    {
      const Eigen::VectorXd y = x + alpha * n1 + (1 - alpha) * n2;
      Eigen::Vector3d found;
      ASSERT_TRUE(phong.project(f, y.data(), found));
      EXPECT_LT((found - xi).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

// The AVX2 + FMA kernel and the portable one agree to rounding: the same triangles have a
// projection, at the same coordinates within 1e-12 (points near and off the surface, starts
// anywhere in the triangle, D = 3 and D = 8).
TEST(PhongProjection, InstructionSetsAgree)
{
  if (detail::supported_simd_level() != detail::SimdLevel::AVX2)
    GTEST_SKIP() << "this CPU has no AVX2 and FMA: only the portable kernel runs";
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  for (const auto& c : cases())
  {
    const SurfaceMesh m(c.surface.V, c.surface.F);
    const Eigen::MatrixXd E = c.lift ? test::lift8(m.V) : m.V;
    const PhongProjection phong(m, E);
    int converged = 0;
    double largest = 0;
    for (int t = 0; t < 2000; ++t)
    {
      const Index f = static_cast<Index>(u(rng) * m.face_count());
      Eigen::Vector3d xi(u(rng), u(rng), u(rng)), start(u(rng), u(rng), u(rng));
      xi /= xi.sum();
      start /= start.sum();
      Eigen::VectorXd y(E.cols());
      phong.position(f, xi, y.data());
      for (Index d = 0; d < y.size(); ++d)
        y(d) += (t % 2 ? 0.3 : 3.0) * m.mean_edge_length * g(rng);
      Eigen::Vector3d a, b;
      detail::set_simd_level(detail::SimdLevel::AVX2);
      const bool ok_a = phong.project(f, y.data(), a, start);
      detail::set_simd_level(detail::SimdLevel::Portable);
      const bool ok_b = phong.project(f, y.data(), b, start);
      detail::set_simd_level(detail::supported_simd_level());
      EXPECT_EQ(ok_a, ok_b) << c.name << " face " << f;
      if (ok_a && ok_b)
        largest = std::max(largest, (a - b).cwiseAbs().maxCoeff());
      converged += ok_a;
    }
    EXPECT_LT(largest, 1e-12) << c.name;
    // both outcomes are compared
    EXPECT_GT(converged, 300) << c.name;
    EXPECT_LT(converged, 1700) << c.name;
  }
}

TEST(PhongProjection, NoProjectionOutsideTheTriangle)
{
  const auto s = test::icosphere(2);
  const SurfaceMesh m(s.V, s.F);
  const PhongProjection phong(m, m.V);
  // A point of face 0 has no projection on a far-away face.
  Eigen::Vector3d xi(0.2, 0.3, 0.5), found;
  Eigen::Vector3d y;
  phong.position(0, xi, y.data());
  Index far = 0;
  double best = 0;
  for (Index f = 0; f < m.face_count(); ++f)
  {
    const double d = (m.V.row(m.F(f, 0)).transpose() - y).norm();
    if (d > best)
    {
      best = d;
      far = f;
    }
  }
  EXPECT_FALSE(phong.project(far, y.data(), found));
}

TEST(PhongProjection, Errors)
{
  const auto s = test::icosphere(1);
  const SurfaceMesh m(s.V, s.F);
  EXPECT_TRUE(throws_error([&] { PhongProjection(m, m.V.topRows(5)); }, ErrorCode::SizeMismatch, { "rows" }));
  EXPECT_TRUE(throws_error([&] { PhongProjection(m, m.V.leftCols(1)); }, ErrorCode::SizeMismatch, { "2 dimensions" }));
  Eigen::MatrixXd E = m.V;
  E(3, 1) = std::nan("");
  EXPECT_TRUE(throws_error([&] { PhongProjection(m, E); }, ErrorCode::NonFinite, { "non-finite" }));
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(m.vertex_count(), 3);
  EXPECT_TRUE(throws_error([&] { PhongProjection(m, Z); }, ErrorCode::InvalidArgument, { "vertex 0", "less than a plane" }));
}
