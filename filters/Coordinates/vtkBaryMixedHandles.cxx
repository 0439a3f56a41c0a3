#include "vtkBaryMixedHandles.h"

#include "vtkBaryConversion.h"

#include "core/common/error.h"
#include "core/coordinates/weight_method.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

vtkStandardNewMacro(vtkBaryMixedHandles);

using bary::Error;
using bary::ErrorCode;

namespace
{
enum Kind
{
  PointKind = 0,
  BoneKind = 1,
  CageKind = 2,
  RegionKind = 3
};

bool is_polygon_type(int type)
{
  return type == VTK_POLYGON || type == VTK_TRIANGLE || type == VTK_QUAD ||
    type == VTK_TRIANGLE_STRIP;
}

bool is_line_type(int type)
{
  return type == VTK_LINE || type == VTK_POLY_LINE;
}

/// The cell's point ids.
std::vector<int> cell_points(vtkPolyData* data, vtkIdType c)
{
  vtkNew<vtkIdList> ids;
  data->GetCellPoints(c, ids);
  std::vector<int> out(static_cast<std::size_t>(ids->GetNumberOfIds()));
  for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    out[static_cast<std::size_t>(k)] = static_cast<int>(ids->GetId(k));
  return out;
}

/// An integer value of a one-component array (NaN / fractions refused, named).
int integer_value(vtkDataArray* array, vtkIdType i, const std::string& what)
{
  const double v = array->GetComponent(i, 0);
  if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e9)
    throw Error(ErrorCode::InvalidArgument,
      what + " is " + std::to_string(v) + ", not an integer");
  return static_cast<int>(v);
}

/// The array @p name of @p arrays, nullptr when there is none; an array that is not numeric
/// (text) or whose tuples do not match the @p count cells / points is an error naming it, never
/// ignored or read past its end.
vtkDataArray* numeric_array(vtkFieldData* arrays, const char* name, const std::string& what,
  vtkIdType count, const char* items)
{
  vtkAbstractArray* any = arrays->GetAbstractArray(name);
  if (!any)
    return nullptr;
  vtkDataArray* array = vtkDataArray::SafeDownCast(any);
  if (!array)
    throw Error(ErrorCode::InvalidArgument,
      what + " " + name + " is not numeric (" + any->GetClassName() + "): give one integer per " +
        std::string(items).substr(0, std::strlen(items) - 1));
  if (array->GetNumberOfTuples() != count)
    throw Error(ErrorCode::SizeMismatch,
      what + " " + name + " has " + std::to_string(array->GetNumberOfTuples()) + " values but there are " +
        std::to_string(count) + " " + items);
  return array;
}

/// Segments (a, b) of a cell: a line's consecutive pairs; a polygon's, closed.
void add_segments(const std::vector<int>& ids, bool closed, std::vector<std::array<int, 2>>& out)
{
  for (std::size_t k = 0; k + 1 < ids.size(); ++k)
    if (ids[k] != ids[k + 1])
      out.push_back({ ids[k], ids[k + 1] });
  if (closed && ids.size() > 2 && ids.front() != ids.back())
    out.push_back({ ids.back(), ids.front() });
}

/// Triangles of a polygon (fan) or a triangle strip.
void add_triangles(const std::vector<int>& ids, int type, std::vector<std::array<int, 3>>& out)
{
  if (type == VTK_TRIANGLE_STRIP)
  {
    for (std::size_t k = 0; k + 2 < ids.size(); ++k)
      out.push_back(k % 2 == 0 ? std::array<int, 3>{ ids[k], ids[k + 1], ids[k + 2] }
                               : std::array<int, 3>{ ids[k + 1], ids[k], ids[k + 2] });
    return;
  }
  for (std::size_t k = 1; k + 1 < ids.size(); ++k)
    out.push_back({ ids[0], ids[k], ids[k + 1] });
}

