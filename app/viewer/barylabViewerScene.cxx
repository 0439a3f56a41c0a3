#include "barylabViewerScene.h"

#include "barylabViewerMode.h"

#include "core/common/error.h"

#include "vtkImageData.h"
#include "vtkImageReader2.h"
#include "vtkImageReader2Factory.h"
#include "vtkFloatArray.h"
#include "vtkTexture.h"
#include "barylabPipeline.h"
#include "barylabRender.h"
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkClipPolyData.h"
#include "vtkCellType.h"
#include "vtkGenericCell.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourFilter.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkDataSet.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkDoubleArray.h"
#include "vtkGradientFilter.h"
#include "vtkIdTypeArray.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkPlane.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkTextActor.h"
#include "vtkTableBasedClipDataSet.h"
#include "vtkTextProperty.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace barylab
{
namespace viewer
{
namespace
{
using bary::Error;
using bary::ErrorCode;

/// Viridis as a 256-entry lookup table, linear or log10.
vtkSmartPointer<vtkLookupTable> make_lut(double lo, double hi, bool log)
{
  static const double viridis[][3] = { { 0.267, 0.005, 0.329 }, { 0.283, 0.141, 0.458 },
    { 0.254, 0.265, 0.530 }, { 0.207, 0.372, 0.553 }, { 0.164, 0.471, 0.558 },
    { 0.128, 0.567, 0.551 }, { 0.135, 0.659, 0.518 }, { 0.267, 0.749, 0.441 },
    { 0.478, 0.821, 0.318 }, { 0.741, 0.873, 0.150 }, { 0.993, 0.906, 0.144 } };
  vtkNew<vtkColorTransferFunction> ctf;
  for (int i = 0; i <= 10; ++i)
    ctf->AddRGBPoint(i / 10.0, viridis[i][0], viridis[i][1], viridis[i][2]);
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(256);
  for (int i = 0; i < 256; ++i)
  {
    double rgb[3];
    ctf->GetColor(i / 255.0, rgb);
    lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
  if (log)
  {
    lut->SetScaleToLog10();
    lut->UseBelowRangeColorOn();
    lut->SetBelowRangeColor(0.55, 0.55, 0.55, 1.0);
  }
  lut->SetTableRange(lo, hi);
  return lut;
}

/// The model's surface with "vtkOriginalPointIds" (so posed points can be mapped onto it).
vtkSmartPointer<vtkPolyData> rest_surface(vtkDataSet* data)
{
  vtkNew<vtkDataSetSurfaceFilter> surface;
  surface->SetInputData(data);
  surface->PassThroughPointIdsOn();
  surface->Update();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->DeepCopy(surface->GetOutput());
  return poly;
}

/// One component of @p weights on @p surface (through the original ids) as array "weight".
vtkSmartPointer<vtkDoubleArray> component_array(vtkPolyData* surface, vtkDataArray* weights,
  vtkIdTypeArray* ids, int component)
{
  auto w = vtkSmartPointer<vtkDoubleArray>::New();
  w->SetName("weight");
  w->SetNumberOfTuples(surface->GetNumberOfPoints());
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    w->SetValue(i, weights->GetComponent(ids ? ids->GetValue(i) : i, component));
  return w;
}

/// |grad w| of scalar array "weight" on @p data (barylab::WeightGradientNorms: VTK's
/// vtkGradientFilter), as array "gradient_norm".
vtkSmartPointer<vtkDataArray> gradient_norm(vtkDataSet* data)
{
  vtkSmartPointer<vtkDataSet> with = WeightGradientNorms(data, "weight");
  vtkSmartPointer<vtkDataArray> norm = with->GetPointData()->GetArray("weightGradientNorm");
  norm->SetName("gradient_norm");
  return norm;
}

void add_level_set(vtkRenderer* renderer, vtkPolyData* surface, const std::vector<double>& values,
  const double rgb[3], double width)
{
  if (values.empty())
    return;
  vtkNew<vtkContourFilter> contour;
  contour->SetInputData(surface);
  for (std::size_t i = 0; i < values.size(); ++i)
    contour->SetValue(static_cast<int>(i), values[i]);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(contour->GetOutputPort());
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetLineWidth(static_cast<float>(width));
  // lift the lines a little towards the viewer so they are not hidden by the surface
  mapper->SetResolveCoincidentTopologyToPolygonOffset();
  renderer->AddActor(actor);
}

double diameter_of(vtkPoints* points)
{
  double b[6];
  points->GetBounds(b);
  return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
    (b[5] - b[4]) * (b[5] - b[4]));
}

void add_controls(vtkRenderer* renderer, vtkPolyData* controls, vtkPoints* posed,
  const SceneOptions& options, vtkDataSet* weighted = nullptr)
{
  vtkPoints* points = posed ? posed : controls->GetPoints();
  const double blue[3] = { 0.2, 0.35, 0.8 }, red[3] = { 0.9, 0.15, 0.1 };
  const double radius = 0.012 * std::max(diameter_of(controls->GetPoints()), 1e-12);
  vtkNew<vtkPoints> selected;
  ModeFor(options.controls).addControlActors(renderer, controls, points, options, selected);
  AddSpheres(renderer, points, radius, blue);
  // control points the weights method added (celestial hull points): fixed, small and grey;
  // their weights components follow the controls'
  if (vtkDataArray* added = weighted && weighted->GetFieldData()
        ? weighted->GetFieldData()->GetArray("AddedControlPoints")
        : nullptr)
  {
    vtkNew<vtkPoints> hull;
    for (vtkIdType k = 0; k < added->GetNumberOfTuples(); ++k)
      hull->InsertNextPoint(added->GetTuple3(k));
    const double grey[3] = { 0.55, 0.55, 0.55 };
    AddSpheres(renderer, hull, 0.6 * radius, grey);
    const vtkIdType k = options.component - points->GetNumberOfPoints();
    if (k >= 0 && k < hull->GetNumberOfPoints())
      selected->InsertNextPoint(hull->GetPoint(k));
  }
  if (selected->GetNumberOfPoints() > 0)
    AddSpheres(renderer, selected, 2.0 * radius, red);
}

/// True when @p data has cells of dimension 3 (a tetrahedral or other volume mesh).
bool has_volume_cells(vtkDataSet* data)
{
  vtkNew<vtkGenericCell> cell;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
  {
    switch (data->GetCellType(c))
    {
      case VTK_TETRA:
      case VTK_HEXAHEDRON:
      case VTK_WEDGE:
      case VTK_PYRAMID:
      case VTK_VOXEL:
        return true;
      case VTK_VERTEX:
      case VTK_POLY_VERTEX:
      case VTK_LINE:
      case VTK_POLY_LINE:
      case VTK_TRIANGLE:
      case VTK_TRIANGLE_STRIP:
      case VTK_QUAD:
      case VTK_POLYGON:
        break;
      default:
        data->GetCell(c, cell);
        if (cell->GetCellDimension() == 3)
          return true;
    }
  }
  return false;
}

/// The plane of the clipping options through @p bounds.
vtkSmartPointer<vtkPlane> clip_plane(const double b[6], const SceneOptions& options)
{
  const int a = std::clamp(options.clip_axis, 0, 2);
  double origin[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  origin[a] = b[2 * a] + std::clamp(options.clip_position, 0.0, 1.0) * (b[2 * a + 1] - b[2 * a]);
  double normal[3] = { 0.0, 0.0, 0.0 };
  normal[a] = 1.0;
  auto plane = vtkSmartPointer<vtkPlane>::New();
  plane->SetOrigin(origin);
  plane->SetNormal(normal);
  return plane;
}

/// A volume mesh cut open by the clipping plane: its cells below the plane (VTK's table-based
/// clip, cells cut exactly), the field on the cut face interpolated linearly inside the cells,
/// then the surface of what is left. "vtkOriginalPointIds" is not kept (the clip makes points).
vtkSmartPointer<vtkPolyData> sliced_volume(vtkDataSet* weighted, vtkDataArray* weights,
  vtkPoints* posed_points, const SceneOptions& options, bool gradient)
{
  auto volume = vtkSmartPointer<vtkDataSet>::Take(weighted->NewInstance());
  volume->CopyStructure(weighted);
  auto w = vtkSmartPointer<vtkDoubleArray>::New();
  w->SetName("weight");
  w->SetNumberOfTuples(weighted->GetNumberOfPoints());
  for (vtkIdType i = 0; i < weighted->GetNumberOfPoints(); ++i)
    w->SetValue(i, weights->GetComponent(i, options.component));
  volume->GetPointData()->AddArray(w);
  volume->GetPointData()->SetActiveScalars("weight");
  if (gradient)
  {
    // the 3D gradient of the volume's field (on the rest geometry), not the surface's
    volume->GetPointData()->AddArray(gradient_norm(volume));
    volume->GetPointData()->SetActiveScalars("gradient_norm");
  }
  if (auto* set = vtkPointSet::SafeDownCast(volume); set && posed_points)
  {
    vtkNew<vtkPoints> moved;
    moved->DeepCopy(posed_points);
    set->SetPoints(moved);
  }
  double b[6];
  volume->GetBounds(b);
  vtkNew<vtkTableBasedClipDataSet> clip;
  clip->SetInputData(volume);
  clip->SetClipFunction(clip_plane(b, options));
  clip->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  clip->InsideOutOn(); // keep the part below the plane: the slider sweeps it through the model
  vtkNew<vtkDataSetSurfaceFilter> surface;
  surface->SetInputConnection(clip->GetOutputPort());
  surface->Update();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->DeepCopy(surface->GetOutput());
  poly->GetPointData()->SetActiveScalars(gradient ? "gradient_norm" : "weight");
  return poly;
}
} // namespace

bool IsPictureFile(const std::string& path)
{
  std::string suffix = path.substr(path.find_last_of('.') == std::string::npos ? path.size()
                                                                               : path.find_last_of('.'));
  std::transform(suffix.begin(), suffix.end(), suffix.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* known : { ".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pnm", ".ppm" })
    if (suffix == known)
      return true;
  return false;
}

vtkSmartPointer<vtkImageData> ReadPicture(const std::string& path)
{
  vtkSmartPointer<vtkImageReader2> reader;
  reader.TakeReference(vtkImageReader2Factory::CreateImageReader2(path.c_str()));
  if (!reader)
    throw Error(ErrorCode::Io, "cannot read '" + path + "' as a picture (PNG, JPEG, BMP, TIFF, PNM)");
  reader->SetFileName(path.c_str());
  reader->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->ShallowCopy(reader->GetOutput());
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] < 1 || dims[1] < 1 || !image->GetPointData()->GetScalars())
    throw Error(ErrorCode::Io, "'" + path + "' holds no picture (empty or unreadable)");
  return image;
}

vtkSmartPointer<vtkDataSet> TexturedCageMesh(vtkPolyData* cage, vtkImageData* picture, int target_cells)
{
  if (!picture)
    throw Error(ErrorCode::InvalidArgument, "no picture for the image mode");
  int dims[3];
  picture->GetDimensions(dims);
  if (dims[0] < 1 || dims[1] < 1)
    throw Error(ErrorCode::InvalidArgument, "the picture is empty");
  double b[6];
  cage->GetBounds(b);
  const double extent = std::max(b[1] - b[0], b[3] - b[2]);
  if (!(extent > 0.0) || b[5] - b[4] > 1e-9 * extent)
    throw Error(ErrorCode::InvalidArgument,
      "the image mode needs a 2D cage (a polygon in the z = 0 plane)");
  MeshParameters mesh;
  mesh.cage_dimension = 2;
  mesh.target_cells = target_cells;
  vtkSmartPointer<vtkUnstructuredGrid> grid = MeshCage(cage, nullptr, mesh);
  // the picture covers the box enlarged by 5% per side, centred, aspect kept
  const double margin = 0.05;
  const double w = (b[1] - b[0]) * (1.0 + 2.0 * margin), h = (b[3] - b[2]) * (1.0 + 2.0 * margin);
  const double aspect = static_cast<double>(dims[0]) / static_cast<double>(dims[1]);
  const double width = std::max(w, h * aspect), height = width / aspect;
  const double x0 = 0.5 * (b[0] + b[1]) - 0.5 * width, y0 = 0.5 * (b[2] + b[3]) - 0.5 * height;
  vtkNew<vtkFloatArray> tc;
  tc->SetName("TextureCoordinates");
  tc->SetNumberOfComponents(2);
  tc->SetNumberOfTuples(grid->GetNumberOfPoints());
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    tc->SetTuple2(i, (p[0] - x0) / width, (p[1] - y0) / height);
  }
  grid->GetPointData()->SetTCoords(tc);
  return grid;
}

