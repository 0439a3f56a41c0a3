// vtkBaryEnclosingCage: the cage it makes encloses the model, checked independently of core's
// exact predicates: 3D by ray casting (crossings of a ray with the cage's triangles, Moller-
// Trumbore, three skew directions that must agree) and a brute-force segment / triangle test of
// the model's edges against the cage; 2D by vtkPolygon::PointInPolygon. Closedness and
// orientation by edge counting. Errors carry bary's error codes.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBaryEnclosingCage.h"

#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkIdList.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <utility>

using namespace barylab_test;

namespace
{
using Vec = Eigen::Vector3d;

Vec Point(vtkPolyData* data, vtkIdType i)
{
  double p[3];
  data->GetPoint(i, p);
  return Vec(p[0], p[1], p[2]);
}

// Parameter t in (0, 1] where segment o + t d meets triangle (a, b, c), or -1.
double SegmentTriangle(const Vec& o, const Vec& d, const Vec& a, const Vec& b, const Vec& c)
{
  const Vec e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300)
    return -1.0;
  const Vec s = o - a;
  const double u = s.dot(p) / det;
  const Vec q = s.cross(e1);
  const double v = d.dot(q) / det;
  const double t = e2.dot(q) / det;
  return (u >= 0 && v >= 0 && u + v <= 1 && t >= 0 && t <= 1) ? t : -1.0;
}

// Crossings of the ray from x along dir (long enough to leave the cage) with the cage.
int Crossings(vtkPolyData* cage, const Vec& x, const Vec& dir)
{
  int n = 0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cage->GetNumberOfCells(); ++c)
  {
    cage->GetCellPoints(c, ids);
    n += SegmentTriangle(x, 1e3 * dir, Point(cage, ids->GetId(0)), Point(cage, ids->GetId(1)),
           Point(cage, ids->GetId(2))) >= 0.0;
  }
  return n;
}

// Every directed edge once and its reverse once: closed, consistently oriented.
bool ClosedAndOriented(vtkPolyData* cage)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> directed;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cage->GetNumberOfCells(); ++c)
  {
    cage->GetCellPoints(c, ids);
    if (cage->GetCellType(c) != VTK_TRIANGLE)
      return false;
    for (int k = 0; k < 3; ++k)
      ++directed[{ ids->GetId(k), ids->GetId((k + 1) % 3) }];
  }
  for (const auto& [e, count] : directed)
  {
    const auto r = directed.find({ e.second, e.first });
    if (count != 1 || r == directed.end() || r->second != 1)
      return false;
  }
  return true;
}

double SignedVolume(vtkPolyData* cage)
{
  double v = 0.0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cage->GetNumberOfCells(); ++c)
  {
    cage->GetCellPoints(c, ids);
    v += Point(cage, ids->GetId(0)).dot(Point(cage, ids->GetId(1)).cross(Point(cage, ids->GetId(2)))) / 6.0;
  }
  return v;
}
} // namespace

TEST(vtkBaryEnclosingCage, SphereIsEnclosedByAClosedOutwardCage)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(0.5);
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(24);
  sphere->Update();
  vtkPolyData* model = sphere->GetOutput();
  vtkNew<vtkBaryEnclosingCage> filter;
  filter->SetInputData(model);
  filter->SetNumberOfVertices(40);
  filter->SetMarginFraction(0.15); // a coarser grid than the default 0.05: a faster test
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  vtkPolyData* cage = filter->GetOutput();
  EXPECT_EQ(cage->GetNumberOfPoints(), 40);
  EXPECT_EQ(cage->GetNumberOfCells(), 76); // genus 0: 2V - 4
  EXPECT_TRUE(filter->GetReachedTarget());
  ASSERT_TRUE(ClosedAndOriented(cage));
  EXPECT_GT(SignedVolume(cage), 0.0) << "outward normals";
  // Inside: odd crossings along three skew directions.
  const Vec dirs[3] = { Vec(0.31, 0.77, 0.55).normalized(), Vec(-0.62, 0.21, 0.75).normalized(),
    Vec(0.13, -0.91, 0.39).normalized() };
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
    for (const Vec& d : dirs)
      ASSERT_EQ(Crossings(cage, Point(model, i), d) % 2, 1) << "model point " << i;
  // No model edge meets a cage triangle.
  vtkNew<vtkIdList> ids, cids;
  for (vtkIdType c = 0; c < model->GetNumberOfCells(); ++c)
  {
    model->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      const Vec a = Point(model, ids->GetId(k)),
                b = Point(model, ids->GetId((k + 1) % ids->GetNumberOfIds()));
      for (vtkIdType f = 0; f < cage->GetNumberOfCells(); ++f)
      {
        cage->GetCellPoints(f, cids);
        ASSERT_LT(SegmentTriangle(a, b - a, Point(cage, cids->GetId(0)), Point(cage, cids->GetId(1)),
                    Point(cage, cids->GetId(2))),
          0.0);
      }
    }
  }
  // The reported figures: the sphere's volume (a polyhedron slightly under 4/3 pi r^3) and
  // distances at about the margin.
  EXPECT_NEAR(filter->GetCageMeasure(), SignedVolume(cage), 1e-12);
  EXPECT_NEAR(filter->GetModelMeasure(), 4.0 / 3.0 * 3.141592653589793 * 0.125, 0.02);
  EXPECT_GT(filter->GetVolumeRatio(), 1.0);
  EXPECT_NEAR(filter->GetMarginUsed(), 0.15 * filter->GetDiagonal(), 1e-15);
  EXPECT_GT(filter->GetMaximumDistance(), 0.0);
  EXPECT_LE(filter->GetMeanDistance(), filter->GetMaximumDistance());
}

