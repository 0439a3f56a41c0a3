/**
 * @class   vtkBaryPVLinearBlendSkinning
 * @brief   vtkBaryLinearBlendSkinning with its transforms as a list of numbers, for ParaView.
 *
 * ParaView's property panels set numbers, not arrays: this subclass of the ParaView plugin takes
 * the handles' transforms as one list of 12 numbers per handle (the 3 x 4 matrix [A | t] row
 * by row, as vtkBaryLinearBlendSkinning's transforms array holds them), through the
 * repeatable-property commands SetNumberOfTransformValues (the list's length, a multiple of 12)
 * and SetTransformValue (one entry). Everything else is vtkBaryLinearBlendSkinning's.
 *
 * @sa vtkBaryLinearBlendSkinning
 */
#ifndef vtkBaryPVLinearBlendSkinning_h
#define vtkBaryPVLinearBlendSkinning_h

#include "BaryLabParaViewModule.h" // for export macro
#include "vtkBaryLinearBlendSkinning.h"

class BARYLABPARAVIEW_EXPORT vtkBaryPVLinearBlendSkinning : public vtkBaryLinearBlendSkinning
{
public:
  static vtkBaryPVLinearBlendSkinning* New();
  vtkTypeMacro(vtkBaryPVLinearBlendSkinning, vtkBaryLinearBlendSkinning);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The number of transform values: 12 per handle. Resets them to 0. A count that is not a
  /// multiple of 12 is an error (the transforms are left unchanged).
  void SetNumberOfTransformValues(int count);
  /// Entry @p index (handle index / 12, row-major [A | t] entry index % 12). An index out of
  /// range is an error.
  void SetTransformValue(int index, double value);

protected:
  vtkBaryPVLinearBlendSkinning() = default;
  ~vtkBaryPVLinearBlendSkinning() override = default;

private:
  vtkBaryPVLinearBlendSkinning(const vtkBaryPVLinearBlendSkinning&) = delete;
  void operator=(const vtkBaryPVLinearBlendSkinning&) = delete;
};

#endif
