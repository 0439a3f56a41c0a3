// Command-line tests of barylab segment: label maps written here (vtkBaryImageIO) and the
// bundled data/organ_label.nii.gz; the JSON summary against counts made here, the same surface
// from NIfTI and NRRD, exit codes (0, 1 bad input, 2 bad command line) and no partial output.
// Part of barylab_cli_test.

#include "vtkBaryDataIO.h"
#include "vtkBaryImageIO.h"

#include "vtkDataSet.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkShortArray.h"
#include "vtkSmartPointer.h"

#include "cli_test_utils.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
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

class CLISegment : public ::testing::Test
{
protected:
  void SetUp() override
  {
    dir_ = barylab_test::FreshTestFolder("cli_segment_");
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

constexpr int kN[3] = { 36, 30, 24 };
constexpr double kSpacing[3] = { 0.9, 1.2, 1.6 };
constexpr double kOrigin[3] = { -40.0, 12.5, 80.0 };

/// A label map with a rotated direction; label(i, j, k) gives the voxels.
vtkSmartPointer<vtkImageData> LabelImage(const std::function<double(int, int, int)>& label,
  bool floating = false)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(kN[0], kN[1], kN[2]);
  image->SetSpacing(kSpacing[0], kSpacing[1], kSpacing[2]);
  image->SetOrigin(kOrigin[0], kOrigin[1], kOrigin[2]);
  const double c = std::cos(0.4), s = std::sin(0.4);
  vtkNew<vtkMatrix3x3> direction; // a rotation about z, then x mirrored (det -1)
  const double D[3][3] = { { -c, s, 0 }, { -s, -c, 0 }, { 0, 0, 1 } };
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q)
      direction->SetElement(r, q, D[r][q]);
  image->SetDirectionMatrix(direction);
  vtkSmartPointer<vtkDataArray> values = floating
    ? vtkSmartPointer<vtkDataArray>(vtkSmartPointer<vtkFloatArray>::New())
    : vtkSmartPointer<vtkDataArray>(vtkSmartPointer<vtkShortArray>::New());
  values->SetNumberOfTuples(image->GetNumberOfPoints());
  for (int k = 0; k < kN[2]; ++k)
    for (int j = 0; j < kN[1]; ++j)
      for (int i = 0; i < kN[0]; ++i)
        values->SetTuple1(i + kN[0] * (j + kN[1] * k), label(i, j, k));
  image->GetPointData()->SetScalars(values);
  return image;
}

/// 1 inside the ellipsoid of semi-axes (10, 11, 12) mm centred at index @p c.
std::function<double(int, int, int)> Blob(std::array<double, 3> c, double value = 1.0)
{
  return [=](int i, int j, int k) {
    const double u = (i - c[0]) * kSpacing[0] / 10.0, v = (j - c[1]) * kSpacing[1] / 11.0,
                 w = (k - c[2]) * kSpacing[2] / 12.0;
    return u * u + v * v + w * w <= 1.0 ? value : 0.0;
  };
}

long long CountVoxels(vtkImageData* image, double label)
{
  long long n = 0;
  vtkDataArray* values = image->GetPointData()->GetScalars();
  for (vtkIdType v = 0; v < values->GetNumberOfTuples(); ++v)
    n += values->GetTuple1(v) == label;
  return n;
}

