#include "vtkBaryPVLocalityStatistics.h"

#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkBaryPVLocalityStatistics);

void vtkBaryPVLocalityStatistics::SetNumberOfTValues(int count)
{
  if (count < 0)
  {
    vtkErrorMacro(<< "t values: a negative count " << count);
    return;
  }
  vtkNew<vtkDoubleArray> values;
  values->SetNumberOfTuples(count);
  values->Fill(0.0);
  this->SetTValues(values);
}

void vtkBaryPVLocalityStatistics::SetTValue(int index, double value)
{
  vtkDoubleArray* values = this->GetTValues();
  if (!values || index < 0 || index >= values->GetNumberOfValues())
  {
    vtkErrorMacro(<< "t value " << index << " is out of range (set the number of values first)");
    return;
  }
  values->SetValue(index, value);
  this->Modified();
}

void vtkBaryPVLocalityStatistics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
