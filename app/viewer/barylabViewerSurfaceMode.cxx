#include "barylabViewerSurfaceMode.h"

#include "barylabPipeline.h"
#include "barylabViewerExamples.h"
#include "barylabRender.h"
#include "barylabSurfacePipeline.h"
#include "barylabViewerScene.h"

#include "vtkBaryDataIO.h"
#include "vtkBarySurfaceCorrespondence.h"
#include "vtkBarySurfaceCurve.h"
#include "vtkBarySurfaceData.h"
#include "vtkBarySurfaceRemesh.h"
#include "vtkBarySurfaceWeights.h"
#include "vtkBaryWeightedAverage.h"
#include "core/common/error.h"
#include "core/surface/remeshing.h"
#include "core/surface/surface_curves.h"
#include "core/surface/surface_mesh.h"

#include <QApplication>
#include <QButtonGroup>
#include <QCheckBox>
#include <QComboBox>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QRadioButton>
#include <QSlider>
#include <QSpinBox>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include <QVTKOpenGLNativeWidget.h>

#include "vtkActor.h"
#include "vtkActorCollection.h"
#include "vtkLookupTable.h"
#include "vtkMapper.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellLocator.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkGenericOpenGLRenderWindow.h"
#include "vtkImageConstantPad.h"
#include "vtkImageData.h"
#include "vtkInteractorObserver.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataNormals.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTexture.h"
#include "vtkTriangle.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace barylab
{
namespace viewer
{
namespace
{
enum Changed
{
  AnchorsChanged = 1,
  WeightsChanged = 2,
  CurveChanged = 4,
  FieldChanged = 8,
  TargetChanged = 16,
  RemeshChanged = 32,
  Everything = 63
};

const char* kSurfaceExample = "torus-averages";

vtkSmartPointer<vtkPolyData> as_points(vtkPoints* points)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  return poly;
}

void add_text(vtkRenderer* renderer, const std::string& text)
{
  vtkNew<vtkTextActor> title;
  title->SetInput(text.c_str());
  title->GetTextProperty()->SetFontSize(16);
  title->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
  title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  title->GetPositionCoordinate()->SetValue(0.01, 0.02);
  renderer->AddViewProp(title);
}

/// The surface drawn plain (light grey), or with @p picture on its `TCoords` (outside [0, 1]
/// the picture's padded border: the surface colour).
void add_surface(vtkRenderer* renderer, vtkPolyData* surface, vtkImageData* picture)
{
  vtkNew<vtkPolyDataNormals> normals; // smooth shading (the texture coordinates pass through)
  normals->SetInputData(surface);
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->Update();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(normals->GetOutputPort());
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.85, 0.85, 0.85);
  if (picture)
  {
    vtkNew<vtkTexture> texture;
    texture->SetInputData(picture);
    texture->InterpolateOn();
    texture->RepeatOff();
    texture->EdgeClampOn();
    actor->SetTexture(texture);
    actor->GetProperty()->SetColor(1.0, 1.0, 1.0);
  }
  renderer->AddActor(actor);
}

/// @p picture with a border of 4 pixels in the plain surface's grey: texture coordinates
/// outside the decal (clamped to the edge) show the surface, not the picture's edge.
vtkSmartPointer<vtkImageData> padded_picture(vtkImageData* picture)
{
  int extent[6];
  picture->GetExtent(extent);
  vtkNew<vtkImageConstantPad> pad;
  pad->SetInputData(picture);
  pad->SetOutputWholeExtent(extent[0] - 4, extent[1] + 4, extent[2] - 4, extent[3] + 4, 0, 0);
  pad->SetConstant(0.85 * 255);
  pad->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(pad->GetOutput());
  // the decal's [0, 1] maps to the picture inside the border
  return out;
}

/// The point of @p surface at face @p face, barycentric @p b.
void surface_point(vtkPolyData* surface, vtkIdType face, const double b[3], double x[3])
{
  const vtkIdType* ids = nullptr;
  vtkIdType n = 0;
  surface->GetCellPoints(face, n, ids);
  x[0] = x[1] = x[2] = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    double p[3];
    surface->GetPoint(ids[k], p);
    for (int d = 0; d < 3; ++d)
      x[d] += b[k] * p[d];
  }
}

/// The first point of a vtkBaryWeightedAverage output as a SurfaceAverage.
SurfaceAverage read_average(vtkPolyData* out)
{
  SurfaceAverage a;
  if (!out || out->GetNumberOfPoints() < 1)
    return a;
  vtkDataArray* valid = out->GetPointData()->GetArray("Valid");
  vtkDataArray* face = out->GetPointData()->GetArray("FaceId");
  vtkDataArray* bary = out->GetPointData()->GetArray("Barycentric");
  a.valid = valid && valid->GetComponent(0, 0) != 0;
  out->GetPoint(0, a.point);
  if (face)
    a.face = static_cast<long long>(face->GetComponent(0, 0));
  if (bary)
    for (int k = 0; k < 3; ++k)
      a.barycentric[k] = bary->GetComponent(0, k);
  return a;
}

double diagonal(vtkPolyData* surface)
{
  double b[6];
  surface->GetBounds(b);
  return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
}

QString point_text(const double p[3])
{
  return QString("(%1, %2, %3)").arg(p[0], 0, 'f', 3).arg(p[1], 0, 'f', 3).arg(p[2], 0, 'f', 3);
}
} // namespace

struct SurfaceWindow::Internals
{
  vtkSmartPointer<vtkPolyData> Surface; ///< with its embedding
  std::unique_ptr<bary::SurfaceMesh> Mesh; ///< for locating points (closest point on the surface)
  nlohmann::json EmbeddingSummary = nlohmann::json::object();
  vtkNew<vtkPoints> Anchors;
  vtkNew<vtkPoints> CurveControls;
  vtkSmartPointer<vtkPolyData> Field;
  vtkSmartPointer<vtkPolyData> Curve;
  vtkSmartPointer<vtkPolyData> Target;
  vtkNew<vtkPoints> TargetAnchors;
  vtkSmartPointer<vtkPolyData> Transferred;
  vtkSmartPointer<vtkImageData> Picture; ///< padded
  int PictureBorder[2] = { 0, 0 };       ///< the picture's size without the border
  int CurveSamples = 16;

  // one filter of each kind: their caches keep the Phong precomputation between updates
  vtkNew<vtkBaryWeightedAverage> AverageFilter;
  vtkNew<vtkBaryWeightedAverage> TargetAverageFilter;
  vtkNew<vtkBarySurfaceWeights> FieldFilter;
  vtkNew<vtkBarySurfaceCurve> CurveFilter;
  vtkNew<vtkBarySurfaceCorrespondence> TransferFilter;
  vtkNew<vtkBarySurfaceRemesh> RemeshFilter;
  vtkSmartPointer<vtkPolyData> Coarse;   ///< the quad layout opened
  vtkSmartPointer<vtkPolyData> Remeshed;
  int RemeshLevels = bary::RemeshOptions{}.levels;
  vtkNew<vtkCellLocator> Locator; ///< rays from the mouse onto the surface; closest points

  QVTKOpenGLNativeWidget* View = nullptr;
  QVTKOpenGLNativeWidget* TargetView = nullptr;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderer> TargetRenderer;
  vtkNew<vtkCallbackCommand> Callback;
  vtkNew<vtkPoints> AveragePoint;       ///< the spheres of the averages (moved in place)
  vtkNew<vtkPoints> TargetAveragePoint;
  bool SceneBuilt = false;
  int Dragging = -1;
  bool DraggingCurve = false;

  QLabel* SurfaceInfo = nullptr;
  QLabel* AverageInfo = nullptr;
  QLabel* CurveInfo = nullptr;
  QLabel* TargetInfo = nullptr;
  QLabel* RemeshInfo = nullptr;
  QSpinBox* LevelsBox = nullptr;
  QComboBox* EditBox = nullptr;
  QComboBox* FieldBox = nullptr;
  QCheckBox* ClosedBox = nullptr;
  QSpinBox* SamplesBox = nullptr;
  QWidget* AnchorRows = nullptr;
  QButtonGroup* AnchorGroup = nullptr;
  std::vector<QSlider*> Sliders;
  std::vector<QLabel*> Values;
  bool Updating = false; ///< panel being filled: its signals are not user edits
};

