// Tests of vtkBaryLabelMapSurface (BaryLab::BaryLabMedical): the surface of a label of a
// synthetic label map (an ellipsoid made here, with anisotropic spacing, a non-zero origin and a
// rotated, mirrored or sheared direction) against references computed here independently: the
// analytic ellipsoid volume, the voxel volume, the label voxels' physical points (origin +
// D (index o spacing) by hand), VTK's vtkMassProperties and vtkFeatureEdges for the volume and
// the closedness. The same label map written as NIfTI (RAS on disk), NRRD and MetaImage (LPS)
// gives the same LPS surface. Bad input: empty / missing labels, several labels, a singular
// direction, non-integer values; border labels are closed and flagged.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryLabelMapSurface.h"

#include "core/common/error.h"

#include "vtkFeatureEdges.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIdList.h"
#include "vtkMassProperties.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkShortArray.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace
{
using namespace barylab_test;
namespace fs = std::filesystem;
using Matrix3 = std::array<std::array<double, 3>, 3>;
using Vec3 = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

Matrix3 Rotation(Vec3 axis, double angle)
{
  const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& a : axis)
    a /= n;
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  return { { { t * x * x + c, t * x * y - s * z, t * x * z + s * y },
    { t * x * y + s * z, t * y * y + c, t * y * z - s * x },
    { t * x * z - s * y, t * y * z + s * x, t * z * z + c } } };
}

Matrix3 Identity()
{
  return { { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } } };
}

/// A label map: dims, spacing, origin, direction, and a labelling function of the index.
struct LabelMap
{
  std::array<int, 3> dims = { 40, 34, 26 };
  Vec3 spacing = { 0.8, 1.1, 1.5 };
  Vec3 origin = { 10.0, -20.0, 5.0 };
  Matrix3 direction = Rotation({ 1.0, -2.0, 0.5 }, 0.7);

  /// Physical point of index (i, j, k), by hand.
  Vec3 Point(double i, double j, double k) const
  {
    const double p[3] = { i * spacing[0], j * spacing[1], k * spacing[2] };
    Vec3 x{};
    for (int r = 0; r < 3; ++r)
      x[r] = origin[r] + direction[r][0] * p[0] + direction[r][1] * p[1] + direction[r][2] * p[2];
    return x;
  }

  double VoxelVolume() const
  {
    const auto& D = direction;
    const double det = D[0][0] * (D[1][1] * D[2][2] - D[1][2] * D[2][1]) -
      D[0][1] * (D[1][0] * D[2][2] - D[1][2] * D[2][0]) +
      D[0][2] * (D[1][0] * D[2][1] - D[1][1] * D[2][0]);
    return std::abs(det) * spacing[0] * spacing[1] * spacing[2];
  }

  vtkSmartPointer<vtkImageData> Image(const std::function<short(int, int, int)>& label) const
  {
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(dims.data());
    image->SetSpacing(spacing.data());
    image->SetOrigin(origin.data());
    vtkNew<vtkMatrix3x3> m;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        m->SetElement(r, c, direction[r][c]);
    image->SetDirectionMatrix(m);
    vtkNew<vtkShortArray> values;
    values->SetNumberOfTuples(image->GetNumberOfPoints());
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i)
          values->SetValue(i + dims[0] * (j + dims[1] * k), label(i, j, k));
    image->GetPointData()->SetScalars(values);
    return image;
  }
};

/// The ellipsoid of semi-axes @p axes (mm, along the index axes) centred at index @p centre.
std::function<short(int, int, int)> Ellipsoid(
  const LabelMap& map, Vec3 centre, Vec3 axes, short value = 3)
{
  return [=](int i, int j, int k) -> short {
    const double u = (i - centre[0]) * map.spacing[0] / axes[0];
    const double v = (j - centre[1]) * map.spacing[1] / axes[1];
    const double w = (k - centre[2]) * map.spacing[2] / axes[2];
    return u * u + v * v + w * w <= 1.0 ? value : 0;
  };
}

