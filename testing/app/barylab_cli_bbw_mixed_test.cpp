// Command-line tests of BBW with mixed handles (points, bones, an open cage, a region in one
// .vtp with a HandleType cell array) and the shape-preservation brush (--shape-preservation:
// a point array of the mesh or a file): the weights' columns and summary, the brush's effect,
// deformation by moved handles, and clear errors. Part of barylab_cli_test.

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include "cli_test_utils.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace
{
using Result = barylab_test::CommandResult;

Result barylab(const std::string& args)
{
  return barylab_test::RunBarylab(args);
}

class CLIMixedBBW : public ::testing::Test
{
protected:
  void SetUp() override
  {
    dir_ = barylab_test::FreshTestFolder("cli_mixed_");
    WriteInputs();
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }

  /// mesh.vtu: the unit square, 21 x 21 vertices, with the point array "paint" (1e4 on a disk
  /// of radius 0.12 around (0.5, 0.6), 0 elsewhere); paint.txt: the same values, one a line;
  /// handles.vtp: a point handle (0.2, 0.8), a bone (0.5, 0.15)-(0.8, 0.15), an open cage on
  /// x = 1 (joints at y = 0.3, 0.6, 0.9) and a square region [0.1, 0.25] x [0.35, 0.5].
  void WriteInputs()
  {
    const int n = 21;
    Eigen::MatrixXd V(n * n, 2);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        V.row(j * n + i) << i / 20.0, j / 20.0;
    Eigen::MatrixXi T(2 * (n - 1) * (n - 1), 3);
    int t = 0;
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i)
      {
        const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
        T.row(t++) << a, b, c;
        T.row(t++) << a, c, d;
      }
    auto mesh = vtkBaryConversion::SimplicesToGrid(V, T, 0.0);
    vtkNew<vtkDoubleArray> paint;
    paint->SetName("paint");
    paint->SetNumberOfTuples(n * n);
    std::ofstream text(out("paint.txt"));
    text << "# rho per vertex of mesh.vtu\n";
    painted_.clear();
    for (int i = 0; i < n * n; ++i)
    {
      const bool in = (V.row(i) - Eigen::RowVector2d(0.5, 0.6)).norm() <= 0.12;
      paint->SetValue(i, in ? 1e4 : 0.0);
      text << (in ? 1e4 : 0.0) << "\n";
      if (in)
        painted_.push_back(i);
    }
    mesh->GetPointData()->AddArray(paint);
    vtkBaryDataIO::Write(mesh, out("mesh.vtu"));

    vtkNew<vtkPolyData> h;
    vtkNew<vtkPoints> p;
    for (const auto& x : std::vector<std::array<double, 2>>{ { 0.2, 0.8 }, { 0.5, 0.15 },
           { 0.8, 0.15 }, { 1, 0.3 }, { 1, 0.6 }, { 1, 0.9 }, { 0.1, 0.35 }, { 0.25, 0.35 },
           { 0.25, 0.5 }, { 0.1, 0.5 } })
      p->InsertNextPoint(x[0], x[1], 0.0);
    h->SetPoints(p);
    vtkNew<vtkCellArray> lines, polys;
    const vtkIdType bone[2] = { 1, 2 }, cage[3] = { 3, 4, 5 }, region[4] = { 6, 7, 8, 9 };
    lines->InsertNextCell(2, bone);
    lines->InsertNextCell(3, cage);
    polys->InsertNextCell(4, region);
    h->SetLines(lines);
    h->SetPolys(polys);
    vtkNew<vtkIntArray> kind;
    kind->SetName("HandleType");
    for (int k : { 1, 2, 3 })
      kind->InsertNextValue(k);
    h->GetCellData()->AddArray(kind);
    vtkBaryDataIO::Write(h, out("handles.vtp"));
  }

  Eigen::MatrixXd Weights(const std::string& file) const
  {
    auto data = vtkBaryDataIO::Read(out(file)); // kept alive while its array is read
    vtkDataArray* w = data->GetPointData()->GetArray("Weights");
    return w ? Eigen::MatrixXd(vtkBaryConversion::ArrayToMatrix(w)) : Eigen::MatrixXd();
  }

  /// The largest range max - min of any weight over the painted vertices.
  double PaintedRange(const Eigen::MatrixXd& W) const
  {
    double worst = 0;
    for (Eigen::Index j = 0; j < W.cols(); ++j)
    {
      double lo = 1, hi = 0;
      for (int i : painted_)
      {
        lo = std::min(lo, W(i, j));
        hi = std::max(hi, W(i, j));
      }
      worst = std::max(worst, hi - lo);
    }
    return worst;
  }

  std::string Inputs() const
  {
    return " --method bbw --fast --handles " + out("handles.vtp") + " --mesh " + out("mesh.vtu");
  }

  fs::path dir_;
  std::vector<int> painted_;
};

