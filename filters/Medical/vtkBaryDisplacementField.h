/**
 * @class   vtkBaryDisplacementField
 * @brief   Samples a cage deformation on a regular grid: a displacement field (and optionally
 *          its inverse) that ITK and 3D Slicer apply as a grid transform.
 *
 * The field is u(x) = T(x) - x at each voxel x of the grid, with T the deformation of
 * vtkBaryCageDeformation (the rest cage on input 0 moved to the deformed cage on input 1, with the
 * WeightMethod and its settings, any method). The forward transform T(x) = x + u(x) maps the rest
 * space to the deformed space; to resample an image into the deformed space, ITK and Slicer need
 * the inverse (ComputeInverse). Coordinates are taken as they are: BaryLab's physical space is
 * LPS in millimetres (docs/organ-workflow.md); converting a field to RAS is the caller's
 * (vtkBaryDisplacementField::SwapLPSRAS).
 *
 * The grid: the reference image on input 2 when one is connected (its extent, origin, spacing
 * and direction matrix), otherwise Bounds (axis-aligned, physical) and Spacing (identity
 * direction): voxel centres from the lower bounds on, the last at or beyond the upper bounds
 * (bary::grid_from_bounds). One of the two is required.
 *
 * Where the method is not defined: mean value and Green coordinates are defined everywhere
 * (outside the cage too), and are evaluated at every voxel, BlockSize voxels at a time (the
 * weights of one block at a time, so the memory does not grow with the grid). The celestial
 * methods (tcc, scc) are evaluated the same way, their hull points (CelestialHullPoints:
 * auto, always, none) decided and placed from the grid's 8 corners and the controls, the same
 * for every block (the grid is the convex hull of its corners, so auto adds them exactly when
 * some voxel needs them); with none, voxels outside the controls' hull are an error. The
 * mesh-based methods (harmonic, bbw, lbc) are computed once at the vertices of a mesh of the
 * cage (vtkBaryCageMesher with the method's cell settings, weights on that mesh as the given
 * domain), the displacements of its vertices interpolated linearly at the voxels inside the
 * cage (the methods' own piecewise-linear interpolation, so the field equals the deformation
 * there); a voxel outside the cage gets the displacement of the closest point of the cage
 * (constant extension along the closest-point direction: continuous across the cage, no
 * jump), whatever the method's OutsidePolicy; GetNumberOfOutsideVoxels counts them.
 *
 * Output 0: a vtkImageData on the grid (extent from 0, the grid's origin, spacing and direction
 * matrix) with the 3-component double point-data array DisplacementArrayName ("Displacement"),
 * also its scalars and vectors (vtkBaryImageIO::Write writes the scalars). Field data: "JacobianMinimum", "FoldedVoxels" (det(I + du/dx) <= 0: T folds
 * there and has no inverse), "OutsideVoxels", and with the inverse "InverseMaximumResidual",
 * "InverseMeanResidual", "InverseNotConverged", "InverseNotConvergedAtBorder",
 * "InverseTolerance". Output 1: with ComputeInverse, the inverse field v on the same grid
 * (bary::invert_displacement_field: T^-1(y) = y + v(y), a relaxed fixed-point iteration to
 * InverseTolerance; the voxels that did not converge are counted and a warning says how many),
 * otherwise an empty image.
 *
 * @sa vtkBaryCageDeformation, vtkBaryImageWarp, vtkBaryImageIO
 */
#ifndef vtkBaryDisplacementField_h
#define vtkBaryDisplacementField_h

#include "BaryLabMedicalModule.h" // for export macro
#include "vtkImageAlgorithm.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#ifndef __VTK_WRAP__
#include "core/imaging/displacement_field.h" // for bary::DisplacementField, bary::ImageGrid
#endif

class vtkBaryWeightMethod;
class vtkImageData;
class vtkPointSet;
class vtkPolyData;

