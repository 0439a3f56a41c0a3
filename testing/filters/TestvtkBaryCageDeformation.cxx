// Tests of vtkBaryCageDeformation: identity, linear precision under affine cage motions (2D and
// 3D), reuse of weights stored on the model, and the weight cache — which must be keyed on the
// content of the rest cage, the model and the parameters, never on point counts (the
// vtkDeformPointSet bug).
#include "filters_test_utils.h"

#include "vtkBaryCageDeformation.h"
#include "vtkBaryCoordinates.h"
#include "vtkBaryReduceWeights.h"
#include "vtkBaryWeightStatistics.h"

#include "core/deformation/cage_deformation.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace
{
using namespace barylab_test;

struct Deformation
{
  vtkNew<vtkBaryCageDeformation> Filter;
  vtkNew<ErrorObserver> Observer;

  Deformation(vtkPointSet* model, vtkPolyData* rest, vtkPointSet* deformed)
  {
    this->Observer->Attach(this->Filter);
    this->Filter->SetInputData(0, model);
    if (rest)
      this->Filter->SetRestCageData(rest);
    if (deformed)
      this->Filter->SetDeformedCageData(deformed);
  }
  int Run() { return RunPipeline(this->Filter); }
  vtkPointSet* Output() { return vtkPointSet::SafeDownCast(this->Filter->GetOutputDataObject(0)); }
  vtkIdType Computations() { return this->Filter->GetNumberOfWeightComputations(); }
};

/// A deep copy (new object, same content).
vtkSmartPointer<vtkPolyData> Copy(vtkPolyData* data)
{
  auto copy = vtkSmartPointer<vtkPolyData>::New();
  copy->DeepCopy(data);
  return copy;
}

/// x -> s R x + t with R the rotation by @p angle about the unit vector @p axis.
struct Affine3
{
  double M[3][3];
  double t[3];
  Affine3(const double axis_in[3], double angle, double s, const double t_in[3])
  {
    const double n =
      std::sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
    const double a[3] = { axis_in[0] / n, axis_in[1] / n, axis_in[2] / n };
    const double c = std::cos(angle), si = std::sin(angle);
    // Rodrigues: R = c I + si [a]x + (1 - c) a a^T
    const double K[3][3] = { { 0, -a[2], a[1] }, { a[2], 0, -a[0] }, { -a[1], a[0], 0 } };
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        M[i][j] = s * ((i == j ? c : 0.0) + si * K[i][j] + (1 - c) * a[i] * a[j]);
    for (int i = 0; i < 3; ++i)
      t[i] = t_in[i];
  }
  void Apply(const double x[3], double y[3]) const
  {
    for (int i = 0; i < 3; ++i)
      y[i] = M[i][0] * x[0] + M[i][1] * x[1] + M[i][2] * x[2] + t[i];
  }
};

/// The points of @p data mapped by @p f, as a cell-less polydata (a deformed cage).
template <class F>
vtkSmartPointer<vtkPolyData> MapPoints(vtkDataSet* data, F f)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    data->GetPoint(i, x);
    f(x, y);
    points->InsertNextPoint(y);
  }
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->SetPoints(points);
  return result;
}

/// Max over points and coordinates of |a - b|.
double MaxPointDifference(vtkDataSet* a, vtkDataSet* b)
{
  EXPECT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  double worst = 0.0;
  for (vtkIdType i = 0; i < std::min(a->GetNumberOfPoints(), b->GetNumberOfPoints()); ++i)
  {
    double x[3], y[3];
    a->GetPoint(i, x);
    b->GetPoint(i, y);
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(x[k] - y[k]));
  }
  return worst;
}

/// x'_p = sum_i W(p, i) C'_i over the first @p dim coordinates; the others kept.
vtkSmartPointer<vtkPolyData> Blend(
  vtkDataSet* model, vtkDataArray* W, vtkDataSet* deformed, int dim)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    double x[3];
    model->GetPoint(p, x);
    double y[3] = { 0, 0, x[2] };
    for (int k = 0; k < dim; ++k)
      y[k] = 0.0;
    for (vtkIdType i = 0; i < deformed->GetNumberOfPoints(); ++i)
    {
      double c[3];
      deformed->GetPoint(i, c);
      const double w = W->GetComponent(p, static_cast<int>(i));
      for (int k = 0; k < dim; ++k)
        y[k] += w * c[k];
    }
    points->InsertNextPoint(y);
  }
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->SetPoints(points);
  return result;
}

/// Weights of @p model w.r.t. @p rest from vtkBaryCoordinates (kept alive by the returned data).
vtkSmartPointer<vtkDataSet> WeightsOf(vtkDataSet* model, vtkPolyData* rest)
{
  vtkNew<vtkBaryCoordinates> coordinates;
  coordinates->SetInputData(0, model);
  coordinates->SetCageData(rest);
  coordinates->Update();
  vtkSmartPointer<vtkDataSet> out = vtkDataSet::SafeDownCast(coordinates->GetOutputDataObject(0));
  EXPECT_NE(GetWeights(out), nullptr);
  return out;
}

