// Tests of the spline filters (BaryLab::BaryLabSpline): the grid of Bézier triangles against
// VTK's own Bézier triangle evaluation (an independent implementation of the same polynomials),
// C1 continuity seen through the exported cells, edits, 2D and 2.5D deformation, errors.
#include "filters_test_utils.h"

#include "vtkBarySplineData.h"
#include "core/common/error.h"
#include "vtkBarySplineDeform.h"
#include "vtkBarySplineEdit.h"
#include "vtkBarySplineSource.h"

#include "vtkBezierTriangle.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using barylab_test::ErrorObserver;

namespace
{

/// A 6 x 4 grid of squares on [-1, 0.5] x [-0.5, 0.5], diagonals alternating, as triangles.
vtkSmartPointer<vtkPolyData> GridDomain()
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  auto pts = vtkSmartPointer<vtkPoints>::New();
  const int nx = 6, ny = 4;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      pts->InsertNextPoint(-1.0 + 0.25 * i, -0.5 + 0.25 * j, 0.0);
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      const vtkIdType t1[3] = { a, b, c }, t2[3] = { a, c, d }, t3[3] = { a, b, d }, t4[3] = { b, c, d };
      polys->InsertNextCell(3, (i + j) % 2 ? t3 : t1);
      polys->InsertNextCell(3, (i + j) % 2 ? t4 : t2);
    }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

vtkSmartPointer<vtkUnstructuredGrid> Edited(vtkUnstructuredGrid* grid, bool prism = false)
{
  auto edit = vtkSmartPointer<vtkBarySplineEdit>::New();
  edit->SetInputData(grid);
  std::vector<vtkBarySplineEdit::Edit> edits;
  for (int k = 0; k < 6; ++k)
  {
    vtkBarySplineEdit::Edit e;
    e.edit.near = { Eigen::Vector2d(-0.8 + 0.23 * k, -0.3 + 0.1 * k) };
    e.edit.by = Eigen::Vector2d(0.03 * std::cos(k), 0.03 * std::sin(k));
    e.edit.delta_max = k % 3;
    edits.push_back(e);
  }
  if (prism)
  {
    vtkBarySplineEdit::Edit e;
    e.target = vtkBarySplineEdit::TOP;
    e.edit.near = { Eigen::Vector2d(-0.25, 0.0) };
    e.edit.by = Eigen::VectorXd::Constant(1, 0.2);
    e.edit.delta_max = 4;
    edits.push_back(e);
  }
  edit->SetEdits(edits);
  edit->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(edit->GetOutput());
  return out;
}

vtkSmartPointer<vtkUnstructuredGrid> Identity(bool prism = false)
{
  auto source = vtkSmartPointer<vtkBarySplineSource>::New();
  source->SetInputData(GridDomain());
  source->SetPrism(prism);
  source->SetPrismBottom(-0.2);
  source->SetPrismTop(0.2);
  source->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(source->GetOutput());
  return out;
}

/// VTK's evaluation of cell c at parametric (r, s): barycentric (1 - r - s, r, s).
Eigen::Vector2d VTKEvaluate(vtkUnstructuredGrid* grid, vtkIdType c, double r, double s)
{
  auto cell = vtkSmartPointer<vtkGenericCell>::New();
  grid->GetCell(c, cell);
  double pc[3] = { r, s, 0 }, x[3], w[128];
  int sub = 0;
  cell->EvaluateLocation(sub, pc, x, w);
  return { x[0], x[1] };
}

} // namespace

TEST(vtkBarySpline, GridRoundTripAndVTKEvaluation)
{
  const auto identity = Identity();
  EXPECT_EQ(identity->GetNumberOfCells(), 48);
  EXPECT_EQ(identity->GetCellType(0), VTK_BEZIER_TRIANGLE);
  EXPECT_EQ(identity->GetCell(0)->GetNumberOfPoints(), 21);
  const auto grid = Edited(identity);
  const vtkBarySpline spline = vtkBarySplineData::FromGrid(grid);
  ASSERT_TRUE(spline.xy);
  EXPECT_EQ(spline.xy->net().degree(), 5);
  // Round trip: the same values, bit for bit.
  const vtkBarySpline again = vtkBarySplineData::FromGrid(vtkBarySplineData::ToGrid(spline));
  EXPECT_EQ(again.xy->values(), spline.xy->values());
  EXPECT_GT((spline.xy->values() - spline.xy->net().nominal()).norm(), 0.01);
  // VTK's Bézier triangle evaluates the same polynomial (an independent implementation).
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    double r = u(rng), s = u(rng);
    if (r + s > 1)
    {
      r = 1 - r;
      s = 1 - s;
    }
    const Eigen::RowVectorXd ours = spline.xy->evaluate(c, Eigen::Vector3d(1 - r - s, r, s));
    EXPECT_LT((VTKEvaluate(grid, c, r, s) - ours.transpose()).norm(), 1e-13) << "cell " << c;
  }
}

