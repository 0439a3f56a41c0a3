// Independent reference for 2D mean value coordinates: CGAL's
// CGAL::Barycentric_coordinates::mean_value_coordinates_2 (CGAL 5.x), with its default policy
// PRECISE_WITH_EDGE_CASES. That policy uses Floater's product formula (the CGAL 5.5 header cites
// "Wachspress and mean value coordinates", Sect. 4.2, formula 16), not core's half-angle
// tangents, and handles points on the boundary with its own exact location predicates, so
// agreement is evidence that both are right.
//
// Tolerance: both sides are accurate to about 1e-14 * sum|w| for points at least 1e-3 diam from
// the cage (core: see mean_value_coordinates_test.cpp; CGAL's product of n - 2 factors each
// with relative error ~u adds ~n u); 1e-10 * sum|w| leaves room for CGAL's square roots of
// long products on the 64-gon.
#include "cage_catalogue.h"
#include "core/coordinates/mean_value_coordinates.h"

#include <CGAL/Barycentric_coordinates_2/Mean_value_coordinates_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <iterator>
#include <sstream>
#include <vector>

namespace
{
using namespace bary;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;

constexpr double kAgreement = 1e-10;

std::vector<Point2> to_cgal(const Cage& cage)
{
  std::vector<Point2> polygon;
  for (Index i = 0; i < cage.num_controls(); ++i)
    polygon.emplace_back(cage.V(i, 0), cage.V(i, 1));
  return polygon;
}

Eigen::VectorXd cgal_mvc(const std::vector<Point2>& polygon, double x, double y)
{
  std::vector<double> w;
  w.reserve(polygon.size());
  CGAL::Barycentric_coordinates::mean_value_coordinates_2(
    polygon, Point2(x, y), std::back_inserter(w), Kernel());
  return Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Index>(w.size()));
}

class MeanValueVersusCgal : public ::testing::TestWithParam<test::CatalogueCage>
{
};

TEST_P(MeanValueVersusCgal, InteriorAndExteriorPoints)
{
  const Cage& cage = GetParam().cage;
  const std::vector<Point2> polygon = to_cgal(cage);
  const MeanValueCoordinates mvc(cage);
  Points P(300, 2);
  P << test::sample_inside(cage, 200, 1e-3, 41), test::sample_outside(cage, 100, 1e-3, 2.0, 42);
  const MeanValueResult r = mvc.evaluate(P);
  double worst = 0.0;
  for (Index p = 0; p < P.rows(); ++p)
  {
    const Eigen::VectorXd ref = cgal_mvc(polygon, P(p, 0), P(p, 1));
    ASSERT_EQ(ref.size(), cage.num_controls());
    ASSERT_TRUE(ref.allFinite()) << "CGAL gave non-finite weights at " << P.row(p);
    ASSERT_TRUE(r.W.row(p).allFinite()) << "non-finite weights at " << P.row(p);
    const double diff = (r.W.row(p).transpose() - ref).cwiseAbs().maxCoeff();
    const double scale = ref.cwiseAbs().sum();
    worst = std::max(worst, diff / scale);
    EXPECT_LE(diff, kAgreement * scale)
      << "x = " << P.row(p) << (p < 200 ? " (inside)" : " (outside)");
  }
  std::ostringstream worst_text;
  worst_text << std::scientific << worst;
  RecordProperty("worst_relative_difference", worst_text.str());
}

TEST_P(MeanValueVersusCgal, BoundaryPoints)
{
  // CGAL decides "on the boundary" with exact predicates; core with a tolerance. On the
  // vertices and at the midpoints of the edges both must give the linear interpolant. A
  // computed midpoint is often off the edge by a rounding; CGAL then treats it as interior and
  // its product formula loses accuracy that close to an edge (~1e-10), so only midpoints that
  // are exactly on their edge (CGAL::collinear, an exact predicate) are compared.
  const Cage& cage = GetParam().cage;
  const std::vector<Point2> polygon = to_cgal(cage);
  const MeanValueCoordinates mvc(cage);
  const Index n = cage.num_controls();
  Index compared = 0;
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1) % n;
    for (const double t : { 0.0, 0.5 })
    {
      const Eigen::Vector2d x = ((1 - t) * cage.V.row(i) + t * cage.V.row(j)).transpose();
      if (t > 0.0 &&
        !CGAL::collinear(polygon[static_cast<std::size_t>(i)], polygon[static_cast<std::size_t>(j)],
          Point2(x(0), x(1))))
        continue;
      ++compared;
      Eigen::VectorXd w(n);
      mvc.evaluate(x.data(), w.data());
      const Eigen::VectorXd ref = cgal_mvc(polygon, x(0), x(1));
      EXPECT_LE((w - ref).cwiseAbs().maxCoeff(), 1e-12) << "edge " << i << ", t = " << t;
    }
  }
  EXPECT_GE(compared, n) << "at least the vertices";
}

std::string cage_name(const ::testing::TestParamInfo<test::CatalogueCage>& info)
{
  return info.param.name;
}

INSTANTIATE_TEST_SUITE_P(
  Catalogue2D, MeanValueVersusCgal, ::testing::ValuesIn(test::cages_2d()), cage_name);
} // namespace
