#include "vtkBarySplineData.h"

#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkHigherOrderTriangle.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <memory>
#include <string>

vtkStandardNewMacro(vtkBarySplineData);

int vtkBarySplineData::VTKIndex(int d, int i, int j)
{
  // VTK's barycentric index (b0, b1, b2) has its first vertex at b2 = d, its second at b0 = d.
  const vtkIdType b[3] = { j, d - i - j, i };
  return static_cast<int>(vtkHigherOrderTriangle::Index(b, d));
}

namespace
{

vtkSmartPointer<vtkDoubleArray> Column(const char* name, const Eigen::MatrixXd& X, int c)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(X.rows());
  for (bary::Index p = 0; p < X.rows(); ++p)
    a->SetValue(p, X(p, c));
  return a;
}

void AddScalar(vtkFieldData* fd, const char* name, double v)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->InsertNextValue(v);
  fd->AddArray(a);
}

double GetScalar(vtkFieldData* fd, const char* name)
{
  vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
  if (!a || a->GetNumberOfTuples() < 1)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      std::string("the spline grid has no field data '") + name + "'");
  return a->GetComponent(0, 0);
}

} // namespace

vtkSmartPointer<vtkUnstructuredGrid> vtkBarySplineData::ToGrid(const vtkBarySpline& spline)
{
  if (!spline.xy)
    throw bary::Error(bary::ErrorCode::EmptyInput, "no spline to write");
  const bary::TriangularSpline& phi = *spline.xy;
  const bary::SplineNet& net = phi.net();
  const int d = net.degree();
  const bary::Index n = net.num_points();
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (bary::Index p = 0; p < n; ++p)
    points->SetPoint(p, phi.values()(p, 0), phi.values()(p, 1), 0.0);
  grid->SetPoints(points);
  const int nb = bary::bezier_count(d);
  std::vector<int> order(static_cast<size_t>(nb));
  for (int i = 0; i <= d; ++i)
    for (int j = 0; j <= d - i; ++j)
      order[static_cast<size_t>(VTKIndex(d, i, j))] = bary::bezier_index(d, i, j);
  grid->Allocate(net.num_triangles());
  std::vector<vtkIdType> ids(static_cast<size_t>(nb));
  auto degrees = vtkSmartPointer<vtkIntArray>::New();
  degrees->SetName("HigherOrderDegrees");
  degrees->SetNumberOfComponents(3);
  for (bary::Index t = 0; t < net.num_triangles(); ++t)
  {
    for (int k = 0; k < nb; ++k)
      ids[static_cast<size_t>(k)] = net.local_to_global()(t, order[static_cast<size_t>(k)]);
    grid->InsertNextCell(VTK_BEZIER_TRIANGLE, nb, ids.data());
    const int deg[3] = { d, d, d };
    degrees->InsertNextTypedTuple(deg);
  }
  grid->GetCellData()->SetHigherOrderDegrees(degrees);

  auto nominal = vtkSmartPointer<vtkDoubleArray>::New();
  nominal->SetName("Nominal");
  nominal->SetNumberOfComponents(3);
  nominal->SetNumberOfTuples(n);
  auto type = vtkSmartPointer<vtkIntArray>::New();
  type->SetName("ControlPointType");
  type->SetNumberOfTuples(n);
  auto pinned = vtkSmartPointer<vtkUnsignedCharArray>::New();
  pinned->SetName("Pinned");
  pinned->SetNumberOfTuples(n);
  pinned->FillValue(0);
  for (bary::Index p = 0; p < n; ++p)
  {
    nominal->SetTuple3(p, net.nominal()(p, 0), net.nominal()(p, 1), 0.0);
    type->SetValue(p, static_cast<int>(net.type(p)));
  }
  for (bary::Index p : spline.pinned)
    pinned->SetValue(p, 1);
  grid->GetPointData()->AddArray(nominal);
  grid->GetPointData()->AddArray(type);
  grid->GetPointData()->AddArray(pinned);
  auto fd = grid->GetFieldData();
  AddScalar(fd, "SplineDegree", d);
  if (spline.is_prism())
  {
    grid->GetPointData()->AddArray(Column("Bottom", spline.bottom->values(), 0));
    grid->GetPointData()->AddArray(Column("Top", spline.top->values(), 0));
    AddScalar(fd, "PrismBottom", spline.prism_bottom);
    AddScalar(fd, "PrismTop", spline.prism_top);
  }
  return grid;
}