// C1 across interior edges, measured through the exported cells with VTK's evaluation: the
// derivative across the edge (second-order one-sided differences from each side) agrees; a
// spline with one control point moved off its C1 position shows a jump.
TEST(vtkBarySpline, C1ThroughTheExportedCells)
{
  const auto grid = Edited(Identity());
  auto jump = [](vtkUnstructuredGrid* g) {
    const vtkBarySpline sp = vtkBarySplineData::FromGrid(g);
    const auto& net = sp.xy->net();
    double worst = 0;
    const double h = 1e-5;
    for (bary::Index e = 0; e < net.edges().rows(); ++e)
    {
      const int u = net.edge_triangles()(e, 0), v = net.edge_triangles()(e, 1);
      if (u < 0 || v < 0)
        continue;
      const Eigen::Vector2d P = net.vertices().row(net.edges()(e, 0)), Q = net.vertices().row(net.edges()(e, 1));
      const Eigen::Vector2d n = Eigen::Vector2d(-(Q - P).y(), (Q - P).x()).normalized(); // into u
      for (double a : { 0.2, 0.5, 0.8 })
      {
        const Eigen::Vector2d x = P + a * (Q - P);
        auto at = [&](int t, const Eigen::Vector2d& y) {
          const Eigen::Vector3d b = net.barycentric(t, y);
          return VTKEvaluate(g, t, b[1], b[2]);
        };
        const Eigen::Vector2d du = (-3 * at(u, x) + 4 * at(u, x + h * n) - at(u, x + 2 * h * n)) / (2 * h);
        const Eigen::Vector2d dv = -(-3 * at(v, x) + 4 * at(v, x - h * n) - at(v, x - 2 * h * n)) / (2 * h);
        worst = std::max(worst, (du - dv).norm());
      }
    }
    return worst;
  };
  EXPECT_LT(jump(grid), 1e-7);
  auto broken = vtkSmartPointer<vtkUnstructuredGrid>::New();
  broken->DeepCopy(grid);
  // An inner corner (type 3) moved: no longer C1.
  vtkDataArray* type = broken->GetPointData()->GetArray("ControlPointType");
  vtkIdType p = 0;
  while (type->GetComponent(p, 0) != 3)
    ++p;
  double x[3];
  broken->GetPoint(p, x);
  x[0] += 0.05;
  broken->GetPoints()->SetPoint(p, x);
  EXPECT_GT(jump(broken), 0.1);
}

TEST(vtkBarySpline, EditReportsAndErrors)
{
  auto edit = vtkSmartPointer<vtkBarySplineEdit>::New();
  edit->SetInputData(Identity());
  vtkBarySplineEdit::Edit e;
  e.edit.near = { Eigen::Vector2d(-0.5, 0.0) };
  e.edit.op = bary::SplineEditOp::Rotate;
  e.edit.center = Eigen::Vector2d(-0.5, 0.0);
  e.edit.angle_degrees = 20;
  e.edit.delta_max = 3;
  edit->SetEdits({ e });
  edit->Update();
  vtkFieldData* fd = edit->GetOutput()->GetFieldData();
  ASSERT_NE(fd->GetArray("Derived"), nullptr);
  EXPECT_GT(fd->GetArray("Derived")->GetComponent(0, 0), 10);
  EXPECT_LT(fd->GetArray("Residual")->GetComponent(0, 0), 1e-13);
  EXPECT_GT(fd->GetArray("MinJacobian")->GetComponent(0, 0), 0.0);
  // A bottom-surface edit on a spline that is not a prism; an unknown control point.
  auto errors = vtkSmartPointer<ErrorObserver>::New();
  errors->Attach(edit);
  e.target = vtkBarySplineEdit::BOTTOM;
  edit->SetEdits({ e });
  edit->Update();
  EXPECT_TRUE(errors->HasError("not a 2.5D")) << errors->AllErrors();
  errors->Clear();
  e.target = vtkBarySplineEdit::XY;
  e.edit.near.clear();
  e.edit.anchors = { 100000 };
  edit->SetEdits({ e });
  edit->Update();
  EXPECT_TRUE(errors->HasError("edit 0: anchor 100000 is not a control point")) << errors->AllErrors();
}

