// Tests for core/coordinates/mean_value_coordinates.h.
//
// Property tests run over the whole cage catalogue (cage_catalogue.h): partition of unity,
// linear reproduction, Lagrange property, linearity on edges and faces, continuity at the
// boundary, behaviour outside, non-negativity on convex cages, thread-count and orientation
// independence, and the counts of MeanValueResult. Then independent checks that do not use the
// implementation: symmetry, and a numerical quadrature of the defining integral of 3D mean
// value coordinates (Ju, Schaefer & Warren 2005: the spherical integral of the linear hat
// functions divided by the distance) on each face. The 2D cross-check against CGAL is in
// mean_value_coordinates_cgal_test.cpp.
//
// Tolerances. u = 2^-53 ~ 1.1e-16 is the unit roundoff.
// - Partition of unity: the weights are divided by their sum, so sum_i w_i - 1 is the rounding
//   of n + 1 operations on terms of size |w_i|: |sum - 1| <= (n + 1) u sum_i |w_i|. With n <= 162
//   controls that is < 2e-14 sum|w|; we allow kSumTol = 1e-13 times sum|w|.
// - Linear reproduction: each raw weight comes out of O(10-30) floating-point operations whose
//   relative error is amplified by at most the conditioning of the angles involved; for points at
//   least 1e-3 * diam from the cage that gives a relative error of each term below ~1e-13. The
//   error of sum_i w_i c_i - x is then below that times diam * sum|w|; we allow kReproTol = 1e-12.
// - Lagrange property: exact (the implementation returns the unit vector at a vertex).
// - Edge/face interpolation: a point built as (1-t) a + t b carries a rounding of u |a|, which
//   moves the weights by u * |a| / |b - a|, < 1e-14 for the catalogue; we allow 1e-12.
// - Continuity: at distance delta = rel * (local feature size: distance to the nearest vertex
//   or edge) inside an edge or face, the weights differ from the boundary interpolant by about
//   |grad w| delta <~ 5 rel; we allow kContinuityTol = 1e-5 plus 5 rel (rel = 1e-7), and
//   NearTheBoundaryAsInside goes down to 1e-8.
// - Orientation: reversing changes only the order/sign of operations; 1e-12 times sum|w|.
// - 3D outside: see kOutside3DTol (grazing faces).
#include "cage_catalogue.h"
#include "core/common/error.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/detail/simd.h"
#include "error_matchers.h"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace bary
{
/// GoogleTest printer for PointLocation.
void PrintTo(PointLocation l, std::ostream* os)
{
  *os << (l == PointLocation::Inside ? "Inside"
      : l == PointLocation::Outside  ? "Outside"
                                     : "Boundary");
}
} // namespace bary

