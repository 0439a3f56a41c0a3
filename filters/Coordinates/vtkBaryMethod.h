/**
 * @class   vtkBaryMethod
 * @brief   Internal: the coordinate methods behind vtkBaryCoordinates and
 *          vtkBaryCageDeformation, dispatched from one place.
 *
 * Every method BaryLab offers is listed in Method and computed by Compute(); both public
 * filters (and the command line) go through here, so a new method is added once.
 */
#ifndef vtkBaryMethod_h
#define vtkBaryMethod_h

#include "BaryLabFiltersModule.h"
#include "vtkBaryConversion.h"
#include "vtkDataArray.h"
#include "vtkObject.h"

#include "core/domain_mesh.h"
#include "core/skeleton.h"
#include "core/progress.h"
#include "core/types.h"

#include <string>
#include <utility>
#include <vector>

/// Parameters shared by every filter that computes weights (the CLI and the viewer edit the
/// same fields through the filters' setters).
struct vtkBaryMethodParameters
{
  int Method = 0;                   ///< vtkBaryCoordinates::Methods
  double BoundaryTolerance = 1e-10; ///< relative to the cage diameter (mean value coordinates)
  bool ValidateCage = true;
  int NumberOfThreads = 0;          ///< 0 = all cores
  // mesh-based methods (harmonic, ...)
  int TargetNumberOfCells = 0;      ///< 0 = method default (2D: 3000 triangles, 3D: 20000 tets)
  double MaximumCellSize = 0.0;     ///< max triangle area / tet volume; 0 = from the target
  bool InsertPointsIntoMesh = false; ///< make the evaluation points mesh vertices
  int OutsidePolicy = 0;            ///< vtkBaryCoordinates::OutsidePolicies
  // bounded biharmonic weights
  int BBWMode = 1;                  ///< vtkBaryCoordinates::BBWModes (default coupled)
  // celestial coordinates
  double Lambda = 2.0;              ///< SCC wrapping-sphere parameter (> 1)
  std::vector<double> UserWeights;  ///< TCC s_i (one per control point); empty = none
  // local barycentric coordinates (defaults: bary::LBCOptions')
  int LBCLocality = 0;              ///< vtkBaryCoordinates::LBCLocalityFunctions (squared)
  double LBCRelaxedEpsilon = 0.0;   ///< relaxed total variation epsilon (0: plain TV)
  double LBCPrimalTolerance = 1e-6; ///< per residual entry (Eq. 26)
  double LBCDualTolerance = 1e-5;   ///< per residual entry (Eq. 27)
  int LBCMaximumIterations = 20000; ///< ADMM iteration cap
  int LBCDistanceNormalization = 0; ///< vtkBaryCoordinates::LBCDistanceNormalizations
  bool LBCBarycentricConstraints = true; ///< partition of unity and reproduction enforced
};

/// The method parameters of a filter with the standard weights settings (vtkBaryCoordinates,
/// vtkBaryCageDeformation): one place copies them, so a new setting is added once.
template <class Filter>
vtkBaryMethodParameters vtkBaryParametersOf(Filter* filter)
{
  vtkBaryMethodParameters p;
  p.Method = filter->GetMethod();
  p.BoundaryTolerance = filter->GetBoundaryTolerance();
  p.ValidateCage = filter->GetValidateCage();
  p.NumberOfThreads = filter->GetNumberOfThreads();
  p.TargetNumberOfCells = filter->GetTargetNumberOfCells();
  p.MaximumCellSize = filter->GetMaximumCellSize();
  p.InsertPointsIntoMesh = filter->GetInsertPointsIntoMesh();
  p.OutsidePolicy = filter->GetOutsidePolicy();
  p.BBWMode = filter->GetBBWMode();
  p.Lambda = filter->GetLambda();
  if (vtkDataArray* s = filter->GetUserWeights())
    for (vtkIdType i = 0; i < s->GetNumberOfTuples(); ++i)
      p.UserWeights.push_back(s->GetComponent(i, 0));
  p.LBCLocality = filter->GetLBCLocality();
  p.LBCRelaxedEpsilon = filter->GetLBCRelaxedEpsilon();
  p.LBCPrimalTolerance = filter->GetLBCPrimalTolerance();
  p.LBCDualTolerance = filter->GetLBCDualTolerance();
  p.LBCMaximumIterations = filter->GetLBCMaximumIterations();
  p.LBCDistanceNormalization = filter->GetLBCDistanceNormalization();
  p.LBCBarycentricConstraints = filter->GetLBCBarycentricConstraints();
  return p;
}