/// A grid of points strictly inside the cube [-1, 1]^3.
vtkSmartPointer<vtkPolyData> PointsInCube()
{
  std::vector<std::array<double, 3>> xs;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k)
        xs.push_back({ -0.8 + 0.4 * i, -0.7 + 0.45 * j + 0.01 * i, -0.5 + 0.5 * k - 0.02 * j });
  return MakePointCloud(xs);
}

/// Some non-affine motion of the cube's corners.
vtkSmartPointer<vtkPolyData> TwistedCube(double amount)
{
  return MapPoints(MakeCube(),
    [amount](const double* x, double* y)
    {
      y[0] = x[0] + amount * x[1] * x[2];
      y[1] = x[1] * (1.0 + 0.3 * amount * x[0]);
      y[2] = x[2] + 0.2 * amount * x[0] * x[1] + 0.1;
    });
}

// ---------------------------------------------------------------------------------------------
// Identity and linear precision
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCageDeformation, IdentityReproducesTheModel3D)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  Deformation d(model, cage, cage);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(d.Output(), model), 1e-12);
  EXPECT_EQ(d.Output()->GetNumberOfCells(), model->GetNumberOfCells());
  EXPECT_NE(vtkPolyData::SafeDownCast(d.Output()), nullptr) << "output type = input type";
}

TEST(vtkBaryCageDeformation, IdentityReproducesTheModel2D)
{
  auto model = ReadData("model2d.obj");
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(model && cage);
  Deformation d(model, cage, cage);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(d.Output(), model), 1e-12);
}

TEST(vtkBaryCageDeformation, AffineCageMotionMovesPointsAffinely3D)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  const double axis[3] = { 1, 2, 3 }, t[3] = { 0.4, -1.2, 2.5 };
  const Affine3 A(axis, 0.7, 1.3, t);
  auto apply = [&](const double* x, double* y) { A.Apply(x, y); };
  auto deformed = MapPoints(cage, apply);
  auto expected = MapPoints(model, apply);
  Deformation d(model, cage, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-11);
}

TEST(vtkBaryCageDeformation, AffineCageMotionMovesPointsAffinely2DAndKeepsZ)
{
  auto model2d = ReadData("model2d.obj");
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(model2d && cage);
  // Give every model point its own z, which the 2D deformation must keep exactly.
  auto model = MapPoints(model2d,
    [](const double* x, double* y)
    {
      y[0] = x[0];
      y[1] = x[1];
      y[2] = 0.25 * x[0] - 0.5 * x[1] + 3.0;
    });
  const double c = std::cos(0.4) * 0.8, s = std::sin(0.4) * 0.8;
  auto affine = [&](const double* x, double* y)
  {
    y[0] = c * x[0] - s * x[1] + 0.3;
    y[1] = s * x[0] + c * x[1] - 0.2;
    y[2] = 7.0; // the deformed cage's z is irrelevant for a 2D cage
  };
  auto deformed = MapPoints(cage, affine);
  Deformation d(model, cage, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  vtkPointSet* out = d.Output();
  ASSERT_EQ(out->GetNumberOfPoints(), model->GetNumberOfPoints());
  double worst = 0.0;
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3], e[3];
    model->GetPoint(p, x);
    out->GetPoint(p, y);
    affine(x, e);
    worst = std::max({ worst, std::abs(y[0] - e[0]), std::abs(y[1] - e[1]) });
    ASSERT_EQ(y[2], x[2]) << "z of point " << p << " must be kept";
  }
  EXPECT_LE(worst, 1e-12);
}

TEST(vtkBaryCageDeformation, PosedCageMatchesWeightsTimesControlPoints)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  auto posed = ReadData("cage3d_posed.obj");
  ASSERT_TRUE(model && cage && posed);
  auto weighted = WeightsOf(model, cage);
  auto expected = Blend(model, GetWeights(weighted), posed, 3);
  Deformation d(model, cage, posed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
  // The pose does move the model (so the comparison above is not vacuous).
  EXPECT_GT(MaxPointDifference(d.Output(), model), 0.05);
  // PassWeights (default on): the weights come along.
  vtkDataArray* W = GetWeights(d.Output());
  ASSERT_NE(W, nullptr);
  EXPECT_EQ(W->GetNumberOfComponents(), 72);
}

