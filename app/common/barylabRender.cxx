#include "barylabRender.h"

#include "vtkBaryConversion.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBarySplineData.h"

#include "core/common/error.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourFilter.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkDoubleArray.h"
#include "vtkElevationFilter.h"
#include "vtkFloatArray.h"
#include "vtkExtractEdges.h"
#include "vtkGlyph3D.h"
#include "vtkMath.h"
#include "vtkPNGReader.h"
#include "vtkPNGWriter.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkScalarBarActor.h"
#include "vtkSphereSource.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkCellData.h"
#include "vtkImageData.h"
#include "vtkWindowToImageFilter.h"
#include "vtkCutter.h"
#include "vtkMatrix3x3.h"
#include "vtkPlane.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace barylab
{
namespace
{
using bary::Error;
using bary::ErrorCode;

/// Perceptually uniform map (viridis control points).
vtkSmartPointer<vtkColorTransferFunction> make_colormap(double lo, double hi)
{
  static const double viridis[][3] = { { 0.267, 0.005, 0.329 }, { 0.283, 0.141, 0.458 },
    { 0.254, 0.265, 0.530 }, { 0.207, 0.372, 0.553 }, { 0.164, 0.471, 0.558 },
    { 0.128, 0.567, 0.551 }, { 0.135, 0.659, 0.518 }, { 0.267, 0.749, 0.441 },
    { 0.478, 0.821, 0.318 }, { 0.741, 0.873, 0.150 }, { 0.993, 0.906, 0.144 } };
  auto ctf = vtkSmartPointer<vtkColorTransferFunction>::New();
  for (int i = 0; i <= 10; ++i)
    ctf->AddRGBPoint(lo + (hi - lo) * i / 10.0, viridis[i][0], viridis[i][1], viridis[i][2]);
  return ctf;
}

/// The surface of @p data with one weight component as active scalars named "weight".
vtkSmartPointer<vtkPolyData> surface_with_component(
  vtkDataSet* data, const RenderOptions& options, double range[2])
{
  vtkDataArray* weights = data->GetPointData()->GetArray(options.weights_name.c_str());
  vtkNew<vtkDataSetSurfaceFilter> surface;
  surface->SetInputData(data);
  surface->Update();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->ShallowCopy(surface->GetOutput());
  range[0] = 0.0;
  range[1] = 1.0;
  if (!weights)
    return poly;
  if (options.component < 0 || options.component >= weights->GetNumberOfComponents())
    throw Error(ErrorCode::InvalidArgument,
      "control point " + std::to_string(options.component) + " does not exist (the weights have " +
        std::to_string(weights->GetNumberOfComponents()) + " components)");
  vtkDataArray* surfaceWeights = poly->GetPointData()->GetArray(options.weights_name.c_str());
  vtkNew<vtkDoubleArray> w;
  w->SetName("weight");
  w->SetNumberOfTuples(poly->GetNumberOfPoints());
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
    w->SetValue(i, surfaceWeights->GetComponent(i, options.component));
  poly->GetPointData()->SetScalars(w);
  w->GetRange(range);
  range[0] = std::min(range[0], 0.0);
  range[1] = std::max(range[1], range[0] + 1e-12);
  return poly;
}

void add_weight_actors(vtkRenderer* renderer, vtkPolyData* surface, const double range[2],
  const RenderOptions& options, bool colored)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(surface);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  if (colored)
  {
    mapper->SetLookupTable(make_colormap(range[0], range[1]));
    mapper->SetScalarRange(range[0], range[1]);
    mapper->ScalarVisibilityOn();
    mapper->SetScalarModeToUsePointData();
  }
  else
  {
    mapper->ScalarVisibilityOff();
    actor->GetProperty()->SetColor(0.85, 0.75, 0.6);
  }
  renderer->AddActor(actor);
  if (colored && !options.levels.empty())
  { // requested level sets (e.g. the influence level), blue and thick, under the isolines
    vtkNew<vtkContourFilter> level;
    level->SetInputData(surface);
    for (std::size_t i = 0; i < options.levels.size(); ++i)
      level->SetValue(static_cast<int>(i), options.levels[i]);
    vtkNew<vtkPolyDataMapper> lm;
    lm->SetInputConnection(level->GetOutputPort());
    lm->ScalarVisibilityOff();
    vtkNew<vtkActor> la;
    la->SetMapper(lm);
    la->GetProperty()->SetColor(0.1, 0.25, 0.95);
    la->GetProperty()->SetLineWidth(3.0);
    renderer->AddActor(la);
  }
  if (!colored || options.isolines <= 0)
    return;
  vtkNew<vtkContourFilter> contour;
  contour->SetInputData(surface);
  // evenly spaced over the positive part of the range (0.1 ... 0.9 for a [0, 1] field)
  const int n = options.isolines;
  const double top = std::max(range[1], 1e-12);
  for (int i = 0; i < n; ++i)
    contour->SetValue(i, top * (i + 1.0) / (n + 1.0));
  vtkNew<vtkPolyDataMapper> lines;
  lines->SetInputConnection(contour->GetOutputPort());
  lines->ScalarVisibilityOff();
  vtkNew<vtkActor> lineActor;
  lineActor->SetMapper(lines);
  lineActor->GetProperty()->SetColor(0.05, 0.05, 0.05);
  lineActor->GetProperty()->SetLineWidth(1.5);
  renderer->AddActor(lineActor);
  if (range[0] < 0.0)
  { // where the weight changes sign
    vtkNew<vtkContourFilter> zero;
    zero->SetInputData(surface);
    zero->SetValue(0, 0.0);
    vtkNew<vtkPolyDataMapper> zm;
    zm->SetInputConnection(zero->GetOutputPort());
    zm->ScalarVisibilityOff();
    vtkNew<vtkActor> za;
    za->SetMapper(zm);
    za->GetProperty()->SetColor(0.9, 0.1, 0.1);
    za->GetProperty()->SetLineWidth(2.5);
    renderer->AddActor(za);
  }
}

/// The cage as a wireframe (2D: the polygon in order; 3D: the triangle edges), its control
/// points as spheres, control point @p highlight in red.
void add_cage_actors(vtkRenderer* renderer, vtkPolyData* rest_cage, vtkPointSet* posed,
  const RenderOptions& options)
{
  const vtkBaryCage cage = options.free_points
    ? vtkBaryConversion::ToControlPoints(rest_cage, options.cage_dimension)
    : vtkBaryConversion::ToCage(rest_cage, options.cage_dimension);
  vtkPoints* points = posed ? posed->GetPoints() : rest_cage->GetPoints();
  if (!options.free_points)
  {
    vtkNew<vtkPolyData> wire;
    wire->SetPoints(points);
    if (cage.Cage.dimension() == 2)
    {
      vtkNew<vtkCellArray> loop;
      const vtkIdType n = static_cast<vtkIdType>(cage.ControlPointIds.size());
      loop->InsertNextCell(n + 1);
      for (vtkIdType k = 0; k <= n; ++k)
        loop->InsertCellPoint(cage.ControlPointIds[static_cast<std::size_t>(k % n)]);
      wire->SetLines(loop);
    }
    else
      wire->SetPolys(rest_cage->GetPolys());
    vtkNew<vtkExtractEdges> edges;
    edges->SetInputData(wire);
    vtkNew<vtkPolyDataMapper> wm;
    wm->SetInputConnection(cage.Cage.dimension() == 2 ? nullptr : edges->GetOutputPort());
    if (cage.Cage.dimension() == 2)
      wm->SetInputData(wire);
    wm->ScalarVisibilityOff();
    vtkNew<vtkActor> wa;
    wa->SetMapper(wm);
    wa->GetProperty()->SetColor(0.25, 0.25, 0.3);
    wa->GetProperty()->SetLineWidth(2.0);
    renderer->AddActor(wa);
  }

  const double radius = 0.012 * cage.Cage.diameter();
  const double blue[3] = { 0.2, 0.35, 0.8 };
  AddSpheres(renderer, points, radius, blue);

  if (options.component >= 0 && options.component < points->GetNumberOfPoints())
  {
    vtkNew<vtkSphereSource> selected;
    selected->SetCenter(points->GetPoint(options.component));
    selected->SetRadius(2.0 * radius);
    selected->SetThetaResolution(16);
    selected->SetPhiResolution(16);
    vtkNew<vtkPolyDataMapper> sm;
    sm->SetInputConnection(selected->GetOutputPort());
    vtkNew<vtkActor> sa;
    sa->SetMapper(sm);
    sa->GetProperty()->SetColor(0.9, 0.15, 0.1);
    renderer->AddActor(sa);
  }
}

/// Skeleton handles: bones as thick lines, joints as spheres, handle options.component in red.
/// Returns the selected handle's centre in @p selected.
void add_skeleton_actors(vtkRenderer* renderer, vtkPolyData* handles, vtkPointSet* posed,
  const RenderOptions& options, double selected[3], bool* has_selected)
{
  const bary::Skeleton skeleton = vtkBaryConversion::ToSkeleton(handles, 3);
  vtkPoints* points = posed ? posed->GetPoints() : handles->GetPoints();
  double bounds[6];
  points->GetBounds(bounds);
  const double diameter = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) + (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const auto lines_actor = [&](const std::vector<int>& bones, double width, const double rgb[3]) {
    vtkNew<vtkCellArray> cells;
    for (int b : bones)
    {
      const vtkIdType ids[2] = { skeleton.BE(b, 0), skeleton.BE(b, 1) };
      cells->InsertNextCell(2, ids);
    }
    AddLines(renderer, points, cells, width, rgb);
  };
  const auto sphere_actor = [&](const double* center, double radius, const double rgb[3]) {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(center[0], center[1], center[2]);
    sphere->SetRadius(radius);
    sphere->SetThetaResolution(16);
    sphere->SetPhiResolution(16);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(sphere->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
    renderer->AddActor(actor);
  };
  const double grey[3] = { 0.25, 0.25, 0.3 }, blue[3] = { 0.2, 0.35, 0.8 }, red[3] = { 0.9, 0.15, 0.1 };
  std::vector<int> all(static_cast<std::size_t>(skeleton.BE.rows()));
  for (std::size_t b = 0; b < all.size(); ++b)
    all[b] = static_cast<int>(b);
  lines_actor(all, 4.0, grey);
  const double radius = 0.012 * diameter;
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    sphere_actor(points->GetPoint(i), radius, blue);
  *has_selected = false;
  const int j = options.component, np = static_cast<int>(skeleton.P.size());
  if (j >= 0 && j < np)
  {
    points->GetPoint(skeleton.P(j), selected);
    sphere_actor(selected, 2.0 * radius, red);
    *has_selected = true;
  }
  else if (j >= np && j < np + skeleton.BE.rows())
  {
    lines_actor({ j - np }, 7.0, red);
    double a[3], b[3];
    points->GetPoint(skeleton.BE(j - np, 0), a);
    points->GetPoint(skeleton.BE(j - np, 1), b);
    for (int k = 0; k < 3; ++k)
      selected[k] = 0.5 * (a[k] + b[k]);
    sphere_actor(a, 1.5 * radius, red);
    sphere_actor(b, 1.5 * radius, red);
    *has_selected = true;
  }
}

/// 2 when the points of @p data lie in a plane z = const, else 3.
int planar_dimension(vtkDataSet* data)
{
  double b[6];
  data->GetBounds(b);
  return b[5] - b[4] <= 1e-9 * std::max(1.0, std::max(b[1] - b[0], b[3] - b[2])) ? 2 : 3;
}

/// 2D: orthographic view from +z. 3D: perspective view from the side of the selected control
/// point @p towards (if given), so the region it influences most faces the viewer.
void set_camera(vtkRenderer* renderer, int dimension, const double* towards = nullptr)
{
  renderer->ResetCamera();
  vtkCamera* camera = renderer->GetActiveCamera();
  if (dimension == 2)
  {
    camera->ParallelProjectionOn();
    renderer->ResetCamera();
    camera->SetParallelScale(camera->GetParallelScale() * 0.92);
  }
  else
  {
    double focal[3], position[3];
    camera->GetFocalPoint(focal);
    camera->GetPosition(position);
    if (towards)
    {
      const double distance = std::sqrt(vtkMath::Distance2BetweenPoints(focal, position));
      double dir[3] = { towards[0] - focal[0], towards[1] - focal[1], towards[2] - focal[2] };
      // tilt towards +z a little so the shape reads as 3D
      const double n = vtkMath::Norm(dir);
      if (n > 0.0)
      {
        for (double& d : dir)
          d /= n;
        dir[2] += 0.5;
        vtkMath::Normalize(dir);
        camera->SetPosition(focal[0] + distance * dir[0], focal[1] + distance * dir[1],
          focal[2] + distance * dir[2]);
        camera->SetViewUp(std::abs(dir[2]) > 0.9 ? 0.0 : 0.0, std::abs(dir[2]) > 0.9 ? 1.0 : 0.0,
          std::abs(dir[2]) > 0.9 ? 0.0 : 1.0);
      }
    }
    else
    {
      camera->Azimuth(35.0);
      camera->Elevation(20.0);
    }
    camera->OrthogonalizeViewUp();
    renderer->ResetCamera();
    camera->Zoom(1.15);
  }
  renderer->ResetCameraClippingRange();
}

vtkSmartPointer<vtkRenderWindow> make_window(const RenderOptions& options)
{
  if (!HasDisplay())
    throw Error(ErrorCode::InvalidArgument,
      "rendering needs an X display, but DISPLAY is not set; run under Xvfb "
      "(e.g. xvfb-run -a barylab ...)");
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetSize(options.width, options.height);
  window->SetMultiSamples(0);
  window->SetOffScreenRendering(options.offscreen ? 1 : 0);
  return window;
}

void add_title(vtkRenderer* renderer, const std::string& text)
{
  if (text.empty())
    return;
  vtkNew<vtkTextActor> title;
  title->SetInput(text.c_str());
  title->GetTextProperty()->SetFontSize(18);
  title->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
  title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  title->GetPositionCoordinate()->SetValue(0.015, 0.02);
  renderer->AddViewProp(title);
}
} // namespace

namespace
{
/// Physical point of the (continuous) structured index @p ijk of @p image: origin + D (s ∘ ijk).
void index_to_physical(vtkImageData* image, const double ijk[3], double x[3])
{
  const double* o = image->GetOrigin();
  const double* s = image->GetSpacing();
  vtkMatrix3x3* D = image->GetDirectionMatrix();
  for (int r = 0; r < 3; ++r)
    x[r] = o[r] + D->GetElement(r, 0) * s[0] * ijk[0] + D->GetElement(r, 1) * s[1] * ijk[1] +
      D->GetElement(r, 2) * s[2] * ijk[2];
}

/// The structured index of physical point @p x of @p image (the inverse of index_to_physical).
void physical_to_index(vtkImageData* image, const double x[3], double ijk[3])
{
  vtkNew<vtkMatrix3x3> inverse;
  vtkMatrix3x3::Invert(image->GetDirectionMatrix(), inverse);
  const double* o = image->GetOrigin();
  const double* s = image->GetSpacing();
  const double d[3] = { x[0] - o[0], x[1] - o[1], x[2] - o[2] };
  for (int c = 0; c < 3; ++c)
    ijk[c] = (inverse->GetElement(c, 0) * d[0] + inverse->GetElement(c, 1) * d[1] +
               inverse->GetElement(c, 2) * d[2]) / s[c];
}

/// The colour of label @p value: 1 an organ's brown-red, 2 a lesion's yellow, others spread
/// over the hues.
void label_colour(double value, unsigned char rgb[3])
{
  double c[3];
  if (value == 1.0)
    c[0] = 0.78, c[1] = 0.42, c[2] = 0.36;
  else if (value == 2.0)
    c[0] = 0.96, c[1] = 0.82, c[2] = 0.20;
  else
    vtkMath::HSVToRGB(std::fmod(0.13 * std::abs(value), 1.0), 0.6, 0.85, c, c + 1, c + 2);
  for (int k = 0; k < 3; ++k)
    rgb[k] = static_cast<unsigned char>(std::lround(255.0 * c[k]));
}

/// The non-zero voxels of @p image's slice through @p center normal to its second axis, as
/// flat quads (one cell per voxel, direct RGB colours); @p plane_origin gets a point of the
/// slice's plane and @p normal the plane's unit normal (the second axis).
vtkSmartPointer<vtkPolyData> label_slice(
  vtkImageData* image, const double center[3], double plane_origin[3], double normal[3])
{
  int e[6];
  image->GetExtent(e);
  double c[3];
  physical_to_index(image, center, c);
  const int j = std::clamp(static_cast<int>(std::lround(c[1])), e[2], e[3]);
  const double on_plane[3] = { static_cast<double>(e[0]), static_cast<double>(j), static_cast<double>(e[4]) };
  index_to_physical(image, on_plane, plane_origin);
  for (int r = 0; r < 3; ++r)
    normal[r] = image->GetDirectionMatrix()->GetElement(r, 1);
  vtkMath::Normalize(normal);
  vtkDataArray* labels = image->GetPointData()->GetScalars();
  if (!labels)
    throw Error(ErrorCode::EmptyInput, "the label map has no voxel values to draw");
  const int nx = e[1] - e[0] + 1, nz = e[5] - e[4] + 1;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(nx + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int i = 0; i <= nx; ++i)
    {
      const double ijk[3] = { e[0] + i - 0.5, static_cast<double>(j), e[4] + k - 0.5 };
      double x[3];
      index_to_physical(image, ijk, x);
      points->SetPoint(static_cast<vtkIdType>(k) * (nx + 1) + i, x);
    }
  vtkNew<vtkCellArray> quads;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  colours->SetName("LabelColour");
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i)
    {
      int ijk[3] = { e[0] + i, j, e[4] + k };
      const double value = labels->GetComponent(image->ComputePointId(ijk), 0);
      if (value == 0.0)
        continue;
      const vtkIdType a = static_cast<vtkIdType>(k) * (nx + 1) + i;
      const vtkIdType quad[4] = { a, a + 1, a + nx + 2, a + nx + 1 };
      quads->InsertNextCell(4, quad);
      unsigned char rgb[3];
      label_colour(value, rgb);
      colours->InsertNextTypedTuple(rgb);
    }
  auto slice = vtkSmartPointer<vtkPolyData>::New();
  slice->SetPoints(points);
  slice->SetPolys(quads);
  slice->GetCellData()->SetScalars(colours);
  return slice;
}
} // namespace

