#include "core/common/weights_result.h"

#include <algorithm>

namespace bary
{

double WeightsResult::statistic(const std::string& name, double fallback) const
{
  const auto at = std::find_if(statistics.begin(), statistics.end(),
    [&name](const std::pair<std::string, double>& entry) { return entry.first == name; });
  return at == statistics.end() ? fallback : at->second;
}

Index WeightsResult::count(PointLocation where) const
{
  return static_cast<Index>(std::count(location.begin(), location.end(), where));
}

} // namespace bary