SurfaceWindow::SurfaceWindow(QWidget* parent)
  : QMainWindow(parent)
  , I(new Internals)
{
  this->setWindowTitle("BaryLab viewer: weighted averages on surfaces");
  this->I->CurveSamples = this->I->CurveFilter->GetSamplesPerSegment();
  auto* splitter = new QSplitter(this);
  for (QVTKOpenGLNativeWidget** view : { &this->I->View, &this->I->TargetView })
  {
    *view = new QVTKOpenGLNativeWidget(splitter);
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    (*view)->setRenderWindow(window);
    splitter->addWidget(*view);
  }
  this->I->View->renderWindow()->AddRenderer(this->I->Renderer);
  this->I->TargetView->renderWindow()->AddRenderer(this->I->TargetRenderer);
  for (vtkRenderer* r : { this->I->Renderer.Get(), this->I->TargetRenderer.Get() })
    r->SetBackground(1.0, 1.0, 1.0);
  this->I->TargetView->hide();
  this->setCentralWidget(splitter);
  this->buildPanel();
  this->buildMenus();
  this->installInteraction();
  this->statusBar()->showMessage("Open a surface (File menu) or the torus example");
}

SurfaceWindow::~SurfaceWindow() = default;

QStringList SurfaceWindow::ExampleNames()
{
  return { kSurfaceExample };
}

bool SurfaceWindow::IsExample(const QString& name)
{
  return ExampleNames().contains(name);
}

vtkPolyData* SurfaceWindow::surface() const
{
  return this->I->Surface;
}
const nlohmann::json& SurfaceWindow::embeddingSummary() const
{
  return this->I->EmbeddingSummary;
}
vtkPoints* SurfaceWindow::anchors() const
{
  return this->I->Anchors;
}
int SurfaceWindow::anchorCount() const
{
  return static_cast<int>(this->I->Anchors->GetNumberOfPoints());
}
vtkPolyData* SurfaceWindow::field() const
{
  return this->I->Field;
}
vtkPoints* SurfaceWindow::curveControls() const
{
  return this->I->CurveControls;
}
vtkPolyData* SurfaceWindow::curve() const
{
  return this->I->Curve;
}
vtkPolyData* SurfaceWindow::remeshed() const
{
  return this->I->Remeshed;
}
int SurfaceWindow::remeshLevels() const
{
  return this->I->RemeshLevels;
}
vtkPolyData* SurfaceWindow::target() const
{
  return this->I->Target;
}
vtkPolyData* SurfaceWindow::transferred() const
{
  return this->I->Transferred;
}
QVTKOpenGLNativeWidget* SurfaceWindow::view() const
{
  return this->I->View;
}
QVTKOpenGLNativeWidget* SurfaceWindow::targetView() const
{
  return this->I->TargetView;
}
vtkRenderer* SurfaceWindow::renderer() const
{
  return this->I->Renderer;
}
vtkRenderer* SurfaceWindow::targetRenderer() const
{
  return this->I->TargetRenderer;
}

std::vector<double> SurfaceWindow::normalizedWeights() const
{
  std::vector<double> w = this->Weights;
  const double sum = std::accumulate(w.begin(), w.end(), 0.0);
  for (double& x : w)
    x = sum != 0.0 ? x / sum : std::numeric_limits<double>::quiet_NaN();
  return w;
}

void SurfaceWindow::reportError(const QString& message)
{
  this->Errors << message;
  this->statusBar()->showMessage(message);
  emit this->errorReported(message);
  if (this->Interactive)
    QMessageBox::warning(this, "BaryLab viewer", message);
}

template <class Action>
bool SurfaceWindow::reporting(Action&& action)
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

bool SurfaceWindow::openSurface(const QString& mesh, const QString& embedding)
{
  QApplication::setOverrideCursor(Qt::WaitCursor);
  const bool ok = this->reporting([&]() {
    auto surface = ReadSurface(mesh.toStdString());
    nlohmann::json summary = nlohmann::json::object();
    vtkSmartPointer<vtkPolyData> embedded;
    if (!embedding.isEmpty())
      embedded = AttachEmbedding(surface, embedding.toStdString());
    else
    {
      this->statusBar()->showMessage("computing the Euclidean embedding of " + mesh + "...");
      QApplication::processEvents();
      embedded = ComputeEmbedding(surface, bary::EmbeddingOptions{}, {}, &summary);
    }
    this->I->Mesh = std::make_unique<bary::SurfaceMesh>(vtkBarySurfaceData::ToSurfaceMesh(embedded));
    this->I->Surface = embedded;
    this->I->EmbeddingSummary = summary;
    this->I->Locator->SetDataSet(embedded);
    this->I->Locator->BuildLocator();
  });
  QApplication::restoreOverrideCursor();
  if (!ok)
    return false;
  this->I->Anchors->Reset();
  this->I->CurveControls->Reset();
  this->Weights.clear();
  this->Selected = -1;
  this->I->Field = nullptr;
  this->I->Curve = nullptr;
  this->I->Coarse = nullptr;
  this->I->Remeshed = nullptr;
  this->closeTarget();
  this->CameraNeedsReset = true;
  QString info = QString("%1: %2 points, %3 triangles")
                   .arg(QFileInfo(mesh).fileName())
                   .arg(this->I->Surface->GetNumberOfPoints())
                   .arg(this->I->Surface->GetNumberOfPolys());
  const nlohmann::json& s = this->I->EmbeddingSummary;
  if (s.contains("quality"))
    info += QString("\nembedding in R^%1, %2 landmarks, %3 s; distance error mean %4%, max %5%")
              .arg(QString::fromStdString(s.value("dimension", nlohmann::json()).dump()))
              .arg(QString::fromStdString(s.value("landmarks", nlohmann::json()).dump()))
              .arg(s["seconds"].value("total", 0.0), 0, 'f', 2)
              .arg(100.0 * s["quality"].value("mean_relative_error", 0.0), 0, 'f', 2)
              .arg(100.0 * s["quality"].value("max_relative_error", 0.0), 0, 'f', 1);
  else
    info += "\nembedding read from " + QFileInfo(embedding).fileName();
  this->I->SurfaceInfo->setText(info);
  this->statusBar()->showMessage("Ctrl + click on the surface adds an anchor");
  this->update(Everything);
  return true;
}

bool SurfaceWindow::loadExample(const QString& name)
{
  if (name != kSurfaceExample)
  {
    this->reportError("no surface example named '" + name + "' (" + ExampleNames().join(", ") + ")");
    return false;
  }
  // the embeddings bundled (made by `barylab embed` with its defaults): the example opens at
  // once instead of after ~15 s of precomputation
  return this->openSurface(DataPath("wa_torus.obj"), DataPath("wa_torus_embedding.txt")) &&
    this->openAnchors(DataPath("wa_anchors.txt")) &&
    this->openWeights(DataPath("wa_weights.txt"), 1) &&
    this->openCurve(DataPath("wa_curve_controls.txt")) &&
    this->openPicture(DataPath("gingerbread.png")) &&
    this->openTarget(DataPath("wa_torus_target.obj"), DataPath("wa_target_anchors.txt"),
      DataPath("wa_torus_target_embedding.txt"));
}

namespace
{
/// The points of @p path (text x y z a line, or a data file's points).
vtkSmartPointer<vtkPoints> read_points(const QString& path)
{
  auto points = ReadSurfacePoints(path.toStdString());
  auto out = vtkSmartPointer<vtkPoints>::New();
  out->SetDataTypeToDouble();
  if (points->GetPoints())
    out->DeepCopy(points->GetPoints());
  return out;
}
} // namespace

bool SurfaceWindow::openAnchors(const QString& path)
{
  if (!this->I->Surface)
  {
    this->reportError("open a surface before its anchors");
    return false;
  }
  vtkSmartPointer<vtkPoints> points;
  if (!this->reporting([&]() {
        points = read_points(path);
        if (points->GetNumberOfPoints() == 0)
          throw bary::Error(bary::ErrorCode::EmptyInput, path.toStdString() + ": no anchors in the file");
        // each on the surface (an error names the first one off it)
        vtkBarySurfaceData::Locate(*this->I->Mesh, as_points(points), bary::kDefaultSurfaceTolerance, "anchor");
      }))
    return false;
  this->I->Anchors->DeepCopy(points);
  this->CameraNeedsReset = true; // look at them
  const auto n = static_cast<std::size_t>(points->GetNumberOfPoints());
  this->Weights.assign(n, 1.0 / static_cast<double>(n));
  this->Selected = 0;
  this->update(Everything);
  return true;
}

