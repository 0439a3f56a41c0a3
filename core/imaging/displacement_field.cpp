#include "core/imaging/displacement_field.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"
#include "core/imaging/trilinear.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace bary
{
namespace
{
constexpr Index kFieldChunk = 4096; // voxels or points per parallel chunk
constexpr int kStallWindow = 20;    // the inverse stops when a window gains too little

std::string field_voxel_name(const ImageGrid& grid, Index v)
{
  const Index i = v % grid.size[0], j = (v / grid.size[0]) % grid.size[1],
              k = v / (grid.size[0] * grid.size[1]);
  const Eigen::Vector3d p = grid.point(i, j, k);
  return "voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
    ") at " + detail::format_point(p.data(), 3);
}
} // namespace

void validate_displacement_field(const DisplacementField& field, const char* what)
{
  validate_image_grid(field.grid, what);
  const std::string name = what;
  if (field.values.cols() != field.grid.voxel_count())
    throw Error(ErrorCode::SizeMismatch,
      name + " has " + std::to_string(field.values.cols()) + " displacements for " +
        std::to_string(field.grid.voxel_count()) + " voxels");
  if (!field.values.allFinite())
    for (Index v = 0; v < field.values.cols(); ++v)
      if (!field.values.col(v).allFinite())
        throw Error(ErrorCode::NonFinite,
          name + " has a NaN or infinite displacement at " + field_voxel_name(field.grid, v));
}

DisplacementField displacement_field_from_points(const ImageGrid& grid, const Points& deformed)
{
  validate_image_grid(grid);
  const Index n = grid.voxel_count();
  if (deformed.rows() != n || deformed.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "the deformed grid points are " + std::to_string(deformed.rows()) + " by " +
        std::to_string(deformed.cols()) + ", the grid has " + std::to_string(n) +
        " voxels (3 coordinates each)");
  DisplacementField field;
  field.grid = grid;
  field.values.resize(3, n);
  const Eigen::Matrix3d M = grid.index_to_physical();
  for (Index k = 0; k < grid.size[2]; ++k)
    for (Index j = 0; j < grid.size[1]; ++j)
      for (Index i = 0; i < grid.size[0]; ++i)
      {
        const Index v = grid.voxel(i, j, k);
        const Eigen::Vector3d p = grid.origin + M * Eigen::Vector3d(double(i), double(j), double(k));
        const Eigen::Vector3d q = deformed.row(v).transpose();
        if (!q.allFinite())
          throw Error(ErrorCode::NonFinite,
            "the deformation is NaN or infinite at " + field_voxel_name(grid, v),
            "the method may not be defined there (outside the cage): use an outside policy or a "
            "grid inside the cage");
        field.values.col(v) = q - p;
      }
  return field;
}

FieldSampler::FieldSampler(const DisplacementField& field)
  : field_(&field)
{
  validate_displacement_field(field);
  to_index_ = field.grid.index_to_physical().inverse();
}

bool FieldSampler::inside(const Eigen::Vector3d& p) const
{
  detail::TrilinearStencil s;
  return detail::trilinear_stencil(to_index_ * (p - field_->grid.origin), field_->grid.size, s);
}

Eigen::Vector3d FieldSampler::displacement(const Eigen::Vector3d& p) const
{
  detail::TrilinearStencil s;
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  if (detail::trilinear_stencil(to_index_ * (p - field_->grid.origin), field_->grid.size, s))
    detail::trilinear_sum<3>(s, field_->grid.size, field_->values.data(), u.data());
  return u;
}

Points transform_points(const DisplacementField& field, const Points& points, int threads)
{
  if (points.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(points.cols()) + " coordinates; a displacement field "
      "moves 3D points");
  if (!points.allFinite())
    throw Error(ErrorCode::NonFinite, "the points to transform contain NaN or infinity");
  const FieldSampler sampler(field);
  Points out(points.rows(), 3);
  ProgressReporter reporter({}, std::max<Index>(1, points.rows()));
  detail::parallel_for(points.rows(), kFieldChunk, threads, reporter, "transforming points",
    [&](Index begin, Index end) {
      for (Index p = begin; p < end; ++p)
      {
        const Eigen::Vector3d x = points.row(p).transpose();
        out.row(p) = (x + sampler.displacement(x)).transpose();
      }
    });
  return out;
}

JacobianStatistics jacobian_statistics(
  const DisplacementField& field, int threads, Eigen::VectorXd* determinants)
{
  validate_displacement_field(field);
  const ImageGrid& g = field.grid;
  const Index n = g.voxel_count();
  const Eigen::Matrix3d to_index = g.index_to_physical().inverse();
  const Index nchunks = (n + kFieldChunk - 1) / kFieldChunk;
  std::vector<JacobianStatistics> partial(static_cast<size_t>(nchunks));
  if (determinants)
    determinants->resize(n);
  const Index stride[3] = { 1, g.size[0], g.size[0] * g.size[1] };
  ProgressReporter reporter({}, std::max<Index>(1, n));
  detail::parallel_for(n, kFieldChunk, threads, reporter, "the Jacobian determinant",
    [&](Index begin, Index end) {
      JacobianStatistics s;
      s.minimum = std::numeric_limits<double>::infinity();
      s.maximum = -std::numeric_limits<double>::infinity();
      for (Index v = begin; v < end; ++v)
      {
        const Index idx[3] = { v % g.size[0], (v / g.size[0]) % g.size[1], v / stride[2] };
        Eigen::Matrix3d G; // column a: du / d(index a)
        for (int a = 0; a < 3; ++a)
        {
          const Index lo = idx[a] > 0 ? v - stride[a] : v;
          const Index hi = idx[a] + 1 < g.size[a] ? v + stride[a] : v;
          const double h = double((hi - lo) / stride[a]);
          G.col(a) = h > 0 ? Eigen::Vector3d((field.values.col(hi) - field.values.col(lo)) / h)
                           : Eigen::Vector3d::Zero();
        }
        const double det = (Eigen::Matrix3d::Identity() + G * to_index).determinant();
        if (determinants)
          (*determinants)(v) = det;
        s.minimum = std::min(s.minimum, det);
        s.maximum = std::max(s.maximum, det);
        if (!(det > 0.0))
        {
          if (s.folded == 0)
            s.first_folded = v;
          ++s.folded;
        }
      }
      partial[size_t(begin / kFieldChunk)] = s;
    });
  JacobianStatistics total;
  total.voxels = n;
  total.minimum = std::numeric_limits<double>::infinity();
  total.maximum = -std::numeric_limits<double>::infinity();
  for (const JacobianStatistics& s : partial)
  {
    total.minimum = std::min(total.minimum, s.minimum);
    total.maximum = std::max(total.maximum, s.maximum);
    if (s.folded > 0 && total.first_folded < 0)
      total.first_folded = s.first_folded;
    total.folded += s.folded;
  }
  return total;
}

InverseFieldResult invert_displacement_field(const DisplacementField& forward,
  const ImageGrid& grid, const InverseFieldOptions& options, const ProgressCallback& progress)
{
  const FieldSampler sampler(forward); // validates the field
  validate_image_grid(grid, "the inverse field's grid");
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance))
    throw Error(ErrorCode::InvalidArgument,
      "the inverse's tolerance " + detail::format_number(options.tolerance) +
        " must be finite and >= 0");
  if (options.max_iterations < 1)
    throw Error(ErrorCode::InvalidArgument,
      "the inverse's maximum number of iterations " + std::to_string(options.max_iterations) +
        " must be at least 1");
  const double tol =
    options.tolerance > 0.0 ? options.tolerance : 1e-4 * forward.grid.spacing.minCoeff();
  const Index n = grid.voxel_count();
  InverseFieldResult result;
  result.tolerance = tol;
  result.voxels = n;
  result.inverse.grid = grid;
  result.inverse.values.resize(3, n);
  struct Partial
  {
    double max_residual = 0.0, sum_residual = 0.0;
    Index not_converged = 0, first_not_converged = -1, at_border = 0;
    int max_iterations = 0;
  };
  const Index nchunks = (n + kFieldChunk - 1) / kFieldChunk;
  std::vector<Partial> partial(static_cast<size_t>(nchunks));
  const Eigen::Matrix3d M = grid.index_to_physical();
  const Eigen::Matrix3d to_forward_index = forward.grid.index_to_physical().inverse();
  ProgressReporter reporter(progress, std::max<Index>(1, n));
  detail::parallel_for(n, kFieldChunk, options.threads, reporter, "inverting the displacement field",
    [&](Index begin, Index end) {
      Partial s;
      for (Index v = begin; v < end; ++v)
      {
        const Eigen::Vector3d index(double(v % grid.size[0]),
          double((v / grid.size[0]) % grid.size[1]), double(v / (grid.size[0] * grid.size[1])));
        const Eigen::Vector3d y = grid.origin + M * index;
        Eigen::Vector3d x = y - sampler.displacement(y);
        Eigen::Vector3d R = x + sampler.displacement(x) - y; // residual vector
        double r = R.norm();
        double alpha = 1.0; // the relaxation
        int it = 0;
        double r_checkpoint = r; // the residual kStallWindow iterations ago
        while (r > tol && it < options.max_iterations && alpha >= 1e-6)
        {
          if (it > 0 && it % kStallWindow == 0)
          {
            // stalled: the window gained less than the tolerance or 1% of the residual (a
            // contraction of rate L gains 1 - L^20, over 1% for any L < 0.9995)
            if (r_checkpoint - r < std::max(tol, 0.01 * r_checkpoint))
              break;
            r_checkpoint = r;
          }
          ++it;
          const Eigen::Vector3d xn = x - alpha * R;
          const Eigen::Vector3d Rn = xn + sampler.displacement(xn) - y;
          const double rn = Rn.norm();
          if (rn < r)
          {
            x = xn;
            R = Rn;
            r = rn;
            alpha = std::min(1.0, 2.0 * alpha);
          }
          else
            alpha *= 0.5;
        }
        result.inverse.values.col(v) = x - y;
        s.max_residual = std::max(s.max_residual, r);
        s.sum_residual += r;
        s.max_iterations = std::max(s.max_iterations, it);
        if (!(r <= tol))
        {
          if (s.not_converged == 0)
            s.first_not_converged = v;
          ++s.not_converged;
          const Eigen::Vector3d c = to_forward_index * (x - forward.grid.origin);
          for (int a = 0; a < 3; ++a)
            if (!(c(a) >= -1e-9 && c(a) <= double(forward.grid.size[a] - 1) + 1e-9))
            {
              ++s.at_border;
              break;
            }
        }
      }
      partial[size_t(begin / kFieldChunk)] = s;
    });
  double sum = 0.0;
  for (const Partial& s : partial)
  {
    result.max_residual = std::max(result.max_residual, s.max_residual);
    sum += s.sum_residual;
    if (s.not_converged > 0 && result.first_not_converged < 0)
      result.first_not_converged = s.first_not_converged;
    result.not_converged += s.not_converged;
    result.not_converged_at_border += s.at_border;
    result.max_iterations_used = std::max(result.max_iterations_used, s.max_iterations);
  }
  result.mean_residual = n > 0 ? sum / double(n) : 0.0;
  return result;
}

InverseFieldResult invert_displacement_field(const DisplacementField& forward,
  const InverseFieldOptions& options, const ProgressCallback& progress)
{
  return invert_displacement_field(forward, forward.grid, options, progress);
}

} // namespace bary
