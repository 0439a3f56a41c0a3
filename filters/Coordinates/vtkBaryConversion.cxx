#include "vtkBaryConversion.h"

#include "core/common/error.h"
#include "core/analysis/locality_statistics.h"

#include "vtkCell.h"
#include "vtkCellArray.h"
#include "vtkDataSet.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkErrorCode.h"
#include "vtkIdList.h"
#include "vtkObjectFactory.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <cstring>
#include <string>
#include <type_traits>

vtkStandardNewMacro(vtkBaryConversion);

namespace
{
using bary::Error;
using bary::ErrorCode;

[[noreturn]] void fail(const std::string& message)
{
  throw Error(ErrorCode::InvalidCage, "invalid cage: " + message);
}

/// Throws Error(NonFinite) naming the first point with a NaN / infinite coordinate, called
/// "<what> <id>".
void check_finite(vtkPoints* points, const char* what = "cage point")
{
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw Error(ErrorCode::NonFinite,
        std::string(what) + " " + std::to_string(i) + " has a non-finite coordinate (NaN or inf)");
  }
}

/// True if the points lie in a plane z = const up to round-off (relative to their xy extent).
/// One tolerance for every 2D form (polygon cell, polyline, bare points).
bool flat_in_z(vtkPoints* points, double bounds[6])
{
  points->GetBounds(bounds);
  const double extent = std::max(bounds[1] - bounds[0], bounds[3] - bounds[2]);
  return bounds[5] - bounds[4] <= 1e-9 * std::max(1.0, extent);
}

/// Builds a 2D cage from the polygon order @p order (point ids).
vtkBaryCage make_polygon(vtkPoints* points, std::vector<vtkIdType> order, const char* source)
{
  const vtkIdType n = points->GetNumberOfPoints();
  if (order.size() > 1 && order.front() == order.back())
    order.pop_back(); // closed polyline repeats its first point
  if (static_cast<vtkIdType>(order.size()) != n)
    fail(std::string("the 2D cage ") + source + " visits " + std::to_string(order.size()) +
      " points but the cage has " + std::to_string(n) +
      "; every cage point must appear exactly once along the polygon");
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (vtkIdType id : order)
  {
    if (id < 0 || id >= n || seen[static_cast<std::size_t>(id)]++)
      fail(std::string("the 2D cage ") + source + " visits point " + std::to_string(id) +
        " twice; every cage point must appear exactly once along the polygon");
  }
  double bounds[6];
  if (!flat_in_z(points, bounds))
    fail("a 2D cage (polygon) must lie in a plane z = const, but its z ranges over [" +
      std::to_string(bounds[4]) + ", " + std::to_string(bounds[5]) +
      "]; a 3D cage needs triangle faces");
  vtkBaryCage cage;
  cage.Cage.V.resize(n, 2);
  cage.ControlPointIds = order;
  cage.PlaneZ = bounds[4];
  for (vtkIdType k = 0; k < n; ++k)
  {
    double x[3];
    points->GetPoint(order[static_cast<std::size_t>(k)], x);
    cage.Cage.V(k, 0) = x[0];
    cage.Cage.V(k, 1) = x[1];
    cage.IdentityOrder = cage.IdentityOrder && order[static_cast<std::size_t>(k)] == k;
  }
  return cage;
}

std::vector<vtkIdType> cell_ids(vtkCellArray* cells, vtkIdType cell)
{
  vtkNew<vtkIdList> ids;
  cells->GetCellAtId(cell, ids);
  return std::vector<vtkIdType>(ids->begin(), ids->end());
}
} // namespace

