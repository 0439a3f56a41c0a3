/**
 * @class   vtkBaryImageWarp
 * @brief   Warps an image by a displacement field: the moving image resampled at T^-1(y).
 *
 * Input 0: the moving image (vtkImageData, one-component point scalars of any numeric type: a
 * label map or intensities). Input 1: a displacement field (vtkImageData with a 3-component
 * point array, vtkBaryDisplacementField's output or a field read with vtkBaryImageIO). Optional
 * input 2: the reference image whose grid the output takes (default: the moving image's grid).
 *
 * The output voxel y gets moving(y + v(y)), v the pull-back field (the moving image pulled back,
 * as itk::ResampleImageFilter does with a transform from the output to the input space). With
 * FieldIsInverse on (default) input 1 is v itself: the inverse field of a deformation (what
 * vtkBaryDisplacementField's output 1 and `barylab export-transform --inverse` write). With it
 * off, input 1 is the forward field u of the deformation T(x) = x + u(x) (rest to deformed)
 * and is inverted here first (bary::invert_displacement_field, to InverseTolerance; the voxels
 * that did not converge are counted and a warning says so), so that the moving image, in the
 * rest space, is carried into the deformed space.
 *
 * Interpolation: NEAREST (label maps: every output value is one of the input's) or LINEAR
 * (trilinear; integer types are rounded to the nearest integer and clamped to the type's
 * range). Sampling follows ITK 5.2 (inside iff every continuous index is in [-0.5, n - 0.5),
 * the field's displacement zero outside its grid); output voxels whose point falls outside the
 * moving image get DefaultValue (GetNumberOfOutsideVoxels counts them).
 *
 * Output: a vtkImageData on the output grid (extent from 0, origin, spacing, direction matrix)
 * with the moving scalars' name and type.
 *
 * @sa vtkBaryDisplacementField, bary::warp_image
 */
#ifndef vtkBaryImageWarp_h
#define vtkBaryImageWarp_h

#include "BaryLabMedicalModule.h" // for export macro
#include "vtkImageAlgorithm.h"

class vtkImageData;

class BARYLABMEDICAL_EXPORT vtkBaryImageWarp : public vtkImageAlgorithm
{
public:
  static vtkBaryImageWarp* New();
  vtkTypeMacro(vtkBaryImageWarp, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Interpolations
  {
    NEAREST = 0,
    LINEAR = 1
  };

  ///@{
  /// Inputs 1 (the field) and 2 (optional: the reference grid); input 0 is the moving image.
  void SetFieldData(vtkImageData* field);
  void SetFieldConnection(vtkAlgorithmOutput* output);
  void SetReferenceImageData(vtkImageData* image);
  void SetReferenceImageConnection(vtkAlgorithmOutput* output);
  ///@}

  ///@{
  /// NEAREST or LINEAR (default).
  vtkSetClampMacro(Interpolation, int, NEAREST, LINEAR);
  vtkGetMacro(Interpolation, int);
  void SetInterpolationToNearest() { this->SetInterpolation(NEAREST); }
  void SetInterpolationToLinear() { this->SetInterpolation(LINEAR); }
  ///@}

  ///@{
  /// Input 1 is the pull-back (inverse) field (default on), or the forward field (off).
  vtkSetMacro(FieldIsInverse, bool);
  vtkGetMacro(FieldIsInverse, bool);
  vtkBooleanMacro(FieldIsInverse, bool);
  ///@}

  ///@{
  /// The value of output voxels outside the moving image. Default 0.
  vtkSetMacro(DefaultValue, double);
  vtkGetMacro(DefaultValue, double);
  ///@}

  ///@{
  /// The field's array (default: its point vectors, else 3-component scalars).
  vtkSetStringMacro(DisplacementArrayName);
  vtkGetStringMacro(DisplacementArrayName);
  ///@}

  ///@{
  /// With FieldIsInverse off: the inverse's tolerance (0: 1e-4 times the smallest spacing) and
  /// iterations per voxel at most (default 200).
  vtkSetClampMacro(InverseTolerance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(InverseTolerance, double);
  vtkSetClampMacro(InverseMaximumIterations, int, 1, 100000);
  vtkGetMacro(InverseMaximumIterations, int);
  ///@}

  ///@{
  /// Threads (0: all cores). The result does not depend on it.
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  /// @name Figures of the last execution
  ///@{
  vtkGetMacro(NumberOfOutsideVoxels, vtkIdType);
  vtkGetMacro(InverseMaximumResidual, double);
  vtkGetMacro(InverseMeanResidual, double);
  vtkGetMacro(InverseNotConverged, vtkIdType);
  vtkGetMacro(InverseNotConvergedAtBorder, vtkIdType);
  ///@}

protected:
  vtkBaryImageWarp();
  ~vtkBaryImageWarp() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Interpolation = LINEAR;
  bool FieldIsInverse = true;
  double DefaultValue = 0.0;
  char* DisplacementArrayName = nullptr;
  double InverseTolerance = 0.0;
  int InverseMaximumIterations = 200;
  int NumberOfThreads = 0;

  vtkIdType NumberOfOutsideVoxels = 0;
  double InverseMaximumResidual = 0.0;
  double InverseMeanResidual = 0.0;
  vtkIdType InverseNotConverged = 0;
  vtkIdType InverseNotConvergedAtBorder = 0;

private:
  vtkBaryImageWarp(const vtkBaryImageWarp&) = delete;
  void operator=(const vtkBaryImageWarp&) = delete;
};

#endif
