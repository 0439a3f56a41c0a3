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

TEST(Skeleton, MixedHandlesCountSampleAndPose)
{
  // A 3D mix: a point handle (joint 0), a bone (1-2), an open cage of two triangles (3-6) and a
  // tetrahedral region (7-10). Columns: point, bone, cage joints 3, 4, 5, 6, region.
  Skeleton s;
  s.C.resize(11, 3);
  s.C << -1, -1, -1, 0, 0, 2, 0, 0, 3, //
    1, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, //
    0, 0, 0, 0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5;
  s.P.resize(1);
  s.P << 0;
  s.BE.resize(1, 2);
  s.BE << 1, 2;
  s.CF.resize(2, 3);
  s.CF << 3, 4, 5, 3, 5, 6;
  s.regions.push_back((Eigen::MatrixXi(4, 3) << 7, 9, 8, 7, 8, 10, 7, 10, 9, 8, 9, 10).finished());
  validate_skeleton(s);
  EXPECT_EQ(s.cage_joints(), (Eigen::VectorXi(4) << 3, 4, 5, 6).finished());
  ASSERT_EQ(s.handle_count(), 7);

  // Samples: every joint once, then points on the bone, the cage triangles and the region's
  // faces; each sample lies on one of them, and the cage's sampling is no coarser than asked.
  const double spacing = 0.25;
  const Eigen::MatrixXd S = skeleton_samples(s, spacing);
  auto on_triangle = [](const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (std::abs((p - a).dot(n)) > 1e-12 * n.norm())
      return false;
    const double area = n.norm();
    const double sum = (b - p).cross(c - p).norm() + (c - p).cross(a - p).norm() +
      (a - p).cross(b - p).norm();
    return std::abs(sum - area) <= 1e-12 * area;
  };
  int on_cage = 0;
  for (Eigen::Index i = 0; i < S.rows(); ++i)
  {
    const Eigen::Vector3d p = S.row(i);
    bool on = false;
    const Eigen::Vector3d a = s.C.row(1), b = s.C.row(2);
    on = on || ((p - a).cross(b - a).norm() <= 1e-12 && (p - a).dot(p - b) <= 1e-12);
    bool cage = false;
    for (Eigen::Index f = 0; f < 2; ++f)
      cage = cage || on_triangle(p, s.C.row(s.CF(f, 0)), s.C.row(s.CF(f, 1)), s.C.row(s.CF(f, 2)));
    on_cage += cage;
    for (Eigen::Index f = 0; f < 4; ++f)
      on = on || on_triangle(p, s.C.row(s.regions[0](f, 0)), s.C.row(s.regions[0](f, 1)),
                   s.C.row(s.regions[0](f, 2)));
    EXPECT_TRUE(on || cage || (p - Eigen::Vector3d(s.C.row(0))).norm() == 0) << "sample " << i;
  }
  // The cage (two triangles of area 1/2, longest edge sqrt 2 -> 6 pieces) holds at least the
  // grid of each triangle: 28 points each, sharing an edge's 7.
  EXPECT_GE(on_cage, 28 + 28 - 7);

  // Pose: a rigid motion of everything; the cage vertices get translations by their
  // displacements, the region the rigid motion itself (Kabsch, exact for a rigid motion).
  std::mt19937 rng(11);
  const Eigen::Matrix3d R = random_rotation(rng).toRotationMatrix();
  const Eigen::Vector3d t(0.5, 1.0, -2.0);
  const Eigen::MatrixXd posed = (s.C * R.transpose()).rowwise() + t.transpose();
  const AffineTransforms T = transforms_from_joints(s, posed);
  ASSERT_EQ(T.size(), 7u);
  for (int k = 0; k < 4; ++k)
  {
    const int c = 3 + k;
    EXPECT_LT((T[2 + k].leftCols(3) - Eigen::Matrix3d::Identity()).norm(), 1e-15);
    EXPECT_LT((T[2 + k].col(3) - (posed.row(c) - s.C.row(c)).transpose()).norm(), 1e-14);
  }
  EXPECT_LT((T[6].leftCols(3) - R).norm(), 1e-12);
  EXPECT_LT((T[6].col(3) - t).norm(), 1e-12);
  // 2D region: a rotation by 0.4 and a translation are recovered.
  Skeleton r2;
  r2.C.resize(3, 2);
  r2.C << 0, 0, 1, 0, 0, 2;
  r2.regions.push_back((Eigen::MatrixXi(3, 2) << 0, 1, 1, 2, 2, 0).finished());
  Eigen::Matrix2d R2;
  R2 << std::cos(0.4), -std::sin(0.4), std::sin(0.4), std::cos(0.4);
  const Eigen::MatrixXd posed2 = (r2.C * R2.transpose()).rowwise() + Eigen::RowVector2d(3, 1);
  const AffineTransforms T2 = transforms_from_joints(r2, posed2);
  ASSERT_EQ(T2.size(), 1u);
  EXPECT_LT((T2[0].leftCols(2) - R2).norm(), 1e-14);
  EXPECT_LT((T2[0].col(2) - Eigen::Vector2d(3, 1)).norm(), 1e-14);

  // Validation: a region of edges in 3D, a cage vertex that is a bone joint, a region corner
  // out of range.
  Skeleton bad = s;
  bad.regions[0] = (Eigen::MatrixXi(1, 2) << 7, 8).finished();
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::SizeMismatch, { "region 0" }));
  bad = s;
  bad.CF(0, 0) = 1;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::InvalidArgument,
    { "joint 1", "bone's joint", "cage vertex" }));
  bad = s;
  bad.regions[0](0, 0) = 11;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(bad); }, ErrorCode::InvalidArgument,
    { "region 0 face 0", "joint 11" }));
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
