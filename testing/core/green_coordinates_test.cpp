// Tests for core/coordinates/green_coordinates.h and the Green deformation of
// core/deformation/cage_deformation.h (Lipman, Levin & Cohen-Or 2008). Built into the mean value
// coordinates test executable (one executable less to compile and link in CI's two trees).
//
// What is checked, and against what:
// - Linear reproduction and partition of unity inside (Green's third identity for x and for 1):
//   sum phi_i = 1 and phi V + psi N = x over the 2D and 3D catalogue cages, both orientations.
// - An independent reference: the defining boundary integrals (phi_i = integral of dG/dn times
//   the hat function of v_i, psi_j = -integral of G over face j) by composite Gauss-Legendre
//   quadrature written here, at interior points away from the cage.
// - The deformation commutes with similarities (rotation + uniform scale + translation of the
//   deformed cage moves the deformed points by exactly that similarity), and a similarity of
//   the rest cage moves every point by it.
// - 2D conformality: the deformation's Jacobian by central differences satisfies the
//   Cauchy-Riemann equations for a non-trivial deformed cage; MVC's does not (a number is
//   printed and compared).
// - Points on the cage: the limits from inside (reproduction and partition of unity hold there,
//   and points just inside converge to them).
// - Outside: the raw integrals satisfy Green's identity outside (sum phi = 0, phi V + psi N = 0);
//   the paper's extension reproduces x and is continuous across a face's interior.
// - Bad input: open, self-intersecting, non-finite; options; shapes of the deformation.
//
// Tolerances (u ~ 1.1e-16): each coordinate is a sum of #faces terms of O(10) operations on
// quantities of the cage's size, so reproduction and partition of unity hold to ~1e2 u times
// sum |phi| + sum |psi|; allowed 1e-12 of that (relative to the diameter for x). The quadrature
// reference converges to ~1e-13 at points 0.05 diam from the cage (checked by halving the
// panels: QuadratureReferenceIsConverged); allowed 1e-9. Central differences with step
// h = 1e-4 diam have truncation error ~h^2 |x'''| ~ 1e-8 and rounding u / h ~ 1e-12; allowed
// 1e-6 relative to |J|.
#include "cage_catalogue.h"
#include "core/common/error.h"
#include "core/coordinates/green_coordinates.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/deformation/cage_deformation.h"
#include "error_matchers.h"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using namespace bary;
using bary::test::CatalogueCage;
using bary::test::throws_error;

constexpr double kPi = 3.14159265358979323846;
constexpr double kIdentityTol = 1e-12;
constexpr double kQuadratureTol = 1e-9;

/// Unit normals of the faces (2D: edges) as their vertex order orients them, computed here.
Eigen::MatrixXd own_normals(const Cage& cage)
{
  const Index n = cage.num_controls();
  if (cage.dimension() == 2)
  {
    Eigen::MatrixXd N(n, 2);
    for (Index j = 0; j < n; ++j)
    {
      const Eigen::Vector2d e = cage.V.row((j + 1) % n) - cage.V.row(j);
      N.row(j) = Eigen::Vector2d(e.y(), -e.x()).normalized().transpose();
    }
    return N;
  }
  Eigen::MatrixXd N(cage.F.rows(), 3);
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d a = cage.V.row(cage.F(f, 0)), b = cage.V.row(cage.F(f, 1)),
                          c = cage.V.row(cage.F(f, 2));
    N.row(f) = (b - a).cross(c - a).normalized().transpose();
  }
  return N;
}

struct Coordinates
{
  Eigen::VectorXd phi, psi;
  PointLocation where;
};

Coordinates at(const GreenCoordinates& gc, const Eigen::VectorXd& x)
{
  Coordinates c{ Eigen::VectorXd(gc.num_controls()), Eigen::VectorXd(gc.num_faces()),
    PointLocation::Inside };
  c.where = gc.evaluate(x.data(), c.phi.data(), c.psi.data());
  return c;
}

