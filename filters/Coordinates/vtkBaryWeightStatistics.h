/**
 * @class   vtkBaryWeightStatistics
 * @brief   The properties of a weight field as a table: partition of unity, reproduction,
 *          range, negative entries and significant weights per point.
 *
 * Computed by bary::weight_statistics (core/analysis/weight_statistics.h) from the point-data array
 * WeightsArrayName (one component per control point) of input 0. With the cage (or free
 * control points) on the optional input 1, also the reproduction error
 * max_p |sum_i w_i(p) c_i - p| relative to the cage's bounding-box diagonal; the cage is read
 * as vtkBaryCoordinates reads it (CageDimension; bare points are free control points, component
 * i = point i), and its point count must equal the number of components. Green coordinates'
 * weights do not reproduce x alone: when the input also carries the point-data array
 * FaceWeightsArrayName (default "FaceWeights", written by vtkBaryCoordinates with GREEN: one
 * component per cage face or 2D edge), the reproduction error is that of
 * sum_i w_i c_i + sum_j psi_j n_j, n_j the faces' unit normals as their vertex order orients
 * them, and the table gets the column "face_coefficients" (their number). Partition of unity,
 * range and significance are those of the weights (phi) alone.
 *
 * Outputs (vtkTable each):
 * - port 0: one row, vtkDoubleArray columns "points", "controls", "threshold", "min_weight",
 *   "max_weight", "negative_weights", "non_finite_rows", "max_partition_error",
 *   "mean_partition_error", "mean_significant", "max_significant", and, with a cage,
 *   "max_reproduction_error", "mean_reproduction_error";
 * - port 1: the histogram of significant weights per point: columns "k" (vtkIntArray, 0 ..
 *   max) and "points" (vtkIdTypeArray, how many points have exactly k weights above the
 *   threshold).
 *
 * Errors (vtkErrorMacro, the request fails): no points, a missing weights array (the message
 * lists the arrays present), a cage whose point count differs from the components.
 *
 * @sa vtkBaryLocalityStatistics vtkBaryCoordinates
 */
#ifndef vtkBaryWeightStatistics_h
#define vtkBaryWeightStatistics_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkTableAlgorithm.h"

class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryWeightStatistics : public vtkTableAlgorithm
{
public:
  static vtkBaryWeightStatistics* New();
  vtkTypeMacro(vtkBaryWeightStatistics, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Name of the point-data weights array. Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  ///@}

  ///@{
  /// A weight is significant when it is > Threshold. Negative (default -1): the LBC paper's
  /// 10^-3 / #controls.
  vtkSetMacro(Threshold, double);
  vtkGetMacro(Threshold, double);
  ///@}

  ///@{
  /// How the cage on input 1 is read: 0 automatic (default), 2 or 3 (see vtkBaryConversion).
  vtkSetClampMacro(CageDimension, int, 0, 3);
  vtkGetMacro(CageDimension, int);
  ///@}

  ///@{
  /// Name of the face-coefficients array (Green coordinates' psi), used with a cage when
  /// present. Default "FaceWeights".
  vtkSetStringMacro(FaceWeightsArrayName);
  vtkGetStringMacro(FaceWeightsArrayName);
  ///@}

  /// The cage or control points (input 1, optional).
  void SetCageData(vtkPolyData* cage);

protected:
  vtkBaryWeightStatistics();
  ~vtkBaryWeightStatistics() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* WeightsArrayName = nullptr;
  char* FaceWeightsArrayName = nullptr;
  double Threshold = -1.0;
  int CageDimension = 0;

private:
  vtkBaryWeightStatistics(const vtkBaryWeightStatistics&) = delete;
  void operator=(const vtkBaryWeightStatistics&) = delete;
};

#endif