vtkSmartPointer<vtkRenderWindow> LabelSliceWindow(vtkImageData* before, vtkImageData* after,
  vtkPolyData* rest_surface, vtkPolyData* deformed_surface, const double center[3],
  const RenderOptions& options)
{
  auto window = make_window(options);
  vtkImageData* images[2] = { before, after };
  vtkPolyData* surfaces[2] = { rest_surface, deformed_surface };
  const char* titles[2] = { "label map; line: the organ's surface",
    "warped label map; line: the surface deformed directly" };
  double plane_origin[3], normal[3], up[3];
  vtkRenderer* first = nullptr;
  double bounds[6] = { 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 };
  for (int side = 0; side < 2; ++side)
  {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(0.5 * side, 0.0, 0.5 * side + 0.5, 1.0);
    renderer->SetBackground(side == 0 ? 0.97 : 1.0, side == 0 ? 0.97 : 1.0, 1.0);
    window->AddRenderer(renderer);
    auto slice = label_slice(images[side], center, plane_origin, normal);
    double b[6];
    slice->GetBounds(b);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
    }
    vtkNew<vtkPolyDataMapper> sliceMapper;
    sliceMapper->SetInputData(slice);
    sliceMapper->SetColorModeToDirectScalars();
    sliceMapper->SetScalarModeToUseCellData();
    vtkNew<vtkActor> sliceActor;
    sliceActor->SetMapper(sliceMapper);
    sliceActor->GetProperty()->LightingOff();
    renderer->AddActor(sliceActor);
    if (surfaces[side])
    {
      vtkNew<vtkPlane> plane;
      plane->SetOrigin(plane_origin);
      plane->SetNormal(normal);
      vtkNew<vtkCutter> cutter;
      cutter->SetInputData(surfaces[side]);
      cutter->SetCutFunction(plane);
      // drawn a little in front of the slice (the camera looks along +normal)
      vtkNew<vtkTransform> shift;
      const double h = 0.5 * images[side]->GetSpacing()[1];
      shift->Translate(-h * normal[0], -h * normal[1], -h * normal[2]);
      vtkNew<vtkTransformPolyDataFilter> shifted;
      shifted->SetInputConnection(cutter->GetOutputPort());
      shifted->SetTransform(shift);
      vtkNew<vtkPolyDataMapper> lineMapper;
      lineMapper->SetInputConnection(shifted->GetOutputPort());
      lineMapper->ScalarVisibilityOff();
      vtkNew<vtkActor> lineActor;
      lineActor->SetMapper(lineMapper);
      lineActor->GetProperty()->SetColor(0.05, 0.15, 0.55);
      lineActor->GetProperty()->SetLineWidth(3.0);
      lineActor->GetProperty()->LightingOff();
      renderer->AddActor(lineActor);
    }
    add_title(renderer, side == 0 ? titles[0] : titles[1]);
    if (!first)
      first = renderer;
    else
      renderer->SetActiveCamera(first->GetActiveCamera());
  }
  for (int r = 0; r < 3; ++r)
    up[r] = before->GetDirectionMatrix()->GetElement(r, 2);
  // Seen from the front of the second axis (anterior for LPS), head (third axis) up.
  const double d = vtkMath::Dot(normal, center) - vtkMath::Dot(normal, plane_origin);
  double focal[3];
  for (int r = 0; r < 3; ++r)
    focal[r] = center[r] - d * normal[r];
  vtkCamera* camera = first->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(focal);
  camera->SetPosition(focal[0] - 500.0 * normal[0], focal[1] - 500.0 * normal[1], focal[2] - 500.0 * normal[2]);
  camera->SetViewUp(up);
  camera->OrthogonalizeViewUp();
  first->ResetCamera(bounds);
  camera->Zoom(1.1);
  for (vtkRenderer* renderer : { first, vtkRenderer::SafeDownCast(window->GetRenderers()->GetItemAsObject(1)) })
    if (renderer)
      renderer->ResetCameraClippingRange(bounds);
  return window;
}