TEST(vtkBaryCageDeformation, PermutedPolygonCellRestCage2D)
{
  // Rest cage A: bare points in polygon order. Rest cage B: the same points stored shuffled,
  // with one polygon cell walking them. Deformed cages follow each rest cage's point order.
  auto model = ReadData("model2d.obj");
  auto bare = ReadData("cage2d.obj");
  auto posed = ReadData("cage2d_posed.obj");
  ASSERT_TRUE(model && bare && posed);
  const vtkIdType n = bare->GetNumberOfPoints();
  std::vector<vtkIdType> pi(n), inverse(n);
  for (vtkIdType j = 0; j < n; ++j)
    inverse[pi[j] = (3 * j + 1) % n] = j;
  vtkNew<vtkPoints> rest_points, posed_points;
  rest_points->SetDataTypeToDouble(); // as read: .obj coordinates are doubles
  posed_points->SetDataTypeToDouble();
  for (vtkIdType j = 0; j < n; ++j)
  {
    rest_points->InsertNextPoint(bare->GetPoint(pi[j]));
    posed_points->InsertNextPoint(posed->GetPoint(pi[j]));
  }
  std::vector<vtkIdType> ids;
  for (vtkIdType k = 0; k < n; ++k)
    ids.push_back(inverse[(k + 4) % n]);
  vtkNew<vtkCellArray> polys;
  polys->InsertNextCell(n, ids.data());
  vtkNew<vtkPolyData> rest_b, posed_b;
  rest_b->SetPoints(rest_points);
  rest_b->SetPolys(polys);
  posed_b->SetPoints(posed_points);

  Deformation a(model, bare, posed), b(model, rest_b, posed_b);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();
  ASSERT_EQ(b.Run(), 1) << b.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(a.Output(), b.Output()), 1e-12);
  EXPECT_GT(MaxPointDifference(a.Output(), model), 0.01);

  // Weights stored on the model by vtkBaryCoordinates for cage B (component j = B's point j)
  // are read back in the right order.
  auto weighted = vtkSmartPointer<vtkPolyData>::New();
  weighted->DeepCopy(WeightsOf(model, rest_b));
  Deformation c(weighted, rest_b, posed_b);
  ASSERT_EQ(c.Run(), 1) << c.Observer->AllErrors();
  EXPECT_EQ(c.Computations(), 0);
  EXPECT_LE(MaxPointDifference(a.Output(), c.Output()), 1e-12);
}

