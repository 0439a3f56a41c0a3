#pragma once
/// @file detail/cgal_convex_hull.h
/// Convex hulls in the plane and in space (CGAL, exact predicates), for the celestial
/// coordinates' hull of the controls. In a translation unit of their own, with the other CGAL
/// files, so that CGAL's headers and its -frounding-math reach no other core file.

#include <array>
#include <vector>

namespace bary::detail
{

/// The vertices of the convex hull of @p points, counterclockwise, as positions into
/// @p points (the first of equal points).
std::vector<int> convex_hull_2d(const std::vector<std::array<double, 2>>& points);

/// The faces of the convex hull of @p points (at least four, not coplanar) as triples of
/// positions into @p points (the first of equal points): the first three vertices of each face
/// of CGAL's hull, whatever the orientation.
std::vector<std::array<int, 3>> convex_hull_3d(const std::vector<std::array<double, 3>>& points);

} // namespace bary::detail
