// Tests of vtkBaryLinearBlendSkinning (Eq. 1 of Jacobson et al. 2011) against a direct
// evaluation in the test, its error paths, and of vtkBaryDataIO::ReadPose (BaryLab pose text,
// libigl .dmat quaternions through forward kinematics, libigl stacked transforms).
#include "filters_test_utils.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryLinearBlendSkinning.h"

#include "core/common/error.h"
#include "core/deformation/skeleton.h"

#include "vtkDoubleArray.h"
#include "vtkPointData.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>

namespace
{
using namespace barylab_test;

/// Random points with random convex weights over @p m handles in array "Weights".
vtkSmartPointer<vtkPolyData> WeightedPoints(int n, int m, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.0, 1.0);
  std::vector<std::array<double, 3>> xs;
  for (int i = 0; i < n; ++i)
    xs.push_back({ u(rng), u(rng), u(rng) });
  auto cloud = MakePointCloud(xs);
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("Weights");
  weights->SetNumberOfComponents(m);
  weights->SetNumberOfTuples(n);
  for (int i = 0; i < n; ++i)
  {
    std::vector<double> row(static_cast<std::size_t>(m));
    double sum = 0;
    for (auto& v : row)
      sum += (v = w(rng));
    for (int j = 0; j < m; ++j)
      weights->SetComponent(i, j, row[static_cast<std::size_t>(j)] / sum);
  }
  cloud->GetPointData()->AddArray(weights);
  return cloud;
}

vtkSmartPointer<vtkDoubleArray> TransformsArray(const std::vector<Eigen::Matrix<double, 3, 4>>& Ts)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetNumberOfComponents(12);
  a->SetNumberOfTuples(static_cast<vtkIdType>(Ts.size()));
  for (std::size_t j = 0; j < Ts.size(); ++j)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        a->SetComponent(static_cast<vtkIdType>(j), 4 * r + c, Ts[j](r, c));
  return a;
}

