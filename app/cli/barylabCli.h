#pragma once
/// @file barylabCli.h
/// What the subcommands of the barylab command line share: the subcommand registry that `main`
/// dispatches through, the usage error (exit code 2), the progress bar, output checks, the
/// weights summary, the method options and the small input readers.
///
/// A subcommand is one file, barylabCommand<Name>.cxx, defining Add<Name>Command() (declared
/// below): it declares the subcommand with Subcommands::Add (name, description, run function),
/// then its options on the CLI::App that Add returns, bound to the arguments struct that the run
/// function receives. `main` (barylab.cxx) calls every Add<Name>Command in --help order, parses,
/// calls Subcommands::Run and turns exceptions into exit codes.

#include "barylabDistributed.h"
#include "barylabPipeline.h"

#include "vtkDataSet.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <stdexcept>
#include <CLI/CLI.hpp>

#include <string>
#include <utility>
#include <vector>

namespace CLI
{
class App;
}

namespace barylab
{
namespace cli
{

/// A command line that parses but does not make sense (exit code 2, like a parse error).
struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// The subcommands of a CLI::App and what each runs once the command line is parsed.
class Subcommands
{
public:
  /// What a subcommand does with its parsed options: returns the exit code (0); throws UsageError
  /// for a command line that makes no sense (exit 2), bary::Error or another std::exception for
  /// bad input or a failed computation (exit 1).
  using RunFunction = std::function<int()>;

  explicit Subcommands(CLI::App& app);

  /// Declares subcommand @p name (listed by --help in the order of the calls) that runs @p run;
  /// returns it, to add its options to.
  CLI::App* Add(const std::string& name, const std::string& description, RunFunction run);

  /// The usual case: a subcommand whose options are bound to the members of one @p Args
  /// (made here) and that runs `run(args)`, @p run taking an Args or a const Args&. Returns the
  /// subcommand and the Args, for `const auto [command, a] = subcommands.Add<Args>(...)`.
  template <class Args, class Run>
  std::pair<CLI::App*, std::shared_ptr<Args>> Add(
    const std::string& name, const std::string& description, Run run)
  {
    auto args = std::make_shared<Args>();
    return { Add(name, description, [args, run] { return run(*args); }), args };
  }

