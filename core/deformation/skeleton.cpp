#include "core/deformation/skeleton.h"

#include "core/common/error.h"

#include <Eigen/SVD>

#include <algorithm>
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

/// Checks the faces @p F (segments or triangles) over @p nc joints of @p C: indices in range,
/// no degenerate face. @p what names a face ("cage face", "region 2 face").
void check_faces(const Eigen::MatrixXi& F, const Eigen::MatrixXd& C, const std::string& what)
{
  const Index nc = C.rows();
  for (Index f = 0; f < F.rows(); ++f)
  {
    const std::string name = what + " " + std::to_string(f);
    for (Index k = 0; k < F.cols(); ++k)
      if (F(f, k) < 0 || F(f, k) >= nc)
        throw Error(ErrorCode::InvalidArgument,
          name + " refers to joint " + std::to_string(F(f, k)) + ", outside [0, " +
            std::to_string(nc) + ")");
    const Eigen::VectorXd a = C.row(F(f, 0)).transpose(), b = C.row(F(f, 1)).transpose();
    double measure = (b - a).norm();
    if (F.cols() == 3)
    {
      const Eigen::Vector3d u = (b - a).head<3>(),
                            v = (C.row(F(f, 2)).transpose() - a).head<3>();
      measure = u.cross(v).norm();
    }
    if (!(measure > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        name + " is degenerate (zero " + (F.cols() == 3 ? "area" : "length") + ")");
  }
}

void check_face_columns(const Eigen::MatrixXi& F, Index dim, bool triangles_only_3d,
  const std::string& what)
{
  if (F.rows() == 0)
    return;
  const bool ok = triangles_only_3d ? F.cols() == dim
                                    : (F.cols() == 2 || (F.cols() == 3 && dim == 3));
  if (!ok)
    throw Error(ErrorCode::SizeMismatch,
      what + " must be #F by " +
        (triangles_only_3d ? std::to_string(dim) + (dim == 2 ? " (edges)" : " (triangles)")
                           : std::string(dim == 3 ? "2 (segments) or 3 (triangles)" : "2 (segments)")) +
        ", got " + std::to_string(F.rows()) + " by " + std::to_string(F.cols()));
}
} // namespace

Eigen::VectorXi Skeleton::cage_joints() const
{
  std::vector<int> joints(CF.data(), CF.data() + CF.size());
  std::sort(joints.begin(), joints.end());
  joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
  return Eigen::Map<const Eigen::VectorXi>(joints.data(), static_cast<Index>(joints.size()));
}

