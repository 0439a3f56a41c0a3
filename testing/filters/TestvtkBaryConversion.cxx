// Tests of vtkBaryConversion: how a vtkPolyData becomes a 2D or 3D cage (each accepted 2D form,
// each rejected form), and the weights array <-> matrix round trip with a permutation.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"

#include "core/common/error.h"

#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>

namespace
{
using namespace barylab_test;

/// A square-ish pentagon in the plane z = 0.5 (counter-clockwise), as bare points.
vtkSmartPointer<vtkPolyData> Pentagon()
{
  return MakePointCloud(
    { { 0, 0, 0.5 }, { 2, 0, 0.5 }, { 2, 1, 0.5 }, { 1, 1.8, 0.5 }, { 0, 1, 0.5 } });
}

vtkSmartPointer<vtkCellArray> OneCell(const std::vector<vtkIdType>& ids)
{
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  return cells;
}

/// Expects ToCage to throw bary::Error with @p code and a message containing @p needle.
void ExpectToCageThrows(
  vtkPolyData* data, int dimension, bary::ErrorCode code, const std::string& needle)
{
  try
  {
    vtkBaryConversion::ToCage(data, dimension);
    ADD_FAILURE() << "ToCage accepted the data; expected an error mentioning '" << needle << "'";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
      << "message '" << e.what() << "' should mention '" << needle << "'";
  }
}

/// Expects a 2D cage whose core vertex k is polydata point ids[k].
void Expect2DCage(const vtkBaryCage& cage, vtkPolyData* data, const std::vector<vtkIdType>& ids)
{
  ASSERT_EQ(cage.Cage.dimension(), 2);
  ASSERT_EQ(cage.Cage.num_controls(), static_cast<bary::Index>(ids.size()));
  EXPECT_EQ(cage.Cage.F.size(), 0);
  EXPECT_EQ(cage.ControlPointIds, ids);
  std::vector<vtkIdType> identity(ids.size());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(cage.IdentityOrder, ids == identity);
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    double x[3];
    data->GetPoint(ids[k], x);
    EXPECT_EQ(cage.Cage.V(static_cast<bary::Index>(k), 0), x[0]);
    EXPECT_EQ(cage.Cage.V(static_cast<bary::Index>(k), 1), x[1]);
  }
}

// ---------------------------------------------------------------------------------------------
// 2D forms
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryConversion, BarePointsArePolygonInPointOrder)
{
  auto data = Pentagon();
  Expect2DCage(vtkBaryConversion::ToCage(data), data, { 0, 1, 2, 3, 4 });
}

TEST(vtkBaryConversion, PolygonCell)
{
  auto data = Pentagon();
  data->SetPolys(OneCell({ 0, 1, 2, 3, 4 }));
  Expect2DCage(vtkBaryConversion::ToCage(data), data, { 0, 1, 2, 3, 4 });
  data->SetPolys(OneCell({ 2, 3, 4, 0, 1 })); // rotated
  Expect2DCage(vtkBaryConversion::ToCage(data), data, { 2, 3, 4, 0, 1 });
  data->SetPolys(OneCell({ 4, 3, 2, 1, 0 })); // clockwise
  Expect2DCage(
    vtkBaryConversion::ToCage(data, vtkBaryConversion::CAGE_2D), data, { 4, 3, 2, 1, 0 });
}

TEST(vtkBaryConversion, ClosedPolylineWithRepeatedLastId)
{
  auto data = Pentagon();
  data->SetLines(OneCell({ 1, 2, 3, 4, 0, 1 }));
  Expect2DCage(vtkBaryConversion::ToCage(data), data, { 1, 2, 3, 4, 0 });
}

TEST(vtkBaryConversion, OpenPolyline)
{
  auto data = Pentagon();
  data->SetLines(OneCell({ 3, 4, 0, 1, 2 }));
  Expect2DCage(vtkBaryConversion::ToCage(data), data, { 3, 4, 0, 1, 2 });
}

