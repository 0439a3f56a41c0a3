// Tests of vtkBaryCoordinates: output arrays and type, the properties of mean value
// coordinates on the bundled data (partition of unity, linear reproduction, Lagrange property),
// the cage point <-> component correspondence, location counts, every error path, progress and
// cancellation.
#include "filters_test_utils.h"

#include "vtkBaryCoordinates.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkPointSource.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace
{
using namespace barylab_test;

/// A filter with an error observer attached; Run() updates it and returns the executive's verdict.
struct Coordinates
{
  vtkNew<vtkBaryCoordinates> Filter;
  vtkNew<ErrorObserver> Observer;

  Coordinates(vtkDataSet* input, vtkPolyData* cage)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->SetInputData(0, input);
    if (cage)
      this->Filter->SetCageData(cage);
  }
  int Run() { return RunPipeline(this->Filter); }
  vtkDataSet* Output() { return vtkDataSet::SafeDownCast(this->Filter->GetOutputDataObject(0)); }
  vtkDataArray* Weights()
  {
    return GetWeights(this->Output(), this->Filter->GetWeightsArrayName());
  }
};

/// Max over points of |sum_i w_i - 1| and of |sum_i w_i c_i - x| (first @p dim coordinates).
void ExpectPartitionAndReproduction(
  vtkDataSet* data, vtkDataArray* W, vtkPolyData* cage, int dim, double tolerance)
{
  ASSERT_NE(W, nullptr);
  ASSERT_EQ(W->GetNumberOfComponents(), cage->GetNumberOfPoints());
  ASSERT_EQ(W->GetNumberOfTuples(), data->GetNumberOfPoints());
  double worst_sum = 0.0, worst_x = 0.0;
  for (vtkIdType p = 0; p < data->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3] = { 0, 0, 0 }, sum = 0.0;
    data->GetPoint(p, x);
    for (vtkIdType i = 0; i < cage->GetNumberOfPoints(); ++i)
    {
      const double w = W->GetComponent(p, static_cast<int>(i));
      double c[3];
      cage->GetPoint(i, c);
      sum += w;
      for (int k = 0; k < dim; ++k)
        y[k] += w * c[k];
    }
    worst_sum = std::max(worst_sum, std::abs(sum - 1.0));
    for (int k = 0; k < dim; ++k)
      worst_x = std::max(worst_x, std::abs(y[k] - x[k]));
  }
  EXPECT_LE(worst_sum, tolerance) << "partition of unity";
  EXPECT_LE(worst_x, tolerance) << "linear reproduction";
}

/// Expects row p of @p W to be the unit vector e_p (evaluation at the cage points themselves).
void ExpectLagrange(vtkDataArray* W, vtkIdType n, double tolerance)
{
  ASSERT_NE(W, nullptr);
  ASSERT_EQ(W->GetNumberOfTuples(), n);
  ASSERT_EQ(W->GetNumberOfComponents(), n);
  for (vtkIdType p = 0; p < n; ++p)
    for (vtkIdType i = 0; i < n; ++i)
      EXPECT_NEAR(W->GetComponent(p, static_cast<int>(i)), p == i ? 1.0 : 0.0, tolerance)
        << "cage point " << p << ", component " << i;
}

/// Records progress events; an optional hook may act on the algorithm (e.g. abort it).
class ProgressRecorder : public vtkCommand
{
public:
  static ProgressRecorder* New() { return new ProgressRecorder; }
  void Execute(vtkObject* caller, unsigned long, void* data) override
  {
    const double f = *static_cast<double*>(data);
    this->Values.push_back(f);
    if (this->Hook)
      this->Hook(vtkAlgorithm::SafeDownCast(caller), f);
  }
  std::vector<double> Values;
  std::function<void(vtkAlgorithm*, double)> Hook;
};

vtkSmartPointer<vtkPolyData> ManyPointsInsideCube(int n)
{
  vtkNew<vtkPointSource> source;
  source->SetNumberOfPoints(n);
  source->SetRadius(0.9);
  source->SetCenter(0, 0, 0);
  source->SetRandomSequence(nullptr);
  source->Update();
  return source->GetOutput();
}

