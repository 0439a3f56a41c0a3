// Tests of vtkBaryCoordinates with Method LBC (local barycentric coordinates, Zhang et al. 2014):
// the barycentric properties at points of the bundled 2D and 3D cages (partition of unity and
// reproduction to 1e-10 at points inserted as mesh vertices, non-negativity, Lagrange property at
// the cage vertices, linear on the 2D cage's edges), the filter's weights equal to core's on the
// same mesh (1e-12), a domain mesh on input 2 (the LBC authors' own triangulation of their logo
// cage, skipped without ../shared), the statistics, thread independence, progress, cancel and the
// error paths (a cage vertex missing from the domain mesh, non-convergence, a wrong domain).
#include "filters_test_utils.h"

#include "vtkBaryCageDeformation.h"
#include "vtkBaryCageMesher.h"
#include "vtkBaryConversion.h"
#include "vtkBaryCoordinates.h"

#include "core/meshing/domain_mesh.h"
#include "core/coordinates/local_barycentric_coordinates.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace
{
using namespace barylab_test;

struct LBC
{
  vtkNew<vtkBaryCoordinates> Filter;
  vtkNew<ErrorObserver> Observer;
  LBC(vtkDataSet* points, vtkPolyData* cage, int cells)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->GetWeightMethod()->SetMethodToLBC();
    this->Filter->SetInputData(0, points);
    this->Filter->SetCageData(cage);
    this->Filter->GetWeightMethod()->SetTargetNumberOfCells(cells);
  }
  int Run() { return RunPipeline(this->Filter); }
  bary::DenseWeights Weights()
  {
    vtkDataArray* w = GetWeights(vtkDataSet::SafeDownCast(this->Filter->GetOutputDataObject(0)));
    return w ? vtkBaryConversion::ArrayToMatrix(w) : bary::DenseWeights();
  }
};

/// @p n model vertices (every k-th, deterministic) plus the cage vertices and points on every
/// cage edge (2D) at t = 0.25, 0.5.
vtkSmartPointer<vtkPolyData> Samples(vtkDataSet* model, vtkPolyData* cage, int n, bool edges)
{
  std::vector<std::array<double, 3>> xs;
  const vtkIdType step = std::max<vtkIdType>(1, model->GetNumberOfPoints() / n);
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); i += step)
  {
    std::array<double, 3> x;
    model->GetPoint(i, x.data());
    xs.push_back(x);
  }
  const vtkIdType nc = cage->GetNumberOfPoints();
  for (vtkIdType i = 0; i < nc; ++i)
  {
    std::array<double, 3> a, b;
    cage->GetPoint(i, a.data());
    xs.push_back(a);
    if (!edges)
      continue;
    cage->GetPoint((i + 1) % nc, b.data());
    for (double t : { 0.25, 0.5 })
      xs.push_back({ (1 - t) * a[0] + t * b[0], (1 - t) * a[1] + t * b[1], (1 - t) * a[2] + t * b[2] });
  }
  return MakePointCloud(xs);
}

/// Partition of unity, reproduction (relative to the cage diameter) and non-negativity.
void ExpectBarycentric(const bary::DenseWeights& W, vtkDataSet* points, vtkPolyData* cage,
  int dim, double tolerance)
{
  const Eigen::MatrixXd C = vtkBaryConversion::ToMatrix(cage->GetPoints(), dim);
  const Eigen::MatrixXd P = vtkBaryConversion::PointsToMatrix(points, dim);
  ASSERT_EQ(W.rows(), P.rows());
  ASSERT_EQ(W.cols(), C.rows());
  const double diameter = vtkBaryConversion::ToCage(cage).Cage.diameter();
  const double partition = (W.rowwise().sum().array() - 1.0).abs().maxCoeff();
  const double reproduction = (W * C - P).rowwise().norm().maxCoeff() / diameter;
  EXPECT_LE(partition, tolerance);
  EXPECT_LE(reproduction, tolerance);
  EXPECT_GE(W.minCoeff(), -1e-15);
  std::printf("[ info ] %dD: %ld points, partition %.1e, reproduction %.1e, min %.1e\n", dim,
    static_cast<long>(W.rows()), partition, reproduction, W.minCoeff());
}

std::string SharedLBC()
{
  return std::string(BARYLAB_SHARED_DIR) + "/lbc";
}
} // namespace

