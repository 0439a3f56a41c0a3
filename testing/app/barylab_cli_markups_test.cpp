// Command-line tests of 3D Slicer markups (.mrk.json, .fcsv) as control points, moved control
// points, the points to deform and the output: T-celestial coordinates reproduce affine maps
// (linear precision), so a model and landmarks strictly inside the control points' hull move by
// exactly the affine map that moved the control points; the written markups parse as JSON
// (nlohmann, independent of BaryLab's reader) in the form 3D Slicer reads, with the labels kept.
// Part of barylab_cli_test.

#include "vtkBaryDataIO.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"

#include "cli_test_utils.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace fs = std::filesystem;

namespace
{
using CommandRun = barylab_test::CommandResult;

CommandRun run_barylab(const std::string& args)
{
  return barylab_test::RunBarylab(args);
}

using Point = std::array<double, 3>;

/// The affine map that moves the control points: a shear, a scaling and a shift (in LPS).
Point affine(const Point& x)
{
  return { 1.1 * x[0] + 0.2 * x[1] + 3.0, 0.95 * x[1] - 0.1 * x[2] - 2.0, 0.9 * x[2] + 0.05 * x[0] + 7.5 };
}

class CLIMarkups : public ::testing::Test
{
protected:
  void SetUp() override
  {
    dir_ = barylab_test::FreshTestFolder("cli_markups_");
    // control points: the corners of the box [-2, 2] x [-1.5, 1.5] x [-1, 1.2] around the
    // bundled kidney (data/model3d.off, within about +-1.15 x +-0.75 x +-0.6), and two inside
    for (double z : { -1.0, 1.2 })
      for (double y : { -1.5, 1.5 })
        for (double x : { -2.0, 2.0 })
          controls_.push_back({ x, y, z });
    controls_.push_back({ 0.3, -0.2, 0.1 });
    controls_.push_back({ -0.6, 0.4, -0.2 });
    landmarks_ = { { 0.9, 0.1, 0.2 }, { -1.0, -0.3, 0.0 }, { 0.0, 0.6, -0.4 }, { 0.2, -0.5, 0.45 } };
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }

  /// Points as a Slicer markups JSON: RAS (x, y negated) when @p ras.
  void WriteJson(const std::string& name, const std::vector<Point>& points, bool ras,
    const std::string& prefix) const
  {
    std::ofstream f(out(name));
    f.precision(17);
    f << "{\"@schema\": \"https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/"
         "Markups/Resources/Schema/markups-schema-v1.0.3.json#\", \"markups\": [{\"type\": "
         "\"Fiducial\", \"coordinateSystem\": \""
      << (ras ? "RAS" : "LPS") << "\", \"coordinateUnits\": \"mm\", \"controlPoints\": [\n";
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const double s = ras ? -1.0 : 1.0;
      f << (i ? ",\n" : "") << "{\"id\": \"" << i + 1 << "\", \"label\": \"" << prefix << i
        << "\", \"position\": [" << s * points[i][0] << ", " << s * points[i][1] << ", "
        << points[i][2] << "], \"positionStatus\": \"defined\"}";
    }
    f << "]}]}\n";
  }

  /// Points as a legacy Slicer .fcsv in RAS.
  void WriteFcsvRAS(const std::string& name, const std::vector<Point>& points) const
  {
    std::ofstream f(out(name));
    f.precision(17);
    f << "# Markups fiducial file version = 4.11\n# CoordinateSystem = RAS\n"
         "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n";
    for (std::size_t i = 0; i < points.size(); ++i)
      f << "vtkMRMLMarkupsFiducialNode_" << i << "," << -points[i][0] << "," << -points[i][1]
        << "," << points[i][2] << ",0,0,0,1,1,1,0,M-" << i << ",,\n";
  }

  fs::path dir_;
  std::vector<Point> controls_, landmarks_;
};