/// |phi V + psi N - x| / (diam (1 + sum|phi| + sum|psi|)) and |sum phi - 1| / (1 + sum|phi|).
std::pair<double, double> identity_errors(const Cage& cage, const Coordinates& c, const Eigen::VectorXd& x,
  double expected_sum = 1.0, bool reproduce_x = true)
{
  const Eigen::MatrixXd N = own_normals(cage);
  const Eigen::VectorXd y = cage.V.transpose() * c.phi + N.transpose() * c.psi;
  const double scale = 1.0 + c.phi.cwiseAbs().sum() + c.psi.cwiseAbs().sum();
  const Eigen::VectorXd target = reproduce_x ? x : Eigen::VectorXd::Zero(x.size());
  return { (y - target).norm() / (cage.diameter() * scale),
    std::abs(c.phi.sum() - expected_sum) / (1.0 + c.phi.cwiseAbs().sum()) };
}

std::vector<CatalogueCage> all_cages()
{
  std::vector<CatalogueCage> out = test::builtin_cages_2d();
  for (auto& c : test::cages_3d())
    out.push_back(std::move(c));
  return out;
}

class GreenProperties : public ::testing::TestWithParam<CatalogueCage>
{
protected:
  const Cage& cage() const { return GetParam().cage; }
};

TEST_P(GreenProperties, PartitionOfUnityAndReproductionInside)
{
  const GreenCoordinates gc(cage());
  const Points P = test::sample_inside(cage(), 60, 1e-3, 11);
  const GreenResult r = gc.evaluate(P);
  ASSERT_EQ(r.W.rows(), P.rows());
  ASSERT_EQ(r.face_weights.cols(), gc.num_faces());
  EXPECT_EQ(r.inside, P.rows());
  EXPECT_TRUE(r.undefined.empty());
  for (Index p = 0; p < P.rows(); ++p)
  {
    const Coordinates c{ r.W.row(p).transpose(), r.face_weights.row(p).transpose(), r.location[p] };
    const auto [repro, sum] = identity_errors(cage(), c, P.row(p).transpose());
    EXPECT_LT(repro, kIdentityTol) << GetParam().name << " point " << p;
    EXPECT_LT(sum, kIdentityTol) << GetParam().name << " point " << p;
  }
}

TEST_P(GreenProperties, OnTheCageTheLimitsFromInside)
{
  // Points on edges and faces (and the vertices) are Boundary; their coordinates reproduce x
  // and sum to one (the interior limits), and points moved inside by delta approach them.
  const Cage& C = cage();
  const GreenCoordinates gc(C);
  const Index n = C.num_controls();
  std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> points; // (x on the cage, inward)
  const auto edges = test::cage_edges(C);
  for (std::size_t e = 0; e < edges.size(); e += (C.dimension() == 3 ? 3 : 1))
  {
    const Eigen::VectorXd a = C.V.row(edges[e].first).transpose(), b = C.V.row(edges[e].second).transpose();
    points.push_back({ 0.7 * a + 0.3 * b, Eigen::VectorXd() });
  }
  for (Index i = 0; i < n; i += 3)
    points.push_back({ C.V.row(i).transpose(), Eigen::VectorXd() });
  if (C.dimension() == 3)
    for (Index f = 0; f < C.F.rows(); f += 2)
      points.push_back({ ((C.V.row(C.F(f, 0)) + C.V.row(C.F(f, 1)) * 2.0 + C.V.row(C.F(f, 2))) / 4.0).transpose(),
        test::inward_normal(C, f) });
  else
    for (Index j = 0; j < n; ++j)
      points.push_back({ (0.5 * (C.V.row(j) + C.V.row((j + 1) % n))).transpose(), test::inward_normal(C, j) });
  for (const auto& [x, inward] : points)
  {
    const Coordinates c = at(gc, x);
    EXPECT_EQ(c.where, PointLocation::Boundary) << GetParam().name << " x = " << x.transpose();
    const auto [repro, sum] = identity_errors(C, c, x);
    EXPECT_LT(repro, kIdentityTol) << GetParam().name << " x = " << x.transpose();
    EXPECT_LT(sum, kIdentityTol) << GetParam().name << " x = " << x.transpose();
    if (inward.size() == 0)
      continue;
    // just inside a face's (edge's) interior: the coordinates converge linearly to the limit
    const double delta = 1e-7 * C.diameter();
    const Coordinates inside = at(gc, x + delta * inward);
    EXPECT_EQ(inside.where, PointLocation::Inside);
    EXPECT_LT((inside.phi - c.phi).cwiseAbs().maxCoeff(), 1e-5) << GetParam().name;
    EXPECT_LT((inside.psi - c.psi).cwiseAbs().maxCoeff(), 1e-5) << GetParam().name;
  }
}

