/**
 * @class   vtkBaryMixedHandles
 * @brief   Mixed handles of bounded biharmonic weights (points, bones, cages, regions) and the
 *          shape-preservation brush, from VTK data.
 *
 * Static helpers only; vtkBaryCoordinates uses them for Method BBW when
 * UsesMixedHandles(handles, domain) (see there).
 *
 * **Handles** (input 1 of vtkBaryCoordinates, a vtkPolyData): the points are the joints; each
 * cell is a handle of the kind its cell-data array "HandleType" gives (any numeric type, one
 * component), or by default its cell type:
 * | HandleType | default for | meaning |
 * |---|---|---|
 * | 0 point | vertex / poly-vertex cells | its points are point handles |
 * | 1 bone | lines / polylines | every segment is a bone |
 * | 2 cage | polygons, triangle strips | cage faces: 2D: the polygon's edges (a closed loop), a polyline's segments (open); 3D: the polygon's triangles (fan), a line's segments |
 * | 3 region | — | a region: 2D: a polygon cell or closed polyline; 3D: triangles; cells with the same cell-data "RegionId" (integer) form one region (without the array, each cell is one) |
 * Every point used by no cell is a point handle too (libigl's .tgf convention: a joint on no
 * bone). Without HandleType and polygons this is exactly vtkBaryConversion::ToSkeleton.
 * Weights columns: point handles (point order), bones (cell, then segment order), cage vertices
 * (ascending point id), regions (ascending RegionId, or cell order), then the domain's vertex
 * regions (ascending HandleRegion value): bary::mixed_bbw_handles.
 *
 * **Domain arrays** (input 2, a tetrahedral or planar triangle mesh, used as is):
 * - "HandleRegion" (point data, integer): vertices with value k >= 0 form region handle k
 *   (values need not be consecutive: regions are numbered in ascending value); -1 = none.
 * - "ShapePreservation" (point data, one component): the brush rho >= 0 per vertex (§3.3),
 *   turned into the per-element brush of Eq. 9 (bary::shape_preservation_per_element).
 *
 * @sa vtkBaryCoordinates bary::mixed_bbw_handles bary::Skeleton
 */
#ifndef vtkBaryMixedHandles_h
#define vtkBaryMixedHandles_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkObject.h"

#ifndef __VTK_WRAP__
#include "core/common/progress.h" // for bary::ProgressCallback
#include "core/common/weights_result.h" // for bary::WeightsResult
#include "core/coordinates/weight_methods.h" // for bary::WeightsSettings
#include "core/deformation/skeleton.h" // for bary::Skeleton
#include <vector>                      // for std::vector
#endif

class vtkDataSet;
class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryMixedHandles : public vtkObject
{
public:
  static vtkBaryMixedHandles* New();
  vtkTypeMacro(vtkBaryMixedHandles, vtkObject);

  /// Names of the arrays read (see the class comment).
  static const char* HandleTypeArrayName() { return "HandleType"; }
  static const char* RegionIdArrayName() { return "RegionId"; }
  static const char* HandleRegionArrayName() { return "HandleRegion"; }
  static const char* ShapePreservationArrayName() { return "ShapePreservation"; }

#ifndef __VTK_WRAP__
  /// True when BBW must read @p handles and @p domain as mixed handles: a domain is given and
  /// the handles carry a HandleType array, or have polygon cells together with lines, vertex
  /// cells or points on no cell, or the domain carries HandleRegion or ShapePreservation. (A
  /// plain skeleton, or a cage with a mesh of its interior, keeps vtkBaryWeightMethod's path.)
  static bool UsesMixedHandles(vtkPolyData* handles, vtkDataSet* domain);

  /// The handles as a bary::Skeleton (see the class comment).
  /// Throws bary::Error: EmptyInput (no points, no handle), InvalidArgument naming the cell for
  /// an unknown HandleType, a cell of a type that kind cannot take (a region of one line, a 2D
  /// triangle cage face...), and validate_skeleton's errors; NonFinite; and for @p dimension 2
  /// when the points are not in a plane z = const.
  static bary::Skeleton ToHandles(vtkPolyData* handles, int dimension);

  /// The domain's HandleRegion array as lists of vertex ids (empty when absent).
  /// Throws bary::Error(InvalidArgument) for an array of more than one component or a value
  /// that is not an integer >= -1 (named).
  static std::vector<std::vector<int>> RegionVertices(vtkDataSet* domain);

  /// The domain's ShapePreservation array (empty when absent). Throws bary::Error(SizeMismatch)
  /// for more than one component, (NonFinite) / (InvalidArgument) naming a NaN / negative value.
  static Eigen::VectorXd ShapePreservation(vtkDataSet* domain);

  /// BBW of the points of @p input with mixed handles in @p domain (a simplicial mesh used as
  /// is, or a closed surface / polygon meshed with the handles' samples). @p solved: the mesh
  /// weights of the same solve done elsewhere (a distributed run): interpolation only.
  static bary::WeightsResult Compute(const bary::WeightsSettings& settings, vtkDataSet* input,
    vtkPolyData* handles, vtkDataSet* domain, const bary::ProgressCallback& progress,
    const bary::MeshWeights* solved = nullptr);
#endif

protected:
  vtkBaryMixedHandles() = default;
  ~vtkBaryMixedHandles() override = default;

private:
  vtkBaryMixedHandles(const vtkBaryMixedHandles&) = delete;
  void operator=(const vtkBaryMixedHandles&) = delete;
};

#endif
