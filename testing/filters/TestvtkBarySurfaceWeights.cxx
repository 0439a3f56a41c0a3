// vtkBarySurfaceWeights: the inverse problem through the filter, with the round trip.
#include "vtkBarySurfaceWeights.h"

#include "filters_test_utils.h"
#include "surface_test_utils.h"

#include "vtkBaryConversion.h"

#include "vtkUnsignedCharArray.h"

using namespace barylab_test;

TEST(vtkBarySurfaceWeights, FlatSquareWeightsReproduceThePoints)
{
  auto square = FlatSquare(10);
  EmbedAsIs(square, 5);
  auto anchors = MakePointCloud({ { -0.7, -0.7, 0 }, { 0.7, -0.6, 0 }, { 0.6, 0.7, 0 }, { -0.6, 0.6, 0 }, { 0, 0, 0 } });
  vtkNew<vtkBarySurfaceWeights> filter;
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  filter->SetInputData(0, square); // weights at every vertex
  filter->SetSurfaceData(square);
  filter->SetAnchorsData(anchors);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  auto* out = vtkPointSet::SafeDownCast(filter->GetOutputDataObject(0));
  const Eigen::MatrixXd W = vtkBaryConversion::ArrayToMatrix(out->GetPointData()->GetArray("Weights"));
  const Eigen::MatrixXd A = vtkBaryConversion::ToMatrix(anchors->GetPoints(), 3);
  const Eigen::MatrixXd X = vtkBaryConversion::ToMatrix(square->GetPoints(), 3);
  ASSERT_EQ(W.rows(), square->GetNumberOfPoints());
  ASSERT_EQ(W.cols(), 5);
  // On a plane the tangential constraint is the whole of reproduction: sum w_i a_i = x.
  EXPECT_LT((W * A - X).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  auto* defined = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Defined"));
  ASSERT_NE(defined, nullptr);
  EXPECT_EQ(filter->GetNumberOfUndefined(), 0);
  EXPECT_LT(filter->GetMaximumRoundTripError(), 1e-10);
  EXPECT_NE(out->GetPointData()->GetArray("RoundTripError"), nullptr);

  // At the anchors the weights interpolate.
  vtkNew<vtkBarySurfaceWeights> at;
  at->SetInputData(0, anchors);
  at->SetSurfaceData(square);
  at->SetAnchorsData(anchors);
  ASSERT_EQ(RunPipeline(at), 1);
  const Eigen::MatrixXd I = vtkBaryConversion::ArrayToMatrix(
    vtkPointSet::SafeDownCast(at->GetOutputDataObject(0))->GetPointData()->GetArray("Weights"));
  EXPECT_LT((I - Eigen::MatrixXd::Identity(5, 5)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(vtkBarySurfaceWeights, BadInputIsNamed)
{
  auto square = FlatSquare(6);
  EmbedAsIs(square);
  auto anchors = MakePointCloud({ { -0.5, 0, 0 }, { 0.5, 0, 0 }, { 0, 0.5, 0 } });
  auto off = MakePointCloud({ { 0, 0, 0 }, { 0.2, 0.1, 3.0 } });
  vtkNew<vtkBarySurfaceWeights> filter;
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  filter->SetInputData(0, off);
  filter->SetSurfaceData(square);
  filter->SetAnchorsData(anchors);
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("point 1")) << observer->AllErrors();
  filter->SetInputData(0, anchors);
  filter->SetGamma(0.1);
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("gamma must be in [1, 1e6]")) << observer->AllErrors();
}
