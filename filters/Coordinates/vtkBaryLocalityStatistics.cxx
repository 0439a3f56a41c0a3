#include "vtkBaryLocalityStatistics.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"
#include "core/analysis/locality_statistics.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTable.h"

#include <algorithm>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBaryLocalityStatistics);
vtkCxxSetObjectMacro(vtkBaryLocalityStatistics, TValues, vtkDoubleArray);

vtkBaryLocalityStatistics::vtkBaryLocalityStatistics()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(3);
  this->SetWeightsArrayName("Weights");
}

vtkBaryLocalityStatistics::~vtkBaryLocalityStatistics()
{
  this->SetWeightsArrayName(nullptr);
  this->SetTValues(nullptr);
}

vtkMTimeType vtkBaryLocalityStatistics::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->TValues)
    t = std::max(t, this->TValues->GetMTime());
  return t;
}

const char* vtkBaryLocalityStatistics::GetMeasureUsedAsString() const
{
  switch (this->MeasureUsed)
  {
    case MEASURE_AREA:
      return "area";
    case MEASURE_VOLUME:
      return "volume";
    default:
      return "uniform";
  }
}

vtkTable* vtkBaryLocalityStatistics::GetPTable()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(0));
}
vtkTable* vtkBaryLocalityStatistics::GetQTable()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}
vtkTable* vtkBaryLocalityStatistics::GetInfluenceTable()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(2));
}

int vtkBaryLocalityStatistics::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

namespace
{
vtkSmartPointer<vtkDoubleArray> double_column(const char* name, const std::vector<double>& v)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(static_cast<vtkIdType>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    a->SetValue(static_cast<vtkIdType>(i), v[i]);
  return a;
}

vtkSmartPointer<vtkIntArray> int_column(const char* name, const std::vector<int>& v)
{
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(static_cast<vtkIdType>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    a->SetValue(static_cast<vtkIdType>(i), v[i]);
  return a;
}
} // namespace

int vtkBaryLocalityStatistics::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkTable* pTable = vtkTable::GetData(outputVector, 0);
  vtkTable* qTable = vtkTable::GetData(outputVector, 1);
  vtkTable* influenceTable = vtkTable::GetData(outputVector, 2);
  this->SetErrorCode(0);
  this->ThresholdUsed = this->MeanSupport = this->MaxSupport = 0.0;
  this->MeasureUsed = MEASURE_UNIFORM;
  try
  {
    if (!input || input->GetNumberOfPoints() == 0)
      throw bary::Error(bary::ErrorCode::EmptyInput,
        "the input has no points: locality statistics need weights at points");
    const std::string name = this->WeightsArrayName ? this->WeightsArrayName : "";
    vtkDataArray* array = vtkBaryConversion::RequirePointArray(input, name,
      "set WeightsArrayName to the weights array, one component per control point");
    const bary::DenseWeights W = vtkBaryConversion::ArrayToMatrix(array);

    Eigen::VectorXd measure;
    int used = MEASURE_UNIFORM;
    if (this->UseMeshMeasure)
      used = vtkBaryConversion::PointMeasures(input, measure);
    std::vector<double> t;
    if (this->TValues)
      for (vtkIdType i = 0; i < this->TValues->GetNumberOfTuples(); ++i)
        t.push_back(this->TValues->GetValue(i));
    this->UpdateProgress(0.1);
    const bary::LocalityStatistics s = bary::locality_statistics(W, this->Threshold, measure, t);

    vtkNew<vtkTable> p, q, influence;
    p->AddColumn(double_column("t", s.t));
    p->AddColumn(double_column("P", s.P));
    q->AddColumn(int_column("k", s.k));
    q->AddColumn(double_column("Q", s.Q));
    std::vector<int> controls(s.influence_fraction.size());
    for (std::size_t i = 0; i < controls.size(); ++i)
      controls[i] = static_cast<int>(i);
    influence->AddColumn(int_column("control", controls));
    influence->AddColumn(double_column("influence_fraction", s.influence_fraction));
    pTable->ShallowCopy(p);
    qTable->ShallowCopy(q);
    influenceTable->ShallowCopy(influence);

    this->ThresholdUsed = s.threshold;
    this->MeanSupport = s.mean_support;
    this->MaxSupport = s.max_support;
    this->MeasureUsed = used;
    this->UpdateProgress(1.0);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryLocalityStatistics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "UseMeshMeasure: " << this->UseMeshMeasure << "\n";
  os << indent << "TValues: " << (this->TValues ? this->TValues->GetNumberOfTuples() : 0) << " values\n";
  os << indent << "ThresholdUsed: " << this->ThresholdUsed << "\n";
  os << indent << "MeanSupport: " << this->MeanSupport << "\n";
  os << indent << "MaxSupport: " << this->MaxSupport << "\n";
  os << indent << "MeasureUsed: " << this->GetMeasureUsedAsString() << "\n";
}
