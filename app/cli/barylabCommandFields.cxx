// barylab fields: gradient norms of the weights and level sets of one.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct FieldsArgs
{
  std::string input, output, level_sets, array = "Weights";
  int control = 0;
  std::vector<double> levels;
  bool json_out = false;
};

/// Gradient norms of every weight and level sets of one (VTK's gradient and contour filters
/// through barylab::WeightGradientNorms / WeightLevelSets).
int run_fields(const FieldsArgs& a)
{
  if (a.output.empty() && a.level_sets.empty())
    throw UsageError("give --output (gradient norms) and/or --level-sets (contours)");
  if (!a.output.empty())
  {
    check_output(a.output, OutputKind::Data, { a.input });
    const std::string ext = vtkBaryDataIO::Extension(a.output);
    if (ext != ".vtp" && ext != ".vtu" && ext != ".vtk")
      throw bary::Error(bary::ErrorCode::Io,
        "cannot write '" + a.output + "': gradient norms are a point-data array, kept only by "
        ".vtp, .vtu or .vtk");
  }
  if (!a.level_sets.empty())
    check_output(a.level_sets, OutputKind::Data, { a.input, a.output });
  auto data = vtkBaryDataIO::Read(a.input);
  json summary;
  summary["input"] = a.input;
  if (!a.output.empty())
  {
    auto with = barylab::WeightGradientNorms(data, a.array, &summary);
    vtkBaryDataIO::Write(with, a.output);
    summary["output"] = a.output;
  }
  if (!a.level_sets.empty())
  {
    auto lines = barylab::WeightLevelSets(data, a.control, a.levels, a.array);
    vtkBaryDataIO::Write(lines, a.level_sets);
    const int n = data->GetPointData()->GetArray(a.array.c_str())->GetNumberOfComponents();
    summary["level_sets"] = { { "file", a.level_sets }, { "control", a.control },
      { "levels", a.levels.empty() ? std::vector<double>{ 1e-3 / n } : a.levels },
      { "points", lines->GetNumberOfPoints() }, { "cells", lines->GetNumberOfCells() } };
  }
  if (a.json_out)
  {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  if (summary.contains("gradient_norm"))
  {
    const auto& g = summary["gradient_norm"];
    double top = 0.0;
    for (const auto& v : g["max"])
      top = std::max(top, v.get<double>());
    std::cout << "wrote " << a.output << ": array " << g["array"].get<std::string>() << " ("
              << g["max"].size() << " components), largest |grad w| " << top << "\n";
  }
  if (summary.contains("level_sets"))
    std::cout << "wrote " << a.level_sets << ": " << summary["level_sets"]["cells"]
              << " cells of the level sets " << summary["level_sets"]["levels"].dump()
              << " of control " << a.control << "\n";
  return 0;
}

} // namespace

void AddFieldsCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<FieldsArgs>("fields",
    "gradient norms |grad w_i| of all weights and level sets of one (VTK's gradient and contour "
    "filters)",
    run_fields);
  command->add_option("--input,-i", a->input, "weights at the vertices of a mesh (.vtp/.vtu/.vtk)")
    ->required();
  command->add_option("--output,-o", a->output,
    "copy of the input with <array>GradientNorm (one component per weight)");
  command->add_option("--level-sets", a->level_sets, "level sets of --control (lines / surfaces)");
  command->add_option("--control", a->control, "weights component of the level sets")
    ->default_val(0);
  command->add_option("--level", a->levels, "level value (repeatable; default 1e-3 / #controls)");
  command->add_option("--array", a->array, "weights array name")->default_val(a->array);
  command->add_flag("--json", a->json_out, "print the summary as JSON");
}

} // namespace cli
} // namespace barylab
