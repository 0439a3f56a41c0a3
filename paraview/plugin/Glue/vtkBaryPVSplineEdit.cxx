#include "vtkBaryPVSplineEdit.h"

#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkObjectFactory.h"

#include "core/spline/decles.h"

vtkStandardNewMacro(vtkBaryPVSplineEdit);

vtkBaryPVSplineEdit::vtkBaryPVSplineEdit()
{
  const bary::SplineEdit defaults;
  this->Center[0] = defaults.center.x();
  this->Center[1] = defaults.center.y();
  this->Angle = defaults.angle_degrees;
  this->Factor = defaults.factor;
  this->DeltaMax = defaults.delta_max;
  this->Near->SetNumberOfComponents(2);
}

vtkBaryPVSplineEdit::~vtkBaryPVSplineEdit() = default;

void vtkBaryPVSplineEdit::SetNumberOfAnchors(int count)
{
  if (count < 0)
  {
    vtkErrorMacro(<< "anchors: a negative number (" << count << ")");
    return;
  }
  this->Anchors->SetNumberOfTuples(count);
  this->Anchors->Fill(0);
  this->Modified();
}

void vtkBaryPVSplineEdit::SetAnchor(int index, vtkIdType anchor)
{
  if (index < 0 || index >= this->Anchors->GetNumberOfTuples())
  {
    vtkErrorMacro(<< "anchor " << index << " is out of range (set the number of anchors first)");
    return;
  }
  this->Anchors->SetValue(index, anchor);
  this->Modified();
}

void vtkBaryPVSplineEdit::SetNumberOfNearPositions(int count)
{
  if (count < 0)
  {
    vtkErrorMacro(<< "near positions: a negative number (" << count << ")");
    return;
  }
  this->Near->SetNumberOfTuples(count);
  this->Near->Fill(0.0);
  this->Modified();
}

void vtkBaryPVSplineEdit::SetNearPosition(int index, double x, double y)
{
  if (index < 0 || index >= this->Near->GetNumberOfTuples())
  {
    vtkErrorMacro(<< "near position " << index
                  << " is out of range (set the number of positions first)");
    return;
  }
  this->Near->SetTuple2(index, x, y);
  this->Modified();
}

int vtkBaryPVSplineEdit::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkIdTypeArray* anchors = this->Anchors->GetNumberOfTuples() ? this->Anchors.Get() : nullptr;
  vtkDoubleArray* near = this->Near->GetNumberOfTuples() ? this->Near.Get() : nullptr;
  this->ClearEdits();
  switch (this->Operation)
  {
    case TRANSLATE:
      this->AddTranslateEdit(this->Target, anchors, near, this->By[0], this->By[1], this->DeltaMax);
      break;
    case ROTATE:
      this->AddRotateEdit(
        this->Target, anchors, near, this->Center[0], this->Center[1], this->Angle, this->DeltaMax);
      break;
    case SCALE:
      this->AddScaleEdit(
        this->Target, anchors, near, this->Center[0], this->Center[1], this->Factor, this->DeltaMax);
      break;
    default:
      vtkErrorMacro(<< "operation " << this->Operation
                    << ": 0 (translate), 1 (rotate) or 2 (scale)");
      return 0;
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

void vtkBaryPVSplineEdit::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Operation: " << this->Operation << "\n"
     << indent << "Target: " << this->Target << "\n"
     << indent << "By: " << this->By[0] << " " << this->By[1] << "\n"
     << indent << "Center: " << this->Center[0] << " " << this->Center[1] << "\n"
     << indent << "Angle: " << this->Angle << "\n"
     << indent << "Factor: " << this->Factor << "\n"
     << indent << "DeltaMax: " << this->DeltaMax << "\n"
     << indent << "Anchors: " << this->Anchors->GetNumberOfTuples() << "\n"
     << indent << "Near positions: " << this->Near->GetNumberOfTuples() << "\n";
}
