#include "vtkBaryPVLinearBlendSkinning.h"

#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkBaryPVLinearBlendSkinning);

void vtkBaryPVLinearBlendSkinning::SetNumberOfTransformValues(int count)
{
  if (count < 0 || count % 12 != 0)
  {
    vtkErrorMacro(<< "transforms: " << count
                  << " values is not a whole number of transforms (12 values per handle: the "
                     "3 x 4 matrix [A | t] row by row)");
    return;
  }
  vtkNew<vtkDoubleArray> transforms;
  transforms->SetNumberOfComponents(12);
  transforms->SetNumberOfTuples(count / 12);
  transforms->Fill(0.0);
  this->SetTransforms(transforms);
}

void vtkBaryPVLinearBlendSkinning::SetTransformValue(int index, double value)
{
  vtkDoubleArray* transforms = this->GetTransforms();
  if (!transforms || index < 0 || index >= transforms->GetNumberOfValues())
  {
    vtkErrorMacro(<< "transform value " << index << " is out of range (set the number of values "
                     "first: 12 per handle)");
    return;
  }
  transforms->SetValue(index, value);
  this->Modified();
}

void vtkBaryPVLinearBlendSkinning::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
