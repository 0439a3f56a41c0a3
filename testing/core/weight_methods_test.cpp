// The one table of weight methods and settings (core/coordinates/weight_methods.h) and the method
// dispatch (core/coordinates/weight_method.h): names and flags unique, defaults equal to the algorithms'
// option defaults and inside their own ranges, every range enforced (non-finite values too),
// the content hash sensitive to every setting that changes weights and to no other, and
// compute_weights equal to calling the algorithm directly.

#include "core/coordinates/weight_method.h"
#include "core/coordinates/weight_methods.h"
#include "core/deformation/cage_deformation.h"

#include "core/coordinates/celestial_coordinates.h"
#include "core/common/error.h"
#include "core/coordinates/local_barycentric_coordinates.h"
#include "core/coordinates/mean_value_coordinates.h"

#include "cage_catalogue.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

namespace
{
using bary::MethodId;
using bary::SettingField;
using bary::WeightsSettings;
using Kind = SettingField::Kind;

/// Another allowed value of @p field than its current one in @p s.
double other_value(const SettingField& field, const WeightsSettings& s)
{
  const double now = field.get(s);
  switch (field.kind)
  {
    case Kind::Bool:
      return now != 0.0 ? 0.0 : 1.0;
    case Kind::Choice:
      return now == 0.0 ? 1.0 : 0.0;
    default:
      break;
  }
  if (!field.values.empty())
    return field.values.front() == now ? field.values.back() : field.values.front();
  const double candidate = field.kind == Kind::Int ? now + 1 : (now == 0.0 ? field.maximum / 2 : now * 1.5);
  return field.accepts(candidate) ? candidate : field.minimum;
}
} // namespace

TEST(MethodTable, IdsNamesAndLookups)
{
  const auto& table = bary::method_table();
  ASSERT_EQ(table.size(), 7u);
  std::set<std::string> names;
  for (std::size_t i = 0; i < table.size(); ++i)
  {
    EXPECT_EQ(static_cast<std::size_t>(table[i].id), i) << "rows in MethodId order";
    EXPECT_TRUE(names.insert(table[i].name).second) << table[i].name;
    EXPECT_EQ(bary::method_from_name(table[i].name), table[i].id);
    EXPECT_EQ(&bary::method_info(table[i].id), &table[i]);
    EXPECT_NE(table[i].instance, nullptr);
  }
  EXPECT_EQ(bary::method_names(), "mvc|harmonic|bbw|tcc|scc|lbc|green");
  EXPECT_EQ(bary::find_method("nope"), nullptr);
  try
  {
    bary::method_from_name("nope");
    FAIL() << "no error";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::InvalidArgument);
    EXPECT_STREQ(e.what(), "unknown method 'nope' (available: mvc, harmonic, bbw, tcc, scc, lbc, green)");
  }
  // what the table says about the methods
  EXPECT_EQ(bary::method_info(MethodId::TCelestial).controls, bary::ControlKind::FreePoints);
  EXPECT_EQ(bary::method_info(MethodId::BBW).controls, bary::ControlKind::CageOrSkeleton);
  EXPECT_FALSE(bary::method_info(MethodId::BBW).linear_precision);
  EXPECT_FALSE(bary::method_info(MethodId::MeanValue).non_negative);
  EXPECT_TRUE(bary::method_info(MethodId::LBC).domain_mesh);
  // Green coordinates: only the method with face terms (x = W C + face_weights N)
  for (const bary::MethodInfo& m : table)
    EXPECT_EQ(m.face_terms, m.id == MethodId::Green) << m.name;
  EXPECT_FALSE(bary::method_info(MethodId::Green).non_negative);
  EXPECT_EQ(bary::method_info(MethodId::Green).controls, bary::ControlKind::Cage);
}

