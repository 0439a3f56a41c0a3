// barylab export-transform and warp-image: a cage deformation as a displacement field that ITK
// and 3D Slicer apply (with its inverse), and an image warped by such a field.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryDisplacementField.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryImageWarp.h"
#include "vtkBaryWeightMethod.h"

#include "core/common/error.h"
#include "core/imaging/displacement_field.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{
namespace fs = std::filesystem;

double seconds_from(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// An image output: a known image extension (vtkBaryImageIO), an existing folder, not a folder,
/// not one of @p inputs; checked before any computation.
void check_image_output(const std::string& path, const std::vector<std::string>& inputs)
{
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "': it is a folder");
  for (const std::string& input : inputs)
    if (!input.empty() && fs::exists(path, ec) && fs::equivalent(path, input, ec))
      throw bary::Error(bary::ErrorCode::Io,
        "cannot write '" + path + "': it is the input '" + input +
          "' (an output never overwrites an input: choose another name)");
  if (!vtkBaryImageIO::CanWrite(path))
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + path + "': unknown image extension '" + vtkBaryImageIO::Extension(path) +
        "' (images and displacement fields are written as .mha, .mhd, .nii, .nii.gz or .nrrd)");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
}

json grid_json(const bary::ImageGrid& g)
{
  json direction = json::array();
  for (int r = 0; r < 3; ++r)
    direction.push_back({ g.direction(r, 0), g.direction(r, 1), g.direction(r, 2) });
  return { { "size", { g.size[0], g.size[1], g.size[2] } },
    { "origin", { g.origin(0), g.origin(1), g.origin(2) } },
    { "spacing", { g.spacing(0), g.spacing(1), g.spacing(2) } }, { "direction", direction },
    { "voxels", g.voxel_count() } };
}

/// @p image's field written in @p space (LPS as computed, or converted to RAS).
vtkSmartPointer<vtkImageData> in_space(vtkImageData* image, const std::string& space)
{
  if (space == "LPS")
    return image;
  return vtkBaryDisplacementField::FromField(
    vtkBaryDisplacementField::SwapLPSRAS(vtkBaryDisplacementField::ToField(image, "Displacement")));
}

struct ExportArgs
{
  WeightsParameters parameters;
  std::string cage, posed, controls, posed_controls, user_weights;
  std::string reference, output, inverse, space = "LPS", json_path;
  double spacing = 0.0, margin = 0.0, inverse_tolerance = 0.0;
  int inverse_iterations = 200;
  bool quiet = false;
};

