#include "vtkBaryReduceWeights.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"
#include "core/analysis/locality_statistics.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <limits>
#include <string>

vtkStandardNewMacro(vtkBaryReduceWeights);

vtkBaryReduceWeights::vtkBaryReduceWeights()
{
  this->SetNumberOfInputPorts(2);
  this->SetWeightsArrayName("Weights");
}

vtkBaryReduceWeights::~vtkBaryReduceWeights()
{
  this->SetWeightsArrayName(nullptr);
}

void vtkBaryReduceWeights::SetCageData(vtkPolyData* cage)
{
  this->SetInputData(1, cage);
}
void vtkBaryReduceWeights::SetCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

int vtkBaryReduceWeights::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  else
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

int vtkBaryReduceWeights::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* cagePoints = vtkPolyData::GetData(inputVector[1]);
  vtkDataSet* output = vtkDataSet::GetData(outputVector);
  this->SetErrorCode(0);
  this->ThresholdUsed = this->PartitionError = this->MaxDropped = 0.0;
  this->ReproductionError = std::numeric_limits<double>::quiet_NaN();
  this->MaximumSupport = 0;
  this->MemoryFraction = this->CSRMemoryFraction = 0.0;
  this->NumberOfNonzeros = 0;
  try
  {
    if (!input || input->GetNumberOfPoints() == 0)
      throw bary::Error(bary::ErrorCode::EmptyInput, "the input has no points: nothing to reduce");
    const std::string name = this->WeightsArrayName ? this->WeightsArrayName : "";
    if (name.empty())
      throw bary::Error(bary::ErrorCode::InvalidArgument, "WeightsArrayName is empty");
    vtkDataArray* array = vtkBaryConversion::RequirePointArray(
      input, name, "set WeightsArrayName to the dense weights array");
    const bary::DenseWeights W = vtkBaryConversion::ArrayToMatrix(array);
    const bary::Renormalization mode = this->Renormalization == RENORMALIZE_NONE
      ? bary::Renormalization::None
      : this->Renormalization == RENORMALIZE_AFFINE ? bary::Renormalization::Affine
                                                    : bary::Renormalization::RowSum;
    Eigen::MatrixXd controls, points;
    if (cagePoints)
    {
      const vtkBaryCage cage = vtkBaryConversion::ToControlPoints(cagePoints);
      if (cage.Cage.num_controls() != W.cols())
        throw bary::Error(bary::ErrorCode::SizeMismatch,
          "the weights array '" + name + "' has " + std::to_string(W.cols()) +
            " components but the cage has " + std::to_string(cage.Cage.num_controls()) +
            " points (component i must be cage point i)");
      controls = cage.Cage.V;
      points = vtkBaryConversion::PointsToMatrix(input, cage.Cage.dimension());
    }
    else if (mode == bary::Renormalization::Affine)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "affine renormalisation needs the control points: connect the cage to input port 1 "
        "(SetCageData)");
    this->UpdateProgress(0.1);
    const bary::ReducedWeights r = bary::reduce_weights(W, this->Threshold, mode,
      cagePoints ? &controls : nullptr, cagePoints ? &points : nullptr);
    this->UpdateProgress(0.8);

    vtkNew<vtkIntArray> indices;
    vtkNew<vtkDoubleArray> values;
    indices->SetName((name + "Indices").c_str());
    values->SetName((name + "Values").c_str());
    const int K = vtkBaryConversion::ToCompactArrays(r.W, indices, values);

    output->ShallowCopy(input);
    if (!this->KeepDenseArray)
      output->GetPointData()->RemoveArray(name.c_str());
    output->GetPointData()->AddArray(indices);
    output->GetPointData()->AddArray(values);
    vtkNew<vtkIntArray> count;
    count->SetName((name + "NumberOfControlPoints").c_str());
    count->InsertNextValue(static_cast<int>(W.cols()));
    vtkNew<vtkDoubleArray> threshold;
    threshold->SetName((name + "Threshold").c_str());
    threshold->InsertNextValue(r.threshold);
    output->GetFieldData()->AddArray(count);
    output->GetFieldData()->AddArray(threshold);

    this->ThresholdUsed = r.threshold;
    this->PartitionError = r.partition_error;
    this->ReproductionError =
      cagePoints ? r.reproduction_error : std::numeric_limits<double>::quiet_NaN();
    this->MaxDropped = r.max_dropped;
    this->MaximumSupport = K;
    this->MemoryFraction = (4.0 + 8.0) * K / (8.0 * static_cast<double>(W.cols()));
    this->CSRMemoryFraction = r.memory_fraction;
    this->NumberOfNonzeros = static_cast<vtkIdType>(r.nonzeros);
    this->UpdateProgress(1.0);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryReduceWeights::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "Renormalization: " << this->Renormalization << "\n";
  os << indent << "KeepDenseArray: " << this->KeepDenseArray << "\n";
  os << indent << "PartitionError: " << this->PartitionError << "\n";
  os << indent << "ReproductionError: " << this->ReproductionError << "\n";
  os << indent << "MaximumSupport: " << this->MaximumSupport << "\n";
  os << indent << "MemoryFraction: " << this->MemoryFraction << "\n";
}
