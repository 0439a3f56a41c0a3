#pragma once
/// @file decles.h
/// Editing a C1 spline by constrained least squares: DECLeS (Rodrigues, Stolfi, Gomide,
/// "Editing C1-continuous 2D spline deformations by constrained least squares", 2014, §4,
/// Algorithm 1) and the editing operations of §5.1 (soft translation, rotation and scale of
/// anchors with slaves within a graph distance delta_max).
///
/// Each edit splits the control points into anchors A (set by the edit), slaves S (the points
/// within delta_max of an anchor in the global Bézier net), derived points D (S plus the points
/// the C1 conditions need, chosen by type, §4.2) and fixed points F (the rest). The conditions E
/// are every quadrilateral condition that involves a point of A or D. Redundant conditions are
/// removed by Gaussian elimination in exact rational arithmetic (§4.3.2), which also proves that
/// any anchor positions can be met (property 2 of §4.2); where the type rules are not enough
/// (at some vertices of even degree, near the border, next to pinned points) D grows by the
/// other points of E's conditions until they are. The derived points then move as little as
/// possible from their suggested positions (Eqs. 13-23, w_s = 1) subject to E:
/// X'' = X' - A^T (A A^T)^-1 (A X' - b), A the independent conditions' columns of D.

#include "core/common/types.h"
#include "core/spline/triangular_spline.h"

#include <map>
#include <vector>

namespace bary
{

/// Largest delta_max an edit accepts.
inline constexpr int kMaxDeltaMax = 1000;

/// The editing operations of §5.1.
enum class SplineEditOp
{
  Translate, ///< anchors move by `by`; derived points by theta_s by (Eq. 24)
  Rotate,    ///< about `center` by angle_degrees (derived points by theta_s times the angle)
  Scale      ///< about `center` by factor (derived points by factor^theta_s)
};

/// Name of an operation ("translate", "rotate", "scale").
const char* to_string(SplineEditOp op) noexcept;

/// One edit.
struct SplineEdit
{
  SplineEditOp op = SplineEditOp::Translate;
  std::vector<Index> anchors;   ///< global control points, distinct
  /// Positions whose nearest control points (SplineEditor::nearest_point, at the time of the
  /// edit) are anchors too: how a user who clicks names them. Resolved when the edit is applied
  /// (the log keeps the positions, so a replay resolves them the same way).
  std::vector<Eigen::Vector2d> near;
  Eigen::VectorXd by;           ///< Translate: the displacement (one value per spline column)
  Eigen::Vector2d center = Eigen::Vector2d::Zero(); ///< Rotate, Scale
  double angle_degrees = 0;     ///< Rotate
  double factor = 1;            ///< Scale, > 0
  int delta_max = 0;            ///< slaves: points within this net distance, [0, kMaxDeltaMax]
};

/// What step 2 of Algorithm 1 chose for an edit.
struct EditSets
{
  std::vector<Index> anchors;     ///< A, increasing
  std::vector<Index> slaves;      ///< S, increasing
  std::vector<Index> derived;     ///< D (includes S), increasing
  std::vector<Index> constraints; ///< E: conditions (SplineNet::conditions() rows), increasing
  std::vector<Index> independent; ///< the conditions of E kept after the exact elimination
  int expansions = 0; ///< times D grew beyond the type rules to make the anchors reachable
};

/// What an edit did.
struct SplineEditReport
{
  EditSets sets;
  double seconds = 0;       ///< the whole edit
  double exact_seconds = 0; ///< of which the exact elimination (0 when cached)
  bool cached = false;      ///< the elimination of the same A and D was reused
  double residual = 0;      ///< largest residual of E's conditions after the edit
  double max_move = 0;      ///< largest displacement of a control point
};

/// Interactive editing of a spline: edits, undo, redo and a log that replays exactly.
class SplineEditor
{
public:
  /// @throws Error(InvalidArgument) when the spline is not C1 (condition residual above 1e-9
  ///   times the grid size times the values' scale): edits keep C1, they cannot create it
  explicit SplineEditor(TriangularSpline spline);

  const TriangularSpline& spline() const noexcept { return spline_; }

  /// Points no edit moves (the paper's F made permanent: e.g. the border). An edit naming one
  /// as an anchor fails; derived points never include them.
  /// @throws Error(InvalidArgument) for an index out of range
  void set_pinned(const std::vector<Index>& pinned);
  const std::vector<char>& pinned() const noexcept { return pinned_; }

  /// Step 2 for @p anchors and @p delta_max (A, S, D, E and the independent conditions).
  /// @throws Error(InvalidArgument) for an anchor out of range, repeated or pinned, delta_max out
  ///   of range, or anchors that no set of derived points can follow (C1 would break)
  EditSets select(const std::vector<Index>& anchors, int delta_max) const;

  /// Applies an edit (Algorithm 1). On any error the spline is unchanged.
  /// @throws as select, and Error(InvalidArgument) for a displacement with the wrong number of
  ///   values, rotation or scale of a scalar spline, a factor <= 0, Error(NonFinite)
  SplineEditReport apply(const SplineEdit& edit);

  bool can_undo() const noexcept { return done_ > 0; }
  bool can_redo() const noexcept { return done_ < history_.size(); }
  /// Undoes the last edit (restores the values it changed, bit for bit). False when none.
  bool undo();
  /// Redoes the last undone edit (the same values, bit for bit). False when none.
  bool redo();
  /// The edits in effect, in order (undone edits are not in it; an edit after an undo drops the
  /// undone ones). Applying them in order to the spline the editor started from gives the
  /// same values, bit for bit.
  std::vector<SplineEdit> log() const;

  /// Forgets the cached eliminations (each A and D's exact elimination is kept for the next edit
  /// with the same sets: a drag repeats them).
  void clear_cache() { cache_.clear(); }

  /// The control point nearest @p x: by its current value for a deformation (where it is drawn),
  /// by its nominal position for a scalar spline. Ties: the smallest index.
  Index nearest_point(const Eigen::Vector2d& x) const;

private:
  struct Change
  {
    SplineEdit edit;
    std::vector<Index> points;
    Eigen::MatrixXd before, after;
  };
  struct Elimination
  {
    std::vector<Index> constraints, independent;
    int expansions = 0;
    std::vector<Index> derived;
  };
  Elimination eliminate(const std::vector<Index>& anchors, std::vector<Index> derived,
    double* exact_seconds) const;

  TriangularSpline spline_;
  std::vector<char> pinned_;
  std::vector<Change> history_;
  size_t done_ = 0;
  mutable std::map<std::vector<Index>, Elimination> cache_;
  /// Flags over the control points, all 0 between calls (set and cleared per touched point).
  mutable std::vector<char> scratch_[5];
  mutable bool last_cached_ = false;         ///< select() found its elimination in the cache
  mutable double last_exact_seconds_ = 0;    ///< and otherwise took this long for it
};

} // namespace bary
