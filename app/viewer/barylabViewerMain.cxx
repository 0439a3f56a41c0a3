// barylab-viewer: look at, compare and use generalized barycentric coordinates.
//
//   barylab-viewer [CONTROLS MODEL [DOMAIN]] [--example NAME] [--method M] [--compare M]
//                  [--control I] [--pose FILE] [--session FILE] [--screenshot PNG]
//   barylab-viewer --surface MESH [--embedding E] [--anchors A] [--weights W] [--curve C]
//                  [--quads Q] [--target MESH --target-anchors A] [--picture P]
//                  [--field none|weight|decal]
//                  [--control I] [--screenshot PNG]           (the surface mode; also
//                  --example torus-averages)
//   barylab-viewer --spline S.vtu [--model M] [--picture P] [--edit xy|bottom|top]
//                  [--delta-max K] [--screenshot PNG]          (the spline mode; also
//                  --example organism-spline)
//
// With --screenshot the viewer computes synchronously, writes the window to PNG and exits
// (0 on success, 1 with a message on stderr on any error).

#include "barylabViewerParameters.h"
#include "barylabViewerSplineMode.h"
#include "barylabViewerSurfaceMode.h"
#include "barylabViewerWindow.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QSurfaceFormat>
#include <QTimer>

#include <QVTKOpenGLNativeWidget.h>

#include <iostream>
#include <string>

namespace
{
/// The surface mode (weighted averages on surfaces): its window, what the command line asks of
/// it, and in batch mode the screenshot. Exit codes as main's.
int run_surface_mode(const QCommandLineParser& parser, bool batch)
{
  using barylab::viewer::SurfaceField;
  using barylab::viewer::SurfaceWindow;
  SurfaceWindow window;
  window.setInteractive(!batch);
  window.resize(1400, 800);
  QStringList errors;
  QObject::connect(&window, &SurfaceWindow::errorReported,
    [&errors](const QString& message) { errors << message; });
  window.show();
  QApplication::processEvents();
  const auto value = [&](const char* name) { return parser.value(name); };
  if (parser.isSet("field") && value("field") != "none" && value("field") != "weight" &&
    value("field") != "decal")
  {
    std::cerr << "barylab-viewer: error: --field " << value("field").toStdString()
              << ": the surface mode shows none, weight or decal\n";
    return 2;
  }
  if (parser.isSet("example"))
    window.loadExample(value("example"));
  else
  {
    window.openSurface(value("surface"), value("embedding")) &&
      (!parser.isSet("anchors") || window.openAnchors(value("anchors"))) &&
      (!parser.isSet("weights") || window.openWeights(value("weights"))) &&
      (!parser.isSet("curve") || window.openCurve(value("curve"))) &&
      (!parser.isSet("picture") || window.openPicture(value("picture"))) &&
      (!parser.isSet("quads") || window.openQuadLayout(value("quads"))) &&
      (!parser.isSet("target") ||
        window.openTarget(value("target"), value("target-anchors"), value("target-embedding")));
  }
  if (parser.isSet("field"))
  {
    const QString f = value("field"); // checked above
    window.setField(f == "none" ? SurfaceField::None
        : f == "decal"          ? SurfaceField::Decal
                                : SurfaceField::AnchorWeight);
  }
  if (parser.isSet("control"))
  {
    bool whole = false;
    const int id = value("control").toInt(&whole);
    if (!whole || id < 0 || id >= window.anchorCount())
    {
      std::cerr << "barylab-viewer: error: --control " << value("control").toStdString()
                << ": not an anchor (0 to " << window.anchorCount() - 1 << ")\n";
      return 2;
    }
    window.selectAnchor(id);
  }
  if (!batch)
    return QApplication::exec();
  if (errors.isEmpty() && !window.saveScreenshot(value("screenshot")))
    errors << "cannot write " + value("screenshot");
  if (!errors.isEmpty())
  {
    std::cerr << "barylab-viewer: error: " << errors.join("; ").toStdString() << "\n";
    return 1;
  }
  return 0;
}
/// The spline mode (C1 spline deformations): its window, what the command line asks of it, and
/// in batch mode the screenshot. Exit codes as main's.
int run_spline_mode(const QCommandLineParser& parser, bool batch)
{
  using barylab::viewer::SplineTarget;
  using barylab::viewer::SplineWindow;
  const auto value = [&](const char* name) { return parser.value(name); };
  const auto usage = [](const std::string& message) {
    std::cerr << "barylab-viewer: error: " << message << "\n";
    return 2;
  };
  for (const char* other : { "surface", "field", "control", "pose", "session", "method", "compare" })
    if (parser.isSet(other))
      return usage(std::string("--") + other + " is not an option of the spline mode");
  if (parser.isSet("edit") && value("edit") != "xy" && value("edit") != "bottom" &&
    value("edit") != "top")
    return usage("--edit " + value("edit").toStdString() + ": the spline mode edits xy, bottom or top");
  int delta_max = -1;
  if (parser.isSet("delta-max"))
  {
    bool whole = false;
    delta_max = value("delta-max").toInt(&whole);
    if (!whole || delta_max < 0 || delta_max > 1000)
      return usage("--delta-max " + value("delta-max").toStdString() + ": a whole number in [0, 1000]");
  }
  SplineWindow window;
  window.setInteractive(!batch);
  window.resize(1400, 800);
  QStringList errors;
  QObject::connect(&window, &SplineWindow::errorReported,
    [&errors](const QString& message) { errors << message; });
  window.show();
  QApplication::processEvents();
  if (parser.isSet("example"))
    window.loadExample(value("example"));
  else
  {
    window.openSpline(value("spline")) &&
      (!parser.isSet("model") || window.openModel(value("model"))) &&
      (!parser.isSet("picture") || window.openPicture(value("picture")));
  }
  if (errors.isEmpty() && parser.isSet("edit"))
    window.setTarget(value("edit") == "top" ? SplineTarget::Top
        : value("edit") == "bottom"        ? SplineTarget::Bottom
                                           : SplineTarget::XY);
  if (delta_max >= 0)
    window.setDeltaMax(delta_max);
  if (!batch)
    return QApplication::exec();
  if (errors.isEmpty() && !window.saveScreenshot(value("screenshot")))
    errors << "cannot write " + value("screenshot");
  if (!errors.isEmpty())
  {
    std::cerr << "barylab-viewer: error: " << errors.join("; ").toStdString() << "\n";
    return 1;
  }
  return 0;
}
} // namespace

