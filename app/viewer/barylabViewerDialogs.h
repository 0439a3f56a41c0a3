#pragma once
/// @file barylabViewerDialogs.h
/// The viewer's file dialogs (File menu) and the "Run in terminal" dialog: each asks for a
/// path and then calls the window's public slot, which does the work and reports errors, so
/// tests and scripts call the slots directly and skip the dialogs.

class QString;
class QWidget;

namespace barylab
{
namespace viewer
{
class ViewerWindow;

/// CONTROLS, MODEL and, for a skeleton (.tgf), the DOMAIN to mesh; then openFiles.
void OpenFilesDialog(ViewerWindow& window);
void LoadSessionDialog(ViewerWindow& window);
void SaveSessionDialog(ViewerWindow& window);
void LoadPoseDialog(ViewerWindow& window);
void SavePoseDialog(ViewerWindow& window);
void SaveDeformedDialog(ViewerWindow& window);
void SaveScreenshotDialog(ViewerWindow& window);
/// A PNG path; writes the charts there and the CSV tables next to it (same prefix).
void ExportLocalityDialog(ViewerWindow& window);
/// Shows the `barylab weights` command line @p line, read-only, to copy.
void ShowCommandLineDialog(QWidget* parent, const QString& line);

} // namespace viewer
} // namespace barylab
