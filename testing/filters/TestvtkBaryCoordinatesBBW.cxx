// Tests of vtkBaryCoordinates with Method BBW: skeleton handles in a domain that is meshed
// (2D polygon, 3D closed surface) or given as a mesh, cage handles (weights linear on the cage's
// faces), the handle <-> component order (libigl's: point handles, then bones), fast and coupled
// modes, solver statistics, and the error paths.
#include "filters_test_utils.h"

#include "vtkBaryCageMesher.h"
#include "vtkBaryConversion.h"
#include "vtkBaryCoordinates.h"

#include "core/coordinates/bbw.h"

#include "vtkCellArray.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
using namespace barylab_test;

/// The unit square as one polygon cell (a 2D domain to be meshed).
vtkSmartPointer<vtkPolyData> MakeSquarePolygon()
{
  auto square = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, ids);
  square->SetPolys(polys);
  return square;
}

/// Joints: 0 (0.2, 0.2) a point handle; 1 (0.3, 0.75) - 2 (0.7, 0.75) - 3 (0.8, 0.45) two bones;
/// 4 (0.8, 0.15) another point handle. Handles: P = {0, 4}, bones {(1,2), (2,3)}.
vtkSmartPointer<vtkPolyData> MakeSkeleton2D()
{
  auto skeleton = MakePointCloud(
    { { 0.2, 0.2, 0 }, { 0.3, 0.75, 0 }, { 0.7, 0.75, 0 }, { 0.8, 0.45, 0 }, { 0.8, 0.15, 0 } });
  vtkNew<vtkCellArray> lines;
  const vtkIdType chain[3] = { 1, 2, 3 };
  lines->InsertNextCell(3, chain); // one polyline = two bones
  skeleton->SetLines(lines);
  vtkNew<vtkCellArray> verts;
  const vtkIdType p0 = 0, p4 = 4;
  verts->InsertNextCell(1, &p0);
  verts->InsertNextCell(1, &p4);
  skeleton->SetVerts(verts);
  return skeleton;
}

/// Random points strictly inside [m, 1-m]^2 (z = 0) plus the given extra points.
vtkSmartPointer<vtkPolyData> SquareSamples(int n, std::vector<std::array<double, 3>> extra)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  for (int i = 0; i < n; ++i)
    extra.push_back({ u(rng), u(rng), 0.0 });
  return MakePointCloud(extra);
}

struct BBW
{
  vtkNew<vtkBaryCoordinates> Filter;
  vtkNew<ErrorObserver> Observer;
  BBW(vtkDataSet* points, vtkPolyData* handles, vtkDataSet* domain)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->GetWeightMethod()->SetMethodToBBW();
    this->Filter->SetInputData(0, points);
    this->Filter->SetCageData(handles);
    if (domain)
      this->Filter->SetDomainData(domain);
  }
  int Run() { return RunPipeline(this->Filter); }
  vtkDataArray* Weights()
  {
    return GetWeights(vtkDataSet::SafeDownCast(this->Filter->GetOutputDataObject(0)));
  }
};

/// Bounds, partition of unity; returns the max partition error.
void ExpectBoundedAndNormalized(vtkDataArray* W, double tolerance)
{
  ASSERT_NE(W, nullptr);
  double worst = 0.0, lo = 0.0, hi = 1.0;
  for (vtkIdType p = 0; p < W->GetNumberOfTuples(); ++p)
  {
    double sum = 0.0;
    for (int j = 0; j < W->GetNumberOfComponents(); ++j)
    {
      const double w = W->GetComponent(p, j);
      lo = std::min(lo, w);
      hi = std::max(hi, w);
      sum += w;
    }
    worst = std::max(worst, std::abs(sum - 1.0));
  }
  EXPECT_GE(lo, 0.0) << "non-negativity (Eq. 6)";
  EXPECT_LE(hi, 1.0) << "upper bound (Eq. 6)";
  EXPECT_LE(worst, tolerance) << "partition of unity (Eq. 5)";
}

