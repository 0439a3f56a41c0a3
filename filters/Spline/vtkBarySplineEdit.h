/**
 * @class   vtkBarySplineEdit
 * @brief   Applies DECLeS edits (Rodrigues et al. 2014, §4, §5.1: soft translation, rotation and
 *          scale of anchors with slaves within delta_max) to a spline grid (vtkBarySplineData),
 *          each to the xy deformation or, for a 2.5D deformation, to its bottom or top surface.
 *          The output is the edited grid; the C1 conditions hold after every edit. Field data of
 *          the output: `EditSeconds`, `ExactSeconds`, `Anchors`, `Slaves`, `Derived`,
 *          `Constraints`, `IndependentConstraints`, `Residual` (one tuple per edit),
 *          `MinJacobian` (of the xy deformation after the last edit, §3.4).
 *
 * @sa vtkBarySplineData vtkBarySplineSource vtkBarySplineDeform
 */
#ifndef vtkBarySplineEdit_h
#define vtkBarySplineEdit_h

#include "BaryLabSplineModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

#ifndef __VTK_WRAP__
#include "core/spline/decles.h" // for bary::SplineEdit

#include <vector>
#endif

class vtkDataArray;
class vtkIdTypeArray;

class BARYLABSPLINE_EXPORT vtkBarySplineEdit : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkBarySplineEdit* New();
  vtkTypeMacro(vtkBarySplineEdit, vtkUnstructuredGridAlgorithm);

  /// Which spline an edit changes.
  enum Target
  {
    XY = 0,     ///< the deformation phi
    BOTTOM = 1, ///< the 2.5D bottom surface sigma0
    TOP = 2     ///< the 2.5D top surface sigma1
  };

#ifndef __VTK_WRAP__
  struct Edit
  {
    bary::SplineEdit edit;
    int target = XY;
  };
  /// The edits, applied in order on every update.
  void SetEdits(const std::vector<Edit>& edits);
  const std::vector<Edit>& GetEdits() const { return this->Edits; }
  /// What each edit of the last update did.
  const std::vector<bary::SplineEditReport>& GetReports() const { return this->Reports; }
#endif
  void ClearEdits();

  ///@{
  /// One edit appended to the edits (the wrapped form of SetEdits, for Python's spline_edit;
  /// the fields of `barylab spline edit`'s EDITS.json): the anchors are the control points of
  /// the indices in @p anchors and those nearest to the positions in @p near (2 components a
  /// tuple); either may be null, not both. @p target XY, BOTTOM or TOP; a translation of BOTTOM
  /// or TOP moves by @p dx alone (a height). Checked when applied (the request then fails,
  /// naming the edit).
  void AddTranslateEdit(
    int target, vtkIdTypeArray* anchors, vtkDataArray* near, double dx, double dy, int deltaMax);
  void AddRotateEdit(int target, vtkIdTypeArray* anchors, vtkDataArray* near, double centerX,
    double centerY, double angleDegrees, int deltaMax);
  void AddScaleEdit(int target, vtkIdTypeArray* anchors, vtkDataArray* near, double centerX,
    double centerY, double factor, int deltaMax);
  ///@}

protected:
  vtkBarySplineEdit() = default;
  ~vtkBarySplineEdit() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

#ifndef __VTK_WRAP__
  /// Appends @p edit with its anchors from @p anchors and @p near (AddTranslateEdit ...).
  void AddEdit(Edit edit, vtkIdTypeArray* anchors, vtkDataArray* near);
  std::vector<Edit> Edits;
  std::vector<bary::SplineEditReport> Reports;
#endif

private:
  vtkBarySplineEdit(const vtkBarySplineEdit&) = delete;
  void operator=(const vtkBarySplineEdit&) = delete;
};

#endif
