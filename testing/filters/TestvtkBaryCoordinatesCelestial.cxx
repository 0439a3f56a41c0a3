// Tests of vtkBaryCoordinates and vtkBaryCageDeformation with the celestial methods (free control
// points, no cage): partition of unity, reproduction, positivity, Lagrange at the controls, the
// outside policies, user weights, warm starts along the input's edges giving the same weights,
// 2D controls, deformation by moved controls, hull points (AddedControlPoints), and the error
// paths.
#include "filters_test_utils.h"

#include "vtkBaryCageDeformation.h"
#include "vtkBaryCoordinates.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using namespace barylab_test;

/// Octahedron-ish control points (6) plus two inside, 3D.
vtkSmartPointer<vtkPolyData> Controls3D()
{
  return MakePointCloud({ { 1.2, 0, 0 }, { -1.1, 0.1, 0 }, { 0, 1.3, 0.1 }, { 0.1, -1.2, 0 },
    { 0, 0, 1.25 }, { 0.05, 0, -1.15 }, { 0.3, 0.2, 0.1 }, { -0.2, -0.3, 0.2 } });
}

/// Random points inside the octahedron |x|+|y|+|z| < 0.9 (inside the controls' hull), with
/// triangle cells joining consecutive triples (edges for the warm starts).
vtkSmartPointer<vtkPolyData> Inside3D(int n)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  std::vector<std::array<double, 3>> xs;
  while (static_cast<int>(xs.size()) < n)
  {
    const std::array<double, 3> x = { u(rng), u(rng), u(rng) };
    if (std::abs(x[0]) + std::abs(x[1]) + std::abs(x[2]) < 0.9)
      xs.push_back(x);
  }
  auto cloud = MakePointCloud(xs);
  vtkNew<vtkCellArray> tris;
  for (vtkIdType i = 0; i + 2 < n; i += 3)
  {
    const vtkIdType ids[3] = { i, i + 1, i + 2 };
    tris->InsertNextCell(3, ids);
  }
  cloud->SetPolys(tris);
  return cloud;
}

struct Celestial
{
  vtkNew<vtkBaryCoordinates> Filter;
  vtkNew<ErrorObserver> Observer;
  Celestial(vtkDataSet* points, vtkPolyData* controls, int method)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->GetWeightMethod()->SetMethod(method);
    this->Filter->SetInputData(0, points);
    this->Filter->SetCageData(controls);
  }
  int Run() { return RunPipeline(this->Filter); }
  vtkDataArray* Weights() { return GetWeights(vtkDataSet::SafeDownCast(this->Filter->GetOutputDataObject(0))); }
};

/// Max partition and reproduction errors, min weight.
std::array<double, 3> Properties(vtkDataSet* points, vtkDataArray* W, vtkPolyData* controls, int dim)
{
  double partition = 0, reproduction = 0, lo = 1;
  for (vtkIdType p = 0; p < W->GetNumberOfTuples(); ++p)
  {
    double x[3], y[3] = { 0, 0, 0 }, sum = 0;
    points->GetPoint(p, x);
    for (int i = 0; i < W->GetNumberOfComponents(); ++i)
    {
      double c[3];
      controls->GetPoint(i, c);
      const double w = W->GetComponent(p, i);
      sum += w;
      lo = std::min(lo, w);
      for (int k = 0; k < dim; ++k)
        y[k] += w * c[k];
    }
    partition = std::max(partition, std::abs(sum - 1));
    for (int k = 0; k < dim; ++k)
      reproduction = std::max(reproduction, std::abs(y[k] - x[k]));
  }
  return { partition, reproduction, lo };
}

TEST(vtkBaryCoordinatesCelestial, SCCAndTCCHaveTheirPropertiesIn3D)
{
  auto controls = Controls3D();
  auto points = Inside3D(300);
  for (int method : { vtkBaryWeightMethod::S_CELESTIAL, vtkBaryWeightMethod::T_CELESTIAL })
  {
    SCOPED_TRACE(vtkBaryWeightMethod::GetMethodName(method));
    Celestial c(points, controls, method);
    ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
    vtkDataArray* W = c.Weights();
    ASSERT_NE(W, nullptr);
    ASSERT_EQ(W->GetNumberOfComponents(), 8);
    const auto [partition, reproduction, lo] = Properties(points, W, controls, 3);
    EXPECT_LE(partition, 1e-12);
    EXPECT_LE(reproduction, 1e-10);
    EXPECT_GT(lo, 0.0) << "celestial coordinates are positive inside the hull";
    EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), 300);
    EXPECT_EQ(c.Filter->GetStatistic("not_converged"), 0.0);
    EXPECT_GT(c.Filter->GetStatistic("warm_starts"), 0.0) << "the triangles' edges order the warm starts";
    EXPECT_LE(c.Filter->GetStatistic("max_residual"), 1e-11);
  }
}

