#pragma once
/// @file barylabSplinePipeline.h
/// The spline family's shared pipelines (C1 spline deformations, Rodrigues et al. 2014): the
/// bundled organism example, used by `barylab demo`, the image regression test and the viewer.

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <string>

class vtkPointSet;
class vtkUnstructuredGrid;

namespace barylab
{

/// The organism matched to its picture.
struct OrganismSpline
{
  vtkSmartPointer<vtkUnstructuredGrid> rest_grid; ///< the identity 2.5D spline (border pinned)
  vtkSmartPointer<vtkUnstructuredGrid> grid;      ///< fitted, then edited
  vtkSmartPointer<vtkPointSet> model;             ///< data/spline_organism.obj
  vtkSmartPointer<vtkPointSet> deformed;          ///< the model deformed in 2.5D by grid
  std::string picture;                            ///< data/spline_organism_picture.png
};

/// A 2.5D spline (prism [-0.1, 0.1]) on data/spline_domain.obj with its border pinned, fitted to
/// landmarks (the organism's vertices and where its picture shows them, y + 0.18 sin(pi x),
/// data/README.md), then edited with DECLeS as a user would: the head turned 8 degrees about the
/// neck (delta_max 4), the middle raised by 0.03 through the top surface (delta_max 6), the tail
/// narrowed by 0.85 (delta_max 3); the organism deformed by it. @p summary (optional) gets the
/// fit's errors, per-edit figures, the C1 residual and the minimum Jacobian.
/// @throws bary::Error for unreadable data
OrganismSpline OrganismSplineExample(const std::string& data_dir, nlohmann::json* summary = nullptr);

/// A picture deformed by a 2D spline.
struct GingerbreadSpline
{
  vtkSmartPointer<vtkUnstructuredGrid> rest_grid; ///< the identity on the meshed cage polygon
  vtkSmartPointer<vtkUnstructuredGrid> grid;      ///< after the edits
  std::string picture;                            ///< data/gingerbread.png
  double bounds[4] = { 0, 0, 0, 0 };              ///< where the picture lies (xmin, xmax, ymin, ymax)
};

/// The gingerbread man's picture (data/gingerbread.png, placed as data/README.md says: the
/// cage's bounding box enlarged by 5% per side, square, centred) on a spline over his cage
/// polygon (data/cage2d.obj meshed into about 150 triangles, degree 5), edited with DECLeS:
/// the left hand raised by 0.3 (its two corners, delta_max 15), the right hand turned down 25
/// degrees about the shoulder (delta_max 15) and the head tilted 12 degrees about the neck (its
/// five corners, delta_max 8).
/// @p summary (optional) gets per-edit figures, the C1 residual and the minimum Jacobian.
GingerbreadSpline GingerbreadSplineExample(const std::string& data_dir, nlohmann::json* summary = nullptr);

} // namespace barylab
