#include "barylabViewerWindow.h"

#include "barylabRender.h"
#include "barylabViewerLocality.h"
#include "barylabViewerParameters.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"

#include "core/error.h"
#include "core/skeleton.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QImage>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QSlider>
#include <QSpinBox>
#include <QSplitter>
#include <QStatusBar>
#include <QTimer>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>

#include <QVTKOpenGLNativeWidget.h>

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkGenericOpenGLRenderWindow.h"
#include "vtkInteractorObserver.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

namespace barylab
{
namespace viewer
{
namespace
{
using json = nlohmann::json;

QString data_path(const char* name)
{
  return QString(BARYLAB_DEFAULT_DATA_DIR) + "/" + name;
}

struct Example
{
  const char* name;
  const char* controls;
  const char* model;
  const char* domain;
  const char* method;
  const char* pose;
  int selected;
};

const Example kExamples[] = {
  { "gingerbread-mvc", "cage2d.obj", "model2d.obj", "", "mvc", "cage2d_posed.obj", 14 },
  { "kidney-mvc", "cage3d.obj", "model3d.off", "", "mvc", "cage3d_posed.obj", 36 },
  { "gingerbread-bbw", "skeleton2d.tgf", "model2d.obj", "cage2d.obj", "bbw", "skeleton2d_pose.txt",
    3 },
  { "heart-scc", "heart_controls.obj", "heart.off", "", "scc", "heartbeat/frame_05.obj", 0 },
  // local barycentric coordinates: compare with mvc and open the locality charts (S)
  { "gingerbread-lbc", "cage2d.obj", "model2d.obj", "", "lbc", "cage2d_posed.obj", 14 },
  // 2D image mode: a picture as the model, warped as a texture by the cage
  { "gingerbread-image", "cage2d.obj", "gingerbread.png", "", "mvc", "cage2d_posed.obj", 14 },
};

std::string to_std(const QString& s)
{
  return s.toStdString();
}

vtkSmartPointer<vtkPoints> copy_points(vtkPoints* points)
{
  if (!points)
    return nullptr;
  auto copy = vtkSmartPointer<vtkPoints>::New();
  copy->SetDataTypeToDouble();
  copy->DeepCopy(points);
  return copy;
}

template <class T>
vtkSmartPointer<T> deep_copy(T* data)
{
  if (!data)
    return nullptr;
  vtkSmartPointer<T> copy;
  copy.TakeReference(T::SafeDownCast(data->NewInstance()));
  copy->DeepCopy(data);
  return copy;
}

bool is_skeleton_file(const QString& path)
{
  return QFileInfo(path).suffix().toLower() == "tgf";
}

QString quoted(const QString& s)
{
  if (!s.isEmpty() && !s.contains(QRegExp("[^A-Za-z0-9_./=:+-]")))
    return s;
  QString q = s;
  q.replace("'", "'\\''");
  return "'" + q + "'";
}

/// The weights computation a worker runs: no Qt, no shared state but the atomics.
ComputeResult run_compute(vtkSmartPointer<vtkDataSet> model, vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkDataSet> domain, WeightsParameters parameters, QString compare_method,
  std::shared_ptr<std::atomic<double>> progress, std::shared_ptr<std::atomic<bool>> cancel)
{
  ComputeResult result;
  const auto t0 = std::chrono::steady_clock::now();
  try
  {
    const int runs = compare_method.isEmpty() ? 1 : 2;
    for (int run = 0; run < runs; ++run)
    {
      WeightsParameters p = parameters;
      if (run == 1)
        p.method = to_std(compare_method);
      RunCallbacks callbacks;
      callbacks.progress = [progress, run, runs](double f) {
        progress->store((run + f) / runs);
      };
      callbacks.cancel = [cancel]() { return cancel->load(); };
      auto weighted = ComputeWeights(model, controls, p, callbacks, nullptr, domain);
      (run == 0 ? result.weighted : result.compare) = weighted;
    }
  }
  catch (const bary::Error& e)
  {
    result.cancelled = e.code() == bary::ErrorCode::Cancelled;
    result.error = QString::fromStdString(e.what());
  }
  catch (const std::exception& e)
  {
    result.error = QString::fromStdString(e.what());
  }
  result.seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress->store(1.0);
  return result;
}
} // namespace

QStringList ViewerWindow::ExampleNames()
{
  QStringList names;
  for (const Example& e : kExamples)
    names << e.name;
  return names;
}

ViewerWindow::ViewerWindow(QWidget* parent)
  : QMainWindow(parent)
  , Progress(std::make_shared<std::atomic<double>>(0.0))
  , CancelFlag(std::make_shared<std::atomic<bool>>(false))
{
  qRegisterMetaType<barylab::viewer::Inputs>();
  this->Watcher = std::make_unique<QFutureWatcher<ComputeResult>>();
  connect(this->Watcher.get(), &QFutureWatcher<ComputeResult>::finished, this,
    &ViewerWindow::onComputeDone);
  this->buildUi();
  this->syncPanel();
  this->updateScene();
  this->statusBar()->showMessage("Open a cage and a model (File > Open) or an example.");
}

ViewerWindow::~ViewerWindow()
{
  if (this->Watcher && this->Watcher->isRunning())
  {
    this->CancelFlag->store(true);
    this->Watcher->waitForFinished();
  }
}

// ------------------------------------------------------------------------------------------
// user interface

void ViewerWindow::buildUi()
{
  this->setWindowTitle("BaryLab viewer");
  this->resize(1280, 800);

  // views
  auto* splitter = new QSplitter(Qt::Horizontal, this);
  this->Renderer = vtkSmartPointer<vtkRenderer>::New();
  this->CompareRenderer = vtkSmartPointer<vtkRenderer>::New();
  this->CompareRenderer->SetActiveCamera(this->Renderer->GetActiveCamera()); // linked cameras
  for (int k = 0; k < 2; ++k)
  {
    auto* widget = new QVTKOpenGLNativeWidget(splitter);
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    window->SetMultiSamples(0);
    widget->setRenderWindow(window);
    window->AddRenderer(k == 0 ? this->Renderer : this->CompareRenderer);
    widget->setMinimumSize(320, 320);
    splitter->addWidget(widget);
    (k == 0 ? this->View : this->CompareView) = widget;
  }
  this->CompareView->hide();
  this->setCentralWidget(splitter);

  // locality charts (P(t), Q(k)), hidden until asked for
  this->Locality = new LocalityPanel(this);
  this->LocalityDock = new QDockWidget("Locality statistics", this);
  this->LocalityDock->setObjectName("locality_dock");
  this->LocalityDock->setWidget(this->Locality);
  this->addDockWidget(Qt::BottomDockWidgetArea, this->LocalityDock);
  this->LocalityDock->hide();
  connect(this->LocalityDock, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    if (visible)
      this->updateLocality();
  });

  this->InteractorCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->InteractorCallback->SetCallback(&ViewerWindow::OnInteractorEvent);
  this->InteractorCallback->SetClientData(this);
  vtkRenderWindowInteractor* interactor = this->View->interactor();
  for (unsigned long e : { vtkCommand::LeftButtonPressEvent, vtkCommand::MouseMoveEvent,
         vtkCommand::LeftButtonReleaseEvent })
    interactor->AddObserver(e, this->InteractorCallback, 10.0f);
  this->CameraCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->CameraCallback->SetCallback(&ViewerWindow::OnCameraModified);
  this->CameraCallback->SetClientData(this);
  this->Renderer->GetActiveCamera()->AddObserver(vtkCommand::ModifiedEvent, this->CameraCallback);

  // side panel
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);