TEST(vtkBaryCoordinatesCelestial, LagrangeAtControlsAnd2DControls)
{
  auto controls = MakePointCloud({ { 0, 0, 0.5 }, { 2, 0, 0.5 }, { 2, 1, 0.5 }, { 0, 1, 0.5 }, { 1, 0.5, 0.5 } });
  auto points = MakePointCloud({ { 0, 0, 0.5 }, { 1, 0.5, 0.5 }, { 0.3, 0.7, 0.5 }, { 1.9, 0.1, 0.5 } });
  Celestial c(points, controls, vtkBaryWeightMethod::S_CELESTIAL);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  vtkDataArray* W = c.Weights();
  ASSERT_EQ(W->GetNumberOfComponents(), 5);
  for (int j = 0; j < 5; ++j)
  {
    EXPECT_EQ(W->GetComponent(0, j), j == 0 ? 1.0 : 0.0);
    EXPECT_EQ(W->GetComponent(1, j), j == 4 ? 1.0 : 0.0);
  }
  const auto [partition, reproduction, lo] = Properties(points, W, controls, 2);
  EXPECT_LE(partition, 1e-12);
  EXPECT_LE(reproduction, 1e-10);
  EXPECT_GE(lo, 0.0);
  EXPECT_EQ(c.Filter->GetNumberOfBoundaryPoints(), 2) << "points at controls count as on the hull";
}

TEST(vtkBaryCoordinatesCelestial, OutsidePointsFollowThePolicyAndUserWeightsChangeTCC)
{
  auto controls = Controls3D();
  auto points = MakePointCloud({ { 0.1, 0.1, 0.1 }, { 3, 3, 3 } });
  Celestial c(points, controls, vtkBaryWeightMethod::S_CELESTIAL);
  // the default (hull points auto) would add hull points around the outside point
  c.Filter->GetWeightMethod()->SetCelestialHullPointsToNone();
  EXPECT_EQ(c.Run(), 0);
  EXPECT_TRUE(c.Observer->HasError("outside")) << c.Observer->AllErrors();
  c.Observer->Clear();
  c.Filter->GetWeightMethod()->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NAN);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_EQ(c.Filter->GetNumberOfOutsidePoints(), 1);
  EXPECT_EQ(c.Filter->GetNumberOfUndefinedPoints(), 1);
  EXPECT_TRUE(std::isnan(c.Weights()->GetComponent(1, 0)));
  EXPECT_FALSE(std::isnan(c.Weights()->GetComponent(0, 0)));
  c.Observer->Clear();
  c.Filter->GetWeightMethod()->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NEAREST);
  EXPECT_EQ(c.Run(), 0);
  EXPECT_TRUE(c.Observer->HasError("convex hull only")) << c.Observer->AllErrors();

  // user weights (TCC's s_i): a large s on control 0 raises its weight at an inside point
  auto inside = MakePointCloud({ { 0.1, 0.1, 0.1 } });
  Celestial plain(inside, controls, vtkBaryWeightMethod::T_CELESTIAL);
  ASSERT_EQ(plain.Run(), 1);
  const double w0 = plain.Weights()->GetComponent(0, 0);
  Celestial weighted(inside, controls, vtkBaryWeightMethod::T_CELESTIAL);
  vtkNew<vtkDoubleArray> s;
  s->SetNumberOfTuples(8);
  s->Fill(0.0);
  s->SetValue(0, 5.0);
  weighted.Filter->GetWeightMethod()->SetUserWeights(s);
  ASSERT_EQ(weighted.Run(), 1) << weighted.Observer->AllErrors();
  EXPECT_GT(weighted.Weights()->GetComponent(0, 0), w0 + 1e-3);
  const auto [partition, reproduction, lo] = Properties(inside, weighted.Weights(), controls, 3);
  EXPECT_LE(partition, 1e-12);
  EXPECT_LE(reproduction, 1e-10);
  // SCC takes no user weights; a wrong count is named
  Celestial scc(inside, controls, vtkBaryWeightMethod::S_CELESTIAL);
  scc.Filter->GetWeightMethod()->SetUserWeights(s);
  EXPECT_EQ(scc.Run(), 0);
  EXPECT_TRUE(scc.Observer->HasError("take none")) << scc.Observer->AllErrors();
  s->SetNumberOfTuples(3);
  weighted.Filter->Modified();
  EXPECT_EQ(weighted.Run(), 0);
}