int run_export(ExportArgs a)
{
  if (!a.controls.empty() && !a.cage.empty())
    throw UsageError("give --cage or --control-points, not both");
  use_control_points(a.controls, a.posed_controls, a.cage, a.posed);
  if (a.parameters.method == bary::MethodId::BBW && a.cage.empty())
    throw UsageError("export-transform --method bbw takes cage handles (--cage), not a skeleton");
  check_bbw_inputs(a.parameters.method, a.cage, {}, {}, !a.controls.empty());
  if (a.posed.empty())
    throw UsageError("--deformed-cage is required (or --deformed-control-points)");
  if (!a.user_weights.empty() && a.parameters.method != bary::MethodId::TCelestial)
    throw UsageError("--user-weights is for --method tcc (Eq. 8's s_i)");
  a.parameters.user_weights = read_user_weights(a.user_weights);
  if (a.reference.empty() == (a.spacing <= 0.0))
    throw UsageError("give the grid: --reference IMAGE or --spacing S (with --margin M), not both");
  if (!a.reference.empty() && a.margin != 0.0)
    throw UsageError("--margin goes with --spacing (the reference image fixes the grid)");
  const std::vector<std::string> inputs = { a.cage, a.posed, a.reference, a.user_weights };
  check_image_output(a.output, inputs);
  if (!a.inverse.empty())
  {
    check_image_output(a.inverse, inputs);
    if (fs::absolute(a.inverse) == fs::absolute(a.output))
      throw UsageError("--inverse and --output must be different files");
  }
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, inputs);

  const auto t0 = std::chrono::steady_clock::now();
  vtkSmartPointer<vtkPolyData> cage = vtkBaryDataIO::ReadPolyData(a.cage);
  vtkSmartPointer<vtkDataSet> posedData = vtkBaryDataIO::Read(a.posed);
  auto* posed = vtkPointSet::SafeDownCast(posedData);
  if (!posed)
    throw bary::Error(bary::ErrorCode::Io, "'" + a.posed + "' does not hold a point set");
  vtkNew<vtkBaryDisplacementField> filter;
  vtkBaryWeightMethod* method = filter->GetWeightMethod();
  method->SetSettings(a.parameters);
  if (!a.parameters.user_weights.empty())
  {
    vtkNew<vtkDoubleArray> s;
    s->SetName("UserWeights");
    for (double w : a.parameters.user_weights)
      s->InsertNextValue(w);
    method->SetUserWeights(s);
  }
  filter->SetRestCageData(cage);
  filter->SetDeformedCageData(posed);
  vtkSmartPointer<vtkImageData> reference;
  if (!a.reference.empty())
  {
    reference = vtkBaryImageIO::Read(a.reference);
    filter->SetReferenceImageData(reference);
  }
  else
  {
    double b[6];
    cage->GetBounds(b);
    filter->SetBounds(b[0] - a.margin, b[1] + a.margin, b[2] - a.margin, b[3] + a.margin,
      b[4] - a.margin, b[5] + a.margin);
    filter->SetSpacing(a.spacing, a.spacing, a.spacing);
  }
  filter->SetComputeInverse(!a.inverse.empty());
  filter->SetInverseTolerance(a.inverse_tolerance);
  filter->SetInverseMaximumIterations(a.inverse_iterations);
  const double read_seconds = seconds_from(t0);
  ProgressBar bar(!a.quiet, "export-transform");
  const auto t1 = std::chrono::steady_clock::now();
  RunAlgorithm(filter, callbacks(bar, a.quiet), bary::ErrorCode::InvalidArgument);
  bar.done();
  const double compute_seconds = seconds_from(t1);
  const auto t2 = std::chrono::steady_clock::now();
  vtkBaryImageIO::Write(in_space(filter->GetOutput(0), a.space), a.output);
  if (!a.inverse.empty())
    vtkBaryImageIO::Write(in_space(filter->GetOutput(1), a.space), a.inverse);
  const double write_seconds = seconds_from(t2);

  json summary;
  summary["method"] = MethodName(a.parameters);
  summary["space"] = a.space;
  summary["output"] = a.output;
  summary["grid"] = grid_json(vtkBaryDisplacementField::ToGrid(filter->GetOutput(0)));
  summary["jacobian"] = { { "minimum", filter->GetJacobianMinimum() },
    { "folded_voxels", filter->GetNumberOfFoldedVoxels() } };
  summary["outside_voxels"] = filter->GetNumberOfOutsideVoxels();
  if (!a.inverse.empty())
    summary["inverse"] = { { "file", a.inverse }, { "tolerance", filter->GetInverseToleranceUsed() },
      { "max_residual", filter->GetInverseMaximumResidual() },
      { "mean_residual", filter->GetInverseMeanResidual() },
      { "not_converged", filter->GetInverseNotConverged() },
      { "not_converged_at_border", filter->GetInverseNotConvergedAtBorder() },
      { "max_iterations_used", filter->GetInverseIterations() } };
  summary["seconds"] = { { "read", read_seconds }, { "field", compute_seconds },
    { "write", write_seconds }, { "total", seconds_from(t0) } };
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
  {
    const json& g = summary["grid"];
    std::cerr << "barylab: wrote " << a.output << " (" << g["size"][0] << " x " << g["size"][1]
              << " x " << g["size"][2] << " voxels, " << a.space << ", "
              << summary["method"].get<std::string>() << ") in " << compute_seconds << " s";
    if (filter->GetNumberOfFoldedVoxels() > 0)
      std::cerr << "; folds at " << filter->GetNumberOfFoldedVoxels() << " voxels";
    std::cerr << "\n";
    if (!a.inverse.empty())
      std::cerr << "barylab: wrote " << a.inverse << " (inverse: max residual "
                << filter->GetInverseMaximumResidual() << ", mean "
                << filter->GetInverseMeanResidual() << ", tolerance "
                << filter->GetInverseToleranceUsed() << "; not converged "
                << filter->GetInverseNotConverged() << " voxels, "
                << filter->GetInverseNotConvergedAtBorder() << " of them at the border)\n";
  }
  return 0;
}

struct WarpArgs
{
  std::string image, transform, inverse, reference, output, json_path;
  std::string interpolation = "linear", space = "LPS";
  double default_value = 0.0, inverse_tolerance = 0.0;
  int inverse_iterations = 200, threads = 0;
  bool quiet = false;
};