TEST(vtkBaryCoordinatesBBW, Skeleton2DInAPolygonIsMeshedWithTheHandlesInLibiglOrder)
{
  auto square = MakeSquarePolygon();
  auto skeleton = MakeSkeleton2D();
  // evaluation points: the joints first, then random points
  auto points = SquareSamples(200,
    { { 0.2, 0.2, 0 }, { 0.3, 0.75, 0 }, { 0.7, 0.75, 0 }, { 0.8, 0.45, 0 }, { 0.8, 0.15, 0 } });
  for (bool fast : { true, false })
  {
    SCOPED_TRACE(fast ? "fast" : "coupled");
    BBW bbw(points, skeleton, square);
    bbw.Filter->GetWeightMethod()->SetBBWFast(fast);
    bbw.Filter->GetWeightMethod()->SetTargetNumberOfCells(800);
    ASSERT_EQ(bbw.Run(), 1) << bbw.Observer->AllErrors();
    vtkDataArray* W = bbw.Weights();
    ASSERT_NE(W, nullptr);
    ASSERT_EQ(W->GetNumberOfComponents(), 4); // 2 point handles + 2 bones
    ExpectBoundedAndNormalized(W, 1e-12);
    // Lagrange: point handle 0 is joint 0, point handle 1 is joint 4; bone 0 = (1,2), bone 1 =
    // (2,3); joint 2 is shared by the two bones (a joint: 1/2 each, paper §3.1).
    const double expected[5][4] = { { 1, 0, 0, 0 }, { 0, 0, 1, 0 }, { 0, 0, 0.5, 0.5 },
      { 0, 0, 0, 1 }, { 0, 1, 0, 0 } };
    for (int p = 0; p < 5; ++p)
      for (int j = 0; j < 4; ++j)
        EXPECT_NEAR(W->GetComponent(p, j), expected[p][j], 1e-12) << "joint " << p << " handle " << j;
    EXPECT_LE(bbw.Filter->GetStatistic("max_kkt_residual"), 1e-9);
    EXPECT_EQ(bbw.Filter->GetStatistic("converged"), 1.0);
    EXPECT_EQ(bbw.Filter->GetStatistic("max_bound_violation"), 0.0);
    EXPECT_GE(bbw.Filter->GetStatistic("mesh_cells"), 800.0);
    EXPECT_TRUE(std::isnan(bbw.Filter->GetStatistic("no such figure")));
    EXPECT_EQ(bbw.Filter->GetStatistic("coupled"), fast ? 0.0 : 1.0);
    EXPECT_EQ(bbw.Filter->GetNumberOfInsidePoints(), points->GetNumberOfPoints());
  }
}

