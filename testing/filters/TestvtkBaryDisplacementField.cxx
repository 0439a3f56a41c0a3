// Tests of vtkBaryDisplacementField and vtkBaryImageWarp (BaryLab::BaryLabMedical) with the real
// client: the field is written with vtkBaryImageIO and read back by ITK 5.2 itself
// (itk::ImageFileReader), applied to points as itk::DisplacementFieldTransform and compared with
// BaryLab's own deformation of those points (vtkBaryCageDeformation), in LPS and RAS, forward
// and inverse; a rigid cage motion gives a rigid field; a known landmark lands where expected;
// label maps are warped with their labels preserved. The only test that includes ITK's headers
// (compiled once, where the Medical module is built: not in a sanitizer tree).
#include "filters_test_utils.h"
#include "itk_displacement_client.h"

#include "vtkBaryCageDeformation.h"
#include "vtkBaryDisplacementField.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryImageWarp.h"
#include "vtkBaryWeightMethod.h"

#include "core/imaging/displacement_field.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace
{
namespace fs = std::filesystem;
using namespace barylab_test;

const Eigen::Vector3d kOffset(10.0, -5.0, 30.0); // the cage's centre, mm (LPS)
constexpr double kHalf = 20.0;                      // the cube cage's half side, mm

fs::path Scratch(const std::string& name)
{
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(BARYLAB_TEST_OUTPUT_DIR) / "filters_displacement_field" /
    (std::string(test->test_suite_name()) + "." + test->name()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The cube cage [-20, 20]^3 mm around kOffset.
vtkSmartPointer<vtkPolyData> RestCage()
{
  auto cage = MakeCube(kHalf);
  for (vtkIdType i = 0; i < cage->GetNumberOfPoints(); ++i)
  {
    double x[3];
    cage->GetPoint(i, x);
    cage->GetPoints()->SetPoint(i, x[0] + kOffset(0), x[1] + kOffset(1), x[2] + kOffset(2));
  }
  return cage;
}

/// The rest cage with each vertex moved by @p f.
template<class F>
vtkSmartPointer<vtkPolyData> MovedCage(vtkPolyData* rest, F&& f)
{
  auto moved = vtkSmartPointer<vtkPolyData>::New();
  moved->DeepCopy(rest);
  for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
  {
    double x[3];
    rest->GetPoint(i, x);
    const Eigen::Vector3d y = f(Eigen::Vector3d(x[0], x[1], x[2]));
    moved->GetPoints()->SetPoint(i, y.data());
  }
  return moved;
}

/// A non-affine motion: the top face pushed along x and twisted, the bottom squeezed.
Eigen::Vector3d Bend(const Eigen::Vector3d& x)
{
  const Eigen::Vector3d c = x - kOffset;
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  if (c(2) > 0)
    d = Eigen::Vector3d(6.0, 0.0, 2.0) + 0.1 * Eigen::Vector3d(-c(1), c(0), 0.0);
  else
    d = Eigen::Vector3d(-0.1 * c(0), -0.05 * c(1), 0.0);
  return x + d;
}

/// @p count random points in the cube of half side @p half around kOffset.
std::vector<Eigen::Vector3d> ModelPoints(int count, double half, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<Eigen::Vector3d> P;
  for (int i = 0; i < count; ++i)
    P.push_back(kOffset + Eigen::Vector3d(u(rng), u(rng), u(rng)));
  return P;
}

/// BaryLab's own deformation of @p P (vtkBaryCageDeformation with @p method).
std::vector<Eigen::Vector3d> Deform(const std::vector<Eigen::Vector3d>& P, vtkPolyData* rest,
  vtkPolyData* moved, vtkBaryWeightMethod* method)
{
  std::vector<std::array<double, 3>> xs;
  for (const auto& p : P)
    xs.push_back({ p(0), p(1), p(2) });
  vtkNew<vtkBaryCageDeformation> deformation;
  deformation->SetWeightMethod(method);
  deformation->SetInputData(MakePointCloud(xs));
  deformation->SetRestCageData(rest);
  deformation->SetDeformedCageData(moved);
  EXPECT_EQ(RunPipeline(deformation), 1);
  std::vector<Eigen::Vector3d> out;
  vtkPointSet* result = deformation->GetOutput();
  for (vtkIdType i = 0; i < result->GetNumberOfPoints(); ++i)
  {
    double x[3];
    result->GetPoint(i, x);
    out.emplace_back(x[0], x[1], x[2]);
  }
  return out;
}

/// The field filter on the cage's bounds plus @p margin, spacing @p h.
vtkSmartPointer<vtkBaryDisplacementField> FieldFilter(vtkPolyData* rest, vtkPolyData* moved,
  double h, double margin, vtkBaryWeightMethod* method = nullptr, bool inverse = false)
{
  auto filter = vtkSmartPointer<vtkBaryDisplacementField>::New();
  if (method)
    filter->SetWeightMethod(method);
  filter->SetRestCageData(rest);
  filter->SetDeformedCageData(moved);
  double b[6];
  rest->GetBounds(b);
  filter->SetBounds(b[0] - margin, b[1] + margin, b[2] - margin, b[3] + margin, b[4] - margin,
    b[5] + margin);
  filter->SetSpacing(h, h, h);
  filter->SetComputeInverse(inverse);
  return filter;
}

/// The points @p P moved by the field in @p path as ITK reads and applies it.
std::vector<Eigen::Vector3d> ApplyWithITK(const std::string& path, const std::vector<Eigen::Vector3d>& P)
{
  std::vector<std::array<double, 3>> xs;
  for (const auto& p : P)
    xs.push_back({ p(0), p(1), p(2) });
  std::vector<Eigen::Vector3d> out;
  for (const auto& y : ItkTransformPoints(path, xs))
    out.emplace_back(y[0], y[1], y[2]);
  return out;
}

/// A bound of the trilinear interpolation error of the deformation near the points @p P on a
/// grid of spacing h: (h^2 / 8) sum_a max |d^2 T / dx_a^2| (per component, then the norm),
/// the second derivatives estimated by second differences of BaryLab's own deformation with
/// step h around each point, the largest over the points, times 2 for the variation within a
/// cell.
double InterpolationBound(const std::vector<Eigen::Vector3d>& P, vtkPolyData* rest,
  vtkPolyData* moved, vtkBaryWeightMethod* method, double h)
{
  std::vector<Eigen::Vector3d> samples;
  for (const auto& p : P)
    for (int a = 0; a < 3; ++a)
    {
      samples.push_back(p - h * Eigen::Vector3d::Unit(a));
      samples.push_back(p);
      samples.push_back(p + h * Eigen::Vector3d::Unit(a));
    }
  const std::vector<Eigen::Vector3d> T = Deform(samples, rest, moved, method);
  double worst = 0.0;
  for (size_t i = 0; i < P.size(); ++i)
  {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a)
    {
      const size_t k = 9 * i + 3 * size_t(a);
      sum += (T[k] - 2.0 * T[k + 1] + T[k + 2]).cwiseAbs(); // h^2 |d_aa T|
    }
    worst = std::max(worst, sum.norm() / 8.0);
  }
  return 2.0 * worst;
}

TEST(vtkBaryDisplacementField, ITKAppliesTheFieldAsBaryLabDeforms)
{
  auto rest = RestCage();
  auto moved = MovedCage(rest, Bend);
  vtkNew<vtkBaryWeightMethod> mvc; // mean value coordinates
  const std::vector<Eigen::Vector3d> P = ModelPoints(150, 0.9 * kHalf, 1);
  const std::vector<Eigen::Vector3d> direct = Deform(P, rest, moved, mvc);
  const fs::path dir = Scratch("out");
  std::vector<double> errors;
  for (const double h : { 2.0, 1.0 })
  {
    auto filter = FieldFilter(rest, moved, h, 4.0, mvc);
    ASSERT_EQ(RunPipeline(filter), 1);
    vtkImageData* field = filter->GetOutput();
    EXPECT_EQ(filter->GetNumberOfFoldedVoxels(), 0);
    const std::string path = (dir / ("field_" + std::to_string(int(h)) + ".mha")).string();
    vtkBaryImageIO::Write(field, path);
    const std::vector<Eigen::Vector3d> moved_by_itk = ApplyWithITK(path, P);
    // ITK applies what BaryLab samples (the same trilinear rule), to rounding
    const bary::DisplacementField core = vtkBaryDisplacementField::ToField(field, "Displacement");
    const bary::FieldSampler sampler(core);
    const double bound = InterpolationBound(P, rest, moved, mvc, h);
    double worst = 0.0;
    for (size_t i = 0; i < P.size(); ++i)
    {
      const Eigen::Vector3d viaITK = moved_by_itk[i];
      EXPECT_LE((viaITK - (P[i] + sampler.displacement(P[i]))).norm(), 1e-9) << i;
      worst = std::max(worst, (viaITK - direct[i]).norm());
    }
    EXPECT_LE(worst, bound) << "h = " << h;
    // ITK's rules at the grid's border: the half voxel beyond the outer centres repeats the
    // border value, a point beyond it is not moved; BaryLab's sampler says the same
    const auto& n = core.grid.size;
    std::vector<Eigen::Vector3d> border;
    for (const Eigen::Vector3d& c : { Eigen::Vector3d(-0.3, 2.2, 3.7), Eigen::Vector3d(n[0] - 0.6, 1.5, 2.0),
           Eigen::Vector3d(3.3, -0.45, n[2] - 0.55), Eigen::Vector3d(-0.7, 2.0, 3.0),
           Eigen::Vector3d(1.0, n[1] - 0.2, 2.0), Eigen::Vector3d(-3.0, -3.0, -3.0) })
      border.push_back(core.grid.point(c));
    const std::vector<Eigen::Vector3d> border_by_itk = ApplyWithITK(path, border);
    for (size_t i = 0; i < border.size(); ++i)
    {
      EXPECT_LE((border_by_itk[i] - (border[i] + sampler.displacement(border[i]))).norm(), 1e-9) << i;
      EXPECT_EQ(sampler.inside(border[i]), i < 3) << i;
    }
    // the deformation is large against the bound: the comparison can fail
    EXPECT_GT((direct[0] - P[0]).norm(), 10.0 * bound);
    errors.push_back(worst);
  }
  EXPECT_LT(errors[1], errors[0] / 2.5); // second order in the spacing
}

TEST(vtkBaryDisplacementField, InverseReturnsTheDeformedPointsToRest)
{
  auto rest = RestCage();
  auto moved = MovedCage(rest, Bend);
  vtkNew<vtkBaryWeightMethod> mvc;
  const double h = 1.0;
  auto filter = FieldFilter(rest, moved, h, 10.0, mvc, true);
  ASSERT_EQ(RunPipeline(filter), 1);
  const std::string path = (Scratch("out") / "inverse.nrrd").string();
  vtkBaryImageIO::Write(filter->GetOutput(1), path);
  // the inside of the deformed cage: its preimages are well inside the grid
  EXPECT_EQ(filter->GetInverseNotConverged(), filter->GetInverseNotConvergedAtBorder());
  EXPECT_GT(filter->GetInverseToleranceUsed(), 0.0);
  const std::vector<Eigen::Vector3d> P = ModelPoints(150, 0.8 * kHalf, 2);
  const std::vector<Eigen::Vector3d> deformed = Deform(P, rest, moved, mvc);
  const std::vector<Eigen::Vector3d> back = ApplyWithITK(path, deformed);
  // |T_h^-1(T(p)) - p| <= interpolation error of the inverse (its second derivatives: those of
  // T amplified by (1 - L)^-3, L = |du/dx| <= 0.3 here, i.e. < 3x) + the forward error carried
  // through the inverse (1 / (1 - L)) + the inverse's tolerance: 5 x the forward bound + tol
  const double bound =
    5.0 * InterpolationBound(P, rest, moved, mvc, h) + filter->GetInverseToleranceUsed();
  for (size_t i = 0; i < P.size(); ++i)
    EXPECT_LE((back[i] - P[i]).norm(), bound) << i;
}

TEST(vtkBaryDisplacementField, RigidCageMotionGivesARigidField)
{
  auto rest = RestCage();
  const Eigen::Matrix3d R =
    Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(3.0, -4.0, 7.0);
  auto rigid = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(R * x + t); };
  auto moved = MovedCage(rest, rigid);
  const fs::path dir = Scratch("out");
  // mean value coordinates (closed form everywhere) and harmonic coordinates (on a mesh of the
  // cage, interpolated: exact inside; outside the cage the displacement is the closest
  // point's, not rigid)
  // (and Green coordinates, exact under similarities, on a grid strictly inside the cage)
  vtkNew<vtkBaryWeightMethod> mvc, harmonic, green;
  harmonic->SetMethodToHarmonic();
  harmonic->SetTargetNumberOfCells(1500);
  green->SetMethodToGreen();
  for (vtkBaryWeightMethod* method : { mvc.Get(), harmonic.Get(), green.Get() })
  {
    const bool inside_only = method != mvc.Get();
    auto filter = FieldFilter(
      rest, moved, 2.5, method == mvc.Get() ? 5.0 : method == green.Get() ? -1.25 : 0.0, method);
    ASSERT_EQ(RunPipeline(filter), 1);
    const bary::DisplacementField field =
      vtkBaryDisplacementField::ToField(filter->GetOutput(), "Displacement");
    // at every voxel (harmonic: inside or on the cage), u = R x + t - x, to the weights' rounding
    for (bary::Index k = 0; k < field.grid.size[2]; ++k)
      for (bary::Index j = 0; j < field.grid.size[1]; ++j)
        for (bary::Index i = 0; i < field.grid.size[0]; ++i)
        {
          const Eigen::Vector3d x = field.grid.point(i, j, k);
          if (inside_only && ((x - kOffset).cwiseAbs().maxCoeff() > kHalf + 1e-9))
            continue;
          ASSERT_LE((field.values.col(field.grid.voxel(i, j, k)) - (rigid(x) - x)).norm(), 1e-8)
            << method->GetMethodName(method->GetMethod()) << " voxel " << i << " " << j << " " << k;
        }
    // the Jacobian determinant of a rigid motion is 1
    EXPECT_NEAR(filter->GetJacobianMinimum(), 1.0, 1e-8);
    if (!inside_only)
    {
      // and ITK moves points rigidly (trilinear interpolation of an affine field is exact)
      const std::string path = (dir / "rigid.nii.gz").string();
      vtkBaryImageIO::Write(filter->GetOutput(), path);
      const std::vector<Eigen::Vector3d> Q = ModelPoints(50, kHalf + 4.0, 3);
      const std::vector<Eigen::Vector3d> moved_by_itk = ApplyWithITK(path, Q);
      for (size_t i = 0; i < Q.size(); ++i)
        EXPECT_LE((moved_by_itk[i] - rigid(Q[i])).norm(), 1e-8);
    }
    else
      EXPECT_EQ(filter->GetNumberOfOutsideVoxels(), 0);
  }
  // harmonic coordinates outside the cage: each voxel takes the displacement of the cage's
  // closest point, here the voxel clamped to the cube: u(x) = rigid(c) - c, c = clamp(x)
  auto filter = FieldFilter(rest, moved, 2.5, 5.0, harmonic);
  ASSERT_EQ(RunPipeline(filter), 1);
  const bary::DisplacementField field =
    vtkBaryDisplacementField::ToField(filter->GetOutput(), "Displacement");
  bary::Index outside = 0;
  for (bary::Index v = 0; v < field.grid.voxel_count(); ++v)
  {
    const Eigen::Vector3d x = field.grid.point(
      v % field.grid.size[0], (v / field.grid.size[0]) % field.grid.size[1], v / (field.grid.size[0] * field.grid.size[1]));
    const Eigen::Vector3d c =
      kOffset + (x - kOffset).cwiseMax(Eigen::Vector3d::Constant(-kHalf)).cwiseMin(Eigen::Vector3d::Constant(kHalf));
    outside += (x - c).norm() > 1e-9;
    ASSERT_LE((field.values.col(v) - (rigid(c) - c)).norm(), 1e-8) << "voxel " << v;
  }
  EXPECT_EQ(filter->GetNumberOfOutsideVoxels(), outside);
  EXPECT_GT(outside, 1000);
}

vtkSmartPointer<vtkImageData> Labels(); // below

TEST(vtkBaryDisplacementField, ObliqueReferenceGridIsKept)
{
  // a reference with a rotated direction matrix and an extent not starting at 0: the field
  // lies on the same physical voxels (VTK's own index -> point map of the reference), and the
  // output's direction is the reference's, through the pipeline (warp) as well
  auto rest = RestCage();
  const Eigen::Matrix3d R =
    Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.0, 1.0, 1.0).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(1.0, 2.0, -3.0);
  auto rigid = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(R * (x - kOffset) + kOffset + t); };
  auto moved = MovedCage(rest, rigid);
  auto reference = Labels();
  reference->SetExtent(2, 31, -3, 21, 5, 24);
  const Eigen::Matrix3d D =
    Eigen::AngleAxisd(0.5, Eigen::Vector3d(1.0, 0.3, -0.2).normalized()).toRotationMatrix();
  reference->SetDirectionMatrix(D.data()); // row-major: this is D^T, also a rotation
  auto field = vtkSmartPointer<vtkBaryDisplacementField>::New();
  field->SetRestCageData(rest);
  field->SetDeformedCageData(moved);
  field->SetReferenceImageData(reference);
  vtkNew<vtkBaryImageWarp> warp;
  warp->SetInputData(reference);
  warp->SetFieldConnection(field->GetOutputPort());
  warp->SetInterpolationToNearest();
  ASSERT_EQ(RunPipeline(warp), 1);
  vtkImageData* out = field->GetOutput();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_DOUBLE_EQ(out->GetDirectionMatrix()->GetElement(r, c),
        reference->GetDirectionMatrix()->GetElement(r, c));
      EXPECT_DOUBLE_EQ(warp->GetOutput()->GetDirectionMatrix()->GetElement(r, c),
        reference->GetDirectionMatrix()->GetElement(r, c));
    }
  vtkDataArray* u = out->GetPointData()->GetArray("Displacement");
  ASSERT_EQ(u->GetNumberOfTuples(), reference->GetNumberOfPoints());
  for (const int v : { 0, 777, 5000, 14999 })
  {
    const int i = v % 30, j = (v / 30) % 25, k = v / 750;
    double x[3];
    reference->TransformIndexToPhysicalPoint(i + 2, j - 3, k + 5, x);
    const Eigen::Vector3d p(x[0], x[1], x[2]);
    const Eigen::Vector3d expected = rigid(p) - p;
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(u->GetComponent(v, a), expected(a), 1e-8) << v;
  }
}

