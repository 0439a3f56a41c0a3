// Tests of core/surface/euclidean_embedding: the embedding of Panozzo et al. 2013 §3.5 against
// exact distances (a flat patch: Euclidean; the unit sphere: great circles), its stages
// (landmarks, SMACOF, least-squares upsampling) and its errors; the authors' meshes
// (BARYLAB_SHARED_DIR/wa) when present.
#include "core/surface/euclidean_embedding.h"
#include "error_matchers.h"
#include "igl_formats.h"
#include "surface_catalogue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>

using namespace bary;
using bary::test::throws_error;

namespace
{

struct Errors
{
  double mean = 0, max = 0;
};

/// Relative error of embedded distances against exact ones over random pairs farther apart
/// than min_distance.
template<class Exact>
Errors distance_errors(const Eigen::MatrixXd& E, Index n, Exact exact, double min_distance)
{
  std::mt19937 rng(7);
  std::uniform_int_distribution<Index> pick(0, n - 1);
  Errors e;
  int count = 0;
  for (int t = 0; t < 20000; ++t)
  {
    const Index i = pick(rng), j = pick(rng);
    const double g = exact(i, j);
    if (g < min_distance)
      continue;
    const double r = std::abs((E.row(i) - E.row(j)).norm() - g) / g;
    e.mean += r;
    e.max = std::max(e.max, r);
    ++count;
  }
  e.mean /= count;
  return e;
}

} // namespace

// A flat patch is embedded isometrically up to the heat method's first-order error.
TEST(EuclideanEmbedding, FlatPatchDistancesAreEuclidean)
{
  const auto g = test::flat_grid(40);
  const SurfaceMesh m(g.V, g.F);
  for (const auto method : { LandmarkMethod::Decimation, LandmarkMethod::FarthestPoint })
  {
    EmbeddingOptions options;
    options.landmarks = 300;
    options.landmark_method = method;
    const EmbeddingResult r = euclidean_embedding(m, options);
    ASSERT_EQ(r.E.rows(), m.vertex_count());
    ASSERT_EQ(r.E.cols(), 8);
    EXPECT_EQ(r.landmarks.size(), 300u);
    const Errors e = distance_errors(r.E, m.vertex_count(),
      [&](Index i, Index j) { return (m.V.row(i) - m.V.row(j)).norm(); }, 0.2);
    EXPECT_LT(e.mean, 0.03);
    EXPECT_LT(e.max, 0.25);
    EXPECT_LE(r.stress, r.initial_stress);
    EXPECT_TRUE(r.smacof_converged);
  }
}

// The unit sphere: embedded distances against great-circle distances.
TEST(EuclideanEmbedding, SphereDistancesAreGreatCircles)
{
  const auto s = test::icosphere(4);
  const SurfaceMesh m(s.V, s.F);
  EmbeddingOptions options;
  options.landmarks = 400;
  const EmbeddingResult r = euclidean_embedding(m, options);
  const Errors e = distance_errors(r.E, m.vertex_count(),
    [&](Index i, Index j) { return std::acos(std::clamp(m.V.row(i).dot(m.V.row(j)), -1.0, 1.0)); },
    0.3);
  // No Euclidean embedding matches great circles (an arc of length pi against a chord of 2):
  // MDS compromises. Measured: mean 0.075, max 0.30; bounds with margin.
  EXPECT_LT(e.mean, 0.1);
  EXPECT_LT(e.max, 0.4);
  // The quality report measures the same thing against heat-method distances.
  EXPECT_GT(r.quality.pairs, 1000);
  EXPECT_LT(r.quality.mean_relative_error, 0.1);
  EXPECT_LE(r.quality.median_relative_error, r.quality.max_relative_error);
}

// The landmarks keep their MDS positions (Eq. 15 fixes them); all vertices embed finitely.
TEST(EuclideanEmbedding, UpsamplingInterpolatesTheLandmarks)
{
  const auto t = test::torus(40, 16);
  const SurfaceMesh m(t.V, t.F);
  EmbeddingOptions options;
  options.landmarks = 120;
  options.max_iterations = 0; // classical MDS only: the landmark positions are its eigenvectors
  const EmbeddingResult r = euclidean_embedding(m, options);
  EXPECT_TRUE(r.E.allFinite());
  EXPECT_EQ(r.smacof_iterations, 0);
  const std::set<int> unique(r.landmarks.begin(), r.landmarks.end());
  EXPECT_EQ(unique.size(), r.landmarks.size());
  // Every non-landmark vertex lies near its neighbours' average (a smooth LS mesh), and no
  // two landmarks collapse.
  for (std::size_t a = 0; a < r.landmarks.size(); ++a)
    for (std::size_t b = a + 1; b < r.landmarks.size(); ++b)
      EXPECT_GT((r.E.row(r.landmarks[a]) - r.E.row(r.landmarks[b])).norm(), 1e-3);
}