// ---------------------------------------------------------------------------------------------
// Output arrays and output type
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCoordinates, DefaultArraysOneComponentPerCagePoint)
{
  vtkNew<vtkBaryCoordinates> defaults;
  EXPECT_STREQ(defaults->GetWeightsArrayName(), "Weights");
  EXPECT_STREQ(defaults->GetLocationArrayName(), "CageLocation");
  EXPECT_EQ(defaults->GetWeightMethod()->GetMethod(), vtkBaryWeightMethod::MEAN_VALUE);

  auto cube = MakeCube();
  auto points = MakePointCloud({ { 0, 0, 0 }, { 0.5, -0.25, 0.1 } });
  Coordinates c(points, cube);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  vtkDataArray* W = GetWeights(c.Output(), "Weights");
  ASSERT_NE(W, nullptr);
  EXPECT_EQ(W->GetNumberOfComponents(), 8);
  EXPECT_EQ(W->GetNumberOfTuples(), 2);
  vtkDataArray* location = c.Output()->GetPointData()->GetArray("CageLocation");
  ASSERT_NE(location, nullptr);
  EXPECT_NE(vtkUnsignedCharArray::SafeDownCast(location), nullptr);
  // Inside a convex cage mean value coordinates are positive. (They are not 1/8 at the centre:
  // they depend on how the faces are triangulated.)
  for (int i = 0; i < 8; ++i)
    EXPECT_GT(W->GetComponent(0, i), 0.0);
  ExpectPartitionAndReproduction(c.Output(), W, cube, 3, 1e-14);
  EXPECT_TRUE(c.Observer->Errors.empty()) << c.Observer->AllErrors();
}

TEST(vtkBaryCoordinates, ArrayNamesAreSettable)
{
  auto cube = MakeCube();
  auto points = MakePointCloud({ { 0.1, 0.2, 0.3 } });
  Coordinates c(points, cube);
  c.Filter->SetWeightsArrayName("MVC");
  c.Filter->SetLocationArrayName("Where");
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_EQ(GetWeights(c.Output(), "Weights"), nullptr);
  EXPECT_EQ(c.Output()->GetPointData()->GetArray("CageLocation"), nullptr);
  ASSERT_NE(GetWeights(c.Output(), "MVC"), nullptr);
  EXPECT_EQ(GetWeights(c.Output(), "MVC")->GetNumberOfComponents(), 8);
  EXPECT_NE(c.Output()->GetPointData()->GetArray("Where"), nullptr);

  c.Filter->GenerateLocationOff();
  ASSERT_EQ(c.Run(), 1);
  EXPECT_EQ(c.Output()->GetPointData()->GetArray("Where"), nullptr);
  EXPECT_NE(GetWeights(c.Output(), "MVC"), nullptr);
}

TEST(vtkBaryCoordinates, EmptyWeightsArrayNameIsAnError)
{
  auto cube = MakeCube();
  auto points = MakePointCloud({ { 0.1, 0.2, 0.3 } });
  Coordinates c(points, cube);
  c.Filter->SetWeightsArrayName("");
  EXPECT_EQ(c.Run(), 0);
  EXPECT_TRUE(c.Observer->HasError("WeightsArrayName")) << c.Observer->AllErrors();
}

TEST(vtkBaryCoordinates, PolyDataInPolyDataOut)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  Coordinates c(model, cage);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  auto* out = vtkPolyData::SafeDownCast(c.Output());
  ASSERT_NE(out, nullptr) << c.Output()->GetClassName();
  EXPECT_EQ(out->GetNumberOfPolys(), model->GetNumberOfPolys()); // cells are passed
  EXPECT_EQ(out->GetNumberOfPoints(), model->GetNumberOfPoints());
}

