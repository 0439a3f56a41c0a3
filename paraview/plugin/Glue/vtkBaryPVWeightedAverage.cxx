#include "vtkBaryPVWeightedAverage.h"

#include "vtkAlgorithm.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTable.h"

vtkStandardNewMacro(vtkBaryPVWeightedAverage);

vtkBaryPVWeightedAverage::vtkBaryPVWeightedAverage()
{
  this->SetNumberOfInputPorts(3);
  this->SetWeightsArrayName("Weights");
}

vtkBaryPVWeightedAverage::~vtkBaryPVWeightedAverage()
{
  this->SetWeightsArrayName(nullptr);
}

int vtkBaryPVWeightedAverage::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port < 2)
    return this->Superclass::FillInputPortInformation(port, info);
  info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  return 1;
}

int vtkBaryPVWeightedAverage::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* data = vtkDataObject::GetData(inputVector[2]);
  vtkDataSetAttributes* attributes = nullptr;
  if (auto* set = vtkDataSet::SafeDownCast(data))
    attributes = set->GetPointData();
  else if (auto* table = vtkTable::SafeDownCast(data))
    attributes = table->GetRowData();
  const char* name = this->WeightsArrayName ? this->WeightsArrayName : "";
  vtkDataArray* weights = attributes ? attributes->GetArray(name) : nullptr;
  if (!weights || weights->GetNumberOfTuples() == 0)
  {
    vtkErrorMacro(<< "weights: the Weights input has no " << (weights ? "rows in its " : "")
                  << "array '" << name
                  << "' (point data of a data set, row data of a table; one tuple per query, "
                     "one component per anchor)");
    return 0;
  }
  this->SetWeights(weights);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

void vtkBaryPVWeightedAverage::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightsArrayName: "
     << (this->WeightsArrayName ? this->WeightsArrayName : "(none)") << "\n";
}
