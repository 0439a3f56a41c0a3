#include "barylabViewerParameters.h"

#include "core/coordinates/weight_methods.h"

#include "core/common/error.h"

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

/// Runs @p set, turning a JSON type error into bary::Error naming the key.
template <class F>
void with_type_check(const std::string& key, const json& value, F set)
{
  try
  {
    set();
  }
  catch (const json::exception&)
  {
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "parameter '" + key + "': " + value.dump() + " has the wrong type");
  }
}

/// The TCC user weights s_i (Eq. 8) as a String row: "1, 2.5, 1" (commas or spaces); an
/// empty text means none. Sessions may also hold a JSON array.
void bind_numbers(ParameterField& f, const bary::SettingField& setting)
{
  f.kind = Kind::String;
  f.get = [setting](const WeightsParameters& p) {
    std::ostringstream out;
    out.precision(17);
    const std::vector<double> numbers = setting.get_numbers(p);
    for (std::size_t i = 0; i < numbers.size(); ++i)
      out << (i ? ", " : "") << numbers[i];
    return json(out.str());
  };
  const std::string key = setting.key;
  f.set = [setting, key](WeightsParameters& p, const json& value) {
    std::vector<double> weights;
    if (value.is_array())
    {
      for (const json& v : value)
      {
        if (!v.is_number())
          throw bary::Error(bary::ErrorCode::InvalidArgument,
            "parameter '" + key + "': " + v.dump() + " is not a number");
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
            "parameter '" + key + "': '" + token + "' is not a number");
        weights.push_back(v);
      }
    }
    else
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "parameter '" + key + "': " + value.dump() + " is neither a list of numbers nor text");
    setting.set_numbers(p, std::move(weights));
  };
}

/// The panel row of one setting of the table (bary::weights_setting_fields).
ParameterField row_of(const bary::SettingField& setting)
{
  ParameterField f;
  f.key = setting.key;
  f.label = setting.label;
  f.cli_flag = setting.primary_flag();
  f.tooltip = setting.help + " (" + setting.range_text() + ")";
  f.minimum = setting.minimum;
  f.maximum = setting.maximum;
  for (bary::MethodId m : setting.methods)
    f.methods.push_back(bary::method_info(m).name);
  const std::string key = setting.key;
  using SKind = bary::SettingField::Kind;
  switch (setting.kind)
  {
    case SKind::Numbers:
      bind_numbers(f, setting);
      return f;
    case SKind::Bool:
      f.kind = Kind::Bool;
      f.get = [setting](const WeightsParameters& p) { return json(setting.get(p) != 0.0); };
      f.set = [key](WeightsParameters& p, const json& value) {
        with_type_check(key, value, [&] { bary::set_setting(p, key, value.get<bool>() ? 1.0 : 0.0); });
      };
      return f;
    case SKind::Choice:
      f.kind = Kind::Choice;
      f.choices = setting.choices;
      f.get = [key](const WeightsParameters& p) { return json(bary::choice_name(p, key)); };
      f.set = [key](WeightsParameters& p, const json& value) {
        with_type_check(key, value, [&] { bary::set_setting(p, key, value.get<std::string>()); });
      };
      return f;
    case SKind::Int:
      f.kind = setting.values.empty() ? Kind::Int : Kind::Choice; // a few allowed values: a list
      for (double v : setting.values)
        f.choices.push_back(std::to_string(static_cast<int>(v)));
      f.get = [setting](const WeightsParameters& p) { return json(static_cast<int>(setting.get(p))); };
      f.set = [key](WeightsParameters& p, const json& value) {
        with_type_check(key, value, [&] { bary::set_setting(p, key, value.get<int>()); });
      };
      return f;
    case SKind::Double:
      f.kind = Kind::Double;
      f.get = [setting](const WeightsParameters& p) { return json(setting.get(p)); };
      f.set = [key](WeightsParameters& p, const json& value) {
        with_type_check(key, value, [&] { bary::set_setting(p, key, value.get<double>()); });
      };
      return f;
  }
  return f;
}
} // namespace

bool ParameterField::AppliesTo(const std::string& method) const
{
  return methods.empty() || std::find(methods.begin(), methods.end(), method) != methods.end();
}

const std::vector<ParameterField>& WeightsParameterFields()
{
  // One row per setting of the core table, in its order.
  static const std::vector<ParameterField> fields = [] {
    std::vector<ParameterField> rows;
    for (const bary::SettingField& setting : bary::weights_setting_fields())
      rows.push_back(row_of(setting));
    return rows;
  }();
  return fields;
}

std::vector<std::string> MethodNames()
{
  std::vector<std::string> names;
  for (const bary::MethodInfo& m : bary::method_table())
    names.push_back(m.name);
  return names;
}

json ParametersToJson(const WeightsParameters& parameters)
{
  json j;
  j["method"] = MethodName(parameters);
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
    base.method = bary::method_from_name(j["method"].get<std::string>());
  }
  for (const ParameterField& f : WeightsParameterFields())
    if (j.contains(f.key))
      f.set(base, j[f.key]);
  return base;
}

std::vector<std::string> CommandLineFlags(const WeightsParameters& parameters)
{
  std::vector<std::string> flags = { "--method", MethodName(parameters) };
  const WeightsParameters defaults;
  for (const ParameterField& f : WeightsParameterFields())
  {
    if (f.cli_flag.empty() || !f.AppliesTo(MethodName(parameters)))
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