TEST(vtkBaryCoordinatesCelestial, DegenerateControlsAreNamed)
{
  auto coplanar = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 1e-16 + 0.0 }, { 0.5, 0.5, 1.0 } });
  coplanar->GetPoints()->SetPoint(4, 0.5, 0.5, 0.0);
  // all five in z = 0 up to rounding: read as 2D, which is fine; force 3D to see the error
  Celestial c(MakePointCloud({ { 0.5, 0.5, 0 } }), coplanar, vtkBaryWeightMethod::S_CELESTIAL);
  c.Filter->GetWeightMethod()->SetCageDimension(3);
  // hull points auto (the default) give flat controls an interior: the 8 corners are added
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_EQ(c.Weights()->GetNumberOfComponents(), 5 + 8);
  c.Filter->GetWeightMethod()->SetCelestialHullPointsToNone();
  EXPECT_EQ(c.Run(), 0);
  EXPECT_TRUE(c.Observer->HasError("plane")) << c.Observer->AllErrors();
  auto twice = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 0 } });
  Celestial d(MakePointCloud({ { 0.1, 0.1, 0.1 } }), twice, vtkBaryWeightMethod::S_CELESTIAL);
  EXPECT_EQ(d.Run(), 0);
  EXPECT_TRUE(d.Observer->HasError("control points 1 and 4 coincide")) << d.Observer->AllErrors();
}

TEST(vtkBaryCoordinatesCelestial, DeformationByMovedControlPoints)
{
  auto controls = Controls3D();
  auto model = Inside3D(60);
  // an affine motion of the controls moves the model by the same map (reproduction)
  auto moved = vtkSmartPointer<vtkPolyData>::New();
  moved->DeepCopy(controls);
  const auto affine = [](const double x[3], double y[3]) {
    y[0] = 1.2 * x[0] + 0.3 * x[1] + 0.5;
    y[1] = -0.2 * x[0] + 0.9 * x[1] + 0.1 * x[2] - 1.0;
    y[2] = 0.4 * x[2] + 0.2;
  };
  for (vtkIdType i = 0; i < controls->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    controls->GetPoint(i, x);
    affine(x, y);
    moved->GetPoints()->SetPoint(i, y);
  }
  vtkNew<vtkBaryCageDeformation> deform;
  vtkNew<ErrorObserver> errors;
  errors->Attach(deform);
  deform->GetWeightMethod()->SetMethod(vtkBaryWeightMethod::S_CELESTIAL);
  deform->SetInputData(model);
  deform->SetRestCageData(controls);
  deform->SetDeformedCageData(moved);
  ASSERT_EQ(RunPipeline(deform), 1) << errors->AllErrors();
  double worst = 0;
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3], z[3];
    model->GetPoint(p, x);
    affine(x, y);
    deform->GetOutput()->GetPoint(p, z);
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(y[k] - z[k]));
  }
  EXPECT_LE(worst, 1e-9);
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 1);
  // moving the controls again reuses the weights
  moved->GetPoints()->SetPoint(0, 2.0, 0.0, 0.0);
  moved->Modified();
  ASSERT_EQ(RunPipeline(deform), 1);
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 1);
}