namespace
{
using namespace bary;
using bary::test::CatalogueCage;
using bary::test::throws_error;

constexpr double kSumTol = 1e-13;
constexpr double kReproTol = 1e-12;
constexpr double kInterpTol = 1e-12;
constexpr double kContinuityTol = 1e-5;
constexpr double kOrientationTol = 1e-12;
// 3D, outside: faces near the silhouette are seen almost edge-on; their contribution is a
// ratio of two vanishing quantities (theta_i - c theta - c theta and det[u0,u1,u2]), so core
// loses digits: an independent quadrature reproduces x to 1e-15 at the same points, core only
// to ~1e-10 (see MeanValueCoordinates3D.MatchesQuadratureOutside). Allowed: 1e-9 times sum|w|.
constexpr double kOutside3DTol = 1e-9;
constexpr double kMinDistance = 1e-3; // sampled points keep this * diam from the cage

/// |sum_i w_i - 1| and sum_i |w_i| of one row.
struct RowCheck
{
  double partition_error;
  double abs_sum;
  double reproduction_error; // |sum_i w_i c_i - x| / diam
};

RowCheck check_row(const Cage& cage, const double* w, const Eigen::VectorXd& x)
{
  RowCheck r{ 0, 0, 0 };
  const Index n = cage.num_controls();
  const int dim = cage.dimension();
  double sum = 0.0;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(dim);
  for (Index i = 0; i < n; ++i)
  {
    sum += w[i];
    r.abs_sum += std::abs(w[i]);
    y += w[i] * cage.V.row(i).transpose();
  }
  r.partition_error = std::abs(sum - 1.0);
  r.reproduction_error = (y - x).norm() / cage.diameter();
  return r;
}

Eigen::VectorXd weights_at(
  const MeanValueCoordinates& mvc, const Eigen::VectorXd& x, PointLocation* location = nullptr)
{
  Eigen::VectorXd w(mvc.num_controls());
  const PointLocation l = mvc.evaluate(x.data(), w.data());
  if (location)
    *location = l;
  return w;
}

std::string describe(const Eigen::VectorXd& x)
{
  std::ostringstream s;
  s.precision(17);
  s << "x = (" << x.transpose() << ")";
  return s.str();
}

/// The boundary interpolant: weights @p values on vertices @p ids, 0 elsewhere.
Eigen::VectorXd interpolant(Index n, std::initializer_list<std::pair<int, double>> entries)
{
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  for (const auto& [id, value] : entries)
    w(id) += value;
  return w;
}

/// Points on the boundary with their exact interpolant: 2D edges at t, 3D edges at t and face
/// interior points at fixed barycentric coordinates.
struct BoundaryPoint
{
  Eigen::VectorXd x;
  Eigen::VectorXd expected;
  Eigen::VectorXd inward; // unit direction into the cage
  double local_size;      // distance from x to the nearest vertex (edges) or edge (faces)
  std::string what;
};

std::vector<BoundaryPoint> boundary_points(const Cage& cage)
{
  std::vector<BoundaryPoint> out;
  const Index n = cage.num_controls();
  const Eigen::MatrixXd& V = cage.V;
  const auto edges = test::cage_edges(cage);
  // 3D: inward direction at an edge = sum of the inward normals of its two faces.
  std::map<std::pair<int, int>, Eigen::VectorXd> edge_inward;
  if (cage.dimension() == 3)
    for (Index f = 0; f < cage.F.rows(); ++f)
    {
      const Eigen::VectorXd nf = test::inward_normal(cage, f);
      for (int k = 0; k < 3; ++k)
      {
        const int a = cage.F(f, k), b = cage.F(f, (k + 1) % 3);
        auto& acc = edge_inward[{ std::min(a, b), std::max(a, b) }];
        if (acc.size() == 0)
          acc = Eigen::VectorXd::Zero(3);
        acc += nf;
      }
    }
  for (std::size_t e = 0; e < edges.size(); ++e)
  {
    const auto [a, b] = edges[e];
    const Eigen::VectorXd inward = cage.dimension() == 2
      ? test::inward_normal(cage, static_cast<Index>(e))
      : Eigen::VectorXd(edge_inward.at({ a, b }).normalized());
    for (const double t : { 0.5, 0.3, 0.9 })
      out.push_back({ ((1 - t) * V.row(a) + t * V.row(b)).transpose(),
        interpolant(n, { { a, 1 - t }, { b, t } }), inward,
        std::min(t, 1 - t) * (V.row(b) - V.row(a)).norm(),
        "edge (" + std::to_string(a) + ", " + std::to_string(b) +
          ") at t = " + std::to_string(t) });
  }
  if (cage.dimension() == 3)
    for (Index f = 0; f < cage.F.rows(); ++f)
    {
      const int i0 = cage.F(f, 0), i1 = cage.F(f, 1), i2 = cage.F(f, 2);
      const Eigen::Vector3d p0 = V.row(i0), p1 = V.row(i1), p2 = V.row(i2);
      const double twice_area = (p1 - p0).cross(p2 - p0).norm();
      // distance to the edge opposite vertex k = l_k * (twice area / |opposite edge|)
      const double h[3] = { twice_area / (p2 - p1).norm(), twice_area / (p0 - p2).norm(),
        twice_area / (p1 - p0).norm() };
      for (const auto& l : { std::array<double, 3>{ 1.0 / 3, 1.0 / 3, 1.0 / 3 },
             std::array<double, 3>{ 0.2, 0.3, 0.5 }, std::array<double, 3>{ 0.6, 0.3, 0.1 } })
        out.push_back({ (l[0] * V.row(i0) + l[1] * V.row(i1) + l[2] * V.row(i2)).transpose(),
          interpolant(n, { { i0, l[0] }, { i1, l[1] }, { i2, l[2] } }),
          test::inward_normal(cage, f), std::min({ l[0] * h[0], l[1] * h[1], l[2] * h[2] }),
          "face " + std::to_string(f) + " at (" + std::to_string(l[0]) + ", " +
            std::to_string(l[1]) + ", " + std::to_string(l[2]) + ")" });
    }
  return out;
}

std::vector<CatalogueCage> all_cages()
{
  std::vector<CatalogueCage> out = test::cages_2d();
  for (auto& c : test::cages_3d())
    out.push_back(std::move(c));
  return out;
}

// --- Properties over the catalogue ------------------------------------------------------------

class MeanValueProperties : public ::testing::TestWithParam<CatalogueCage>
{
protected:
  const Cage& cage() const { return GetParam().cage; }
  /// A seed per cage (FNV-1a of its name: the same on every platform, unlike std::hash).
  std::uint64_t seed() const
  {
    std::uint64_t h = 14695981039346656037ULL;
    for (const char c : GetParam().name)
      h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
    return h;
  }
};

TEST_P(MeanValueProperties, PartitionOfUnityAndReproductionInside)
{
  const MeanValueCoordinates mvc(cage());
  const Points P = test::sample_inside(cage(), 300, kMinDistance, seed());
  const MeanValueResult r = mvc.evaluate(P);
  ASSERT_EQ(r.W.rows(), P.rows());
  ASSERT_EQ(r.W.cols(), cage().num_controls());
  EXPECT_EQ(r.inside, P.rows());
  EXPECT_TRUE(r.undefined.empty());
  for (Index p = 0; p < P.rows(); ++p)
  {
    ASSERT_TRUE(r.W.row(p).allFinite()) << describe(P.row(p));
    EXPECT_EQ(r.location[static_cast<std::size_t>(p)], PointLocation::Inside) << describe(P.row(p));
    const RowCheck c = check_row(cage(), r.W.row(p).data(), P.row(p).transpose());
    EXPECT_LE(c.partition_error, kSumTol * c.abs_sum) << describe(P.row(p));
    EXPECT_LE(c.reproduction_error, kReproTol * c.abs_sum) << describe(P.row(p));
  }
}

TEST_P(MeanValueProperties, LagrangeAtVertices)
{
  const MeanValueCoordinates mvc(cage());
  const Index n = cage().num_controls();
  for (Index i = 0; i < n; ++i)
  {
    PointLocation where;
    const Eigen::VectorXd w = weights_at(mvc, cage().V.row(i).transpose(), &where);
    EXPECT_EQ(where, PointLocation::Boundary) << "vertex " << i;
    for (Index j = 0; j < n; ++j)
      EXPECT_EQ(w(j), i == j ? 1.0 : 0.0) << "vertex " << i << ", weight " << j;
  }
  // The batch path agrees and counts them as boundary points.
  const MeanValueResult r = mvc.evaluate(cage().V);
  EXPECT_EQ(r.boundary, n);
  EXPECT_EQ((r.W - DenseWeights::Identity(n, n)).cwiseAbs().maxCoeff(), 0.0);
}

TEST_P(MeanValueProperties, LinearOnEdgesAndFaces)
{
  // 2D: (1-t, t) on the edge's ends. 3D: the same on every edge (VTK's vtkMeanValueCoordinates
  // gets edges wrong) and barycentric coordinates inside every face.
  const MeanValueCoordinates mvc(cage());
  for (const BoundaryPoint& b : boundary_points(cage()))
  {
    PointLocation where;
    const Eigen::VectorXd w = weights_at(mvc, b.x, &where);
    EXPECT_EQ(where, PointLocation::Boundary) << b.what;
    ASSERT_TRUE(w.allFinite()) << b.what;
    EXPECT_LE((w - b.expected).cwiseAbs().maxCoeff(), kInterpTol)
      << b.what << "\n got      " << w.transpose() << "\n expected " << b.expected.transpose();
  }
}

TEST_P(MeanValueProperties, ContinuousAtTheBoundary)
{
  // Just inside an edge or face the weights approach the boundary interpolant. The distance is
  // relative to the local feature size (the gradient of the weights grows like 1 / distance to
  // the nearest vertex or edge): 1e-7 of it, in 2D and 3D.
  const MeanValueCoordinates mvc(cage());
  const double rel = 1e-7;
  for (const BoundaryPoint& b : boundary_points(cage()))
  {
    const Eigen::VectorXd x = b.x + rel * b.local_size * b.inward;
    ASSERT_GT(std::abs(test::winding_number(cage(), x.data())), 0.5) << "test bug: " << b.what;
    PointLocation where;
    const Eigen::VectorXd w = weights_at(mvc, x, &where);
    EXPECT_EQ(where, PointLocation::Inside) << b.what;
    ASSERT_TRUE(w.allFinite()) << b.what;
    // The weights themselves move by |grad w| * distance, with |grad w| up to a few / local
    // size on the catalogue's dihedral angles: allow 5 rel on top of kContinuityTol.
    EXPECT_LE((w - b.expected).cwiseAbs().maxCoeff(), kContinuityTol + 5 * rel)
      << b.what << "\n got      " << w.transpose() << "\n expected " << b.expected.transpose();
  }
}

// Regression test for two 3D bugs of the first implementation (Ju et al.'s Fig. 4 verbatim):
// at 1e-7 and 1e-8 of the local feature size inside an edge or face it reported Boundary
// ("pi - h <= 1e-12" caught points up to ~1e-6 * face size away) and near edges gave weights
// off by up to 1e-3 (s = sqrt(1 - c^2) cancels as c -> -1; error ~ 1/distance^2). Core now
// takes s from det[u0, u1, u2].
TEST_P(MeanValueProperties, NearTheBoundaryAsInside)
{
  const MeanValueCoordinates mvc(cage());
  for (const double rel : { 1e-7, 1e-8 })
    for (const BoundaryPoint& b : boundary_points(cage()))
    {
      const double delta = rel * b.local_size;
      if (delta < 10 * MeanValueOptions{}.boundary_tolerance * cage().diameter())
        continue; // within reach of the boundary tolerance: Boundary is right there
      const Eigen::VectorXd x = b.x + delta * b.inward;
      PointLocation where;
      const Eigen::VectorXd w = weights_at(mvc, x, &where);
      EXPECT_EQ(where, PointLocation::Inside) << b.what << " at " << rel;
      EXPECT_LE((w - b.expected).cwiseAbs().maxCoeff(), kContinuityTol) << b.what << " at " << rel;
    }
}

TEST_P(MeanValueProperties, FiniteJustBeyondTheBoundaryTolerance)
{
  // Points closer than options.boundary_tolerance (1e-10 diam) get the interpolant exactly;
  // points just farther away go through the general formula, which must stay finite there.
  // Distances: 3, 10 and 100 times the tolerance. (2D gave NaN here, and Outside, before the
  // tangent of the half angle was computed as (r_i r_j - D_i) / (2 A_i) for obtuse angles.)
  // In 2D the weights must also be close to the interpolant and the point Inside; in 3D that is
  // the known bug above.
  const MeanValueCoordinates mvc(cage());
  for (const double rel : { 3e-10, 1e-9, 1e-8 })
  {
    const double delta = rel * cage().diameter();
    for (const BoundaryPoint& b : boundary_points(cage()))
    {
      const Eigen::VectorXd x = b.x + delta * b.inward;
      PointLocation where;
      const Eigen::VectorXd w = weights_at(mvc, x, &where);
      ASSERT_TRUE(w.allFinite()) << b.what << " at distance " << rel << " diam: " << describe(x)
                                 << "\n got " << w.transpose();
      EXPECT_NE(where, PointLocation::Outside) << b.what << " at " << rel << " diam";
      EXPECT_LE(std::abs(w.sum() - 1.0), kSumTol * w.cwiseAbs().sum()) << b.what;
      if (cage().dimension() == 2)
      {
        EXPECT_EQ(where, PointLocation::Inside) << b.what << " at " << rel << " diam";
        EXPECT_LE((w - b.expected).cwiseAbs().maxCoeff(), kContinuityTol)
          << b.what << " at " << rel << " diam";
      }
    }
  }
}

TEST_P(MeanValueProperties, WithinTheBoundaryToleranceIsBoundary)
{
  // Half the tolerance off an edge/face, towards the inside and the outside: the interpolant.
  MeanValueOptions options;
  options.boundary_tolerance = 1e-6; // large enough that the offset is far above rounding
  const MeanValueCoordinates mvc(cage(), options);
  const double delta = 0.5 * options.boundary_tolerance * cage().diameter();
  for (const BoundaryPoint& b : boundary_points(cage()))
    for (const double side : { 1.0, -1.0 })
    {
      PointLocation where;
      const Eigen::VectorXd w = weights_at(mvc, b.x + side * delta * b.inward, &where);
      EXPECT_EQ(where, PointLocation::Boundary) << b.what << ", side " << side;
      // The offset is (nearly) normal to the edge/face, so the projection barely moves: the
      // interpolant changes by at most delta / (height of the face) ~ 5e-7 diam / height.
      EXPECT_LE((w - b.expected).cwiseAbs().maxCoeff(), 1e-5) << b.what;
      EXPECT_NEAR(w.sum(), 1.0, 1e-14) << b.what;
    }
}

TEST_P(MeanValueProperties, OutsideReproducesAndIsOutside)
{
  const MeanValueCoordinates mvc(cage());
  const Points P = test::sample_outside(cage(), 200, kMinDistance, 2.0, seed());
  const MeanValueResult r = mvc.evaluate(P);
  EXPECT_EQ(r.outside, P.rows());
  EXPECT_EQ(r.inside, 0);
  EXPECT_EQ(r.boundary, 0);
  std::set<Index> undefined(r.undefined.begin(), r.undefined.end());
  for (Index p = 0; p < P.rows(); ++p)
  {
    EXPECT_EQ(r.location[static_cast<std::size_t>(p)], PointLocation::Outside)
      << describe(P.row(p));
    if (!r.W.row(p).allFinite())
    { // allowed only where the raw weights sum to ~0, and then it is reported
      EXPECT_TRUE(undefined.count(p)) << describe(P.row(p));
      EXPECT_TRUE(r.W.row(p).array().isNaN().all()) << describe(P.row(p));
      continue;
    }
    const RowCheck c = check_row(cage(), r.W.row(p).data(), P.row(p).transpose());
    EXPECT_LE(c.partition_error, kSumTol * c.abs_sum) << describe(P.row(p));
    EXPECT_LE(
      c.reproduction_error, (cage().dimension() == 2 ? kReproTol : kOutside3DTol) * c.abs_sum)
      << describe(P.row(p));
  }
  // Undefined points are the exception: a sum of raw weights that is exactly ~0 is a
  // measure-zero event for random points.
  EXPECT_LE(r.undefined.size(), 2u);
}

TEST_P(MeanValueProperties, IndependentOfThreadCount)
{
  // 5000 points: inside, outside and on the boundary, shuffled so that threads see a mix.
  const Points in = test::sample_inside(cage(), 3000, 0.0, seed() + 2);
  const Points out = test::sample_outside(cage(), 1800, 0.0, 1.5, seed() + 3);
  Points P(5000, cage().dimension());
  P << in, out, cage().V.topRows(std::min<Index>(200, cage().num_controls())),
    Points::Zero(std::max<Index>(0, 200 - cage().num_controls()), cage().dimension());
  // Fill the remainder (if the cage has fewer than 200 vertices) with edge midpoints.
  const auto edges = test::cage_edges(cage());
  for (Index p = 4800 + std::min<Index>(200, cage().num_controls()), e = 0; p < 5000; ++p, ++e)
  {
    const auto [a, b] = edges[static_cast<std::size_t>(e) % edges.size()];
    P.row(p) = 0.5 * (cage().V.row(a) + cage().V.row(b));
  }
  test::Rng rng(seed() + 4);
  for (Index p = P.rows() - 1; p > 0; --p)
    P.row(p).swap(P.row(static_cast<Index>(rng.next() % static_cast<std::uint64_t>(p + 1))));

  MeanValueOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const MeanValueResult a = MeanValueCoordinates(cage(), one).evaluate(P);
  const MeanValueResult b = MeanValueCoordinates(cage(), two).evaluate(P);
  ASSERT_EQ(a.W.size(), b.W.size());
  EXPECT_EQ(
    std::memcmp(a.W.data(), b.W.data(), sizeof(double) * static_cast<std::size_t>(a.W.size())), 0)
    << "weights differ between 1 and 2 threads";
  EXPECT_EQ(a.location, b.location);
  EXPECT_EQ(a.undefined, b.undefined);
  EXPECT_EQ(a.inside, b.inside);
  EXPECT_EQ(a.outside, b.outside);
  EXPECT_EQ(a.boundary, b.boundary);
}

TEST_P(MeanValueProperties, IndependentOfOrientation)
{
  const Cage flipped = test::reversed(cage());
  const MeanValueCoordinates mvc(cage()), mvc_flipped(flipped);
  Points P(300, cage().dimension());
  P << test::sample_inside(cage(), 200, kMinDistance, seed() + 5),
    test::sample_outside(cage(), 100, kMinDistance, 2.0, seed() + 6);
  const MeanValueResult r = mvc.evaluate(P), rf = mvc_flipped.evaluate(P);
  EXPECT_EQ(r.location, rf.location);
  const Index n = cage().num_controls();
  for (Index p = 0; p < P.rows(); ++p)
  {
    if (!r.W.row(p).allFinite())
      continue;
    const bool outside_3d = p >= 200 && cage().dimension() == 3;
    const double scale =
      r.W.row(p).cwiseAbs().sum() * (outside_3d ? kOutside3DTol : kOrientationTol);
    for (Index i = 0; i < n; ++i)
      EXPECT_NEAR(r.W(p, i), rf.W(p, test::reversed_index(cage(), i)), scale)
        << describe(P.row(p)) << ", vertex " << i;
  }
}

TEST_P(MeanValueProperties, ResultCountsOnAConstructedSet)
{
  // 7 inside, 5 outside, every vertex and 3 edge midpoints on the boundary, interleaved.
  const Points in = test::sample_inside(cage(), 7, kMinDistance, seed() + 7);
  const Points out = test::sample_outside(cage(), 5, kMinDistance, 2.0, seed() + 8);
  const auto edges = test::cage_edges(cage());
  const Index n = cage().num_controls();
  Points P(12 + n + 3, cage().dimension());
  std::vector<PointLocation> expected;
  Index row = 0;
  for (Index k = 0; k < 7; ++k)
  {
    P.row(row++) = in.row(k);
    expected.push_back(PointLocation::Inside);
    if (k < 5)
    {
      P.row(row++) = out.row(k);
      expected.push_back(PointLocation::Outside);
    }
  }
  for (Index i = 0; i < n; ++i)
  {
    P.row(row++) = cage().V.row(i);
    expected.push_back(PointLocation::Boundary);
  }
  for (std::size_t e = 0; e < 3; ++e)
  {
    P.row(row++) = 0.5 * (cage().V.row(edges[e].first) + cage().V.row(edges[e].second));
    expected.push_back(PointLocation::Boundary);
  }
  ASSERT_EQ(row, P.rows());
  const MeanValueResult r = MeanValueCoordinates(cage()).evaluate(P);
  EXPECT_EQ(r.inside, 7);
  EXPECT_EQ(r.outside, 5);
  EXPECT_EQ(r.boundary, n + 3);
  EXPECT_EQ(r.location, expected);
  EXPECT_TRUE(r.undefined.empty());
  // the shared result shape: the same counts, no statistics, always converged
  EXPECT_EQ(r.count(PointLocation::Inside), 7);
  EXPECT_EQ(r.count(PointLocation::Outside), 5);
  EXPECT_EQ(r.count(PointLocation::Boundary), n + 3);
  EXPECT_TRUE(r.statistics.empty());
  EXPECT_TRUE(r.converged);
}

TEST_P(MeanValueProperties, OneCallFormMatchesTheEvaluator)
{
  const Points P = test::sample_inside(cage(), 20, kMinDistance, seed() + 9);
  const DenseWeights a = mean_value_coordinates(cage(), P);
  const DenseWeights b = MeanValueCoordinates(cage()).evaluate(P).W;
  EXPECT_TRUE((a.array() == b.array()).all());
}

TEST_P(MeanValueProperties, ReusedResultEqualsAFreshOne)
{
  // inside, outside and on the boundary (every vertex), 7 + 5 + n points: a partial last group
  // of the vector kernel for most n
  const Points in = test::sample_inside(cage(), 7, kMinDistance, seed() + 10);
  const Points out = test::sample_outside(cage(), 5, kMinDistance, 2.0, seed() + 11);
  const Index n = cage().num_controls();
  Points P(12 + n, cage().dimension());
  P << in, out, cage().V;
  const MeanValueCoordinates mvc(cage());
  const MeanValueResult fresh = mvc.evaluate(P);
  const auto same = [&](const MeanValueResult& r) {
    ASSERT_EQ(r.W.rows(), fresh.W.rows());
    ASSERT_EQ(r.W.cols(), fresh.W.cols());
    EXPECT_EQ(std::memcmp(r.W.data(), fresh.W.data(), sizeof(double) * r.W.size()), 0);
    EXPECT_EQ(r.location, fresh.location);
    EXPECT_EQ(r.undefined, fresh.undefined);
    EXPECT_EQ(r.inside, fresh.inside);
    EXPECT_EQ(r.outside, fresh.outside);
    EXPECT_EQ(r.boundary, fresh.boundary);
    EXPECT_TRUE(r.statistics.empty());
    EXPECT_EQ(r.face_weights.size(), 0);
  };
  // storage of the right shape holding garbage: every row is overwritten, every field reset
  MeanValueResult reused;
  reused.W = DenseWeights::Constant(P.rows(), n, std::numeric_limits<double>::quiet_NaN());
  reused.location.assign(static_cast<std::size_t>(P.rows()), PointLocation::Boundary);
  reused.undefined = { 0, 3 };
  reused.inside = reused.outside = reused.boundary = 99;
  reused.statistics = { { "stale", 1.0 } };
  reused.face_weights = DenseWeights::Ones(2, 2);
  const double* storage = reused.W.data();
  mvc.evaluate(P, reused);
  same(reused);
  EXPECT_EQ(reused.W.data(), storage) << "W's storage was not reused";
  // again (the previous weights in place), then from storage of another shape
  mvc.evaluate(P, reused);
  same(reused);
  MeanValueResult other;
  other.W = DenseWeights::Constant(3, n + 1, -1.0);
  mvc.evaluate(P, other);
  same(other);
}

std::string cage_name(const ::testing::TestParamInfo<CatalogueCage>& info)
{
  return info.param.name;
}

INSTANTIATE_TEST_SUITE_P(
  Catalogue, MeanValueProperties, ::testing::ValuesIn(all_cages()), cage_name);

// --- Known properties of particular cages -----------------------------------------------------

TEST(MeanValueCoordinates, NonNegativeInsideConvexCages)
{
  // Mean value coordinates are positive inside convex cages (Floater 2003; Ju et al. 2005).
  // 2D: every term of Hormann & Floater's Eq. (7) is positive inside a convex polygon, so rounding
  // cannot make a weight negative. 3D: the terms of Ju et al.'s Fig. 4 differ in sign; allow a few
  // roundings.
  std::vector<CatalogueCage> convex;
  for (auto& entry : all_cages())
    if (entry.convex)
      convex.push_back(std::move(entry));
  ASSERT_GE(convex.size(), 4u);
  for (const CatalogueCage& entry : convex)
  {
    const Points P = test::sample_inside(entry.cage, 500, kMinDistance, 77);
    const DenseWeights W = MeanValueCoordinates(entry.cage).evaluate(P).W;
    EXPECT_GE(W.minCoeff(), entry.cage.dimension() == 2 ? 0.0 : -1e-15) << entry.name;
  }
}

TEST(MeanValueCoordinates, NonConvexCagesHaveNegativeWeights)
{
  // Mean value coordinates are not positive inside non-convex polygons in general (Floater 2003
  // proves positivity only in the kernel of star-shaped polygons). A grid
  // over the bounding box finds negative weights inside the thin-armed star and the U (a point
  // in one arm of the U sees the other arm's inner wall from behind).
  for (const Cage& cage : { test::star_polygon(5, 1.0, 0.3), test::u_polygon() })
  {
    const Eigen::Vector2d lo = cage.V.colwise().minCoeff(), hi = cage.V.colwise().maxCoeff();
    const int n = 300;
    Points P(n * n, 2);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        P.row(i * n + j) << lo.x() + (hi.x() - lo.x()) * (i + 0.5) / n,
          lo.y() + (hi.y() - lo.y()) * (j + 0.5) / n;
    const MeanValueResult r = MeanValueCoordinates(cage).evaluate(P);
    double min_inside = 0.0;
    for (Index p = 0; p < P.rows(); ++p)
      if (r.location[static_cast<std::size_t>(p)] == PointLocation::Inside)
        min_inside = std::min(min_inside, r.W.row(p).minCoeff());
    EXPECT_LT(min_inside, -1e-5) << cage.num_controls() << "-vertex cage";
  }
}

TEST(MeanValueCoordinates, SymmetricCentres2D)
{
  // Square and regular 64-gon: the dihedral symmetry forces equal weights at the centre.
  const Eigen::Vector2d centre_square(0.5, 0.5);
  const Eigen::VectorXd ws = weights_at(MeanValueCoordinates(test::unit_square()), centre_square);
  for (Index i = 0; i < 4; ++i)
    EXPECT_NEAR(ws(i), 0.25, 1e-15);
  const Eigen::VectorXd w64 =
    weights_at(MeanValueCoordinates(test::regular_polygon(64)), Eigen::Vector2d::Zero());
  for (Index i = 0; i < 64; ++i)
    EXPECT_NEAR(w64(i), 1.0 / 64, 1e-15);
}

/// Mean value coordinates from their definition (Floater 2003; Hormann & Floater 2006):
/// w_i = (tan(a_{i-1} / 2) + tan(a_i / 2)) / r_i, with the signed angles a_i at x spanned
/// by edge i taken from atan2 and everything in long double. Independent of core's tangent
/// formula (sin / (1 + cos)).
Eigen::VectorXd mvc_by_definition(const Cage& cage, const Eigen::VectorXd& x)
{
  const Index n = cage.num_controls();
  std::vector<long double> t(static_cast<std::size_t>(n)), r(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1) % n;
    const long double ax = static_cast<long double>(cage.V(i, 0)) - x(0);
    const long double ay = static_cast<long double>(cage.V(i, 1)) - x(1);
    const long double bx = static_cast<long double>(cage.V(j, 0)) - x(0);
    const long double by = static_cast<long double>(cage.V(j, 1)) - x(1);
    t[static_cast<std::size_t>(i)] = std::tan(std::atan2(ax * by - ay * bx, ax * bx + ay * by) / 2);
    r[static_cast<std::size_t>(i)] = std::sqrt(ax * ax + ay * ay);
  }
  std::vector<long double> w(static_cast<std::size_t>(n));
  long double sum = 0;
  for (Index i = 0; i < n; ++i)
  {
    const auto k = static_cast<std::size_t>(i), h = static_cast<std::size_t>((i + n - 1) % n);
    sum += (w[k] = (t[h] + t[k]) / r[k]);
  }
  Eigen::VectorXd out(n);
  for (Index i = 0; i < n; ++i)
    out(i) = static_cast<double>(w[static_cast<std::size_t>(i)] / sum);
  return out;
}

