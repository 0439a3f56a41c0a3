// Tests of vtkBaryCoordinates with Method BBW and mixed handles (vtkBaryMixedHandles): a
// handles poly data mixing points, bones, an open or closed cage and regions (HandleType,
// RegionId), the domain's HandleRegion and ShapePreservation arrays, against the core computed
// from the same handles built by hand; the brush's effect measured; errors. Part of the
// TestvtkBaryCoordinatesBBW executable.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBaryCoordinates.h"
#include "vtkBaryMixedHandles.h"

#include "core/coordinates/bbw_handles.h"
#include "core/coordinates/weight_method.h"
#include "core/solvers/fem_operators.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkStringArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
using namespace barylab_test;

/// The unit square as an n x n grid of vertices, triangulated (a 2D domain used as is).
struct SquareMesh
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  vtkSmartPointer<vtkUnstructuredGrid> Grid;
  int n = 0;
  int id(int i, int j) const { return j * n + i; }
};

SquareMesh square_mesh(int n)
{
  SquareMesh m;
  m.n = n;
  m.V.resize(n * n, 2);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.V.row(m.id(i, j)) << double(i) / (n - 1), double(j) / (n - 1);
  m.T.resize(2 * (n - 1) * (n - 1), 3);
  int t = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i)
    {
      const int a = m.id(i, j), b = m.id(i + 1, j), c = m.id(i + 1, j + 1), d = m.id(i, j + 1);
      m.T.row(t++) << a, b, c;
      m.T.row(t++) << a, c, d;
    }
  m.Grid = vtkBaryConversion::SimplicesToGrid(m.V, m.T, 0.0);
  return m;
}

/// Joints 0 (0.2, 0.8) a point handle; 1-2 a bone (0.5, 0.15)-(0.8, 0.15); 3-4-5 an open cage
/// polyline on x = 1 (HandleType 2); 6-9 a square region (HandleType 3, RegionId 7).
vtkSmartPointer<vtkPolyData> mixed_handles_2d()
{
  auto h = MakePointCloud({ { 0.2, 0.8, 0 }, { 0.5, 0.15, 0 }, { 0.8, 0.15, 0 }, { 1, 0.3, 0 },
    { 1, 0.6, 0 }, { 1, 0.9, 0 }, { 0.35, 0.4, 0 }, { 0.55, 0.4, 0 }, { 0.55, 0.6, 0 },
    { 0.35, 0.6, 0 } });
  vtkNew<vtkCellArray> lines, polys;
  const vtkIdType bone[2] = { 1, 2 }, cage[3] = { 3, 4, 5 }, region[4] = { 6, 7, 8, 9 };
  lines->InsertNextCell(2, bone);
  lines->InsertNextCell(3, cage);
  polys->InsertNextCell(4, region);
  h->SetLines(lines);
  h->SetPolys(polys);
  vtkNew<vtkIntArray> kind, region_id;
  kind->SetName("HandleType");
  region_id->SetName("RegionId");
  // cell ids: lines first (bone 0, cage 1), then the polygon (2)
  for (int k : { 1, 2, 3 })
    kind->InsertNextValue(k);
  for (int r : { -1, -1, 7 })
    region_id->InsertNextValue(r);
  h->GetCellData()->AddArray(kind);
  h->GetCellData()->AddArray(region_id);
  return h;
}

struct Mixed
{
  vtkNew<vtkBaryCoordinates> Filter;
  vtkNew<ErrorObserver> Observer;
  Mixed(vtkDataSet* points, vtkPolyData* handles, vtkDataSet* domain, bool fast = false)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->GetWeightMethod()->SetMethodToBBW();
    this->Filter->GetWeightMethod()->SetBBWFast(fast);
    this->Filter->SetInputData(0, points);
    this->Filter->SetCageData(handles);
    if (domain)
      this->Filter->SetDomainData(domain);
  }
  int Update() { return RunPipeline(this->Filter); }
  Eigen::MatrixXd W()
  {
    vtkDataArray* a = GetWeights(vtkDataSet::SafeDownCast(this->Filter->GetOutputDataObject(0)));
    return a ? Eigen::MatrixXd(vtkBaryConversion::ArrayToMatrix(a)) : Eigen::MatrixXd();
  }
};

bary::WeightsResult core_weights(const SquareMesh& m, const bary::Skeleton& s, bool fast,
  const std::vector<std::vector<int>>* regions = nullptr, const Eigen::VectorXd* brush = nullptr)
{
  bary::WeightsSettings settings;
  settings.method = bary::MethodId::BBW;
  settings.bbw_fast = fast;
  bary::WeightsInput in;
  in.skeleton = &s;
  in.domain_V = &m.V;
  in.domain_T = &m.T;
  in.points = &m.V;
  in.region_vertices = regions;
  in.shape_preservation = brush;
  return bary::compute_weights(in, settings);
}