TEST_F(CLIMarkups, DeformWithMarkupsControlPointsReproducesTheAffineMap)
{
  std::vector<Point> moved;
  for (const Point& c : controls_)
    moved.push_back(affine(c));
  WriteJson("L.mrk.json", controls_, false, "C-");
  WriteJson("M.mrk.json", moved, false, "C-");
  WriteFcsvRAS("M.fcsv", moved); // the same moved points, in RAS in the legacy format
  const std::string model = std::string(BARYLAB_DATA_DIR) + "/model3d.off";
  for (const char* deformed : { "M.mrk.json", "M.fcsv" })
  {
    const std::string output = out(std::string("out_") + deformed + ".vtp");
    const CommandRun r = run_barylab("deform --method tcc --control-points " + out("L.mrk.json") +
      " --deformed-control-points " + out(deformed) + " --points " + model + " --output " +
      output + " --quiet");
    ASSERT_EQ(r.code, 0) << r.output;
    auto rest = vtkBaryDataIO::Read(model);
    auto result = vtkBaryDataIO::Read(output);
    ASSERT_EQ(result->GetNumberOfPoints(), rest->GetNumberOfPoints());
    double worst = 0;
    for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
    {
      Point x;
      rest->GetPoint(i, x.data());
      const Point y = affine(x);
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, std::abs(result->GetPoint(i)[k] - y[k]));
    }
    // linear precision: reproduction to ~1e-12 of the controls' diameter (docs/celestial-coordinates.md)
    EXPECT_LT(worst, 1e-9) << deformed;
  }
}

TEST_F(CLIMarkups, MovedLandmarksAreWrittenBackWithTheirLabels)
{
  std::vector<Point> moved;
  for (const Point& c : controls_)
    moved.push_back(affine(c));
  WriteJson("L.mrk.json", controls_, false, "C-");
  WriteJson("M.mrk.json", moved, false, "C-");
  WriteJson("landmarks.mrk.json", landmarks_, true, "liver-"); // given in RAS
  const CommandRun r = run_barylab("deform --method tcc --control-points " + out("L.mrk.json") +
    " --deformed-control-points " + out("M.mrk.json") + " --points " + out("landmarks.mrk.json") +
    " --output " + out("moved.mrk.json") + " --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(out("moved.mrk.json"));
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(in));
  EXPECT_NE(j["@schema"].get<std::string>().find("/markups-schema-v1.0."), std::string::npos);
  ASSERT_EQ(j["markups"].size(), 1u);
  const nlohmann::json& m = j["markups"][0];
  EXPECT_EQ(m["type"], "Fiducial");
  EXPECT_EQ(m["coordinateSystem"], "LPS");
  EXPECT_EQ(m["coordinateUnits"], "mm");
  ASSERT_EQ(m["controlPoints"].size(), landmarks_.size());
  for (std::size_t i = 0; i < landmarks_.size(); ++i)
  {
    const nlohmann::json& p = m["controlPoints"][i];
    EXPECT_EQ(p["label"], "liver-" + std::to_string(i));
    EXPECT_EQ(p["id"], std::to_string(i + 1));
    EXPECT_EQ(p["positionStatus"], "defined");
    const Point y = affine(landmarks_[i]); // the landmarks were given in RAS, written in LPS
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(p["position"][k].get<double>(), y[k], 1e-9) << "landmark " << i << " axis " << k;
  }
  // .fcsv output too, read back by BaryLab with the labels
  const CommandRun f = run_barylab("deform --method tcc --control-points " + out("L.mrk.json") +
    " --deformed-control-points " + out("M.mrk.json") + " --points " + out("landmarks.mrk.json") +
    " --output " + out("moved.fcsv") + " --quiet");
  ASSERT_EQ(f.code, 0) << f.output;
  auto back = vtkBaryDataIO::Read(out("moved.fcsv"));
  auto* labels = vtkStringArray::SafeDownCast(back->GetPointData()->GetAbstractArray("Label"));
  ASSERT_NE(labels, nullptr);
  ASSERT_EQ(labels->GetNumberOfValues(), static_cast<vtkIdType>(landmarks_.size()));
  EXPECT_EQ(labels->GetValue(3), "liver-3");
}