/// Default target cell count of the domain mesh for a cage of dimension @p dim.
inline int vtkBaryDefaultTargetCells(int dim)
{
  return dim == 2 ? 3000 : 20000;
}

/// What Compute() returns besides the weights.
struct vtkBaryMethodReport
{
  vtkIdType Inside = 0, Outside = 0, Boundary = 0;
  std::vector<vtkIdType> Undefined; ///< points whose weights are undefined (NaN rows)
  std::vector<unsigned char> Location; ///< per point: 0 inside, 1 outside, 2 on the cage
  /// Solver and mesh figures of iterative / mesh-based methods, in the order computed
  /// (e.g. "iterations", "max_kkt_residual", "mesh_vertices", "seconds").
  std::vector<std::pair<std::string, double>> Statistics;
};

class vtkDataSet;

class BARYLABFILTERS_NO_EXPORT vtkBaryMethod : public vtkObject
{
public:
  static vtkBaryMethod* New();
  vtkTypeMacro(vtkBaryMethod, vtkObject);

  /// Domain-mesh options for @p parameters (size bound, Steiner points = @p points when
  /// InsertPointsIntoMesh). Shared by the methods and vtkBaryCageMesher.
  static bary::PolygonMeshOptions PolygonMeshOptions(
    const vtkBaryMethodParameters& parameters, const Eigen::MatrixXd& points);
  static bary::SurfaceMeshOptions SurfaceMeshOptions(
    const vtkBaryMethodParameters& parameters, const Eigen::MatrixXd& points);

  /// Weights (#P by #C, core control order) of @p points w.r.t. @p cage.
  /// @p edges (#E by 2 point ids, optional): the input's mesh edges, for methods that order
  /// their work along neighbours (celestial coordinates' warm starts).
  /// @p domain (optional, LBC only): a triangulation (2D) / tetrahedralization (3D) of the
  /// cage's interior used as is instead of meshing the cage (see LBCDomainMesh).
  /// @throws bary::Error
  static bary::DenseWeights Compute(const vtkBaryCage& cage, const Eigen::MatrixXd& points,
    const vtkBaryMethodParameters& parameters, const bary::ProgressCallback& progress,
    vtkBaryMethodReport* report, const Eigen::MatrixXi& edges = Eigen::MatrixXi(),
    vtkDataSet* domain = nullptr);

  /**
   * The domain mesh of local barycentric coordinates for @p cage: with @p domain (triangles in
   * a plane z = const for a 2D cage, tetrahedra for a 3D one), that mesh as is, each cage vertex
   * matched to the mesh's boundary vertex at its coordinates (within 1e-6 of the cage diameter;
   * bary::domain_mesh_from_simplices then checks that every boundary vertex lies on the cage);
   * without, the cage's interior meshed as for HARMONIC (PolygonMeshOptions /
   * SurfaceMeshOptions of @p parameters and @p points). Progress covers the meshing.
   * @throws bary::Error(InvalidArgument) naming a cage vertex with no mesh boundary vertex
   *   there, or a mesh of the wrong dimension; the meshers' and converters' errors
   */
  static bary::DomainMesh LBCDomainMesh(const vtkBaryCage& cage, vtkDataSet* domain,
    const Eigen::MatrixXd& points, const vtkBaryMethodParameters& parameters,
    const bary::ProgressCallback& progress);

  /// True for methods whose controls are free points (no cage): celestial coordinates.
  static bool IsPointBased(int method);

  /**
   * Bounded biharmonic weights of skeleton handles (points and bones, see
   * vtkBaryConversion::ToSkeleton) on @p domain (see vtkBaryConversion::DomainDimension): a simplicial mesh is used
   * as is (it must hold the joints and vertices along the bones: libigl's rule,
   * bary::handles_from_skeleton); a closed surface / polygon is meshed first with the joints and
   * bone samples (and, with InsertPointsIntoMesh, @p points) as Steiner points. Weights at
   * @p points (#P by dim) are interpolated on the mesh; columns in libigl's handle order.
   * @throws bary::Error
   */
  static bary::DenseWeights ComputeBBW(const bary::Skeleton& skeleton, vtkDataSet* domain,
    const Eigen::MatrixXd& points, const vtkBaryMethodParameters& parameters,
    const bary::ProgressCallback& progress, vtkBaryMethodReport* report);

protected:
  vtkBaryMethod() = default;
  ~vtkBaryMethod() override = default;

private:
  vtkBaryMethod(const vtkBaryMethod&) = delete;
  void operator=(const vtkBaryMethod&) = delete;
};

#endif