TEST_P(GreenProperties, RawIntegralsOutsideSatisfyGreensIdentity)
{
  // Outside, Green's third identity gives 0: sum phi = 0 and phi V + psi N = 0 (an independent
  // check of the closed forms' signs and of the winding test).
  GreenOptions options;
  options.extend_outside = false;
  const GreenCoordinates gc(cage(), options);
  const Points P = test::sample_outside(cage(), 30, 1e-2, 2.0, 5);
  for (Index p = 0; p < P.rows(); ++p)
  {
    const Coordinates c = at(gc, P.row(p).transpose());
    EXPECT_EQ(c.where, PointLocation::Outside);
    const auto [repro, sum] = identity_errors(cage(), c, P.row(p).transpose(), 0.0, false);
    EXPECT_LT(repro, kIdentityTol) << GetParam().name << " point " << p;
    EXPECT_LT(sum, kIdentityTol) << GetParam().name << " point " << p;
  }
}

TEST_P(GreenProperties, ExtensionReproducesOutside)
{
  const GreenCoordinates gc(cage());
  const Points P = test::sample_outside(cage(), 30, 1e-2, 2.0, 7);
  const GreenResult r = gc.evaluate(P);
  EXPECT_EQ(r.outside, P.rows());
  for (Index p = 0; p < P.rows(); ++p)
  {
    const Coordinates c{ r.W.row(p).transpose(), r.face_weights.row(p).transpose(), r.location[p] };
    const auto [repro, sum] = identity_errors(cage(), c, P.row(p).transpose());
    EXPECT_LT(repro, kIdentityTol) << GetParam().name << " point " << p;
    EXPECT_LT(sum, kIdentityTol) << GetParam().name << " point " << p;
  }
}

TEST_P(GreenProperties, ExtensionIsContinuousAcrossAFace)
{
  // The deformation of a point just inside and one just outside each face (edge) interior agree:
  // the inside limit equals the outside limit of the extended coordinates.
  const Cage& C = cage();
  const GreenCoordinates gc(C);
  test::Rng rng(3);
  Eigen::MatrixXd D = C.V;
  for (Index i = 0; i < D.rows(); ++i)
    for (Index k = 0; k < D.cols(); ++k)
      D(i, k) += 0.1 * C.diameter() * rng.uniform(-1.0, 1.0);
  const Eigen::MatrixXd N = green_face_terms(C, D);
  const Index nf = gc.num_faces();
  const double delta = 1e-8 * C.diameter();
  for (Index f = 0; f < nf; ++f)
  {
    Eigen::VectorXd x0;
    if (C.dimension() == 2)
      x0 = (0.4 * C.V.row(f) + 0.6 * C.V.row((f + 1) % C.num_controls())).transpose();
    else
      x0 = ((C.V.row(C.F(f, 0)) + C.V.row(C.F(f, 1)) + C.V.row(C.F(f, 2))) / 3.0).transpose();
    const Eigen::VectorXd inward = test::inward_normal(C, f);
    const Coordinates in = at(gc, x0 + delta * inward), out = at(gc, x0 - delta * inward);
    ASSERT_EQ(in.where, PointLocation::Inside);
    ASSERT_EQ(out.where, PointLocation::Outside);
    EXPECT_LT((in.phi - out.phi).cwiseAbs().maxCoeff(), 1e-6) << GetParam().name << " face " << f;
    EXPECT_LT((in.psi - out.psi).cwiseAbs().maxCoeff(), 1e-6) << GetParam().name << " face " << f;
    const Eigen::VectorXd y_in = D.transpose() * in.phi + N.transpose() * in.psi;
    const Eigen::VectorXd y_out = D.transpose() * out.phi + N.transpose() * out.psi;
    EXPECT_LT((y_in - y_out).norm(), 1e-6 * C.diameter()) << GetParam().name << " face " << f;
  }
}

