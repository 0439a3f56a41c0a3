#pragma once
/// @file barylabRender.h
/// Rendering of weight fields and deformations, shared by the command line (PNG output), the
/// viewer and the regression image tests. Fixed size, camera and background; no multisampling,
/// so images are reproducible. Needs an X display (Xvfb in headless runs).

#include "vtkSmartPointer.h"

#include <Eigen/Core>

#include <string>
#include <vector>

class vtkCellArray;
class vtkDataSet;
class vtkPoints;
class vtkPointSet;
class vtkImageData;
class vtkPolyData;
class vtkRenderWindow;
class vtkRenderer;
class vtkUnstructuredGrid;

namespace barylab
{

struct RenderOptions
{
  int width = 900;
  int height = 700;
  int component = 0;        ///< which control point's weight to show
  int isolines = 9;         ///< isolines evenly spaced in (0, max w) (0 = none), plus w = 0 if negative
  /// Extra level sets of the weight, drawn as thick blue lines (vtkContourFilter), e.g. the
  /// influence level 1e-3 / #controls of local weights (the LBC paper's Fig. 4). Default none.
  std::vector<double> levels;
  /// Also draw the influence level 1e-3 / #controls (#controls = the weights' components), the
  /// threshold of the significant-weight statistics. Default off.
  bool influence_level = false;
  bool show_cage = true;
  bool offscreen = true;
  std::string title;        ///< text in the upper-left corner
  std::string weights_name = "Weights";
  int cage_dimension = 0;   ///< 0 automatic
  /// The "cage" arguments are BBW skeleton handles (points and lines, see
  /// vtkBaryConversion::ToSkeleton): bones are drawn as thick lines, joints as spheres, and
  /// the selected handle (options.component: point handles first, then bones) in red.
  bool skeleton = false;
  /// The "cage" arguments are free control points (celestial coordinates): drawn as spheres
  /// only, options.component in red.
  bool free_points = false;
};

/// The weight of control point options.component over @p data (which carries the weights
/// array), as a colour map with isolines, the cage as a wireframe with its control points and
/// the selected one highlighted, and a colour bar.
vtkSmartPointer<vtkRenderWindow> WeightFieldWindow(
  vtkDataSet* data, vtkPolyData* cage, const RenderOptions& options);

/// A deep copy of vtkBarySurfaceWeights' output with the weights array @p name set to NaN where
/// they mean nothing (Panozzo et al. 2013, §4.4: the round trip does not return — `Defined` 0 —
/// or a weight is below -1, the paper's "large negative weights"): what is drawn of them here
/// and in the viewer. @throws bary::Error(InvalidArgument) without the arrays.
vtkSmartPointer<vtkPolyData> MeaningfulSurfaceWeights(vtkPolyData* weighted, const std::string& name);

/// Weights on a surface w.r.t. anchors (vtkBarySurfaceWeights' output: `Weights`, `Defined`):
/// the weight of anchor options.component as WeightFieldWindow draws it, but only where the
/// weights mean something (Panozzo et al. 2013, §4.4: the round trip returns and no weight is
/// below -1, the paper's "large negative weights"); the rest is left uncoloured (NaN colour).
/// @p curve (optional): polylines drawn over it in yellow (a B-spline on the surface).
vtkSmartPointer<vtkRenderWindow> SurfaceWeightsWindow(vtkPolyData* weighted, vtkPointSet* anchors,
  vtkPolyData* curve, const RenderOptions& options);

/// Rest pose (left) and deformed pose (right) side by side, each with its cage; both coloured
/// by the weight of options.component when the data carry the weights array.
vtkSmartPointer<vtkRenderWindow> DeformationWindow(vtkDataSet* rest, vtkPolyData* rest_cage,
  vtkDataSet* deformed, vtkPointSet* posed_cage, const RenderOptions& options);

/// The edges of a spline grid (vtkBarySplineData) as the spline draws them: every domain edge
/// sampled at @p samples + 1 points and mapped by the xy deformation (curved), as polylines at
/// height @p z. Cell data `Border` (1 on the domain's border).
vtkSmartPointer<vtkPolyData> SplineGridLines(vtkUnstructuredGrid* grid, int samples = 16, double z = 0.0);
/// A spline deformation drawn from above (Rodrigues et al. 2014, §5): the rest pose (top) and the
/// deformed one (bottom), each over the picture @p picture_png (optional, "" for none; placed on
/// the domain's bounding rectangle), with the grid's curved edges, the model (@p rest_model,
/// @p model; optional) coloured by height, and triangles where the deformation folds
/// (TriangularSpline::check_jacobian) filled red.
vtkSmartPointer<vtkRenderWindow> SplineDeformationWindow(vtkUnstructuredGrid* rest_grid,
  vtkUnstructuredGrid* grid, vtkPointSet* rest_model, vtkPointSet* model,
  const std::string& picture_png, const RenderOptions& options);
/// A picture deformed by a spline (2D): @p picture_png placed on the rectangle @p bounds
/// (xmin, xmax, ymin, ymax) and drawn on the spline's domain, each domain triangle cut into
/// 12 x 12 small ones whose corners are mapped by the xy deformation (texture coordinates from
/// their rest positions): the rest picture (left) and the deformed one (right), with the grid's
/// curved edges and folds in red.
vtkSmartPointer<vtkRenderWindow> SplinePictureWindow(vtkUnstructuredGrid* rest_grid,
  vtkUnstructuredGrid* grid, const std::string& picture_png, const double bounds[4],
  const RenderOptions& options);
/// A slice of a label map before and after a warp, side by side: the plane through @p center
/// normal to the image's second axis (coronal for an axial LPS image, seen from the front with
/// the head up: the patient's right on the left, as radiologists show it), each voxel a flat
/// cell coloured by its label (0 clear, 1 organ, 2 lesion, others by a categorical map), with the
/// cut of a surface by the same plane drawn over it: @p rest_surface on @p before, the directly
/// deformed @p deformed_surface on @p after, so that where the warp and the deformation agree
/// the line follows the warped label's edge. @p after may be on another grid than @p before.
vtkSmartPointer<vtkRenderWindow> LabelSliceWindow(vtkImageData* before, vtkImageData* after,
  vtkPolyData* rest_surface, vtkPolyData* deformed_surface, const double center[3],
  const RenderOptions& options);

/// The joints of skeleton @p handles moved by @p pose (one 3 x 4 [A | t] per handle, point
/// handles first, then bones): a point handle's joint by its transform, any other joint by the
/// first bone ending there (else starting there). For drawing posed skeletons.
vtkSmartPointer<vtkPolyData> PoseHandles(vtkPolyData* handles, const std::vector<Eigen::MatrixXd>& pose);

/// Renders @p window and writes it as PNG to @p path (atomically). Throws bary::Error(Io).
void WritePNG(vtkRenderWindow* window, const std::string& path);

/// One sphere of @p radius at each of @p points (one glyph actor), in colour @p rgb: how cages'
/// and free control points are drawn here and in the viewer.
void AddSpheres(vtkRenderer* renderer, vtkPoints* points, double radius, const double rgb[3]);

/// @p lines over @p points as one actor of line width @p width and colour @p rgb: how
/// skeletons' bones are drawn here and cages' and skeletons' wires in the viewer.
void AddLines(vtkRenderer* renderer, vtkPoints* points, vtkCellArray* lines, double width,
  const double rgb[3]);

/// True if an X display is available (DISPLAY is set); rendering needs one.
bool HasDisplay();

} // namespace barylab