vtkBarySpline vtkBarySplineData::FromGrid(vtkUnstructuredGrid* grid)
{
  using bary::Error;
  using bary::ErrorCode;
  if (!grid || grid->GetNumberOfCells() == 0)
    throw Error(ErrorCode::EmptyInput, "the spline grid has no cells");
  const vtkIdType nc = grid->GetNumberOfCells();
  vtkIdType nb = -1;
  auto ids = vtkSmartPointer<vtkIdList>::New();
  for (vtkIdType c = 0; c < nc; ++c)
  {
    if (grid->GetCellType(c) != VTK_BEZIER_TRIANGLE)
      throw Error(ErrorCode::InvalidArgument,
        "cell " + std::to_string(c) + " of the spline grid is not a Bézier triangle");
    grid->GetCellPoints(c, ids);
    if (nb < 0)
      nb = ids->GetNumberOfIds();
    else if (ids->GetNumberOfIds() != nb)
      throw Error(ErrorCode::InvalidArgument,
        "the spline grid's Bézier triangles have different degrees (cell " + std::to_string(c) + ")");
  }
  int d = 1;
  while (bary::bezier_count(d) < nb)
    ++d;
  if (bary::bezier_count(d) != nb)
    throw Error(ErrorCode::InvalidArgument,
      "the spline grid's cells have " + std::to_string(nb) + " points, no triangle degree has that many");
  vtkDataArray* nominal = grid->GetPointData()->GetArray("Nominal");
  if (!nominal || nominal->GetNumberOfComponents() < 2)
    throw Error(ErrorCode::InvalidArgument,
      "the spline grid has no 'Nominal' point array: it was not written by BaryLab",
      "make spline grids with barylab spline create or vtkBarySplineSource");
  // The domain: corners of the cells (VTK's points 0, 1, 2 are the triangle's vertices in order).
  Eigen::MatrixXi T(nc, 3);
  int nv = 0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    grid->GetCellPoints(c, ids);
    for (int k = 0; k < 3; ++k)
    {
      T(c, k) = static_cast<int>(ids->GetId(k));
      nv = std::max(nv, T(c, k) + 1);
    }
  }
  if (nv > grid->GetNumberOfPoints())
    throw Error(ErrorCode::InvalidArgument, "the spline grid's cells name points it does not have");
  Eigen::MatrixXd V(nv, 2);
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < 2; ++k)
      V(v, k) = nominal->GetComponent(v, k);
  auto net = std::make_shared<bary::SplineNet>(V, T, d);
  if (net->reversed() || net->num_points() != grid->GetNumberOfPoints())
    throw Error(ErrorCode::InvalidArgument,
      "the spline grid's control points are not numbered as BaryLab numbers them");
  for (vtkIdType c = 0; c < nc; ++c)
  {
    grid->GetCellPoints(c, ids);
    for (int i = 0; i <= d; ++i)
      for (int j = 0; j <= d - i; ++j)
        if (ids->GetId(VTKIndex(d, i, j)) != net->point(c, i, j))
          throw Error(ErrorCode::InvalidArgument,
            "the spline grid's control points are not numbered as BaryLab numbers them (cell " +
              std::to_string(c) + ")");
  }
  const bary::Index n = net->num_points();
  Eigen::MatrixXd X(n, 2);
  for (bary::Index p = 0; p < n; ++p)
  {
    double x[3];
    grid->GetPoint(p, x);
    X(p, 0) = x[0];
    X(p, 1) = x[1];
  }
  vtkBarySpline out;
  out.xy.emplace(net, X);
  vtkDataArray* bottom = grid->GetPointData()->GetArray("Bottom");
  vtkDataArray* top = grid->GetPointData()->GetArray("Top");
  if ((bottom != nullptr) != (top != nullptr))
    throw Error(ErrorCode::InvalidArgument, "the spline grid has one of 'Bottom' and 'Top' but not both");
  if (bottom)
  {
    Eigen::MatrixXd B(n, 1), U(n, 1);
    for (bary::Index p = 0; p < n; ++p)
    {
      B(p, 0) = bottom->GetComponent(p, 0);
      U(p, 0) = top->GetComponent(p, 0);
    }
    out.bottom.emplace(net, B);
    out.top.emplace(net, U);
    out.prism_bottom = GetScalar(grid->GetFieldData(), "PrismBottom");
    out.prism_top = GetScalar(grid->GetFieldData(), "PrismTop");
    if (!(out.prism_top > out.prism_bottom))
      throw Error(ErrorCode::InvalidArgument, "the spline grid's PrismTop is not above PrismBottom");
  }
  if (vtkDataArray* pinned = grid->GetPointData()->GetArray("Pinned"))
    for (bary::Index p = 0; p < n && p < pinned->GetNumberOfTuples(); ++p)
      if (pinned->GetComponent(p, 0) != 0)
        out.pinned.push_back(p);
  return out;
}