SceneInfo BuildScene(vtkRenderer* renderer, vtkDataSet* weighted, vtkPoints* posed_points,
  vtkPolyData* controls, vtkPoints* posed_controls, const SceneOptions& options)
{
  renderer->RemoveAllViewProps();
  renderer->SetBackground(1.0, 1.0, 1.0);
  SceneInfo info;
  if (!weighted)
  {
    if (controls && options.show_controls)
      add_controls(renderer, controls, posed_controls, options);
    return info;
  }
  vtkDataArray* weights = weighted->GetPointData()->GetArray(options.weights_name.c_str());
  if (!weights)
    throw Error(ErrorCode::InvalidArgument,
      "the model has no weights array '" + options.weights_name + "'");
  info.components = weights->GetNumberOfComponents();
  if (options.component < 0 || options.component >= info.components)
    throw Error(ErrorCode::InvalidArgument,
      "control " + std::to_string(options.component) + " does not exist (the weights have " +
        std::to_string(info.components) + " components)");
  info.influence_level = 1e-3 / info.components;

  vtkSmartPointer<vtkPolyData> surface = rest_surface(weighted);
  auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetPointData()->GetArray("vtkOriginalPointIds"));
  auto w = component_array(surface, weights, ids, options.component);
  surface->GetPointData()->AddArray(w);
  surface->GetPointData()->SetActiveScalars("weight");
  const bool gradient = options.field == SceneOptions::Field::GradientNorm;
  if (gradient)
  {
    auto g = gradient_norm(surface); // on the rest geometry
    surface->GetPointData()->AddArray(g);
    surface->GetPointData()->SetActiveScalars("gradient_norm");
  }
  if (posed_points)
  {
    vtkNew<vtkPoints> moved;
    moved->SetNumberOfPoints(surface->GetNumberOfPoints());
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
      moved->SetPoint(i, posed_points->GetPoint(ids ? ids->GetValue(i) : i));
    surface->SetPoints(moved);
  }

  if (options.field == SceneOptions::Field::Image)
  {
    // 2D image mode: the picture warped by the deformation (texture coordinates of the rest
    // mesh on the posed points), the controls on top; no colour map, no level sets
    if (!options.texture || !surface->GetPointData()->GetTCoords())
      throw Error(ErrorCode::InvalidArgument,
        "the image view needs a picture: open a picture as the model (image mode)");
    vtkNew<vtkTexture> texture;
    texture->SetInputData(options.texture);
    texture->InterpolateOn();
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(surface);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->SetTexture(texture);
    actor->GetProperty()->LightingOff();
    renderer->AddActor(actor);
    info.shown_points = surface->GetNumberOfPoints();
    if (controls && options.show_controls)
      add_controls(renderer, controls, posed_controls, options, weighted);
    return info;
  }

  vtkSmartPointer<vtkPolyData> shown = surface;
  if (options.clip && options.dimension == 3 && has_volume_cells(weighted))
  {
    // a volume mesh is sliced: the cut face shows the field inside
    shown = sliced_volume(weighted, weights, posed_points, options, gradient);
    info.sliced_volume = true;
  }
  else if (options.clip && options.dimension == 3)
  {
    double b[6];
    surface->GetBounds(b);
    vtkNew<vtkClipPolyData> clip;
    clip->SetInputData(surface);
    clip->SetClipFunction(clip_plane(b, options));
    clip->InsideOutOn(); // keep the part below the plane: the slider sweeps it through the model
    clip->Update();
    shown = clip->GetOutput();
  }
  info.shown_points = shown->GetNumberOfPoints();

  vtkDataArray* field = shown->GetPointData()->GetScalars();
  double range[2] = { 0.0, 1.0 };
  if (field && field->GetNumberOfTuples() > 0)
    field->GetRange(range);
  if (options.log_scale)
  {
    range[1] = std::max(range[1], 1e-12);
    range[0] = std::max(range[1] * 1e-6, gradient ? range[0] : info.influence_level * 1e-2);
    range[0] = std::min(range[0], range[1] * 0.1);
  }
  else
  {
    if (!gradient)
      range[0] = std::min(range[0], 0.0);
    range[1] = std::max(range[1], range[0] + 1e-12);
  }
  info.range[0] = range[0];
  info.range[1] = range[1];

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(shown);
  auto lut = make_lut(range[0], range[1], options.log_scale);
  mapper->SetLookupTable(lut);
  mapper->SetScalarRange(range);
  mapper->UseLookupTableScalarRangeOn();
  mapper->SetScalarModeToUsePointData();
  mapper->ScalarVisibilityOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  if (options.clip && options.dimension == 3)
    actor->GetProperty()->BackfaceCullingOff();
  renderer->AddActor(actor);

  // level sets
  std::vector<double> levels;
  if (options.isolines > 0)
  {
    if (options.log_scale)
      for (double v = std::pow(10.0, std::ceil(std::log10(range[0]))); v < range[1]; v *= 10.0)
        levels.push_back(v);
    else
      for (int i = 0; i < options.isolines; ++i)
        levels.push_back(range[1] * (i + 1.0) / (options.isolines + 1.0));
  }
  const double black[3] = { 0.05, 0.05, 0.05 }, magenta[3] = { 0.85, 0.1, 0.75 },
               red[3] = { 0.9, 0.1, 0.1 };
  add_level_set(renderer, shown, levels, black, 1.5);
  if (!gradient && range[0] < 0.0 && options.isolines > 0)
    add_level_set(renderer, shown, { 0.0 }, red, 2.5);
  if (!gradient && options.influence_level)
    add_level_set(renderer, shown, { info.influence_level }, magenta, 3.0);

  if (controls && options.show_controls)
    add_controls(renderer, controls, posed_controls, options, weighted);

  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  bar->SetTitle(gradient ? "|grad w|" : "w");
  bar->SetNumberOfLabels(5);
  bar->SetWidth(0.08);
  bar->SetHeight(0.6);
  bar->SetPosition(0.9, 0.2);
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->SetLabelFormat(options.log_scale ? "%.0e" : "%.2g");
  renderer->AddActor2D(bar);
  if (!options.title.empty())
  {
    vtkNew<vtkTextActor> text;
    text->SetInput(options.title.c_str());
    text->GetTextProperty()->SetFontSize(16);
    text->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
    text->SetPosition(10, 10);
    renderer->AddActor2D(text);
  }
  return info;
}

