// Tests for core/common/error.h: codes, names and the message an Error carries.
#include "core/common/error.h"

#include "cage_catalogue.h"
#include "core/meshing/domain_mesh.h"
#include "core/coordinates/local_barycentric_coordinates.h"

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
    EXPECT_EQ(bary_error->message(), "point 3 has a non-finite coordinate");
    EXPECT_EQ(bary_error->advice(), "");
  }
}

TEST(Error, AdviceFollowsTheMessageInWhat)
{
  const Error e(ErrorCode::InvalidCage, "vertex 2 repeats vertex 1", "remove the duplicate vertex");
  EXPECT_EQ(e.code(), ErrorCode::InvalidCage);
  EXPECT_EQ(e.message(), "vertex 2 repeats vertex 1");
  EXPECT_EQ(e.advice(), "remove the duplicate vertex");
  EXPECT_STREQ(e.what(), "vertex 2 repeats vertex 1; remove the duplicate vertex");
  const Error copy = e; // copies keep both parts
  EXPECT_EQ(copy.message(), e.message());
  EXPECT_EQ(copy.advice(), e.advice());
  EXPECT_STREQ(copy.what(), e.what());
}

/// A caller replaces core's advice with its own: the message, without the advice.
TEST(Error, LBCNotConvergedSplitsItsAdvice)
{
  bary::PolygonMeshOptions mesh_options;
  mesh_options.target_cells = 300;
  const bary::DomainMesh mesh =
    bary::mesh_polygon(bary::test::star_polygon(5, 1.0, 0.5), mesh_options);
  bary::LBCOptions options;
  options.threads = 1;
  options.max_iterations = 5;
  try
  {
    bary::local_barycentric_coordinates(mesh, options);
    FAIL() << "did not throw";
  }
  catch (const Error& e)
  {
    EXPECT_EQ(e.code(), ErrorCode::NotConverged);
    const std::string what = e.what();
    EXPECT_EQ(e.message().rfind("local barycentric coordinates did not converge in 5 iterations (", 0), 0u)
      << e.message();
    EXPECT_EQ(e.message().back(), ')');
    // the default stopping rule is the converged one: the advice offers the paper's
    EXPECT_EQ(e.advice(), "raise max_iterations, loosen the tolerances, set stopping = Paper or set "
                          "require_convergence = false");
    EXPECT_EQ(what, e.message() + "; " + e.advice());
    // what the filter used to cut by hand
    EXPECT_EQ(what.substr(0, what.find("; raise")), e.message());
  }
}
} // namespace
