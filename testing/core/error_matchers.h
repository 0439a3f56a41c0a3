#pragma once
/// @file error_matchers.h
/// Asserting on bary::Error: the code and the fragments the message must contain.

#include "core/common/error.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace bary::test
{

/// Success iff @p f throws bary::Error with @p code and a message containing every fragment.
/// Use as EXPECT_TRUE(throws_error([&] { ... }, ErrorCode::X, { "edge (0, 1)" })).
template<class Function>
::testing::AssertionResult throws_error(
  Function&& f, ErrorCode code, std::initializer_list<std::string> fragments = {})
{
  try
  {
    f();
  }
  catch (const Error& e)
  {
    const std::string message = e.what();
    if (e.code() != code)
      return ::testing::AssertionFailure()
        << "threw code '" << to_string(e.code()) << "' instead of '" << to_string(code)
        << "'; message: " << message;
    for (const std::string& fragment : fragments)
      if (message.find(fragment) == std::string::npos)
        return ::testing::AssertionFailure()
          << "message \"" << message << "\" does not contain \"" << fragment << "\"";
    return ::testing::AssertionSuccess() << "threw: " << message;
  }
  catch (const std::exception& e)
  {
    return ::testing::AssertionFailure() << "threw a non-bary exception: " << e.what();
  }
  return ::testing::AssertionFailure() << "did not throw (expected '" << to_string(code) << "')";
}

} // namespace bary::test