TEST(vtkBaryCageDeformation, DeformedCageMayBeAnyPointSet)
{
  auto cube = MakeCube();
  auto model = PointsInCube();
  auto twisted = TwistedCube(0.3);
  vtkNew<vtkUnstructuredGrid> deformed; // points only, no cells
  deformed->SetPoints(twisted->GetPoints());
  Deformation d(model, cube, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  auto expected = Blend(model, GetWeights(WeightsOf(model, cube)), twisted, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Weights given on the model
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCageDeformation, UsesWeightsStoredOnTheModel)
{
  auto cube = MakeCube();
  auto weighted = WeightsOf(PointsInCube(), cube);
  auto model = vtkSmartPointer<vtkPolyData>::New();
  model->DeepCopy(weighted);
  auto twisted = TwistedCube(0.5);
  Deformation d(model, cube, twisted);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 0);
  auto expected = Blend(model, GetWeights(model), twisted, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

TEST(vtkBaryCageDeformation, StoredWeightsReallyAreUsed)
{
  // Fake weights: everything on cage point 3, so every point must land on deformed point 3.
  auto cube = MakeCube();
  auto model = PointsInCube();
  vtkNew<vtkDoubleArray> fake;
  fake->SetName("Weights");
  fake->SetNumberOfComponents(8);
  fake->SetNumberOfTuples(model->GetNumberOfPoints());
  fake->Fill(0.0);
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
    fake->SetComponent(p, 3, 1.0);
  model->GetPointData()->AddArray(fake);
  auto twisted = TwistedCube(0.5);
  double target[3];
  twisted->GetPoint(3, target);

  Deformation d(model, cube, twisted);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 0);
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    double y[3];
    d.Output()->GetPoint(p, y);
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(y[k], target[k]) << "point " << p;
  }

  // UseInputWeights off: the fake weights are ignored and real ones computed.
  d.Filter->UseInputWeightsOff();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 1);
  auto model_plain = PointsInCube();
  auto expected = Blend(model_plain, GetWeights(WeightsOf(model_plain, cube)), twisted, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

TEST(vtkBaryCageDeformation, StoredWeightsWithWrongComponentsAreIgnoredWithAWarning)
{
  auto cube = MakeCube();
  auto model = PointsInCube();
  vtkNew<vtkDoubleArray> wrong;
  wrong->SetName("Weights");
  wrong->SetNumberOfComponents(5);
  wrong->SetNumberOfTuples(model->GetNumberOfPoints());
  wrong->Fill(0.2);
  model->GetPointData()->AddArray(wrong);
  auto twisted = TwistedCube(0.2);
  Deformation d(model, cube, twisted);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 1);
  EXPECT_TRUE(d.Observer->HasWarning("Weights")) << d.Observer->AllWarnings();
  auto plain = PointsInCube();
  auto expected = Blend(plain, GetWeights(WeightsOf(plain, cube)), twisted, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

TEST(vtkBaryCageDeformation, PassWeightsOff)
{
  auto cube = MakeCube();
  auto model = PointsInCube();
  Deformation d(model, cube, TwistedCube(0.2));
  d.Filter->PassWeightsOff();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(GetWeights(d.Output()), nullptr);
  d.Filter->PassWeightsOn();
  ASSERT_EQ(d.Run(), 1);
  ASSERT_NE(GetWeights(d.Output()), nullptr);
  EXPECT_EQ(GetWeights(d.Output())->GetNumberOfComponents(), 8);
  EXPECT_EQ(d.Computations(), 1) << "toggling PassWeights must not recompute";
}

// ---------------------------------------------------------------------------------------------
// The cache
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCageDeformation, MovingOnlyTheDeformedCageDoesNotRecompute)
{
  auto cube = MakeCube();
  auto model = PointsInCube();
  auto W = WeightsOf(model, cube);
  auto deformed = TwistedCube(0.0);
  Deformation d(model, cube, deformed);
  for (int step = 0; step < 4; ++step)
  {
    auto target = TwistedCube(0.15 * step);
    for (vtkIdType i = 0; i < 8; ++i)
      deformed->GetPoints()->SetPoint(i, target->GetPoint(i));
    deformed->GetPoints()->Modified();
    deformed->Modified();
    ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
    EXPECT_EQ(d.Computations(), 1) << "step " << step;
    auto expected = Blend(model, GetWeights(W), target, 3);
    EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12) << "step " << step;
  }
  // A new deformed cage object too.
  auto other = TwistedCube(-0.4);
  d.Filter->SetDeformedCageData(other);
  ASSERT_EQ(d.Run(), 1);
  EXPECT_EQ(d.Computations(), 1);
  EXPECT_LE(MaxPointDifference(d.Output(), Blend(model, GetWeights(W), other, 3)), 1e-12);
}

TEST(vtkBaryCageDeformation, ChangingRestCageCoordinatesRecomputes)
{
  auto rest = MakeCube();
  auto model = PointsInCube();
  auto deformed = TwistedCube(0.3);
  Deformation d(model, rest, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  ASSERT_EQ(d.Computations(), 1);
  vtkNew<vtkPoints> before;
  before->SetDataTypeToDouble();
  before->DeepCopy(d.Output()->GetPoints());

  // Same number of points and faces, one corner moved, in place.
  rest->GetPoints()->SetPoint(6, 1.4, 1.3, 1.2);
  rest->GetPoints()->Modified();
  rest->Modified();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 2);
  auto expected = Blend(model, GetWeights(WeightsOf(model, Copy(rest))), deformed, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
  vtkNew<vtkPolyData> old;
  old->SetPoints(before);
  EXPECT_GT(MaxPointDifference(old, expected), 1e-3) << "the test needs the change to matter";

  // A different rest cage object with the same counts (the cube scaled).
  auto bigger = MakeCube(1.5);
  d.Filter->SetRestCageData(bigger);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 3);
  expected = Blend(model, GetWeights(WeightsOf(model, bigger)), deformed, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

TEST(vtkBaryCageDeformation, ChangingRestCageConnectivityRecomputes)
{
  // Same points, same number of faces, one quad side triangulated along the other diagonal.
  auto rest = MakeCube();
  auto model = PointsInCube();
  auto deformed = TwistedCube(0.4);
  Deformation d(model, rest, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  auto flipped = Copy(rest);
  vtkNew<vtkCellArray> polys;
  vtkIdType size;
  const vtkIdType* ids;
  for (vtkIdType f = 0; f < 12; ++f)
  {
    rest->GetPolys()->GetCellAtId(f, size, ids);
    if (f == 0 || f == 1)
      continue; // side z = -1: {0,3,2}, {0,2,1} -> {0,3,1}, {3,2,1}
    polys->InsertNextCell(size, ids);
  }
  const vtkIdType a[3] = { 0, 3, 1 }, b[3] = { 3, 2, 1 };
  polys->InsertNextCell(3, a);
  polys->InsertNextCell(3, b);
  flipped->SetPolys(polys);
  d.Filter->SetRestCageData(flipped);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 2);
  auto expected = Blend(model, GetWeights(WeightsOf(model, flipped)), deformed, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

TEST(vtkBaryCageDeformation, ChangingModelPointsRecomputes)
{
  auto rest = MakeCube();
  auto model = PointsInCube();
  auto deformed = TwistedCube(0.3);
  Deformation d(model, rest, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  model->GetPoints()->SetPoint(0, 0.3, -0.6, 0.45);
  model->GetPoints()->Modified();
  model->Modified();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 2);
  auto expected = Blend(model, GetWeights(WeightsOf(model, rest)), deformed, 3);
  EXPECT_LE(MaxPointDifference(d.Output(), expected), 1e-12);
}

TEST(vtkBaryCageDeformation, ChangingParametersRecomputes)
{
  auto rest = MakeCube();
  auto model = PointsInCube();
  Deformation d(model, rest, TwistedCube(0.3));
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  ASSERT_EQ(d.Computations(), 1);
  d.Filter->GetWeightMethod()->SetBoundaryTolerance(1e-6);
  ASSERT_EQ(d.Run(), 1);
  EXPECT_EQ(d.Computations(), 2) << "BoundaryTolerance is part of the key";
  d.Filter->GetWeightMethod()->SetBoundaryTolerance(1e-6);
  d.Filter->Modified();
  ASSERT_EQ(d.Run(), 1);
  EXPECT_EQ(d.Computations(), 2) << "same parameters: cached";
  d.Filter->GetWeightMethod()->ValidateCageOff();
  ASSERT_EQ(d.Run(), 1);
  EXPECT_EQ(d.Computations(), 3) << "ValidateCage is part of the key";
  d.Filter->ClearCache();
  d.Filter->Modified();
  ASSERT_EQ(d.Run(), 1);
  EXPECT_EQ(d.Computations(), 4) << "ClearCache drops the weights";
}

TEST(vtkBaryCageDeformation, MethodIsClampedToKnownMethods)
{
  // Like vtkBaryCoordinates, the setter clamps: an out-of-range method cannot be selected, so
  // no request can run with an undefined method (or reuse weights computed by another one).
  vtkNew<vtkBaryCageDeformation> filter;
  filter->GetWeightMethod()->SetMethod(vtkBaryWeightMethod::NUMBER_OF_METHODS + 3);
  EXPECT_EQ(filter->GetWeightMethod()->GetMethod(), vtkBaryWeightMethod::NUMBER_OF_METHODS - 1);
  filter->GetWeightMethod()->SetMethod(-5);
  EXPECT_EQ(filter->GetWeightMethod()->GetMethod(), vtkBaryWeightMethod::MEAN_VALUE);
}

TEST(vtkBaryCageDeformation, IdenticalContentInNewObjectsDoesNotRecompute)
{
  auto rest = MakeCube();
  auto model = PointsInCube();
  auto deformed = TwistedCube(0.3);
  Deformation d(model, rest, deformed);
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  vtkNew<vtkPoints> first;
  first->SetDataTypeToDouble();
  first->DeepCopy(d.Output()->GetPoints());
  d.Filter->SetRestCageData(Copy(rest));
  d.Filter->SetInputData(0, Copy(model));
  d.Filter->SetDeformedCageData(Copy(deformed));
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 1);
  vtkNew<vtkPolyData> a;
  a->SetPoints(first);
  EXPECT_EQ(MaxPointDifference(a, d.Output()), 0.0);
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryCageDeformation, DeformedCageWithWrongNumberOfPointsIsAnError)
{
  auto rest = MakeCube();
  auto model = PointsInCube();
  auto seven = MakePointCloud(
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 0 }, { 1, 0, 1 }, { 0, 1, 1 } });
  Deformation d(model, rest, seven);
  EXPECT_EQ(d.Run(), 0);
  EXPECT_TRUE(d.Observer->HasError("7 points")) << d.Observer->AllErrors();
  EXPECT_TRUE(d.Observer->HasError("8")) << d.Observer->AllErrors();
}

TEST(vtkBaryCageDeformation, MissingInputsAreReported)
{
  auto model = PointsInCube();
  {
    Deformation d(model, MakeCube(), nullptr);
    EXPECT_EQ(d.Run(), 0);
    EXPECT_TRUE(d.Observer->HasError("port 2")) << d.Observer->AllErrors();
  }
  {
    Deformation d(model, nullptr, MakeCube());
    EXPECT_EQ(d.Run(), 0);
    EXPECT_TRUE(d.Observer->HasError("port 1")) << d.Observer->AllErrors();
  }
}

TEST(vtkBaryCageDeformation, InvalidRestCageIsReported)
{
  auto open = ReadData("bad/open_cage.obj");
  ASSERT_TRUE(open);
  Deformation d(PointsInCube(), open, open);
  EXPECT_EQ(d.Run(), 0);
  EXPECT_TRUE(d.Observer->HasError("not closed")) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 0);
}

TEST(vtkBaryCageDeformation, EmptyModelWarnsAndSucceeds)
{
  vtkNew<vtkPolyData> empty;
  Deformation d(empty, MakeCube(), MakeCube());
  EXPECT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_TRUE(d.Observer->HasWarning("no points")) << d.Observer->AllWarnings();
  EXPECT_EQ(d.Output()->GetNumberOfPoints(), 0);
}

// ---------------------------------------------------------------------------------------------
// Compact (reduced) weights from vtkBaryReduceWeights
// ---------------------------------------------------------------------------------------------

/// The kidney model with mean value weights, reduced with @p mode at threshold 0.005 (at the
/// default 1e-3 / 72 some points keep all 72 weights: mean value coordinates are global).
vtkSmartPointer<vtkPointSet> ReducedKidney(vtkPolyData* model, vtkPolyData* cage, int mode,
  double* reproductionError = nullptr)
{
  Deformation d(model, cage, cage);
  EXPECT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  vtkNew<vtkBaryReduceWeights> reduce;
  reduce->SetInputData(d.Output());
  reduce->SetCageData(cage);
  reduce->SetRenormalization(mode);
  reduce->SetThreshold(0.005);
  reduce->Update();
  if (reproductionError)
    *reproductionError = reduce->GetReproductionError();
  auto out = vtkSmartPointer<vtkPointSet>::Take(vtkPointSet::SafeDownCast(
    reduce->GetOutputDataObject(0)->NewInstance()));
  out->ShallowCopy(reduce->GetOutputDataObject(0));
  // mean value weights are global: the reduction drops only some of the 72
  EXPECT_LT(reduce->GetMaximumSupport(), 72);
  EXPECT_EQ(out->GetPointData()->GetArray("Weights"), nullptr);
  return out;
}

/// The compact pair as a dense "Weights" array on a copy of @p compact (same reduced weights).
vtkSmartPointer<vtkPointSet> Densified(vtkPointSet* compact, int controls)
{
  auto dense = vtkSmartPointer<vtkPointSet>::Take(compact->NewInstance());
  dense->DeepCopy(compact);
  vtkDataArray* indices = compact->GetPointData()->GetArray("WeightsIndices");
  vtkDataArray* values = compact->GetPointData()->GetArray("WeightsValues");
  vtkNew<vtkDoubleArray> w;
  w->SetName("Weights");
  w->SetNumberOfComponents(controls);
  w->SetNumberOfTuples(compact->GetNumberOfPoints());
  w->Fill(0.0);
  for (vtkIdType p = 0; p < compact->GetNumberOfPoints(); ++p)
    for (int k = 0; k < indices->GetNumberOfComponents(); ++k)
      if (indices->GetComponent(p, k) >= 0)
        w->SetComponent(p, static_cast<int>(indices->GetComponent(p, k)), values->GetComponent(p, k));
  dense->GetPointData()->RemoveArray("WeightsIndices");
  dense->GetPointData()->RemoveArray("WeightsValues");
  dense->GetPointData()->AddArray(w);
  return dense;
}

TEST(vtkBaryCageDeformation, CompactWeightsDeformLikeTheSameDenseWeights)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  auto posed = ReadData("cage3d_posed.obj");
  ASSERT_TRUE(model && cage && posed);
  auto compact = ReducedKidney(model, cage, vtkBaryReduceWeights::RENORMALIZE_ROW_SUM);
  auto dense = Densified(compact, 72);
  Deformation a(compact, cage, posed), b(dense, cage, posed);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();
  ASSERT_EQ(b.Run(), 1) << b.Observer->AllErrors();
  EXPECT_EQ(a.Computations(), 0);
  EXPECT_EQ(b.Computations(), 0);
  // the same sums in another order: equal to rounding (coordinates ~1)
  EXPECT_LE(MaxPointDifference(a.Output(), b.Output()), 1e-13);
  EXPECT_NE(a.Output()->GetPointData()->GetArray("WeightsIndices"), nullptr);
  EXPECT_EQ(a.Output()->GetPointData()->GetArray("Weights"), nullptr);

  // BBW blends displacements with compact weights too
  a.Filter->GetWeightMethod()->SetMethod(vtkBaryWeightMethod::BBW);
  b.Filter->GetWeightMethod()->SetMethod(vtkBaryWeightMethod::BBW);
  ASSERT_EQ(a.Run(), 1) << a.Observer->AllErrors();
  ASSERT_EQ(b.Run(), 1) << b.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(a.Output(), b.Output()), 1e-13);
}