bool SurfaceWindow::openWeights(const QString& path, int row)
{
  Eigen::MatrixXd W;
  if (!this->reporting([&]() {
        W = vtkBaryDataIO::ReadMatrix(path.toStdString(), this->anchorCount());
        if (row < 0 || row >= W.rows())
          throw bary::Error(bary::ErrorCode::InvalidArgument,
            path.toStdString() + ": no row " + std::to_string(row) + " (" + std::to_string(W.rows()) + " rows)");
      }))
    return false;
  std::vector<double> w(W.cols());
  for (Eigen::Index k = 0; k < W.cols(); ++k)
    w[static_cast<std::size_t>(k)] = W(row, k);
  return this->setWeights(w);
}

bool SurfaceWindow::openPicture(const QString& path)
{
  return this->reporting([&]() {
    auto picture = ReadPicture(path.toStdString());
    int dims[3];
    picture->GetDimensions(dims);
    this->I->PictureBorder[0] = dims[0];
    this->I->PictureBorder[1] = dims[1];
    this->I->Picture = padded_picture(picture);
    this->update(FieldChanged);
  });
}

bool SurfaceWindow::openCurve(const QString& path)
{
  if (!this->I->Surface)
  {
    this->reportError("open a surface before a curve on it");
    return false;
  }
  vtkSmartPointer<vtkPoints> points;
  if (!this->reporting([&]() {
        points = read_points(path);
        vtkBarySurfaceData::Locate(*this->I->Mesh, as_points(points), bary::kDefaultSurfaceTolerance, "control point");
      }))
    return false;
  this->I->CurveControls->DeepCopy(points);
  this->update(CurveChanged);
  return true;
}

bool SurfaceWindow::openTarget(const QString& mesh, const QString& anchors, const QString& embedding)
{
  if (!this->I->Surface)
  {
    this->reportError("open a surface before its correspondence target");
    return false;
  }
  QApplication::setOverrideCursor(Qt::WaitCursor);
  const bool ok = this->reporting([&]() {
    auto surface = ReadSurface(mesh.toStdString());
    vtkSmartPointer<vtkPolyData> embedded = embedding.isEmpty()
      ? ComputeEmbedding(surface, bary::EmbeddingOptions{})
      : AttachEmbedding(surface, embedding.toStdString());
    auto points = read_points(anchors);
    const bary::SurfaceMesh target_mesh = vtkBarySurfaceData::ToSurfaceMesh(embedded);
    vtkBarySurfaceData::Locate(target_mesh, as_points(points), bary::kDefaultSurfaceTolerance, "target anchor");
    this->I->Target = embedded;
    this->I->TargetAnchors->DeepCopy(points);
  });
  QApplication::restoreOverrideCursor();
  if (!ok)
    return false;
  this->I->TargetView->show();
  if (auto* splitter = qobject_cast<QSplitter*>(this->centralWidget()))
  {
    const int half = std::max(1, splitter->width() / 2);
    splitter->setSizes({ half, half });
  }
  this->CameraNeedsReset = true;
  this->update(TargetChanged);
  return true;
}

bool SurfaceWindow::openQuadLayout(const QString& path)
{
  if (!this->I->Surface)
  {
    this->reportError("open a surface before a quad layout on it");
    return false;
  }
  vtkSmartPointer<vtkPolyData> coarse;
  if (!this->reporting([&]() { coarse = vtkBaryDataIO::ReadPolyData(path.toStdString()); }))
    return false;
  const auto previous = this->I->Coarse;
  this->I->Coarse = coarse;
  this->updateRemesh();
  if (!this->I->Remeshed)
  {
    this->I->Coarse = previous; // refused (reported): the previous layout stays
    this->updateRemesh();
    return false;
  }
  this->update(RemeshChanged);
  return true;
}

void SurfaceWindow::setRemeshLevels(int levels)
{
  const int previous = this->I->RemeshLevels;
  this->I->RemeshLevels = levels;
  if (this->I->Coarse)
  {
    this->updateRemesh();
    if (!this->I->Remeshed)
    {
      this->I->RemeshLevels = previous; // out of range (reported)
      this->updateRemesh();
    }
  }
  this->update(RemeshChanged);
}

void SurfaceWindow::closeQuadLayout()
{
  this->I->Coarse = nullptr;
  this->I->Remeshed = nullptr;
  this->update(RemeshChanged);
}

void SurfaceWindow::updateRemesh()
{
  this->I->Remeshed = nullptr;
  if (!this->I->Coarse || !this->I->Surface)
    return;
  vtkBarySurfaceRemesh* f = this->I->RemeshFilter;
  f->SetInputData(0, this->I->Surface);
  f->SetInputData(1, this->I->Coarse);
  f->SetLevels(this->I->RemeshLevels);
  this->reporting([&]() {
    RunAlgorithm(f, {});
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(f->GetOutput());
    this->I->Remeshed = out;
  });
}

void SurfaceWindow::closeTarget()
{
  this->I->Target = nullptr;
  this->I->Transferred = nullptr;
  this->I->TargetAnchors->Reset();
  this->TargetAverage = SurfaceAverage();
  this->TransferSummary = nlohmann::json::object();
  this->I->TargetRenderer->RemoveAllViewProps();
  this->I->TargetView->hide();
  if (this->I->TargetInfo)
    this->I->TargetInfo->setText("no target: File > Open correspondence target...");
}

// --- editing ------------------------------------------------------------------------------

namespace
{
/// The surface point closest to @p x (within the surface tolerance), written to @p out.
void on_surface(const bary::SurfaceMesh& mesh, vtkPolyData* surface, const double x[3], double out[3],
  const char* what)
{
  vtkNew<vtkPoints> p;
  p->InsertNextPoint(x);
  const auto located = vtkBarySurfaceData::Locate(mesh, as_points(p), bary::kDefaultSurfaceTolerance, what);
  surface_point(surface, static_cast<vtkIdType>(located[0].face), located[0].barycentric.data(), out);
}
} // namespace

int SurfaceWindow::addAnchor(double x, double y, double z)
{
  if (!this->I->Surface)
  {
    this->reportError("open a surface before adding anchors");
    return -1;
  }
  const double p[3] = { x, y, z };
  double q[3];
  if (!this->reporting([&]() { on_surface(*this->I->Mesh, this->I->Surface, p, q, "anchor"); }))
    return -1;
  const int id = static_cast<int>(this->I->Anchors->InsertNextPoint(q));
  // the new anchor gets 1/n of the total, the others keep their proportions
  const double n = static_cast<double>(this->Weights.size() + 1);
  const double sum = std::accumulate(this->Weights.begin(), this->Weights.end(), 0.0);
  for (double& w : this->Weights)
    w *= (n - 1.0) / n;
  this->Weights.push_back(this->Weights.empty() || sum == 0.0 ? 1.0 / n : sum / n);
  this->Selected = id;
  this->update(AnchorsChanged);
  return id;
}

bool SurfaceWindow::moveAnchor(int i, double x, double y, double z)
{
  if (i < 0 || i >= this->anchorCount())
  {
    this->reportError(QString("no anchor %1 (%2 anchors)").arg(i).arg(this->anchorCount()));
    return false;
  }
  const double p[3] = { x, y, z };
  double q[3];
  if (!this->reporting([&]() { on_surface(*this->I->Mesh, this->I->Surface, p, q, "anchor"); }))
    return false;
  this->I->Anchors->SetPoint(i, q);
  this->I->Anchors->Modified();
  this->update(AnchorsChanged);
  return true;
}

bool SurfaceWindow::removeAnchor(int i)
{
  if (i < 0 || i >= this->anchorCount())
  {
    this->reportError(QString("no anchor %1 (%2 anchors)").arg(i).arg(this->anchorCount()));
    return false;
  }
  vtkNew<vtkPoints> kept;
  for (vtkIdType k = 0; k < this->I->Anchors->GetNumberOfPoints(); ++k)
    if (k != i)
      kept->InsertNextPoint(this->I->Anchors->GetPoint(k));
  this->I->Anchors->DeepCopy(kept);
  this->Weights.erase(this->Weights.begin() + i);
  this->Selected = std::min(this->Selected, this->anchorCount() - 1);
  this->update(AnchorsChanged);
  return true;
}

void SurfaceWindow::selectAnchor(int i)
{
  const int n = this->anchorCount();
  if (n == 0)
    return;
  this->Selected = ((i % n) + n) % n;
  this->update(FieldChanged);
}