TEST(EuclideanEmbedding, DeterministicAndThreadIndependent)
{
  const auto s = test::icosphere(3);
  const SurfaceMesh m(s.V, s.F);
  EmbeddingOptions one, two;
  one.landmarks = two.landmarks = 200;
  one.threads = 1;
  two.threads = 2;
  const EmbeddingResult a = euclidean_embedding(m, one), b = euclidean_embedding(m, two);
  EXPECT_EQ(a.landmarks, b.landmarks);
  EXPECT_EQ(a.smacof_iterations, b.smacof_iterations);
  EXPECT_TRUE(a.E.cwiseEqual(b.E).all());
}

TEST(EuclideanEmbedding, FarthestPointLandmarksAreSpread)
{
  const auto s = test::icosphere(4);
  const SurfaceMesh m(s.V, s.F);
  const auto l = farthest_point_landmarks(m, 100);
  ASSERT_EQ(l.size(), 100u);
  EXPECT_TRUE(std::is_sorted(l.begin(), l.end()));
  // 100 spread points on the unit sphere: every vertex within ~0.35 of one (area 4 pi / 100
  // per sample, radius ~0.2; FPS covers within twice the packing radius).
  for (Index v = 0; v < m.vertex_count(); ++v)
  {
    double best = 10;
    for (const int i : l)
      best = std::min(best, (m.V.row(v) - m.V.row(i)).norm());
    ASSERT_LT(best, 0.45) << "vertex " << v;
  }
  EXPECT_EQ(farthest_point_landmarks(m, 100000).size(), static_cast<std::size_t>(m.vertex_count()));
}

TEST(EuclideanEmbedding, OptionsOutOfRangeAreNamed)
{
  const auto s = test::icosphere(1);
  const SurfaceMesh m(s.V, s.F);
  EmbeddingOptions o;
  o.dimension = 1;
  EXPECT_TRUE(throws_error([&] { euclidean_embedding(m, o); }, ErrorCode::InvalidArgument, { "dimension", "[2, 64]" }));
  o = {};
  o.landmarks = 5;
  EXPECT_TRUE(throws_error([&] { euclidean_embedding(m, o); }, ErrorCode::InvalidArgument, { "landmarks", "[10, 100000]" }));
  o = {};
  o.stress_tolerance = 0;
  EXPECT_TRUE(throws_error([&] { euclidean_embedding(m, o); }, ErrorCode::InvalidArgument, { "stress tolerance" }));
  o = {};
  o.heat_time_factor = -1;
  EXPECT_TRUE(throws_error([&] { euclidean_embedding(m, o); }, ErrorCode::InvalidArgument, { "heat time factor" }));
  o = {};
  o.dimension = 40; // needs 42 vertices; the icosphere(1) has 42
  o.landmarks = 42;
  EXPECT_NO_THROW(euclidean_embedding(m, o));
  o.dimension = 41;
  o.landmarks = 43;
  EXPECT_TRUE(throws_error([&] { euclidean_embedding(m, o); }, ErrorCode::InvalidArgument, { "42 vertices" }));
}

TEST(EuclideanEmbedding, Cancellation)
{
  const auto s = test::icosphere(3);
  const SurfaceMesh m(s.V, s.F);
  EmbeddingOptions o;
  o.landmarks = 100;
  int calls = 0;
  EXPECT_TRUE(throws_error([&] { euclidean_embedding(m, o, [&](double) { return ++calls < 3; }); },
    ErrorCode::Cancelled, {}));
}

// The authors' meshes: the embedding's distances against heat-method geodesics.
TEST(EuclideanEmbedding, AuthorsMeshes)
{
  const std::filesystem::path dir = std::filesystem::path(BARYLAB_SHARED_DIR) / "wa";
  if (!std::filesystem::exists(dir / "3holes.obj"))
    GTEST_SKIP() << "no shared data at " << dir;
  const auto mesh = test::read_obj((dir / "3holes.obj").string());
  const SurfaceMesh m(mesh.V, mesh.F);
  EXPECT_EQ(m.genus(), 3);
  EmbeddingOptions o;
  o.landmarks = 400;
  const EmbeddingResult r = euclidean_embedding(m, o);
  EXPECT_TRUE(r.smacof_converged);
  EXPECT_LT(r.quality.mean_relative_error, 0.12);
  EXPECT_LT(r.stress, r.initial_stress);
}
