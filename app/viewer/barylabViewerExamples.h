#pragma once
/// @file barylabViewerExamples.h
/// The examples bundled with the viewer (File > Open example, --example): inputs from the
/// data directory, the method, the example's pose and the control selected at first.

#include <QString>
#include <QStringList>

#include <vector>

namespace barylab
{
namespace viewer
{
struct Inputs;

struct Example
{
  const char* name;
  const char* controls; ///< file names in the data directory
  const char* model;
  const char* domain; ///< "" = none
  const char* method;
  const char* pose;
  int selected; ///< the weights component selected when the weights are computed

  /// The example's files (paths in the data directory), its name and its pose.
  Inputs inputs() const;
};

/// Every bundled example, in menu order.
const std::vector<Example>& Examples();
/// Their names.
QStringList ExampleNames();
/// The example named @p name; null when there is none.
const Example* FindExample(const QString& name);
/// The path of the bundled data file @p name (in BARYLAB_DEFAULT_DATA_DIR).
QString DataPath(const char* name);

} // namespace viewer
} // namespace barylab
