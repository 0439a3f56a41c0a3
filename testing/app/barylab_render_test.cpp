// Regression images of rendered weight fields and deformations (the CLI's and the demo's
// rendering code), compared with baselines in testing/baselines by vtkTesting (VTK's image
// comparison, threshold 10 as in VTK's own tests). Needs an X display: run under Xvfb.
//
// A missing baseline fails and leaves the rendered image in BARYLAB_TEST_OUTPUT_DIR, to be
// inspected and copied in (with a commit message that says why).

#include "barylabPipeline.h"
#include "barylabRender.h"
#include "barylabSplinePipeline.h"
#include "barylabSurfacePipeline.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"
#include "vtkBaryDisplacementField.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryImageWarp.h"
#include "vtkBaryLabelMapSurface.h"

#include "core/imaging/displacement_field.h"
#include "core/imaging/image_grid.h"

#include "core/deformation/skeleton.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkTesting.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace
{
std::string data(const std::string& name)
{
  return std::string(BARYLAB_DATA_DIR) + "/" + name;
}

/// Compares @p window with testing/baselines/<name>.png.
void ExpectMatchesBaseline(vtkRenderWindow* window, const std::string& name)
{
  ASSERT_TRUE(barylab::HasDisplay()) << "image tests need an X display: run them under Xvfb";
  const std::string baseline = std::string(BARYLAB_BASELINE_DIR) + "/" + name + ".png";
  const std::string outdir = std::string(BARYLAB_TEST_OUTPUT_DIR) + "/images";
  fs::create_directories(outdir);
  window->Render();
  vtkNew<vtkTesting> testing;
  testing->AddArgument("-V");
  testing->AddArgument(baseline.c_str());
  testing->AddArgument("-T");
  testing->AddArgument(outdir.c_str());
  testing->SetRenderWindow(window);
  const int result = testing->RegressionTest(10.0);
  // keep the rendered image for people and docs
  barylab::WritePNG(window, outdir + "/" + name + ".png");
  EXPECT_EQ(result, vtkTesting::PASSED)
    << "rendered image differs from " << baseline << " (see " << outdir << ")";
}

struct Example
{
  vtkSmartPointer<vtkPolyData> cage;
  vtkSmartPointer<vtkDataSet> posed;
  vtkSmartPointer<vtkDataSet> weighted;
};

Example load(const std::string& cage, const std::string& posed, const std::string& model)
{
  Example e;
  e.cage = vtkBaryDataIO::ReadPolyData(data(cage));
  e.posed = vtkBaryDataIO::Read(data(posed));
  e.weighted = barylab::ComputeWeights(vtkBaryDataIO::Read(data(model)), e.cage, {});
  return e;
}
} // namespace

TEST(RenderImages, WeightField2D)
{
  const Example e = load("cage2d.obj", "cage2d_posed.obj", "model2d.obj");
  barylab::RenderOptions options;
  options.component = 14; // the left hand: a field with negative parts and a w = 0 isoline
  options.title = "mean value coordinate of control point 14";
  ExpectMatchesBaseline(barylab::WeightFieldWindow(e.weighted, e.cage, options), "weight_field_2d");
}

TEST(RenderImages, WeightField3D)
{
  const Example e = load("cage3d.obj", "cage3d_posed.obj", "model3d.off");
  barylab::RenderOptions options;
  options.component = 36;
  options.title = "mean value coordinate of control point 36";
  ExpectMatchesBaseline(barylab::WeightFieldWindow(e.weighted, e.cage, options), "weight_field_3d");
}

TEST(RenderImages, Deformation2D)
{
  const Example e = load("cage2d.obj", "cage2d_posed.obj", "model2d.obj");
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(e.weighted), e.cage,
    vtkPointSet::SafeDownCast(e.posed), {});
  barylab::RenderOptions options;
  options.component = 14;
  options.width = 1000;
  options.height = 500;
  ExpectMatchesBaseline(
    barylab::DeformationWindow(e.weighted, e.cage, deformed, vtkPointSet::SafeDownCast(e.posed), options),
    "deformation_2d");
}

TEST(RenderImages, GreenDeformation2D)
{
  // The same cage, model and pose as Deformation2D (mean value coordinates, deformation_2d.png),
  // deformed with Green coordinates: the shape-preserving (conformal) deformation beside it.
  barylab::WeightsParameters p;
  p.method = bary::MethodId::Green;
  auto cage = vtkBaryDataIO::ReadPolyData(data("cage2d.obj"));
  vtkSmartPointer<vtkDataSet> posed_data = vtkBaryDataIO::Read(data("cage2d_posed.obj"));
  vtkPointSet* posed = vtkPointSet::SafeDownCast(posed_data);
  auto weighted = barylab::ComputeWeights(vtkBaryDataIO::Read(data("model2d.obj")), cage, p);
  ASSERT_NE(weighted->GetPointData()->GetArray("FaceWeights"), nullptr);
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(weighted), cage, posed, p);
  barylab::RenderOptions options;
  options.component = 14;
  options.width = 1000;
  options.height = 500;
  ExpectMatchesBaseline(barylab::DeformationWindow(weighted, cage, deformed, posed, options),
    "green_deformation_2d");
}

