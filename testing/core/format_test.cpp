// Tests for core/detail/format.h: numbers, points and index rows as messages write them.
#include "core/detail/format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace
{
using namespace bary;

TEST(Format, NumbersWithTheStreamsSignificantDigits)
{
  EXPECT_EQ(detail::format_number(1.0 / 3.0), "0.333333");
  EXPECT_EQ(detail::format_number(1.0 / 3.0, 3), "0.333");
  EXPECT_EQ(detail::format_number(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(detail::format_number(1e-12), "1e-12");
  EXPECT_EQ(detail::format_number(2.0), "2");
  EXPECT_EQ(detail::format_number(-3.5), "-3.5");
  EXPECT_EQ(detail::format_number(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(detail::format_number(std::nan("")), "nan");
  // the same text as printf's %.17g, which domain_mesh wrote with before
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", 1.0 / 7.0);
  EXPECT_EQ(detail::format_number(1.0 / 7.0, 17), buffer);
}

TEST(Format, PointsAndRows)
{
  const double x[3] = { 0.5, -1.0, 1.0 / 3.0 };
  EXPECT_EQ(detail::format_point(x, 2), "(0.5, -1)");
  EXPECT_EQ(detail::format_point(x, 3, 3), "(0.5, -1, 0.333)");
  EXPECT_EQ(detail::format_point(x, 0), "()");
  Eigen::MatrixXd V(2, 2);
  V << 0, 1, 0.5, 1.5;
  EXPECT_EQ(detail::format_row(V, 1), "(0.5, 1.5)");
  EXPECT_EQ(detail::format_row(V, 0, 17), "(0, 1)");
  Eigen::MatrixXi T(2, 3);
  T << 0, 1, 2, 7, 8, 9;
  EXPECT_EQ(detail::format_index_row(T, 1), "7, 8, 9");
}
} // namespace
