/**
 * @class   vtkBaryCageDeformation
 * @brief   Deforms a point set by moving the control points of a cage.
 *
 * x'_p = sum_i w_i(x_p) c'_i, with w the generalized barycentric coordinates of the rest pose.
 * Celestial methods (T_CELESTIAL, S_CELESTIAL) take free control points as the rest "cage" (any
 * points, cells ignored) and the moved control points as the deformed one.
 * Method BBW (cage handles) has no linear precision, so it blends displacements instead:
 * x'_p = x_p + sum_i w_i(x_p) (c'_i - c_i) (linear blend skinning with the cage vertices'
 * translations, as Jacobson et al. 2011 deform with cages); the rest cage then reproduces the
 * model exactly and a translated cage translates it.
 *
 * Green coordinates (GREEN, Lipman et al. 2008) deform with the vertex weights phi and the
 * face coefficients psi: x'_p = sum_i phi_i(x_p) c'_i + sum_j psi_j(x_p) s_j n(t'_j), with n(t'_j)
 * the unit normal of the deformed face (2D: edge) j and s_j its stretch (bary::
 * deform_points_green): conformal in 2D, quasi-conformal in 3D, exact under similarities of the
 * cage. The model's arrays WeightsArrayName and FaceWeightsArrayName (both from
 * vtkBaryCoordinates with GREEN) are used when both are present with the right component
 * counts; otherwise both are computed and cached. Compact (reduced) weights cannot carry them
 * and are refused with GREEN.
 *
 * Input 0: the model (any vtkPointSet). Input 1: the rest cage (vtkPolyData, as in
 * vtkBaryCoordinates). Input 2: the deformed cage: a vtkPointSet with the same number of points
 * as the rest cage, in the same order (its cells, if any, are ignored).
 *
 * Weights: if UseInputWeights is on and the model carries a point-data array named
 * WeightsArrayName with one component per cage point, those weights are used. Otherwise they
 * are computed with the WeightMethod and cached; the cache is keyed on the *content* of the rest
 * cage (points and cells), of the model's points and on the method's settings hash — not on counts or
 * modification times — so a new rest cage or model always recomputes, and moving only the
 * deformed cage (the interactive case) never does.
 *
 * Compact (reduced) weights: when the model has no array WeightsArrayName but carries the pair
 * `<WeightsArrayName>Indices` / `<WeightsArrayName>Values` written by vtkBaryReduceWeights
 * (and UseInputWeights is on), those are used, for every method (BBW blends displacements as
 * above): a sparse product, O(K) per point instead of O(#controls). The indices must lie in
 * [-1, #cage points) (-1 = padding) and the values be finite; field data
 * `<WeightsArrayName>NumberOfControlPoints`, when present, must equal the cage's point count.
 * The output then carries the compact pair (no dense array is added).
 *
 * Output: a copy of the model with moved points; with PassWeights (default on) the weights array
 * is added too (with it off, a weights array the model already carried is still passed, like
 * every other input array). For a 2D cage the z coordinate of every model point is kept.
 * Weights read from the model must be finite; computed weights may hold NaN rows for points far
 * outside the cage (a warning says so, and those points come out as NaN).
 *
 * @sa vtkBaryCoordinates
 */
#ifndef vtkBaryCageDeformation_h
#define vtkBaryCageDeformation_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkBaryWeightMethod.h" // for the methods and their settings
#include "vtkPointSetAlgorithm.h"

#include <memory> // for std::unique_ptr

class vtkDataArray;
class vtkPointSet;
class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryCageDeformation : public vtkPointSetAlgorithm
{
public:
  static vtkBaryCageDeformation* New();
  vtkTypeMacro(vtkBaryCageDeformation, vtkPointSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The weight method and all its settings (see vtkBaryWeightMethod); may be shared with a
  /// vtkBaryCoordinates. A new vtkBaryWeightMethod (mean value coordinates) by default; never
  /// nullptr.
  virtual void SetWeightMethod(vtkBaryWeightMethod* method);
  vtkGetObjectMacro(WeightMethod, vtkBaryWeightMethod);
  ///@}

  /// Includes the weight method's modification time (a setting changed on a shared method
  /// re-executes the filter).
  vtkMTimeType GetMTime() override;

  ///@{
  /// Weights array read from the model (with UseInputWeights) and written to the output (with
  /// PassWeights). Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  ///@}

  ///@{
  /// Face coefficients array (GREEN only: psi, one component per cage face or 2D edge) read from
  /// the model with UseInputWeights and written with PassWeights. Default "FaceWeights".
  vtkSetStringMacro(FaceWeightsArrayName);
  vtkGetStringMacro(FaceWeightsArrayName);
  ///@}

  ///@{
  /// Use weights stored on the model when present. Default on.
  vtkSetMacro(UseInputWeights, bool);
  vtkGetMacro(UseInputWeights, bool);
  vtkBooleanMacro(UseInputWeights, bool);
  ///@}

  ///@{
  /// Add the weights to the output. Default on.
  vtkSetMacro(PassWeights, bool);
  vtkGetMacro(PassWeights, bool);
  vtkBooleanMacro(PassWeights, bool);
  ///@}

  ///@{
  /// Inputs 1 and 2.
  void SetRestCageData(vtkPolyData* cage);
  void SetRestCageConnection(vtkAlgorithmOutput* output);
  void SetDeformedCageData(vtkPointSet* cage);
  void SetDeformedCageConnection(vtkAlgorithmOutput* output);
  ///@}

  /// How many times weights were computed (not taken from the cache or the input) since
  /// construction. For tests and for users who want to see the cache work.
  vtkGetMacro(NumberOfWeightComputations, vtkIdType);

  /// Drop the cached weights.
  void ClearCache();

protected:
  vtkBaryCageDeformation();
  ~vtkBaryCageDeformation() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkBaryWeightMethod* WeightMethod = nullptr;
  char* WeightsArrayName = nullptr;
  char* FaceWeightsArrayName = nullptr;
  bool UseInputWeights = true;
  bool PassWeights = true;
  vtkIdType NumberOfWeightComputations = 0;

private:
  vtkBaryCageDeformation(const vtkBaryCageDeformation&) = delete;
  void operator=(const vtkBaryCageDeformation&) = delete;

  struct Cache;
  std::unique_ptr<Cache> WeightCache;
};

#endif
