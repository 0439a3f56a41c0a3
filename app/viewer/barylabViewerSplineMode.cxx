#include "barylabViewerSplineMode.h"

#include "barylabPipeline.h"
#include "barylabViewerExamples.h"
#include "barylabViewerScene.h"

#include "vtkBaryDataIO.h"
#include "vtkBarySplineData.h"
#include "vtkBarySplineSource.h"
#include "core/common/error.h"
#include "core/spline/decles.h"
#include "core/spline/triangular_spline.h"

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QFileInfo>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QSpinBox>
#include <QStatusBar>
#include <QVBoxLayout>

#include <QVTKOpenGLNativeWidget.h>

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkGenericOpenGLRenderWindow.h"
#include "vtkImageData.h"
#include "vtkInteractorObserver.h"
#include "vtkInteractorStyleImage.h"
#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataNormals.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace barylab
{
namespace viewer
{
namespace
{
const char* kSplineExample = "organism-spline";
/// Samples along each domain edge of the drawn grid, and per side of a folded triangle's fill.
constexpr int kEdgeSamples = 16;
constexpr int kFoldSamples = 12;
/// The side view's share of the view's height (bottom / top modes), and its section's samples.
constexpr double kSideHeight = 0.3;
constexpr int kSectionSamples = 240;

const char* target_name(SplineTarget t)
{
  return t == SplineTarget::XY ? "xy" : t == SplineTarget::Bottom ? "bottom" : "top";
}

/// Colours of the control points by ControlPointType (Table 1), and of the last edit's sets.
const unsigned char kTypeColour[6][3] = {
  { 30, 30, 30 },   // corner
  { 40, 90, 200 },  // edge corner
  { 90, 150, 230 }, // edge
  { 20, 140, 60 },  // inner corner
  { 90, 190, 110 }, // inner edge
  { 170, 170, 170 } // interior
};
const unsigned char kPinned[3] = { 110, 70, 40 };
const unsigned char kDerived[3] = { 255, 150, 0 };
const unsigned char kAnchor[3] = { 220, 0, 0 };
const unsigned char kSelected[3] = { 255, 230, 0 };
} // namespace

struct SplineWindow::Internals
{
  std::unique_ptr<bary::SplineEditor> Editors[3]; ///< xy, bottom, top (the latter two for 2.5D)
  double PrismBottom = 0.0, PrismTop = 0.0;
  std::vector<bary::Index> Pinned;
  QString SplineName;
  double Bounds[4] = { 0.0, 1.0, 0.0, 1.0 }; ///< the domain's bounding rectangle
  double Size = 1.0;                         ///< its diagonal

  vtkSmartPointer<vtkPolyData> Model;    ///< at rest
  vtkSmartPointer<vtkPolyData> Deformed; ///< same cells, moved points, `Z` (active scalars)
  Eigen::MatrixXd ModelRest;             ///< #P by 3
  bary::TriangularSpline::Locations Where; ///< the model's points in the domain (located once)
  QString ModelName;

  bary::TriangularSpline::Locations GridWhere; ///< the samples of the domain's edges
  vtkNew<vtkPolyData> Grid;
  vtkNew<vtkPolyData> Points; ///< phi's control points with `Colours`
  vtkNew<vtkPolyData> Folds;  ///< folded triangles (sampled, filled)
  vtkNew<vtkPoints> CentrePoint;
  vtkSmartPointer<vtkImageData> Picture;
  QString PictureName;
  /// The model's mappers coloured by z in the view (bottom / top modes): their range follows.
  std::vector<vtkPolyDataMapper*> ZMappers;
  vtkTextActor* Title = nullptr; ///< the view's title (says when the map folds)

  std::vector<SplineTarget> Done, Undone; ///< which spline each undo / redo step changes
  std::vector<bary::Index> LastAnchors, LastDerived;
  QString LastEdit;
  double Residual = 0.0; ///< of xy's C1 conditions, relative to the grid size

  // a drag in the view
  int Dragging = -1;
  bool DragApplied = false;
  double DragStart[2] = { 0.0, 0.0 }; ///< the mouse in world coordinates at the press

  QVTKOpenGLNativeWidget* View = nullptr;
  vtkNew<vtkRenderer> Renderer; ///< picture and model (layer 0)
  vtkNew<vtkRenderer> Overlay;  ///< grid, control points, centre, folds (layer 1: on top)
  /// bottom / top modes: the side view (from -y) of the model and the prism's section, a strip
  /// under the view from above
  vtkNew<vtkRenderer> Side;
  vtkNew<vtkPolyData> Section; ///< the bottom and top surfaces along y = SectionY, deformed
  bary::TriangularSpline::Locations SectionWhere;
  double SectionY = 0.0;
  bool SectionLocated = false;
  vtkNew<vtkCallbackCommand> Callback;
  vtkNew<vtkCallbackCommand> ResizeCallback;
  /// The camera as resetCamera left it: while it is so, a resized view is fitted again.
  double FittedScale = 0.0;
  double FittedFocal[3] = { 0.0, 0.0, 0.0 };

  QLabel* Info = nullptr;
  QLabel* PointInfo = nullptr;
  QLabel* CentreInfo = nullptr;
  QLabel* EditInfo = nullptr;
  QLabel* Warning = nullptr;
  QComboBox* TargetBox = nullptr;
  QSpinBox* DeltaBox = nullptr;
  QDoubleSpinBox* DxBox = nullptr;
  QDoubleSpinBox* DyBox = nullptr;
  QDoubleSpinBox* DzBox = nullptr;
  QDoubleSpinBox* AngleBox = nullptr;
  QDoubleSpinBox* FactorBox = nullptr;
  QWidget* XYRow = nullptr;
  QWidget* ZRow = nullptr;
  QPushButton* RotateButton = nullptr;
  QPushButton* ScaleButton = nullptr;
  QPushButton* UndoButton = nullptr;
  QPushButton* RedoButton = nullptr;
  bool Updating = false;

  const bary::TriangularSpline& xy() const { return this->Editors[0]->spline(); }
};

SplineWindow::SplineWindow(QWidget* parent)
  : QMainWindow(parent)
  , I(new Internals)
{
  this->setWindowTitle("BaryLab viewer: C1 spline deformations");
  this->I->View = new QVTKOpenGLNativeWidget(this);
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  this->I->View->setRenderWindow(window);
  window->SetNumberOfLayers(2);
  window->SetMultiSamples(0);
  this->I->Renderer->SetBackground(1.0, 1.0, 1.0);
  this->I->Overlay->SetLayer(1);
  this->I->Overlay->InteractiveOff();
  this->I->Overlay->SetActiveCamera(this->I->Renderer->GetActiveCamera());
  window->AddRenderer(this->I->Renderer);
  window->AddRenderer(this->I->Overlay);
  window->AddRenderer(this->I->Side);
  this->I->Side->SetBackground(0.97, 0.97, 0.97);
  vtkNew<vtkInteractorStyleImage> style; // 2D: no rotation; wheel / right drag zoom, middle pans
  this->I->View->interactor()->SetInteractorStyle(style);
  this->setCentralWidget(this->I->View);
  this->buildPanel();
  this->buildMenus();
  this->installInteraction();
  this->statusBar()->showMessage("Open a spline (File menu) or the organism example");
}

SplineWindow::~SplineWindow() = default;

QStringList SplineWindow::ExampleNames()
{
  return { kSplineExample };
}

bool SplineWindow::IsExample(const QString& name)
{
  return ExampleNames().contains(name);
}

bool SplineWindow::hasSpline() const
{
  return this->I->Editors[0] != nullptr;
}

bool SplineWindow::isPrism() const
{
  return this->I->Editors[1] != nullptr;
}

const bary::TriangularSpline* SplineWindow::spline(SplineTarget t) const
{
  const auto& e = this->I->Editors[static_cast<int>(t)];
  return e ? &e->spline() : nullptr;
}

bary::SplineEditor* SplineWindow::editor(SplineTarget t) const
{
  return this->I->Editors[static_cast<int>(t)].get();
}

vtkPolyData* SplineWindow::model() const
{
  return this->I->Model;
}

vtkPolyData* SplineWindow::deformedModel() const
{
  return this->I->Deformed;
}

vtkPolyData* SplineWindow::deformedGrid() const
{
  return this->I->Grid;
}

vtkPoints* SplineWindow::controlPoints() const
{
  return this->I->Points->GetPoints();
}

QVTKOpenGLNativeWidget* SplineWindow::view() const
{
  return this->I->View;
}

vtkRenderer* SplineWindow::renderer() const
{
  return this->I->Renderer;
}

vtkRenderer* SplineWindow::sideRenderer() const
{
  return this->I->Side;
}

vtkPolyData* SplineWindow::sectionData() const
{
  return this->I->Section;
}

bool SplineWindow::canUndo() const
{
  return !this->I->Done.empty();
}

bool SplineWindow::canRedo() const
{
  return !this->I->Undone.empty();
}

QString SplineWindow::warning() const
{
  if (!this->hasSpline())
    return QString();
  if (!this->Folded.empty())
    return QString("The map folds: Jacobian <= 0 in %1 triangle%2 (red), min %3")
      .arg(this->Folded.size())
      .arg(this->Folded.size() == 1 ? "" : "s")
      .arg(this->MinJacobian, 0, 'g', 3);
  if (this->MinJacobian <= 0.0)
    return QString("The Jacobian reaches %1: the map degenerates").arg(this->MinJacobian, 0, 'g', 3);
  return QString();
}

void SplineWindow::reportError(const QString& message)
{
  this->Errors << message;
  this->statusBar()->showMessage(message);
  emit this->errorReported(message);
  if (this->Interactive)
    QMessageBox::warning(this, "BaryLab viewer", message);
}

template <class Action>
bool SplineWindow::reporting(Action&& action)
{
  try
  {
    action();
    return true;
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
}

// --- opening ------------------------------------------------------------------------------

namespace
{
/// The samples of every domain edge (bary::edge_sample_locations, kEdgeSamples + 1 each) and the
/// polylines over them.
bary::TriangularSpline::Locations edge_samples(const bary::SplineNet& net, vtkCellArray* lines)
{
  bary::TriangularSpline::Locations where = bary::edge_sample_locations(net, kEdgeSamples);
  for (bary::Index e = 0; e < net.edges().rows(); ++e)
  {
    lines->InsertNextCell(kEdgeSamples + 1);
    for (int s = 0; s <= kEdgeSamples; ++s)
      lines->InsertCellPoint(static_cast<vtkIdType>(e * (kEdgeSamples + 1) + s));
  }
  return where;
}
} // namespace

bool SplineWindow::openSpline(const QString& path)
{
  vtkBarySpline spline;
  const bool ok = this->reporting([&]() {
    vtkSmartPointer<vtkDataSet> data = vtkBaryDataIO::Read(path.toStdString());
    auto* grid = vtkUnstructuredGrid::SafeDownCast(data);
    if (!grid)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "'" + path.toStdString() + "' is not an unstructured grid of Bézier triangles",
        "make one with barylab spline create");
    spline = vtkBarySplineData::FromGrid(grid);
  });
  return ok && this->useSpline(spline, QFileInfo(path).fileName());
}

bool SplineWindow::useSpline(const vtkBarySpline& spline, const QString& name)
{
  std::unique_ptr<bary::SplineEditor> editors[3];
  const bool ok = this->reporting([&]() {
    if (!spline.xy)
      throw bary::Error(bary::ErrorCode::InvalidArgument, name.toStdString() + " holds no spline");
    // the editors check C1 (edits keep it, they cannot create it) and the pinned points
    editors[0] = std::make_unique<bary::SplineEditor>(*spline.xy);
    if (spline.is_prism())
    {
      editors[1] = std::make_unique<bary::SplineEditor>(*spline.bottom);
      editors[2] = std::make_unique<bary::SplineEditor>(*spline.top);
    }
    for (auto& e : editors)
      if (e)
        e->set_pinned(spline.pinned);
  });
  if (!ok)
    return false;
  Internals& I = *this->I;
  for (int k = 0; k < 3; ++k)
    I.Editors[k] = std::move(editors[k]);
  I.Pinned = spline.pinned;
  I.PrismBottom = spline.prism_bottom;
  I.PrismTop = spline.prism_top;
  I.SplineName = name;
  const bary::SplineNet& net = I.xy().net();
  const Eigen::MatrixXd& V = net.vertices();
  I.Bounds[0] = V.col(0).minCoeff();
  I.Bounds[1] = V.col(0).maxCoeff();
  I.Bounds[2] = V.col(1).minCoeff();
  I.Bounds[3] = V.col(1).maxCoeff();
  I.Size = std::hypot(I.Bounds[1] - I.Bounds[0], I.Bounds[3] - I.Bounds[2]);
  vtkNew<vtkCellArray> lines;
  I.GridWhere = edge_samples(net, lines);
  vtkNew<vtkPoints> samples;
  samples->SetDataTypeToDouble();
  samples->SetNumberOfPoints(static_cast<vtkIdType>(I.GridWhere.triangle.size()));
  I.Grid->Initialize();
  I.Grid->SetPoints(samples);
  I.Grid->SetLines(lines);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(net.num_points());
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("Colours");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(net.num_points());
  for (vtkIdType p = 0; p < net.num_points(); ++p)
    verts->InsertNextCell(1, &p);
  I.Points->Initialize();
  I.Points->SetPoints(points);
  I.Points->SetVerts(verts);
  I.Points->GetPointData()->SetScalars(colours);
  I.SectionLocated = false;
  I.Done.clear();
  I.Undone.clear();
  I.LastAnchors.clear();
  I.LastDerived.clear();
  I.LastEdit.clear();
  I.Dragging = -1;
  this->Selected = -1;
  this->Selection.clear();
  this->HasCentre = false;
  I.CentrePoint->Reset();
  I.CentrePoint->Modified();
  if (!this->isPrism() && this->Target != SplineTarget::XY)
    this->Target = SplineTarget::XY;
  // the model stays when it lies in the new domain
  if (I.Model)
  {
    vtkSmartPointer<vtkPolyData> model = I.Model;
    I.Model = nullptr;
    I.Deformed = nullptr;
    this->reporting([&]() {
      I.Where = I.xy().locate(I.ModelRest.leftCols(2));
      I.Model = model;
    });
  }
  if (I.Model)
  {
    I.Deformed = vtkSmartPointer<vtkPolyData>::New();
    I.Deformed->ShallowCopy(I.Model);
  }
  this->CameraNeedsReset = true;
  this->statusBar()->showMessage("Drag a control point; Ctrl + click picks the centre of rotations and scales");
  this->update();
  this->updateScene();
  return true;
}

bool SplineWindow::openModel(const QString& path)
{
  if (!this->hasSpline())
  {
    this->reportError("open a spline first: the model is placed in its domain");
    return false;
  }
  Internals& I = *this->I;
  vtkSmartPointer<vtkPolyData> model;
  Eigen::MatrixXd rest;
  bary::TriangularSpline::Locations where;
  const bool ok = this->reporting([&]() {
    model = vtkBaryDataIO::ReadPolyData(path.toStdString());
    const vtkIdType n = model->GetNumberOfPoints();
    if (n == 0)
      throw bary::Error(bary::ErrorCode::EmptyInput, "'" + path.toStdString() + "' has no points");
    rest.resize(n, 3);
    for (vtkIdType p = 0; p < n; ++p)
    {
      double x[3];
      model->GetPoint(p, x);
      rest.row(p) << x[0], x[1], x[2];
    }
    where = I.xy().locate(rest.leftCols(2));
    if (this->isPrism())
    {
      const double lo = I.PrismBottom, hi = I.PrismTop;
      for (vtkIdType p = 0; p < n; ++p)
        if (!(rest(p, 2) >= lo - 1e-12 * (hi - lo) && rest(p, 2) <= hi + 1e-12 * (hi - lo)))
          throw bary::Error(bary::ErrorCode::PointsOutside,
            "point " + std::to_string(p) + " of '" + path.toStdString() + "' (z = " +
              std::to_string(rest(p, 2)) + ") lies outside the prism [" + std::to_string(lo) +
              ", " + std::to_string(hi) + "]");
    }
  });
  if (!ok)
    return false;
  I.Model = model;
  I.ModelRest = rest;
  I.Where = std::move(where);
  I.ModelName = QFileInfo(path).fileName();
  I.Deformed = vtkSmartPointer<vtkPolyData>::New();
  I.Deformed->ShallowCopy(model);
  this->update();
  this->updateScene();
  return true;
}

bool SplineWindow::openPicture(const QString& path)
{
  vtkSmartPointer<vtkImageData> picture;
  if (!this->reporting([&]() { picture = ReadPicture(path.toStdString()); }))
    return false;
  this->I->Picture = picture;
  this->I->PictureName = QFileInfo(path).fileName();
  this->updatePanel();
  this->updateScene();
  return true;
}

bool SplineWindow::loadExample(const QString& name)
{
  if (name != kSplineExample)
  {
    this->reportError("no spline example named '" + name + "' (" + ExampleNames().join(", ") + ")");
    return false;
  }
  vtkBarySpline spline;
  const bool ok = this->reporting([&]() {
    auto source = vtkSmartPointer<vtkBarySplineSource>::New();
    source->SetInputData(vtkBaryDataIO::ReadPolyData(DataPath("spline_domain.obj").toStdString()));
    source->PrismOn();
    source->SetPrismBottom(-0.1);
    source->SetPrismTop(0.1);
    RunAlgorithm(source, RunCallbacks{});
    spline = vtkBarySplineData::FromGrid(source->GetOutput());
  });
  if (!ok || !this->useSpline(spline, "the identity spline on spline_domain.obj"))
    return false;
  return this->openModel(DataPath("spline_organism.obj")) &&
    this->openPicture(DataPath("spline_organism_picture.png"));
}

// --- edits --------------------------------------------------------------------------------

void SplineWindow::setTarget(SplineTarget t)
{
  if (this->I->Dragging >= 0)
    return; // the drag's edits belong to one spline (its moves undo one another)
  if (t != SplineTarget::XY && !this->isPrism())
  {
    this->reportError("the bottom and top modes edit a 2.5D (prism) spline; this one is 2D");
    t = SplineTarget::XY;
  }
  const bool changed = t != this->Target;
  this->Target = t;
  this->I->LastAnchors.clear();
  this->I->LastDerived.clear();
  this->updatePointColours();
  this->updatePanel();
  if (changed)
    this->updateScene(); // the model coloured by z in the bottom / top modes
}

void SplineWindow::setDeltaMax(int delta_max)
{
  this->DeltaMax = std::clamp(delta_max, 0, bary::kMaxDeltaMax);
  this->updatePanel();
}

void SplineWindow::selectPoint(int i)
{
  if (!this->hasSpline() || i < 0 || i >= this->I->xy().net().num_points())
    i = -1;
  this->Selection.clear();
  if (i >= 0)
    this->Selection.push_back(i);
  this->selectionChanged();
}

void SplineWindow::toggleSelection(int i)
{
  if (!this->hasSpline() || i < 0 || i >= this->I->xy().net().num_points())
    return;
  const auto at = std::find(this->Selection.begin(), this->Selection.end(), i);
  if (at != this->Selection.end())
    this->Selection.erase(at);
  else
    this->Selection.push_back(i);
  this->selectionChanged();
}

void SplineWindow::selectionChanged()
{
  this->Selected = this->Selection.empty() ? -1 : this->Selection.back();
  this->updatePointColours();
  if (this->hasSpline())
    this->updateSection();
  this->updatePanel();
  if (this->hasSpline())
    this->I->View->renderWindow()->Render();
}

void SplineWindow::setCentre(double x, double y)
{
  this->HasCentre = true;
  this->Centre[0] = x;
  this->Centre[1] = y;
  this->I->CentrePoint->SetNumberOfPoints(1);
  this->I->CentrePoint->SetPoint(0, x, y, 0.0);
  this->I->CentrePoint->Modified();
  this->updatePanel();
  this->updateScene();
}

bool SplineWindow::applyEdit(const bary::SplineEdit& edit)
{
  Internals& I = *this->I;
  bary::SplineEditor* e = this->editor(this->Target);
  if (!e)
  {
    this->reportError("no spline: open one (File menu) or the organism example");
    return false;
  }
  bary::SplineEditReport report;
  if (!this->reporting([&]() { report = e->apply(edit); }))
    return false;
  I.Done.push_back(this->Target);
  I.Undone.clear();
  this->EditSeconds = report.seconds;
  I.LastAnchors = report.sets.anchors;
  I.LastDerived = report.sets.derived;
  I.LastEdit = QString("%1 %2: %3 anchor, %4 slaves, %5 derived, %6 conditions (%7 independent); "
                       "%8 ms%9")
                 .arg(target_name(this->Target))
                 .arg(bary::to_string(edit.op))
                 .arg(report.sets.anchors.size())
                 .arg(report.sets.slaves.size())
                 .arg(report.sets.derived.size())
                 .arg(report.sets.constraints.size())
                 .arg(report.sets.independent.size())
                 .arg(1e3 * report.seconds, 0, 'f', 2)
                 .arg(report.cached ? " (elimination cached)" : "");
  this->update();
  return true;
}

namespace
{
bary::SplineEdit anchored(const std::vector<int>& points, int delta_max)
{
  bary::SplineEdit edit;
  for (int p : points)
    edit.anchors.push_back(static_cast<bary::Index>(p));
  edit.delta_max = delta_max;
  return edit;
}
} // namespace

bool SplineWindow::translatePoint(int i, double dx, double dy)
{
  if (!this->hasSpline() || i < 0 || i >= this->I->xy().net().num_points())
  {
    this->reportError(QString("no control point %1 to move").arg(i));
    return false;
  }
  bary::SplineEdit edit = anchored({ i }, this->DeltaMax);
  edit.op = bary::SplineEditOp::Translate;
  if (this->Target == SplineTarget::XY)
    edit.by = Eigen::Vector2d(dx, dy);
  else
    edit.by = Eigen::VectorXd::Constant(1, dx);
  return this->applyEdit(edit);
}

bool SplineWindow::translateSelection(double dx, double dy)
{
  if (this->Selection.empty())
  {
    this->reportError("no control point selected: press on one (Shift + click adds more)");
    return false;
  }
  bary::SplineEdit edit = anchored(this->Selection, this->DeltaMax);
  edit.op = bary::SplineEditOp::Translate;
  if (this->Target == SplineTarget::XY)
    edit.by = Eigen::Vector2d(dx, dy);
  else
    edit.by = Eigen::VectorXd::Constant(1, dx);
  return this->applyEdit(edit);
}

bool SplineWindow::movePointTo(int i, double x, double y)
{
  if (!this->hasSpline() || i < 0 || i >= this->I->xy().net().num_points() ||
    this->Target != SplineTarget::XY)
  {
    this->reportError(QString("no control point %1 to move in the xy mode").arg(i));
    return false;
  }
  const Eigen::MatrixXd& v = this->I->xy().values();
  return this->translatePoint(i, x - v(i, 0), y - v(i, 1));
}

bool SplineWindow::rotateSelected(double degrees)
{
  if (this->Target != SplineTarget::XY || this->Selected < 0 || !this->HasCentre)
  {
    this->reportError("a rotation needs the xy mode, a selected control point and a centre "
                      "(Ctrl + click)");
    return false;
  }
  bary::SplineEdit edit = anchored(this->Selection, this->DeltaMax);
  edit.op = bary::SplineEditOp::Rotate;
  edit.center = Eigen::Vector2d(this->Centre[0], this->Centre[1]);
  edit.angle_degrees = degrees;
  return this->applyEdit(edit);
}

bool SplineWindow::scaleSelected(double factor)
{
  if (this->Target != SplineTarget::XY || this->Selected < 0 || !this->HasCentre)
  {
    this->reportError("a scale needs the xy mode, a selected control point and a centre "
                      "(Ctrl + click)");
    return false;
  }
  bary::SplineEdit edit = anchored(this->Selection, this->DeltaMax);
  edit.op = bary::SplineEditOp::Scale;
  edit.center = Eigen::Vector2d(this->Centre[0], this->Centre[1]);
  edit.factor = factor;
  return this->applyEdit(edit);
}

bool SplineWindow::undo()
{
  Internals& I = *this->I;
  if (I.Done.empty() || I.Dragging >= 0)
    return false;
  const SplineTarget t = I.Done.back();
  if (!this->editor(t)->undo())
    return false;
  I.Done.pop_back();
  I.Undone.push_back(t);
  I.LastAnchors.clear();
  I.LastDerived.clear();
  I.LastEdit = QString("undone (%1)").arg(target_name(t));
  this->update();
  return true;
}

bool SplineWindow::redo()
{
  Internals& I = *this->I;
  if (I.Undone.empty() || I.Dragging >= 0)
    return false;
  const SplineTarget t = I.Undone.back();
  if (!this->editor(t)->redo())
    return false;
  I.Undone.pop_back();
  I.Done.push_back(t);
  I.LastAnchors.clear();
  I.LastDerived.clear();
  I.LastEdit = QString("redone (%1)").arg(target_name(t));
  this->update();
  return true;
}

// --- what the splines give ----------------------------------------------------------------

void SplineWindow::update()
{
  if (!this->hasSpline())
    return;
  QElapsedTimer timer;
  timer.start();
  this->updateModel();
  this->updateGrid();
  this->updateSection();
  const qint64 jacobian_start = timer.nsecsElapsed();
  this->updateJacobian();
  this->JacobianSeconds = 1e-9 * static_cast<double>(timer.nsecsElapsed() - jacobian_start);
  // the C1 residual (a few ms): after every edit but a drag's moves (measured at the release)
  if (this->I->Dragging < 0)
    this->I->Residual =
      this->I->xy().continuity().max_condition_residual / this->I->xy().net().mean_edge_length();
  this->updatePointColours();
  this->updatePanel();
  if (this->I->Title)
    this->I->Title->SetInput(this->titleText().c_str());
  this->I->View->renderWindow()->Render();
  this->UpdateSeconds = 1e-9 * static_cast<double>(timer.nsecsElapsed());
  emit this->sceneUpdated();
}

void SplineWindow::updateModel()
{
  Internals& I = *this->I;
  if (!I.Model)
    return;
  const Eigen::MatrixXd xy = I.xy().evaluate(I.Where);
  const Eigen::Index n = xy.rows();
  Eigen::VectorXd z = I.ModelRest.col(2);
  if (this->isPrism())
  {
    const Eigen::MatrixXd b = I.Editors[1]->spline().evaluate(I.Where);
    const Eigen::MatrixXd t = I.Editors[2]->spline().evaluate(I.Where);
    const double lo = I.PrismBottom, hi = I.PrismTop;
    for (Eigen::Index p = 0; p < n; ++p)
    {
      const double u = (I.ModelRest(p, 2) - lo) / (hi - lo);
      z[p] = b(p, 0) + u * (t(p, 0) - b(p, 0));
    }
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkDoubleArray> height;
  height->SetName("Z");
  height->SetNumberOfTuples(n);
  for (Eigen::Index p = 0; p < n; ++p)
  {
    points->SetPoint(p, xy(p, 0), xy(p, 1), z[p]);
    height->SetValue(p, z[p]);
  }
  // the same data object (the actors follow it), its points replaced
  I.Deformed->SetPoints(points);
  I.Deformed->GetPointData()->SetScalars(height);
  I.Deformed->Modified();
  if (!I.ZMappers.empty())
  {
    double range[2];
    this->zRange(range);
    for (vtkPolyDataMapper* mapper : I.ZMappers)
      mapper->SetScalarRange(range);
  }
}

void SplineWindow::updateGrid()
{
  Internals& I = *this->I;
  const Eigen::MatrixXd g = I.xy().evaluate(I.GridWhere);
  vtkPoints* samples = I.Grid->GetPoints();
  for (Eigen::Index k = 0; k < g.rows(); ++k)
    samples->SetPoint(k, g(k, 0), g(k, 1), 0.0);
  samples->Modified();
  const Eigen::MatrixXd& v = I.xy().values();
  vtkPoints* points = I.Points->GetPoints();
  for (Eigen::Index k = 0; k < v.rows(); ++k)
    points->SetPoint(k, v(k, 0), v(k, 1), 0.0);
  points->Modified();
}

void SplineWindow::updateSection()
{
  Internals& I = *this->I;
  if (!this->isPrism())
    return;
  // the section through the selected point (its nominal y), else through the domain's middle
  const double y = this->Selected >= 0 ? I.xy().net().nominal()(this->Selected, 1)
                                       : 0.5 * (I.Bounds[2] + I.Bounds[3]);
  if (!I.SectionLocated || y != I.SectionY)
  {
    Eigen::MatrixXd P(kSectionSamples + 1, 2);
    for (int k = 0; k <= kSectionSamples; ++k)
      P.row(k) << I.Bounds[0] + (I.Bounds[1] - I.Bounds[0]) * k / kSectionSamples, y;
    I.SectionWhere = I.xy().locate(P, bary::OutsidePolicy::NaN);
    I.SectionY = y;
    I.SectionLocated = true;
  }
  const Eigen::MatrixXd xy = I.xy().evaluate(I.SectionWhere);
  const Eigen::MatrixXd b = I.Editors[1]->spline().evaluate(I.SectionWhere);
  const Eigen::MatrixXd t = I.Editors[2]->spline().evaluate(I.SectionWhere);
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  const unsigned char blue[3] = { 30, 60, 220 }, red[3] = { 220, 30, 30 };
  for (const Eigen::MatrixXd* z : { &b, &t })
  {
    std::vector<vtkIdType> run;
    const auto flush = [&]() {
      if (run.size() > 1)
        lines->InsertNextCell(static_cast<vtkIdType>(run.size()), run.data());
      run.clear();
    };
    for (int k = 0; k <= kSectionSamples; ++k)
    {
      if (I.SectionWhere.triangle[static_cast<size_t>(k)] < 0)
      {
        flush();
        continue;
      }
      run.push_back(points->InsertNextPoint(xy(k, 0), xy(k, 1), (*z)(k, 0)));
      colours->InsertNextTypedTuple(z == &b ? blue : red);
    }
    flush();
  }
  I.Section->SetPoints(points);
  I.Section->SetLines(lines);
  I.Section->GetPointData()->SetScalars(colours);
  I.Section->Modified();
}

void SplineWindow::updateJacobian()
{
  Internals& I = *this->I;
  const bary::JacobianReport report = I.xy().check_jacobian();
  this->MinJacobian = report.min_jacobian;
  this->Folded.assign(report.folded.begin(), report.folded.end());
  // the folded triangles, sampled and filled
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> triangles;
  const int m = kFoldSamples;
  for (bary::Index t : report.folded)
  {
    const vtkIdType first = points->GetNumberOfPoints();
    std::vector<vtkIdType> row_start;
    for (int i = 0; i <= m; ++i)
    {
      row_start.push_back(points->GetNumberOfPoints() - first);
      for (int j = 0; j <= m - i; ++j)
      {
        const Eigen::Vector3d b(static_cast<double>(i) / m, static_cast<double>(j) / m,
          static_cast<double>(m - i - j) / m);
        const Eigen::RowVectorXd x = I.xy().evaluate(t, b);
        points->InsertNextPoint(x[0], x[1], 0.0);
      }
    }
    const auto id = [&](int i, int j) { return first + row_start[static_cast<size_t>(i)] + j; };
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m - i; ++j)
      {
        triangles->InsertNextCell({ id(i, j), id(i + 1, j), id(i, j + 1) });
        if (j + 1 < m - i)
          triangles->InsertNextCell({ id(i + 1, j), id(i + 1, j + 1), id(i, j + 1) });
      }
  }
  I.Folds->SetPoints(points);
  I.Folds->SetPolys(triangles);
  I.Folds->Modified();
}

void SplineWindow::updatePointColours()
{
  Internals& I = *this->I;
  if (!this->hasSpline())
    return;
  const bary::SplineNet& net = I.xy().net();
  auto* colours = vtkUnsignedCharArray::SafeDownCast(I.Points->GetPointData()->GetScalars());
  for (bary::Index p = 0; p < net.num_points(); ++p)
    colours->SetTypedTuple(p, kTypeColour[static_cast<int>(net.type(p))]);
  for (bary::Index p : I.Pinned)
    colours->SetTypedTuple(p, kPinned);
  for (bary::Index p : I.LastDerived)
    colours->SetTypedTuple(p, kDerived);
  for (bary::Index p : I.LastAnchors)
    colours->SetTypedTuple(p, kAnchor);
  for (int p : this->Selection)
    colours->SetTypedTuple(p, kSelected);
  colours->Modified();
}

// --- drawing ------------------------------------------------------------------------------

namespace
{
vtkSmartPointer<vtkActor> line_actor(vtkPolyData* data, double width, const double rgb[3])
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(data);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetLineWidth(static_cast<float>(width));
  actor->GetProperty()->LightingOff();
  return actor;
}
} // namespace

double SplineWindow::verticalScale() const
{
  const Internals& I = *this->I;
  return this->isPrism() ? (I.PrismTop - I.PrismBottom) / (I.Bounds[3] - I.Bounds[2]) : 1.0;
}

void SplineWindow::zRange(double range[2]) const
{
  const Internals& I = *this->I;
  range[0] = I.PrismBottom;
  range[1] = I.PrismTop;
  if (I.Deformed)
    if (vtkDataArray* z = I.Deformed->GetPointData()->GetArray("Z"))
    {
      range[0] = std::min(range[0], z->GetRange()[0]);
      range[1] = std::max(range[1], z->GetRange()[1]);
    }
}

void SplineWindow::drawScene(vtkRenderer* scene, vtkRenderer* overlay, vtkRenderer* side)
{
  Internals& I = *this->I;
  const bool view = scene == I.Renderer.Get();
  if (view)
  {
    I.ZMappers.clear();
    I.Title = nullptr;
  }
  scene->RemoveAllViewProps();
  overlay->RemoveAllViewProps();
  if (side)
    side->RemoveAllViewProps();
  if (!this->hasSpline())
    return;
  // bottom / top modes: the side view is a strip under the view from above
  const bool with_side = side && this->isPrism() && this->Target != SplineTarget::XY;
  const double bottom = with_side ? kSideHeight : 0.0;
  scene->SetViewport(0.0, bottom, 1.0, 1.0);
  overlay->SetViewport(0.0, bottom, 1.0, 1.0);
  if (side)
  {
    side->SetViewport(0.0, 0.0, 1.0, with_side ? kSideHeight : 0.01);
    side->SetDraw(with_side);
  }
  // layer 0: the picture on the domain's rectangle, under the model
  double zlo = this->isPrism() ? I.PrismBottom : 0.0;
  if (I.Model)
    zlo = std::min(zlo, I.Model->GetBounds()[4]);
  const double zpicture = zlo - 0.05 * I.Size;
  if (I.Picture)
  {
    vtkNew<vtkPlaneSource> plane;
    plane->SetOrigin(I.Bounds[0], I.Bounds[2], zpicture);
    plane->SetPoint1(I.Bounds[1], I.Bounds[2], zpicture);
    plane->SetPoint2(I.Bounds[0], I.Bounds[3], zpicture);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(plane->GetOutputPort());
    vtkNew<vtkTexture> texture;
    texture->SetInputData(I.Picture);
    texture->InterpolateOn();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->SetTexture(texture);
    actor->GetProperty()->LightingOff();
    scene->AddActor(actor);
  }
  // the model: plain (xy mode) or coloured by z, blue (the prism's bottom) to red (top)
  vtkNew<vtkLookupTable> lut;
  lut->SetHueRange(0.667, 0.0);
  lut->SetTableRange(I.PrismBottom, I.PrismTop);
  lut->Build();
  const auto model_actor = [&](bool by_z) {
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputData(I.Deformed);
    normals->SplittingOff();
    normals->ConsistencyOff();
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(normals->GetOutputPort());
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    if (!by_z)
    {
      mapper->ScalarVisibilityOff();
      actor->GetProperty()->SetColor(0.95, 0.55, 0.2);
      actor->GetProperty()->SetOpacity(0.6);
      return actor;
    }
    mapper->SetLookupTable(lut);
    double range[2];
    this->zRange(range);
    mapper->SetScalarRange(range);
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray("Z");
    mapper->ScalarVisibilityOn();
    if (view)
      I.ZMappers.push_back(mapper);
    return actor;
  };
  if (I.Deformed)
  {
    scene->AddActor(model_actor(this->Target != SplineTarget::XY));
    if (this->Target != SplineTarget::XY)
    {
      vtkNew<vtkScalarBarActor> bar;
      bar->SetLookupTable(lut);
      bar->SetNumberOfLabels(3);
      bar->UnconstrainedFontSizeOn();
      bar->GetLabelTextProperty()->SetFontSize(12);
      bar->SetOrientationToHorizontal(); // under the domain, right of the title
      bar->SetPosition(0.55, 0.01);
      bar->SetWidth(0.42);
      bar->SetHeight(0.09);
      bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
      overlay->AddViewProp(bar);
    }
  }
  if (with_side)
  {
    if (I.Deformed)
      side->AddActor(model_actor(true));
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(I.Section);
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
    vtkNew<vtkActor> section;
    section->SetMapper(mapper);
    section->GetProperty()->SetLineWidth(2.0f);
    section->GetProperty()->LightingOff();
    side->AddActor(section);
    vtkNew<vtkTextActor> title;
    const std::string text = "side view (from -y): the model, and the bottom (blue) and top (red) "
                             "surfaces along the selected point's row";
    title->SetInput(text.c_str());
    title->GetTextProperty()->SetFontSize(14);
    title->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
    title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    title->GetPositionCoordinate()->SetValue(0.01, 0.86);
    side->AddViewProp(title);
    // orthographic, along +y, the prism's height and the domain's width fitted
    vtkCamera* camera = side->GetActiveCamera();
    const double cx = 0.5 * (I.Bounds[0] + I.Bounds[1]), cy = 0.5 * (I.Bounds[2] + I.Bounds[3]);
    const double cz = 0.5 * (I.PrismBottom + I.PrismTop);
    camera->ParallelProjectionOn();
    camera->SetFocalPoint(cx, cy, cz);
    camera->SetPosition(cx, cy - 4.0 * I.Size, cz);
    camera->SetViewUp(0.0, 0.0, 1.0);
    const double aspect = std::max(side->GetTiledAspectRatio(), 1e-6);
    camera->SetParallelScale(0.5 * 1.1 *
      std::max(2.0 * (I.PrismTop - I.PrismBottom), (I.Bounds[1] - I.Bounds[0]) / aspect));
    camera->SetClippingRange(0.1 * I.Size, 10.0 * I.Size);
  }
  // layer 1, always on top: folds, grid, control points, centre
  if (I.Folds)
  {
    const double red[3] = { 0.9, 0.0, 0.0 };
    vtkSmartPointer<vtkActor> folds = line_actor(I.Folds, 1.0, red);
    folds->GetProperty()->SetOpacity(0.45);
    overlay->AddActor(folds);
  }
  const double blue[3] = { 0.1, 0.2, 0.55 };
  overlay->AddActor(line_actor(I.Grid, 1.5, blue));
  {
    // points drawn as spheres by the GPU (no glyph geometry to rebuild on every drag step)
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(I.Points);
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetRepresentationToPoints();
    actor->GetProperty()->RenderPointsAsSpheresOn();
    actor->GetProperty()->SetPointSize(5.0f);
    overlay->AddActor(actor);
  }
  if (this->HasCentre)
  {
    const double magenta[3] = { 0.8, 0.0, 0.8 };
    vtkNew<vtkPoints> cross;
    vtkNew<vtkCellArray> lines;
    const double r = 0.02 * I.Size;
    cross->InsertNextPoint(this->Centre[0] - r, this->Centre[1], 0.0);
    cross->InsertNextPoint(this->Centre[0] + r, this->Centre[1], 0.0);
    cross->InsertNextPoint(this->Centre[0], this->Centre[1] - r, 0.0);
    cross->InsertNextPoint(this->Centre[0], this->Centre[1] + r, 0.0);
    lines->InsertNextCell({ 0, 1 });
    lines->InsertNextCell({ 2, 3 });
    vtkNew<vtkPolyData> data;
    data->SetPoints(cross);
    data->SetLines(lines);
    overlay->AddActor(line_actor(data, 3.0, magenta));
  }
  vtkNew<vtkTextActor> title;
  title->SetInput(this->titleText().c_str());
  if (view)
    I.Title = title;
  title->GetTextProperty()->SetFontSize(16);
  title->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
  title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  title->GetPositionCoordinate()->SetValue(0.01, 0.02);
  overlay->AddViewProp(title);
}

std::string SplineWindow::titleText() const
{
  return std::string("spline mode: ") + target_name(this->Target) +
    (this->Target == SplineTarget::XY ? "" : " (the model coloured by z)") +
    (this->Folded.empty() ? "" : "   red: the map folds");
}

void SplineWindow::updateScene()
{
  if (!this->hasSpline())
    return;
  vtkCamera* camera = this->I->Renderer->GetActiveCamera();
  double f[3];
  camera->GetFocalPoint(f);
  const bool fitted = camera->GetParallelScale() == this->I->FittedScale &&
    f[0] == this->I->FittedFocal[0] && f[1] == this->I->FittedFocal[1];
  this->drawScene(this->I->Renderer, this->I->Overlay, this->I->Side);
  if (this->CameraNeedsReset || fitted) // (the view's height changes with the side view)
  {
    this->fitCamera();
    this->CameraNeedsReset = false;
  }
  this->I->View->renderWindow()->Render();
  emit this->sceneUpdated();
}

void SplineWindow::resetCamera()
{
  if (!this->hasSpline())
    return;
  this->fitCamera();
  this->I->View->renderWindow()->Render();
}

void SplineWindow::fitCamera()
{
  Internals& I = *this->I;
  vtkCamera* camera = I.Renderer->GetActiveCamera();
  const double cx = 0.5 * (I.Bounds[0] + I.Bounds[1]), cy = 0.5 * (I.Bounds[2] + I.Bounds[3]);
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(cx, cy, 0.0);
  camera->SetPosition(cx, cy, 4.0 * I.Size);
  camera->SetViewUp(0.0, 1.0, 0.0);
  const double aspect = std::max(I.Renderer->GetTiledAspectRatio(), 1e-6);
  const double w = I.Bounds[1] - I.Bounds[0], h = I.Bounds[3] - I.Bounds[2];
  camera->SetParallelScale(0.5 * 1.08 * std::max(h, w / aspect));
  camera->SetClippingRange(0.1 * I.Size, 10.0 * I.Size);
  I.FittedScale = camera->GetParallelScale();
  camera->GetFocalPoint(I.FittedFocal);
}

vtkSmartPointer<vtkRenderWindow> SplineWindow::snapshot(int width, int height)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(width, height);
  window->SetNumberOfLayers(2);
  if (!this->hasSpline())
    return window;
  // the scene drawn afresh into renderers of this window (no actor shared between OpenGL
  // contexts), seen by the view's camera, framed for this window's aspect
  vtkNew<vtkRenderer> scene, overlay, side;
  scene->SetBackground(1.0, 1.0, 1.0);
  side->SetBackground(0.97, 0.97, 0.97);
  overlay->SetLayer(1);
  overlay->SetActiveCamera(scene->GetActiveCamera());
  window->AddRenderer(scene);
  window->AddRenderer(overlay);
  window->AddRenderer(side);
  this->drawScene(scene, overlay, side);
  vtkCamera* camera = scene->GetActiveCamera();
  camera->DeepCopy(this->I->Renderer->GetActiveCamera());
  const Internals& I = *this->I;
  const double w = I.Bounds[1] - I.Bounds[0], h = I.Bounds[3] - I.Bounds[2];
  camera->SetParallelScale(0.5 * 1.08 * std::max(h, w / std::max(scene->GetTiledAspectRatio(), 1e-6)));
  window->Render();
  return window;
}

