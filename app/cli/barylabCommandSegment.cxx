// barylab segment: the closed surface of one label of a label map (NIfTI, NRRD, MetaImage),
// in the image's physical coordinates (LPS, millimetres): vtkBaryImageIO reads the image through
// ITK, vtkBaryLabelMapSurface extracts, smooths, decimates and validates the surface.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryLabelMapSurface.h"

#include "core/common/error.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct SegmentArgs
{
  std::string image, output, json_path;
  long long label = 0;
  int smoothing = 20;
  int faces = 5000;
  double reduction = std::numeric_limits<double>::quiet_NaN(); ///< NaN: not given
  double threshold = std::numeric_limits<double>::quiet_NaN(); ///< NaN: not given
  bool quiet = false;
};

std::string millilitres(double mm3)
{
  std::ostringstream s;
  s.precision(4);
  s << mm3 / 1000.0 << " mL";
  return s.str();
}

int run_segment(const SegmentArgs& a)
{
  const bool reduction_given = std::isfinite(a.reduction);
  check_output(a.output, OutputKind::Data, { a.image });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.image, a.output });
  const auto start = std::chrono::steady_clock::now();
  vtkSmartPointer<vtkImageData> image = vtkBaryImageIO::Read(a.image);

  vtkNew<vtkBaryLabelMapSurface> surface;
  surface->SetInputData(image);
  surface->SetLabel(a.label);
  if (std::isfinite(a.threshold))
  {
    surface->UseThresholdOn();
    surface->SetThreshold(a.threshold);
  }
  surface->SetSmoothingIterations(a.smoothing);
  surface->SetTargetNumberOfFaces(reduction_given ? 0 : a.faces);
  surface->SetTargetReduction(reduction_given ? a.reduction : 0.0);
  ProgressBar bar(!a.quiet, "segment");
  RunAlgorithm(surface, callbacks(bar, a.quiet), bary::ErrorCode::InvalidArgument);
  bar.done();
  vtkPolyData* result = surface->GetOutput();
  vtkBaryDataIO::Write(result, a.output);
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  json summary;
  summary["image"] = a.image;
  summary["output"] = a.output;
  summary["space"] = "LPS";
  summary["units"] = "mm";
  if (surface->GetUseThreshold())
    summary["threshold"] = a.threshold;
  else
    summary["label"] = surface->GetLabelUsed();
  summary["voxels"] = surface->GetNumberOfLabelVoxels();
  summary["label_volume"] = surface->GetLabelVolume();
  summary["enclosed_volume"] = surface->GetEnclosedVolume();
  summary["triangles"] = result->GetNumberOfCells();
  summary["vertices"] = result->GetNumberOfPoints();
  summary["extracted_triangles"] = surface->GetNumberOfExtractedFaces();
  summary["components_dropped"] = surface->GetNumberOfDroppedComponents();
  summary["border_cut"] = surface->GetTouchesBorder();
  summary["smoothing"] = a.smoothing;
  summary["smoothing_used"] = surface->GetSmoothingIterationsUsed();
  summary["decimation"] = surface->GetDecimationUsed();
  summary["attempts"] = surface->GetNumberOfAttempts();
  if (reduction_given)
    summary["reduction"] = a.reduction;
  else
    summary["target_faces"] = a.faces;
  summary["seconds"] = seconds;
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);

  if (!a.quiet)
  {
    const std::string what = surface->GetUseThreshold()
      ? "the voxels >= " + json(a.threshold).dump()
      : "label " + std::to_string(surface->GetLabelUsed());
    if (surface->GetTouchesBorder())
      std::cerr << "barylab: warning: " << what
                << " touches the image's border (the field of view cuts it): the surface is "
                   "closed along the border\n";
    if (surface->GetNumberOfAttempts() > 1)
      std::cerr << "barylab: warning: the first surface failed BaryLab's checks ("
                << surface->GetFirstFailure() << "); the surface written is attempt "
                << surface->GetNumberOfAttempts() << ": decimation "
                << surface->GetDecimationUsed() << ", " << surface->GetSmoothingIterationsUsed()
                << " smoothing iterations\n";
    if (surface->GetNumberOfDroppedComponents() > 0)
      std::cerr << "barylab: warning: " << surface->GetNumberOfDroppedComponents()
                << " smaller surface piece(s) of " << what
                << " dropped (islands, or the walls of cavities); the largest is kept\n";
    std::cerr << "barylab: " << what << ": " << surface->GetNumberOfLabelVoxels() << " voxels ("
              << millilitres(surface->GetLabelVolume()) << "), surface of "
              << result->GetNumberOfCells() << " triangles enclosing "
              << millilitres(surface->GetEnclosedVolume()) << " (LPS, mm) in "
              << std::fixed << std::setprecision(2) << seconds << " s\n";
  }
  return 0;
}

} // namespace

void AddSegmentCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<SegmentArgs>("segment",
    "the closed surface of one label of a label map (.nii, .nii.gz, .nrrd, .mha, .mhd), in the "
    "image's LPS coordinates (mm)",
    run_segment);
  command->add_option("--image,-i", a->image, "label map: .nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd")
    ->required();
  auto* label = command->add_option("--label,-l", a->label,
    "the label value (default: the image's only non-zero label)")
    ->check(CLI::Validator(
      [](std::string& text) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value == 0)
          return "'" + text + "' is not a non-zero integer label";
        return {};
      },
      "INT != 0", ""));
  command->add_option("--threshold", a->threshold,
       "segment the voxels >= T instead of a label (any image, e.g. intensities)")
    ->check(FiniteRange(-1e300, 1e300, "a finite number"))
    ->excludes(label);
  command->add_option("--output,-o", a->output,
    "the surface: .vtp, .vtk, .stl, .obj, .ply, .off (LPS, mm: what 3D Slicer assumes)")
    ->required();
  command->add_option("--smoothing", a->smoothing,
       "windowed-sinc smoothing iterations (0: none)")
    ->default_val(a->smoothing)
    ->check(CLI::Range(0, 1000));
  auto* faces = command->add_option("--faces", a->faces,
       "decimate to about F triangles (0: no decimation)")
    ->default_val(a->faces)
    ->check(CLI::Range(0, 50000000));
  command->add_option("--reduction", a->reduction,
       "decimate by removing this fraction of the triangles instead of --faces")
    ->check(FiniteRange(0.0, 0.99))
    ->excludes(faces);
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar, summary or warnings (errors still)");
}

} // namespace cli
} // namespace barylab
