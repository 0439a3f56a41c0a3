// Tests of vtkBaryReduceWeights: the compact arrays equal core's bary::reduce_weights, K and the
// memory fraction, partition of unity exact with the row sum, reproduction exact with the affine
// correction, KeepDenseArray and field data, and errors.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBaryReduceWeights.h"

#include "core/analysis/locality_statistics.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
using namespace barylab_test;

/// 9 controls on a 3 x 3 grid of [0, 1]^2 (z = 0.25) and an n x n grid of points with smooth,
/// fairly local, normalised weights (no linear precision).
struct Case
{
  vtkSmartPointer<vtkPolyData> Points, Cage;
  bary::DenseWeights W;
  Eigen::MatrixXd X, C;
  explicit Case(int n)
  {
    std::vector<std::array<double, 3>> xs, cs;
    for (int c = 0; c < 9; ++c)
      cs.push_back({ (c % 3) / 2.0, (c / 3) / 2.0, 0.25 });
    C.resize(9, 2);
    for (int c = 0; c < 9; ++c)
      C.row(c) << cs[c][0], cs[c][1];
    W.resize(n * n, 9);
    X.resize(n * n, 2);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double x = i / (n - 1.0), y = j / (n - 1.0);
        xs.push_back({ x, y, 0.25 });
        X.row(j * n + i) << x, y;
        for (int c = 0; c < 9; ++c)
          W(j * n + i, c) =
            std::exp(-((x - C(c, 0)) * (x - C(c, 0)) + (y - C(c, 1)) * (y - C(c, 1))) / 0.05);
        W.row(j * n + i) /= W.row(j * n + i).sum();
      }
    Points = MakePointCloud(xs);
    Cage = MakePointCloud(cs);
    vtkNew<vtkDoubleArray> a;
    a->SetName("Weights");
    a->SetNumberOfComponents(9);
    a->SetNumberOfTuples(n * n);
    for (int p = 0; p < n * n; ++p)
      for (int c = 0; c < 9; ++c)
        a->SetComponent(p, c, W(p, c));
    Points->GetPointData()->AddArray(a);
  }
};

struct Reduce
{
  vtkNew<vtkBaryReduceWeights> Filter;
  vtkNew<ErrorObserver> Observer;
  explicit Reduce(vtkDataObject* input, vtkPolyData* cage = nullptr)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->SetInputData(input);
    if (cage)
      this->Filter->SetCageData(cage);
  }
  int Run() { return RunPipeline(this->Filter); }
  vtkDataSet* Output() { return vtkDataSet::SafeDownCast(this->Filter->GetOutputDataObject(0)); }
};

TEST(vtkBaryReduceWeights, CompactArraysEqualCoreRowSum)
{
  Case c(15);
  Reduce r(c.Points, c.Cage);
  r.Filter->SetThreshold(0.01);
  ASSERT_EQ(r.Run(), 1) << r.Observer->AllErrors();
  const bary::ReducedWeights ref =
    bary::reduce_weights(c.W, 0.01, bary::Renormalization::RowSum, &c.C, &c.X);
  // K = the largest number of weights > threshold at one point
  int K = 0;
  for (Eigen::Index p = 0; p < c.W.rows(); ++p)
    K = std::max(K, static_cast<int>((c.W.row(p).array() > 0.01).count()));
  EXPECT_EQ(r.Filter->GetMaximumSupport(), K);
  EXPECT_LT(K, 9);
  EXPECT_DOUBLE_EQ(r.Filter->GetMemoryFraction(), 12.0 * K / (8.0 * 9));
  EXPECT_DOUBLE_EQ(r.Filter->GetCSRMemoryFraction(), ref.memory_fraction);
  EXPECT_EQ(r.Filter->GetNumberOfNonzeros(), ref.nonzeros);
  EXPECT_DOUBLE_EQ(r.Filter->GetThresholdUsed(), 0.01);
  EXPECT_EQ(r.Filter->GetPartitionError(), ref.partition_error);
  EXPECT_LT(r.Filter->GetPartitionError(), 1e-14); // row sum: exact to rounding
  EXPECT_EQ(r.Filter->GetReproductionError(), ref.reproduction_error);
  EXPECT_EQ(r.Filter->GetMaxDropped(), ref.max_dropped);
  EXPECT_GT(r.Filter->GetMaxDropped(), 0.0);

  vtkDataSet* out = r.Output();
  EXPECT_EQ(out->GetPointData()->GetArray("Weights"), nullptr); // replaced
  auto* indices = vtkIntArray::SafeDownCast(out->GetPointData()->GetArray("WeightsIndices"));
  auto* values = vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("WeightsValues"));
  ASSERT_NE(indices, nullptr);
  ASSERT_NE(values, nullptr);
  ASSERT_EQ(indices->GetNumberOfComponents(), K);
  ASSERT_EQ(values->GetNumberOfComponents(), K);
  const bary::SparseWeights back = vtkBaryConversion::FromCompactArrays(indices, values, 9);
  EXPECT_EQ((bary::DenseWeights(back) - bary::DenseWeights(ref.W)).cwiseAbs().maxCoeff(), 0.0);
  for (vtkIdType p = 0; p < indices->GetNumberOfTuples(); ++p)
  {
    int previous = -1;
    for (int k = 0; k < K; ++k)
    {
      const int id = indices->GetTypedComponent(p, k);
      if (id == -1)
        EXPECT_EQ(values->GetTypedComponent(p, k), 0.0); // padding
      else
      {
        EXPECT_GT(id, previous); // increasing, padding at the end
        previous = id;
      }
    }
  }
  vtkDataArray* count = out->GetFieldData()->GetArray("WeightsNumberOfControlPoints");
  ASSERT_NE(count, nullptr);
  EXPECT_EQ(count->GetComponent(0, 0), 9.0);
  ASSERT_NE(out->GetFieldData()->GetArray("WeightsThreshold"), nullptr);
  // the input is untouched
  EXPECT_NE(c.Points->GetPointData()->GetArray("Weights"), nullptr);
}