TEST(vtkBaryMixedHandles, APolyDataOfEveryKindIsTheCoresMixedHandles)
{
  const SquareMesh m = square_mesh(21);
  auto handles = mixed_handles_2d();
  ASSERT_TRUE(vtkBaryMixedHandles::UsesMixedHandles(handles, m.Grid));
  const bary::Skeleton parsed = vtkBaryMixedHandles::ToHandles(handles, 2);
  EXPECT_EQ(parsed.P, (Eigen::VectorXi(1) << 0).finished());
  EXPECT_EQ(parsed.BE, (Eigen::MatrixXi(1, 2) << 1, 2).finished());
  EXPECT_EQ(parsed.CF, (Eigen::MatrixXi(2, 2) << 3, 4, 4, 5).finished());
  ASSERT_EQ(parsed.regions.size(), 1u);
  EXPECT_EQ(parsed.regions[0], (Eigen::MatrixXi(4, 2) << 6, 7, 7, 8, 8, 9, 9, 6).finished());

  // The same handles built by hand in core.
  bary::Skeleton s;
  s.C = vtkBaryConversion::ToMatrix(handles->GetPoints(), 2);
  s.P = parsed.P;
  s.BE = (Eigen::MatrixXi(1, 2) << 1, 2).finished();
  s.CF = (Eigen::MatrixXi(2, 2) << 3, 4, 4, 5).finished();
  s.regions.push_back((Eigen::MatrixXi(4, 2) << 6, 7, 7, 8, 8, 9, 9, 6).finished());
  const bary::WeightsResult reference = core_weights(m, s, true);

  Mixed run(m.Grid, handles, m.Grid, true);
  ASSERT_EQ(run.Update(), 1) << run.Observer->AllErrors();
  const Eigen::MatrixXd W = run.W();
  ASSERT_EQ(W.cols(), 6); // point, bone, cage joints 3 4 5, region
  EXPECT_LE((W - reference.W).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  EXPECT_GE(W.minCoeff(), 0.0);
  // Eq. 4 on the open cage: at (1, 0.45), halfway between joints 3 and 4.
  EXPECT_NEAR(W(m.id(20, 9), 2), 0.5, 1e-12);
  EXPECT_NEAR(W(m.id(20, 9), 3), 0.5, 1e-12);
  // The region's vertices move with it.
  EXPECT_NEAR(W(m.id(9, 10), 5), 1.0, 1e-14);
  EXPECT_GT(run.Filter->GetStatistic("fixed_vertices"), 25.0);
}

TEST(vtkBaryMixedHandles, AClosedCagePolygonWithAPointHandleAndTheDomainsRegions)
{
  // A polygon cell on the square's boundary (a closed cage), a point handle (a point on no
  // cell), and a HandleRegion array on the domain: the cage is linear on the boundary (Eq. 4),
  // the point's and the region's rows are unit rows.
  const SquareMesh m = square_mesh(11);
  auto handles = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.3, 0.3, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType square[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, square);
  handles->SetPolys(polys);
  vtkNew<vtkIntArray> region;
  region->SetName("HandleRegion");
  region->SetNumberOfTuples(m.Grid->GetNumberOfPoints());
  region->Fill(-1);
  region->SetValue(m.id(7, 7), 4);
  region->SetValue(m.id(7, 6), 4);
  auto domain = vtkSmartPointer<vtkUnstructuredGrid>::New();
  domain->ShallowCopy(m.Grid);
  domain->GetPointData()->AddArray(region);
  Mixed run(m.Grid, handles, domain, true);
  ASSERT_EQ(run.Update(), 1) << run.Observer->AllErrors();
  const Eigen::MatrixXd W = run.W();
  ASSERT_EQ(W.cols(), 6); // point 4, cage joints 0-3, region 4
  EXPECT_NEAR(W(m.id(3, 3), 0), 1.0, 1e-14);
  EXPECT_NEAR(W(m.id(7, 7), 5), 1.0, 1e-14);
  EXPECT_NEAR(W(m.id(7, 6), 5), 1.0, 1e-14);
  for (int i = 0; i < 11; ++i)
  {
    const double x = i / 10.0;
    // bottom edge: joints 0 (0, 0) and 1 (1, 0); top edge: 3 (0, 1) and 2 (1, 1)
    EXPECT_NEAR(W(m.id(i, 0), 1), 1 - x, 1e-12);
    EXPECT_NEAR(W(m.id(i, 0), 2), x, 1e-12);
    EXPECT_NEAR(W(m.id(i, 10), 4), 1 - x, 1e-12);
    EXPECT_NEAR(W(m.id(i, 10), 3), x, 1e-12);
  }
  // The same with the region given to the core as a vertex list.
  bary::Skeleton s;
  s.C = vtkBaryConversion::ToMatrix(handles->GetPoints(), 2);
  s.P = (Eigen::VectorXi(1) << 4).finished();
  s.CF = (Eigen::MatrixXi(4, 2) << 0, 1, 1, 2, 2, 3, 3, 0).finished();
  const std::vector<std::vector<int>> regions{ { m.id(7, 6), m.id(7, 7) } };
  EXPECT_LE((W - core_weights(m, s, true, &regions).W).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(vtkBaryMixedHandles, ShapePreservationArrayFlattensThePaintedDisk)
{
  // Fig. 5 through the filter: the domain's ShapePreservation array (a soft disk) makes the
  // weights nearly constant there; measured as the mean |grad w| over the fully painted
  // triangles with and without the array.
  const SquareMesh m = square_mesh(31);
  auto handles = MakePointCloud({ { 0.1, 0.5, 0 }, { 0.9, 0.5, 0 }, { 0.5, 0.1, 0 } });
  vtkNew<vtkDoubleArray> rho;
  rho->SetName("ShapePreservation");
  rho->SetNumberOfTuples(m.Grid->GetNumberOfPoints());
  const double strength = 1e4;
  for (vtkIdType i = 0; i < rho->GetNumberOfTuples(); ++i)
  {
    const double r = (m.V.row(i) - Eigen::RowVector2d(0.5, 0.55)).norm();
    rho->SetValue(i, strength * std::clamp((0.2 - r) / 0.05, 0.0, 1.0));
  }
  auto painted_domain = vtkSmartPointer<vtkUnstructuredGrid>::New();
  painted_domain->ShallowCopy(m.Grid);
  painted_domain->GetPointData()->AddArray(rho);
  Mixed plain(m.Grid, handles, m.Grid, true), painted(m.Grid, handles, painted_domain, true);
  ASSERT_EQ(plain.Update(), 1) << plain.Observer->AllErrors();
  ASSERT_EQ(painted.Update(), 1) << painted.Observer->AllErrors();
  const Eigen::MatrixXd W0 = plain.W(), W1 = painted.W();
  const Eigen::SparseMatrix<double> G = bary::gradient_operator(m.V, m.T);
  auto mean_gradient = [&](const Eigen::MatrixXd& W) {
    double sum = 0;
    int count = 0;
    for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    {
      bool inside = true;
      for (int k = 0; k < 3; ++k)
        inside = inside && rho->GetValue(m.T(t, k)) >= strength;
      if (!inside)
        continue;
      for (Eigen::Index j = 0; j < W.cols(); ++j)
      {
        const Eigen::VectorXd g = G * Eigen::VectorXd(W.col(j));
        sum += g.segment(2 * t, 2).norm();
        ++count;
      }
    }
    return sum / count;
  };
  const double before = mean_gradient(W0), after = mean_gradient(W1);
  std::cout << "[ info ] filter: mean |grad w| in the painted disk " << before << " -> " << after
            << "\n";
  EXPECT_LT(after, 0.05 * before);
  // Against the core with the brush given per vertex.
  bary::Skeleton s;
  s.C = vtkBaryConversion::ToMatrix(handles->GetPoints(), 2);
  s.P = (Eigen::VectorXi(3) << 0, 1, 2).finished();
  Eigen::VectorXd brush(rho->GetNumberOfTuples());
  for (vtkIdType i = 0; i < rho->GetNumberOfTuples(); ++i)
    brush(i) = rho->GetValue(i);
  EXPECT_LE((W1 - core_weights(m, s, true, nullptr, &brush).W).cwiseAbs().maxCoeff(), 1e-14);

  // Validation: NaN, negative, two components, a domain to be meshed.
  auto bad = [&](double value, int components) {
    vtkNew<vtkDoubleArray> a;
    a->SetName("ShapePreservation");
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(m.Grid->GetNumberOfPoints());
    a->Fill(1.0);
    a->SetComponent(5, 0, value);
    auto d = vtkSmartPointer<vtkUnstructuredGrid>::New();
    d->ShallowCopy(m.Grid);
    d->GetPointData()->AddArray(a);
    Mixed r(m.Grid, handles, d, true);
    EXPECT_EQ(r.Update(), 0);
    return r.Observer->AllErrors();
  };
  EXPECT_NE(bad(std::nan(""), 1).find("NaN or infinite at vertex 5"), std::string::npos);
  EXPECT_NE(bad(-1.0, 1).find("negative at vertex 5"), std::string::npos);
  EXPECT_NE(bad(1.0, 2).find("2 components"), std::string::npos);
  auto polygon = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, ids);
  polygon->SetPolys(polys);
  vtkNew<vtkDoubleArray> on_polygon;
  on_polygon->SetName("ShapePreservation");
  on_polygon->SetNumberOfTuples(4);
  on_polygon->Fill(1.0);
  polygon->GetPointData()->AddArray(on_polygon);
  Mixed meshed(m.Grid, handles, polygon, true);
  EXPECT_EQ(meshed.Update(), 0);
  EXPECT_TRUE(meshed.Observer->HasError("given domain mesh")) << meshed.Observer->AllErrors();
}

TEST(vtkBaryMixedHandles, MixedHandlesInAPolygonDomainToMesh)
{
  // The domain a polygon to mesh: the joints and samples of the bone, the open cage and the
  // region are inserted, so every handle is fixed somewhere; weights bounded, partition exact.
  auto polygon = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, ids);
  polygon->SetPolys(polys);
  auto handles = mixed_handles_2d();
  // the open cage inside the square (x = 0.9) rather than on its boundary
  for (vtkIdType i = 3; i <= 5; ++i)
  {
    double x[3];
    handles->GetPoint(i, x);
    handles->GetPoints()->SetPoint(i, 0.9, x[1], 0);
  }
  auto points = MakePointCloud({ { 0.45, 0.5, 0 }, { 0.9, 0.45, 0 }, { 0.2, 0.8, 0 }, { 0.05, 0.05, 0 } });
  Mixed run(points, handles, polygon, true);
  run.Filter->GetWeightMethod()->SetTargetNumberOfCells(800);
  ASSERT_EQ(run.Update(), 1) << run.Observer->AllErrors();
  const Eigen::MatrixXd W = run.W();
  ASSERT_EQ(W.cols(), 6);
  EXPECT_NEAR(W(0, 5), 1.0, 1e-12);  // inside the region
  EXPECT_NEAR(W(1, 2), 0.5, 1e-9);   // halfway along the first cage edge
  EXPECT_NEAR(W(1, 3), 0.5, 1e-9);
  EXPECT_NEAR(W(2, 0), 1.0, 1e-12);  // the point handle
  EXPECT_GE(W.minCoeff(), 0.0);
  EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
}

TEST(vtkBaryMixedHandles, Errors)
{
  const SquareMesh m = square_mesh(21);
  auto expect_error = [&](vtkPolyData* handles, vtkDataSet* domain, const std::string& text) {
    Mixed run(m.Grid, handles, domain, true);
    EXPECT_EQ(run.Update(), 0);
    EXPECT_TRUE(run.Observer->HasError(text)) << run.Observer->AllErrors();
  };
  // An unknown HandleType; a bone marked on a polygon; a region cell that is a line.
  auto handles = mixed_handles_2d();
  vtkIntArray::SafeDownCast(handles->GetCellData()->GetArray("HandleType"))->SetValue(0, 9);
  expect_error(handles, m.Grid, "handle cell 0 has HandleType 9");
  // HandleType or RegionId with fewer values than cells (never read past their end), or text
  for (const char* name : { "HandleType", "RegionId" })
  {
    handles = mixed_handles_2d();
    vtkNew<vtkIntArray> one;
    one->SetName(name);
    one->InsertNextValue(1);
    handles->GetCellData()->AddArray(one);
    expect_error(handles, m.Grid, std::string(name) + " has 1 values but there are 3 cells");
    handles = mixed_handles_2d();
    vtkNew<vtkStringArray> text;
    text->SetName(name);
    for (int k = 0; k < 3; ++k)
      text->InsertNextValue("1");
    handles->GetCellData()->AddArray(text);
    expect_error(handles, m.Grid, std::string(name) + " is not numeric");
  }
  handles = mixed_handles_2d();
  vtkIntArray::SafeDownCast(handles->GetCellData()->GetArray("HandleType"))->SetValue(2, 1);
  expect_error(handles, m.Grid, "handle cell 2 is marked a bone");
  handles = mixed_handles_2d();
  vtkIntArray::SafeDownCast(handles->GetCellData()->GetArray("HandleType"))->SetValue(0, 3);
  expect_error(handles, m.Grid, "handle cell 0 is marked a region");
  // Overlapping handles: the domain's region on the point handle's vertex.
  handles = mixed_handles_2d();
  vtkNew<vtkIntArray> region;
  region->SetName("HandleRegion");
  region->SetNumberOfTuples(m.Grid->GetNumberOfPoints());
  region->Fill(-1);
  region->SetValue(m.id(4, 16), 0);
  auto domain = vtkSmartPointer<vtkUnstructuredGrid>::New();
  domain->ShallowCopy(m.Grid);
  domain->GetPointData()->AddArray(region);
  expect_error(handles, domain, "handles must be disjoint");
  region->SetValue(m.id(4, 16), -3);
  expect_error(handles, domain, "use -1 for no region");
}

} // namespace
