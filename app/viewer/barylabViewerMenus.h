#pragma once
/// @file barylabViewerMenus.h
/// The viewer's menu bar (File, Edit, Compute, View: actions and keys), the file dialogs behind
/// the File menu and the "Run in terminal" dialog. Every action calls a public slot of the
/// window (a dialog first asks for a path), which does the work and reports errors, so tests
/// and scripts call the slots directly and skip menus and dialogs.

class QString;
class QWidget;

namespace barylab
{
namespace viewer
{
class ViewerWindow;

/// Fills @p window's menu bar; each mode adds its own actions to the Edit menu (Mode::addActions).
void BuildMenus(ViewerWindow& window);

/// CONTROLS, MODEL and, for a skeleton (.tgf), the DOMAIN to mesh; then openFiles.
void OpenFilesDialog(ViewerWindow& window);
void LoadSessionDialog(ViewerWindow& window);
void SaveSessionDialog(ViewerWindow& window);
void LoadPoseDialog(ViewerWindow& window);
void SavePoseDialog(ViewerWindow& window);
void SaveDeformedDialog(ViewerWindow& window);
/// The organ workflow: a label map (then its label and the cage's size), a cage around the
/// model, the displacement field (and its inverse), the warped label map.
void OpenLabelMapDialog(ViewerWindow& window);
void MakeCageDialog(ViewerWindow& window);
void SaveTransformDialog(ViewerWindow& window);
void SaveWarpedLabelMapDialog(ViewerWindow& window);
void SaveScreenshotDialog(ViewerWindow& window);
/// A PNG path; writes the charts there and the CSV tables next to it (same prefix).
void ExportLocalityDialog(ViewerWindow& window);
/// Shows the `barylab weights` command line @p line, read-only, to copy.
void ShowCommandLineDialog(QWidget* parent, const QString& line);

} // namespace viewer
} // namespace barylab