TEST(vtkBaryCoordinatesLBC, MethodNameAndDefaults)
{
  EXPECT_STREQ(vtkBaryWeightMethod::GetMethodName(vtkBaryWeightMethod::LBC), "lbc");
  EXPECT_EQ(vtkBaryWeightMethod::GetMethodFromName("lbc"), vtkBaryWeightMethod::LBC);
  EXPECT_EQ(vtkBaryWeightMethod::NUMBER_OF_METHODS, 7);
  vtkNew<vtkBaryCoordinates> f;
  const bary::LBCOptions core;
  EXPECT_EQ(f->GetWeightMethod()->GetLBCLocality(), vtkBaryWeightMethod::LBC_LOCALITY_SQUARED);
  EXPECT_EQ(f->GetWeightMethod()->GetLBCRelaxedEpsilon(), core.relaxed_tv_epsilon);
  EXPECT_EQ(f->GetWeightMethod()->GetLBCPrimalTolerance(), core.primal_tolerance);
  EXPECT_EQ(f->GetWeightMethod()->GetLBCDualTolerance(), core.dual_tolerance);
  EXPECT_EQ(f->GetWeightMethod()->GetLBCMaximumIterations(), core.max_iterations);
  EXPECT_EQ(f->GetWeightMethod()->GetLBCDistanceNormalization(), vtkBaryWeightMethod::LBC_NORMALIZE_PER_CONTROL_POINT);
  EXPECT_FALSE(f->GetWeightMethod()->GetLBCUnconstrained());
  f->GetWeightMethod()->SetLBCMaximumIterations(0);
  EXPECT_EQ(f->GetWeightMethod()->GetLBCMaximumIterations(), 1); // clamped
}

TEST(vtkBaryCoordinatesLBC, BarycentricPropertiesOnTheBundled2DCage)
{
  auto cage = ReadData("cage2d.obj");
  auto model = ReadData("model2d.obj");
  ASSERT_TRUE(cage && model);
  auto points = Samples(model, cage, 150, true);
  LBC lbc(points, cage, 800);
  lbc.Filter->GetWeightMethod()->InsertPointsIntoMeshOn();
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  const bary::DenseWeights W = lbc.Weights();
  ExpectBarycentric(W, points, cage, 2, 1e-10);
  // Lagrange at the cage vertices, linear along the cage edges (3 rows per cage vertex at the end)
  const int nc = 20;
  const Eigen::Index first = W.rows() - 3 * nc;
  double lagrange = 0, linear = 0;
  for (int i = 0; i < nc; ++i)
  {
    const int j = (i + 1) % nc;
    for (int k = 0; k < nc; ++k)
    {
      lagrange = std::max(lagrange, std::abs(W(first + 3 * i, k) - (k == i ? 1.0 : 0.0)));
      const double t[2] = { 0.25, 0.5 };
      for (int e = 0; e < 2; ++e)
      {
        const double expected = k == i ? 1 - t[e] : k == j ? t[e] : 0.0;
        linear = std::max(linear, std::abs(W(first + 3 * i + 1 + e, k) - expected));
      }
    }
  }
  EXPECT_LE(lagrange, 1e-12);
  EXPECT_LE(linear, 1e-12);
  EXPECT_EQ(lbc.Filter->GetNumberOfOutsidePoints(), 0);
}

TEST(vtkBaryCoordinatesLBC, BarycentricPropertiesOnTheBundled3DCage)
{
  auto cage = ReadData("cage3d.obj");
  auto model = ReadData("model3d.off");
  ASSERT_TRUE(cage && model);
  auto points = Samples(model, cage, 60, false);
  LBC lbc(points, cage, 600);
  lbc.Filter->GetWeightMethod()->InsertPointsIntoMeshOn();
  // the properties hold at any stop: the paper's rule keeps this test short (the converged
  // default takes about 5 times its iterations here)
  lbc.Filter->GetWeightMethod()->SetLBCStoppingToPaper();
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const bary::DenseWeights W = lbc.Weights();
  ExpectBarycentric(W, points, cage, 3, 1e-10);
  const int nc = 72;
  const Eigen::Index first = W.rows() - nc;
  double lagrange = 0;
  for (int i = 0; i < nc; ++i)
    for (int k = 0; k < nc; ++k)
      lagrange = std::max(lagrange, std::abs(W(first + i, k) - (k == i ? 1.0 : 0.0)));
  EXPECT_LE(lagrange, 1e-12);
  std::printf("[ info ] kidney cage (72 control points): %.0f mesh vertices, %.0f tets, %.0f "
              "iterations, %.2f s\n",
    lbc.Filter->GetStatistic("mesh_vertices"), lbc.Filter->GetStatistic("mesh_cells"),
    lbc.Filter->GetStatistic("iterations"), seconds);
  EXPECT_EQ(lbc.Filter->GetStatistic("converged"), 1.0);
}

