// Tests of the barylab command line: good runs produce the files with the documented arrays,
// bad input gives a one-line message naming the problem, a non-zero exit and no output file.

#include "vtkBaryDataIO.h"

#include "vtkCell.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include "cli_test_utils.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace fs = std::filesystem;

namespace
{
using CommandResult = barylab_test::CommandResult;

CommandResult run(const std::string& args)
{
  return barylab_test::RunBarylab(args);
}

std::string data(const std::string& name)
{
  return barylab_test::DataPath(name);
}

class CLI : public ::testing::Test
{
protected:
  void SetUp() override
  {
    dir_ = barylab_test::FreshTestFolder("cli_");
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  /// The folder holds nothing (no partial or temporary files).
  void ExpectEmptyFolder() const { EXPECT_TRUE(fs::is_empty(dir_)) << "files left in " << dir_; }
  fs::path dir_;
};

/// A bad-input run: exit code 1, one line "barylab: error: ..." containing @p needle.
void ExpectError(const CommandResult& r, const std::string& needle)
{
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("barylab: error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in:\n" << r.output;
  // one line, no VTK stack dump
  EXPECT_EQ(r.output.find("vtkExecutive"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("ERR|"), std::string::npos) << r.output;
}
} // namespace

TEST_F(CLI, HelpListsSubcommands)
{
  const CommandResult r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* sub : { "weights", "deform", "stats", "render", "demo" })
    EXPECT_NE(r.output.find(sub), std::string::npos) << sub;
  for (const char* sub : { "weights", "deform", "stats", "render", "demo" })
    EXPECT_EQ(run(std::string(sub) + " --help").code, 0) << sub;
}

TEST_F(CLI, NoSubcommandIsAUsageError)
{
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("weights --cage x.obj").code, 2); // missing required options
}

TEST_F(CLI, Weights3DWritesArrayAndSummary)
{
  const CommandResult r = run("weights --method mvc --cage " + data("cage3d.obj") + " --points " +
    data("model3d.off") + " --output " + out("w.vtp") + " --json " + out("w.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto result = vtkBaryDataIO::Read(out("w.vtp"));
  vtkDataArray* w = result->GetPointData()->GetArray("Weights");
  ASSERT_NE(w, nullptr);
  auto cage = vtkBaryDataIO::Read(data("cage3d.obj"));
  auto model = vtkBaryDataIO::Read(data("model3d.off"));
  EXPECT_EQ(w->GetNumberOfComponents(), cage->GetNumberOfPoints());
  EXPECT_EQ(w->GetNumberOfTuples(), model->GetNumberOfPoints());
  // partition of unity and reproduction, checked here independently of `barylab stats`
  double worst_sum = 0.0, worst_rep = 0.0;
  for (vtkIdType p = 0; p < w->GetNumberOfTuples(); ++p)
  {
    double sum = 0.0, x[3] = { 0, 0, 0 };
    for (int i = 0; i < w->GetNumberOfComponents(); ++i)
    {
      const double wi = w->GetComponent(p, i);
      sum += wi;
      double c[3];
      cage->GetPoint(i, c);
      for (int k = 0; k < 3; ++k)
        x[k] += wi * c[k];
    }
    double y[3];
    model->GetPoint(p, y);
    worst_sum = std::max(worst_sum, std::abs(sum - 1.0));
    for (int k = 0; k < 3; ++k)
      worst_rep = std::max(worst_rep, std::abs(x[k] - y[k]));
  }
  EXPECT_LT(worst_sum, 1e-12);
  EXPECT_LT(worst_rep, 1e-12);

  std::ifstream in(out("w.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["method"], "mvc");
  EXPECT_EQ(s["cage"]["dimension"], 3);
  EXPECT_EQ(s["cage"]["control_points"], cage->GetNumberOfPoints());
  EXPECT_EQ(s["points"]["count"], model->GetNumberOfPoints());
  EXPECT_EQ(s["points"]["outside"], 0);
  EXPECT_LT(s["statistics"]["partition_of_unity"]["max_error"].get<double>(), 1e-12);
}

TEST_F(CLI, BBWOfAVertexOnlyOrPolylineCage)
{
  // --help offers "bbw with --cage"; a v-only .obj or one polyline was read as a skeleton and
  // failed with "need a domain" (issue 17). A cage's BBW: partition of unity, in [0, 1].
  fs::path polyline = out("square.vtk");
  {
    std::ofstream f(polyline);
    f << "# vtk DataFile Version 3.0\nsquare\nASCII\nDATASET POLYDATA\nPOINTS 4 double\n"
         "0 0 0 1 0 0 1 1 0 0 1 0\nLINES 1 6\n5 0 1 2 3 0\n";
  }
  std::ofstream(out("p.obj")) << "v 0.3 0.3 0\nv 0.6 0.5 0\nv 0.9 0.1 0\n";
  for (const std::string& cage : { data("cage2d.obj"), polyline.string() })
  {
    SCOPED_TRACE(cage);
    const std::string points = cage == polyline.string() ? out("p.obj") : data("model2d.obj");
    const CommandResult r = run("weights --method bbw --cells 600 --cage " + cage + " --points " +
      points + " --output " + out("b.vtp") + " --json " + out("b.json") + " -q");
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream in(out("b.json"));
    const nlohmann::json s = nlohmann::json::parse(in);
    EXPECT_EQ(s["method"], "bbw");
    EXPECT_EQ(s["cage"]["dimension"], 2);
    EXPECT_LT(s["statistics"]["partition_of_unity"]["max_error"].get<double>(), 1e-8);
    EXPECT_GE(s["statistics"]["min_weight"].get<double>(), -1e-8);
  }
}

TEST_F(CLI, Weights2DFromVertexOnlyObj)
{
  const CommandResult r = run("weights --cage " + data("cage2d.obj") + " --points " + data("model2d.obj") +
    " --output " + out("w.vtu") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto result = vtkBaryDataIO::Read(out("w.vtu"));
  vtkDataArray* w = result->GetPointData()->GetArray("Weights");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->GetNumberOfComponents(), 20);
}

TEST_F(CLI, OutsidePointsAreComputedAndCounted)
{
  // Evaluate at the posed cage's vertices: unmoved ones lie on the rest cage, the raised arm's
  // lie outside it.
  const CommandResult r = run("weights --cage " + data("cage2d.obj") + " --points " +
    data("cage2d_posed.obj") + " --output " + out("w.vtp") + " --json " + out("s.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(out("s.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  const long long outside = s["points"]["outside"], inside = s["points"]["inside"],
                  on = s["points"]["on_cage"];
  EXPECT_EQ(inside + outside + on, 20);
  EXPECT_GT(outside, 0) << "the posed cage's raised arm lies outside the rest cage";
  EXPECT_NE(r.output.find("outside the cage"), std::string::npos) << r.output;
}

TEST_F(CLI, DeformMatchesAffineMapAndReusesWeights)
{
  ASSERT_EQ(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
              " --output " + out("w.vtp") + " -q")
              .code,
    0);
  // The posed cage from the bundled data; deform once computing weights, once reusing them.
  CommandResult a = run("deform --cage " + data("cage3d.obj") + " --deformed-cage " +
    data("cage3d_posed.obj") + " --points " + data("model3d.off") + " --output " + out("a.vtp"));
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_NE(a.output.find("weights computed"), std::string::npos) << a.output;
  CommandResult b = run("deform --cage " + data("cage3d.obj") + " --deformed-cage " +
    data("cage3d_posed.obj") + " --weights " + out("w.vtp") + " --output " + out("b.vtp"));
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_NE(b.output.find("weights from the input"), std::string::npos) << b.output;
  auto da = vtkBaryDataIO::Read(out("a.vtp"));
  auto db = vtkBaryDataIO::Read(out("b.vtp"));
  auto rest = vtkBaryDataIO::Read(data("model3d.off"));
  ASSERT_EQ(da->GetNumberOfPoints(), db->GetNumberOfPoints());
  double diff = 0.0, moved = 0.0;
  for (vtkIdType i = 0; i < da->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3], z[3];
    da->GetPoint(i, x);
    db->GetPoint(i, y);
    rest->GetPoint(i, z);
    for (int k = 0; k < 3; ++k)
    {
      diff = std::max(diff, std::abs(x[k] - y[k]));
      moved = std::max(moved, std::abs(x[k] - z[k]));
    }
  }
  EXPECT_LT(diff, 1e-12);
  EXPECT_GT(moved, 1e-2) << "the posed cage must actually move the model";
}

TEST_F(CLI, DeformDropWeightsWritesTheSamePointsWithoutTheWeights)
{
  // By default the deformed model carries its weights; --drop-weights writes the same points
  // without them (dense array, and the compact pair of 'barylab reduce').
  const std::string common = "deform --cage " + data("cage3d.obj") + " --deformed-cage " +
    data("cage3d_posed.obj") + " --points " + data("model3d.off") + " -q --output ";
  ASSERT_EQ(run(common + out("kept.vtp")).code, 0);
  const CommandResult r = run(common + out("dropped.vtp") + " --drop-weights");
  ASSERT_EQ(r.code, 0) << r.output;
  auto kept = vtkBaryDataIO::Read(out("kept.vtp"));
  auto dropped = vtkBaryDataIO::Read(out("dropped.vtp"));
  EXPECT_NE(kept->GetPointData()->GetArray("Weights"), nullptr);
  EXPECT_EQ(dropped->GetPointData()->GetArray("Weights"), nullptr);
  ASSERT_EQ(kept->GetNumberOfPoints(), dropped->GetNumberOfPoints());
  for (vtkIdType i = 0; i < kept->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    kept->GetPoint(i, x);
    dropped->GetPoint(i, y);
    ASSERT_TRUE(x[0] == y[0] && x[1] == y[1] && x[2] == y[2]) << "point " << i;
  }
  EXPECT_LT(fs::file_size(out("dropped.vtp")), fs::file_size(out("kept.vtp")));
  // the compact pair from 'barylab reduce'
  ASSERT_EQ(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
              " --output " + out("w.vtp") + " -q").code, 0);
  ASSERT_EQ(run("reduce --input " + out("w.vtp") + " --output " + out("r.vtp")).code, 0);
  ASSERT_EQ(run("deform --cage " + data("cage3d.obj") + " --deformed-cage " +
              data("cage3d_posed.obj") + " --weights " + out("r.vtp") + " -q --drop-weights --output " +
              out("rd.vtp")).code, 0);
  auto rd = vtkBaryDataIO::Read(out("rd.vtp"));
  auto reduced = vtkBaryDataIO::Read(out("r.vtp"));
  EXPECT_NE(reduced->GetPointData()->GetArray("WeightsIndices"), nullptr);
  for (int i = 0; i < rd->GetPointData()->GetNumberOfArrays(); ++i)
    EXPECT_NE(std::string(rd->GetPointData()->GetArrayName(i)).rfind("Weights", 0), 0u)
      << rd->GetPointData()->GetArrayName(i);
  EXPECT_EQ(rd->GetFieldData()->GetArray("WeightsNumberOfControlPoints"), nullptr);
}

TEST_F(CLI, DeformRejectsWeightsForOtherPoints)
{
  ASSERT_EQ(run("weights --cage " + data("cage2d.obj") + " --points " + data("model2d.obj") +
              " --output " + out("w.vtp") + " -q")
              .code,
    0);
  fs::remove(out("w.json"));
  const CommandResult r = run("deform --cage " + data("cage3d.obj") + " --deformed-cage " +
    data("cage3d_posed.obj") + " --weights " + out("w.vtp") + " --output " + out("d.vtp"));
  ExpectError(r, "components but the cage");
  EXPECT_FALSE(fs::exists(out("d.vtp")));
}

TEST_F(CLI, DeformRefusesANaNInGivenWeightsNamingThePoint)
{
  ASSERT_EQ(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
              " --output " + out("w.vtp") + " -q").code, 0);
  auto weighted = vtkBaryDataIO::Read(out("w.vtp"));
  weighted->GetPointData()->GetArray("Weights")->SetComponent(5, 3, std::nan(""));
  vtkBaryDataIO::Write(weighted, out("w_nan.vtp"));
  const CommandResult r = run("deform --cage " + data("cage3d.obj") + " --deformed-cage " +
    data("cage3d_posed.obj") + " --weights " + out("w_nan.vtp") + " --drop-weights --output " +
    out("d_nan.vtp"));
  ExpectError(r, "NaN or infinite values (first at point 5)");
  EXPECT_FALSE(fs::exists(out("d_nan.vtp")));
}

TEST_F(CLI, StatsJsonAndText)
{
  ASSERT_EQ(run("weights --cage " + data("cage2d.obj") + " --points " + data("model2d.obj") +
              " --output " + out("w.vtp") + " -q")
              .code,
    0);
  const CommandResult j = run("stats --input " + out("w.vtp") + " --cage " + data("cage2d.obj") + " --json");
  ASSERT_EQ(j.code, 0) << j.output;
  const nlohmann::json s = nlohmann::json::parse(j.output);
  EXPECT_EQ(s["controls"], 20);
  EXPECT_LT(s["partition_of_unity"]["max_error"].get<double>(), 1e-12);
  EXPECT_LT(s["reproduction"]["max_error"].get<double>(), 1e-12);
  EXPECT_LT(s["min_weight"].get<double>(), 0.0) << "MVC are negative somewhere in a non-convex cage";
  EXPECT_DOUBLE_EQ(s["significant"]["threshold"].get<double>(), 1e-3 / 20);
  const CommandResult t = run("stats --input " + out("w.vtp"));
  ASSERT_EQ(t.code, 0);
  EXPECT_NE(t.output.find("partition of unity"), std::string::npos);
  ExpectError(run("stats --input " + out("w.vtp") + " --array Nope"), "no point-data array 'Nope'");
  ExpectError(run("stats --input " + out("w.vtp") + " --cage " + data("cage3d.obj")),
    "components but the cage has 72");
}

// ---- bad input: message, exit code 1, no output file ------------------------------------

struct BadCase
{
  const char* name;
  std::string cage, points;
  const char* needle;
};

class CLIBadInput : public CLI, public ::testing::WithParamInterface<BadCase>
{
};

TEST_P(CLIBadInput, ClearErrorNoOutput)
{
  const BadCase& c = GetParam();
  const CommandResult r = run("weights --cage " + c.cage + " --points " + c.points + " --output " +
    out("w.vtp") + " --json " + out("w.json"));
  ExpectError(r, c.needle);
  ExpectEmptyFolder();
}

INSTANTIATE_TEST_SUITE_P(Cages, CLIBadInput,
  ::testing::Values(
    BadCase{ "open", data("bad/open_cage.obj"), data("model3d.off"), "not closed: edge (" },
    BadCase{ "nan", data("bad/nan_cage.obj"), data("model3d.off"), "not finite" },
    BadCase{ "bowtie", data("bad/bowtie2d.obj"), data("model2d.obj"), "not simple" },
    BadCase{ "flipped", data("bad/inconsistent_cage.obj"), data("model3d.off"),
      "not consistently oriented" },
    BadCase{ "quads", data("bad/quad_cage.obj"), data("model3d.off"), "triangulated" },
    BadCase{ "empty", data("bad/empty.obj"), data("model3d.off"), "empty" },
    BadCase{ "garbage", data("bad/garbage.off"), data("model3d.off"), "garbage.off" },
    BadCase{ "missing", data("no_such_cage.obj"), data("model3d.off"), "no such file" },
    BadCase{ "unknown_ext", data("README.md"), data("model3d.off"), "unknown file extension" },
    BadCase{ "nan_points", data("cage3d.obj"), data("bad/nan_cage.obj"), "not finite" },
    BadCase{ "empty_points", data("cage3d.obj"), data("bad/empty.obj"), "empty" }),
  [](const ::testing::TestParamInfo<BadCase>& param_info) { return std::string(param_info.param.name); });

TEST_F(CLI, BadOutputPathsFailBeforeComputing)
{
  ExpectError(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
                " --output " + out("w.xyz")),
    "unknown file extension '.xyz'");
  ExpectError(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
                " --output " + out("nofolder/w.vtp")),
    "does not exist");
  ExpectEmptyFolder();
}

TEST_F(CLI, OutputThatCannotHoldTheResultFailsBeforeComputing)
{
  // A tetrahedral mesh (an unstructured grid) as the points: the weights are written as a copy
  // of it, which no surface-only format holds. The cage is open, so a run that computed first
  // would fail on the cage instead: the output's message shows the check came first.
  const fs::path grids = dir_.parent_path() / (dir_.filename().string() + "_inputs");
  fs::remove_all(grids);
  fs::create_directories(grids);
  const std::string tets = (grids / "tets.vtu").string();
  ASSERT_EQ(run("mesh --cage " + data("cage3d.obj") + " --cells 300 --output " + tets + " -q").code, 0);
  const std::string open = " --cage " + data("bad/open_cage.obj") + " --points " + tets;
  for (const char* name : { "w.vtp", "w.obj", "w.stl", "w.ply", "w.off" })
  {
    const CommandResult r = run("weights" + open + " --output " + out(name));
    ExpectError(r, "holds surfaces only; use .vtu or .vtk");
    EXPECT_EQ(r.output.find("not closed"), std::string::npos) << r.output;
  }
  // a parallel file of the other type
  const CommandResult p = run("weights" + open + " --output " + out("w.pvtp"));
  EXPECT_EQ(p.code, 1) << p.output;
  EXPECT_NE(p.output.find("give the output a .pvtu name"), std::string::npos) << p.output;
  // deform: the deformed model has the model's type
  const CommandResult d = run("deform" + open + " --deformed-cage " + data("cage3d_posed.obj") +
    " --output " + out("d.off"));
  ExpectError(d, "holds surfaces only");
  EXPECT_EQ(d.output.find("not closed"), std::string::npos) << d.output;
  // the check is not a refusal of what works: the same grid written as .vtu, with a closed cage
  EXPECT_EQ(run("weights --cage " + data("cage3d.obj") + " --points " + tets + " --output " +
              out("w.vtu") + " -q").code, 0);
  EXPECT_TRUE(fs::exists(out("w.vtu")));
  fs::remove(out("w.vtu"));
  ExpectEmptyFolder();
  fs::remove_all(grids);
}

TEST_F(CLI, UnknownMethodAndMismatchedDeformedCage)
{
  ExpectError(run("weights --method nope --cage " + data("cage3d.obj") + " --points " +
                data("model3d.off") + " --output " + out("w.vtp")),
    "unknown method 'nope'");
  ExpectError(run("deform --cage " + data("cage2d.obj") + " --deformed-cage " +
                data("cage3d_posed.obj") + " --points " + data("model2d.obj") + " --output " +
                out("d.vtp")),
    "the deformed cage has 72 points but the rest cage has 20");
  ExpectEmptyFolder();
}

namespace
{
/// The demo's local barycentric coordinates case (gingerbread2d_lbc), checked against what the
/// mathematics guarantees rather than against recorded numbers.
void ExpectDemoLBC(const fs::path& dir, const nlohmann::json& c)
{
  for (const char* f : { "gingerbread2d_lbc_weights.vtp", "gingerbread2d_lbc_sparse.vtp",
         "gingerbread2d_lbc_deformed.vtp", "gingerbread2d_locality_P.csv",
         "gingerbread2d_locality_Q.csv" })
    ASSERT_TRUE(fs::exists(dir / f)) << f;
  ASSERT_TRUE(c.is_object()) << "no cases.lbc2d in summary.json";
  const int n = 20; // control points of data/cage2d.obj
  EXPECT_EQ(c["method"], "lbc");
  EXPECT_EQ(c["solver"]["converged"].get<double>(), 1.0);
  // dense LBC: partition of unity and reproduction are constraints of the solve, kept exactly by
  // the linear interpolation to the model's points; the weights are non-negative
  const nlohmann::json& st = c["statistics"];
  EXPECT_LT(st["partition_of_unity"]["max_error"].get<double>(), 1e-9);
  EXPECT_LT(st["reproduction"]["max_error"].get<double>(), 1e-9);
  EXPECT_GE(st["min_weight"].get<double>(), -1e-12);

  // locality (Eq. 19-21) of LBC against MVC at the same points, same threshold 1e-3/n
  const nlohmann::json& mvc = c["locality"]["mvc"];
  const nlohmann::json& lbc = c["locality"]["lbc"];
  const double threshold = 1e-3 / n;
  for (const nlohmann::json* l : { &mvc, &lbc })
  {
    EXPECT_NEAR((*l)["threshold"].get<double>(), threshold, 1e-18);
    EXPECT_EQ((*l)["controls"].get<int>(), n);
    EXPECT_EQ((*l)["points"], lbc["points"]);
    // Q(k), k = 1..n: Q(1) = 1 (weights summing to 1 have one >= 1/n), non-increasing, in
    // [0, 1], zero beyond the max support, and sum_k Q(k) = mean support (E[N] = sum P(N >= k))
    const auto& Q = (*l)["Q"];
    ASSERT_EQ(Q.size(), static_cast<std::size_t>(n));
    EXPECT_NEAR(Q[0].get<double>(), 1.0, 1e-12);
    double sum = 0.0;
    for (std::size_t k = 0; k < Q.size(); ++k)
    {
      EXPECT_EQ((*l)["k"][k].get<int>(), static_cast<int>(k) + 1);
      EXPECT_GE(Q[k].get<double>(), 0.0);
      EXPECT_LE(Q[k].get<double>(), 1.0 + 1e-12);
      if (k > 0)
      {
        EXPECT_LE(Q[k].get<double>(), Q[k - 1].get<double>() + 1e-12) << "k = " << k + 1;
      }
      if (static_cast<double>(k + 1) > (*l)["max_support"].get<double>())
      {
        EXPECT_EQ(Q[k].get<double>(), 0.0) << "k = " << k + 1;
      }
      sum += Q[k].get<double>();
    }
    EXPECT_NEAR(sum, (*l)["mean_support"].get<double>(), 1e-9);
    // P(t): a distribution function of |w| over the domain, averaged over the controls
    const auto& P = (*l)["P"];
    ASSERT_EQ(P.size(), (*l)["t"].size());
    for (std::size_t j = 0; j < P.size(); ++j)
    {
      EXPECT_GE(P[j].get<double>(), 0.0);
      EXPECT_LE(P[j].get<double>(), 1.0 + 1e-12);
      if (j > 0)
      {
        EXPECT_GE(P[j].get<double>(), P[j - 1].get<double>() - 1e-12);
      }
    }
  }
  EXPECT_EQ(mvc["t"], lbc["t"]);
  // the point of LBC: far fewer significant weights per point than the global MVC
  EXPECT_LT(lbc["mean_support"].get<double>(), mvc["mean_support"].get<double>());
  EXPECT_LT(lbc["max_support"].get<double>(), mvc["max_support"].get<double>());
  EXPECT_EQ(c["locality"]["mean_support"]["lbc"], lbc["mean_support"]);
  EXPECT_EQ(c["locality"]["mean_support"]["mvc"], mvc["mean_support"]);
  // P(t) at t = 1e-6: MVC weights are nearly never that small, LBC's mostly exactly zero
  for (std::size_t j = 0; j < lbc["t"].size(); ++j)
  {
    if (std::abs(lbc["t"][j].get<double>() - 1e-6) < 1e-15)
    {
      EXPECT_GT(lbc["P"][j].get<double>(), mvc["P"][j].get<double>() + 0.5);
    }
  }

  // the CSV pair: the columns of `barylab stats --locality --csv`, the numbers of the JSON
  for (const auto& [file, key, value] : { std::array<std::string, 3>{ "P", "t", "P" },
         std::array<std::string, 3>{ "Q", "k", "Q" } })
  {
    std::ifstream csv(dir / ("gingerbread2d_locality_" + file + ".csv"));
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line, key + "," + value + "_mvc," + value + "_lbc");
    std::size_t row = 0;
    while (std::getline(csv, line))
    {
      double x, a, b;
      char c1, c2;
      std::istringstream fields(line);
      ASSERT_TRUE(fields >> x >> c1 >> a >> c2 >> b) << line;
      ASSERT_LT(row, lbc[value].size());
      EXPECT_DOUBLE_EQ(x, lbc[key][row].get<double>());
      EXPECT_DOUBLE_EQ(a, mvc[value][row].get<double>());
      EXPECT_DOUBLE_EQ(b, lbc[value][row].get<double>());
      ++row;
    }
    EXPECT_EQ(row, lbc[value].size()) << file;
  }

