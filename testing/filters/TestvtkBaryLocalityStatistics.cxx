// Tests of vtkBaryLocalityStatistics: a hand-computed case, the tables equal core's
// bary::locality_statistics on the same data (with and without the mesh measure), which
// measure is used for 2D triangles, tetrahedra, curved surfaces and point clouds, and errors.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBaryLocalityStatistics.h"

#include "core/analysis/locality_statistics.h"

#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVariant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace
{
using namespace barylab_test;

vtkSmartPointer<vtkDoubleArray> WeightsArray(const bary::DenseWeights& W, const char* name = "Weights")
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(static_cast<int>(W.cols()));
  a->SetNumberOfTuples(W.rows());
  for (Eigen::Index p = 0; p < W.rows(); ++p)
    for (Eigen::Index k = 0; k < W.cols(); ++k)
      a->SetComponent(p, static_cast<int>(k), W(p, k));
  return a;
}

/// An n x n grid of points on [0, 1]^2 (z = @p z, or bent into z = x^2 when @p curved), two
/// triangles per square, and smooth, fairly local weights of 9 controls on a 3 x 3 grid.
vtkSmartPointer<vtkPolyData> GridWithWeights(int n, bool curved, bary::DenseWeights& W,
  Eigen::MatrixXd& V, Eigen::MatrixXi& T)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  V.resize(n * n, 2);
  W.resize(n * n, 9);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const double x = i / (n - 1.0), y = j / (n - 1.0);
      points->InsertNextPoint(x, y, curved ? x * x : 0.25);
      V.row(j * n + i) << x, y;
      double sum = 0;
      for (int c = 0; c < 9; ++c)
      {
        const double cx = (c % 3) / 2.0, cy = (c / 3) / 2.0;
        const double r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        W(j * n + i, c) = std::exp(-r2 / 0.02);
        sum += W(j * n + i, c);
      }
      W.row(j * n + i) /= sum;
    }
  vtkNew<vtkCellArray> polys;
  T.resize(2 * (n - 1) * (n - 1), 3);
  int t = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i)
    {
      const vtkIdType a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      const vtkIdType t0[3] = { a, b, c }, t1[3] = { a, c, d };
      polys->InsertNextCell(3, t0);
      polys->InsertNextCell(3, t1);
      T.row(t++) << int(a), int(b), int(c);
      T.row(t++) << int(a), int(c), int(d);
    }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetPolys(polys);
  data->GetPointData()->AddArray(WeightsArray(W));
  return data;
}

struct Statistics
{
  vtkNew<vtkBaryLocalityStatistics> Filter;
  vtkNew<ErrorObserver> Observer;
  explicit Statistics(vtkDataObject* input)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->SetInputData(input);
  }
  int Run() { return RunPipeline(this->Filter); }
};

/// The three tables equal @p s exactly (same arithmetic on the same data).
void ExpectTablesEqual(vtkBaryLocalityStatistics* f, const bary::LocalityStatistics& s)
{
  vtkTable* p = f->GetPTable();
  vtkTable* q = f->GetQTable();
  vtkTable* inf = f->GetInfluenceTable();
  ASSERT_NE(p->GetColumnByName("t"), nullptr);
  ASSERT_NE(p->GetColumnByName("P"), nullptr);
  ASSERT_NE(vtkIntArray::SafeDownCast(q->GetColumnByName("k")), nullptr);
  ASSERT_NE(q->GetColumnByName("Q"), nullptr);
  ASSERT_NE(vtkIntArray::SafeDownCast(inf->GetColumnByName("control")), nullptr);
  ASSERT_NE(inf->GetColumnByName("influence_fraction"), nullptr);
  ASSERT_EQ(p->GetNumberOfRows(), static_cast<vtkIdType>(s.t.size()));
  ASSERT_EQ(q->GetNumberOfRows(), static_cast<vtkIdType>(s.k.size()));
  ASSERT_EQ(inf->GetNumberOfRows(), static_cast<vtkIdType>(s.influence_fraction.size()));
  for (std::size_t i = 0; i < s.t.size(); ++i)
  {
    EXPECT_EQ(p->GetValueByName(i, "t").ToDouble(), s.t[i]);
    EXPECT_EQ(p->GetValueByName(i, "P").ToDouble(), s.P[i]);
  }
  for (std::size_t i = 0; i < s.k.size(); ++i)
  {
    EXPECT_EQ(q->GetValueByName(i, "k").ToInt(), s.k[i]);
    EXPECT_EQ(q->GetValueByName(i, "Q").ToDouble(), s.Q[i]);
  }
  for (std::size_t i = 0; i < s.influence_fraction.size(); ++i)
  {
    EXPECT_EQ(inf->GetValueByName(i, "control").ToInt(), static_cast<int>(i));
    EXPECT_EQ(inf->GetValueByName(i, "influence_fraction").ToDouble(), s.influence_fraction[i]);
  }
  EXPECT_EQ(f->GetThresholdUsed(), s.threshold);
  EXPECT_EQ(f->GetMeanSupport(), s.mean_support);
  EXPECT_EQ(f->GetMaxSupport(), s.max_support);
}

