/**
 * @class   vtkBaryWeightMethod
 * @brief   A weight method with all its settings: the strategy that vtkBaryCoordinates and
 *          vtkBaryCageDeformation share, as VTK's point-interpolation filters share a
 *          vtkInterpolationKernel.
 *
 * Holds the method (MEAN_VALUE, HARMONIC, BBW, T_CELESTIAL, S_CELESTIAL, LBC, GREEN) and every
 * setting of every method. The settings, their defaults, ranges and documentation are BaryLab's
 * one settings table (core/coordinates/weight_methods.h, bary::weights_setting_fields()): each property
 * below is a view of one row of it (the row's `property` name), so the command line's options,
 * the viewer's panel, this class and its PrintSelf agree by construction. Setters clamp to the
 * row's range as vtkSetClampMacro does (a non-finite value is refused with an error); the
 * command line and the viewer refuse out-of-range values instead.
 *
 * Compute() turns VTK inputs into the core's (the cage or control points, a skeleton, the
 * domain) and runs bary::compute_weights. GetSettingsHash() is a content hash of every setting
 * that affects the weights, for caches.
 *
 * @sa vtkBaryCoordinates vtkBaryCageDeformation
 */
#ifndef vtkBaryWeightMethod_h
#define vtkBaryWeightMethod_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkObject.h"

#ifndef __VTK_WRAP__
#include "vtkBaryConversion.h"   // for vtkBaryCage
#include "core/common/progress.h"       // for bary::ProgressCallback
#include "core/coordinates/weight_methods.h" // for bary::WeightsSettings
#include "core/common/weights_result.h" // for bary::WeightsResult
#include <string>                // for std::string
#include <vector>                // for std::vector

/// What the processes of a distributed run share (vtkBaryCoordinates with a controller of
/// several processes): the weights solved once on the domain mesh, and all the points (whose
/// hull decides celestial coordinates' hull points). Both optional (null: a serial run).
struct vtkBaryShared
{
  const bary::MeshWeights* MeshWeights = nullptr;
  vtkDataSet* AllPoints = nullptr;
};
#endif

class vtkDataArray;
class vtkDataSet;
class vtkDataObject;
class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryWeightMethod : public vtkObject
{
public:
  static vtkBaryWeightMethod* New();
  vtkTypeMacro(vtkBaryWeightMethod, vtkObject);
  /// Every setting of the table, with its value.
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkMTimeType GetMTime() override;

  /// The methods (values are bary::MethodId's and stable).
  enum Methods
  {
    MEAN_VALUE = 0,  ///< Hormann & Floater 2006 (2D), Ju et al. 2005 (3D); closed form, any point
    HARMONIC = 1,    ///< Joshi et al. 2007: finite elements on a mesh of the cage's interior
    BBW = 2,         ///< Jacobson et al. 2011: bounded biharmonic weights (cage or skeleton)
    T_CELESTIAL = 3, ///< Cerveró et al.: T-celestial coordinates of free control points
    S_CELESTIAL = 4, ///< Cerveró et al.: S-celestial coordinates of free control points
    LBC = 5,         ///< Zhang et al. 2014: local barycentric coordinates on a mesh of the cage
    GREEN = 6,       ///< Lipman et al. 2008: Green coordinates (vertex weights and face coefficients)
    NUMBER_OF_METHODS
  };

  /// What mesh-based methods do with points outside the cage (choices of "outside").
  enum OutsidePolicies
  {
    OUTSIDE_ERROR = 0,   ///< fail, naming how many and the first one (default)
    OUTSIDE_NEAREST = 1, ///< use the weights of the nearest point of the domain
    OUTSIDE_NAN = 2      ///< NaN weights, counted as undefined
  };

  /// LBC: tau of the paper's §3.3 (Eq. 11), choices of "lbc_locality".
  enum LBCLocalityFunctions
  {
    LBC_LOCALITY_SQUARED = 0,  ///< tau(D) = D^2, the paper's choice for all its results (default)
    LBC_LOCALITY_CONSTANT = 1, ///< tau = 1: plain total variation (problem (5)), no distances
    LBC_LOCALITY_LINEAR = 2    ///< tau(D) = D
  };

