/**
 * @class   vtkBaryPVWeightedAverage
 * @brief   vtkBaryWeightedAverage with its weights from a third input, for ParaView.
 *
 * ParaView connects data, not arrays set from code: this subclass of the ParaView plugin takes
 * the weights from input 2 (Weights: a data set whose point data, or a table whose row data,
 * holds the array WeightsArrayName, default `Weights` as Surface Weights writes it: one tuple
 * per query, one component per anchor) and passes that array to SetWeights at the start of
 * every run. A missing array, or one of no tuples, is an error naming it. Everything else is
 * vtkBaryWeightedAverage's.
 *
 * @sa vtkBaryWeightedAverage
 */
#ifndef vtkBaryPVWeightedAverage_h
#define vtkBaryPVWeightedAverage_h

#include "BaryLabParaViewModule.h" // for export macro
#include "vtkBaryWeightedAverage.h"

class BARYLABPARAVIEW_EXPORT vtkBaryPVWeightedAverage : public vtkBaryWeightedAverage
{
public:
  static vtkBaryPVWeightedAverage* New();
  vtkTypeMacro(vtkBaryPVWeightedAverage, vtkBaryWeightedAverage);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The weights' data (input 2).
  void SetWeightsConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(2, output); }

  /// The weights array of input 2 (point data of a data set, row data of a table).
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);

protected:
  vtkBaryPVWeightedAverage();
  ~vtkBaryPVWeightedAverage() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* WeightsArrayName = nullptr;

private:
  vtkBaryPVWeightedAverage(const vtkBaryPVWeightedAverage&) = delete;
  void operator=(const vtkBaryPVWeightedAverage&) = delete;
};

#endif