bool SplineWindow::saveSpline(const QString& path)
{
  return this->reporting([&]() {
    if (!this->hasSpline())
      throw bary::Error(bary::ErrorCode::EmptyInput, "no spline to save");
    if (vtkBaryDataIO::Extension(path.toStdString()) != ".vtu")
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "a spline is written as .vtu (VTK Bézier triangles), not '" + path.toStdString() + "'");
    const Internals& I = *this->I;
    vtkBarySpline s;
    s.xy = I.xy();
    if (this->isPrism())
    {
      s.bottom = I.Editors[1]->spline();
      s.top = I.Editors[2]->spline();
      s.prism_bottom = I.PrismBottom;
      s.prism_top = I.PrismTop;
    }
    s.pinned = I.Pinned;
    vtkBaryDataIO::Write(vtkBarySplineData::ToGrid(s), path.toStdString());
  });
}

bool SplineWindow::saveDeformedModel(const QString& path)
{
  return this->reporting([&]() {
    if (!this->I->Deformed)
      throw bary::Error(bary::ErrorCode::EmptyInput, "no model to save: open one (File menu)");
    vtkNew<vtkPolyData> out; // without the drawing's `Z`
    out->ShallowCopy(this->I->Deformed);
    out->GetPointData()->RemoveArray("Z");
    vtkBaryDataIO::Write(out, path.toStdString());
  });
}

