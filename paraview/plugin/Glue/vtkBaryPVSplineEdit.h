/**
 * @class   vtkBaryPVSplineEdit
 * @brief   vtkBarySplineEdit applying one edit given as numbers, for ParaView.
 *
 * ParaView's property panels set numbers, not lists of edits: this subclass of the ParaView
 * plugin holds ONE DECLeS edit as properties and, at the start of every run, replaces the
 * filter's edits by it (ClearEdits, then AddTranslateEdit, AddRotateEdit or AddScaleEdit).
 * Operation: TRANSLATE (by By: dx, dy on the xy deformation; dx alone, a height, on the bottom
 * or top surface), ROTATE (by Angle degrees about Center) or SCALE (by Factor about Center).
 * Target: vtkBarySplineEdit::XY, BOTTOM or TOP. The anchors: the control points of the indices
 * set with SetNumberOfAnchors / SetAnchor and those nearest to the positions set with
 * SetNumberOfNearPositions / SetNearPosition; an edit with neither, or with bad values, is
 * the filter's error naming it. DeltaMax: slaves within this net distance. Several edits:
 * several filters in a chain. The defaults are bary::SplineEdit's.
 *
 * @sa vtkBarySplineEdit
 */
#ifndef vtkBaryPVSplineEdit_h
#define vtkBaryPVSplineEdit_h

#include "BaryLabParaViewModule.h" // for export macro
#include "vtkBarySplineEdit.h"
#include "vtkNew.h" // for the arrays

class vtkDoubleArray;
class vtkIdTypeArray;

class BARYLABPARAVIEW_EXPORT vtkBaryPVSplineEdit : public vtkBarySplineEdit
{
public:
  static vtkBaryPVSplineEdit* New();
  vtkTypeMacro(vtkBaryPVSplineEdit, vtkBarySplineEdit);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Operation
  {
    TRANSLATE = 0,
    ROTATE = 1,
    SCALE = 2
  };
  vtkSetMacro(Operation, int);
  vtkGetMacro(Operation, int);
  vtkSetMacro(Target, int);
  vtkGetMacro(Target, int);
  vtkSetVector2Macro(By, double);
  vtkGetVector2Macro(By, double);
  vtkSetVector2Macro(Center, double);
  vtkGetVector2Macro(Center, double);
  vtkSetMacro(Angle, double);
  vtkGetMacro(Angle, double);
  vtkSetMacro(Factor, double);
  vtkGetMacro(Factor, double);
  vtkSetMacro(DeltaMax, int);
  vtkGetMacro(DeltaMax, int);

  /// The anchor indices: their number (resets them to 0; negative is an error) and entry @p
  /// index (out of range is an error).
  void SetNumberOfAnchors(int count);
  void SetAnchor(int index, vtkIdType anchor);
  /// The near positions: their number (resets them to (0, 0); negative is an error) and
  /// position @p index (out of range is an error).
  void SetNumberOfNearPositions(int count);
  void SetNearPosition(int index, double x, double y);

protected:
  vtkBaryPVSplineEdit();
  ~vtkBaryPVSplineEdit() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Operation = TRANSLATE;
  int Target = XY;
  double By[2] = { 0, 0 };
  double Center[2];
  double Angle;
  double Factor;
  int DeltaMax;
  vtkNew<vtkIdTypeArray> Anchors;
  vtkNew<vtkDoubleArray> Near;

private:
  vtkBaryPVSplineEdit(const vtkBaryPVSplineEdit&) = delete;
  void operator=(const vtkBaryPVSplineEdit&) = delete;
};

#endif