const Vec3 kCentre = { 19.5, 16.0, 12.5 };
const Vec3 kAxes = { 12.0, 13.0, 14.0 };

/// The labelled voxels' physical points (by hand) of @p image.
std::vector<Vec3> LabelPoints(const LabelMap& map, vtkImageData* image, double label)
{
  std::vector<Vec3> points;
  vtkDataArray* values = image->GetPointData()->GetScalars();
  for (int k = 0; k < map.dims[2]; ++k)
    for (int j = 0; j < map.dims[1]; ++j)
      for (int i = 0; i < map.dims[0]; ++i)
        if (values->GetTuple1(i + map.dims[0] * (j + map.dims[1] * k)) == label)
          points.push_back(map.Point(i, j, k));
  return points;
}

struct Surface
{
  vtkSmartPointer<vtkPolyData> poly;
  vtkSmartPointer<vtkBaryLabelMapSurface> filter;
  std::string errors;
  bool ok = false;
};

Surface Extract(vtkImageData* image, const std::function<void(vtkBaryLabelMapSurface*)>& setup = {})
{
  Surface s;
  s.filter = vtkSmartPointer<vtkBaryLabelMapSurface>::New();
  vtkNew<ErrorObserver> observer;
  observer->Attach(s.filter);
  s.filter->SetInputData(image);
  if (setup)
    setup(s.filter);
  s.ok = RunPipeline(s.filter) == 1 && observer->Errors.empty();
  s.errors = observer->AllErrors();
  s.poly = s.filter->GetOutput();
  return s;
}

/// Signed volume and volume centroid of a closed triangle surface (divergence theorem).
double SignedVolume(vtkPolyData* poly, Vec3* centroid = nullptr)
{
  double volume = 0.0;
  Vec3 c = { 0, 0, 0 };
  vtkNew<vtkIdList> ids;
  for (vtkIdType t = 0; t < poly->GetNumberOfCells(); ++t)
  {
    poly->GetCellPoints(t, ids);
    double a[3], b[3], d[3];
    poly->GetPoint(ids->GetId(0), a);
    poly->GetPoint(ids->GetId(1), b);
    poly->GetPoint(ids->GetId(2), d);
    const double v = (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
                       a[2] * (b[0] * d[1] - b[1] * d[0])) /
      6.0;
    volume += v;
    for (int r = 0; r < 3; ++r)
      c[r] += v * (a[r] + b[r] + d[r]) / 4.0;
  }
  if (centroid)
    for (int r = 0; r < 3; ++r)
      (*centroid)[r] = c[r] / volume;
  return volume;
}

/// Boundary and non-manifold edges, by VTK's vtkFeatureEdges.
vtkIdType OpenOrNonManifoldEdges(vtkPolyData* poly)
{
  vtkNew<vtkFeatureEdges> edges;
  edges->SetInputData(poly);
  edges->BoundaryEdgesOn();
  edges->NonManifoldEdgesOn();
  edges->FeatureEdgesOff();
  edges->ManifoldEdgesOff();
  edges->Update();
  return edges->GetOutput()->GetNumberOfCells();
}