TEST(vtkBaryCageDeformation, CompactWeightsReproduceATranslatedCage)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  const double t[3] = { 0.3, -0.7, 1.1 };
  auto shift = [&](const double* x, double* y) {
    for (int i = 0; i < 3; ++i)
      y[i] = x[i] + t[i];
  };
  auto translated = MapPoints(cage, shift);
  auto expected = MapPoints(model, shift);

  // Row sum: partition of unity is exact, so the deformation moves every point by exactly t
  // (to rounding); the rest pose is off by at most the reproduction error.
  double reproduction = 0;
  auto rowsum = ReducedKidney(model, cage, vtkBaryReduceWeights::RENORMALIZE_ROW_SUM, &reproduction);
  Deformation rest(rowsum, cage, cage), moved(rowsum, cage, translated);
  ASSERT_EQ(rest.Run(), 1) << rest.Observer->AllErrors();
  ASSERT_EQ(moved.Run(), 1) << moved.Observer->AllErrors();
  const double diameter = cage->GetLength();
  EXPECT_LE(MaxPointDifference(rest.Output(), model), reproduction * diameter * 1.0001 + 1e-12);
  EXPECT_LE(MaxPointDifference(MapPoints(vtkPolyData::SafeDownCast(rest.Output()), shift),
              moved.Output()),
    1e-12);

  // Affine: reproduction exact, so the translated cage gives the translated model.
  auto affine = ReducedKidney(model, cage, vtkBaryReduceWeights::RENORMALIZE_AFFINE, &reproduction);
  EXPECT_LT(reproduction, 1e-12);
  Deformation restA(affine, cage, cage), movedA(affine, cage, translated);
  ASSERT_EQ(restA.Run(), 1) << restA.Observer->AllErrors();
  ASSERT_EQ(movedA.Run(), 1) << movedA.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(restA.Output(), model), 1e-11);
  EXPECT_LE(MaxPointDifference(movedA.Output(), expected), 1e-11);
}