TEST_F(CLIMixedBBW, WeightsOfMixedHandlesAndTheBrushFromAnArrayOrAFile)
{
  const Result plain = barylab("weights" + Inputs() + " --output " + out("w.vtu") + " --json " +
    out("w.json"));
  ASSERT_EQ(plain.code, 0) << plain.output;
  EXPECT_NE(plain.output.find("6 handles (1 points, 1 bones, 3 cage vertices, 1 regions; 2D)"),
    std::string::npos) << plain.output;
  std::ifstream in(out("w.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["handles"]["cage_vertices"], 3);
  EXPECT_EQ(s["handles"]["regions"], 1);
  EXPECT_EQ(s["handles"]["shape_preservation"], false);
  const Eigen::MatrixXd W = Weights("w.vtu");
  ASSERT_EQ(W.cols(), 6);
  EXPECT_NEAR(W(16 * 21 + 4, 0), 1.0, 1e-14);         // the point handle's vertex
  // (1, 0.45): halfway along the cage (to float rounding: the files store float coordinates)
  EXPECT_NEAR(W(9 * 21 + 20, 2), 0.5, 1e-6);
  EXPECT_NEAR(W(9 * 21 + 4, 5), 1.0, 1e-14);          // (0.2, 0.45): inside the region
  EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);

  const Result by_array = barylab("weights" + Inputs() + " --shape-preservation paint --output " +
    out("a.vtu") + " -q");
  ASSERT_EQ(by_array.code, 0) << by_array.output;
  const Result by_file = barylab("weights" + Inputs() + " --shape-preservation " +
    out("paint.txt") + " --output " + out("f.vtu") + " -q");
  ASSERT_EQ(by_file.code, 0) << by_file.output;
  const Eigen::MatrixXd A = Weights("a.vtu"), F = Weights("f.vtu");
  EXPECT_LE((A - F).cwiseAbs().maxCoeff(), 1e-14) << "the same brush, as an array or a file";
  const double before = PaintedRange(W), after = PaintedRange(A);
  std::cout << "[ info ] largest weight range over the painted disk: " << before << " -> "
            << after << "\n";
  EXPECT_LT(after, 0.1 * before);
}

TEST_F(CLIMixedBBW, DeformByMovedHandlesTranslatesRigidly)
{
  // Every joint translated by t: bones and the region get the identity rotation, cage vertices
  // their displacement t, the point handle t: the domain moves by t exactly.
  auto handles = vtkBaryDataIO::Read(out("handles.vtp"));
  {
    std::ofstream obj(out("posed.obj"));
    obj.precision(17);
    for (vtkIdType i = 0; i < handles->GetNumberOfPoints(); ++i)
    {
      double x[3];
      handles->GetPoint(i, x);
      obj << "v " << x[0] + 0.3 << " " << x[1] - 0.2 << " 0\n";
    }
  }
  const Result r = barylab("deform" + Inputs() + " --points " + out("mesh.vtu") +
    " --deformed-handles " + out("posed.obj") + " --output " + out("d.vtu") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto rest = vtkBaryDataIO::Read(out("mesh.vtu"));
  auto moved = vtkBaryDataIO::Read(out("d.vtu"));
  double worst = 0;
  for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    rest->GetPoint(i, x);
    moved->GetPoint(i, y);
    worst = std::max(worst, std::hypot(y[0] - x[0] - 0.3, y[1] - x[1] + 0.2));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST_F(CLIMixedBBW, BadBrushesAreClearErrors)
{
  auto expect_error = [&](const std::string& args, const std::string& needle, int code = 1) {
    const Result r = barylab(args);
    EXPECT_EQ(r.code, code) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in\n"
                                                        << r.output;
    EXPECT_FALSE(fs::exists(out("x.vtu")));
  };
  expect_error("weights" + Inputs() + " --shape-preservation nosuch --output " + out("x.vtu"),
    "neither a file nor a point-data array");
  std::ofstream(out("short.txt")) << "1 2 3\n";
  expect_error("weights" + Inputs() + " --shape-preservation " + out("short.txt") + " --output " +
      out("x.vtu"),
    "has 3 values but the domain");
  {
    std::ofstream bad(out("bad.txt"));
    for (int i = 0; i < 441; ++i)
      bad << (i == 7 ? -1.0 : 0.0) << "\n";
  }
  expect_error("weights" + Inputs() + " --shape-preservation " + out("bad.txt") + " --output " +
      out("x.vtu"),
    "negative at vertex 7");
  expect_error("weights --method bbw --cage " + out("handles.vtp") + " --shape-preservation paint"
      " --points " + out("mesh.vtu") + " --output " + out("x.vtu"),
    "--shape-preservation is for --method bbw with a domain mesh", 2);
}

// Hostile handles, regions and brushes: each a clear error naming the problem, exit code 1, no
// output file (never a crash, a hang or weights computed from a misread file).
TEST_F(CLIMixedBBW, HostileHandlesRegionsAndBrushesAreClearErrors)
{
  auto expect_error = [&](const std::string& args, const std::string& needle) {
    fs::remove(out("x.vtu"));
    const Result r = barylab(args + " --output " + out("x.vtu"));
    EXPECT_EQ(r.code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in\n"
                                                        << r.output;
    EXPECT_FALSE(fs::exists(out("x.vtu")));
  };
  const std::string mesh = " --mesh " + out("mesh.vtu");
  const auto handles_with = [&](const std::string& name, auto edit) {
    auto h = vtkBaryDataIO::Read(out("handles.vtp"));
    vtkPolyData* poly = vtkPolyData::SafeDownCast(h);
    edit(poly);
    vtkBaryDataIO::Write(poly, out(name));
    return " --method bbw --fast --handles " + out(name) + mesh;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // a NaN handle point (refused as the file is read)
  expect_error("weights" + handles_with("nan.vtp", [&](vtkPolyData* h) { h->GetPoints()->SetPoint(4, nan, 0.6, 0); }),
    "point 4 has a non-finite coordinate");
  // HandleType: text instead of numbers (ignored before: the region read as a cage), too few
  // values (fractions and unknown kinds: TestvtkBaryMixedHandles)
  expect_error("weights" + handles_with("text.vtp", [&](vtkPolyData* h) {
    h->GetCellData()->RemoveArray("HandleType");
    vtkNew<vtkStringArray> kind;
    kind->SetName("HandleType");
    for (const char* k : { "bone", "cage", "region" })
      kind->InsertNextValue(k);
    h->GetCellData()->AddArray(kind);
  }),
    "HandleType is not numeric");
  expect_error("weights" + handles_with("short.vtp", [&](vtkPolyData* h) {
    vtkNew<vtkIntArray> kind;
    kind->SetName("HandleType");
    kind->InsertNextValue(1);
    h->GetCellData()->AddArray(kind); // replaces the 3-value array
  }),
    "Cannot read cell data array \"HandleType\""); // VTK's reader refuses it
  // RegionId: text (ignored before), NaN
  expect_error("weights" + handles_with("rtext.vtp", [&](vtkPolyData* h) {
    vtkNew<vtkStringArray> id;
    id->SetName("RegionId");
    for (const char* k : { "a", "b", "c" })
      id->InsertNextValue(k);
    h->GetCellData()->AddArray(id);
  }),
    "RegionId is not numeric");
  expect_error("weights" + handles_with("rnan.vtp", [&](vtkPolyData* h) {
    vtkNew<vtkDoubleArray> id;
    id->SetName("RegionId");
    for (double k : { 0.0, 0.0, nan })
      id->InsertNextValue(k);
    h->GetCellData()->AddArray(id);
  }),
    "handle cell 2's RegionId is nan");
  // a region with no mesh vertex inside it (a square between the grid's vertices)
  expect_error("weights" + handles_with("empty.vtp", [&](vtkPolyData* h) {
    const double square[4][2] = { { 0.11, 0.36 }, { 0.14, 0.36 }, { 0.14, 0.39 }, { 0.11, 0.39 } };
    for (int k = 0; k < 4; ++k)
      h->GetPoints()->SetPoint(6 + k, square[k][0], square[k][1], 0);
  }),
    "region 0");
  // the domain's HandleRegion array as text (ignored before)
  {
    auto m = vtkBaryDataIO::Read(out("mesh.vtu"));
    vtkNew<vtkStringArray> region;
    region->SetName("HandleRegion");
    region->SetNumberOfValues(m->GetNumberOfPoints());
    for (vtkIdType i = 0; i < m->GetNumberOfPoints(); ++i)
      region->SetValue(i, "-1");
    vtkDataSet::SafeDownCast(m)->GetPointData()->AddArray(region);
    vtkBaryDataIO::Write(m, out("textregion.vtu"));
  }
  expect_error("weights --method bbw --fast --handles " + out("handles.vtp") + " --mesh " +
      out("textregion.vtu"),
    "HandleRegion is not numeric");
  // brushes with NaN or a negative value: from a file and from a point array
  for (const std::string value : { "nan", "-2" })
  {
    {
      std::ofstream bad(out("brush.txt"));
      for (int i = 0; i < 441; ++i)
        bad << (i == 30 ? value : std::string("0")) << "\n";
    }
    expect_error("weights" + Inputs() + " --shape-preservation " + out("brush.txt"),
      value == "-2" ? "negative at vertex 30" : "line 31 holds NaN or infinity");
    auto m = vtkBaryDataIO::Read(out("mesh.vtu"));
    vtkDataArray* paint = vtkDataSet::SafeDownCast(m)->GetPointData()->GetArray("paint");
    paint->SetComponent(30, 0, std::stod(value));
    vtkBaryDataIO::Write(m, out("badpaint.vtu"));
    expect_error("weights --method bbw --fast --handles " + out("handles.vtp") + " --mesh " +
        out("badpaint.vtu") + " --shape-preservation paint",
      "vertex 30");
  }
  // a brush array with 3 components
  {
    auto m = vtkBaryDataIO::Read(out("mesh.vtu"));
    vtkNew<vtkDoubleArray> three;
    three->SetName("paint");
    three->SetNumberOfComponents(3);
    three->SetNumberOfTuples(m->GetNumberOfPoints());
    three->Fill(0.0);
    vtkDataSet::SafeDownCast(m)->GetPointData()->AddArray(three);
    vtkBaryDataIO::Write(m, out("paint3.vtu"));
  }
  expect_error("weights --method bbw --fast --handles " + out("handles.vtp") + " --mesh " +
      out("paint3.vtu") + " --shape-preservation paint",
    "has 3 components");
}
} // namespace
