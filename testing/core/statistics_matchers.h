#pragma once
/// @file statistics_matchers.h
/// Asserting on WeightsResult::statistics: exactly these names, in this order, finite values.

#include "core/common/weights_result.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace bary::test
{

/// Success iff @p statistics holds exactly @p names, in that order, each with a finite value.
inline ::testing::AssertionResult has_statistics(
  const Statistics& statistics, const std::vector<std::string>& names)
{
  std::string got;
  for (const auto& entry : statistics)
    got += (got.empty() ? "" : ", ") + entry.first;
  std::string want;
  for (const std::string& name : names)
    want += (want.empty() ? "" : ", ") + name;
  if (got != want)
    return ::testing::AssertionFailure() << "statistics [" << got << "], expected [" << want << "]";
  for (const auto& entry : statistics)
    if (!std::isfinite(entry.second))
      return ::testing::AssertionFailure() << "statistic " << entry.first << " = " << entry.second;
  return ::testing::AssertionSuccess();
}

} // namespace bary::test
