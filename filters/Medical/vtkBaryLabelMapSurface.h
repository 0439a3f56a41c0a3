/**
 * @class   vtkBaryLabelMapSurface
 * @brief   The closed, smooth, manifold surface of one label of a label map, in the image's
 *          physical (LPS) coordinates.
 *
 * Input: a vtkImageData with one-component point scalars (a label map, e.g. from
 * vtkBaryImageIO::Read) and its origin, spacing and direction matrix. Output: a vtkPolyData of
 * triangles, oriented outward, that passed BaryLab's cage validation (bary::validate_cage:
 * closed, every edge shared by two faces, consistently oriented, vertex-manifold, no degenerate
 * face, no self-intersection, by exact predicates): usable as a model, and as a cage.
 *
 * Steps:
 * 1. The label: Label when not 0, otherwise the only non-zero value of the image (an image
 *    with several needs Label). Floating-point images are accepted when every value is an
 *    integer (label maps saved as float); other images need UseThreshold: the object is then
 *    every voxel whose value is >= Threshold.
 * 2. The label's voxels, cropped to their bounding box and padded with one voxel of background
 *    on every side, so the surface closes also where the label touches the image's border (the
 *    field of view cut the organ: reported by GetTouchesBorder()).
 * 3. vtkDiscreteFlyingEdges3D in index · spacing coordinates (no direction: VTK 9.1's filters
 *    do not all honour vtkImageData's direction matrix).
 * 4. The largest connected piece (by triangles) is kept; the others (islands, the inner wall
 *    of a cavity) are dropped and counted (GetNumberOfDroppedComponents()).
 * 5. Smoothing: vtkWindowedSincPolyDataFilter, SmoothingIterations iterations (0: none), pass
 *    band SmoothingPassBand, normalised coordinates (the result does not depend on the scale).
 * 6. Decimation: vtkDecimatePro with PreserveTopology (no holes, no splitting) to
 *    TargetNumberOfFaces, or by TargetReduction when TargetNumberOfFaces is 0 (neither: none).
 *    A topology-preserving decimation may stop above the target.
 * 7. The points are mapped to physical space explicitly, x = origin + D · p (D the direction
 *    matrix), which is also right for a non-orthogonal (sheared) but invertible D; a singular
 *    or non-finite D, spacing or origin is refused.
 * 8. Oriented outward (positive enclosed volume; a direction with negative determinant mirrors
 *    the triangles, which are then flipped) and validated. VTK's decimations keep the topology
 *    of most surfaces but not of all (vtkDecimatePro with PreserveTopology once left an edge
 *    shared by four triangles), and smoothing can make close sheets cross: a surface that fails
 *    is replaced by the next candidate, in this order: vtkDecimatePro; vtkQuadricDecimation
 *    (volume preserving); both at twice the target triangles (half the reduction); no
 *    decimation; then the same without smoothing. What was used is reported
 *    (GetSmoothingIterationsUsed, GetDecimationUsed, GetNumberOfAttempts, GetFirstFailure); when
 *    no candidate passes, the filter fails with the first one's reason. An invalid surface is
 *    never output.
 *
 * Reported after an update: the label used, its voxels, its volume (voxels times the voxel
 * volume |det D| sx sy sz), the surface's enclosed volume, dropped components, whether the label
 * touches the border.
 *
 * Errors (vtkErrorMacro; the error code is the bary::ErrorCode's, vtkBaryConversion::ErrorCodeOf):
 * no scalars or several components, an empty label or image without a non-zero label (the
 * message lists the labels present with their voxel counts), several labels and no Label,
 * non-integer values without UseThreshold, a singular / non-finite geometry, a surface that
 * fails validation.
 */
#ifndef vtkBaryLabelMapSurface_h
#define vtkBaryLabelMapSurface_h