  /// LBC: how geodesic distances are normalised (Eq. 12), choices of
  /// "lbc_distance_normalization".
  enum LBCDistanceNormalizations
  {
    LBC_NORMALIZE_PER_CONTROL_POINT = 0, ///< by each control point's own maximum (default)
    LBC_NORMALIZE_GLOBAL = 1             ///< by one maximum over all control points
  };

  /// BBW: the lumped mass matrix (§3.4), choices of "bbw_mass_lumping".
  enum BBWMassLumpings
  {
    BBW_MASS_BARYCENTRIC = 0, ///< each element's measure split equally among its vertices
    BBW_MASS_VORONOI = 1      ///< the Voronoi area / volume of each vertex
  };

  /// Celestial coordinates: hull points added (§6), choices of "celestial_hull_points".
  enum CelestialHullPointsModes
  {
    HULL_POINTS_NONE = 0,  ///< the controls as given
    HULL_POINTS_AUTO = 1,  ///< the default: added only when a point is not strictly inside the controls' hull
    HULL_POINTS_ALWAYS = 2 ///< always added (the same components whatever the points)
  };

  /// LBC: the stopping rule, choices of "lbc_stopping".
  enum LBCStoppingRules
  {
    LBC_STOPPING_PAPER = 0,    ///< the paper's Eqs. 26-27 as printed
    LBC_STOPPING_CONVERGED = 1 ///< BaryLab's converged rule (docs/local-barycentric-coordinates.md)
  };

  ///@{
  /// The method. Default MEAN_VALUE.
  virtual void SetMethod(int method);
  int GetMethod() const;
  void SetMethodToMeanValue() { this->SetMethod(MEAN_VALUE); }
  void SetMethodToHarmonic() { this->SetMethod(HARMONIC); }
  void SetMethodToBBW() { this->SetMethod(BBW); }
  void SetMethodToTCelestial() { this->SetMethod(T_CELESTIAL); }
  void SetMethodToSCelestial() { this->SetMethod(S_CELESTIAL); }
  void SetMethodToLBC() { this->SetMethod(LBC); }
  void SetMethodToGreen() { this->SetMethod(GREEN); }
  /// By command-line name ("mvc", "lbc", ...); false (and no change) for an unknown name.
  bool SetMethodByName(const char* name);
  ///@}

  /// Short name of a method as used on the command line ("mvc"), nullptr if unknown.
  static const char* GetMethodName(int method);
  /// Inverse of GetMethodName; -1 if unknown.
  static int GetMethodFromName(const char* name);
  /// True for methods whose controls are free points (celestial coordinates).
  static bool IsPointBased(int method);
  /// True for methods that also compute face coefficients (Green coordinates: the result's
  /// face_weights, the filters' FaceWeights array) and deform with the faces' normals.
  static bool HasFaceTerms(int method);

  ///@{
  /// Any setting by its table key ("lbc_primal_tolerance"); a Choice by its index, a Bool as
  /// 0/1. Clamped to the setting's range (vtkSetClampMacro's behaviour); an unknown key or a
  /// non-finite value is an error and leaves the setting unchanged.
  void SetSetting(const char* key, double value);
  double GetSetting(const char* key) const;
  ///@}