TEST(vtkBaryCageDeformation, CompactWeightsErrors)
{
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  auto compact = ReducedKidney(model, cage, vtkBaryReduceWeights::RENORMALIZE_ROW_SUM);
  {
    vtkNew<vtkIntArray> count;
    count->SetName("WeightsNumberOfControlPoints");
    count->InsertNextValue(71);
    compact->GetFieldData()->AddArray(count);
    Deformation d(compact, cage, cage);
    EXPECT_EQ(d.Run(), 0);
    EXPECT_TRUE(d.Observer->HasError("are for 71 control points but the cage has 72"))
      << d.Observer->AllErrors();
    compact->GetFieldData()->RemoveArray("WeightsNumberOfControlPoints");
  }
  {
    compact->GetPointData()->GetArray("WeightsIndices")->SetComponent(5, 0, 72);
    Deformation d(compact, cage, cage);
    EXPECT_EQ(d.Run(), 0);
    EXPECT_TRUE(d.Observer->HasError("outside [0, 72)")) << d.Observer->AllErrors();
  }
}

// ---------------------------------------------------------------------------------------------
// Green coordinates (Lipman et al. 2008): vertex weights and face coefficients
// ---------------------------------------------------------------------------------------------

/// Green coordinates of @p model w.r.t. @p rest from vtkBaryCoordinates (Weights, FaceWeights).
vtkSmartPointer<vtkDataSet> GreenOf(vtkDataSet* model, vtkPolyData* rest)
{
  vtkNew<vtkBaryCoordinates> coordinates;
  coordinates->GetWeightMethod()->SetMethodToGreen();
  coordinates->SetInputData(0, model);
  coordinates->SetCageData(rest);
  coordinates->Update();
  return vtkDataSet::SafeDownCast(coordinates->GetOutputDataObject(0));
}

