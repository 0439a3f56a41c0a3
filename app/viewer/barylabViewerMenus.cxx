#include "barylabViewerMenus.h"

#include "barylabViewerExamples.h"
#include "barylabViewerMode.h"
#include "barylabViewerSession.h"
#include "barylabViewerSplineMode.h"
#include "barylabViewerSurfaceMode.h"
#include "barylabViewerWindow.h"

#include <QDialog>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QDir>
#include <QMessageBox>
#include <QInputDialog>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QVBoxLayout>

namespace barylab
{
namespace viewer
{
namespace
{
enum class Ask
{
  Open,
  Save
};

/// Asks for a file to open or to save to; hands a chosen path to @p use.
template <class Use>
void ask_path(ViewerWindow& window, Ask ask, const QString& title, const QString& name,
  const QString& filter, Use&& use)
{
  const QString path = ask == Ask::Open
    ? QFileDialog::getOpenFileName(&window, title, name, filter)
    : QFileDialog::getSaveFileName(&window, title, name, filter);
  if (!path.isEmpty())
    use(path);
}
} // namespace

void BuildMenus(ViewerWindow& window)
{
  ViewerWindow* w = &window;
  QMenu* file = w->menuBar()->addMenu("&File");
  file->addAction("&Open cage and model...", w, [w]() { OpenFilesDialog(*w); }, QKeySequence::Open);
  QMenu* examples = file->addMenu("Open &example");
  for (const QString& name : ExampleNames())
    examples->addAction(name, w, [w, name]() { w->loadExample(name); });
  file->addAction("Open &label map (organ: surface and cage)...", w, [w]() { OpenLabelMapDialog(*w); });
  file->addAction("Weighted averages on a &surface...", w, []() {
    // the surface mode: a window of its own, with the torus example
    auto* surface = new SurfaceWindow;
    surface->setAttribute(Qt::WA_DeleteOnClose);
    surface->resize(1400, 800);
    surface->show();
    surface->loadExample(SurfaceWindow::ExampleNames().front());
  });
  file->addAction("C1 s&pline deformations (editor)...", w, []() {
    // the spline mode: a window of its own, with the organism example
    auto* spline = new SplineWindow;
    spline->setAttribute(Qt::WA_DeleteOnClose);
    spline->resize(1400, 800);
    spline->show();
    spline->loadExample(SplineWindow::ExampleNames().front());
  });
  file->addSeparator();
  file->addAction("&Load session...", w, [w]() { LoadSessionDialog(*w); }, QKeySequence("Ctrl+L"));
  file->addAction("&Save session...", w, [w]() { SaveSessionDialog(*w); }, QKeySequence::Save);
  file->addSeparator();
  file->addAction("Load &pose...", w, [w]() { LoadPoseDialog(*w); });
  file->addAction("Apply the example's pose", w, &ViewerWindow::applyExamplePose, QKeySequence("Ctrl+P"));
  file->addAction("Save p&ose...", w, [w]() { SavePoseDialog(*w); });
  file->addAction("Save &deformed model...", w, [w]() { SaveDeformedDialog(*w); }, QKeySequence("Ctrl+D"));
  file->addAction("Save &transform (displacement field)...", w, [w]() { SaveTransformDialog(*w); });
  file->addAction("Save &warped label map...", w, [w]() { SaveWarpedLabelMapDialog(*w); });
  file->addAction("Save screens&hot...", w, [w]() { SaveScreenshotDialog(*w); }, QKeySequence("Ctrl+Shift+S"));
  file->addAction("&Export locality statistics (PNG, CSV)...", w, [w]() { ExportLocalityDialog(*w); });
  file->addSeparator();
  file->addAction("&Quit", w, &QWidget::close, QKeySequence::Quit);
  QMenu* edit = w->menuBar()->addMenu("&Edit");
  edit->addAction("&Undo move", w, &ViewerWindow::undo, QKeySequence::Undo);
  edit->addAction("&Reset pose", w, &ViewerWindow::resetPose, QKeySequence("Ctrl+Shift+R"));
  for (const Mode* mode : Modes())
    mode->addActions(edit, window);
  QMenu* compute = w->menuBar()->addMenu("&Compute");
  compute->addAction("&Compute weights", w, &ViewerWindow::compute, QKeySequence("F5"));
  compute->addAction("C&ancel", w, &ViewerWindow::cancel, QKeySequence("Ctrl+."));
  compute->addAction("Make a ca&ge around the model...", w, [w]() { MakeCageDialog(*w); });
  compute->addAction("&Run in terminal...", w, &ViewerWindow::showCommandLine, QKeySequence("Ctrl+T"));
  QMenu* view = w->menuBar()->addMenu("&View");
  view->addAction("&Weight", w, &ViewerWindow::showWeight, QKeySequence("W"));
  view->addAction("&Gradient norm", w, &ViewerWindow::showGradientNorm, QKeySequence("G"));
  view->addAction("&Logarithmic scale", w, [w]() { w->setLogScale(!w->sceneOptions().log_scale); },
    QKeySequence("L"));
  view->addAction("&Clipping", w, [w]() { w->setClipping(!w->sceneOptions().clip); },
    QKeySequence("C"));
  view->addAction("Next control", w, [w]() { w->selectControl(w->selectedControl() + 1); },
    QKeySequence("N"));
  view->addAction("Previous control", w, [w]() { w->selectControl(w->selectedControl() - 1); },
    QKeySequence("P"));
  view->addAction("Reset &camera", w, &ViewerWindow::resetCamera, QKeySequence("Ctrl+R"));
  view->addAction("Locality &statistics (P, Q)", w,
    [w]() { w->showLocality(!w->isLocalityShown()); }, QKeySequence("S"));
}

void OpenFilesDialog(ViewerWindow& window)
{
  const QString filter = "Geometry (*.obj *.off *.vtp *.vtu *.vtk *.stl *.ply *.mesh *.tgf "
                         "*.mrk.json *.fcsv);;All files (*)";
  const QString controls = QFileDialog::getOpenFileName(&window,
    "Controls: cage, skeleton (.tgf) or control points", QString(), filter);
  if (controls.isEmpty())
    return;
  const QString model = QFileDialog::getOpenFileName(&window, "Model (points to compute weights at)",
    QFileInfo(controls).path(), filter);
  if (model.isEmpty())
    return;
  QStringList files = { controls, model };
  if (IsSkeletonFile(controls))
  {
    const QString domain = QFileDialog::getOpenFileName(&window,
      "Domain to mesh (polygon, closed surface or .mesh)", QFileInfo(controls).path(), filter);
    if (domain.isEmpty())
      return;
    files << domain;
  }
  window.openFiles(files);
}

void LoadSessionDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Open, "Load session", QString(), "BaryLab viewer session (*.json)",
    [&](const QString& path) { window.loadSession(path); });
}

void SaveSessionDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Save session", "session.json", "BaryLab viewer session (*.json)",
    [&](const QString& path) { window.saveSession(path); });
}

void LoadPoseDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Open, "Load pose", QString(),
    "Posed cage / control points / BBW transforms (*.obj *.off *.vtp *.vtk *.txt *.dmat);;All files (*)",
    [&](const QString& path) { window.loadPose(path); });
}

void SavePoseDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Save pose", "pose.obj", "Posed controls (*.obj *.vtp *.vtk)",
    [&](const QString& path) { window.savePose(path); });
}

void SaveDeformedDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Save deformed model", "deformed.vtp",
    "Model (*.vtp *.vtu *.vtk *.obj *.stl *.ply *.off)",
    [&](const QString& path) { window.saveDeformedModel(path); });
}

void OpenLabelMapDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Open, "Open label map", "",
    "Label map (*.nii *.nii.gz *.nrrd *.nhdr *.mha *.mhd)", [&](const QString& path) {
      bool ok = false;
      const int label = QInputDialog::getInt(&window, "Open label map",
        "Label of the organ (0: the image's only label):", 1, 0, 1000000, 1, &ok);
      if (!ok)
        return;
      const int vertices = QInputDialog::getInt(&window, "Open label map",
        "Vertices of the cage made around it:", 60, 4, 100000, 1, &ok);
      if (ok)
        window.openLabelMap(path, label, vertices);
    });
}

void MakeCageDialog(ViewerWindow& window)
{
  bool ok = false;
  const int vertices = QInputDialog::getInt(&window, "Make a cage",
    "Vertices of the cage made around the model:", 60, 3, 100000, 1, &ok);
  if (ok)
    window.makeCage(vertices);
}

void SaveTransformDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Save transform (displacement field, LPS)", "transform.nii.gz",
    "Displacement field (*.nii.gz *.nii *.nrrd *.mha *.mhd)", [&](const QString& path) {
      const auto answer = QMessageBox::question(&window, "Save transform",
        "Also write the inverse field (what ITK and 3D Slicer need to resample an image into the "
        "deformed space) beside it, as *_inverse?");
      QString inverse;
      if (answer == QMessageBox::Yes)
      {
        const QFileInfo info(path);
        const QString name = info.fileName();
        const int dot = name.indexOf('.');
        inverse = info.dir().filePath(
          (dot > 0 ? name.left(dot) : name) + "_inverse" + (dot > 0 ? name.mid(dot) : QString()));
      }
      window.saveTransform(path, inverse);
    });
}

void SaveWarpedLabelMapDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Save warped label map", "warped.nii.gz",
    "Label map (*.nii.gz *.nii *.nrrd *.mha *.mhd)",
    [&](const QString& path) { window.saveWarpedLabelMap(path); });
}

void SaveScreenshotDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Save screenshot", "barylab.png", "PNG (*.png)",
    [&](const QString& path) { window.saveScreenshot(path); });
}

void ExportLocalityDialog(ViewerWindow& window)
{
  ask_path(window, Ask::Save, "Export locality statistics", "locality.png",
    "PNG chart and CSV tables (*.png)", [&](const QString& path) {
      QString prefix = path;
      if (prefix.endsWith(".png", Qt::CaseInsensitive))
        prefix.chop(4);
      if (window.exportLocalityPng(prefix + ".png"))
        window.exportLocalityCsv(prefix);
    });
}

void ShowCommandLineDialog(QWidget* parent, const QString& line)
{
  QDialog dialog(parent);
  dialog.setWindowTitle("Run in terminal");
  auto* layout = new QVBoxLayout(&dialog);
  layout->addWidget(new QLabel("The same weights from the command line:"));
  auto* text = new QPlainTextEdit(line);
  text->setReadOnly(true);
  layout->addWidget(text);
  auto* close = new QPushButton("Close");
  QObject::connect(close, &QPushButton::clicked, &dialog, &QDialog::accept);
  layout->addWidget(close);
  dialog.resize(700, 160);
  dialog.exec();
}

} // namespace viewer
} // namespace barylab