TEST(RenderImages, Deformation3D)
{
  const Example e = load("cage3d.obj", "cage3d_posed.obj", "model3d.off");
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(e.weighted), e.cage,
    vtkPointSet::SafeDownCast(e.posed), {});
  barylab::RenderOptions options;
  options.component = 36;
  options.width = 1000;
  options.height = 500;
  ExpectMatchesBaseline(
    barylab::DeformationWindow(e.weighted, e.cage, deformed, vtkPointSet::SafeDownCast(e.posed), options),
    "deformation_3d");
}

/// BBW of the bundled 2D skeleton in the gingerbread man (fast mode), at the model's vertices.
struct BBWExample
{
  vtkSmartPointer<vtkPolyData> handles;
  vtkSmartPointer<vtkDataSet> weighted;
  std::vector<Eigen::MatrixXd> pose;
};

BBWExample load_bbw2d()
{
  BBWExample e;
  e.handles = vtkBaryDataIO::ReadPolyData(data("skeleton2d.tgf"));
  barylab::WeightsParameters p;
  p.method = bary::MethodId::BBW;
  p.bbw_fast = true;
  e.weighted = barylab::ComputeWeights(
    vtkBaryDataIO::Read(data("model2d.obj")), e.handles, p, {}, nullptr, vtkBaryDataIO::Read(data("cage2d.obj")));
  const bary::Skeleton skeleton = vtkBaryConversion::ToSkeleton(e.handles, 2);
  e.pose = vtkBaryDataIO::ReadPose(data("skeleton2d_pose.txt"), skeleton.handle_count(), &skeleton);
  return e;
}

TEST(RenderImages, BBWWeightField2D)
{
  const BBWExample e = load_bbw2d();
  barylab::RenderOptions options;
  options.skeleton = true;
  options.component = 3; // the right arm's bone
  options.title = "bounded biharmonic weight of bone 3";
  ExpectMatchesBaseline(barylab::WeightFieldWindow(e.weighted, e.handles, options), "bbw_weight_field_2d");
}

TEST(RenderImages, BBWSkinning2D)
{
  const BBWExample e = load_bbw2d();
  barylab::WeightsParameters p;
  auto deformed = barylab::Skin(vtkPointSet::SafeDownCast(e.weighted), e.pose, p);
  barylab::RenderOptions options;
  options.skeleton = true;
  options.component = 3;
  options.width = 1000;
  options.height = 500;
  ExpectMatchesBaseline(barylab::DeformationWindow(e.weighted, e.handles, deformed,
                          barylab::PoseHandles(e.handles, e.pose), options),
    "bbw_skinning_2d");
}

TEST(RenderImages, BBWSkinningLibiglHand3D)
{
  // libigl's BBW tutorial: the hand tet mesh, its skeleton and its pose (a fist).
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl";
  if (!fs::exists(dir + "/hand.mesh"))
    GTEST_SKIP() << "shared data not found in " << dir;
  auto mesh = vtkBaryDataIO::Read(dir + "/hand.mesh");
  auto handles = vtkBaryDataIO::ReadPolyData(dir + "/hand.tgf");
  barylab::WeightsParameters p;
  p.method = bary::MethodId::BBW;
  p.bbw_fast = true;
  auto weighted = barylab::ComputeWeights(mesh, handles, p, {}, nullptr, mesh);
  const bary::Skeleton skeleton = vtkBaryConversion::ToSkeleton(handles, 3);
  const auto pose = vtkBaryDataIO::ReadPose(dir + "/hand-pose.dmat", skeleton.handle_count(), &skeleton);
  auto deformed = barylab::Skin(vtkPointSet::SafeDownCast(weighted), pose, p);
  barylab::RenderOptions options;
  options.skeleton = true;
  options.component = 6; // a finger bone
  options.width = 1000;
  options.height = 500;
  ExpectMatchesBaseline(barylab::DeformationWindow(weighted, handles, deformed,
                          barylab::PoseHandles(handles, pose), options),
    "bbw_skinning_hand_3d");
}