TEST(vtkBaryReduceWeights, AffineReproducesAndNoneKeepsValues)
{
  Case c(15);
  // 1e-3 keeps at least 3 non-collinear controls at every point (at 0.01 corner points keep
  // fewer and fall back to the row sum, as documented)
  Reduce r(c.Points, c.Cage);
  r.Filter->SetThreshold(1e-3);
  r.Filter->SetRenormalizationToAffine();
  ASSERT_EQ(r.Run(), 1) << r.Observer->AllErrors();
  EXPECT_LT(r.Filter->GetPartitionError(), 1e-12);
  EXPECT_LT(r.Filter->GetReproductionError(), 1e-12); // relative to the controls' diameter
  // the same rows with the row sum do not reproduce (these weights have no linear precision)
  Reduce rs(c.Points, c.Cage);
  rs.Filter->SetThreshold(1e-3);
  ASSERT_EQ(rs.Run(), 1) << rs.Observer->AllErrors();
  EXPECT_GT(rs.Filter->GetReproductionError(), 1e-6);

  Reduce none(c.Points);
  none.Filter->SetThreshold(0.01);
  none.Filter->SetRenormalization(vtkBaryReduceWeights::RENORMALIZE_NONE);
  none.Filter->KeepDenseArrayOn();
  ASSERT_EQ(none.Run(), 1) << none.Observer->AllErrors();
  EXPECT_TRUE(std::isnan(none.Filter->GetReproductionError())); // no cage
  EXPECT_NEAR(none.Filter->GetPartitionError(), none.Filter->GetMaxDropped(), 1e-15);
  EXPECT_NE(none.Output()->GetPointData()->GetArray("Weights"), nullptr); // kept
  auto* values = vtkDoubleArray::SafeDownCast(none.Output()->GetPointData()->GetArray("WeightsValues"));
  auto* indices = vtkIntArray::SafeDownCast(none.Output()->GetPointData()->GetArray("WeightsIndices"));
  ASSERT_NE(values, nullptr);
  for (vtkIdType p = 0; p < values->GetNumberOfTuples(); ++p)
    for (int k = 0; k < values->GetNumberOfComponents(); ++k)
      if (indices->GetTypedComponent(p, k) >= 0)
      {
        EXPECT_EQ(values->GetTypedComponent(p, k), c.W(p, indices->GetTypedComponent(p, k)));
      }
}

TEST(vtkBaryReduceWeights, DefaultThresholdAndGlobalWeights)
{
  // threshold 1e-3 / 9; rows with all 9 weights above it: K = 9 and the compact form is larger
  Case c(5);
  Reduce r(c.Points);
  ASSERT_EQ(r.Run(), 1) << r.Observer->AllErrors();
  EXPECT_DOUBLE_EQ(r.Filter->GetThresholdUsed(), 1e-3 / 9);
  const bary::ReducedWeights ref = bary::reduce_weights(c.W, -1.0);
  int K = 0;
  for (Eigen::Index p = 0; p < ref.W.rows(); ++p)
    K = std::max(K, static_cast<int>(ref.W.row(p).nonZeros()));
  EXPECT_EQ(r.Filter->GetMaximumSupport(), K);
}

TEST(vtkBaryReduceWeights, Errors)
{
  Case c(5);
  {
    Reduce r(c.Points);
    r.Filter->SetWeightsArrayName("Nope");
    EXPECT_EQ(r.Run(), 0);
    EXPECT_TRUE(r.Observer->HasError("no point-data array 'Nope'")) << r.Observer->AllErrors();
  }
  {
    Reduce r(c.Points);
    r.Filter->SetRenormalizationToAffine();
    EXPECT_EQ(r.Run(), 0);
    EXPECT_TRUE(r.Observer->HasError("affine renormalisation needs the control points"))
      << r.Observer->AllErrors();
  }
  {
    auto cage = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } });
    Reduce r(c.Points, cage);
    EXPECT_EQ(r.Run(), 0);
    EXPECT_TRUE(r.Observer->HasError("the cage has 3 points")) << r.Observer->AllErrors();
  }
  {
    Reduce r(c.Points);
    r.Filter->SetThreshold(0.0);
    EXPECT_EQ(r.Run(), 0);
    EXPECT_FALSE(r.Observer->Errors.empty());
  }
  {
    vtkNew<vtkPolyData> empty;
    Reduce r(empty);
    EXPECT_EQ(r.Run(), 0);
    EXPECT_TRUE(r.Observer->HasError("no points")) << r.Observer->AllErrors();
  }
  {
    Case bad(3);
    vtkDataArray* w = bad.Points->GetPointData()->GetArray("Weights");
    w->SetComponent(4, 2, std::nan(""));
    Reduce r(bad.Points);
    EXPECT_EQ(r.Run(), 0);
    EXPECT_EQ(vtkBaryConversion::ErrorCodeOf(r.Filter->GetErrorCode(), bary::ErrorCode::Internal),
      bary::ErrorCode::NonFinite) << r.Observer->AllErrors();
  }
}
} // namespace