TEST(vtkBaryConversion, SingleTriangleInAPlaneIs2D)
{
  auto data = MakePointCloud({ { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 } });
  data->SetPolys(OneCell({ 0, 1, 2 }));
  Expect2DCage(vtkBaryConversion::ToCage(data), data, { 0, 1, 2 });
}

TEST(vtkBaryConversion, BundledObjCageIs2D)
{
  auto data = ReadData("cage2d.obj");
  ASSERT_TRUE(data);
  std::vector<vtkIdType> ids(20);
  std::iota(ids.begin(), ids.end(), 0);
  Expect2DCage(vtkBaryConversion::ToCage(data), data, ids);
}

TEST(vtkBaryConversion, NonPlanarBarePointsAreRejected)
{
  auto data = Pentagon();
  data->GetPoints()->SetPoint(3, 1, 1.8, 0.7);
  ExpectToCageThrows(data, vtkBaryConversion::AUTOMATIC, bary::ErrorCode::InvalidCage, "plane");
}

TEST(vtkBaryConversion, RoundOffInZIsToleratedTheSameWayForEveryForm)
{
  // z = 0.5 up to round-off (as after a transform or a float round trip): every 2D form must
  // accept it, not only bare points.
  auto noisy = []
  {
    auto data = Pentagon();
    data->GetPoints()->SetPoint(3, 1, 1.8, 0.5 + 1e-13);
    return data;
  };
  auto bare = noisy();
  Expect2DCage(vtkBaryConversion::ToCage(bare), bare, { 0, 1, 2, 3, 4 });
  auto polyline = noisy();
  polyline->SetLines(OneCell({ 0, 1, 2, 3, 4, 0 }));
  Expect2DCage(vtkBaryConversion::ToCage(polyline), polyline, { 0, 1, 2, 3, 4 });
  auto polygon = noisy();
  polygon->SetPolys(OneCell({ 0, 1, 2, 3, 4 }));
  try
  {
    Expect2DCage(vtkBaryConversion::ToCage(polygon), polygon, { 0, 1, 2, 3, 4 });
  }
  catch (const bary::Error& e)
  {
    ADD_FAILURE() << "a polygon cell with round-off in z was rejected: " << e.what();
  }
}

TEST(vtkBaryConversion, MultiplePolygonsAreRejected)
{
  // Two quads: with automatic detection several polygons mean a 3D cage, which must be
  // triangles; forced to 2D the message says there is more than one polygon.
  auto data = MakePointCloud({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 2, 0, 0 },
    { 3, 0, 0 }, { 3, 1, 0 }, { 2, 1, 0 } });
  vtkNew<vtkCellArray> polys;
  const vtkIdType a[4] = { 0, 1, 2, 3 }, b[4] = { 4, 5, 6, 7 };
  polys->InsertNextCell(4, a);
  polys->InsertNextCell(4, b);
  data->SetPolys(polys);
  ExpectToCageThrows(data, vtkBaryConversion::CAGE_2D, bary::ErrorCode::InvalidCage, "2 polygons");
  ExpectToCageThrows(
    data, vtkBaryConversion::AUTOMATIC, bary::ErrorCode::InvalidCage, "triangulated");
}

TEST(vtkBaryConversion, SeveralPolylinesAreRejected)
{
  auto data = Pentagon();
  vtkNew<vtkCellArray> lines;
  const vtkIdType a[3] = { 0, 1, 2 }, b[3] = { 2, 3, 4 };
  lines->InsertNextCell(3, a);
  lines->InsertNextCell(3, b);
  data->SetLines(lines);
  ExpectToCageThrows(
    data, vtkBaryConversion::AUTOMATIC, bary::ErrorCode::InvalidCage, "2 line cells");
}