TEST_P(GreenProperties, DeformationCommutesWithSimilarities)
{
  const Cage& C = cage();
  const int dim = C.dimension();
  const GreenCoordinates gc(C);
  const Points P = test::sample_inside(C, 40, 1e-3, 23);
  const GreenResult r = gc.evaluate(P);
  test::Rng rng(9);
  Eigen::MatrixXd D = C.V;
  for (Index i = 0; i < D.rows(); ++i)
    for (Index k = 0; k < dim; ++k)
      D(i, k) += 0.1 * C.diameter() * rng.uniform(-1.0, 1.0);
  // a rotation (det +1), a scale and a translation
  Eigen::MatrixXd R;
  if (dim == 2)
    R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
  else
    R = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const double s = 2.5;
  const Eigen::RowVectorXd t = Eigen::RowVectorXd::LinSpaced(dim, 3.0, -1.0);
  auto similarity = [&](const Eigen::MatrixXd& X) {
    return Eigen::MatrixXd((s * X * R.transpose()).rowwise() + t);
  };
  const double tol = 1e-11 * s * C.diameter();
  // the rest cage moved by the similarity moves every point by it
  const Points moved = deform_points_green(r.W, r.face_weights, C, similarity(C.V));
  EXPECT_LT((moved - similarity(P)).cwiseAbs().maxCoeff(), tol) << GetParam().name;
  // the rest cage itself: the identity
  EXPECT_LT((deform_points_green(r.W, r.face_weights, C, C.V) - P).cwiseAbs().maxCoeff(),
    1e-11 * C.diameter());
  // a deformed cage, then the similarity: the deformed points move by the similarity
  const Points X = deform_points_green(r.W, r.face_weights, C, D);
  const Points Y = deform_points_green(r.W, r.face_weights, C, similarity(D));
  EXPECT_LT((Y - similarity(X)).cwiseAbs().maxCoeff(), tol) << GetParam().name;
}

INSTANTIATE_TEST_SUITE_P(Catalogue, GreenProperties, ::testing::ValuesIn(all_cages()),
  [](const ::testing::TestParamInfo<CatalogueCage>& param) { return param.param.name; });

// --- Independent reference: quadrature of the boundary integrals ------------------------------

/// Gauss-Legendre nodes and weights on [0, 1] (8 points, from the Golub-Welsch values on
/// [-1, 1]).
void gauss8(double* t, double* w)
{
  const double x[4] = { 0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363 };
  const double a[4] = { 0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763 };
  for (int i = 0; i < 4; ++i)
  {
    t[2 * i] = 0.5 * (1.0 - x[i]);
    t[2 * i + 1] = 0.5 * (1.0 + x[i]);
    w[2 * i] = w[2 * i + 1] = 0.5 * a[i];
  }
}