TEST(vtkBarySpline, DeformInTwoAndTwoAndAHalfDimensions)
{
  // Model points: a small grid inside the domain, z in [-0.1, 0.1].
  auto model = vtkSmartPointer<vtkPolyData>::New();
  auto pts = vtkSmartPointer<vtkPoints>::New();
  for (int k = 0; k < 200; ++k)
    pts->InsertNextPoint(-0.9 + 1.3 * ((k * 37) % 200) / 200.0, -0.4 + 0.8 * ((k * 91) % 200) / 200.0,
      -0.1 + 0.2 * (k % 7) / 6.0);
  model->SetPoints(pts);
  for (bool prism : { false, true })
  {
    const auto grid = Edited(Identity(prism), prism);
    auto deform = vtkSmartPointer<vtkBarySplineDeform>::New();
    deform->SetInputData(model);
    deform->SetSplineData(grid);
    deform->Update();
    vtkPointSet* out = vtkPointSet::SafeDownCast(deform->GetOutput());
    ASSERT_EQ(out->GetNumberOfPoints(), 200);
    const vtkBarySpline sp = vtkBarySplineData::FromGrid(grid);
    bary::Points P(200, 2);
    for (vtkIdType p = 0; p < 200; ++p)
      P.row(p) << pts->GetPoint(p)[0], pts->GetPoint(p)[1];
    const auto where = sp.xy->locate(P);
    const Eigen::MatrixXd Q = sp.xy->evaluate(where);
    double moved_z = 0;
    for (vtkIdType p = 0; p < 200; ++p)
    {
      double x[3];
      out->GetPoint(p, x);
      EXPECT_NEAR(x[0], Q(p, 0), 1e-14);
      EXPECT_NEAR(x[1], Q(p, 1), 1e-14);
      const double z = pts->GetPoint(p)[2];
      if (!prism)
      {
        EXPECT_EQ(x[2], z);
      }
      else
      {
        // z' = sigma0 + (z - bottom) / (top - bottom) (sigma1 - sigma0), sigma0 = -0.2 here.
        const double top = sp.top->evaluate(where)(p, 0);
        EXPECT_NEAR(x[2], -0.2 + (z + 0.2) / 0.4 * (top + 0.2), 1e-14);
        moved_z = std::max(moved_z, std::abs(x[2] - z));
      }
    }
    if (prism)
    {
      EXPECT_GT(moved_z, 0.01);
    }
    ASSERT_NE(out->GetPointData()->GetArray("SplineJacobian"), nullptr);
  }
  // A point outside the domain.
  auto errors = vtkSmartPointer<ErrorObserver>::New();
  auto deform = vtkSmartPointer<vtkBarySplineDeform>::New();
  errors->Attach(deform);
  auto bad = vtkSmartPointer<vtkPolyData>::New();
  auto bp = vtkSmartPointer<vtkPoints>::New();
  bp->InsertNextPoint(0, 0, 0);
  bp->InsertNextPoint(3, 0, 0);
  bad->SetPoints(bp);
  deform->SetInputData(bad);
  deform->SetSplineData(Identity());
  deform->Update();
  EXPECT_TRUE(errors->HasError("1 of 2 points lie outside the spline's domain")) << errors->AllErrors();
}

TEST(vtkBarySpline, RefusesGridsItDidNotWrite)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->DeepCopy(Identity());
  grid->GetPointData()->RemoveArray("Nominal");
  EXPECT_THROW(vtkBarySplineData::FromGrid(grid), bary::Error);
  try
  {
    vtkBarySplineData::FromGrid(grid);
  }
  catch (const bary::Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("no 'Nominal'"), std::string::npos);
  }
}
