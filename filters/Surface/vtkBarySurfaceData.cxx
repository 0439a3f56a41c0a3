#include "vtkBarySurfaceData.h"

#include "vtkBaryConversion.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/surface/weighted_averages.h"

#include <cmath>
#include <limits>
#include <sstream>

vtkStandardNewMacro(vtkBarySurfaceData);

using bary::Error;
using bary::ErrorCode;

bary::SurfaceMesh vtkBarySurfaceData::ToSurfaceMesh(vtkPolyData* surface)
{
  if (!surface || surface->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, "the surface has no points");
  if (surface->GetNumberOfStrips() > 0)
    throw Error(ErrorCode::InvalidArgument, "the surface has triangle strips",
      "triangulate it first (vtkTriangleFilter)");
  vtkCellArray* polys = surface->GetPolys();
  const vtkIdType nf = polys ? polys->GetNumberOfCells() : 0;
  if (nf == 0)
    throw Error(ErrorCode::EmptyInput, "the surface has no triangles");
  Eigen::MatrixXi F(nf, 3);
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  vtkIdType f = 0;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++f)
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    it->GetCurrentCell(n, ids);
    if (n != 3)
      throw Error(ErrorCode::InvalidArgument, "polygon " + std::to_string(f) + " of the surface has " +
          std::to_string(n) + " points, not 3", "triangulate it first (vtkTriangleFilter)");
    for (int k = 0; k < 3; ++k)
      F(f, k) = static_cast<int>(ids[k]);
  }
  const Eigen::MatrixXd V = vtkBaryConversion::ToMatrix(surface->GetPoints(), 3);
  return bary::SurfaceMesh(V, F);
}

Eigen::MatrixXd vtkBarySurfaceData::Embedding(vtkPolyData* surface, const std::string& name)
{
  vtkDataArray* array = surface ? surface->GetPointData()->GetArray(name.c_str()) : nullptr;
  if (!array)
    throw Error(ErrorCode::InvalidArgument, "the surface has no point array '" + name + "'",
      "compute the embedding first (vtkBarySurfaceEmbedding, barylab embed)");
  if (array->GetNumberOfComponents() < 2)
    throw Error(ErrorCode::InvalidArgument, "the embedding array '" + name + "' has " +
        std::to_string(array->GetNumberOfComponents()) + " component(s); at least 2 are needed");
  const vtkIdType n = array->GetNumberOfTuples();
  const int D = array->GetNumberOfComponents();
  Eigen::MatrixXd E(n, D);
  for (vtkIdType i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d)
    {
      E(i, d) = array->GetComponent(i, d);
      if (!std::isfinite(E(i, d)))
        throw Error(ErrorCode::NonFinite,
          "the embedding of point " + std::to_string(i) + " is not finite");
    }
  return E;
}

std::vector<bary::SurfacePoint> vtkBarySurfaceData::Locate(const bary::SurfaceMesh& mesh,
  const Eigen::MatrixXd& P, double tolerance, const char* what, std::vector<double>* distance)
{
  bary::validate_surface_tolerance(tolerance);
  if (P.rows() == 0)
    throw Error(ErrorCode::EmptyInput, std::string("no ") + what + "s");
  std::vector<double> d;
  std::vector<bary::SurfacePoint> points = bary::closest_surface_points(mesh, P, &d);
  const double diagonal = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  const double limit = tolerance * diagonal;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d[i] > limit)
    {
      std::ostringstream s;
      s.precision(6);
      s << what << " " << i << " at " << bary::detail::format_point(P.row(static_cast<Eigen::Index>(i)).eval().data(), 3, 17)
        << " is at distance " << d[i] << " from the surface (more than " << tolerance
        << " of its size, " << limit << ")";
      throw Error(ErrorCode::PointsOutside, s.str(),
        std::string("place ") + what + "s on the surface (or raise the surface tolerance)");
    }
  if (distance)
    *distance = std::move(d);
  return points;
}

std::vector<bary::SurfacePoint> vtkBarySurfaceData::Locate(const bary::SurfaceMesh& mesh,
  vtkPointSet* points, double tolerance, const char* what, std::vector<double>* distance)
{
  if (!points || points->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, std::string("no ") + what + "s");
  return Locate(mesh, vtkBaryConversion::ToMatrix(points->GetPoints(), 3), tolerance, what, distance);
}

void vtkBarySurfaceData::AddSurfacePointArrays(
  vtkPointSet* data, const std::vector<bary::SurfacePoint>& points)
{
  vtkNew<vtkIdTypeArray> face;
  face->SetName("FaceId");
  face->SetNumberOfTuples(static_cast<vtkIdType>(points.size()));
  vtkNew<vtkDoubleArray> bary;
  bary->SetName("Barycentric");
  bary->SetNumberOfComponents(3);
  bary->SetNumberOfTuples(static_cast<vtkIdType>(points.size()));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const auto id = static_cast<vtkIdType>(i);
    face->SetValue(id, points[i].face);
    for (int k = 0; k < 3; ++k)
      bary->SetComponent(id, k, points[i].face >= 0 ? points[i].barycentric(k) : nan);
  }
  data->GetPointData()->AddArray(face);
  data->GetPointData()->AddArray(bary);
}

std::shared_ptr<const bary::WeightedAverages> vtkBarySurfaceData::Cache::Get(
  vtkPolyData* surface, const std::string& name)
{
  vtkDataArray* array = surface ? surface->GetPointData()->GetArray(name.c_str()) : nullptr;
  const vtkMTimeType surfaceTime = surface ? surface->GetMTime() : 0;
  const vtkMTimeType arrayTime = array ? array->GetMTime() : 0;
  if (this->Value && this->Surface == surface && this->SurfaceTime == surfaceTime &&
    this->ArrayTime == arrayTime && this->Name == name)
    return this->Value;
  this->Value.reset();
  bary::SurfaceMesh mesh = vtkBarySurfaceData::ToSurfaceMesh(surface);
  const Eigen::MatrixXd E = vtkBarySurfaceData::Embedding(surface, name);
  if (E.rows() != mesh.vertex_count())
    throw Error(ErrorCode::SizeMismatch, "the embedding array '" + name + "' has " +
        std::to_string(E.rows()) + " tuples but the surface has " +
        std::to_string(mesh.vertex_count()) + " points");
  this->Value = std::make_shared<const bary::WeightedAverages>(std::move(mesh), E);
  this->Surface = surface;
  this->SurfaceTime = surfaceTime;
  this->ArrayTime = arrayTime;
  this->Name = name;
  return this->Value;
}
