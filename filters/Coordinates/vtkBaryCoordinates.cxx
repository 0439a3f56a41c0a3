#include "vtkBaryCoordinates.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBaryMethod.h"

#include "core/error.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkBaryCoordinates);

namespace
{
const char* const kMethodNames[] = { "mvc", "harmonic", "bbw", "tcc", "scc", "lbc" };
}

vtkBaryCoordinates::vtkBaryCoordinates()
{
  this->SetNumberOfInputPorts(3);
  this->SetWeightsArrayName("Weights");
  this->SetLocationArrayName("CageLocation");
}

vtkCxxSetObjectMacro(vtkBaryCoordinates, UserWeights, vtkDataArray);

vtkMTimeType vtkBaryCoordinates::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->UserWeights)
    t = std::max(t, this->UserWeights->GetMTime());
  return t;
}

vtkBaryCoordinates::~vtkBaryCoordinates()
{
  this->SetUserWeights(nullptr);
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

void vtkBaryCoordinates::SetDomainData(vtkDataSet* domain)
{
  this->SetInputData(2, domain);
}

void vtkBaryCoordinates::SetDomainConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

double vtkBaryCoordinates::GetStatistic(const char* name) const
{
  for (const auto& entry : this->Statistics)
    if (name && entry.first == name)
      return entry.second;
  return std::nan("");
}

const char* vtkBaryCoordinates::GetStatisticName(int i) const
{
  return i >= 0 && i < this->GetNumberOfStatistics()
    ? this->Statistics[static_cast<std::size_t>(i)].first.c_str()
    : nullptr;
}

double vtkBaryCoordinates::GetStatisticValue(int i) const
{
  return i >= 0 && i < this->GetNumberOfStatistics()
    ? this->Statistics[static_cast<std::size_t>(i)].second
    : std::nan("");
}

int vtkBaryCoordinates::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  else if (port == 1)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkBaryCoordinates::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* cagePoly = vtkPolyData::GetData(inputVector[1]);
  vtkDataSet* domain = vtkDataSet::GetData(inputVector[2]);
  vtkDataSet* output = vtkDataSet::GetData(outputVector);
  this->SetErrorCode(0);
  this->Statistics.clear();
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
    const auto progress = [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    // BBW with a skeleton (points and lines) on a domain; a BBW cage goes the cage way below.
    const bool skeleton = this->Method == BBW && cagePoly->GetNumberOfPolys() == 0 &&
      cagePoly->GetNumberOfStrips() == 0;
    if (skeleton)
    {
      const int dim = vtkBaryConversion::DomainDimension(domain);
      const bary::Skeleton handles = vtkBaryConversion::ToSkeleton(cagePoly, dim);
      const Eigen::MatrixXd points = vtkBaryConversion::PointsToMatrix(input, dim);
      vtkBaryMethodReport report;
      this->UpdateProgress(0.0);
      const bary::DenseWeights W = vtkBaryMethod::ComputeBBW(
        handles, domain, points, vtkBaryParametersOf(this), progress, &report);
      vtkBaryCage columns; // identity column order: handle j is component j
      columns.ControlPointIds.resize(static_cast<std::size_t>(W.cols()));
      for (std::size_t j = 0; j < columns.ControlPointIds.size(); ++j)
        columns.ControlPointIds[j] = static_cast<vtkIdType>(j);
      this->FinishOutput(output, W, columns, report);
      return 1;
    }
    if (domain && this->Method == LBC && this->InsertPointsIntoMesh)
      vtkWarningMacro(<< "InsertPointsIntoMesh is ignored: LBC uses the domain mesh (input 2) as "
                         "is; the points are interpolated on it.");
    if (domain && this->Method != BBW && this->Method != LBC)
      vtkWarningMacro(<< "The domain (input 2) is used by BBW with skeleton handles and by LBC "
                         "only; ignored.");
    const bool pointBased = vtkBaryMethod::IsPointBased(this->Method);
    const vtkBaryCage cage = pointBased
      ? vtkBaryConversion::ToControlPoints(cagePoly, this->CageDimension)
      : vtkBaryConversion::ToCage(cagePoly, this->CageDimension);
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
    const bary::DenseWeights W = vtkBaryMethod::Compute(cage, points, parameters, progress,
      &report, pointBased ? vtkBaryConversion::CellEdges(input) : Eigen::MatrixXi(),
      this->Method == LBC ? domain : nullptr);
    this->FinishOutput(output, W, cage, report);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryCoordinates::FinishOutput(vtkDataSet* output, const bary::DenseWeights& W,
  const vtkBaryCage& columns, const vtkBaryMethodReport& report)
{
  output->GetPointData()->AddArray(vtkBaryConversion::ToArray(W, columns, this->WeightsArrayName));
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
  this->Statistics = report.Statistics;
  if (!report.Undefined.empty())
    vtkWarningMacro(<< report.Undefined.size()
                    << " point(s) outside the domain have undefined weights (NaN), first id "
                    << report.Undefined.front());
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
  os << indent << "Lambda: " << this->Lambda << "\n";
  os << indent << "UserWeights: " << (this->UserWeights ? "set" : "(none)") << "\n";
  os << indent << "BBWMode: " << (this->BBWMode == BBW_FAST ? "fast" : "coupled") << "\n";
  static const char* const localities[] = { "squared", "constant", "linear" };
  os << indent << "LBCLocality: " << localities[this->LBCLocality] << "\n";
  os << indent << "LBCRelaxedEpsilon: " << this->LBCRelaxedEpsilon << "\n";
  os << indent << "LBCPrimalTolerance: " << this->LBCPrimalTolerance << "\n";
  os << indent << "LBCDualTolerance: " << this->LBCDualTolerance << "\n";
  os << indent << "LBCMaximumIterations: " << this->LBCMaximumIterations << "\n";
  os << indent << "LBCDistanceNormalization: "
     << (this->LBCDistanceNormalization == LBC_NORMALIZE_GLOBAL ? "global" : "per control point")
     << "\n";
  os << indent << "LBCBarycentricConstraints: " << this->LBCBarycentricConstraints << "\n";
}