TEST(MeanValueCoordinates2D, MatchesTheDefinitionInLongDouble)
{
  for (const CatalogueCage& entry : test::cages_2d())
  {
    const MeanValueCoordinates mvc(entry.cage);
    Points P(120, 2);
    P << test::sample_inside(entry.cage, 80, kMinDistance, 11),
      test::sample_outside(entry.cage, 40, kMinDistance, 2.0, 12);
    const DenseWeights W = mvc.evaluate(P).W;
    for (Index p = 0; p < P.rows(); ++p)
    {
      const Eigen::VectorXd ref = mvc_by_definition(entry.cage, P.row(p).transpose());
      const double scale = ref.cwiseAbs().sum();
      EXPECT_LE((W.row(p).transpose() - ref).cwiseAbs().maxCoeff(), kReproTol * scale)
        << entry.name << ", " << describe(P.row(p));
    }
  }
}

// --- Independent 3D reference: quadrature of the defining integral ----------------------------

/// Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n, Golub-Welsch not needed).
std::pair<std::vector<double>, std::vector<double>> gauss_legendre(int n)
{
  std::vector<double> x(static_cast<std::size_t>(n)), w(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
  {
    long double z = std::cos(3.14159265358979323846L * (i + 0.75L) / (n + 0.5L));
    long double dp = 0;
    for (int it = 0; it < 100; ++it)
    {
      long double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k)
      {
        const long double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const long double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-19L)
        break;
    }
    x[static_cast<std::size_t>(i)] = static_cast<double>(0.5L * (1 - z));
    w[static_cast<std::size_t>(i)] = static_cast<double>(1.0L / ((1 - z * z) * dp * dp));
  }
  return { x, w };
}