vtkBaryCage vtkBaryConversion::ToCage(vtkPolyData* data, int dimension)
{
  if (!data || !data->GetPoints() || data->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, "the cage has no points");
  if (dimension != AUTOMATIC && dimension != CAGE_2D && dimension != CAGE_3D)
    throw Error(ErrorCode::InvalidArgument, "cage dimension must be 0 (automatic), 2 or 3");
  vtkPoints* points = data->GetPoints();
  check_finite(points);
  const vtkIdType npolys = data->GetNumberOfPolys(), nlines = data->GetNumberOfLines();
  if (data->GetNumberOfStrips() > 0)
    fail("triangle strips are not supported; convert the cage with vtkTriangleFilter");

  bool three_d = false;
  if (dimension == CAGE_3D)
    three_d = true;
  else if (dimension == AUTOMATIC && npolys > 0)
  {
    // a single polygon in a plane z = const is a 2D cage; anything else with faces is 3D
    three_d = true;
    if (npolys == 1)
    {
      double bounds[6];
      three_d = !flat_in_z(points, bounds);
    }
  }

  if (three_d)
  {
    if (npolys == 0)
      fail("a 3D cage needs triangle faces, but the data has none (only " +
        std::to_string(nlines) + " lines and " + std::to_string(data->GetNumberOfVerts()) +
        " vertices)");
    if (nlines > 0)
      fail("a 3D cage must consist of triangles only, but it also has " +
        std::to_string(nlines) + " line cells");
    vtkBaryCage cage;
    const vtkIdType n = points->GetNumberOfPoints();
    cage.Cage.V.resize(n, 3);
    for (vtkIdType i = 0; i < n; ++i)
    {
      double x[3];
      points->GetPoint(i, x);
      cage.Cage.V.row(i) << x[0], x[1], x[2];
    }
    vtkCellArray* polys = data->GetPolys();
    cage.Cage.F.resize(npolys, 3);
    for (vtkIdType f = 0; f < npolys; ++f)
    {
      const vtkIdType size = polys->GetCellSize(f);
      if (size != 3)
        fail("cage face " + std::to_string(f) + " has " + std::to_string(size) +
          " vertices; 3D cages must be triangulated (e.g. with vtkTriangleFilter)");
      const auto ids = cell_ids(polys, f);
      for (int k = 0; k < 3; ++k)
        cage.Cage.F(f, k) = static_cast<int>(ids[static_cast<std::size_t>(k)]);
    }
    cage.ControlPointIds.resize(static_cast<std::size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
      cage.ControlPointIds[static_cast<std::size_t>(i)] = i;
    return cage;
  }

  // 2D
  if (npolys > 1)
    fail("a 2D cage is one polygon, but the data has " + std::to_string(npolys) +
      " polygons (a 3D cage needs triangles forming a closed surface)");
  if (npolys == 1)
  {
    if (nlines > 0)
      fail("a 2D cage is one polygon, but the data also has line cells");
    return make_polygon(points, cell_ids(data->GetPolys(), 0), "polygon");
  }
  if (nlines > 1)
    fail("a 2D cage is one closed polyline, but the data has " + std::to_string(nlines) +
      " line cells; join them into one polyline");
  if (nlines == 1)
    return make_polygon(points, cell_ids(data->GetLines(), 0), "polyline");
  // bare points (an .obj with only v lines): the polygon in point order
  std::vector<vtkIdType> order(static_cast<std::size_t>(points->GetNumberOfPoints()));
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = static_cast<vtkIdType>(i);
  return make_polygon(points, order, "given as points in order");
}

Eigen::MatrixXd vtkBaryConversion::ToMatrix(vtkPoints* points, int dimension)
{
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  Eigen::MatrixXd X(n, dimension);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    for (int k = 0; k < dimension; ++k)
      X(i, k) = x[k];
  }
  return X;
}

Eigen::MatrixXd vtkBaryConversion::PointsToMatrix(vtkDataSet* data, int dimension)
{
  const vtkIdType n = data ? data->GetNumberOfPoints() : 0;
  Eigen::MatrixXd X(n, dimension);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    data->GetPoint(i, x);
    for (int k = 0; k < dimension; ++k)
      X(i, k) = x[k];
  }
  return X;
}