TEST(vtkBaryCoordinates, UnstructuredGridInUnstructuredGridOut)
{
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(-0.5, -0.5, -0.5);
  points->InsertNextPoint(0.5, -0.5, -0.5);
  points->InsertNextPoint(0.0, 0.5, -0.5);
  points->InsertNextPoint(0.0, 0.0, 0.5);
  points->InsertNextPoint(0.9, 0.9, 0.9);
  grid->SetPoints(points);
  const vtkIdType tet[4] = { 0, 1, 2, 3 };
  grid->InsertNextCell(VTK_TETRA, 4, tet);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  for (int i = 0; i < 5; ++i)
    temperature->InsertNextValue(20.0 + i);
  grid->GetPointData()->AddArray(temperature);

  auto cube = MakeCube();
  Coordinates c(grid, cube);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  auto* out = vtkUnstructuredGrid::SafeDownCast(c.Output());
  ASSERT_NE(out, nullptr) << c.Output()->GetClassName();
  EXPECT_EQ(out->GetNumberOfCells(), 1);
  EXPECT_EQ(out->GetCellType(0), VTK_TETRA);
  ASSERT_NE(out->GetPointData()->GetArray("Temperature"), nullptr) << "input arrays are passed";
  EXPECT_EQ(out->GetPointData()->GetArray("Temperature")->GetComponent(4, 0), 24.0);
  ExpectPartitionAndReproduction(out, c.Weights(), cube, 3, 1e-13);
}

TEST(vtkBaryCoordinates, ImageDataInput)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 5, 3);
  image->SetOrigin(-0.75, -0.8, -0.5);
  image->SetSpacing(0.5, 0.4, 0.5);
  auto cube = MakeCube();
  Coordinates c(image, cube);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  auto* out = vtkImageData::SafeDownCast(c.Output());
  ASSERT_NE(out, nullptr) << c.Output()->GetClassName();
  int dims[3];
  out->GetDimensions(dims);
  EXPECT_EQ(dims[0] * dims[1] * dims[2], 60);
  ASSERT_NE(c.Weights(), nullptr);
  EXPECT_EQ(c.Weights()->GetNumberOfTuples(), 60);
  ExpectPartitionAndReproduction(out, c.Weights(), cube, 3, 1e-13);
  EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), 60);
}

TEST(vtkBaryCoordinates, MethodNames)
{
  EXPECT_STREQ(vtkBaryWeightMethod::GetMethodName(vtkBaryWeightMethod::MEAN_VALUE), "mvc");
  EXPECT_EQ(vtkBaryWeightMethod::GetMethodFromName("mvc"), vtkBaryWeightMethod::MEAN_VALUE);
  EXPECT_EQ(vtkBaryWeightMethod::GetMethodFromName("harmonic?"), -1);
  EXPECT_EQ(vtkBaryWeightMethod::GetMethodFromName(nullptr), -1);
  EXPECT_EQ(vtkBaryWeightMethod::GetMethodName(-1), nullptr);
  EXPECT_EQ(vtkBaryWeightMethod::GetMethodName(vtkBaryWeightMethod::NUMBER_OF_METHODS), nullptr);
}

// ---------------------------------------------------------------------------------------------
// Properties on the bundled data
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCoordinates, PartitionAndReproduction2D)
{
  auto model = ReadData("model2d.obj");
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(model && cage);
  ASSERT_EQ(cage->GetNumberOfPoints(), 20);
  Coordinates c(model, cage);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  ExpectPartitionAndReproduction(c.Output(), c.Weights(), cage, 2, 1e-12);
  // data/README.md: every model vertex is at least 0.025 inside the cage.
  EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), model->GetNumberOfPoints());
  EXPECT_EQ(c.Filter->GetNumberOfOutsidePoints(), 0);
  EXPECT_EQ(c.Filter->GetNumberOfBoundaryPoints(), 0);
  EXPECT_EQ(c.Filter->GetNumberOfUndefinedPoints(), 0);
}

TEST(vtkBaryCoordinates, PartitionAndReproduction3D)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  ASSERT_EQ(cage->GetNumberOfPoints(), 72);
  Coordinates c(model, cage);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  ExpectPartitionAndReproduction(c.Output(), c.Weights(), cage, 3, 1e-12);
  // data/README.md: every model vertex has winding number 1 w.r.t. the cage.
  EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), model->GetNumberOfPoints());
  EXPECT_EQ(c.Filter->GetNumberOfOutsidePoints(), 0);
}