/// Mean value coordinates of a closed triangle mesh by quadrature of Ju et al.'s integral
///   w_i(x) ~ int_S phi_i(p(s)) / |p(s) - x| ds   (S the unit sphere around x),
/// rewritten on each face T as int_T phi_i(p) ((p - x) . n_T) / |p - x|^4 dA (the solid-angle
/// element is ((p - x) . n) / |p - x|^3 dA, signed, which also covers non-convex cages). Each
/// face is split into 4^levels triangles, each integrated with an order x order Gauss-Legendre
/// rule on the Duffy square. Accurate when x is not close to the cage.
Eigen::VectorXd mvc_by_quadrature(const Cage& cage, const Eigen::Vector3d& x, int levels, int order)
{
  const auto [gx, gw] = gauss_legendre(order);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(cage.num_controls());
  const int m = 1 << levels; // sub-triangles per edge
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const int id[3] = { cage.F(f, 0), cage.F(f, 1), cage.F(f, 2) };
    const Eigen::Vector3d A = cage.V.row(id[0]), B = cage.V.row(id[1]), C = cage.V.row(id[2]);
    const Eigen::Vector3d normal2 = (B - A).cross(C - A); // 2 area * unit normal
    // Sub-triangles in barycentric (u, v) of the face, p = A + u (B - A) + v (C - A).
    auto integrate = [&](const Eigen::Vector2d& q0, const Eigen::Vector2d& q1,
                       const Eigen::Vector2d& q2) {
      const double sub_area_ratio =
        std::abs((q1 - q0).x() * (q2 - q0).y() - (q1 - q0).y() * (q2 - q0).x());
      for (std::size_t a = 0; a < gx.size(); ++a)
        for (std::size_t b = 0; b < gx.size(); ++b)
        {
          const double s = gx[a], t = gx[b];
          const Eigen::Vector2d q = q0 + s * (q1 - q0) + s * t * (q2 - q1);
          const Eigen::Vector3d p = A + q.x() * (B - A) + q.y() * (C - A);
          const Eigen::Vector3d d = p - x;
          const double r2 = d.squaredNorm();
          // dA = |normal2| * sub_area_ratio * s ds dt (Duffy), and n dA = normal2 * ...
          const double g = d.dot(normal2) / (r2 * r2) * sub_area_ratio * s * gw[a] * gw[b];
          w(id[0]) += g * (1 - q.x() - q.y());
          w(id[1]) += g * q.x();
          w(id[2]) += g * q.y();
        }
    };
    for (int i = 0; i < m; ++i)
      for (int j = 0; i + j < m; ++j)
      {
        const double h = 1.0 / m;
        const Eigen::Vector2d q00(i * h, j * h), q10((i + 1) * h, j * h), q01(i * h, (j + 1) * h);
        integrate(q00, q10, q01);
        if (i + j + 1 < m)
          integrate(q10, Eigen::Vector2d((i + 1) * h, (j + 1) * h), q01);
      }
  }
  return w / w.sum();
}