  // The table's settings as typed properties (defaults and ranges: bary::weights_setting_fields).
  void SetCageDimension(int v) { this->SetSetting("cage_dimension", v); }
  int GetCageDimension() const { return static_cast<int>(this->GetSetting("cage_dimension")); }
  void SetBoundaryTolerance(double v) { this->SetSetting("boundary_tolerance", v); }
  double GetBoundaryTolerance() const { return this->GetSetting("boundary_tolerance"); }
  void SetValidateCage(bool v) { this->SetSetting("validate_cage", v); }
  bool GetValidateCage() const { return this->GetSetting("validate_cage") != 0; }
  vtkBooleanMacro(ValidateCage, bool);
  void SetNumberOfThreads(int v) { this->SetSetting("threads", v); }
  int GetNumberOfThreads() const { return static_cast<int>(this->GetSetting("threads")); }
  void SetTargetNumberOfCells(int v) { this->SetSetting("target_cells", v); }
  int GetTargetNumberOfCells() const { return static_cast<int>(this->GetSetting("target_cells")); }
  void SetMaximumCellSize(double v) { this->SetSetting("max_cell_size", v); }
  double GetMaximumCellSize() const { return this->GetSetting("max_cell_size"); }
  void SetInsertPointsIntoMesh(bool v) { this->SetSetting("insert_points", v); }
  bool GetInsertPointsIntoMesh() const { return this->GetSetting("insert_points") != 0; }
  vtkBooleanMacro(InsertPointsIntoMesh, bool);
  void SetOutsidePolicy(int v) { this->SetSetting("outside", v); }
  int GetOutsidePolicy() const { return static_cast<int>(this->GetSetting("outside")); }
  void SetBBWFast(bool v) { this->SetSetting("bbw_fast", v); }
  bool GetBBWFast() const { return this->GetSetting("bbw_fast") != 0; }
  vtkBooleanMacro(BBWFast, bool);
  void SetBBWMassLumping(int v) { this->SetSetting("bbw_mass_lumping", v); }
  int GetBBWMassLumping() const { return static_cast<int>(this->GetSetting("bbw_mass_lumping")); }
  void SetBBWMassLumpingToBarycentric() { this->SetBBWMassLumping(BBW_MASS_BARYCENTRIC); }
  void SetBBWMassLumpingToVoronoi() { this->SetBBWMassLumping(BBW_MASS_VORONOI); }
  void SetBBWUnbounded(bool v) { this->SetSetting("bbw_unbounded", v); }
  bool GetBBWUnbounded() const { return this->GetSetting("bbw_unbounded") != 0; }
  vtkBooleanMacro(BBWUnbounded, bool);
  void SetBBWCompareWithFast(bool v) { this->SetSetting("bbw_compare_fast", v); }
  bool GetBBWCompareWithFast() const { return this->GetSetting("bbw_compare_fast") != 0; }
  vtkBooleanMacro(BBWCompareWithFast, bool);
  void SetLambda(double v) { this->SetSetting("lambda", v); }
  double GetLambda() const { return this->GetSetting("lambda"); }
  void SetCelestialHullPoints(int v) { this->SetSetting("celestial_hull_points", v); }
  int GetCelestialHullPoints() const
  {
    return static_cast<int>(this->GetSetting("celestial_hull_points"));
  }
  void SetCelestialHullPointsToNone() { this->SetCelestialHullPoints(HULL_POINTS_NONE); }
  void SetCelestialHullPointsToAuto() { this->SetCelestialHullPoints(HULL_POINTS_AUTO); }
  void SetCelestialHullPointsToAlways() { this->SetCelestialHullPoints(HULL_POINTS_ALWAYS); }
  void SetCelestialHullMargin(double v) { this->SetSetting("celestial_hull_margin", v); }
  double GetCelestialHullMargin() const { return this->GetSetting("celestial_hull_margin"); }
  void SetLBCLocality(int v) { this->SetSetting("lbc_locality", v); }
  int GetLBCLocality() const { return static_cast<int>(this->GetSetting("lbc_locality")); }
  void SetLBCLocalityToSquared() { this->SetLBCLocality(LBC_LOCALITY_SQUARED); }
  void SetLBCLocalityToConstant() { this->SetLBCLocality(LBC_LOCALITY_CONSTANT); }
  void SetLBCLocalityToLinear() { this->SetLBCLocality(LBC_LOCALITY_LINEAR); }
  void SetLBCRelaxedEpsilon(double v) { this->SetSetting("lbc_relaxed_epsilon", v); }
  double GetLBCRelaxedEpsilon() const { return this->GetSetting("lbc_relaxed_epsilon"); }
  void SetLBCPrimalTolerance(double v) { this->SetSetting("lbc_primal_tolerance", v); }
  double GetLBCPrimalTolerance() const { return this->GetSetting("lbc_primal_tolerance"); }
  void SetLBCDualTolerance(double v) { this->SetSetting("lbc_dual_tolerance", v); }
  double GetLBCDualTolerance() const { return this->GetSetting("lbc_dual_tolerance"); }
  void SetLBCMaximumIterations(int v) { this->SetSetting("lbc_max_iterations", v); }
  int GetLBCMaximumIterations() const
  {
    return static_cast<int>(this->GetSetting("lbc_max_iterations"));
  }
  void SetLBCDistanceNormalization(int v) { this->SetSetting("lbc_distance_normalization", v); }
  int GetLBCDistanceNormalization() const
  {
    return static_cast<int>(this->GetSetting("lbc_distance_normalization"));
  }
  void SetLBCUnconstrained(bool v) { this->SetSetting("lbc_unconstrained", v); }
  bool GetLBCUnconstrained() const { return this->GetSetting("lbc_unconstrained") != 0; }
  vtkBooleanMacro(LBCUnconstrained, bool);
  void SetLBCStopping(int v) { this->SetSetting("lbc_stopping", v); }
  int GetLBCStopping() const { return static_cast<int>(this->GetSetting("lbc_stopping")); }
  void SetLBCStoppingToPaper() { this->SetLBCStopping(LBC_STOPPING_PAPER); }
  void SetLBCStoppingToConverged() { this->SetLBCStopping(LBC_STOPPING_CONVERGED); }

