#pragma once
/// \file timing.h
/// Wall-clock seconds for the solvers' reported timings (one definition for every core file).

#include <chrono>

namespace bary
{
/// Seconds elapsed since @p start on the steady clock.
inline double seconds_since(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
} // namespace bary
