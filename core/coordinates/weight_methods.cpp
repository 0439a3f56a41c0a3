#include "core/coordinates/weight_methods.h"

#include "core/coordinates/celestial_coordinates.h"
#include "core/common/error.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/coordinates/weight_method.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

namespace bary
{
namespace
{
using Kind = SettingField::Kind;
constexpr double kHuge = 1e300; // "no upper bound" for sizes: shown as ">= minimum"

const std::vector<MethodId> kMeshMethods = { MethodId::Harmonic, MethodId::BBW, MethodId::LBC };

std::string number_text(double v)
{
  std::ostringstream out;
  out.precision(12);
  out << v;
  return out.str();
}

/// A Double or Int field bound to a member.
template <class T>
SettingField number_field(T WeightsSettings::*member)
{
  SettingField f;
  f.kind = std::is_same<T, double>::value ? Kind::Double : Kind::Int;
  f.get = [member](const WeightsSettings& s) { return static_cast<double>(s.*member); };
  f.set = [member](WeightsSettings& s, double v) { s.*member = static_cast<T>(v); };
  return f;
}

SettingField bool_field(bool WeightsSettings::*member)
{
  SettingField f;
  f.kind = Kind::Bool;
  f.minimum = 0;
  f.maximum = 1;
  f.get = [member](const WeightsSettings& s) { return s.*member ? 1.0 : 0.0; };
  f.set = [member](WeightsSettings& s, double v) { s.*member = v != 0.0; };
  return f;
}

/// A Choice field bound to an enum member; @p order lists the enum values in choice order.
template <class E>
SettingField choice_field(E WeightsSettings::*member, std::vector<E> order,
  std::vector<std::string> names)
{
  SettingField f;
  f.kind = Kind::Choice;
  f.choices = std::move(names);
  f.minimum = 0;
  f.maximum = static_cast<double>(f.choices.size() - 1);
  f.get = [member, order](const WeightsSettings& s) {
    const auto it = std::find(order.begin(), order.end(), s.*member);
    return static_cast<double>(it - order.begin());
  };
  f.set = [member, order](WeightsSettings& s, double v) {
    const auto i = static_cast<std::size_t>(std::clamp(v, 0.0, double(order.size() - 1)));
    s.*member = order[i];
  };
  return f;
}

SettingField& describe(SettingField& f, std::string key, std::string flag, std::string property,
  std::string label, std::string group, std::string help, std::vector<MethodId> methods = {})
{
  f.key = std::move(key);
  f.flag = std::move(flag);
  f.property = std::move(property);
  f.label = std::move(label);
  f.group = std::move(group);
  f.help = std::move(help);
  f.methods = std::move(methods);
  return f;
}

SettingField& range(SettingField& f, double lo, double hi)
{
  f.minimum = lo;
  f.maximum = hi;
  return f;
}

std::vector<SettingField> make_fields()
{
  std::vector<SettingField> fields;
  const std::string mesh_group = "domain mesh";
  const std::string bbw_group = "bounded biharmonic weights";
  const std::string celestial_group = "celestial coordinates";
  const std::string lbc_group = "local barycentric coordinates";

  {
    SettingField f = number_field(&WeightsSettings::cage_dimension);
    describe(f, "cage_dimension", "--cage-dimension", "CageDimension", "Cage dimension", "",
      "how to read the cage: 0 automatic (triangles: 3D; one polygon/polyline/bare points: 2D), "
      "2, 3");
    range(f, 0, 3);
    f.values = { 0, 2, 3 };
    fields.push_back(f);
  }
  {
    SettingField f = number_field(&WeightsSettings::boundary_tolerance);
    describe(f, "boundary_tolerance", "--boundary-tolerance", "BoundaryTolerance",
      "Boundary tolerance", "",
      "points closer to the cage than this fraction of its diagonal count as on the cage");
    fields.push_back(range(f, 0.0, 1e-3));
  }
  {
    SettingField f = bool_field(&WeightsSettings::validate_cage);
    describe(f, "validate_cage", "", "ValidateCage", "Validate cage", "",
      "check that the cage is closed, manifold and consistently oriented");
    fields.push_back(f);
  }
  {
    SettingField f = number_field(&WeightsSettings::threads);
    describe(f, "threads", "--threads", "NumberOfThreads", "Threads", "",
      "threads (0 = all cores); results do not depend on it");
    f.affects_weights = false;
    fields.push_back(range(f, 0, 1024));
  }
  {
    SettingField f = number_field(&WeightsSettings::target_cells);
    describe(f, "target_cells", "--cells", "TargetNumberOfCells", "Mesh cells", mesh_group,
      "approximate number of cells of the domain mesh (0: 3000 in 2D, 20000 in 3D)",
      kMeshMethods);
    fields.push_back(range(f, 0, 50000000));
  }
  {
    SettingField f = number_field(&WeightsSettings::max_cell_size);
    describe(f, "max_cell_size", "--max-volume,--max-area", "MaximumCellSize", "Max cell size",
      mesh_group, "maximum tetrahedron volume / triangle area (overrides --cells)", kMeshMethods);
    fields.push_back(range(f, 0.0, kHuge));
  }
  {
    SettingField f = bool_field(&WeightsSettings::insert_points);
    describe(f, "insert_points", "--insert-points", "InsertPointsIntoMesh", "Insert points",
      mesh_group, "make the points mesh vertices (exact finite-element values there)",
      kMeshMethods);
    fields.push_back(f);
  }
  {
    SettingField f = choice_field(&WeightsSettings::outside,
      { OutsidePolicy::Error, OutsidePolicy::Nearest, OutsidePolicy::NaN },
      { "error", "nearest", "nan" });
    describe(f, "outside", "--outside", "OutsidePolicy", "Outside points", mesh_group,
      "points outside the cage/domain: error|nearest|nan", kMeshMethods);
    fields.push_back(f);
  }
  {
    SettingField f = bool_field(&WeightsSettings::bbw_fast);
    describe(f, "bbw_fast", "--fast", "BBWFast", "Fast BBW", bbw_group,
      "solve each handle alone, then normalize (the paper's fast mode); default: the coupled "
      "problem with partition of unity enforced",
      { MethodId::BBW });
    fields.push_back(f);
  }
  {
    SettingField f = choice_field(&WeightsSettings::bbw_mass_lumping,
      { BBWMassLumping::Barycentric, BBWMassLumping::Voronoi }, { "barycentric", "voronoi" });
    describe(f, "bbw_mass_lumping", "--mass-lumping", "BBWMassLumping", "Mass lumping (BBW)",
      bbw_group,
      "lumped mass matrix of the Laplacian: barycentric (each element split equally) | voronoi "
      "(the Voronoi area/volume of each vertex, the paper's §3.4)",
      { MethodId::BBW });
    fields.push_back(f);
  }
  {
    SettingField f = bool_field(&WeightsSettings::bbw_unbounded);
    describe(f, "bbw_unbounded", "--unbounded", "BBWUnbounded", "Unbounded (BBW)", bbw_group,
      "drop the bounds 0 <= w <= 1: unbounded biharmonic weights (Figs. 4, 16), a comparison "
      "that shows what the bounds buy",
      { MethodId::BBW });
    fields.push_back(f);
  }
  {
    SettingField f = bool_field(&WeightsSettings::bbw_compare_fast);
    describe(f, "bbw_compare_fast", "--compare-fast", "BBWCompareWithFast",
      "Compare with fast (BBW)", bbw_group,
      "coupled mode: also solve the fast mode and report how far the coupled weights are from "
      "it (the paper's Table 2: fast_difference_mean / _max); the weights do not change, the "
      "time about doubles",
      { MethodId::BBW });
    fields.push_back(f);
  }
  {
    SettingField f = number_field(&WeightsSettings::lambda);
    describe(f, "lambda", "--lambda", "Lambda", "Lambda (SCC)", celestial_group,
      "scc: wrapping-sphere parameter (> 1; the coordinates do not depend on it)",
      { MethodId::SCelestial });
    fields.push_back(range(f, 1.000001, 1e6));
  }
  {
    SettingField f;
    f.kind = Kind::Numbers;
    describe(f, "user_weights", "", "UserWeights", "User weights s_i (TCC)", celestial_group,
      "T-celestial coordinates' user weights s_i >= 0 (Eq. 8), one per control point, "
      "separated by commas or spaces; empty: all zero (Eq. 7). (Command line: --user-weights "
      "FILE with the same numbers.)",
      { MethodId::TCelestial });
    range(f, 0.0, kHuge);
    f.get = [](const WeightsSettings& s) { return static_cast<double>(s.user_weights.size()); };
    f.set = [](WeightsSettings&, double) {};
    f.get_numbers = [](const WeightsSettings& s) { return s.user_weights; };
    f.set_numbers = [](WeightsSettings& s, std::vector<double> v) { s.user_weights = std::move(v); };
    fields.push_back(f);
  }
  {
    SettingField f = choice_field(&WeightsSettings::celestial_hull_points,
      { CelestialHullPoints::None, CelestialHullPoints::Auto, CelestialHullPoints::Always },
      { "none", "auto", "always" });
    describe(f, "celestial_hull_points", "--hull-points", "CelestialHullPoints",
      "Hull points", celestial_group,
      "control points added around the model so that every point is strictly inside the "
      "controls' convex hull (§6; the 4 / 8 corners of a box oriented by the points, so the "
      "weights stay rotation invariant): auto (only when some point is not strictly inside) | "
      "always | none",
      { MethodId::TCelestial, MethodId::SCelestial });
    fields.push_back(f);
  }
  {
    SettingField f = number_field(&WeightsSettings::celestial_hull_margin);
    describe(f, "celestial_hull_margin", "--hull-margin", "CelestialHullMargin", "Hull margin",
      celestial_group,
      "margin of the added hull points, relative to the diagonal of the box around the points "
      "and the controls (> 0)",
      { MethodId::TCelestial, MethodId::SCelestial });
    fields.push_back(range(f, 1e-6, 10.0));
  }
  {
    SettingField f = choice_field(&WeightsSettings::lbc_locality,
      { LocalityFunction::Squared, LocalityFunction::Constant, LocalityFunction::Linear },
      { "squared", "constant", "linear" });
    describe(f, "lbc_locality", "--locality", "LBCLocality", "Locality (LBC)", lbc_group,
      "locality function tau of the geodesic distance: squared (the paper's) | constant (plain "
      "total variation) | linear",
      { MethodId::LBC });
    fields.push_back(f);
  }
  {
    SettingField f = number_field(&WeightsSettings::lbc_relaxed_epsilon);
    describe(f, "lbc_relaxed_epsilon", "--relaxed-epsilon", "LBCRelaxedEpsilon",
      "Relaxed TV epsilon (LBC)", lbc_group,
      "relaxed total variation epsilon (Eq. 7-8, relative to the diameter; 0: plain TV, > 0: "
      "C1 weights, less local)",
      { MethodId::LBC });
    fields.push_back(range(f, 0.0, 1e6));
  }
  {
    SettingField f = number_field(&WeightsSettings::lbc_primal_tolerance);
    describe(f, "lbc_primal_tolerance", "--primal-tolerance", "LBCPrimalTolerance",
      "Primal tolerance (LBC)", lbc_group,
      "ADMM primal stopping threshold per residual entry (Eq. 26)", { MethodId::LBC });
    fields.push_back(range(f, 1e-15, 0.5));
  }
  {
    SettingField f = number_field(&WeightsSettings::lbc_dual_tolerance);
    describe(f, "lbc_dual_tolerance", "--dual-tolerance", "LBCDualTolerance",
      "Dual tolerance (LBC)", lbc_group,
      "ADMM dual stopping threshold per residual entry (Eq. 27)", { MethodId::LBC });
    fields.push_back(range(f, 1e-15, 0.5));
  }
  {
    SettingField f = number_field(&WeightsSettings::lbc_max_iterations);
    describe(f, "lbc_max_iterations", "--max-iterations", "LBCMaximumIterations",
      "Max iterations (LBC)", lbc_group, "ADMM iteration cap; reaching it is an error",
      { MethodId::LBC });
    fields.push_back(range(f, 1, 1000000000));
  }
  {
    SettingField f = choice_field(&WeightsSettings::lbc_distance_normalization,
      { DistanceNormalization::PerControlPoint, DistanceNormalization::Global },
      { "per-control-point", "global" });
    describe(f, "lbc_distance_normalization", "--distance-normalization",
      "LBCDistanceNormalization", "Distance normalization (LBC)", lbc_group,
      "geodesic distances normalised by each control point's maximum (Eq. 12) or by one global "
      "maximum (the authors' code): per-control-point | global",
      { MethodId::LBC });
    fields.push_back(f);
  }
  {
    SettingField f = bool_field(&WeightsSettings::lbc_unconstrained);
    describe(f, "lbc_unconstrained", "--unconstrained-tv", "LBCUnconstrained",
      "Unconstrained TV (LBC)", lbc_group,
      "drop partition of unity and reproduction (the paper's unconstrained TV, §3.2): not "
      "barycentric coordinates",
      { MethodId::LBC });
    fields.push_back(f);
  }
  {
    SettingField f = choice_field(&WeightsSettings::lbc_stopping,
      { LBCStopping::Paper, LBCStopping::Converged }, { "paper", "converged" });
    describe(f, "lbc_stopping", "--stopping", "LBCStopping", "Stopping rule (LBC)", lbc_group,
      "when the ADMM stops: paper (Eqs. 26-27 as printed) | converged (BaryLab's rule, see the "
      "LBC page)",
      { MethodId::LBC });
    fields.push_back(f);
  }
  return fields;
}

std::string keys_text()
{
  std::string keys;
  for (const SettingField& f : weights_setting_fields())
    keys += (keys.empty() ? "" : ", ") + f.key;
  return keys;
}

void check_value(const SettingField& f, double value)
{
  if (!f.accepts(value))
    throw Error(ErrorCode::InvalidArgument,
      "setting '" + f.key + "': " + (std::isfinite(value) ? number_text(value) : "non-finite value " + number_text(value)) +
        " is out of range (" + f.range_text() + ")");
}

void hash_bytes(std::uint64_t& h, const void* data, std::size_t n)
{
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i)
  {
    h ^= bytes[i];
    h *= 1099511628211ull;
  }
}
} // namespace