TEST(MeanValueCoordinates3D, QuadratureReferenceIsConverged)
{
  // The reference must itself be trustworthy: two resolutions agree, and on the octahedron's
  // centre it gives the symmetric 1/6.
  const Cage cube = test::unit_cube();
  const Eigen::Vector3d x(0.3, 0.6, 0.45);
  const Eigen::VectorXd used = mvc_by_quadrature(cube, x, 2, 16);
  const Eigen::VectorXd finer = mvc_by_quadrature(cube, x, 3, 20);
  EXPECT_LE((used - finer).cwiseAbs().maxCoeff(), 1e-13);
  const Eigen::VectorXd oct = mvc_by_quadrature(test::octahedron(), Eigen::Vector3d::Zero(), 1, 12);
  for (Index i = 0; i < 6; ++i)
    EXPECT_NEAR(oct(i), 1.0 / 6, 1e-13);
}

TEST(MeanValueCoordinates3D, MatchesQuadratureOfTheDefiningIntegral)
{
  struct Case
  {
    Cage cage;
    std::vector<Eigen::Vector3d> points;
  };
  const std::vector<Case> cases = {
    { test::unit_cube(), { { 0.5, 0.5, 0.5 }, { 0.2, 0.7, 0.4 }, { 0.85, 0.15, 0.6 } } },
    { test::reversed(test::unit_cube()), { { 0.2, 0.7, 0.4 } } },
    { test::octahedron(), { { 0, 0, 0 }, { 0.1, -0.2, 0.3 }, { 0.4, 0.2, -0.1 } } },
    // In the base of the U, in an arm (sees the other arm's walls from behind), and in the
    // plane x = 1 of the notch's wall.
    { test::u_box(),
      { { 1.5, 0.5, 0.5 }, { 0.5, 1.6, 0.3 }, { 2.6, 1.2, 0.7 }, { 1.0, 0.5, 0.5 } } },
    { test::noisy_icosphere(2, 0.1, 20240601), { { 0, 0, 0 }, { 0.3, -0.2, 0.25 } } },
  };
  for (const Case& c : cases)
  {
    const MeanValueCoordinates mvc(c.cage);
    for (const Eigen::Vector3d& x : c.points)
    {
      const Eigen::VectorXd ref = mvc_by_quadrature(c.cage, x, 2, 16);
      const Eigen::VectorXd got = weights_at(mvc, x);
      EXPECT_LE((got - ref).cwiseAbs().maxCoeff(), 1e-10)
        << describe(x) << "\n got " << got.transpose() << "\n ref " << ref.transpose();
    }
  }
}