TEST(vtkBaryLocalityStatistics, HandComputedPointCloud)
{
  // 4 points, 2 controls, threshold 1e-3 / 2 = 5e-4 (0.0005 is not above it).
  auto cloud = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 }, { 3, 0, 0 } });
  bary::DenseWeights W(4, 2);
  W << 1, 0, 0.5, 0.5, 0, 1, 0.9995, 0.0005;
  cloud->GetPointData()->AddArray(WeightsArray(W));
  Statistics s(cloud);
  vtkNew<vtkDoubleArray> t;
  t->InsertNextValue(0.5);
  t->InsertNextValue(0.0);
  s.Filter->SetTValues(t);
  ASSERT_EQ(s.Run(), 1) << s.Observer->AllErrors();
  EXPECT_EQ(s.Filter->GetMeasureUsed(), vtkBaryLocalityStatistics::MEASURE_UNIFORM);
  EXPECT_STREQ(s.Filter->GetMeasureUsedAsString(), "uniform");
  EXPECT_DOUBLE_EQ(s.Filter->GetThresholdUsed(), 5e-4);
  EXPECT_DOUBLE_EQ(s.Filter->GetMeanSupport(), 1.25); // supports 1, 2, 1, 1
  EXPECT_DOUBLE_EQ(s.Filter->GetMaxSupport(), 2.0);
  vtkTable* p = s.Filter->GetPTable();
  ASSERT_EQ(p->GetNumberOfRows(), 2);
  EXPECT_DOUBLE_EQ(p->GetValueByName(0, "t").ToDouble(), 0.0);
  EXPECT_DOUBLE_EQ(p->GetValueByName(0, "P").ToDouble(), 0.25);  // (1/4 + 1/4) / 2
  EXPECT_DOUBLE_EQ(p->GetValueByName(1, "t").ToDouble(), 0.5);
  EXPECT_DOUBLE_EQ(p->GetValueByName(1, "P").ToDouble(), 0.625); // (2/4 + 3/4) / 2
  vtkTable* q = s.Filter->GetQTable();
  ASSERT_EQ(q->GetNumberOfRows(), 2);
  EXPECT_EQ(q->GetValueByName(0, "k").ToInt(), 1);
  EXPECT_DOUBLE_EQ(q->GetValueByName(0, "Q").ToDouble(), 1.0);
  EXPECT_EQ(q->GetValueByName(1, "k").ToInt(), 2);
  EXPECT_DOUBLE_EQ(q->GetValueByName(1, "Q").ToDouble(), 0.25);
  vtkTable* inf = s.Filter->GetInfluenceTable();
  ASSERT_EQ(inf->GetNumberOfRows(), 2);
  EXPECT_DOUBLE_EQ(inf->GetValueByName(0, "influence_fraction").ToDouble(), 0.75);
  EXPECT_DOUBLE_EQ(inf->GetValueByName(1, "influence_fraction").ToDouble(), 0.5);

  // an explicit threshold: 1e-4 makes 0.0005 significant
  s.Filter->SetThreshold(1e-4);
  ASSERT_EQ(s.Run(), 1) << s.Observer->AllErrors();
  EXPECT_DOUBLE_EQ(s.Filter->GetMeanSupport(), 1.5);
  EXPECT_DOUBLE_EQ(s.Filter->GetThresholdUsed(), 1e-4);
}