vtkSmartPointer<vtkDoubleArray> vtkBaryConversion::ToArray(
  const bary::DenseWeights& W, const vtkBaryCage& cage, const char* name)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(static_cast<int>(W.cols()));
  array->SetNumberOfTuples(W.rows());
  double* out = array->GetPointer(0);
  const vtkIdType nc = W.cols();
  if (cage.IdentityOrder)
    std::copy(W.data(), W.data() + W.size(), out);
  else
    for (vtkIdType p = 0; p < W.rows(); ++p)
      for (vtkIdType k = 0; k < nc; ++k)
        out[p * nc + cage.ControlPointIds[static_cast<std::size_t>(k)]] = W(p, k);
  for (vtkIdType k = 0; k < nc; ++k)
    array->SetComponentName(k, ("c" + std::to_string(k)).c_str());
  return array;
}

vtkSmartPointer<vtkDoubleArray> vtkBaryConversion::FaceArray(
  const bary::DenseWeights& face_weights, const char* name)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(static_cast<int>(face_weights.cols()));
  array->SetNumberOfTuples(face_weights.rows());
  std::copy(face_weights.data(), face_weights.data() + face_weights.size(), array->GetPointer(0));
  for (vtkIdType j = 0; j < face_weights.cols(); ++j)
    array->SetComponentName(j, ("f" + std::to_string(j)).c_str());
  return array;
}

