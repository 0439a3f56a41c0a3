#include "barylabViewerParameters.h"

#include "vtkBaryCoordinates.h"

#include "core/error.h"

#include <algorithm>
#include <sstream>

namespace barylab
{
namespace viewer
{
namespace
{
using json = nlohmann::json;
using Kind = ParameterField::Kind;

/// A row bound to a member of WeightsParameters.
template <class T>
ParameterField field(const std::string& key, const std::string& label, Kind kind,
  T WeightsParameters::*member, const std::string& cli, const std::string& tooltip,
  std::vector<std::string> methods = {}, double lo = 0.0, double hi = 0.0,
  std::vector<std::string> choices = {})
{
  ParameterField f;
  f.key = key;
  f.label = label;
  f.kind = kind;
  f.cli_flag = cli;
  f.tooltip = tooltip;
  f.methods = std::move(methods);
  f.minimum = lo;
  f.maximum = hi;
  f.choices = std::move(choices);
  f.get = [member](const WeightsParameters& p) { return json(p.*member); };
  f.set = [member, key](WeightsParameters& p, const json& value) {
    try
    {
      p.*member = value.get<T>();
    }
    catch (const json::exception&)
    {
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "parameter '" + key + "': " + value.dump() + " has the wrong type");
    }
  };
  return f;
}
/// The TCC user weights s_i (Eq. 8) as a String row: "1, 2.5, 1" (commas or spaces); an
/// empty text means none. Sessions may also hold a JSON array.
ParameterField user_weights_field()
{
  ParameterField f;
  f.key = "user_weights";
  f.label = "User weights s_i (TCC)";
  f.kind = Kind::String;
  f.tooltip = "T-celestial coordinates' user weights s_i >= 0 (Eq. 8), one per control point, "
              "separated by commas or spaces; empty: all zero (Eq. 7). (Command line: "
              "--user-weights FILE with the same numbers.)";
  f.methods = { "tcc" };
  f.get = [](const WeightsParameters& p) {
    std::ostringstream out;
    out.precision(17);
    for (std::size_t i = 0; i < p.user_weights.size(); ++i)
      out << (i ? ", " : "") << p.user_weights[i];
    return json(out.str());
  };
  f.set = [](WeightsParameters& p, const json& value) {
    std::vector<double> weights;
    if (value.is_array())
    {
      for (const json& v : value)
      {
        if (!v.is_number())
          throw bary::Error(bary::ErrorCode::InvalidArgument,
            "parameter 'user_weights': " + v.dump() + " is not a number");
        weights.push_back(v.get<double>());
      }
    }
    else if (value.is_string())
    {
      std::string text = value.get<std::string>();
      std::replace(text.begin(), text.end(), ',', ' ');
      std::istringstream in(text);
      std::string token;
      while (in >> token)
      {
        std::size_t used = 0;
        double v = 0.0;
        try
        {
          v = std::stod(token, &used);
        }
        catch (const std::exception&)
        {
          used = 0;
        }
        if (used != token.size())
          throw bary::Error(bary::ErrorCode::InvalidArgument,
            "parameter 'user_weights': '" + token + "' is not a number");
        weights.push_back(v);
      }
    }
    else
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "parameter 'user_weights': " + value.dump() + " is neither a list of numbers nor text");
    p.user_weights = std::move(weights);
  };
  return f;
}
} // namespace

bool ParameterField::AppliesTo(const std::string& method) const
{
  return methods.empty() || std::find(methods.begin(), methods.end(), method) != methods.end();
}

