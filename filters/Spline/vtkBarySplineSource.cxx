#include "vtkBarySplineSource.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySplineData.h"

#include "core/meshing/domain_mesh.h"
#include "core/spline/spline_fit.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

vtkStandardNewMacro(vtkBarySplineSource);

vtkBarySplineSource::vtkBarySplineSource()
  : Degree(bary::kDefaultSplineDegree)
{
  this->SetNumberOfInputPorts(3);
}

void vtkBarySplineSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Degree: " << this->Degree << "\n"
     << indent << "TargetTriangles: " << this->TargetTriangles << "\n"
     << indent << "Prism: " << this->Prism << " [" << this->PrismBottom << ", " << this->PrismTop
     << "]\n";
}

int vtkBarySplineSource::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkBarySplineSource::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  try
  {
    vtkPolyData* domain = vtkPolyData::GetData(inputVector[0]);
    vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
    if (!domain || domain->GetNumberOfPoints() == 0)
      throw bary::Error(bary::ErrorCode::EmptyInput, "the spline's domain is empty");
    if (this->Prism && !(this->PrismTop > this->PrismBottom))
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "the prism's top (" + std::to_string(this->PrismTop) + ") is not above its bottom (" +
          std::to_string(this->PrismBottom) + ")");
    Eigen::MatrixXd V;
    Eigen::MatrixXi T;
    bool triangles = domain->GetNumberOfPolys() > 0;
    if (triangles)
    {
      // Triangles are used as given; one polygon of more sides is a boundary to mesh.
      vtkIdType npts;
      const vtkIdType* pts;
      auto polys = domain->GetPolys();
      polys->InitTraversal();
      if (domain->GetNumberOfPolys() == 1 && polys->GetNextCell(npts, pts) && npts > 3)
        triangles = false;
    }
    if (triangles)
      vtkBaryConversion::ToSimplices(domain, 2, V, T);
    else
    {
      const vtkBaryCage cage = vtkBaryConversion::ToCage(domain, vtkBaryConversion::CAGE_2D);
      bary::PolygonMeshOptions o;
      if (this->TargetTriangles < 2)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "TargetTriangles " + std::to_string(this->TargetTriangles) + " is below 2");
      o.target_cells = this->TargetTriangles;
      const bary::DomainMesh m = bary::mesh_polygon(cage.Cage, o);
      V = m.V;
      T = m.T;
    }
    auto net = std::make_shared<bary::SplineNet>(V, T, this->Degree);
    vtkBarySpline spline;
    if (this->PinBorder)
    {
      const auto& E = net->edges();
      const auto& ET = net->edge_triangles();
      const int d = net->degree();
      std::vector<char> mark(static_cast<size_t>(net->num_points()), 0);
      for (bary::Index e = 0; e < E.rows(); ++e)
        if (ET(e, 0) < 0 || ET(e, 1) < 0)
        {
          mark[static_cast<size_t>(E(e, 0))] = mark[static_cast<size_t>(E(e, 1))] = 1;
          for (int s = 1; s < d; ++s)
            mark[static_cast<size_t>(net->edge_point(e, s))] = 1;
        }
      for (bary::Index p = 0; p < net->num_points(); ++p)
        if (mark[static_cast<size_t>(p)])
          spline.pinned.push_back(p);
    }
    vtkPointSet* from = vtkPointSet::GetData(inputVector[1]);
    vtkPointSet* to = vtkPointSet::GetData(inputVector[2]);
    if ((from != nullptr) != (to != nullptr))
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "a spline fit needs both the sample points and their images");
    if (from)
    {
      if (from->GetNumberOfPoints() != to->GetNumberOfPoints())
        throw bary::Error(bary::ErrorCode::SizeMismatch,
          "the fit's samples have " + std::to_string(from->GetNumberOfPoints()) +
            " points and their images " + std::to_string(to->GetNumberOfPoints()));
      if (from->GetNumberOfPoints() == 0)
        throw bary::Error(bary::ErrorCode::EmptyInput, "the fit has no samples");
      const Eigen::MatrixXd X = vtkBaryConversion::ToMatrix(from->GetPoints(), 2);
      const Eigen::MatrixXd Y = vtkBaryConversion::ToMatrix(to->GetPoints(), 2);
      bary::SplineFit fit = bary::fit_spline(net, X, Y, 1e-6, spline.pinned);
      spline.xy.emplace(std::move(*fit.spline));
      this->FitRMSError = fit.rms_error;
      this->FitMaxError = fit.max_error;
    }
    else
      spline.xy.emplace(bary::TriangularSpline::identity(net));

    if (this->Prism)
    {
      spline.bottom.emplace(bary::TriangularSpline::constant(net, this->PrismBottom));
      spline.top.emplace(bary::TriangularSpline::constant(net, this->PrismTop));
      spline.prism_bottom = this->PrismBottom;
      spline.prism_top = this->PrismTop;
    }
    output->ShallowCopy(vtkBarySplineData::ToGrid(spline));
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}
