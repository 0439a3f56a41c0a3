// barylab stats: property statistics of a weights file, or (--locality) the locality
// statistics of several.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataSet.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct StatsArgs
{
  std::vector<std::string> inputs;
  std::string cage, array = "Weights";
  double threshold = -1.0;
  bool json_out = false;
  int cage_dimension = 0;
  // --locality
  bool locality = false, no_measure = false;
  std::string csv_prefix, json_file;
};

/// Column labels for several inputs: the file names without folder and extension, made unique.
std::vector<std::string> input_labels(const std::vector<std::string>& inputs)
{
  std::vector<std::string> labels;
  for (const std::string& f : inputs)
  {
    std::string label = fs::path(f).stem().string();
    const std::string base = label;
    for (int n = 2; std::find(labels.begin(), labels.end(), label) != labels.end(); ++n)
      label = base + "_" + std::to_string(n);
    labels.push_back(label);
  }
  return labels;
}

int run_locality(const StatsArgs& a)
{
  if (!a.cage.empty())
    throw UsageError("--locality needs no --cage (use 'barylab reduce --cage' for reproduction)");
  if (!a.json_file.empty())
    check_output(a.json_file, OutputKind::Json);
  if (!a.csv_prefix.empty())
  {
    const fs::path parent = fs::path(a.csv_prefix).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
      throw bary::Error(bary::ErrorCode::Io,
        "cannot write '" + a.csv_prefix + "_P.csv': folder '" + parent.string() + "' does not exist");
  }
  const std::vector<std::string> labels = input_labels(a.inputs);
  json inputs = json::array();
  for (std::size_t i = 0; i < a.inputs.size(); ++i)
  {
    auto data = vtkBaryDataIO::Read(a.inputs[i]);
    json s;
    try
    {
      s = barylab::LocalityStatisticsJson(data, a.array, a.threshold, !a.no_measure);
    }
    catch (const bary::Error& e)
    {
      throw bary::Error(e.code(), "'" + a.inputs[i] + "': " + e.what());
    }
    s["input"] = a.inputs[i];
    s["label"] = labels[i];
    inputs.push_back(s);
  }
  const std::size_t nt = inputs[0]["t"].size();
  for (const json& s : inputs)
    if (s["t"] != inputs[0]["t"] || s["t"].size() != nt)
      throw bary::Error(bary::ErrorCode::Internal, "inputs sampled P(t) at different t");
  json result;
  result["locality"] = inputs;
  if (!a.csv_prefix.empty())
  {
    write_locality_csv(a.csv_prefix + "_P.csv", inputs, "t", "P", labels);
    write_locality_csv(a.csv_prefix + "_Q.csv", inputs, "k", "Q", labels);
  }
  if (!a.json_file.empty())
    barylab::WriteJson(result, a.json_file);
  if (a.json_out)
  {
    std::cout << result.dump(2) << "\n";
    return 0;
  }
  for (const json& s : inputs)
  {
    std::cout << s["input"].get<std::string>() << ": " << s["points"] << " points x "
              << s["controls"] << " controls\n"
              << "  threshold " << s["threshold"].get<double>() << ", measure "
              << s["measure"].get<std::string>() << "\n"
              << "  support (weights > threshold per point): mean "
              << s["mean_support"].get<double>() << ", max " << s["max_support"].get<double>()
              << "\n  Q(k), k = 1..max support:";
    const int kmax = static_cast<int>(s["max_support"].get<double>());
    for (int k = 0; k < kmax && k < static_cast<int>(s["Q"].size()); ++k)
      std::cout << " " << s["Q"][static_cast<std::size_t>(k)].get<double>();
    std::cout << "\n  P(t) at t = 1e-6, 1e-4, 1e-2, 1:";
    for (std::size_t j = 0; j < s["t"].size(); ++j)
    {
      const double t = s["t"][j].get<double>();
      for (double want : { 1e-6, 1e-4, 1e-2, 1.0 })
        if (std::abs(t - want) <= 1e-9 * want)
          std::cout << " " << s["P"][j].get<double>();
    }
    std::cout << "\n";
  }
  return 0;
}

int run_stats(const StatsArgs& a)
{
  if (a.locality)
    return run_locality(a);
  if (a.inputs.size() != 1)
    throw UsageError("several --input files are for --locality");
  if (!a.csv_prefix.empty() || !a.json_file.empty() || a.no_measure)
    throw UsageError("--csv, --json-output and --no-measure go with --locality");
  // the points of a distributed run's file once each (those written in two pieces are flagged)
  auto data = OwnedPoints(vtkBaryDataIO::Read(a.inputs.front()));
  vtkSmartPointer<vtkPolyData> cage = a.cage.empty() ? nullptr : vtkBaryDataIO::ReadPolyData(a.cage);
  json s = barylab::WeightStatisticsJson(data, a.array, cage, a.threshold, a.cage_dimension);
  if (a.json_out)
  {
    std::cout << s.dump(2) << "\n";
    return 0;
  }
  std::cout << "points                     " << s["points"] << "\n"
            << "control points             " << s["controls"] << "\n"
            << "min / max weight           " << s["min_weight"] << " / " << s["max_weight"] << "\n"
            << "negative weights           " << s["negative_weights"] << "\n"
            << "non-finite rows            " << s["non_finite_rows"] << "\n"
            << "partition of unity error   max " << s["partition_of_unity"]["max_error"]
            << ", mean " << s["partition_of_unity"]["mean_error"] << "\n";
  if (s.contains("reproduction"))
    std::cout << "reproduction error         max " << s["reproduction"]["max_error"] << ", mean "
              << s["reproduction"]["mean_error"] << " (relative to the cage diagonal"
              << (s["reproduction"].contains("face_coefficients")
                     ? "; with the " + s["reproduction"]["face_coefficients"].dump() +
                       " face coefficients' normal terms (Green coordinates)"
                     : std::string())
              << ")\n";
  std::cout << "weights > " << s["significant"]["threshold"] << " per point: mean "
            << s["significant"]["mean_per_point"] << ", max " << s["significant"]["max_per_point"]
            << "\n";
  return 0;
}

} // namespace

void AddStatsCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<StatsArgs>("stats",
    "property statistics of a weights file", run_stats);
  command->add_option("--input,-i", a->inputs,
    "file with a weights point-data array (several with --locality: --input A --input B)")
    ->required();
  command->add_option("--cage,-c", a->cage, "the cage, for the reproduction error");
  command->add_option("--array", a->array, "weights array name")->default_val(a->array);
  command->add_option("--threshold", a->threshold,
    "a weight is significant above this (default 1e-3 / #controls)");
  command->add_option("--cage-dimension", a->cage_dimension, "0 automatic, 2, 3")
    ->check(CLI::IsMember({ 0, 2, 3 }));
  command->add_flag("--json", a->json_out, "print JSON");
  command->add_flag("--locality", a->locality,
    "locality statistics (Zhang et al. 2014, Eq. 19-21): P(t), Q(k), mean/max support");
  command->add_option("--csv", a->csv_prefix,
    "--locality: write PREFIX_P.csv and PREFIX_Q.csv (one column per input)");
  command->add_option("--json-output", a->json_file, "--locality: write the JSON to this file");
  command->add_flag("--no-measure", a->no_measure,
    "--locality: count every point the same (default: lumped area/volume on a domain mesh)");
}

} // namespace cli
} // namespace barylab