template<std::size_t N>
Eigen::MatrixXi to_matrix(const std::vector<std::array<int, N>>& rows)
{
  Eigen::MatrixXi M(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(N));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t k = 0; k < N; ++k)
      M(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) = rows[r][k];
  return M;
}
} // namespace

bool vtkBaryMixedHandles::UsesMixedHandles(vtkPolyData* handles, vtkDataSet* domain)
{
  if (!handles || !domain)
    return false;
  if (domain->GetPointData()->GetAbstractArray(HandleRegionArrayName()) ||
    domain->GetPointData()->GetAbstractArray(ShapePreservationArrayName()))
    return true;
  if (handles->GetCellData()->GetAbstractArray(HandleTypeArrayName()))
    return true;
  if (handles->GetNumberOfPolys() == 0 && handles->GetNumberOfStrips() == 0)
    return false;
  if (handles->GetNumberOfLines() > 0 || handles->GetNumberOfVerts() > 0)
    return true;
  std::vector<char> used(static_cast<std::size_t>(handles->GetNumberOfPoints()), 0);
  for (vtkIdType c = 0; c < handles->GetNumberOfCells(); ++c)
    for (int i : cell_points(handles, c))
      used[static_cast<std::size_t>(i)] = 1;
  return std::find(used.begin(), used.end(), 0) != used.end();
}