TEST(vtkBaryCoordinates, LagrangeAtCageVertices2D)
{
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(cage);
  auto at_vertices = PointsOnly(cage);
  Coordinates c(at_vertices, cage);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  ExpectLagrange(c.Weights(), 20, 1e-12);
  EXPECT_EQ(c.Filter->GetNumberOfBoundaryPoints(), 20);
}

TEST(vtkBaryCoordinates, LagrangeAtCageVertices3D)
{
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(cage);
  auto at_vertices = PointsOnly(cage);
  Coordinates c(at_vertices, cage);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  ExpectLagrange(c.Weights(), 72, 1e-12);
  EXPECT_EQ(c.Filter->GetNumberOfBoundaryPoints(), 72);
}

/// Query points for the 2D tests: the model's vertices and a few points outside the cage.
vtkSmartPointer<vtkPolyData> Queries2D()
{
  auto model = ReadData("model2d.obj");
  auto q = PointsOnly(model);
  q->GetPoints()->InsertNextPoint(1.5, 0.3, 0.0);
  q->GetPoints()->InsertNextPoint(0.0, -0.7, 0.0); // between the legs
  return q;
}

TEST(vtkBaryCoordinates, PolygonCellWithPermutedPointsKeepsComponentPerPoint)
{
  auto bare = ReadData("cage2d.obj"); // v lines only: polygon order = point order
  ASSERT_TRUE(bare);
  const vtkIdType n = bare->GetNumberOfPoints();
  ASSERT_EQ(n, 20);
  // Store the cage points in a shuffled order: permuted point j = bare point pi[j].
  std::vector<vtkIdType> pi(n), inverse(n);
  for (vtkIdType j = 0; j < n; ++j)
    pi[j] = (7 * j + 3) % n;
  for (vtkIdType j = 0; j < n; ++j)
    inverse[pi[j]] = j;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (vtkIdType j = 0; j < n; ++j)
    points->InsertNextPoint(bare->GetPoint(pi[j]));
  // One polygon cell walking the same polygon, starting at bare vertex 5.
  std::vector<vtkIdType> ids;
  for (vtkIdType k = 0; k < n; ++k)
    ids.push_back(inverse[(5 + k) % n]);
  vtkNew<vtkCellArray> polys;
  polys->InsertNextCell(n, ids.data());
  vtkNew<vtkPolyData> permuted;
  permuted->SetPoints(points);
  permuted->SetPolys(polys);

  auto queries = Queries2D();
  Coordinates a(queries, bare);
  Coordinates b(queries, permuted);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();
  ASSERT_EQ(b.Run(), 1) << b.Observer->AllErrors();
  vtkDataArray* WA = a.Weights();
  vtkDataArray* WB = b.Weights();
  ASSERT_TRUE(WA && WB);
  ASSERT_EQ(WB->GetNumberOfComponents(), n);
  double worst = 0.0;
  for (vtkIdType p = 0; p < queries->GetNumberOfPoints(); ++p)
    for (vtkIdType j = 0; j < n; ++j)
      worst = std::max(worst,
        std::abs(
          WB->GetComponent(p, static_cast<int>(j)) - WA->GetComponent(p, static_cast<int>(pi[j]))));
  EXPECT_LE(worst, 1e-12) << "component j of the permuted cage must be the weight of its point j";
  ExpectPartitionAndReproduction(b.Output(), WB, permuted, 2, 1e-12);

  // Lagrange at the permuted cage's own points: component j is 1 at point j.
  auto at_vertices = PointsOnly(permuted);
  Coordinates l(at_vertices, permuted);
  ASSERT_EQ(l.Run(), 1) << l.Observer->AllErrors();
  ExpectLagrange(l.Weights(), n, 1e-12);
}