/// The checks of a smooth blob's surface: closed (VTK), outward, enclosed volume against the
/// voxel volume and VTK's vtkMassProperties, centroid and bounds against the voxels' points.
void ExpectGoodSurface(const LabelMap& map, vtkImageData* image, const Surface& s, double label)
{
  ASSERT_TRUE(s.ok) << s.errors;
  vtkPolyData* poly = s.poly;
  ASSERT_GT(poly->GetNumberOfCells(), 100);
  EXPECT_EQ(OpenOrNonManifoldEdges(poly), 0);
  Vec3 centroid{};
  const double volume = SignedVolume(poly, &centroid);
  EXPECT_GT(volume, 0.0) << "the surface must face outward";
  vtkNew<vtkMassProperties> mass;
  mass->SetInputData(poly);
  mass->Update();
  EXPECT_NEAR(s.filter->GetEnclosedVolume(), mass->GetVolume(), 1e-6 * mass->GetVolume());

  const std::vector<Vec3> points = LabelPoints(map, image, label);
  ASSERT_EQ(static_cast<vtkIdType>(points.size()), s.filter->GetNumberOfLabelVoxels());
  const double voxel_volume = points.size() * map.VoxelVolume();
  EXPECT_NEAR(s.filter->GetLabelVolume(), voxel_volume, 1e-9 * voxel_volume);
  // The discrete surface cuts the voxels' corners and smoothing rounds it a little more: within
  // 4% of the voxel volume for a blob of ~25 voxels across.
  EXPECT_NEAR(volume, voxel_volume, 0.04 * voxel_volume);

  // Centroid: the voxel points' mean, within a fifth of the largest spacing.
  Vec3 mean = { 0, 0, 0 };
  Vec3 lo = { 1e300, 1e300, 1e300 }, hi = { -1e300, -1e300, -1e300 };
  for (const Vec3& p : points)
    for (int r = 0; r < 3; ++r)
    {
      mean[r] += p[r] / static_cast<double>(points.size());
      lo[r] = std::min(lo[r], p[r]);
      hi[r] = std::max(hi[r], p[r]);
    }
  const double h = std::max({ map.spacing[0], map.spacing[1], map.spacing[2] });
  for (int r = 0; r < 3; ++r)
    EXPECT_NEAR(centroid[r], mean[r], 0.2 * h) << "centroid " << r;
  // Bounds: the voxel points' bounds, within half a voxel diagonal (the surface passes between
  // the last voxel inside and the first outside).
  const double half_diagonal = 0.5 *
    std::sqrt(map.spacing[0] * map.spacing[0] + map.spacing[1] * map.spacing[1] +
      map.spacing[2] * map.spacing[2]);
  double b[6];
  poly->GetBounds(b);
  for (int r = 0; r < 3; ++r)
  {
    EXPECT_NEAR(b[2 * r], lo[r], half_diagonal) << "lower bound " << r;
    EXPECT_NEAR(b[2 * r + 1], hi[r], half_diagonal) << "upper bound " << r;
  }
}

TEST(LabelMapSurface, EllipsoidVolumeCentroidBoundsRotatedDirection)
{
  LabelMap map;
  auto image = map.Image(Ellipsoid(map, kCentre, kAxes));
  Surface s = Extract(image);
  ExpectGoodSurface(map, image, s, 3);
  EXPECT_EQ(s.filter->GetLabelUsed(), 3);
  EXPECT_FALSE(s.filter->GetTouchesBorder());
  EXPECT_EQ(s.filter->GetNumberOfDroppedComponents(), 0);
  // The analytic volume 4/3 pi a b c, within 5% (voxelisation and smoothing).
  const double analytic = 4.0 / 3.0 * kPi * kAxes[0] * kAxes[1] * kAxes[2];
  EXPECT_NEAR(s.filter->GetEnclosedVolume(), analytic, 0.05 * analytic);
  // The default decimation: about 5000 triangles (a topology-preserving decimation may stop
  // above its target).
  EXPECT_LE(s.poly->GetNumberOfCells(), 5500);
  EXPECT_GE(s.poly->GetNumberOfCells(), 4000);
}

// A mirrored direction (determinant -1, as NIfTI images read into LPS often have) and a
// sheared, non-orthogonal one: the same checks, the surface still outward.
TEST(LabelMapSurface, MirroredAndShearedDirections)
{
  LabelMap map;
  map.direction = Rotation({ 0.3, 1.0, -0.4 }, 1.1);
  for (int r = 0; r < 3; ++r)
    map.direction[r][0] = -map.direction[r][0];
  auto image = map.Image(Ellipsoid(map, kCentre, kAxes));
  ExpectGoodSurface(map, image, Extract(image), 3);

  LabelMap sheared;
  sheared.direction = Identity();
  sheared.direction[0][1] = 0.35; // y axis leaning along x
  sheared.direction[2][0] = -0.2;
  auto image2 = sheared.Image(Ellipsoid(sheared, kCentre, kAxes));
  ExpectGoodSurface(sheared, image2, Extract(image2), 3);
}

