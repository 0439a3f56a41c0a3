#include "core/deformation/skeleton.h"

#include "core/common/error.h"

#include <cmath>
#include <string>

namespace bary
{

namespace
{
std::string bone_name(Index b, const Eigen::MatrixXi& BE)
{
  return "bone " + std::to_string(b) + " (joints " + std::to_string(BE(b, 0)) + ", " +
    std::to_string(BE(b, 1)) + ")";
}
} // namespace

void validate_skeleton(const Skeleton& s)
{
  const Index nc = s.C.rows();
  if (s.C.cols() != 2 && s.C.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "skeleton joints must be 2D or 3D, got " + std::to_string(s.C.cols()) + " columns");
  if (s.BE.rows() > 0 && s.BE.cols() != 2)
    throw Error(ErrorCode::SizeMismatch,
      "bones must be #B by 2 (pairs of joint indices), got " + std::to_string(s.BE.rows()) +
        " by " + std::to_string(s.BE.cols()));
  if (s.handle_count() == 0)
    throw Error(ErrorCode::EmptyInput,
      "the skeleton has no handle: give point handles (joints on no bone) or bones");
  for (Index c = 0; c < nc; ++c)
    if (!s.C.row(c).allFinite())
      throw Error(ErrorCode::NonFinite, "joint " + std::to_string(c) + " has NaN or infinite coordinates");
  std::vector<char> is_point(static_cast<std::size_t>(nc), 0);
  for (Index p = 0; p < s.P.size(); ++p)
  {
    const int c = s.P(p);
    if (c < 0 || c >= nc)
      throw Error(ErrorCode::InvalidArgument,
        "point handle " + std::to_string(p) + " refers to joint " + std::to_string(c) +
          ", outside [0, " + std::to_string(nc) + ")");
    if (is_point[static_cast<std::size_t>(c)])
      throw Error(ErrorCode::InvalidArgument,
        "joint " + std::to_string(c) + " is listed twice as a point handle");
    is_point[static_cast<std::size_t>(c)] = 1;
  }
  for (Index b = 0; b < s.BE.rows(); ++b)
  {
    const int a = s.BE(b, 0), c = s.BE(b, 1);
    if (a < 0 || a >= nc || c < 0 || c >= nc)
      throw Error(ErrorCode::InvalidArgument,
        bone_name(b, s.BE) + " refers to a joint outside [0, " + std::to_string(nc) + ")");
    if (a == c || !((s.C.row(a) - s.C.row(c)).norm() > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        bone_name(b, s.BE) + " has zero length: a bone needs two distinct joints");
  }
}

Eigen::MatrixXd skeleton_samples(const Skeleton& s, double spacing)
{
  validate_skeleton(s);
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw Error(ErrorCode::InvalidArgument, "the bone sampling spacing must be > 0");
  const Index nc = s.C.rows(), dim = s.C.cols();
  std::vector<char> used(static_cast<std::size_t>(nc), 0);
  for (Index p = 0; p < s.P.size(); ++p)
    used[static_cast<std::size_t>(s.P(p))] = 1;
  double count = 0;
  for (Index b = 0; b < s.BE.rows(); ++b)
  {
    used[static_cast<std::size_t>(s.BE(b, 0))] = used[static_cast<std::size_t>(s.BE(b, 1))] = 1;
    count += std::ceil((s.C.row(s.BE(b, 1)) - s.C.row(s.BE(b, 0))).norm() / spacing);
  }
  if (count > 1e7)
    throw Error(ErrorCode::InvalidArgument,
      "a bone sampling spacing of " + std::to_string(spacing) + " asks for more than 1e7 samples");
  std::vector<Eigen::RowVectorXd> rows;
  for (Index c = 0; c < nc; ++c)
    if (used[static_cast<std::size_t>(c)])
      rows.push_back(s.C.row(c));
  for (Index b = 0; b < s.BE.rows(); ++b)
  {
    const Eigen::RowVectorXd a = s.C.row(s.BE(b, 0)), h = s.C.row(s.BE(b, 1));
    const auto pieces = static_cast<int>(std::ceil((h - a).norm() / spacing));
    for (int k = 1; k < pieces; ++k)
    {
      const double t = static_cast<double>(k) / pieces;
      rows.push_back((1.0 - t) * a + t * h);
    }
  }
  Eigen::MatrixXd S(static_cast<Index>(rows.size()), dim);
  for (std::size_t r = 0; r < rows.size(); ++r)
    S.row(static_cast<Index>(r)) = rows[r];
  return S;
}

Eigen::VectorXi bone_parents(const Eigen::MatrixXi& BE)
{
  if (BE.rows() > 0 && BE.cols() != 2)
    throw Error(ErrorCode::SizeMismatch,
      "bones must be #B by 2 (pairs of joint indices), got " + std::to_string(BE.rows()) +
        " by " + std::to_string(BE.cols()));
  const Index nb = BE.rows();
  Eigen::VectorXi parent = Eigen::VectorXi::Constant(nb, -1);
  for (Index b = 0; b < nb; ++b)
    for (Index p = 0; p < nb; ++p)
      if (p != b && BE(p, 1) == BE(b, 0))
      {
        parent(b) = static_cast<int>(p);
        break;
      }
  // A chain of parents longer than #B is a cycle.
  for (Index b = 0; b < nb; ++b)
  {
    Index steps = 0;
    for (int p = parent(b); p >= 0; p = parent(p))
      if (++steps > nb)
        throw Error(ErrorCode::InvalidArgument,
          bone_name(b, BE) + " is on a cycle of bones (each one's tail is another's head): a "
          "skeleton for forward kinematics must be a forest");
  }
  return parent;
}

AffineTransforms forward_kinematics(
  const Skeleton& s, const std::vector<Eigen::Quaterniond>& rotations)
{
  validate_skeleton(s);
  if (s.dimension() != 3)
    throw Error(ErrorCode::SizeMismatch, "forward kinematics with quaternions needs a 3D skeleton");
  const Index nb = s.BE.rows();
  if (static_cast<Index>(rotations.size()) != nb)
    throw Error(ErrorCode::SizeMismatch,
      "the pose has " + std::to_string(rotations.size()) + " rotations but the skeleton has " +
        std::to_string(nb) + " bones (one rotation per bone, in bone order)");
  std::vector<Eigen::Quaterniond> relative(rotations.size());
  for (Index b = 0; b < nb; ++b)
  {
    const Eigen::Quaterniond& q = rotations[static_cast<std::size_t>(b)];
    if (!q.coeffs().allFinite())
      throw Error(ErrorCode::NonFinite, "the rotation of bone " + std::to_string(b) + " is not finite");
    if (!(q.norm() > 1e-12))
      throw Error(ErrorCode::InvalidArgument,
        "the rotation of bone " + std::to_string(b) + " is the zero quaternion");
    relative[static_cast<std::size_t>(b)] = q.normalized();
  }
  const Eigen::VectorXi parent = bone_parents(s.BE);
  std::vector<Eigen::Quaterniond> absolute(static_cast<std::size_t>(nb));
  std::vector<Eigen::Vector3d> translation(static_cast<std::size_t>(nb));
  std::vector<char> done(static_cast<std::size_t>(nb), 0);
  for (Index start = 0; start < nb; ++start)
  {
    // Walk up to the first solved ancestor (or a root), then solve back down.
    std::vector<Index> chain;
    for (Index b = start; b >= 0 && !done[static_cast<std::size_t>(b)]; b = parent(b))
      chain.push_back(b);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
    {
      const auto b = static_cast<std::size_t>(*it);
      const Eigen::Vector3d tail = s.C.row(s.BE(*it, 0)).transpose();
      const int p = parent(*it);
      if (p < 0)
      {
        absolute[b] = relative[b];
        translation[b] = tail - absolute[b] * tail;
      }
      else
      {
        const auto pp = static_cast<std::size_t>(p);
        absolute[b] = absolute[pp] * relative[b];
        // the parent's transform carries the tail; rotate about it from there
        translation[b] = translation[pp] + absolute[pp] * tail - absolute[b] * tail;
      }
      done[b] = 1;
    }
  }
  AffineTransforms transforms(static_cast<std::size_t>(nb));
  for (std::size_t b = 0; b < transforms.size(); ++b)
  {
    Eigen::MatrixXd T(3, 4);
    T.leftCols(3) = absolute[b].toRotationMatrix();
    T.col(3) = translation[b];
    transforms[b] = T;
  }
  return transforms;
}

AffineTransforms transforms_from_joints(
  const Skeleton& s, const Eigen::MatrixXd& posed_C, const Eigen::MatrixXi& pseudo_edges)
{
  validate_skeleton(s);
  if (posed_C.rows() != s.C.rows() || posed_C.cols() != s.C.cols())
    throw Error(ErrorCode::SizeMismatch,
      "the posed joints are " + std::to_string(posed_C.rows()) + " by " +
        std::to_string(posed_C.cols()) + " but the rest joints are " + std::to_string(s.C.rows()) +
        " by " + std::to_string(s.C.cols()));
  if (!posed_C.allFinite())
    throw Error(ErrorCode::NonFinite, "the posed joints contain NaN or infinity");
  const Index dim = s.C.cols(), np = s.P.size(), nb = s.BE.rows();
  AffineTransforms transforms;
  transforms.reserve(static_cast<std::size_t>(np + nb));
  if (np > 0)
  {
    Points rest(np, dim), posed(np, dim);
    for (Index p = 0; p < np; ++p)
    {
      rest.row(p) = s.C.row(s.P(p));
      posed.row(p) = posed_C.row(s.P(p));
    }
    for (auto& T : transforms_from_pseudo_edges(rest, posed, pseudo_edges))
      transforms.push_back(std::move(T));
  }
  else if (pseudo_edges.rows() > 0)
    throw Error(ErrorCode::InvalidArgument,
      "pseudo-edges connect point handles, but the skeleton has none");
  for (Index b = 0; b < nb; ++b)
  {
    const Eigen::VectorXd r = (s.C.row(s.BE(b, 1)) - s.C.row(s.BE(b, 0))).transpose();
    const Eigen::VectorXd q = (posed_C.row(s.BE(b, 1)) - posed_C.row(s.BE(b, 0))).transpose();
    if (!(q.norm() > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        bone_name(b, s.BE) + " has zero length when posed, so its rotation is undefined");
    Eigen::MatrixXd R(dim, dim);
    if (dim == 2)
    {
      const double theta = std::atan2(r(0) * q(1) - r(1) * q(0), r.dot(q));
      R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
    }
    else
      R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(r), Eigen::Vector3d(q))
            .toRotationMatrix();
    Eigen::MatrixXd T(dim, dim + 1);
    T.leftCols(dim) = R;
    T.col(dim) = posed_C.row(s.BE(b, 0)).transpose() - R * s.C.row(s.BE(b, 0)).transpose();
    transforms.push_back(std::move(T));
  }
  return transforms;
}

double bone_sample_spacing(int dim, double cell_measure)
{
  if (dim != 2 && dim != 3)
    throw Error(ErrorCode::InvalidArgument,
      "bone samples are spaced in 2D or 3D, not " + std::to_string(dim) + "D");
  return dim == 2 ? std::sqrt(4.0 * cell_measure / std::sqrt(3.0))
                  : std::cbrt(6.0 * std::sqrt(2.0) * cell_measure);
}

} // namespace bary
