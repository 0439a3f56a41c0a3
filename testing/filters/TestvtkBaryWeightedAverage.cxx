// vtkBaryWeightedAverage: the forward problem through the filter: on a flat square the average
// is the planar affine combination; failures are flagged; bad input is named.
#include "vtkBaryWeightedAverage.h"

#include "filters_test_utils.h"
#include "surface_test_utils.h"

#include "vtkBaryConversion.h"

#include "vtkIdTypeArray.h"
#include "vtkUnsignedCharArray.h"

using namespace barylab_test;

namespace
{

vtkSmartPointer<vtkDoubleArray> WeightsArray(const Eigen::MatrixXd& W)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetNumberOfComponents(static_cast<int>(W.cols()));
  a->SetNumberOfTuples(W.rows());
  for (vtkIdType r = 0; r < W.rows(); ++r)
    for (int c = 0; c < W.cols(); ++c)
      a->SetComponent(r, c, W(r, c));
  return a;
}

struct Average
{
  vtkNew<vtkBaryWeightedAverage> Filter;
  vtkNew<ErrorObserver> Observer;
  Average(vtkPolyData* surface, vtkPolyData* anchors, const Eigen::MatrixXd& W)
  {
    this->Filter->SetInputData(0, surface);
    this->Filter->SetAnchorsData(anchors);
    this->Filter->SetWeights(WeightsArray(W));
    this->Observer->Attach(this->Filter);
  }
  int Run() { return RunPipeline(this->Filter); }
};

} // namespace

TEST(vtkBaryWeightedAverage, FlatSquareGivesTheAffineCombination)
{
  auto square = FlatSquare(12);
  EmbedAsIs(square, 5); // R^8
  auto anchors = MakePointCloud({ { -0.6, -0.6, 0 }, { 0.7, -0.5, 0 }, { 0.1, 0.8, 0 }, { -0.2, 0.1, 0 } });
  Eigen::MatrixXd A(4, 3);
  A << -0.6, -0.6, 0, 0.7, -0.5, 0, 0.1, 0.8, 0, -0.2, 0.1, 0;
  Eigen::MatrixXd W = Eigen::MatrixXd::Random(200, 4).cwiseAbs();
  W = (W.array().colwise() / W.rowwise().sum().array()).matrix();
  Average a(square, anchors, W);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();
  vtkPolyData* out = a.Filter->GetOutput();
  ASSERT_EQ(out->GetNumberOfPoints(), 200);
  EXPECT_EQ(out->GetNumberOfVerts(), 200);
  EXPECT_EQ(a.Filter->GetNumberOfFailures(), 0);
  const Eigen::MatrixXd X = vtkBaryConversion::ToMatrix(out->GetPoints(), 3);
  EXPECT_LT((X - W * A).cwiseAbs().maxCoeff(), 1e-12);
  // FaceId and Barycentric locate the same points on the input's cells.
  auto* face = vtkIdTypeArray::SafeDownCast(out->GetPointData()->GetArray("FaceId"));
  vtkDataArray* bary = out->GetPointData()->GetArray("Barycentric");
  auto* valid = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Valid"));
  ASSERT_TRUE(face && bary && valid);
  for (vtkIdType q = 0; q < 200; ++q)
  {
    EXPECT_EQ(valid->GetValue(q), 1);
    vtkCell* cell = square->GetCell(face->GetValue(q));
    double p[3] = { 0, 0, 0 };
    for (int k = 0; k < 3; ++k)
    {
      double v[3];
      square->GetPoint(cell->GetPointId(k), v);
      for (int d = 0; d < 3; ++d)
        p[d] += bary->GetComponent(q, k) * v[d];
    }
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(p[d], X(q, d), 1e-12);
  }
  // New weights re-run the queries.
  a.Filter->SetWeights(WeightsArray(W.topRows(3)));
  ASSERT_EQ(a.Run(), 1);
  EXPECT_EQ(a.Filter->GetOutput()->GetNumberOfPoints(), 3);
}

TEST(vtkBaryWeightedAverage, FailedQueriesAreFlaggedWithNaN)
{
  auto sphere = Sphere(16, 12);
  EmbedAsIs(sphere);
  // Antipodal anchors with equal weights average to the centre; one triangle per search.
  auto anchors = MakePointCloud({ { 0, 0, 1 }, { 0, 0, -1 } });
  Eigen::MatrixXd W(2, 2);
  W << 0.5, 0.5, 1.0, 0.0;
  Average a(sphere, anchors, W);
  a.Filter->SetMaximumTriangles(1);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();
  auto* valid = vtkUnsignedCharArray::SafeDownCast(a.Filter->GetOutput()->GetPointData()->GetArray("Valid"));
  EXPECT_EQ(valid->GetValue(1), 1);
  if (valid->GetValue(0) == 0)
  {
    double x[3];
    a.Filter->GetOutput()->GetPoint(0, x);
    EXPECT_TRUE(std::isnan(x[0]));
    EXPECT_EQ(a.Filter->GetNumberOfFailures(), 1);
    EXPECT_EQ(a.Filter->GetOutput()->GetNumberOfVerts(), 1);
  }
}

TEST(vtkBaryWeightedAverage, BadInputIsNamed)
{
  auto square = FlatSquare(6);
  auto anchors = MakePointCloud({ { -0.5, 0, 0 }, { 0.5, 0, 0 } });
  Eigen::MatrixXd W(1, 2);
  W << 0.5, 0.5;
  {
    Average a(square, anchors, W);
    EXPECT_EQ(a.Run(), 0);
    EXPECT_TRUE(a.Observer->HasError("no point array 'Embedding'")) << a.Observer->AllErrors();
    EXPECT_TRUE(a.Observer->HasError("vtkBarySurfaceEmbedding")) << a.Observer->AllErrors();
  }
  EmbedAsIs(square);
  {
    auto off = MakePointCloud({ { -0.5, 0, 0 }, { 0.5, 0, 0.5 } });
    Average a(square, off, W);
    EXPECT_EQ(a.Run(), 0);
    EXPECT_TRUE(a.Observer->HasError("anchor 1")) << a.Observer->AllErrors();
    EXPECT_TRUE(a.Observer->HasError("from the surface")) << a.Observer->AllErrors();
  }
  {
    Eigen::MatrixXd W3(1, 3);
    W3 << 0.2, 0.3, 0.5;
    Average a(square, anchors, W3);
    EXPECT_EQ(a.Run(), 0);
    EXPECT_TRUE(a.Observer->HasError("3 columns but there are 2 anchors")) << a.Observer->AllErrors();
  }
  {
    Eigen::MatrixXd Wbad(1, 2);
    Wbad << 0.5, 0.6;
    Average a(square, anchors, Wbad);
    EXPECT_EQ(a.Run(), 0);
    EXPECT_TRUE(a.Observer->HasError("sums to 1.1")) << a.Observer->AllErrors();
  }
}