// Hull points (CelestialHullPoints auto, the default) in 2D at z = 0.5: points far outside three
// controls get 3 + 4 weights, positive, a partition of unity reproducing them with the added
// corners, whose positions are the field data AddedControlPoints (z: the controls' plane): a
// rectangle holding every point and control at least the margin times its diagonal inside, the
// nearest exactly that; with none the points outside are an error, and with none and NaN rows
// the array is dropped again; points strictly inside get no hull points.
TEST(vtkBaryCoordinatesCelestial, HullPointsAreAddedAndReported)
{
  auto controls = MakePointCloud({ { 0, 0, 0.5 }, { 1, 0, 0.5 }, { 0, 1, 0.5 } });
  auto points = MakePointCloud({ { 3, 2, 0.5 }, { -2, 0.5, 0.5 }, { 0.2, 0.2, 0.5 }, { 1, -4, 0.5 } });
  Celestial c(points, controls, vtkBaryWeightMethod::S_CELESTIAL);
  EXPECT_EQ(c.Filter->GetWeightMethod()->GetCelestialHullPoints(),
    vtkBaryWeightMethod::HULL_POINTS_AUTO);
  c.Filter->GetWeightMethod()->SetCelestialHullPointsToNone();
  EXPECT_EQ(c.Run(), 0) << "outside the hull without hull points";
  c.Observer->Clear();
  c.Filter->GetWeightMethod()->SetCelestialHullPointsToAuto();
  c.Filter->GetWeightMethod()->SetCelestialHullMargin(0.25);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  vtkDataArray* W = c.Weights();
  ASSERT_NE(W, nullptr);
  ASSERT_EQ(W->GetNumberOfComponents(), 7);
  vtkDataSet* out = vtkDataSet::SafeDownCast(c.Filter->GetOutputDataObject(0));
  vtkDataArray* added = out->GetFieldData()->GetArray("AddedControlPoints");
  ASSERT_NE(added, nullptr);
  ASSERT_EQ(added->GetNumberOfTuples(), 4);
  // a rectangle: corner 3 = corner 0 + both edges, the edges orthogonal
  double h[4][3];
  for (vtkIdType k = 0; k < 4; ++k)
  {
    added->GetTuple(k, h[k]);
    EXPECT_EQ(h[k][2], 0.5);
  }
  const double e[2][2] = { { h[1][0] - h[0][0], h[1][1] - h[0][1] },
    { h[2][0] - h[0][0], h[2][1] - h[0][1] } };
  EXPECT_NEAR(h[3][0], h[0][0] + e[0][0] + e[1][0], 1e-12);
  EXPECT_NEAR(h[3][1], h[0][1] + e[0][1] + e[1][1], 1e-12);
  EXPECT_NEAR(e[0][0] * e[1][0] + e[0][1] * e[1][1], 0.0, 1e-12);
  // every point and control at least pad inside each side, the nearest exactly pad, where pad
  // is 0.25 times the diagonal of the rectangle without it
  const std::vector<std::array<double, 2>> all_points = { { 3, 2 }, { -2, 0.5 }, { 0.2, 0.2 },
    { 1, -4 }, { 0, 0 }, { 1, 0 }, { 0, 1 } };
  double length[2], slack[2][2];
  for (int j = 0; j < 2; ++j)
  {
    length[j] = std::hypot(e[j][0], e[j][1]);
    slack[j][0] = slack[j][1] = std::numeric_limits<double>::infinity();
    for (const auto& p : all_points)
    {
      const double t = ((p[0] - h[0][0]) * e[j][0] + (p[1] - h[0][1]) * e[j][1]) / length[j];
      slack[j][0] = std::min(slack[j][0], t);
      slack[j][1] = std::min(slack[j][1], length[j] - t);
    }
  }
  const double pad = 0.25 * std::hypot(length[0] - 2 * slack[0][0], length[1] - 2 * slack[0][0]);
  for (int j = 0; j < 2; ++j)
    for (int side = 0; side < 2; ++side)
      EXPECT_NEAR(slack[j][side], pad, 1e-12) << "axis " << j << " side " << side;
  auto all = MakePointCloud({ { 0, 0, 0.5 }, { 1, 0, 0.5 }, { 0, 1, 0.5 } });
  for (vtkIdType k = 0; k < 4; ++k)
    all->GetPoints()->InsertNextPoint(added->GetTuple3(k));
  const auto [partition, reproduction, lo] = Properties(points, W, all, 2);
  EXPECT_LE(partition, 1e-12);
  EXPECT_LE(reproduction, 1e-10);
  EXPECT_GT(lo, 0.0);
  EXPECT_EQ(c.Filter->GetStatistic("hull_points_added"), 4.0);
  c.Filter->GetWeightMethod()->SetCelestialHullPoints(vtkBaryWeightMethod::HULL_POINTS_NONE);
  c.Filter->GetWeightMethod()->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NAN);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  out = vtkDataSet::SafeDownCast(c.Filter->GetOutputDataObject(0));
  EXPECT_EQ(out->GetFieldData()->GetArray("AddedControlPoints"), nullptr);
  EXPECT_EQ(c.Weights()->GetNumberOfComponents(), 3);
  // strictly inside: auto adds nothing, always adds the 4 corners
  auto inside = MakePointCloud({ { 0.2, 0.2, 0.5 }, { 0.3, 0.1, 0.5 } });
  Celestial d(inside, controls, vtkBaryWeightMethod::S_CELESTIAL);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Weights()->GetNumberOfComponents(), 3);
  EXPECT_EQ(d.Filter->GetStatistic("hull_points_added"), 0.0);
  d.Filter->GetWeightMethod()->SetCelestialHullPointsToAlways();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Weights()->GetNumberOfComponents(), 7);
}

} // namespace