TEST(vtkBaryCoordinatesLBC, FilterEqualsCoreOnTheSameMesh)
{
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(cage);
  const vtkBaryCage c = vtkBaryConversion::ToCage(cage);
  bary::PolygonMeshOptions mo;
  mo.target_cells = 600;
  const bary::DomainMesh mesh = bary::mesh_polygon(c.Cage, mo);
  bary::LBCOptions options;
  options.threads = 1;
  const bary::LBCResult core = bary::local_barycentric_coordinates(mesh, options);

  // the filter meshes the same cage with the same options (deterministic) and evaluates at the
  // mesh's vertices
  std::vector<std::array<double, 3>> xs;
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
    xs.push_back({ mesh.V(v, 0), mesh.V(v, 1), 0.0 });
  auto points = MakePointCloud(xs);
  LBC lbc(points, cage, 600);
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  const bary::DenseWeights W = lbc.Weights();
  ASSERT_EQ(W.rows(), core.W.rows());
  EXPECT_LE((W - core.W).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(lbc.Filter->GetStatistic("iterations"), core.iterations);
  EXPECT_EQ(lbc.Filter->GetStatistic("objective"), core.objective);
  EXPECT_EQ(lbc.Filter->GetStatistic("mesh_vertices"), mesh.num_vertices());

  // every statistic is there, converged and consistent
  for (const char* name : { "mesh_vertices", "mesh_cells", "iterations", "primal_residual",
         "dual_residual", "primal_threshold", "dual_threshold", "objective", "converged",
         "partition_error", "reproduction_error", "geodesic_seconds", "factor_seconds",
         "admm_seconds", "solve_seconds" })
    EXPECT_TRUE(std::isfinite(lbc.Filter->GetStatistic(name))) << name;
  EXPECT_EQ(lbc.Filter->GetStatistic("converged"), 1.0);
  EXPECT_LE(lbc.Filter->GetStatistic("primal_residual"), lbc.Filter->GetStatistic("primal_threshold"));
  EXPECT_LE(lbc.Filter->GetStatistic("dual_residual"), lbc.Filter->GetStatistic("dual_threshold"));
  EXPECT_LE(lbc.Filter->GetStatistic("partition_error"), 1e-13);
  EXPECT_EQ(lbc.Filter->GetStatistic("threads"), 1.0); // NumberOfThreads 0 -> one thread

  // the parameters reach the core: a linear locality function changes the solution
  lbc.Filter->GetWeightMethod()->SetLBCLocalityToLinear();
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  options.locality = bary::LocalityFunction::Linear;
  const bary::LBCResult linear = bary::local_barycentric_coordinates(mesh, options);
  EXPECT_LE((lbc.Weights() - linear.W).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT((linear.W - core.W).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(vtkBaryCoordinatesLBC, ResultsDoNotDependOnTheThreadCount)
{
  auto cage = ReadData("cage2d.obj");
  auto model = ReadData("model2d.obj");
  ASSERT_TRUE(cage && model);
  auto points = Samples(model, cage, 300, false);
  bary::DenseWeights first;
  for (int threads : { 1, 2, 0 })
  {
    LBC lbc(points, cage, 600);
    lbc.Filter->GetWeightMethod()->SetNumberOfThreads(threads);
    ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
    std::printf("[ info ] NumberOfThreads %d: ADMM %.3f s, total %.3f s (%.0f iterations)\n",
      threads, lbc.Filter->GetStatistic("admm_seconds"), lbc.Filter->GetStatistic("solve_seconds"),
      lbc.Filter->GetStatistic("iterations"));
    if (first.size() == 0)
      first = lbc.Weights();
    else
      EXPECT_EQ((lbc.Weights() - first).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(vtkBaryCoordinatesLBC, AuthorsTriangulationOnInputTwo)
{
  const std::string dir = SharedLBC();
  if (!std::filesystem::exists(dir + "/reference/LBClogo.mesh.obj"))
    GTEST_SKIP() << "shared data not found in " << dir;
  auto cage = vtkBaryDataIO::ReadPolyData(dir + "/cages/LBClogo-control-edgeset.obj");
  auto mesh = vtkBaryDataIO::Read(dir + "/reference/LBClogo.mesh.obj");
  std::vector<int> control;
  {
    std::ifstream in(dir + "/reference/LBClogo.ctrl_idx.txt");
    for (int id; in >> id;)
      control.push_back(id);
  }
  ASSERT_EQ(control.size(), 6u);
  // the core on the authors' mesh with their control indices
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  vtkBaryConversion::ToSimplices(mesh, 2, V, T);
  const vtkBaryCage c = vtkBaryConversion::ToCage(cage);
  ASSERT_EQ(c.Cage.num_controls(), 6);
  const bary::DomainMesh domain = bary::domain_mesh_from_simplices(c.Cage, V, T,
    Eigen::Map<Eigen::VectorXi>(control.data(), static_cast<Eigen::Index>(control.size())), 1e-6);
  bary::LBCOptions options;
  options.threads = 1;
  options.distance_normalization = bary::DistanceNormalization::Global; // as the authors' code
  const bary::LBCResult core = bary::local_barycentric_coordinates(domain, options);

  // the filter: the same mesh on input 2, weights at its vertices
  LBC lbc(mesh, cage, 0);
  lbc.Filter->SetDomainData(mesh);
  lbc.Filter->GetWeightMethod()->SetLBCDistanceNormalization(vtkBaryWeightMethod::LBC_NORMALIZE_GLOBAL);
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  const bary::DenseWeights W = lbc.Weights();
  ASSERT_EQ(W.rows(), V.rows());
  EXPECT_LE((W - core.W).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(lbc.Filter->GetStatistic("mesh_vertices"), V.rows());
  EXPECT_EQ(lbc.Filter->GetStatistic("mesh_cells"), T.rows());
  EXPECT_EQ(lbc.Filter->GetStatistic("converged"), 1.0);
  // the authors' weights on that mesh (their solver's own tolerance: 1e-2 max, as in core's test)
  std::ifstream in(dir + "/reference/LBClogo.weights.txt");
  std::string header;
  std::getline(in, header);
  bary::DenseWeights reference(V.rows(), 6);
  for (Eigen::Index r = 0; r < reference.rows(); ++r)
    for (Eigen::Index k = 0; k < 6; ++k)
      in >> reference(r, k);
  ASSERT_TRUE(static_cast<bool>(in));
  const double diff = (W - reference).cwiseAbs().maxCoeff();
  std::printf("[ info ] LBClogo on the authors' mesh: %.0f iterations, %.3f s, max |W - W_ref| "
              "%.1e\n",
    lbc.Filter->GetStatistic("iterations"), lbc.Filter->GetStatistic("solve_seconds"), diff);
  EXPECT_LT(diff, 0.01);
  EXPECT_TRUE(lbc.Observer->Warnings.empty()) << lbc.Observer->AllWarnings();
  // meshing settings do not apply to a given mesh: said, not silently dropped
  lbc.Filter->GetWeightMethod()->InsertPointsIntoMeshOn();
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  EXPECT_TRUE(lbc.Observer->HasWarning("InsertPointsIntoMesh is ignored")) << lbc.Observer->AllWarnings();
}

TEST(vtkBaryCoordinatesLBC, CageVertexMissingFromTheDomainMeshIsNamed)
{
  // a mesh of the unit square, a cage with a fifth vertex above it
  auto square = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, ids);
  square->SetPolys(polys);
  vtkNew<vtkBaryCageMesher> mesher;
  mesher->SetCageData(square);
  mesher->SetTargetNumberOfCells(200);
  mesher->Update();
  auto pentagon = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0.5, 1.5, 0 }, { 0, 1, 0 } });
  LBC lbc(mesher->GetOutput(), pentagon, 0);
  lbc.Filter->SetDomainConnection(mesher->GetOutputPort());
  EXPECT_EQ(lbc.Run(), 0);
  EXPECT_TRUE(lbc.Observer->HasError("cage vertex 3 at (0.5, 1.5)")) << lbc.Observer->AllErrors();

  // a tetrahedral domain for a 2D cage
  LBC wrong(mesher->GetOutput(), square, 0);
  vtkNew<vtkBaryCageMesher> tets;
  tets->SetCageData(MakeCube());
  tets->SetTargetNumberOfCells(100);
  wrong.Filter->SetDomainConnection(tets->GetOutputPort());
  EXPECT_EQ(wrong.Run(), 0);
  EXPECT_TRUE(wrong.Observer->HasError("made of tetrahedra but the cage is 2D"))
    << wrong.Observer->AllErrors();
}

TEST(vtkBaryCoordinatesLBC, NonConvergenceIsAnError)
{
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(cage);
  LBC lbc(Samples(cage, cage, 20, false), cage, 300);
  lbc.Filter->GetWeightMethod()->SetLBCMaximumIterations(1);
  EXPECT_EQ(lbc.Run(), 0);
  EXPECT_TRUE(lbc.Observer->HasError("did not converge in 1 iterations")) << lbc.Observer->AllErrors();
  EXPECT_TRUE(lbc.Observer->HasError("raise LBCMaximumIterations (--max-iterations)"))
    << lbc.Observer->AllErrors();
}

TEST(vtkBaryCoordinatesLBC, ProgressAndCancel)
{
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(cage);
  LBC lbc(Samples(cage, cage, 20, false), cage, 600);
  std::vector<double> fractions;
  vtkNew<vtkCallbackCommand> record;
  record->SetClientData(&fractions);
  record->SetCallback([](vtkObject*, unsigned long, void* client, void* data) {
    static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(data));
  });
  lbc.Filter->AddObserver(vtkCommand::ProgressEvent, record);
  ASSERT_EQ(lbc.Run(), 1) << lbc.Observer->AllErrors();
  ASSERT_GT(fractions.size(), 5u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_GE(fractions.back(), 0.95);
  // cancel in the middle of the ADMM
  LBC cancelled(Samples(cage, cage, 20, false), cage, 600);
  vtkNew<vtkCallbackCommand> abort;
  abort->SetCallback([](vtkObject* caller, unsigned long, void*, void* data) {
    if (*static_cast<double*>(data) > 0.3)
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
  });
  cancelled.Filter->AddObserver(vtkCommand::ProgressEvent, abort);
  EXPECT_EQ(cancelled.Run(), 0);
  EXPECT_TRUE(cancelled.Observer->HasError("cancelled")) << cancelled.Observer->AllErrors();
}

TEST(vtkBaryCoordinatesLBC, CageDeformationRecomputesWhenAnLBCParameterChanges)
{
  // vtkBaryCageDeformation shares the settings (its vtkBaryWeightMethod) and keys its weight cache
  // on them: the posed cage alone reuses the weights, an LBC parameter recomputes them.
  auto cage = ReadData("cage2d.obj");
  auto posed = ReadData("cage2d_posed.obj");
  ASSERT_TRUE(cage && posed);
  vtkNew<vtkBaryCageDeformation> deform;
  vtkNew<ErrorObserver> observer;
  observer->Attach(deform);
  deform->GetWeightMethod()->SetMethod(vtkBaryWeightMethod::LBC);
  deform->GetWeightMethod()->SetTargetNumberOfCells(300);
  deform->SetInputData(Samples(cage, cage, 20, false));
  deform->SetRestCageData(cage);
  deform->SetDeformedCageData(posed);
  ASSERT_EQ(RunPipeline(deform), 1) << observer->AllErrors();
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 1);
  // the cage vertices (Lagrange) move exactly onto the posed cage's
  vtkPointSet* out = deform->GetOutput();
  double worst = 0;
  for (vtkIdType i = 0; i < 20; ++i)
  {
    double a[3], b[3];
    out->GetPoint(out->GetNumberOfPoints() - 20 + i, a);
    posed->GetPoint(i, b);
    worst = std::max(worst, std::hypot(a[0] - b[0], a[1] - b[1]));
  }
  EXPECT_LE(worst, 1e-12);
  deform->GetWeightMethod()->SetLBCLocality(vtkBaryWeightMethod::LBC_LOCALITY_CONSTANT);
  ASSERT_EQ(RunPipeline(deform), 1) << observer->AllErrors();
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 2);
  deform->GetWeightMethod()->SetLBCDualTolerance(1e-6);
  ASSERT_EQ(RunPipeline(deform), 1) << observer->AllErrors();
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 3);
}