void AddSpheres(vtkRenderer* renderer, vtkPoints* points, double radius, const double rgb[3])
{
  vtkNew<vtkPolyData> verts;
  verts->SetPoints(points);
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(12);
  sphere->SetPhiResolution(12);
  vtkNew<vtkGlyph3D> glyphs;
  glyphs->SetInputData(verts);
  glyphs->SetSourceConnection(sphere->GetOutputPort());
  glyphs->ScalingOff();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(glyphs->GetOutputPort());
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  renderer->AddActor(actor);
}

void AddLines(vtkRenderer* renderer, vtkPoints* points, vtkCellArray* lines, double width,
  const double rgb[3])
{
  vtkNew<vtkPolyData> wire;
  wire->SetPoints(points);
  wire->SetLines(lines);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(wire);
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetLineWidth(static_cast<float>(width));
  renderer->AddActor(actor);
}

bool HasDisplay()
{
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

vtkSmartPointer<vtkRenderWindow> WeightFieldWindow(
  vtkDataSet* data, vtkPolyData* cage, const RenderOptions& options)
{
  if (!data)
    throw Error(ErrorCode::EmptyInput, "no data to render");
  vtkBaryConversion::RequirePointArray(data, options.weights_name);
  auto window = make_window(options);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1.0, 1.0, 1.0);
  window->AddRenderer(renderer);
  double range[2];
  auto surface = surface_with_component(data, options, range);
  RenderOptions drawn = options;
  if (options.influence_level)
    drawn.levels.push_back(
      1e-3 / data->GetPointData()->GetArray(options.weights_name.c_str())->GetNumberOfComponents());
  add_weight_actors(renderer, surface, range, drawn, true);
  int dimension = 3;
  double selected[3];
  bool has_selected = false;
  if (cage && options.skeleton)
  {
    dimension = planar_dimension(data);
    add_skeleton_actors(renderer, cage, nullptr, options, selected, &has_selected);
  }
  else if (cage)
  {
    dimension = (options.free_points ? vtkBaryConversion::ToControlPoints(cage, options.cage_dimension)
                                     : vtkBaryConversion::ToCage(cage, options.cage_dimension))
                  .Cage.dimension();
    if (options.show_cage)
      add_cage_actors(renderer, cage, nullptr, options);
    if (options.component >= 0 && options.component < cage->GetNumberOfPoints())
    {
      cage->GetPoint(options.component, selected);
      has_selected = true;
    }
  }
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(make_colormap(range[0], range[1]));
  bar->SetTitle(("w" + std::to_string(options.component)).c_str());
  bar->SetNumberOfLabels(5);
  bar->SetMaximumWidthInPixels(90);
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->SetPosition(0.88, 0.1);
  bar->SetWidth(0.1);
  bar->SetHeight(0.8);
  renderer->AddViewProp(bar);
  add_title(renderer, options.title);
  set_camera(renderer, dimension, has_selected ? selected : nullptr);
  return window;
}