bool SplineWindow::saveScreenshot(const QString& path)
{
  return this->reporting([&]() {
    QApplication::processEvents();
    this->I->View->renderWindow()->Render();
    const QImage image = this->grab().toImage();
    if (image.isNull() || !image.save(path))
      throw bary::Error(bary::ErrorCode::Io, "cannot write the screenshot " + path.toStdString());
  });
}

// --- interaction --------------------------------------------------------------------------

void SplineWindow::displayToWorld(int x, int y, double world[2]) const
{
  double p[4];
  vtkInteractorObserver::ComputeDisplayToWorld(this->I->Renderer, x, y, 0.0, p);
  world[0] = p[0];
  world[1] = p[1];
}

int SplineWindow::pickPoint(int x, int y) const
{
  if (!this->hasSpline())
    return -1;
  // the control points' display positions: the view from +z is orthographic, so one
  // world-to-display map for all (the renderer's composite matrix, applied by hand)
  vtkRenderer* r = this->I->Renderer;
  double o[3], ex[3], ey[3];
  vtkInteractorObserver::ComputeWorldToDisplay(r, 0.0, 0.0, 0.0, o);
  vtkInteractorObserver::ComputeWorldToDisplay(r, 1.0, 0.0, 0.0, ex);
  vtkInteractorObserver::ComputeWorldToDisplay(r, 0.0, 1.0, 0.0, ey);
  const Eigen::MatrixXd& v = this->I->xy().values();
  int best = -1;
  double best_d2 = 10.0 * 10.0; // pixels
  for (Eigen::Index p = 0; p < v.rows(); ++p)
  {
    const double dx = o[0] + v(p, 0) * (ex[0] - o[0]) + v(p, 1) * (ey[0] - o[0]) - x;
    const double dy = o[1] + v(p, 0) * (ex[1] - o[1]) + v(p, 1) * (ey[1] - o[1]) - y;
    const double d2 = dx * dx + dy * dy;
    if (d2 < best_d2)
    {
      best_d2 = d2;
      best = static_cast<int>(p);
    }
  }
  return best;
}

