#pragma once
/// @file barylabViewerScene.h
/// What the viewer draws: the model at its current pose coloured by one control point's weight
/// (or by the norm of its gradient, vtkGradientFilter), linear or logarithmic colour scale,
/// level sets including the influence threshold 10^-3/n, an optional clipping plane (3D: a
/// tetrahedral model is sliced, its cut face showing the field inside), and
/// the controls (cage, skeleton or free points) with the selected one highlighted. Display
/// code only; the weights come from barylab::ComputeWeights.

#include "vtkSmartPointer.h"

#include <string>

class vtkDataSet;
class vtkImageData;
class vtkPoints;
class vtkPolyData;
class vtkRenderer;

namespace barylab
{
namespace viewer
{

/// How the controls are drawn and what a weights component means.
enum class ControlKind
{
  Cage,       ///< a cage: component i = cage point i; wireframe + spheres
  Skeleton,   ///< BBW skeleton: components are point handles, then bones; joints are dragged
  FreePoints  ///< free control points (celestial coordinates): spheres only
};

struct SceneOptions
{
  enum class Field
  {
    Weight,      ///< the weight of the selected component
    GradientNorm, ///< |grad w| of the selected component (on the rest geometry)
    Image         ///< 2D image mode: the model drawn with SceneOptions::texture (warped)
  };
  Field field = Field::Weight;
  int component = 0;           ///< selected weights component
  bool log_scale = false;      ///< logarithmic colour scale (values <= 0 drawn grey)
  int isolines = 9;            ///< evenly spaced level sets (decades on a log scale); 0 = none
  bool influence_level = true; ///< the level set w = 10^-3 / n (n = number of components)
  bool show_controls = true;
  bool clip = false;           ///< clip by a plane normal to clip_axis (3D models)
  int clip_axis = 0;           ///< 0 x, 1 y, 2 z
  double clip_position = 0.5;  ///< plane position as a fraction of the bounds along the axis
  std::string title;
  std::string weights_name = "Weights";
  ControlKind controls = ControlKind::Cage;
  /// 2D image mode: the picture the model carries as a texture (its texture coordinates come
  /// from TexturedCageMesh); drawn with Field::Image.
  vtkSmartPointer<vtkImageData> texture;
  int dimension = 3;           ///< 2: orthographic view from +z
};

/// What the scene shows, for the window and the tests.
struct SceneInfo
{
  double range[2] = { 0.0, 1.0 }; ///< colour range of the shown field
  double influence_level = 0.0;   ///< 10^-3 / n
  long long shown_points = 0;     ///< points of the drawn model (after clipping)
  /// true when the clipping plane cut a volume (tetrahedral) model: the cut face shows the
  /// field inside, interpolated in the cells (a surface model is only cut open)
  bool sliced_volume = false;
  int components = 0;
};

/// Reads a picture (PNG, JPEG, BMP, TIFF, PNM) for the 2D image mode.
/// @throws bary::Error(Io) naming the file when it cannot be read.
vtkSmartPointer<vtkImageData> ReadPicture(const std::string& path);

/// True for the file suffixes ReadPicture reads.
bool IsPictureFile(const std::string& path);

/// The model of the 2D image mode: the interior of the polygon @p cage meshed (about
/// @p target_cells triangles, barylab::MeshCage) with texture coordinates ("TextureCoordinates",
/// the active TCoords) that place @p picture over the cage: the picture covers the cage's
/// bounding box enlarged by 5% on each side, centred, its aspect ratio kept (the larger side
/// fits). Moving the cage then warps the picture with the deformation (the LBC paper's
/// gecko/logo examples are this).
/// @throws bary::Error from the meshing (open / self-intersecting cage), or InvalidArgument for
///   a 3D cage or an empty picture.
vtkSmartPointer<vtkDataSet> TexturedCageMesh(vtkPolyData* cage, vtkImageData* picture,
  int target_cells = 4000);

/// Fills @p renderer (cleared first) with the scene.
/// @param weighted the model at rest carrying the weights array (ComputeWeights' output)
/// @param posed_points the model's points at the current pose (same ids), or null for rest
/// @param controls the rest controls (cage / skeleton / control points) as read
/// @param posed_controls the controls' points at the current pose, or null for rest
/// @throws bary::Error(InvalidArgument) for a component that does not exist
SceneInfo BuildScene(vtkRenderer* renderer, vtkDataSet* weighted, vtkPoints* posed_points,
  vtkPolyData* controls, vtkPoints* posed_controls, const SceneOptions& options);

/// 2D: orthographic from +z; 3D: a perspective view of the whole scene.
void ResetSceneCamera(vtkRenderer* renderer, int dimension);

} // namespace viewer
} // namespace barylab