TEST(SettingsTable, NamesFlagsAndPropertiesAreUnique)
{
  std::set<std::string> keys, flags, properties;
  for (const SettingField& f : bary::weights_setting_fields())
  {
    EXPECT_TRUE(keys.insert(f.key).second) << f.key;
    EXPECT_TRUE(properties.insert(f.property).second) << f.property;
    EXPECT_FALSE(f.label.empty()) << f.key;
    EXPECT_FALSE(f.help.empty()) << f.key;
    std::string rest = f.flag;
    while (!rest.empty())
    {
      const std::string flag = rest.substr(0, rest.find(','));
      rest = rest.find(',') == std::string::npos ? "" : rest.substr(rest.find(',') + 1);
      EXPECT_EQ(flag.rfind("--", 0), 0u) << f.key << ": " << flag;
      EXPECT_TRUE(flags.insert(flag).second) << flag;
    }
    EXPECT_EQ(&bary::setting_field(f.key), &f);
    EXPECT_EQ(bary::setting_field_of_property(f.property), &f);
  }
  EXPECT_THROW(bary::setting_field("nope"), bary::Error);
  EXPECT_EQ(bary::setting_field_of_property("Nope"), nullptr);
}

TEST(SettingsTable, DefaultsAreTheAlgorithmsAndInRange)
{
  const WeightsSettings s;
  EXPECT_NO_THROW(bary::validate_settings(s));
  for (const SettingField& f : bary::weights_setting_fields())
  {
    if (f.kind != Kind::Numbers)
    {
      EXPECT_TRUE(f.accepts(f.default_value())) << f.key << " = " << f.default_value();
    }
  }
  const bary::LBCOptions lbc;
  EXPECT_EQ(s.lbc_primal_tolerance, lbc.primal_tolerance);
  EXPECT_EQ(s.lbc_dual_tolerance, lbc.dual_tolerance);
  EXPECT_EQ(s.lbc_max_iterations, lbc.max_iterations);
  EXPECT_EQ(s.lbc_relaxed_epsilon, lbc.relaxed_tv_epsilon);
  EXPECT_EQ(s.lbc_locality, lbc.locality);
  EXPECT_EQ(s.lbc_distance_normalization, lbc.distance_normalization);
  EXPECT_EQ(!s.lbc_unconstrained, lbc.barycentric_constraints);
  EXPECT_EQ(s.boundary_tolerance, bary::MeanValueOptions{}.boundary_tolerance);
  EXPECT_EQ(s.lambda, bary::CelestialOptions{}.lambda);
  EXPECT_FALSE(s.bbw_fast) << "the front ends' BBW default is the coupled problem";
  EXPECT_EQ(s.celestial_hull_points, bary::CelestialHullPoints::Auto)
    << "the front ends add celestial hull points when needed";
  EXPECT_EQ(s.celestial_hull_margin, bary::CelestialOptions{}.hull_margin);
  EXPECT_FALSE(bary::setting_field("celestial_hull_margin").accepts(0.0)) << "a margin must be > 0";
  EXPECT_EQ(s.method, MethodId::MeanValue);
}

