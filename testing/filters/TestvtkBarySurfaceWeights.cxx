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

// A decal (§4.2): anchors at the corners of a square with texture coordinates that are an
// affine function of their positions; on a plane the weights reproduce positions, so the
// texture coordinates are that affine function of every defined point, exactly.
TEST(vtkBarySurfaceWeights, DecalTextureCoordinatesOnAPlane)
{
  auto square = FlatSquare(10);
  EmbedAsIs(square, 5);
  auto anchors = MakePointCloud({ { -0.5, -0.5, 0 }, { 0.5, -0.5, 0 }, { 0.5, 0.5, 0 }, { -0.5, 0.5, 0 } });
  vtkNew<vtkDoubleArray> uv;
  uv->SetNumberOfComponents(2);
  const double corners[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
  for (const auto& c : corners)
    uv->InsertNextTuple(c);
  vtkNew<vtkBarySurfaceWeights> filter;
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  filter->SetInputData(0, square);
  filter->SetSurfaceData(square);
  filter->SetAnchorsData(anchors);
  filter->SetAnchorTextureCoordinates(uv);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  auto* out = vtkPointSet::SafeDownCast(filter->GetOutputDataObject(0));
  vtkDataArray* t = out->GetPointData()->GetTCoords();
  ASSERT_NE(t, nullptr);
  EXPECT_STREQ(t->GetName(), "TCoords");
  vtkDataArray* defined = out->GetPointData()->GetArray("Defined");
  int count = 0;
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
  {
    if (defined->GetComponent(p, 0) == 0)
    {
      EXPECT_TRUE(std::isnan(t->GetComponent(p, 0)));
      continue;
    }
    ++count;
    const double* x = out->GetPoint(p);
    EXPECT_NEAR(t->GetComponent(p, 0), x[0] + 0.5, 1e-10);
    EXPECT_NEAR(t->GetComponent(p, 1), x[1] + 0.5, 1e-10);
  }
  EXPECT_EQ(count, out->GetNumberOfPoints()); // a plane: every point is an affine combination
  // One pair of texture coordinates too few is named.
  uv->SetNumberOfTuples(3);
  uv->Modified();
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("3 tuples of 2 components; 4 tuples of 2")) << observer->AllErrors();
}
