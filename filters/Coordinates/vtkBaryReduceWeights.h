/**
 * @class   vtkBaryReduceWeights
 * @brief   Sparse (reduced) weights: drops the negligible weights and stores the rest compactly.
 *
 * The compact representation of Zhang et al., "Local barycentric coordinates", ACM TOG 33(6),
 * 2014, §5 and Table 1: at each point only the weights above a threshold of negligible
 * influence (10^-3 / #controls by default) are kept, computed by bary::reduce_weights
 * (core/analysis/locality_statistics.h). Useful for local weights (LBC, BBW, harmonic coordinates),
 * useless for global ones (mean value coordinates keep every weight).
 *
 * Rows are renormalised after the drop (Renormalization):
 * - RENORMALIZE_NONE: the kept weights stay as they are; partition of unity is then off by the
 *   dropped mass (at most #controls x threshold = 10^-3 by default).
 * - RENORMALIZE_ROW_SUM (default): each row is divided by the sum of its kept weights, so
 *   partition of unity holds to rounding and non-negative weights stay non-negative;
 *   reproduction (sum_i w_i c_i = x) is off by at most the dropped mass times the distance to
 *   the farthest dropped control point.
 * - RENORMALIZE_AFFINE: the least-norm correction of the kept weights that restores partition
 *   of unity and reproduction exactly (to rounding); needs the control points (input 1); a
 *   weight may become slightly negative (by about the dropped mass). Rows whose kept controls
 *   do not span the space fall back to the row sum.
 *
 * Input 0: any vtkDataSet with the dense point-data array WeightsArrayName (one component per
 * control point). Input 1 (optional): the cage / control points (vtkPolyData, point i =
 * control point i = component i; cells ignored; 2D when all its points share one z, then the
 * points' x, y are used): gives the reproduction error and is required for RENORMALIZE_AFFINE.
 *
 * Output: a copy of input 0 where the dense array is replaced (or, with KeepDenseArray,
 * accompanied) by two point-data arrays with K components, K = the largest number of kept
 * weights at one point:
 * - `<WeightsArrayName>Indices` (vtkIntArray): the kept controls (component indices of the
 *   dense array) in increasing order, padded with -1;
 * - `<WeightsArrayName>Values` (vtkDoubleArray): their weights, padded with 0;
 * and field data `<WeightsArrayName>NumberOfControlPoints` (vtkIntArray, 1 value: #controls)
 * and `<WeightsArrayName>Threshold` (vtkDoubleArray, 1 value). vtkBaryCageDeformation reads
 * this pair when the dense array is absent (O(K) per point).
 *
 * @warning The compact arrays cost 12 K bytes per point against 8 #controls for the dense
 * array (GetMemoryFraction); with global weights K = #controls and they are larger.
 *
 * Errors (vtkErrorMacro, RequestData returns 0): no points, a missing weights array, NaN/inf
 * weights, a zero threshold, a cage whose point count differs from the components, Affine
 * without a cage, a row whose kept weights sum to <= 0 (RowSum).
 *
 * @sa vtkBaryLocalityStatistics vtkBaryCageDeformation
 */
#ifndef vtkBaryReduceWeights_h
#define vtkBaryReduceWeights_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkDataSetAlgorithm.h"

class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryReduceWeights : public vtkDataSetAlgorithm
{
public:
  static vtkBaryReduceWeights* New();
  vtkTypeMacro(vtkBaryReduceWeights, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// How rows are fixed after the drop (see the class description).
  enum Renormalizations
  {
    RENORMALIZE_NONE = 0,
    RENORMALIZE_ROW_SUM = 1,
    RENORMALIZE_AFFINE = 2
  };

  ///@{
  /// Name of the dense weights array; the compact arrays are named after it. Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  ///@}

  ///@{
  /// Weights <= Threshold are dropped. Negative (default -1): 10^-3 / #controls. 0 is an error.
  vtkSetMacro(Threshold, double);
  vtkGetMacro(Threshold, double);
  ///@}

  ///@{
  /// Row renormalisation, clamped to [RENORMALIZE_NONE, RENORMALIZE_AFFINE]. Default
  /// RENORMALIZE_ROW_SUM.
  vtkSetClampMacro(Renormalization, int, RENORMALIZE_NONE, RENORMALIZE_AFFINE);
  vtkGetMacro(Renormalization, int);
  void SetRenormalizationToNone() { this->SetRenormalization(RENORMALIZE_NONE); }
  void SetRenormalizationToRowSum() { this->SetRenormalization(RENORMALIZE_ROW_SUM); }
  void SetRenormalizationToAffine() { this->SetRenormalization(RENORMALIZE_AFFINE); }
  ///@}

  ///@{
  /// Keep the dense array in the output too. Default off.
  vtkSetMacro(KeepDenseArray, bool);
  vtkGetMacro(KeepDenseArray, bool);
  vtkBooleanMacro(KeepDenseArray, bool);
  ///@}

  ///@{
  /// Input 1: the cage / control points (optional).
  void SetCageData(vtkPolyData* cage);
  void SetCageConnection(vtkAlgorithmOutput* output);
  ///@}

  ///@{
  /// Results of the last successful update.
  vtkGetMacro(ThresholdUsed, double);
  /// max_p |sum_i w_i - 1| after reduction.
  vtkGetMacro(PartitionError, double);
  /// max_p |sum_i w_i c_i - x_p| / (diameter of the controls' bounding box); NaN without a cage.
  vtkGetMacro(ReproductionError, double);
  /// Largest sum of dropped |weights| at one point.
  vtkGetMacro(MaxDropped, double);
  /// K: components of the compact arrays (largest number of kept weights at one point).
  vtkGetMacro(MaximumSupport, int);
  /// Bytes of the compact arrays (4 + 8 bytes per entry, K per point) / bytes of the dense
  /// array (8 bytes x #controls per point).
  vtkGetMacro(MemoryFraction, double);
  /// The same for core's CSR form (only the kept entries, plus row offsets).
  vtkGetMacro(CSRMemoryFraction, double);
  /// Kept entries in all.
  vtkGetMacro(NumberOfNonzeros, vtkIdType);
  ///@}

protected:
  vtkBaryReduceWeights();
  ~vtkBaryReduceWeights() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* WeightsArrayName = nullptr;
  double Threshold = -1.0;
  int Renormalization = RENORMALIZE_ROW_SUM;
  bool KeepDenseArray = false;

  double ThresholdUsed = 0.0;
  double PartitionError = 0.0;
  double ReproductionError = 0.0;
  double MaxDropped = 0.0;
  int MaximumSupport = 0;
  double MemoryFraction = 0.0;
  double CSRMemoryFraction = 0.0;
  vtkIdType NumberOfNonzeros = 0;

private:
  vtkBaryReduceWeights(const vtkBaryReduceWeights&) = delete;
  void operator=(const vtkBaryReduceWeights&) = delete;
};

#endif