TEST(vtkBaryCoordinatesBBW, GivenMeshMatchesTheCoreOnItsVertices)
{
  // Mesh a cube with the skeleton inserted (vtkBaryCageMesher), then give that mesh as the
  // domain: the filter must use it as is, so its weights at the mesh vertices are the core's.
  auto cube = MakeCube();
  auto skeleton = MakePointCloud({ { -0.5, -0.5, -0.5 }, { 0.5, 0.5, 0.5 }, { 0.5, -0.5, 0.0 } });
  vtkNew<vtkCellArray> lines;
  const vtkIdType bone[2] = { 0, 1 };
  lines->InsertNextCell(2, bone);
  skeleton->SetLines(lines);
  // bone samples every 0.25 of the diagonal so the bone is made of mesh vertices
  std::vector<std::array<double, 3>> samples;
  for (int k = 0; k <= 4; ++k)
  {
    const double t = -0.5 + 0.25 * k;
    samples.push_back({ t, t, t });
  }
  samples.push_back({ 0.5, -0.5, 0.0 });
  vtkNew<vtkBaryCageMesher> mesher;
  mesher->SetCageData(cube);
  mesher->SetPointsData(MakePointCloud(samples));
  mesher->SetTargetNumberOfCells(1500);
  ASSERT_EQ(RunPipeline(mesher), 1);
  vtkUnstructuredGrid* mesh = mesher->GetOutput();

  BBW bbw(mesh, skeleton, mesh);
  bbw.Filter->GetWeightMethod()->SetBBWFast(true);
  ASSERT_EQ(bbw.Run(), 1) << bbw.Observer->AllErrors();
  vtkDataArray* W = bbw.Weights();
  ASSERT_NE(W, nullptr);
  ASSERT_EQ(W->GetNumberOfComponents(), 2); // point handle (joint 2), then the bone
  ExpectBoundedAndNormalized(W, 1e-12);

  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  vtkBaryConversion::ToSimplices(mesh, 0, V, T);
  ASSERT_EQ(T.cols(), 4);
  Eigen::MatrixXd C(3, 3);
  C << -0.5, -0.5, -0.5, 0.5, 0.5, 0.5, 0.5, -0.5, 0.0;
  Eigen::VectorXi P(1);
  P << 2;
  Eigen::MatrixXi BE(1, 2);
  BE << 0, 1;
  bary::BBWOptions options;
  options.mode = bary::BBWMode::Fast;
  const bary::BBWResult core =
    bary::bounded_biharmonic_weights(V, T, bary::handles_from_skeleton(V, C, P, BE), options);
  double diff = 0.0;
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
    for (int j = 0; j < 2; ++j)
      diff = std::max(diff, std::abs(W->GetComponent(p, j) - core.W(p, j)));
  EXPECT_LE(diff, 1e-14);
  EXPECT_EQ(bbw.Filter->GetStatistic("mesh_vertices"), static_cast<double>(mesh->GetNumberOfPoints()));
}

TEST(vtkBaryCoordinatesBBW, ClosedSurfaceDomainIsTetrahedralizedAroundTheSkeleton)
{
  auto cube = MakeCube();
  auto skeleton = MakePointCloud({ { -0.6, 0.0, 0.0 }, { 0.6, 0.0, 0.0 }, { 0.0, 0.6, 0.3 } });
  vtkNew<vtkCellArray> lines;
  const vtkIdType bone[2] = { 0, 1 };
  lines->InsertNextCell(2, bone);
  skeleton->SetLines(lines);
  auto points = MakePointCloud({ { -0.6, 0.0, 0.0 }, { 0.0, 0.0, 0.0 }, { 0.0, 0.6, 0.3 },
    { 0.9, 0.9, 0.9 }, { -0.9, 0.2, -0.7 } });
  BBW bbw(points, skeleton, cube);
  bbw.Filter->GetWeightMethod()->SetBBWFast(true);
  bbw.Filter->GetWeightMethod()->SetTargetNumberOfCells(3000);
  ASSERT_EQ(bbw.Run(), 1) << bbw.Observer->AllErrors();
  vtkDataArray* W = bbw.Weights();
  ASSERT_EQ(W->GetNumberOfComponents(), 2);
  ExpectBoundedAndNormalized(W, 1e-12);
  EXPECT_NEAR(W->GetComponent(0, 1), 1.0, 1e-12); // bone tail
  EXPECT_NEAR(W->GetComponent(1, 1), 1.0, 1e-9);  // on the bone (between samples)
  EXPECT_NEAR(W->GetComponent(2, 0), 1.0, 1e-12); // the point handle
}