TEST(MeanValueCoordinates3D, MatchesQuadratureOutside)
{
  // Outside, the defining integral is still well defined (signed solid angles) and the
  // quadrature stays accurate to ~1e-15 (it reproduces x to that level). Core loses a few
  // digits there (faces seen nearly edge-on, see kOutside3DTol); this pins the accuracy.
  struct Case
  {
    Cage cage;
    std::vector<Eigen::Vector3d> points;
  };
  const std::vector<Case> cases = {
    { test::octahedron(), { { 1.2, 0.3, -0.4 }, { -2, -1.3, 1.7 } } },
    { test::u_box(), { { 1.5, 1.5, 0.5 }, { 4, -1, 2 } } },
    { test::noisy_icosphere(2, 0.1, 20240601),
      { { 0.40355518839036, -1.12855288913147, -1.97955263455910 }, { 2.2, 0, 0 } } },
  };
  for (const Case& c : cases)
  {
    const MeanValueCoordinates mvc(c.cage);
    for (const Eigen::Vector3d& x : c.points)
    {
      ASSERT_LT(std::abs(test::winding_number(c.cage, x.data())), 0.5) << "test bug";
      const Eigen::VectorXd ref = mvc_by_quadrature(c.cage, x, 2, 16);
      ASSERT_LE((c.cage.V.transpose() * ref - x).norm(), 1e-13) << "reference not converged";
      PointLocation where;
      const Eigen::VectorXd got = weights_at(mvc, x, &where);
      EXPECT_EQ(where, PointLocation::Outside) << describe(x);
      EXPECT_LE((got - ref).cwiseAbs().maxCoeff(), kOutside3DTol * ref.cwiseAbs().sum())
        << describe(x) << "\n got " << got.transpose() << "\n ref " << ref.transpose();
    }
  }
}

// --- The batch call's vector kernel (four points per vector, AVX2 or portable) -----------------