const std::vector<ParameterField>& WeightsParameterFields()
{
  // Rows in panel order. Ranges match the command line's checks.
  static const std::vector<ParameterField> fields = {
    field("cage_dimension", "Cage dimension", Kind::Choice, &WeightsParameters::cage_dimension,
      "--cage-dimension", "how to read the cage: 0 automatic, 2, 3", {}, 0, 3, { "0", "2", "3" }),
    field("boundary_tolerance", "Boundary tolerance", Kind::Double,
      &WeightsParameters::boundary_tolerance, "--boundary-tolerance",
      "points closer to the cage than this fraction of its diagonal count as on the cage", {},
      0.0, 1e-3),
    field("validate_cage", "Validate cage", Kind::Bool, &WeightsParameters::validate_cage, "",
      "check that the cage is closed, manifold and consistently oriented"),
    field("threads", "Threads", Kind::Int, &WeightsParameters::threads, "--threads",
      "0 = all cores; results do not depend on it", {}, 0, 1024),
    field("target_cells", "Mesh cells", Kind::Int, &WeightsParameters::target_cells, "--cells",
      "approximate number of cells of the domain mesh (0: 3000 in 2D, 20000 in 3D)",
      { "harmonic", "bbw", "lbc" }, 0, 50000000),
    field("max_cell_size", "Max cell size", Kind::Double, &WeightsParameters::max_cell_size,
      "--max-volume", "maximum tetrahedron volume / triangle area (overrides the cell count)",
      { "harmonic", "bbw", "lbc" }, 0.0, 1e9),
    field("insert_points", "Insert points", Kind::Bool, &WeightsParameters::insert_points,
      "--insert-points", "make the points mesh vertices (exact finite-element values there)",
      { "harmonic", "bbw", "lbc" }),
    field("outside", "Outside points", Kind::Choice, &WeightsParameters::outside, "--outside",
      "points outside the cage/domain: error | nearest | nan", { "harmonic", "bbw", "lbc" }, 0,
      0, { "error", "nearest", "nan" }),
    field("bbw_fast", "Fast BBW", Kind::Bool, &WeightsParameters::bbw_fast, "--fast",
      "solve each handle alone, then normalize (the paper's fast mode)", { "bbw" }),
    field("lambda", "Lambda (SCC)", Kind::Double, &WeightsParameters::lambda, "--lambda",
      "wrapping-sphere parameter (> 1; the coordinates do not depend on it)", { "scc" },
      1.000001, 1e6),
    field("lbc_locality", "Locality (LBC)", Kind::Choice, &WeightsParameters::lbc_locality,
      "--locality",
      "locality function tau of the geodesic distance: squared (the paper's) | constant (plain "
      "total variation) | linear",
      { "lbc" }, 0, 0, { "squared", "constant", "linear" }),
    field("lbc_relaxed_epsilon", "Relaxed TV epsilon", Kind::Double,
      &WeightsParameters::lbc_relaxed_epsilon, "--relaxed-epsilon",
      "relaxed total variation (Eq. 7-8; 0: plain TV, > 0: C1 weights, less local)", { "lbc" },
      0.0, 1e6),
    field("lbc_primal_tolerance", "Primal tolerance", Kind::Double,
      &WeightsParameters::lbc_primal_tolerance, "--primal-tolerance",
      "ADMM primal stopping threshold per residual entry (Eq. 26)", { "lbc" }, 1e-15, 0.5),
    field("lbc_dual_tolerance", "Dual tolerance", Kind::Double,
      &WeightsParameters::lbc_dual_tolerance, "--dual-tolerance",
      "ADMM dual stopping threshold per residual entry (Eq. 27)", { "lbc" }, 1e-15, 0.5),
    field("lbc_max_iterations", "Max iterations", Kind::Int,
      &WeightsParameters::lbc_max_iterations, "--max-iterations",
      "ADMM iteration cap; reaching it is an error", { "lbc" }, 1, 1000000000),
    field("lbc_distance_normalization", "Distance normalization", Kind::Choice,
      &WeightsParameters::lbc_distance_normalization, "--distance-normalization",
      "geodesic distances normalised per control point (Eq. 12) or globally (the authors' code)",
      { "lbc" }, 0, 0, { "per-control-point", "global" }),
    field("lbc_unconstrained", "Unconstrained TV", Kind::Bool,
      &WeightsParameters::lbc_unconstrained, "--unconstrained-tv",
      "drop partition of unity and reproduction (§3.2): not barycentric coordinates", { "lbc" }),
    user_weights_field(),
  };
  return fields;
}

std::vector<std::string> MethodNames()
{
  std::vector<std::string> names;
  for (int m = 0; m < vtkBaryCoordinates::NUMBER_OF_METHODS; ++m)
    if (const char* name = vtkBaryCoordinates::GetMethodName(m))
      names.emplace_back(name);
  return names;
}

json ParametersToJson(const WeightsParameters& parameters)
{
  json j;
  j["method"] = parameters.method;
  for (const ParameterField& f : WeightsParameterFields())
    j[f.key] = f.get(parameters);
  return j;
}

WeightsParameters ParametersFromJson(const json& j, WeightsParameters base)
{
  if (!j.is_object())
    throw bary::Error(bary::ErrorCode::InvalidArgument, "parameters must be a JSON object");
  if (j.contains("method"))
  {
    if (!j["method"].is_string())
      throw bary::Error(bary::ErrorCode::InvalidArgument, "parameter 'method' must be a string");
    base.method = j["method"].get<std::string>();
  }
  for (const ParameterField& f : WeightsParameterFields())
    if (j.contains(f.key))
      f.set(base, j[f.key]);
  return base;
}

std::vector<std::string> CommandLineFlags(const WeightsParameters& parameters)
{
  std::vector<std::string> flags = { "--method", parameters.method };
  const WeightsParameters defaults;
  for (const ParameterField& f : WeightsParameterFields())
  {
    if (f.cli_flag.empty() || !f.AppliesTo(parameters.method))
      continue;
    const json value = f.get(parameters);
    if (value == f.get(defaults))
      continue;
    if (f.kind == Kind::Bool)
    {
      if (value.get<bool>())
        flags.push_back(f.cli_flag);
      continue;
    }
    flags.push_back(f.cli_flag);
    if (value.is_string())
      flags.push_back(value.get<std::string>());
    else if (value.is_number_float())
    {
      std::ostringstream s;
      s.precision(17);
      s << value.get<double>();
      flags.push_back(s.str());
    }
    else
      flags.push_back(value.dump());
  }
  return flags;
}

} // namespace viewer
} // namespace barylab