Index Skeleton::handle_count() const
{
  return P.size() + BE.rows() + cage_joints().size() + static_cast<Index>(regions.size());
}

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
  check_face_columns(s.CF, s.C.cols(), false, "cage faces");
  for (std::size_t r = 0; r < s.regions.size(); ++r)
  {
    if (s.regions[r].rows() == 0)
      throw Error(ErrorCode::EmptyInput, "region " + std::to_string(r) + " has no face");
    check_face_columns(s.regions[r], s.C.cols(), true, "region " + std::to_string(r));
  }
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
  // Cage faces and regions: valid faces, and joints not shared between kinds of handle.
  // owner[c]: 0 free, 1 point handle, 2 bone, 3 cage, 4 + r region r.
  check_faces(s.CF, s.C, "cage face");
  for (std::size_t r = 0; r < s.regions.size(); ++r)
    check_faces(s.regions[r], s.C, "region " + std::to_string(r) + " face");
  std::vector<int> owner(static_cast<std::size_t>(nc), 0);
  auto owner_name = [](int o) {
    return o == 1 ? std::string("a point handle")
      : o == 2   ? std::string("a bone's joint")
      : o == 3   ? std::string("a cage vertex")
                 : "region " + std::to_string(o - 4) + "'s corner";
  };
  auto claim = [&](int c, int o) {
    int& current = owner[static_cast<std::size_t>(c)];
    if (current != 0 && current != o)
      throw Error(ErrorCode::InvalidArgument,
        "joint " + std::to_string(c) + " is both " + owner_name(current) + " and " +
          owner_name(o) + ": handles must be disjoint (§2)",
        "give each handle its own joints");
    current = o;
  };
  for (Index p = 0; p < s.P.size(); ++p)
    claim(s.P(p), 1);
  for (Index b = 0; b < s.BE.rows(); ++b)
  {
    claim(s.BE(b, 0), 2);
    claim(s.BE(b, 1), 2);
  }
  for (Index k = 0; k < s.CF.size(); ++k)
    claim(s.CF.data()[k], 3);
  for (std::size_t r = 0; r < s.regions.size(); ++r)
    for (Index k = 0; k < s.regions[r].size(); ++k)
      claim(s.regions[r].data()[k], 4 + static_cast<int>(r));
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
  // Cage faces and region faces: their joints, and the pieces per face (the longest edge
  // split into pieces no longer than spacing).
  std::vector<const Eigen::MatrixXi*> face_sets{ &s.CF };
  for (const Eigen::MatrixXi& region : s.regions)
    face_sets.push_back(&region);
  auto face_pieces = [&](const Eigen::MatrixXi& F, Index f) {
    double longest = 0;
    for (Index k = 0; k < F.cols(); ++k)
      longest = std::max(longest, (s.C.row(F(f, (k + 1) % F.cols())) - s.C.row(F(f, k))).norm());
    return std::ceil(longest / spacing);
  };
  for (const Eigen::MatrixXi* F : face_sets)
    for (Index f = 0; f < F->rows(); ++f)
    {
      for (Index k = 0; k < F->cols(); ++k)
        used[static_cast<std::size_t>((*F)(f, k))] = 1;
      const double n = face_pieces(*F, f);
      count += F->cols() == 3 ? (n + 1) * (n + 2) / 2 : n;
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
  for (const Eigen::MatrixXi* F : face_sets)
    for (Index f = 0; f < F->rows(); ++f)
    {
      const auto n = static_cast<int>(face_pieces(*F, f));
      const Eigen::RowVectorXd a = s.C.row((*F)(f, 0)), b = s.C.row((*F)(f, 1));
      if (F->cols() == 2)
      {
        for (int k = 1; k < n; ++k)
        {
          const double t = static_cast<double>(k) / n;
          rows.push_back((1.0 - t) * a + t * b);
        }
        continue;
      }
      // Triangle: the grid points i/n, j/n other than the corners (shared edges repeat their
      // samples; the mesher merges coincident Steiner points).
      const Eigen::RowVectorXd c = s.C.row((*F)(f, 2));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
        {
          const int k = n - i - j;
          if (i == n || j == n || k == n)
            continue;
          rows.push_back((static_cast<double>(i) * a + static_cast<double>(j) * b +
                           static_cast<double>(k) * c) / n);
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
  const Eigen::VectorXi cage = s.cage_joints();
  for (Index k = 0; k < cage.size(); ++k)
  {
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(dim, dim + 1);
    T.leftCols(dim).setIdentity();
    T.col(dim) = (posed_C.row(cage(k)) - s.C.row(cage(k))).transpose();
    transforms.push_back(std::move(T));
  }
  for (const Eigen::MatrixXi& region : s.regions)
  {
    std::vector<int> joints(region.data(), region.data() + region.size());
    std::sort(joints.begin(), joints.end());
    joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
    const auto n = static_cast<Index>(joints.size());
    Eigen::MatrixXd X(n, dim), Y(n, dim);
    for (Index k = 0; k < n; ++k)
    {
      X.row(k) = s.C.row(joints[static_cast<std::size_t>(k)]);
      Y.row(k) = posed_C.row(joints[static_cast<std::size_t>(k)]);
    }
    const Eigen::RowVectorXd cx = X.colwise().mean(), cy = Y.colwise().mean();
    // Kabsch: R = V diag(1, .., det) U^T of the SVD of the cross-covariance X0^T Y0 = U S V^T.
    const Eigen::MatrixXd H = (X.rowwise() - cx).transpose() * (Y.rowwise() - cy);
    // H is square, so JacobiSVD's QR preconditioner would never run: without it the same
    // iteration compiles in a fraction of the time.
    Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner> svd(
      H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::VectorXd d = Eigen::VectorXd::Ones(dim);
    d(dim - 1) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Eigen::MatrixXd R = svd.matrixV() * d.asDiagonal() * svd.matrixU().transpose();
    Eigen::MatrixXd T(dim, dim + 1);
    T.leftCols(dim) = R;
    T.col(dim) = cy.transpose() - R * cx.transpose();
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