std::string TempFile(const std::string& name, const std::string& text)
{
  const std::string path = std::string(BARYLAB_TEST_OUTPUT_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(vtkBaryLinearBlendSkinning, MatchesADirectEvaluationOfEquation1)
{
  const int n = 50, m = 4;
  auto cloud = WeightedPoints(n, m, 3);
  std::mt19937 rng(9);
  std::normal_distribution<double> g;
  std::vector<Eigen::Matrix<double, 3, 4>> Ts(m);
  for (auto& T : Ts)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        T(r, c) = g(rng);
  vtkNew<vtkBaryLinearBlendSkinning> skin;
  vtkNew<ErrorObserver> errors;
  errors->Attach(skin);
  skin->SetInputData(cloud);
  skin->SetTransforms(TransformsArray(Ts));
  ASSERT_EQ(RunPipeline(skin), 1) << errors->AllErrors();
  vtkPointSet* out = skin->GetOutput();
  ASSERT_EQ(out->GetNumberOfPoints(), n);
  vtkDataArray* W = GetWeights(out);
  ASSERT_NE(W, nullptr) << "the weights are passed through";
  double worst = 0;
  for (vtkIdType p = 0; p < n; ++p)
  {
    Eigen::Vector3d x, y;
    cloud->GetPoint(p, x.data());
    out->GetPoint(p, y.data());
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    for (int j = 0; j < m; ++j)
      expected += W->GetComponent(p, j) * (Ts[j].leftCols(3) * x + Ts[j].col(3));
    worst = std::max(worst, (expected - y).norm());
  }
  EXPECT_LE(worst, 1e-13);
}

TEST(vtkBaryLinearBlendSkinning, OneRigidMotionOnEveryHandleMovesEveryPointRigidly)
{
  auto cloud = WeightedPoints(40, 5, 4);
  Eigen::Matrix<double, 3, 4> T;
  T.leftCols(3) = Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.col(3) = Eigen::Vector3d(0.5, -2, 1);
  vtkNew<vtkBaryLinearBlendSkinning> skin;
  skin->SetInputData(cloud);
  skin->SetTransforms(TransformsArray(std::vector<Eigen::Matrix<double, 3, 4>>(5, T)));
  ASSERT_EQ(RunPipeline(skin), 1);
  for (vtkIdType p = 0; p < 40; ++p)
  {
    Eigen::Vector3d x, y;
    cloud->GetPoint(p, x.data());
    skin->GetOutput()->GetPoint(p, y.data());
    EXPECT_LE((T.leftCols(3) * x + T.col(3) - y).norm(), 1e-14);
  }
  // editing the transforms array in place re-executes (MTime includes it)
  vtkDoubleArray* a = skin->GetTransforms();
  for (vtkIdType j = 0; j < 5; ++j)
    for (int c = 0; c < 12; ++c)
      a->SetComponent(j, c, c % 5 == 0 ? 1.0 : 0.0); // identity
  a->Modified();
  ASSERT_EQ(RunPipeline(skin), 1);
  double x[3], y[3];
  cloud->GetPoint(7, x);
  skin->GetOutput()->GetPoint(7, y);
  EXPECT_NEAR(x[0], y[0], 1e-15);
  EXPECT_NEAR(x[2], y[2], 1e-15);
}

TEST(vtkBaryLinearBlendSkinning, Errors)
{
  auto cloud = WeightedPoints(5, 3, 5);
  vtkNew<vtkBaryLinearBlendSkinning> skin;
  vtkNew<ErrorObserver> errors;
  errors->Attach(skin);
  skin->SetInputData(cloud);
  EXPECT_EQ(RunPipeline(skin), 0);
  EXPECT_TRUE(errors->HasError("no handle transforms")) << errors->AllErrors();

  errors->Clear();
  Eigen::Matrix<double, 3, 4> I = Eigen::Matrix<double, 3, 4>::Zero();
  I.leftCols(3).setIdentity();
  skin->SetTransforms(TransformsArray(std::vector<Eigen::Matrix<double, 3, 4>>(2, I)));
  EXPECT_EQ(RunPipeline(skin), 0);
  EXPECT_TRUE(errors->HasError("3 components (handles) but 2 transforms")) << errors->AllErrors();

  errors->Clear();
  vtkNew<vtkDoubleArray> nine;
  nine->SetNumberOfComponents(9);
  nine->SetNumberOfTuples(3);
  skin->SetTransforms(nine);
  EXPECT_EQ(RunPipeline(skin), 0);
  EXPECT_TRUE(errors->HasError("needs 12")) << errors->AllErrors();

  errors->Clear();
  skin->SetTransforms(TransformsArray(std::vector<Eigen::Matrix<double, 3, 4>>(3, I)));
  skin->SetWeightsArrayName("Nope");
  EXPECT_EQ(RunPipeline(skin), 0);
  EXPECT_TRUE(errors->HasError("no point-data array 'Nope'")) << errors->AllErrors();

  errors->Clear();
  skin->SetWeightsArrayName("Weights");
  GetWeights(cloud)->SetComponent(2, 1, std::nan(""));
  cloud->Modified();
  EXPECT_EQ(RunPipeline(skin), 0);
  EXPECT_TRUE(errors->HasError("point 2 has NaN weights")) << errors->AllErrors();
}

TEST(vtkBaryDataIOPose, TextPoseLinesIn3DAnd2DWithComments)
{
  const std::string path = TempFile("pose_text.txt",
    "# handle transforms\n"
    "1 0 0 0.5  0 1 0 0  0 0 1 -1   # a translation as a full matrix\n"
    "\n"
    "0 -1 2  1 0 3\n"   // 2D rotation by 90 degrees + (2, 3)
    "4 5 6\n"            // 3D translation
    "7 8\n");            // 2D translation
  const auto pose = vtkBaryDataIO::ReadPose(path, 4);
  ASSERT_EQ(pose.size(), 4u);
  Eigen::Matrix<double, 3, 4> e0, e1, e2, e3;
  e0 << 1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, -1;
  e1 << 0, -1, 0, 2, 1, 0, 0, 3, 0, 0, 1, 0;
  e2 << 1, 0, 0, 4, 0, 1, 0, 5, 0, 0, 1, 6;
  e3 << 1, 0, 0, 7, 0, 1, 0, 8, 0, 0, 1, 0;
  EXPECT_EQ(pose[0], e0);
  EXPECT_EQ(pose[1], e1);
  EXPECT_EQ(pose[2], e2);
  EXPECT_EQ(pose[3], e3);

  try
  {
    vtkBaryDataIO::ReadPose(path, 3);
    ADD_FAILURE() << "a pose with 4 transforms for 3 handles must fail";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::SizeMismatch);
    EXPECT_NE(std::string(e.what()).find("4 transforms"), std::string::npos) << e.what();
  }
  const std::string bad = TempFile("pose_bad.txt", "1 0 0 0\n1 2 x\n");
  try
  {
    vtkBaryDataIO::ReadPose(bad, 2);
    ADD_FAILURE() << "a bad pose must fail";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find("line 1: 4 numbers"), std::string::npos) << e.what();
  }
  EXPECT_THROW(vtkBaryDataIO::ReadPose(TempFile("pose_bad2.txt", "1 2 x\n"), 1), bary::Error);
  EXPECT_THROW(vtkBaryDataIO::ReadPose("/nonexistent/pose.txt", 1), bary::Error);
}