TEST(vtkBaryCageDeformation, GreenCoordinatesArraysAndStatistics)
{
  // vtkBaryCoordinates with GREEN writes phi as "Weights" (#C components) and psi as
  // "FaceWeights" (#F); the statistics filter checks reproduction with the face term.
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  auto weighted = GreenOf(model, cage);
  ASSERT_NE(GetWeights(weighted), nullptr);
  EXPECT_EQ(GetWeights(weighted)->GetNumberOfComponents(), cage->GetNumberOfPoints());
  vtkDataArray* faces = GetWeights(weighted, "FaceWeights");
  ASSERT_NE(faces, nullptr);
  EXPECT_EQ(faces->GetNumberOfComponents(), cage->GetNumberOfPolys());
  EXPECT_STREQ(faces->GetComponentName(0), "f0");
  auto figures = [&](const char* faceName) {
    vtkNew<vtkBaryWeightStatistics> stats;
    stats->SetInputData(0, weighted);
    stats->SetCageData(cage);
    stats->SetFaceWeightsArrayName(faceName);
    stats->Update();
    return vtkSmartPointer<vtkTable>(stats->GetOutput(0));
  };
  auto with = figures("FaceWeights");
  EXPECT_LT(with->GetValueByName(0, "max_partition_error").ToDouble(), 1e-12);
  EXPECT_LT(with->GetValueByName(0, "max_reproduction_error").ToDouble(), 1e-12);
  EXPECT_EQ(with->GetValueByName(0, "face_coefficients").ToDouble(), cage->GetNumberOfPolys());
  // phi alone does not reproduce x: the statistics must not pretend it does
  auto without = figures("NoSuchArray");
  EXPECT_GT(without->GetValueByName(0, "max_reproduction_error").ToDouble(), 1e-3);
  EXPECT_EQ(without->GetColumnByName("face_coefficients"), nullptr);
  // another method on the same data drops the stale face coefficients
  vtkNew<vtkBaryCoordinates> mvc;
  mvc->SetInputData(0, weighted);
  mvc->SetCageData(cage);
  mvc->Update();
  EXPECT_EQ(GetWeights(vtkDataSet::SafeDownCast(mvc->GetOutputDataObject(0)), "FaceWeights"), nullptr);
}

TEST(vtkBaryCageDeformation, GreenSimilarityMovesTheModelBySimilarity3D)
{
  // A rotated, scaled, translated cage moves the model by exactly that similarity (the paper's
  // invariance; with W alone the model would not even stay in place).
  auto model = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model && cage);
  const double axis[3] = { 1, -2, 0.5 }, t[3] = { 0.4, -1.2, 2.5 };
  const Affine3 A(axis, 0.9, 1.7, t);
  auto apply = [&](const double* x, double* y) { A.Apply(x, y); };
  Deformation d(model, cage, MapPoints(cage, apply));
  d.Filter->GetWeightMethod()->SetMethodToGreen();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(d.Output(), MapPoints(model, apply)), 1e-10);
  EXPECT_NE(GetWeights(d.Output(), "FaceWeights"), nullptr);
}

