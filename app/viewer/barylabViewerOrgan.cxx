// barylab-viewer: the organ workflow (docs/organ-workflow.md) — a label map to a surface and a
// cage, and the deformation out as a displacement field and a warped label map. The same
// filters as `barylab segment`, `barylab cage`, `barylab export-transform` and
// `barylab warp-image`; no algorithm code here.

#include "barylabViewerWindow.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryDisplacementField.h"
#include "vtkBaryEnclosingCage.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryImageWarp.h"
#include "vtkBaryLabelMapSurface.h"
#include "vtkBaryWeightMethod.h"

#include "core/common/error.h"

#include "vtkImageData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <QDir>
#include <QFileInfo>
#include <QStandardPaths>
#include <QStatusBar>

#include <algorithm>
#include <exception>

namespace barylab
{
namespace viewer
{
namespace
{
/// Runs @p algorithm; its VTK error (a vtkBary filter reports bary::Error so) becomes an
/// exception with the filter's message.
void run(vtkAlgorithm* algorithm)
{
  barylab::RunAlgorithm(algorithm, {}, bary::ErrorCode::InvalidArgument);
}

/// "liver.nii.gz" -> "liver"
QString image_stem(const QString& path)
{
  QString name = QFileInfo(path).fileName();
  for (const char* ext : { ".nii.gz", ".nii", ".nrrd", ".nhdr", ".mha", ".mhd" })
    if (name.endsWith(ext, Qt::CaseInsensitive))
      return name.left(name.size() - static_cast<int>(qstrlen(ext)));
  return QFileInfo(path).completeBaseName();
}

vtkSmartPointer<vtkPolyData> make_cage(vtkPolyData* model, int vertices)
{
  vtkNew<vtkBaryEnclosingCage> cager;
  cager->SetInputData(model);
  cager->SetNumberOfVertices(vertices);
  run(cager);
  return cager->GetOutput();
}

/// The displacement field of moving @p rest to @p posed_points with @p settings, on
/// @p reference's grid, or (null reference) on the cage's bounds grown by a tenth with spacing
/// @p spacing (0: a 64th of the longest side); with its inverse if @p inverse.
vtkSmartPointer<vtkBaryDisplacementField> displacement_field(const bary::WeightsSettings& settings,
  vtkPolyData* rest, vtkPoints* posed_points, vtkImageData* reference, double spacing, bool inverse)
{
  auto field = vtkSmartPointer<vtkBaryDisplacementField>::New();
  field->GetWeightMethod()->SetSettings(settings);
  vtkNew<vtkPolyData> posed;
  posed->ShallowCopy(rest);
  vtkNew<vtkPoints> points; // doubles: the pose as dragged, not rounded to float
  points->SetDataTypeToDouble();
  points->DeepCopy(posed_points);
  posed->SetPoints(points);
  field->SetRestCageData(rest);
  field->SetDeformedCageData(posed);
  if (reference)
    field->SetReferenceImageData(reference);
  else
  {
    double b[6];
    rest->GetBounds(b);
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, b[2 * k + 1] - b[2 * k]);
    const double h = spacing > 0.0 ? spacing : longest / 64.0;
    for (int k = 0; k < 3; ++k)
    {
      const double grow = 0.1 * (b[2 * k + 1] - b[2 * k]);
      b[2 * k] -= grow;
      b[2 * k + 1] += grow;
    }
    field->SetBounds(b);
    field->SetSpacing(h, h, h);
  }
  field->SetComputeInverse(inverse);
  run(field);
  return field;
}
} // namespace

QString ViewerWindow::organFolder()
{
  return QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation) + "/organ";
}

