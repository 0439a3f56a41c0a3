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
#include <QCheckBox>
#include <QLabel>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QMenu>
#include <QPushButton>

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellPicker.h"
#include "vtkDoubleArray.h"
#include "vtkInteractorObserver.h"
#include "vtkPointData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkUnsignedCharArray.h"
#include <QVTKOpenGLNativeWidget.h>
#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

namespace barylab
{
namespace viewer
{
namespace
{
const char* const BrushArray = "ShapePreservation";

/// The size of a domain: its bounding box diagonal.
double domain_size(vtkDataSet* domain)
{
  double b[6];
  domain->GetBounds(b);
  return std::max(1e-12, std::sqrt((b[1] - b[0]) * (b[1] - b[0]) +
                           (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4])));
}

/// The windows whose brush overlay a renderer draws (one entry per brush panel).
std::map<vtkRenderer*, const ViewerWindow*>& brush_windows()
{
  static std::map<vtkRenderer*, const ViewerWindow*> windows;
  return windows;
}

/// The "Shape brush" row's state and its mouse observer on the window's main view: while
/// "Paint" is checked, the left button paints (or erases) on the domain instead of picking
/// joints or turning the camera; releasing it recomputes the weights with the brush.
class ShapeBrushTool : public QObject
{
public:
  ShapeBrushTool(ViewerWindow& window, QCheckBox* paint, QDoubleSpinBox* radius,
    QDoubleSpinBox* strength, QCheckBox* erase, QObject* parent)
    : QObject(parent)
    , Window(window)
    , Paint(paint)
    , Radius(radius)
    , Strength(strength)
    , Erase(erase)
  {
    this->Callback = vtkSmartPointer<vtkCallbackCommand>::New();
    this->Callback->SetCallback(&ShapeBrushTool::OnEvent);
    this->Callback->SetClientData(this);
    this->Interactor = window.view() ? window.view()->interactor() : nullptr;
    if (this->Interactor)
      for (unsigned long e : { vtkCommand::LeftButtonPressEvent, vtkCommand::MouseMoveEvent,
             vtkCommand::LeftButtonReleaseEvent })
        this->Interactor->AddObserver(e, this->Callback, 20.0f); // before the views' (10)
    this->Renderer = window.renderer();
    brush_windows()[this->Renderer] = &window;
  }
  ~ShapeBrushTool() override
  {
    if (this->Interactor)
      this->Interactor->RemoveObserver(this->Callback);
    brush_windows().erase(this->Renderer);
  }

private:
  /// One dab at the display position (x, y): the world point on the domain's plane (2D) or
  /// on the picked surface (3D). False when there is nothing to paint on.
  bool dab(int x, int y)
  {
    vtkDataSet* domain = this->Window.session().domain();
    if (!SkeletonMode::CanPaint(domain) || !this->Renderer)
      return false;
    const double size = domain_size(domain);
    double world[4] = { 0, 0, 0, 1 };
    double b[6];
    domain->GetBounds(b);
    if (b[5] - b[4] <= 1e-9 * size)
    {
      // the view ray through (x, y) meets the domain's plane z = b[4]
      double near_point[4], far_point[4];
      vtkInteractorObserver::ComputeDisplayToWorld(this->Renderer, x, y, 0.0, near_point);
      vtkInteractorObserver::ComputeDisplayToWorld(this->Renderer, x, y, 1.0, far_point);
      const double dz = far_point[2] - near_point[2];
      if (std::abs(dz) > 0.0)
      {
        const double t = (b[4] - near_point[2]) / dz;
        for (int k = 0; k < 3; ++k)
          world[k] = near_point[k] + t * (far_point[k] - near_point[k]);
      }
    }
    else
    {
      vtkNew<vtkCellPicker> picker;
      picker->SetTolerance(0.002);
      if (!picker->Pick(x, y, 0.0, this->Renderer))
        return false;
      picker->GetPickPosition(world);
    }
    const double value = this->Strength->value() / (size * size);
    SkeletonMode::PaintShapeBrush(
      domain, world, this->Radius->value() / 100.0 * size, value, this->Erase->isChecked());
    this->Painted = true;
    return true;
  }