TEST_F(CLIMarkups, BBWPointHandlesFromMarkupsAreTheSameHandles)
{
  // Landmarks as bounded biharmonic handles: five point handles inside the gingerbread man (his
  // head, hands and feet, joints of data/skeleton2d.tgf) given once as a Slicer markups file
  // (RAS, so the reader must negate x and y back) and once as an .obj: the same weights.
  const std::vector<Point> handles = { { 0.0, 0.72, 0.0 }, { -0.82, 0.22, 0.0 }, { 0.82, 0.22, 0.0 },
    { -0.25, -0.85, 0.0 }, { 0.25, -0.85, 0.0 } };
  WriteJson("handles.mrk.json", handles, true, "H-");
  {
    std::ofstream obj(out("handles.obj"));
    obj.precision(17);
    for (const Point& h : handles)
      obj << "v " << h[0] << " " << h[1] << " " << h[2] << "\n";
  }
  const std::string common = " --method bbw --mesh " + barylab_test::DataPath("cage2d.obj") +
    " --points " + barylab_test::DataPath("model2d.obj") + " --cells 1500 --quiet";
  const CommandRun a = run_barylab("weights --handles " + out("handles.mrk.json") + common +
    " --output " + out("markups.vtp"));
  ASSERT_EQ(a.code, 0) << a.output;
  const CommandRun b = run_barylab("weights --handles " + out("handles.obj") + common +
    " --output " + out("obj.vtp"));
  ASSERT_EQ(b.code, 0) << b.output;
  auto wa = vtkBaryDataIO::Read(out("markups.vtp"));
  auto wb = vtkBaryDataIO::Read(out("obj.vtp"));
  vtkDataArray* A = wa->GetPointData()->GetArray("Weights");
  vtkDataArray* B = wb->GetPointData()->GetArray("Weights");
  ASSERT_TRUE(A && B);
  ASSERT_EQ(A->GetNumberOfComponents(), 5);
  ASSERT_EQ(A->GetNumberOfTuples(), B->GetNumberOfTuples());
  double worst = 0.0, partition = 0.0;
  for (vtkIdType i = 0; i < A->GetNumberOfTuples(); ++i)
  {
    double sum = 0.0;
    for (int k = 0; k < 5; ++k)
    {
      worst = std::max(worst, std::abs(A->GetComponent(i, k) - B->GetComponent(i, k)));
      sum += A->GetComponent(i, k);
    }
    partition = std::max(partition, std::abs(sum - 1.0));
  }
  EXPECT_LT(worst, 1e-12) << "markups handles differ from the same points as .obj";
  EXPECT_LT(partition, 1e-9);
}

TEST_F(CLIMarkups, BadMarkupsAreRunErrorsWithoutOutput)
{
  WriteJson("L.mrk.json", controls_, false, "C-");
  std::ofstream(out("preview.mrk.json"))
    << R"({"markups": [{"controlPoints": [{"label": "P", "position": [0, 0, 0], "positionStatus": "preview"}]}]})";
  const CommandRun r = run_barylab("deform --method tcc --control-points " + out("L.mrk.json") +
    " --deformed-control-points " + out("preview.mrk.json") + " --points " + out("L.mrk.json") +
    " --output " + out("x.mrk.json") + " --quiet");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("control point 0 ('P')"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out("x.mrk.json")));
  // a .json that is not .mrk.json is not a data file: a command-line error naming the formats
  const CommandRun j = run_barylab("deform --method tcc --control-points " + out("L.mrk.json") +
    " --deformed-control-points " + out("L.mrk.json") + " --points " + out("L.mrk.json") +
    " --output " + out("x.json") + " --quiet");
  EXPECT_NE(j.code, 0);
  EXPECT_NE(j.output.find(".mrk.json"), std::string::npos) << j.output;
}
} // namespace
