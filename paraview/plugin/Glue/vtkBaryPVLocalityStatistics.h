/**
 * @class   vtkBaryPVLocalityStatistics
 * @brief   vtkBaryLocalityStatistics with its t values as a list of numbers, for ParaView.
 *
 * ParaView's property panels set numbers, not arrays: this subclass of the ParaView plugin takes
 * the t values of P(t) through the repeatable-property commands SetNumberOfTValues and
 * SetTValue. No values (the default): the 26 default t values. Everything else is
 * vtkBaryLocalityStatistics'.
 *
 * @sa vtkBaryLocalityStatistics
 */
#ifndef vtkBaryPVLocalityStatistics_h
#define vtkBaryPVLocalityStatistics_h

#include "BaryLabParaViewModule.h" // for export macro
#include "vtkBaryLocalityStatistics.h"

class BARYLABPARAVIEW_EXPORT vtkBaryPVLocalityStatistics : public vtkBaryLocalityStatistics
{
public:
  static vtkBaryPVLocalityStatistics* New();
  vtkTypeMacro(vtkBaryPVLocalityStatistics, vtkBaryLocalityStatistics);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The number of t values (0: the defaults). Resets them to 0; a negative count is an error.
  void SetNumberOfTValues(int count);
  /// Value @p index. An index out of range is an error.
  void SetTValue(int index, double value);

protected:
  vtkBaryPVLocalityStatistics() = default;
  ~vtkBaryPVLocalityStatistics() override = default;

private:
  vtkBaryPVLocalityStatistics(const vtkBaryPVLocalityStatistics&) = delete;
  void operator=(const vtkBaryPVLocalityStatistics&) = delete;
};

#endif
