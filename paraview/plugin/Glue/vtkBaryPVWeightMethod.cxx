#include "vtkBaryPVWeightMethod.h"

#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkBaryPVWeightMethod);

void vtkBaryPVWeightMethod::SetNumberOfUserWeightsValues(int count)
{
  if (count < 0)
  {
    vtkErrorMacro(<< "user weights: a negative count " << count);
    return;
  }
  if (count == 0)
  {
    this->SetUserWeights(nullptr);
    return;
  }
  vtkNew<vtkDoubleArray> weights;
  weights->SetNumberOfTuples(count);
  weights->Fill(0.0);
  this->SetUserWeights(weights);
}

void vtkBaryPVWeightMethod::SetUserWeightsValue(int index, double value)
{
  vtkDataArray* weights = this->GetUserWeights();
  if (!weights || index < 0 || index >= weights->GetNumberOfTuples())
  {
    vtkErrorMacro(<< "user weight " << index
                  << " is out of range (set the number of values first: one per control point)");
    return;
  }
  weights->SetComponent(index, 0, value);
  this->Modified();
}

void vtkBaryPVWeightMethod::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