TEST(vtkBaryCoordinatesBBW, CageHandlesAreLinearOnTheCageFaces)
{
  auto cube = MakeCube();
  // cage vertices, face centroids (faces 2 and 7) and interior points
  std::vector<std::array<double, 3>> xs;
  for (vtkIdType i = 0; i < 8; ++i)
  {
    std::array<double, 3> x;
    cube->GetPoint(i, x.data());
    xs.push_back(x);
  }
  xs.push_back({ 1.0 / 3, -1.0 / 3, 1.0 });   // centroid of face (4, 5, 6)
  xs.push_back({ 1.0, -1.0 / 3, 1.0 / 3 });   // centroid of face (1, 6, 5)
  xs.push_back({ 0.1, 0.2, -0.3 });
  xs.push_back({ -0.7, 0.5, 0.6 });
  auto points = MakePointCloud(xs);
  for (bool fast : { true, false })
  {
    BBW bbw(points, cube, nullptr);
    bbw.Filter->GetWeightMethod()->SetBBWFast(fast);
    bbw.Filter->GetWeightMethod()->SetTargetNumberOfCells(400);
    ASSERT_EQ(bbw.Run(), 1) << bbw.Observer->AllErrors();
    vtkDataArray* W = bbw.Weights();
    ASSERT_EQ(W->GetNumberOfComponents(), 8);
    ExpectBoundedAndNormalized(W, 1e-12);
    for (int p = 0; p < 8; ++p)
      for (int j = 0; j < 8; ++j)
        EXPECT_NEAR(W->GetComponent(p, j), p == j ? 1.0 : 0.0, 1e-12);
    const int face_a[3] = { 4, 5, 6 }, face_b[3] = { 1, 6, 5 };
    for (int j = 0; j < 8; ++j)
    {
      const bool in_a = j == face_a[0] || j == face_a[1] || j == face_a[2];
      const bool in_b = j == face_b[0] || j == face_b[1] || j == face_b[2];
      EXPECT_NEAR(W->GetComponent(8, j), in_a ? 1.0 / 3 : 0.0, 1e-12) << "face (4,5,6), handle " << j;
      EXPECT_NEAR(W->GetComponent(9, j), in_b ? 1.0 / 3 : 0.0, 1e-12) << "face (1,6,5), handle " << j;
    }
  }
}

TEST(vtkBaryCoordinatesBBW, Errors)
{
  auto square = MakeSquarePolygon();
  auto skeleton = MakeSkeleton2D();
  auto points = SquareSamples(10, {});
  {
    BBW bbw(points, skeleton, nullptr); // a skeleton needs a domain
    EXPECT_EQ(bbw.Run(), 0);
    EXPECT_TRUE(bbw.Observer->HasError("need a domain")) << bbw.Observer->AllErrors();
  }
  {
    auto cube = MakeCube(); // 3D domain, 2D skeleton (z = 0 is fine: the skeleton is read as 3D)
    auto far = MakePointCloud({ { 5, 5, 5 }, { 6, 5, 5 } });
    vtkNew<vtkCellArray> lines;
    const vtkIdType bone[2] = { 0, 1 };
    lines->InsertNextCell(2, bone);
    far->SetLines(lines);
    BBW bbw(MakePointCloud({ { 0, 0, 0 } }), far, cube);
    bbw.Filter->GetWeightMethod()->SetBBWFast(true);
    bbw.Filter->GetWeightMethod()->SetTargetNumberOfCells(500);
    EXPECT_EQ(bbw.Run(), 0);
    EXPECT_TRUE(bbw.Observer->HasError("bone 0")) << bbw.Observer->AllErrors();
  }
  {
    // points outside the domain: error by default, NaN when asked
    auto outside = MakePointCloud({ { 0.5, 0.5, 0 }, { 2.0, 0.5, 0 } });
    BBW bbw(outside, skeleton, square);
    bbw.Filter->GetWeightMethod()->SetBBWFast(true);
    bbw.Filter->GetWeightMethod()->SetTargetNumberOfCells(300);
    EXPECT_EQ(bbw.Run(), 0);
    EXPECT_TRUE(bbw.Observer->HasError("outside the mesh")) << bbw.Observer->AllErrors();
    bbw.Observer->Clear();
    bbw.Filter->GetWeightMethod()->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NAN);
    ASSERT_EQ(bbw.Run(), 1) << bbw.Observer->AllErrors();
    EXPECT_EQ(bbw.Filter->GetNumberOfOutsidePoints(), 1);
    EXPECT_TRUE(std::isnan(bbw.Weights()->GetComponent(1, 0)));
    EXPECT_FALSE(std::isnan(bbw.Weights()->GetComponent(0, 0)));
  }
  {
    // a domain of quads is neither simplicial nor one polygon
    auto quads = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 2, 0, 0 },
      { 2, 1, 0 } });
    vtkNew<vtkCellArray> polys;
    const vtkIdType q0[4] = { 0, 1, 2, 3 }, q1[4] = { 1, 4, 5, 2 };
    polys->InsertNextCell(4, q0);
    polys->InsertNextCell(4, q1);
    quads->SetPolys(polys);
    BBW bbw(points, skeleton, quads);
    EXPECT_EQ(bbw.Run(), 0);
    EXPECT_TRUE(bbw.Observer->HasError("one polygon")) << bbw.Observer->AllErrors();
  }
  {
    // a NaN joint is named
    auto bad = MakeSkeleton2D();
    bad->GetPoints()->SetPoint(3, std::nan(""), 0.4, 0.0);
    BBW bbw(points, bad, square);
    EXPECT_EQ(bbw.Run(), 0);
    EXPECT_TRUE(bbw.Observer->HasError("handle point 3")) << bbw.Observer->AllErrors();
  }
}

} // namespace