nlohmann::json ReadJson(const std::string& path)
{
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void ExpectRunError(const Result& r, const std::string& needle)
{
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("barylab: error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in:\n"
                                                       << r.output;
}
} // namespace

TEST_F(CLISegment, SummaryMatchesTheVoxelsAndTheSurface)
{
  auto image = LabelImage(Blob({ 17.5, 14.0, 11.5 }, 4.0));
  vtkBaryImageIO::Write(image, out("blob.nii.gz"));
  const Result r = barylab("segment --image " + out("blob.nii.gz") + " --output " +
    out("blob.vtp") + " --json " + out("blob.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json j = ReadJson(out("blob.json"));
  const long long voxels = CountVoxels(image, 4.0);
  const double voxel_volume = voxels * kSpacing[0] * kSpacing[1] * kSpacing[2]; // |det D| = 1
  EXPECT_EQ(j["label"].get<long long>(), 4);
  EXPECT_EQ(j["voxels"].get<long long>(), voxels);
  EXPECT_NEAR(j["label_volume"].get<double>(), voxel_volume, 1e-5 * voxel_volume);
  EXPECT_NEAR(j["enclosed_volume"].get<double>(), voxel_volume, 0.04 * voxel_volume);
  EXPECT_EQ(j["border_cut"].get<bool>(), false);
  EXPECT_EQ(j["components_dropped"].get<int>(), 0);
  EXPECT_EQ(j["space"].get<std::string>(), "LPS");
  auto surface = vtkBaryDataIO::Read(out("blob.vtp"));
  EXPECT_EQ(j["triangles"].get<long long>(), surface->GetNumberOfCells());
  EXPECT_EQ(j["vertices"].get<long long>(), surface->GetNumberOfPoints());
  EXPECT_GT(surface->GetNumberOfCells(), 1000);
  EXPECT_LE(surface->GetNumberOfCells(), 5500);
  // The same label map as NRRD (LPS on disk; NIfTI is RAS): the same surface, point by point.
  vtkBaryImageIO::Write(image, out("blob.nrrd"));
  ASSERT_EQ(barylab("segment -q -i " + out("blob.nrrd") + " -o " + out("blob2.vtp")).code, 0);
  auto surface2 = vtkBaryDataIO::Read(out("blob2.vtp"));
  ASSERT_EQ(surface2->GetNumberOfPoints(), surface->GetNumberOfPoints());
  double worst = 0.0;
  for (vtkIdType p = 0; p < surface->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    surface->GetPoint(p, a);
    surface2->GetPoint(p, b);
    for (int d = 0; d < 3; ++d)
      worst = std::max(worst, std::abs(a[d] - b[d]));
  }
  EXPECT_LT(worst, 1e-3); // NIfTI's float32 geometry
}

TEST_F(CLISegment, BundledOrganLabels)
{
  const std::string organ = std::string(BARYLAB_DATA_DIR) + "/organ_label.nii.gz";
  if (!fs::exists(organ))
    GTEST_SKIP() << organ << " is not there";
  auto image = vtkBaryImageIO::Read(organ);
  // Two labels: the choice is required, and the error names them.
  Result r = barylab("segment -i " + organ + " -o " + out("organ.vtp"));
  ExpectRunError(r, "2 labels: 1 (");
  EXPECT_FALSE(fs::exists(out("organ.vtp")));
  r = barylab("segment -i " + organ + " --label 9 -o " + out("organ.vtp"));
  ExpectRunError(r, "label 9 is empty");
  EXPECT_NE(r.output.find("labels present: 1 (" + std::to_string(CountVoxels(image, 1)) +
              " voxels), 2 (" + std::to_string(CountVoxels(image, 2)) + " voxels)"),
    std::string::npos)
    << r.output;
  EXPECT_FALSE(fs::exists(out("organ.vtp")));
  for (int label : { 1, 2 })
  {
    const std::string name = "label" + std::to_string(label);
    r = barylab("segment -i " + organ + " --label " + std::to_string(label) + " -o " +
      out(name + ".stl") + " --json " + out(name + ".json"));
    ASSERT_EQ(r.code, 0) << r.output;
    const nlohmann::json j = ReadJson(out(name + ".json"));
    EXPECT_EQ(j["voxels"].get<long long>(), CountVoxels(image, label));
    EXPECT_FALSE(j["border_cut"].get<bool>());
    EXPECT_GT(j["triangles"].get<int>(), 500);
  }
}

TEST_F(CLISegment, BorderLabelIsClosedAndReported)
{
  vtkBaryImageIO::Write(LabelImage(Blob({ 2.0, 14.0, 11.5 })), out("cut.mha"));
  const Result r =
    barylab("segment -i " + out("cut.mha") + " -o " + out("cut.vtp") + " --json " + out("cut.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("touches the image's border"), std::string::npos) << r.output;
  EXPECT_TRUE(ReadJson(out("cut.json"))["border_cut"].get<bool>());
}

TEST_F(CLISegment, IntensitiesNeedAThreshold)
{
  auto image = LabelImage(
    [](int i, int j, int k) { return 100.0 * Blob({ 17.5, 14.0, 11.5 })(i, j, k) + 0.5 * (i % 3); },
    true);
  vtkBaryImageIO::Write(image, out("ct.nrrd"));
  ExpectRunError(barylab("segment -i " + out("ct.nrrd") + " -o " + out("ct.vtp")),
    "not an integer label");
  EXPECT_FALSE(fs::exists(out("ct.vtp")));
  const Result r = barylab("segment -i " + out("ct.nrrd") + " --threshold 50 -o " + out("ct.vtp") +
    " --json " + out("ct.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(ReadJson(out("ct.json"))["voxels"].get<long long>(),
    CountVoxels(LabelImage(Blob({ 17.5, 14.0, 11.5 })), 1.0));
}

TEST_F(CLISegment, BadInputExit1AndNoOutput)
{
  // A MetaImage written by hand with a singular direction (its z axis along x).
  {
    std::ofstream mha(out("flat.mha"), std::ios::binary);
    mha << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
           "CompressedData = False\nTransformMatrix = 1 0 0 0 1 0 1 0 0\nOffset = 0 0 0\n"
           "ElementSpacing = 1 1 1\nDimSize = 4 4 4\nElementType = MET_SHORT\n"
           "ElementDataFile = LOCAL\n";
    for (int v = 0; v < 64; ++v)
    {
      const short value = (v == 21 || v == 22) ? 1 : 0;
      mha.write(reinterpret_cast<const char*>(&value), sizeof value);
    }
  }
  ExpectRunError(barylab("segment -i " + out("flat.mha") + " -o " + out("flat.vtp")), "singular");
  // Garbage, missing and empty images.
  {
    std::ofstream garbage(out("garbage.nii"), std::ios::binary);
    for (int i = 0; i < 2000; ++i)
      garbage.put(static_cast<char>((i * 131) % 256));
  }
  ExpectRunError(barylab("segment -i " + out("garbage.nii") + " -o " + out("g.vtp")),
    "cannot read");
  ExpectRunError(barylab("segment -i " + out("missing.nrrd") + " -o " + out("m.vtp")),
    "no such file");
  vtkBaryImageIO::Write(LabelImage([](int, int, int) { return 0.0; }), out("empty.nrrd"));
  ExpectRunError(barylab("segment -i " + out("empty.nrrd") + " -o " + out("e.vtp")),
    "no non-zero label");
  // An output that cannot be written fails before the work.
  vtkBaryImageIO::Write(LabelImage(Blob({ 17.5, 14.0, 11.5 })), out("ok.nrrd"));
  ExpectRunError(barylab("segment -i " + out("ok.nrrd") + " -o " + out("surface.png")), ".png");
  ExpectRunError(
    barylab("segment -i " + out("ok.nrrd") + " -o " + out("no_folder/surface.vtp")), "folder");
  for (const char* name : { "flat.vtp", "g.vtp", "m.vtp", "e.vtp", "surface.png" })
    EXPECT_FALSE(fs::exists(out(name))) << name;
  EXPECT_FALSE(fs::exists(out("no_folder")));
}

TEST_F(CLISegment, UsageErrorsExit2)
{
  vtkBaryImageIO::Write(LabelImage(Blob({ 17.5, 14.0, 11.5 })), out("ok.nrrd"));
  const std::string in = " -i " + out("ok.nrrd") + " -o " + out("s.vtp");
  for (const std::string& args : { "segment -o " + out("s.vtp"), "segment" + in + " --label 0",
         "segment" + in + " --faces 100 --reduction 0.5", "segment" + in + " --label 1 --threshold 3",
         "segment" + in + " --smoothing -1", "segment" + in + " --reduction 1.5" })
  {
    const Result r = barylab(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(out("s.vtp")));
}