/// 2D: phi_i, psi_j of the outward-normal convention by composite Gauss-Legendre on each edge.
Coordinates quadrature_2d(const Cage& C, const Eigen::Vector2d& x, int panels)
{
  const Index n = C.num_controls();
  const double sigma = test::winding_number(C, x.data()) > 0 ? 1.0 : -1.0; // orientation
  double t8[8], w8[8];
  gauss8(t8, w8);
  Coordinates c{ Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), PointLocation::Inside };
  for (Index j = 0; j < n; ++j)
  {
    const Index k = (j + 1) % n;
    const Eigen::Vector2d a = C.V.row(j), b = C.V.row(k);
    const double len = (b - a).norm();
    const Eigen::Vector2d n_out = sigma * Eigen::Vector2d((b - a).y(), -(b - a).x()) / len;
    for (int p = 0; p < panels; ++p)
      for (int q = 0; q < 8; ++q)
      {
        const double t = (p + t8[q]) / panels, wt = w8[q] / panels * len;
        const Eigen::Vector2d xi = (1 - t) * a + t * b;
        const double r2 = (xi - x).squaredNorm();
        const double dGdn = (xi - x).dot(n_out) / (2.0 * kPi * r2);
        c.phi(j) += wt * (1 - t) * dGdn;
        c.phi(k) += wt * t * dGdn;
        c.psi(j) -= wt * std::log(r2) / (4.0 * kPi); // -G = -log(r) / (2 pi)
      }
  }
  c.psi *= sigma; // the coefficient of the edge's own normal
  return c;
}

/// 3D: the same on each triangle, split into panels^2 sub-triangles, each integrated with a
/// collapsed (Duffy) 8 x 8 Gauss-Legendre rule.
Coordinates quadrature_3d(const Cage& C, const Eigen::Vector3d& x, int panels)
{
  const Index n = C.num_controls(), nf = C.F.rows();
  const double sigma = test::winding_number(C, x.data()) > 0 ? 1.0 : -1.0;
  double t8[8], w8[8];
  gauss8(t8, w8);
  Coordinates c{ Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(nf), PointLocation::Inside };
  for (Index f = 0; f < nf; ++f)
  {
    const Eigen::Vector3d A = C.V.row(C.F(f, 0)), B = C.V.row(C.F(f, 1)), D = C.V.row(C.F(f, 2));
    const Eigen::Vector3d cr = (B - A).cross(D - A);
    const double area = 0.5 * cr.norm();
    const Eigen::Vector3d n_out = sigma * cr.normalized();
    // sub-triangles in barycentric (u, v) coordinates of the face: the panels x panels grid's
    // lower and upper triangles
    for (int i = 0; i < panels; ++i)
      for (int j = 0; i + j < panels; ++j)
        for (int up = 0; up < (i + j + 1 < panels ? 2 : 1); ++up)
        {
          Eigen::Vector2d p0, p1, p2;
          const double h = 1.0 / panels;
          if (!up)
          {
            p0 = { i * h, j * h };
            p1 = { (i + 1) * h, j * h };
            p2 = { i * h, (j + 1) * h };
          }
          else
          {
            p0 = { (i + 1) * h, (j + 1) * h };
            p1 = { i * h, (j + 1) * h };
            p2 = { (i + 1) * h, j * h };
          }
          const double sub_area = area * h * h; // each sub-triangle: area / panels^2
          for (int a = 0; a < 8; ++a)
            for (int b = 0; b < 8; ++b)
            { // Duffy: (s, t) in [0,1]^2 -> p0 + s (p1 - p0) + s t (p2 - p1), jacobian s
              const double s = t8[a], t = t8[b];
              const Eigen::Vector2d uv = p0 + s * (p1 - p0) + s * t * (p2 - p1);
              const double wt = w8[a] * w8[b] * s * 2.0 * sub_area;
              const double l1 = uv(0), l2 = uv(1), l0 = 1.0 - l1 - l2;
              const Eigen::Vector3d xi = l0 * A + l1 * B + l2 * D;
              const double r = (xi - x).norm();
              const double dGdn = (xi - x).dot(n_out) / (4.0 * kPi * r * r * r);
              c.phi(C.F(f, 0)) += wt * l0 * dGdn;
              c.phi(C.F(f, 1)) += wt * l1 * dGdn;
              c.phi(C.F(f, 2)) += wt * l2 * dGdn;
              c.psi(f) += wt / (4.0 * kPi * r); // -G = 1 / (4 pi r)
            }
        }
  }
  c.psi *= sigma;
  return c;
}