vtkSmartPointer<vtkRenderWindow> DeformationWindow(vtkDataSet* rest, vtkPolyData* rest_cage,
  vtkDataSet* deformed, vtkPointSet* posed_cage, const RenderOptions& options)
{
  auto window = make_window(options);
  const int dimension = options.skeleton ? planar_dimension(rest)
    : options.free_points && rest_cage
    ? vtkBaryConversion::ToControlPoints(rest_cage, options.cage_dimension).Cage.dimension()
    : rest_cage ? vtkBaryConversion::ToCage(rest_cage, options.cage_dimension).Cage.dimension()
                : 3;
  double handle_center[3];
  bool has_handle = false;
  vtkDataSet* datas[2] = { rest, deformed };
  vtkRenderer* first = nullptr;
  for (int side = 0; side < 2; ++side)
  {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(0.5 * side, 0.0, 0.5 * side + 0.5, 1.0);
    renderer->SetBackground(side == 0 ? 0.97 : 1.0, side == 0 ? 0.97 : 1.0, 1.0);
    window->AddRenderer(renderer);
    double range[2];
    const bool colored = datas[side]->GetPointData()->GetArray(options.weights_name.c_str());
    auto surface = surface_with_component(datas[side], options, range);
    add_weight_actors(renderer, surface, range, options, colored);
    if (rest_cage && options.skeleton)
      add_skeleton_actors(renderer, rest_cage, side == 0 ? nullptr : posed_cage, options,
        handle_center, &has_handle);
    else if (rest_cage && options.show_cage)
      add_cage_actors(renderer, rest_cage, side == 0 ? nullptr : posed_cage, options);
    add_title(renderer, side == 0 ? "rest" : "deformed");
    if (!first)
    {
      // frame both poses: camera fitted to the union of both scenes, then shared
      renderer->ResetCamera();
      first = renderer;
    }
    else
      renderer->SetActiveCamera(first->GetActiveCamera());
    if (side == 1)
    {
      double b0[6], b1[6], b[6];
      first->ComputeVisiblePropBounds(b0);
      renderer->ComputeVisiblePropBounds(b1);
      for (int k = 0; k < 3; ++k)
      {
        b[2 * k] = std::min(b0[2 * k], b1[2 * k]);
        b[2 * k + 1] = std::max(b0[2 * k + 1], b1[2 * k + 1]);
      }
      double selected[3];
      bool has_selected = !options.skeleton && rest_cage && options.component >= 0 &&
        options.component < rest_cage->GetNumberOfPoints();
      if (has_selected)
        rest_cage->GetPoint(options.component, selected);
      else if (options.skeleton && has_handle)
      {
        std::copy(handle_center, handle_center + 3, selected);
        has_selected = true;
      }
      set_camera(first, dimension, has_selected ? selected : nullptr);
      first->ResetCamera(b);
      first->ResetCameraClippingRange(b);
      renderer->ResetCameraClippingRange(b);
    }
  }
  return window;
}