TEST(SettingsTable, RangesAreEnforcedWithTheirNames)
{
  WeightsSettings s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const SettingField& f : bary::weights_setting_fields())
  {
    if (f.kind == Kind::Numbers)
      continue;
    SCOPED_TRACE(f.key);
    const double before = f.get(s);
    for (double bad : { nan, inf, -inf, f.minimum - 1.0, f.maximum * 2 + 1.0 })
    {
      try
      {
        bary::set_setting(s, f.key, bad);
        ADD_FAILURE() << bad << " accepted";
      }
      catch (const bary::Error& e)
      {
        EXPECT_EQ(e.code(), bary::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("setting '" + f.key + "'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(f.range_text()), std::string::npos) << e.what();
      }
      EXPECT_EQ(f.get(s), before) << "unchanged after a refused value";
    }
    const double v = other_value(f, s);
    bary::set_setting(s, f.key, v);
    EXPECT_EQ(f.get(s), v);
  }
  EXPECT_THROW(bary::set_setting(s, "target_cells", 10.5), bary::Error) << "integers only";
  EXPECT_THROW(bary::set_setting(s, "cage_dimension", 1.0), bary::Error) << "0, 2 or 3";
  bary::set_setting(s, "outside", std::string("nan"));
  EXPECT_EQ(s.outside, bary::OutsidePolicy::NaN);
  EXPECT_EQ(bary::choice_name(s, "outside"), "nan");
  try
  {
    bary::set_setting(s, "lbc_locality", std::string("cubic"));
    FAIL();
  }
  catch (const bary::Error& e)
  {
    EXPECT_STREQ(e.what(),
      "setting 'lbc_locality': unknown value 'cubic' (available: squared | constant | linear)");
  }
  s.user_weights = { 1.0, -0.5 };
  EXPECT_THROW(bary::validate_settings(s), bary::Error) << "s_i >= 0";
  EXPECT_EQ(bary::setting_field("max_cell_size").range_text(), ">= 0");
  EXPECT_EQ(bary::setting_field("lambda").range_text(), "[1.000001, 1000000]");
  EXPECT_EQ(bary::setting_field("cage_dimension").range_text(), "one of 0, 2, 3");
}

TEST(SettingsTable, HashSeesEverySettingThatChangesWeights)
{
  const WeightsSettings base;
  const std::uint64_t h0 = bary::settings_hash(base);
  EXPECT_EQ(bary::settings_hash(WeightsSettings{}), h0);
  for (const SettingField& f : bary::weights_setting_fields())
  {
    SCOPED_TRACE(f.key);
    WeightsSettings s = base;
    if (f.kind == Kind::Numbers)
      f.set_numbers(s, { 1.0, 2.0 });
    else
      f.set(s, other_value(f, s));
    EXPECT_FALSE(s == base);
    if (f.affects_weights)
    {
      EXPECT_NE(bary::settings_hash(s), h0);
    }
    else
    {
      EXPECT_EQ(bary::settings_hash(s), h0) << "results do not depend on it";
    }
  }
  WeightsSettings other = base;
  other.method = MethodId::LBC;
  EXPECT_NE(bary::settings_hash(other), h0);
  // the user weights' values count, not just their number
  WeightsSettings a = base, b = base;
  a.user_weights = { 1.0, 2.0 };
  b.user_weights = { 1.0, 2.5 };
  EXPECT_NE(bary::settings_hash(a), bary::settings_hash(b));
}

TEST(ComputeWeights, EqualsTheAlgorithmCalledDirectly)
{
  const bary::Cage cage = bary::test::unit_square();
  Eigen::MatrixXd points(3, 2);
  points << 0.25, 0.5, 0.9, 0.1, 2.0, 0.5;
  bary::WeightsInput input;
  input.cage = &cage;
  input.points = &points;
  const bary::WeightsResult result = bary::compute_weights(input, WeightsSettings{});
  const bary::MeanValueResult direct = bary::MeanValueCoordinates(cage).evaluate(points);
  EXPECT_EQ(result.W, direct.W);
  EXPECT_EQ(result.location, direct.location);
  EXPECT_EQ(result.count(bary::PointLocation::Outside), 1);
  // settings out of range are refused before anything runs
  WeightsSettings bad;
  bad.boundary_tolerance = 1.0;
  EXPECT_THROW(bary::compute_weights(input, bad), bary::Error);
  bary::WeightsInput empty;
  EXPECT_THROW(bary::compute_weights(empty, WeightsSettings{}), bary::Error);
}

TEST(ComputeWeights, NonConvergenceAdviceNamesTheSettings)
{
  const bary::Cage cage = bary::test::unit_square();
  Eigen::MatrixXd points(1, 2);
  points << 0.3, 0.4;
  bary::WeightsInput input;
  input.cage = &cage;
  input.points = &points;
  WeightsSettings s;
  s.method = MethodId::LBC;
  s.target_cells = 200;
  s.lbc_max_iterations = 1;
  try
  {
    bary::compute_weights(input, s);
    FAIL() << "converged in one iteration?";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::NotConverged);
    // the default stopping rule is the converged one: the advice also offers the paper's
    EXPECT_EQ(e.advice(), "raise LBCMaximumIterations (--max-iterations) or loosen "
                          "LBCPrimalTolerance / LBCDualTolerance (--primal-tolerance, "
                          "--dual-tolerance) or choose paper for LBCStopping (--stopping)");
    EXPECT_EQ(std::string(e.what()), e.message() + "; " + e.advice());
  }
  // a user already on the paper's rule is not told to choose it
  s.lbc_stopping = bary::LBCStopping::Paper;
  try
  {
    bary::compute_weights(input, s);
    FAIL() << "converged in one iteration?";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.advice(), "raise LBCMaximumIterations (--max-iterations) or loosen "
                          "LBCPrimalTolerance / LBCDualTolerance (--primal-tolerance, "
                          "--dual-tolerance)");
  }
}