bool SurfaceWindow::setWeight(int i, double w)
{
  if (i < 0 || i >= static_cast<int>(this->Weights.size()) || !std::isfinite(w))
  {
    this->reportError(QString("weight %1 of anchor %2: no such anchor or not a finite number").arg(w).arg(i));
    return false;
  }
  this->Weights[static_cast<std::size_t>(i)] = w;
  this->update(WeightsChanged);
  return true;
}

bool SurfaceWindow::setWeights(const std::vector<double>& w)
{
  if (static_cast<int>(w.size()) != this->anchorCount())
  {
    this->reportError(QString("%1 weights for %2 anchors").arg(w.size()).arg(this->anchorCount()));
    return false;
  }
  for (double x : w)
    if (!std::isfinite(x))
    {
      this->reportError("a weight is not a finite number");
      return false;
    }
  this->Weights = w;
  this->update(WeightsChanged);
  return true;
}

void SurfaceWindow::setEditing(SurfaceEdit edit)
{
  this->Editing = edit;
  this->updatePanel();
}

void SurfaceWindow::setField(SurfaceField field)
{
  this->Field = field;
  this->update(FieldChanged);
}

int SurfaceWindow::addCurvePoint(double x, double y, double z)
{
  if (!this->I->Surface)
  {
    this->reportError("open a surface before drawing on it");
    return -1;
  }
  const double p[3] = { x, y, z };
  double q[3];
  if (!this->reporting([&]() { on_surface(*this->I->Mesh, this->I->Surface, p, q, "control point"); }))
    return -1;
  const int id = static_cast<int>(this->I->CurveControls->InsertNextPoint(q));
  this->update(CurveChanged);
  return id;
}

bool SurfaceWindow::moveCurvePoint(int i, double x, double y, double z)
{
  if (i < 0 || i >= this->I->CurveControls->GetNumberOfPoints())
  {
    this->reportError(QString("no curve point %1").arg(i));
    return false;
  }
  const double p[3] = { x, y, z };
  double q[3];
  if (!this->reporting([&]() { on_surface(*this->I->Mesh, this->I->Surface, p, q, "control point"); }))
    return false;
  this->I->CurveControls->SetPoint(i, q);
  this->I->CurveControls->Modified();
  this->update(CurveChanged);
  return true;
}

bool SurfaceWindow::removeCurvePoint(int i)
{
  if (i < 0 || i >= this->I->CurveControls->GetNumberOfPoints())
  {
    this->reportError(QString("no curve point %1").arg(i));
    return false;
  }
  vtkNew<vtkPoints> kept;
  for (vtkIdType k = 0; k < this->I->CurveControls->GetNumberOfPoints(); ++k)
    if (k != i)
      kept->InsertNextPoint(this->I->CurveControls->GetPoint(k));
  this->I->CurveControls->DeepCopy(kept);
  this->update(CurveChanged);
  return true;
}

void SurfaceWindow::setCurveClosed(bool closed)
{
  this->CurveClosed = closed;
  this->update(CurveChanged);
}

void SurfaceWindow::setCurveSamples(int samples_per_segment)
{
  this->I->CurveSamples = samples_per_segment;
  this->update(CurveChanged);
}

// --- computing ----------------------------------------------------------------------------

void SurfaceWindow::update(int what)
{
  if (!this->I->Surface)
  {
    this->updatePanel();
    return;
  }
  const bool had_average = this->Average.valid, had_target_average = this->TargetAverage.valid;
  if (what & (AnchorsChanged | WeightsChanged))
    this->updateAverage();
  if (what & (AnchorsChanged | FieldChanged))
    this->updateField();
  if (what & CurveChanged)
    this->updateCurve();
  if (what & (AnchorsChanged | WeightsChanged | TargetChanged))
    this->updateTargetAverage();
  if (what & (AnchorsChanged | FieldChanged | TargetChanged))
    this->updateTarget();
  this->updatePanel();
  if (what == WeightsChanged && had_average == this->Average.valid &&
    had_target_average == this->TargetAverage.valid && this->I->SceneBuilt)
  {
    // only the averages moved (the fields do not depend on the weights): move their spheres
    if (this->Average.valid)
      this->I->AveragePoint->SetPoint(0, this->Average.point);
    if (this->TargetAverage.valid)
      this->I->TargetAveragePoint->SetPoint(0, this->TargetAverage.point);
    this->I->AveragePoint->Modified();
    this->I->TargetAveragePoint->Modified();
    this->I->View->renderWindow()->Render();
    if (this->I->Target)
      this->I->TargetView->renderWindow()->Render();
    emit this->sceneUpdated();
    return;
  }
  this->updateScene();
}

void SurfaceWindow::updateAverage()
{
  this->Average = SurfaceAverage();
  if (this->anchorCount() == 0)
    return;
  const std::vector<double> w = this->normalizedWeights();
  if (!std::isfinite(w[0]))
    return; // weights summing to 0: no average (said in the panel)
  vtkNew<vtkDoubleArray> weights;
  weights->SetNumberOfComponents(static_cast<int>(w.size()));
  weights->SetNumberOfTuples(1);
  std::copy(w.begin(), w.end(), weights->GetPointer(0));
  vtkBaryWeightedAverage* f = this->I->AverageFilter;
  f->SetInputData(0, this->I->Surface);
  f->SetInputData(1, as_points(this->I->Anchors));
  f->SetWeights(weights);
  f->SetWarmStart(false);
  if (this->reporting([&]() { RunAlgorithm(f, {}); }))
    this->Average = read_average(f->GetOutput());
}

namespace
{
/// Texture coordinates of the anchors for a decal (§4.2): their positions in the plane of
/// their two principal directions, oriented so that the picture is not mirrored as seen from
/// outside (u x v along the surface normal at the anchors' centre), scaled into [0.1, 0.9]
/// keeping the aspect ratio. @throws bary::Error for fewer than 3 anchors or anchors on a line.
vtkSmartPointer<vtkDoubleArray> decal_uv(vtkPoints* anchors, vtkCellLocator* locator, vtkPolyData* surface)
{
  const vtkIdType n = anchors->GetNumberOfPoints();
  if (n < 3)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "a decal needs at least 3 anchors (their positions span the picture), got " + std::to_string(n));
  Eigen::MatrixXd P(n, 3);
  for (vtkIdType i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d)
      P(i, d) = anchors->GetPoint(i)[d];
  const Eigen::RowVector3d c = P.colwise().mean();
  const Eigen::MatrixXd Q = P.rowwise() - c;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Q.transpose() * Q);
  const Eigen::Vector3d ev = eig.eigenvalues(); // ascending
  if (ev(1) <= 1e-12 * ev(2))
    throw bary::Error(bary::ErrorCode::InvalidArgument, "a decal needs anchors that are not on one line");
  Eigen::Vector3d e1 = eig.eigenvectors().col(2), e2 = eig.eigenvectors().col(1);
  double closest[3], d2 = 0.0;
  vtkIdType cell = -1;
  int sub = 0;
  const double centre[3] = { c(0), c(1), c(2) };
  locator->FindClosestPoint(centre, closest, cell, sub, d2);
  double normal[3] = { 0.0, 0.0, 1.0 };
  if (cell >= 0)
  {
    const vtkIdType* ids = nullptr;
    vtkIdType m = 0;
    surface->GetCellPoints(cell, m, ids);
    double a[3], b[3], cc[3];
    surface->GetPoint(ids[0], a);
    surface->GetPoint(ids[1], b);
    surface->GetPoint(ids[2], cc);
    vtkTriangle::ComputeNormal(a, b, cc, normal);
  }
  if (e1.cross(e2).dot(Eigen::Vector3d(normal[0], normal[1], normal[2])) < 0.0)
    e2 = -e2;
  Eigen::MatrixXd uv(n, 2);
  uv.col(0) = Q * e1;
  uv.col(1) = Q * e2;
  const double half = uv.cwiseAbs().maxCoeff();
  uv = (uv.array() * (0.4 / half) + 0.5).matrix();
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetNumberOfComponents(2);
  array->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
    array->SetTuple2(i, uv(i, 0), uv(i, 1));
  return array;
}
} // namespace

void SurfaceWindow::updateField()
{
  this->I->Field = nullptr;
  if (this->Field == SurfaceField::None || this->anchorCount() == 0)
    return;
  vtkBarySurfaceWeights* f = this->I->FieldFilter;
  f->SetInputData(0, this->I->Surface);
  f->SetInputData(1, this->I->Surface);
  f->SetInputData(2, as_points(this->I->Anchors));
  this->reporting([&]() {
    if (this->Field == SurfaceField::Decal)
    {
      if (!this->I->Picture)
        throw bary::Error(bary::ErrorCode::InvalidArgument, "the decal needs a picture: File > Open decal picture...");
      f->SetAnchorTextureCoordinates(decal_uv(this->I->Anchors, this->I->Locator, this->I->Surface));
    }
    else
      f->SetAnchorTextureCoordinates(nullptr);
    RunAlgorithm(f, {});
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(f->GetOutput());
    this->I->Field = out;
  });
}