int run_warp(const WarpArgs& a)
{
  if (a.transform.empty() == a.inverse.empty())
    throw UsageError("give the deformation: --transform FIELD (forward, inverted here) or "
                     "--inverse-transform FIELD (the pull-back field), one of them");
  const std::vector<std::string> inputs = { a.image, a.transform, a.inverse, a.reference };
  check_image_output(a.output, inputs);
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, inputs);
  const auto t0 = std::chrono::steady_clock::now();
  vtkSmartPointer<vtkImageData> image = vtkBaryImageIO::Read(a.image);
  const std::string field_path = a.inverse.empty() ? a.transform : a.inverse;
  vtkSmartPointer<vtkImageData> field = vtkBaryImageIO::Read(field_path);
  if (a.space == "RAS") // back to BaryLab's (and the images') LPS
    field = in_space(field, "RAS");
  vtkNew<vtkBaryImageWarp> warp;
  warp->SetInputData(image);
  warp->SetFieldData(field);
  if (!a.reference.empty())
    warp->SetReferenceImageData(vtkBaryImageIO::Read(a.reference));
  warp->SetFieldIsInverse(!a.inverse.empty());
  warp->SetInterpolation(a.interpolation == "nearest" ? vtkBaryImageWarp::NEAREST
                                                      : vtkBaryImageWarp::LINEAR);
  warp->SetDefaultValue(a.default_value);
  warp->SetInverseTolerance(a.inverse_tolerance);
  warp->SetInverseMaximumIterations(a.inverse_iterations);
  warp->SetNumberOfThreads(a.threads);
  const double read_seconds = seconds_from(t0);
  ProgressBar bar(!a.quiet, "warp-image");
  const auto t1 = std::chrono::steady_clock::now();
  RunAlgorithm(warp, callbacks(bar, a.quiet), bary::ErrorCode::InvalidArgument);
  bar.done();
  const double warp_seconds = seconds_from(t1);
  const auto t2 = std::chrono::steady_clock::now();
  vtkBaryImageIO::Write(warp->GetOutput(), a.output);
  const double write_seconds = seconds_from(t2);
  json summary;
  summary["output"] = a.output;
  summary["interpolation"] = a.interpolation;
  summary["grid"] = grid_json(vtkBaryDisplacementField::ToGrid(warp->GetOutput()));
  summary["outside_voxels"] = warp->GetNumberOfOutsideVoxels();
  if (a.inverse.empty())
    summary["inverse"] = { { "max_residual", warp->GetInverseMaximumResidual() },
      { "mean_residual", warp->GetInverseMeanResidual() },
      { "not_converged", warp->GetInverseNotConverged() },
      { "not_converged_at_border", warp->GetInverseNotConvergedAtBorder() } };
  summary["seconds"] = { { "read", read_seconds }, { "warp", warp_seconds },
    { "write", write_seconds }, { "total", seconds_from(t0) } };
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: wrote " << a.output << " (" << a.interpolation << ", "
              << warp->GetNumberOfOutsideVoxels() << " voxels outside the image) in "
              << warp_seconds << " s\n";
  return 0;
}

/// A configured vtkBaryDisplacementField for @p cage moved to @p moved.
vtkSmartPointer<vtkBaryDisplacementField> field_filter(vtkPolyData* cage, vtkPointSet* moved,
  const WeightsParameters& parameters, vtkImageData* reference, double spacing, double margin)
{
  auto filter = vtkSmartPointer<vtkBaryDisplacementField>::New();
  vtkBaryWeightMethod* method = filter->GetWeightMethod();
  method->SetSettings(parameters);
  if (!parameters.user_weights.empty())
  {
    vtkNew<vtkDoubleArray> s;
    s->SetName("UserWeights");
    for (double w : parameters.user_weights)
      s->InsertNextValue(w);
    method->SetUserWeights(s);
  }
  filter->SetRestCageData(cage);
  filter->SetDeformedCageData(moved);
  if (reference)
    filter->SetReferenceImageData(reference);
  else
  {
    double b[6];
    cage->GetBounds(b);
    filter->SetBounds(
      b[0] - margin, b[1] + margin, b[2] - margin, b[3] + margin, b[4] - margin, b[5] + margin);
    filter->SetSpacing(spacing, spacing, spacing);
  }
  return filter;
}

} // namespace