TEST(vtkBaryCoordinates, PolygonCellRotationAndReversalGiveTheSameWeights)
{
  auto bare = ReadData("cage2d.obj");
  ASSERT_TRUE(bare);
  const vtkIdType n = bare->GetNumberOfPoints();
  auto queries = Queries2D();
  Coordinates a(queries, bare);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();

  for (int reversed = 0; reversed < 2; ++reversed)
  {
    std::vector<vtkIdType> ids;
    for (vtkIdType k = 0; k < n; ++k)
      ids.push_back(reversed ? (n + 11 - k) % n : (k + 11) % n);
    vtkNew<vtkCellArray> polys;
    polys->InsertNextCell(n, ids.data());
    vtkNew<vtkPolyData> cage;
    cage->SetPoints(bare->GetPoints());
    cage->SetPolys(polys);
    Coordinates b(queries, cage);
    ASSERT_EQ(b.Run(), 1) << b.Observer->AllErrors();
    double worst = 0.0;
    for (vtkIdType p = 0; p < queries->GetNumberOfPoints(); ++p)
      for (int j = 0; j < n; ++j)
        worst = std::max(
          worst, std::abs(b.Weights()->GetComponent(p, j) - a.Weights()->GetComponent(p, j)));
    EXPECT_LE(worst, 1e-12) << (reversed ? "reversed" : "rotated") << " polygon cell";
  }
}

TEST(vtkBaryCoordinates, ResultsDoNotDependOnThreads)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  Coordinates one(model, cage), two(model, cage);
  one.Filter->GetWeightMethod()->SetNumberOfThreads(1);
  two.Filter->GetWeightMethod()->SetNumberOfThreads(2);
  ASSERT_EQ(one.Run(), 1);
  ASSERT_EQ(two.Run(), 1);
  vtkDataArray* W1 = one.Weights();
  vtkDataArray* W2 = two.Weights();
  ASSERT_TRUE(W1 && W2);
  bool identical = true;
  for (vtkIdType p = 0; p < W1->GetNumberOfTuples() && identical; ++p)
    for (int i = 0; i < W1->GetNumberOfComponents(); ++i)
      identical = identical && W1->GetComponent(p, i) == W2->GetComponent(p, i);
  EXPECT_TRUE(identical);
}

// ---------------------------------------------------------------------------------------------
// Location counts
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCoordinates, LocationCounts3D)
{
  auto cube = MakeCube();
  // 3 inside, 2 outside, 3 on the cage (face, edge, vertex).
  auto points = MakePointCloud({ { 0, 0, 0 }, { 0.5, 0.2, -0.3 }, { 0.9, 0.9, 0.9 }, { 2, 0, 0 },
    { 0, -3, 1 }, { 1, 0.3, -0.2 }, { 1, 1, 0 }, { -1, -1, -1 } });
  const unsigned char expected[8] = { 0, 0, 0, 1, 1, 2, 2, 2 };
  Coordinates c(points, cube);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), 3);
  EXPECT_EQ(c.Filter->GetNumberOfOutsidePoints(), 2);
  EXPECT_EQ(c.Filter->GetNumberOfBoundaryPoints(), 3);
  EXPECT_EQ(c.Filter->GetNumberOfUndefinedPoints(), 0);
  vtkDataArray* location = c.Output()->GetPointData()->GetArray("CageLocation");
  ASSERT_NE(location, nullptr);
  for (int p = 0; p < 8; ++p)
    EXPECT_EQ(location->GetComponent(p, 0), expected[p]) << "point " << p;
  // Outside, mean value coordinates still reproduce linear functions.
  ExpectPartitionAndReproduction(c.Output(), c.Weights(), cube, 3, 1e-12);
  // On the face x = 1 the weights are barycentric in one of its triangles: the corners with
  // x = -1 get nothing.
  vtkDataArray* W = c.Weights();
  for (int i : { 0, 3, 4, 7 }) // corners with x = -1
    EXPECT_NEAR(W->GetComponent(5, i), 0.0, 1e-12) << "corner " << i;
}