bool ViewerWindow::openLabelMap(const QString& image, long long label, int cage_vertices, const QString& folder)
{
  if (this->isComputing())
  {
    this->reportError("a computation is running: cancel it first");
    return false;
  }
  const QString dir = folder.isEmpty() ? organFolder() : folder;
  vtkSmartPointer<vtkImageData> labels;
  QString surface_path, cage_path;
  try
  {
    labels = vtkBaryImageIO::Read(image.toStdString());
    vtkNew<vtkBaryLabelMapSurface> segment;
    segment->SetInputData(labels);
    segment->SetLabel(label);
    run(segment);
    vtkSmartPointer<vtkPolyData> surface = segment->GetOutput();
    auto cage = make_cage(surface, cage_vertices);
    if (!QDir().mkpath(dir))
      throw bary::Error(bary::ErrorCode::Io, "cannot create the folder '" + dir.toStdString() + "'");
    const QString stem = dir + "/" + image_stem(image) + "_label" + QString::number(segment->GetLabelUsed());
    surface_path = stem + "_surface.vtp";
    cage_path = stem + "_cage.obj";
    vtkBaryDataIO::Write(surface, surface_path.toStdString());
    vtkBaryDataIO::Write(cage, cage_path.toStdString());
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  Inputs in;
  in.controls = cage_path;
  in.model = surface_path;
  if (!this->openInputs(in))
    return false;
  this->LabelMap = labels;
  this->LabelMapPath = QFileInfo(image).absoluteFilePath();
  this->statusBar()->showMessage("Opened label map " + QFileInfo(image).fileName() + ": surface and a cage of " +
    QString::number(this->controls()->GetNumberOfPoints()) + " vertices in " + dir +
    "; press Compute (F5).");
  return true;
}

bool ViewerWindow::makeCage(int vertices, const QString& path)
{
  if (this->isComputing())
  {
    this->reportError("a computation is running: cancel it first");
    return false;
  }
  auto* model = vtkPolyData::SafeDownCast(this->State.model());
  if (!model)
  {
    this->reportError("make a cage: open a model (a closed triangle surface, or a 2D mesh) first");
    return false;
  }
  QString out = path;
  try
  {
    auto cage = make_cage(model, vertices);
    if (out.isEmpty())
    {
      if (!QDir().mkpath(organFolder()))
        throw bary::Error(bary::ErrorCode::Io, "cannot create the folder '" + organFolder().toStdString() + "'");
      out = organFolder() + "/" + QFileInfo(this->inputs().model).completeBaseName() + "_cage" +
        QString::number(cage->GetNumberOfPoints()) + ".obj";
    }
    vtkBaryDataIO::Write(cage, out.toStdString());
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  // the label map stays: the new cage is around the same model
  vtkSmartPointer<vtkImageData> labels = this->LabelMap;
  const QString labels_path = this->LabelMapPath;
  Inputs in;
  in.controls = out;
  in.model = this->inputs().model;
  if (!this->openInputs(in))
    return false;
  this->LabelMap = labels;
  this->LabelMapPath = labels_path;
  this->statusBar()->showMessage("Made a cage of " + QString::number(this->controls()->GetNumberOfPoints()) +
    " vertices (" + out + "); press Compute (F5).");
  return true;
}

bool ViewerWindow::saveTransform(const QString& path, const QString& inverse_path, double spacing)
{
  if (!this->hasWeights())
  {
    this->reportError("save transform: compute the weights first");
    return false;
  }
  if (this->shownKind() == ControlKind::Skeleton)
  {
    this->reportError("save transform: the weights shown are for a BBW skeleton; a displacement "
                      "field is made from a cage or free control points");
    return false;
  }
  try
  {
    auto field = displacement_field(this->State.computed(), this->controls(), this->posedControls(),
      this->LabelMap, spacing, !inverse_path.isEmpty());
    vtkBaryImageIO::Write(field->GetOutput(0), path.toStdString());
    if (!inverse_path.isEmpty())
      vtkBaryImageIO::Write(field->GetOutput(1), inverse_path.toStdString());
    QString message = "Saved the displacement field (LPS) to " + path;
    if (!inverse_path.isEmpty())
      message += " and its inverse to " + inverse_path + " (max residual " +
        QString::number(field->GetInverseMaximumResidual(), 'g', 3) + " mm)";
    if (field->GetNumberOfFoldedVoxels() > 0)
      message += "; folds at " + QString::number(field->GetNumberOfFoldedVoxels()) + " voxels";
    this->statusBar()->showMessage(message);
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  return true;
}

bool ViewerWindow::saveWarpedLabelMap(const QString& path)
{
  if (!this->LabelMap)
  {
    this->reportError("save warped label map: open a label map first (File > Open label map)");
    return false;
  }
  if (!this->hasWeights())
  {
    this->reportError("save warped label map: compute the weights first");
    return false;
  }
  try
  {
    auto field = displacement_field(
      this->State.computed(), this->controls(), this->posedControls(), this->LabelMap, 0.0, true);
    vtkNew<vtkBaryImageWarp> warp;
    warp->SetInputData(this->LabelMap);
    warp->SetFieldData(field->GetOutput(1));
    warp->SetInterpolationToNearest();
    run(warp);
    vtkBaryImageIO::Write(warp->GetOutput(), path.toStdString());
  }
  catch (const std::exception& e)
  {
    this->reportError(QString::fromStdString(e.what()));
    return false;
  }
  this->statusBar()->showMessage("Saved the warped label map to " + path);
  return true;
}

} // namespace viewer
} // namespace barylab