const std::vector<MethodInfo>& method_table()
{
  // name, title, reference, controls, domain mesh, accepts a domain, linear precision,
  // non-negative, 2D, 3D, compute, face terms
  static const std::vector<MethodInfo> table = {
    { MethodId::MeanValue, "mvc", "mean value coordinates",
      "Hormann & Floater 2006 (2D); Ju, Schaefer & Warren 2005 (3D)", ControlKind::Cage, false,
      false, true, false, true, true, &mean_value_method },
    { MethodId::Harmonic, "harmonic", "harmonic coordinates", "Joshi et al. 2007",
      ControlKind::Cage, true, true, true, true, true, true, &harmonic_method },
    { MethodId::BBW, "bbw", "bounded biharmonic weights", "Jacobson et al. 2011",
      ControlKind::CageOrSkeleton, true, true, false, true, true, true, &bbw_method },
    { MethodId::TCelestial, "tcc", "T-celestial coordinates", "Cerveró et al.",
      ControlKind::FreePoints, false, false, true, true, true, true, &t_celestial_method },
    { MethodId::SCelestial, "scc", "S-celestial coordinates", "Cerveró et al.",
      ControlKind::FreePoints, false, false, true, true, true, true, &s_celestial_method },
    { MethodId::LBC, "lbc", "local barycentric coordinates", "Zhang et al. 2014",
      ControlKind::Cage, true, true, true, true, true, true, &lbc_method },
    { MethodId::Green, "green", "Green coordinates", "Lipman, Levin & Cohen-Or 2008",
      ControlKind::Cage, false, false, true, false, true, true, &green_method, true },
  };
  return table;
}