TEST(vtkBaryEnclosingCage, PlanarModelGivesAPolygonInItsPlane)
{
  vtkSmartPointer<vtkPolyData> model = ReadData("model2d.obj");
  ASSERT_TRUE(model);
  vtkNew<vtkBaryEnclosingCage> filter;
  filter->SetInputData(model);
  filter->SetNumberOfVertices(16);
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
  vtkPolyData* cage = filter->GetOutput();
  ASSERT_EQ(cage->GetNumberOfCells(), 1);
  EXPECT_EQ(cage->GetCellType(0), VTK_POLYGON);
  ASSERT_EQ(cage->GetNumberOfPoints(), 16);
  double b[6];
  cage->GetBounds(b);
  EXPECT_EQ(b[4], 0.0);
  EXPECT_EQ(b[5], 0.0);
  // VTK's point-in-polygon for every model point.
  std::vector<double> poly;
  for (vtkIdType i = 0; i < 16; ++i)
  {
    const Vec p = Point(cage, i);
    poly.insert(poly.end(), { p.x(), p.y(), 0.0 });
  }
  double bounds[6], normal[3] = { 0, 0, 1 };
  cage->GetBounds(bounds);
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
  {
    double x[3];
    model->GetPoint(i, x);
    ASSERT_EQ(vtkPolygon::PointInPolygon(x, 16, poly.data(), bounds, normal), 1) << i;
  }
  // The cage as vtkBaryConversion reads cages: a valid 2D cage.
  EXPECT_NO_THROW(vtkBaryConversion::ToCage(cage));
}

TEST(vtkBaryEnclosingCage, PolygonAsBarePointsOrPolylineIsEnclosed)
{
  // A star in the plane z = 0.5: bare points in polygon order (the .obj habit), then the same
  // points as one open polyline. Both are enclosed as segments.
  std::vector<std::array<double, 3>> star;
  for (int i = 0; i < 14; ++i)
  {
    const double t = 2.0 * 3.141592653589793 * i / 14, r = i % 2 ? 0.45 : 1.0;
    star.push_back({ r * std::cos(t), r * std::sin(t), 0.5 });
  }
  vtkSmartPointer<vtkPolyData> points = MakePointCloud(star);
  vtkNew<vtkPolyData> polyline;
  polyline->SetPoints(points->GetPoints());
  vtkNew<vtkCellArray> lines;
  std::vector<vtkIdType> ids(star.size());
  for (std::size_t i = 0; i < ids.size(); ++i)
    ids[i] = static_cast<vtkIdType>(i);
  lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  polyline->SetLines(lines);
  for (vtkPolyData* model : { points.Get(), polyline.Get() })
  {
    vtkNew<vtkBaryEnclosingCage> filter;
    filter->SetInputData(model);
    filter->SetNumberOfVertices(10);
    filter->SetMarginFraction(0.1);
    vtkNew<ErrorObserver> observer;
    observer->Attach(filter);
    ASSERT_EQ(RunPipeline(filter), 1) << observer->AllErrors();
    vtkPolyData* cage = filter->GetOutput();
    ASSERT_EQ(cage->GetNumberOfCells(), 1);
    const vtkIdType n = cage->GetNumberOfPoints();
    EXPECT_EQ(n, 10);
    std::vector<double> poly;
    for (vtkIdType i = 0; i < n; ++i)
    {
      const Vec p = Point(cage, i);
      EXPECT_EQ(p.z(), 0.5) << "in the model's plane";
      poly.insert(poly.end(), { p.x(), p.y(), 0.5 });
    }
    double bounds[6], normal[3] = { 0, 0, 1 };
    cage->GetBounds(bounds);
    for (const auto& x : star)
    {
      double q[3] = { x[0], x[1], x[2] };
      EXPECT_EQ(vtkPolygon::PointInPolygon(q, static_cast<int>(n), poly.data(), bounds, normal), 1);
    }
  }
}

TEST(vtkBaryEnclosingCage, BadInputFailsWithItsErrorCode)
{
  vtkNew<vtkBaryEnclosingCage> filter;
  vtkNew<ErrorObserver> observer;
  observer->Attach(filter);
  vtkNew<vtkPolyData> empty;
  filter->SetInputData(empty);
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("no points")) << observer->AllErrors();
  EXPECT_EQ(vtkBaryConversion::ErrorCodeOf(filter->GetErrorCode(), bary::ErrorCode::Internal),
    bary::ErrorCode::EmptyInput);

  observer->Clear();
  filter->SetInputData(MakeCube());
  filter->SetNumberOfVertices(3); // a closed surface needs 4
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("at least 4")) << observer->AllErrors();
  EXPECT_EQ(vtkBaryConversion::ErrorCodeOf(filter->GetErrorCode(), bary::ErrorCode::Internal),
    bary::ErrorCode::InvalidArgument);

  observer->Clear();
  vtkNew<vtkPolyData> quad; // a quadrilateral in 3D: triangles only
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(1, 1, 1);
  pts->InsertNextPoint(0, 1, 1);
  quad->SetPoints(pts);
  vtkNew<vtkCellArray> cells;
  const vtkIdType q[4] = { 0, 1, 2, 3 };
  cells->InsertNextCell(4, q);
  quad->SetPolys(cells);
  filter->SetInputData(quad);
  filter->SetNumberOfVertices(8);
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(observer->HasError("must be triangles")) << observer->AllErrors();
}
