#include "vtkBarySplineEdit.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySplineData.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkUnstructuredGrid.h"

#include <optional>

vtkStandardNewMacro(vtkBarySplineEdit);

void vtkBarySplineEdit::SetEdits(const std::vector<Edit>& edits)
{
  this->Edits = edits;
  this->Modified();
}

void vtkBarySplineEdit::AddEdit(Edit edit, vtkIdTypeArray* anchors, vtkDataArray* near)
{
  for (vtkIdType i = 0; anchors && i < anchors->GetNumberOfTuples(); ++i)
    edit.edit.anchors.push_back(static_cast<bary::Index>(anchors->GetValue(i)));
  for (vtkIdType i = 0; near && i < near->GetNumberOfTuples(); ++i)
    edit.edit.near.emplace_back(
      near->GetComponent(i, 0), near->GetNumberOfComponents() > 1 ? near->GetComponent(i, 1) : 0.0);
  this->Edits.push_back(std::move(edit));
  this->Modified();
}

void vtkBarySplineEdit::AddTranslateEdit(
  int target, vtkIdTypeArray* anchors, vtkDataArray* near, double dx, double dy, int deltaMax)
{
  Edit e;
  e.target = target;
  e.edit.op = bary::SplineEditOp::Translate;
  if (target == XY)
    e.edit.by = Eigen::Vector2d(dx, dy);
  else
    e.edit.by = Eigen::VectorXd::Constant(1, dx); // a surface's height
  e.edit.delta_max = deltaMax;
  this->AddEdit(std::move(e), anchors, near);
}

void vtkBarySplineEdit::AddRotateEdit(int target, vtkIdTypeArray* anchors, vtkDataArray* near,
  double centerX, double centerY, double angleDegrees, int deltaMax)
{
  Edit e;
  e.target = target;
  e.edit.op = bary::SplineEditOp::Rotate;
  e.edit.center = Eigen::Vector2d(centerX, centerY);
  e.edit.angle_degrees = angleDegrees;
  e.edit.delta_max = deltaMax;
  this->AddEdit(std::move(e), anchors, near);
}

void vtkBarySplineEdit::AddScaleEdit(int target, vtkIdTypeArray* anchors, vtkDataArray* near,
  double centerX, double centerY, double factor, int deltaMax)
{
  Edit e;
  e.target = target;
  e.edit.op = bary::SplineEditOp::Scale;
  e.edit.center = Eigen::Vector2d(centerX, centerY);
  e.edit.factor = factor;
  e.edit.delta_max = deltaMax;
  this->AddEdit(std::move(e), anchors, near);
}

void vtkBarySplineEdit::ClearEdits()
{
  this->Edits.clear();
  this->Modified();
}

int vtkBarySplineEdit::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  try
  {
    vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
    vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
    vtkBarySpline spline = vtkBarySplineData::FromGrid(input);
    std::optional<bary::SplineEditor> editors[3];
    editors[XY].emplace(*spline.xy);
    editors[XY]->set_pinned(spline.pinned);
    if (spline.is_prism())
    {
      editors[BOTTOM].emplace(*spline.bottom);
      editors[TOP].emplace(*spline.top);
      editors[BOTTOM]->set_pinned(spline.pinned);
      editors[TOP]->set_pinned(spline.pinned);
    }
    this->Reports.clear();
    for (size_t k = 0; k < this->Edits.size(); ++k)
    {
      const Edit& e = this->Edits[k];
      if (e.target < XY || e.target > TOP)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "edit " + std::to_string(k) + " names spline " + std::to_string(e.target) +
            "; 0 (xy), 1 (bottom) or 2 (top)");
      if (!editors[e.target])
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "edit " + std::to_string(k) + " changes the " + (e.target == BOTTOM ? "bottom" : "top") +
            " surface, but the spline is not a 2.5D (prism) deformation");
      try
      {
        this->Reports.push_back(editors[e.target]->apply(e.edit));
      }
      catch (const bary::Error& err)
      {
        throw bary::Error(err.code(), "edit " + std::to_string(k) + ": " + err.message(), err.advice());
      }
    }
    spline.xy = editors[XY]->spline();
    if (spline.is_prism())
    {
      spline.bottom = editors[BOTTOM]->spline();
      spline.top = editors[TOP]->spline();
    }
    output->ShallowCopy(vtkBarySplineData::ToGrid(spline));
    const char* names[] = { "EditSeconds", "ExactSeconds", "Anchors", "Slaves", "Derived",
      "Constraints", "IndependentConstraints", "Residual" };
    for (int a = 0; a < 8; ++a)
    {
      auto arr = vtkSmartPointer<vtkDoubleArray>::New();
      arr->SetName(names[a]);
      for (const auto& r : this->Reports)
      {
        const double v[] = { r.seconds, r.exact_seconds, double(r.sets.anchors.size()),
          double(r.sets.slaves.size()), double(r.sets.derived.size()),
          double(r.sets.constraints.size()), double(r.sets.independent.size()), r.residual };
        arr->InsertNextValue(v[a]);
      }
      output->GetFieldData()->AddArray(arr);
    }
    auto minj = vtkSmartPointer<vtkDoubleArray>::New();
    minj->SetName("MinJacobian");
    minj->InsertNextValue(spline.xy->check_jacobian().min_jacobian);
    output->GetFieldData()->AddArray(minj);
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}