int main(int argc, char* argv[])
{
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setApplicationName("barylab-viewer");
  QApplication::setApplicationVersion("0.1");

  QString methods;
  for (const std::string& m : barylab::viewer::MethodNames())
    methods += (methods.isEmpty() ? "" : "|") + QString::fromStdString(m);
  QCommandLineParser parser;
  parser.setApplicationDescription(
    "BaryLab viewer: weight fields, level sets and deformations of generalized barycentric "
    "coordinates.");
  parser.addHelpOption();
  parser.addVersionOption();
  parser.addPositionalArgument("files", "CONTROLS MODEL [DOMAIN]: a cage, skeleton (.tgf) or "
                                        "control points; the model (or a PNG/JPEG picture with a 2D "
                                        "cage: image mode); for a skeleton the domain",
    "[CONTROLS MODEL [DOMAIN]]");
  QCommandLineOption example("example",
    "open a bundled example: " + barylab::viewer::ViewerWindow::ExampleNames().join(", ") + ", " +
      barylab::viewer::SurfaceWindow::ExampleNames().join(", ") + ", " +
      barylab::viewer::SplineWindow::ExampleNames().join(", "),
    "NAME");
  QCommandLineOption method("method", "coordinate method: " + methods, "M");
  QCommandLineOption compare("compare", "second method, side by side", "M");
  QCommandLineOption control("control", "control (weights component) to show", "I");
  QCommandLineOption pose("pose", "pose to apply after computing (posed cage / control points / "
                                  "BBW transforms); 'example' for the example's pose",
    "FILE");
  QCommandLineOption session("session", "load a saved session", "FILE");
  QCommandLineOption field("field", "weight | gradient | image (surface mode: none | weight | decal)", "F");
  QCommandLineOption logScale("log", "logarithmic colour scale");
  QCommandLineOption clip("clip", "clip 3D models by a plane normal to x");
  QCommandLineOption screenshot("screenshot", "compute, write the window to PNG and quit", "PNG");
  QCommandLineOption locality("locality",
    "with --screenshot: also write the locality charts P(t), Q(k) to PREFIX.png and the curves "
    "to PREFIX_P.csv, PREFIX_Q.csv",
    "PREFIX");
  QCommandLineOption surface("surface",
    "surface mode (weighted averages on surfaces): the triangle surface; with --embedding, "
    "--anchors, --weights (first row), --curve, --picture, --target and --target-anchors "
    "(a second surface and its corresponding anchors), --field none|weight|decal, --control "
    "(the anchor shown)",
    "MESH");
  QCommandLineOption embedding("embedding", "surface mode: the surface's embedding (else computed)", "FILE");
  QCommandLineOption anchors("anchors", "surface mode: anchors on the surface", "FILE");
  QCommandLineOption weights("weights", "surface mode: weights, first row used", "FILE");
  QCommandLineOption curve("curve", "surface mode: B-spline control points on the surface", "FILE");
  QCommandLineOption picture("picture",
    "surface mode: the decal's picture; spline mode: the picture to match, on the domain", "FILE");
  QCommandLineOption quads("quads", "surface mode: a coarse quad layout, remeshed semiregularly", "FILE");
  QCommandLineOption target("target", "surface mode: correspondence target surface", "MESH");
  QCommandLineOption targetAnchors("target-anchors", "surface mode: the target's anchors", "FILE");
  QCommandLineOption targetEmbedding("target-embedding", "surface mode: the target's embedding", "FILE");
  QCommandLineOption spline("spline",
    "spline mode (C1 spline deformations, DECLeS editing): the spline (.vtu, barylab spline "
    "create); with --model, --picture, --edit xy|bottom|top, --delta-max",
    "S.vtu");
  QCommandLineOption splineModel("model", "spline mode: the model to deform, in the domain", "FILE");
  QCommandLineOption splineEdit("edit", "spline mode: what the edits change: xy, bottom or top", "MODE");
  QCommandLineOption deltaMax("delta-max", "spline mode: slaves within this net distance", "K");
  parser.addOptions({ example, method, compare, control, pose, session, field, logScale, clip,
    screenshot, locality, surface, embedding, anchors, weights, curve, picture, quads, target,
    targetAnchors, targetEmbedding, spline, splineModel, splineEdit, deltaMax });
  parser.process(app);

  const bool batch = parser.isSet(screenshot);
  if (parser.isSet(surface) ||
    (parser.isSet(example) && barylab::viewer::SurfaceWindow::IsExample(parser.value(example))))
    return run_surface_mode(parser, batch);
  if (parser.isSet(spline) ||
    (parser.isSet(example) && barylab::viewer::SplineWindow::IsExample(parser.value(example))))
    return run_spline_mode(parser, batch);
  for (const QCommandLineOption* only : { &splineModel, &splineEdit, &deltaMax })
    if (parser.isSet(*only))
    {
      std::cerr << "barylab-viewer: error: --" << only->names().front().toStdString()
                << " is an option of the spline mode (--spline or --example organism-spline)\n";
      return 2;
    }
  barylab::viewer::ViewerWindow window;
  window.setInteractive(!batch);
  window.setSynchronous(batch);
  QStringList errors;
  QObject::connect(&window, &barylab::viewer::ViewerWindow::errorReported,
    [&errors](const QString& message) { errors << message; });
  window.show();

  const auto fail = [&](const QString& message) {
    std::cerr << "barylab-viewer: error: " << message.toStdString() << "\n";
    return 1;
  };
  // Batch runs need a mapped window: let Qt process the show before computing.
  QApplication::processEvents();

  const QStringList files = parser.positionalArguments();
  if (parser.isSet(session))
    window.loadSession(parser.value(session));
  else if (parser.isSet(example))
  {
    window.loadExample(parser.value(example), !parser.isSet(method) && !parser.isSet(compare));
  }
  else if (!files.isEmpty())
    window.openFiles(files);
  if (batch && !errors.isEmpty())
    return fail(errors.join("; "));

  const bool reconfigure = parser.isSet(method) || parser.isSet(compare);
  if (parser.isSet(method))
    window.setMethod(parser.value(method));
  if (parser.isSet(compare))
    window.setCompareMethod(parser.value(compare));
  if ((reconfigure || (!files.isEmpty() && !parser.isSet(session) && !parser.isSet(example))) &&
    window.controls())
    window.compute();
  if (batch && !window.waitForComputation(600000))
    return fail("the computation did not finish");
  if (parser.isSet(control))
  {
    // A control id the weights do not have is a bad command line (exit 2), not a wrap-around.
    bool whole = false;
    const int id = parser.value(control).toInt(&whole);
    const int n = window.componentCount();
    if (!whole || id < 0 || (n > 0 && id >= n))
    {
      std::cerr << "barylab-viewer: error: --control " << parser.value(control).toStdString()
                << ": "
                << (n > 0 ? "not a control of these weights (0 to " + std::to_string(n - 1) + ")"
                          : std::string("not a control id (a whole number >= 0)"))
                << "\n";
      return 2;
    }
    window.selectControl(id);
  }
  if (parser.isSet(pose))
    parser.value(pose) == "example" ? window.applyExamplePose() : window.loadPose(parser.value(pose));
  if (parser.isSet(field))
    parser.value(field).startsWith("grad")    ? window.showGradientNorm()
      : parser.value(field).startsWith("image") ? window.showImage()
                                                : window.showWeight();
  if (parser.isSet(logScale))
    window.setLogScale(true);
  if (parser.isSet(clip))
    window.setClipping(true);

  if (!batch)
    return QApplication::exec();
  if (!errors.isEmpty())
    return fail(errors.join("; "));
  if (!window.hasWeights())
    return fail("nothing was computed: give CONTROLS MODEL, --example or --session");
  if (!window.saveScreenshot(parser.value(screenshot)))
    return fail(errors.join("; "));
  if (parser.isSet(locality) &&
    !(window.exportLocalityPng(parser.value(locality) + ".png") &&
      window.exportLocalityCsv(parser.value(locality))))
    return fail(errors.join("; "));
  return 0;
}
