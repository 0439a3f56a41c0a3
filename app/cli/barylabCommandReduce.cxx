// barylab reduce: sparse weights (the compact arrays that deform reads).

#include "barylabCli.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataSet.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <iostream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct ReduceArgs
{
  barylab::ReduceParameters parameters;
  std::string input, cage, output;
  bool json_out = false;
};

int run_reduce(const ReduceArgs& a)
{
  if (a.parameters.renormalize == "affine" && a.cage.empty())
    throw UsageError("--renormalize affine needs --cage (the control points the rows must reproduce)");
  check_output(a.output, OutputKind::Data, { a.input, a.cage });
  const std::string ext = vtkBaryDataIO::Extension(a.output);
  if (ext != ".vtp" && ext != ".vtu" && ext != ".vtk")
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + a.output + "': compact weights are point-data arrays, kept only by "
      ".vtp, .vtu or .vtk");
  auto data = vtkBaryDataIO::Read(a.input);
  vtkSmartPointer<vtkPolyData> cage = a.cage.empty() ? nullptr : vtkBaryDataIO::ReadPolyData(a.cage);
  json summary;
  auto reduced = barylab::ReduceWeights(data, cage, a.parameters, {}, &summary);
  vtkBaryDataIO::Write(reduced, a.output);
  summary["input"] = a.input;
  summary["output"] = a.output;
  if (a.json_out)
  {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  std::cout << "kept weights > " << summary["threshold"].get<double>() << ": K = "
            << summary["K"] << " per point at most, " << summary["mean_support"].get<double>()
            << " on average, of " << summary["controls"] << "\n"
            << "renormalization            " << summary["renormalization"].get<std::string>() << "\n"
            << "partition of unity error   " << summary["partition_error"].get<double>() << "\n"
            << "reproduction error         "
            << (summary["reproduction_error"].is_null()
                   ? std::string("(give --cage)")
                   : summary["reproduction_error"].dump() + " (relative to the controls' diameter)")
            << "\n"
            << "max dropped weight sum     " << summary["max_dropped"].get<double>() << "\n"
            << "memory                     " << 100.0 * summary["memory_fraction"].get<double>()
            << "% of the dense array (CSR: "
            << 100.0 * summary["csr_memory_fraction"].get<double>() << "%)\n";
  return 0;
}

} // namespace

void AddReduceCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<ReduceArgs>("reduce",
    "sparse weights: drop weights <= threshold, store <array>Indices/<array>Values (deform reads them)",
    run_reduce);
  command->add_option("--input,-i", a->input, "file with a dense weights point-data array")
    ->required();
  command->add_option("--cage,-c", a->cage,
    "cage / control points (point i = component i): reproduction error, needed for affine");
  command->add_option("--output,-o", a->output, "output file (.vtp, .vtu, .vtk)")->required();
  command->add_option("--threshold", a->parameters.threshold,
    "drop weights <= T (default 1e-3 / #controls)");
  command->add_option("--renormalize", a->parameters.renormalize,
       "rowsum: rows sum to one; affine: also reproduce the points (needs --cage); none")
    ->default_val(a->parameters.renormalize)
    ->check(CLI::IsMember({ "rowsum", "affine", "none" }));
  command->add_option("--array", a->parameters.weights_name, "weights array name")
    ->default_val(a->parameters.weights_name);
  command->add_flag("--keep-dense", a->parameters.keep_dense, "keep the dense array too");
  command->add_flag("--json", a->json_out, "print the summary as JSON");
}

} // namespace cli
} // namespace barylab