TEST(RenderImages, HeartbeatSystoleSCC3D)
{
  // The organ workflow: S-celestial weights of the bundled heart w.r.t. its free control points,
  // deformed by the heartbeat's peak-systole frame.
  auto controls = vtkBaryDataIO::ReadPolyData(data("heart_controls.obj"));
  auto frame = vtkBaryDataIO::Read(data("heartbeat/frame_10.obj"));
  barylab::WeightsParameters p;
  p.method = bary::MethodId::SCelestial;
  auto weighted = barylab::ComputeWeights(vtkBaryDataIO::Read(data("heart.off")), controls, p);
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(weighted), controls,
    vtkPointSet::SafeDownCast(frame), p);
  barylab::RenderOptions options;
  options.free_points = true;
  options.component = 7;
  options.width = 1000;
  options.height = 500;
  ExpectMatchesBaseline(barylab::DeformationWindow(weighted, controls, deformed,
                          vtkPointSet::SafeDownCast(frame), options),
    "heartbeat_systole_scc_3d");
}

TEST(RenderImages, NoDisplayIsAClearError)
{
  // Without DISPLAY, rendering must fail with a message, not crash (VTK aborts without X).
  const char* saved = std::getenv("DISPLAY");
  const std::string keep = saved ? saved : "";
  unsetenv("DISPLAY");
  const Example e = load("cage2d.obj", "cage2d_posed.obj", "model2d.obj");
  try
  {
    barylab::WeightFieldWindow(e.weighted, e.cage, {});
    ADD_FAILURE() << "expected an error without DISPLAY";
  }
  catch (const bary::Error& err)
  {
    EXPECT_NE(std::string(err.what()).find("Xvfb"), std::string::npos) << err.what();
  }
  if (!keep.empty())
    setenv("DISPLAY", keep.c_str(), 1);
}

/// Local barycentric coordinates (Zhang et al. 2014) in the style of the paper's Fig. 4: one
/// control point's weight with its influence level set w = 1e-3 / n (n control points, blue),
/// beyond which the weight is insignificant (exactly 0 a little further). Small meshes.
TEST(RenderImages, LBCWeightField2D)
{
  auto cage = vtkBaryDataIO::ReadPolyData(data("cage2d.obj"));
  barylab::MeshParameters mp;
  mp.target_cells = 1500;
  auto mesh = barylab::MeshCage(cage, nullptr, mp);
  barylab::WeightsParameters p;
  p.method = bary::MethodId::LBC;
  auto weighted = barylab::ComputeWeights(mesh, cage, p, {}, nullptr, mesh);
  barylab::RenderOptions options;
  options.component = 14; // the left hand
  options.influence_level = true;
  options.title = "local barycentric coordinate of control point 14; blue: w = 1e-3/20";
  ExpectMatchesBaseline(barylab::WeightFieldWindow(weighted, cage, options), "lbc_weight_field_2d");
}

TEST(RenderImages, LBCWeightField3D)
{
  auto cage = vtkBaryDataIO::ReadPolyData(data("cage3d.obj"));
  barylab::WeightsParameters p;
  p.method = bary::MethodId::LBC;
  // a coarse mesh, with thresholds ten times tighter than the paper's: its per-entry thresholds
  // grow with the mesh size and stop 3D runs before the weights are local (68 of 72 weights
  // above 1e-3/72 per point at the default tolerances, 20 here)
  p.target_cells = 200;
  p.lbc_primal_tolerance = 1e-7;
  p.lbc_dual_tolerance = 1e-6;
  // the paper's rule, pinned since the default became the converged rule: the picture of a
  // weight field is what this test checks, and its baseline was made with the paper's rule
  p.lbc_stopping = bary::LBCStopping::Paper;
  auto weighted = barylab::ComputeWeights(vtkBaryDataIO::Read(data("model3d.off")), cage, p);
  barylab::RenderOptions options;
  options.component = 36;
  options.influence_level = true;
  options.title = "local barycentric coordinate of control point 36; blue: w = 1e-3/72";
  ExpectMatchesBaseline(barylab::WeightFieldWindow(weighted, cage, options), "lbc_weight_field_3d");
}