  static void OnEvent(vtkObject*, unsigned long event, void* client, void*)
  {
    auto* self = static_cast<ShapeBrushTool*>(client);
    if (!self->Paint->isChecked())
      return;
    int pos[2];
    self->Interactor->GetEventPosition(pos);
    if (event == vtkCommand::LeftButtonPressEvent)
    {
      self->Stroking = self->dab(pos[0], pos[1]);
      if (self->Stroking)
        self->Callback->AbortFlagOn();
    }
    else if (event == vtkCommand::MouseMoveEvent && self->Stroking)
    {
      self->Callback->AbortFlagOn();
      self->dab(pos[0], pos[1]);
      self->Window.renderer()->GetRenderWindow()->Render();
    }
    else if (event == vtkCommand::LeftButtonReleaseEvent && self->Stroking)
    {
      self->Callback->AbortFlagOn();
      self->Stroking = false;
      if (self->Painted && self->Window.hasWeights())
        self->Window.compute(); // the weights with the brush (the scene shows the mask)
      self->Painted = false;
    }
  }

  ViewerWindow& Window;
  QCheckBox* Paint;
  QDoubleSpinBox* Radius;
  QDoubleSpinBox* Strength;
  QCheckBox* Erase;
  vtkSmartPointer<vtkCallbackCommand> Callback;
  vtkRenderWindowInteractor* Interactor = nullptr;
  vtkRenderer* Renderer = nullptr;
  bool Stroking = false;
  bool Painted = false;
};
} // namespace

bool SkeletonMode::CanPaint(vtkDataSet* domain)
{
  if (!domain || domain->GetNumberOfPoints() == 0 || domain->GetNumberOfCells() == 0)
    return false;
  for (vtkIdType c = 0; c < domain->GetNumberOfCells(); ++c)
    if (domain->GetCellType(c) != VTK_TRIANGLE && domain->GetCellType(c) != VTK_TETRA)
      return false;
  return true;
}

int SkeletonMode::PaintShapeBrush(
  vtkDataSet* domain, const double center[3], double radius, double value, bool erase)
{
  if (!CanPaint(domain) || !(radius > 0.0))
    return 0;
  auto* rho = vtkDoubleArray::SafeDownCast(domain->GetPointData()->GetArray(BrushArray));
  if (!rho || rho->GetNumberOfTuples() != domain->GetNumberOfPoints() ||
    rho->GetNumberOfComponents() != 1)
  {
    vtkNew<vtkDoubleArray> fresh;
    fresh->SetName(BrushArray);
    fresh->SetNumberOfTuples(domain->GetNumberOfPoints());
    fresh->Fill(0.0);
    domain->GetPointData()->AddArray(fresh);
    rho = fresh;
  }
  int touched = 0;
  for (vtkIdType i = 0; i < domain->GetNumberOfPoints(); ++i)
  {
    double x[3];
    domain->GetPoint(i, x);
    const double d = std::sqrt((x[0] - center[0]) * (x[0] - center[0]) +
      (x[1] - center[1]) * (x[1] - center[1]) + (x[2] - center[2]) * (x[2] - center[2]));
    if (d >= radius)
      continue;
    const double q = 1.0 - (d / radius) * (d / radius), f = q * q;
    const double old = rho->GetValue(i);
    rho->SetValue(i, erase ? old * (1.0 - f) : std::max(old, value * f));
    ++touched;
  }
  rho->Modified();
  domain->Modified();
  return touched;
}

void SkeletonMode::SetShapeBrush(vtkDataSet* domain, const std::vector<double>& values)
{
  if (!domain)
    return;
  if (values.empty())
  {
    domain->GetPointData()->RemoveArray(BrushArray);
    domain->Modified();
    return;
  }
  if (static_cast<vtkIdType>(values.size()) != domain->GetNumberOfPoints())
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the session's shape brush has " + std::to_string(values.size()) +
        " values but the domain has " + std::to_string(domain->GetNumberOfPoints()) + " vertices");
  vtkNew<vtkDoubleArray> rho;
  rho->SetName(BrushArray);
  rho->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    rho->SetValue(static_cast<vtkIdType>(i), values[i]);
  domain->GetPointData()->AddArray(rho);
  domain->Modified();
}

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
  // the painted shape-preservation brush: the domain's painted vertices as orange dots, more
  // opaque where rho is larger (at the rest pose: the brush lives on the undeformed domain)
  const auto found = brush_windows().find(renderer);
  vtkDataSet* domain = found != brush_windows().end() ? found->second->session().domain() : nullptr;
  vtkDataArray* rho = domain ? domain->GetPointData()->GetArray(BrushArray) : nullptr;
  if (rho && rho->GetNumberOfTuples() == domain->GetNumberOfPoints())
  {
    double top = 0.0;
    for (vtkIdType i = 0; i < rho->GetNumberOfTuples(); ++i)
      top = std::max(top, rho->GetComponent(i, 0));
    vtkNew<vtkPoints> dots;
    vtkNew<vtkCellArray> verts;
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetNumberOfComponents(4);
    colors->SetName("BrushColors");
    for (vtkIdType i = 0; top > 0.0 && i < rho->GetNumberOfTuples(); ++i)
    {
      const double v = rho->GetComponent(i, 0) / top;
      if (!(v > 1e-3))
        continue;
      double x[3];
      domain->GetPoint(i, x);
      const vtkIdType id = dots->InsertNextPoint(x);
      verts->InsertNextCell(1, &id);
      const unsigned char c[4] = { 255, 140, 0, static_cast<unsigned char>(60 + 195 * v) };
      colors->InsertNextTypedTuple(c);
    }
    if (dots->GetNumberOfPoints() > 0)
    {
      vtkNew<vtkPolyData> mask;
      mask->SetPoints(dots);
      mask->SetVerts(verts);
      mask->GetPointData()->SetScalars(colors);
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputData(mask);
      mapper->SetColorModeToDirectScalars();
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      actor->GetProperty()->SetPointSize(6.0);
      actor->GetProperty()->SetRenderPointsAsSpheres(true);
      actor->SetPickable(false);
      renderer->AddActor(actor);
    }
  }
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

  // The shape-preservation brush (§3.3, Fig. 5) on a given domain mesh.
  auto* brush = new QHBoxLayout;
  auto* paint = new QCheckBox("Shape brush");
  paint->setObjectName("shape_brush");
  paint->setToolTip("BBW: paint the shape-preservation brush (rho, paper Eq. 7) on the domain "
                    "mesh with the left mouse button; the weights are recomputed when a stroke "
                    "ends. Needs a triangle / tetrahedral domain mesh.");
  auto* radius = new QDoubleSpinBox;
  radius->setObjectName("shape_brush_radius");
  radius->setRange(0.1, 100.0);
  radius->setValue(5.0);
  radius->setSuffix(" %");
  radius->setToolTip("brush radius, in % of the domain's size (soft falloff to 0 at the radius)");
  auto* strength = new QDoubleSpinBox;
  strength->setObjectName("shape_brush_strength");
  strength->setRange(0.0, 1e9);
  strength->setDecimals(0);
  strength->setValue(1e4);
  strength->setToolTip("brush strength s: rho = s / size^2 at the centre (1e4: nearly rigid)");
  auto* erase = new QCheckBox("Erase");
  erase->setObjectName("shape_brush_erase");
  auto* clear = new QPushButton("Clear");
  clear->setObjectName("shape_brush_clear");
  brush->addWidget(paint);
  brush->addWidget(radius);
  brush->addWidget(strength);
  brush->addWidget(erase);
  brush->addWidget(clear);
  deformation->addLayout(brush);
  new ShapeBrushTool(window, paint, radius, strength, erase, paint);
  QObject::connect(clear, &QPushButton::clicked, w, [w]() {
    vtkDataSet* domain = w->session().domain();
    if (!domain || !domain->GetPointData()->GetArray(BrushArray))
      return;
    SetShapeBrush(domain, {});
    if (w->hasWeights())
      w->compute();
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
  vtkDataSet* domain = session.domain();
  if (vtkDataArray* rho = domain ? domain->GetPointData()->GetArray(BrushArray) : nullptr)
  {
    nlohmann::json values = nlohmann::json::array();
    for (vtkIdType i = 0; i < rho->GetNumberOfTuples(); ++i)
      values.push_back(rho->GetComponent(i, 0));
    document["shape_brush"] = values;
  }
}

void SkeletonMode::readSession(const nlohmann::json& document, SessionFile& file) const
{
  if (document.contains("handle_twists") && document["handle_twists"].is_array())
    for (const nlohmann::json& t : document["handle_twists"])
      file.twists.push_back({ t.at(0).get<double>(), t.at(1).get<double>() });
  if (document.contains("shape_brush") && document["shape_brush"].is_array())
    for (const nlohmann::json& v : document["shape_brush"])
    {
      const double rho = v.get<double>();
      if (!std::isfinite(rho) || rho < 0.0)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "the session's shape brush holds a value that is not finite and >= 0");
      file.shape_brush.push_back(rho);
    }
}

QStringList SkeletonMode::commandLineInputs(const Inputs& inputs) const
{
  return { "--handles", ShellQuoted(inputs.controls), "--mesh", ShellQuoted(inputs.domain) };
}

} // namespace viewer
} // namespace barylab
