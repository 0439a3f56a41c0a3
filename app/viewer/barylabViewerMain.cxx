// barylab-viewer: look at, compare and use generalized barycentric coordinates.
//
//   barylab-viewer [CONTROLS MODEL [DOMAIN]] [--example NAME] [--method M] [--compare M]
//                  [--control I] [--pose FILE] [--session FILE] [--screenshot PNG]
//
// With --screenshot the viewer computes synchronously, writes the window to PNG and exits
// (0 on success, 1 with a message on stderr on any error).

#include "barylabViewerParameters.h"
#include "barylabViewerWindow.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QSurfaceFormat>
#include <QTimer>

#include <QVTKOpenGLNativeWidget.h>

#include <iostream>
#include <string>

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
    "open a bundled example: " + barylab::viewer::ViewerWindow::ExampleNames().join(", "), "NAME");
  QCommandLineOption method("method", "coordinate method: " + methods, "M");
  QCommandLineOption compare("compare", "second method, side by side", "M");
  QCommandLineOption control("control", "control (weights component) to show", "I");
  QCommandLineOption pose("pose", "pose to apply after computing (posed cage / control points / "
                                  "BBW transforms); 'example' for the example's pose",
    "FILE");
  QCommandLineOption session("session", "load a saved session", "FILE");
  QCommandLineOption field("field", "weight | gradient | image", "F");
  QCommandLineOption logScale("log", "logarithmic colour scale");
  QCommandLineOption clip("clip", "clip 3D models by a plane normal to x");
  QCommandLineOption screenshot("screenshot", "compute, write the window to PNG and quit", "PNG");
  QCommandLineOption locality("locality",
    "with --screenshot: also write the locality charts P(t), Q(k) to PREFIX.png and the curves "
    "to PREFIX_P.csv, PREFIX_Q.csv",
    "PREFIX");
  parser.addOptions({ example, method, compare, control, pose, session, field, logScale, clip,
    screenshot, locality });
  parser.process(app);

  const bool batch = parser.isSet(screenshot);
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
