// Independent reference for vtkBaryCoordinates in 3D: VTK's own implementation of Ju et al.
// 2005, vtkMeanValueCoordinatesInterpolator. Inside a closed triangle cage both must agree to
// round-off. On a cage edge they do not: VTK's result there is wrong (a documented VTK
// limitation), while BaryLab returns the exact linear interpolant along the edge.
#include "filters_test_utils.h"

#include "vtkBaryCoordinates.h"

#include "vtkIdList.h"
#include "vtkMeanValueCoordinatesInterpolator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace
{
using namespace barylab_test;

/// The triangles of @p cage as a flat id list (3 ids per triangle), VTK's input format.
vtkSmartPointer<vtkIdList> Triangles(vtkPolyData* cage)
{
  auto tris = vtkSmartPointer<vtkIdList>::New();
  vtkIdType size;
  const vtkIdType* ids;
  for (vtkIdType f = 0; f < cage->GetNumberOfPolys(); ++f)
  {
    cage->GetPolys()->GetCellAtId(f, size, ids);
    EXPECT_EQ(size, 3);
    for (vtkIdType k = 0; k < size; ++k)
      tris->InsertNextId(ids[k]);
  }
  return tris;
}

/// BaryLab's weights at the points of @p queries w.r.t. @p cage.
vtkSmartPointer<vtkDataSet> BaryLabWeights(vtkPolyData* queries, vtkPolyData* cage)
{
  vtkNew<vtkBaryCoordinates> filter;
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  filter->SetInputData(0, queries);
  filter->SetCageData(cage);
  EXPECT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  return vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0));
}

/// Max over all query points and cage points of |BaryLab - VTK|.
double MaxDifferenceToVTK(vtkPolyData* queries, vtkPolyData* cage)
{
  auto out = BaryLabWeights(queries, cage);
  vtkDataArray* W = GetWeights(out);
  EXPECT_NE(W, nullptr);
  if (!W)
    return INFINITY;
  const vtkIdType nc = cage->GetNumberOfPoints();
  EXPECT_EQ(W->GetNumberOfComponents(), nc);
  auto tris = Triangles(cage);
  std::vector<double> reference(static_cast<std::size_t>(nc));
  double worst = 0.0;
  for (vtkIdType p = 0; p < queries->GetNumberOfPoints(); ++p)
  {
    double x[3];
    queries->GetPoint(p, x);
    vtkMeanValueCoordinatesInterpolator::ComputeInterpolationWeights(
      x, cage->GetPoints(), tris, reference.data());
    for (vtkIdType i = 0; i < nc; ++i)
      worst = std::max(worst,
        std::abs(W->GetComponent(p, static_cast<int>(i)) - reference[static_cast<std::size_t>(i)]));
  }
  return worst;
}

TEST(vtkBaryCoordinatesVTKReference, BundledCageAtModelVertices)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  EXPECT_LE(MaxDifferenceToVTK(PointsOnly(model), cage), 1e-10);
}

TEST(vtkBaryCoordinatesVTKReference, BundledCageAtRandomInteriorPoints)
{
  // data/README.md: every model vertex is inside the cage and at least 0.106 from its surface,
  // so a model vertex moved by less than 0.1 is still strictly inside.
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  std::mt19937 rng(20240531);
  std::uniform_int_distribution<vtkIdType> pick(0, model->GetNumberOfPoints() - 1);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05); // |offset| <= 0.0866
  std::vector<std::array<double, 3>> xs;
  for (int n = 0; n < 500; ++n)
  {
    std::array<double, 3> x;
    model->GetPoint(pick(rng), x.data());
    for (double& c : x)
      c += jitter(rng);
    xs.push_back(x);
  }
  auto queries = MakePointCloud(xs);
  EXPECT_LE(MaxDifferenceToVTK(queries, cage), 1e-10);
  auto out = BaryLabWeights(queries, cage);
  auto* location = out->GetPointData()->GetArray("CageLocation");
  ASSERT_NE(location, nullptr);
  for (vtkIdType p = 0; p < queries->GetNumberOfPoints(); ++p)
    ASSERT_EQ(location->GetComponent(p, 0), 0.0) << "point " << p << " should be inside";
}

TEST(vtkBaryCoordinatesVTKReference, CubeAtRandomInteriorPoints)
{
  auto cube = MakeCube();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> inside(-0.999, 0.999);
  std::vector<std::array<double, 3>> xs;
  for (int n = 0; n < 1000; ++n)
    xs.push_back({ inside(rng), inside(rng), inside(rng) });
  xs.push_back({ 0, 0, 0 });
  xs.push_back({ 0.9999, -0.9999, 0.5 }); // close to an edge, still inside
  EXPECT_LE(MaxDifferenceToVTK(MakePointCloud(xs), cube), 1e-10);
}

/// The exact weights at (1 - t) a + t b on the cage edge a-b: linear along the edge.
double LinearOnEdge(vtkIdType i, vtkIdType a, vtkIdType b, double t)
{
  return i == a ? 1.0 - t : (i == b ? t : 0.0);
}