TEST(vtkBaryConversion, StripsAreRejected)
{
  auto cube = MakeCube();
  vtkNew<vtkCellArray> strips;
  const vtkIdType s[4] = { 0, 1, 3, 2 };
  strips->InsertNextCell(4, s);
  cube->SetStrips(strips);
  ExpectToCageThrows(cube, vtkBaryConversion::AUTOMATIC, bary::ErrorCode::InvalidCage, "strips");
}

TEST(vtkBaryConversion, PolygonVisitingAPointTwiceOrMissingPointsIsRejected)
{
  auto data = Pentagon();
  data->SetPolys(OneCell({ 0, 1, 2, 2, 4 }));
  ExpectToCageThrows(data, vtkBaryConversion::CAGE_2D, bary::ErrorCode::InvalidCage, "twice");
  data->SetPolys(OneCell({ 0, 1, 2, 3 }));
  ExpectToCageThrows(
    data, vtkBaryConversion::CAGE_2D, bary::ErrorCode::InvalidCage, "visits 4 points");
}

// ---------------------------------------------------------------------------------------------
// 3D and general errors
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryConversion, TriangleSurfaceIs3D)
{
  auto cube = MakeCube();
  const vtkBaryCage cage = vtkBaryConversion::ToCage(cube);
  ASSERT_EQ(cage.Cage.dimension(), 3);
  EXPECT_EQ(cage.Cage.num_controls(), 8);
  ASSERT_EQ(cage.Cage.F.rows(), 12);
  EXPECT_TRUE(cage.IdentityOrder);
  for (vtkIdType f = 0; f < 12; ++f)
  {
    vtkIdType size;
    const vtkIdType* ids;
    cube->GetPolys()->GetCellAtId(f, size, ids);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(cage.Cage.F(f, k), ids[k]);
  }
  for (vtkIdType i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(cage.Cage.V(i, k), cube->GetPoint(i)[k]);
}

TEST(vtkBaryConversion, Forced3DWithoutFacesIsRejected)
{
  ExpectToCageThrows(
    Pentagon(), vtkBaryConversion::CAGE_3D, bary::ErrorCode::InvalidCage, "triangle faces");
}

TEST(vtkBaryConversion, TrianglesWithLinesAreRejected)
{
  auto cube = MakeCube();
  cube->SetLines(OneCell({ 0, 6 }));
  ExpectToCageThrows(
    cube, vtkBaryConversion::AUTOMATIC, bary::ErrorCode::InvalidCage, "line cells");
}

TEST(vtkBaryConversion, EmptyAndNonFiniteCagesAreRejected)
{
  ExpectToCageThrows(nullptr, 0, bary::ErrorCode::EmptyInput, "no points");
  vtkNew<vtkPolyData> empty;
  ExpectToCageThrows(empty, 0, bary::ErrorCode::EmptyInput, "no points");
  auto cube = MakeCube();
  cube->GetPoints()->SetPoint(2, 1, 1, std::numeric_limits<double>::infinity());
  ExpectToCageThrows(cube, 0, bary::ErrorCode::NonFinite, "cage point 2");
}

TEST(vtkBaryConversion, BadDimensionIsRejected)
{
  ExpectToCageThrows(MakeCube(), 1, bary::ErrorCode::InvalidArgument, "dimension");
}

// ---------------------------------------------------------------------------------------------
// Arrays and matrices
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryConversion, ToArrayFromArrayRoundTripWithPermutation)
{
  vtkBaryCage cage;
  cage.Cage.V.resize(5, 2);
  cage.ControlPointIds = { 3, 0, 4, 1, 2 }; // core control k = polydata point ids[k]
  cage.IdentityOrder = false;
  bary::DenseWeights W(4, 5);
  for (int p = 0; p < 4; ++p)
    for (int k = 0; k < 5; ++k)
      W(p, k) = 10.0 * p + k + 0.125;

  auto array = vtkBaryConversion::ToArray(W, cage, "Weights");
  ASSERT_NE(array, nullptr);
  EXPECT_STREQ(array->GetName(), "Weights");
  ASSERT_EQ(array->GetNumberOfComponents(), 5);
  ASSERT_EQ(array->GetNumberOfTuples(), 4);
  for (int p = 0; p < 4; ++p)
    for (int k = 0; k < 5; ++k)
      EXPECT_EQ(array->GetComponent(p, static_cast<int>(cage.ControlPointIds[k])), W(p, k))
        << "component j of the array belongs to polydata point j";
  EXPECT_STREQ(array->GetComponentName(2), "c2");

  const bary::DenseWeights back = vtkBaryConversion::FromArray(array, cage);
  EXPECT_EQ(back, W);

  // A float array works too (values representable exactly).
  vtkNew<vtkFloatArray> f;
  f->DeepCopy(array);
  EXPECT_EQ(vtkBaryConversion::FromArray(f, cage), W);
}