vtkSmartPointer<vtkPolyData> PoseHandles(vtkPolyData* handles, const std::vector<Eigen::MatrixXd>& pose)
{
  // a skeleton or mixed handles (cage vertices and region corners move with their handle)
  const bary::Skeleton skeleton = vtkBaryMixedHandles::ToHandles(handles, 3);
  if (static_cast<bary::Index>(pose.size()) != skeleton.handle_count())
    throw Error(ErrorCode::SizeMismatch,
      "the pose has " + std::to_string(pose.size()) + " transforms but the skeleton has " +
        std::to_string(skeleton.handle_count()) + " handles");
  const vtkIdType n = handles->GetNumberOfPoints();
  std::vector<int> owner(static_cast<std::size_t>(n), -1);
  const int np = static_cast<int>(skeleton.P.size());
  for (int j = 0; j < np; ++j)
    owner[static_cast<std::size_t>(skeleton.P(j))] = j;
  for (int end : { 1, 0 })
    for (int b = 0; b < skeleton.BE.rows(); ++b)
      if (owner[static_cast<std::size_t>(skeleton.BE(b, end))] < 0)
        owner[static_cast<std::size_t>(skeleton.BE(b, end))] = np + b;
  const Eigen::VectorXi cage = skeleton.cage_joints();
  const int first_cage = np + static_cast<int>(skeleton.BE.rows());
  for (Eigen::Index k = 0; k < cage.size(); ++k)
    owner[static_cast<std::size_t>(cage(k))] = first_cage + static_cast<int>(k);
  for (std::size_t r = 0; r < skeleton.regions.size(); ++r)
    for (Eigen::Index k = 0; k < skeleton.regions[r].size(); ++k)
      owner[static_cast<std::size_t>(skeleton.regions[r].data()[k])] =
        first_cage + static_cast<int>(cage.size() + static_cast<Eigen::Index>(r));
  auto posed = vtkSmartPointer<vtkPolyData>::New();
  posed->DeepCopy(handles);
  for (vtkIdType i = 0; i < n; ++i)
  {
    Eigen::Vector3d x;
    handles->GetPoint(i, x.data());
    const Eigen::MatrixXd& T = pose[static_cast<std::size_t>(owner[static_cast<std::size_t>(i)])];
    const Eigen::Vector3d y = T.leftCols(3) * x + T.col(3);
    posed->GetPoints()->SetPoint(i, y.data());
  }
  return posed;
}