  // sparse weights: threshold 1e-3/n, rows renormalised to sum 1
  const nlohmann::json& sp = c["sparse"];
  EXPECT_NEAR(sp["threshold"].get<double>(), threshold, 1e-18);
  EXPECT_EQ(sp["renormalization"], "rowsum");
  const int K = sp["K"].get<int>();
  EXPECT_EQ(K, static_cast<int>(lbc["max_support"].get<double>())) << "same threshold, same count";
  EXPECT_LT(K, n);
  EXPECT_NEAR(sp["memory_fraction"].get<double>(), 12.0 * K / (8.0 * n), 1e-12);
  EXPECT_LT(sp["memory_fraction"].get<double>(), 1.0);
  EXPECT_LT(sp["partition_error"].get<double>(), 1e-12);
  const double max_dropped = sp["max_dropped"].get<double>();
  EXPECT_GE(max_dropped, 0.0);
  EXPECT_LE(max_dropped, (n - 1) * threshold) << "at most n - 1 weights <= threshold dropped";
  // reproduction: off by the dropped mass times a distance within the cage, relative to its size
  EXPECT_LE(sp["reproduction_error"].get<double>(), max_dropped + 1e-9);
  auto sparse = vtkBaryDataIO::Read((dir / "gingerbread2d_lbc_sparse.vtp").string());
  EXPECT_EQ(sparse->GetPointData()->GetArray("Weights"), nullptr) << "the dense array is dropped";
  vtkDataArray* indices = sparse->GetPointData()->GetArray("WeightsIndices");
  vtkDataArray* values = sparse->GetPointData()->GetArray("WeightsValues");
  ASSERT_NE(indices, nullptr);
  ASSERT_NE(values, nullptr);
  EXPECT_EQ(indices->GetNumberOfComponents(), K);

  // deformation: recomputed here from the written files, x = sum_i w_i v_i (v: posed cage)
  EXPECT_FALSE(c["deformation"]["sparse"]["weights_computed"].get<bool>());
  EXPECT_FALSE(c["deformation"]["dense"]["weights_computed"].get<bool>());
  auto posed = vtkBaryDataIO::Read(data("cage2d_posed.obj"));
  auto dense = vtkBaryDataIO::Read((dir / "gingerbread2d_lbc_weights.vtp").string());
  auto deformed = vtkBaryDataIO::Read((dir / "gingerbread2d_lbc_deformed.vtp").string());
  vtkDataArray* W = dense->GetPointData()->GetArray("Weights");
  ASSERT_NE(W, nullptr);
  ASSERT_EQ(W->GetNumberOfComponents(), n);
  ASSERT_EQ(posed->GetNumberOfPoints(), n);
  ASSERT_EQ(deformed->GetNumberOfPoints(), dense->GetNumberOfPoints());
  ASSERT_EQ(sparse->GetNumberOfPoints(), dense->GetNumberOfPoints());
  double diameter = 0.0;
  for (vtkIdType i = 0; i < n; ++i)
    for (vtkIdType j = 0; j < n; ++j)
    {
      double a[3], b[3];
      posed->GetPoint(i, a);
      posed->GetPoint(j, b);
      diameter = std::max(diameter, std::hypot(a[0] - b[0], a[1] - b[1]));
    }
  EXPECT_NEAR(c["deformation"]["posed_cage_diameter"].get<double>(), diameter, 1e-12);
  double max_difference = 0.0, max_sparse_error = 0.0;
  for (vtkIdType p = 0; p < dense->GetNumberOfPoints(); ++p)
  {
    double x_dense[2] = { 0, 0 }, x_sparse[2] = { 0, 0 }, v[3], x[3];
    for (vtkIdType i = 0; i < n; ++i)
    {
      posed->GetPoint(i, v);
      x_dense[0] += W->GetComponent(p, i) * v[0];
      x_dense[1] += W->GetComponent(p, i) * v[1];
    }
    for (int j = 0; j < K; ++j)
    {
      const auto i = static_cast<vtkIdType>(indices->GetComponent(p, j));
      if (i < 0)
        continue;
      posed->GetPoint(i, v);
      x_sparse[0] += values->GetComponent(p, j) * v[0];
      x_sparse[1] += values->GetComponent(p, j) * v[1];
    }
    deformed->GetPoint(p, x);
    max_sparse_error =
      std::max(max_sparse_error, std::hypot(x[0] - x_sparse[0], x[1] - x_sparse[1]));
    max_difference = std::max(max_difference, std::hypot(x[0] - x_dense[0], x[1] - x_dense[1]));
  }
  EXPECT_LT(max_sparse_error, 1e-12) << "the deformed model is not the sparse weights' deformation";
  EXPECT_NEAR(c["deformation"]["max_difference"].get<double>(), max_difference, 1e-12);
  // w_sparse - w_dense sums to 0 per point with positive part <= the dropped mass, so the
  // deformed points differ by at most max_dropped x the posed cage's diameter
  EXPECT_LE(max_difference, max_dropped * diameter + 1e-12);
  EXPECT_LE(max_difference, c["deformation"]["difference_bound"].get<double>());
}
} // namespace