void FrameTransformOptions::Check() const
{
  if (!Any())
  {
    if (!reference.empty() || spacing > 0.0 || margin > 0.0)
      throw UsageError("--field-reference, --field-spacing and --field-margin go with "
                       "--displacement-fields or --warp-image");
    return;
  }
  if (!reference.empty() && spacing > 0.0)
    throw UsageError("give the fields' grid by --field-reference or --field-spacing, not both");
  if (reference.empty() && spacing <= 0.0 && warp_image.empty())
    throw UsageError("--displacement-fields needs the fields' grid: --field-reference IMAGE or "
                     "--field-spacing S");
  if (margin > 0.0 && spacing <= 0.0)
    throw UsageError("--field-margin goes with --field-spacing");
}

nlohmann::json WriteFrameTransforms(vtkPolyData* cage,
  const std::vector<vtkSmartPointer<vtkPointSet>>& frames, const WeightsParameters& parameters,
  const FrameTransformOptions& o, const std::string& output_dir, const std::string& prefix,
  bool quiet)
{
  json summary = { { "fields", json::array() }, { "warped", json::array() },
    { "frames", json::array() } };
  vtkSmartPointer<vtkImageData> labels =
    o.warp_image.empty() ? nullptr : vtkBaryImageIO::Read(o.warp_image);
  vtkSmartPointer<vtkImageData> reference = !o.reference.empty()
    ? vtkBaryImageIO::Read(o.reference)
    : (o.spacing > 0.0 ? nullptr : labels);
  const std::string labels_ext =
    labels ? vtkBaryImageIO::Extension(o.warp_image) : std::string();
  for (std::size_t f = 0; f < frames.size(); ++f)
  {
    auto filter = field_filter(cage, frames[f], parameters, reference, o.spacing, o.margin);
    filter->SetComputeInverse(static_cast<bool>(labels));
    RunCallbacks warn;
    if (!quiet)
      warn.warning = [f](const std::string& message) {
        std::cerr << "barylab: warning: frame " << f << ": " << message << "\n";
      };
    RunAlgorithm(filter, warn, bary::ErrorCode::InvalidArgument);
    char number[32];
    std::snprintf(number, sizeof(number), "_%03zu", f);
    json frame = { { "frame", f }, { "jacobian_minimum", filter->GetJacobianMinimum() },
      { "folded_voxels", filter->GetNumberOfFoldedVoxels() } };
    if (o.fields)
    {
      const std::string name = prefix + "_field" + number + o.extension;
      vtkBaryImageIO::Write(filter->GetOutput(0), (fs::path(output_dir) / name).string());
      summary["fields"].push_back(name);
    }
    if (labels)
    {
      vtkNew<vtkBaryImageWarp> warp;
      warp->SetInputData(labels);
      warp->SetFieldConnection(filter->GetOutputPort(1));
      warp->SetInterpolationToNearest();
      warp->SetNumberOfThreads(parameters.threads);
      RunAlgorithm(warp, {}, bary::ErrorCode::InvalidArgument);
      const std::string name = prefix + "_warped" + number + labels_ext;
      vtkBaryImageIO::Write(warp->GetOutput(), (fs::path(output_dir) / name).string());
      summary["warped"].push_back(name);
      frame["inverse"] = { { "max_residual", filter->GetInverseMaximumResidual() },
        { "mean_residual", filter->GetInverseMeanResidual() },
        { "not_converged", filter->GetInverseNotConverged() },
        { "not_converged_at_border", filter->GetInverseNotConvergedAtBorder() } };
    }
    summary["frames"].push_back(frame);
  }
  return summary;
}

void add_frame_transform_options(CLI::App* command, FrameTransformOptions& o)
{
  command->add_flag("--displacement-fields", o.fields,
    "also write each frame's displacement field (<prefix>_field_NNN, see export-transform)");
  command->add_option("--warp-image", o.warp_image,
    "also write this label map warped into each frame (<prefix>_warped_NNN, nearest neighbour)");
  command->add_option("--field-reference", o.reference,
    "the fields' grid: this image's (default with --warp-image: the label map's)");
  command->add_option("--field-spacing", o.spacing, "the fields' grid: the cage's bounds at this spacing (mm)")
    ->check(FiniteRange(1e-6, 1e6, "(0, 1e6]"));
  command->add_option("--field-margin", o.margin, "with --field-spacing: grow the bounds by this (mm)")
    ->check(FiniteRange(0.0, 1e6));
  command->add_option("--field-format", o.extension, "the fields' format")
    ->check(CLI::IsMember({ ".mha", ".nrrd", ".nii.gz" }))
    ->default_val(o.extension);
}

