// Shared by the subcommands of the barylab command line (barylabCli.h).

#include "barylabCli.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryMixedHandles.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include "core/common/error.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using nlohmann::json;

namespace barylab
{
namespace cli
{

Subcommands::Subcommands(CLI::App& app)
  : app_(app)
{
}

CLI::App* Subcommands::Add(const std::string& name, const std::string& description, RunFunction run)
{
  CLI::App* command = app_.add_subcommand(name, description);
  commands_.emplace_back(command, std::move(run));
  return command;
}

int Subcommands::Run() const
{
  for (const auto& [command, run] : commands_)
    if (*command)
      return run();
  return 1;
}

void ConfigureApp(CLI::App& app, Subcommands& subcommands)
{
  app.description("BaryLab: generalized barycentric coordinates and cage deformation.\n"
                  "Weights are written as a point-data array 'Weights' with one component per "
                  "control point (component i = cage point i, in the cage file's order).");
  app.name("barylab");
  app.require_subcommand(1);
  app.set_version_flag("--version", "barylab 0.1.0");
  AddWeightsCommand(subcommands);
  AddDeformCommand(subcommands);
  AddAnimateCommand(subcommands);
  AddStatsCommand(subcommands);
  AddReduceCommand(subcommands);
  AddFieldsCommand(subcommands);
  AddSegmentCommand(subcommands);
  AddMeshCommand(subcommands);
  AddCageCommand(subcommands);
  AddEmbedCommand(subcommands);
  AddAverageCommand(subcommands);
  AddCurveCommand(subcommands);
  AddTransferCommand(subcommands);
  AddRemeshCommand(subcommands);
  AddSplineCommand(subcommands);
  AddTransformCommands(subcommands);
  AddRenderCommand(subcommands);
  AddDemoCommand(subcommands);
}

int ParseArguments(CLI::App& app, int argc, const char* const* argv, bool quiet)
{
  const auto usage = [quiet](const std::string& what) {
    if (!quiet)
      std::cerr << "barylab: usage error: " << bary::one_line(what)
                << "\nRun with --help for more information.\n";
    return 2;
  };
  // CLI11 2.1.2 loops forever on an empty argument followed by an unknown option in a
  // subcommand with option groups (barylab weights "" --x); no option takes an empty value.
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] == '\0')
      return usage("argument " + std::to_string(i) + " is empty");
  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::Success& e) // --help, --version: their text, exit 0
  {
    return quiet ? -1 : (app.exit(e), -1);
  }
  catch (const CLI::ParseError& e)
  {
    return usage(e.what());
  }
  catch (const bary::Error& e) // a value the table's lookups refuse (an unknown --method)
  {
    if (!quiet)
      std::cerr << "barylab: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

ProgressBar::ProgressBar(bool enabled, std::string label)
  : enabled_(enabled && isatty(fileno(stderr)))
  , label_(std::move(label))
{
}

void ProgressBar::update(double f)
{
  if (!enabled_)
    return;
  const int percent = static_cast<int>(std::lround(100.0 * std::clamp(f, 0.0, 1.0)));
  if (percent == last_)
    return;
  last_ = percent;
  const int width = 40, filled = percent * width / 100;
  std::fprintf(stderr, "\r%-12s [%s%s] %3d%%", label_.c_str(), std::string(filled, '#').c_str(),
    std::string(width - filled, ' ').c_str(), percent);
  std::fflush(stderr);
  shown_ = true;
}

void ProgressBar::done()
{
  if (shown_)
    std::fprintf(stderr, "\n");
  shown_ = false;
}

RunCallbacks callbacks(ProgressBar& bar, bool quiet)
{
  RunCallbacks c;
  c.progress = [&bar](double f) { bar.update(f); };
  c.warning = [quiet](const std::string& w) {
    if (!quiet)
      std::cerr << "barylab: warning: " << w << "\n";
  };
  return c;
}

CLI::Validator FiniteRange(double lo, double hi, std::string description)
{
  if (description.empty())
  {
    std::ostringstream text;
    text << "[" << lo << ", " << hi << "]";
    description = text.str();
  }
  return CLI::Validator(
    [lo, hi, description](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value < lo ||
        value > hi)
        return "'" + text + "' is not a number in " + description;
      return {};
    },
    description, "");
}

void check_output(const std::string& path, OutputKind kind, const std::vector<std::string>& inputs)
{
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "': it is a folder");
  for (const std::string& input : inputs)
    if (!input.empty() && fs::exists(path, ec) && fs::equivalent(path, input, ec))
      throw bary::Error(bary::ErrorCode::Io,
        "cannot write '" + path + "': it is the input '" + input +
          "' (an output never overwrites an input: choose another name)");
  const std::string ext = vtkBaryDataIO::Extension(path);
  const bool ok = kind == OutputKind::Data ? vtkBaryDataIO::CanWrite(path) || IsParallelFile(path)
    : kind == OutputKind::Json             ? ext == ".json"
    : kind == OutputKind::Text             ? ext == ".txt" || ext == ".vtp" || ext == ".vtu" || ext == ".vtk"
                                           : ext == ".png";
  if (!ok)
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + path + "': unknown file extension '" + ext + "' (" +
        (kind == OutputKind::Data
            ? "writable: .vtp, .vtu, .vtk, .obj, .stl, .ply, .off, .mrk.json, .fcsv, .pvtp, .pvtu"
          : kind == OutputKind::Json ? "a summary is written as .json"
          : kind == OutputKind::Text ? "written as text (.txt) or with point arrays (.vtp, .vtu, .vtk)"
                                     : "images are written as .png") +
        ")");
  if (kind == OutputKind::Data && Distributed() && !IsParallelFile(path))
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + path + "': a distributed run writes one piece per process in VTK's "
      "parallel XML files: give a .pvtp (polygonal data) or .pvtu (unstructured grid) name");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
}