TEST(LabelMapSurface, NoSmoothingNoDecimation)
{
  LabelMap map;
  auto image = map.Image(Ellipsoid(map, kCentre, kAxes));
  Surface s = Extract(image, [](vtkBaryLabelMapSurface* f) {
    f->SetSmoothingIterations(0);
    f->SetTargetNumberOfFaces(0);
  });
  ExpectGoodSurface(map, image, s, 3);
  EXPECT_EQ(s.poly->GetNumberOfCells(), s.filter->GetNumberOfExtractedFaces());
  // TargetReduction: half the triangles (approximately).
  Surface half = Extract(image, [](vtkBaryLabelMapSurface* f) {
    f->SetSmoothingIterations(0);
    f->SetTargetNumberOfFaces(0);
    f->SetTargetReduction(0.5);
  });
  ASSERT_TRUE(half.ok) << half.errors;
  EXPECT_NEAR(static_cast<double>(half.poly->GetNumberOfCells()),
    0.5 * static_cast<double>(s.poly->GetNumberOfCells()),
    0.05 * static_cast<double>(s.poly->GetNumberOfCells()));
}

// The same label map through NIfTI (RAS on disk), NRRD and MetaImage (LPS): one LPS surface.
TEST(LabelMapSurface, SameSurfaceFromEachFileFormat)
{
  LabelMap map;
  auto image = map.Image(Ellipsoid(map, kCentre, kAxes));
  const fs::path dir = fs::path(BARYLAB_TEST_OUTPUT_DIR) / "filters_label_surface";
  fs::create_directories(dir);
  Surface reference = Extract(image);
  ASSERT_TRUE(reference.ok) << reference.errors;
  for (const char* ext : { ".nii.gz", ".nrrd", ".mha" })
  {
    const std::string path = (dir / (std::string("formats") + ext)).string();
    vtkBaryImageIO::Write(image, path);
    auto read = vtkBaryImageIO::Read(path);
    Surface s = Extract(read);
    ASSERT_TRUE(s.ok) << ext << ": " << s.errors;
    ASSERT_EQ(s.poly->GetNumberOfPoints(), reference.poly->GetNumberOfPoints()) << ext;
    double worst = 0.0;
    for (vtkIdType p = 0; p < s.poly->GetNumberOfPoints(); ++p)
    {
      double a[3], b[3];
      s.poly->GetPoint(p, a);
      reference.poly->GetPoint(p, b);
      worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
    }
    // NIfTI's geometry is float32 (1e-5 relative of ~40 mm coordinates); NRRD/MHA: exact text.
    EXPECT_LT(worst, 1e-3) << ext;
    fs::remove(path);
  }
}

TEST(LabelMapSurface, BorderLabelIsClosedAndFlagged)
{
  LabelMap map;
  // The ellipsoid's centre near the x = 0 face: the field of view cuts it.
  auto image = map.Image(Ellipsoid(map, { 3.0, 16.0, 12.5 }, kAxes));
  Surface s = Extract(image);
  ASSERT_TRUE(s.ok) << s.errors;
  EXPECT_TRUE(s.filter->GetTouchesBorder());
  EXPECT_EQ(OpenOrNonManifoldEdges(s.poly), 0);
  EXPECT_GT(SignedVolume(s.poly), 0.0);
  const double voxel_volume = s.filter->GetLabelVolume();
  EXPECT_NEAR(s.filter->GetEnclosedVolume(), voxel_volume, 0.06 * voxel_volume);
}