void SurfaceWindow::updateCurve()
{
  this->I->Curve = nullptr;
  const vtkIdType m = this->I->CurveControls->GetNumberOfPoints();
  if (m < 4)
    return; // a cubic B-spline needs 4 control points (said in the panel)
  vtkBarySurfaceCurve* f = this->I->CurveFilter;
  f->SetInputData(0, this->I->Surface);
  f->SetInputData(1, as_points(this->I->CurveControls));
  f->SetClosed(this->CurveClosed);
  f->SetSamplesPerSegment(this->I->CurveSamples);
  this->reporting([&]() {
    RunAlgorithm(f, {});
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(f->GetOutput());
    this->I->Curve = out;
  });
}

void SurfaceWindow::updateTargetAverage()
{
  this->TargetAverage = SurfaceAverage();
  if (!this->I->Target || this->anchorCount() == 0 ||
    this->I->TargetAnchors->GetNumberOfPoints() != this->anchorCount())
    return; // said in the panel: the anchors no longer correspond
  const std::vector<double> w = this->normalizedWeights();
  if (std::isfinite(w[0]))
  {
    vtkNew<vtkDoubleArray> weights;
    weights->SetNumberOfComponents(static_cast<int>(w.size()));
    weights->SetNumberOfTuples(1);
    std::copy(w.begin(), w.end(), weights->GetPointer(0));
    vtkBaryWeightedAverage* f = this->I->TargetAverageFilter;
    f->SetInputData(0, this->I->Target);
    f->SetInputData(1, as_points(this->I->TargetAnchors));
    f->SetWeights(weights);
    if (this->reporting([&]() { RunAlgorithm(f, {}); }))
      this->TargetAverage = read_average(f->GetOutput());
  }
}

void SurfaceWindow::updateTarget()
{
  this->I->Transferred = nullptr;
  this->TransferSummary = nlohmann::json::object();
  if (!this->I->Target || !this->I->Field ||
    this->I->TargetAnchors->GetNumberOfPoints() != this->anchorCount())
    return;
  vtkBarySurfaceCorrespondence* t = this->I->TransferFilter;
  t->SetInputData(0, this->I->Target);
  t->SetInputData(1, as_points(this->I->TargetAnchors));
  t->SetInputData(2, this->I->Field);
  t->SetInputData(3, as_points(this->I->Anchors));
  t->ClearArrayNames();
  t->AddArrayName("Weights"); // the decal is drawn where they mean something
  if (this->Field == SurfaceField::Decal)
    t->AddArrayName("TCoords");
  this->reporting([&]() {
    RunAlgorithm(t, {});
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(t->GetOutput());
    this->I->Transferred = out;
    this->TransferSummary = { { "undefined", t->GetNumberOfUndefined() },
      { "flipped", t->GetNumberOfFlipped() }, { "stretch_best_95_percent", t->GetStretchBest95() },
      { "points", out->GetNumberOfPoints() } };
  });
}

// --- drawing ------------------------------------------------------------------------------

namespace
{
/// Adds the field of @p data (vtkBarySurfaceWeights' or the correspondence's output) for
/// @p field: the selected anchor's weight where meaningful (BuildScene: colour map, level sets,
/// anchors with the selected one in red), or the decal picture; plain otherwise.
void add_field(vtkRenderer* renderer, vtkPolyData* data, vtkPolyData* plain, vtkPoints* anchors,
  SurfaceField field, int selected, vtkImageData* picture, const std::string& title)
{
  renderer->RemoveAllViewProps();
  const int n = static_cast<int>(anchors->GetNumberOfPoints());
  if (data && field == SurfaceField::AnchorWeight && data->GetPointData()->GetArray("Weights") &&
    selected >= 0 && selected < n)
  {
    SceneOptions options;
    options.controls = ControlKind::FreePoints;
    options.component = selected;
    options.influence_level = false;
    options.title = title;
    vtkNew<vtkPolyData> controls;
    controls->SetPoints(anchors);
    BuildScene(renderer, MeaningfulSurfaceWeights(data, "Weights"), nullptr, controls, nullptr, options);
    // where the weights mean nothing (NaN): the plain surface's grey, not the colour map's red
    vtkActorCollection* actors = renderer->GetActors();
    actors->InitTraversal();
    while (vtkActor* actor = actors->GetNextActor())
      if (vtkMapper* mapper = actor->GetMapper())
        if (auto* table = vtkLookupTable::SafeDownCast(mapper->GetLookupTable()))
          table->SetNanColor(0.85, 0.85, 0.85, 1.0);
    return;
  }
  vtkSmartPointer<vtkPolyData> shown = plain;
  vtkImageData* texture = nullptr;
  if (data && field == SurfaceField::Decal && data->GetPointData()->GetArray("TCoords") && picture)
  {
    // texture coordinates where defined; elsewhere outside the picture (its border)
    shown = vtkSmartPointer<vtkPolyData>::New();
    shown->SetPoints(data->GetPoints());
    vtkDataArray* uv = data->GetPointData()->GetArray("TCoords");
    vtkNew<vtkDoubleArray> tc;
    tc->SetName("TCoords");
    tc->SetNumberOfComponents(2);
    tc->SetNumberOfTuples(uv->GetNumberOfTuples());
    int dims[3];
    picture->GetDimensions(dims);
    // [0, 1] of the decal -> the picture inside its 4-pixel border
    const double su = (dims[0] - 8.0) / dims[0], sv = (dims[1] - 8.0) / dims[1];
    // where the weights mean something (as for the weight field: defined, none below -1, §4.4);
    // far from the anchors the extrapolated uv would repeat pieces of the picture
    vtkDataArray* w = data->GetPointData()->GetArray("Weights");
    vtkDataArray* defined = data->GetPointData()->GetArray("Defined");
    std::vector<bool> valid(static_cast<std::size_t>(uv->GetNumberOfTuples()));
    for (vtkIdType p = 0; p < uv->GetNumberOfTuples(); ++p)
    {
      const double u = uv->GetComponent(p, 0), v = uv->GetComponent(p, 1);
      bool ok = std::isfinite(u) && std::isfinite(v) && (!defined || defined->GetComponent(p, 0) != 0);
      for (int c = 0; ok && w && c < w->GetNumberOfComponents(); ++c)
        ok = w->GetComponent(p, c) >= -1.0;
      tc->SetTuple2(p, ok ? 0.5 + (u - 0.5) * su : -1.0, ok ? 0.5 + (v - 0.5) * sv : -1.0);
      valid[static_cast<std::size_t>(p)] = ok;
    }
    shown->GetPointData()->SetTCoords(tc);
    // triangles with a corner outside are drawn plain: interpolating towards the outside
    // value would smear a band of the picture along the decal's edge
    vtkNew<vtkCellArray> inside, outside;
    const vtkIdType* ids = nullptr;
    vtkIdType m = 0;
    for (vtkIdType c = 0; c < data->GetNumberOfPolys(); ++c)
    {
      data->GetCellPoints(c, m, ids);
      bool all = true;
      for (vtkIdType k = 0; k < m; ++k)
        all = all && valid[static_cast<std::size_t>(ids[k])];
      (all ? inside : outside)->InsertNextCell(m, ids);
    }
    shown->SetPolys(inside);
    vtkNew<vtkPolyData> rest;
    rest->SetPoints(data->GetPoints());
    rest->SetPolys(outside);
    add_surface(renderer, rest, nullptr);
    texture = picture;
  }
  add_surface(renderer, shown, texture);
  const double grey[3] = { 0.25, 0.35, 0.8 };
  if (n > 0)
  {
    double b[6];
    plain->GetBounds(b);
    const double diag = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
    AddSpheres(renderer, anchors, 0.008 * diag, grey);
    if (selected >= 0 && selected < n)
    {
      vtkNew<vtkPoints> one;
      one->InsertNextPoint(anchors->GetPoint(selected));
      const double red[3] = { 0.85, 0.1, 0.1 };
      AddSpheres(renderer, one, 0.0085 * diag, red);
    }
  }
  add_text(renderer, title);
}

} // namespace