TEST(vtkBaryLocalityStatistics, EqualsCoreWithAndWithoutAreaMeasure)
{
  bary::DenseWeights W;
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  auto grid = GridWithWeights(21, false, W, V, T);
  Statistics s(grid);
  ASSERT_EQ(s.Run(), 1) << s.Observer->AllErrors();
  EXPECT_EQ(s.Filter->GetMeasureUsed(), vtkBaryLocalityStatistics::MEASURE_AREA);
  const Eigen::VectorXd measure = bary::vertex_measures(V, T);
  const bary::LocalityStatistics withArea = bary::locality_statistics(W, -1, measure);
  ExpectTablesEqual(s.Filter, withArea);
  EXPECT_EQ(s.Filter->GetPTable()->GetNumberOfRows(), 26); // default t values

  s.Filter->UseMeshMeasureOff();
  ASSERT_EQ(s.Run(), 1) << s.Observer->AllErrors();
  EXPECT_EQ(s.Filter->GetMeasureUsed(), vtkBaryLocalityStatistics::MEASURE_UNIFORM);
  const bary::LocalityStatistics uniform = bary::locality_statistics(W);
  ExpectTablesEqual(s.Filter, uniform);
  // boundary vertices carry less area than interior ones: the two differ
  EXPECT_NE(withArea.mean_support, uniform.mean_support);

  // Properties: Q(1) = 1 (rows sum to one), Q non-increasing, sum Q = mean support, P in [0, 1]
  vtkTable* q = s.Filter->GetQTable();
  double sum = 0;
  for (vtkIdType i = 0; i < q->GetNumberOfRows(); ++i)
  {
    const double Q = q->GetValueByName(i, "Q").ToDouble();
    sum += Q;
    if (i > 0)
    {
      EXPECT_LE(Q, q->GetValueByName(i - 1, "Q").ToDouble());
    }
  }
  EXPECT_DOUBLE_EQ(q->GetValueByName(0, "Q").ToDouble(), 1.0);
  EXPECT_NEAR(sum, s.Filter->GetMeanSupport(), 1e-12);
}

TEST(vtkBaryLocalityStatistics, CurvedSurfaceCountsPointsEqually)
{
  bary::DenseWeights W;
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  auto surface = GridWithWeights(11, true, W, V, T);
  Statistics s(surface);
  ASSERT_EQ(s.Run(), 1) << s.Observer->AllErrors();
  EXPECT_EQ(s.Filter->GetMeasureUsed(), vtkBaryLocalityStatistics::MEASURE_UNIFORM);
  ExpectTablesEqual(s.Filter, bary::locality_statistics(W));
}

TEST(vtkBaryLocalityStatistics, TetrahedraUseVolumes)
{
  // two tetrahedra sharing a face, 5 points; weights of 2 controls
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1, 0, 0);
  points->InsertNextPoint(0, 1, 0);
  points->InsertNextPoint(0, 0, 1);
  points->InsertNextPoint(1, 1, 1);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  const vtkIdType t0[4] = { 0, 1, 2, 3 }, t1[4] = { 1, 2, 3, 4 };
  grid->InsertNextCell(VTK_TETRA, 4, t0);
  grid->InsertNextCell(VTK_TETRA, 4, t1);
  bary::DenseWeights W(5, 2);
  W << 1, 0, 0.6, 0.4, 0.3, 0.7, 0, 1, 1e-5, 1 - 1e-5;
  grid->GetPointData()->AddArray(WeightsArray(W));
  Statistics s(grid);
  ASSERT_EQ(s.Run(), 1) << s.Observer->AllErrors();
  EXPECT_EQ(s.Filter->GetMeasureUsed(), vtkBaryLocalityStatistics::MEASURE_VOLUME);
  Eigen::MatrixXd V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  Eigen::MatrixXi T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 4;
  ExpectTablesEqual(s.Filter, bary::locality_statistics(W, -1, bary::vertex_measures(V, T)));
}

TEST(vtkBaryLocalityStatistics, Errors)
{
  // missing array
  auto cloud = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 } });
  {
    Statistics s(cloud);
    EXPECT_EQ(s.Run(), 0);
    EXPECT_TRUE(s.Observer->HasError("no point-data array 'Weights'")) << s.Observer->AllErrors();
  }
  // NaN
  bary::DenseWeights W(2, 2);
  W << 1, 0, std::numeric_limits<double>::quiet_NaN(), 1;
  cloud->GetPointData()->AddArray(WeightsArray(W));
  {
    Statistics s(cloud);
    EXPECT_EQ(s.Run(), 0);
    EXPECT_FALSE(s.Observer->Errors.empty());
    EXPECT_EQ(vtkBaryConversion::ErrorCodeOf(s.Filter->GetErrorCode(), bary::ErrorCode::Internal),
      bary::ErrorCode::NonFinite) << s.Observer->AllErrors();
  }
  // zero threshold
  W(1, 0) = 0;
  cloud->GetPointData()->AddArray(WeightsArray(W));
  {
    Statistics s(cloud);
    s.Filter->SetThreshold(0.0);
    EXPECT_EQ(s.Run(), 0);
    EXPECT_FALSE(s.Observer->Errors.empty());
  }
  // empty input
  {
    vtkNew<vtkPolyData> empty;
    Statistics s(empty);
    EXPECT_EQ(s.Run(), 0);
    EXPECT_TRUE(s.Observer->HasError("no points")) << s.Observer->AllErrors();
  }
}
} // namespace
