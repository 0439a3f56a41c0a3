// Tests of core/surface/correspondence: maps between surfaces through corresponding anchors
// (Panozzo et al. 2013, §4.3-4.4): the identity, a similar copy (scaled, rotated, mirrored),
// undefined points, the distortion figures and errors.
#include "core/surface/correspondence.h"
#include "error_matchers.h"
#include "surface_catalogue.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

using namespace bary;
using bary::test::throws_error;

namespace
{

/// Anchors: the vertices closest to points of a cap of the unit sphere around +z.
std::vector<SurfacePoint> cap_anchors(const SurfaceMesh& m, const Eigen::Matrix3d& R, double s)
{
  Eigen::MatrixXd P(6, 3);
  const double pi = std::acos(-1.0);
  for (int i = 0; i < 6; ++i)
  {
    const double a = 2 * pi * i / 6;
    P.row(i) = (s * R * Eigen::Vector3d(0.6 * std::cos(a), 0.6 * std::sin(a), 0.8)).transpose();
  }
  return closest_surface_points(m, P);
}

std::vector<SurfacePoint> vertices_of(const SurfaceMesh& m)
{
  std::vector<SurfacePoint> p;
  for (Index v = 0; v < m.vertex_count(); ++v)
  {
    SurfacePoint q;
    q.face = m.vertex_faces[m.face_offsets[v]];
    for (int k = 0; k < 3; ++k)
      q.barycentric(k) = m.F(q.face, k) == v ? 1.0 : 0.0;
    p.push_back(q);
  }
  return p;
}

} // namespace

// A similar copy (scaled by 2, rotated, optionally mirrored) with the same connectivity and the
// scaled embedding: every defined vertex maps onto its own copy, every triangle with stretch 1.
TEST(Correspondence, SimilarCopyMapsVerticesOntoThemselves)
{
  const auto s = test::icosphere(3);
  const SurfaceMesh source(s.V, s.F);
  const Eigen::MatrixXd E = test::lift8(source.V);
  for (const bool mirror : { false, true })
  {
    Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    if (mirror)
      R.col(0) *= -1;
    Eigen::MatrixXi F = s.F;
    if (mirror)
      F.col(1).swap(F.col(2)); // keep the copy outward-oriented
    const SurfaceMesh target((2.0 * s.V * R.transpose()), F);
    const WeightedAverages wa_source(source, E), wa_target(target, 2.0 * E);
    const auto source_anchors = cap_anchors(source, Eigen::Matrix3d::Identity(), 1.0);
    const auto target_anchors = cap_anchors(target, R, 2.0);
    const SurfaceMap map = map_surface_points(
      wa_target, target_anchors, vertices_of(target), wa_source, source_anchors);
    ASSERT_GT(map.undefined, 0);               // the far side of the sphere is not reached
    ASSERT_LT(map.undefined, target.vertex_count() * 3 / 4);
    const Eigen::MatrixXd X = surface_point_positions(source.F, source.V, [&] {
      auto p = map.image;
      for (auto& q : p)
        if (q.face < 0)
          q = SurfacePoint{ 0, Eigen::Vector3d(1, 0, 0) };
      return p;
    }());
    for (Index v = 0; v < target.vertex_count(); ++v)
    {
      if (map.defined[v])
      {
        EXPECT_LT((X.row(v) - source.V.row(v)).norm(), 1e-9) << "vertex " << v;
      }
      else
      {
        EXPECT_EQ(map.image[v].face, -1);
      }
    }
    const MapDistortion d = map_distortion(target, source, map);
    EXPECT_GT(d.measured, 100);
    EXPECT_NEAR(d.stretch_all, 1.0, 1e-9);
    EXPECT_NEAR(d.stretch_best95, 1.0, 1e-9);
    EXPECT_EQ(d.flipped_count, 0) << "mirror " << mirror; // a mirror flips all alike
  }
}

TEST(Correspondence, StretchOfAnAnisotropicMap)
{
  // The target is the source stretched by 2 along x (same connectivity, the source's
  // embedding): the map back is x / 2; sigma of a triangle in the z = 0 plane is
  // sqrt(((1/4 + 1) / 2) ((4 + 1) / 2)) = 1.25.
  const auto g = test::flat_grid(10);
  const SurfaceMesh source(g.V, g.F);
  Eigen::MatrixXd Vt = g.V;
  Vt.col(0) *= 2.0;
  const SurfaceMesh target(Vt, g.F);
  const WeightedAverages wa_source(source, source.V), wa_target(target, target.V);
  Eigen::MatrixXd A(4, 3);
  A << -0.9, -0.9, 0, 0.9, -0.9, 0, 0.9, 0.9, 0, -0.9, 0.9, 0;
  Eigen::MatrixXd At = A;
  At.col(0) *= 2.0;
  const SurfaceMap map = map_surface_points(wa_target, closest_surface_points(target, At),
    vertices_of(target), wa_source, closest_surface_points(source, A));
  const MapDistortion d = map_distortion(target, source, map);
  EXPECT_GT(d.measured, 50);
  for (Index f = 0; f < target.face_count(); ++f)
    if (!std::isnan(d.stretch(f)))
    {
      EXPECT_NEAR(d.stretch(f), 1.25, 1e-9);
    }
}

TEST(Correspondence, Errors)
{
  const auto s = test::icosphere(2);
  const SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, m.V);
  const auto a = cap_anchors(m, Eigen::Matrix3d::Identity(), 1.0);
  auto fewer = a;
  fewer.pop_back();
  EXPECT_TRUE(throws_error([&] { map_surface_points(wa, a, a, wa, fewer); }, ErrorCode::SizeMismatch,
    { "6 anchors but the source has 5" }));
  SurfaceMap short_map;
  EXPECT_TRUE(throws_error([&] { map_distortion(m, m, short_map); }, ErrorCode::SizeMismatch, { "vertices" }));
}