void AddTransformCommands(Subcommands& subcommands)
{
  {
    const auto [command, a] = subcommands.Add<ExportArgs>("export-transform",
      "write a cage deformation as a displacement field (a grid transform ITK and 3D Slicer "
      "load), optionally with its inverse",
      run_export);
    command->add_option("--cage,-c", a->cage, "rest cage");
    command->add_option("--deformed-cage,-d", a->posed, "moved cage (same points, same order)");
    command->add_option("--control-points", a->controls, "tcc|scc: rest control points");
    command->add_option("--deformed-control-points", a->posed_controls,
      "tcc|scc: the control points moved (same points, same order)");
    command->add_option("--user-weights", a->user_weights, "tcc: s_i of Eq. 8 (text or .dmat)");
    command->add_option("--reference", a->reference,
      "image whose grid (extent, origin, spacing, direction) the field takes");
    command->add_option("--spacing", a->spacing,
      "grid spacing (mm) over the cage's bounds, without --reference")
      ->check(FiniteRange(1e-6, 1e6, "(0, 1e6]"));
    command->add_option("--margin", a->margin,
      "with --spacing: grow the cage's bounds by this much on every side (mm; default 0)")
      ->check(FiniteRange(0.0, 1e6));
    command->add_option("--output,-o", a->output,
      "the forward field T(x) = x + u(x), rest to deformed (.mha, .mhd, .nii, .nii.gz, .nrrd)")
      ->required();
    command->add_option("--inverse", a->inverse,
      "also write the inverse field (what ITK / Slicer need to resample an image into the "
      "deformed space)");
    command->add_option("--inverse-tolerance", a->inverse_tolerance,
      "the inverse's residual |x + u(x) - y| per voxel (mm); 0: 1e-4 x the smallest spacing")
      ->check(FiniteRange(0.0, 1e6));
    command->add_option("--inverse-iterations", a->inverse_iterations,
      "the inverse's fixed-point iterations per voxel at most")
      ->check(CLI::Range(1, 100000))
      ->default_val(a->inverse_iterations);
    command->add_option("--space", a->space,
      "coordinates of the written fields: LPS (ITK, Slicer, DICOM) or RAS (x, y negated)")
      ->check(CLI::IsMember({ "LPS", "RAS" }))
      ->default_val(a->space);
    command->add_option("--json", a->json_path,
      "write a JSON summary (grid, Jacobian and folds, inverse residuals, seconds)");
    command->add_flag("--quiet,-q", a->quiet, "no progress bar, summary or warnings (errors still)");
    add_method_options(command, a->parameters);
  }
  {
    const auto [command, a] = subcommands.Add<WarpArgs>("warp-image",
      "warp an image by a displacement field: the image resampled at T^-1(y)", run_warp);
    command->add_option("--image,-i", a->image, "the moving image (a label map or intensities)")
      ->required();
    command->add_option("--transform,-t", a->transform,
      "forward field T(x) = x + u(x) of the image's space (inverted here)");
    command->add_option("--inverse-transform", a->inverse,
      "the inverse (pull-back) field, used as it is (export-transform --inverse)");
    command->add_option("--interpolation", a->interpolation,
      "nearest (label maps: labels kept exactly) or linear (intensities)")
      ->check(CLI::IsMember({ "nearest", "linear" }))
      ->default_val(a->interpolation);
    command->add_option("--reference", a->reference,
      "image whose grid the output takes (default: the moving image's)");
    command->add_option("--default", a->default_value,
      "value of output voxels that map outside the image")
      ->check(FiniteRange(-1e300, 1e300, "a finite number"))
      ->default_val(0);
    command->add_option("--space", a->space, "coordinates of the field file: LPS or RAS")
      ->check(CLI::IsMember({ "LPS", "RAS" }))
      ->default_val(a->space);
    command->add_option("--inverse-tolerance", a->inverse_tolerance,
      "with --transform: the inverse's residual per voxel (mm); 0: 1e-4 x the smallest spacing")
      ->check(FiniteRange(0.0, 1e6));
    command->add_option("--inverse-iterations", a->inverse_iterations,
      "with --transform: the inverse's iterations per voxel at most")
      ->check(CLI::Range(1, 100000))
      ->default_val(a->inverse_iterations);
    command->add_option("--threads", a->threads, "threads (0: all cores)")
      ->check(CLI::Range(0, 1024))
      ->default_val(0);
    command->add_option("--output,-o", a->output, "the warped image (.mha, .nii.gz, .nrrd, ...)")
      ->required();
    command->add_option("--json", a->json_path, "write a JSON summary");
    command->add_flag("--quiet,-q", a->quiet, "no progress bar, summary or warnings (errors still)");
  }
}

} // namespace cli
} // namespace barylab