TEST(GreenCoordinates, QuadratureReferenceIsConverged)
{
  const Cage square = test::unit_square();
  const Eigen::Vector2d x(0.3, 0.6);
  const Coordinates a = quadrature_2d(square, x, 64), b = quadrature_2d(square, x, 128);
  EXPECT_LT((a.phi - b.phi).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((a.psi - b.psi).cwiseAbs().maxCoeff(), 1e-13);
  const Cage cube = test::unit_cube();
  const Eigen::Vector3d y(0.3, 0.6, 0.45);
  const Coordinates c = quadrature_3d(cube, y, 8), d = quadrature_3d(cube, y, 16);
  EXPECT_LT((c.phi - d.phi).cwiseAbs().maxCoeff(), 1e-11);
  EXPECT_LT((c.psi - d.psi).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(GreenCoordinates, MatchQuadratureOfTheBoundaryIntegrals2D)
{
  for (const CatalogueCage& entry : test::builtin_cages_2d())
  {
    const GreenCoordinates gc(entry.cage);
    const Points P = test::sample_inside(entry.cage, 6, 0.05, 31);
    for (Index p = 0; p < P.rows(); ++p)
    {
      const Eigen::Vector2d x = P.row(p).transpose();
      const Coordinates ref = quadrature_2d(entry.cage, x, 128), got = at(gc, x);
      EXPECT_LT((ref.phi - got.phi).cwiseAbs().maxCoeff(), kQuadratureTol) << entry.name << " point " << p;
      EXPECT_LT((ref.psi - got.psi).cwiseAbs().maxCoeff(), kQuadratureTol) << entry.name << " point " << p;
    }
  }
}

TEST(GreenCoordinates, MatchQuadratureOfTheBoundaryIntegrals3D)
{
  for (const CatalogueCage& entry : test::cages_3d())
  {
    if (entry.cage.F.rows() > 40)
      continue; // the icosphere: 320 faces x 16^2 panels is a benchmark, not a test
    const GreenCoordinates gc(entry.cage);
    const Points P = test::sample_inside(entry.cage, 3, 0.05, 37);
    for (Index p = 0; p < P.rows(); ++p)
    {
      const Eigen::Vector3d x = P.row(p).transpose();
      const Coordinates ref = quadrature_3d(entry.cage, x, 16), got = at(gc, x);
      EXPECT_LT((ref.phi - got.phi).cwiseAbs().maxCoeff(), kQuadratureTol) << entry.name << " point " << p;
      EXPECT_LT((ref.psi - got.psi).cwiseAbs().maxCoeff(), kQuadratureTol) << entry.name << " point " << p;
    }
  }
}

// --- 2D conformality --------------------------------------------------------------------------

/// max over the points of the Cauchy-Riemann residual of the map's Jacobian by central
/// differences, |J11 - J22| + |J12 + J21|, relative to |J| (Frobenius): 0 for a conformal map.
template<class Map>
double cauchy_riemann_residual(const Points& P, double h, Map&& map)
{
  double worst = 0.0;
  for (Index p = 0; p < P.rows(); ++p)
  {
    const Eigen::Vector2d x = P.row(p).transpose();
    const Eigen::Vector2d dx = (map(x + Eigen::Vector2d(h, 0)) - map(x - Eigen::Vector2d(h, 0))) / (2 * h);
    const Eigen::Vector2d dy = (map(x + Eigen::Vector2d(0, h)) - map(x - Eigen::Vector2d(0, h))) / (2 * h);
    const double residual = std::abs(dx(0) - dy(1)) + std::abs(dx(1) + dy(0));
    const double size = std::sqrt(dx.squaredNorm() + dy.squaredNorm());
    worst = std::max(worst, residual / size);
  }
  return worst;
}

TEST(GreenCoordinates, Deformation2DIsConformalAndMeanValueIsNot)
{
  // A star cage bent: each vertex (x, y) moved to a parabola-like bend plus a shear of its tips.
  const Cage star = test::star_polygon(5, 1.0, 0.45);
  Eigen::MatrixXd D = star.V;
  for (Index i = 0; i < D.rows(); ++i)
  {
    const double x = star.V(i, 0), y = star.V(i, 1);
    D(i, 0) = x + 0.3 * y * y;
    D(i, 1) = y + 0.25 * x * x - 0.2 * (i % 2 ? 0.0 : x);
  }
  const GreenCoordinates gc(star);
  const MeanValueCoordinates mvc(star);
  const Eigen::MatrixXd N = green_face_terms(star, D);
  const Points P = test::sample_inside(star, 40, 0.02, 41);
  const double h = 1e-4 * star.diameter();
  const double green = cauchy_riemann_residual(P, h, [&](const Eigen::Vector2d& x) {
    const Coordinates c = at(gc, x);
    return Eigen::Vector2d(D.transpose() * c.phi + N.transpose() * c.psi);
  });
  const double mean_value = cauchy_riemann_residual(P, h, [&](const Eigen::Vector2d& x) {
    Eigen::VectorXd w(mvc.num_controls());
    mvc.evaluate(x.data(), w.data());
    return Eigen::Vector2d(D.transpose() * w);
  });
  std::cout << "Cauchy-Riemann residual (max over 40 points, relative to |J|): Green " << green
            << ", mean value " << mean_value << "\n";
  RecordProperty("green_cauchy_riemann", std::to_string(green));
  RecordProperty("mvc_cauchy_riemann", std::to_string(mean_value));
  EXPECT_LT(green, 1e-6);
  EXPECT_GT(mean_value, 1e-2); // MVC's map is far from conformal on this deformation
}

// --- Analytic cases, options, errors ----------------------------------------------------------

TEST(GreenCoordinates, SymmetricCentre)
{
  // At the centre of a regular polygon / the cube every phi_i and every psi_j is equal, by
  // symmetry: phi_i = 1 / n.
  const Cage hexagon = test::regular_polygon(6, 2.0);
  const Coordinates c = at(GreenCoordinates(hexagon), Eigen::Vector2d::Zero());
  for (Index i = 0; i < 6; ++i)
  {
    EXPECT_NEAR(c.phi(i), 1.0 / 6.0, 1e-14);
    EXPECT_NEAR(c.psi(i), c.psi(0), 1e-14);
  }
  const Coordinates d = at(GreenCoordinates(test::octahedron()), Eigen::Vector3d::Zero());
  for (Index i = 0; i < 6; ++i)
    EXPECT_NEAR(d.phi(i), 1.0 / 6.0, 1e-14);
  for (Index f = 0; f < 8; ++f)
    EXPECT_NEAR(d.psi(f), d.psi(0), 1e-14);
}

TEST(GreenCoordinates, OrientationIndependentCoordinates)
{
  // Reversing the cage's orientation keeps phi and flips the sign of psi (the faces' own
  // normals flip); the deformation is the same.
  for (const Cage& C : { test::u_polygon(), test::u_box() })
  {
    const Cage R = test::reversed(C);
    const Points P = test::sample_inside(C, 10, 1e-2, 3);
    const GreenResult a = green_coordinates(C, P), b = green_coordinates(R, P);
    for (Index i = 0; i < C.num_controls(); ++i)
      EXPECT_LT((a.W.col(i) - b.W.col(test::reversed_index(C, i))).cwiseAbs().maxCoeff(), 1e-12);
    if (C.dimension() == 3)
    { // faces keep their index (2D: edge j becomes another edge)
      EXPECT_LT((a.face_weights + b.face_weights).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(GreenCoordinates, ThreadCountDoesNotChangeTheResult)
{
  const Cage C = test::noisy_icosphere(1, 0.1, 5);
  const Points P = test::sample_inside(C, 50, 1e-3, 8);
  GreenOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const GreenResult a = GreenCoordinates(C, one).evaluate(P), b = GreenCoordinates(C, two).evaluate(P);
  EXPECT_EQ(a.W, b.W);
  EXPECT_EQ(a.face_weights, b.face_weights);
}

TEST(GreenCoordinates, RejectsBadInput)
{
  // open 3D cage: the cube without its last face
  Cage open = test::unit_cube();
  open.F.conservativeResize(open.F.rows() - 1, 3);
  EXPECT_TRUE(throws_error([&] { GreenCoordinates g(open); }, ErrorCode::InvalidCage));
  // self-intersecting polygon (a bow tie)
  Cage bow;
  bow.V.resize(4, 2);
  bow.V << 0, 0, 1, 1, 1, 0, 0, 1;
  EXPECT_TRUE(throws_error([&] { GreenCoordinates g(bow); }, ErrorCode::InvalidCage));
  Cage nan = test::unit_square();
  nan.V(1, 0) = std::nan("");
  EXPECT_TRUE(throws_error([&] { GreenCoordinates g(nan); }, ErrorCode::NonFinite));
  GreenOptions bad;
  bad.boundary_tolerance = 0.1;
  EXPECT_TRUE(throws_error([&] { GreenCoordinates g(test::unit_square(), bad); },
    ErrorCode::InvalidArgument, { "boundary_tolerance" }));
  const GreenCoordinates gc(test::unit_square());
  Points P(2, 2);
  P << 0.5, 0.5, std::numeric_limits<double>::infinity(), 0.0;
  EXPECT_TRUE(throws_error([&] { gc.evaluate(P); }, ErrorCode::NonFinite, { "point 1" }));
  EXPECT_TRUE(throws_error([&] { gc.evaluate(Points(1, 3)); }, ErrorCode::SizeMismatch));
  // the deformation's shapes
  const GreenResult r = gc.evaluate(Points::Constant(1, 2, 0.5));
  EXPECT_TRUE(throws_error([&] { deform_points_green(r.W, r.face_weights, test::unit_square(),
                                   Eigen::MatrixXd::Zero(3, 2)); },
    ErrorCode::SizeMismatch));
  EXPECT_TRUE(throws_error([&] { deform_points_green(r.W, DenseWeights(1, 3), test::unit_square(),
                                   test::unit_square().V); },
    ErrorCode::SizeMismatch, { "face coefficients" }));
  Eigen::MatrixXd inf = test::unit_square().V;
  inf(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error(
    [&] { deform_points_green(r.W, r.face_weights, test::unit_square(), inf); }, ErrorCode::NonFinite));
}

TEST(GreenCoordinates, StretchFactors)
{
  // 2D: s_j = |e'| / |e|; 3D: a face scaled by lambda has s = lambda, a face sheared in its plane
  // (u' = u, v' = v + u) has s = sqrt(|M|_F^2 / 2) of the map.
  const Cage square = test::unit_square();
  Eigen::MatrixXd D = square.V;
  D.row(1) *= 3.0; // edge 0 (0 -> 1) three times longer
  const Eigen::MatrixXd N2 = green_face_terms(square, D);
  EXPECT_NEAR(N2.row(0).norm(), (D.row(1) - D.row(0)).norm() / 1.0, 1e-15);
  const Cage cube = test::unit_cube();
  const Eigen::MatrixXd N3 = green_face_terms(cube, 2.0 * cube.V);
  for (Index f = 0; f < cube.F.rows(); ++f)
    EXPECT_NEAR(N3.row(f).norm(), 2.0, 1e-14);
  // a face sheared in its plane: u = (1,0,0), v = (0,1,0) to u' = u, v' = v + u, the map
  // M = [[1, 1], [0, 1]] in that orthonormal basis, |M|_F^2 = 3, s = sqrt(3 / 2)
  Cage tet;
  tet.V.resize(4, 3);
  tet.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  tet.F.resize(4, 3);
  tet.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  Eigen::MatrixXd S = tet.V;
  S.row(2) << 1, 1, 0;
  const Eigen::MatrixXd NS = green_face_terms(tet, S);
  EXPECT_NEAR(NS.row(0).norm(), std::sqrt(1.5), 1e-14);
  // its normal: the deformed face's own normal (still -z for (0, 2, 1))
  EXPECT_NEAR(NS(0, 2) / NS.row(0).norm(), -1.0, 1e-14);
}

} // namespace