TEST(LabelMapSurface, LargestComponentKeptOthersCounted)
{
  LabelMap map;
  auto big = Ellipsoid(map, kCentre, { 8.0, 8.0, 8.0 });
  auto small1 = Ellipsoid(map, { 4.0, 4.0, 3.0 }, { 2.5, 2.5, 3.5 });
  auto small2 = Ellipsoid(map, { 35.0, 29.0, 22.0 }, { 2.5, 2.5, 3.5 });
  auto image = map.Image([&](int i, int j, int k) -> short {
    return std::max({ big(i, j, k), small1(i, j, k), small2(i, j, k) });
  });
  Surface s = Extract(image);
  ASSERT_TRUE(s.ok) << s.errors;
  EXPECT_EQ(s.filter->GetNumberOfDroppedComponents(), 2);
  const auto big_only = map.Image(big);
  const double big_volume = LabelPoints(map, big_only, 3).size() * map.VoxelVolume();
  EXPECT_NEAR(s.filter->GetEnclosedVolume(), big_volume, 0.06 * big_volume);
}

TEST(LabelMapSurface, LabelChoiceAndErrors)
{
  LabelMap map;
  auto two = map.Image([&](int i, int j, int k) -> short {
    const short a = Ellipsoid(map, { 12.0, 16.0, 12.5 }, { 6.0, 6.0, 6.0 }, 1)(i, j, k);
    const short b = Ellipsoid(map, { 29.0, 16.0, 12.5 }, { 5.0, 5.0, 5.0 }, 2)(i, j, k);
    return std::max(a, b);
  });
  // Several labels and no choice: an error listing them.
  Surface s = Extract(two);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("2 labels: 1 ("), std::string::npos) << s.errors;
  EXPECT_EQ(vtkBaryConversion::ErrorCodeOf(s.filter->GetErrorCode(), bary::ErrorCode::Internal),
    bary::ErrorCode::InvalidArgument);
  // A chosen label.
  s = Extract(two, [](vtkBaryLabelMapSurface* f) { f->SetLabel(2); });
  ASSERT_TRUE(s.ok) << s.errors;
  EXPECT_EQ(s.filter->GetLabelUsed(), 2);
  EXPECT_EQ(static_cast<size_t>(s.filter->GetNumberOfLabelVoxels()), LabelPoints(map, two, 2).size());
  // A label that is not there: an error naming the labels present.
  s = Extract(two, [](vtkBaryLabelMapSurface* f) { f->SetLabel(5); });
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("label 5 is empty"), std::string::npos) << s.errors;
  EXPECT_NE(s.errors.find("labels present: 1 ("), std::string::npos) << s.errors;
  EXPECT_EQ(vtkBaryConversion::ErrorCodeOf(s.filter->GetErrorCode(), bary::ErrorCode::Internal),
    bary::ErrorCode::EmptyInput);
  EXPECT_EQ(s.poly->GetNumberOfPoints(), 0);
  // All background.
  s = Extract(map.Image([](int, int, int) -> short { return 0; }));
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("no non-zero label"), std::string::npos) << s.errors;
}

TEST(LabelMapSurface, SingularOrNonFiniteDirectionRefused)
{
  LabelMap map;
  map.direction = Identity();
  map.direction[0][2] = 1.0; // z axis = x axis
  map.direction[2][2] = 0.0;
  auto image = map.Image(Ellipsoid(map, kCentre, kAxes));
  Surface s = Extract(image);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("singular"), std::string::npos) << s.errors;
  image->GetDirectionMatrix()->SetElement(2, 2, std::nan(""));
  s = Extract(image);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("not finite"), std::string::npos) << s.errors;
}

