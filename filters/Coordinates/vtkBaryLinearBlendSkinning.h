/**
 * @class   vtkBaryLinearBlendSkinning
 * @brief   Deforms points by linear blend skinning: x' = sum_j w_j(x) (A_j x + t_j).
 *
 * Eq. (1) of Jacobson et al. 2011 ("Bounded biharmonic weights"). Input 0: a vtkPointSet whose
 * point data hold the weights (array WeightsArrayName, one component per handle, e.g. from
 * vtkBaryCoordinates with Method BBW). The handles' transforms are a vtkDoubleArray with one
 * tuple per handle and 12 components: the 3 x 4 affine matrix [A | t] in row-major order
 * (a00 a01 a02 t0 a10 a11 a12 t1 a20 a21 a22 t2). 2D data use it as well (z = const planes stay
 * put under transforms whose third row is [0 0 1 0]). Output: a copy of the input with moved
 * points (all arrays kept). Points whose weights are NaN (outside the domain under the NaN
 * policy) are an error: their deformed position is undefined.
 *
 * With weights that sum to 1, the same transform on every handle moves every point by exactly
 * that transform. Cost: O(#P x #handles), parallel over points (results do not depend on the
 * thread count).
 *
 * @sa vtkBaryCoordinates, bary::linear_blend_skinning, bary::forward_kinematics
 */
#ifndef vtkBaryLinearBlendSkinning_h
#define vtkBaryLinearBlendSkinning_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkPointSetAlgorithm.h"

#ifndef __VTK_WRAP__
#include <Eigen/Core> // for Eigen::MatrixXd
#include <vector>     // for std::vector
#endif

class vtkDoubleArray;
class vtkPointSet;
class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryLinearBlendSkinning : public vtkPointSetAlgorithm
{
public:
  static vtkBaryLinearBlendSkinning* New();
  vtkTypeMacro(vtkBaryLinearBlendSkinning, vtkPointSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// One tuple per handle, 12 components ([A | t] row-major). Required.
  virtual void SetTransforms(vtkDoubleArray* transforms);
  vtkGetObjectMacro(Transforms, vtkDoubleArray);
  ///@}

  ///@{
  /// Name of the input's weights array. Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  ///@}

  ///@{
  /// Threads; 0 (default) = all cores.
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

#ifndef __VTK_WRAP__
  /**
   * The pose of the handles @p handles (a skeleton of points and lines, or mixed handles with
   * cage faces and regions: vtkBaryMixedHandles::ToHandles) whose joints moved to
   * @p posedJoints (same points, same order): one 3 x 4 transform [A | t] per handle in the
   * weights' column order (bary::transforms_from_joints: bones rigid, cage vertices translated
   * by their displacement, regions by their best rigid fit; 2D transforms lifted to 3 x 4).
   * @p pseudoEdges (#E by 2 indices into the point handles, optional) give point handles their
   * rotations.
   * @throws bary::Error
   */
  static std::vector<Eigen::MatrixXd> PoseFromJoints(vtkPolyData* handles,
    vtkPointSet* posedJoints, int dimension,
    const Eigen::MatrixXi& pseudoEdges = Eigen::MatrixXi());
#endif

  /// Includes the transforms' modification time.
  vtkMTimeType GetMTime() override;

protected:
  vtkBaryLinearBlendSkinning();
  ~vtkBaryLinearBlendSkinning() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkDoubleArray* Transforms = nullptr;
  char* WeightsArrayName = nullptr;
  int NumberOfThreads = 0;

private:
  vtkBaryLinearBlendSkinning(const vtkBaryLinearBlendSkinning&) = delete;
  void operator=(const vtkBaryLinearBlendSkinning&) = delete;
};

#endif
