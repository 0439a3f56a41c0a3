// barylab-viewer's spline mode (SplineWindow) driven through its public slots and through
// synthetic mouse events on its view's interactor, as a person drives it (QTest under Xvfb;
// errors go to a list, no modal dialogs). The regression image is compared with
// testing/baselines/viewer_spline_organism.png (vtkTesting, threshold 10); a missing baseline
// fails and leaves the image in BARYLAB_TEST_OUTPUT_DIR/images.

#include "barylabViewerSplineMode.h"
#include "barylabViewerWindow.h"

#include "vtkBaryDataIO.h"
#include "vtkBarySplineData.h"
#include "vtkBarySplineSource.h"
#include "core/spline/decles.h"
#include "core/spline/triangular_spline.h"

#include <QApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QFile>
#include <QFileInfo>
#include <QImage>
#include <QAction>
#include <QLabel>
#include <QMenuBar>
#include <QProcess>
#include <QSurfaceFormat>
#include <QTest>

#include <QVTKOpenGLNativeWidget.h>

#include "vtkCamera.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPropCollection.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkTesting.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <memory>

using barylab::viewer::SplineTarget;
using barylab::viewer::SplineWindow;
using barylab::viewer::ViewerWindow;

namespace
{
QString data(const char* name)
{
  return QString(BARYLAB_DATA_DIR) + "/" + name;
}

QString output(const QString& name)
{
  const QString dir = QString(BARYLAB_TEST_OUTPUT_DIR) + "/viewer";
  QDir().mkpath(dir);
  return dir + "/" + name;
}

/// C1 condition residual relative to the grid size.
double c1_residual(const bary::TriangularSpline& s)
{
  return s.continuity().max_condition_residual / s.net().mean_edge_length();
}

/// The largest |z| change of the model's points.
double max_z_change(vtkPolyData* a, vtkPolyData* b)
{
  double worst = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
    worst = std::max(worst, std::abs(a->GetPoint(i)[2] - b->GetPoint(i)[2]));
  return worst;
}
} // namespace

class SplineViewerTest : public QObject
{
  Q_OBJECT
  std::unique_ptr<SplineWindow> s;

  /// Display coordinates (rounded) of world point (x, y, 0).
  void toDisplay(double x, double y, int d[2]) const
  {
    vtkRenderer* r = s->renderer();
    r->SetWorldPoint(x, y, 0.0, 1.0);
    r->WorldToDisplay();
    double p[3];
    r->GetDisplayPoint(p);
    d[0] = static_cast<int>(std::lround(p[0]));
    d[1] = static_cast<int>(std::lround(p[1]));
  }
  void toWorld(int x, int y, double w[2]) const
  {
    vtkRenderer* r = s->renderer();
    r->SetDisplayPoint(x, y, 0.0);
    r->DisplayToWorld();
    double p[4];
    r->GetWorldPoint(p);
    w[0] = p[0] / p[3];
    w[1] = p[1] / p[3];
  }
  /// World size of one pixel.
  double pixel() const
  {
    return 2.0 * s->renderer()->GetActiveCamera()->GetParallelScale() /
      s->renderer()->GetSize()[1];
  }
  void event(unsigned long id, int x, int y, bool ctrl = false)
  {
    vtkRenderWindowInteractor* interactor = s->view()->interactor();
    interactor->SetEventInformation(x, y, ctrl ? 1 : 0, 0);
    interactor->InvokeEvent(id);
  }
  /// The domain vertex at (x, y) (the example's grid has vertices every 0.125).
  bary::Index vertexAt(double x, double y) const
  {
    const Eigen::MatrixXd& V = s->spline()->net().vertices();
    for (bary::Index v = 0; v < V.rows(); ++v)
      if (std::abs(V(v, 0) - x) < 1e-9 && std::abs(V(v, 1) - y) < 1e-9)
        return v;
    return -1;
  }

private slots:
  void init()
  {
    s = std::make_unique<SplineWindow>();
    s->setInteractive(false);
    s->resize(1400, 800);
    s->show();
    [[maybe_unused]] const bool exposed = QTest::qWaitForWindowExposed(s.get());
    QVERIFY2(s->loadExample("organism-spline"), qPrintable(s->errors().join("; ")));
    QVERIFY(s->isPrism());
    QVERIFY(s->model() && s->deformedModel());
    QApplication::processEvents();
    s->resetCamera();
  }
  void cleanup() { s.reset(); }