void SurfaceWindow::drawScene(vtkRenderer* left, vtkRenderer* right)
{
  const std::string title = this->Field == SurfaceField::AnchorWeight
    ? "weight of anchor " + std::to_string(this->Selected)
    : this->Field == SurfaceField::Decal ? "decal (inverse problem)" : "weighted average";
  this->reporting([&]() {
    add_field(left, this->I->Field, this->I->Surface, this->I->Anchors, this->Field,
      this->Selected, this->I->Picture, title);
  });
  const double diag = diagonal(this->I->Surface);
  const double yellow[3] = { 1.0, 0.8, 0.0 };
  if (this->Average.valid)
  {
    vtkNew<vtkPoints> p; // the views' sphere follows AveragePoint; a snapshot's is a copy
    p->InsertNextPoint(this->Average.point);
    vtkPoints* shown = left == this->I->Renderer.Get() ? this->I->AveragePoint.Get() : p.Get();
    shown->SetNumberOfPoints(1);
    shown->SetPoint(0, this->Average.point);
    AddSpheres(left, shown, 0.014 * diag, yellow);
  }
  if (this->I->CurveControls->GetNumberOfPoints() > 0)
  {
    const double green[3] = { 0.1, 0.6, 0.2 };
    AddSpheres(left, this->I->CurveControls, 0.007 * diag, green);
  }
  if (this->I->Curve && this->I->Curve->GetNumberOfLines() > 0)
  {
    const double orange[3] = { 1.0, 0.5, 0.0 };
    AddLines(left, this->I->Curve->GetPoints(), this->I->Curve->GetLines(), 4.0, orange);
  }
  if (this->I->Remeshed && this->I->Remeshed->GetNumberOfPolys() > 0)
  {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(this->I->Remeshed);
    mapper->ScalarVisibilityOff();
    // the quads' edges lie on the surface: drawn in front of it
    mapper->SetRelativeCoincidentTopologyLineOffsetParameters(0.0, -66000.0);
    vtkNew<vtkActor> quads;
    quads->SetMapper(mapper);
    quads->GetProperty()->SetRepresentationToWireframe();
    quads->GetProperty()->SetColor(0.1, 0.25, 0.7);
    quads->GetProperty()->SetLineWidth(1.5);
    quads->GetProperty()->LightingOff();
    left->AddActor(quads);
  }
  if (!this->I->Target || !right)
    return;
  this->reporting([&]() {
    add_field(right, this->I->Transferred, this->I->Target, this->I->TargetAnchors, this->Field,
      this->Selected, this->I->Picture, "target: " + title + " transferred");
  });
  if (this->TargetAverage.valid)
  {
    vtkNew<vtkPoints> p;
    vtkPoints* shown = right == this->I->TargetRenderer.Get() ? this->I->TargetAveragePoint.Get() : p.Get();
    shown->SetNumberOfPoints(1);
    shown->SetPoint(0, this->TargetAverage.point);
    AddSpheres(right, shown, 0.014 * diagonal(this->I->Target), yellow);
  }
}

void SurfaceWindow::updateScene()
{
  if (!this->I->Surface)
    return;
  this->drawScene(this->I->Renderer, this->I->TargetRenderer);
  this->I->SceneBuilt = true;
  if (this->CameraNeedsReset)
  {
    this->resetCamera();
    this->CameraNeedsReset = false;
  }
  this->I->View->renderWindow()->Render();
  if (this->I->Target)
    this->I->TargetView->renderWindow()->Render();
  emit this->sceneUpdated();
}

void SurfaceWindow::resetCamera()
{
  // looking at the anchors from outside (from the surface's centre towards their centroid,
  // raised by 30 degrees), or from -y raised when there are none
  const auto aim = [](vtkRenderer* r, vtkPolyData* surface, vtkPoints* anchors) {
    if (!surface)
      return;
    double b[6], centre[3], dir[3] = { 0.0, -1.0, 0.0 };
    surface->GetBounds(b);
    for (int d = 0; d < 3; ++d)
      centre[d] = 0.5 * (b[2 * d] + b[2 * d + 1]);
    if (anchors->GetNumberOfPoints() > 0)
    {
      double c[3] = { 0.0, 0.0, 0.0 };
      for (vtkIdType i = 0; i < anchors->GetNumberOfPoints(); ++i)
        for (int d = 0; d < 3; ++d)
          c[d] += anchors->GetPoint(i)[d] / static_cast<double>(anchors->GetNumberOfPoints());
      const double len = std::hypot(c[0] - centre[0], c[1] - centre[1]);
      if (len > 1e-9 * diagonal(surface))
      {
        dir[0] = (c[0] - centre[0]) / len;
        dir[1] = (c[1] - centre[1]) / len;
      }
    }
    vtkCamera* camera = r->GetActiveCamera();
    camera->SetFocalPoint(centre);
    camera->SetPosition(centre[0] + dir[0], centre[1] + dir[1], centre[2] + std::tan(vtkMath::RadiansFromDegrees(30.0)));
    camera->SetViewUp(0.0, 0.0, 1.0);
    r->ResetCamera();
  };
  aim(this->I->Renderer, this->I->Surface, this->I->Anchors);
  aim(this->I->TargetRenderer, this->I->Target, this->I->TargetAnchors);
  this->I->View->renderWindow()->Render();
  if (this->I->Target)
    this->I->TargetView->renderWindow()->Render();
}

vtkSmartPointer<vtkRenderWindow> SurfaceWindow::snapshot(int width, int height)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(width, height);
  if (!this->I->Surface)
    return window;
  // the scene drawn afresh into renderers of this window (no actor shared between OpenGL
  // contexts), seen by the views' cameras
  const bool two = this->I->Target != nullptr;
  vtkNew<vtkRenderer> left, right;
  this->drawScene(left, two ? right.Get() : nullptr);
  const std::pair<vtkRenderer*, vtkRenderer*> views[2] = { { left, this->I->Renderer },
    { right, this->I->TargetRenderer } };
  for (int k = 0; k < (two ? 2 : 1); ++k)
  {
    vtkRenderer* r = views[k].first;
    r->SetBackground(1.0, 1.0, 1.0);
    r->SetViewport(two ? 0.5 * k : 0.0, 0.0, two ? 0.5 * (k + 1) : 1.0, 1.0);
    r->GetActiveCamera()->DeepCopy(views[k].second->GetActiveCamera());
    r->ResetCamera(); // the views' directions, framed for this window's aspect
    window->AddRenderer(r);
  }
  window->Render();
  return window;
}

bool SurfaceWindow::saveCurve(const QString& path)
{
  return this->reporting([&]() {
    if (!this->I->Curve)
      throw bary::Error(bary::ErrorCode::EmptyInput, "no curve: a cubic B-spline needs 4 control points");
    const std::string p = path.toStdString();
    if (vtkBaryDataIO::CanWrite(p) && vtkBaryDataIO::Extension(p) != ".txt")
      vtkBaryDataIO::Write(this->I->Curve, p);
    else
      WritePointsText(this->I->Curve, p);
  });
}

bool SurfaceWindow::saveScreenshot(const QString& path)
{
  return this->reporting([&]() {
    QApplication::processEvents(); // rows added to the panel are shown by the event loop
    this->I->View->renderWindow()->Render();
    if (this->I->Target)
      this->I->TargetView->renderWindow()->Render();
    const QImage image = this->grab().toImage();
    if (image.isNull() || !image.save(path))
      throw bary::Error(bary::ErrorCode::Io, "cannot write the screenshot " + path.toStdString());
  });
}

// --- interaction --------------------------------------------------------------------------

bool SurfaceWindow::pickSurface(int x, int y, double world[3]) const
{
  if (!this->I->Surface)
    return false;
  double p0[4], p1[4];
  vtkInteractorObserver::ComputeDisplayToWorld(this->I->Renderer, x, y, 0.0, p0);
  vtkInteractorObserver::ComputeDisplayToWorld(this->I->Renderer, x, y, 1.0, p1);
  // the first crossing of the ray from the camera with the surface
  double t = 0.0, pcoords[3];
  int sub = 0;
  vtkIdType cell = -1;
  const double tolerance = 1e-9 * diagonal(this->I->Surface);
  return this->I->Locator->IntersectWithLine(p0, p1, tolerance, t, world, pcoords, sub, cell) != 0;
}