/// Max over the corners of |VTK's weight - the exact weight| at (1 - t) a + t b.
double VTKErrorOnEdge(vtkPolyData* cage, vtkIdType a, vtkIdType b, double t)
{
  double pa[3], pb[3], x[3];
  cage->GetPoint(a, pa);
  cage->GetPoint(b, pb);
  for (int k = 0; k < 3; ++k)
    x[k] = (1.0 - t) * pa[k] + t * pb[k];
  std::vector<double> w(static_cast<std::size_t>(cage->GetNumberOfPoints()));
  auto tris = Triangles(cage);
  vtkMeanValueCoordinatesInterpolator::ComputeInterpolationWeights(
    x, cage->GetPoints(), tris, w.data());
  double error = 0.0;
  for (vtkIdType i = 0; i < cage->GetNumberOfPoints(); ++i)
    error = std::max(error, std::abs(w[static_cast<std::size_t>(i)] - LinearOnEdge(i, a, b, t)));
  return error;
}

TEST(vtkBaryCoordinatesVTKReference, ExactOnEveryCubeEdge)
{
  // The mean value coordinates extend continuously to the cage, where they are linear along
  // an edge. Every edge of the triangulated cube (12 cube edges, 6 face diagonals), at its
  // midpoint and at 30 %.
  auto cube = MakeCube();
  std::vector<std::array<double, 3>> xs;
  struct EdgePoint
  {
    vtkIdType a, b;
    double t;
  };
  std::vector<EdgePoint> where;
  vtkIdType size;
  const vtkIdType* ids;
  for (vtkIdType f = 0; f < cube->GetNumberOfPolys(); ++f)
  {
    cube->GetPolys()->GetCellAtId(f, size, ids);
    for (int e = 0; e < 3; ++e)
    {
      const vtkIdType a = ids[e], b = ids[(e + 1) % 3];
      if (a > b)
        continue; // each edge once (it is a > b in the other face)
      for (double t : { 0.5, 0.3 })
      {
        double pa[3], pb[3];
        cube->GetPoint(a, pa);
        cube->GetPoint(b, pb);
        xs.push_back({ (1 - t) * pa[0] + t * pb[0], (1 - t) * pa[1] + t * pb[1],
          (1 - t) * pa[2] + t * pb[2] });
        where.push_back({ a, b, t });
      }
    }
  }
  ASSERT_EQ(where.size(), 36u);
  auto out = BaryLabWeights(MakePointCloud(xs), cube);
  vtkDataArray* W = GetWeights(out);
  ASSERT_NE(W, nullptr);
  for (std::size_t p = 0; p < where.size(); ++p)
  {
    for (int i = 0; i < 8; ++i)
      EXPECT_NEAR(W->GetComponent(static_cast<vtkIdType>(p), i),
        LinearOnEdge(i, where[p].a, where[p].b, where[p].t), 1e-12)
        << "edge " << where[p].a << "-" << where[p].b << " at t = " << where[p].t << ", corner "
        << i;
    EXPECT_EQ(
      out->GetPointData()->GetArray("CageLocation")->GetComponent(static_cast<vtkIdType>(p), 0),
      2.0);
  }
}

TEST(vtkBaryCoordinatesVTKReference, CubeEdgeMidpointVTKIsRightThere)
{
  // (0, -1, -1): midpoint of the cube edge 0-1, where the faces {0,2,1} and {0,1,5} meet at a
  // right angle. BaryLab gives 1/2, 1/2, 0 (checked in ExactOnEveryCubeEdge). VTK 9.1 turned out
  // to be right here too (measured error ~3e-17: it finds the point on the first face it
  // visits and interpolates there), so no assertion on VTK is made for this edge.
  auto cube = MakeCube();
  auto out = BaryLabWeights(MakePointCloud({ { 0.0, -1.0, -1.0 } }), cube);
  vtkDataArray* W = GetWeights(out);
  ASSERT_NE(W, nullptr);
  for (int i = 0; i < 8; ++i)
    EXPECT_NEAR(W->GetComponent(0, i), LinearOnEdge(i, 0, 1, 0.5), 1e-12) << "corner " << i;
  RecordProperty("vtk_error_on_cube_edge", std::to_string(VTKErrorOnEdge(cube, 0, 1, 0.5)));
}

TEST(vtkBaryCoordinatesVTKReference, FlatEdgeMidpointIsExactInBaryLabButNotInVTK)
{
  // (0, 0, -1): midpoint of the diagonal 0-2 of the side z = -1, the edge shared by the two
  // coplanar triangles {0,3,2} and {0,2,1}. This is the VTK 9.1 bug noted in the platform
  // notes: its weights there are wrong by about 0.34 (measured; the same on every face diagonal
  // of the cube, while the cube's own edges, where the faces meet at an angle, come out right).
  auto cube = MakeCube();
  auto out = BaryLabWeights(MakePointCloud({ { 0.0, 0.0, -1.0 } }), cube);
  vtkDataArray* W = GetWeights(out);
  ASSERT_NE(W, nullptr);
  for (int i = 0; i < 8; ++i)
    EXPECT_NEAR(W->GetComponent(0, i), LinearOnEdge(i, 0, 2, 0.5), 1e-12) << "corner " << i;
  const double vtkError = VTKErrorOnEdge(cube, 0, 2, 0.5);
  RecordProperty("vtk_error_on_flat_edge", std::to_string(vtkError));
  // If a future VTK fixes this, drop this assertion.
  EXPECT_GT(vtkError, 1e-3) << "VTK's mean value coordinates are now right on a flat cage edge";
}

} // namespace