void WritePNG(vtkRenderWindow* window, const std::string& path)
{
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  const std::string tmp = path + ".tmp.png";
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(tmp.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0 || std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw Error(ErrorCode::Io, "cannot write image '" + path + "'");
  }
}

vtkSmartPointer<vtkPolyData> MeaningfulSurfaceWeights(vtkPolyData* weighted, const std::string& name)
{
  auto shown = vtkSmartPointer<vtkPolyData>::New();
  shown->DeepCopy(weighted);
  vtkDataArray* w = shown->GetPointData()->GetArray(name.c_str());
  vtkDataArray* defined = shown->GetPointData()->GetArray("Defined");
  if (!w || !defined)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "the surface has no '" + name + "' and 'Defined' point arrays (vtkBarySurfaceWeights' output)");
  for (vtkIdType p = 0; p < w->GetNumberOfTuples(); ++p)
  {
    bool shown_here = defined->GetComponent(p, 0) != 0;
    for (int c = 0; c < w->GetNumberOfComponents(); ++c)
      shown_here = shown_here && w->GetComponent(p, c) >= -1.0;
    if (!shown_here)
      for (int c = 0; c < w->GetNumberOfComponents(); ++c)
        w->SetComponent(p, c, std::numeric_limits<double>::quiet_NaN());
  }
  return shown;
}

vtkSmartPointer<vtkRenderWindow> SurfaceWeightsWindow(vtkPolyData* weighted, vtkPointSet* anchors,
  vtkPolyData* curve, const RenderOptions& options)
{
  auto shown = MeaningfulSurfaceWeights(weighted, options.weights_name);
  vtkNew<vtkPolyData> anchor_points;
  anchor_points->SetPoints(anchors->GetPoints());
  RenderOptions o = options;
  o.free_points = true;
  auto window = WeightFieldWindow(shown, anchor_points, o);
  if (curve && curve->GetNumberOfLines() > 0)
  {
    const double yellow[3] = { 1.0, 0.85, 0.1 };
    AddLines(window->GetRenderers()->GetFirstRenderer(), curve->GetPoints(), curve->GetLines(), 4.0, yellow);
  }
  return window;
}

// --- C1 spline deformations -----------------------------------------------------------------