TEST(RenderImages, WeightedAveragesOnATorus)
{
  // Weighted averages on a surface: the bundled torus's embedding, the weights of every vertex
  // w.r.t. the 9 bundled anchors (drawn where the round trip returns), the centre anchor's
  // weight, and the closed B-spline of the bundled control points (the demo's picture).
  auto surface = barylab::ReadSurface(data("wa_torus.obj"));
  auto embedded = barylab::ComputeEmbedding(surface, bary::EmbeddingOptions{});
  auto anchors = barylab::ReadSurfacePoints(data("wa_anchors.txt"));
  auto weighted = barylab::SurfaceWeights(embedded, embedded, anchors, bary::InverseOptions{},
    bary::kDefaultSurfaceTolerance, bary::kDefaultRoundTripTolerance);
  auto curve = barylab::SurfaceCurve(embedded, barylab::ReadSurfacePoints(data("wa_curve_controls.txt")),
    24, true, bary::kDefaultSurfaceTolerance, 0);
  barylab::RenderOptions options;
  options.component = 4;
  ExpectMatchesBaseline(
    barylab::SurfaceWeightsWindow(vtkPolyData::SafeDownCast(weighted), anchors, curve, options),
    "surface_weights_torus");
}

TEST(RenderImages, OrganismSpline)
{
  // C1 spline deformations: the bundled organism fitted to its picture and edited (the demo's
  // picture): the curved deformed grid over the picture, the model coloured by height.
  const barylab::OrganismSpline e = barylab::OrganismSplineExample(BARYLAB_DATA_DIR);
  barylab::RenderOptions options;
  options.title = "fitted to the picture, then edited";
  ExpectMatchesBaseline(barylab::SplineDeformationWindow(e.rest_grid, e.grid, e.model, e.deformed,
                          e.picture, options),
    "organism_spline");
}

TEST(RenderImages, GingerbreadSplinePicture)
{
  // C1 spline deformations in 2D: the gingerbread man's picture warped by three DECLeS edits of
  // a spline over his cage polygon (the demo's picture).
  const barylab::GingerbreadSpline e = barylab::GingerbreadSplineExample(BARYLAB_DATA_DIR);
  barylab::RenderOptions options;
  options.title = "left hand raised, right hand and head turned";
  ExpectMatchesBaseline(
    barylab::SplinePictureWindow(e.rest_grid, e.grid, e.picture, e.bounds, options),
    "gingerbread_spline_picture");
}

TEST(RenderImages, OrganLabelSliceWarped)
{
  // The organ workflow's picture (the demo's organ_label_warped.png): a coronal slice of the
  // bundled label map and of the same map warped by a known field (a caudal shift of 12 mm
  // growing to 18 mm from the top of the organ down, and 3 mm forward: an affine breathing
  // motion), each with the cut of a surface: the organ's on the left, the organ moved by the
  // same map on the right, which must follow the warped label's edge.
  vtkSmartPointer<vtkImageData> labels = vtkBaryImageIO::Read(data("organ_label.nii.gz"));
  vtkNew<vtkBaryLabelMapSurface> segment;
  segment->SetInputData(labels);
  segment->SetLabel(1);
  segment->Update();
  vtkPolyData* organ = segment->GetOutput();
  ASSERT_GT(organ->GetNumberOfCells(), 1000);
  double b[6];
  organ->GetBounds(b);
  const double top = b[5], height = b[5] - b[4];
  // T(x) = x + u(x): u = (0, -3, -12 - 6 (top - z) / height) mm, affine in z
  auto move = [&](const double x[3], double y[3]) {
    y[0] = x[0];
    y[1] = x[1] - 3.0;
    y[2] = x[2] - 12.0 - 6.0 * (top - x[2]) / height;
  };
  // the inverse map's field on the label map's grid (T is affine: solved exactly)
  const bary::ImageGrid grid = vtkBaryDisplacementField::ToGrid(labels);
  bary::DisplacementField inverse;
  inverse.grid = grid;
  const bary::Points p = bary::grid_points(grid);
  inverse.values.resize(3, p.rows());
  const double s = 1.0 + 6.0 / height; // dz'/dz
  for (Eigen::Index v = 0; v < p.rows(); ++v)
  {
    const double z = (p(v, 2) + 12.0 + 6.0 * top / height) / s;
    inverse.values(0, v) = 0.0;
    inverse.values(1, v) = 3.0;
    inverse.values(2, v) = z - p(v, 2);
  }
  vtkNew<vtkBaryImageWarp> warp;
  warp->SetInputData(labels);
  warp->SetFieldData(vtkBaryDisplacementField::FromField(inverse));
  warp->SetInterpolationToNearest();
  warp->Update();
  vtkNew<vtkPolyData> moved;
  moved->DeepCopy(organ);
  for (vtkIdType i = 0; i < moved->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    organ->GetPoint(i, x);
    move(x, y);
    moved->GetPoints()->SetPoint(i, y);
  }
  const double center[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  barylab::RenderOptions options;
  options.width = 1200;
  options.height = 600;
  ExpectMatchesBaseline(
    barylab::LabelSliceWindow(labels, warp->GetOutput(), organ, moved, center, options),
    "organ_label_slice_warped");
}