#include "BaryLabMedicalModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class BARYLABMEDICAL_EXPORT vtkBaryLabelMapSurface : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryLabelMapSurface* New();
  vtkTypeMacro(vtkBaryLabelMapSurface, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The label value to extract; 0 (default): the only non-zero label of the image.
  vtkSetMacro(Label, long long);
  vtkGetMacro(Label, long long);
  ///@}

  ///@{
  /// Segment by threshold instead of by label: the object is every voxel >= Threshold (any
  /// image type). Default off.
  vtkSetMacro(UseThreshold, bool);
  vtkGetMacro(UseThreshold, bool);
  vtkBooleanMacro(UseThreshold, bool);
  vtkSetMacro(Threshold, double);
  vtkGetMacro(Threshold, double);
  ///@}

  ///@{
  /// Windowed-sinc smoothing iterations, [0, 1000]; 0 disables smoothing. Default 20.
  vtkSetClampMacro(SmoothingIterations, int, 0, 1000);
  vtkGetMacro(SmoothingIterations, int);
  ///@}

  ///@{
  /// The smoothing's pass band, (0, 2]: smaller is smoother. Default 0.01.
  vtkSetClampMacro(SmoothingPassBand, double, 1e-6, 2.0);
  vtkGetMacro(SmoothingPassBand, double);
  ///@}

  ///@{
  /// Decimate to about this many triangles (0: use TargetReduction). Default 5000.
  vtkSetClampMacro(TargetNumberOfFaces, int, 0, VTK_INT_MAX);
  vtkGetMacro(TargetNumberOfFaces, int);
  ///@}

  ///@{
  /// Fraction of the triangles to remove, [0, 0.99], when TargetNumberOfFaces is 0. Default 0.
  vtkSetClampMacro(TargetReduction, double, 0.0, 0.99);
  vtkGetMacro(TargetReduction, double);
  ///@}

  ///@{
  /// Results of the last update.
  vtkGetMacro(LabelUsed, long long);
  vtkGetMacro(NumberOfLabelVoxels, vtkIdType);
  /// voxels x |det D| sx sy sz, in the image's units cubed (mm^3)
  vtkGetMacro(LabelVolume, double);
  /// volume enclosed by the output surface
  vtkGetMacro(EnclosedVolume, double);
  /// triangles of the surface before smoothing and decimation (the largest piece)
  vtkGetMacro(NumberOfExtractedFaces, vtkIdType);
  vtkGetMacro(NumberOfDroppedComponents, int);
  /// true when the label has voxels on the image's boundary (the field of view cut it; the
  /// surface is closed by the padding there)
  vtkGetMacro(TouchesBorder, bool);
  /// the smoothing iterations and decimation ("decimate-pro", "quadric", "none") of the
  /// surface output: those asked for unless a surface failed validation (step 8)
  vtkGetMacro(SmoothingIterationsUsed, int);
  const char* GetDecimationUsed() const { return this->DecimationUsed; }
  /// surfaces made until one passed validation (1: the first did)
  vtkGetMacro(NumberOfAttempts, int);
  /// why the first surface failed validation ("" when it passed)
  const char* GetFirstFailure() const { return this->FirstFailure.c_str(); }
  ///@}

protected:
  vtkBaryLabelMapSurface();
  ~vtkBaryLabelMapSurface() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  long long Label = 0;
  bool UseThreshold = false;
  double Threshold = 0.0;
  int SmoothingIterations = 20;
  double SmoothingPassBand = 0.01;
  int TargetNumberOfFaces = 5000;
  double TargetReduction = 0.0;

  long long LabelUsed = 0;
  vtkIdType NumberOfLabelVoxels = 0;
  double LabelVolume = 0.0;
  double EnclosedVolume = 0.0;
  vtkIdType NumberOfExtractedFaces = 0;
  int NumberOfDroppedComponents = 0;
  bool TouchesBorder = false;
  int SmoothingIterationsUsed = 0;
  const char* DecimationUsed = "none";
  int NumberOfAttempts = 0;
  std::string FirstFailure;

private:
  vtkBaryLabelMapSurface(const vtkBaryLabelMapSurface&) = delete;
  void operator=(const vtkBaryLabelMapSurface&) = delete;
};

#endif
