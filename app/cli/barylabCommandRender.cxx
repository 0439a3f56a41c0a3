// barylab render: one weight field as a PNG image.

#include "barylabCli.h"

#include "barylabRender.h"

#include "vtkBaryDataIO.h"

#include "vtkDataSet.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"

#include <CLI/CLI.hpp>

namespace barylab
{
namespace cli
{
namespace
{

struct RenderArgs
{
  std::string input, cage, handles, controls, output, title;
  barylab::RenderOptions options;
};

int run_render(const RenderArgs& a)
{
  if ((!a.cage.empty()) + (!a.handles.empty()) + (!a.controls.empty()) > 1)
    throw UsageError("give one of --cage, --handles, --control-points");
  check_output(a.output, OutputKind::Png);
  auto data = vtkBaryDataIO::Read(a.input);
  const std::string& controls = !a.handles.empty() ? a.handles : !a.controls.empty() ? a.controls : a.cage;
  vtkSmartPointer<vtkPolyData> cage = controls.empty() ? nullptr : vtkBaryDataIO::ReadPolyData(controls);
  barylab::RenderOptions options = a.options;
  options.height = options.width * 7 / 9;
  options.title = a.title;
  options.skeleton = !a.handles.empty();
  options.free_points = !a.controls.empty();
  auto window = barylab::WeightFieldWindow(data, cage, options);
  barylab::WritePNG(window, a.output);
  return 0;
}

} // namespace

void AddRenderCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<RenderArgs>("render",
    "render one weight field to a PNG (needs X/Xvfb)", run_render);
  command->add_option("--input,-i", a->input, "file with a weights point-data array")->required();
  command->add_option("--cage,-c", a->cage, "the cage (drawn as wireframe)");
  command->add_option("--handles", a->handles, "BBW skeleton handles (bones and points) to draw");
  command->add_option("--control-points", a->controls, "free control points (tcc|scc) to draw");
  command->add_option("--output,-o", a->output, "PNG file")->required();
  command->add_option("--control", a->options.component,
       "control point / handle whose weight is shown")
    ->default_val(0);
  command->add_option("--size", a->options.width, "image width in pixels")
    ->default_val(900)
    ->check(CLI::Range(16, 8192));
  command->add_option("--title", a->title, "title text");
  command->add_option("--array", a->options.weights_name, "weights array name")
    ->default_val("Weights");
  command->add_option("--level", a->options.levels,
    "draw the level set w = VALUE as a thick blue line (repeatable)");
  command->add_flag("--influence-level", a->options.influence_level,
    "draw the influence level w = 1e-3 / #controls (where a weight stops being significant)");
  command->add_option("--isolines", a->options.isolines,
       "isolines evenly spaced over the weight's positive range (0: none)")
    ->default_val(a->options.isolines)
    ->check(CLI::Range(0, 100));
}

} // namespace cli
} // namespace barylab