  auto* inputs = new QGroupBox("Inputs");
  auto* inputsLayout = new QVBoxLayout(inputs);
  this->InputsLabel = new QLabel("(none)");
  this->InputsLabel->setMinimumHeight(3 * this->fontMetrics().height() + 6);
  this->InputsLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);
  inputsLayout->addWidget(this->InputsLabel);
  layout->addWidget(inputs);

  auto* method = new QGroupBox("Method");
  auto* methodLayout = new QVBoxLayout(method);
  auto* form = new QFormLayout;
  this->MethodBox = new QComboBox;
  this->CompareBox = new QComboBox;
  this->CompareBox->addItem("(none)", QString());
  for (const std::string& name : MethodNames())
  {
    this->MethodBox->addItem(QString::fromStdString(name), QString::fromStdString(name));
    this->CompareBox->addItem(QString::fromStdString(name), QString::fromStdString(name));
  }
  this->MethodBox->setObjectName("method");
  this->CompareBox->setObjectName("compare");
  this->CompareBox->setToolTip("a second method shown side by side, cameras linked");
  form->addRow("Method", this->MethodBox);
  form->addRow("Compare with", this->CompareBox);
  methodLayout->addLayout(form);
  this->ParameterForm = new QVBoxLayout; // one row widget per table row: hidden rows leave no gap
  this->ParameterForm->setContentsMargins(0, 0, 0, 0);
  methodLayout->addLayout(this->ParameterForm);
  this->buildParameterPanel();
  auto* buttons = new QHBoxLayout;
  this->ComputeButton = new QPushButton("Compute");
  this->ComputeButton->setObjectName("compute");
  this->CancelButton = new QPushButton("Cancel");
  this->CancelButton->setObjectName("cancel");
  this->CancelButton->setEnabled(false);
  buttons->addWidget(this->ComputeButton);
  buttons->addWidget(this->CancelButton);
  methodLayout->addLayout(buttons);
  layout->addWidget(method);
  connect(this->MethodBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Updating)
      this->setMethod(this->MethodBox->currentData().toString());
  });
  connect(this->CompareBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Updating)
      this->setCompareMethod(this->CompareBox->currentData().toString());
  });
  connect(this->ComputeButton, &QPushButton::clicked, this, &ViewerWindow::compute);
  connect(this->CancelButton, &QPushButton::clicked, this, &ViewerWindow::cancel);

  auto* controls = new QGroupBox("Controls (weight shown)");
  auto* controlsLayout = new QVBoxLayout(controls);
  this->ControlList = new QListWidget;
  this->ControlList->setObjectName("controls");
  this->ControlList->setMinimumHeight(110);
  controlsLayout->addWidget(this->ControlList);
  layout->addWidget(controls);
  connect(this->ControlList, &QListWidget::currentRowChanged, this, [this](int row) {
    if (!this->Updating && row >= 0)
      this->selectControl(row);
  });

  auto* display = new QGroupBox("Display");
  auto* displayForm = new QFormLayout(display);
  this->FieldBox = new QComboBox;
  this->FieldBox->addItems({ "weight", "gradient norm", "image" });
  this->LogBox = new QCheckBox("logarithmic colour scale");
  this->IsolineBox = new QSpinBox;
  this->IsolineBox->setRange(0, 50);
  this->InfluenceBox = new QCheckBox("influence level 10^-3/n");
  this->ClipBox = new QCheckBox("clip (3D)");
  this->ClipAxisBox = new QComboBox;
  this->ClipAxisBox->addItems({ "x", "y", "z" });
  this->ClipSlider = new QSlider(Qt::Horizontal);
  this->ClipSlider->setRange(0, 100);
  displayForm->addRow("Field", this->FieldBox);
  displayForm->addRow(this->LogBox);
  displayForm->addRow("Level sets", this->IsolineBox);
  displayForm->addRow(this->InfluenceBox);
  auto* clipRow = new QHBoxLayout;
  clipRow->addWidget(this->ClipBox);
  clipRow->addWidget(this->ClipAxisBox);
  displayForm->addRow(clipRow);
  displayForm->addRow("Clip position", this->ClipSlider);
  layout->addWidget(display);
  connect(this->FieldBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int i) {
    if (!this->Updating)
      i == 0 ? this->showWeight() : i == 1 ? this->showGradientNorm() : this->showImage();
  });
  connect(this->LogBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
      this->setLogScale(on);
  });
  connect(this->IsolineBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int n) {
    if (!this->Updating)
      this->setIsolines(n);
  });
  connect(this->InfluenceBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
      this->setInfluenceLevel(on);
  });
  connect(this->ClipBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
      this->setClipping(on);
  });
  connect(this->ClipAxisBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int a) {
    if (!this->Updating)
      this->setClipAxis(a);
  });
  connect(this->ClipSlider, &QSlider::valueChanged, this, [this](int v) {
    if (!this->Updating)
      this->setClipPosition(v / 100.0);
  });

  auto* deform = new QGroupBox("Deformation");
  auto* deformLayout = new QVBoxLayout(deform);
  auto* moveRow = new QHBoxLayout;
  this->MoveIdBox = new QSpinBox;
  this->MoveIdBox->setPrefix("#");
  moveRow->addWidget(this->MoveIdBox);
  for (auto*& box : this->MoveBox)
  {
    box = new QDoubleSpinBox;
    box->setRange(-1e6, 1e6);
    box->setDecimals(4);
    box->setSingleStep(0.05);
    moveRow->addWidget(box);
  }
  deformLayout->addLayout(moveRow);
  auto* deformButtons = new QHBoxLayout;
  auto* setButton = new QPushButton("Move");
  auto* resetButton = new QPushButton("Reset");
  auto* undoButton = new QPushButton("Undo");
  deformButtons->addWidget(setButton);
  deformButtons->addWidget(resetButton);
  deformButtons->addWidget(undoButton);
  deformLayout->addLayout(deformButtons);
  auto* twistRow = new QHBoxLayout;
  this->TwistAngleBox = new QDoubleSpinBox;
  this->TwistAngleBox->setObjectName("twist_angle");
  this->TwistAngleBox->setRange(-360.0, 360.0);
  this->TwistAngleBox->setSuffix(" deg");
  this->TwistAngleBox->setSingleStep(5.0);
  this->TwistAngleBox->setToolTip("BBW: rotation of the selected handle about its centre (2D: about "
                                  "z; 3D bone: about its axis)");
  this->TwistScaleBox = new QDoubleSpinBox;
  this->TwistScaleBox->setObjectName("twist_scale");
  this->TwistScaleBox->setRange(0.05, 20.0);
  this->TwistScaleBox->setDecimals(3);
  this->TwistScaleBox->setSingleStep(0.05);
  this->TwistScaleBox->setValue(1.0);
  this->TwistScaleBox->setToolTip("BBW: uniform scale of the selected handle about its centre");
  auto* twistButton = new QPushButton("Rotate/scale handle");
  twistButton->setObjectName("twist_apply");
  twistRow->addWidget(this->TwistAngleBox);
  twistRow->addWidget(this->TwistScaleBox);
  twistRow->addWidget(twistButton);
  deformLayout->addLayout(twistRow);
  layout->addWidget(deform);
  connect(twistButton, &QPushButton::clicked, this, [this]() {
    this->setHandleTwist(this->Options.component, this->TwistAngleBox->value(),
      this->TwistScaleBox->value());
  });
  connect(this->MoveIdBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int id) {
    if (this->PosedControls && id >= 0 && id < this->PosedControls->GetNumberOfPoints())
    {
      double p[3];
      this->PosedControls->GetPoint(id, p);
      for (int k = 0; k < 3; ++k)
        this->MoveBox[k]->setValue(p[k]);
    }
  });
  connect(setButton, &QPushButton::clicked, this, [this]() {
    this->setControlPosition(this->MoveIdBox->value(), this->MoveBox[0]->value(),
      this->MoveBox[1]->value(), this->MoveBox[2]->value());
  });
  connect(resetButton, &QPushButton::clicked, this, &ViewerWindow::resetPose);
  connect(undoButton, &QPushButton::clicked, this, &ViewerWindow::undo);

  this->StatsLabel = new QLabel;
  this->StatsLabel->setWordWrap(true);
  layout->addWidget(this->StatsLabel);
  layout->addStretch(1);

  auto* scroll = new QScrollArea;
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  scroll->setMinimumWidth(370);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  splitter->insertWidget(0, scroll);
  splitter->setStretchFactor(0, 0);
  splitter->setStretchFactor(1, 1);
  splitter->setStretchFactor(2, 1);

  this->ProgressBar = new QProgressBar;
  this->ProgressBar->setRange(0, 1000);
  this->ProgressBar->setMaximumWidth(220);
  this->ProgressBar->hide();
  this->statusBar()->addPermanentWidget(this->ProgressBar);

  // menus
  QMenu* file = this->menuBar()->addMenu("&File");
  file->addAction("&Open cage and model...", this, &ViewerWindow::openFilesDialog, QKeySequence::Open);
  QMenu* examples = file->addMenu("Open &example");
  for (const Example& e : kExamples)
  {
    const QString name = e.name;
    examples->addAction(name, this, [this, name]() { this->loadExample(name); });
  }
  file->addSeparator();
  file->addAction("&Load session...", this, &ViewerWindow::openSessionDialog, QKeySequence("Ctrl+L"));
  file->addAction("&Save session...", this, &ViewerWindow::saveSessionDialog, QKeySequence::Save);
  file->addSeparator();
  file->addAction("Load &pose...", this, &ViewerWindow::loadPoseDialog);
  file->addAction("Apply the example's pose", this, &ViewerWindow::applyExamplePose, QKeySequence("Ctrl+P"));
  file->addAction("Save p&ose...", this, &ViewerWindow::savePoseDialog);
  file->addAction("Save &deformed model...", this, &ViewerWindow::saveDeformedDialog, QKeySequence("Ctrl+D"));
  file->addAction("Save screens&hot...", this, &ViewerWindow::saveScreenshotDialog, QKeySequence("Ctrl+Shift+S"));
  file->addAction("&Export locality statistics (PNG, CSV)...", this, &ViewerWindow::exportLocalityDialog);
  file->addSeparator();
  file->addAction("&Quit", this, &QWidget::close, QKeySequence::Quit);
  QMenu* edit = this->menuBar()->addMenu("&Edit");
  edit->addAction("&Undo move", this, &ViewerWindow::undo, QKeySequence::Undo);
  edit->addAction("&Reset pose", this, &ViewerWindow::resetPose, QKeySequence("Ctrl+Shift+R"));
  const auto twist_by = [this](double degrees, double factor) {
    const HandleTwist t = this->handleTwist(this->Options.component);
    this->setHandleTwist(this->Options.component, t.angle_degrees + degrees, t.scale * factor);
  };
  edit->addAction("Rotate handle +15 deg", this, [twist_by]() { twist_by(15.0, 1.0); }, QKeySequence("]"));
  edit->addAction("Rotate handle -15 deg", this, [twist_by]() { twist_by(-15.0, 1.0); }, QKeySequence("["));
  edit->addAction("Scale handle x1.1", this, [twist_by]() { twist_by(0.0, 1.1); }, QKeySequence("+"));
  edit->addAction("Scale handle /1.1", this, [twist_by]() { twist_by(0.0, 1.0 / 1.1); }, QKeySequence("-"));
  QMenu* compute = this->menuBar()->addMenu("&Compute");
  compute->addAction("&Compute weights", this, &ViewerWindow::compute, QKeySequence("F5"));
  compute->addAction("C&ancel", this, &ViewerWindow::cancel, QKeySequence("Ctrl+."));
  compute->addAction("&Run in terminal...", this, &ViewerWindow::showCommandLine, QKeySequence("Ctrl+T"));
  QMenu* view = this->menuBar()->addMenu("&View");
  view->addAction("&Weight", this, &ViewerWindow::showWeight, QKeySequence("W"));
  view->addAction("&Gradient norm", this, &ViewerWindow::showGradientNorm, QKeySequence("G"));
  view->addAction("&Logarithmic scale", this, [this]() { this->setLogScale(!this->Options.log_scale); },
    QKeySequence("L"));
  view->addAction("&Clipping", this, [this]() { this->setClipping(!this->Options.clip); },
    QKeySequence("C"));
  view->addAction("Next control", this, [this]() { this->selectControl(this->Options.component + 1); },
    QKeySequence("N"));
  view->addAction("Previous control", this,
    [this]() { this->selectControl(this->Options.component - 1); }, QKeySequence("P"));
  view->addAction("Reset &camera", this, &ViewerWindow::resetCamera, QKeySequence("Ctrl+R"));
  view->addAction("Locality &statistics (P, Q)", this,
    [this]() { this->showLocality(!this->isLocalityShown()); }, QKeySequence("S"));
}