const MethodInfo& method_info(MethodId id)
{
  for (const MethodInfo& m : method_table())
    if (m.id == id)
      return m;
  throw Error(ErrorCode::InvalidArgument,
    "unknown coordinate method " + std::to_string(static_cast<int>(id)));
}

const MethodInfo* find_method(const std::string& name)
{
  for (const MethodInfo& m : method_table())
    if (m.name == name)
      return &m;
  return nullptr;
}

MethodId method_from_name(const std::string& name)
{
  if (const MethodInfo* m = find_method(name))
    return m->id;
  throw Error(ErrorCode::InvalidArgument,
    "unknown method '" + name + "' (available: " + method_names(", ") + ")");
}

std::string method_names(const std::string& separator)
{
  std::string names;
  for (const MethodInfo& m : method_table())
    names += (names.empty() ? "" : separator) + m.name;
  return names;
}

bool SettingField::applies_to(MethodId method) const
{
  return methods.empty() || std::find(methods.begin(), methods.end(), method) != methods.end();
}

double SettingField::default_value() const
{
  return get(WeightsSettings{});
}

std::string SettingField::primary_flag() const
{
  return flag.substr(0, flag.find(','));
}

std::string SettingField::range_text() const
{
  switch (kind)
  {
    case Kind::Bool:
      return "on/off";
    case Kind::Choice:
    {
      std::string text;
      for (const std::string& c : choices)
        text += (text.empty() ? "" : " | ") + c;
      return text;
    }
    default:
      break;
  }
  if (!values.empty())
  {
    std::string text = "one of ";
    for (std::size_t i = 0; i < values.size(); ++i)
      text += (i ? ", " : "") + number_text(values[i]);
    return text;
  }
  const std::string prefix = kind == Kind::Numbers ? "each " : "";
  if (maximum >= kHuge)
    return prefix + ">= " + number_text(minimum);
  return prefix + "[" + number_text(minimum) + ", " + number_text(maximum) + "]";
}