TEST(vtkBaryCoordinates, LocationCounts2D)
{
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(cage);
  // inside the body, inside the head, outside, between the legs (outside), on vertex 5,
  // on the midpoint of edge 5-6 (the right hand). The points on the cage are taken from the
  // cage as read (exactly the doubles of the file, since vtkBaryOBJReader).
  double v5[3], v6[3];
  cage->GetPoint(5, v5);
  cage->GetPoint(6, v6);
  auto points = MakePointCloud({ { 0, 0, 0 }, { 0, 0.6, 0 }, { 2, 2, 0 }, { 0, -0.7, 0 },
    { v5[0], v5[1], 0 }, { 0.5 * (v5[0] + v6[0]), 0.5 * (v5[1] + v6[1]), 0 } });
  const unsigned char expected[6] = { 0, 0, 1, 1, 2, 2 };
  Coordinates c(points, cage);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), 2);
  EXPECT_EQ(c.Filter->GetNumberOfOutsidePoints(), 2);
  EXPECT_EQ(c.Filter->GetNumberOfBoundaryPoints(), 2);
  vtkDataArray* location = c.Output()->GetPointData()->GetArray("CageLocation");
  ASSERT_NE(location, nullptr);
  for (int p = 0; p < 6; ++p)
    EXPECT_EQ(location->GetComponent(p, 0), expected[p]) << "point " << p;
  vtkDataArray* W = c.Weights();
  ASSERT_NE(W, nullptr);
  for (int i = 0; i < 20; ++i)
  {
    EXPECT_NEAR(W->GetComponent(4, i), i == 5 ? 1.0 : 0.0, 1e-12);
    EXPECT_NEAR(W->GetComponent(5, i), (i == 5 || i == 6) ? 0.5 : 0.0, 1e-12);
  }
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

/// Runs the filter on a few interior points with @p cage and expects a failure whose message
/// contains every string of @p needles, and no weights in the output.
void ExpectCageRejected(vtkPolyData* cage, const std::vector<std::string>& needles)
{
  auto points = MakePointCloud({ { 0, 0, 0 }, { 0.1, 0.2, 0.0 } });
  Coordinates c(points, cage);
  EXPECT_EQ(c.Run(), 0) << "the request must fail";
  for (const auto& needle : needles)
    EXPECT_TRUE(c.Observer->HasError(needle)) << "expected '" << needle << "' in:\n"
                                              << c.Observer->AllErrors();
  EXPECT_EQ(c.Weights(), nullptr);
}

TEST(vtkBaryCoordinates, OpenCageIsRejected)
{
  auto cage = ReadData("bad/open_cage.obj");
  ASSERT_TRUE(cage);
  ExpectCageRejected(cage, { "not closed", "edge (" });
}

TEST(vtkBaryCoordinates, OpenCageBuiltInCodeIsRejected)
{
  auto cube = MakeCube();
  vtkNew<vtkCellArray> polys; // drop the last face
  vtkIdType size;
  const vtkIdType* ids;
  for (vtkIdType f = 0; f < 11; ++f)
  {
    cube->GetPolys()->GetCellAtId(f, size, ids);
    polys->InsertNextCell(size, ids);
  }
  cube->SetPolys(polys);
  ExpectCageRejected(cube, { "not closed", "edge (" });
}

TEST(vtkBaryCoordinates, QuadCageIsRejected)
{
  auto cage = ReadData("bad/quad_cage.obj");
  ASSERT_TRUE(cage);
  ExpectCageRejected(cage, { "face ", "triangulated" });
}

TEST(vtkBaryCoordinates, NaNCageIsRejected)
{
  auto cube = MakeCube();
  cube->GetPoints()->SetPoint(6, 1.0, std::numeric_limits<double>::quiet_NaN(), 1.0);
  ExpectCageRejected(cube, { "non-finite", "6" });
}

TEST(vtkBaryCoordinates, InconsistentOrientationIsRejected)
{
  auto cage = ReadData("bad/inconsistent_cage.obj");
  ASSERT_TRUE(cage);
  ExpectCageRejected(cage, { "oriented", "edge (" });
}

TEST(vtkBaryCoordinates, BowtiePolygonIsRejected)
{
  auto cage = ReadData("bad/bowtie2d.obj");
  ASSERT_TRUE(cage);
  ExpectCageRejected(cage, { "not simple", "edge " });
}