bary::Skeleton vtkBaryMixedHandles::ToHandles(vtkPolyData* data, int dimension)
{
  if (!data || !data->GetPoints() || data->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, "the handles have no points");
  if (dimension != 2 && dimension != 3)
    throw Error(ErrorCode::InvalidArgument, "the handles' dimension must be 2 or 3");
  vtkPoints* points = data->GetPoints();
  const vtkIdType n = points->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw Error(ErrorCode::NonFinite, "handle point " + std::to_string(i) + " is NaN or infinite");
  }
  if (dimension == 2)
  {
    double b[6];
    points->GetBounds(b);
    if (b[5] - b[4] > 1e-9 * std::max(1.0, std::max(b[1] - b[0], b[3] - b[2])))
      throw Error(ErrorCode::InvalidArgument,
        "2D handles must lie in a plane z = const, but their z ranges over [" +
          std::to_string(b[4]) + ", " + std::to_string(b[5]) + "]");
  }
  vtkDataArray* kinds = numeric_array(
    data->GetCellData(), HandleTypeArrayName(), "the handles' cell array", data->GetNumberOfCells(), "cells");
  vtkDataArray* region_ids = numeric_array(
    data->GetCellData(), RegionIdArrayName(), "the handles' cell array", data->GetNumberOfCells(), "cells");
  if (kinds && kinds->GetNumberOfComponents() != 1)
    throw Error(ErrorCode::InvalidArgument,
      std::string("the handles' cell array ") + HandleTypeArrayName() + " must have one component");
  if (region_ids && region_ids->GetNumberOfComponents() != 1)
    throw Error(ErrorCode::InvalidArgument,
      std::string("the handles' cell array ") + RegionIdArrayName() + " must have one component");

  std::vector<char> on_cell(static_cast<std::size_t>(n), 0);
  std::vector<int> point_handles;
  std::vector<std::array<int, 2>> bones, cage_segments;
  std::vector<std::array<int, 3>> cage_triangles;
  // Regions by key (RegionId, or the cell id without the array), in ascending key.
  std::map<long long, std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 3>>>>
    regions;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
  {
    const int type = data->GetCellType(c);
    const std::vector<int> ids = cell_points(data, c);
    const std::string name = "handle cell " + std::to_string(c);
    int kind = type == VTK_VERTEX || type == VTK_POLY_VERTEX ? PointKind
      : is_line_type(type)                                 ? BoneKind
      : is_polygon_type(type)                              ? CageKind
                                                           : -1;
    if (kinds)
      kind = integer_value(kinds, c, name + "'s " + HandleTypeArrayName());
    if (type == VTK_EMPTY_CELL)
      continue;
    switch (kind)
    {
      case PointKind:
        if (type != VTK_VERTEX && type != VTK_POLY_VERTEX)
          throw Error(ErrorCode::InvalidArgument,
            name + " is marked a point handle (HandleType 0) but is not a vertex cell");
        for (int i : ids)
          point_handles.push_back(i);
        break;
      case BoneKind:
        if (!is_line_type(type))
          throw Error(ErrorCode::InvalidArgument,
            name + " is marked a bone (HandleType 1) but is not a line or polyline");
        add_segments(ids, false, bones);
        break;
      case CageKind:
        if (is_line_type(type))
          add_segments(ids, false, cage_segments);
        else if (is_polygon_type(type) && dimension == 2)
          add_segments(ids, true, cage_segments);
        else if (is_polygon_type(type))
          add_triangles(ids, type, cage_triangles);
        else
          throw Error(ErrorCode::InvalidArgument,
            name + " is marked a cage (HandleType 2) but is neither a line nor a polygon");
        break;
      case RegionKind:
      {
        const long long key = region_ids
          ? integer_value(region_ids, c, name + "'s " + RegionIdArrayName())
          : static_cast<long long>(c);
        auto& region = regions[key];
        if (dimension == 2 && (is_polygon_type(type) || type == VTK_POLY_LINE))
          add_segments(ids, true, region.first);
        else if (dimension == 3 && is_polygon_type(type))
          add_triangles(ids, type, region.second);
        else
          throw Error(ErrorCode::InvalidArgument,
            name + " is marked a region (HandleType 3) but is not " +
              (dimension == 2 ? "a polygon or closed polyline" : "a polygon (a closed surface's face)"));
        break;
      }
      default:
        throw Error(ErrorCode::InvalidArgument,
          name + (kinds ? " has HandleType " + std::to_string(kind) +
                       ": 0 point, 1 bone, 2 cage, 3 region"
                        : " has an unsupported cell type " + std::to_string(type)));
    }
    if (kind != PointKind)
      for (int i : ids)
        on_cell[static_cast<std::size_t>(i)] = 1;
  }
  for (vtkIdType i = 0; i < n; ++i)
    if (!on_cell[static_cast<std::size_t>(i)])
      point_handles.push_back(static_cast<int>(i));
  std::sort(point_handles.begin(), point_handles.end());
  point_handles.erase(std::unique(point_handles.begin(), point_handles.end()), point_handles.end());
  if (!cage_segments.empty() && !cage_triangles.empty())
    throw Error(ErrorCode::InvalidArgument,
      "the cage mixes segments and triangles: give a 3D cage as triangles only");

  bary::Skeleton s;
  s.C = vtkBaryConversion::ToMatrix(points, dimension);
  s.P = Eigen::Map<const Eigen::VectorXi>(point_handles.data(), static_cast<Eigen::Index>(point_handles.size()));
  s.BE = to_matrix(bones);
  s.CF = cage_triangles.empty() ? to_matrix(cage_segments) : to_matrix(cage_triangles);
  for (const auto& [key, faces] : regions)
    s.regions.push_back(dimension == 2 ? to_matrix(faces.first) : to_matrix(faces.second));
  bary::validate_skeleton(s);
  return s;
}

std::vector<std::vector<int>> vtkBaryMixedHandles::RegionVertices(vtkDataSet* domain)
{
  vtkDataArray* array = domain ? numeric_array(domain->GetPointData(), HandleRegionArrayName(),
                                    "the domain's point array", domain->GetNumberOfPoints(), "points")
                               : nullptr;
  if (!array)
    return {};
  if (array->GetNumberOfComponents() != 1)
    throw Error(ErrorCode::InvalidArgument,
      std::string("the domain's point array ") + HandleRegionArrayName() + " must have one component");
  std::map<int, std::vector<int>> by_value;
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    const int v = integer_value(array, i,
      std::string(HandleRegionArrayName()) + " at domain vertex " + std::to_string(i));
    if (v < -1)
      throw Error(ErrorCode::InvalidArgument,
        std::string(HandleRegionArrayName()) + " at domain vertex " + std::to_string(i) + " is " +
          std::to_string(v) + ": use -1 for no region, k >= 0 for region k");
    if (v >= 0)
      by_value[v].push_back(static_cast<int>(i));
  }
  std::vector<std::vector<int>> regions;
  for (auto& [value, vertices] : by_value)
    regions.push_back(std::move(vertices));
  return regions;
}