// --- extreme scales (issue 17): the geometry is normalised by a power of two ----------------

namespace
{
bary::WeightsResult weights_at_scale(MethodId method, const bary::Cage& unit,
  const Eigen::MatrixXd& unit_points, double scale, int target_cells = 400)
{
  bary::Cage cage = unit;
  cage.V *= scale;
  const Eigen::MatrixXd points = unit_points * scale;
  bary::WeightsInput input;
  input.cage = &cage;
  input.points = &points;
  WeightsSettings s;
  s.method = method;
  s.target_cells = target_cells;
  return bary::compute_weights(input, s);
}

/// Partition of unity and linear reproduction of @p W at @p points to @p tol (relative to the
/// cage's extent @p scale).
void expect_barycentric(const bary::WeightsResult& r, const bary::Cage& cage,
  const Eigen::MatrixXd& points, double scale, double tol)
{
  ASSERT_TRUE(r.W.allFinite());
  for (Eigen::Index p = 0; p < points.rows(); ++p)
  {
    EXPECT_NEAR(r.W.row(p).sum(), 1.0, tol);
    const Eigen::RowVectorXd reproduced = r.W.row(p) * cage.V * scale;
    EXPECT_LE((reproduced - points.row(p) * scale).cwiseAbs().maxCoeff(), tol * scale);
  }
}
} // namespace

