// Tests for core/deformation/skeleton.h: validation, bone samples for meshing, bone parents, forward
// kinematics (checked against joint continuity and an independent composition of rotations) and
// transforms from moved joints.
#include "core/common/error.h"
#include "core/deformation/skeleton.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
using namespace bary;
using bary::test::throws_error;

/// A 3D chain 0-1-2-3 (bones 0: 0->1, 1: 1->2, 2: 2->3), a branch 1->4, and a point handle 5.
Skeleton chain3d()
{
  Skeleton s;
  s.C.resize(6, 3);
  s.C << 0, 0, 0, 1, 0, 0, 2, 0.5, 0, 3, 0.5, 0.5, 1, 1, 0, -1, -1, -1;
  s.P.resize(1);
  s.P << 5;
  s.BE.resize(4, 2);
  s.BE << 0, 1, 1, 2, 2, 3, 1, 4;
  return s;
}

Eigen::Vector3d apply(const Eigen::MatrixXd& T, const Eigen::Vector3d& x)
{
  return T.leftCols(3) * x + T.col(3);
}

Eigen::Quaterniond random_rotation(std::mt19937& rng)
{
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized();
}

TEST(Skeleton, HandleCountAndValidation)
{
  const Skeleton s = chain3d();
  EXPECT_EQ(s.handle_count(), 5);
  EXPECT_NO_THROW(validate_skeleton(s));

  Skeleton bad = s;
  bad.BE(2, 1) = 9;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::InvalidArgument,
    { "bone 2", "outside [0, 6)" }));
  bad = s;
  bad.BE(1, 1) = 1;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::InvalidArgument,
    { "bone 1", "zero length" }));
  bad = s;
  bad.C(3, 2) = std::nan("");
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::NonFinite, { "joint 3" }));
  bad = s;
  bad.P.resize(2);
  bad.P << 5, 5;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::InvalidArgument,
    { "joint 5", "twice" }));
  Skeleton empty;
  empty.C = s.C;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(empty); }, ErrorCode::EmptyInput, { "no handle" }));
}

TEST(Skeleton, SamplesHoldEveryUsedJointOnceAndSplitBonesBelowTheSpacing)
{
  const Skeleton s = chain3d();
  const double spacing = 0.3;
  const Eigen::MatrixXd S = skeleton_samples(s, spacing);
  // every joint (all 6 are used) appears exactly once
  for (Index c = 0; c < s.C.rows(); ++c)
  {
    int hits = 0;
    for (Index r = 0; r < S.rows(); ++r)
      hits += (S.row(r) - s.C.row(c)).norm() < 1e-14;
    EXPECT_EQ(hits, 1) << "joint " << c;
  }
  // every sample but the point handle's joint lies on a bone; along each bone consecutive points
  // are <= spacing apart
  for (Index r = 0; r < S.rows(); ++r)
  {
    if ((S.row(r) - s.C.row(5)).norm() == 0.0)
      continue;
    double best = 1e300;
    for (Index b = 0; b < s.BE.rows(); ++b)
    {
      const Eigen::Vector3d a = s.C.row(s.BE(b, 0)), h = s.C.row(s.BE(b, 1)), x = S.row(r);
      const double t = std::clamp((x - a).dot(h - a) / (h - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (h - a) - x).norm());
    }
    EXPECT_LT(best, 1e-14) << "sample " << r;
  }
  for (Index b = 0; b < s.BE.rows(); ++b)
  {
    const Eigen::Vector3d a = s.C.row(s.BE(b, 0)), h = s.C.row(s.BE(b, 1));
    const int expected_interior = static_cast<int>(std::ceil((h - a).norm() / spacing)) - 1;
    int interior = 0;
    for (Index r = 0; r < S.rows(); ++r)
    {
      const Eigen::Vector3d x = S.row(r);
      const double t = (x - a).dot(h - a) / (h - a).squaredNorm();
      if (t > 1e-12 && t < 1 - 1e-12 && (a + t * (h - a) - x).norm() < 1e-14)
        ++interior;
    }
    EXPECT_EQ(interior, expected_interior) << "bone " << b;
    EXPECT_LE((h - a).norm() / (expected_interior + 1), spacing);
  }
  EXPECT_TRUE(throws_error([&] { skeleton_samples(s, 0.0); }, ErrorCode::InvalidArgument, { "spacing" }));
  EXPECT_TRUE(throws_error([&] { skeleton_samples(s, 1e-9); }, ErrorCode::InvalidArgument, { "1e7" }));
}

