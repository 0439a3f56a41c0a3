/**
 * @class   vtkBaryConversion
 * @brief   The one place where VTK data become Eigen matrices for BaryLab's core, and back.
 *
 * Static helpers only. Cages:
 * - A **3D cage** is a vtkPolyData whose polygons are all triangles (a closed surface); control
 *   point i is point i of the polydata.
 * - A **2D cage** is one closed polygon in the plane z = const, given either as a single polygon
 *   cell, a single (closed or open) polyline, or — the geometry-processing habit of an .obj with
 *   only `v` lines — as bare points with no cells, in order. Control point i is still point i of
 *   the polydata; the polygon order may differ (the permutation is kept in vtkBaryCage).
 *
 * Errors are thrown as bary::Error (filters catch them in RequestData and report them with
 * vtkErrorMacro).
 *
 * @sa vtkBaryCoordinates vtkBaryCageDeformation
 */
#ifndef vtkBaryConversion_h
#define vtkBaryConversion_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkObject.h"

#ifndef __VTK_WRAP__
#include "core/common/cage.h"  // for bary::Cage
#include "core/meshing/domain_mesh.h" // for bary::DomainMesh
#include "core/common/error.h" // for bary::ErrorCode
#include "core/deformation/skeleton.h" // for bary::Skeleton
#include "core/common/types.h" // for bary::DenseWeights
#include <vector>       // for std::vector
#endif

class vtkDataArray;
class vtkDataSet;
class vtkDoubleArray;
class vtkIntArray;
class vtkPointSet;
class vtkPoints;
class vtkPolyData;
class vtkUnstructuredGrid;

#ifndef __VTK_WRAP__
/// A cage as core sees it, plus where its control points come from.
struct vtkBaryCage
{
  bary::Cage Cage;
  /// ControlPointIds[k] = the polydata point id of core control point k (row k of Cage.V).
  std::vector<vtkIdType> ControlPointIds;
  /// True when ControlPointIds is the identity.
  bool IdentityOrder = true;
  /// 2D cages: the z of the cage's plane (2D results are placed there).
  double PlaneZ = 0.0;
};
#endif

class BARYLABFILTERS_EXPORT vtkBaryConversion : public vtkObject
{
public:
  static vtkBaryConversion* New();
  vtkTypeMacro(vtkBaryConversion, vtkObject);

  /// How a cage polydata is interpreted.
  enum CageDimension
  {
    AUTOMATIC = 0, ///< triangles -> 3D; one polygon/polyline or bare planar points -> 2D
    CAGE_2D = 2,
    CAGE_3D = 3
  };

#ifndef __VTK_WRAP__
  /**
   * Interpret @p cage as a 2D or 3D cage (see the class description). Throws bary::Error
   * naming the problem (no points, non-triangle cell k, several polygons, non-planar 2D cage,
   * NaN coordinates ...). Topological validity (closed, manifold, simple) is checked later by
   * bary::validate_cage.
   */
  static vtkBaryCage ToCage(vtkPolyData* cage, int dimension = AUTOMATIC);

  /// The first @p dimension coordinates of every point of @p points, #P by dimension.
  static Eigen::MatrixXd ToMatrix(vtkPoints* points, int dimension);
  /// Same for the points of a data set (any vtkDataSet).
  static Eigen::MatrixXd PointsToMatrix(vtkDataSet* data, int dimension);