TEST(vtkBaryDataIOPose, DmatQuaternionsAreForwardKinematicsAndStackedTransformsAreTransposed)
{
  bary::Skeleton s;
  s.C.resize(3, 3);
  s.C << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  s.BE.resize(2, 2);
  s.BE << 0, 1, 1, 2;
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY()));
  Eigen::MatrixXd column(8, 1);
  column << q0.x(), q0.y(), q0.z(), q0.w(), q1.x(), q1.y(), q1.z(), q1.w();
  const std::string qpath = std::string(BARYLAB_TEST_OUTPUT_DIR) + "/pose_quats.dmat";
  vtkBaryDataIO::WriteDMAT(column, qpath);
  const auto pose = vtkBaryDataIO::ReadPose(qpath, 2, &s);
  const auto expected = bary::forward_kinematics(s, { q0, q1 });
  ASSERT_EQ(pose.size(), 2u);
  for (std::size_t b = 0; b < 2; ++b)
    EXPECT_LE((pose[b] - expected[b]).norm(), 1e-15);
  // the child's tail follows the parent: joint 1 moves with bone 0
  const Eigen::Vector3d j1(1, 0, 0);
  EXPECT_LE(((pose[1].leftCols(3) * j1 + pose[1].col(3)) - (pose[0].leftCols(3) * j1 + pose[0].col(3))).norm(), 1e-15);
  // rows of 4 work too
  Eigen::MatrixXd rows(2, 4);
  rows << q0.x(), q0.y(), q0.z(), q0.w(), q1.x(), q1.y(), q1.z(), q1.w();
  vtkBaryDataIO::WriteDMAT(rows, qpath);
  EXPECT_LE((vtkBaryDataIO::ReadPose(qpath, 2, &s)[1] - expected[1]).norm(), 1e-15);
  // quaternions without a skeleton, or for the wrong number of bones
  EXPECT_THROW(vtkBaryDataIO::ReadPose(qpath, 2, nullptr), bary::Error);
  bary::Skeleton one = s;
  one.BE.conservativeResize(1, 2);
  EXPECT_THROW(vtkBaryDataIO::ReadPose(qpath, 1, &one), bary::Error);

  // libigl stacked transforms: handle j's [A | t]^T in rows 4j .. 4j+3
  Eigen::Matrix<double, 3, 4> T0, T1;
  T0 << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  T1 = -T0;
  Eigen::MatrixXd stacked(8, 3);
  stacked << T0.transpose(), T1.transpose();
  const std::string tpath = std::string(BARYLAB_TEST_OUTPUT_DIR) + "/pose_stacked.dmat";
  vtkBaryDataIO::WriteDMAT(stacked, tpath);
  const auto st = vtkBaryDataIO::ReadPose(tpath, 2);
  EXPECT_EQ(st[0], Eigen::MatrixXd(T0));
  EXPECT_EQ(st[1], Eigen::MatrixXd(T1));
  EXPECT_THROW(vtkBaryDataIO::ReadPose(tpath, 3), bary::Error);
}

} // namespace