TEST(vtkBaryDisplacementField, LandmarkLandsWhereExpectedInLPSAndRAS)
{
  // the cage moves 5 mm to the patient's left (+x in LPS, -x in RAS) and 2 mm up (+z in both)
  auto rest = RestCage();
  const Eigen::Vector3d t(5.0, 0.0, 2.0);
  auto moved = MovedCage(rest, [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(x + t); });
  auto filter = FieldFilter(rest, moved, 4.0, 4.0);
  ASSERT_EQ(RunPipeline(filter), 1);
  const fs::path dir = Scratch("out");
  const Eigen::Vector3d landmark = kOffset + Eigen::Vector3d(3.0, -7.0, 11.0); // LPS
  const std::string lps = (dir / "lps.nii.gz").string(), ras = (dir / "ras.nii.gz").string();
  vtkBaryImageIO::Write(filter->GetOutput(), lps);
  const bary::DisplacementField field =
    vtkBaryDisplacementField::ToField(filter->GetOutput(), "Displacement");
  vtkBaryImageIO::Write(
    vtkBaryDisplacementField::FromField(vtkBaryDisplacementField::SwapLPSRAS(field)), ras);
  // ITK (LPS): the landmark moves by +5 in x
  EXPECT_LE((ApplyWithITK(lps, { landmark })[0] - (landmark + t)).norm(), 1e-9);
  // a RAS reader of the RAS field: the landmark written in RAS, (-x, -y, z), moves by -5 in x
  const Eigen::Vector3d flip(-1.0, -1.0, 1.0);
  const Eigen::Vector3d landmark_ras = landmark.cwiseProduct(flip);
  EXPECT_LE((ApplyWithITK(ras, { landmark_ras })[0] -
              (landmark_ras + Eigen::Vector3d(-5.0, 0.0, 2.0))).norm(), 1e-9);
}