  /**
   * Weights as a multi-component point-data array: tuple p, component j = weight of cage point
   * j. @p cage gives the column permutation (core control k -> cage point ControlPointIds[k]).
   */
  static vtkSmartPointer<vtkDoubleArray> ToArray(
    const bary::DenseWeights& W, const vtkBaryCage& cage, const char* name);
  /// Face coefficients (bary::WeightsResult::face_weights, Green coordinates' psi) as a
  /// point-data array: tuple p, component j (named "f<j>") = the coefficient of face j, faces in
  /// core order (3D: the cage's triangles in cell order; 2D: polygon edge j, from the polygon's
  /// j-th point to its next). No permutation: faces have no other order.
  static vtkSmartPointer<vtkDoubleArray> FaceArray(
    const bary::DenseWeights& face_weights, const char* name);
  /// Inverse of ToArray: #tuples by #components, columns in core control order. Stored weights
  /// must be finite: throws bary::Error(NonFinite) otherwise, (SizeMismatch) for a wrong
  /// number of components.
  static bary::DenseWeights FromArray(vtkDataArray* array, const vtkBaryCage& cage);

  /// A multi-component array as a #tuples by #components matrix, columns in array order.
  static bary::DenseWeights ArrayToMatrix(vtkDataArray* array);

  /// The numeric point-data array @p name of @p data, or nullptr when @p data has no point-data
  /// array of that name. @throws bary::Error(InvalidArgument) when the array of that name holds
  /// text (a vtkStringArray) or other values than numbers.
  static vtkDataArray* FindPointArray(vtkDataSet* data, const std::string& name);

  /// A count or id read from a file, for a message: whole ("72"), or as it is ("nan", "2.5",
  /// "1e+30"); never cast to an integer, which a NaN or 1e300 cannot be.
  static std::string CountText(double value);
  /// FindPointArray, but an array that is not there is an error too: "no point-data array
  /// 'Weights' (arrays present: A, B)", then "; " and @p advice when given.
  static vtkDataArray* RequirePointArray(
    vtkDataSet* data, const std::string& name, const std::string& advice = {});

  /**
   * The points of @p points (e.g. a moved cage) as control points in core order: row k is
   * point cage.ControlPointIds[k], first cage.Cage.dimension() coordinates. Throws
   * bary::Error(SizeMismatch) if the point count differs from the cage's, (NonFinite) for
   * NaN/inf.
   */
  static Eigen::MatrixXd ControlPoints(vtkPointSet* points, const vtkBaryCage& cage);

  /**
   * Replace the point coordinates of @p data by the rows of @p X (#P by 2 or 3). With 2 columns
   * the z coordinate of each point is kept.
   */
  static void SetPoints(vtkPointSet* data, const Eigen::MatrixXd& X);

  /**
   * A domain mesh as a vtkUnstructuredGrid of triangles (2D, at z = cage.PlaneZ) or tetrahedra,
   * with point-data arrays "ControlPointId" (cage point id at cage vertices, -1 elsewhere) and
   * "OnCage" (1 on the cage boundary).
   */
  static vtkSmartPointer<vtkUnstructuredGrid> ToUnstructuredGrid(
    const bary::DomainMesh& mesh, const vtkBaryCage& cage);

  /**
   * Handles of bounded biharmonic weights as a skeleton (libigl's convention, as in a .tgf):
   * the points of @p handles are the joints; every segment of every line/polyline cell is a bone
   * (cell order, then segment order); every point on no bone is a point handle (point order).
   * Vertex cells are allowed (vtkBaryTGFReader writes one per point handle) and change nothing.
   * Handle j of the weights is point handle j for j < #P, then bone j - #P.
   * Throws bary::Error: EmptyInput (no points / no handle), InvalidArgument (polygon cells: a
   * cage is not a skeleton; a zero-length bone, named), NonFinite (named point), and for
   * @p dimension 2 when the points are not in a plane z = const.
   */
  static bary::Skeleton ToSkeleton(vtkPolyData* handles, int dimension);

  /**
   * The simplices of a domain mesh: tetrahedra (#T by 4) when @p data has any — other cells
   * (boundary triangles, edges, vertices) are then ignored — else triangles (#T by 3; other
   * polygons are an error). @p V receives the points (#V by 3, or by 2 for triangles when
   * @p dimension is 2 or the triangles lie in a plane z = const and @p dimension is AUTOMATIC).
   * Throws bary::Error: EmptyInput (no points or no triangle/tetrahedron), InvalidArgument
   * (a non-simplex cell, named, or a non-planar triangle mesh asked as 2D), NonFinite.
   */
  static void ToSimplices(vtkDataSet* data, int dimension, Eigen::MatrixXd& V, Eigen::MatrixXi& T);

