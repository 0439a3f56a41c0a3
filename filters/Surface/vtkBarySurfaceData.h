/**
 * @class   vtkBarySurfaceData
 * @brief   The one place where VTK surfaces, embeddings and points on a surface become the
 *          core's surface types (bary::SurfaceMesh, bary::SurfacePoint) and back.
 *
 * A surface is a vtkPolyData whose polygon cells are all triangles (vertex and line cells are
 * ignored; triangle strips and polygons of other sizes are refused, naming the cell: triangulate
 * first, e.g. with vtkTriangleFilter), closed or with boundary, one connected manifold piece
 * (bary::SurfaceMesh validates it). Its polygon cell i is triangle i of the core, so `FaceId`
 * arrays are cell ids of the input surface.
 *
 * An embedding is a point-data array of the surface with D >= 2 components (default name
 * `Embedding`, vtkBarySurfaceEmbedding's output).
 *
 * Points on the surface (anchors, query points) are located by their closest point; a point
 * farther than Tolerance x (the surface's bounding-box diagonal) is refused, naming it.
 *
 * @sa vtkBarySurfaceEmbedding vtkBaryWeightedAverage vtkBarySurfaceWeights
 */
#ifndef vtkBarySurfaceData_h
#define vtkBarySurfaceData_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkObject.h"

#ifndef __VTK_WRAP__
#include "core/surface/surface_mesh.h" // for bary::SurfaceMesh

#include <memory>
#include <string>
#include <vector>

namespace bary
{
class WeightedAverages;
}
#endif

class vtkDataArray;
class vtkPointSet;
class vtkPolyData;

class BARYLABSURFACE_EXPORT vtkBarySurfaceData : public vtkObject
{
public:
  static vtkBarySurfaceData* New();
  vtkTypeMacro(vtkBarySurfaceData, vtkObject);

  /// The default name of the embedding array.
  static const char* DefaultEmbeddingName() { return "Embedding"; }

#ifndef __VTK_WRAP__
  /// The surface as the core's validated SurfaceMesh. @throws bary::Error naming the problem.
  static bary::SurfaceMesh ToSurfaceMesh(vtkPolyData* surface);
  /// The embedding array @p name of @p surface as a #points by D matrix.
  /// @throws bary::Error(InvalidArgument) when it is missing (naming vtkBarySurfaceEmbedding)
  ///   or has fewer than 2 components; (NonFinite) naming a point with NaN / infinity.
  static Eigen::MatrixXd Embedding(vtkPolyData* surface, const std::string& name);
  /// The points of @p points located on @p mesh. @p what names them in errors ("anchor").
  /// @throws bary::Error(EmptyInput) for no points; (NonFinite); (PointsOutside) naming the
  ///   first point farther than tolerance x the bounding-box diagonal, with its distance.
  static std::vector<bary::SurfacePoint> Locate(const bary::SurfaceMesh& mesh, vtkPointSet* points,
    double tolerance, const char* what, std::vector<double>* distance = nullptr);
  /// The same for a matrix of points (#P by 3).
  static std::vector<bary::SurfacePoint> Locate(const bary::SurfaceMesh& mesh,
    const Eigen::MatrixXd& P, double tolerance, const char* what,
    std::vector<double>* distance = nullptr);
  /// Adds `FaceId` (vtkIdTypeArray) and `Barycentric` (3 components) point arrays describing
  /// @p points to @p data (whose point count must match); invalid entries (face -1) get -1 and
  /// NaN.
  static void AddSurfacePointArrays(
    vtkPointSet* data, const std::vector<bary::SurfacePoint>& points);

  /// A bary::WeightedAverages (Phong projection precomputed) for a surface and its embedding
  /// array, rebuilt only when the surface or the array changed (their MTimes): what
  /// vtkBaryWeightedAverage and vtkBarySurfaceWeights keep between runs, so that moving anchors
  /// or changing weights costs only the queries.
  class Cache
  {
  public:
    std::shared_ptr<const bary::WeightedAverages> Get(vtkPolyData* surface, const std::string& name);

  private:
    std::shared_ptr<const bary::WeightedAverages> Value;
    const void* Surface = nullptr;
    vtkMTimeType SurfaceTime = 0, ArrayTime = 0;
    std::string Name;
  };
#endif

protected:
  vtkBarySurfaceData() = default;
  ~vtkBarySurfaceData() override = default;

private:
  vtkBarySurfaceData(const vtkBarySurfaceData&) = delete;
  void operator=(const vtkBarySurfaceData&) = delete;
};

#endif