/// Points that exercise every path of the 3D kernel: inside and outside at any distance from the
/// cage (down to 0: edges seen at any angle up to pi), far away (tiny angles), every vertex,
/// edge midpoints and face points (boundary), points within half the boundary tolerance of a
/// face and just beyond it, points in a face's plane outside the face, and on the line of an
/// edge outside it (the special cases the kernel hands back to the per-point code).
/// @p kind gets 0 inside, 1 outside, 2 on or near the cage or in a special position.
Points kernel_points(const Cage& cage, std::uint64_t seed, std::vector<int>& kind)
{
  const double tol = MeanValueOptions{}.boundary_tolerance * cage.diameter();
  std::vector<Eigen::Vector3d> pts;
  const Points in = test::sample_inside(cage, 300, 0.0, seed);
  const Points out = test::sample_outside(cage, 150, 0.0, 3.0, seed + 1);
  const Points far = test::sample_outside(cage, 30, 0.5, 8.0, seed + 2);
  for (Index p = 0; p < in.rows(); ++p)
    pts.push_back(in.row(p).transpose()), kind.push_back(0);
  for (const Points* o : { &out, &far })
    for (Index p = 0; p < o->rows(); ++p)
      pts.push_back(o->row(p).transpose()), kind.push_back(1);
  const Eigen::MatrixXd& V = cage.V;
  for (Index i = 0; i < std::min<Index>(V.rows(), 60); ++i)
    pts.push_back(V.row(i).transpose()), kind.push_back(2);
  for (Index f = 0; f < std::min<Index>(cage.F.rows(), 40); ++f)
  {
    const Eigen::Vector3d a = V.row(cage.F(f, 0)), b = V.row(cage.F(f, 1)), c = V.row(cage.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    const Eigen::Vector3d centre = (a + b + c) / 3;
    for (const Eigen::Vector3d& x : { Eigen::Vector3d(0.5 * (a + b)), centre,
           Eigen::Vector3d(centre + 0.5 * tol * n), Eigen::Vector3d(centre - 4 * tol * n),
           Eigen::Vector3d(centre + 4 * tol * n), Eigen::Vector3d(a + 1.5 * (a - c)),
           Eigen::Vector3d(a - 0.5 * (b - a) - 0.5 * (c - a)), Eigen::Vector3d(a + 2.0 * (b - a)) })
      pts.push_back(x), kind.push_back(2);
  }
  // shuffled, so that every lane of a group of four sees every kind
  test::Rng rng(seed + 3);
  std::vector<std::size_t> order(pts.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  for (std::size_t i = order.size() - 1; i > 0; --i)
    std::swap(order[i], order[static_cast<std::size_t>(rng.next() % (i + 1))]);
  Points P(static_cast<Index>(pts.size()), 3);
  std::vector<int> shuffled(kind.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    P.row(static_cast<Index>(i)) = pts[order[i]].transpose();
    shuffled[i] = kind[order[i]];
  }
  kind = shuffled;
  return P;
}

/// The 3D cages of the catalogue and a rougher noisy icosphere (radii 1 +- 0.2 instead of 0.1).
std::vector<CatalogueCage> kernel_cages()
{
  std::vector<CatalogueCage> cages = test::cages_3d();
  cages.push_back({ "rough_icosphere320", test::noisy_icosphere(2, 0.2, 7) });
  return cages;
}

/// Smallest distance from @p x to the plane of a face of @p cage, relative to the cage's diameter.
double plane_distance(const Cage& cage, const Eigen::Vector3d& x)
{
  double best = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d a = cage.V.row(cage.F(f, 0)), b = cage.V.row(cage.F(f, 1)),
                          c = cage.V.row(cage.F(f, 2));
    best = std::min(best, std::abs((b - a).cross(c - a).normalized().dot(x - a)));
  }
  return best / cage.diameter();
}

// The batch call computes four points per vector; the per-point call is the scalar reference.
// Both run the same operations in the same order except asin (the kernel's polynomial, < 0.67
// ulp, against libm's, < 1 ulp) and, on the AVX2 path, fused multiply-adds (one rounding
// instead of two). A face's contribution is a ratio whose denominator det[u0, u1, u2] is
// proportional to x's distance to the face's plane, so a relative perturbation u of the inputs
// moves a weight by about u sum|w| diam / h, h the smallest distance from x to a face's plane.
// Allowed: 4e-15 sum|w| + 2e-16 (diam / h) sum|w| inside and near the cage (measured, points
// >= 1e-3 diam from the cage: portable <= 2.8e-16 on the catalogue's cages, 4.8e-15 in the rough
// icosphere; AVX2 <= 3.3e-16 on the convex cages, 6.9e-14 at a point inside the catalogue's
// noisy icosphere that is 2e-3 diam from the plane of a far face, 1.4e-13 in the rough one). Points the kernel hands to the per-point code (within the boundary tolerance) are
// bit-identical. Outside, faces seen nearly edge-on amplify rounding further (kOutside3DTol, why
// core itself is only accurate to ~1e-10 there): kOutside3DTol (measured: <= 6.6e-11).
TEST(MeanValueCoordinates3D, BatchKernelMatchesThePerPointCall)
{
  for (const CatalogueCage& cc : kernel_cages())
  {
    std::vector<int> kind;
    const Points P = kernel_points(cc.cage, 977, kind);
    const MeanValueCoordinates mvc(cc.cage);
    const Index n = mvc.num_controls();
    Eigen::MatrixXd ref(P.rows(), n);
    std::vector<PointLocation> ref_location(static_cast<std::size_t>(P.rows()));
    for (Index p = 0; p < P.rows(); ++p)
    {
      const Eigen::Vector3d x = P.row(p).transpose();
      Eigen::VectorXd w(n);
      ref_location[static_cast<std::size_t>(p)] = mvc.evaluate(x.data(), w.data());
      ref.row(p) = w.transpose();
    }
    for (const detail::SimdLevel level : { detail::SimdLevel::AVX2, detail::SimdLevel::Portable })
    {
      if (detail::set_simd_level(level) != level)
        continue; // no AVX2 on this CPU
      const MeanValueResult r = mvc.evaluate(P);
      detail::set_simd_level(detail::supported_simd_level());
      const char* name = level == detail::SimdLevel::AVX2 ? "AVX2" : "portable";
      EXPECT_EQ(r.location, ref_location) << cc.name << ", " << name;
      double worst[2] = { 0, 0 };
      for (Index p = 0; p < P.rows(); ++p)
      {
        if (!ref.row(p).allFinite())
        {
          EXPECT_FALSE(r.W.row(p).allFinite()) << cc.name << ", " << name << ", " << describe(P.row(p));
          continue;
        }
        const bool outside = kind[static_cast<std::size_t>(p)] == 1;
        const Eigen::Vector3d x = P.row(p).transpose();
        const double dist = test::boundary_distance(cc.cage, x.data()) / cc.cage.diameter();
        const double diff = (r.W.row(p) - ref.row(p)).cwiseAbs().maxCoeff() / ref.row(p).cwiseAbs().sum();
        if (dist >= 1e-3)
          worst[outside] = std::max(worst[outside], diff);
        const double tol = dist <= 0.5 * MeanValueOptions{}.boundary_tolerance ? 0.0
          : outside                                                          ? kOutside3DTol
                                                  : 4e-15 + 2e-16 / plane_distance(cc.cage, x);
        EXPECT_LE(diff, tol) << cc.name << ", " << name << ", " << describe(P.row(p)) << ", distance "
                             << dist << " diam";
      }
      RecordProperty(cc.name + "_" + name + "_inside_rel_diff", std::to_string(worst[0]));
      RecordProperty(cc.name + "_" + name + "_outside_rel_diff", std::to_string(worst[1]));
      std::printf("%s %s: max |w_batch - w_point| / sum|w| >= 1e-3 diam from the cage: inside %.2g, outside %.2g\n",
        cc.name.c_str(), name, worst[0], worst[1]);
    }
  }
}

// The two instruction sets run the same operations in the same order; they differ only where
// the AVX2 path fuses a * b + c (one rounding instead of two), so they agree to rounding:
// 1e-12 sum|w| (simd.h's contract), outside kOutside3DTol as above. Every lane is computed on
// its own, so the result is the same whichever points share a vector and whichever thread
// computes them: 1 and 2 threads agree bit for bit on both paths.
TEST(MeanValueCoordinates3D, BatchKernelPathsAgreeAndIgnoreThreads)
{
  if (detail::supported_simd_level() != detail::SimdLevel::AVX2)
    GTEST_SKIP() << "no AVX2 on this CPU: only the portable path runs";
  for (const CatalogueCage& cc : kernel_cages())
  {
    std::vector<int> kind;
    const Points P = kernel_points(cc.cage, 4242, kind);
    MeanValueOptions one, two;
    one.threads = 1;
    two.threads = 2;
    const MeanValueCoordinates mvc1(cc.cage, one), mvc2(cc.cage, two);
    MeanValueResult r[2][2]; // [level][threads - 1]
    for (const int level : { 0, 1 })
    {
      detail::set_simd_level(level ? detail::SimdLevel::AVX2 : detail::SimdLevel::Portable);
      r[level][0] = mvc1.evaluate(P);
      r[level][1] = mvc2.evaluate(P);
    }
    detail::set_simd_level(detail::supported_simd_level());
    for (const int level : { 0, 1 })
    {
      const MeanValueResult& a = r[level][0];
      const MeanValueResult& b = r[level][1];
      EXPECT_EQ(std::memcmp(a.W.data(), b.W.data(), sizeof(double) * static_cast<std::size_t>(a.W.size())), 0)
        << cc.name << ": 1 and 2 threads differ, " << (level ? "AVX2" : "portable");
      EXPECT_EQ(a.location, b.location) << cc.name;
    }
    EXPECT_EQ(r[0][0].location, r[1][0].location) << cc.name;
    for (Index p = 0; p < P.rows(); ++p)
    {
      const auto wa = r[0][0].W.row(p), wb = r[1][0].W.row(p);
      if (!wa.allFinite())
      {
        EXPECT_FALSE(wb.allFinite()) << cc.name << ", " << describe(P.row(p));
        continue;
      }
      const double tol = kind[static_cast<std::size_t>(p)] == 1 ? kOutside3DTol : 1e-12;
      EXPECT_LE((wa - wb).cwiseAbs().maxCoeff(), tol * wa.cwiseAbs().sum()) << cc.name << ", " << describe(P.row(p));
    }
  }
}

// Regression test: the first implementation treated x as lying on a face as soon as the face's
// half perimeter h on the unit sphere satisfied pi - h <= 1e-12, i.e. up to ~1e-6 of the face
// size away, whatever options.boundary_tolerance said (default 1e-10 diam).
TEST(MeanValueCoordinates3D, PointsJustInsideAFaceAreInside)
{
  const Cage cube = test::unit_cube();
  const MeanValueCoordinates mvc(cube); // tolerance 1e-10 * sqrt(3) ~ 1.7e-10
  for (const double z : { 1e-9, 1e-8, 1e-7 })
  {
    PointLocation where;
    const Eigen::VectorXd w = weights_at(mvc, Eigen::Vector3d(0.4, 0.3, z), &where);
    EXPECT_EQ(where, PointLocation::Inside) << "z = " << z;
    EXPECT_TRUE(w.allFinite());
  }
}

TEST(MeanValueCoordinates3D, OctahedronCentreAndAxis)
{
  // The regular octahedron's faces are permuted transitively by its symmetries, so the weights
  // at the centre are all 1/6. On the z axis the rotation by 90 degrees about z maps the cage
  // onto itself (+x -> +y -> -x -> -y), so the four equatorial weights agree, and linear
  // reproduction then fixes the poles: w(+z) - w(-z) = z, w(+z) + w(-z) = 1 - 4 w_eq.
  const MeanValueCoordinates mvc(test::octahedron());
  const Eigen::VectorXd c = weights_at(mvc, Eigen::Vector3d::Zero());
  for (Index i = 0; i < 6; ++i)
    EXPECT_NEAR(c(i), 1.0 / 6, 1e-15);
  for (const double z : { -0.7, 0.25, 0.5 })
  {
    const Eigen::VectorXd w = weights_at(mvc, Eigen::Vector3d(0, 0, z));
    for (Index i = 1; i < 4; ++i)
      EXPECT_NEAR(w(i), w(0), 1e-15) << "z = " << z;
    EXPECT_NEAR(w(4) - w(5), z, 1e-15) << "z = " << z;
  }
}

TEST(MeanValueCoordinates3D, CubeCentreAndDiagonal)
{
  // unit_cube()'s triangulation uses the diagonals 0-3, 4-7, 0-5, 2-7, 0-6, 1-7: it is mapped
  // onto itself by the inversion v -> 7 - v and by the rotation (x, y, z) -> (y, z, x) about
  // the main diagonal 0-7 (1 -> 4 -> 2 -> 1, 3 -> 5 -> 6 -> 3). No triangulation of a cube is
  // symmetric under a group transitive on its 8 vertices (6 diagonals give 12 ends, not a
  // multiple of 8), so the centre weights need not all be 1/8; what symmetry forces is
  //   w0 = w7 and w1 = w2 = w3 = w4 = w5 = w6 at the centre,
  //   w1 = w2 = w4 and w3 = w5 = w6 at any point (t, t, t) of the diagonal.
  // The values themselves come from the quadrature reference.
  const Cage cube = test::unit_cube();
  const MeanValueCoordinates mvc(cube);
  const Eigen::VectorXd c = weights_at(mvc, Eigen::Vector3d(0.5, 0.5, 0.5));
  EXPECT_NEAR(c(0), c(7), 1e-15);
  for (Index i = 2; i <= 6; ++i)
    EXPECT_NEAR(c(i), c(1), 1e-15);
  const Eigen::VectorXd ref = mvc_by_quadrature(cube, Eigen::Vector3d(0.5, 0.5, 0.5), 2, 16);
  EXPECT_LE((c - ref).cwiseAbs().maxCoeff(), 1e-12);
  for (const double t : { 0.2, 0.5, 0.8 })
  {
    const Eigen::VectorXd w = weights_at(mvc, Eigen::Vector3d(t, t, t));
    EXPECT_NEAR(w(1), w(2), 1e-15) << t;
    EXPECT_NEAR(w(1), w(4), 1e-15) << t;
    EXPECT_NEAR(w(3), w(5), 1e-15) << t;
    EXPECT_NEAR(w(3), w(6), 1e-15) << t;
  }
}

// --- Options and error paths ------------------------------------------------------------------

TEST(MeanValueCoordinates, ReusingEvaluateRejectsBadPointsAndKeepsTheResult)
{
  // the overload that fills a caller's result checks the points as the other does, before it
  // touches the result
  const MeanValueCoordinates mvc(test::unit_cube());
  Points P(3, 3);
  P << 0.5, 0.5, 0.5, 0.25, 0.5, 0.75, 0.1, 0.2, 0.3;
  MeanValueResult r;
  mvc.evaluate(P, r);
  const DenseWeights before = r.W;
  Points nan = P;
  nan(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { mvc.evaluate(nan, r); }, ErrorCode::NonFinite, { "point 1" }));
  const Points flat = P.leftCols(2);
  EXPECT_TRUE(throws_error([&] { mvc.evaluate(flat, r); }, ErrorCode::SizeMismatch, { "2 coordinates" }));
  ASSERT_EQ(r.W.rows(), before.rows());
  ASSERT_EQ(r.W.cols(), before.cols());
  EXPECT_TRUE((r.W.array() == before.array()).all());
  EXPECT_EQ(r.inside, 3);
  // no points: an empty result
  mvc.evaluate(Points(0, 3), r);
  EXPECT_EQ(r.W.rows(), 0);
  EXPECT_TRUE(r.location.empty());
  EXPECT_EQ(r.inside, 0);
}

