/**
 * @class   vtkBaryLocalityStatistics
 * @brief   How local a weight field is: P(t), Q(k) and per-control influence as tables.
 *
 * The locality statistics of Zhang et al., "Local barycentric coordinates", ACM TOG 33(6),
 * 2014, §5 (Eq. 19-21, Fig. 14-15), of the weights stored on any data set (one point-data
 * array, one component per control point, e.g. written by vtkBaryCoordinates), computed by
 * bary::locality_statistics (core/analysis/locality_statistics.h):
 *
 * - P(t) (Eq. 19-20): the fraction of the domain where |w_i| <= t, averaged over the control
 *   points. Large P at small t: each control point influences a small region.
 * - Q(k) (Eq. 21): the fraction of the domain where at least k weights exceed the threshold
 *   of negligible influence (10^-3 / #controls by default, §3.2). Q(1) = 1 wherever the
 *   weights sum to one; Q is non-increasing; sum_k Q(k) is the mean support.
 * - the influence fraction of control point i: the fraction of the domain where w_i > threshold.
 *
 * "Fraction of the domain": with UseMeshMeasure on (default) and an input whose cells include
 * simplices of the domain's dimension — tetrahedra (3D), or triangles lying in a plane
 * z = const (2D) — each point counts with its lumped volume/area (bary::vertex_measures over
 * those simplices; other cells are ignored and points on no simplex count 0). Otherwise (a
 * point cloud, a curved triangle surface, polylines, or UseMeshMeasure off) every point counts
 * the same. GetMeasureUsed() says which was used.
 *
 * Input 0: any vtkDataSet carrying the point-data array WeightsArrayName.
 *
 * Outputs (vtkTable each; the viewer's P/Q charts read exactly these columns):
 * - port 0: P(t), columns "t" (vtkDoubleArray, ascending) and "P" (vtkDoubleArray, in [0, 1]),
 *   one row per t value (by default 0 and 10^(-6 + j/4), j = 0..24: 26 rows);
 * - port 1: Q(k), columns "k" (vtkIntArray, 1 .. #controls) and "Q" (vtkDoubleArray, in
 *   [0, 1], non-increasing), one row per k;
 * - port 2: per control point, columns "control" (vtkIntArray, the weights array's component
 *   index) and "influence_fraction" (vtkDoubleArray, in [0, 1]).
 *
 * Errors (vtkErrorMacro, RequestData returns 0, the algorithm's error code holds the
 * bary::ErrorCode): no points, a missing or non-numeric weights array, NaN/inf weights, a
 * threshold of 0.
 *
 * @sa vtkBaryReduceWeights vtkBaryCoordinates
 */
#ifndef vtkBaryLocalityStatistics_h
#define vtkBaryLocalityStatistics_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkTableAlgorithm.h"

class vtkDoubleArray;
class vtkTable;

class BARYLABFILTERS_EXPORT vtkBaryLocalityStatistics : public vtkTableAlgorithm
{
public:
  static vtkBaryLocalityStatistics* New();
  vtkTypeMacro(vtkBaryLocalityStatistics, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// What "fraction of the domain" was measured with (GetMeasureUsed).
  enum MeasureTypes
  {
    MEASURE_UNIFORM = 0, ///< every point counts the same
    MEASURE_AREA = 2,    ///< lumped triangle areas (2D domain mesh)
    MEASURE_VOLUME = 3   ///< lumped tetrahedron volumes (3D domain mesh)
  };

  ///@{
  /// Name of the point-data weights array. Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  ///@}

  ///@{
  /// Threshold of negligible influence (for Q, the supports and the influence fractions).
  /// Negative (default -1): the paper's 10^-3 / #controls. 0 is an error.
  vtkSetMacro(Threshold, double);
  vtkGetMacro(Threshold, double);
  ///@}

  ///@{
  /// Weight points by their lumped area/volume when the input has simplices of the domain's
  /// dimension (see the class description). Default on.
  vtkSetMacro(UseMeshMeasure, bool);
  vtkGetMacro(UseMeshMeasure, bool);
  vtkBooleanMacro(UseMeshMeasure, bool);
  ///@}

  ///@{
  /// The t values of P(t) (any order; sorted in the output). Null or empty (default): the
  /// default 26 values (bary::default_locality_t).
  virtual void SetTValues(vtkDoubleArray* values);
  vtkGetObjectMacro(TValues, vtkDoubleArray);
  ///@}

  ///@{
  /// Results of the last successful update.
  /// The threshold actually used (the default resolved to 10^-3 / #controls).
  vtkGetMacro(ThresholdUsed, double);
  /// Measure-weighted mean number of weights > threshold per point (= sum_k Q(k)).
  vtkGetMacro(MeanSupport, double);
  /// Largest number of weights > threshold at one point.
  vtkGetMacro(MaxSupport, double);
  /// MEASURE_UNIFORM, MEASURE_AREA or MEASURE_VOLUME.
  vtkGetMacro(MeasureUsed, int);
  /// "uniform", "area" or "volume".
  const char* GetMeasureUsedAsString() const;
  ///@}

  /// Convenience: the output tables (ports 0, 1, 2).
  vtkTable* GetPTable();
  vtkTable* GetQTable();
  vtkTable* GetInfluenceTable();

protected:
  vtkBaryLocalityStatistics();
  ~vtkBaryLocalityStatistics() override;
  vtkMTimeType GetMTime() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* WeightsArrayName = nullptr;
  double Threshold = -1.0;
  bool UseMeshMeasure = true;
  vtkDoubleArray* TValues = nullptr;

  double ThresholdUsed = 0.0;
  double MeanSupport = 0.0;
  double MaxSupport = 0.0;
  int MeasureUsed = MEASURE_UNIFORM;

private:
  vtkBaryLocalityStatistics(const vtkBaryLocalityStatistics&) = delete;
  void operator=(const vtkBaryLocalityStatistics&) = delete;
};

#endif