std::string vtkBaryConversion::CountText(double value)
{
  if (value == std::floor(value) && std::fabs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  std::ostringstream out; // "nan", "1e+30", "2.5"
  out << value;
  return out.str();
}

vtkDataArray* vtkBaryConversion::FindPointArray(vtkDataSet* data, const std::string& name)
{
  if (!data || name.empty())
    return nullptr;
  vtkAbstractArray* any = data->GetPointData()->GetAbstractArray(name.c_str());
  if (!any)
    return nullptr;
  vtkDataArray* numbers = vtkDataArray::SafeDownCast(any);
  if (!numbers)
    throw Error(ErrorCode::InvalidArgument,
      "the point-data array '" + name + "' holds " +
        (any->IsA("vtkStringArray") ? std::string("text") : std::string(any->GetClassName())) +
        ", not numbers");
  return numbers;
}

vtkDataArray* vtkBaryConversion::RequirePointArray(
  vtkDataSet* data, const std::string& name, const std::string& advice)
{
  if (vtkDataArray* array = FindPointArray(data, name))
    return array;
  std::string names;
  for (int i = 0; data && i < data->GetPointData()->GetNumberOfArrays(); ++i)
    if (const char* n = data->GetPointData()->GetArrayName(i))
      names += (names.empty() ? "" : ", ") + std::string(n);
  throw Error(ErrorCode::InvalidArgument,
    "no point-data array '" + name + "' (arrays present: " + (names.empty() ? "none" : names) +
      ")",
    advice);
}

bary::DenseWeights vtkBaryConversion::ArrayToMatrix(vtkDataArray* array)
{
  if (!array)
    return bary::DenseWeights();
  const int nc = array->GetNumberOfComponents();
  bary::DenseWeights W(array->GetNumberOfTuples(), nc);
  for (vtkIdType p = 0; p < W.rows(); ++p)
    for (int k = 0; k < nc; ++k)
      W(p, k) = array->GetComponent(p, k);
  return W;
}

Eigen::MatrixXd vtkBaryConversion::ControlPoints(vtkPointSet* points, const vtkBaryCage& cage)
{
  const vtkIdType nc = static_cast<vtkIdType>(cage.ControlPointIds.size());
  const vtkIdType np = points ? points->GetNumberOfPoints() : 0;
  if (np != nc)
    throw Error(ErrorCode::SizeMismatch,
      "the deformed cage has " + std::to_string(np) + " points but the rest cage has " +
        std::to_string(nc) + "; both must list the same control points in the same order");
  const int dim = cage.Cage.dimension();
  Eigen::MatrixXd C(nc, dim);
  for (vtkIdType k = 0; k < nc; ++k)
  {
    double x[3];
    points->GetPoint(cage.ControlPointIds[static_cast<std::size_t>(k)], x);
    for (int d = 0; d < dim; ++d)
      C(k, d) = x[d];
  }
  if (!C.allFinite())
    throw Error(ErrorCode::NonFinite, "the deformed cage has non-finite coordinates (NaN or inf)");
  return C;
}

bary::DenseWeights vtkBaryConversion::FromArray(vtkDataArray* array, const vtkBaryCage& cage)
{
  const vtkIdType nc = static_cast<vtkIdType>(cage.ControlPointIds.size());
  if (!array || array->GetNumberOfComponents() != nc)
    throw Error(ErrorCode::SizeMismatch,
      "the weights array has " + std::to_string(array ? array->GetNumberOfComponents() : 0) +
        " components but the cage has " + std::to_string(nc) + " control points");
  bary::DenseWeights W(array->GetNumberOfTuples(), nc);
  const auto& ids = cage.ControlPointIds;
  bool identity = true;
  for (vtkIdType k = 0; k < nc; ++k)
    identity = identity && ids[static_cast<std::size_t>(k)] == k;
  // Double and float arrays are read through their memory (tuples are rows, as in W): a
  // virtual GetComponent per weight took 2/3 of the time of deforming 10^6 points by given
  // weights (72 controls).
  const auto copy = [&](const auto* values) {
    if constexpr (std::is_same_v<std::decay_t<decltype(*values)>, double>)
      if (identity)
      {
        std::memcpy(W.data(), values, sizeof(double) * static_cast<std::size_t>(W.size()));
        return;
      }
    for (vtkIdType p = 0; p < W.rows(); ++p)
      for (vtkIdType k = 0; k < nc; ++k)
        W(p, k) = static_cast<double>(values[p * nc + ids[static_cast<std::size_t>(k)]]);
  };
  if (auto* d = vtkDoubleArray::FastDownCast(array))
    copy(d->GetPointer(0));
  else if (auto* f = vtkFloatArray::FastDownCast(array))
    copy(f->GetPointer(0));
  else
    for (vtkIdType p = 0; p < W.rows(); ++p)
      for (vtkIdType k = 0; k < nc; ++k)
        W(p, k) = array->GetComponent(p, static_cast<int>(ids[static_cast<std::size_t>(k)]));
  if (!W.allFinite())
    for (vtkIdType p = 0; p < W.rows(); ++p)
      if (!W.row(p).allFinite())
        throw Error(ErrorCode::NonFinite,
          "the weights array contains NaN or infinite values (first at point " +
            std::to_string(p) + ")");
  return W;
}

void vtkBaryConversion::SetPoints(vtkPointSet* data, const Eigen::MatrixXd& X)
{
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(X.rows());
  double* out = coordinates->GetPointer(0); // written directly: no virtual call per point
  for (vtkIdType i = 0; i < X.rows(); ++i)
  {
    double* x = out + 3 * i;
    x[2] = 0.0;
    if (X.cols() == 2)
      data->GetPoint(i, x);
    for (int k = 0; k < X.cols(); ++k)
      x[k] = X(i, k);
  }
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  data->SetPoints(points);
}

unsigned long vtkBaryConversion::ToVTKErrorCode(bary::ErrorCode code)
{
  return vtkErrorCode::UserError + 1 + static_cast<unsigned long>(code);
}

bary::ErrorCode vtkBaryConversion::ErrorCodeOf(unsigned long vtkCode, bary::ErrorCode fallback)
{
  const unsigned long first = vtkErrorCode::UserError + 1;
  const unsigned long last = first + static_cast<unsigned long>(bary::ErrorCode::Internal);
  return (vtkCode >= first && vtkCode <= last) ? static_cast<bary::ErrorCode>(vtkCode - first)
                                               : fallback;
}

vtkBaryCage vtkBaryConversion::ToControlPoints(vtkPolyData* data, int dimension)
{
  if (!data || !data->GetPoints() || data->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, "the control points file has no points");
  if (dimension != AUTOMATIC && dimension != CAGE_2D && dimension != CAGE_3D)
    throw Error(ErrorCode::InvalidArgument, "the control points' dimension must be 0 (automatic), 2 or 3");
  vtkPoints* points = data->GetPoints();
  const vtkIdType n = points->GetNumberOfPoints();
  check_finite(points, "control point");
  double bounds[6];
  const bool flat = flat_in_z(points, bounds);
  const int dim = dimension == AUTOMATIC ? (flat ? 2 : 3) : dimension;
  if (dim == 2 && !flat)
    throw Error(ErrorCode::InvalidArgument,
      "2D control points must lie in a plane z = const, but their z ranges over [" +
        std::to_string(bounds[4]) + ", " + std::to_string(bounds[5]) + "]");
  vtkBaryCage controls;
  controls.Cage.V = ToMatrix(points, dim);
  controls.ControlPointIds.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
    controls.ControlPointIds[static_cast<std::size_t>(i)] = i;
  controls.PlaneZ = bounds[4];
  return controls;
}

Eigen::MatrixXi vtkBaryConversion::CellEdges(vtkDataSet* data)
{
  std::vector<std::array<int, 2>> edges;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; data && c < data->GetNumberOfCells(); ++c)
  {
    vtkCell* cell = data->GetCell(c);
    const int ne = cell->GetNumberOfEdges();
    if (ne == 0 && cell->GetNumberOfPoints() == 2)
    {
      const int a = static_cast<int>(cell->GetPointId(0)), b = static_cast<int>(cell->GetPointId(1));
      edges.push_back({ std::min(a, b), std::max(a, b) });
    }
    for (int e = 0; e < ne; ++e)
    {
      vtkCell* edge = cell->GetEdge(e);
      for (vtkIdType k = 0; k + 1 < edge->GetNumberOfPoints(); ++k)
      {
        const int a = static_cast<int>(edge->GetPointId(k)), b = static_cast<int>(edge->GetPointId(k + 1));
        if (a != b)
          edges.push_back({ std::min(a, b), std::max(a, b) });
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Eigen::MatrixXi E(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t e = 0; e < edges.size(); ++e)
    E.row(static_cast<Eigen::Index>(e)) << edges[e][0], edges[e][1];
  return E;
}

bary::Skeleton vtkBaryConversion::ToSkeleton(vtkPolyData* data, int dimension)
{
  if (!data || !data->GetPoints() || data->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, "the handles have no points");
  if (dimension != CAGE_2D && dimension != CAGE_3D)
    throw Error(ErrorCode::InvalidArgument, "the handles' dimension must be 2 or 3");
  if (data->GetNumberOfPolys() > 0 || data->GetNumberOfStrips() > 0)
    throw Error(ErrorCode::InvalidArgument,
      "the handles have polygon cells: a skeleton is points (point handles) and lines (bones); "
      "a closed surface or polygon is a cage (give it as cage handles, without a domain)");
  vtkPoints* points = data->GetPoints();
  const vtkIdType n = points->GetNumberOfPoints();
  check_finite(points, "handle point");
  if (dimension == CAGE_2D)
  {
    double bounds[6];
    if (!flat_in_z(points, bounds))
      throw Error(ErrorCode::InvalidArgument,
        "2D handles must lie in a plane z = const, but their z ranges over [" +
          std::to_string(bounds[4]) + ", " + std::to_string(bounds[5]) + "]");
  }
  bary::Skeleton skeleton;
  skeleton.C = ToMatrix(points, dimension);
  std::vector<std::array<int, 2>> bones;
  std::vector<char> on_bone(static_cast<std::size_t>(n), 0);
  vtkCellArray* lines = data->GetLines();
  for (vtkIdType c = 0; lines && c < lines->GetNumberOfCells(); ++c)
  {
    const std::vector<vtkIdType> ids = cell_ids(lines, c);
    for (std::size_t k = 0; k + 1 < ids.size(); ++k)
    {
      bones.push_back({ static_cast<int>(ids[k]), static_cast<int>(ids[k + 1]) });
      on_bone[static_cast<std::size_t>(ids[k])] = on_bone[static_cast<std::size_t>(ids[k + 1])] = 1;
    }
  }
  skeleton.BE.resize(static_cast<Eigen::Index>(bones.size()), 2);
  for (std::size_t b = 0; b < bones.size(); ++b)
  {
    skeleton.BE(static_cast<Eigen::Index>(b), 0) = bones[b][0];
    skeleton.BE(static_cast<Eigen::Index>(b), 1) = bones[b][1];
  }
  std::vector<int> point_handles;
  for (vtkIdType i = 0; i < n; ++i)
    if (!on_bone[static_cast<std::size_t>(i)])
      point_handles.push_back(static_cast<int>(i));
  skeleton.P = Eigen::Map<const Eigen::VectorXi>(
    point_handles.data(), static_cast<Eigen::Index>(point_handles.size()));
  bary::validate_skeleton(skeleton);
  return skeleton;
}

void vtkBaryConversion::ToSimplices(
  vtkDataSet* data, int dimension, Eigen::MatrixXd& V, Eigen::MatrixXi& T)
{
  if (!data || data->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput, "the domain mesh has no points");
  const vtkIdType nc = data->GetNumberOfCells();
  vtkIdType tets = 0, triangles = 0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const int type = data->GetCellType(c);
    tets += type == VTK_TETRA;
    triangles += type == VTK_TRIANGLE;
  }
  if (tets == 0 && triangles == 0)
    throw Error(ErrorCode::EmptyInput,
      "the domain mesh has no tetrahedra and no triangles: give a tetrahedral mesh (.vtu, "
      ".mesh) or a triangle mesh");
  const int corners = tets > 0 ? 4 : 3;
  T.resize(tets > 0 ? tets : triangles, corners);
  vtkNew<vtkIdList> ids;
  Eigen::Index row = 0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const int type = data->GetCellType(c);
    if (tets > 0 ? type != VTK_TETRA : type != VTK_TRIANGLE)
    {
      const bool lower = type == VTK_VERTEX || type == VTK_POLY_VERTEX || type == VTK_LINE ||
        type == VTK_POLY_LINE || (tets > 0 && (type == VTK_TRIANGLE || type == VTK_POLYGON ||
        type == VTK_QUAD || type == VTK_TRIANGLE_STRIP));
      if (lower || type == VTK_EMPTY_CELL)
        continue;
      throw Error(ErrorCode::InvalidArgument,
        "domain mesh cell " + std::to_string(c) + " is a " +
          std::string(vtkCellTypes::GetClassNameFromTypeId(type)) + "; the domain must be " +
          (tets > 0 ? "tetrahedra" : "triangles") + " (triangulate it, e.g. vtkDataSetTriangleFilter)");
    }
    data->GetCellPoints(c, ids);
    for (int k = 0; k < corners; ++k)
      T(row, k) = static_cast<int>(ids->GetId(k));
    ++row;
  }
  bool planar = false;
  if (corners == 3)
  {
    double b[6];
    data->GetBounds(b);
    const double extent = std::max(b[1] - b[0], b[3] - b[2]);
    planar = b[5] - b[4] <= 1e-9 * std::max(1.0, extent);
    if (dimension == CAGE_2D && !planar)
      throw Error(ErrorCode::InvalidArgument,
        "a 2D domain mesh must lie in a plane z = const, but its z ranges over [" +
          std::to_string(b[4]) + ", " + std::to_string(b[5]) + "]");
  }
  const int dim = corners == 3 && (dimension == CAGE_2D || (dimension == AUTOMATIC && planar)) ? 2 : 3;
  V = PointsToMatrix(data, dim);
  if (!V.allFinite())
    throw Error(ErrorCode::NonFinite, "the domain mesh has NaN or infinite point coordinates");
}

int vtkBaryConversion::DomainDimension(vtkDataSet* domain)
{
  if (!domain || domain->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput,
      "bounded biharmonic weights with point/bone handles need a domain: a tetrahedral or "
      "triangle mesh, or a closed surface / polygon to mesh (none given)");
  bool triangles = false, polygon = false;
  for (vtkIdType c = 0; c < domain->GetNumberOfCells(); ++c)
  {
    const int type = domain->GetCellType(c);
    if (type == VTK_TETRA)
      return 3;
    triangles = triangles || type == VTK_TRIANGLE;
    polygon = polygon || type == VTK_POLYGON || type == VTK_POLY_LINE || type == VTK_QUAD;
  }
  double b[6];
  domain->GetBounds(b);
  const bool planar = b[5] - b[4] <= 1e-9 * std::max(1.0, std::max(b[1] - b[0], b[3] - b[2]));
  if (triangles && !polygon)
    return planar ? 2 : 3;
  if (polygon && !triangles && planar)
    return 2;
  vtkPolyData* poly = vtkPolyData::SafeDownCast(domain);
  if (domain->GetNumberOfCells() == 0 && poly && planar && domain->GetNumberOfPoints() >= 3)
    return 2; // bare points in order: a polygon (an .obj with only `v` lines)
  throw Error(ErrorCode::InvalidArgument,
    "the domain is neither a simplicial mesh (tetrahedra, or triangles in a plane z = const) nor "
    "a closed triangle surface nor one planar polygon");
}

vtkSmartPointer<vtkUnstructuredGrid> vtkBaryConversion::SimplicesToGrid(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, double z)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(V.rows());
  const bool planar = V.cols() == 2;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    points->SetPoint(i, V(i, 0), V(i, 1), planar ? z : V(i, 2));
  grid->SetPoints(points);
  const int corners = static_cast<int>(T.cols());
  const int type = corners == 3 ? VTK_TRIANGLE : VTK_TETRA;
  grid->Allocate(T.rows());
  vtkIdType ids[4];
  for (Eigen::Index t = 0; t < T.rows(); ++t)
  {
    for (int k = 0; k < corners; ++k)
      ids[k] = T(t, k);
    grid->InsertNextCell(type, corners, ids);
  }
  return grid;
}

