// Tests for core/error.h: codes, names and the message an Error carries.
#include "core/error.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace
{
using bary::Error;
using bary::ErrorCode;

const ErrorCode kAllCodes[] = { ErrorCode::InvalidArgument, ErrorCode::EmptyInput,
  ErrorCode::SizeMismatch, ErrorCode::NonFinite, ErrorCode::InvalidCage, ErrorCode::Io,
  ErrorCode::Cancelled, ErrorCode::NotConverged, ErrorCode::Internal };

TEST(Error, EveryCodeHasADistinctName)
{
  std::set<std::string> names;
  for (const ErrorCode code : kAllCodes)
  {
    const std::string name = bary::to_string(code);
    EXPECT_FALSE(name.empty());
    EXPECT_NE(name, "unknown error") << "code " << static_cast<int>(code) << " has no name";
    names.insert(name);
  }
  EXPECT_EQ(names.size(), std::size(kAllCodes));
  EXPECT_STREQ(bary::to_string(ErrorCode::InvalidCage), "invalid cage");
  EXPECT_STREQ(bary::to_string(ErrorCode::Cancelled), "cancelled");
}

TEST(Error, CarriesCodeAndMessage)
{
  try
  {
    throw Error(ErrorCode::NonFinite, "point 3 has a non-finite coordinate");
  }
  catch (const std::runtime_error& e) // catchable as a standard exception
  {
    EXPECT_STREQ(e.what(), "point 3 has a non-finite coordinate");
    const auto* bary_error = dynamic_cast<const Error*>(&e);
    ASSERT_NE(bary_error, nullptr);
    EXPECT_EQ(bary_error->code(), ErrorCode::NonFinite);
  }
}
} // namespace
