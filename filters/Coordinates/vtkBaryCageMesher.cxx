#include "vtkBaryCageMesher.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"

#include "core/meshing/domain_mesh.h"
#include "core/common/error.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>

vtkStandardNewMacro(vtkBaryCageMesher);

vtkBaryCageMesher::vtkBaryCageMesher()
{
  this->SetNumberOfInputPorts(2);
}

void vtkBaryCageMesher::SetCageData(vtkPolyData* cage)
{
  this->SetInputData(0, cage);
}

void vtkBaryCageMesher::SetPointsData(vtkPointSet* points)
{
  this->SetInputData(1, points);
}

void vtkBaryCageMesher::SetPointsConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

int vtkBaryCageMesher::FillInputPortInformation(int port, vtkInformation* info)
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

int vtkBaryCageMesher::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* cagePoly = vtkPolyData::GetData(inputVector[0]);
  vtkPointSet* points = vtkPointSet::GetData(inputVector[1]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfSkippedPoints = 0;
  if (!cagePoly)
  {
    vtkErrorMacro(<< "No cage: connect a vtkPolyData to input port 0 (SetCageData).");
    return 0;
  }
  try
  {
    const vtkBaryCage cage = vtkBaryConversion::ToCage(cagePoly, this->CageDimension);
    const int dim = cage.Cage.dimension();
    const Eigen::MatrixXd steiner = points && points->GetNumberOfPoints() > 0
      ? vtkBaryConversion::ToMatrix(points->GetPoints(), dim)
      : Eigen::MatrixXd(0, dim);
    auto progress = [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    bary::DomainMesh mesh;
    if (dim == 2)
    {
      bary::PolygonMeshOptions options;
      options.target_cells = this->TargetNumberOfCells;
      options.max_area = this->MaximumCellSize;
      options.min_angle_degrees = this->MinimumAngle;
      options.steiner_points = steiner;
      mesh = bary::mesh_polygon(cage.Cage, options, progress);
    }
    else
    {
      bary::SurfaceMeshOptions options;
      options.target_cells = this->TargetNumberOfCells;
      options.max_volume = this->MaximumCellSize;
      options.radius_edge_ratio = this->RadiusEdgeRatio;
      options.preserve_boundary = this->PreserveBoundary;
      options.steiner_points = steiner;
      mesh = bary::mesh_closed_surface(cage.Cage, options, progress);
    }
    for (Eigen::Index s = 0; s < mesh.steiner_vertex.size(); ++s)
      this->NumberOfSkippedPoints += mesh.steiner_vertex(s) < 0;
    if (this->NumberOfSkippedPoints > 0)
      vtkWarningMacro(<< this->NumberOfSkippedPoints
                      << " point(s) to insert lie outside the cage (or on it) and were skipped.");
    output->ShallowCopy(vtkBaryConversion::ToUnstructuredGrid(mesh, cage));
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryCageMesher::SetMinimumAngle(double degrees)
{
  const double clamped = std::clamp(degrees, 0.0, bary::kMaxMinAngleDegrees);
  if (this->MinimumAngle != clamped)
  {
    this->MinimumAngle = clamped;
    this->Modified();
  }
}

void vtkBaryCageMesher::SetRadiusEdgeRatio(double ratio)
{
  const double clamped = std::clamp(ratio, 0.0, bary::kMaxRadiusEdgeRatio);
  if (this->RadiusEdgeRatio != clamped)
  {
    this->RadiusEdgeRatio = clamped;
    this->Modified();
  }
}

void vtkBaryCageMesher::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetNumberOfCells: " << this->TargetNumberOfCells << "\n";
  os << indent << "MaximumCellSize: " << this->MaximumCellSize << "\n";
  os << indent << "MinimumAngle: " << this->MinimumAngle << "\n";
  os << indent << "RadiusEdgeRatio: " << this->RadiusEdgeRatio << "\n";
  os << indent << "PreserveBoundary: " << this->PreserveBoundary << "\n";
  os << indent << "CageDimension: " << this->CageDimension << "\n";
}