class BARYLABMEDICAL_EXPORT vtkBaryDisplacementField : public vtkImageAlgorithm
{
public:
  static vtkBaryDisplacementField* New();
  vtkTypeMacro(vtkBaryDisplacementField, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The weight method and its settings (see vtkBaryWeightMethod); never nullptr.
  virtual void SetWeightMethod(vtkBaryWeightMethod* method);
  vtkGetObjectMacro(WeightMethod, vtkBaryWeightMethod);
  ///@}
  vtkMTimeType GetMTime() override;

  ///@{
  /// Inputs 0 (rest cage), 1 (deformed cage, same points in the same order) and 2 (optional:
  /// the reference image whose grid is sampled).
  void SetRestCageData(vtkPolyData* cage);
  void SetRestCageConnection(vtkAlgorithmOutput* output);
  void SetDeformedCageData(vtkPointSet* cage);
  void SetDeformedCageConnection(vtkAlgorithmOutput* output);
  void SetReferenceImageData(vtkImageData* image);
  void SetReferenceImageConnection(vtkAlgorithmOutput* output);
  ///@}

  ///@{
  /// The grid without a reference image: physical bounds (xmin, xmax, ymin, ymax, zmin, zmax)
  /// and spacing (each > 0). Default: empty bounds (an error without a reference image).
  vtkSetVector6Macro(Bounds, double);
  vtkGetVector6Macro(Bounds, double);
  vtkSetVector3Macro(Spacing, double);
  vtkGetVector3Macro(Spacing, double);
  ///@}

  ///@{
  /// Compute the inverse field (output 1). Default off.
  vtkSetMacro(ComputeInverse, bool);
  vtkGetMacro(ComputeInverse, bool);
  vtkBooleanMacro(ComputeInverse, bool);
  ///@}

  ///@{
  /// The inverse's residual tolerance |x + u(x) - y| (physical units); 0 (default): 1e-4 times
  /// the smallest spacing. And its iterations per voxel at most (default 200).
  vtkSetClampMacro(InverseTolerance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(InverseTolerance, double);
  vtkSetClampMacro(InverseMaximumIterations, int, 1, 100000);
  vtkGetMacro(InverseMaximumIterations, int);
  ///@}

  ///@{
  /// Voxels per block for the methods evaluated per voxel. Default 65536.
  vtkSetClampMacro(BlockSize, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(BlockSize, vtkIdType);
  ///@}

  ///@{
  /// Name of the displacement arrays. Default "Displacement".
  vtkSetStringMacro(DisplacementArrayName);
  vtkGetStringMacro(DisplacementArrayName);
  ///@}

  /// @name Figures of the last execution
  ///@{
  vtkGetMacro(JacobianMinimum, double);
  vtkGetMacro(NumberOfFoldedVoxels, vtkIdType);
  vtkGetMacro(NumberOfOutsideVoxels, vtkIdType);
  vtkGetMacro(InverseMaximumResidual, double);
  vtkGetMacro(InverseMeanResidual, double);
  vtkGetMacro(InverseNotConverged, vtkIdType);
  vtkGetMacro(InverseNotConvergedAtBorder, vtkIdType);
  vtkGetMacro(InverseToleranceUsed, double);
  vtkGetMacro(InverseIterations, int);
  ///@}

#ifndef __VTK_WRAP__
  /// @name Conversions between vtkImageData and core's grids and fields
  ///@{
  /// The grid of @p image (its extent's first voxel as the origin, spacing, direction matrix).
  /// @throws bary::Error(InvalidArgument) for an empty image or an invalid grid.
  static bary::ImageGrid ToGrid(vtkImageData* image);
  /// Sets @p image's extent (from 0), origin, spacing and direction matrix to @p grid's.
  static void SetGrid(vtkImageData* image, const bary::ImageGrid& grid);
  /// The field held by @p image's 3-component point array @p name (the image's point vectors,
  /// then its 3-component scalars when @p name is null or empty).
  /// @throws bary::Error(InvalidArgument) naming what is missing, (NonFinite) for NaN/inf.
  static bary::DisplacementField ToField(vtkImageData* image, const char* name = nullptr);
  /// A new image on @p field's grid with its values as the 3-component double array @p name
  /// (the point scalars and vectors).
  static vtkSmartPointer<vtkImageData> FromField(
    const bary::DisplacementField& field, const char* name = "Displacement");
  /// A field written in LPS converted to RAS (or back: the map is its own inverse): the grid's
  /// origin, the rows of its direction matrix for x and y and the displacements' x and y
  /// negated (the same geometric transform written in the other convention).
  static bary::DisplacementField SwapLPSRAS(const bary::DisplacementField& field);
  ///@}
#endif

protected:
  vtkBaryDisplacementField();
  ~vtkBaryDisplacementField() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkBaryWeightMethod* WeightMethod = nullptr;
  double Bounds[6] = { 0, -1, 0, -1, 0, -1 };
  double Spacing[3] = { 1, 1, 1 };
  bool ComputeInverse = false;
  double InverseTolerance = 0.0;
  int InverseMaximumIterations = 200;
  vtkIdType BlockSize = 65536;
  char* DisplacementArrayName = nullptr;

  double JacobianMinimum = 0.0;
  vtkIdType NumberOfFoldedVoxels = 0;
  vtkIdType NumberOfOutsideVoxels = 0;
  double InverseMaximumResidual = 0.0;
  double InverseMeanResidual = 0.0;
  vtkIdType InverseNotConverged = 0;
  vtkIdType InverseNotConvergedAtBorder = 0;
  double InverseToleranceUsed = 0.0;
  int InverseIterations = 0;

private:
  vtkBaryDisplacementField(const vtkBaryDisplacementField&) = delete;
  void operator=(const vtkBaryDisplacementField&) = delete;

#ifndef __VTK_WRAP__
  /// The grid the parameters and inputs ask for.
  bary::ImageGrid RequestedGrid(vtkInformationVector** inputVector);
#endif
};

#endif