void print_summary(const json& s)
{
  const json& p = s["points"];
  std::cerr << "barylab: " << s["method"].get<std::string>() << " weights: " << p["count"]
            << " points x ";
  if (s.contains("handles") && s["handles"].contains("count"))
  {
    const nlohmann::json& h = s["handles"];
    std::cerr << h["count"] << " handles (" << h["point_handles"] << " points, " << h["bones"]
              << " bones";
    // mixed handles: the cage vertices and regions, when there are any
    if (h.value("cage_vertices", 0) > 0)
      std::cerr << ", " << h["cage_vertices"] << " cage vertices";
    if (h.value("regions", 0) > 0)
      std::cerr << ", " << h["regions"] << " regions";
    std::cerr << "; " << h["dimension"] << "D" << (h.value("shape_preservation", false) ? ", shape brush" : "") << ")";
  }
  else if (s["cage"].contains("free_points"))
  {
    std::cerr << s["cage"]["control_points"] << " free control points (" << s["cage"]["dimension"]
              << "D";
    if (s.contains("added_control_points")) // celestial hull points, the last weight columns
      std::cerr << ", " << s["added_control_points"].size() << " hull points added";
    std::cerr << ")";
  }
  else
    std::cerr << s["cage"]["control_points"] << " control points (" << s["cage"]["dimension"]
              << "D cage)";
  std::cerr << " in " << s["seconds"].get<double>() << " s; " << p["inside"] << " inside, "
            << p["outside"] << " outside, " << p["on_cage"] << " on the cage";
  if (p["undefined"].get<long long>() > 0)
    std::cerr << ", " << p["undefined"] << " undefined (NaN)";
  std::cerr << "\n";
  if (s.contains("solver"))
  {
    const json& v = s["solver"];
    std::cerr << "barylab: solver:";
    for (const char* key : { "mesh_vertices", "mesh_cells", "fast_iterations", "outer_iterations",
           "max_kkt_residual", "max_bound_violation", "partition_error", "mean_newton_iterations",
           "max_newton_iterations", "max_residual", "not_converged", "iterations",
           "primal_residual", "dual_residual", "objective", "converged", "reproduction_error",
           "solve_seconds" })
      if (v.contains(key))
        std::cerr << " " << key << " " << v[key].get<double>();
    std::cerr << "\n";
  }
}

void use_control_points(const std::string& controls, const std::string& posed_controls,
  std::string& cage, std::string& posed)
{
  if (!controls.empty())
  {
    if (posed_controls.empty())
      throw UsageError("--deformed-control-points is required with --control-points");
    cage = controls;
    posed = posed_controls;
  }
  else if (!posed_controls.empty())
    throw UsageError("--deformed-control-points goes with --control-points");
}

std::vector<double> read_user_weights(const std::string& path)
{
  return path.empty() ? std::vector<double>() : vtkBaryDataIO::ReadNumbers(path);
}

vtkSmartPointer<vtkDataSet> with_shape_preservation(
  vtkDataSet* domain, const std::string& spec, const std::string& mesh_path)
{
  if (spec.empty())
    return domain;
  vtkSmartPointer<vtkDataSet> copy;
  copy.TakeReference(domain->NewInstance());
  copy->ShallowCopy(domain);
  const char* name = vtkBaryMixedHandles::ShapePreservationArrayName();
  vtkNew<vtkDoubleArray> rho;
  rho->SetName(name);
  std::error_code ec;
  if (std::filesystem::is_regular_file(spec, ec))
  {
    const std::vector<double> values = vtkBaryDataIO::ReadNumbers(spec);
    if (static_cast<vtkIdType>(values.size()) != domain->GetNumberOfPoints())
      throw bary::Error(bary::ErrorCode::SizeMismatch,
        "--shape-preservation '" + spec + "' has " + std::to_string(values.size()) +
          " values but the domain '" + mesh_path + "' has " +
          std::to_string(domain->GetNumberOfPoints()) + " vertices (one value per vertex)");
    rho->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
    for (std::size_t i = 0; i < values.size(); ++i)
      rho->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  else
  {
    vtkDataArray* array = domain->GetPointData()->GetArray(spec.c_str());
    if (!array)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "--shape-preservation '" + spec + "' is neither a file nor a point-data array of the "
        "domain '" + mesh_path + "'");
    if (array->GetNumberOfComponents() != 1)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "--shape-preservation: the domain's array '" + spec + "' has " +
          std::to_string(array->GetNumberOfComponents()) + " components, expected 1 (rho per vertex)");
    rho->SetNumberOfTuples(array->GetNumberOfTuples());
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
      rho->SetValue(i, array->GetComponent(i, 0));
  }
  copy->GetPointData()->AddArray(rho);
  return copy;
}

void write_locality_csv(const std::string& path, const json& inputs, const char* key,
  const char* value, const std::vector<std::string>& labels)
{
  std::size_t rows = 0, longest = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i)
    if (inputs[i][key].size() > rows)
    {
      rows = inputs[i][key].size();
      longest = i;
    }
  std::ofstream out(path);
  if (!out)
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
  out.precision(17);
  out << key;
  for (const std::string& l : labels)
    out << "," << value << "_" << l;
  out << "\n";
  for (std::size_t r = 0; r < rows; ++r)
  {
    out << inputs[longest][key][r].get<double>();
    for (std::size_t i = 0; i < inputs.size(); ++i)
    {
      out << ",";
      if (r < inputs[i][value].size())
        out << inputs[i][value][r].get<double>();
    }
    out << "\n";
  }
  if (!out)
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
}

} // namespace cli
} // namespace barylab
