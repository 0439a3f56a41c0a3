#include "core/surface/correspondence.h"

#include "core/common/error.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace bary
{

SurfaceMap map_surface_points(const WeightedAverages& target,
  const std::vector<SurfacePoint>& target_anchors, const std::vector<SurfacePoint>& target_points,
  const WeightedAverages& source, const std::vector<SurfacePoint>& source_anchors,
  const CorrespondenceOptions& options, const ProgressCallback& progress)
{
  if (target_anchors.size() != source_anchors.size())
    throw Error(ErrorCode::SizeMismatch, "the target has " + std::to_string(target_anchors.size()) +
        " anchors but the source has " + std::to_string(source_anchors.size()),
      "give corresponding anchors: anchor i of one surface is anchor i of the other");
  auto phase = [&](double begin, double end) -> ProgressCallback {
    if (!progress)
      return {};
    return [&progress, begin, end](double f) { return progress(begin + (end - begin) * f); };
  };
  SurfaceMap map;
  map.weights = target.inverse(target_anchors, target_points, options.inverse, phase(0.0, 0.3));
  const RoundTrip rt = target.round_trip(target_anchors, target_points, map.weights,
    options.round_trip_tolerance, options.forward, phase(0.3, 0.65));
  const ForwardResult image = source.forward(source_anchors, map.weights, options.forward, phase(0.65, 1.0));
  const std::size_t n = target_points.size();
  map.image.assign(n, SurfacePoint{});
  map.defined.assign(n, 0);
  map.round_trip_error = rt.error;
  for (std::size_t p = 0; p < n; ++p)
  {
    const bool returned = rt.returned[p] != 0, mapped = image.valid[p] != 0;
    if (!returned)
      ++map.not_returned;
    if (!mapped)
      ++map.source_failures;
    if (returned && mapped)
    {
      map.defined[p] = 1;
      map.image[p] = image.points[p];
    }
    else
      ++map.undefined;
  }
  return map;
}

MapDistortion map_distortion(
  const SurfaceMesh& target, const SurfaceMesh& source, const SurfaceMap& vertex_map)
{
  const Index nv = target.vertex_count(), nf = target.face_count();
  if (static_cast<Index>(vertex_map.image.size()) != nv)
    throw Error(ErrorCode::SizeMismatch, "the map has " + std::to_string(vertex_map.image.size()) +
        " points but the target has " + std::to_string(nv) + " vertices");
  const Eigen::MatrixXd X = surface_point_positions(source.F, source.V, [&] {
    std::vector<SurfacePoint> p = vertex_map.image;
    for (auto& q : p)
      if (q.face < 0)
        q = SurfacePoint{ 0, Eigen::Vector3d(1, 0, 0) }; // placeholder, never used
    return p;
  }());
  MapDistortion d;
  d.stretch = Eigen::VectorXd::Constant(nf, std::numeric_limits<double>::quiet_NaN());
  d.flipped.assign(static_cast<std::size_t>(nf), 0);
  std::vector<int> sign(static_cast<std::size_t>(nf), 0);
  std::vector<double> area(static_cast<std::size_t>(nf), 0.0);
  Index positive = 0, negative = 0;
  for (Index f = 0; f < nf; ++f)
  {
    const int a = target.F(f, 0), b = target.F(f, 1), c = target.F(f, 2);
    if (!vertex_map.defined[static_cast<std::size_t>(a)] || !vertex_map.defined[static_cast<std::size_t>(b)] ||
      !vertex_map.defined[static_cast<std::size_t>(c)])
      continue;
    // The target triangle in its own plane: e1 along (b - a), e2 in the plane.
    const Eigen::Vector3d ta = target.V.row(a), tb = target.V.row(b), tc = target.V.row(c);
    const Eigen::Vector3d u = tb - ta, v = tc - ta;
    const Eigen::Vector3d n = u.cross(v);
    const double twice_area = n.norm();
    const Eigen::Vector3d e1 = u.normalized(), e2 = n.cross(u).normalized();
    Eigen::Matrix2d T;
    T << u.dot(e1), v.dot(e1), u.dot(e2), v.dot(e2);
    const Eigen::Vector3d ia = X.row(a), ib = X.row(b), ic = X.row(c);
    Eigen::Matrix<double, 3, 2> S;
    S.col(0) = ib - ia;
    S.col(1) = ic - ia;
    const Eigen::Matrix<double, 3, 2> J = S * T.inverse();
    const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(J).singularValues();
    area[static_cast<std::size_t>(f)] = 0.5 * twice_area;
    ++d.measured;
    if (!(sv(1) > 0))
    {
      d.stretch(f) = std::numeric_limits<double>::infinity();
      continue;
    }
    const double G2 = sv(0) * sv(0), g2 = sv(1) * sv(1);
    d.stretch(f) = std::sqrt(0.5 * (G2 + g2) * 0.5 * (1.0 / G2 + 1.0 / g2));
    // Orientation of the image against the source's normal at the image of the centroid.
    const SurfacePoint& pa = vertex_map.image[static_cast<std::size_t>(a)];
    const Eigen::Vector3d image_normal = (ib - ia).cross(ic - ia);
    const Eigen::Vector3d sa = source.V.row(source.F(pa.face, 0)), sb = source.V.row(source.F(pa.face, 1)),
                          sc = source.V.row(source.F(pa.face, 2));
    const double s = image_normal.dot((sb - sa).cross(sc - sa));
    sign[static_cast<std::size_t>(f)] = s > 0 ? 1 : s < 0 ? -1 : 0;
    positive += s > 0;
    negative += s < 0;
  }
  const int majority = positive >= negative ? 1 : -1;
  double measured_area = 0, flipped_area = 0;
  std::vector<std::pair<double, Index>> order;
  for (Index f = 0; f < nf; ++f)
  {
    if (std::isnan(d.stretch(f)))
      continue;
    measured_area += area[static_cast<std::size_t>(f)];
    if (sign[static_cast<std::size_t>(f)] == -majority)
    {
      d.flipped[static_cast<std::size_t>(f)] = 1;
      ++d.flipped_count;
      flipped_area += area[static_cast<std::size_t>(f)];
    }
    order.emplace_back(d.stretch(f), f);
  }
  d.flipped_area_fraction = measured_area > 0 ? flipped_area / measured_area : 0.0;
  auto rms = [&](std::size_t count) {
    double s = 0, w = 0;
    for (std::size_t k = 0; k < count; ++k)
    {
      const double a = area[static_cast<std::size_t>(order[k].second)];
      s += a * order[k].first * order[k].first;
      w += a;
    }
    return w > 0 ? std::sqrt(s / w) : 0.0;
  };
  std::sort(order.begin(), order.end());
  d.stretch_all = rms(order.size());
  d.stretch_best95 = rms(static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(order.size()))));
  return d;
}

} // namespace bary