void SplineWindow::installInteraction()
{
  this->I->Callback->SetClientData(this);
  this->I->Callback->SetCallback([](vtkObject* caller, unsigned long event, void* client, void*) {
    auto* self = static_cast<SplineWindow*>(client);
    Internals& I = *self->I;
    auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
    if (!self->hasSpline())
      return;
    int pos[2];
    interactor->GetEventPosition(pos);
    double world[2];
    self->displayToWorld(pos[0], pos[1], world);
    if (event == vtkCommand::LeftButtonPressEvent)
    {
      if (!I.Renderer->IsInViewport(pos[0], pos[1]))
        return; // the side view: the camera's
      if (interactor->GetControlKey())
      {
        I.Callback->AbortFlagOn();
        self->setCentre(world[0], world[1]);
        return;
      }
      const int id = self->pickPoint(pos[0], pos[1]);
      if (id < 0)
        return;
      I.Callback->AbortFlagOn();
      if (interactor->GetShiftKey())
      {
        self->toggleSelection(id);
        return;
      }
      // a drag on a selected point moves the whole selection; on another point, that point
      if (std::find(self->Selection.begin(), self->Selection.end(), id) == self->Selection.end())
        self->selectPoint(id);
      I.Dragging = id;
      I.DragApplied = false;
      I.DragStart[0] = world[0];
      I.DragStart[1] = world[1];
    }
    else if (event == vtkCommand::MouseMoveEvent && I.Dragging >= 0)
    {
      I.Callback->AbortFlagOn();
      // the drag's edit from its start: the previous move's edit is undone first, so the
      // drag is one undo step (and when this move's edit fails, the previous one is back)
      bary::SplineEditor* e = self->editor(self->Target);
      if (I.DragApplied)
      {
        e->undo();
        I.Done.pop_back();
      }
      bary::SplineEdit edit = anchored(self->Selection, self->DeltaMax);
      if (self->Target == SplineTarget::XY)
        edit.by = Eigen::Vector2d(world[0] - I.DragStart[0], world[1] - I.DragStart[1]);
      else
        edit.by = Eigen::VectorXd::Constant(1, (world[1] - I.DragStart[1]) * self->verticalScale());
      const bool was_applied = I.DragApplied;
      // a move the editor refuses (a pinned anchor, say) is reported in the status bar: no
      // message box in the middle of a drag
      const bool interactive = self->Interactive;
      self->Interactive = false;
      I.DragApplied = self->applyEdit(edit);
      self->Interactive = interactive;
      if (!I.DragApplied && was_applied && e->redo())
      {
        I.Done.push_back(self->Target);
        I.DragApplied = true;
        self->update();
      }
    }
    else if (event == vtkCommand::LeftButtonReleaseEvent && I.Dragging >= 0)
    {
      I.Callback->AbortFlagOn();
      I.Dragging = -1;
      I.Residual = I.xy().continuity().max_condition_residual / I.xy().net().mean_edge_length();
      self->updatePanel();
      if (I.DragApplied)
        self->statusBar()->showMessage(QString("drag: last step %1 ms edit + %2 ms update")
                                         .arg(1e3 * self->EditSeconds, 0, 'f', 2)
                                         .arg(1e3 * self->UpdateSeconds, 0, 'f', 1));
    }
  });
  // a resized view (the panel filled, the window resized) is fitted again unless the camera
  // was moved since the last reset
  this->I->ResizeCallback->SetClientData(this);
  this->I->ResizeCallback->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
    auto* self = static_cast<SplineWindow*>(client);
    vtkCamera* camera = self->I->Renderer->GetActiveCamera();
    double f[3];
    camera->GetFocalPoint(f);
    if (self->hasSpline() && camera->GetParallelScale() == self->I->FittedScale &&
      f[0] == self->I->FittedFocal[0] && f[1] == self->I->FittedFocal[1])
      self->fitCamera(); // the render under way shows it
  });
  this->I->View->renderWindow()->AddObserver(vtkCommand::WindowResizeEvent, this->I->ResizeCallback);
  vtkRenderWindowInteractor* interactor = this->I->View->interactor();
  for (unsigned long e : { vtkCommand::LeftButtonPressEvent, vtkCommand::MouseMoveEvent,
         vtkCommand::LeftButtonReleaseEvent })
    interactor->AddObserver(e, this->I->Callback, 10.0f);
}

