#include "vtkBaryCoordinates.h"

#include "vtkBaryConversion.h"
#include "vtkBaryMethod.h"

#include "core/error.h"

#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <cstring>

vtkStandardNewMacro(vtkBaryCoordinates);

namespace
{
const char* const kMethodNames[] = { "mvc", "harmonic" };
}

vtkBaryCoordinates::vtkBaryCoordinates()
{
  this->SetNumberOfInputPorts(2);
  this->SetWeightsArrayName("Weights");
  this->SetLocationArrayName("CageLocation");
}

vtkBaryCoordinates::~vtkBaryCoordinates()
{
  this->SetWeightsArrayName(nullptr);
  this->SetLocationArrayName(nullptr);
}

const char* vtkBaryCoordinates::GetMethodName(int method)
{
  return (method >= 0 && method < NUMBER_OF_METHODS) ? kMethodNames[method] : nullptr;
}

int vtkBaryCoordinates::GetMethodFromName(const char* name)
{
  for (int m = 0; name && m < NUMBER_OF_METHODS; ++m)
    if (std::strcmp(name, kMethodNames[m]) == 0)
      return m;
  return -1;
}

void vtkBaryCoordinates::SetCageData(vtkPolyData* cage)
{
  this->SetInputData(1, cage);
}

void vtkBaryCoordinates::SetCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

int vtkBaryCoordinates::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  else
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkBaryCoordinates::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* cagePoly = vtkPolyData::GetData(inputVector[1]);
  vtkDataSet* output = vtkDataSet::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfInsidePoints = this->NumberOfOutsidePoints = 0;
  this->NumberOfBoundaryPoints = this->NumberOfUndefinedPoints = 0;
  if (!input || !output)
  {
    vtkErrorMacro(<< "No input data set.");
    return 0;
  }
  output->ShallowCopy(input);
  if (!cagePoly)
  {
    vtkErrorMacro(<< "No cage: connect a vtkPolyData to input port 1 (SetCageData).");
    return 0;
  }
  if (!this->WeightsArrayName || !*this->WeightsArrayName)
  {
    vtkErrorMacro(<< "WeightsArrayName must not be empty.");
    return 0;
  }
  if (input->GetNumberOfPoints() == 0)
  {
    vtkWarningMacro(<< "The input has no points; nothing to compute.");
    return 1;
  }

  try
  {
    const vtkBaryCage cage = vtkBaryConversion::ToCage(cagePoly, this->CageDimension);
    const Eigen::MatrixXd points =
      vtkBaryConversion::PointsToMatrix(input, cage.Cage.dimension());
    if (cage.Cage.dimension() == 2)
    {
      double bounds[6];
      input->GetBounds(bounds);
      if (bounds[5] > bounds[4])
        vtkWarningMacro(<< "The cage is 2D (a polygon): the points' z coordinates (from "
                        << bounds[4] << " to " << bounds[5] << ") are ignored.");
    }
    const vtkBaryMethodParameters parameters = vtkBaryParametersOf(this);
    vtkBaryMethodReport report;
    this->UpdateProgress(0.0);
    const bary::DenseWeights W = vtkBaryMethod::Compute(cage, points, parameters,
      [this](double f) {
        this->UpdateProgress(f);
        return !this->GetAbortExecute();
      },
      &report);

    output->GetPointData()->AddArray(
      vtkBaryConversion::ToArray(W, cage, this->WeightsArrayName));
    if (this->GenerateLocation && this->LocationArrayName && *this->LocationArrayName)
    {
      vtkNew<vtkUnsignedCharArray> location;
      location->SetName(this->LocationArrayName);
      location->SetNumberOfTuples(static_cast<vtkIdType>(report.Location.size()));
      std::copy(report.Location.begin(), report.Location.end(), location->GetPointer(0));
      output->GetPointData()->AddArray(location);
    }
    this->NumberOfInsidePoints = report.Inside;
    this->NumberOfOutsidePoints = report.Outside;
    this->NumberOfBoundaryPoints = report.Boundary;
    this->NumberOfUndefinedPoints = static_cast<vtkIdType>(report.Undefined.size());
    if (!report.Undefined.empty())
      vtkWarningMacro(<< report.Undefined.size()
                      << " point(s) outside the cage have undefined weights (NaN), first id "
                      << report.Undefined.front());
  }
  catch (const bary::Error& e)
  {
    // keep the kind of problem for callers (vtkBaryConversion::ErrorCodeOf)
    this->SetErrorCode(vtkBaryConversion::ToVTKErrorCode(e.code()));
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const std::exception& e)
  {
    this->SetErrorCode(vtkBaryConversion::ToVTKErrorCode(bary::ErrorCode::Internal));
    vtkErrorMacro(<< "Unexpected failure: " << e.what());
    return 0;
  }
  return 1;
}

void vtkBaryCoordinates::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << (GetMethodName(this->Method) ? GetMethodName(this->Method) : "?")
     << "\n";
  os << indent << "CageDimension: " << this->CageDimension << "\n";
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "GenerateLocation: " << this->GenerateLocation << "\n";
  os << indent << "BoundaryTolerance: " << this->BoundaryTolerance << "\n";
  os << indent << "ValidateCage: " << this->ValidateCage << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "TargetNumberOfCells: " << this->TargetNumberOfCells << "\n";
  os << indent << "MaximumCellSize: " << this->MaximumCellSize << "\n";
  os << indent << "InsertPointsIntoMesh: " << this->InsertPointsIntoMesh << "\n";
  os << indent << "OutsidePolicy: " << this->OutsidePolicy << "\n";
}