vtkSmartPointer<vtkUnstructuredGrid> vtkBaryConversion::ToUnstructuredGrid(
  const bary::DomainMesh& mesh, const vtkBaryCage& cage)
{
  auto grid = SimplicesToGrid(mesh.V, mesh.T, cage.PlaneZ);
  vtkNew<vtkIdTypeArray> control;
  control->SetName("ControlPointId");
  control->SetNumberOfTuples(mesh.V.rows());
  control->Fill(-1);
  for (Eigen::Index k = 0; k < mesh.control_vertex.size(); ++k)
    control->SetValue(mesh.control_vertex(k), cage.ControlPointIds[static_cast<std::size_t>(k)]);
  vtkNew<vtkUnsignedCharArray> on_cage;
  on_cage->SetName("OnCage");
  on_cage->SetNumberOfTuples(mesh.V.rows());
  on_cage->Fill(0);
  for (int v : mesh.boundary_vertices)
    on_cage->SetValue(v, 1);
  grid->GetPointData()->AddArray(control);
  grid->GetPointData()->AddArray(on_cage);
  return grid;
}

int vtkBaryConversion::PointMeasures(vtkDataSet* data, Eigen::VectorXd& measure)
{
  measure.resize(0);
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  try
  {
    vtkBaryConversion::ToSimplices(data, AUTOMATIC, V, T);
  }
  catch (const Error&)
  {
    return 0; // no simplices, or other polygons: uniform
  }
  const bool volume = T.cols() == 4, area = T.cols() == 3 && V.cols() == 2;
  if (!volume && !area)
    return 0; // a curved triangle surface: not the domain of 3D weights
  measure = bary::vertex_measures(V, T);
  return volume ? 3 : 2;
}

