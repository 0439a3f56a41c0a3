/**
 * @class   vtkBaryPVWeightMethod
 * @brief   vtkBaryWeightMethod with its list settings as lists of numbers, for ParaView.
 *
 * The settings table's `Numbers` rows (the T-celestial user weights) are arrays on
 * vtkBaryWeightMethod (SetUserWeights); ParaView's panels set numbers. This subclass of the
 * ParaView plugin takes them through the repeatable-property commands the plugin's generated
 * XML names after the row's property: SetNumberOf<Property>Values and Set<Property>Value. No
 * values: none (SetUserWeights(nullptr), Eq. 7). Everything else is vtkBaryWeightMethod's.
 *
 * @sa vtkBaryWeightMethod
 */
#ifndef vtkBaryPVWeightMethod_h
#define vtkBaryPVWeightMethod_h

#include "BaryLabParaViewModule.h" // for export macro
#include "vtkBaryWeightMethod.h"

class BARYLABPARAVIEW_EXPORT vtkBaryPVWeightMethod : public vtkBaryWeightMethod
{
public:
  static vtkBaryPVWeightMethod* New();
  vtkTypeMacro(vtkBaryPVWeightMethod, vtkBaryWeightMethod);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The number of user weights (one per control point; 0: none). Resets them to 0; a negative
  /// count is an error.
  void SetNumberOfUserWeightsValues(int count);
  /// User weight @p index. An index out of range is an error.
  void SetUserWeightsValue(int index, double value);

protected:
  vtkBaryPVWeightMethod() = default;
  ~vtkBaryPVWeightMethod() override = default;

private:
  vtkBaryPVWeightMethod(const vtkBaryPVWeightMethod&) = delete;
  void operator=(const vtkBaryPVWeightMethod&) = delete;
};

#endif
