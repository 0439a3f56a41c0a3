#pragma once
/// \file constants.h
/// Numerical constants shared by core files (one definition each).

#include <limits>

namespace bary
{
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
} // namespace bary
