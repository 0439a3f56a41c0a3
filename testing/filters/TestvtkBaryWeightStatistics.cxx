// vtkBaryWeightStatistics: a hand-computed case (partition and reproduction errors, range,
// negative entries, the significant-weights histogram), the same figures as the core function,
// and the errors (missing array listing the arrays present, cage of the wrong size, no points).

#include "vtkBaryWeightStatistics.h"
#include "vtkBaryConversion.h"

#include "filters_test_utils.h"

#include "core/analysis/weight_statistics.h"

#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkVariant.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace barylab_test;

namespace
{
vtkSmartPointer<vtkPolyData> UnitSquare()
{
  return MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } });
}

/// Three points with weights w.r.t. the unit square's corners (component i = corner i).
vtkSmartPointer<vtkPolyData> Weighted()
{
  auto data = MakePointCloud({ { 0.5, 0.5, 0 }, { 0.5, 0, 0 }, { 0, 0, 0 } });
  vtkNew<vtkDoubleArray> w;
  w->SetName("Weights");
  w->SetNumberOfComponents(4);
  const double rows[3][4] = {
    { 0.25, 0.25, 0.25, 0.25 }, // exact bilinear weights at the centre
    { 0.5, 0.5, 0.0, 0.0 },     // exact on the edge (0,0)-(1,0)
    { 1.0, 0.0, -0.2, 0.3 },    // sum 1.1; reproduces (-0.2 + 0, -0.2 + 0.3) = (-0.2, 0.1)
  };
  for (const auto& row : rows)
    w->InsertNextTuple(row);
  data->GetPointData()->AddArray(w);
  return data;
}

double Figure(vtkBaryWeightStatistics* f, const char* name)
{
  vtkAbstractArray* column = f->GetOutput(0)->GetColumnByName(name);
  return column ? column->GetVariantValue(0).ToDouble() : std::nan("");
}
} // namespace

TEST(vtkBaryWeightStatistics, HandComputedFigures)
{
  vtkNew<vtkBaryWeightStatistics> f;
  f->SetInputData(0, Weighted());
  f->SetCageData(UnitSquare());
  ASSERT_EQ(RunPipeline(f), 1);
  EXPECT_EQ(Figure(f, "points"), 3);
  EXPECT_EQ(Figure(f, "controls"), 4);
  EXPECT_DOUBLE_EQ(Figure(f, "threshold"), 1e-3 / 4);
  EXPECT_DOUBLE_EQ(Figure(f, "min_weight"), -0.2);
  EXPECT_DOUBLE_EQ(Figure(f, "max_weight"), 1.0);
  EXPECT_EQ(Figure(f, "negative_weights"), 1);
  EXPECT_EQ(Figure(f, "non_finite_rows"), 0);
  EXPECT_NEAR(Figure(f, "max_partition_error"), 0.1, 1e-15);
  EXPECT_NEAR(Figure(f, "mean_partition_error"), 0.1 / 3, 1e-15);
  // |(-0.2, 0.1) - (0, 0)| / sqrt(2), the square's diagonal
  EXPECT_NEAR(Figure(f, "max_reproduction_error"), std::sqrt(0.05) / std::sqrt(2.0), 1e-15);
  // significant (> 2.5e-4) per point: 4, 2, 2 (the negative one is not)
  EXPECT_NEAR(Figure(f, "mean_significant"), 8.0 / 3, 1e-15);
  EXPECT_EQ(Figure(f, "max_significant"), 4);
  vtkTable* histogram = f->GetOutput(1);
  ASSERT_EQ(histogram->GetNumberOfRows(), 5);
  const long long expected[5] = { 0, 0, 2, 0, 1 };
  for (vtkIdType k = 0; k < 5; ++k)
  {
    EXPECT_EQ(histogram->GetColumnByName("k")->GetVariantValue(k).ToInt(), k);
    EXPECT_EQ(histogram->GetColumnByName("points")->GetVariantValue(k).ToLongLong(), expected[k]);
  }
}

TEST(vtkBaryWeightStatistics, EqualsTheCoreWithoutACageAndWithAThreshold)
{
  vtkNew<vtkBaryWeightStatistics> f;
  auto data = Weighted();
  f->SetInputData(0, data);
  f->SetThreshold(0.3);
  ASSERT_EQ(RunPipeline(f), 1);
  bary::WeightStatisticsOptions options;
  options.threshold = 0.3;
  const bary::WeightStatistics s = bary::weight_statistics(
    vtkBaryConversion::ArrayToMatrix(GetWeights(data)), nullptr, nullptr, options);
  EXPECT_EQ(f->GetOutput(0)->GetColumnByName("max_reproduction_error"), nullptr);
  EXPECT_EQ(Figure(f, "threshold"), 0.3);
  EXPECT_EQ(Figure(f, "mean_significant"), s.mean_significant);
  EXPECT_EQ(Figure(f, "max_partition_error"), s.max_partition_error);
  EXPECT_EQ(Figure(f, "max_significant"), s.max_significant);
}

TEST(vtkBaryWeightStatistics, Errors)
{
  vtkNew<vtkBaryWeightStatistics> f;
  vtkNew<ErrorObserver> observer;
  observer->Attach(f);
  f->SetInputData(0, Weighted());
  f->SetWeightsArrayName("Nope");
  EXPECT_EQ(RunPipeline(f), 0);
  EXPECT_TRUE(observer->HasError("no point-data array 'Nope' (arrays present: Weights)"))
    << observer->AllErrors();
  observer->Clear();
  // a text array of the right name: it said "no array 'Weights' (arrays present: Weights)"
  {
    vtkSmartPointer<vtkPolyData> text = Weighted();
    text->GetPointData()->RemoveArray("Weights");
    vtkNew<vtkStringArray> names;
    names->SetName("Weights");
    names->SetNumberOfValues(text->GetNumberOfPoints());
    text->GetPointData()->AddArray(names);
    f->SetInputData(0, text);
    f->SetWeightsArrayName("Weights");
    EXPECT_EQ(RunPipeline(f), 0);
    EXPECT_TRUE(observer->HasError("the point-data array 'Weights' holds text, not numbers"))
      << observer->AllErrors();
    observer->Clear();
    f->SetInputData(0, Weighted());
  }
  f->SetWeightsArrayName("Weights");
  f->SetCageData(MakeCube());
  EXPECT_EQ(RunPipeline(f), 0);
  EXPECT_TRUE(observer->HasError("has 4 components but the cage has 8 points"))
    << observer->AllErrors();
}
