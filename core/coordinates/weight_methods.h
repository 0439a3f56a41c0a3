#pragma once
/// @file weight_methods.h
/// The one table of BaryLab's weight methods and of their settings. Every layer reads it: the
/// filters (vtkBaryWeightMethod's properties, defaults, ranges, content hash and PrintSelf), the
/// command line (its `--method` choices, option groups, help texts and range checks), the
/// viewer (its parameter panel, session keys and "run in terminal" command line) and the docs.
/// A method, a setting, its default and its range are written here once.
///
/// Defaults of the settings are those of the core option structs (bary::MeanValueOptions,
/// bary::CelestialOptions, bary::LBCOptions, ...), read from them, except where BaryLab's
/// front ends choose differently on purpose (BBW: coupled; documented at the field).

#include "core/coordinates/bbw.h"
#include "core/coordinates/celestial_coordinates.h"
#include "core/coordinates/local_barycentric_coordinates.h"
#include "core/meshing/mesh_point_locator.h"
#include "core/common/types.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace bary
{

/// The weight methods; values are stable (files and sessions store them by name, the VTK
/// filters by value).
enum class MethodId : int
{
  MeanValue = 0,  ///< Hormann & Floater 2006 (2D), Ju et al. 2005 (3D)
  Harmonic = 1,   ///< Joshi et al. 2007, finite elements on a mesh of the cage's interior
  BBW = 2,        ///< Jacobson et al. 2011, bounded biharmonic weights
  TCelestial = 3, ///< Cerveró et al., T-celestial coordinates of free control points
  SCelestial = 4, ///< Cerveró et al., S-celestial coordinates of free control points
  LBC = 5,        ///< Zhang et al. 2014, local barycentric coordinates
  Green = 6       ///< Lipman, Levin & Cohen-Or 2008, Green coordinates (vertices and face normals)
};

/// What a method's controls are.
enum class ControlKind
{
  Cage,          ///< a closed cage: polygon (2D) or closed triangle surface (3D)
  CageOrSkeleton, ///< a cage, or a skeleton (points and bones) in a domain (BBW)
  FreePoints     ///< free control points, no cage (celestial coordinates)
};

class WeightMethod;

/// One row of the method table.
struct MethodInfo
{
  MethodId id;
  std::string name;      ///< the command-line and session name ("mvc")
  std::string title;     ///< "mean value coordinates"
  std::string reference; ///< the paper
  ControlKind controls;
  bool domain_mesh;      ///< computed on a mesh of the domain (and interpolated at the points)
  bool accepts_domain;   ///< takes a given domain mesh / surface (filter input 2)
  bool linear_precision; ///< reproduces linear functions (x = sum w_i c_i)
  bool non_negative;     ///< weights >= 0 inside the domain
  bool dim2, dim3;       ///< dimensions supported
  /// The method's compute (see weight_method.h).
  const WeightMethod& (*instance)();
  /// The method also returns face coefficients (WeightsResult::face_weights), and a deformation
  /// is x' = W C' + face_weights N' with N' the deformed cage's face normals scaled by their
  /// stretch (deform_points_green): W alone neither reproduces x nor deforms (Green
  /// coordinates). Its linear_precision is that of W and face_weights together.
  bool face_terms = false;
};

/// Every method, in MethodId order.
const std::vector<MethodInfo>& method_table();
/// The row of @p id. @throws Error(InvalidArgument) for an unknown id.
const MethodInfo& method_info(MethodId id);
/// The row named @p name, nullptr if none.
const MethodInfo* find_method(const std::string& name);
/// The id named @p name. @throws Error(InvalidArgument) listing the known names.
MethodId method_from_name(const std::string& name);
/// "mvc|harmonic|bbw|..." (with @p separator between the names).
std::string method_names(const std::string& separator = "|");

/// Every setting of every weight method, with its default.
struct WeightsSettings
{
  MethodId method = MethodId::MeanValue;
  /// How the filters read the cage: 0 automatic (triangles: 3D; one polygon, polyline or bare
  /// points: 2D), 2 or 3.
  int cage_dimension = 0;
  double boundary_tolerance = 1e-10; ///< relative to the cage diameter (MeanValueOptions')
  bool validate_cage = true;
  int threads = 0; ///< 0: all cores (LBC: one thread, see the field's help)
  // mesh-based methods (harmonic, bbw, lbc)
  int target_cells = 0;        ///< 0: default_target_cells(dim)
  double max_cell_size = 0.0;  ///< max triangle area / tetrahedron volume; 0: from target_cells
  bool insert_points = false;  ///< make the evaluation points mesh vertices
  OutsidePolicy outside = OutsidePolicy::Error;
  // bounded biharmonic weights: the front ends' default is the coupled problem (partition of
  // unity exact), not BBWOptions' fast mode
  bool bbw_fast = false;
  BBWMassLumping bbw_mass_lumping = BBWOptions{}.mass_lumping;
  bool bbw_unbounded = !BBWOptions{}.bounded;
  bool bbw_compare_fast = BBWOptions{}.compare_with_fast;
  // celestial coordinates
  double lambda = 2.0;              ///< SCC wrapping-sphere parameter (CelestialOptions')
  std::vector<double> user_weights; ///< TCC s_i, one per control point; empty: none (Eq. 7)
  // celestial hull points: the front ends' default is Auto (added only when some point is not
  // strictly inside the controls' hull, so nothing changes for points inside), not
  // CelestialOptions' None
  CelestialHullPoints celestial_hull_points = CelestialHullPoints::Auto;
  double celestial_hull_margin = CelestialOptions{}.hull_margin;
  // local barycentric coordinates (LBCOptions' defaults: the paper's)
  LocalityFunction lbc_locality = LBCOptions{}.locality;
  double lbc_relaxed_epsilon = LBCOptions{}.relaxed_tv_epsilon;
  double lbc_primal_tolerance = LBCOptions{}.primal_tolerance;
  double lbc_dual_tolerance = LBCOptions{}.dual_tolerance;
  int lbc_max_iterations = LBCOptions{}.max_iterations;
  DistanceNormalization lbc_distance_normalization = LBCOptions{}.distance_normalization;
  bool lbc_unconstrained = !LBCOptions{}.barycentric_constraints;
  LBCStopping lbc_stopping = LBCOptions{}.stopping;
};

/// One setting of WeightsSettings: its names in every layer, its documentation, its range.
struct SettingField
{
  enum class Kind
  {
    Bool,
    Int,
    Double,
    Choice, ///< an enum: value = index into choices
    Numbers ///< a list of numbers (TCC user weights)
  };
  std::string key;      ///< session / JSON / summary name (the WeightsSettings member's name)
  std::string flag;     ///< command-line flag(s), comma-separated ("" = no flag)
  std::string property; ///< the vtkBaryWeightMethod property ("LBCPrimalTolerance")
  std::string label;    ///< viewer label
  std::string group;    ///< option group ("" = general)
  std::string help;     ///< help text and tooltip
  Kind kind = Kind::Double;
  double minimum = 0.0; ///< Int, Double, Numbers (each entry); inclusive
  double maximum = 0.0;
  std::vector<double> values;       ///< Int: the allowed values (empty: the range)
  std::vector<std::string> choices; ///< Choice: names in enum order
  std::vector<MethodId> methods;    ///< methods it applies to; empty = all
  bool affects_weights = true;      ///< false: results do not depend on it (threads)
  /// Value as a number (Bool 0/1, Choice index); Numbers: the count.
  std::function<double(const WeightsSettings&)> get;
  /// Sets the value (unchecked; see set_setting).
  std::function<void(WeightsSettings&, double)> set;
  /// Numbers only.
  std::function<std::vector<double>(const WeightsSettings&)> get_numbers;
  std::function<void(WeightsSettings&, std::vector<double>)> set_numbers;

  bool applies_to(MethodId method) const;
  /// The default (get of a default WeightsSettings).
  double default_value() const;
  /// "[1e-15, 0.5]", ">= 0", "one of 0, 2, 3", "squared | constant | linear", "on/off".
  std::string range_text() const;
  /// True when @p value is allowed (finite, in range, an allowed value / choice index).
  bool accepts(double value) const;
  /// The first flag ("--max-volume" of "--max-volume,--max-area").
  std::string primary_flag() const;
};

/// Every setting, in panel order (not the method: it is chosen separately).
const std::vector<SettingField>& weights_setting_fields();
/// The field named @p key. @throws Error(InvalidArgument) listing the keys.
const SettingField& setting_field(const std::string& key);
/// The field of the vtkBaryWeightMethod property @p property, nullptr if none.
const SettingField* setting_field_of_property(const std::string& property);

/// Sets @p key to @p value after checking it. @throws Error(InvalidArgument) naming the
/// setting, the value and the range (non-finite values included).
void set_setting(WeightsSettings& settings, const std::string& key, double value);
/// Choice settings by name ("nearest"). @throws Error(InvalidArgument) listing the choices.
void set_setting(WeightsSettings& settings, const std::string& key, const std::string& choice);
/// The choice name of a Choice setting's current value.
std::string choice_name(const WeightsSettings& settings, const std::string& key);

/// Checks every setting's range (and the user weights' entries).
/// @throws Error(InvalidArgument) naming the first setting out of range.
void validate_settings(const WeightsSettings& settings);

/// A 64-bit content hash (FNV-1a) of every field of @p settings that affects the weights (the
/// method included; not the thread count), for caches: equal settings give equal hashes, any
/// change gives a different one with overwhelming probability.
std::uint64_t settings_hash(const WeightsSettings& settings);

/// True when the settings are equal field by field.
bool operator==(const WeightsSettings& a, const WeightsSettings& b);
inline bool operator!=(const WeightsSettings& a, const WeightsSettings& b)
{
  return !(a == b);
}

} // namespace bary