bool SettingField::accepts(double value) const
{
  if (!std::isfinite(value) || value < minimum || value > maximum)
    return false;
  if (kind == Kind::Int || kind == Kind::Choice || kind == Kind::Bool)
    if (value != std::floor(value))
      return false;
  if (!values.empty())
    return std::find(values.begin(), values.end(), value) != values.end();
  return true;
}

const std::vector<SettingField>& weights_setting_fields()
{
  static const std::vector<SettingField> fields = make_fields();
  return fields;
}

const SettingField& setting_field(const std::string& key)
{
  for (const SettingField& f : weights_setting_fields())
    if (f.key == key)
      return f;
  throw Error(ErrorCode::InvalidArgument,
    "unknown setting '" + key + "' (available: " + keys_text() + ")");
}

const SettingField* setting_field_of_property(const std::string& property)
{
  for (const SettingField& f : weights_setting_fields())
    if (f.property == property)
      return &f;
  return nullptr;
}

void set_setting(WeightsSettings& settings, const std::string& key, double value)
{
  const SettingField& f = setting_field(key);
  if (f.kind == Kind::Numbers)
    throw Error(ErrorCode::InvalidArgument, "setting '" + key + "' is a list of numbers");
  check_value(f, value);
  f.set(settings, value);
}

void set_setting(WeightsSettings& settings, const std::string& key, const std::string& choice)
{
  const SettingField& f = setting_field(key);
  if (f.kind != Kind::Choice)
    throw Error(ErrorCode::InvalidArgument, "setting '" + key + "' is not a choice");
  const auto it = std::find(f.choices.begin(), f.choices.end(), choice);
  if (it == f.choices.end())
    throw Error(ErrorCode::InvalidArgument,
      "setting '" + key + "': unknown value '" + choice + "' (available: " + f.range_text() + ")");
  f.set(settings, static_cast<double>(it - f.choices.begin()));
}