Eigen::VectorXd vtkBaryMixedHandles::ShapePreservation(vtkDataSet* domain)
{
  vtkDataArray* array =
    domain ? domain->GetPointData()->GetArray(ShapePreservationArrayName()) : nullptr;
  if (!array)
  {
    if (domain && domain->GetPointData()->GetAbstractArray(ShapePreservationArrayName()))
      throw Error(ErrorCode::InvalidArgument,
        std::string("the domain's ") + ShapePreservationArrayName() + " array is not numeric");
    return {};
  }
  if (array->GetNumberOfComponents() != 1)
    throw Error(ErrorCode::SizeMismatch,
      std::string("the domain's point array ") + ShapePreservationArrayName() + " has " +
        std::to_string(array->GetNumberOfComponents()) + " components, expected 1 (rho per vertex)");
  Eigen::VectorXd rho(array->GetNumberOfTuples());
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
    rho(i) = array->GetComponent(i, 0);
  return rho; // checked (finite, >= 0, one per vertex) by bary::shape_preservation_per_element
}

bary::WeightsResult vtkBaryMixedHandles::Compute(const bary::WeightsSettings& settings,
  vtkDataSet* input, vtkPolyData* handles, vtkDataSet* domain, const bary::ProgressCallback& progress,
  const bary::MeshWeights* solved)
{
  const int dim = vtkBaryConversion::DomainDimension(domain);
  const std::vector<std::vector<int>> regions = RegionVertices(domain);
  const Eigen::VectorXd brush = ShapePreservation(domain);
  // Handles: the cells and free points of input 1; a file of only the domain's regions may
  // have no handle there (its points are then ignored).
  bary::Skeleton skeleton;
  const bool region_only = !regions.empty() && handles->GetNumberOfCells() == 0 &&
    handles->GetNumberOfPoints() == 0;
  if (!region_only)
    skeleton = ToHandles(handles, dim);
  const Eigen::MatrixXd points = vtkBaryConversion::PointsToMatrix(input, dim);
  bool tets = false, triangles = false, polygons = false;
  for (vtkIdType c = 0; c < domain->GetNumberOfCells(); ++c)
  {
    const int type = domain->GetCellType(c);
    tets = tets || type == VTK_TETRA;
    triangles = triangles || type == VTK_TRIANGLE;
    polygons = polygons || type == VTK_POLYGON || type == VTK_POLY_LINE || type == VTK_QUAD;
  }
  bary::WeightsInput in;
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  vtkBaryCage boundary;
  if (tets || (dim == 2 && triangles && !polygons))
  {
    vtkBaryConversion::ToSimplices(domain, dim, V, T);
    in.domain_V = &V;
    in.domain_T = &T;
  }
  else
  {
    vtkPolyData* surface = vtkPolyData::SafeDownCast(domain);
    if (!surface)
      throw Error(ErrorCode::InvalidArgument,
        "a domain to be meshed must be a vtkPolyData (a closed triangle surface or a polygon)");
    boundary = vtkBaryConversion::ToCage(surface, dim);
    in.domain_boundary = &boundary.Cage;
  }
  in.skeleton = &skeleton;
  in.points = &points;
  in.region_vertices = regions.empty() ? nullptr : &regions;
  in.shape_preservation = brush.size() > 0 ? &brush : nullptr;
  in.mesh_weights = solved;
  return bary::compute_weights(in, settings, progress);
}