// --- panel and menus ----------------------------------------------------------------------

namespace
{
QDoubleSpinBox* spin(QWidget* parent, const char* name, double lo, double hi, double step,
  double value, int decimals)
{
  auto* box = new QDoubleSpinBox(parent);
  box->setObjectName(name);
  box->setRange(lo, hi);
  box->setSingleStep(step);
  box->setDecimals(decimals);
  box->setValue(value);
  return box;
}
} // namespace

void SplineWindow::buildPanel()
{
  auto* dock = new QDockWidget("C1 spline editor (DECLeS)", this);
  dock->setFeatures(QDockWidget::DockWidgetMovable);
  auto* panel = new QWidget(dock);
  auto* layout = new QVBoxLayout(panel);
  Internals& I = *this->I;

  I.Info = new QLabel("no spline", panel);
  I.Info->setObjectName("spline_info");
  I.Info->setWordWrap(true);
  layout->addWidget(I.Info);

  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("Edit", panel));
  I.TargetBox = new QComboBox(panel);
  I.TargetBox->setObjectName("spline_target");
  I.TargetBox->addItems({ "xy (the deformation)", "bottom surface", "top surface" });
  row->addWidget(I.TargetBox, 1);
  layout->addLayout(row);
  connect(I.TargetBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int i) {
    if (!this->I->Updating)
      this->setTarget(static_cast<SplineTarget>(i));
  });
  row = new QHBoxLayout;
  row->addWidget(new QLabel("δ_max (slaves within)", panel));
  I.DeltaBox = new QSpinBox(panel);
  I.DeltaBox->setObjectName("spline_delta_max");
  I.DeltaBox->setRange(0, 100);
  row->addWidget(I.DeltaBox);
  layout->addLayout(row);
  connect(I.DeltaBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int v) {
    if (!this->I->Updating)
      this->setDeltaMax(v);
  });

  auto* point = new QGroupBox("Selected control points (the anchors)", panel);
  auto* pointLayout = new QVBoxLayout(point);
  I.PointInfo = new QLabel(point);
  I.PointInfo->setObjectName("spline_point");
  I.PointInfo->setWordWrap(true);
  I.PointInfo->setMinimumHeight(2 * I.PointInfo->fontMetrics().lineSpacing());
  pointLayout->addWidget(I.PointInfo);
  I.XYRow = new QWidget(point);
  auto* xyRow = new QHBoxLayout(I.XYRow);
  xyRow->setContentsMargins(0, 0, 0, 0);
  I.DxBox = spin(I.XYRow, "spline_dx", -10.0, 10.0, 0.01, 0.05, 3);
  I.DyBox = spin(I.XYRow, "spline_dy", -10.0, 10.0, 0.01, 0.0, 3);
  auto* move = new QPushButton("Translate", I.XYRow);
  connect(move, &QPushButton::clicked, this, [this]() {
    this->translateSelection(this->I->DxBox->value(), this->I->DyBox->value());
  });
  xyRow->addWidget(new QLabel("dx", I.XYRow));
  xyRow->addWidget(I.DxBox);
  xyRow->addWidget(new QLabel("dy", I.XYRow));
  xyRow->addWidget(I.DyBox);
  xyRow->addWidget(move);
  pointLayout->addWidget(I.XYRow);
  I.ZRow = new QWidget(point);
  auto* zRow = new QHBoxLayout(I.ZRow);
  zRow->setContentsMargins(0, 0, 0, 0);
  I.DzBox = spin(I.ZRow, "spline_dz", -10.0, 10.0, 0.005, 0.02, 3);
  auto* raise = new QPushButton("Raise", I.ZRow);
  connect(raise, &QPushButton::clicked, this,
    [this]() { this->translateSelection(this->I->DzBox->value(), 0.0); });
  zRow->addWidget(new QLabel("dz", I.ZRow));
  zRow->addWidget(I.DzBox);
  zRow->addWidget(raise);
  pointLayout->addWidget(I.ZRow);
  layout->addWidget(point);

  auto* about = new QGroupBox("About the centre (Ctrl + click)", panel);
  auto* aboutLayout = new QVBoxLayout(about);
  I.CentreInfo = new QLabel(about);
  I.CentreInfo->setObjectName("spline_centre");
  aboutLayout->addWidget(I.CentreInfo);
  row = new QHBoxLayout;
  I.AngleBox = spin(about, "spline_angle", -180.0, 180.0, 1.0, 15.0, 1);
  I.RotateButton = new QPushButton("Rotate", about);
  connect(I.RotateButton, &QPushButton::clicked, this,
    [this]() { this->rotateSelected(this->I->AngleBox->value()); });
  row->addWidget(new QLabel("degrees", about));
  row->addWidget(I.AngleBox);
  row->addWidget(I.RotateButton);
  aboutLayout->addLayout(row);
  row = new QHBoxLayout;
  I.FactorBox = spin(about, "spline_factor", 0.05, 20.0, 0.05, 1.2, 3);
  I.ScaleButton = new QPushButton("Scale", about);
  connect(I.ScaleButton, &QPushButton::clicked, this,
    [this]() { this->scaleSelected(this->I->FactorBox->value()); });
  row->addWidget(new QLabel("factor", about));
  row->addWidget(I.FactorBox);
  row->addWidget(I.ScaleButton);
  aboutLayout->addLayout(row);
  layout->addWidget(about);

  row = new QHBoxLayout;
  I.UndoButton = new QPushButton("Undo", panel);
  I.RedoButton = new QPushButton("Redo", panel);
  connect(I.UndoButton, &QPushButton::clicked, this, &SplineWindow::undo);
  connect(I.RedoButton, &QPushButton::clicked, this, &SplineWindow::redo);
  row->addWidget(I.UndoButton);
  row->addWidget(I.RedoButton);
  layout->addLayout(row);
  I.EditInfo = new QLabel(panel);
  I.EditInfo->setObjectName("spline_edit");
  I.EditInfo->setWordWrap(true);
  I.EditInfo->setMinimumHeight(3 * I.EditInfo->fontMetrics().lineSpacing());
  layout->addWidget(I.EditInfo);
  I.Warning = new QLabel(panel);
  I.Warning->setObjectName("spline_warning");
  I.Warning->setWordWrap(true);
  I.Warning->setStyleSheet("QLabel { color: #c00000; font-weight: bold; }");
  layout->addWidget(I.Warning);
  layout->addStretch(1);
  dock->setWidget(panel);
  dock->setMinimumWidth(330);
  dock->setMaximumWidth(430);
  this->addDockWidget(Qt::RightDockWidgetArea, dock);
  this->updatePanel();
}