  ///@{
  /// T-celestial coordinates: the user weights s_i >= 0 of Eq. 8, one tuple per control point
  /// (first component used). nullptr (default): none (Eq. 7).
  virtual void SetUserWeights(vtkDataArray* weights);
  vtkGetObjectMacro(UserWeights, vtkDataArray);
  ///@}

  /// Content hash of every setting that affects the weights (not the thread count).
  vtkTypeUInt64 GetSettingsHash();

  /// For the filters that hold a weight method: @p slot (owned by @p owner, never nullptr)
  /// becomes @p method, registered by @p owner; nullptr and the same object change nothing.
  /// True when it changed.
  static bool Replace(vtkObjectBase* owner, vtkBaryWeightMethod*& slot, vtkBaryWeightMethod* method);

  /// Copies every setting of @p other (the user weights array is shared).
  void DeepCopy(vtkBaryWeightMethod* other);

#ifndef __VTK_WRAP__
  /// The settings (with the user weights copied in).
  bary::WeightsSettings GetSettings() const;
  /// Sets every setting. @throws bary::Error(InvalidArgument) naming a setting out of range.
  void SetSettings(const bary::WeightsSettings& settings);

  /// True when @p controls are a skeleton for BBW: points and lines, no polygons, and either a
  /// @p domain or lines other than one polyline through every point. Without a domain, bare
  /// points or one such polyline are a 2D cage (the `v`-only .obj habit), which BBW meshes.
  bool IsSkeleton(vtkPolyData* controls, vtkDataObject* domain) const;
  /// The controls as the method reads them: a cage (ToCage) or free points (ToControlPoints),
  /// with the cage dimension setting.
  struct vtkBaryCage ReadControls(vtkPolyData* controls) const;

  /**
   * Weights of the points of @p input w.r.t. @p controls (a cage, free control points, or a
   * BBW skeleton), with @p domain (optional: LBC's given mesh; BBW-skeleton's mesh or surface).
   * @p columns receives the controls (its ControlPointIds order the result's columns into
   * VTK components; identity for a skeleton). @p warnings receives what the caller should warn
   * about (an ignored domain, ignored z of a 2D cage's points).
   * @throws bary::Error
   */
  bary::WeightsResult Compute(vtkDataSet* input, vtkPolyData* controls, vtkDataSet* domain,
    const bary::ProgressCallback& progress, struct vtkBaryCage* columns,
    std::vector<std::string>* warnings, const vtkBaryShared& shared = {}) const;
#endif

protected:
  vtkBaryWeightMethod();
  ~vtkBaryWeightMethod() override;

#ifndef __VTK_WRAP__
  bary::WeightsSettings Settings;
#endif
  vtkDataArray* UserWeights = nullptr;

private:
  vtkBaryWeightMethod(const vtkBaryWeightMethod&) = delete;
  void operator=(const vtkBaryWeightMethod&) = delete;
};

#endif
