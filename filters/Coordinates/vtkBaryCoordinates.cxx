#include "vtkBaryCoordinates.h"

#include "vtkBaryConversion.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiProcessStream.h"
#include "vtkObjectFactory.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>

vtkStandardNewMacro(vtkBaryCoordinates);

vtkBaryCoordinates::vtkBaryCoordinates()
{
  this->SetNumberOfInputPorts(3);
  this->WeightMethod = vtkBaryWeightMethod::New();
  this->SetWeightsArrayName("Weights");
  this->SetLocationArrayName("CageLocation");
  this->SetFaceWeightsArrayName("FaceWeights");
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

vtkCxxSetObjectMacro(vtkBaryCoordinates, Controller, vtkMultiProcessController);

void vtkBaryCoordinates::SetWeightMethod(vtkBaryWeightMethod* method)
{
  if (vtkBaryWeightMethod::Replace(this, this->WeightMethod, method))
    this->Modified();
}

vtkMTimeType vtkBaryCoordinates::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  return std::max(t, this->WeightMethod->GetMTime());
}

vtkBaryCoordinates::~vtkBaryCoordinates()
{
  this->WeightMethod->UnRegister(this);
  this->SetController(nullptr);
  this->SetWeightsArrayName(nullptr);
  this->SetLocationArrayName(nullptr);
  this->SetFaceWeightsArrayName(nullptr);
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

int vtkBaryCoordinates::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // input 0 keeps the piece the executive copied from the output's request
  for (int port = 1; port < 3; ++port)
    if (vtkInformation* info = inputVector[port]->GetInformationObject(0))
    {
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
    }
  return 1;
}