TEST(vtkBaryCoordinates, EmptyCageIsRejected)
{
  vtkNew<vtkPolyData> empty;
  ExpectCageRejected(empty, { "no points" });
  vtkNew<vtkPolyData> no_points;
  vtkNew<vtkPoints> none;
  no_points->SetPoints(none);
  ExpectCageRejected(no_points, { "no points" });
}

TEST(vtkBaryCoordinates, MissingCageIsReported)
{
  auto points = MakePointCloud({ { 0, 0, 0 } });
  Coordinates c(points, nullptr);
  EXPECT_EQ(c.Run(), 0);
  EXPECT_FALSE(c.Observer->Errors.empty());
  EXPECT_TRUE(c.Observer->HasError("port 1")) << c.Observer->AllErrors();
  EXPECT_EQ(GetWeights(c.Output()), nullptr);
}

TEST(vtkBaryCoordinates, NonFiniteQueryPointIsRejected)
{
  auto points = MakePointCloud(
    { { 0, 0, 0 }, { std::numeric_limits<double>::infinity(), 0, 0 }, { 0.5, 0.5, 0.5 } });
  Coordinates c(points, MakeCube());
  EXPECT_EQ(c.Run(), 0);
  EXPECT_TRUE(c.Observer->HasError("non-finite")) << c.Observer->AllErrors();
  EXPECT_TRUE(c.Observer->HasError("point 1")) << c.Observer->AllErrors();
  EXPECT_EQ(c.Weights(), nullptr);
}

TEST(vtkBaryCoordinates, EmptyInputWarnsAndSucceeds)
{
  vtkNew<vtkPolyData> empty;
  Coordinates c(empty, MakeCube());
  EXPECT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_TRUE(c.Observer->Errors.empty()) << c.Observer->AllErrors();
  EXPECT_TRUE(c.Observer->HasWarning("no points")) << c.Observer->AllWarnings();
  ASSERT_NE(c.Output(), nullptr);
  EXPECT_EQ(c.Output()->GetNumberOfPoints(), 0);
  EXPECT_EQ(c.Filter->GetNumberOfInsidePoints(), 0);
}

TEST(vtkBaryCoordinates, PointsOffThePlaneOfA2DCageWarn)
{
  // A 2D cage ignores z: the weights of (x, y, z) are those of (x, y), with a warning.
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(cage);
  Coordinates flat(MakePointCloud({ { 0.1, 0.2, 0.0 }, { -0.1, 0.5, 0.0 } }), cage);
  Coordinates lifted(MakePointCloud({ { 0.1, 0.2, 3.0 }, { -0.1, 0.5, -1.0 } }), cage);
  ASSERT_EQ(flat.Run(), 1) << flat.Observer->AllErrors();
  ASSERT_EQ(lifted.Run(), 1) << lifted.Observer->AllErrors();
  EXPECT_TRUE(flat.Observer->Warnings.empty()) << flat.Observer->AllWarnings();
  EXPECT_TRUE(lifted.Observer->HasWarning("z")) << lifted.Observer->AllWarnings();
  for (int p = 0; p < 2; ++p)
    for (int i = 0; i < 20; ++i)
      EXPECT_EQ(lifted.Weights()->GetComponent(p, i), flat.Weights()->GetComponent(p, i));
}

TEST(vtkBaryCoordinates, ErrorThenRecovery)
{
  // A failed request must not poison the next one.
  auto points = MakePointCloud({ { 0.1, 0.2, 0.3 } });
  auto bad = ReadData("bad/open_cage.obj");
  Coordinates c(points, bad);
  EXPECT_EQ(c.Run(), 0);
  c.Filter->SetCageData(MakeCube());
  c.Observer->Clear();
  EXPECT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  ASSERT_NE(c.Weights(), nullptr);
  EXPECT_EQ(c.Weights()->GetNumberOfComponents(), 8);
}

