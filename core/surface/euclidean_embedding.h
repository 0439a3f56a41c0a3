#pragma once
/// @file euclidean_embedding.h
/// The Euclidean embedding of a surface of Panozzo et al., "Weighted averages on surfaces"
/// (ACM TOG 32(4), 2013), §3.5: a map of the mesh vertices into R^D whose Euclidean distances
/// approximate geodesic distances on the surface, smooth, so that weighted averages can be
/// computed in R^D and projected back (§3.1). The paper's pipeline, all in C++ here (the
/// authors ran it in MATLAB):
///
/// 1. **Landmarks** S (the paper: 1000): the vertices left by halfedge-collapse decimation that
///    changes face normals least (landmark_decimation.h), or farthest-point samples (Dijkstra
///    distances on the edge graph, from vertex 0's farthest vertex).
/// 2. **Geodesic distances** between landmarks, Q_ij = d_geo(s_i, s_j): the heat method
///    (geodesic_heat.h; one factorization, sources in blocks), symmetrised (Q + Q^T) / 2. The
///    paper used fast marching; both are first-order accurate.
/// 3. **Metric MDS** into R^D (the paper: D = 8) minimising the stress (14),
///    sum_ij (1 - |e(s_i) - e(s_j)| / Q_ij)^2, i.e. the weighted raw stress with weights
///    1 / Q_ij^2, by SMACOF (de Leeuw 1977; Borg & Groenen, "Modern Multidimensional Scaling",
///    2005, §8.2: Guttman transforms with the weighted Laplacian's pseudo-inverse, factored once)
///    started from classical MDS (Torgerson: the D largest eigenpairs of -1/2 J Q^2 J), until
///    the stress decreases by less than a relative tolerance in an iteration.
/// 4. **Least-squares mesh upsampling** (15): the other vertices minimise
///    tr(v^T K M^-1 K v) with the landmarks fixed (K the cotangent stiffness matrix, M the
///    lumped mass matrix of the original mesh), one sparse factorization for all D columns.
///
/// The embedding's quality is reported as the relative error of embedded distances against
/// heat-method geodesic distances from a sample of sources to every vertex.

#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/surface/surface_mesh.h"

#include <string>
#include <vector>

namespace bary
{

/// How the landmarks are chosen.
enum class LandmarkMethod
{
  Decimation,   ///< the vertices left by normal-preserving halfedge collapses (the paper's)
  FarthestPoint ///< farthest-point sampling with edge-graph (Dijkstra) distances
};

/// Options of euclidean_embedding; every default is the paper's where it gives one.
struct EmbeddingOptions
{
  /// Embedding dimension D, range [2, 64]. Default 8 (the paper's; "no improvement in quality
  /// above eight dimensions").
  int dimension = 8;
  /// Number of landmarks, range [D + 2, 100000]; all vertices when the mesh has fewer.
  /// Default 1000 (the paper's).
  Index landmarks = 1000;
  /// How landmarks are chosen. Default Decimation (the paper's).
  LandmarkMethod landmark_method = LandmarkMethod::Decimation;
  /// SMACOF stops when an iteration lowers the stress (14) by less than this fraction of it.
  /// Range [1e-14, 0.1]. Default 1e-4, the relative tolerance of MATLAB's mdscale that the
  /// authors used; measured on the authors' face and statue (docs/weighted-averages.md), the
  /// embedding's distance error against geodesics is then within 0.1% (absolute) of what 1e-6
  /// gives, at a third of the iterations.
  double stress_tolerance = 1e-4;
  /// SMACOF iteration cap, range [0, 100000] (0: classical MDS only). Reaching it with the
  /// tolerance unmet is reported in EmbeddingResult::smacof_converged, not thrown: the
  /// embedding is still valid, only less faithful. Default 1000.
  int max_iterations = 1000;
  /// Heat-method time factor (geodesic_heat.h), range (0, 1e6]. Default 1.
  double heat_time_factor = 1.0;
  /// Number of sources for the quality report (distances from each to every vertex); 0 skips
  /// it. Range [0, 1000]. Default 16.
  int quality_sources = 16;
  /// OpenMP threads (0 = OpenMP's default); the embedding does not depend on it. Default 0.
  int threads = 0;
};

/// Relative error of embedded distances |e(x) - e(y)| against geodesic distances d(x, y).
struct EmbeddingQuality
{
  Index pairs = 0;          ///< (source, vertex) pairs measured
  double mean_relative_error = 0;
  double max_relative_error = 0;
  double median_relative_error = 0;
};

/// The embedding and what it took.
struct EmbeddingResult
{
  Eigen::MatrixXd E;                ///< #V by D: the embedded vertices
  std::vector<int> landmarks;       ///< the landmark vertices, ascending
  double initial_stress = 0;        ///< stress (14) of classical MDS, divided by #pairs
  double stress = 0;                ///< stress (14) at the end, divided by #pairs
  int smacof_iterations = 0;
  bool smacof_converged = true;
  EmbeddingQuality quality;         ///< empty when quality_sources = 0
  /// Seconds of each stage: "landmarks", "geodesics", "mds", "smacof", "upsampling",
  /// "quality", in order.
  std::vector<std::pair<std::string, double>> seconds;
};

/// Computes the embedding of a validated surface.
/// @throws Error(InvalidArgument) for options out of range (named); Error(Cancelled) when
///   @p progress returns false; Error(NotConverged) when the geodesic distances between two
///   landmarks are not finite or not positive (a mesh too fine for the heat method's time step:
///   raise heat_time_factor).
EmbeddingResult euclidean_embedding(const SurfaceMesh& mesh, const EmbeddingOptions& options = {},
  const ProgressCallback& progress = {});

/// Validates options (as euclidean_embedding does first).
void validate_embedding_options(const EmbeddingOptions& options);

/// Quality of an embedding E (#V by D) of @p mesh: heat-method geodesic distances from
/// @p sources to every vertex against the embedded distances, over pairs whose geodesic
/// distance exceeds 3 mean edge lengths (the heat method's own error is largest near its
/// source).
/// @throws Error(SizeMismatch) when E does not have #V rows; Error(InvalidArgument) for a
///   source out of range.
EmbeddingQuality embedding_quality(const SurfaceMesh& mesh, const Eigen::MatrixXd& E,
  const std::vector<int>& sources, double heat_time_factor = 1.0);

/// Farthest-point samples: @p count vertices, the first the farthest (edge-graph distance) from
/// vertex 0, each next the farthest from those chosen; ascending. All vertices when count >= #V.
std::vector<int> farthest_point_landmarks(const SurfaceMesh& mesh, Index count);

} // namespace bary