TEST(LabelMapSurface, FloatImagesNeedIntegersOrAThreshold)
{
  LabelMap map;
  auto labels = map.Image(Ellipsoid(map, kCentre, kAxes));
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(labels);
  vtkNew<vtkFloatArray> f;
  f->SetNumberOfTuples(image->GetNumberOfPoints());
  vtkDataArray* l = labels->GetPointData()->GetScalars();
  for (vtkIdType v = 0; v < f->GetNumberOfTuples(); ++v)
    f->SetValue(v, static_cast<float>(l->GetTuple1(v)));
  image->GetPointData()->SetScalars(f);
  // Integer values stored as float: a label map.
  Surface s = Extract(image);
  ASSERT_TRUE(s.ok) << s.errors;
  EXPECT_EQ(s.filter->GetLabelUsed(), 3);
  // Intensities: refused, unless thresholded.
  for (vtkIdType v = 0; v < f->GetNumberOfTuples(); ++v)
    f->SetValue(v, 0.25f * static_cast<float>(l->GetTuple1(v)) + 0.1f);
  f->Modified();
  s = Extract(image);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("not an integer label"), std::string::npos) << s.errors;
  s = Extract(image, [](vtkBaryLabelMapSurface* fl) {
    fl->UseThresholdOn();
    fl->SetThreshold(0.5);
  });
  ASSERT_TRUE(s.ok) << s.errors;
  EXPECT_EQ(static_cast<size_t>(s.filter->GetNumberOfLabelVoxels()), LabelPoints(map, labels, 3).size());
  s = Extract(image, [](vtkBaryLabelMapSurface* fl) {
    fl->UseThresholdOn();
    fl->SetThreshold(5.0);
  });
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.errors.find("no voxel is at or above"), std::string::npos) << s.errors;
}
// Rough labels (unions of random balls with salt-and-pepper noise, where smoothing and
// decimation can fold the surface): every surface output is closed and manifold by VTK's own
// vtkFeatureEdges, outward, and of the volume vtkMassProperties measures; what was used to make
// it is reported (a surface that failed validation was replaced by the next candidate).
TEST(LabelMapSurface, RoughLabelsGiveValidSurfaces)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> centre(8.0, 26.0), radius(2.0, 7.0);
  std::bernoulli_distribution flip(0.02);
  LabelMap map;
  map.dims = { 34, 34, 34 };
  for (int trial = 0; trial < 6; ++trial)
  {
    std::vector<std::array<double, 4>> balls(3 + trial);
    for (auto& b : balls)
      b = { centre(rng), centre(rng), centre(rng), radius(rng) };
    auto image = map.Image([&](int i, int j, int k) -> short {
      bool in = false;
      for (const auto& b : balls)
        in = in || (i - b[0]) * (i - b[0]) + (j - b[1]) * (j - b[1]) + (k - b[2]) * (k - b[2]) <= b[3] * b[3];
      return (in != flip(rng)) ? 1 : 0;
    });
    Surface s = Extract(image, [&](vtkBaryLabelMapSurface* f) {
      f->SetLabel(1);
      f->SetTargetNumberOfFaces(trial % 2 ? 2000 : 5000);
    });
    ASSERT_TRUE(s.ok) << "trial " << trial << ": " << s.errors;
    EXPECT_EQ(OpenOrNonManifoldEdges(s.poly), 0) << "trial " << trial;
    EXPECT_GT(SignedVolume(s.poly), 0.0) << "trial " << trial;
    vtkNew<vtkMassProperties> mass;
    mass->SetInputData(s.poly);
    mass->Update();
    EXPECT_NEAR(s.filter->GetEnclosedVolume(), mass->GetVolume(), 1e-6 * mass->GetVolume());
    EXPECT_GE(s.filter->GetNumberOfAttempts(), 1);
    const std::string used = s.filter->GetDecimationUsed();
    EXPECT_TRUE(used == "decimate-pro" || used == "quadric" || used == "none") << used;
    EXPECT_EQ(std::string(s.filter->GetFirstFailure()).empty(), s.filter->GetNumberOfAttempts() == 1);
    EXPECT_GT(s.filter->GetNumberOfDroppedComponents(), 0) << "the noise makes islands";
  }
}
} // namespace