  /// Runs the subcommand given on the parsed command line; 1 when none was.
  int Run() const;

private:
  CLI::App& app_;
  std::vector<std::pair<CLI::App*, RunFunction>> commands_;
};

/// The barylab command line on @p app: its description, --version and every subcommand, in
/// --help order (the one list `main` and the parsing fuzzer use).
void ConfigureApp(CLI::App& app, Subcommands& subcommands);

/// Parses @p argv into @p app (set up by ConfigureApp). Returns 0 when the command line parsed,
/// -1 when --help or --version answered it (exit 0), 2 for a usage error (one line "barylab:
/// usage error: ..." on stderr, printable whatever the arguments held), 1 for a value the
/// method table refuses. Prints nothing when @p quiet.
int ParseArguments(CLI::App& app, int argc, const char* const* argv, bool quiet = false);

/// @name The subcommands, in --help order; each in barylabCommand<Name>.cxx.
/// @{
void AddWeightsCommand(Subcommands& subcommands);
void AddDeformCommand(Subcommands& subcommands);
void AddAnimateCommand(Subcommands& subcommands);
void AddStatsCommand(Subcommands& subcommands);
void AddReduceCommand(Subcommands& subcommands);
void AddFieldsCommand(Subcommands& subcommands);
/// barylab segment (barylabCommandSegment.cxx).
void AddSegmentCommand(Subcommands& subcommands);
void AddMeshCommand(Subcommands& subcommands);
/// barylab cage (barylabCommandCage.cxx).
void AddCageCommand(Subcommands& subcommands);
void AddEmbedCommand(Subcommands& subcommands);
void AddAverageCommand(Subcommands& subcommands);
void AddCurveCommand(Subcommands& subcommands);
void AddTransferCommand(Subcommands& subcommands);
void AddRemeshCommand(Subcommands& subcommands);
void AddSplineCommand(Subcommands& subcommands);

/// The surface of --mesh with its embedding: read from --embedding, or computed with the
/// defaults (and written to --save-embedding when given); summary gets "mesh" and "embedding".
/// Shared by barylab average, curve and transfer.
vtkSmartPointer<vtkPolyData> embedded_surface(const std::string& mesh, const std::string& embedding,
  const std::string& save, bool quiet, nlohmann::json& summary);

/// check_output for a surface command's output (text or point data), its --json and its
/// --save-embedding (each when given).
void check_surface_outputs(const std::string& output, const std::string& json_path,
  const std::string& save, const std::vector<std::string>& inputs);
void AddRenderCommand(Subcommands& subcommands);
/// export-transform and warp-image (barylabCommandTransform.cxx).
void AddTransformCommands(Subcommands& subcommands);

/// animate's per-frame transforms (barylabCommandTransform.cxx).
struct FrameTransformOptions
{
  bool fields = false;        ///< --displacement-fields: write each frame's forward field
  std::string warp_image;     ///< --warp-image LABELMAP: write it warped into each frame
  std::string reference;      ///< --field-reference IMAGE: the fields' grid
  double spacing = 0.0;       ///< --field-spacing S over the cage's bounds (+ margin)
  double margin = 0.0;        ///< --field-margin M
  std::string extension = ".mha"; ///< --field-format: .mha, .nrrd or .nii.gz
  /// UsageError for options that do not fit together (checked before any computation).
  void Check() const;
  bool Any() const { return fields || !warp_image.empty(); }
};
/// For each of @p frames (the rest @p cage's points moved): the field of the deformation on the
/// grid of the options (the reference, else the label map's grid, else the cage's bounds +
/// margin at the spacing), written as <prefix>_field_NNN<ext> in @p output_dir, and the label
/// map warped into the frame by the field's inverse (nearest neighbour) as
/// <prefix>_warped_NNN<ext of the label map>. Returns {"fields": [...], "warped": [...],
/// "frames": [per frame: jacobian, inverse residuals]}. The filters' warnings (folds, voxels
/// whose inverse did not converge) go to stderr as "barylab: warning: frame N: ..." unless
/// @p quiet.
nlohmann::json WriteFrameTransforms(vtkPolyData* cage,
  const std::vector<vtkSmartPointer<vtkPointSet>>& frames, const WeightsParameters& parameters,
  const FrameTransformOptions& options, const std::string& output_dir, const std::string& prefix,
  bool quiet = false);
/// Adds the options of @p o to animate's @p command.
void add_frame_transform_options(CLI::App* command, FrameTransformOptions& o);
void AddDemoCommand(Subcommands& subcommands);
/// @}

/// A progress bar on stderr when it is a terminal (nothing in logs and pipes).
class ProgressBar
{
public:
  explicit ProgressBar(bool enabled, std::string label);
  ~ProgressBar() { done(); }
  void update(double f);
  void done();

private:
  bool enabled_;
  std::string label_;
  int last_ = -1;
  bool shown_ = false;
};

/// Progress to @p bar; warnings to stderr as "barylab: warning: ..." unless @p quiet.
RunCallbacks callbacks(ProgressBar& bar, bool quiet);

/// The flags of a weights computation (--method, the method's options) bound to @p p
/// (barylabMethodOptions.cxx).
void add_method_options(CLI::App* cmd, WeightsParameters& p);

/// UsageError unless the inputs fit --method @p method: a cage, a skeleton in a domain (bbw) or
/// free control points (tcc, scc; @p controls) (barylabMethodOptions.cxx).
void check_bbw_inputs(bary::MethodId method, const std::string& cage,
  const std::string& handles, const std::string& mesh, bool controls = false);

enum class OutputKind
{
  Data, ///< a data set: .vtp .vtu .vtk .obj .stl .ply .off
  Json,
  Png,
  /// a text matrix or points as text (.txt), or a data set that keeps point arrays (.vtp .vtu .vtk)
  Text
};

/// A CLI11 check for a number in [@p lo, @p hi] that is finite (CLI11's Range lets NaN through);
/// @p description is what --help shows (default "[lo, hi]").
CLI::Validator FiniteRange(double lo, double hi, std::string description = {});

/// Fails early (before any computation) on an output path that cannot be written: unknown or
/// wrong extension for what is written there, a folder that does not exist, a folder, or one
/// of @p inputs (outputs never overwrite inputs).
void check_output(const std::string& path, OutputKind kind,
  const std::vector<std::string>& inputs = {});

/// Counts and statistics printed after a weights computation.
void print_summary(const nlohmann::json& s);

/// tcc user weights: one number per control point (whitespace separated, '#' comments), or a
/// libigl .dmat column.
std::vector<double> read_user_weights(const std::string& path);
/// Free control points (--control-points, --deformed-control-points) stand where a cage and
/// its moved copy do: copies them into @p cage and @p posed when given.
/// @throws UsageError when only one of the two control-point files is given.
void use_control_points(const std::string& controls, const std::string& posed_controls,
  std::string& cage, std::string& posed);

/// BBW's --shape-preservation SPEC: a shallow copy of @p domain (read from @p mesh_path) with
/// the point-data array "ShapePreservation" (rho >= 0 per domain vertex, §3.3) that
/// vtkBaryCoordinates reads: SPEC is a file of one number per domain vertex (text: whitespace
/// separated, '#' comments; or a libigl .dmat), or else the name of a one-component point-data
/// array of the domain. An empty SPEC returns @p domain. Values are checked by the filter.
/// @throws bary::Error(SizeMismatch) for a file with another count than the domain's vertices;
///   (InvalidArgument) when SPEC is neither a file nor a point array of the domain, or names an
///   array of more than one component; the errors of vtkBaryDataIO::ReadNumbers.
vtkSmartPointer<vtkDataSet> with_shape_preservation(
  vtkDataSet* domain, const std::string& spec, const std::string& mesh_path);

/// Writes one CSV: first column @p key (the longest series' values), then one column per input.
void write_locality_csv(const std::string& path, const nlohmann::json& inputs, const char* key,
  const char* value, const std::vector<std::string>& labels);

} // namespace cli
} // namespace barylab