TEST(vtkBaryCageDeformation, GreenSimilarityMovesTheModelBySimilarity2DAndKeepsZ)
{
  auto model = ReadData("model2d.obj");
  auto cage = ReadData("cage2d.obj");
  ASSERT_TRUE(model && cage);
  const double c = std::cos(0.4) * 0.8, s = std::sin(0.4) * 0.8;
  auto similarity = [&](const double* x, double* y)
  {
    y[0] = c * x[0] - s * x[1] + 0.3;
    y[1] = s * x[0] + c * x[1] - 0.2;
    y[2] = x[2];
  };
  Deformation d(model, cage, MapPoints(cage, similarity));
  d.Filter->GetWeightMethod()->SetMethodToGreen();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_LE(MaxPointDifference(d.Output(), MapPoints(model, similarity)), 1e-11);
}

TEST(vtkBaryCageDeformation, GreenStoredArraysCacheAndCoreAgree)
{
  // The deformation from stored arrays, from computed (cached) ones and core's
  // deform_points_green on the same numbers agree; moving the deformed cage never recomputes.
  auto cube = MakeCube();
  auto model = PointsInCube();
  auto twisted = TwistedCube(0.3);
  auto weighted = GreenOf(model, cube);
  Deformation stored(vtkPointSet::SafeDownCast(weighted), cube, twisted);
  stored.Filter->GetWeightMethod()->SetMethodToGreen();
  ASSERT_EQ(stored.Run(), 1) << stored.Observer->AllErrors();
  EXPECT_EQ(stored.Computations(), 0);
  Deformation computed(model, cube, twisted);
  computed.Filter->GetWeightMethod()->SetMethodToGreen();
  ASSERT_EQ(computed.Run(), 1) << computed.Observer->AllErrors();
  EXPECT_EQ(computed.Computations(), 1);
  EXPECT_LE(MaxPointDifference(stored.Output(), computed.Output()), 1e-13);
  // core on the stored arrays (cube points and cells in order: core order = VTK order)
  bary::Cage rest;
  rest.V.resize(8, 3);
  rest.F.resize(12, 3);
  Eigen::MatrixXd moved(8, 3);
  for (vtkIdType i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k)
    {
      rest.V(i, k) = cube->GetPoint(i)[k];
      moved(i, k) = twisted->GetPoint(i)[k];
    }
  for (vtkIdType f = 0; f < 12; ++f)
    for (int k = 0; k < 3; ++k)
      rest.F(f, k) = static_cast<int>(cube->GetCell(f)->GetPointId(k));
  vtkDataArray* phi = GetWeights(weighted);
  vtkDataArray* psi = GetWeights(weighted, "FaceWeights");
  bary::DenseWeights Phi(model->GetNumberOfPoints(), 8), Psi(model->GetNumberOfPoints(), 12);
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    for (int i = 0; i < 8; ++i)
      Phi(p, i) = phi->GetComponent(p, i);
    for (int f = 0; f < 12; ++f)
      Psi(p, f) = psi->GetComponent(p, f);
  }
  const Eigen::MatrixXd X = bary::deform_points_green(Phi, Psi, rest, moved);
  double worst = 0.0;
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(X(p, k) - stored.Output()->GetPoint(p)[k]));
  EXPECT_LE(worst, 1e-13);
  // the cache: a new deformed cage only
  computed.Filter->SetDeformedCageData(TwistedCube(-0.2));
  ASSERT_EQ(computed.Run(), 1);
  EXPECT_EQ(computed.Computations(), 1);
}

TEST(vtkBaryCageDeformation, GreenWithoutFaceWeightsComputesAndCompactIsRefused)
{
  auto cube = MakeCube();
  auto model = PointsInCube();
  auto twisted = TwistedCube(0.2);
  // mean value weights on the model, Green asked for: the face coefficients are missing
  auto mvcWeighted = WeightsOf(model, cube);
  Deformation d(vtkPointSet::SafeDownCast(mvcWeighted), cube, twisted);
  d.Filter->GetWeightMethod()->SetMethodToGreen();
  ASSERT_EQ(d.Run(), 1) << d.Observer->AllErrors();
  EXPECT_EQ(d.Computations(), 1);
  EXPECT_TRUE(d.Observer->HasWarning("FaceWeights")) << d.Observer->AllWarnings();
  // compact (reduced) weights cannot carry psi
  auto model3d = ReadData("model3d.off");
  auto cage = ReadData("cage3d.obj");
  ASSERT_TRUE(model3d && cage);
  auto compact = ReducedKidney(model3d, cage, vtkBaryReduceWeights::RENORMALIZE_ROW_SUM);
  Deformation g(compact, cage, cage);
  g.Filter->GetWeightMethod()->SetMethodToGreen();
  EXPECT_EQ(g.Run(), 0);
  EXPECT_TRUE(g.Observer->HasError("compact (reduced) weights")) << g.Observer->AllErrors();
}

} // namespace
