// Tests for core/common/weights_result.h: the shape every weights computation returns.
#include "core/coordinates/bbw.h"
#include "core/coordinates/celestial_coordinates.h"
#include "core/coordinates/local_barycentric_coordinates.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/common/weights_result.h"

#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>

namespace
{
using namespace bary;

TEST(WeightsResult, LocationValuesAreThoseOfTheCageLocationArray)
{
  // The filters write these values as the "CageLocation" array: 0 inside, 1 outside, 2 on it.
  EXPECT_EQ(static_cast<int>(PointLocation::Inside), 0);
  EXPECT_EQ(static_cast<int>(PointLocation::Outside), 1);
  EXPECT_EQ(static_cast<int>(PointLocation::Boundary), 2);
  EXPECT_EQ(sizeof(PointLocation), 1u);
}

TEST(WeightsResult, DefaultsToAnEmptyConvergedResult)
{
  const WeightsResult r;
  EXPECT_EQ(r.W.size(), 0);
  EXPECT_TRUE(r.location.empty());
  EXPECT_TRUE(r.undefined.empty());
  EXPECT_TRUE(r.statistics.empty());
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.count(PointLocation::Inside), 0);
  EXPECT_TRUE(std::isnan(r.statistic("iterations")));
}

TEST(WeightsResult, StatisticLooksUpTheFirstEntryOfThatName)
{
  WeightsResult r;
  r.statistics = { { "iterations", 12.0 }, { "residual", 1e-9 }, { "iterations", 99.0 } };
  EXPECT_EQ(r.statistic("iterations"), 12.0);
  EXPECT_EQ(r.statistic("residual"), 1e-9);
  EXPECT_TRUE(std::isnan(r.statistic("seconds")));
  EXPECT_EQ(r.statistic("seconds", -1.0), -1.0);
  EXPECT_EQ(r.statistic("Iterations", 7.0), 7.0); // names are case-sensitive
}

TEST(WeightsResult, CountCountsEachLocation)
{
  WeightsResult r;
  r.location = { PointLocation::Inside, PointLocation::Boundary, PointLocation::Inside,
    PointLocation::Outside, PointLocation::Inside };
  EXPECT_EQ(r.count(PointLocation::Inside), 3);
  EXPECT_EQ(r.count(PointLocation::Outside), 1);
  EXPECT_EQ(r.count(PointLocation::Boundary), 1);
}

TEST(WeightsResult, EveryMethodsResultIsAWeightsResult)
{
  EXPECT_TRUE((std::is_base_of_v<WeightsResult, MeanValueResult>));
  EXPECT_TRUE((std::is_base_of_v<WeightsResult, CelestialResult>));
  EXPECT_TRUE((std::is_base_of_v<WeightsResult, LBCResult>));
  EXPECT_TRUE((std::is_base_of_v<WeightsResult, BBWResult>));
}
} // namespace