TEST(MeanValueCoordinates, RejectsBadOptionsAndCages)
{
  MeanValueOptions bad_tol;
  bad_tol.boundary_tolerance = 1e-2;
  EXPECT_TRUE(throws_error([&] { MeanValueCoordinates(test::unit_square(), bad_tol); },
    ErrorCode::InvalidArgument, { "boundary_tolerance" }));
  bad_tol.boundary_tolerance = -1.0;
  EXPECT_TRUE(throws_error([&] { MeanValueCoordinates(test::unit_square(), bad_tol); },
    ErrorCode::InvalidArgument, { "boundary_tolerance" }));
  MeanValueOptions bad_threads;
  bad_threads.threads = -1;
  EXPECT_TRUE(throws_error([&] { MeanValueCoordinates(test::unit_square(), bad_threads); },
    ErrorCode::InvalidArgument, { "threads" }));
  // The constructor validates the cage ...
  Cage open = test::unit_cube();
  open.F.conservativeResize(11, 3);
  EXPECT_TRUE(
    throws_error([&] { MeanValueCoordinates{ open }; }, ErrorCode::InvalidCage, { "not closed" }));
  // ... unless told not to, but an empty cage is always rejected.
  MeanValueOptions no_validation;
  no_validation.validate = false;
  EXPECT_NO_THROW(MeanValueCoordinates(open, no_validation));
  EXPECT_TRUE(
    throws_error([&] { MeanValueCoordinates(Cage{}, no_validation); }, ErrorCode::EmptyInput));
}

TEST(MeanValueCoordinates, WrongPointDimension)
{
  const MeanValueCoordinates mvc2(test::unit_square());
  EXPECT_TRUE(throws_error([&] { mvc2.evaluate(Points::Zero(4, 3)); }, ErrorCode::SizeMismatch,
    { "3 coordinates", "2D" }));
  const MeanValueCoordinates mvc3(test::unit_cube());
  EXPECT_TRUE(throws_error([&] { mvc3.evaluate(Points::Zero(4, 2)); }, ErrorCode::SizeMismatch,
    { "2 coordinates", "3D" }));
}

TEST(MeanValueCoordinates, NonFinitePointIsNamed)
{
  const MeanValueCoordinates mvc(test::unit_cube());
  Points P = Points::Constant(10, 3, 0.5);
  P(7, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { mvc.evaluate(P); }, ErrorCode::NonFinite, { "point 7" }));
  P(7, 2) = 0.5;
  P(3, 0) = -std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error([&] { mvc.evaluate(P); }, ErrorCode::NonFinite, { "point 3" }));
}

TEST(MeanValueCoordinates, EmptyPointSet)
{
  const MeanValueResult r = MeanValueCoordinates(test::unit_square()).evaluate(Points(0, 2));
  EXPECT_EQ(r.W.rows(), 0);
  EXPECT_EQ(r.W.cols(), 4);
  EXPECT_EQ(r.inside + r.outside + r.boundary, 0);
}

TEST(MeanValueCoordinates, ProgressIsMonotoneAndEndsAtOne)
{
  const Cage cage = test::regular_polygon(64);
  const Points P = test::sample_inside(cage, 5000, 0.0, 5);
  std::vector<double> seen;
  const MeanValueResult r = MeanValueCoordinates(cage).evaluate(P, [&](double f) {
    seen.push_back(f);
    return true;
  });
  ASSERT_GE(seen.size(), 2u) << "5000 points should report more than once";
  for (std::size_t k = 0; k < seen.size(); ++k)
  {
    EXPECT_GE(seen[k], 0.0);
    EXPECT_LE(seen[k], 1.0);
    if (k > 0)
    {
      EXPECT_LE(seen[k - 1], seen[k]) << "call " << k;
    }
  }
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_EQ(r.inside, 5000);
}

TEST(MeanValueCoordinates, CancelledByTheProgressCallback)
{
  // One thread: the calling thread does all the work and reports every 1%, so the third call
  // is certain to come; the callback must not be called again after it returned false.
  const Cage cage = test::unit_cube();
  const Points P = test::sample_inside(cage, 5000, 0.0, 6);
  MeanValueOptions one;
  one.threads = 1;
  int calls = 0;
  EXPECT_TRUE(throws_error(
    [&] { MeanValueCoordinates(cage, one).evaluate(P, [&](double) { return ++calls < 3; }); },
    ErrorCode::Cancelled, { "mean value coordinates", "cancelled" }));
  EXPECT_EQ(calls, 3) << "the callback must not be called again after it returned false";

  // Two threads: how often the calling thread reports depends on how much work it gets, but a
  // refusal at the first call always cancels.
  MeanValueOptions two;
  two.threads = 2;
  calls = 0;
  EXPECT_TRUE(throws_error(
    [&] { MeanValueCoordinates(cage, two).evaluate(P, [&](double) { return ++calls < 1; }); },
    ErrorCode::Cancelled, { "mean value coordinates", "cancelled" }));
  EXPECT_EQ(calls, 1);
}
} // namespace