bary::WeightsResult vtkBaryCoordinates::ComputeShared(vtkDataSet* input,
  const std::function<bary::WeightsResult(vtkDataSet*, const bary::MeshWeights*)>& compute)
{
  vtkMultiProcessController* controller = this->Controller;
  const int rank = controller->GetLocalProcessId();
  vtkMultiProcessStream header;
  bary::WeightsResult result;
  std::exception_ptr failure;
  if (rank == 0)
  {
    try
    {
      // the solve alone (no points): the others need not wait for process 0's interpolation
      vtkSmartPointer<vtkDataSet> none;
      none.TakeReference(input->NewInstance());
      vtkNew<vtkPoints> noPoints;
      if (auto* set = vtkPointSet::SafeDownCast(none))
        set->SetPoints(noPoints);
      result = compute(none, nullptr);
      if (!result.mesh_weights)
        throw bary::Error(bary::ErrorCode::Internal, "a mesh-based method returned no mesh weights");
      const bary::MeshWeights& m = *result.mesh_weights;
      header << 1 << static_cast<vtkTypeInt64>(m.V.rows()) << static_cast<int>(m.V.cols())
             << static_cast<vtkTypeInt64>(m.T.rows()) << static_cast<int>(m.T.cols())
             << static_cast<vtkTypeInt64>(m.W.cols())
             << static_cast<int>(m.statistics.size());
      for (const auto& entry : m.statistics)
        header << entry.first << entry.second;
    }
    catch (const bary::Error& e)
    {
      failure = std::current_exception();
      header << 0 << static_cast<int>(e.code()) << e.message() << e.advice();
    }
    catch (const std::exception& e)
    {
      failure = std::current_exception();
      header << 0 << static_cast<int>(bary::ErrorCode::Internal)
             << std::string("Unexpected failure: ") + e.what() << std::string();
    }
  }
  controller->Broadcast(header, 0);
  int ok = 0;
  header >> ok;
  if (!ok)
  {
    if (failure)
      std::rethrow_exception(failure);
    int code = 0;
    std::string message, advice;
    header >> code >> message >> advice;
    throw bary::Error(static_cast<bary::ErrorCode>(code), message, advice);
  }
  vtkTypeInt64 vertices = 0, cells = 0, columns = 0;
  int dim = 0, corners = 0, statistics = 0;
  header >> vertices >> dim >> cells >> corners >> columns >> statistics;
  auto m = std::make_shared<bary::MeshWeights>();
  if (rank == 0)
    m = result.mesh_weights;
  else
  {
    m->V.resize(vertices, dim);
    m->T.resize(cells, corners);
    m->W.resize(vertices, columns);
    for (int k = 0; k < statistics; ++k)
    {
      std::string name;
      double value = 0;
      header >> name >> value;
      m->statistics.emplace_back(name, value);
    }
  }
  controller->Broadcast(m->V.data(), static_cast<vtkIdType>(m->V.size()), 0);
  controller->Broadcast(m->T.data(), static_cast<vtkIdType>(m->T.size()), 0);
  controller->Broadcast(m->W.data(), static_cast<vtkIdType>(m->W.size()), 0);
  return compute(input, m.get()); // every process interpolates its piece
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
  const bool distributed = this->Controller && this->Controller->GetNumberOfProcesses() > 1;
  if (input->GetNumberOfPoints() == 0 && !distributed) // a distributed run's piece takes part
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
    vtkBaryCage columns;
    std::vector<std::string> warnings;
    this->UpdateProgress(0.0);
    // BBW with mixed handles (cage faces among other handles, regions, a HandleType array) or
    // with the domain's HandleRegion / ShapePreservation arrays: vtkBaryMixedHandles.
    const bool mixed = this->WeightMethod->GetMethod() == vtkBaryWeightMethod::BBW &&
      vtkBaryMixedHandles::UsesMixedHandles(cagePoly, domain);
    const bary::WeightsSettings settings = this->WeightMethod->GetSettings();
    vtkBaryShared shared;
    vtkNew<vtkPolyData> allPoints;
    const bool celestial = settings.method == bary::MethodId::TCelestial ||
      settings.method == bary::MethodId::SCelestial;
    if (distributed && celestial && settings.celestial_hull_points != bary::CelestialHullPoints::None)
    { // the hull points are the whole's: every piece's own points (not those flagged as
      // duplicates in vtkGhostType), in the order of their global ids when the pieces have them
      vtkUnsignedCharArray* ghosts = input->GetPointGhostArray();
      vtkDataArray* ids = input->GetPointData()->GetGlobalIds();
      vtkNew<vtkDoubleArray> mine, all, mineIds, allIds;
      mine->SetNumberOfComponents(3);
      for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
        if (!ghosts || !(ghosts->GetValue(i) & vtkDataSetAttributes::DUPLICATEPOINT))
        {
          mine->InsertNextTuple(input->GetPoint(i));
          mineIds->InsertNextValue(ids ? ids->GetComponent(i, 0) : 0.0);
        }
      int withIds = ids ? 1 : 0, allWithIds = 0;
      this->Controller->AllReduce(&withIds, &allWithIds, 1, vtkCommunicator::MIN_OP);
      all->SetNumberOfComponents(3);
      this->Controller->AllGatherV(mine, all);
      this->Controller->AllGatherV(mineIds, allIds);
      vtkNew<vtkPoints> points;
      if (allWithIds)
      {
        std::vector<vtkIdType> order(static_cast<std::size_t>(all->GetNumberOfTuples()));
        for (std::size_t k = 0; k < order.size(); ++k)
          order[k] = static_cast<vtkIdType>(k);
        std::stable_sort(order.begin(), order.end(), [&allIds](vtkIdType a, vtkIdType b) {
          return allIds->GetValue(a) < allIds->GetValue(b);
        });
        vtkNew<vtkDoubleArray> sorted;
        sorted->SetNumberOfComponents(3);
        sorted->SetNumberOfTuples(all->GetNumberOfTuples());
        for (std::size_t k = 0; k < order.size(); ++k)
          sorted->SetTuple(static_cast<vtkIdType>(k), order[k], all);
        points->SetData(sorted);
      }
      else
        points->SetData(all);
      allPoints->SetPoints(points);
      shared.AllPoints = allPoints;
    }
    const auto compute = [&](vtkDataSet* points, const bary::MeshWeights* solved) {
      shared.MeshWeights = solved;
      warnings.clear();
      return mixed
        ? vtkBaryMixedHandles::Compute(settings, points, cagePoly, domain, progress, solved)
        : this->WeightMethod->Compute(points, cagePoly, domain, progress, &columns, &warnings, shared);
    };
    const bool meshBased = bary::method_info(settings.method).domain_mesh;
    if (distributed && meshBased && settings.insert_points)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "InsertPointsIntoMesh (--insert-points) makes the mesh of all the points, but a "
        "distributed run (" + std::to_string(this->Controller->GetNumberOfProcesses()) +
          " processes) solves one mesh for all the pieces: turn it off");
    const bary::WeightsResult result = distributed && meshBased
      ? this->ComputeShared(input, compute)
      : compute(input, nullptr);
    if (mixed)
    {
      columns = vtkBaryCage(); // identity column order: handle j is component j
      columns.ControlPointIds.resize(static_cast<std::size_t>(result.W.cols()));
      for (std::size_t j = 0; j < columns.ControlPointIds.size(); ++j)
        columns.ControlPointIds[j] = static_cast<vtkIdType>(j);
    }
    for (const std::string& warning : warnings)
      vtkWarningMacro(<< warning);
    this->FinishOutput(output, result, columns);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryCoordinates::FinishOutput(
  vtkDataSet* output, const bary::WeightsResult& result, const vtkBaryCage& columns)
{
  output->GetPointData()->AddArray(
    vtkBaryConversion::ToArray(result.W, columns, this->WeightsArrayName));
  // Green coordinates: the faces' normal coefficients (psi), faces in core order
  if (result.face_weights.cols() > 0)
  {
    if (!this->FaceWeightsArrayName || !*this->FaceWeightsArrayName)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "FaceWeightsArrayName must not be empty: the method computes face coefficients");
    output->GetPointData()->AddArray(
      vtkBaryConversion::FaceArray(result.face_weights, this->FaceWeightsArrayName));
  }
  else if (this->FaceWeightsArrayName && *this->FaceWeightsArrayName)
    output->GetPointData()->RemoveArray(this->FaceWeightsArrayName); // stale: not these weights'
  // control points the method added (celestial hull points): their positions, columns last
  vtkNew<vtkFieldData> field;
  if (output->GetFieldData())
    field->ShallowCopy(output->GetFieldData());
  field->RemoveArray("AddedControlPoints");
  if (result.added_controls.rows() > 0)
  {
    vtkNew<vtkDoubleArray> added;
    added->SetName("AddedControlPoints");
    added->SetNumberOfComponents(3);
    added->SetNumberOfTuples(result.added_controls.rows());
    for (Eigen::Index k = 0; k < result.added_controls.rows(); ++k)
      for (int j = 0; j < 3; ++j)
        added->SetComponent(k, j,
          j < result.added_controls.cols() ? result.added_controls(k, j) : columns.PlaneZ);
    field->AddArray(added);
  }
  output->SetFieldData(field);
  if (this->GenerateLocation && this->LocationArrayName && *this->LocationArrayName)
  {
    vtkNew<vtkUnsignedCharArray> location;
    location->SetName(this->LocationArrayName);
    location->SetNumberOfTuples(static_cast<vtkIdType>(result.location.size()));
    for (std::size_t i = 0; i < result.location.size(); ++i)
      location->SetValue(static_cast<vtkIdType>(i), static_cast<unsigned char>(result.location[i]));
    output->GetPointData()->AddArray(location);
  }
  this->NumberOfInsidePoints = result.count(bary::PointLocation::Inside);
  this->NumberOfOutsidePoints = result.count(bary::PointLocation::Outside);
  this->NumberOfBoundaryPoints = result.count(bary::PointLocation::Boundary);
  this->NumberOfUndefinedPoints = static_cast<vtkIdType>(result.undefined.size());
  this->Statistics = result.statistics;
  if (!result.undefined.empty())
    vtkWarningMacro(<< result.undefined.size()
                    << " point(s) outside the domain have undefined weights (NaN), first id "
                    << result.undefined.front());
}

void vtkBaryCoordinates::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightMethod:\n";
  this->WeightMethod->PrintSelf(os, indent.GetNextIndent());
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "FaceWeightsArrayName: "
     << (this->FaceWeightsArrayName ? this->FaceWeightsArrayName : "(none)") << "\n";
  os << indent << "GenerateLocation: " << this->GenerateLocation << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "LocationArrayName: "
     << (this->LocationArrayName ? this->LocationArrayName : "(none)") << "\n";
}