int SurfaceWindow::pickPoint(vtkPoints* points, int x, int y) const
{
  int best = -1;
  double best_d2 = 12.0 * 12.0; // pixels
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double p[3], d[3];
    points->GetPoint(i, p);
    vtkInteractorObserver::ComputeWorldToDisplay(this->I->Renderer, p[0], p[1], p[2], d);
    const double d2 = (d[0] - x) * (d[0] - x) + (d[1] - y) * (d[1] - y);
    if (d2 < best_d2)
    {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

void SurfaceWindow::installInteraction()
{
  this->I->Callback->SetClientData(this);
  this->I->Callback->SetCallback([](vtkObject* caller, unsigned long event, void* client, void*) {
    auto* self = static_cast<SurfaceWindow*>(client);
    Internals& I = *self->I;
    auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
    int pos[2];
    interactor->GetEventPosition(pos);
    if (event == vtkCommand::LeftButtonPressEvent)
    {
      const bool curve = self->Editing == SurfaceEdit::Curve;
      const int id = self->pickPoint(curve ? I.CurveControls.Get() : I.Anchors.Get(), pos[0], pos[1]);
      if (id >= 0)
      {
        I.Callback->AbortFlagOn();
        I.Dragging = id;
        I.DraggingCurve = curve;
        if (!curve)
          self->selectAnchor(id);
        return;
      }
      double world[3];
      if (interactor->GetControlKey() && self->pickSurface(pos[0], pos[1], world))
      {
        I.Callback->AbortFlagOn();
        curve ? self->addCurvePoint(world[0], world[1], world[2]) : self->addAnchor(world[0], world[1], world[2]);
      }
    }
    else if (event == vtkCommand::MouseMoveEvent && I.Dragging >= 0)
    {
      I.Callback->AbortFlagOn();
      double world[3];
      if (self->pickSurface(pos[0], pos[1], world))
        I.DraggingCurve ? self->moveCurvePoint(I.Dragging, world[0], world[1], world[2])
                        : self->moveAnchor(I.Dragging, world[0], world[1], world[2]);
    }
    else if (event == vtkCommand::LeftButtonReleaseEvent && I.Dragging >= 0)
    {
      I.Callback->AbortFlagOn();
      I.Dragging = -1;
    }
  });
  vtkRenderWindowInteractor* interactor = this->I->View->interactor();
  for (unsigned long e : { vtkCommand::LeftButtonPressEvent, vtkCommand::MouseMoveEvent,
         vtkCommand::LeftButtonReleaseEvent })
    interactor->AddObserver(e, this->I->Callback, 10.0f);
}

// --- panel and menus ----------------------------------------------------------------------

void SurfaceWindow::buildPanel()
{
  auto* dock = new QDockWidget("Weighted averages on the surface", this);
  dock->setFeatures(QDockWidget::DockWidgetMovable);
  auto* panel = new QWidget(dock);
  auto* layout = new QVBoxLayout(panel);
  Internals& I = *this->I;

  I.SurfaceInfo = new QLabel("no surface", panel);
  I.SurfaceInfo->setWordWrap(true);
  layout->addWidget(I.SurfaceInfo);

  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("Ctrl + click adds", panel));
  I.EditBox = new QComboBox(panel);
  I.EditBox->setObjectName("surface_edit");
  I.EditBox->addItems({ "anchors", "curve points" });
  row->addWidget(I.EditBox);
  layout->addLayout(row);
  connect(I.EditBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int i) {
    if (!this->I->Updating)
      this->setEditing(i == 1 ? SurfaceEdit::Curve : SurfaceEdit::Anchors);
  });

  row = new QHBoxLayout;
  row->addWidget(new QLabel("Surface shows", panel));
  I.FieldBox = new QComboBox(panel);
  I.FieldBox->setObjectName("surface_field");
  I.FieldBox->addItems({ "nothing", "the selected anchor's weight", "a decal (picture)" });
  row->addWidget(I.FieldBox);
  layout->addLayout(row);
  connect(I.FieldBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int i) {
    if (!this->I->Updating)
      this->setField(static_cast<SurfaceField>(i));
  });

  auto* anchors = new QGroupBox("Anchors and weights", panel);
  auto* anchorsLayout = new QVBoxLayout(anchors);
  I.AnchorRows = new QWidget(anchors);
  new QVBoxLayout(I.AnchorRows);
  I.AnchorGroup = new QButtonGroup(this);
  connect(I.AnchorGroup, &QButtonGroup::idClicked, this, [this](int id) {
    if (!this->I->Updating)
      this->selectAnchor(id);
  });
  anchorsLayout->addWidget(I.AnchorRows);
  auto* buttons = new QHBoxLayout;
  auto* uniform = new QPushButton("Uniform weights", anchors);
  connect(uniform, &QPushButton::clicked, this, [this]() {
    this->setWeights(std::vector<double>(this->Weights.size(), 1.0 / std::max<std::size_t>(1, this->Weights.size())));
  });
  auto* remove = new QPushButton("Remove selected", anchors);
  connect(remove, &QPushButton::clicked, this, [this]() { this->removeAnchor(this->Selected); });
  buttons->addWidget(uniform);
  buttons->addWidget(remove);
  anchorsLayout->addLayout(buttons);
  I.AverageInfo = new QLabel(anchors);
  I.AverageInfo->setObjectName("surface_average");
  I.AverageInfo->setWordWrap(true);
  anchorsLayout->addWidget(I.AverageInfo);
  layout->addWidget(anchors);

  auto* curve = new QGroupBox("Cubic B-spline on the surface", panel);
  auto* curveLayout = new QVBoxLayout(curve);
  I.ClosedBox = new QCheckBox("closed", curve);
  I.ClosedBox->setObjectName("surface_curve_closed");
  connect(I.ClosedBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->I->Updating)
      this->setCurveClosed(on);
  });
  row = new QHBoxLayout;
  row->addWidget(I.ClosedBox);
  row->addWidget(new QLabel("samples per segment", curve));
  I.SamplesBox = new QSpinBox(curve);
  I.SamplesBox->setObjectName("surface_curve_samples");
  I.SamplesBox->setRange(1, static_cast<int>(bary::kMaxSamplesPerSegment));
  connect(I.SamplesBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int v) {
    if (!this->I->Updating)
      this->setCurveSamples(v);
  });
  row->addWidget(I.SamplesBox);
  curveLayout->addLayout(row);
  auto* clear = new QPushButton("Clear the curve", curve);
  connect(clear, &QPushButton::clicked, this, [this]() {
    this->I->CurveControls->Reset();
    this->I->CurveControls->Modified();
    this->update(CurveChanged);
  });
  curveLayout->addWidget(clear);
  I.CurveInfo = new QLabel(curve);
  I.CurveInfo->setWordWrap(true);
  curveLayout->addWidget(I.CurveInfo);
  layout->addWidget(curve);

  auto* remesh = new QGroupBox("Semiregular remeshing", panel);
  auto* remeshLayout = new QVBoxLayout(remesh);
  row = new QHBoxLayout;
  auto* openLayout = new QPushButton("Quad layout...", remesh);
  connect(openLayout, &QPushButton::clicked, this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open a coarse quad layout on the surface");
    if (!path.isEmpty())
      this->openQuadLayout(path);
  });
  row->addWidget(openLayout);
  row->addWidget(new QLabel("levels", remesh));
  I.LevelsBox = new QSpinBox(remesh);
  I.LevelsBox->setObjectName("surface_remesh_levels");
  I.LevelsBox->setRange(0, bary::kMaxRemeshLevels);
  connect(I.LevelsBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int v) {
    if (!this->I->Updating)
      this->setRemeshLevels(v);
  });
  row->addWidget(I.LevelsBox);
  auto* clearLayout = new QPushButton("Clear", remesh);
  connect(clearLayout, &QPushButton::clicked, this, &SurfaceWindow::closeQuadLayout);
  row->addWidget(clearLayout);
  remeshLayout->addLayout(row);
  I.RemeshInfo = new QLabel(remesh);
  I.RemeshInfo->setWordWrap(true);
  remeshLayout->addWidget(I.RemeshInfo);
  layout->addWidget(remesh);

  auto* target = new QGroupBox("Correspondence", panel);
  auto* targetLayout = new QVBoxLayout(target);
  I.TargetInfo = new QLabel("no target: File > Open correspondence target...", target);
  I.TargetInfo->setObjectName("surface_target");
  I.TargetInfo->setWordWrap(true);
  I.TargetInfo->setMinimumHeight(5 * I.TargetInfo->fontMetrics().lineSpacing());
  targetLayout->addWidget(I.TargetInfo);
  layout->addWidget(target);
  layout->addStretch(1);
  dock->setWidget(panel);
  dock->setMinimumWidth(330);
  this->addDockWidget(Qt::RightDockWidgetArea, dock);
  this->updatePanel();
}