TEST(Skeleton, BoneParentsFollowTailToHead)
{
  const Skeleton s = chain3d();
  const Eigen::VectorXi parent = bone_parents(s.BE);
  ASSERT_EQ(parent.size(), 4);
  EXPECT_EQ(parent(0), -1);
  EXPECT_EQ(parent(1), 0);
  EXPECT_EQ(parent(2), 1);
  EXPECT_EQ(parent(3), 0);
  Eigen::MatrixXi cycle(3, 2);
  cycle << 0, 1, 1, 2, 2, 0;
  EXPECT_TRUE(throws_error([&] { bone_parents(cycle); }, ErrorCode::InvalidArgument, { "cycle" }));
}

TEST(Skeleton, ForwardKinematicsIdentityPoseIsIdentity)
{
  const Skeleton s = chain3d();
  const AffineTransforms T =
    forward_kinematics(s, std::vector<Eigen::Quaterniond>(4, Eigen::Quaterniond::Identity()));
  ASSERT_EQ(T.size(), 4u);
  Eigen::MatrixXd I = Eigen::MatrixXd::Zero(3, 4);
  I.leftCols(3).setIdentity();
  for (const auto& t : T)
    EXPECT_LT((t - I).norm(), 1e-15);
}

TEST(Skeleton, ForwardKinematicsKeepsJointsTogetherAndComposesRotations)
{
  const Skeleton s = chain3d();
  std::mt19937 rng(3);
  std::vector<Eigen::Quaterniond> pose;
  for (int b = 0; b < 4; ++b)
    pose.push_back(random_rotation(rng));
  const AffineTransforms T = forward_kinematics(s, pose);
  // roots rotate about their tail
  const Eigen::Vector3d root_tail = s.C.row(0);
  EXPECT_LT((apply(T[0], root_tail) - root_tail).norm(), 1e-14);
  // a child's tail is where its parent takes it (joints stay attached)
  const Eigen::VectorXi parent = bone_parents(s.BE);
  for (int b = 0; b < 4; ++b)
    if (parent(b) >= 0)
    {
      const Eigen::Vector3d tail = s.C.row(s.BE(b, 0));
      EXPECT_LT((apply(T[b], tail) - apply(T[parent(b)], tail)).norm(), 1e-14) << "bone " << b;
    }
  // absolute rotations are the products along the chain (independent composition)
  const Eigen::Matrix3d R2 = (pose[0] * pose[1] * pose[2]).toRotationMatrix();
  EXPECT_LT((T[2].leftCols(3) - R2).norm(), 1e-14);
  const Eigen::Matrix3d R3 = (pose[0] * pose[3]).toRotationMatrix();
  EXPECT_LT((T[3].leftCols(3) - R3).norm(), 1e-14);
  // bone lengths are kept (rigid per bone)
  for (int b = 0; b < 4; ++b)
  {
    const Eigen::Vector3d a = s.C.row(s.BE(b, 0)), h = s.C.row(s.BE(b, 1));
    EXPECT_NEAR((apply(T[b], h) - apply(T[b], a)).norm(), (h - a).norm(), 1e-14);
  }
  // quaternions need not be normalized
  std::vector<Eigen::Quaterniond> scaled = pose;
  for (auto& q : scaled)
    q.coeffs() *= 3.0;
  const AffineTransforms T2 = forward_kinematics(s, scaled);
  for (int b = 0; b < 4; ++b)
    EXPECT_LT((T2[b] - T[b]).norm(), 1e-14);

  EXPECT_TRUE(throws_error([&] { forward_kinematics(s, std::vector<Eigen::Quaterniond>(3)); },
    ErrorCode::SizeMismatch, { "3 rotations", "4 bones" }));
  std::vector<Eigen::Quaterniond> zero = pose;
  zero[1].coeffs().setZero();
  EXPECT_TRUE(throws_error([&] { forward_kinematics(s, zero); }, ErrorCode::InvalidArgument,
    { "bone 1", "zero quaternion" }));
}

