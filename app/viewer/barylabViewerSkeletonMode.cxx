#include "barylabViewerSkeletonMode.h"

#include "barylabRender.h"
#include "barylabViewerSession.h"
#include "barylabViewerWindow.h"

#include "vtkBaryConversion.h"
#include "vtkBaryLinearBlendSkinning.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include <QBoxLayout>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QMenu>
#include <QPushButton>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

#include <Eigen/Geometry>

#include <fstream>

namespace barylab
{
namespace viewer
{

bool SkeletonMode::serves(const std::string& method, const Session& session) const
{
  vtkPolyData* controls = session.controls();
  // a skeleton, or mixed handles marked by a HandleType cell array (vtkBaryMixedHandles)
  return controls && method == "bbw" &&
    ((controls->GetNumberOfPolys() == 0 &&
       (controls->GetNumberOfLines() > 0 || IsSkeletonFile(session.inputs().controls))) ||
      controls->GetCellData()->GetAbstractArray(vtkBaryMixedHandles::HandleTypeArrayName()));
}

void SkeletonMode::addControlActors(vtkRenderer* renderer, vtkPolyData* controls,
  vtkPoints* points, const SceneOptions& options, vtkPoints* selected) const
{
  const double grey[3] = { 0.25, 0.25, 0.3 }, red[3] = { 0.9, 0.15, 0.1 };
  const bary::Skeleton skeleton = vtkBaryMixedHandles::ToHandles(controls, options.dimension);
  vtkNew<vtkCellArray> bones, chosen;
  // mixed handles: the cage's faces and the regions' boundaries as thinner lines (their
  // edges), the selected cage vertex as its joint, a selected region as its outline
  const Eigen::VectorXi cage = skeleton.cage_joints();
  const Eigen::Index first_cage = skeleton.P.size() + skeleton.BE.rows();
  const Eigen::Index first_region = first_cage + cage.size();
  vtkNew<vtkCellArray> outlines;
  auto add_edges = [](vtkCellArray* cells, const Eigen::MatrixXi& F) {
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (Eigen::Index k = 0; k < F.cols(); ++k)
      {
        if (F.cols() == 2 && k == 1)
          break;
        const vtkIdType ids[2] = { F(f, k), F(f, (k + 1) % F.cols()) };
        cells->InsertNextCell(2, ids);
      }
  };
  add_edges(outlines, skeleton.CF);
  for (std::size_t r = 0; r < skeleton.regions.size(); ++r)
  {
    add_edges(outlines, skeleton.regions[r]);
    if (options.component == first_region + static_cast<Eigen::Index>(r))
      add_edges(chosen, skeleton.regions[r]);
  }
  if (outlines->GetNumberOfCells() > 0)
    AddLines(renderer, points, outlines, 2.0, grey);
  if (options.component >= first_cage && options.component < first_region)
    selected->InsertNextPoint(points->GetPoint(cage(options.component - first_cage)));
  for (Eigen::Index b = 0; b < skeleton.BE.rows(); ++b)
  {
    const vtkIdType ids[2] = { skeleton.BE(b, 0), skeleton.BE(b, 1) };
    bones->InsertNextCell(2, ids);
    if (options.component == skeleton.P.size() + b)
    {
      chosen->InsertNextCell(2, ids);
      selected->InsertNextPoint(points->GetPoint(ids[0]));
      selected->InsertNextPoint(points->GetPoint(ids[1]));
    }
  }
  AddLines(renderer, points, bones, 4.0, grey);
  if (chosen->GetNumberOfCells() > 0)
    AddLines(renderer, points, chosen, 7.0, red);
  if (options.component >= 0 && options.component < skeleton.P.size())
    selected->InsertNextPoint(points->GetPoint(skeleton.P(options.component)));
}

QStringList SkeletonMode::controlLabels(const Session& session, int components) const
{
  QStringList labels;
  if (components <= 0)
    return labels;
  try
  {
    const bary::Skeleton s =
      vtkBaryMixedHandles::ToHandles(session.controls(), session.modelDimension());
    for (Eigen::Index j = 0; j < s.P.size(); ++j)
      labels << QString("point handle %1 (joint %2)").arg(j).arg(s.P(j));
    for (Eigen::Index b = 0; b < s.BE.rows(); ++b)
      labels << QString("bone %1 (joints %2-%3)").arg(b).arg(s.BE(b, 0)).arg(s.BE(b, 1));
    const Eigen::VectorXi cage = s.cage_joints();
    for (Eigen::Index k = 0; k < cage.size(); ++k)
      labels << QString("cage vertex %1 (joint %2)").arg(k).arg(cage(k));
    for (std::size_t r = 0; r < s.regions.size(); ++r)
      labels << QString("region %1").arg(r);
  }
  catch (const std::exception&)
  {
  }
  return labels;
}

void SkeletonMode::addActions(QMenu* edit, ViewerWindow& window) const
{
  ViewerWindow* w = &window;
  const auto twist_by = [w](double degrees, double factor) {
    const HandleTwist t = w->handleTwist(w->selectedControl());
    w->setHandleTwist(w->selectedControl(), t.angle_degrees + degrees, t.scale * factor);
  };
  edit->addAction("Rotate handle +15 deg", w, [twist_by]() { twist_by(15.0, 1.0); }, QKeySequence("]"));
  edit->addAction("Rotate handle -15 deg", w, [twist_by]() { twist_by(-15.0, 1.0); }, QKeySequence("["));
  edit->addAction("Scale handle x1.1", w, [twist_by]() { twist_by(0.0, 1.1); }, QKeySequence("+"));
  edit->addAction("Scale handle /1.1", w, [twist_by]() { twist_by(0.0, 1.0 / 1.1); }, QKeySequence("-"));
}

void SkeletonMode::addPanelWidgets(QBoxLayout* deformation, ViewerWindow& window) const
{
  auto* row = new QHBoxLayout;
  auto* angle = new QDoubleSpinBox;
  angle->setObjectName("twist_angle");
  angle->setRange(-360.0, 360.0);
  angle->setSuffix(" deg");
  angle->setSingleStep(5.0);
  angle->setToolTip("BBW: rotation of the selected handle about its centre (2D: about "
                    "z; 3D bone: about its axis)");
  auto* scale = new QDoubleSpinBox;
  scale->setObjectName("twist_scale");
  scale->setRange(0.05, 20.0);
  scale->setDecimals(3);
  scale->setSingleStep(0.05);
  scale->setValue(1.0);
  scale->setToolTip("BBW: uniform scale of the selected handle about its centre");
  auto* apply = new QPushButton("Rotate/scale handle");
  apply->setObjectName("twist_apply");
  row->addWidget(angle);
  row->addWidget(scale);
  row->addWidget(apply);
  deformation->addLayout(row);
  ViewerWindow* w = &window;
  QObject::connect(apply, &QPushButton::clicked, w, [w, angle, scale]() {
    w->setHandleTwist(w->selectedControl(), angle->value(), scale->value());
  });
}

vtkSmartPointer<vtkPointSet> SkeletonMode::deform(const Session& session, vtkDataSet* weighted,
  const WeightsParameters& parameters) const
{
  return Skin(vtkPointSet::SafeDownCast(weighted), Transforms(session), parameters);
}

std::vector<Eigen::MatrixXd> SkeletonMode::Transforms(const Session& session)
{
  const int dim = session.modelDimension();
  const bary::Skeleton s = vtkBaryMixedHandles::ToHandles(session.controls(), dim);
  const Eigen::MatrixXd posed = vtkBaryConversion::ToMatrix(session.posedControls(), dim);
  const Eigen::VectorXi cage = s.cage_joints();
  const Eigen::Index first_cage = s.P.size() + s.BE.rows();
  vtkNew<vtkPolyData> joints;
  joints->SetPoints(session.posedControls());
  std::vector<Eigen::MatrixXd> pose;
  int handle = 0;
  // the joints' pose as 3 x 4 transforms, as the command line computes it
  for (Eigen::MatrixXd T : vtkBaryLinearBlendSkinning::PoseFromJoints(session.controls(), joints, dim))
  {
    const HandleTwist twist = session.twist(handle);
    if (!twist.IsIdentity())
    {
      // centre and axis at the current pose: a point handle's joint, a bone's first joint, a
      // cage vertex's joint, a region's corners' centroid
      const bool bone = handle >= s.P.size() && handle < first_cage;
      Eigen::Vector3d c = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
      if (handle < s.P.size())
        c.head(dim) = posed.row(s.P(handle)).transpose();
      else if (bone)
        c.head(dim) = posed.row(s.BE(handle - s.P.size(), 0)).transpose();
      else if (handle < first_cage + cage.size())
        c.head(dim) = posed.row(cage(handle - first_cage)).transpose();
      else
      {
        const Eigen::MatrixXi& F = s.regions[static_cast<std::size_t>(handle - first_cage - cage.size())];
        for (Eigen::Index k = 0; k < F.size(); ++k)
          c.head(dim) += posed.row(F.data()[k]).transpose() / static_cast<double>(F.size());
      }
      const int joint = bone ? s.BE(handle - s.P.size(), 0) : 0;
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

vtkSmartPointer<vtkPoints> SkeletonMode::readPose(const Session& session, const QString& path) const
{
  const QString ext = QFileInfo(path).suffix().toLower();
  if (ext != "txt" && ext != "dmat")
    return this->Mode::readPose(session, path);
  const bary::Skeleton s =
    vtkBaryMixedHandles::ToHandles(session.controls(), session.modelDimension());
  const auto pose = vtkBaryDataIO::ReadPose(path.toStdString(), s.handle_count(), &s);
  return CopyPoints(PoseHandles(session.controls(), pose)->GetPoints());
}

void SkeletonMode::writePose(const Session& session, const QString& path) const
{
  if (!session.weighted() || QFileInfo(path).suffix().toLower() != "txt")
  {
    this->Mode::writePose(session, path);
    return;
  }
  // BBW: the per-handle transforms (joints and rotations / scales), BaryLab pose text that
  // `barylab deform --transforms` and File > Load pose read
  const int dim = session.modelDimension();
  std::ofstream out(path.toStdString());
  out.precision(17);
  out << "# BaryLab pose: one affine transform per handle (weights column order), "
      << (dim == 2 ? "a00 a01 t0 a10 a11 t1" : "a00 a01 a02 t0 a10 a11 a12 t1 a20 a21 a22 t2")
      << "\n";
  for (const Eigen::MatrixXd& T : Transforms(session))
  {
    for (int r = 0; r < dim; ++r)
    {
      for (int c = 0; c < dim; ++c)
        out << T(r, c) << ' ';
      out << T(r, 3) << (r + 1 < dim ? ' ' : '\n');
    }
  }
  if (!out)
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path.toStdString() + "'");
}

void SkeletonMode::writeSession(const Session& session, nlohmann::json& document) const
{
  nlohmann::json twists = nlohmann::json::array();
  for (const HandleTwist& t : session.twists())
    twists.push_back({ t.angle_degrees, t.scale });
  document["handle_twists"] = twists;
}

void SkeletonMode::readSession(const nlohmann::json& document, SessionFile& file) const
{
  if (document.contains("handle_twists") && document["handle_twists"].is_array())
    for (const nlohmann::json& t : document["handle_twists"])
      file.twists.push_back({ t.at(0).get<double>(), t.at(1).get<double>() });
}

QStringList SkeletonMode::commandLineInputs(const Inputs& inputs) const
{
  return { "--handles", ShellQuoted(inputs.controls), "--mesh", ShellQuoted(inputs.domain) };
}

} // namespace viewer
} // namespace barylab
