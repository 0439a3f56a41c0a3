// The flags of a weights computation, shared by 'weights', 'deform' and 'animate'
// (barylabCli.h).

#include "barylabCli.h"

#include "core/coordinates/weight_methods.h"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <map>
#include <sstream>

namespace barylab
{
namespace cli
{

namespace
{
/// A CLI11 validator from a setting's own range (shown in --help as the row's range text).
CLI::Validator range_of(const bary::SettingField& field)
{
  return CLI::Validator(
    [field](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value) || !field.accepts(value))
        return "'" + text + "' is out of range (" + field.range_text() + ")";
      return {};
    },
    field.range_text(), "");
}

std::string default_text(const bary::SettingField& field)
{
  std::ostringstream out;
  out << field.default_value();
  return out.str();
}
} // namespace

void add_method_options(CLI::App* cmd, WeightsParameters& p)
{
  // --method: an unknown name is a bad input (exit 1, listing the methods), as it always was
  cmd->add_option_function<std::string>(
       "--method,-m",
       [&p](const std::string& name) { p.method = bary::method_from_name(name); },
       "coordinate method: " + bary::method_names())
    ->default_str(MethodName(p));
  cmd->add_option("--weights-name", p.weights_name, "name of the weights point-data array")
    ->default_val(p.weights_name);
  // Every other setting with a flag, from the one settings table (core/coordinates/weight_methods.h): its
  // help, range and default are the table's.
  std::map<std::string, CLI::Option_group*> groups;
  for (const bary::SettingField& field : bary::weights_setting_fields())
  {
    if (field.flag.empty())
      continue;
    CLI::App* group = cmd;
    if (!field.group.empty())
    {
      CLI::Option_group*& g = groups[field.group];
      if (!g)
      {
        std::vector<std::string> names;
        for (bary::MethodId m : field.methods)
          names.push_back(bary::method_info(m).name);
        std::string methods;
        for (const std::string& n : names)
          methods += (methods.empty() ? "" : "|") + n;
        g = cmd->add_option_group(field.group, "--method " + methods);
      }
      group = g;
    }
    const std::string key = field.key;
    switch (field.kind)
    {
      case bary::SettingField::Kind::Bool:
        group->add_flag_function(
          field.flag, [&p, key](std::int64_t count) { bary::set_setting(p, key, count > 0 ? 1.0 : 0.0); },
          field.help);
        break;
      case bary::SettingField::Kind::Choice:
        group
          ->add_option_function<std::string>(
            field.flag, [&p, key](const std::string& choice) { bary::set_setting(p, key, choice); },
            field.help)
          ->default_str(bary::choice_name(p, key))
          ->check(CLI::IsMember(field.choices));
        break;
      case bary::SettingField::Kind::Int:
      case bary::SettingField::Kind::Double:
        group
          ->add_option_function<double>(
            field.flag, [&p, key](const double& value) { bary::set_setting(p, key, value); },
            field.help)
          ->type_name(field.kind == bary::SettingField::Kind::Int ? "INT" : "FLOAT")
          ->default_str(default_text(field))
          ->check(range_of(field));
        break;
      case bary::SettingField::Kind::Numbers:
        break; // the command lines read them from a file (--user-weights)
    }
  }
}

/// BBW inputs: --cage (cage handles) or --handles with --mesh (a skeleton in a domain).
/// Celestial coordinates: --control-points (passed here as @p cage with @p controls set).
void check_bbw_inputs(bary::MethodId id, const std::string& cage,
  const std::string& handles, const std::string& mesh, bool controls)
{
  const std::string method = bary::method_info(id).name;
  if (id != bary::MethodId::BBW)
  {
    const bool takes_mesh = bary::method_info(id).accepts_domain;
    if (!handles.empty() || (!mesh.empty() && !takes_mesh))
      throw UsageError(takes_mesh ? "--handles is for --method bbw"
                                  : "--handles and --mesh are for --method bbw (--mesh also for "
                                    "harmonic and lbc)");
    const bool point_based = barylab::IsPointBasedMethod(id);
    if (point_based && !controls)
      throw UsageError("--method " + method + " takes free control points: --control-points "
                       "FILE (not --cage)");
    if (!point_based && controls)
      throw UsageError("--control-points is for --method tcc|scc; --method " + method +
        " takes --cage");
    if (cage.empty())
      throw UsageError(std::string(point_based ? "--control-points" : "--cage") +
        " is required for --method " + method);
    return;
  }
  if (controls)
    throw UsageError("--control-points is for --method tcc|scc");
  if (!cage.empty() && (!handles.empty() || !mesh.empty()))
    throw UsageError("--method bbw takes either --cage (cage handles) or --handles with --mesh "
                     "(points and bones in a domain), not both");
  if (cage.empty() && (handles.empty() || mesh.empty()))
    throw UsageError("--method bbw needs --handles HANDLES and --mesh DOMAIN (or --cage CAGE for "
                     "cage handles)");
}

} // namespace cli
} // namespace barylab
