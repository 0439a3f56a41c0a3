// barylab cage: the cage file it writes is accepted by the weights commands of every kind of
// method (mean value coordinates validate it; harmonic coordinates mesh its interior with
// TetGen / CGAL and, with the default --outside error, fail if a model point lies outside the
// mesh: an independent enclosure check), its JSON summary, and bad input: usage errors exit 2,
// run errors exit 1 with one line naming the problem, and no output file is left.

#include "vtkBaryDataIO.h"

#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

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
using Result = barylab_test::CommandResult;

Result run(const std::string& args)
{
  return barylab_test::RunBarylab(args);
}

std::string data(const std::string& name)
{
  return barylab_test::DataPath(name);
}

class CageCLI : public ::testing::Test
{
protected:
  void SetUp() override
  {
    dir_ = barylab_test::FreshTestFolder("cli_cage_");
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// Partition of unity of the "Weights" array of a weights command's output.
double PartitionError(const std::string& path)
{
  auto data = vtkBaryDataIO::Read(path);
  vtkDataArray* w = data->GetPointData()->GetArray("Weights");
  if (!w)
    return 1e300;
  double worst = 0.0;
  for (vtkIdType i = 0; i < w->GetNumberOfTuples(); ++i)
  {
    double sum = 0.0;
    for (int c = 0; c < w->GetNumberOfComponents(); ++c)
      sum += w->GetComponent(i, c);
    worst = std::max(worst, std::abs(sum - 1.0));
  }
  return worst;
}
} // namespace

TEST_F(CageCLI, Kidney3DCageIsUsedByMeanValueAndHarmonicWeights)
{
  const Result r = run("cage --model " + data("model3d.off") + " --vertices 60 --margin-fraction 0.1 --output " +
    out("cage.obj") + " --json " + out("cage.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto cage = vtkBaryDataIO::ReadPolyData(out("cage.obj"));
  EXPECT_EQ(cage->GetNumberOfPoints(), 60);
  EXPECT_EQ(cage->GetNumberOfCells(), 116);
  std::ifstream in(out("cage.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["vertices"], 60);
  EXPECT_EQ(s["faces"], 116);
  EXPECT_EQ(s["dimension"], 3);
  EXPECT_TRUE(s["reached_target"].get<bool>());
  EXPECT_EQ(s["stop_reason"], "target reached");
  EXPECT_EQ(s["collapses"].get<int>() + 60, s["offset_vertices"].get<int>());
  EXPECT_GT(s["tighten_moves"].get<int>(), 0);
  EXPECT_GT(s["measure_ratio"].get<double>(), 1.0);
  EXPECT_GT(s["max_distance"].get<double>(), 0.0);
  EXPECT_NEAR(s["margin"].get<double>(), 0.1 * s["diagonal"].get<double>(), 1e-12);
  const Result mvc = run("weights --method mvc --cage " + out("cage.obj") + " --points " +
    data("model3d.off") + " --output " + out("mvc.vtp") + " -q");
  ASSERT_EQ(mvc.code, 0) << mvc.output;
  EXPECT_LT(PartitionError(out("mvc.vtp")), 1e-9);
  const Result harmonic = run("weights --method harmonic --cells 3000 --cage " + out("cage.obj") +
    " --points " + data("model3d.off") + " --output " + out("harmonic.vtp") + " -q");
  ASSERT_EQ(harmonic.code, 0) << harmonic.output;
  EXPECT_LT(PartitionError(out("harmonic.vtp")), 1e-9);
}

TEST_F(CageCLI, Planar2DCageIsAPolygonTheMethodsAccept)
{
  const Result r =
    run("cage --model " + data("model2d.obj") + " -n 16 --output " + out("cage2d.vtp") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto cage = vtkBaryDataIO::ReadPolyData(out("cage2d.vtp"));
  EXPECT_EQ(cage->GetNumberOfPoints(), 16);
  ASSERT_EQ(cage->GetNumberOfCells(), 1);
  EXPECT_EQ(cage->GetCellType(0), VTK_POLYGON);
  const Result harmonic = run("weights --method harmonic --cage " + out("cage2d.vtp") +
    " --points " + data("model2d.obj") + " --output " + out("harmonic.vtp") + " -q");
  ASSERT_EQ(harmonic.code, 0) << harmonic.output;
  EXPECT_LT(PartitionError(out("harmonic.vtp")), 1e-9);
}

TEST_F(CageCLI, BadInputExitsWithoutOutput)
{
  const std::string model = " --model " + data("model3d.off");
  const std::string output = " --output " + out("cage.obj");
  // Command-line errors: 2.
  for (const std::string& args : { model + " --vertices 2" + output,
         model + " --margin 0" + output, model + " --margin nan" + output,
         model + " --resolution 1" + output })
  {
    const Result r = run("cage" + args + " -q");
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
  }
  // Run errors: 1, one line naming the problem.
  const Result small = run("cage" + model + " --vertices 3" + output + " -q");
  EXPECT_EQ(small.code, 1) << small.output;
  EXPECT_NE(small.output.find("at least 4"), std::string::npos) << small.output;
  const Result missing = run("cage --model " + out("none.off") + output + " -q");
  EXPECT_EQ(missing.code, 1) << missing.output;
  const Result tight = run("cage" + model + " --margin 1e-9" + output + " -q");
  EXPECT_EQ(tight.code, 1) << tight.output;
  EXPECT_NE(tight.output.find("raise the margin"), std::string::npos) << tight.output;
  const Result overwrite = run("cage" + model + " --output " + data("model3d.off") + " -q");
  EXPECT_NE(overwrite.code, 0) << overwrite.output;
  EXPECT_TRUE(fs::is_empty(dir_)) << "files left in " << dir_;
}