  void splineModeDragging()
  {
    // the identity: the model as it is
    for (vtkIdType i = 0; i < s->model()->GetNumberOfPoints(); i += 97)
      for (int d = 0; d < 3; ++d)
        QVERIFY(std::abs(s->model()->GetPoint(i)[d] - s->deformedModel()->GetPoint(i)[d]) < 1e-12);
    QVERIFY(s->foldedTriangles().empty());
    QVERIFY(s->warning().isEmpty());
    const bary::Index anchor = vertexAt(0.25, 0.0);
    QVERIFY(anchor >= 0);
    const Eigen::MatrixXd before = s->spline()->values();
    const Eigen::MatrixXd deformed_before = [&]() {
      Eigen::MatrixXd m(s->deformedModel()->GetNumberOfPoints(), 3);
      for (vtkIdType i = 0; i < m.rows(); ++i)
        for (int d = 0; d < 3; ++d)
          m(i, d) = s->deformedModel()->GetPoint(i)[d];
      return m;
    }();
    s->setDeltaMax(5);
    int press[2];
    toDisplay(before(anchor, 0), before(anchor, 1), press);
    event(vtkCommand::LeftButtonPressEvent, press[0], press[1]);
    QCOMPARE(s->selectedPoint(), static_cast<int>(anchor));
    // ten moves, the last one 40 pixels right and 30 up: one edit in effect; the first move
    // also makes the exact elimination (cached for the others)
    QElapsedTimer timer;
    double first_ms = 0.0, rest_ms = 0.0;
    for (int k = 1; k <= 10; ++k)
    {
      timer.start();
      event(vtkCommand::MouseMoveEvent, press[0] + 40 * k / 10, press[1] + 30 * k / 10);
      (k == 1 ? first_ms : rest_ms) += 1e-6 * static_cast<double>(timer.nsecsElapsed());
    }
    event(vtkCommand::LeftButtonReleaseEvent, press[0] + 40, press[1] + 30);
    qInfo("drag step (DECLeS edit, model of 2402 points, grid, Jacobian test, panel, redraw): "
          "first %.1f ms, then %.1f ms on average (last: edit %.2f ms, update %.1f ms, of which "
          "the Jacobian test %.1f ms)",
      first_ms, rest_ms / 9.0, 1e3 * s->lastEditSeconds(), 1e3 * s->lastUpdateSeconds(),
      1e3 * s->lastJacobianSeconds());
    QVERIFY2(s->errors().isEmpty(), qPrintable(s->errors().join("; ")));
    // the anchor is under the mouse (within the press's rounding: one pixel)
    double mouse[2];
    toWorld(press[0] + 40, press[1] + 30, mouse);
    const Eigen::MatrixXd after = s->spline()->values();
    const double off = std::hypot(after(anchor, 0) - mouse[0], after(anchor, 1) - mouse[1]);
    QVERIFY2(off < 1.0 * pixel(), qPrintable(QString("%1 pixels off").arg(off / pixel())));
    QVERIFY(std::hypot(after(anchor, 0) - before(anchor, 0), after(anchor, 1) - before(anchor, 1)) > 30 * pixel());
    // C1 after the edit, the model moved, the drawn control point follows
    QVERIFY2(c1_residual(*s->spline()) < 1e-9, qPrintable(QString::number(c1_residual(*s->spline()))));
    double p[3];
    s->controlPoints()->GetPoint(anchor, p);
    QVERIFY(std::abs(p[0] - after(anchor, 0)) < 1e-12 && std::abs(p[1] - after(anchor, 1)) < 1e-12);
    double moved = 0.0;
    for (vtkIdType i = 0; i < deformed_before.rows(); ++i)
      moved = std::max(moved, std::abs(s->deformedModel()->GetPoint(i)[1] - deformed_before(i, 1)));
    QVERIFY(moved > 1e-3);
    QVERIFY(s->findChild<QLabel*>("spline_edit")->text().contains("translate"));
    // one drag is one undo step: the values back bit for bit, and the model
    QVERIFY(s->canUndo());
    QVERIFY(s->undo());
    QVERIFY(!s->canUndo());
    QVERIFY((s->spline()->values().array() == before.array()).all());
    for (vtkIdType i = 0; i < deformed_before.rows(); ++i)
      for (int d = 0; d < 3; ++d)
        QVERIFY(s->deformedModel()->GetPoint(i)[d] == deformed_before(i, d));
    QVERIFY(s->redo());
    QVERIFY((s->spline()->values().array() == after.array()).all());
    // a press away from every control point moves the camera, edits nothing
    int empty[2];
    toDisplay(before(anchor, 0) + 0.0125, before(anchor, 1) + 0.0125 * 0.5, empty);
    event(vtkCommand::LeftButtonPressEvent, empty[0], empty[1]);
    event(vtkCommand::LeftButtonReleaseEvent, empty[0], empty[1]);
    QVERIFY((s->spline()->values().array() == after.array()).all());
    // saved and read back: the same spline
    QVERIFY(s->saveSpline(output("spline_dragged.vtu")));
    const vtkSmartPointer<vtkDataSet> read = vtkBaryDataIO::Read(output("spline_dragged.vtu").toStdString());
    auto* grid = vtkUnstructuredGrid::SafeDownCast(read);
    QVERIFY(grid);
    const vtkBarySpline back = vtkBarySplineData::FromGrid(grid);
    QVERIFY(back.is_prism());
    QVERIFY((back.xy->values() - after).cwiseAbs().maxCoeff() < 1e-12);
    QVERIFY(s->saveDeformedModel(output("spline_organism_deformed.vtp")));
    QCOMPARE(vtkBaryDataIO::ReadPolyData(output("spline_organism_deformed.vtp").toStdString())->GetNumberOfPoints(),
      s->model()->GetNumberOfPoints());
  }

