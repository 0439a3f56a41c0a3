// Command-line tests of barylab export-transform and warp-image (issue 15): the field's voxels
// hold what `barylab deform` does to the voxel points; the inverse's residuals, folds and the
// grid are in the JSON summary; a RAS field is the LPS one with x and y negated; a label map
// warped through a translation by whole voxels is shifted exactly, with --transform (inverted
// here) and with --inverse-transform; the identity leaves it unchanged; usage and input errors
// exit 2 and 1 and leave no file. Part of barylab_cli_test.

#include "vtkBaryDataIO.h"
#include "vtkBaryImageIO.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkUnsignedCharArray.h"

#include "cli_test_utils.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace
{
using TransformRun = barylab_test::CommandResult;

TransformRun run_transform(const std::string& args)
{
  return barylab_test::RunBarylab(args);
}

class TransformCLI : public ::testing::Test
{
protected:
  void SetUp() override
  {
    dir_ = barylab_test::FreshTestFolder("cli_transform_");
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }

  /// A cube cage [c - 20, c + 20]^3 mm (c = (10, -5, 30)) as .obj, each vertex moved by
  /// @p move (x, y, z) -> (x', y', z').
  template<class Move>
  std::string Cube(const std::string& name, Move&& move) const
  {
    const double corners[8][3] = { { -1, -1, -1 }, { 1, -1, -1 }, { 1, 1, -1 }, { -1, 1, -1 },
      { -1, -1, 1 }, { 1, -1, 1 }, { 1, 1, 1 }, { -1, 1, 1 } };
    const int faces[12][3] = { { 0, 3, 2 }, { 0, 2, 1 }, { 4, 5, 6 }, { 4, 6, 7 }, { 0, 1, 5 },
      { 0, 5, 4 }, { 1, 2, 6 }, { 1, 6, 5 }, { 2, 3, 7 }, { 2, 7, 6 }, { 3, 0, 4 }, { 3, 4, 7 } };
    std::ofstream f(out(name));
    f.precision(17);
    for (const auto& c : corners)
    {
      std::array<double, 3> x = { 10 + 20 * c[0], -5 + 20 * c[1], 30 + 20 * c[2] };
      x = move(x);
      f << "v " << x[0] << " " << x[1] << " " << x[2] << "\n";
    }
    for (const auto& t : faces)
      f << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
    return out(name);
  }

  /// A label map (30 x 25 x 20 voxels of 2 mm around the cage): 1 in a box, 7 in a smaller one.
  std::string Labels() const
  {
    vtkNew<vtkImageData> image;
    image->SetExtent(0, 29, 0, 24, 0, 19);
    image->SetOrigin(10 - 29.0, -5 - 24.0, 30 - 19.0);
    image->SetSpacing(2, 2, 2);
    vtkNew<vtkUnsignedCharArray> labels;
    labels->SetNumberOfTuples(30 * 25 * 20);
    for (int k = 0; k < 20; ++k)
      for (int j = 0; j < 25; ++j)
        for (int i = 0; i < 30; ++i)
          labels->SetValue(i + 30 * (j + 25 * k),
            (i >= 10 && i < 15 && j >= 8 && j < 12 && k >= 7 && k < 10) ? 7
              : (i >= 5 && i < 25 && j >= 5 && j < 20 && k >= 4 && k < 16) ? 1
                                                                            : 0);
    image->GetPointData()->SetScalars(labels);
    vtkBaryImageIO::Write(image, out("labels.nii.gz"));
    return out("labels.nii.gz");
  }
  fs::path dir_;
};

std::array<double, 3> Bend(std::array<double, 3> x)
{
  if (x[2] > 30)
    x[0] += 6.0;
  else
    x[1] -= 0.05 * (x[1] + 5);
  return x;
}

TEST_F(TransformCLI, FieldHoldsTheDeformationOfTheVoxelPointsAndTheSummarySaysSo)
{
  const std::string rest = Cube("rest.obj", [](auto x) { return x; });
  const std::string moved = Cube("moved.obj", Bend);
  const TransformRun r = run_transform("export-transform --cage " + rest + " --deformed-cage " +
    moved + " --spacing 4 --margin 2 --output " + out("field.mha") + " --inverse " +
    out("inverse.nrrd") + " --json " + out("summary.json") + " --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json s;
  std::ifstream(out("summary.json")) >> s;
  // bounds [-12, 32] x [-27, 17] x [8, 52] at 4 mm: 12 voxels per axis
  EXPECT_EQ(s["grid"]["size"], nlohmann::json({ 12, 12, 12 }));
  EXPECT_EQ(s["grid"]["origin"], nlohmann::json({ -12.0, -27.0, 8.0 }));
  EXPECT_EQ(s["space"], "LPS");
  EXPECT_EQ(s["jacobian"]["folded_voxels"], 0);
  EXPECT_GT(s["jacobian"]["minimum"].get<double>(), 0.0);
  EXPECT_LE(s["inverse"]["mean_residual"].get<double>(), s["inverse"]["max_residual"].get<double>());
  EXPECT_GT(s["inverse"]["tolerance"].get<double>(), 0.0);
  EXPECT_TRUE(s["seconds"].contains("field"));
  // the field at a few voxels against `barylab deform` of those voxel points
  auto field = vtkBaryImageIO::Read(out("field.mha"));
  vtkDataArray* u = field->GetPointData()->GetScalars();
  ASSERT_NE(u, nullptr);
  ASSERT_EQ(u->GetNumberOfComponents(), 3);
  {
    std::ofstream pts(out("points.obj"));
    pts.precision(17);
    for (const vtkIdType v : { 0, 100, 777, 1727 })
    {
      double p[3];
      field->GetPoint(v, p);
      pts << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
    }
  }
  ASSERT_EQ(run_transform("deform --cage " + rest + " --deformed-cage " + moved + " --points " +
              out("points.obj") + " --output " + out("moved.vtp") + " --quiet")
              .code,
    0);
  const vtkSmartPointer<vtkDataSet> moved_data = vtkBaryDataIO::Read(out("moved.vtp"));
  auto* deformed = vtkPointSet::SafeDownCast(moved_data);
  ASSERT_NE(deformed, nullptr);
  int row = 0;
  for (const vtkIdType v : { 0, 100, 777, 1727 })
  {
    double p[3], q[3];
    field->GetPoint(v, p);
    deformed->GetPoint(row++, q);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(u->GetComponent(v, a), q[a] - p[a], 1e-9) << "voxel " << v;
  }
  // RAS: the same field with the origin, the direction's rows and the displacements' x and y
  // negated
  ASSERT_EQ(run_transform("export-transform --cage " + rest + " --deformed-cage " + moved +
              " --spacing 4 --margin 2 --space RAS --output " + out("ras.nii.gz") + " --quiet")
              .code,
    0);
  auto ras = vtkBaryImageIO::Read(out("ras.nii.gz"));
  double o[3];
  ras->GetOrigin(o);
  EXPECT_NEAR(o[0], 12.0, 1e-9);
  EXPECT_NEAR(o[1], 27.0, 1e-9);
  EXPECT_NEAR(o[2], 8.0, 1e-9);
  vtkDataArray* w = ras->GetPointData()->GetScalars();
  for (const vtkIdType v : { 0, 100, 777, 1727 })
  {
    EXPECT_NEAR(w->GetComponent(v, 0), -u->GetComponent(v, 0), 1e-9);
    EXPECT_NEAR(w->GetComponent(v, 1), -u->GetComponent(v, 1), 1e-9);
    EXPECT_NEAR(w->GetComponent(v, 2), u->GetComponent(v, 2), 1e-9);
  }
}

TEST_F(TransformCLI, WarpShiftsLabelsByWholeVoxelsAndTheIdentityChangesNothing)
{
  const std::string labels = Labels();
  const std::string rest = Cube("rest.obj", [](auto x) { return x; });
  const std::string shifted = Cube("shifted.obj", [](auto x) {
    x[1] += 4.0; // 2 voxels along j (posterior)
    return x;
  });
  auto input = vtkBaryImageIO::Read(labels);
  vtkDataArray* in = input->GetPointData()->GetScalars();
  for (const bool identity : { true, false })
  {
    const std::string moved = identity ? rest : shifted;
    ASSERT_EQ(run_transform("export-transform --cage " + rest + " --deformed-cage " + moved +
                " --reference " + labels + " --output " + out("f.nii.gz") + " --inverse " +
                out("inv.nii.gz") + " --quiet")
                .code,
      0);
    for (const std::string& how : { "--inverse-transform " + out("inv.nii.gz"),
           "--transform " + out("f.nii.gz") })
    {
      fs::remove(out("warped.nii.gz"));
      const TransformRun r = run_transform("warp-image --image " + labels + " " + how +
        " --interpolation nearest --output " + out("warped.nii.gz") + " --json " +
        out("warp.json") + " --quiet");
      ASSERT_EQ(r.code, 0) << r.output;
      auto warped = vtkBaryImageIO::Read(out("warped.nii.gz"));
      vtkDataArray* res = warped->GetPointData()->GetScalars();
      ASSERT_NE(res, nullptr);
      EXPECT_EQ(res->GetDataType(), in->GetDataType());
      const int s = identity ? 0 : 2;
      for (int k = 0; k < 20; ++k)
        for (int j = 0; j < 25; ++j)
          for (int i = 0; i < 30; ++i)
            ASSERT_EQ(res->GetComponent(i + 30 * (j + 25 * k), 0),
              j - s >= 0 ? in->GetComponent(i + 30 * (j - s + 25 * k), 0) : 0.0)
              << how << " " << i << " " << j << " " << k;
    }
  }
}

TEST_F(TransformCLI, AnimateWritesPerFrameFieldsAndWarpedLabelMaps)
{
  const std::string labels = Labels();
  const std::string rest = Cube("rest.obj", [](auto x) { return x; });
  const std::string shifted = Cube("shifted.obj", [](auto x) {
    x[1] += 4.0; // 2 voxels along j
    return x;
  });
  fs::create_directories(out("anim"));
  const TransformRun r = run_transform("animate --cage " + rest + " --frames " + rest + " " +
    shifted + " --points " + rest + " --output-dir " + out("anim") +
    " --displacement-fields --field-format .nrrd --warp-image " + labels + " --json " +
    out("anim.json") + " --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json s;
  std::ifstream(out("anim.json")) >> s;
  EXPECT_EQ(s["transforms"]["fields"],
    nlohmann::json({ "animation_field_000.nrrd", "animation_field_001.nrrd" }));
  EXPECT_EQ(s["transforms"]["frames"][0]["inverse"]["not_converged"], 0);
  auto input = vtkBaryImageIO::Read(labels);
  vtkDataArray* in = input->GetPointData()->GetScalars();
  for (const int frame : { 0, 1 })
  {
    // the field: zero for the rest frame, 4 mm along y for the shifted one (a translation of
    // the cage moves every point by it)
    auto field = vtkBaryImageIO::Read(out("anim/animation_field_00" + std::to_string(frame) + ".nrrd"));
    vtkDataArray* u = field->GetPointData()->GetScalars();
    ASSERT_EQ(u->GetNumberOfTuples(), 30 * 25 * 20);
    for (const vtkIdType v : { 0, 4321, 14999 })
      EXPECT_NEAR(u->GetComponent(v, 1), frame == 1 ? 4.0 : 0.0, 1e-9);
    auto warped = vtkBaryImageIO::Read(out("anim/animation_warped_00" + std::to_string(frame) + ".nii.gz"));
    vtkDataArray* res = warped->GetPointData()->GetScalars();
    const int sh = frame == 1 ? 2 : 0;
    for (int k = 0; k < 20; ++k)
      for (int j = 0; j < 25; ++j)
        for (int i = 0; i < 30; ++i)
          ASSERT_EQ(res->GetComponent(i + 30 * (j + 25 * k), 0),
            j - sh >= 0 ? in->GetComponent(i + 30 * (j - sh + 25 * k), 0) : 0.0)
            << frame << ": " << i << " " << j << " " << k;
  }
  // the grid options without a field or a warp, and both grids, are usage errors
  EXPECT_EQ(run_transform("animate --cage " + rest + " --frames " + rest + " --points " + rest +
              " --output-dir " + out("anim") + " --field-spacing 2")
              .code,
    2);
  EXPECT_EQ(run_transform("animate --cage " + rest + " --frames " + rest + " --points " + rest +
              " --output-dir " + out("anim") + " --displacement-fields --field-spacing 2 "
              "--field-reference " + labels)
              .code,
    2);
}

TEST_F(TransformCLI, BadCommandLinesAndInputs)
{
  const std::string rest = Cube("rest.obj", [](auto x) { return x; });
  const std::string base = "export-transform --cage " + rest + " --deformed-cage " + rest;
  // the grid: one of --reference and --spacing
  EXPECT_EQ(run_transform(base + " --output " + out("f.mha")).code, 2);
  EXPECT_EQ(run_transform(base + " --spacing 2 --reference " + rest + " --output " + out("f.mha")).code, 2);
  EXPECT_EQ(run_transform(base + " --spacing 2 --space XYZ --output " + out("f.mha")).code, 2);
  EXPECT_EQ(run_transform(base + " --spacing -1 --output " + out("f.mha")).code, 2);
  // an output that is no image, an unreadable reference, a mismatched deformed cage
  TransformRun r = run_transform(base + " --spacing 2 --output " + out("f.vtp"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("unknown image extension"), std::string::npos) << r.output;
  r = run_transform(base + " --reference " + out("missing.nii.gz") + " --output " + out("f.mha"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("missing.nii.gz"), std::string::npos) << r.output;
  {
    std::ofstream f(out("short.obj"));
    f << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  }
  r = run_transform("export-transform --cage " + rest + " --deformed-cage " + out("short.obj") +
    " --spacing 8 --output " + out("f.mha"));
  EXPECT_EQ(r.code, 1) << r.output;
  // warp-image: exactly one of the fields
  EXPECT_EQ(run_transform("warp-image --image " + rest + " --output " + out("w.mha")).code, 2);
  // nothing was written
  for (const char* name : { "f.mha", "f.vtp", "w.mha" })
    EXPECT_FALSE(fs::exists(out(name))) << name;
}

} // namespace