  /**
   * Free control points (cage-free, point-based methods such as celestial coordinates): every
   * point of @p points, in point order; cells are ignored. @p dimension AUTOMATIC gives 2 when
   * the points lie in a plane z = const, else 3. Throws bary::Error for no points or NaN (named).
   */
  static vtkBaryCage ToControlPoints(vtkPolyData* points, int dimension = AUTOMATIC);

  /// The distinct edges (#E by 2, smaller id first, sorted) of the cells of @p data: polygon
  /// and polyline sides, tetrahedron edges, ... (for neighbour-ordered computations).
  static Eigen::MatrixXi CellEdges(vtkDataSet* data);

  /// Dimension (2 or 3) of a BBW domain: a tetrahedral mesh -> 3, a triangle mesh in a plane
  /// z = const -> 2, a closed triangle surface (to be tetrahedralized) -> 3, one polygon or
  /// polyline, or bare points in a plane in polygon order (to be triangulated) -> 2. Throws
  /// bary::Error for anything else or no domain.
  static int DomainDimension(vtkDataSet* domain);

  /// A simplicial mesh (#V by 2 or 3, #T by 3 or 4) as a vtkUnstructuredGrid (2D at z = @p z).
  static vtkSmartPointer<vtkUnstructuredGrid> SimplicesToGrid(
    const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, double z = 0.0);

  /**
   * Per-point measures of @p data for "fractions of the domain" (vtkBaryLocalityStatistics):
   * with tetrahedra, each point's lumped volume (bary::vertex_measures over the tetrahedra);
   * with only triangles lying in a plane z = const, its lumped area; otherwise (no simplices,
   * a curved triangle surface, other polygons) @p measure is left empty. Returns 3, 2 or 0
   * accordingly. Points on no simplex get 0.
   */
  static int PointMeasures(vtkDataSet* data, Eigen::VectorXd& measure);

  /**
   * Sparse weights (#P by #C, CSR, columns = weights components) as the compact pair of
   * point-data arrays written by vtkBaryReduceWeights: @p indices (vtkIntArray) and @p values
   * (vtkDoubleArray), K components each with K = the largest row's number of entries (at least
   * 1); row p lists its control indices in increasing order, padded with -1 (indices) and 0
   * (values). Returns K.
   */
  static int ToCompactArrays(const bary::SparseWeights& W, vtkIntArray* indices,
    vtkDoubleArray* values);

  /**
   * Inverse of ToCompactArrays: the compact pair as a #tuples by @p numberOfControls CSR matrix.
   * Throws bary::Error: SizeMismatch (different tuple or component counts), InvalidArgument (an
   * index outside [-1, numberOfControls), or a repeated index in a row, named), NonFinite (a
   * NaN/inf value, named).
   */
  static bary::SparseWeights FromCompactArrays(
    vtkDataArray* indices, vtkDataArray* values, vtkIdType numberOfControls);

  /// bary::ErrorCode carried in vtkAlgorithm's error code (vtkErrorCode::UserError + 1 + code).
  static unsigned long ToVTKErrorCode(bary::ErrorCode code);
  /// Inverse of ToVTKErrorCode; @p fallback when @p vtkCode does not hold a bary::ErrorCode.
  static bary::ErrorCode ErrorCodeOf(unsigned long vtkCode, bary::ErrorCode fallback);
#endif

protected:
  vtkBaryConversion() = default;
  ~vtkBaryConversion() override = default;

private:
  vtkBaryConversion(const vtkBaryConversion&) = delete;
  void operator=(const vtkBaryConversion&) = delete;
};

#endif
