// vtkBarySurfaceRemesh: a coarse quad layout on a flat square subdivided by forward problems
// is the regular grid; polygons other than quads are named.
#include "vtkBarySurfaceRemesh.h"

#include "filters_test_utils.h"
#include "surface_test_utils.h"

#include "vtkBaryConversion.h"

using namespace barylab_test;

namespace
{

vtkSmartPointer<vtkPolyData> CoarseQuads(int corners)
{
  auto coarse = MakePointCloud({ { -0.8, -0.8, 0 }, { 0.8, -0.8, 0 }, { 0.8, 0.8, 0 }, { -0.8, 0.8, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(corners, ids);
  coarse->SetPolys(polys);
  return coarse;
}

} // namespace

TEST(vtkBarySurfaceRemesh, OneQuadOnASquareBecomesTheRegularGrid)
{
  auto square = FlatSquare(8);
  EmbedAsIs(square, 5);
  vtkNew<vtkBarySurfaceRemesh> remesh;
  vtkNew<ErrorObserver> observer;
  observer->Attach(remesh);
  remesh->SetInputData(0, square);
  remesh->SetCoarseMeshData(CoarseQuads(4));
  remesh->SetLevels(3);
  ASSERT_EQ(RunPipeline(remesh), 1) << observer->AllErrors();
  vtkPolyData* out = remesh->GetOutput();
  EXPECT_EQ(out->GetNumberOfPolys(), 64);
  EXPECT_EQ(out->GetNumberOfPoints(), 81);
  EXPECT_EQ(remesh->GetNumberOfFailures(), 0);
  const Eigen::MatrixXd X = vtkBaryConversion::ToMatrix(out->GetPoints(), 3);
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    for (int c = 0; c < 2; ++c)
    {
      const double k = (X(v, c) + 0.8) / 0.2; // nodes of spacing 0.2
      EXPECT_NEAR(k, std::round(k), 1e-10);
    }
  for (const char* name : { "FaceId", "Barycentric", "Valid" })
    EXPECT_NE(out->GetPointData()->GetArray(name), nullptr) << name;
}

TEST(vtkBarySurfaceRemesh, TrianglesAreNotAQuadLayout)
{
  auto square = FlatSquare(4);
  EmbedAsIs(square);
  vtkNew<vtkBarySurfaceRemesh> remesh;
  vtkNew<ErrorObserver> observer;
  observer->Attach(remesh);
  remesh->SetInputData(0, square);
  remesh->SetCoarseMeshData(CoarseQuads(3));
  EXPECT_EQ(RunPipeline(remesh), 0);
  EXPECT_TRUE(observer->HasError("polygon 0 of the coarse mesh has 3 points, not 4")) << observer->AllErrors();
}
