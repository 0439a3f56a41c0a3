#pragma once
/// @file barylabViewerParameters.h
/// The viewer's view of BaryLab's one settings table (bary::weights_setting_fields, in
/// core/coordinates/weight_methods.h): the parameter panel, the session files and the "Run in terminal"
/// command line are generated from its rows. A new method or setting is a row there, not GUI
/// code.

#include "barylabPipeline.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace barylab
{
namespace viewer
{

/// One editable field of WeightsParameters.
struct ParameterField
{
  enum class Kind
  {
    Bool,
    Int,
    Double,
    Choice, ///< one of @ref choices (a string)
    String
  };
  std::string key;      ///< session JSON key (the WeightsParameters member's name)
  std::string label;    ///< panel label
  Kind kind = Kind::Int;
  std::string cli_flag; ///< the `barylab weights` flag ("" when the command line has none)
  std::string tooltip;
  double minimum = 0.0; ///< Int / Double
  double maximum = 0.0; ///< Int / Double
  std::vector<std::string> choices; ///< Choice
  /// Methods the field applies to (bary::method_table names); empty = all.
  std::vector<std::string> methods;
  std::function<nlohmann::json(const WeightsParameters&)> get;
  std::function<void(WeightsParameters&, const nlohmann::json&)> set;

  bool AppliesTo(const std::string& method) const;
};

/// Every field the panel shows, in panel order (not the method: it has its own selector).
const std::vector<ParameterField>& WeightsParameterFields();

/// The method names BaryLab's filters know, in bary::method_table order (a method added to the
/// filters appears here without viewer changes).
std::vector<std::string> MethodNames();

/// {"method": ..., <key>: value ...} for every field.
nlohmann::json ParametersToJson(const WeightsParameters& parameters);
/// @p json's fields applied to @p base (unknown keys are ignored, a wrong type throws
/// bary::Error(InvalidArgument) naming the key).
WeightsParameters ParametersFromJson(const nlohmann::json& json, WeightsParameters base = {});

/// The command-line flags that reproduce @p parameters (method first, then every field that
/// applies to the method and differs from its default), e.g. {"--method", "harmonic",
/// "--cells", "5000"}.
std::vector<std::string> CommandLineFlags(const WeightsParameters& parameters);

} // namespace viewer
} // namespace barylab