#include "vtkBaryCageDeformation.h"

namespace
{
TEST(vtkBaryCoordinatesBBW, CageDeformationWithCageHandlesFollowsATranslatedCage)
{
  // BBW with cage handles have partition of unity but no linear precision (the paper says so):
  // a translated cage translates the model exactly; a scaled one does not scale it exactly.
  auto cube = MakeCube();
  auto model = MakePointCloud({ { 0.1, 0.2, -0.3 }, { -0.7, 0.5, 0.6 }, { 0.0, 0.0, 0.0 } });
  const auto moved_cube = [&](double scale, double tx, double ty, double tz) {
    auto moved = vtkSmartPointer<vtkPolyData>::New();
    moved->DeepCopy(cube);
    for (vtkIdType i = 0; i < moved->GetNumberOfPoints(); ++i)
    {
      double c[3];
      cube->GetPoint(i, c);
      moved->GetPoints()->SetPoint(i, scale * c[0] + tx, scale * c[1] + ty, scale * c[2] + tz);
    }
    return moved;
  };
  vtkNew<vtkBaryCageDeformation> deform;
  vtkNew<ErrorObserver> errors;
  errors->Attach(deform);
  deform->GetWeightMethod()->SetMethod(vtkBaryWeightMethod::BBW);
  deform->GetWeightMethod()->SetBBWFast(true);
  deform->GetWeightMethod()->SetTargetNumberOfCells(400);
  deform->SetInputData(model);
  deform->SetRestCageData(cube);
  deform->SetDeformedCageData(moved_cube(1.0, 0.3, -1.2, 0.5));
  ASSERT_EQ(RunPipeline(deform), 1) << errors->AllErrors();
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3];
    model->GetPoint(p, x);
    deform->GetOutput()->GetPoint(p, y);
    EXPECT_NEAR(y[0], x[0] + 0.3, 1e-12);
    EXPECT_NEAR(y[1], x[1] - 1.2, 1e-12);
    EXPECT_NEAR(y[2], x[2] + 0.5, 1e-12);
  }
  deform->SetDeformedCageData(moved_cube(2.0, 0.0, 0.0, 0.0));
  ASSERT_EQ(RunPipeline(deform), 1) << errors->AllErrors();
  double x[3], y[3];
  model->GetPoint(1, x);
  deform->GetOutput()->GetPoint(1, y);
  EXPECT_GT(std::abs(y[0] - 2.0 * x[0]) + std::abs(y[1] - 2.0 * x[1]), 1e-3)
    << "BBW have no linear precision: scaling the cage does not scale interior points exactly";
}
} // namespace