TEST(vtkBaryConversion, ToArrayIdentityOrder)
{
  vtkBaryCage cage;
  cage.Cage.V.resize(3, 2);
  cage.ControlPointIds = { 0, 1, 2 };
  bary::DenseWeights W(2, 3);
  W << 0.2, 0.3, 0.5, 1.0, 0.0, 0.0;
  auto array = vtkBaryConversion::ToArray(W, cage, "w");
  for (int p = 0; p < 2; ++p)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(array->GetComponent(p, k), W(p, k));
}

TEST(vtkBaryConversion, FromArrayRejectsWrongShapeAndNaN)
{
  vtkBaryCage cage;
  cage.Cage.V.resize(3, 2);
  cage.ControlPointIds = { 0, 1, 2 };
  vtkNew<vtkDoubleArray> two;
  two->SetNumberOfComponents(2);
  two->SetNumberOfTuples(1);
  try
  {
    vtkBaryConversion::FromArray(two, cage);
    ADD_FAILURE() << "expected SizeMismatch";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::SizeMismatch) << e.what();
  }
  vtkNew<vtkDoubleArray> nan;
  nan->SetNumberOfComponents(3);
  nan->SetNumberOfTuples(2);
  nan->Fill(1.0 / 3.0);
  nan->SetComponent(1, 2, std::numeric_limits<double>::quiet_NaN());
  try
  {
    vtkBaryConversion::FromArray(nan, cage);
    ADD_FAILURE() << "expected NonFinite";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::NonFinite) << e.what();
  }
}

TEST(vtkBaryConversion, MatricesAndSetPoints)
{
  auto data = MakePointCloud({ { 1, 2, 3 }, { 4, 5, 6 } });
  const Eigen::MatrixXd X2 = vtkBaryConversion::ToMatrix(data->GetPoints(), 2);
  ASSERT_EQ(X2.rows(), 2);
  ASSERT_EQ(X2.cols(), 2);
  EXPECT_EQ(X2(1, 0), 4.0);
  EXPECT_EQ(X2(1, 1), 5.0);
  const Eigen::MatrixXd X3 = vtkBaryConversion::PointsToMatrix(data, 3);
  ASSERT_EQ(X3.cols(), 3);
  EXPECT_EQ(X3(0, 2), 3.0);

  Eigen::MatrixXd Y(2, 2);
  Y << 10, 20, 40, 50;
  vtkBaryConversion::SetPoints(data, Y);
  EXPECT_EQ(data->GetPoint(0)[0], 10.0);
  EXPECT_EQ(data->GetPoint(1)[1], 50.0);
  EXPECT_EQ(data->GetPoint(0)[2], 3.0) << "2 columns keep z";
  EXPECT_EQ(data->GetPoint(1)[2], 6.0) << "2 columns keep z";
  Eigen::MatrixXd Z(2, 3);
  Z << 1, 1, 1, 2, 2, 2;
  vtkBaryConversion::SetPoints(data, Z);
  EXPECT_EQ(data->GetPoint(1)[2], 2.0);
}

} // namespace