TEST(Skeleton, TransformsFromJointsMoveBonesRigidlyOntoTheirPosedJoints)
{
  const Skeleton s = chain3d();
  std::mt19937 rng(5);
  // A rigid motion of the whole skeleton: every bone gets a rotation that maps its direction
  // correctly and its tail exactly; the point handle gets the translation.
  const Eigen::Matrix3d R = random_rotation(rng).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -0.2, 1.5);
  Eigen::MatrixXd posed = (s.C * R.transpose()).rowwise() + t.transpose();
  const AffineTransforms T = transforms_from_joints(s, posed);
  ASSERT_EQ(T.size(), 5u);
  const Eigen::Vector3d p = s.C.row(5), pp = posed.row(5);
  EXPECT_LT((apply(T[0], p) - pp).norm(), 1e-14); // point handle: no pseudo-edge, translation
  for (int b = 0; b < 4; ++b)
  {
    const Eigen::Vector3d a = s.C.row(s.BE(b, 0)), h = s.C.row(s.BE(b, 1));
    const Eigen::Vector3d pa = posed.row(s.BE(b, 0)), ph = posed.row(s.BE(b, 1));
    EXPECT_LT((apply(T[1 + b], a) - pa).norm(), 1e-13) << "bone " << b;
    EXPECT_LT((apply(T[1 + b], h) - ph).norm(), 1e-13) << "bone " << b;
    EXPECT_LT((T[1 + b].leftCols(3).transpose() * T[1 + b].leftCols(3) -
                Eigen::Matrix3d::Identity()).norm(), 1e-14);
  }
  // 2D: a rigid motion is recovered exactly
  Skeleton s2;
  s2.C.resize(3, 2);
  s2.C << 0, 0, 1, 0, 1, 1;
  s2.BE.resize(2, 2);
  s2.BE << 0, 1, 1, 2;
  const double theta = 0.7;
  Eigen::Matrix2d R2;
  R2 << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  const Eigen::MatrixXd posed2 = (s2.C * R2.transpose()).rowwise() + Eigen::RowVector2d(2, -1);
  for (const auto& T2 : transforms_from_joints(s2, posed2))
  {
    EXPECT_LT((T2.leftCols(2) - R2).norm(), 1e-14);
    EXPECT_LT((T2.col(2) - Eigen::Vector2d(2, -1)).norm(), 1e-14);
  }
  Eigen::MatrixXd collapsed = posed;
  collapsed.row(2) = collapsed.row(1);
  EXPECT_TRUE(throws_error([&] { transforms_from_joints(s, collapsed); },
    ErrorCode::InvalidArgument, { "bone 1", "zero length when posed" }));
  EXPECT_TRUE(throws_error([&] { transforms_from_joints(s, posed.topRows(4)); },
    ErrorCode::SizeMismatch, { "posed joints" }));
}

TEST(BoneSampleSpacing, TheEdgeOfARegularCellOfThatMeasure)
{
  // the unit equilateral triangle (area sqrt 3 / 4) and the unit regular tetrahedron
  // (volume 1 / (6 sqrt 2)) have edges of length 1
  EXPECT_NEAR(bone_sample_spacing(2, std::sqrt(3.0) / 4.0), 1.0, 1e-15);
  EXPECT_NEAR(bone_sample_spacing(3, 1.0 / (6.0 * std::sqrt(2.0))), 1.0, 1e-15);
  // exactly the formulas the filter used (evaluated at run time, as there: a constant folded
  // by the compiler may round differently from libm)
  volatile double measure = 0.01;
  const double cell = measure;
  EXPECT_EQ(bone_sample_spacing(2, cell), std::sqrt(4.0 * cell / std::sqrt(3.0)));
  EXPECT_EQ(bone_sample_spacing(3, cell), std::cbrt(6.0 * std::sqrt(2.0) * cell));
  // scaling: length ~ area^(1/2), volume^(1/3)
  EXPECT_NEAR(bone_sample_spacing(2, 4.0) / bone_sample_spacing(2, 1.0), 2.0, 1e-15);
  EXPECT_NEAR(bone_sample_spacing(3, 8.0) / bone_sample_spacing(3, 1.0), 2.0, 1e-15);
  EXPECT_TRUE(throws_error([] { bone_sample_spacing(4, 1.0); }, ErrorCode::InvalidArgument, { "4D" }));
}

} // namespace