int vtkBaryConversion::ToCompactArrays(
  const bary::SparseWeights& W, vtkIntArray* indices, vtkDoubleArray* values)
{
  Eigen::Index K = 1;
  for (Eigen::Index p = 0; p < W.rows(); ++p)
    K = std::max<Eigen::Index>(K, W.outerIndexPtr()[p + 1] - W.outerIndexPtr()[p]);
  indices->SetNumberOfComponents(static_cast<int>(K));
  indices->SetNumberOfTuples(W.rows());
  values->SetNumberOfComponents(static_cast<int>(K));
  values->SetNumberOfTuples(W.rows());
  int* ip = indices->GetPointer(0);
  double* vp = values->GetPointer(0);
  for (Eigen::Index p = 0; p < W.rows(); ++p)
  {
    Eigen::Index k = 0;
    for (bary::SparseWeights::InnerIterator it(W, p); it; ++it, ++k)
    {
      ip[p * K + k] = static_cast<int>(it.col());
      vp[p * K + k] = it.value();
    }
    for (; k < K; ++k)
    {
      ip[p * K + k] = -1;
      vp[p * K + k] = 0.0;
    }
  }
  return static_cast<int>(K);
}

bary::SparseWeights vtkBaryConversion::FromCompactArrays(
  vtkDataArray* indices, vtkDataArray* values, vtkIdType numberOfControls)
{
  if (!indices || !values)
    throw Error(ErrorCode::InvalidArgument, "compact weights need both an indices and a values array");
  const int K = indices->GetNumberOfComponents();
  const vtkIdType np = indices->GetNumberOfTuples();
  if (values->GetNumberOfComponents() != K || values->GetNumberOfTuples() != np)
    throw Error(ErrorCode::SizeMismatch,
      "compact weights: the indices array '" + std::string(indices->GetName() ? indices->GetName() : "") +
        "' is " + std::to_string(np) + " x " + std::to_string(K) + " but the values array is " +
        std::to_string(values->GetNumberOfTuples()) + " x " +
        std::to_string(values->GetNumberOfComponents()));
  std::vector<Eigen::Triplet<double, Eigen::Index>> entries;
  entries.reserve(static_cast<std::size_t>(np) * static_cast<std::size_t>(K));
  std::vector<vtkIdType> seen(static_cast<std::size_t>(std::max<vtkIdType>(numberOfControls, 0)), -1);
  for (vtkIdType p = 0; p < np; ++p)
    for (int k = 0; k < K; ++k)
    {
      const double id = indices->GetComponent(p, k);
      if (id == -1.0)
        continue;
      if (!(id >= 0 && id < static_cast<double>(numberOfControls)) || id != std::floor(id))
        throw Error(ErrorCode::InvalidArgument,
          "compact weights: point " + std::to_string(p) + " names control index " +
            std::to_string(id) + ", outside [0, " + std::to_string(numberOfControls) + ")");
      const auto c = static_cast<std::size_t>(id);
      if (seen[c] == p)
        throw Error(ErrorCode::InvalidArgument,
          "compact weights: point " + std::to_string(p) + " names control " + std::to_string(c) +
            " twice");
      seen[c] = p;
      const double w = values->GetComponent(p, k);
      if (!std::isfinite(w))
        throw Error(ErrorCode::NonFinite,
          "compact weights: point " + std::to_string(p) + " has a non-finite weight (NaN or inf)");
      entries.emplace_back(p, static_cast<Eigen::Index>(c), w);
    }
  bary::SparseWeights W(np, numberOfControls);
  W.setFromTriplets(entries.begin(), entries.end());
  W.makeCompressed();
  return W;
}
