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

protected:
  vtkBarySplineEdit() = default;
  ~vtkBarySplineEdit() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

#ifndef __VTK_WRAP__
  std::vector<Edit> Edits;
  std::vector<bary::SplineEditReport> Reports;
#endif

private:
  vtkBarySplineEdit(const vtkBarySplineEdit&) = delete;
  void operator=(const vtkBarySplineEdit&) = delete;
};

#endif