void SplineWindow::updatePanel()
{
  Internals& I = *this->I;
  I.Updating = true;
  const bool prism = this->isPrism();
  I.TargetBox->setCurrentIndex(static_cast<int>(this->Target));
  I.TargetBox->setEnabled(prism);
  I.DeltaBox->setValue(this->DeltaMax);
  const bool xy = this->Target == SplineTarget::XY;
  I.XYRow->setVisible(xy);
  I.ZRow->setVisible(!xy);
  I.RotateButton->setEnabled(xy && this->Selected >= 0 && this->HasCentre);
  I.ScaleButton->setEnabled(xy && this->Selected >= 0 && this->HasCentre);
  I.UndoButton->setEnabled(this->canUndo());
  I.RedoButton->setEnabled(this->canRedo());
  if (!this->hasSpline())
  {
    I.Info->setText("no spline: File > Open spline, or File > Open example");
    I.PointInfo->setText("");
    I.Updating = false;
    return;
  }
  const bary::SplineNet& net = I.xy().net();
  QString info = QString("%1: degree %2, %3 triangles, %4 control points%5")
                   .arg(I.SplineName)
                   .arg(net.degree())
                   .arg(net.num_triangles())
                   .arg(net.num_points())
                   .arg(prism ? QString(", prism [%1, %2]").arg(I.PrismBottom).arg(I.PrismTop) : QString());
  info += I.Dragging >= 0 ? QString("\nC1 residual: measured when the drag ends")
                          : QString("\nC1 residual %1 (relative to the grid size)").arg(I.Residual, 0, 'g', 2);
  if (I.Model)
    info += QString("\nmodel %1: %2 points").arg(I.ModelName).arg(I.Model->GetNumberOfPoints());
  if (I.Picture)
    info += QString("\npicture %1").arg(I.PictureName);
  I.Info->setText(info);
  if (this->Selected >= 0)
  {
    const Eigen::MatrixXd& v = I.xy().values();
    QString text = this->Selection.size() > 1
      ? QString("%1 points selected (Shift + click adds or removes one); the last: ").arg(this->Selection.size())
      : QString();
    text += QString("point %1 (%2%3) at (%4, %5)")
                     .arg(this->Selected)
                     .arg(bary::to_string(net.type(this->Selected)))
                     .arg(std::find(I.Pinned.begin(), I.Pinned.end(), this->Selected) != I.Pinned.end() ? ", pinned" : "")
                     .arg(v(this->Selected, 0), 0, 'f', 4)
                     .arg(v(this->Selected, 1), 0, 'f', 4);
    if (prism)
      text += QString("; bottom %1, top %2")
                .arg(I.Editors[1]->spline().values()(this->Selected, 0), 0, 'f', 4)
                .arg(I.Editors[2]->spline().values()(this->Selected, 0), 0, 'f', 4);
    I.PointInfo->setText(text);
  }
  else
    I.PointInfo->setText("none: press on a control point (drag to move it; Shift + click selects several)");
  I.CentreInfo->setText(this->HasCentre
      ? QString("centre (%1, %2)").arg(this->Centre[0], 0, 'f', 4).arg(this->Centre[1], 0, 'f', 4)
      : QString("no centre: Ctrl + click in the view"));
  I.EditInfo->setText(I.LastEdit.isEmpty() ? QString("no edit yet") : I.LastEdit);
  const QString warning = this->warning();
  I.Warning->setText(warning.isEmpty()
      ? QString("<span style='color:#206020; font-weight:normal'>Jacobian positive everywhere (min %1)</span>")
          .arg(this->MinJacobian, 0, 'g', 3)
      : warning);
  I.Updating = false;
}