std::string choice_name(const WeightsSettings& settings, const std::string& key)
{
  const SettingField& f = setting_field(key);
  if (f.kind != Kind::Choice)
    throw Error(ErrorCode::InvalidArgument, "setting '" + key + "' is not a choice");
  return f.choices.at(static_cast<std::size_t>(f.get(settings)));
}

void validate_settings(const WeightsSettings& settings)
{
  method_info(settings.method);
  for (const SettingField& f : weights_setting_fields())
  {
    if (f.kind == Kind::Numbers)
    {
      for (double v : f.get_numbers(settings))
        check_value(f, v);
      continue;
    }
    check_value(f, f.get(settings));
  }
}

std::uint64_t settings_hash(const WeightsSettings& settings)
{
  std::uint64_t h = 1469598103934665603ull;
  const int method = static_cast<int>(settings.method);
  hash_bytes(h, &method, sizeof method);
  for (const SettingField& f : weights_setting_fields())
  {
    if (!f.affects_weights)
      continue;
    hash_bytes(h, f.key.data(), f.key.size());
    if (f.kind == Kind::Numbers)
    {
      const std::vector<double> numbers = f.get_numbers(settings);
      const std::size_t n = numbers.size();
      hash_bytes(h, &n, sizeof n);
      hash_bytes(h, numbers.data(), n * sizeof(double));
    }
    else
    {
      const double v = f.get(settings);
      hash_bytes(h, &v, sizeof v);
    }
  }
  return h;
}

bool operator==(const WeightsSettings& a, const WeightsSettings& b)
{
  if (a.method != b.method)
    return false;
  for (const SettingField& f : weights_setting_fields())
  {
    if (f.kind == Kind::Numbers ? f.get_numbers(a) != f.get_numbers(b) : f.get(a) != f.get(b))
      return false;
  }
  return true;
}

} // namespace bary