// ---------------------------------------------------------------------------------------------
// Progress and cancellation
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCoordinates, ProgressIsARealIncreasingFraction)
{
  auto points = ManyPointsInsideCube(200000);
  ASSERT_EQ(points->GetNumberOfPoints(), 200000);
  Coordinates c(points, MakeCube());
  vtkNew<ProgressRecorder> progress;
  c.Filter->AddObserver(vtkCommand::ProgressEvent, progress);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  const auto& v = progress->Values;
  ASSERT_FALSE(v.empty());
  EXPECT_DOUBLE_EQ(v.back(), 1.0);
  for (std::size_t i = 1; i < v.size(); ++i)
    EXPECT_GE(v[i], v[i - 1]) << "progress went back at event " << i;
  const auto strictly_between =
    std::count_if(v.begin(), v.end(), [](double f) { return f > 0.0 && f < 1.0; });
  EXPECT_GE(strictly_between, 5) << "progress must be reported during the computation";
  for (double f : v)
  {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
  }
}

TEST(vtkBaryCoordinates, AbortFromProgressObserverCancels)
{
  auto points = ManyPointsInsideCube(200000);
  Coordinates c(points, MakeCube());
  vtkNew<ProgressRecorder> progress;
  progress->Hook = [](vtkAlgorithm* algorithm, double f)
  {
    if (f > 0.1 && f < 1.0)
      algorithm->SetAbortExecute(1);
  };
  c.Filter->AddObserver(vtkCommand::ProgressEvent, progress);
  EXPECT_EQ(c.Run(), 0);
  EXPECT_TRUE(c.Observer->HasError("cancelled")) << c.Observer->AllErrors();
  EXPECT_EQ(c.Weights(), nullptr);
  ASSERT_FALSE(progress->Values.empty());
  EXPECT_LT(progress->Values.back(), 0.5) << "the computation must stop soon after the abort";

  // Without the abort the same filter completes.
  progress->Hook = nullptr;
  c.Observer->Clear();
  c.Filter->Modified();
  EXPECT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  ASSERT_NE(c.Weights(), nullptr);
  EXPECT_EQ(c.Weights()->GetNumberOfTuples(), 200000);
}

} // namespace

TEST(vtkBaryCoordinates, CageIsRequestedWholeWhenAPieceIsRequested)
{
  // In VTK's parallel pipeline (ParaView, mpirun) the output is requested by pieces; the
  // points follow the piece, the cage must not: half a sphere is an open cage. vtkSphereSource
  // makes only the requested piece of itself, which shows whether the filter asks for it whole.
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(12);
  sphere->SetPhiResolution(8);
  sphere->UpdatePiece(1, 2, 0);
  vtkNew<vtkPolyData> half;
  half->DeepCopy(sphere->GetOutput());
  sphere->UpdatePiece(0, 1, 0);
  ASSERT_LT(half->GetNumberOfPolys(), sphere->GetOutput()->GetNumberOfPolys())
    << "the premise: the source makes pieces";
  vtkNew<vtkPointSource> points;
  points->SetNumberOfPoints(50);
  points->SetRadius(0.4);
  points->Update();
  vtkNew<vtkBaryCoordinates> filter;
  filter->SetInputData(points->GetOutput());
  filter->SetCageConnection(sphere->GetOutputPort());
  vtkNew<ErrorObserver> errors;
  errors->Attach(filter);
  filter->UpdatePiece(1, 2, 0);
  ASSERT_EQ(errors->AllErrors(), "(none)");
  vtkDataArray* w = vtkDataSet::SafeDownCast(filter->GetOutput())->GetPointData()->GetArray("Weights");
  vtkPolyData* cage = sphere->GetOutput();
  ASSERT_NE(w, nullptr);
  ASSERT_EQ(w->GetNumberOfComponents(), cage->GetNumberOfPoints()) << "the whole sphere's";
  for (vtkIdType p = 0; p < w->GetNumberOfTuples(); ++p)
  { // linear reproduction with the whole cage's points (1e-12 of its size)
    double x[3] = { 0, 0, 0 }, sum = 0;
    for (int i = 0; i < w->GetNumberOfComponents(); ++i)
    {
      const double wi = w->GetComponent(p, i);
      sum += wi;
      for (int k = 0; k < 3; ++k)
        x[k] += wi * cage->GetPoint(i)[k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(x[k], points->GetOutput()->GetPoint(p)[k], 1e-12);
  }
}