TEST_F(CLI, DemoWithoutRendering)
{
  const CommandResult r = run("demo --no-render --output-dir " + out("demo"));
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : { "summary.json", "gingerbread2d_weights.vtp", "gingerbread2d_deformed.vtp",
         "kidney3d_weights.vtp", "kidney3d_deformed.vtp" })
    EXPECT_TRUE(fs::exists(dir_ / "demo" / f)) << f;
  std::ifstream in(out("demo/summary.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_LT(s["cases"]["3d"]["statistics"]["reproduction"]["max_error"].get<double>(), 1e-12);
  EXPECT_LT(s["cases"]["2d"]["statistics"]["reproduction"]["max_error"].get<double>(), 1e-12);
  ExpectDemoLBC(dir_ / "demo", s["cases"]["lbc2d"]);
  // The spline cases: C1 to rounding, no fold, the organism fitted to its picture.
  for (const char* c : { "spline2d", "organism_spline" })
  {
    EXPECT_LT(s["cases"][c]["c1_condition_residual"].get<double>(), 1e-12) << c;
    EXPECT_EQ(s["cases"][c]["folded_triangles"].get<int>(), 0) << c;
    EXPECT_GT(s["cases"][c]["min_jacobian"].get<double>(), 0.0) << c;
  }
  EXPECT_LT(s["cases"]["organism_spline"]["fit"]["max_error"].get<double>(), 1e-4);
  for (const char* f : { "gingerbread2d_spline.vtu", "organism_spline.vtu", "organism_deformed.vtp" })
    EXPECT_TRUE(fs::exists(dir_ / "demo" / f)) << f;
  // The organ workflow: the landmarks move the cage affinely (to the celestial coordinates'
  // 1e-5), so the deformation is affine and the field's trilinear interpolation at the organ's
  // points reproduces it to that; the warped label's surface lies within a voxel diagonal of the
  // deformed surface (both smoothed the same way; nearest-neighbour labels move by whole voxels).
  const nlohmann::json& organ = s["cases"]["organ"];
  EXPECT_LT(organ["field"]["max_difference_at_organ_points"].get<double>(), 1e-3);
  EXPECT_EQ(organ["field"]["folded_voxels"].get<int>(), 0);
  EXPECT_LT(organ["warp"]["max_distance_deformed_to_warped_surface"].get<double>(),
    organ["warp"]["voxel_diagonal"].get<double>());
  EXPECT_EQ(organ["cage"]["vertices"].get<int>(), 60);
  EXPECT_GT(organ["cage"]["volume_ratio"].get<double>(), 1.0);
  for (const char* f : { "organ_surface.vtp", "organ_cage.obj", "organ_cage_moved.obj",
         "organ_deformed.vtp", "organ_field.mha", "organ_field_inverse.mha", "organ_label_warped.nii.gz" })
    EXPECT_TRUE(fs::exists(dir_ / "demo" / f)) << f;
  for (const char* png : { "gingerbread2d_weights.png", "gingerbread2d_lbc_weights.png",
         "gingerbread2d_lbc_deformed.png", "gingerbread2d_spline.png", "organism_spline.png",
         "organ_deformed.png", "organ_label_warped.png" })
    EXPECT_FALSE(fs::exists(dir_ / "demo" / png)) << png << " written with --no-render";
}

// ---- mesh-based methods ---------------------------------------------------------------------

TEST_F(CLI, MeshWritesADomainWithControlPointIds)
{
  for (const char* cage : { "cage2d.obj", "cage3d.obj" })
  {
    const std::string out_file = out(std::string(cage) + ".vtu");
    const CommandResult r = run("mesh --cage " + data(cage) + " --cells 2000 --output " + out_file + " -q");
    ASSERT_EQ(r.code, 0) << r.output;
    auto grid = vtkBaryDataIO::Read(out_file);
    auto cagedata = vtkBaryDataIO::Read(data(cage));
    vtkDataArray* ids = grid->GetPointData()->GetArray("ControlPointId");
    ASSERT_NE(ids, nullptr);
    ASSERT_NE(grid->GetPointData()->GetArray("OnCage"), nullptr);
    // every cage point is a mesh vertex at the same place
    vtkIdType found = 0;
    for (vtkIdType v = 0; v < grid->GetNumberOfPoints(); ++v)
    {
      const auto c = static_cast<vtkIdType>(ids->GetTuple1(v));
      if (c < 0)
        continue;
      ++found;
      double a[3], b[3];
      grid->GetPoint(v, a);
      cagedata->GetPoint(c, b);
      EXPECT_EQ(a[0], b[0]);
      EXPECT_EQ(a[1], b[1]);
    }
    EXPECT_EQ(found, cagedata->GetNumberOfPoints()) << cage;
    EXPECT_GT(grid->GetNumberOfCells(), 1000) << cage;
  }
}

TEST_F(CLI, HarmonicWeightsHaveTheirProperties)
{
  const CommandResult r = run("weights --method harmonic --cage " + data("cage2d.obj") +
    " --points " + data("model2d.obj") + " --output " + out("h.vtp") + " --json " + out("h.json") +
    " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(out("h.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["method"], "harmonic");
  EXPECT_LT(s["statistics"]["partition_of_unity"]["max_error"].get<double>(), 1e-10);
  EXPECT_LT(s["statistics"]["reproduction"]["max_error"].get<double>(), 1e-10);
  EXPECT_GE(s["statistics"]["min_weight"].get<double>(), -1e-12) << "2D harmonic weights are >= 0";
  EXPECT_EQ(s["statistics"]["negative_weights"].get<long long>(), 0);
}

TEST_F(CLI, HarmonicOutsidePolicies)
{
  // the posed cage's raised arm lies outside the rest cage
  const std::string base = "weights --method harmonic --cells 800 --cage " + data("cage2d.obj") +
    " --points " + data("cage2d_posed.obj") + " --output " + out("h.vtp");
  const CommandResult refused = run(base);
  ExpectError(refused, "lie outside");
  // the advice in the command line's words (it named OutsidePolicy::Nearest before)
  ExpectError(refused, "set OutsidePolicy (--outside) to nearest");
  EXPECT_EQ(refused.output.find("::"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(out("h.vtp")));
  // celestial coordinates: outside the control points' hull (CelestialOutsidePolicy::Flag before)
  const CommandResult hull = run("weights --method scc --hull-points none --control-points " +
    data("cage2d.obj") + " --points " + data("cage2d_posed.obj") + " --output " + out("s.vtp"));
  ExpectError(hull, "outside the convex hull");
  ExpectError(hull, "set OutsidePolicy (--outside) to nan");
  EXPECT_EQ(hull.output.find("::"), std::string::npos) << hull.output;
  const CommandResult nearest = run(base + " --outside nearest --json " + out("n.json") + " -q");
  ASSERT_EQ(nearest.code, 0) << nearest.output;
  std::ifstream in(out("n.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_GT(s["points"]["outside"].get<long long>(), 0);
  EXPECT_EQ(s["points"]["undefined"].get<long long>(), 0);
  const CommandResult nan = run(base + " --outside nan --json " + out("u.json") + " -q");
  ASSERT_EQ(nan.code, 0) << nan.output;
  std::ifstream iu(out("u.json"));
  const nlohmann::json u = nlohmann::json::parse(iu);
  EXPECT_EQ(u["points"]["undefined"], u["points"]["outside"]);
}

TEST_F(CLI, HarmonicDeformation3D)
{
  const CommandResult r = run("deform --method harmonic --cage " + data("cage3d.obj") +
    " --deformed-cage " + data("cage3d_posed.obj") + " --points " + data("model3d.off") +
    " --cells 8000 --output " + out("d.vtp"));
  ASSERT_EQ(r.code, 0) << r.output;
  auto deformed = vtkBaryDataIO::Read(out("d.vtp"));
  auto rest = vtkBaryDataIO::Read(data("model3d.off"));
  ASSERT_EQ(deformed->GetNumberOfPoints(), rest->GetNumberOfPoints());
  double moved = 0.0;
  for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    rest->GetPoint(i, a);
    deformed->GetPoint(i, b);
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_TRUE(std::isfinite(b[k]));
      moved = std::max(moved, std::abs(a[k] - b[k]));
    }
  }
  EXPECT_GT(moved, 1e-2);
}

// ---- bounded biharmonic weights -----------------------------------------------------------------

namespace
{
/// Max |sum_j w_j - 1| and the extreme weights of the weights array of @p path.
struct WeightCheck
{
  int components = 0;
  vtkIdType points = 0;
  double partition = 0, min = 1, max = 0;
};
WeightCheck CheckWeights(const std::string& path)
{
  WeightCheck c;
  auto result = vtkBaryDataIO::Read(path);
  vtkDataArray* w = result->GetPointData()->GetArray("Weights");
  if (!w)
    return c;
  c.components = w->GetNumberOfComponents();
  c.points = w->GetNumberOfTuples();
  for (vtkIdType p = 0; p < w->GetNumberOfTuples(); ++p)
  {
    double sum = 0.0;
    for (int j = 0; j < w->GetNumberOfComponents(); ++j)
    {
      const double v = w->GetComponent(p, j);
      sum += v;
      c.min = std::min(c.min, v);
      c.max = std::max(c.max, v);
    }
    c.partition = std::max(c.partition, std::abs(sum - 1.0));
  }
  return c;
}

std::string bbw2d_inputs()
{
  return " --method bbw --mesh " + data("cage2d.obj") + " --handles " + data("skeleton2d.tgf") +
    " --points " + data("model2d.obj") + " --fast";
}

/// Largest coordinate difference between the points of two files.
double MaxPointDifference(const std::string& a, const std::string& b)
{
  auto da = vtkBaryDataIO::Read(a);
  auto db = vtkBaryDataIO::Read(b);
  if (da->GetNumberOfPoints() != db->GetNumberOfPoints())
    return 1e300;
  double diff = 0.0;
  for (vtkIdType i = 0; i < da->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    da->GetPoint(i, x);
    db->GetPoint(i, y);
    for (int k = 0; k < 3; ++k)
      diff = std::max(diff, std::abs(x[k] - y[k]));
  }
  return diff;
}
} // namespace

TEST_F(CLI, BBWWeightsOfASkeletonInAPolygon)
{
  const CommandResult r =
    run("weights" + bbw2d_inputs() + " --output " + out("w.vtp") + " --json " + out("w.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("8 handles (0 points, 8 bones; 2D)"), std::string::npos) << r.output;
  const WeightCheck c = CheckWeights(out("w.vtp"));
  EXPECT_EQ(c.components, 8);
  EXPECT_EQ(c.points, vtkBaryDataIO::Read(data("model2d.obj"))->GetNumberOfPoints());
  EXPECT_LE(c.partition, 1e-12);
  EXPECT_GE(c.min, 0.0);
  EXPECT_LE(c.max, 1.0 + 1e-15) << "interpolated at the model's points: convex combinations of "
                                   "mesh weights in [0, 1], up to rounding";
  std::ifstream in(out("w.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["method"], "bbw");
  EXPECT_EQ(s["handles"]["bones"], 8);
  EXPECT_EQ(s["handles"]["point_handles"], 0);
  EXPECT_LE(s["solver"]["max_kkt_residual"].get<double>(), 1e-9);
  EXPECT_EQ(s["solver"]["max_bound_violation"].get<double>(), 0.0);
  EXPECT_EQ(s["solver"]["converged"].get<double>(), 1.0);
  EXPECT_GT(s["solver"]["mesh_vertices"].get<double>(), 1000.0);
}

TEST_F(CLI, BBWCoupledComparesWithFastOnlyWhenAsked)
{
  // The coupled mode (the default) does not solve the fast mode unless --compare-fast asks for
  // the paper's Table 2 comparison, which leaves the weights as they are.
  std::string coupled = bbw2d_inputs();
  coupled.erase(coupled.rfind(" --fast"));
  ASSERT_EQ(run("weights" + coupled + " --output " + out("w.vtp") + " --json " + out("w.json") + " -q").code, 0);
  ASSERT_EQ(run("weights" + coupled + " --compare-fast --output " + out("wc.vtp") + " --json " +
              out("wc.json") + " -q")
              .code,
    0);
  std::ifstream in(out("w.json")), in_compared(out("wc.json"));
  const nlohmann::json s = nlohmann::json::parse(in), sc = nlohmann::json::parse(in_compared);
  EXPECT_EQ(s["solver"]["coupled"].get<double>(), 1.0);
  EXPECT_FALSE(s["solver"].contains("fast_difference_mean"));
  EXPECT_EQ(s["solver"]["fast_iterations"].get<double>(), 0.0);
  const double e_mean = sc["solver"]["fast_difference_mean"].get<double>();
  const double e_max = sc["solver"]["fast_difference_max"].get<double>();
  EXPECT_GT(e_mean, 1e-4); // the paper's Table 2: E_mean 1e-3 .. 5e-3, E_max 0.06 .. 0.4
  EXPECT_LT(e_mean, 1e-2);
  EXPECT_GT(e_max, e_mean);
  EXPECT_LT(e_max, 0.5);
  EXPECT_GT(sc["solver"]["fast_iterations"].get<double>(), 0.0);
  EXPECT_EQ(sc["solver"]["outer_iterations"], s["solver"]["outer_iterations"]);
  const auto plain = vtkBaryDataIO::Read(out("w.vtp")), compared = vtkBaryDataIO::Read(out("wc.vtp"));
  vtkDataArray* w = plain->GetPointData()->GetArray("Weights");
  vtkDataArray* wc = compared->GetPointData()->GetArray("Weights");
  ASSERT_TRUE(w != nullptr && wc != nullptr);
  ASSERT_EQ(w->GetNumberOfTuples(), wc->GetNumberOfTuples());
  ASSERT_EQ(w->GetNumberOfComponents(), wc->GetNumberOfComponents());
  for (vtkIdType i = 0; i < w->GetNumberOfTuples(); ++i)
    for (int k = 0; k < w->GetNumberOfComponents(); ++k)
      ASSERT_EQ(w->GetComponent(i, k), wc->GetComponent(i, k)) << "point " << i << ", handle " << k;
}

TEST_F(CLI, BBWDeformByPoseFileAndByMovedJoints)
{
  ASSERT_EQ(run("weights" + bbw2d_inputs() + " --output " + out("w.vtp") + " -q").code, 0);
  // the bundled pose moves the model; reusing the weights gives the same result
  CommandResult a = run("deform" + bbw2d_inputs() + " --transforms " +
    data("skeleton2d_pose.txt") + " --output " + out("a.vtp"));
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_NE(a.output.find("weights computed"), std::string::npos) << a.output;
  CommandResult b = run("deform --method bbw --handles " + data("skeleton2d.tgf") +
    " --weights " + out("w.vtp") + " --transforms " + data("skeleton2d_pose.txt") + " --output " +
    out("b.vtp"));
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_NE(b.output.find("weights from the input"), std::string::npos) << b.output;
  EXPECT_LT(MaxPointDifference(out("a.vtp"), out("b.vtp")), 1e-12);
  EXPECT_GT(MaxPointDifference(out("a.vtp"), data("model2d.obj")), 0.1) << "the pose must move the arm";

  // One rotation for every bone (a rigid motion of the whole figure), given as joints moved by
  // it: every model point moves by exactly that rigid motion (partition of unity + LBS).
  auto skeleton = vtkBaryDataIO::Read(data("skeleton2d.tgf"));
  const double c = std::cos(0.4), s = std::sin(0.4), tx = 0.3, ty = -0.2;
  {
    std::ofstream obj(out("posed.obj"));
    for (vtkIdType i = 0; i < skeleton->GetNumberOfPoints(); ++i)
    {
      double x[3];
      skeleton->GetPoint(i, x);
      obj << "v " << c * x[0] - s * x[1] + tx << " " << s * x[0] + c * x[1] + ty << " 0\n";
    }
  }
  CommandResult r = run("deform" + bbw2d_inputs() + " --deformed-handles " + out("posed.obj") +
    " --output " + out("r.vtp") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto rigid = vtkBaryDataIO::Read(out("r.vtp"));
  auto model = vtkBaryDataIO::Read(data("model2d.obj"));
  double worst = 0.0;
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    model->GetPoint(i, x);
    rigid->GetPoint(i, y);
    worst = std::max(worst, std::hypot(c * x[0] - s * x[1] + tx - y[0], s * x[0] + c * x[1] + ty - y[1]));
  }
  EXPECT_LT(worst, 1e-5) << "a rigid motion of every bone moves the model rigidly (OBJ keeps 6 digits)";
}

TEST_F(CLI, BBWUsageErrorsExitWith2)
{
  for (const std::string& args :
    { "weights --method bbw --handles " + data("skeleton2d.tgf") + " --points " + data("model2d.obj") +
        " --output " + out("w.vtp"),
      "weights --method mvc --handles " + data("skeleton2d.tgf") + " --mesh " + data("cage2d.obj") +
        " --points " + data("model2d.obj") + " --output " + out("w.vtp"),
      "weights --method bbw --cage " + data("cage2d.obj") + " --handles " + data("skeleton2d.tgf") +
        " --mesh " + data("cage2d.obj") + " --output " + out("w.vtp"),
      "deform" + bbw2d_inputs() + " --output " + out("d.vtp"),
      "deform" + bbw2d_inputs() + " --transforms " + data("skeleton2d_pose.txt") +
        " --deformed-handles " + data("skeleton2d.tgf") + " --output " + out("d.vtp") })
  {
    const CommandResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("usage error"), std::string::npos) << r.output;
  }
  ExpectEmptyFolder();
}

TEST_F(CLI, BBWBadPoseAndBadHandlesAreClearErrors)
{
  {
    std::ofstream(out("pose.txt")) << "1 0 0 0 1 0\n1 0 0 0 1\n";
    const CommandResult r = run("deform" + bbw2d_inputs() + " --transforms " + out("pose.txt") +
      " --output " + out("d.vtp"));
    ExpectError(r, "line 2: 5 numbers");
  }
  {
    std::ofstream(out("pose.txt")) << "1 0 0 0 1 0\n";
    const CommandResult r = run("deform" + bbw2d_inputs() + " --transforms " + out("pose.txt") +
      " --output " + out("d.vtp"));
    ExpectError(r, "1 transforms but the weights have 8 handles");
  }
  {
    // a joint outside the domain: no mesh vertex for it
    std::ofstream(out("far.tgf")) << "1 5 5 0\n2 6 5 0\n#\n1 2\n#\n";
    const CommandResult r = run("weights --method bbw --mesh " + data("cage2d.obj") + " --handles " +
      out("far.tgf") + " --points " + data("model2d.obj") + " --fast --output " + out("w.vtp"));
    ExpectError(r, "bone 0");
  }
  EXPECT_FALSE(fs::exists(out("d.vtp")));
  EXPECT_FALSE(fs::exists(out("w.vtp")));
}

TEST_F(CLI, BBWOnLibiglsKnightMeshAndSkeleton)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl";
  if (!fs::exists(dir + "/decimated-knight.mesh"))
    GTEST_SKIP() << "shared data not found in " << dir;
  const CommandResult r = run("weights --method bbw --fast --mesh " + dir +
    "/decimated-knight.mesh --handles " + dir + "/decimated-knight.tgf --output " + out("k.vtu") +
    " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  const WeightCheck c = CheckWeights(out("k.vtu"));
  EXPECT_EQ(c.components, 7);
  EXPECT_EQ(c.points, 1822);
  EXPECT_LE(c.partition, 1e-12);
  EXPECT_GE(c.min, 0.0);
}

TEST_F(CLI, BBWPointHandlesRotateThroughPseudoEdges)
{
  // Three point handles (no bones) in the gingerbread man; every joint moved by one rotation
  // plus translation. Through the pseudo-edges (0,1), (1,2), (2,0) each handle recovers the full
  // rotation (paper §3.4), so the model moves rigidly; without them the handles only translate
  // and the model does not.
  {
    std::ofstream tgf(out("points.tgf"));
    tgf << "1 0 0.5 0\n2 -0.5 0.2 0\n3 0.15 -0.6 0\n#\n#\n";
    std::ofstream edges(out("pseudo.txt"));
    edges << "# pseudo-edges between point handles\n0 1\n1 2\n2 0\n";
  }
  const double c = std::cos(0.5), s = std::sin(0.5), tx = -0.1, ty = 0.25;
  {
    std::ofstream obj(out("posed.obj"));
    for (auto [x, y] : { std::pair{ 0.0, 0.5 }, { -0.5, 0.2 }, { 0.15, -0.6 } })
      obj << "v " << c * x - s * y + tx << " " << s * x + c * y + ty << " 0\n";
  }
  const std::string inputs = " --method bbw --fast --mesh " + data("cage2d.obj") + " --handles " +
    out("points.tgf") + " --points " + data("model2d.obj") + " --deformed-handles " + out("posed.obj");
  CommandResult r = run("deform" + inputs + " --pseudo-edges " + out("pseudo.txt") + " --output " +
    out("r.vtp") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  CommandResult t = run("deform" + inputs + " --output " + out("t.vtp") + " -q");
  ASSERT_EQ(t.code, 0) << t.output;
  auto model = vtkBaryDataIO::Read(data("model2d.obj"));
  const auto rigid_error = [&](const std::string& path) {
    auto deformed = vtkBaryDataIO::Read(path);
    double worst = 0.0;
    for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
    {
      double x[3], y[3];
      model->GetPoint(i, x);
      deformed->GetPoint(i, y);
      worst = std::max(worst, std::hypot(c * x[0] - s * x[1] + tx - y[0], s * x[0] + c * x[1] + ty - y[1]));
    }
    return worst;
  };
  EXPECT_LT(rigid_error(out("r.vtp")), 1e-5);
  EXPECT_GT(rigid_error(out("t.vtp")), 0.05);
  // a pseudo-edge naming a handle that does not exist
  {
    std::ofstream edges(out("bad.txt"));
    edges << "0 7\n";
  }
  ExpectError(run("deform" + inputs + " --pseudo-edges " + out("bad.txt") + " --output " + out("b.vtp")),
    "pseudo-edge 0 (0, 7)");
}

// ---- celestial coordinates ----------------------------------------------------------------------

TEST_F(CLI, CelestialWeightsAndDeformationOfTheHeart)
{
  for (const std::string method : { "scc", "tcc" })
  {
    const CommandResult r = run("weights --method " + method + " --control-points " +
      data("heart_controls.obj") + " --points " + data("heart.off") + " --output " +
      out(method + ".vtp") + " --json " + out(method + ".json"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("22 free control points (3D)"), std::string::npos) << r.output;
    const WeightCheck c = CheckWeights(out(method + ".vtp"));
    EXPECT_EQ(c.components, 22);
    EXPECT_LE(c.partition, 1e-12);
    EXPECT_GT(c.min, 0.0) << "positive inside the hull";
    std::ifstream in(out(method + ".json"));
    const nlohmann::json s = nlohmann::json::parse(in);
    EXPECT_EQ(s["cage"]["free_points"], true);
    EXPECT_EQ(s["solver"]["not_converged"].get<double>(), 0.0);
    EXPECT_LE(s["statistics"]["reproduction"]["max_error"].get<double>(), 1e-10);
  }
  // deformation by a heartbeat frame, with weights computed or reused
  CommandResult a = run("deform --method scc --control-points " + data("heart_controls.obj") +
    " --deformed-control-points " + data("heartbeat/frame_10.obj") + " --points " +
    data("heart.off") + " --output " + out("a.vtp"));
  ASSERT_EQ(a.code, 0) << a.output;
  CommandResult b = run("deform --method scc --control-points " + data("heart_controls.obj") +
    " --deformed-control-points " + data("heartbeat/frame_10.obj") + " --weights " +
    out("scc.vtp") + " --output " + out("b.vtp"));
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_LT(MaxPointDifference(out("a.vtp"), out("b.vtp")), 1e-12);
  EXPECT_GT(MaxPointDifference(out("a.vtp"), data("heart.off")), 0.02) << "systole moves the heart";
}

// Hull points (--hull-points auto, the default, the paper's §6): a heart far larger than a small
// control set. With none it is an error naming the flag and nothing is written. The weights get
// the 8 corners' columns last and their positions in the field data (the corners of a box holding
// the heart and the controls 0.1 of its diagonal inside); `always` adds them for the controls'
// own points too, `auto` does not;
// `deform` moves the 5 given controls and keeps the corners: the rest pose reproduces the heart,
// a translation of the controls by (d, 0, 0) moves every point by its controls' share of d,
// strictly between 0 and d (the corners hold it), the same with weights computed or reused.
TEST_F(CLI, CelestialHullPointsInWeightsAndDeform)
{
  const double v[5][3] = { { 0, 0, 0 }, { 0.2, 0, 0 }, { 0, 0.2, 0 }, { 0, 0, 0.2 }, { 0.1, 0.1, 0.1 } };
  {
    std::ofstream rest(out("small.obj")), moved(out("moved.obj"));
    for (const auto& c : v)
    {
      rest << "v " << c[0] << " " << c[1] << " " << c[2] << "\n";
      moved << "v " << c[0] + 0.5 << " " << c[1] << " " << c[2] << "\n";
    }
  }
  const std::string base = "--method scc --control-points " + out("small.obj") + " --points " + data("heart.off");
  ExpectError(run("weights " + base + " --hull-points none --output " + out("none.vtp")),
    "(--hull-points) to auto (the default)");
  EXPECT_FALSE(fs::exists(out("none.vtp")));
  const CommandResult w = run("weights " + base + " --output " + out("w.vtp") + " --json " + out("w.json"));
  ASSERT_EQ(w.code, 0) << w.output;
  EXPECT_NE(w.output.find("5 free control points (3D, 8 hull points added)"), std::string::npos) << w.output;
  const WeightCheck c = CheckWeights(out("w.vtp"));
  EXPECT_EQ(c.components, 5 + 8);
  EXPECT_LE(c.partition, 1e-12);
  EXPECT_GT(c.min, 0.0) << "every point strictly inside the added hull";
  auto weighted = vtkBaryDataIO::Read(out("w.vtp"));
  vtkDataArray* added = weighted->GetFieldData()->GetArray("AddedControlPoints");
  ASSERT_NE(added, nullptr);
  EXPECT_EQ(added->GetNumberOfTuples(), 8);
  std::ifstream in(out("w.json"));
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["solver"]["hull_points_added"].get<double>(), 8.0);
  ASSERT_EQ(s["added_control_points"].size(), 8u);
  EXPECT_EQ(s["added_control_points"][7][0].get<double>(), added->GetComponent(7, 0));
  // the corners: a box (corner k = corner 0 + the edges of k's bits, orthogonal edges) holding
  // every heart vertex and control at least pad inside each face, the nearest exactly pad, with
  // pad = 0.1 times the diagonal of the box without it
  auto heart = vtkBaryDataIO::Read(data("heart.off"));
  std::vector<std::array<double, 3>> inner;
  for (vtkIdType p = 0; p < heart->GetNumberOfPoints(); ++p)
  {
    std::array<double, 3> x;
    heart->GetPoint(p, x.data());
    inner.push_back(x);
  }
  for (const auto& control : v)
    inner.push_back({ control[0], control[1], control[2] });
  double h[8][3], e[3][3], length[3], slack[3][2];
  for (vtkIdType k = 0; k < 8; ++k)
    added->GetTuple(k, h[k]);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      e[j][i] = h[1 << j][i] - h[0][i];
  double diag = 0.0; // of the corners' box
  for (int i = 0; i < 3; ++i)
    diag += std::pow(h[7][i] - h[0][i], 2);
  diag = std::sqrt(diag);
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(h[k][i], h[0][i] + ((k & 1) ? e[0][i] : 0) + ((k & 2) ? e[1][i] : 0) + ((k & 4) ? e[2][i] : 0),
        1e-12 * diag);
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      EXPECT_NEAR(e[a][0] * e[b][0] + e[a][1] * e[b][1] + e[a][2] * e[b][2], 0.0, 1e-12 * diag * diag);
  for (int j = 0; j < 3; ++j)
  {
    length[j] = std::sqrt(e[j][0] * e[j][0] + e[j][1] * e[j][1] + e[j][2] * e[j][2]);
    slack[j][0] = slack[j][1] = std::numeric_limits<double>::infinity();
    for (const auto& x : inner)
    {
      const double t =
        ((x[0] - h[0][0]) * e[j][0] + (x[1] - h[0][1]) * e[j][1] + (x[2] - h[0][2]) * e[j][2]) / length[j];
      slack[j][0] = std::min(slack[j][0], t);
      slack[j][1] = std::min(slack[j][1], length[j] - t);
    }
  }
  const double pad = 0.1 *
    std::sqrt(std::pow(length[0] - 2 * slack[0][0], 2) + std::pow(length[1] - 2 * slack[0][0], 2) +
      std::pow(length[2] - 2 * slack[0][0], 2));
  for (int j = 0; j < 3; ++j)
    for (int side = 0; side < 2; ++side)
      EXPECT_NEAR(slack[j][side], pad, 1e-9 * diag) << "axis " << j << " side " << side;
  // auto adds nothing for points strictly inside the controls' hull; always adds the corners
  {
    std::ofstream inside(out("inside.obj"));
    inside << "v 0.05 0.05 0.05\nv 0.08 0.04 0.03\n";
  }
  const std::string small = "weights --method scc --control-points " + out("small.obj") + " --points " +
    out("inside.obj") + " -q --output ";
  ASSERT_EQ(run(small + out("auto.vtp")).code, 0);
  EXPECT_EQ(CheckWeights(out("auto.vtp")).components, 5);
  ASSERT_EQ(run(small + out("always.vtp") + " --hull-points always").code, 0);
  EXPECT_EQ(CheckWeights(out("always.vtp")).components, 5 + 8);
  // deform: the rest pose, then the controls translated
  ASSERT_EQ(run("deform " + base + " --hull-points auto --deformed-control-points " + out("small.obj") +
              " --output " + out("rest.vtp")).code, 0);
  EXPECT_LT(MaxPointDifference(out("rest.vtp"), data("heart.off")), 1e-9 * diag);
  const CommandResult a = run("deform " + base + " --hull-points auto --deformed-control-points " +
    out("moved.obj") + " --output " + out("a.vtp"));
  ASSERT_EQ(a.code, 0) << a.output;
  const CommandResult r = run("deform --method scc --hull-points auto --control-points " + out("small.obj") +
    " --deformed-control-points " + out("moved.obj") + " --weights " + out("w.vtp") + " --output " + out("b.vtp"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_LT(MaxPointDifference(out("a.vtp"), out("b.vtp")), 1e-12);
  auto moved = vtkBaryDataIO::Read(out("a.vtp"));
  vtkDataArray* W = weighted->GetPointData()->GetArray("Weights");
  for (vtkIdType p = 0; p < heart->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3], share = 0.0;
    heart->GetPoint(p, x);
    moved->GetPoint(p, y);
    for (int j = 0; j < 5; ++j)
      share += W->GetComponent(p, j);
    ASSERT_NEAR(y[0] - x[0], 0.5 * share, 1e-9 * diag) << "point " << p;
    ASSERT_GT(y[0] - x[0], 0.0);
    ASSERT_LT(y[0] - x[0], 0.5) << "the corners did not move";
    ASSERT_NEAR(y[1], x[1], 1e-9 * diag);
  }
}

TEST_F(CLI, AnimateWritesFramesAndAParaViewCollection)
{
  // the rest control points first (the heartbeat's frame 0 already has the atria contracted)
  const std::string frames = " " + data("heart_controls.obj") + " " + data("heartbeat/frame_05.obj") +
    " " + data("heartbeat/frame_10.obj");
  const CommandResult r = run("animate --method scc --control-points " + data("heart_controls.obj") +
    " --frames" + frames + " --points " + data("heart.off") + " --output-dir " + out("anim") +
    " --prefix beat --period 0.9 --json " + out("anim.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  // the .pvd lists the three frames with their times, and each frame file reads back
  std::ifstream pvd(out("anim/beat.pvd"));
  const std::string text((std::istreambuf_iterator<char>(pvd)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("type=\"Collection\""), std::string::npos) << text;
  for (const char* entry : { "timestep=\"0\" group=\"\" part=\"0\" file=\"beat_000.vtp\"",
         "timestep=\"0.3\" group=\"\" part=\"0\" file=\"beat_001.vtp\"",
         "timestep=\"0.6\" group=\"\" part=\"0\" file=\"beat_002.vtp\"" })
    EXPECT_NE(text.find(entry), std::string::npos) << entry << " in\n" << text;
  // frame 0 is the rest pose: the heart is reproduced (linear precision of celestial coordinates)
  EXPECT_LT(MaxPointDifference(out("anim/beat_000.vtp"), data("heart.off")), 1e-5);
  EXPECT_GT(MaxPointDifference(out("anim/beat_002.vtp"), data("heart.off")), 0.02);
  // a frame with the wrong number of points
  const CommandResult bad = run("animate --method scc --control-points " + data("heart_controls.obj") +
    " --frames " + data("cage3d.obj") + " --points " + data("heart.off") + " --output-dir " + out("bad"));
  ExpectError(bad, "must hold the 22 points");
}

TEST_F(CLI, CelestialUsageAndInputErrors)
{
  for (const std::string& args :
    { "weights --method scc --cage " + data("heart_controls.obj") + " --points " + data("heart.off") +
        " --output " + out("w.vtp"),
      "weights --method mvc --control-points " + data("heart_controls.obj") + " --points " +
        data("heart.off") + " --output " + out("w.vtp"),
      "weights --method scc --control-points " + data("heart_controls.obj") + " --user-weights " +
        data("heart_controls.obj") + " --points " + data("heart.off") + " --output " + out("w.vtp") })
  {
    const CommandResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
  }
  // points outside the hull: hull points added by default (auto), an error with none
  ExpectError(run("weights --method scc --hull-points none --control-points " + data("cage2d.obj") +
                " --points " + data("model3d.off") + " --output " + out("w.vtp")),
    "outside");
  {
    std::ofstream(out("s.txt")) << "# s_i\n1 0 0\n0 0 0 0\n";
    const CommandResult r = run("weights --method tcc --control-points " + data("heart_controls.obj") +
      " --user-weights " + out("s.txt") + " --points " + data("heart.off") + " --output " + out("w.vtp"));
    ExpectError(r, "user");
  }
  EXPECT_FALSE(fs::exists(out("w.vtp")));
}

// ---- local barycentric coordinates ------------------------------------------------------------

namespace
{
nlohmann::json read_json(const std::string& path)
{
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// The authors' LBC cage @p name as an .obj with only its `v` lines (their polygon, in order).
std::string authors_vertex_only_cage(const std::string& name, const std::string& to)
{
  std::ifstream in(std::string(BARYLAB_SHARED_DIR) + "/lbc/cages/" + name + "-control-edgeset.obj");
  std::ofstream o(to);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("v ", 0) == 0)
      o << line << "\n";
  return to;
}
} // namespace

TEST_F(CLI, LBCWeightsOnTheBundledCage)
{
  // interpolated at the model's vertices: barycentric to rounding (piecewise-linear interpolation
  // of vertex weights that reproduce their vertex keeps reproduction)
  const CommandResult r = run("weights --method lbc --cage " + data("cage2d.obj") + " --points " +
    data("model2d.obj") + " --cells 800 --output " + out("l.vtp") + " --json " + out("l.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("converged 1"), std::string::npos) << r.output;
  const nlohmann::json s = read_json(out("l.json"));
  EXPECT_EQ(s["method"], "lbc");
  EXPECT_EQ(s["cage"]["control_points"], 20);
  for (const char* key : { "mesh_vertices", "mesh_cells", "iterations", "primal_residual",
         "dual_residual", "primal_threshold", "dual_threshold", "objective", "converged",
         "partition_error", "reproduction_error", "geodesic_seconds", "factor_seconds",
         "admm_seconds", "solve_seconds" })
    EXPECT_TRUE(s["solver"].contains(key)) << key;
  EXPECT_EQ(s["solver"]["converged"].get<double>(), 1.0);
  EXPECT_GT(s["solver"]["iterations"].get<double>(), 0.0);
  EXPECT_LT(s["statistics"]["partition_of_unity"]["max_error"].get<double>(), 1e-10);
  EXPECT_LT(s["statistics"]["reproduction"]["max_error"].get<double>(), 1e-10);
  EXPECT_GE(s["statistics"]["min_weight"].get<double>(), 0.0);
  auto result = vtkBaryDataIO::Read(out("l.vtp"));
  ASSERT_NE(result->GetPointData()->GetArray("Weights"), nullptr);
  EXPECT_EQ(result->GetNumberOfPoints(), vtkBaryDataIO::Read(data("model2d.obj"))->GetNumberOfPoints());
}

// --stopping: both rules run through the command line; the converged rule (the default: the
// same run without the flag) meets the paper's thresholds and its own residual targets (root
// mean square <= 10 x 10^3 tolerance / #C; with residual balancing it may stop in fewer
// iterations than the paper's rule, 300 against 370 here); a bad value is named.
TEST_F(CLI, LBCStoppingRules)
{
  const std::string base =
    "weights --method lbc --cage " + data("cage2d.obj") + " --cells 400 --threads 1";
  const CommandResult paper =
    run(base + " --stopping paper --output " + out("p.vtu") + " --json " + out("p.json"));
  ASSERT_EQ(paper.code, 0) << paper.output;
  const CommandResult converged =
    run(base + " --stopping converged --output " + out("c.vtu") + " --json " + out("c.json"));
  ASSERT_EQ(converged.code, 0) << converged.output;
  const CommandResult fallback = run(base + " --output " + out("d.vtu") + " --json " + out("d.json"));
  ASSERT_EQ(fallback.code, 0) << fallback.output;
  const nlohmann::json p = read_json(out("p.json"))["solver"], c = read_json(out("c.json"))["solver"];
  EXPECT_EQ(read_json(out("d.json"))["solver"]["iterations"], c["iterations"]);
  EXPECT_EQ(p["converged"].get<double>(), 1.0);
  EXPECT_EQ(c["converged"].get<double>(), 1.0);
  EXPECT_LE(c["primal_residual"].get<double>(), c["primal_threshold"].get<double>());
  EXPECT_LE(c["dual_residual"].get<double>(), c["dual_threshold"].get<double>());
  const double root = std::sqrt(c["primal_threshold"].get<double>() / 1e-6); // sqrt(N)
  EXPECT_LE(c["primal_residual"].get<double>() / root, 10 * 1e-3 / 20);
  EXPECT_LE(c["dual_residual"].get<double>() / root, 10 * 1e-2 / 20);
  const CommandResult bad = run(base + " --stopping soon --output " + out("b.vtu"));
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.output.find("--stopping"), std::string::npos) << bad.output;
}

TEST_F(CLI, LBCWithoutPointsWritesTheDomainMeshWithItsWeights)
{
  const CommandResult r = run("weights --method lbc --cage " + data("cage2d.obj") +
    " --cells 300 --locality linear --output " + out("d.vtu") + " --json " + out("d.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json s = read_json(out("d.json"));
  auto mesh = vtkBaryDataIO::Read(out("d.vtu"));
  EXPECT_EQ(mesh->GetNumberOfPoints(), s["solver"]["mesh_vertices"].get<double>());
  EXPECT_EQ(mesh->GetNumberOfCells(), s["solver"]["mesh_cells"].get<double>());
  ASSERT_NE(mesh->GetPointData()->GetArray("Weights"), nullptr);
  EXPECT_EQ(mesh->GetPointData()->GetArray("Weights")->GetNumberOfComponents(), 20);
  EXPECT_LT(s["statistics"]["reproduction"]["max_error"].get<double>(), 1e-12);
  // the same for harmonic coordinates
  ASSERT_EQ(run("weights --method harmonic --cage " + data("cage2d.obj") + " --cells 300 --output " +
              out("h.vtu") + " -q").code, 0);
  EXPECT_EQ(vtkBaryDataIO::Read(out("h.vtu"))->GetNumberOfPoints(), mesh->GetNumberOfPoints());
}

TEST_F(CLI, HarmonicOnAGivenMeshEqualsTheMeshItMakes)
{
  // the mesh the method would make, given with --mesh, is used as is: the same weights at the
  // same vertices (and the command without --mesh meshes the cage only once)
  ASSERT_EQ(run("mesh --cage " + data("cage2d.obj") + " --cells 500 --output " + out("m.vtu") +
              " -q").code, 0);
  ASSERT_EQ(run("weights --method harmonic --cage " + data("cage2d.obj") + " --mesh " +
              out("m.vtu") + " --output " + out("given.vtu") + " -q").code, 0);
  ASSERT_EQ(run("weights --method harmonic --cage " + data("cage2d.obj") + " --cells 500 " +
              "--output " + out("made.vtu") + " -q").code, 0);
  auto given = vtkBaryDataIO::Read(out("given.vtu"));
  auto made = vtkBaryDataIO::Read(out("made.vtu"));
  ASSERT_EQ(given->GetNumberOfPoints(), made->GetNumberOfPoints());
  vtkDataArray* wg = given->GetPointData()->GetArray("Weights");
  vtkDataArray* wm = made->GetPointData()->GetArray("Weights");
  ASSERT_NE(wg, nullptr);
  ASSERT_NE(wm, nullptr);
  double most = 0.0;
  for (vtkIdType p = 0; p < wg->GetNumberOfTuples(); ++p)
    for (int c = 0; c < wg->GetNumberOfComponents(); ++c)
      most = std::max(most, std::abs(wg->GetComponent(p, c) - wm->GetComponent(p, c)));
  EXPECT_EQ(most, 0.0);
  // deform computes on a mesh of its own: --mesh there is a usage error naming the way
  const CommandResult r = run("deform --method harmonic --cage " + data("cage2d.obj") +
    " --deformed-cage " + data("cage2d_posed.obj") + " --points " + data("model2d.obj") +
    " --mesh " + out("m.vtu") + " --output " + out("d.vtp"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("barylab weights --method harmonic --mesh DOMAIN"), std::string::npos)
    << r.output;
}

TEST_F(CLI, LBCOnTheAuthorsCagesAndTriangulation)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/lbc";
  if (!fs::exists(dir + "/reference/LBClogo.mesh.obj"))
    GTEST_SKIP() << "shared data not found in " << dir;
  // their v-only polygon, meshed here
  const std::string cage = authors_vertex_only_cage("LBClogo", out("logo.obj"));
  CommandResult r = run("weights --method lbc --cage " + cage + " --cells 1000 --output " +
    out("logo.vtu") + " --json " + out("logo.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json s = read_json(out("logo.json"));
  EXPECT_EQ(s["cage"]["dimension"], 2);
  EXPECT_EQ(s["cage"]["control_points"], 6);
  EXPECT_EQ(s["solver"]["converged"].get<double>(), 1.0);
  // their own triangulation as the domain (--mesh), weights at its vertices
  r = run("weights --method lbc --cage " + dir + "/cages/LBClogo-control-edgeset.obj --mesh " + dir +
    "/reference/LBClogo.mesh.obj --distance-normalization global --output " + out("ref.vtu") +
    " --json " + out("ref.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  s = read_json(out("ref.json"));
  EXPECT_EQ(s["solver"]["mesh_vertices"].get<double>(), 1621);
  EXPECT_EQ(s["points"]["count"], 1621);
  EXPECT_LT(s["statistics"]["partition_of_unity"]["max_error"].get<double>(), 1e-12);
  // a mesh of another cage is refused, naming the cage vertex
  r = run("weights --method lbc --cage " + data("cage2d.obj") + " --mesh " + dir +
    "/reference/LBClogo.mesh.obj --output " + out("bad.vtu"));
  ExpectError(r, "cage vertex 0 at (0, -0.4) is not a boundary vertex of the mesh");
  EXPECT_FALSE(fs::exists(out("bad.vtu")));
}

TEST_F(CLI, LBCBadInputIsAClearError)
{
  const std::string w = " --output " + out("w.vtu") + " --json " + out("w.json");
  ExpectError(run("weights --method lbc --cage " + data("bad/open_cage.obj") + " --cells 300" + w),
    "not closed: edge (");
  ExpectError(run("weights --method lbc --cage " + data("bad/nan_cage.obj") + w), "not finite");
  ExpectError(run("weights --method lbc --cage " + data("bad/bowtie2d.obj") + w), "not simple");
  ExpectError(run("weights --method lbc --cage " + data("cage2d.obj") +
                " --cells 300 --max-iterations 1" + w),
    "did not converge in 1 iterations");
  // points outside the cage under the default policy
  ExpectError(run("weights --method lbc --cage " + data("cage2d.obj") + " --cells 300 --points " +
                data("cage3d.obj") + w),
    "outside");
  ExpectEmptyFolder();
  // usage errors: exit code 2
  EXPECT_EQ(run("weights --method lbc --cage " + data("cage2d.obj") + " --locality cubic" + w).code, 2);
  EXPECT_EQ(run("weights --method lbc --cage " + data("cage2d.obj") + " --primal-tolerance 2" + w).code, 2);
  EXPECT_EQ(run("weights --method lbc --cage " + data("cage2d.obj") + " --handles " +
                data("skeleton2d.tgf") + w).code, 2);
  EXPECT_EQ(run("deform --method lbc --cage " + data("cage2d.obj") + " --deformed-cage " +
                data("cage2d_posed.obj") + " --mesh " + data("cage2d.obj") + " --points " +
                data("model2d.obj") + " --output " + out("d.vtp")).code, 2);
  ExpectEmptyFolder();
}

// ---- locality statistics and sparse weights (stats --locality, reduce, deform --weights) ----

namespace
{
/// Max |a - b| over points and coordinates.
double MaxPointDistance(vtkDataSet* a, vtkDataSet* b)
{
  EXPECT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  double worst = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints() && i < b->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    a->GetPoint(i, x);
    b->GetPoint(i, y);
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(x[k] - y[k]));
  }
  return worst;
}
} // namespace

TEST_F(CLI, ReducedWeightsDeformLikeTheSameDenseWeights)
{
  ASSERT_EQ(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
              " --output " + out("w.vtp") + " -q")
              .code,
    0);
  // mean value weights are global: a threshold of 0.005 drops a real part of them
  const CommandResult r = run("reduce --input " + out("w.vtp") + " --cage " + data("cage3d.obj") +
    " --output " + out("sparse.vtp") + " --threshold 0.005 --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json s = nlohmann::json::parse(r.output);
  EXPECT_EQ(s["controls"], 72);
  EXPECT_LT(s["K"].get<int>(), 72);
  EXPECT_LT(s["partition_error"].get<double>(), 1e-13); // row sum
  EXPECT_GT(s["max_dropped"].get<double>(), 0.0);
  EXPECT_NEAR(s["memory_fraction"].get<double>(), 12.0 * s["K"].get<int>() / (8.0 * 72), 1e-15);
  auto sparse = vtkBaryDataIO::Read(out("sparse.vtp"));
  EXPECT_EQ(sparse->GetPointData()->GetArray("Weights"), nullptr);
  vtkDataArray* indices = sparse->GetPointData()->GetArray("WeightsIndices");
  vtkDataArray* values = sparse->GetPointData()->GetArray("WeightsValues");
  ASSERT_NE(indices, nullptr);
  ASSERT_NE(values, nullptr);
  EXPECT_EQ(indices->GetNumberOfComponents(), s["K"].get<int>());

  // The same reduced weights as a dense array, written by the test itself.
  vtkNew<vtkDoubleArray> dense;
  dense->SetName("Weights");
  dense->SetNumberOfComponents(72);
  dense->SetNumberOfTuples(sparse->GetNumberOfPoints());
  dense->Fill(0.0);
  for (vtkIdType p = 0; p < sparse->GetNumberOfPoints(); ++p)
    for (int k = 0; k < indices->GetNumberOfComponents(); ++k)
      if (indices->GetComponent(p, k) >= 0)
        dense->SetComponent(p, static_cast<int>(indices->GetComponent(p, k)), values->GetComponent(p, k));
  auto densified = vtkSmartPointer<vtkDataSet>::Take(sparse->NewInstance());
  densified->DeepCopy(sparse);
  densified->GetPointData()->RemoveArray("WeightsIndices");
  densified->GetPointData()->RemoveArray("WeightsValues");
  densified->GetPointData()->AddArray(dense);
  vtkBaryDataIO::Write(densified, out("densified.vtp"));

  const std::string deform = "deform --cage " + data("cage3d.obj") + " --deformed-cage " +
    data("cage3d_posed.obj") + " --output ";
  for (const char* name : { "sparse", "densified", "w" })
  {
    const CommandResult d = run(deform + out(std::string(name) + "_posed.vtp") + " --weights " +
      out(std::string(name) + ".vtp"));
    ASSERT_EQ(d.code, 0) << d.output;
    EXPECT_NE(d.output.find("weights from the input"), std::string::npos) << d.output;
  }
  // with --points too (the compact pair is attached to the model)
  ASSERT_EQ(run(deform + out("sparse_posed2.vtp") + " --weights " + out("sparse.vtp") +
              " --points " + data("model3d.off") + " -q")
              .code,
    0);
  auto a = vtkBaryDataIO::Read(out("sparse_posed.vtp"));
  auto b = vtkBaryDataIO::Read(out("densified_posed.vtp"));
  auto c = vtkBaryDataIO::Read(out("w_posed.vtp"));
  auto a2 = vtkBaryDataIO::Read(out("sparse_posed2.vtp"));
  EXPECT_LE(MaxPointDistance(a, b), 1e-12); // same weights, sums in another order
  EXPECT_LE(MaxPointDistance(a, a2), 0.0);
  // against the full weights: |x_r - x| <= ||w_r - w||_1 max_i |c'_i - o| <= about
  // 2 max_dropped x (the posed cage's bounding-box diagonal)
  auto posed = vtkBaryDataIO::Read(data("cage3d_posed.obj"));
  EXPECT_LE(MaxPointDistance(a, c), 2.01 * s["max_dropped"].get<double>() * posed->GetLength());
  EXPECT_GT(MaxPointDistance(a, c), 0.0);
}

TEST_F(CLI, ReduceAffineAndErrors)
{
  ASSERT_EQ(run("weights --cage " + data("cage3d.obj") + " --points " + data("model3d.off") +
              " --output " + out("w.vtp") + " -q")
              .code,
    0);
  const CommandResult r = run("reduce --input " + out("w.vtp") + " --cage " + data("cage3d.obj") +
    " --output " + out("affine.vtp") + " --threshold 0.005 --renormalize affine --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json s = nlohmann::json::parse(r.output);
  EXPECT_LT(s["partition_error"].get<double>(), 1e-12);
  EXPECT_LT(s["reproduction_error"].get<double>(), 1e-12);
  const CommandResult t = run("reduce --input " + out("w.vtp") + " --output " + out("t.vtp"));
  ASSERT_EQ(t.code, 0) << t.output;
  EXPECT_NE(t.output.find("of the dense array"), std::string::npos) << t.output;

  // a usage error in the command line's words (it said "connect the cage to input port 1
  // (SetCageData)" before)
  const CommandResult affine = run("reduce --input " + out("w.vtp") + " --output " + out("x.vtp") +
    " --renormalize affine");
  EXPECT_EQ(affine.code, 2) << affine.output;
  EXPECT_NE(affine.output.find("--renormalize affine needs --cage"), std::string::npos) << affine.output;
  EXPECT_EQ(affine.output.find("SetCageData"), std::string::npos) << affine.output;
  ExpectError(run("reduce --input " + out("w.vtp") + " --output " + out("x.vtp") + " --array Nope"),
    "no point-data array 'Nope'");
  ExpectError(run("reduce --input " + out("w.vtp") + " --cage " + data("cage2d.obj") +
                " --output " + out("x.vtp")),
    "the cage has 20 points");
  ExpectError(run("reduce --input " + out("w.vtp") + " --output " + out("x.obj")), "x.obj");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
  EXPECT_EQ(run("reduce --input " + out("w.vtp") + " --output " + out("x.vtp") +
              " --renormalize maybe")
              .code,
    2);
  // compact weights for another cage
  ExpectError(run("deform --cage " + data("cage2d.obj") + " --deformed-cage " +
                data("cage2d_posed.obj") + " --weights " + out("t.vtp") + " --output " + out("d.vtp")),
    "are for 72 control points but the cage");
}

TEST_F(CLI, LocalityStatisticsOfTwoMethodsOnTheBundled2DCage)
{
  for (const char* method : { "mvc", "harmonic" })
    ASSERT_EQ(run(std::string("weights --method ") + method + " --cage " + data("cage2d.obj") +
                " --points " + data("model2d.obj") + " --output " + out(std::string(method) + ".vtp") +
                " -q")
                .code,
      0)
      << method;
  const CommandResult r = run("stats --locality --input " + out("mvc.vtp") + " --input " +
    out("harmonic.vtp") + " --json --csv " + out("cmp") + " --json-output " + out("cmp.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["locality"].size(), 2u);
  std::ifstream file(out("cmp.json"));
  EXPECT_EQ(nlohmann::json::parse(file), j);
  for (const nlohmann::json& s : j["locality"])
  {
    SCOPED_TRACE(s["label"].get<std::string>());
    EXPECT_EQ(s["controls"], 20);
    EXPECT_EQ(s["measure"], "area"); // model2d.obj is a planar triangle mesh
    EXPECT_DOUBLE_EQ(s["threshold"].get<double>(), 1e-3 / 20);
    // Q(1) = 1: the weights sum to one, so one of the 20 is >= 1/20 > threshold, everywhere
    const auto& Q = s["Q"];
    ASSERT_EQ(Q.size(), 20u);
    EXPECT_NEAR(Q[0].get<double>(), 1.0, 1e-12);
    double sum = 0.0;
    for (std::size_t k = 0; k < Q.size(); ++k)
    {
      sum += Q[k].get<double>();
      if (k > 0)
      {
        EXPECT_LE(Q[k].get<double>(), Q[k - 1].get<double>()); // non-increasing
      }
    }
    EXPECT_NEAR(sum, s["mean_support"].get<double>(), 1e-9); // mean support = sum_k Q(k)
    EXPECT_LE(s["max_support"].get<double>(), 20.0);
    EXPECT_GE(s["mean_support"].get<double>(), 1.0);
    const auto& P = s["P"];
    ASSERT_EQ(P.size(), s["t"].size());
    for (std::size_t i = 0; i < P.size(); ++i)
    {
      // in [0, 1] up to the rounding of measure-weighted sums
      EXPECT_GE(P[i].get<double>(), 0.0);
      EXPECT_LE(P[i].get<double>(), 1.0 + 1e-12);
      if (i > 0)
      {
        EXPECT_GE(P[i].get<double>(), P[i - 1].get<double>() - 1e-15); // a CDF in t
      }
    }
  }
  // harmonic coordinates are a convex combination (0 <= w <= 1): P(1) = 1
  EXPECT_NEAR(j["locality"][1]["P"].back().get<double>(), 1.0, 1e-12);
  EXPECT_EQ(j["locality"][0]["t"], j["locality"][1]["t"]);

  std::ifstream pcsv(out("cmp_P.csv")), qcsv(out("cmp_Q.csv"));
  std::string header;
  ASSERT_TRUE(std::getline(pcsv, header));
  EXPECT_EQ(header, "t,P_mvc,P_harmonic");
  ASSERT_TRUE(std::getline(qcsv, header));
  EXPECT_EQ(header, "k,Q_mvc,Q_harmonic");
  int rows = 0;
  for (std::string line; std::getline(qcsv, line);)
    ++rows;
  EXPECT_EQ(rows, 20);

  // text output and errors
  const CommandResult t = run("stats --locality --input " + out("mvc.vtp"));
  ASSERT_EQ(t.code, 0) << t.output;
  EXPECT_NE(t.output.find("mean"), std::string::npos) << t.output;
  EXPECT_EQ(run("stats --input " + out("mvc.vtp") + " --input " + out("harmonic.vtp")).code, 2);
  ExpectError(run("stats --locality --input " + out("mvc.vtp") + " --array Nope"),
    "no point-data array 'Nope'");
}

TEST_F(CLI, FieldsGradientNormsAndLevelSetsOfLinearFields)
{
  // two linear fields on the gingerbread triangles: their gradients are exact on every
  // triangle, so VTK's gradient filter must give |grad| = sqrt(13) and 1 everywhere, and the
  // level sets of w1 = 0.5 - x are the lines x = 0.5 - level
  vtkSmartPointer<vtkDataSet> mesh = vtkBaryDataIO::Read(data("model2d.obj"));
  vtkNew<vtkDoubleArray> w;
  w->SetName("Weights");
  w->SetNumberOfComponents(2);
  w->SetNumberOfTuples(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double p[3];
    mesh->GetPoint(i, p);
    w->SetComponent(i, 0, 2.0 * p[0] + 3.0 * p[1]);
    w->SetComponent(i, 1, 0.5 - p[0]);
  }
  mesh->GetPointData()->AddArray(w);
  vtkBaryDataIO::Write(mesh, out("linear.vtp"));
  const CommandResult r = run("fields --input " + out("linear.vtp") + " --output " +
    out("gradient.vtp") + " --level-sets " + out("levels.vtp") +
    " --control 1 --level 0.3 --level 0.6 --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto summary = nlohmann::json::parse(r.output);
  EXPECT_EQ(summary["level_sets"]["levels"].size(), 2u);

  vtkSmartPointer<vtkDataSet> g = vtkBaryDataIO::Read(out("gradient.vtp"));
  vtkDataArray* norm = g->GetPointData()->GetArray("WeightsGradientNorm");
  ASSERT_NE(norm, nullptr);
  ASSERT_EQ(norm->GetNumberOfComponents(), 2);
  double worst = 0.0;
  for (vtkIdType i = 0; i < norm->GetNumberOfTuples(); ++i)
  {
    worst = std::max(worst, std::abs(norm->GetComponent(i, 0) - std::sqrt(13.0)));
    worst = std::max(worst, std::abs(norm->GetComponent(i, 1) - 1.0));
  }
  EXPECT_LT(worst, 1e-12) << worst; // exact for linear fields (1e-6 while .obj was read as float)

  vtkSmartPointer<vtkDataSet> levels = vtkBaryDataIO::Read(out("levels.vtp"));
  ASSERT_GT(levels->GetNumberOfPoints(), 20);
  int at_03 = 0, at_06 = 0;
  for (vtkIdType i = 0; i < levels->GetNumberOfPoints(); ++i)
  {
    double p[3];
    levels->GetPoint(i, p);
    const bool a = std::abs(p[0] - 0.2) < 1e-6, b = std::abs(p[0] + 0.1) < 1e-6;
    EXPECT_TRUE(a || b) << "level-set point at x = " << p[0];
    at_03 += a;
    at_06 += b;
  }
  EXPECT_GT(at_03, 5);
  EXPECT_GT(at_06, 5);
}

TEST_F(CLI, FieldsOfComputedWeightsAndErrors)
{
  ASSERT_EQ(run("weights -q --cage " + data("cage2d.obj") + " --points " + data("model2d.obj") +
              " --output " + out("w.vtp")).code, 0);
  // default level: the influence threshold 1e-3 / 20
  CommandResult r = run("fields --input " + out("w.vtp") + " --output " + out("g.vtp") +
    " --level-sets " + out("l.vtp") + " --control 14 --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto summary = nlohmann::json::parse(r.output);
  EXPECT_DOUBLE_EQ(summary["level_sets"]["levels"][0].get<double>(), 5e-5);
  EXPECT_GT(summary["level_sets"]["cells"].get<int>(), 0);
  ASSERT_EQ(summary["gradient_norm"]["max"].size(), 20u);
  for (const auto& v : summary["gradient_norm"]["max"])
    EXPECT_TRUE(std::isfinite(v.get<double>()) && v.get<double>() > 0.0);

  // a point cloud has no gradient; a missing component; nothing to write; a missing array
  vtkSmartPointer<vtkDataSet> mesh = vtkBaryDataIO::Read(out("w.vtp"));
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(vtkPointSet::SafeDownCast(mesh)->GetPoints());
  cloud->GetPointData()->ShallowCopy(mesh->GetPointData());
  vtkBaryDataIO::Write(cloud, out("points_only.vtp"));
  ExpectError(run("fields --input " + out("points_only.vtp") + " --output " + out("x.vtp")),
    "gradient norms need a mesh");
  ExpectError(run("fields --input " + out("w.vtp") + " --level-sets " + out("x.vtp") +
                " --control 20"),
    "control 20 does not exist");
  ExpectError(run("fields --input " + out("w.vtp") + " --output " + out("x.vtp") + " --array W"),
    "no point-data array 'W'");
  EXPECT_EQ(run("fields --input " + out("w.vtp")).code, 2);
  // NaN weights (e.g. points outside, computed with --outside nan)
  vtkDataArray* weights = mesh->GetPointData()->GetArray("Weights");
  weights->SetComponent(5, 3, std::nan(""));
  vtkBaryDataIO::Write(mesh, out("nan.vtp"));
  ExpectError(run("fields --input " + out("nan.vtp") + " --output " + out("x.vtp")),
    "the weights of point 5 hold NaN");
  ExpectError(run("fields --input " + out("nan.vtp") + " --level-sets " + out("x.vtp")),
    "the weights of point 5 hold NaN");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
}

// ---- hostile input (issue 17): refused with one line, nothing written, inputs untouched ----

TEST_F(CLI, UnsafeFilesAreRefusedInOneLine)
{
  // a short array in a legacy file (heap corruption in 'fields' before), a cell naming a point
  // that does not exist (SIGSEGV in stats --locality, fields, render before)
  const std::string head = "# vtk DataFile Version 3.0\nbad\nASCII\nDATASET POLYDATA\n";
  {
    std::ofstream f(out("short.vtk"));
    f << head << "POINTS 3 double\n0.2 0.2 0\n0.3 0.3 0\n0.4 0.2 0\nPOINT_DATA 3\n"
      << "SCALARS Weights double 2\nLOOKUP_TABLE default\n0.5 0.5\n0.5 0.5\n";
  }
  {
    std::ofstream f(out("cell.vtk"));
    f << head << "POINTS 3 double\n0 0 0\n1 0 0\n0 1 0\nPOLYGONS 1 4\n3 0 1 7\n";
  }
  for (const std::string& command :
    { "stats --input " + out("short.vtk"), "fields --input " + out("short.vtk") + " --output " +
        out("g.vtp"), "stats --locality --input " + out("cell.vtk") })
  {
    const CommandResult r = run(command);
    ExpectError(r, "cannot read '");
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  EXPECT_FALSE(fs::exists(out("g.vtp")));
  ExpectError(run("stats --locality --input " + out("cell.vtk")), "cell 0 names point 7");
}

TEST_F(CLI, RawBytesOfArgumentsAndFilesAreEscapedInOneLine)
{
  // an unknown --method and a bad token of a binary file were echoed raw (terminal escapes,
  // line breaks): every message is one printable line, bytes that are not text as \xNN
  const std::string w = " --cage " + data("cage2d.obj") + " --points " + data("model2d.obj") +
    " --output " + out("raw.vtp");
  const CommandResult method = run("weights --method '\x1b[31mred\nx\xff'" + w);
  EXPECT_NE(method.code, 0) << method.output;
  EXPECT_EQ(method.output.find('\x1b'), std::string::npos) << method.output;
  EXPECT_NE(method.output.find("\\x1b[31mred x\\xff"), std::string::npos) << method.output;
  EXPECT_EQ(method.output.rfind("barylab: ", 0), 0u) << method.output;
  EXPECT_LE(std::count(method.output.begin(), method.output.end(), '\n'), 2) << method.output;
  {
    std::ofstream f(out("binary.off"), std::ios::binary);
    f << "OFF\n3 1 0\n0 0 \x1b\x01\xfe\n1 0 0\n0 1 0\n3 0 1 2\n";
  }
  const CommandResult file = run("stats --input " + out("binary.off"));
  ExpectError(file, "'\\x1b\\x01\\xfe' is not a number");
  EXPECT_EQ(std::count(file.output.begin(), file.output.end(), '\n'), 1) << file.output;
  EXPECT_FALSE(fs::exists(out("raw.vtp")));
}

TEST_F(CLI, OptionsOutOfRangeOrNotFiniteAreUsageErrors)
{
  const std::string w = "weights --cage " + data("cage2d.obj") + " --points " +
    data("model2d.obj") + " --output " + out("w.vtp");
  EXPECT_EQ(run(w + " --boundary-tolerance nan").code, 2);
  EXPECT_EQ(run(w + " --threads inf").code, 2);
  EXPECT_EQ(run(w + " --method lbc --relaxed-epsilon nan").code, 2);
  EXPECT_EQ(run(w + " --method harmonic --cells 1.5").code, 2);
  const std::string r = "render --input " + data("model2d.obj") + " --output " + out("r.png");
  EXPECT_EQ(run(r + " --size 100000").code, 2); // killed for memory before
  EXPECT_EQ(run(r + " --size -5").code, 2);      // silently 300 x 300 before
  const std::string a = "animate --method scc --control-points " + data("heart_controls.obj") +
    " --points " + data("heart.off") + " --frames " + data("heartbeat/frame_00.obj") +
    " --output-dir " + out("anim");
  EXPECT_EQ(run(a + " --period nan").code, 2);
  EXPECT_EQ(run(a + " --prefix ../../x").code, 2); // wrote outside --output-dir before
  const std::string m = "mesh --cage " + data("cage3d.obj") + " --output " + out("m.vtu");
  EXPECT_EQ(run(m + " --radius-edge-ratio nan").code, 2);
  EXPECT_EQ(run(m + " --radius-edge-ratio 1.0").code, 2); // ran 4+ minutes to 4.8 GB before
  EXPECT_EQ(run("weights \"\" --x").code, 2); // CLI11 looped forever (found by fuzzing)
  EXPECT_EQ(run(m + " --min-angle 25").code, 2);
  ExpectEmptyFolder();
  // the same command lines with sensible values are not usage errors (so the 2s above come
  // from the values)
  EXPECT_NE(run(w + " --boundary-tolerance 1e-9 -q").code, 2);
  EXPECT_NE(run(r + " --size 200").code, 2);
  EXPECT_EQ(run(a + " --period 2 --prefix beat -q").code, 0);
  EXPECT_TRUE(fs::exists(out("anim/beat.pvd")));
  EXPECT_EQ(run(m + " --radius-edge-ratio 1.1 -q").code, 0);
  // --help shows the one range the command enforces
  const auto help = run("mesh --help");
  EXPECT_NE(help.output.find("0 or [1.1, 10]"), std::string::npos) << help.output;
}

TEST_F(CLI, OutputsNeverOverwriteInputsOrFolders)
{
  fs::copy_file(data("model2d.obj"), out("model.obj"));
  const auto before = fs::file_size(out("model.obj"));
  ExpectError(run("weights --cage " + data("cage2d.obj") + " --points " + out("model.obj") +
                " --output " + out("model.obj")),
    "is the input");
  EXPECT_EQ(fs::file_size(out("model.obj")), before);
  // a folder as the summary: refused before anything is computed, no data file left
  fs::create_directories(out("summary.json"));
  ExpectError(run("weights --cage " + data("cage2d.obj") + " --points " + out("model.obj") +
                " --output " + out("w.vtp") + " --json " + out("summary.json")),
    "it is a folder");
  EXPECT_FALSE(fs::exists(out("w.vtp")));
}

TEST_F(CLI, ReadmeTutorialShowsWhatItSays)
{
  // The README's tutorial states figures; they are read from README.md and compared with what
  // the commands give (issue 17: "about 20000 tetrahedra" gave 50,289 (50,405 since .obj is read in double precision), a level-set example wrote
  // 0 cells, the reduce example kept all 72 weights).
  std::ifstream readme_file(std::string(BARYLAB_DATA_DIR) + "/../README.md");
  ASSERT_TRUE(readme_file) << "README.md not found";
  std::stringstream buffer;
  buffer << readme_file.rdbuf();
  const std::string readme = buffer.str();
  const auto number = [&readme](const std::string& pattern) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(readme, m, std::regex(pattern))) << pattern;
    std::string digits = m.size() > 1 ? m[1].str() : "nan";
    digits.erase(std::remove(digits.begin(), digits.end(), ','), digits.end());
    return std::stod(digits);
  };
  const double tets = number("makes more: ([0-9,]+) tetrahedra here");
  const double kept = number("keeping weights > 0\\.01 keeps ([0-9.]+) of 72 on average");
  const double csr = number("\\(([0-9.]+)% of the dense array in CSR\\)");
  const double reproduction = number("reproduction error of ([0-9.]+)% of the cage's diameter");

  const std::string w = out("kidney_w.vtp");
  ASSERT_EQ(run("weights --method mvc --cage " + data("cage3d.obj") + " --points " +
              data("model3d.off") + " --output " + w + " -q").code, 0);
  const CommandResult reduce = run("reduce --input " + w + " --cage " + data("cage3d.obj") +
    " --output " + out("kidney_sparse.vtp") + " --threshold 0.01 --json");
  ASSERT_EQ(reduce.code, 0) << reduce.output;
  const nlohmann::json r = nlohmann::json::parse(reduce.output);
  EXPECT_NEAR(r["mean_support"].get<double>(), kept, 0.05);
  EXPECT_NEAR(100.0 * r["csr_memory_fraction"].get<double>(), csr, 0.5);
  EXPECT_NEAR(100.0 * r["reproduction_error"].get<double>(), reproduction, 0.05);
  EXPECT_LT(r["csr_memory_fraction"].get<double>(), 1.0) << "a compact copy larger than dense";

  const CommandResult fields = run("fields --input " + w + " --level-sets " + out("w36.vtp") +
    " --control 36 --level 0.01 --level 0.05 --json");
  ASSERT_EQ(fields.code, 0) << fields.output;
  EXPECT_GT(nlohmann::json::parse(fields.output)["level_sets"]["cells"].get<int>(), 100);

  ASSERT_EQ(run("weights --method harmonic --cage " + data("cage3d.obj") + " --points " +
              data("model3d.off") + " --output " + out("kidney_h.vtp") + " --json " +
              out("h.json") + " -q").code, 0);
  std::ifstream h(out("h.json"));
  EXPECT_EQ(nlohmann::json::parse(h)["solver"]["mesh_cells"].get<double>(), tets);
}

// ---------------------------------------------------------------------------------------------
// Weighted averages on surfaces: barylab embed, barylab average (forward and --inverse).

namespace
{

/// Rows of a text matrix written by barylab (numbers, "nan" allowed).
std::vector<std::vector<double>> read_rows(const std::string& path)
{
  std::vector<std::vector<double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream s(line);
    std::vector<double> row;
    std::string token;
    while (s >> token)
      row.push_back(std::stod(token));
    if (!row.empty())
      rows.push_back(row);
  }
  return rows;
}

} // namespace

TEST_F(CLI, EmbedWritesOneLinePerVertex)
{
  const CommandResult r = run("embed --mesh " + data("wa_torus.obj") + " --output " +
    out("e.txt") + " --dimension 5 --landmarks 150 --json " + out("e.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = read_rows(out("e.txt"));
  auto torus = vtkBaryDataIO::Read(data("wa_torus.obj"));
  ASSERT_EQ(static_cast<vtkIdType>(rows.size()), torus->GetNumberOfPoints());
  for (const auto& row : rows)
    ASSERT_EQ(row.size(), 5u);
  std::ifstream j(out("e.json"));
  const nlohmann::json s = nlohmann::json::parse(j);
  EXPECT_EQ(s["landmarks"].get<int>(), 150);
  EXPECT_EQ(s["dimension"].get<int>(), 5);
  EXPECT_LT(s["quality"]["mean_relative_error"].get<double>(), 0.2);
  EXPECT_GT(s["quality"]["pairs"].get<int>(), 1000);
  // With the surface: the .vtp keeps it as a point array.
  ASSERT_EQ(run("embed --mesh " + data("wa_torus.obj") + " --output " + out("e.vtp") +
              " --landmarks 150 -q").code, 0);
  auto e = vtkBaryDataIO::Read(out("e.vtp"));
  ASSERT_NE(e->GetPointData()->GetArray("Embedding"), nullptr);
  EXPECT_EQ(e->GetPointData()->GetArray("Embedding")->GetNumberOfComponents(), 8);
}

TEST_F(CLI, AverageForwardInverseRoundTrip)
{
  const std::string mesh = data("wa_torus.obj"), anchors = data("wa_anchors.txt");
  ASSERT_EQ(run("embed --mesh " + mesh + " --output " + out("e.txt") + " --landmarks 300 -q").code, 0);
  // Forward: one point per row, the first (weight 1 on anchor 4) is anchor 4.
  const CommandResult f = run("average --mesh " + mesh + " --embedding " + out("e.txt") +
    " --anchors " + anchors + " --weights " + data("wa_weights.txt") + " --output " +
    out("avg.txt") + " --json " + out("avg.json") + " -q");
  ASSERT_EQ(f.code, 0) << f.output;
  const auto avg = read_rows(out("avg.txt"));
  const auto weights = read_rows(data("wa_weights.txt"));
  const auto anchor_rows = read_rows(anchors);
  ASSERT_EQ(avg.size(), weights.size());
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(avg[0][k], anchor_rows[4][k], 1e-9);
  std::ifstream fj(out("avg.json"));
  const nlohmann::json fs = nlohmann::json::parse(fj);
  EXPECT_EQ(fs["forward"]["failures"].get<int>(), 0);
  EXPECT_EQ(fs["forward"]["queries"].get<int>(), static_cast<int>(weights.size()));
  // The same as .vtp: FaceId, Barycentric and Valid point arrays.
  ASSERT_EQ(run("average --mesh " + mesh + " --embedding " + out("e.txt") + " --anchors " +
              anchors + " --weights " + data("wa_weights.txt") + " --output " + out("avg.vtp") +
              " -q").code, 0);
  auto points = vtkBaryDataIO::Read(out("avg.vtp"));
  for (const char* name : { "FaceId", "Barycentric", "Valid" })
    EXPECT_NE(points->GetPointData()->GetArray(name), nullptr) << name;

  // Inverse of the forward results gives weights whose forward problem returns the points.
  const CommandResult i = run("average --inverse --mesh " + mesh + " --embedding " +
    out("e.txt") + " --anchors " + anchors + " --points " + out("avg.txt") + " --output " +
    out("w.txt") + " --json " + out("inv.json") + " -q");
  ASSERT_EQ(i.code, 0) << i.output;
  const auto w = read_rows(out("w.txt"));
  ASSERT_EQ(w.size(), avg.size());
  for (const auto& row : w)
  {
    ASSERT_EQ(row.size(), 9u);
    double sum = 0;
    for (const double x : row)
      sum += x;
    EXPECT_NEAR(sum, 1.0, 1e-9);
  }
  for (int k = 0; k < 9; ++k) // at anchor 4 the weights interpolate
    EXPECT_NEAR(w[0][k], k == 4 ? 1.0 : 0.0, 1e-9);
  std::ifstream ij(out("inv.json"));
  const nlohmann::json is = nlohmann::json::parse(ij);
  EXPECT_EQ(is["inverse"]["round_trip"]["not_returned"].get<int>(), 0);
  EXPECT_LT(is["inverse"]["round_trip"]["max_error"].get<double>(), 1e-8);
  ASSERT_EQ(run("average --mesh " + mesh + " --embedding " + out("e.txt") + " --anchors " +
              anchors + " --weights " + out("w.txt") + " --output " + out("back.txt") + " -q").code, 0);
  const auto back = read_rows(out("back.txt"));
  for (std::size_t q = 0; q < avg.size(); ++q)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(back[q][k], avg[q][k], 1e-8) << "query " << q;
}

TEST_F(CLI, AverageBadInputIsNamed)
{
  const std::string mesh = data("wa_torus.obj"), anchors = data("wa_anchors.txt");
  ASSERT_EQ(run("embed --mesh " + mesh + " --output " + out("e.txt") + " --landmarks 100 -q").code, 0);
  const std::string common = "average --mesh " + mesh + " --embedding " + out("e.txt") +
    " --anchors " + anchors + " -q --output " + out("o.txt");
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(out(name)) << text;
    return out(name);
  };
  ExpectError(run(common + " --weights " + write("cols.txt", "0.5 0.5\n")), "2 weights a row but there are 9 anchors");
  ExpectError(run(common + " --weights " + write("sum.txt", "0.5 0.6 0 0 0 0 0 0 0\n")), "row 0 sums to 1.1");
  ExpectError(run(common + " --weights " + write("nan.txt", "nan 1 0 0 0 0 0 0 0\n")), "NaN");
  ExpectError(run(common + " --weights " + write("ragged.txt", "1 0 0 0 0 0 0 0 0\n1 0\n")), "line 2");
  ExpectError(run("average --mesh " + mesh + " --embedding " + out("e.txt") + " --anchors " +
                write("off.txt", "0 0 5\n") + " --weights " + write("one.txt", "1\n") + " -q --output " +
                out("o.txt")),
    "anchor 0");
  ExpectError(run("average --mesh " + mesh + " --embedding " + write("short.txt", "1 2\n3 4\n") +
                " --anchors " + anchors + " --weights " + data("wa_weights.txt") + " -q --output " +
                out("o.txt")),
    "2 lines but the surface has 2016 points");
  ExpectError(run("embed --mesh " + data("cage2d.obj") + " --output " + out("x.txt") + " -q"), "no triangles");
  // Command-line errors: exit 2.
  EXPECT_EQ(run(common + " --inverse --weights " + data("wa_weights.txt")).code, 2);
  EXPECT_EQ(run(common).code, 2);
  EXPECT_EQ(run(common + " --weights " + data("wa_weights.txt") + " --gamma 0.5").code, 2);
  EXPECT_EQ(run("embed --mesh " + mesh + " --output " + out("x.txt") + " --dimension 1 -q").code, 2);
  EXPECT_EQ(run("embed --mesh " + mesh + " --output " + out("x.png") + " -q").code, 1);
  // No partial outputs.
  for (const char* name : { "o.txt", "x.txt" })
    EXPECT_FALSE(fs::exists(out(name))) << name;
}

TEST_F(CLI, CurveOnTheTorus)
{
  const std::string mesh = data("wa_torus.obj");
  ASSERT_EQ(run("embed --mesh " + mesh + " --output " + out("e.txt") + " --landmarks 300 -q").code, 0);
  const CommandResult r = run("curve --mesh " + mesh + " --embedding " + out("e.txt") +
    " --controls " + data("wa_curve_controls.txt") + " --closed --samples 12 --output " +
    out("c.vtp") + " --json " + out("c.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto curve = vtkBaryDataIO::Read(out("c.vtp"));
  EXPECT_EQ(curve->GetNumberOfPoints(), 8 * 12);
  std::ifstream j(out("c.json"));
  const nlohmann::json s = nlohmann::json::parse(j);
  EXPECT_EQ(s["curve"]["failures"].get<int>(), 0);
  // Every sample lies on the torus (its point is a barycentric combination of a triangle's).
  auto torus = vtkBaryDataIO::Read(mesh);
  vtkDataArray* face = curve->GetPointData()->GetArray("FaceId");
  vtkDataArray* bary = curve->GetPointData()->GetArray("Barycentric");
  ASSERT_TRUE(face && bary);
  for (vtkIdType q = 0; q < curve->GetNumberOfPoints(); ++q)
  {
    vtkCell* cell = torus->GetCell(static_cast<vtkIdType>(face->GetComponent(q, 0)));
    double p[3] = { 0, 0, 0 }, x[3];
    for (int k = 0; k < 3; ++k)
    {
      double v[3];
      torus->GetPoint(cell->GetPointId(k), v);
      for (int d = 0; d < 3; ++d)
        p[d] += bary->GetComponent(q, k) * v[d];
    }
    curve->GetPoint(q, x);
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(p[d], x[d], 1e-9);
  }
  // Usage: fewer than 4 control points is an input error naming it; --samples 0 a usage error.
  {
    std::ifstream anchors(data("wa_anchors.txt"));
    std::ofstream three(out("three.txt"));
    std::string line;
    for (int k = 0; k < 3 && std::getline(anchors, line); ++k)
      three << line << "\n";
  }
  ExpectError(run("curve --mesh " + mesh + " --embedding " + out("e.txt") + " --controls " +
                out("three.txt") + " --output " + out("x.vtp") + " -q"),
    "at least 4 control points");
  EXPECT_EQ(run("curve --mesh " + mesh + " --embedding " + out("e.txt") + " --controls " +
              data("wa_curve_controls.txt") + " --samples 0 --output " + out("x.vtp") + " -q").code, 2);
  EXPECT_FALSE(fs::exists(out("x.vtp")));
}

TEST_F(CLI, TransferToAScaledCopyAndMorph)
{
  // Source: the torus with an array; target: the torus scaled by 2, anchors scaled alike. Their
  // embeddings are computed independently; the map is the scaling where it is defined.
  auto torus = vtkBaryDataIO::Read(data("wa_torus.obj"));
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  height->SetNumberOfTuples(torus->GetNumberOfPoints());
  for (vtkIdType i = 0; i < torus->GetNumberOfPoints(); ++i)
    height->SetValue(i, torus->GetPoint(i)[2]);
  torus->GetPointData()->AddArray(height);
  vtkBaryDataIO::Write(torus, out("source.vtp"));
  auto scaled = vtkBaryDataIO::Read(data("wa_torus.obj"));
  vtkPoints* p = vtkPointSet::SafeDownCast(scaled)->GetPoints();
  for (vtkIdType i = 0; i < p->GetNumberOfPoints(); ++i)
  {
    double x[3];
    p->GetPoint(i, x);
    p->SetPoint(i, 2 * x[0], 2 * x[1], 2 * x[2]);
  }
  vtkBaryDataIO::Write(scaled, out("target.vtp"));
  {
    std::ifstream in(data("wa_anchors.txt"));
    std::ofstream a2(out("anchors2.txt"));
    double x, y, z;
    while (in >> x >> y >> z)
      a2 << 2 * x << " " << 2 * y << " " << 2 * z << "\n";
  }
  for (const char* s : { "source", "target" })
    ASSERT_EQ(run("embed --mesh " + out(std::string(s) + ".vtp") + " --output " +
                out(std::string(s) + "_e.txt") + " --landmarks 300 -q").code, 0);
  const CommandResult r = run("transfer --source " + out("source.vtp") + " --source-embedding " +
    out("source_e.txt") + " --source-anchors " + data("wa_anchors.txt") + " --target " +
    out("target.vtp") + " --target-embedding " + out("target_e.txt") + " --target-anchors " +
    out("anchors2.txt") + " --output " + out("t.vtp") + " --morph 3 --morph-dir " + out("morph") +
    " --json " + out("t.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto t = vtkBaryDataIO::Read(out("t.vtp"));
  vtkDataArray* h = t->GetPointData()->GetArray("Height");
  vtkDataArray* defined = t->GetPointData()->GetArray("Defined");
  ASSERT_TRUE(h && defined);
  std::vector<double> errors;
  for (vtkIdType i = 0; i < t->GetNumberOfPoints(); ++i)
    if (defined->GetComponent(i, 0) != 0)
      errors.push_back(std::abs(h->GetComponent(i, 0) - t->GetPoint(i)[2] / 2));
  ASSERT_GT(errors.size(), 300u);
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 1e-4);
  EXPECT_LT(errors[errors.size() * 95 / 100], 1e-3);
  std::ifstream j(out("t.json"));
  const nlohmann::json s = nlohmann::json::parse(j);
  EXPECT_LT(s["transfer"]["stretch"]["best_95_percent"].get<double>(), 1.01);
  EXPECT_TRUE(fs::exists(out("morph/morph.pvd")));
  EXPECT_TRUE(fs::exists(out("morph/morph_003.vtp")));
  // An array the source does not have is named; nothing is written.
  ExpectError(run("transfer --source " + out("source.vtp") + " --source-embedding " +
                out("source_e.txt") + " --source-anchors " + data("wa_anchors.txt") + " --target " +
                out("target.vtp") + " --target-embedding " + out("target_e.txt") +
                " --target-anchors " + out("anchors2.txt") + " --array Nope --output " + out("x.vtp") + " -q"),
    "no point array 'Nope'");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
}

TEST_F(CLI, RemeshTheTorus)
{
  const std::string mesh = data("wa_torus.obj");
  ASSERT_EQ(run("embed --mesh " + mesh + " --output " + out("e.txt") + " --landmarks 300 -q").code, 0);
  const CommandResult r = run("remesh --mesh " + mesh + " --embedding " + out("e.txt") +
    " --coarse " + data("wa_quads.obj") + " --levels 2 --output " + out("q.vtp") + " --json " +
    out("q.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  auto q = vtkBaryDataIO::Read(out("q.vtp"));
  EXPECT_EQ(q->GetNumberOfCells(), 32 * 16);
  EXPECT_EQ(q->GetNumberOfPoints(), 32 * 16); // a closed quad mesh of genus 1: V = F
  std::ifstream j(out("q.json"));
  EXPECT_EQ(nlohmann::json::parse(j)["remesh"]["failures"].get<int>(), 0);
  EXPECT_EQ(run("remesh --mesh " + mesh + " --embedding " + out("e.txt") + " --coarse " +
              data("wa_quads.obj") + " --levels 9 --output " + out("x.vtp") + " -q").code, 2);
  ExpectError(run("remesh --mesh " + mesh + " --embedding " + out("e.txt") + " --coarse " +
                data("wa_torus.obj") + " --output " + out("x.vtp") + " -q"),
    "not 4");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
}

// barylab spline create / edit / deform: the identity on the bundled domain, edits from JSON
// (translate, rotate, scale, a top-surface edit), the 2.5D organism deformed; the JSON report's
// C1 residual and sets; errors name the edit and write nothing.
TEST_F(CLI, SplineCreateEditDeform)
{
  ASSERT_EQ(run("spline create --domain " + data("spline_domain.obj") + " --prism -0.1 0.1 --output " +
              out("s.vtu") + " -q").code, 0);
  {
    std::ofstream e(out("edits.json"));
    e << R"({"edits": [
      {"op": "translate", "near": [0.5, 0.0], "by": [0.0, 0.05], "delta_max": 4},
      {"op": "rotate", "index": 60, "center": [0.0, 0.0], "angle_degrees": 5, "delta_max": 2},
      {"op": "scale", "near": [-0.5, 0.0], "center": [-0.5, 0.0], "factor": 1.05, "delta_max": 3},
      {"op": "translate", "spline": "top", "near": [0.0, 0.0], "by": 0.02, "delta_max": 4}]})";
  }
  const CommandResult r = run("spline edit --spline " + out("s.vtu") + " --edits " + out("edits.json") +
    " --output " + out("s2.vtu") + " --json " + out("e.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream j(out("e.json"));
  const nlohmann::json s = nlohmann::json::parse(j);
  EXPECT_EQ(s["edits"].size(), 4u);
  EXPECT_LT(s["c1_condition_residual_relative"].get<double>(), 1e-9);
  EXPECT_LT(s["max_gradient_jump"].get<double>(), 1e-9);
  EXPECT_TRUE(s["jacobian_positive_everywhere"].get<bool>());
  EXPECT_EQ(s["edits"][1]["anchors"][0].get<int>(), 60);
  for (const auto& e : s["edits"])
    EXPECT_GT(e["derived"].get<int>(), 0);
  // The edits file is a log: applied again to the same spline, the same control points, bit for
  // bit (the files differ only in the timings of their field data).
  ASSERT_EQ(run("spline edit --spline " + out("s.vtu") + " --edits " + out("edits.json") +
              " --output " + out("s3.vtu") + " -q").code, 0);
  {
    auto a = vtkBaryDataIO::Read(out("s2.vtu")), b = vtkBaryDataIO::Read(out("s3.vtu"));
    ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
    for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
    {
      double x[3], y[3];
      a->GetPoint(p, x);
      b->GetPoint(p, y);
      ASSERT_TRUE(x[0] == y[0] && x[1] == y[1]) << "control point " << p;
      ASSERT_EQ(a->GetPointData()->GetArray("Top")->GetComponent(p, 0),
        b->GetPointData()->GetArray("Top")->GetComponent(p, 0));
    }
  }
  ASSERT_EQ(run("spline deform --spline " + out("s2.vtu") + " --points " + data("spline_organism.obj") +
              " --output " + out("o.vtp") + " -q").code, 0);
  auto model = vtkBaryDataIO::Read(data("spline_organism.obj"));
  auto moved = vtkBaryDataIO::Read(out("o.vtp"));
  ASSERT_EQ(moved->GetNumberOfPoints(), model->GetNumberOfPoints());
  double change = 0;
  for (vtkIdType p = 0; p < model->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    model->GetPoint(p, a);
    moved->GetPoint(p, b);
    change = std::max(change, std::hypot(a[0] - b[0], a[1] - b[1]));
  }
  EXPECT_GT(change, 0.01);
  EXPECT_LT(change, 0.2);
  // Errors: an unknown op, an unknown control point, a model outside, a .vtp spline output.
  {
    std::ofstream e(out("bad.json"));
    e << R"({"edits": [{"op": "twist", "near": [0, 0]}]})";
  }
  ExpectError(run("spline edit --spline " + out("s.vtu") + " --edits " + out("bad.json") +
                " --output " + out("x.vtu") + " -q"), "edit 0 has op \"twist\"");
  {
    std::ofstream e(out("bad2.json"));
    e << R"({"edits": [{"op": "translate", "index": 999999, "by": [0, 1]}]})";
  }
  ExpectError(run("spline edit --spline " + out("s.vtu") + " --edits " + out("bad2.json") +
                " --output " + out("x.vtu") + " -q"), "anchor 999999 is not a control point");
  ExpectError(run("spline deform --spline " + out("s.vtu") + " --points " + data("wa_torus.obj") +
                " --output " + out("x.vtp") + " -q"), "outside");
  EXPECT_EQ(run("spline create --domain " + data("spline_domain.obj") + " --output " + out("x.vtp") + " -q").code, 2);
  EXPECT_EQ(run("spline create --domain " + data("spline_domain.obj") + " --degree 4 --output " + out("x.vtu") + " -q").code, 2);
  EXPECT_FALSE(fs::exists(out("x.vtu")));
  EXPECT_FALSE(fs::exists(out("x.vtp")));
}

// The picture-matching use: a spline fitted to the organism bent as in its picture
// (y + 0.18 sin(pi x), data/README.md) carries the organism onto the bent one; with the border
// pinned, an edit of a border control point is refused and nothing is written.
TEST_F(CLI, SplineFitAndPinnedBorder)
{
  auto model = vtkBaryDataIO::Read(data("spline_organism.obj"));
  auto bent = vtkSmartPointer<vtkPolyData>::New();
  bent->DeepCopy(model);
  for (vtkIdType p = 0; p < bent->GetNumberOfPoints(); ++p)
  {
    double x[3];
    bent->GetPoint(p, x);
    x[1] += 0.18 * std::sin(M_PI * x[0]);
    vtkPointSet::SafeDownCast(bent)->GetPoints()->SetPoint(p, x);
  }
  vtkBaryDataIO::Write(bent, out("bent.vtp"));
  const CommandResult r = run("spline create --domain " + data("spline_domain.obj") + " --fit-from " +
    data("spline_organism.obj") + " --fit-to " + out("bent.vtp") + " --pin-border --output " +
    out("fit.vtu") + " --json " + out("fit.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream j(out("fit.json"));
  const nlohmann::json s = nlohmann::json::parse(j);
  EXPECT_LT(s["fit"]["max_error"].get<double>(), 1e-4);
  EXPECT_TRUE(s["jacobian_positive_everywhere"].get<bool>());
  ASSERT_EQ(run("spline deform --spline " + out("fit.vtu") + " --points " + data("spline_organism.obj") +
              " --output " + out("o.vtp") + " -q").code, 0);
  auto moved = vtkBaryDataIO::Read(out("o.vtp"));
  double worst = 0;
  for (vtkIdType p = 0; p < moved->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    moved->GetPoint(p, a);
    bent->GetPoint(p, b);
    worst = std::max(worst, std::hypot(a[0] - b[0], a[1] - b[1]));
  }
  EXPECT_LT(worst, 1e-4);
  {
    std::ofstream e(out("corner.json"));
    e << R"({"edits": [{"op": "translate", "near": [-1.0, -0.5], "by": [0.1, 0.0]}]})";
  }
  ExpectError(run("spline edit --spline " + out("fit.vtu") + " --edits " + out("corner.json") +
                " --output " + out("x.vtu") + " -q"), "pinned");
  EXPECT_FALSE(fs::exists(out("x.vtu")));
}

// ---- Green coordinates --------------------------------------------------------------------------

TEST_F(CLI, GreenWeightsAndDeformRoundTrip)
{
  // weights --method green writes phi ("Weights") and psi ("FaceWeights"); the summary's
  // reproduction includes the face term; deform with the stored arrays equals deform computing
  // them; a rotated, scaled, translated cage moves the model by exactly that similarity.
  const CommandResult w = run("weights --method green --cage " + data("cage2d.obj") + " --points " +
    data("model2d.obj") + " --output " + out("w.vtp") + " --json " + out("w.json") + " -q");
  ASSERT_EQ(w.code, 0) << w.output;
  auto weighted = vtkBaryDataIO::Read(out("w.vtp"));
  auto cage = vtkBaryDataIO::Read(data("cage2d.obj"));
  ASSERT_NE(weighted->GetPointData()->GetArray("Weights"), nullptr);
  ASSERT_NE(weighted->GetPointData()->GetArray("FaceWeights"), nullptr);
  EXPECT_EQ(weighted->GetPointData()->GetArray("Weights")->GetNumberOfComponents(), cage->GetNumberOfPoints());
  EXPECT_EQ(weighted->GetPointData()->GetArray("FaceWeights")->GetNumberOfComponents(), cage->GetNumberOfPoints());
  std::ifstream json_file(out("w.json"));
  const nlohmann::json summary = nlohmann::json::parse(json_file);
  EXPECT_LT(summary["statistics"]["reproduction"]["max_error"].get<double>(), 1e-12);
  EXPECT_LT(summary["statistics"]["partition_of_unity"]["max_error"].get<double>(), 1e-12);
  EXPECT_EQ(summary["statistics"]["reproduction"]["face_coefficients"].get<long long>(),
    cage->GetNumberOfPoints());

  // a similarity of the cage, written as a file
  const double c = 1.3 * std::cos(0.8), s = 1.3 * std::sin(0.8);
  auto similar = [&](const double* x, double* y) {
    y[0] = c * x[0] - s * x[1] + 2.0;
    y[1] = s * x[0] + c * x[1] - 1.0;
    y[2] = x[2];
  };
  vtkNew<vtkPolyData> moved;
  moved->DeepCopy(cage);
  for (vtkIdType i = 0; i < moved->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    cage->GetPoint(i, x);
    similar(x, y);
    moved->GetPoints()->SetPoint(i, y);
  }
  vtkBaryDataIO::Write(moved, out("moved.vtp"));
  const CommandResult a = run("deform --method green --cage " + data("cage2d.obj") +
    " --deformed-cage " + out("moved.vtp") + " --points " + data("model2d.obj") + " --output " + out("a.vtp"));
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_NE(a.output.find("weights computed"), std::string::npos) << a.output;
  const CommandResult b = run("deform --method green --cage " + data("cage2d.obj") +
    " --deformed-cage " + out("moved.vtp") + " --weights " + out("w.vtp") + " --output " + out("b.vtp"));
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_NE(b.output.find("weights from the input"), std::string::npos) << b.output;
  auto da = vtkBaryDataIO::Read(out("a.vtp"));
  auto db = vtkBaryDataIO::Read(out("b.vtp"));
  auto model = vtkBaryDataIO::Read(data("model2d.obj"));
  ASSERT_EQ(da->GetNumberOfPoints(), model->GetNumberOfPoints());
  double same = 0.0, similarity = 0.0;
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3], p[3], q[3];
    model->GetPoint(i, x);
    similar(x, y);
    da->GetPoint(i, p);
    db->GetPoint(i, q);
    for (int k = 0; k < 3; ++k)
    {
      same = std::max(same, std::abs(p[k] - q[k]));
      similarity = std::max(similarity, std::abs(p[k] - y[k]));
    }
  }
  EXPECT_LT(same, 1e-12);
  EXPECT_LT(similarity, 1e-11);
}

// Hostile input on Green coordinates and celestial hull points: NaN model points, a NaN cage
// vertex, a cage with a zero-area face (3D) or a zero-length edge (2D), and hull margins <= 0,
// NaN or too large: each a clear error naming the problem (exit 1; 2 for a flag's value out of
// range), no output file.
TEST_F(CLI, GreenAndHullPointsHostileInput)
{
  // a unit cube with a vertex M at the middle of edge 0-1 and the zero-area face (0, 1, M)
  {
    std::ofstream cube(out("flatface.obj"));
    cube << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nv 0.5 0 0\n"
            "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 9\nf 2 6 9\nf 6 5 9\nf 5 1 9\n"
            "f 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";
    std::ofstream inside(out("inside3d.obj"));
    inside << "v 0.5 0.5 0.5\nv 0.2 0.3 0.4\n";
  }
  ExpectError(run("weights --method green --cage " + out("flatface.obj") + " --points " +
                out("inside3d.obj") + " --output " + out("x.vtp")),
    "zero area");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
  // 2D: the gingerbread cage with vertex 3 repeated (a zero-length edge)
  {
    std::ifstream in(data("cage2d.obj"));
    std::ofstream dup(out("dup2d.obj"));
    std::string line;
    int k = 0;
    while (std::getline(in, line))
    {
      dup << line << "\n";
      if (line.rfind("v ", 0) == 0 && k++ == 3)
        dup << line << "\n";
    }
  }
  const CommandResult dup = run("weights --method green --cage " + out("dup2d.obj") + " --points " +
    data("model2d.obj") + " --output " + out("x.vtp"));
  ExpectError(dup, "coincide");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
  // NaN model points and a NaN cage vertex (written by VTK, read back as NaN)
  const double nan = std::numeric_limits<double>::quiet_NaN();
  {
    auto model = vtkBaryDataIO::Read(data("model2d.obj"));
    vtkPointSet::SafeDownCast(model)->GetPoints()->SetPoint(5, nan, 0.1, 0.0);
    vtkBaryDataIO::Write(model, out("nanmodel.vtp"));
    auto cage = vtkBaryDataIO::Read(data("cage2d.obj"));
    vtkPointSet::SafeDownCast(cage)->GetPoints()->SetPoint(2, 0.45, nan, 0.0);
    vtkBaryDataIO::Write(cage, out("nancage.vtp"));
  }
  ExpectError(run("weights --method green --cage " + data("cage2d.obj") + " --points " +
                out("nanmodel.vtp") + " --output " + out("x.vtp")),
    "point 5");
  ExpectError(run("weights --method green --cage " + out("nancage.vtp") + " --points " +
                data("model2d.obj") + " --output " + out("x.vtp")),
    "non-finite");
  ExpectError(run("deform --method green --cage " + data("cage2d.obj") + " --deformed-cage " +
                out("nancage.vtp") + " --points " + data("model2d.obj") + " --output " + out("x.vtp")),
    "non-finite");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
  // hull margins out of range: a command-line error (exit 2) naming the flag
  const std::string scc = "weights --method scc --control-points " + data("cage2d.obj") +
    " --points " + data("cage2d_posed.obj") + " --output " + out("x.vtp") + " --hull-margin ";
  for (const std::string margin : { "0", "-0.5", "nan", "inf", "11" })
  {
    const CommandResult r = run(scc + margin);
    EXPECT_EQ(r.code, 2) << margin << "\n" << r.output;
    EXPECT_NE(r.output.find("--hull-margin"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(out("x.vtp")));
  EXPECT_EQ(run(scc + "1e-6 -q").code, 0) << "the smallest margin is accepted";
}

TEST_F(CLI, GreenDeformation3DAndBadCages)
{
  // the rest cage as the deformed one: the identity (the face term included); the posed cage
  // moves the model, finitely
  for (const std::string posed : { "cage3d.obj", "cage3d_posed.obj" })
  {
    const CommandResult r = run("deform --method green --cage " + data("cage3d.obj") +
      " --deformed-cage " + data(posed) + " --points " + data("model3d.off") + " --output " +
      out("d.vtp") + " -q");
    ASSERT_EQ(r.code, 0) << r.output;
    auto deformed = vtkBaryDataIO::Read(out("d.vtp"));
    auto rest = vtkBaryDataIO::Read(data("model3d.off"));
    double moved = 0.0;
    for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
      for (int k = 0; k < 3; ++k)
      {
        ASSERT_TRUE(std::isfinite(deformed->GetPoint(i)[k]));
        moved = std::max(moved, std::abs(rest->GetPoint(i)[k] - deformed->GetPoint(i)[k]));
      }
    if (posed == "cage3d.obj")
      EXPECT_LT(moved, 1e-12);
    else
      EXPECT_GT(moved, 1e-2);
  }
  ExpectError(run("weights --method green --cage " + data("bad/open_cage.obj") + " --points " +
                data("model3d.off") + " --output " + out("x.vtp")),
    "the cage is not closed");
  ExpectError(run("weights --method green --cage " + data("bad/bowtie2d.obj") + " --points " +
                data("model2d.obj") + " --output " + out("y.vtp")),
    "the polygon is not simple");
  EXPECT_FALSE(fs::exists(out("x.vtp")));
}