  void splineModeSeveralAnchors()
  {
    // Shift + click selects several points; a drag on one of them moves them all by the drag
    const int a = static_cast<int>(vertexAt(-0.25, 0.0)), b = static_cast<int>(vertexAt(0.25, 0.125));
    const Eigen::MatrixXd before = s->spline()->values();
    int da[2], db[2];
    toDisplay(before(a, 0), before(a, 1), da);
    toDisplay(before(b, 0), before(b, 1), db);
    event(vtkCommand::LeftButtonPressEvent, da[0], da[1]);
    event(vtkCommand::LeftButtonReleaseEvent, da[0], da[1]);
    vtkRenderWindowInteractor* interactor = s->view()->interactor();
    interactor->SetEventInformation(db[0], db[1], 0, 1); // Shift
    interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent);
    interactor->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
    QCOMPARE(static_cast<int>(s->selection().size()), 2);
    QVERIFY(s->findChild<QLabel*>("spline_point")->text().contains("2 points selected"));
    QVERIFY((s->spline()->values().array() == before.array()).all()); // clicks edit nothing
    s->setDeltaMax(4);
    event(vtkCommand::LeftButtonPressEvent, da[0], da[1]);
    event(vtkCommand::MouseMoveEvent, da[0] + 15, da[1] - 20);
    event(vtkCommand::MouseMoveEvent, da[0] + 30, da[1] - 40);
    event(vtkCommand::LeftButtonReleaseEvent, da[0] + 30, da[1] - 40);
    QVERIFY2(s->errors().isEmpty(), qPrintable(s->errors().join("; ")));
    const Eigen::MatrixXd after = s->spline()->values();
    const Eigen::RowVector2d move_a = after.row(a) - before.row(a), move_b = after.row(b) - before.row(b);
    QVERIFY(move_a.norm() > 30 * pixel());
    QVERIFY((move_a - move_b).norm() < 1e-12);
    QVERIFY(c1_residual(*s->spline()) < 1e-9);
    QVERIFY(s->findChild<QLabel*>("spline_edit")->text().contains("2 anchor"));
    // Shift + click on a selected point removes it; the panel's Translate moves what is left
    toDisplay(after(b, 0), after(b, 1), db);
    interactor->SetEventInformation(db[0], db[1], 0, 1);
    interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent);
    interactor->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
    QCOMPARE(s->selection(), std::vector<int>{ a });
    QVERIFY(s->translateSelection(0.01, 0.0));
    QVERIFY(std::abs(s->spline()->values()(a, 0) - after(a, 0) - 0.01) < 1e-12);
    QVERIFY(s->undo() && s->undo());
    QVERIFY((s->spline()->values().array() == before.array()).all());
  }

  void splineModeRotateScale()
  {
    // Ctrl + click picks the centre
    int c[2];
    toDisplay(0.0, 0.0, c);
    event(vtkCommand::LeftButtonPressEvent, c[0], c[1], true);
    event(vtkCommand::LeftButtonReleaseEvent, c[0], c[1], true);
    QVERIFY(s->hasCentre());
    QVERIFY(std::hypot(s->centre()[0], s->centre()[1]) < pixel());
    s->setCentre(0.0, 0.0);
    const bary::Index anchor = vertexAt(0.375, 0.25);
    s->selectPoint(static_cast<int>(anchor));
    s->setDeltaMax(6);
    const Eigen::Vector2d p0 = s->spline()->values().row(anchor).transpose();
    QVERIFY(s->rotateSelected(30.0));
    const Eigen::Vector2d p1 = s->spline()->values().row(anchor).transpose();
    const double angle = std::atan2(p0.x() * p1.y() - p0.y() * p1.x(), p0.dot(p1)) * 180.0 / M_PI;
    QVERIFY2(std::abs(angle - 30.0) < 1e-9, qPrintable(QString::number(angle)));
    QVERIFY(std::abs(p1.norm() - p0.norm()) < 1e-12);
    QVERIFY(c1_residual(*s->spline()) < 1e-9);
    QVERIFY(s->scaleSelected(1.5));
    const Eigen::Vector2d p2 = s->spline()->values().row(anchor).transpose();
    QVERIFY(std::abs(p2.norm() - 1.5 * p1.norm()) < 1e-12);
    QVERIFY(std::abs(p2.normalized().dot(p1.normalized()) - 1.0) < 1e-12);
    QVERIFY(c1_residual(*s->spline()) < 1e-9);
    // not in the bottom / top modes (a scalar spline turns no point)
    s->setTarget(SplineTarget::Top);
    QVERIFY(!s->rotateSelected(10.0));
    QVERIFY(!s->errors().isEmpty());
  }

  void splineModeTopEdit()
  {
    QVERIFY(!s->sideRenderer()->GetDraw()); // xy mode: no side view
    vtkNew<vtkPolyData> rest;
    rest->DeepCopy(s->deformedModel());
    const Eigen::MatrixXd xy = s->spline()->values();
    s->setTarget(SplineTarget::Top);
    const bary::Index v = vertexAt(0.0, 0.0);
    s->setDeltaMax(6);
    // a vertical drag raises the top surface by the mouse's motion, scaled: the domain's height
    // (1) is the prism's (0.2)
    int d[2];
    toDisplay(xy(v, 0), xy(v, 1), d);
    event(vtkCommand::LeftButtonPressEvent, d[0], d[1]);
    QCOMPARE(s->selectedPoint(), static_cast<int>(v));
    event(vtkCommand::MouseMoveEvent, d[0], d[1] + 40);
    event(vtkCommand::LeftButtonReleaseEvent, d[0], d[1] + 40);
    const double top = s->spline(SplineTarget::Top)->values()(v, 0);
    double w0[2], w1[2];
    toWorld(d[0], d[1], w0);
    toWorld(d[0], d[1] + 40, w1);
    QVERIFY2(std::abs(top - (0.1 + 0.2 * (w1[1] - w0[1]))) < 1e-9, qPrintable(QString::number(top)));
    QVERIFY(c1_residual(*s->spline(SplineTarget::Top)) < 1e-9);
    // the model rises where the top did, xy untouched
    QVERIFY(max_z_change(rest, s->deformedModel()) > 0.005);
    QVERIFY(s->saveScreenshot(output("viewer_spline_top.png")));
    // the side view: drawn in the top mode, its section through the selected point's row (y =
    // 0) reaching the raised top there
    QVERIFY(s->sideRenderer()->GetDraw());
    QVERIFY(s->sideRenderer()->GetViewProps()->GetNumberOfItems() >= 2);
    double highest_section = -1.0;
    for (vtkIdType i = 0; i < s->sectionData()->GetNumberOfPoints(); ++i)
    {
      QVERIFY(std::abs(s->sectionData()->GetPoint(i)[1]) < 1e-12);
      highest_section = std::max(highest_section, s->sectionData()->GetPoint(i)[2]);
    }
    QVERIFY(std::abs(highest_section - top) < 1e-3);
    QVERIFY((s->spline()->values().array() == xy.array()).all());
    double highest = -1.0;
    for (vtkIdType i = 0; i < s->deformedModel()->GetNumberOfPoints(); ++i)
      highest = std::max(highest, s->deformedModel()->GetPoint(i)[2]);
    QVERIFY(highest > rest->GetBounds()[5] + 0.005);
    // the panel's dz on the bottom surface: lowers it
    s->setTarget(SplineTarget::Bottom);
    QVERIFY(s->translatePoint(static_cast<int>(v), -0.03, 0.0));
    QVERIFY(std::abs(s->spline(SplineTarget::Bottom)->values()(v, 0) - (-0.13)) < 1e-12);
    // undo goes back through both, whichever spline each changed
    QVERIFY(s->undo());
    QVERIFY(s->spline(SplineTarget::Bottom)->values()(v, 0) == -0.1);
    QVERIFY(s->undo());
    QVERIFY(s->spline(SplineTarget::Top)->values()(v, 0) == 0.1);
    QVERIFY(max_z_change(rest, s->deformedModel()) == 0.0);
  }

  void splineModeFoldWarning()
  {
    QVERIFY(s->findChild<QLabel*>("spline_warning")->text().contains("positive"));
    // a vertex pushed well past its neighbours with no slaves: the map folds
    const bary::Index v = vertexAt(0.0, 0.0);
    s->setDeltaMax(0);
    QVERIFY(s->translatePoint(static_cast<int>(v), 0.3, 0.0));
    QVERIFY(c1_residual(*s->spline()) < 1e-9);
    QVERIFY(!s->foldedTriangles().empty());
    QVERIFY(s->minJacobian() <= 0.0);
    qInfo("update with %d folded triangles: %.1f ms, of which the Jacobian test (with "
          "subdivision) and the folds' fill %.1f ms",
      static_cast<int>(s->foldedTriangles().size()), 1e3 * s->lastUpdateSeconds(),
      1e3 * s->lastJacobianSeconds());
    QVERIFY(s->warning().contains("folds"));
    QVERIFY(s->findChild<QLabel*>("spline_warning")->text().contains("folds"));
    QVERIFY(s->saveScreenshot(output("viewer_spline_fold.png")));
    QVERIFY(s->undo());
    QVERIFY(s->foldedTriangles().empty());
    QVERIFY(s->warning().isEmpty());
  }

  void splineModeImage()
  {
    // a fixed edit sequence: the organism bent towards its picture (y += 0.18 sin(pi x)),
    // the top raised in the middle, a rotation about a centre
    s->setDeltaMax(8);
    QVERIFY(s->movePointTo(static_cast<int>(vertexAt(0.5, 0.0)), 0.5, 0.18));
    QVERIFY(s->movePointTo(static_cast<int>(vertexAt(-0.5, 0.0)), -0.5, -0.18));
    s->setTarget(SplineTarget::Top);
    QVERIFY(s->translatePoint(static_cast<int>(vertexAt(0.0, 0.0)), 0.04, 0.0));
    s->setTarget(SplineTarget::XY);
    s->setCentre(0.75, 0.0);
    s->selectPoint(static_cast<int>(vertexAt(0.875, 0.0)));
    QVERIFY(s->rotateSelected(20.0));
    QVERIFY2(s->errors().isEmpty(), qPrintable(s->errors().join("; ")));
    QVERIFY(s->foldedTriangles().empty());
    s->resetCamera();
    auto window = s->snapshot(1000, 560);
    const std::string outdir = std::string(BARYLAB_TEST_OUTPUT_DIR) + "/images";
    QDir().mkpath(QString::fromStdString(outdir));
    const std::string baseline = std::string(BARYLAB_BASELINE_DIR) + "/viewer_spline_organism.png";
    vtkNew<vtkTesting> testing;
    testing->AddArgument("-V");
    testing->AddArgument(baseline.c_str());
    testing->AddArgument("-T");
    testing->AddArgument(outdir.c_str());
    testing->SetRenderWindow(window);
    const int result = testing->RegressionTest(10.0);
    QVERIFY(s->saveScreenshot(QString::fromStdString(outdir + "/viewer_spline_organism_window.png")));
    QVERIFY2(result == vtkTesting::PASSED, qPrintable(QString::fromStdString("image differs from " + baseline)));
  }

  void splineMode2D()
  {
    // a 2D spline (no prism) made like `barylab spline create` without --prism, opened over the
    // example: the model stays (it lies in the same domain), the bottom / top modes are refused
    vtkNew<vtkBarySplineSource> source;
    source->SetInputData(vtkBaryDataIO::ReadPolyData(data("spline_domain.obj").toStdString()));
    source->Update();
    vtkBaryDataIO::Write(source->GetOutput(), output("spline_2d.vtu").toStdString());
    QVERIFY(s->openSpline(output("spline_2d.vtu")));
    QVERIFY(s->hasSpline() && !s->isPrism());
    QVERIFY(!s->spline(SplineTarget::Top) && !s->editor(SplineTarget::Bottom));
    QVERIFY(s->model() && s->deformedModel());
    QVERIFY(!s->canUndo());
    s->setTarget(SplineTarget::Top);
    QCOMPARE(s->target(), SplineTarget::XY);
    QVERIFY(s->errors().last().contains("2.5D"));
    QVERIFY(!s->sideRenderer()->GetDraw());
    // 2D: the model's z is kept, its xy follow the deformation
    const int v = static_cast<int>(vertexAt(0.0, 0.0));
    s->setDeltaMax(6);
    QVERIFY(s->translatePoint(v, 0.0, 0.05));
    double zchange = 0.0, ychange = 0.0;
    for (vtkIdType i = 0; i < s->model()->GetNumberOfPoints(); ++i)
    {
      zchange = std::max(zchange, std::abs(s->model()->GetPoint(i)[2] - s->deformedModel()->GetPoint(i)[2]));
      ychange = std::max(ychange, std::abs(s->model()->GetPoint(i)[1] - s->deformedModel()->GetPoint(i)[1]));
    }
    QVERIFY(zchange < 1e-6); // (the model's points are floats, the deformed ones doubles)
    QVERIFY(ychange > 0.01);
    // a saved 2D spline reads back without the prism
    QVERIFY(s->saveSpline(output("spline_2d_edited.vtu")));
    const vtkSmartPointer<vtkDataSet> read = vtkBaryDataIO::Read(output("spline_2d_edited.vtu").toStdString());
    const vtkBarySpline back = vtkBarySplineData::FromGrid(vtkUnstructuredGrid::SafeDownCast(read));
    QVERIFY(!back.is_prism());
    QVERIFY((back.xy->values() - s->spline()->values()).cwiseAbs().maxCoeff() < 1e-12);
    // not a spline: refused, the spline kept
    QVERIFY(!s->openSpline(data("spline_domain.obj")));
    QVERIFY(s->hasSpline() && s->canUndo());
    QVERIFY(!s->saveSpline(output("spline.vtk")));
  }

  void splineModeKeysAndMenu()
  {
    // Ctrl+Z / Ctrl+Shift+Z reach undo / redo through the Edit menu's shortcuts
    s->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(s.get()));
    const Eigen::MatrixXd before = s->spline()->values();
    QVERIFY(s->translatePoint(static_cast<int>(vertexAt(0.25, 0.25)), 0.03, 0.01));
    const Eigen::MatrixXd after = s->spline()->values();
    QTest::keyClick(s.get(), Qt::Key_Z, Qt::ControlModifier);
    QVERIFY((s->spline()->values().array() == before.array()).all());
    QTest::keyClick(s.get(), Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    QVERIFY((s->spline()->values().array() == after.array()).all());
    // 3 and 1 choose the top and xy modes; ] and [ change delta_max
    QTest::keyClick(s.get(), Qt::Key_3);
    QCOMPARE(s->target(), SplineTarget::Top);
    QTest::keyClick(s.get(), Qt::Key_1);
    QCOMPARE(s->target(), SplineTarget::XY);
    const int delta = s->deltaMax();
    QTest::keyClick(s.get(), Qt::Key_BracketRight);
    QCOMPARE(s->deltaMax(), delta + 1);
    QTest::keyClick(s.get(), Qt::Key_BracketLeft);
    QCOMPARE(s->deltaMax(), delta);
    s.reset();

    // the main window's File menu opens the spline mode with its example
    ViewerWindow main;
    main.setInteractive(false);
    main.show();
    QAction* open = nullptr;
    for (QAction* menu : main.menuBar()->actions())
      if (menu->menu())
        for (QAction* a : menu->menu()->actions())
          if (QString(a->text()).remove(QChar('&')).contains("spline deformations"))
            open = a;
    QVERIFY(open);
    open->trigger();
    SplineWindow* opened = nullptr;
    for (QWidget* w : QApplication::topLevelWidgets())
      if (auto* sw = qobject_cast<SplineWindow*>(w))
        opened = sw;
    QVERIFY(opened);
    QVERIFY(opened->hasSpline() && opened->isPrism() && opened->model());
    opened->close(); // deletes itself (WA_DeleteOnClose)
  }

  void splineModeCommandLine()
  {
    const QString png = output("viewer_spline_cli.png");
    QFile::remove(png);
    QProcess run;
    run.start(BARYLAB_VIEWER_EXE, { "--example", "organism-spline", "--edit", "top", "--delta-max", "3",
                                    "--screenshot", png });
    QVERIFY(run.waitForFinished(60000));
    QVERIFY2(run.exitCode() == 0, run.readAllStandardError().constData());
    QVERIFY(!QImage(png).isNull());
    // files as the command line gives them
    QVERIFY(s->saveSpline(output("spline_identity.vtu")));
    QProcess files;
    files.start(BARYLAB_VIEWER_EXE, { "--spline", output("spline_identity.vtu"), "--model",
                                      data("spline_organism.obj"), "--picture",
                                      data("spline_organism_picture.png"), "--screenshot", png });
    QVERIFY(files.waitForFinished(60000));
    QVERIFY2(files.exitCode() == 0, files.readAllStandardError().constData());
    // a bad spline file: 1 with the file named
    for (const QString& bad : { data("spline_domain.obj"), data("no_such_spline.vtu") })
    {
      QProcess badSpline;
      badSpline.start(BARYLAB_VIEWER_EXE, { "--spline", bad, "--screenshot", output("never.png") });
      QVERIFY(badSpline.waitForFinished(60000));
      QCOMPARE(badSpline.exitCode(), 1);
      QVERIFY(badSpline.readAllStandardError().contains(QFileInfo(bad).fileName().toUtf8()));
    }
    // a model outside the domain: 1
    QProcess badModel;
    badModel.start(BARYLAB_VIEWER_EXE, { "--spline", output("spline_identity.vtu"), "--model",
                                         data("model3d.off"), "--screenshot", output("never.png") });
    QVERIFY(badModel.waitForFinished(60000));
    QCOMPARE(badModel.exitCode(), 1);
    // bad options: 2
    const QList<QStringList> bad_options = {
      { "--example", "organism-spline", "--edit", "sideways" },
      { "--example", "organism-spline", "--delta-max", "x" },
      { "--example", "organism-spline", "--delta-max", "-1" },
      { "--spline", output("spline_identity.vtu"), "--control", "3" },
      { "--model", data("spline_organism.obj") },
    };
    for (const QStringList& options : bad_options)
    {
      QProcess bad;
      bad.start(BARYLAB_VIEWER_EXE, options + QStringList{ "--screenshot", output("never.png") });
      QVERIFY(bad.waitForFinished(60000));
      QVERIFY2(bad.exitCode() == 2, qPrintable(options.join(" ")));
      QVERIFY(options[0] == "--model" || bad.readAllStandardError().contains(options[2].toUtf8()));
    }
    QVERIFY(!QFileInfo::exists(output("never.png")));
    QVERIFY(!s->loadExample("no-such-example"));
  }
};

int main(int argc, char* argv[])
{
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  SplineViewerTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "viewer_spline_test.moc"