void ResetSceneCamera(vtkRenderer* renderer, int dimension)
{
  vtkCamera* camera = renderer->GetActiveCamera();
  if (dimension == 2)
  {
    camera->SetFocalPoint(0.0, 0.0, 0.0);
    camera->SetPosition(0.0, 0.0, 1.0);
    camera->SetViewUp(0.0, 1.0, 0.0);
    camera->ParallelProjectionOn();
    renderer->ResetCamera();
    // fit the bounds to the viewport (narrow side-by-side views included)
    double b[6];
    renderer->ComputeVisiblePropBounds(b);
    const double aspect = std::max(renderer->GetTiledAspectRatio(), 1e-6);
    if (b[0] <= b[1])
    {
      const double scale = 0.5 * std::max(b[3] - b[2], 1.25 * (b[1] - b[0]) / aspect) * 1.06;
      camera->SetParallelScale(scale);
      // leave the right tenth of the view to the colour bar
      const double shift = 0.08 * 2.0 * scale * aspect;
      double f[3], p[3];
      camera->GetFocalPoint(f);
      camera->GetPosition(p);
      camera->SetFocalPoint(f[0] + shift, f[1], f[2]);
      camera->SetPosition(p[0] + shift, p[1], p[2]);
    }
  }
  else
  {
    camera->ParallelProjectionOff();
    camera->SetFocalPoint(0.0, 0.0, 0.0);
    camera->SetPosition(0.3, -1.0, 0.6);
    camera->SetViewUp(0.0, 0.0, 1.0);
    renderer->ResetCamera();
  }
}

} // namespace viewer
} // namespace barylab
