// vtkBarySurfaceCurve: a B-spline on a surface through forward problems; on a flat square it
// is the planar B-spline of the control points.
#include "vtkBarySurfaceCurve.h"

#include "filters_test_utils.h"
#include "surface_test_utils.h"

#include "vtkBaryConversion.h"

#include "core/surface/surface_curves.h"

using namespace barylab_test;

TEST(vtkBarySurfaceCurve, FlatSquareGivesThePlanarBSpline)
{
  auto square = FlatSquare(12);
  EmbedAsIs(square, 5);
  auto controls = MakePointCloud(
    { { -0.7, -0.7, 0 }, { 0.6, -0.7, 0 }, { 0.7, 0.6, 0 }, { -0.1, 0.8, 0 }, { -0.6, 0.2, 0 } });
  for (const bool closed : { false, true })
  {
    vtkNew<vtkBarySurfaceCurve> curve;
    vtkNew<ErrorObserver> observer;
    observer->Attach(curve);
    curve->SetInputData(0, square);
    curve->SetControlPointsData(controls);
    curve->SetSamplesPerSegment(10);
    curve->SetClosed(closed);
    ASSERT_EQ(RunPipeline(curve), 1) << observer->AllErrors();
    vtkPolyData* out = curve->GetOutput();
    const bary::DenseWeights W = bary::bspline_weights(5, 10, closed);
    ASSERT_EQ(out->GetNumberOfPoints(), W.rows());
    EXPECT_EQ(out->GetNumberOfLines(), 1);
    EXPECT_EQ(curve->GetNumberOfFailures(), 0);
    const Eigen::MatrixXd X = vtkBaryConversion::ToMatrix(out->GetPoints(), 3);
    const Eigen::MatrixXd C = vtkBaryConversion::ToMatrix(controls->GetPoints(), 3);
    EXPECT_LT((X - W * C).cwiseAbs().maxCoeff(), 1e-12);
    // A closed curve's polyline returns to its first point.
    EXPECT_EQ(out->GetLines()->GetNumberOfConnectivityIds(), W.rows() + (closed ? 1 : 0));
  }
}

TEST(vtkBarySurfaceCurve, TooFewControlPointsAreNamed)
{
  auto square = FlatSquare(4);
  EmbedAsIs(square);
  auto controls = MakePointCloud({ { -0.5, 0, 0 }, { 0.5, 0, 0 }, { 0, 0.5, 0 } });
  vtkNew<vtkBarySurfaceCurve> curve;
  vtkNew<ErrorObserver> observer;
  observer->Attach(curve);
  curve->SetInputData(0, square);
  curve->SetControlPointsData(controls);
  EXPECT_EQ(RunPipeline(curve), 0);
  EXPECT_TRUE(observer->HasError("at least 4 control points")) << observer->AllErrors();
}
