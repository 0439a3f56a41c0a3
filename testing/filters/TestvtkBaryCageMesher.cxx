// vtkBaryCageMesher, and the mesh-based HARMONIC method of vtkBaryCoordinates.
#include "filters_test_utils.h"

#include "vtkBaryCageMesher.h"
#include "vtkBaryCoordinates.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace barylab_test;

namespace
{
/// The unit square as a 2D cage: bare points in order (the .obj habit), z = 0.25.
vtkSmartPointer<vtkPolyData> Square()
{
  return MakePointCloud({ { 0, 0, 0.25 }, { 1, 0, 0.25 }, { 1, 1, 0.25 }, { 0, 1, 0.25 } });
}

double CellMeasure(vtkUnstructuredGrid* grid, vtkIdType c)
{
  vtkIdType n;
  const vtkIdType* ids;
  grid->GetCellPoints(c, n, ids);
  double p[4][3];
  for (vtkIdType k = 0; k < n; ++k)
    grid->GetPoint(ids[k], p[k]);
  double a[3], b[3], d[3];
  for (int k = 0; k < 3; ++k)
  {
    a[k] = p[1][k] - p[0][k];
    b[k] = p[2][k] - p[0][k];
    d[k] = n == 4 ? p[3][k] - p[0][k] : 0.0;
  }
  const double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2],
               cz = a[0] * b[1] - a[1] * b[0];
  if (n == 3)
    return 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
  return std::abs(cx * d[0] + cy * d[1] + cz * d[2]) / 6.0;
}
} // namespace

TEST(vtkBaryCageMesher, Square2DFillsTheCageInItsPlane)
{
  vtkNew<vtkBaryCageMesher> mesher;
  mesher->SetCageData(Square());
  mesher->SetTargetNumberOfCells(500);
  vtkNew<ErrorObserver> observer;
  observer->Attach(mesher);
  ASSERT_EQ(RunPipeline(mesher), 1) << observer->AllErrors();
  vtkUnstructuredGrid* grid = mesher->GetOutput();
  ASSERT_GT(grid->GetNumberOfCells(), 400);
  double area = 0.0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(grid->GetCellType(c), VTK_TRIANGLE);
    area += CellMeasure(grid, c);
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
  double bounds[6];
  grid->GetBounds(bounds);
  EXPECT_EQ(bounds[4], 0.25);
  EXPECT_EQ(bounds[5], 0.25) << "2D meshes lie in the cage's plane";
  vtkDataArray* ids = grid->GetPointData()->GetArray("ControlPointId");
  ASSERT_NE(ids, nullptr);
  int corners = 0;
  for (vtkIdType v = 0; v < grid->GetNumberOfPoints(); ++v)
    corners += ids->GetTuple1(v) >= 0;
  EXPECT_EQ(corners, 4);
}

TEST(vtkBaryCageMesher, Cube3DVolumeAndInsertedPoints)
{
  vtkNew<vtkBaryCageMesher> mesher;
  mesher->SetCageData(MakeCube());
  mesher->SetMaximumCellSize(0.01);
  mesher->SetPointsData(MakePointCloud({ { 0.1, 0.2, 0.3 }, { 5, 5, 5 } }));
  vtkNew<ErrorObserver> observer;
  observer->Attach(mesher);
  ASSERT_EQ(RunPipeline(mesher), 1) << observer->AllErrors();
  vtkUnstructuredGrid* grid = mesher->GetOutput();
  double volume = 0.0, largest = 0.0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(grid->GetCellType(c), VTK_TETRA);
    const double v = CellMeasure(grid, c);
    volume += v;
    largest = std::max(largest, v);
  }
  EXPECT_NEAR(volume, 8.0, 1e-10);
  EXPECT_LE(largest, 0.01 * (1 + 1e-9));
  EXPECT_EQ(mesher->GetNumberOfSkippedPoints(), 1) << "the point (5,5,5) is outside";
  EXPECT_TRUE(observer->HasWarning("outside")) << observer->AllWarnings();
  bool inserted = false;
  for (vtkIdType v = 0; v < grid->GetNumberOfPoints(); ++v)
  {
    double x[3];
    grid->GetPoint(v, x);
    inserted = inserted || (x[0] == 0.1 && x[1] == 0.2 && x[2] == 0.3);
  }
  EXPECT_TRUE(inserted);
}

TEST(vtkBaryCageMesher, OpenCageIsReported)
{
  auto cube = MakeCube();
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 1; c < 12; ++c) // drop face 0
  {
    vtkIdType n;
    const vtkIdType* ids;
    cube->GetPolys()->GetCellAtId(c, n, ids);
    polys->InsertNextCell(n, ids);
  }
  cube->SetPolys(polys);
  vtkNew<vtkBaryCageMesher> mesher;
  mesher->SetCageData(cube);
  vtkNew<ErrorObserver> observer;
  observer->Attach(mesher);
  EXPECT_EQ(RunPipeline(mesher), 0);
  EXPECT_TRUE(observer->HasError("not closed")) << observer->AllErrors();
}

TEST(vtkBaryCoordinatesHarmonic, SquareIsBilinear)
{
  // Harmonic coordinates of a square are the bilinear functions (an independent analytic
  // reference); P1 elements on 3000 triangles are within a few 1e-4 of them.
  vtkNew<vtkBaryCoordinates> filter;
  filter->GetWeightMethod()->SetMethodToHarmonic();
  filter->SetInputData(0, MakePointCloud({ { 0.3, 0.6, 0.25 }, { 0.9, 0.1, 0.25 }, { 0.5, 0.5, 0.25 } }));
  filter->SetCageData(Square());
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  vtkDataArray* w = GetWeights(vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0)));
  ASSERT_NE(w, nullptr);
  ASSERT_EQ(w->GetNumberOfComponents(), 4);
  const double pts[3][2] = { { 0.3, 0.6 }, { 0.9, 0.1 }, { 0.5, 0.5 } };
  for (int p = 0; p < 3; ++p)
  {
    const double x = pts[p][0], y = pts[p][1];
    const double exact[4] = { (1 - x) * (1 - y), x * (1 - y), x * y, (1 - x) * y };
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(w->GetComponent(p, i), exact[i], 1e-3) << "point " << p << " corner " << i;
  }
}

TEST(vtkBaryCoordinatesHarmonic, OutsidePointsFollowThePolicy)
{
  vtkNew<vtkBaryCoordinates> filter;
  filter->GetWeightMethod()->SetMethodToHarmonic();
  filter->GetWeightMethod()->SetTargetNumberOfCells(300);
  filter->SetInputData(0, MakePointCloud({ { 0.5, 0.5, 0.25 }, { 2, 0.5, 0.25 } }));
  filter->SetCageData(Square());
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("outside")) << observer->AllErrors();
  observer->Clear();
  filter->GetWeightMethod()->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NAN);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  EXPECT_EQ(filter->GetNumberOfOutsidePoints(), 1);
  EXPECT_EQ(filter->GetNumberOfUndefinedPoints(), 1);
  EXPECT_TRUE(std::isnan(GetWeights(vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0)))->GetComponent(1, 0)));
  filter->GetWeightMethod()->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NEAREST);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  // nearest point of (2, 0.5) is (1, 0.5): corners 1 and 2 at one half
  EXPECT_NEAR(GetWeights(vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0)))->GetComponent(1, 1), 0.5, 1e-12);
  EXPECT_NEAR(GetWeights(vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0)))->GetComponent(1, 2), 0.5, 1e-12);
}
