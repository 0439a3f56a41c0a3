#pragma once
/// @file igl_formats.h
/// Test-only readers for the libigl file formats of the shared oracle data
/// (BARYLAB_SHARED_DIR/igl): MEDIT .mesh, skeleton .tgf and matrix .dmat, and the triangle
/// meshes of BARYLAB_SHARED_DIR/wa (.obj). Written from the
/// format descriptions, not from libigl's code. They throw std::runtime_error naming the file and
/// the line or token that could not be read.

#include <Eigen/Core>

#include <string>

namespace bary::test
{

/// A MEDIT mesh: "MeshVersionFormatted", "Dimension d", then sections "Vertices n" (n lines
/// "x y z ref"), "Triangles m" (m lines "a b c ref"), "Tetrahedra m" (m lines "a b c d ref")
/// and others ("Edges", ...) that are skipped; indices are 1-based in the file, 0-based here.
/// The count may be on the keyword's line or the next one. "End" stops reading.
struct MeditMesh
{
  Eigen::MatrixXd V; ///< #V by d
  Eigen::MatrixXi T; ///< #T by 4 tetrahedra (0 rows if none)
  Eigen::MatrixXi F; ///< #F by 3 triangles (0 rows if none)
};
MeditMesh read_medit_mesh(const std::string& path);

/// A skeleton from a .tgf file: vertex lines "i x y z [more columns]" (1-based i, in order),
/// a line "#", edge lines "a b [more columns]" (1-based), an optional final "#".
struct TgfSkeleton
{
  Eigen::MatrixXd C; ///< #C by 3 joint positions
  Eigen::MatrixXi E; ///< #E by 2 edges (0-based), in file order
};
TgfSkeleton read_tgf(const std::string& path);

/// A dense matrix from a .dmat file: header "cols rows", then cols * rows values in
/// column-major order.
Eigen::MatrixXd read_dmat(const std::string& path);

/// A triangle mesh from a Wavefront .obj file: "v x y z" and "f a b c" lines (1-based indices,
/// negative ones relative to the vertices so far, "a/t/n" forms read as a; polygons fanned into
/// triangles); other lines are skipped.
struct ObjMesh
{
  Eigen::MatrixXd V; ///< #V by 3
  Eigen::MatrixXi F; ///< #F by 3
};
ObjMesh read_obj(const std::string& path);

} // namespace bary::test