TEST(ComputeWeights, PowerOfTwoScalesGiveTheUnitScaleWeights)
{
  // Scaling by 2^k is exact and every method is invariant under scaling, so the weights of a
  // cage at 2^+-300 are those at scale 1 (to rounding where the normalised scale differs).
  const bary::Cage square = bary::test::unit_square(), cube = bary::test::unit_cube();
  Eigen::MatrixXd p2(3, 2), p3(3, 3);
  p2 << 0.25, 0.5, 0.9, 0.1, 0.5, 0.5;
  p3 << 0.25, 0.5, 0.4, 0.9, 0.1, 0.2, 0.5, 0.5, 0.5;
  for (const double scale : { std::ldexp(1.0, 300), std::ldexp(1.0, -300) })
  {
    SCOPED_TRACE(scale);
    for (const MethodId m : { MethodId::MeanValue, MethodId::Harmonic, MethodId::BBW, MethodId::LBC })
    {
      SCOPED_TRACE(bary::method_info(m).name);
      const bary::WeightsResult ref = weights_at_scale(m, square, p2, 1.0);
      const bary::WeightsResult big = weights_at_scale(m, square, p2, scale);
      ASSERT_EQ(big.W.rows(), ref.W.rows());
      EXPECT_LE((big.W - ref.W).cwiseAbs().maxCoeff(), 1e-9);
    }
    for (const MethodId m : { MethodId::MeanValue, MethodId::Harmonic })
    {
      SCOPED_TRACE(bary::method_info(m).name);
      const bary::WeightsResult ref = weights_at_scale(m, cube, p3, 1.0, 2000);
      const bary::WeightsResult big = weights_at_scale(m, cube, p3, scale, 2000);
      EXPECT_LE((big.W - ref.W).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

TEST(ComputeWeights, GreenCoordinatesAtExtremeScales)
{
  // Green coordinates' psi is not scale invariant (3D: psi scales with the cage; 2D: also a
  // log term): compute_weights scales it back, so x = W V + psi N holds at every scale and W
  // is the unit scale's (independently of how psi is stored).
  for (const bary::Cage& unit : { bary::test::unit_square(), bary::test::unit_cube() })
  {
    const int dim = unit.dimension();
    Eigen::MatrixXd p(2, dim);
    p.row(0).setConstant(0.3);
    p.row(1).setConstant(0.6);
    p(1, 0) = 0.2;
    const bary::WeightsResult ref = weights_at_scale(MethodId::Green, unit, p, 1.0);
    for (const double scale : { std::ldexp(1.0, 300), 1e300, 1e-300, std::ldexp(1.0, -290) })
    {
      SCOPED_TRACE(scale);
      bary::Cage cage = unit;
      cage.V *= scale;
      const bary::WeightsResult r = weights_at_scale(MethodId::Green, unit, p, scale);
      ASSERT_EQ(r.face_weights.cols(), dim == 2 ? 4 : 12);
      EXPECT_LE((r.W - ref.W).cwiseAbs().maxCoeff(), 1e-12);
      const Eigen::MatrixXd N = bary::green_face_terms(cage, cage.V); // unit normals
      const Eigen::MatrixXd x = r.W * cage.V + r.face_weights * N;
      EXPECT_LE((x - p * scale).cwiseAbs().maxCoeff(), 1e-12 * scale);
      if (dim == 3)
      { // psi = integral of 1 / (4 pi r): exactly proportional to the scale
        EXPECT_LE((r.face_weights / scale - ref.face_weights).cwiseAbs().maxCoeff(), 1e-12);
      }
    }
  }
}

TEST(ComputeWeights, CubesFrom1e300Down1e_300AreBarycentric)
{
  // A cube of side 1e100 gave NaN weights ("every point outside"), 1e75 crashed TetGen, 1e-50
  // ran TetGen out of memory (issue 17). Scales that are not powers of two change the mesh a
  // little (TetGen sees other coordinates), so the mesh methods are checked by their properties.
  const bary::Cage cube = bary::test::unit_cube();
  Eigen::MatrixXd p3(2, 3);
  p3 << 0.25, 0.5, 0.4, 0.9, 0.1, 0.2;
  const bary::WeightsResult mvc_ref = weights_at_scale(MethodId::MeanValue, cube, p3, 1.0);
  for (const double scale : { 1e300, 1e100, 1e75, 1e-50, 1e-75, 1e-300 })
  {
    SCOPED_TRACE(scale);
    const bary::WeightsResult mvc = weights_at_scale(MethodId::MeanValue, cube, p3, scale);
    EXPECT_EQ(mvc.count(bary::PointLocation::Inside), 2);
    EXPECT_LE((mvc.W - mvc_ref.W).cwiseAbs().maxCoeff(), 1e-12);
    const bary::WeightsResult harmonic = weights_at_scale(MethodId::Harmonic, cube, p3, scale, 2000);
    expect_barycentric(harmonic, cube, p3, scale, 1e-9);
    EXPECT_GE(harmonic.W.minCoeff(), -1e-12);
  }
}

TEST(ComputeWeights, MeshWeightsGivenBackInterpolateToTheSameWeights)
{
  // A distributed run solves once and sends WeightsResult::mesh_weights to the other processes,
  // which interpolate their pieces (WeightsInput::mesh_weights): every piece must get exactly
  // the rows of the whole run, at unit and at extreme (power-of-two rescaled) scales.
  const bary::Cage u = bary::test::regular_polygon(7); // convex about the origin
  Eigen::MatrixXd points(40, 2);
  for (Eigen::Index i = 0; i < points.rows(); ++i) // inside: 30% to 96% of the way to a vertex
    points.row(i) = u.V.row(i % u.V.rows()) * (0.3 + 0.0165 * static_cast<double>(i));
  for (const double scale : { 1.0, std::ldexp(1.0, 400) })
    for (const MethodId m : { MethodId::Harmonic, MethodId::BBW, MethodId::LBC })
    {
      SCOPED_TRACE(std::string(bary::method_info(m).name) + " at scale " + std::to_string(scale));
      bary::Cage cage = u;
      cage.V *= scale;
      const Eigen::MatrixXd X = points * scale;
      WeightsSettings settings;
      settings.method = m;
      settings.target_cells = 300;
      bary::WeightsInput input;
      input.cage = &cage;
      input.points = &X;
      const bary::WeightsResult whole = bary::compute_weights(input, settings);
      ASSERT_TRUE(whole.mesh_weights);
      const bary::MeshWeights& mesh = *whole.mesh_weights;
      EXPECT_EQ(mesh.W.rows(), mesh.V.rows());
      EXPECT_EQ(mesh.W.cols(), cage.V.rows());
      EXPECT_LE((mesh.V.colwise().maxCoeff() - cage.V.colwise().maxCoeff()).cwiseAbs().maxCoeff(),
        1e-12 * scale) << "the mesh at the input's scale";
      EXPECT_EQ(mesh.statistics, whole.statistics);
      const Eigen::MatrixXd piece = X.bottomRows(15);
      bary::WeightsInput given = input;
      given.points = &piece;
      given.mesh_weights = &mesh;
      const bary::WeightsResult interpolated = bary::compute_weights(given, settings);
      EXPECT_EQ(interpolated.W, bary::DenseWeights(whole.W.bottomRows(15))) << "bitwise";
      EXPECT_EQ(interpolated.statistics, whole.statistics);
    }
  // not a mesh-based method: refused by name
  WeightsSettings mvc;
  const bary::Cage cage = bary::test::unit_square();
  Eigen::MatrixXd X(1, 2);
  X << 0.5, 0.5;
  bary::MeshWeights mesh;
  bary::WeightsInput input;
  input.cage = &cage;
  input.points = &X;
  input.mesh_weights = &mesh;
  EXPECT_THROW(bary::compute_weights(input, mvc), bary::Error);
}

TEST(ComputeWeights, CelestialHullPointsOfAPieceAreTheWholesWithAReference)
{
  // The hull points (auto) depend on all the points; a piece that lies inside the controls'
  // hull would get none of its own. With the whole as reference, it gets the whole's columns.
  const bary::Cage square = bary::test::unit_square();
  Eigen::MatrixXd whole(4, 2);
  whole << 0.5, 0.5, 0.25, 0.75, 1.5, 0.5, -0.25, -0.5; // the last two are outside the square
  const Eigen::MatrixXd piece = whole.topRows(2);
  WeightsSettings settings;
  settings.method = MethodId::TCelestial;
  bary::WeightsInput input;
  input.cage = &square;
  input.points = &whole;
  const bary::WeightsResult all = bary::compute_weights(input, settings);
  ASSERT_EQ(all.added_controls.rows(), 4);
  input.points = &piece;
  const bary::WeightsResult alone = bary::compute_weights(input, settings);
  EXPECT_EQ(alone.added_controls.rows(), 0) << "inside points alone need no hull points";
  input.hull_reference_points = &whole;
  const bary::WeightsResult shared = bary::compute_weights(input, settings);
  EXPECT_EQ(shared.added_controls, all.added_controls);
  ASSERT_EQ(shared.W.cols(), all.W.cols());
  EXPECT_LE((shared.W - all.W.topRows(2)).cwiseAbs().maxCoeff(), 1e-12);
}
