#pragma once
/// @file barylabViewerMode.h
/// An interaction mode of the viewer: what the controls are for a family of methods and how a
/// person works with them (cage points dragged, skeleton joints dragged and handles twisted,
/// free control points). The window asks the mode of the weights shown (or of the method
/// chosen, before any weights) for everything that differs between families; the modes keep
/// no state (the session holds it), so one instance of each serves every window.
///
/// How to add a mode (a family of methods with their own controls):
/// 1. a ControlKind value (barylabViewerScene.h) naming it;
/// 2. a class derived from Mode in barylabViewer<Name>Mode.h/.cxx that overrides what differs
///    from control points deformed by their weights (the defaults below);
/// 3. one line in Modes() (barylabViewerMode.cxx), before the modes that would otherwise claim
///    its methods, and the .cxx in app/viewer/CMakeLists.txt.

#include "barylabViewerScene.h"

#include <QString>
#include <QStringList>

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

class QBoxLayout;
class QMenu;
class vtkDataSet;
class vtkPoints;
class vtkPointSet;
class vtkPolyData;
class vtkRenderer;

namespace barylab
{
struct WeightsParameters;

namespace viewer
{
struct Inputs;
class Session;
struct SessionFile;
class ViewerWindow;

class Mode
{
public:
  virtual ~Mode() = default;

  /// How the scene draws the controls and what a weights component means (also the mode's id).
  virtual ControlKind controlKind() const = 0;
  /// True when this mode serves the method @p method with @p session's controls (the controls
  /// may be null: no inputs yet).
  virtual bool serves(const std::string& method, const Session& session) const = 0;

  // --- scene ---------------------------------------------------------------------------
  /// The controls' actors but their spheres (wires, bones), and into @p selected the points
  /// to highlight for weights component @p options.component. @p points are the controls'
  /// points at the current pose. Default: no wire, the control point of that index.
  virtual void addControlActors(vtkRenderer* renderer, vtkPolyData* controls, vtkPoints* points,
    const SceneOptions& options, vtkPoints* selected) const;
  /// The Controls list: one label per weights component (@p components of them).
  virtual QStringList controlLabels(const Session& session, int components) const;

  // --- picking, dragging, keys ---------------------------------------------------------
  /// True when weights component i is control point i: clicking a point selects its weight
  /// and selecting a weight puts its point in the Move row. Default: true.
  virtual bool componentsAreControlPoints() const { return true; }
  /// True when weights components are handles that can be rotated and scaled (HandleTwist).
  /// Default: false.
  virtual bool twistsHandles() const { return false; }
  /// Menu actions (and their keys) of this mode, added to the Edit menu of every window.
  virtual void addActions(QMenu* edit, ViewerWindow& window) const;
  /// Widgets of this mode, added to the Deformation group of every window's panel.
  virtual void addPanelWidgets(QBoxLayout* deformation, ViewerWindow& window) const;

  // --- deformation and poses -----------------------------------------------------------
  /// @p weighted (weights of @p parameters) deformed to @p session's pose. Default:
  /// barylab::Deform with the posed controls.
  virtual vtkSmartPointer<vtkPointSet> deform(const Session& session, vtkDataSet* weighted,
    const WeightsParameters& parameters) const;
  /// The posed controls a pose file holds. Default: a posed copy of the controls (same points,
  /// same order). @throws bary::Error
  virtual vtkSmartPointer<vtkPoints> readPose(const Session& session, const QString& path) const;
  /// Writes the pose to @p path. Default: the controls with their posed points (refused while
  /// a handle is twisted). @throws bary::Error
  virtual void writePose(const Session& session, const QString& path) const;

  // --- session file and command line ---------------------------------------------------
  /// Adds this mode's part to a session document (the mode of the weights shown).
  virtual void writeSession(const Session& session, nlohmann::json& document) const;
  /// Reads this mode's part of @p document, if present, into @p file; called for every mode
  /// before anything is opened, so a malformed file changes nothing. @throws on a bad part
  virtual void readSession(const nlohmann::json& document, SessionFile& file) const;
  /// The `barylab weights` arguments naming the inputs' controls (e.g. `--cage FILE`).
  virtual QStringList commandLineInputs(const Inputs& inputs) const = 0;
};

/// Every mode, in the order they are asked whether they serve a method.
const std::vector<const Mode*>& Modes();
/// The mode serving @p method with @p session's controls.
const Mode& ModeFor(const std::string& method, const Session& session);
/// The mode drawing controls of kind @p kind.
const Mode& ModeFor(ControlKind kind);

/// @p s quoted for a POSIX shell when it needs to be.
QString ShellQuoted(const QString& s);

} // namespace viewer
} // namespace barylab
