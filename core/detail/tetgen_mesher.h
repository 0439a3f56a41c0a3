#pragma once
/// @file detail/tetgen_mesher.h
/// The TetGen part of mesh_closed_surface (domain_mesh.h): the only file that includes
/// tetgen.h.

#include "core/common/types.h"

#include <string>

namespace bary::detail
{

/// TetGen's output, in TetGen's numbering (zero-based).
struct TetgenOutput
{
  Eigen::MatrixXd V;                   ///< #V by 3
  Eigen::MatrixXi T;                   ///< #T by 4, as TetGen writes them
  Eigen::MatrixXi boundary_faces;      ///< #B by 3 mesh faces on the input surface
  Eigen::VectorXi boundary_face_input; ///< #B: row of F each boundary face lies on (-1: unknown)
};

/// Runs TetGen 1.5's tetrahedralize(@p switches) on the piecewise linear complex whose points
/// are @p V (#V by 3) followed by @p addin (#A by 3, may be empty) and whose facets are the
/// triangles @p F (#F by 3, indices into V). The addin points are isolated vertices of the PLC:
/// TetGen keeps those inside the domain as mesh vertices at their exact coordinates (TetGen
/// 1.5.0's own 'i' switch crashed on some cages and dropped points under 'Y', so it is not
/// used). The switches must contain 'p' and 'z' (zero-based) and should contain 'Q' (quiet).
/// Calls are serialised (TetGen keeps global state in its exact predicates).
/// @throws Error(InvalidCage) for TetGen's errors 3 (self-intersection), 4 (very small input
///   feature) and 5 (two very close facets), Error(InvalidArgument) for 10 (input error, e.g.
///   switches that do not go together), Error(Internal) for the others (1 out of memory,
///   2 internal error); the message names TetGen's code.
TetgenOutput tetgen_tetrahedralize(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
  const Eigen::MatrixXd& addin, const std::string& switches);

} // namespace bary::detail