void SplineWindow::buildMenus()
{
  QMenu* file = this->menuBar()->addMenu("&File");
  file->addAction("&Open spline...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open a spline (barylab spline create)",
      QString(), "Splines (*.vtu);;All files (*)");
    if (!path.isEmpty())
      this->openSpline(path);
  }, QKeySequence::Open);
  file->addAction("Open &model...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open a model in the spline's domain");
    if (!path.isEmpty())
      this->openModel(path);
  });
  file->addAction("Open &picture...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open a picture to match", QString(),
      "Pictures (*.png *.jpg *.jpeg *.bmp *.tif *.tiff *.pnm)");
    if (!path.isEmpty())
      this->openPicture(path);
  });
  QMenu* examples = file->addMenu("Open &example");
  for (const QString& name : ExampleNames())
    examples->addAction(name, this, [this, name]() { this->loadExample(name); });
  file->addSeparator();
  file->addAction("&Save spline...", this, [this]() {
    const QString path = QFileDialog::getSaveFileName(this, "Save the spline", "spline.vtu", "Splines (*.vtu)");
    if (!path.isEmpty())
      this->saveSpline(path);
  }, QKeySequence::Save);
  file->addAction("Save &deformed model...", this, [this]() {
    const QString path = QFileDialog::getSaveFileName(this, "Save the deformed model", "deformed.vtp");
    if (!path.isEmpty())
      this->saveDeformedModel(path);
  });
  file->addAction("Save screens&hot...", this, [this]() {
    const QString path = QFileDialog::getSaveFileName(this, "Save a screenshot", "spline.png", "PNG (*.png)");
    if (!path.isEmpty())
      this->saveScreenshot(path);
  });
  file->addSeparator();
  file->addAction("&Close", this, &QWidget::close, QKeySequence::Close);
  QMenu* edit = this->menuBar()->addMenu("&Edit");
  edit->addAction("&Undo", this, &SplineWindow::undo, QKeySequence("Ctrl+Z"));
  edit->addAction("&Redo", this, &SplineWindow::redo, QKeySequence("Ctrl+Shift+Z"));
  edit->addSeparator();
  edit->addAction("Edit &xy", this, [this]() { this->setTarget(SplineTarget::XY); }, QKeySequence("1"));
  edit->addAction("Edit the &bottom surface", this, [this]() { this->setTarget(SplineTarget::Bottom); }, QKeySequence("2"));
  edit->addAction("Edit the &top surface", this, [this]() { this->setTarget(SplineTarget::Top); }, QKeySequence("3"));
  edit->addAction("δ_max + 1", this, [this]() { this->setDeltaMax(this->DeltaMax + 1); }, QKeySequence("]"));
  edit->addAction("δ_max - 1", this, [this]() { this->setDeltaMax(this->DeltaMax - 1); }, QKeySequence("["));
  QMenu* view = this->menuBar()->addMenu("&View");
  view->addAction("&Reset camera", this, &SplineWindow::resetCamera, QKeySequence("R"));
}

} // namespace viewer
} // namespace barylab