vtkSmartPointer<vtkPolyData> SplineGridLines(vtkUnstructuredGrid* grid, int samples, double z)
{
  const vtkBarySpline spline = vtkBarySplineData::FromGrid(grid);
  const bary::SplineNet& net = spline.xy->net();
  const auto& E = net.edges();
  const auto& ET = net.edge_triangles();
  const bary::TriangularSpline::Locations where = bary::edge_sample_locations(net, samples);
  const Eigen::MatrixXd X = spline.xy->evaluate(where);
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(X.rows());
  for (bary::Index p = 0; p < X.rows(); ++p)
    points->SetPoint(p, X(p, 0), X(p, 1), z);
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkUnsignedCharArray> border;
  border->SetName("Border");
  std::vector<vtkIdType> ids(static_cast<size_t>(samples) + 1);
  for (bary::Index e = 0; e < E.rows(); ++e)
  {
    for (int s = 0; s <= samples; ++s)
      ids[static_cast<size_t>(s)] = e * (samples + 1) + s;
    lines->InsertNextCell(samples + 1, ids.data());
    border->InsertNextValue(ET(e, 0) < 0 || ET(e, 1) < 0);
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  out->SetLines(lines);
  out->GetCellData()->AddArray(border);
  return out;
}

namespace
{

/// Folded triangles (check_jacobian) of a spline grid, sampled and mapped, as filled polygons.
vtkSmartPointer<vtkPolyData> spline_folds(vtkUnstructuredGrid* grid, double z)
{
  const vtkBarySpline spline = vtkBarySplineData::FromGrid(grid);
  const bary::JacobianReport rep = spline.xy->check_jacobian();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys;
  const int n = 8;
  for (bary::Index t : rep.folded)
  {
    // A triangle fan of the sampled triangle: the boundary mapped, as one polygon.
    std::vector<vtkIdType> ids;
    const Eigen::Vector3d corner[3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    for (int k = 0; k < 3; ++k)
      for (int s = 0; s < n; ++s)
      {
        const Eigen::Vector3d b = corner[k] + (double(s) / n) * (corner[(k + 1) % 3] - corner[k]);
        const Eigen::RowVectorXd x = spline.xy->evaluate(t, b);
        ids.push_back(points->InsertNextPoint(x[0], x[1], z));
      }
    polys->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  out->SetPoints(points);
  out->SetPolys(polys);
  return out;
}

} // namespace

vtkSmartPointer<vtkRenderWindow> SplineDeformationWindow(vtkUnstructuredGrid* rest_grid,
  vtkUnstructuredGrid* grid, vtkPointSet* rest_model, vtkPointSet* model,
  const std::string& picture_png, const RenderOptions& options)
{
  auto window = make_window(options);
  const vtkBarySpline rest = vtkBarySplineData::FromGrid(rest_grid);
  const Eigen::MatrixXd& V = rest.xy->net().vertices();
  const double lo[2] = { V.col(0).minCoeff(), V.col(1).minCoeff() };
  const double hi[2] = { V.col(0).maxCoeff(), V.col(1).maxCoeff() };
  // Heights of both models on one colour scale.
  double zr[2] = { std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity() };
  for (vtkPointSet* m : { rest_model, model })
    if (m)
    {
      double b[6];
      m->GetBounds(b);
      zr[0] = std::min(zr[0], b[4]);
      zr[1] = std::max(zr[1], b[5]);
    }
  vtkSmartPointer<vtkTexture> texture;
  if (!picture_png.empty())
  {
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(picture_png.c_str());
    reader->Update();
    if (reader->GetOutput()->GetNumberOfPoints() == 0)
      throw Error(ErrorCode::Io, "cannot read the picture '" + picture_png + "'");
    texture = vtkSmartPointer<vtkTexture>::New();
    texture->SetInputConnection(reader->GetOutputPort());
    texture->InterpolateOn();
  }
  vtkUnstructuredGrid* grids[2] = { rest_grid, grid };
  vtkPointSet* models[2] = { rest_model, model };
  vtkRenderer* first = nullptr;
  for (int side = 0; side < 2; ++side)
  {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(0.0, side == 0 ? 0.5 : 0.0, 1.0, side == 0 ? 1.0 : 0.5);
    renderer->SetBackground(1.0, 1.0, 1.0);
    window->AddRenderer(renderer);
    const double top = zr[1] > zr[0] ? zr[1] + 0.01 : 0.01;
    if (texture)
    {
      vtkNew<vtkPlaneSource> plane;
      const double bottom = zr[1] > zr[0] ? zr[0] - 0.01 : -0.01;
      plane->SetOrigin(lo[0], lo[1], bottom);
      plane->SetPoint1(hi[0], lo[1], bottom);
      plane->SetPoint2(lo[0], hi[1], bottom);
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(plane->GetOutputPort());
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      actor->SetTexture(texture);
      actor->GetProperty()->LightingOff();
      renderer->AddActor(actor);
    }
    if (models[side])
    {
      vtkNew<vtkDataSetSurfaceFilter> surface;
      surface->SetInputData(models[side]);
      vtkNew<vtkElevationFilter> height;
      height->SetInputConnection(surface->GetOutputPort());
      height->SetLowPoint(0, 0, zr[0]);
      height->SetHighPoint(0, 0, zr[1] > zr[0] ? zr[1] : zr[0] + 1);
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(height->GetOutputPort());
      mapper->SetScalarRange(0, 1);
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      actor->GetProperty()->SetOpacity(0.85);
      renderer->AddActor(actor);
    }
    {
      auto lines = SplineGridLines(grids[side], 16, top);
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputData(lines);
      mapper->ScalarVisibilityOff();
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      actor->GetProperty()->SetColor(0.15, 0.3, 0.75);
      actor->GetProperty()->SetLineWidth(1.5);
      actor->GetProperty()->LightingOff();
      renderer->AddActor(actor);
      auto folds = spline_folds(grids[side], top + 0.001);
      if (folds->GetNumberOfCells() > 0)
      {
        vtkNew<vtkPolyDataMapper> fm;
        fm->SetInputData(folds);
        vtkNew<vtkActor> fa;
        fa->SetMapper(fm);
        fa->GetProperty()->SetColor(0.9, 0.1, 0.1);
        fa->GetProperty()->SetOpacity(0.6);
        fa->GetProperty()->LightingOff();
        renderer->AddActor(fa);
      }
    }
    add_title(renderer, side == 0 ? "rest" : (options.title.empty() ? "deformed" : options.title));
    if (!first)
    {
      vtkCamera* camera = renderer->GetActiveCamera();
      camera->ParallelProjectionOn();
      camera->SetFocalPoint(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0);
      camera->SetPosition(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 10);
      camera->SetViewUp(0, 1, 0);
      renderer->ResetCamera();
      camera->SetParallelScale(0.56 * std::max(hi[1] - lo[1], (hi[0] - lo[0]) * 0.5 * options.height / options.width));
      renderer->ResetCameraClippingRange();
      first = renderer;
    }
    else
    {
      renderer->SetActiveCamera(first->GetActiveCamera());
    }
  }
  return window;
}

namespace
{

/// The spline's domain cut into k x k small triangles per domain triangle, mapped by the xy
/// deformation, with texture coordinates of the rest positions in @p bounds.
vtkSmartPointer<vtkPolyData> spline_textured_domain(
  vtkUnstructuredGrid* grid, int k, const double bounds[4], double z)
{
  const vtkBarySpline spline = vtkBarySplineData::FromGrid(grid);
  const bary::SplineNet& net = spline.xy->net();
  const auto& V = net.vertices();
  const auto& T = net.triangles();
  bary::TriangularSpline::Locations where;
  std::vector<Eigen::Vector2d> rest;
  for (bary::Index t = 0; t < net.num_triangles(); ++t)
    for (int i = 0; i <= k; ++i)
      for (int j = 0; j <= k - i; ++j)
      {
        const Eigen::Vector3d b(double(k - i - j) / k, double(i) / k, double(j) / k);
        where.triangle.push_back(t);
        where.barycentric.push_back(b);
        rest.push_back(b[0] * V.row(T(t, 0)).transpose() + b[1] * V.row(T(t, 1)).transpose() +
          b[2] * V.row(T(t, 2)).transpose());
      }
  const Eigen::MatrixXd X = spline.xy->evaluate(where);
  vtkNew<vtkPoints> points;
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  for (size_t p = 0; p < rest.size(); ++p)
  {
    points->InsertNextPoint(X(static_cast<bary::Index>(p), 0), X(static_cast<bary::Index>(p), 1), z);
    tcoords->InsertNextTuple2((rest[p].x() - bounds[0]) / (bounds[1] - bounds[0]),
      (rest[p].y() - bounds[2]) / (bounds[3] - bounds[2]));
  }
  vtkNew<vtkCellArray> polys;
  const int per = (k + 1) * (k + 2) / 2;
  auto id = [&](bary::Index t, int i, int j) {
    // row i holds k - i + 1 points
    int offset = 0;
    for (int r = 0; r < i; ++r)
      offset += k - r + 1;
    return static_cast<vtkIdType>(t * per + offset + j);
  };
  for (bary::Index t = 0; t < net.num_triangles(); ++t)
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k - i; ++j)
      {
        const vtkIdType a[3] = { id(t, i, j), id(t, i + 1, j), id(t, i, j + 1) };
        polys->InsertNextCell(3, a);
        if (j + 1 < k - i)
        {
          const vtkIdType b[3] = { id(t, i + 1, j), id(t, i + 1, j + 1), id(t, i, j + 1) };
          polys->InsertNextCell(3, b);
        }
      }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  out->SetPolys(polys);
  out->GetPointData()->SetTCoords(tcoords);
  return out;
}

} // namespace

vtkSmartPointer<vtkRenderWindow> SplinePictureWindow(vtkUnstructuredGrid* rest_grid,
  vtkUnstructuredGrid* grid, const std::string& picture_png, const double bounds[4],
  const RenderOptions& options)
{
  auto window = make_window(options);
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(picture_png.c_str());
  reader->Update();
  if (reader->GetOutput()->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::Io, "cannot read the picture '" + picture_png + "'");
  vtkNew<vtkTexture> texture;
  texture->SetInputConnection(reader->GetOutputPort());
  texture->InterpolateOn();
  vtkUnstructuredGrid* grids[2] = { rest_grid, grid };
  vtkRenderer* first = nullptr;
  double view[6] = { 1e300, -1e300, 1e300, -1e300, 0, 0 };
  for (int side = 0; side < 2; ++side)
  {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(0.5 * side, 0.0, 0.5 * side + 0.5, 1.0);
    renderer->SetBackground(side == 0 ? 0.97 : 1.0, side == 0 ? 0.97 : 1.0, 1.0);
    window->AddRenderer(renderer);
    auto mesh = spline_textured_domain(grids[side], 12, bounds, 0.0);
    double b[6];
    mesh->GetBounds(b);
    for (int c = 0; c < 2; ++c)
    {
      view[2 * c] = std::min(view[2 * c], b[2 * c]);
      view[2 * c + 1] = std::max(view[2 * c + 1], b[2 * c + 1]);
    }
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(mesh);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->SetTexture(texture);
    actor->GetProperty()->LightingOff();
    renderer->AddActor(actor);
    auto lines = SplineGridLines(grids[side], 16, 0.01);
    vtkNew<vtkPolyDataMapper> lm;
    lm->SetInputData(lines);
    lm->ScalarVisibilityOff();
    vtkNew<vtkActor> la;
    la->SetMapper(lm);
    la->GetProperty()->SetColor(0.15, 0.3, 0.75);
    la->GetProperty()->SetOpacity(0.5);
    la->GetProperty()->LightingOff();
    renderer->AddActor(la);
    auto folds = spline_folds(grids[side], 0.02);
    if (folds->GetNumberOfCells() > 0)
    {
      vtkNew<vtkPolyDataMapper> fm;
      fm->SetInputData(folds);
      vtkNew<vtkActor> fa;
      fa->SetMapper(fm);
      fa->GetProperty()->SetColor(0.9, 0.1, 0.1);
      fa->GetProperty()->SetOpacity(0.6);
      fa->GetProperty()->LightingOff();
      renderer->AddActor(fa);
    }
    add_title(renderer, side == 0 ? "rest" : (options.title.empty() ? "deformed" : options.title));
    if (!first)
      first = renderer;
    else
      renderer->SetActiveCamera(first->GetActiveCamera());
  }
  vtkCamera* camera = first->GetActiveCamera();
  camera->ParallelProjectionOn();
  const double cx = 0.5 * (view[0] + view[1]), cy = 0.5 * (view[2] + view[3]);
  camera->SetFocalPoint(cx, cy, 0);
  camera->SetPosition(cx, cy, 10);
  camera->SetViewUp(0, 1, 0);
  const double aspect = 0.5 * options.width / options.height;
  camera->SetParallelScale(0.54 * std::max(view[3] - view[2], (view[1] - view[0]) / aspect));
  first->ResetCameraClippingRange();
  return window;
}

} // namespace barylab