void SurfaceWindow::updatePanel()
{
  Internals& I = *this->I;
  I.Updating = true;
  I.EditBox->setCurrentIndex(this->Editing == SurfaceEdit::Curve ? 1 : 0);
  I.FieldBox->setCurrentIndex(static_cast<int>(this->Field));
  I.ClosedBox->setChecked(this->CurveClosed);
  I.SamplesBox->setValue(I.CurveSamples);

  // one row per anchor: select button, slider (weight in [0, 1]), the normalised weight
  const int n = this->anchorCount();
  auto* rows = static_cast<QVBoxLayout*>(I.AnchorRows->layout());
  if (static_cast<int>(I.Sliders.size()) != n)
  {
    while (QLayoutItem* item = rows->takeAt(0))
    {
      if (QLayout* line = item->layout())
        while (QLayoutItem* inner = line->takeAt(0))
        {
          delete inner->widget();
          delete inner;
        }
      delete item->widget();
      delete item; // a layout item that is a layout deletes the layout
    }
    I.Sliders.clear();
    I.Values.clear();
    for (QAbstractButton* b : I.AnchorGroup->buttons())
      I.AnchorGroup->removeButton(b);
    for (int i = 0; i < n; ++i)
    {
      auto* line = new QHBoxLayout;
      auto* select = new QRadioButton(QString("a%1").arg(i), I.AnchorRows);
      I.AnchorGroup->addButton(select, i);
      auto* slider = new QSlider(Qt::Horizontal, I.AnchorRows);
      slider->setObjectName(QString("surface_weight_%1").arg(i));
      slider->setRange(0, 1000);
      connect(slider, &QSlider::valueChanged, this, [this, i](int v) {
        if (!this->I->Updating)
          this->setWeight(i, v / 1000.0);
      });
      auto* value = new QLabel(I.AnchorRows);
      value->setMinimumWidth(48);
      line->addWidget(select);
      line->addWidget(slider, 1);
      line->addWidget(value);
      rows->addLayout(line);
      I.Sliders.push_back(slider);
      I.Values.push_back(value);
    }
  }
  const std::vector<double> w = this->normalizedWeights();
  for (int i = 0; i < n; ++i)
  {
    I.Sliders[static_cast<std::size_t>(i)]->setValue(static_cast<int>(std::lround(1000.0 * std::clamp(this->Weights[static_cast<std::size_t>(i)], 0.0, 1.0))));
    I.Values[static_cast<std::size_t>(i)]->setText(QString::number(w[static_cast<std::size_t>(i)], 'f', 3));
    if (QAbstractButton* b = I.AnchorGroup->button(i))
      b->setChecked(i == this->Selected);
  }
  if (n == 0)
    I.AverageInfo->setText("no anchors: Ctrl + click on the surface");
  else if (!std::isfinite(w[0]))
    I.AverageInfo->setText("the weights sum to 0: no weighted average");
  else if (this->Average.valid)
    I.AverageInfo->setText("average " + point_text(this->Average.point) +
      QString(" on triangle %1").arg(this->Average.face));
  else
    I.AverageInfo->setText("no projection found for these weights (the forward problem failed)");

  const vtkIdType m = I.CurveControls->GetNumberOfPoints();
  if (m < 4)
    I.CurveInfo->setText(QString("%1 control points: a cubic B-spline needs 4 (choose \"curve points\" "
                                 "above and Ctrl + click)").arg(m));
  else if (I.Curve)
    I.CurveInfo->setText(QString("%1 control points, %2 samples, %3 failed")
                           .arg(m)
                           .arg(I.Curve->GetNumberOfPoints())
                           .arg(I.CurveFilter->GetNumberOfFailures()));
  I.LevelsBox->setValue(I.RemeshLevels);
  I.RemeshInfo->setText(I.Remeshed ? QString("%1 quads from %2, %3 vertices failed")
                                       .arg(I.Remeshed->GetNumberOfPolys())
                                       .arg(I.Coarse->GetNumberOfPolys())
                                       .arg(I.RemeshFilter->GetNumberOfFailures())
                                   : QString("no quad layout"));
  if (I.Target)
  {
    QString text = QString("target: %1 points; ").arg(I.Target->GetNumberOfPoints());
    if (I.TargetAnchors->GetNumberOfPoints() != n)
      text += QString("%1 target anchors for %2 anchors: they no longer correspond")
                .arg(I.TargetAnchors->GetNumberOfPoints())
                .arg(n);
    else
    {
      text += this->TargetAverage.valid ? "average " + point_text(this->TargetAverage.point)
                                        : QString("no average on the target");
      if (!this->TransferSummary.empty())
        text += QString("\ntransfer: %1 undefined points, %2 flipped triangles, stretch (best 95%) %3")
                  .arg(this->TransferSummary["undefined"].get<long long>())
                  .arg(this->TransferSummary["flipped"].get<long long>())
                  .arg(this->TransferSummary["stretch_best_95_percent"].get<double>(), 0, 'f', 3);
    }
    I.TargetInfo->setText(text);
  }
  I.Updating = false;
}

void SurfaceWindow::buildMenus()
{
  QMenu* file = this->menuBar()->addMenu("&File");
  file->addAction("&Open surface...", this, [this]() {
    const QString mesh = QFileDialog::getOpenFileName(this, "Open a triangle surface", QString(),
      "Surfaces (*.obj *.off *.ply *.stl *.vtp *.vtk);;All files (*)");
    if (mesh.isEmpty())
      return;
    const QString embedding = QFileDialog::getOpenFileName(this,
      "Its embedding (cancel to compute it)", QString(), "Embeddings (*.txt *.vtp);;All files (*)");
    this->openSurface(mesh, embedding);
  }, QKeySequence::Open);
  file->addAction("Open &anchors...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open anchors");
    if (!path.isEmpty())
      this->openAnchors(path);
  });
  file->addAction("Open &weights (first row)...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open weights");
    if (!path.isEmpty())
      this->openWeights(path);
  });
  file->addAction("Open &curve control points...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open curve control points");
    if (!path.isEmpty())
      this->openCurve(path);
  });
  file->addAction("Open decal &picture...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open a picture", QString(),
      "Pictures (*.png *.jpg *.jpeg *.bmp *.tif *.tiff *.pnm)");
    if (!path.isEmpty())
      this->openPicture(path);
  });
  file->addAction("Open correspondence &target...", this, [this]() {
    const QString mesh = QFileDialog::getOpenFileName(this, "Open the target surface");
    if (mesh.isEmpty())
      return;
    const QString anchors = QFileDialog::getOpenFileName(this, "Its anchors, in the same order");
    if (!anchors.isEmpty())
      this->openTarget(mesh, anchors);
  });
  file->addAction("Close the target", this, &SurfaceWindow::closeTarget);
  file->addAction("Open &quad layout (semiregular remeshing)...", this, [this]() {
    const QString path = QFileDialog::getOpenFileName(this, "Open a coarse quad layout on the surface");
    if (!path.isEmpty())
      this->openQuadLayout(path);
  });
  QMenu* examples = file->addMenu("Open &example");
  for (const QString& name : ExampleNames())
    examples->addAction(name, this, [this, name]() { this->loadExample(name); });
  file->addSeparator();
  file->addAction("Save the c&urve...", this, [this]() {
    const QString path = QFileDialog::getSaveFileName(this, "Save the curve's samples", "curve.vtp");
    if (!path.isEmpty())
      this->saveCurve(path);
  });
  file->addAction("Save screens&hot...", this, [this]() {
    const QString path = QFileDialog::getSaveFileName(this, "Save a screenshot", "surface.png", "PNG (*.png)");
    if (!path.isEmpty())
      this->saveScreenshot(path);
  });
  file->addSeparator();
  file->addAction("&Close", this, &QWidget::close, QKeySequence::Close);
  QMenu* view = this->menuBar()->addMenu("&View");
  view->addAction("&Reset camera", this, &SurfaceWindow::resetCamera, QKeySequence("R"));
  view->addAction("Next anchor", this, [this]() { this->selectAnchor(this->Selected + 1); }, QKeySequence("N"));
  view->addAction("Previous anchor", this, [this]() { this->selectAnchor(this->Selected - 1); }, QKeySequence("P"));
}

} // namespace viewer
} // namespace barylab
