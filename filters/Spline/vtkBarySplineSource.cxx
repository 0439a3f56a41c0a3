#include "vtkBarySplineSource.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySplineData.h"

#include "core/meshing/domain_mesh.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

vtkStandardNewMacro(vtkBarySplineSource);

vtkBarySplineSource::vtkBarySplineSource()
  : Degree(bary::kDefaultSplineDegree)
{
}

void vtkBarySplineSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Degree: " << this->Degree << "\n"
     << indent << "TargetTriangles: " << this->TargetTriangles << "\n"
     << indent << "Prism: " << this->Prism << " [" << this->PrismBottom << ", " << this->PrismTop
     << "]\n";
}

int vtkBarySplineSource::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
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