void ViewerWindow::buildParameterPanel()
{
  for (const ParameterField& f : WeightsParameterFields())
  {
    QWidget* editor = nullptr;
    const QString key = QString::fromStdString(f.key);
    switch (f.kind)
    {
      case ParameterField::Kind::Bool:
      {
        auto* box = new QCheckBox;
        connect(box, &QCheckBox::toggled, this, [this, key](bool on) {
          if (!this->Updating)
            this->setParameter(key, on);
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::Int:
      {
        auto* box = new QSpinBox;
        box->setRange(static_cast<int>(f.minimum), static_cast<int>(std::min(f.maximum, 2e9)));
        connect(box, QOverload<int>::of(&QSpinBox::valueChanged), this, [this, key](int v) {
          if (!this->Updating)
            this->setParameter(key, v);
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::Double:
      {
        auto* box = new QLineEdit; // free-form: tolerances span many decades
        box->setValidator(new QDoubleValidator(f.minimum, f.maximum, 17, box));
        connect(box, &QLineEdit::editingFinished, this, [this, key, box]() {
          if (!this->Updating)
            this->setParameter(key, box->text().toDouble());
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::Choice:
      {
        auto* box = new QComboBox;
        for (const std::string& c : f.choices)
          box->addItem(QString::fromStdString(c));
        connect(box, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this, key, box](int) {
          if (!this->Updating)
            this->setParameter(key, box->currentText());
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::String:
      {
        auto* box = new QLineEdit;
        connect(box, &QLineEdit::editingFinished, this, [this, key, box]() {
          if (!this->Updating)
            this->setParameter(key, box->text());
        });
        editor = box;
        break;
      }
    }
    editor->setObjectName(key);
    editor->setToolTip(QString::fromStdString(f.tooltip));
    auto* row = new QWidget;
    auto* rowLayout = new QHBoxLayout(row);
    rowLayout->setContentsMargins(0, 0, 0, 0);
    auto* label = new QLabel(QString::fromStdString(f.label));
    label->setToolTip(editor->toolTip());
    label->setMinimumWidth(130);
    rowLayout->addWidget(label);
    rowLayout->addWidget(editor, 1);
    this->ParameterForm->addWidget(row);
    this->ParameterWidgets.emplace_back(row, editor);
  }
}

/// Widgets from the state (parameters, display options), without feedback.
void ViewerWindow::syncPanel()
{
  this->Updating = true;
  const QString method = QString::fromStdString(this->Parameters.method);
  this->MethodBox->setCurrentIndex(this->MethodBox->findData(method));
  this->CompareBox->setCurrentIndex(std::max(0, this->CompareBox->findData(this->CompareMethod)));
  const auto& fields = WeightsParameterFields();
  for (std::size_t i = 0; i < fields.size(); ++i)
  {
    const ParameterField& f = fields[i];
    const json value = f.get(this->Parameters);
    QWidget* editor = this->ParameterWidgets[i].second;
    const bool applies = f.AppliesTo(this->Parameters.method) ||
      (!this->CompareMethod.isEmpty() && f.AppliesTo(to_std(this->CompareMethod)));
    this->ParameterWidgets[i].first->setVisible(applies);
    if (auto* b = qobject_cast<QCheckBox*>(editor))
      b->setChecked(value.get<bool>());
    else if (auto* s = qobject_cast<QSpinBox*>(editor))
      s->setValue(value.get<int>());
    else if (auto* c = qobject_cast<QComboBox*>(editor))
      c->setCurrentText(value.is_string() ? QString::fromStdString(value.get<std::string>())
                                          : QString::fromStdString(value.dump()));
    else if (auto* l = qobject_cast<QLineEdit*>(editor))
      l->setText(value.is_string() ? QString::fromStdString(value.get<std::string>())
                                   : QString::number(value.get<double>(), 'g', 17));
  }
  this->FieldBox->setCurrentIndex(this->Options.field == SceneOptions::Field::Weight ? 0
      : this->Options.field == SceneOptions::Field::GradientNorm                  ? 1
                                                                                 : 2);
  this->LogBox->setChecked(this->Options.log_scale);
  this->IsolineBox->setValue(this->Options.isolines);
  this->InfluenceBox->setChecked(this->Options.influence_level);
  this->ClipBox->setChecked(this->Options.clip);
  this->ClipAxisBox->setCurrentIndex(this->Options.clip_axis);
  this->ClipSlider->setValue(static_cast<int>(std::lround(this->Options.clip_position * 100.0)));
  this->ComputeButton->setEnabled(!this->isComputing());
  this->CancelButton->setEnabled(this->isComputing());
  if (this->ControlList->currentRow() != this->Options.component &&
    this->Options.component < this->ControlList->count())
    this->ControlList->setCurrentRow(this->Options.component);
  this->Updating = false;
}

void ViewerWindow::reportError(const QString& message)
{
  this->Errors << message;
  this->statusBar()->showMessage("Error: " + message);
  emit errorReported(message);
  if (this->Interactive)
    QMessageBox::warning(this, "BaryLab viewer", message);
}

// ------------------------------------------------------------------------------------------
// inputs

bool ViewerWindow::openFiles(const QStringList& files)
{
  Inputs in;
  if (files.size() < 2 || files.size() > 3)
  {
    this->reportError("open CONTROLS MODEL [DOMAIN]: a cage, skeleton (.tgf) or control points, "
                      "the model, and for a skeleton the domain to mesh (" +
      QString::number(files.size()) + " file(s) given)");
    return false;
  }
  in.controls = files[0];
  in.model = files[1];
  if (files.size() == 3)
    in.domain = files[2];
  return this->openInputs(in);
}

bool ViewerWindow::openInputs(const Inputs& given)
{
  Inputs in = given; // absolute paths: sessions work from any folder
  for (QString* path : { &in.controls, &in.model, &in.domain, &in.pose })
    if (!path->isEmpty())
      *path = QFileInfo(*path).absoluteFilePath();
  if (this->isComputing())
  {
    this->reportError("a computation is running: cancel it first");
    return false;
  }
  vtkSmartPointer<vtkPolyData> controls;
  vtkSmartPointer<vtkDataSet> model, domain;
  vtkSmartPointer<vtkImageData> picture;
  try
  {
    if (is_skeleton_file(in.controls) && in.domain.isEmpty())
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "the skeleton '" + to_std(in.controls) +
          "' needs a domain to mesh (a polygon, closed surface or tet mesh) as third file");
    controls = vtkBaryDataIO::ReadPolyData(to_std(in.controls));
    if (IsPictureFile(to_std(in.model)))
    {
      // 2D image mode: the model is the cage's interior meshed, carrying the picture
      picture = ReadPicture(to_std(in.model));
      model = TexturedCageMesh(controls, picture);
    }
    else
      model = vtkBaryDataIO::Read(to_std(in.model));
    if (!vtkPointSet::SafeDownCast(model))
      throw bary::Error(bary::ErrorCode::Io, "'" + to_std(in.model) + "' does not hold a point set");
    if (!in.domain.isEmpty())
      domain = vtkBaryDataIO::Read(to_std(in.domain));
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->In = in;
  this->Controls = controls;
  this->Model = model;
  this->Domain = domain;
  this->Weighted = nullptr;
  this->CompareWeighted = nullptr;
  this->Deformed = nullptr;
  this->CompareDeformed = nullptr;
  this->PosedControls = copy_points(controls->GetPoints());
  this->UndoStack.clear();
  this->Twists.clear();
  this->Options.component = 0;
  this->Options.dimension = this->modelDimension();
  this->Options.clip = false;
  this->Picture = picture;
  this->Options.texture = picture;
  if (picture)
    this->Options.field = SceneOptions::Field::Image;
  else if (this->Options.field == SceneOptions::Field::Image)
    this->Options.field = SceneOptions::Field::Weight;
  this->CameraNeedsReset = true;
  if (is_skeleton_file(in.controls) && this->Parameters.method != "bbw")
    this->Parameters.method = "bbw";
  QString text = "<b>controls</b> " + QFileInfo(in.controls).fileName() + " (" +
    QString::number(controls->GetNumberOfPoints()) + " points)<br><b>model</b> " +
    QFileInfo(in.model).fileName() + " (" + QString::number(model->GetNumberOfPoints()) + " points)";
  if (!in.domain.isEmpty())
    text += "<br><b>domain</b> " + QFileInfo(in.domain).fileName();
  this->InputsLabel->setText(text);
  this->MoveIdBox->setRange(0, std::max<int>(0, static_cast<int>(controls->GetNumberOfPoints()) - 1));
  this->setWindowTitle("BaryLab viewer - " +
    (in.example.isEmpty() ? QFileInfo(in.model).fileName() : in.example));
  this->updateControlList();
  this->syncPanel();
  this->updateScene();
  this->statusBar()->showMessage("Opened " + QFileInfo(in.model).fileName() + ": press Compute (F5).");
  return true;
}

bool ViewerWindow::loadExample(const QString& name, bool compute)
{
  for (const Example& e : kExamples)
  {
    if (name != e.name)
      continue;
    Inputs in;
    in.controls = data_path(e.controls);
    in.model = data_path(e.model);
    if (*e.domain)
      in.domain = data_path(e.domain);
    in.example = e.name;
    in.pose = data_path(e.pose);
    this->Parameters = WeightsParameters();
    this->Parameters.method = e.method;
    this->CompareMethod.clear();
    if (!this->openInputs(in))
      return false;
    this->PendingSelection = e.selected;
    this->syncPanel();
    if (compute)
      this->compute();
    return true;
  }
  this->reportError("unknown example '" + name + "' (known: " + ExampleNames().join(", ") + ")");
  return false;
}

int ViewerWindow::modelDimension() const
{
  if (!this->Model)
    return 3;
  double b[6];
  this->Model->GetBounds(b);
  const double extent = std::max(1.0, std::max(b[1] - b[0], b[3] - b[2]));
  return b[5] - b[4] <= 1e-9 * extent ? 2 : 3;
}

ControlKind ViewerWindow::kindFor(const std::string& method) const
{
  if (this->Controls && method == "bbw" && this->Controls->GetNumberOfPolys() == 0 &&
    (this->Controls->GetNumberOfLines() > 0 || is_skeleton_file(this->In.controls)))
    return ControlKind::Skeleton;
  if (IsPointBasedMethod(method))
    return ControlKind::FreePoints;
  return ControlKind::Cage;
}

int ViewerWindow::componentCount() const
{
  if (this->Weighted)
    if (vtkDataArray* w =
          this->Weighted->GetPointData()->GetArray(this->Parameters.weights_name.c_str()))
      return w->GetNumberOfComponents();
  return 0;
}

void ViewerWindow::updateControlList()
{
  this->Updating = true;
  this->ControlList->clear();
  const int n = this->componentCount();
  if (n > 0 && this->shownKind() == ControlKind::Skeleton)
  {
    try
    {
      const bary::Skeleton s = vtkBaryConversion::ToSkeleton(this->Controls, this->modelDimension());
      for (Eigen::Index j = 0; j < s.P.size(); ++j)
        this->ControlList->addItem(QString("point handle %1 (joint %2)").arg(j).arg(s.P(j)));
      for (Eigen::Index b = 0; b < s.BE.rows(); ++b)
        this->ControlList->addItem(
          QString("bone %1 (joints %2-%3)").arg(b).arg(s.BE(b, 0)).arg(s.BE(b, 1)));
    }
    catch (const std::exception&)
    {
    }
  }
  else
    for (int i = 0; i < n; ++i)
      this->ControlList->addItem(QString("control point %1").arg(i));
  if (this->Options.component < this->ControlList->count())
    this->ControlList->setCurrentRow(this->Options.component);
  this->Updating = false;
}

// ------------------------------------------------------------------------------------------
// parameters and computation

void ViewerWindow::setMethod(const QString& method)
{
  const auto names = MethodNames();
  if (std::find(names.begin(), names.end(), to_std(method)) == names.end())
  {
    this->reportError("unknown method '" + method + "'");
    this->syncPanel();
    return;
  }
  this->Parameters.method = to_std(method);
  this->syncPanel();
  this->statusBar()->showMessage("Method " + method + ": press Compute (F5).");
}

bool ViewerWindow::setParameter(const QString& key, const QVariant& value)
{
  for (const ParameterField& f : WeightsParameterFields())
  {
    if (f.key != to_std(key))
      continue;
    try
    {
      json v;
      switch (f.kind)
      {
        case ParameterField::Kind::Bool: v = value.toBool(); break;
        case ParameterField::Kind::Int: v = value.toInt(); break;
        case ParameterField::Kind::Double: v = value.toDouble(); break;
        case ParameterField::Kind::Choice:
          v = f.get(this->Parameters).is_number() ? json(value.toString().toInt())
                                                  : json(to_std(value.toString()));
          break;
        case ParameterField::Kind::String: v = to_std(value.toString()); break;
      }
      f.set(this->Parameters, v);
    }
    catch (const std::exception& e)
    {
      this->reportError(QString::fromStdString(e.what()));
      return false;
    }
    this->syncPanel();
    this->statusBar()->showMessage("Parameter " + key + " = " + value.toString() +
      ": press Compute (F5).");
    return true;
  }
  this->reportError("unknown parameter '" + key + "'");
  return false;
}

void ViewerWindow::setParameters(const WeightsParameters& parameters)
{
  this->Parameters = parameters;
  this->syncPanel();
}

void ViewerWindow::setCompareMethod(const QString& method)
{
  this->CompareMethod = method;
  this->CompareView->setVisible(!method.isEmpty());
  this->CameraNeedsReset = true; // the views' aspect changes
  QApplication::processEvents(QEventLoop::ExcludeUserInputEvents); // lay the views out
  this->CompareWeighted = nullptr;
  this->CompareDeformed = nullptr;
  this->syncPanel();
  if (!method.isEmpty())
    this->statusBar()->showMessage("Compare with " + method + ": press Compute (F5).");
  this->updateScene();
}

void ViewerWindow::compute()
{
  if (this->isComputing())
    return;
  if (!this->Model || !this->Controls)
  {
    this->reportError("nothing to compute: open a cage and a model, or an example");
    return;
  }
  this->Progress->store(0.0);
  this->CancelFlag->store(false);
  this->Running = this->Parameters;
  this->RunningCompare = this->CompareMethod;
  // the worker gets its own copies: the views keep drawing the originals
  auto model = deep_copy(this->Model.Get());
  auto controls = deep_copy(this->Controls.Get());
  auto domain = deep_copy(this->Domain.Get());
  if (this->Synchronous)
  {
    QApplication::setOverrideCursor(Qt::WaitCursor);
    ComputeResult result = run_compute(model, controls, domain, this->Parameters,
      this->CompareMethod, this->Progress, this->CancelFlag);
    QApplication::restoreOverrideCursor();
    this->finishCompute(result);
    return;
  }
  this->Busy = true;
  const WeightsParameters parameters = this->Parameters;
  const QString compare = this->CompareMethod;
  const auto progress = this->Progress;
  const auto cancel = this->CancelFlag;
  this->Watcher->setFuture(QtConcurrent::run([=]() {
    return run_compute(model, controls, domain, parameters, compare, progress, cancel);
  }));
  this->ProgressBar->setValue(0);
  this->ProgressBar->show();
  this->syncPanel();
  this->statusBar()->showMessage("Computing " + QString::fromStdString(this->Parameters.method) +
    " weights...");
  QTimer::singleShot(100, this, &ViewerWindow::onPollProgress);
}

void ViewerWindow::onPollProgress()
{
  if (!this->isComputing())
    return;
  this->ProgressBar->setValue(static_cast<int>(1000.0 * this->Progress->load()));
  QTimer::singleShot(100, this, &ViewerWindow::onPollProgress);
}

void ViewerWindow::cancel()
{
  if (this->isComputing())
  {
    this->CancelFlag->store(true);
    this->statusBar()->showMessage("Cancelling...");
  }
}

bool ViewerWindow::waitForComputation(int timeout_ms)
{
  QElapsedTimer timer;
  timer.start();
  while (this->isComputing())
  {
    if (timer.elapsed() > timeout_ms)
      return false;
    QApplication::processEvents(QEventLoop::AllEvents, 20);
  }
  return true;
}

void ViewerWindow::onComputeDone()
{
  const QFuture<ComputeResult> future = this->Watcher->future();
  if (future.resultCount() == 0)
  {
    this->Busy = false;
    this->ProgressBar->hide();
    this->syncPanel();
    return;
  }
  const ComputeResult result = future.result();
  this->Watcher->setFuture(QFuture<ComputeResult>());
  this->finishCompute(result);
}

void ViewerWindow::finishCompute(const ComputeResult& result)
{
  this->Busy = false;
  this->ProgressBar->hide();
  this->LastSeconds = result.seconds;
  if (!result.error.isEmpty())
  {
    this->syncPanel();
    if (result.cancelled)
      this->statusBar()->showMessage("Computation cancelled.");
    else
      this->reportError("computing " + QString::fromStdString(this->Running.method) +
        " weights failed: " + result.error);
    this->PendingPose = nullptr;
    this->PendingSelection = -1;
    emit computeFinished(false);
    return;
  }
  this->Computed = this->Running;
  this->ComputedCompare = this->RunningCompare;
  this->Weighted = result.weighted;
  this->CompareWeighted = result.compare;
  if (this->PendingPose && this->PendingPose->GetNumberOfPoints() == this->Controls->GetNumberOfPoints())
    this->PosedControls = this->PendingPose;
  else if (!this->PosedControls ||
    this->PosedControls->GetNumberOfPoints() != this->Controls->GetNumberOfPoints())
    this->PosedControls = copy_points(this->Controls->GetPoints());
  this->PendingPose = nullptr;
  if (!this->PendingTwists.empty())
    this->Twists = std::move(this->PendingTwists);
  this->PendingTwists.clear();
  if (!this->Twists.empty() &&
    (this->shownKind() != ControlKind::Skeleton ||
      static_cast<int>(this->Twists.size()) != this->componentCount()))
    this->Twists.clear();
  if (this->PendingSelection >= 0)
    this->Options.component = this->PendingSelection;
  this->PendingSelection = -1;
  this->Options.component = std::clamp(this->Options.component, 0, std::max(0, this->componentCount() - 1));
  this->updateControlList();
  this->syncPanel();
  this->updateDeformation();
  this->updateScene();
  const json stats =
    WeightStatisticsJson(this->Weighted, this->Parameters.weights_name, nullptr, -1.0, 0);
  this->StatsLabel->setText(QString("%1 weights in %2 s: %3 points x %4 controls<br>"
                                    "min %5, max %6, partition of unity error %7<br>"
                                    "mean significant weights per point %8")
                              .arg(QString::fromStdString(this->Computed.method))
                              .arg(result.seconds, 0, 'f', 3)
                              .arg(stats.value("points", 0LL))
                              .arg(stats.value("controls", 0LL))
                              .arg(stats.value("min_weight", 0.0), 0, 'g', 3)
                              .arg(stats.value("max_weight", 0.0), 0, 'g', 3)
                              .arg(stats["partition_of_unity"].value("max_error", 0.0), 0, 'g', 2)
                              .arg(stats["significant"].value("mean_per_point", 0.0), 0, 'g', 3));
  if (this->isLocalityShown())
    this->updateLocality();
  this->statusBar()->showMessage(QString("Computed %1 weights in %2 s.")
                                   .arg(QString::fromStdString(this->Computed.method))
                                   .arg(result.seconds, 0, 'f', 3));
  emit computeFinished(true);
}

// ------------------------------------------------------------------------------------------
// display

void ViewerWindow::selectControl(int component)
{
  const int n = this->componentCount();
  if (n <= 0)
    return;
  component = (component % n + n) % n;
  this->Options.component = component;
  this->syncPanel();
  if (this->shownKind() != ControlKind::Skeleton)
    this->MoveIdBox->setValue(component);
  this->updateScene();
}

void ViewerWindow::showWeight()
{
  this->Options.field = SceneOptions::Field::Weight;
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::showImage()
{
  if (!this->Picture)
  {
    this->reportError("no picture: open a cage and a picture (PNG/JPEG) as the model for the image mode");
    this->syncPanel();
    return;
  }
  this->Options.field = SceneOptions::Field::Image;
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::showGradientNorm()
{
  this->Options.field = SceneOptions::Field::GradientNorm;
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::setLogScale(bool on)
{
  this->Options.log_scale = on;
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::setIsolines(int count)
{
  this->Options.isolines = std::clamp(count, 0, 50);
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::setInfluenceLevel(bool on)
{
  this->Options.influence_level = on;
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::setClipping(bool on)
{
  this->Options.clip = on;
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::setClipAxis(int axis)
{
  this->Options.clip_axis = std::clamp(axis, 0, 2);
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::setClipPosition(double fraction)
{
  this->Options.clip_position = std::clamp(fraction, 0.0, 1.0);
  this->syncPanel();
  this->updateScene();
}

void ViewerWindow::resetCamera()
{
  ResetSceneCamera(this->Renderer, this->Options.dimension);
  this->renderViews();
}

void ViewerWindow::updateScene()
{
  SceneOptions options = this->Options;
  options.controls = this->shownKind();
  options.weights_name = this->Parameters.weights_name;
  options.texture = this->Picture;
  const auto title = [&](const std::string& method) {
    std::string t = method + (options.field == SceneOptions::Field::Weight ? ": weight"
        : options.field == SceneOptions::Field::GradientNorm              ? ": |grad w|"
                                                                          : ": picture");
    if (this->ControlList->currentItem())
      t += " of " + to_std(this->ControlList->currentItem()->text());
    return t;
  };
  try
  {
    options.title = this->Weighted ? title(this->Computed.method) : std::string();
    vtkPointSet* deformed = this->deformedModel();
    this->Info = BuildScene(this->Renderer, this->Weighted,
      this->Weighted && deformed ? deformed->GetPoints() : nullptr, this->Controls,
      this->PosedControls, options);
    if (!this->CompareMethod.isEmpty())
    {
      options.title = this->CompareWeighted ? title(to_std(this->ComputedCompare)) : std::string();
      BuildScene(this->CompareRenderer, this->CompareWeighted,
        this->CompareDeformed ? this->CompareDeformed->GetPoints() : nullptr, this->Controls,
        this->PosedControls, options);
    }
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
  }
  if (this->CameraNeedsReset && (this->Weighted || this->Controls))
  {
    ResetSceneCamera(this->Renderer, this->Options.dimension);
    this->CameraNeedsReset = !this->Weighted;
  }
  this->renderViews();
  emit sceneUpdated();
}

void ViewerWindow::renderViews()
{
  this->SyncingCameras = true;
  this->Renderer->ResetCameraClippingRange();
  this->View->renderWindow()->Render();
  if (this->CompareView->isVisible())
  {
    this->CompareRenderer->ResetCameraClippingRange();
    this->CompareView->renderWindow()->Render();
  }
  this->View->update();
  this->CompareView->update();
  this->SyncingCameras = false;
}

void ViewerWindow::OnCameraModified(vtkObject*, unsigned long, void* client, void*)
{
  auto* self = static_cast<ViewerWindow*>(client);
  if (self->SyncingCameras || !self->CompareView->isVisible())
    return;
  // the cameras are one object; re-render the other view once the interaction step is done
  QTimer::singleShot(0, self, [self]() {
    self->SyncingCameras = true;
    self->CompareRenderer->ResetCameraClippingRange();
    self->CompareView->renderWindow()->Render();
    self->CompareView->update();
    self->SyncingCameras = false;
  });
}

// ------------------------------------------------------------------------------------------
// deformation

vtkPointSet* ViewerWindow::deformedModel() const
{
  if (this->Deformed)
    return this->Deformed;
  return vtkPointSet::SafeDownCast(this->Weighted ? this->Weighted.Get() : this->Model.Get());
}

void ViewerWindow::updateDeformation()
{
  this->Deformed = nullptr;
  this->CompareDeformed = nullptr;
  if (!this->Weighted || !this->PosedControls)
    return;
  bool moved = false;
  for (vtkIdType i = 0; i < this->PosedControls->GetNumberOfPoints() && !moved; ++i)
  {
    double a[3], b[3];
    this->PosedControls->GetPoint(i, a);
    this->Controls->GetPoint(i, b);
    moved = a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
  }
  for (const HandleTwist& t : this->Twists)
    moved = moved || !t.IsIdentity();
  if (!moved)
    return;
  try
  {
    const auto deform = [this](vtkDataSet* weighted, const std::string& method) {
      WeightsParameters p = this->Computed;
      p.method = method;
      vtkPointSet* model = vtkPointSet::SafeDownCast(weighted);
      if (this->shownKind() == ControlKind::Skeleton)
      {
        const std::vector<Eigen::MatrixXd> pose = this->skeletonTransforms();
        return Skin(model, pose, p);
      }
      vtkNew<vtkPolyData> posed;
      posed->ShallowCopy(this->Controls);
      posed->SetPoints(this->PosedControls);
      return Deform(model, this->Controls, posed, p);
    };
    this->Deformed = deform(this->Weighted, this->Computed.method);
    if (this->CompareWeighted)
      this->CompareDeformed = deform(this->CompareWeighted, to_std(this->ComputedCompare));
  }
  catch (const std::exception& e)
  {
    this->Deformed = nullptr;
    this->CompareDeformed = nullptr;
    this->reportError("deformation failed: " + QString::fromStdString(e.what()));
  }
}

std::vector<Eigen::MatrixXd> ViewerWindow::skeletonTransforms() const
{
  const int dim = this->modelDimension();
  const bary::Skeleton s = vtkBaryConversion::ToSkeleton(this->Controls, dim);
  const Eigen::MatrixXd posed = vtkBaryConversion::ToMatrix(this->PosedControls, dim);
  std::vector<Eigen::MatrixXd> pose;
  int handle = 0;
  for (Eigen::MatrixXd T : bary::transforms_from_joints(s, posed))
  {
    if (dim == 2)
    { // lift [A | t] (2 x 3) to 3 x 4, as the command line does
      Eigen::MatrixXd L = Eigen::MatrixXd::Zero(3, 4);
      L.topLeftCorner(2, 2) = T.leftCols(2);
      L.block(0, 3, 2, 1) = T.col(2);
      L(2, 2) = 1.0;
      T = L;
    }
    const HandleTwist twist = this->handleTwist(handle);
    if (!twist.IsIdentity())
    {
      // centre and axis at the current pose: a point handle's joint, a bone's first joint
      const bool bone = handle >= s.P.size();
      const int joint = bone ? s.BE(handle - s.P.size(), 0) : s.P(handle);
      Eigen::Vector3d c = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
      c.head(dim) = posed.row(joint).transpose();
      if (dim == 3 && bone)
      {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d.head(3) = (posed.row(s.BE(handle - s.P.size(), 1)) - posed.row(joint)).transpose();
        if (d.norm() > 0.0)
          axis = d.normalized();
      }
      const double pi = 3.14159265358979323846;
      const Eigen::Matrix3d M = twist.scale *
        Eigen::AngleAxisd(twist.angle_degrees * pi / 180.0, axis).toRotationMatrix();
      Eigen::MatrixXd U(3, 4);
      U.leftCols(3) = M * T.leftCols(3);
      U.col(3) = M * T.col(3) + c - M * c;
      if (dim == 2)
        U.row(2) << 0.0, 0.0, 1.0, 0.0; // stays in the plane
      T = U;
    }
    pose.push_back(T);
    ++handle;
  }
  return pose;
}

HandleTwist ViewerWindow::handleTwist(int handle) const
{
  if (handle < 0 || handle >= static_cast<int>(this->Twists.size()))
    return {};
  return this->Twists[static_cast<std::size_t>(handle)];
}

bool ViewerWindow::setHandleTwist(int handle, double angle_degrees, double scale)
{
  if (!this->Weighted || this->shownKind() != ControlKind::Skeleton)
  {
    this->reportError("rotating / scaling a handle needs BBW weights of a skeleton (compute bbw "
                      "with a .tgf skeleton first); move cage and control points instead");
    return false;
  }
  const int n = this->componentCount();
  if (handle < 0 || handle >= n)
  {
    this->reportError(QString("handle %1 does not exist (the skeleton has %2 handles)").arg(handle).arg(n));
    return false;
  }
  if (!(scale > 0.0) || !std::isfinite(scale) || !std::isfinite(angle_degrees))
  {
    this->reportError(QString("the scale of a handle must be a number > 0 and the angle finite "
                              "(got %1, %2)").arg(scale).arg(angle_degrees));
    return false;
  }
  this->pushUndo();
  this->Twists.resize(static_cast<std::size_t>(n));
  this->Twists[static_cast<std::size_t>(handle)] = { angle_degrees, scale };
  this->updateDeformation();
  this->updateScene();
  this->statusBar()->showMessage(QString("Handle %1 rotated by %2 deg, scaled by %3.")
                                   .arg(handle).arg(angle_degrees).arg(scale));
  return true;
}

void ViewerWindow::pushUndo()
{
  if (this->PosedControls)
    this->UndoStack.push_back({ copy_points(this->PosedControls), this->Twists });
}

void ViewerWindow::moveControlLive(int id, const double x[3])
{
  this->PosedControls->SetPoint(id, x);
  this->PosedControls->Modified();
  this->updateDeformation();
  this->updateScene();
}

void ViewerWindow::setControlPosition(int id, double x, double y, double z)
{
  if (!this->PosedControls || id < 0 || id >= this->PosedControls->GetNumberOfPoints())
  {
    this->reportError(QString("control %1 does not exist").arg(id));
    return;
  }
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
  {
    this->reportError("control positions must be finite numbers");
    return;
  }
  this->pushUndo();
  const double p[3] = { x, y, z };
  this->moveControlLive(id, p);
  this->MoveIdBox->setValue(id);
  for (int k = 0; k < 3; ++k)
    this->MoveBox[k]->setValue(p[k]);
}

void ViewerWindow::resetPose()
{
  if (!this->Controls)
    return;
  this->pushUndo();
  this->PosedControls = copy_points(this->Controls->GetPoints());
  this->Twists.clear();
  this->updateDeformation();
  this->updateScene();
}

void ViewerWindow::undo()
{
  if (this->UndoStack.empty())
  {
    this->statusBar()->showMessage("Nothing to undo.");
    return;
  }
  this->PosedControls = this->UndoStack.back().points;
  this->Twists = this->UndoStack.back().twists;
  this->UndoStack.pop_back();
  this->updateDeformation();
  this->updateScene();
}

bool ViewerWindow::loadPose(const QString& path)
{
  if (!this->Controls)
  {
    this->reportError("open inputs before a pose");
    return false;
  }
  try
  {
    vtkSmartPointer<vtkPoints> posed;
    const QString ext = QFileInfo(path).suffix().toLower();
    if (this->shownKind() == ControlKind::Skeleton && (ext == "txt" || ext == "dmat"))
    {
      const bary::Skeleton s = vtkBaryConversion::ToSkeleton(this->Controls, this->modelDimension());
      const auto pose = vtkBaryDataIO::ReadPose(to_std(path), s.handle_count(), &s);
      posed = copy_points(PoseHandles(this->Controls, pose)->GetPoints());
    }
    else
    {
      auto data = vtkBaryDataIO::Read(to_std(path));
      auto* set = vtkPointSet::SafeDownCast(data);
      if (!set || set->GetNumberOfPoints() != this->Controls->GetNumberOfPoints())
        throw bary::Error(bary::ErrorCode::SizeMismatch,
          "the pose '" + to_std(path) + "' must hold the " +
            std::to_string(this->Controls->GetNumberOfPoints()) + " controls, moved (same order)");
      posed = copy_points(set->GetPoints());
    }
    this->pushUndo();
    this->PosedControls = posed;
    this->updateDeformation();
    this->updateScene();
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  return true;
}

bool ViewerWindow::applyExamplePose()
{
  if (this->In.pose.isEmpty())
  {
    this->reportError("these inputs have no bundled pose: use File > Load pose");
    return false;
  }
  return this->loadPose(this->In.pose);
}

bool ViewerWindow::savePose(const QString& path)
{
  if (!this->Controls || !this->PosedControls)
  {
    this->reportError("no pose to save: open inputs first");
    return false;
  }
  try
  {
    if (this->Weighted && this->shownKind() == ControlKind::Skeleton &&
      QFileInfo(path).suffix().toLower() == "txt")
    {
      // BBW: the per-handle transforms (joints and rotations / scales), BaryLab pose text that
      // `barylab deform --transforms` and File > Load pose read
      const int dim = this->modelDimension();
      std::ofstream out(to_std(path));
      out.precision(17);
      out << "# BaryLab pose: one affine transform per handle (weights column order), "
          << (dim == 2 ? "a00 a01 t0 a10 a11 t1" : "a00 a01 a02 t0 a10 a11 a12 t1 a20 a21 a22 t2")
          << "\n";
      for (const Eigen::MatrixXd& T : this->skeletonTransforms())
      {
        for (int r = 0; r < dim; ++r)
        {
          for (int c = 0; c < dim; ++c)
            out << T(r, c) << ' ';
          out << T(r, 3) << (r + 1 < dim ? ' ' : '\n');
        }
      }
      if (!out)
        throw bary::Error(bary::ErrorCode::Io, "cannot write '" + to_std(path) + "'");
    }
    else
    {
      if (!this->Twists.empty())
        for (const HandleTwist& t : this->Twists)
          if (!t.IsIdentity())
            throw bary::Error(bary::ErrorCode::InvalidArgument,
              "handles are rotated / scaled: save the pose as transforms (a .txt file), posed "
              "joints cannot hold rotations");
      vtkNew<vtkPolyData> posed;
      posed->DeepCopy(this->Controls);
      posed->SetPoints(copy_points(this->PosedControls));
      vtkBaryDataIO::Write(posed, to_std(path));
    }
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->statusBar()->showMessage("Saved the pose to " + path);
  return true;
}

bool ViewerWindow::saveDeformedModel(const QString& path)
{
  vtkPointSet* deformed = this->deformedModel();
  if (!deformed || !this->Weighted)
  {
    this->reportError("nothing to save: compute the weights first");
    return false;
  }
  try
  {
    vtkBaryDataIO::Write(deformed, to_std(path));
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->statusBar()->showMessage("Saved the deformed model to " + path);
  return true;
}

// ------------------------------------------------------------------------------------------
// picking and dragging control points in the view

int ViewerWindow::pickControl(int x, int y) const
{
  if (!this->PosedControls)
    return -1;
  int best = -1;
  double bestD2 = 12.0 * 12.0; // pixels
  for (vtkIdType i = 0; i < this->PosedControls->GetNumberOfPoints(); ++i)
  {
    double p[3];
    this->PosedControls->GetPoint(i, p);
    this->Renderer->SetWorldPoint(p[0], p[1], p[2], 1.0);
    this->Renderer->WorldToDisplay();
    const double* d = this->Renderer->GetDisplayPoint();
    const double d2 = (d[0] - x) * (d[0] - x) + (d[1] - y) * (d[1] - y);
    if (d2 < bestD2)
    {
      bestD2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

void ViewerWindow::OnInteractorEvent(vtkObject* caller, unsigned long event, void* client, void*)
{
  auto* self = static_cast<ViewerWindow*>(client);
  auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
  int pos[2];
  interactor->GetEventPosition(pos);
  if (event == vtkCommand::LeftButtonPressEvent)
  {
    const int id = self->pickControl(pos[0], pos[1]);
    if (id < 0)
      return; // the camera moves
    self->InteractorCallback->AbortFlagOn();
    if (self->shownKind() != ControlKind::Skeleton && id < self->componentCount())
      self->selectControl(id);
    if (!self->Weighted)
      return;
    self->pushUndo();
    self->Dragging = id;
    self->MoveIdBox->setValue(id);
  }
  else if (event == vtkCommand::MouseMoveEvent && self->Dragging >= 0)
  {
    self->InteractorCallback->AbortFlagOn();
    double p[3];
    self->PosedControls->GetPoint(self->Dragging, p);
    double display[3];
    vtkInteractorObserver::ComputeWorldToDisplay(self->Renderer, p[0], p[1], p[2], display);
    double world[4];
    vtkInteractorObserver::ComputeDisplayToWorld(self->Renderer, pos[0], pos[1], display[2], world);
    if (self->Options.dimension == 2)
      world[2] = p[2];
    self->moveControlLive(self->Dragging, world);
  }
  else if (event == vtkCommand::LeftButtonReleaseEvent && self->Dragging >= 0)
  {
    self->InteractorCallback->AbortFlagOn();
    double p[3];
    self->PosedControls->GetPoint(self->Dragging, p);
    for (int k = 0; k < 3; ++k)
      self->MoveBox[k]->setValue(p[k]);
    self->Dragging = -1;
  }
}

// ------------------------------------------------------------------------------------------
// sessions, screenshots, command line

bool ViewerWindow::saveSession(const QString& path)
{
  try
  {
    json s;
    s["barylab_viewer_session"] = 1;
    s["inputs"] = { { "controls", to_std(this->In.controls) }, { "model", to_std(this->In.model) },
      { "domain", to_std(this->In.domain) }, { "example", to_std(this->In.example) },
      { "pose_file", to_std(this->In.pose) } };
    s["parameters"] = ParametersToJson(this->Parameters);
    s["compare_method"] = to_std(this->CompareMethod);
    s["selected"] = this->Options.component;
    s["view"] = { { "field", this->Options.field == SceneOptions::Field::Weight ? "weight"
          : this->Options.field == SceneOptions::Field::GradientNorm            ? "gradient_norm"
                                                                                : "image" },
      { "log_scale", this->Options.log_scale }, { "isolines", this->Options.isolines },
      { "influence_level", this->Options.influence_level }, { "clip", this->Options.clip },
      { "clip_axis", this->Options.clip_axis }, { "clip_position", this->Options.clip_position } };
    json pose = json::array();
    if (this->PosedControls)
      for (vtkIdType i = 0; i < this->PosedControls->GetNumberOfPoints(); ++i)
      {
        double p[3];
        this->PosedControls->GetPoint(i, p);
        pose.push_back({ p[0], p[1], p[2] });
      }
    s["pose"] = pose;
    json twists = json::array();
    for (const HandleTwist& t : this->Twists)
      twists.push_back({ t.angle_degrees, t.scale });
    s["handle_twists"] = twists;
    WriteJson(s, to_std(path));
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->statusBar()->showMessage("Saved the session to " + path);
  return true;
}

bool ViewerWindow::loadSession(const QString& path)
{
  json s;
  Inputs in;
  WeightsParameters parameters;
  SceneOptions options = this->Options;
  vtkSmartPointer<vtkPoints> pose;
  std::vector<HandleTwist> twists;
  try
  {
    std::ifstream file(to_std(path));
    if (!file)
      throw bary::Error(bary::ErrorCode::Io, "cannot open the session '" + to_std(path) + "'");
    try
    {
      file >> s;
    }
    catch (const json::exception& e)
    {
      throw bary::Error(bary::ErrorCode::Io,
        "the session '" + to_std(path) + "' is not valid JSON: " + e.what());
    }
    if (!s.is_object() || !s.contains("barylab_viewer_session"))
      throw bary::Error(bary::ErrorCode::Io, "'" + to_std(path) + "' is not a BaryLab viewer session");
    const json& i = s.at("inputs");
    in.controls = QString::fromStdString(i.value("controls", ""));
    in.model = QString::fromStdString(i.value("model", ""));
    in.domain = QString::fromStdString(i.value("domain", ""));
    in.example = QString::fromStdString(i.value("example", ""));
    in.pose = QString::fromStdString(i.value("pose_file", ""));
    parameters = ParametersFromJson(s.value("parameters", json::object()));
    const json v = s.value("view", json::object());
    const std::string field = v.value("field", "weight");
    options.field = field == "image" ? SceneOptions::Field::Image
      : field == "weight"            ? SceneOptions::Field::Weight
                                     : SceneOptions::Field::GradientNorm;
    options.log_scale = v.value("log_scale", false);
    options.isolines = v.value("isolines", 9);
    options.influence_level = v.value("influence_level", true);
    options.clip_axis = v.value("clip_axis", 0);
    options.clip_position = v.value("clip_position", 0.5);
    if (s.contains("pose") && s["pose"].is_array() && !s["pose"].empty())
    {
      pose = vtkSmartPointer<vtkPoints>::New();
      pose->SetDataTypeToDouble();
      for (const json& p : s["pose"])
        pose->InsertNextPoint(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
    }
    if (s.contains("handle_twists") && s["handle_twists"].is_array())
      for (const json& t : s["handle_twists"])
        twists.push_back({ t.at(0).get<double>(), t.at(1).get<double>() });
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->Parameters = parameters;
  this->CompareMethod = QString::fromStdString(s.value("compare_method", ""));
  this->CompareView->setVisible(!this->CompareMethod.isEmpty());
  if (!this->openInputs(in))
    return false;
  const bool clip = s.value("view", json::object()).value("clip", false);
  options.component = 0;
  this->Options = options;
  this->Options.texture = this->Picture;
  if (this->Options.field == SceneOptions::Field::Image && !this->Picture)
    this->Options.field = SceneOptions::Field::Weight;
  this->Options.dimension = this->modelDimension();
  this->Options.clip = clip;
  this->PendingPose = pose;
  this->PendingTwists = twists;
  this->PendingSelection = s.value("selected", 0);
  this->syncPanel();
  this->compute();
  return true;
}

bool ViewerWindow::saveScreenshot(const QString& path)
{
  this->renderViews();
  QApplication::processEvents();
  const QImage image = this->grab().toImage();
  if (image.isNull() || !image.save(path, "PNG"))
  {
    this->reportError("cannot write the screenshot '" + path + "'");
    return false;
  }
  this->statusBar()->showMessage("Saved " + path);
  return true;
}

QString ViewerWindow::commandLine() const
{
  if (!this->Controls)
    return QString();
  QStringList args = { "barylab", "weights" };
  for (const std::string& f : CommandLineFlags(this->Parameters))
    args << quoted(QString::fromStdString(f));
  const ControlKind kind = this->controlKind();
  if (kind == ControlKind::Skeleton)
    args << "--handles" << quoted(this->In.controls) << "--mesh" << quoted(this->In.domain);
  else if (kind == ControlKind::FreePoints)
    args << "--control-points" << quoted(this->In.controls);
  else
    args << "--cage" << quoted(this->In.controls);
  args << "--points" << quoted(this->In.model) << "--output" << "weights.vtp"
       << "--json" << "weights.json";
  return args.join(' ');
}

void ViewerWindow::showCommandLine()
{
  const QString line = this->commandLine();
  if (line.isEmpty())
  {
    this->reportError("open inputs first: there is no command line to show");
    return;
  }
  if (!this->Interactive)
  {
    this->statusBar()->showMessage(line);
    return;
  }
  QDialog dialog(this);
  dialog.setWindowTitle("Run in terminal");
  auto* layout = new QVBoxLayout(&dialog);
  layout->addWidget(new QLabel("The same weights from the command line:"));
  auto* text = new QPlainTextEdit(line);
  text->setReadOnly(true);
  layout->addWidget(text);
  auto* close = new QPushButton("Close");
  connect(close, &QPushButton::clicked, &dialog, &QDialog::accept);
  layout->addWidget(close);
  dialog.resize(700, 160);
  dialog.exec();
}

// ------------------------------------------------------------------------------------------
// file dialogs

void ViewerWindow::openFilesDialog()
{
  const QString filter = "Geometry (*.obj *.off *.vtp *.vtu *.vtk *.stl *.ply *.mesh *.tgf);;All files (*)";
  const QString controls = QFileDialog::getOpenFileName(this,
    "Controls: cage, skeleton (.tgf) or control points", QString(), filter);
  if (controls.isEmpty())
    return;
  const QString model = QFileDialog::getOpenFileName(this, "Model (points to compute weights at)",
    QFileInfo(controls).path(), filter);
  if (model.isEmpty())
    return;
  QStringList files = { controls, model };
  if (is_skeleton_file(controls))
  {
    const QString domain = QFileDialog::getOpenFileName(this,
      "Domain to mesh (polygon, closed surface or .mesh)", QFileInfo(controls).path(), filter);
    if (domain.isEmpty())
      return;
    files << domain;
  }
  this->openFiles(files);
}

void ViewerWindow::openSessionDialog()
{
  const QString path = QFileDialog::getOpenFileName(this, "Load session", QString(),
    "BaryLab viewer session (*.json)");
  if (!path.isEmpty())
    this->loadSession(path);
}

void ViewerWindow::saveSessionDialog()
{
  const QString path = QFileDialog::getSaveFileName(this, "Save session", "session.json",
    "BaryLab viewer session (*.json)");
  if (!path.isEmpty())
    this->saveSession(path);
}

void ViewerWindow::loadPoseDialog()
{
  const QString path = QFileDialog::getOpenFileName(this, "Load pose", QString(),
    "Posed cage / control points / BBW transforms (*.obj *.off *.vtp *.vtk *.txt *.dmat);;All files (*)");
  if (!path.isEmpty())
    this->loadPose(path);
}

void ViewerWindow::savePoseDialog()
{
  const QString path = QFileDialog::getSaveFileName(this, "Save pose", "pose.obj",
    "Posed controls (*.obj *.vtp *.vtk)");
  if (!path.isEmpty())
    this->savePose(path);
}

void ViewerWindow::saveDeformedDialog()
{
  const QString path = QFileDialog::getSaveFileName(this, "Save deformed model", "deformed.vtp",
    "Model (*.vtp *.vtu *.vtk *.obj *.stl *.ply *.off)");
  if (!path.isEmpty())
    this->saveDeformedModel(path);
}

const json& ViewerWindow::localityStatistics() const
{
  return this->Locality->statistics();
}

bool ViewerWindow::isLocalityShown() const
{
  return this->LocalityDock && this->LocalityDock->isVisible();
}

void ViewerWindow::updateLocality()
{
  json all = json::array();
  try
  {
    const std::pair<vtkDataSet*, std::string> shown[] = {
      { this->Weighted, this->Computed.method },
      { this->CompareWeighted, to_std(this->ComputedCompare) } };
    for (const auto& [data, method] : shown)
      if (data)
      {
        json s = LocalityStatisticsJson(data, this->Computed.weights_name);
        s["method"] = method;
        all.push_back(std::move(s));
      }
  }
  catch (const std::exception& e)
  {
    this->reportError(QString("locality statistics: ") + e.what());
    all = json::array();
  }
  this->Locality->setStatistics(all);
}

void ViewerWindow::showLocality(bool on)
{
  if (on)
  {
    this->LocalityDock->show();
    this->updateLocality(); // also when it was visible already
  }
  else
    this->LocalityDock->hide();
}

bool ViewerWindow::exportLocalityCsv(const QString& prefix)
{
  try
  {
    this->updateLocality();
    this->Locality->writeCsv(to_std(prefix));
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->statusBar()->showMessage("Wrote " + prefix + "_P.csv and " + prefix + "_Q.csv");
  return true;
}

bool ViewerWindow::exportLocalityPng(const QString& path)
{
  try
  {
    this->updateLocality();
    if (this->Locality->statistics().empty())
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "no locality statistics to export: compute weights first");
    this->Locality->writePng(to_std(path));
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->statusBar()->showMessage("Wrote " + path);
  return true;
}

void ViewerWindow::exportLocalityDialog()
{
  const QString path = QFileDialog::getSaveFileName(this, "Export locality statistics",
    "locality.png", "PNG chart and CSV tables (*.png)");
  if (path.isEmpty())
    return;
  QString prefix = path;
  if (prefix.endsWith(".png", Qt::CaseInsensitive))
    prefix.chop(4);
  if (this->exportLocalityPng(prefix + ".png"))
    this->exportLocalityCsv(prefix);
}

void ViewerWindow::saveScreenshotDialog()
{
  const QString path = QFileDialog::getSaveFileName(this, "Save screenshot", "barylab.png", "PNG (*.png)");
  if (!path.isEmpty())
    this->saveScreenshot(path);
}

} // namespace viewer
} // namespace barylab