TEST(vtkBaryDisplacementField, CelestialControlPointsAreTheSameInEveryBlock)
{
  // T-celestial coordinates of free control points (the cube's corners and centre) on a grid
  // reaching 6 mm beyond their hull, so that hull points are added (auto): identical control
  // points do not move any voxel (linear precision, the hull points included), and a
  // translation of the controls gives the same field in blocks of 100 voxels as in one block
  // (every block gets the hull points placed from the grid's corners)
  auto rest = RestCage();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
    points->InsertNextPoint(rest->GetPoint(i));
  points->InsertNextPoint(kOffset.data());
  vtkNew<vtkPolyData> controls;
  controls->SetPoints(points);
  auto moved = MovedCage(controls, [](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(x + Eigen::Vector3d(2.0, 0.0, 0.0));
  });
  vtkNew<vtkBaryWeightMethod> tcc;
  tcc->SetMethodToTCelestial();
  std::vector<bary::DisplacementField> fields;
  for (vtkPolyData* target : { static_cast<vtkPolyData*>(controls), moved.Get(), moved.Get() })
  {
    auto filter = FieldFilter(controls, target, 8.0, 6.0, tcc);
    filter->SetBlockSize(fields.size() == 2 ? 1000000 : 100);
    ASSERT_EQ(RunPipeline(filter), 1);
    fields.push_back(vtkBaryDisplacementField::ToField(filter->GetOutput(), "Displacement"));
  }
  EXPECT_LE(fields[0].values.cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT(fields[1].values.row(0).maxCoeff(), 0.5); // the translation moves the inside
  // the same up to the iterative solver's convergence (its warm starts come from the points of
  // the same block): 1e-9 mm on a 40 mm cage; placing the hull points from each block's own
  // points instead differed by 0.13 mm
  EXPECT_LE((fields[1].values - fields[2].values).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(vtkBaryDisplacementField, NoGridIsAnError)
{
  auto rest = RestCage();
  vtkNew<vtkBaryDisplacementField> filter;
  filter->SetRestCageData(rest);
  filter->SetDeformedCageData(rest);
  vtkNew<ErrorObserver> errors;
  errors->Attach(filter);
  EXPECT_EQ(RunPipeline(filter), 0);
  EXPECT_TRUE(errors->HasError("no grid")) << errors->AllErrors();
}

/// A label image on an oblique grid: 0 outside, 1 in a box, 7 in a smaller box.
vtkSmartPointer<vtkImageData> Labels()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetExtent(0, 29, 0, 24, 0, 19);
  image->SetOrigin(kOffset(0) - 29.0, kOffset(1) - 24.0, kOffset(2) - 19.0);
  image->SetSpacing(2.0, 2.0, 2.0);
  vtkNew<vtkUnsignedCharArray> labels;
  labels->SetName("labels");
  labels->SetNumberOfTuples(30 * 25 * 20);
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 25; ++j)
      for (int i = 0; i < 30; ++i)
      {
        unsigned char v = 0;
        if (i >= 5 && i < 25 && j >= 5 && j < 20 && k >= 4 && k < 16)
          v = 1;
        if (i >= 10 && i < 15 && j >= 8 && j < 12 && k >= 7 && k < 10)
          v = 7;
        labels->SetValue(i + 30 * (j + 25 * k), v);
      }
  image->GetPointData()->SetScalars(labels);
  return image;
}

TEST(vtkBaryImageWarp, IdentityLeavesTheImageUnchangedAndTranslationShiftsLabels)
{
  auto labels = Labels();
  auto rest = RestCage();
  for (const double shift : { 0.0, 4.0 }) // 4 mm = 2 voxels along x
  {
    auto moved = MovedCage(rest, [&](const Eigen::Vector3d& x) {
      return Eigen::Vector3d(x + Eigen::Vector3d(shift, 0.0, 0.0));
    });
    // a forward field on the label map's own grid (mvc: a translation everywhere), inverted by
    // the warp
    auto field = vtkSmartPointer<vtkBaryDisplacementField>::New();
    field->SetRestCageData(rest);
    field->SetDeformedCageData(moved);
    field->SetReferenceImageData(labels);
    vtkNew<vtkBaryImageWarp> warp;
    warp->SetInputData(labels);
    warp->SetFieldConnection(field->GetOutputPort());
    warp->FieldIsInverseOff();
    warp->SetInterpolationToNearest();
    ASSERT_EQ(RunPipeline(warp), 1);
    vtkImageData* out = warp->GetOutput();
    vtkDataArray* in = labels->GetPointData()->GetScalars();
    vtkDataArray* res = out->GetPointData()->GetScalars();
    ASSERT_NE(res, nullptr);
    EXPECT_EQ(res->GetDataType(), VTK_UNSIGNED_CHAR);
    EXPECT_STREQ(res->GetName(), "labels");
    const int s = int(shift / 2.0);
    for (int k = 0; k < 20; ++k)
      for (int j = 0; j < 25; ++j)
        for (int i = 0; i < 30; ++i)
        {
          // out(y) = in(T^-1(y)) = in(y - shift): voxel i takes voxel i - s (0 before the image)
          const double expected = i - s >= 0 ? in->GetComponent(i - s + 30 * (j + 25 * k), 0) : 0.0;
          ASSERT_EQ(res->GetComponent(i + 30 * (j + 25 * k), 0), expected) << i << " " << j << " " << k;
        }
    double o1[3], o2[3];
    labels->GetOrigin(o1);
    out->GetOrigin(o2);
    EXPECT_EQ(std::vector<double>(o1, o1 + 3), std::vector<double>(o2, o2 + 3));
  }
}

TEST(vtkBaryImageWarp, NearestNeighbourKeepsOnlyTheLabels)
{
  auto labels = Labels();
  auto rest = RestCage();
  auto moved = MovedCage(rest, Bend);
  auto field = vtkSmartPointer<vtkBaryDisplacementField>::New();
  field->SetRestCageData(rest);
  field->SetDeformedCageData(moved);
  field->SetReferenceImageData(labels);
  field->ComputeInverseOn();
  vtkNew<vtkBaryImageWarp> warp;
  warp->SetInputData(labels);
  warp->SetFieldConnection(field->GetOutputPort(1)); // the inverse: a pull-back field
  warp->SetInterpolationToNearest();
  ASSERT_EQ(RunPipeline(warp), 1);
  vtkDataArray* res = warp->GetOutput()->GetPointData()->GetScalars();
  std::set<double> values;
  for (vtkIdType v = 0; v < res->GetNumberOfTuples(); ++v)
    values.insert(res->GetComponent(v, 0));
  EXPECT_EQ(values, (std::set<double>{ 0, 1, 7 }));
  // the bend moves the top of the organ by +6 mm in x: label 1 appears where it was not
  vtkDataArray* in = labels->GetPointData()->GetScalars();
  vtkIdType changed = 0;
  for (vtkIdType v = 0; v < res->GetNumberOfTuples(); ++v)
    changed += res->GetComponent(v, 0) != in->GetComponent(v, 0);
  EXPECT_GT(changed, 100);
}

TEST(vtkBaryImageWarp, BadInputIsAnError)
{
  auto labels = Labels();
  vtkNew<vtkImageData> notAField;
  notAField->DeepCopy(labels); // one component: not a displacement field
  vtkNew<vtkBaryImageWarp> warp;
  warp->SetInputData(labels);
  warp->SetFieldData(notAField);
  vtkNew<ErrorObserver> errors;
  errors->Attach(warp);
  EXPECT_EQ(RunPipeline(warp), 0);
  EXPECT_TRUE(errors->HasError("3-component")) << errors->AllErrors();
}

} // namespace
