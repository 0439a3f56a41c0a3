#include "core/spline/decles.h"

#include "core/common/error.h"
#include "core/detail/exact_elimination.h"
#include "core/detail/format.h"
#include "core/detail/timing.h"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <unordered_map>

namespace bary
{

const char* to_string(SplineEditOp op) noexcept
{
  switch (op)
  {
    case SplineEditOp::Translate:
      return "translate";
    case SplineEditOp::Rotate:
      return "rotate";
    case SplineEditOp::Scale:
      return "scale";
  }
  return "?";
}

namespace
{

/// Flags over the control points that are set and cleared in time proportional to the points
/// touched (an edit's cost must not grow with the grid).
class Marks
{
public:
  explicit Marks(std::vector<char>& storage)
    : v_(storage)
  {
  }
  ~Marks()
  {
    for (Index p : touched_)
      v_[static_cast<size_t>(p)] = 0;
  }
  Marks(const Marks&) = delete;
  Marks& operator=(const Marks&) = delete;
  void set(Index p)
  {
    if (!v_[static_cast<size_t>(p)])
    {
      v_[static_cast<size_t>(p)] = 1;
      touched_.push_back(p);
    }
  }
  bool operator[](Index p) const { return v_[static_cast<size_t>(p)] != 0; }
  const std::vector<char>& storage() const { return v_; }

private:
  std::vector<char>& v_;
  std::vector<Index> touched_;
};

/// Breadth-first distances inside the set @p inside (a map point -> distance), from sources
/// with the given start distance, up to @p max_distance.
std::unordered_map<Index, int> local_distances(const SplineNet& net,
  const std::vector<Index>& sources, int start, const std::vector<char>* inside,
  int max_distance = std::numeric_limits<int>::max())
{
  std::unordered_map<Index, int> dist;
  std::deque<Index> q;
  for (Index s : sources)
    if (dist.emplace(s, start).second)
      q.push_back(s);
  while (!q.empty())
  {
    const Index p = q.front();
    q.pop_front();
    const int dp = dist[p];
    if (dp >= max_distance)
      continue;
    for (Index r : net.net_neighbours(p))
      if ((!inside || (*inside)[static_cast<size_t>(r)]) && dist.emplace(r, dp + 1).second)
        q.push_back(r);
  }
  return dist;
}

} // namespace

SplineEditor::SplineEditor(TriangularSpline spline)
  : spline_(std::move(spline))
  , pinned_(static_cast<size_t>(spline_.net().num_points()), 0)
{
  for (auto& s : scratch_)
    s.assign(static_cast<size_t>(spline_.net().num_points()), 0);
  const ContinuityReport c = spline_.continuity();
  const double scale = spline_.values().cwiseAbs().maxCoeff() + spline_.net().mean_edge_length();
  if (c.max_condition_residual > 1e-9 * scale)
    throw Error(ErrorCode::InvalidArgument,
      "the spline is not C1: a quadrilateral condition has residual " +
        detail::format_number(c.max_condition_residual),
      "edits keep a spline C1 but cannot make it so; start from the identity spline");
}

void SplineEditor::set_pinned(const std::vector<Index>& pinned)
{
  std::vector<char> mark(static_cast<size_t>(spline_.net().num_points()), 0);
  for (Index p : pinned)
  {
    if (p < 0 || p >= spline_.net().num_points())
      throw Error(ErrorCode::InvalidArgument,
        "pinned control point " + std::to_string(p) + " is out of range [0, " +
          std::to_string(spline_.net().num_points() - 1) + "]");
    mark[static_cast<size_t>(p)] = 1;
  }
  pinned_ = std::move(mark);
  cache_.clear();
}

SplineEditor::Elimination SplineEditor::eliminate(
  const std::vector<Index>& anchors, std::vector<Index> derived, double* exact_seconds) const
{
  const SplineNet& net = spline_.net();
  Marks inA(scratch_[3]), inD(scratch_[4]);
  for (Index a : anchors)
    inA.set(a);
  for (Index p : derived)
    inD.set(p);
  Elimination out;
  const auto t0 = std::chrono::steady_clock::now();
  for (;;)
  {
    // E: every condition with a point of A or D.
    std::vector<Index> E;
    for (const std::vector<Index>* set : { &anchors, const_cast<const std::vector<Index>*>(&derived) })
      for (Index p : *set)
        for (Index c : net.conditions_of(p))
          E.push_back(c);
    std::sort(E.begin(), E.end());
    E.erase(std::unique(E.begin(), E.end()), E.end());

    std::unordered_map<Index, int> column;
    for (size_t k = 0; k < derived.size(); ++k)
      column[derived[k]] = static_cast<int>(k);
    for (size_t k = 0; k < anchors.size(); ++k)
      column[anchors[k]] = static_cast<int>(derived.size() + k);
    std::vector<detail::ExactCondition> rows(E.size());
    const auto& V = net.vertices();
    for (size_t r = 0; r < E.size(); ++r)
    {
      const QuadCondition& c = net.conditions()[static_cast<size_t>(E[r])];
      for (int k = 0; k < 4; ++k)
      {
        const auto it = column.find(c.point[static_cast<size_t>(k)]);
        rows[r].column[static_cast<size_t>(k)] = it == column.end() ? -1 : it->second;
        const int v = c.vertex[static_cast<size_t>(k)];
        rows[r].vertex[static_cast<size_t>(k)] = { V(v, 0), V(v, 1) };
      }
    }
    const detail::ExactElimination ex = detail::eliminate_exact(
      rows, static_cast<int>(derived.size()), static_cast<int>(anchors.size()));
    if (ex.conflict < 0)
    {
      out.constraints = E;
      for (int r : ex.independent)
        out.independent.push_back(E[static_cast<size_t>(r)]);
      out.derived = derived;
      break;
    }
    // The type rules were not enough: D grows by the other points of E's conditions.
    size_t added = 0;
    for (Index c : E)
      for (Index p : net.conditions()[static_cast<size_t>(c)].point)
      {
        if (!inA[p] && !inD[p] && !pinned_[static_cast<size_t>(p)])
        {
          inD.set(p);
          derived.push_back(p);
          ++added;
        }
      }
    std::sort(derived.begin(), derived.end());
    ++out.expansions;
    if (added == 0)
    {
      std::string list;
      for (size_t k = 0; k < anchors.size() && k < 8; ++k)
        list += (k ? ", " : "") + std::to_string(anchors[k]);
      throw Error(ErrorCode::InvalidArgument,
        "the edit cannot keep the spline C1: no choice of the other control points can follow "
        "anchors " + list + " (condition " + std::to_string(E[static_cast<size_t>(ex.conflict)]) +
          " ties them to fixed points)",
        "unpin control points near the anchors, or move fewer anchors at once");
    }
  }
  if (exact_seconds)
    *exact_seconds = seconds_since(t0);
  return out;
}

EditSets SplineEditor::select(const std::vector<Index>& anchors, int delta_max) const
{
  const SplineNet& net = spline_.net();
  const Index n = net.num_points();
  if (anchors.empty())
    throw Error(ErrorCode::EmptyInput, "an edit needs at least one anchor");
  if (delta_max < 0 || delta_max > kMaxDeltaMax)
    throw Error(ErrorCode::InvalidArgument,
      "delta_max " + std::to_string(delta_max) + " is out of range [0, " +
        std::to_string(kMaxDeltaMax) + "]");
  EditSets sets;
  for (Index a : anchors)
  {
    if (a < 0 || a >= n)
      throw Error(ErrorCode::InvalidArgument,
        "anchor " + std::to_string(a) + " is not a control point: the spline has " +
          std::to_string(n) + " (0 to " + std::to_string(n - 1) + ")");
    if (pinned_[static_cast<size_t>(a)])
      throw Error(ErrorCode::InvalidArgument,
        "control point " + std::to_string(a) + " is pinned (fixed) and cannot be edited",
        "unpin it first");
    sets.anchors.push_back(a);
  }
  std::sort(sets.anchors.begin(), sets.anchors.end());
  for (size_t k = 1; k < sets.anchors.size(); ++k)
    if (sets.anchors[k] == sets.anchors[k - 1])
      throw Error(ErrorCode::InvalidArgument,
        "anchor " + std::to_string(sets.anchors[k]) + " is given twice");
  Marks inA(scratch_[0]), inD(scratch_[1]);
  for (Index a : sets.anchors)
    inA.set(a);

  auto add = [&](Index p) {
    if (!inA[p] && !inD[p] && !pinned_[static_cast<size_t>(p)])
    {
      inD.set(p);
      sets.derived.push_back(p);
    }
  };
  // S: the points within delta_max of an anchor.
  if (delta_max > 0)
  {
    const auto dist = local_distances(net, sets.anchors, 0, nullptr, delta_max);
    for (const auto& [p, dp] : dist)
      if (dp > 0 && dp <= delta_max && !pinned_[static_cast<size_t>(p)])
        sets.slaves.push_back(p);
    std::sort(sets.slaves.begin(), sets.slaves.end());
    for (Index p : sets.slaves)
      add(p);
  }
  // The type rules (§4.2, Fig. 13) for every point of A and S.
  std::vector<Index> seeds = sets.anchors;
  seeds.insert(seeds.end(), sets.slaves.begin(), sets.slaves.end());
  for (Index p : seeds)
  {
    const int v = net.near_vertex(p);
    if (v >= 0)
    {
      // Corner, edge corner, inner corner, or edge point two steps from v: the conditions
      // t = 0, 1 around v tie all of v's block together; the edge points two steps out also
      // take part in the next condition along their edge, whose row points follow.
      for (Index q : net.vertex_block(v))
      {
        add(q);
        if (net.type(q) == ControlPointType::Edge)
          for (Index c : net.conditions_of(q))
          {
            add(net.conditions()[static_cast<size_t>(c)].point[0]);
            add(net.conditions()[static_cast<size_t>(c)].point[1]);
          }
      }
    }
    else
    {
      // Other edge points: the row points of both their conditions; inner edge points: the
      // point across their edge; interior points: none.
      for (Index c : net.conditions_of(p))
      {
        add(net.conditions()[static_cast<size_t>(c)].point[0]);
        add(net.conditions()[static_cast<size_t>(c)].point[1]);
      }
    }
  }
  std::sort(sets.derived.begin(), sets.derived.end());

  std::vector<Index> key = sets.anchors;
  key.push_back(-1);
  key.insert(key.end(), sets.derived.begin(), sets.derived.end());
  auto it = cache_.find(key);
  last_cached_ = it != cache_.end();
  last_exact_seconds_ = 0;
  if (it == cache_.end())
  {
    if (cache_.size() > 256)
      cache_.clear();
    it = cache_.emplace(key, eliminate(sets.anchors, sets.derived, &last_exact_seconds_)).first;
  }
  sets.derived = it->second.derived;
  sets.constraints = it->second.constraints;
  sets.independent = it->second.independent;
  sets.expansions = it->second.expansions;
  return sets;
}

SplineEditReport SplineEditor::apply(const SplineEdit& edit)
{
  const auto t0 = std::chrono::steady_clock::now();
  const SplineNet& net = spline_.net();
  const int m = spline_.dimension();
  const Eigen::MatrixXd& X = spline_.values();
  switch (edit.op)
  {
    case SplineEditOp::Translate:
      if (edit.by.size() != m)
        throw Error(ErrorCode::InvalidArgument,
          "a translation of this spline needs " + std::to_string(m) + " values, " +
            std::to_string(edit.by.size()) + " were given");
      if (!edit.by.allFinite())
        throw Error(ErrorCode::NonFinite, "the translation is not finite");
      break;
    case SplineEditOp::Rotate:
    case SplineEditOp::Scale:
      if (m != 2)
        throw Error(ErrorCode::InvalidArgument,
          std::string("a ") + to_string(edit.op) +
            " needs a deformation of the plane; this spline has one value per control point");
      if (!edit.center.allFinite() || !std::isfinite(edit.angle_degrees) ||
        !std::isfinite(edit.factor))
        throw Error(ErrorCode::NonFinite, std::string("the ") + to_string(edit.op) +
            "'s centre, angle or factor is not finite");
      if (edit.op == SplineEditOp::Scale && !(edit.factor > 0))
        throw Error(ErrorCode::InvalidArgument,
          "scale factor " + detail::format_number(edit.factor) + " is not positive");
      break;
  }

  // Step 1: the anchors (named, or nearest to the given positions).
  std::vector<Index> anchors = edit.anchors;
  for (const Eigen::Vector2d& x : edit.near)
  {
    if (!x.allFinite())
      throw Error(ErrorCode::NonFinite, "an edit's anchor position is not finite");
    anchors.push_back(nearest_point(x));
  }
  SplineEditReport rep;
  // Step 2 (timing the exact part when it is not cached).
  rep.sets = select(anchors, edit.delta_max);
  rep.cached = last_cached_;
  rep.exact_seconds = last_exact_seconds_;
  const EditSets& sets = rep.sets;

  // Step 3: the new positions p' (Eqs. 24-25).
  Marks inside(scratch_[2]);
  for (Index p : sets.anchors)
    inside.set(p);
  for (Index p : sets.derived)
    inside.set(p);
  const auto d_anchor = local_distances(net, sets.anchors, 0, &inside.storage());
  std::vector<Index> next_to_fixed;
  for (const auto* set : { &sets.anchors, &sets.derived })
    for (Index p : *set)
      for (Index r : net.net_neighbours(p))
        if (!inside[r])
        {
          next_to_fixed.push_back(p);
          break;
        }
  const auto d_fixed = local_distances(net, next_to_fixed, 1, &inside.storage());
  auto theta = [&](Index p) {
    const auto a = d_anchor.find(p);
    const auto f = d_fixed.find(p);
    if (a == d_anchor.end())
      return 0.0;
    if (f == d_fixed.end())
      return 1.0;
    return double(f->second) / double(a->second + f->second);
  };
  const double angle = edit.angle_degrees * M_PI / 180.0;
  auto moved = [&](Index p, double th) -> Eigen::RowVectorXd {
    switch (edit.op)
    {
      case SplineEditOp::Translate:
        return X.row(p) + th * edit.by.transpose();
      case SplineEditOp::Rotate:
      {
        const double a = th * angle;
        const Eigen::Vector2d r = X.row(p).transpose() - edit.center;
        const Eigen::Vector2d q =
          edit.center + Eigen::Vector2d(std::cos(a) * r.x() - std::sin(a) * r.y(),
                          std::sin(a) * r.x() + std::cos(a) * r.y());
        return q.transpose();
      }
      case SplineEditOp::Scale:
      {
        const Eigen::Vector2d r = X.row(p).transpose() - edit.center;
        return (edit.center + std::pow(edit.factor, th) * r).transpose();
      }
    }
    return X.row(p);
  };
  const Index nd = static_cast<Index>(sets.derived.size());
  Eigen::MatrixXd Xa(static_cast<Index>(sets.anchors.size()), m);
  for (size_t k = 0; k < sets.anchors.size(); ++k)
    Xa.row(static_cast<Index>(k)) = moved(sets.anchors[k], 1.0);
  Eigen::MatrixXd Xd(nd, m);
  for (Index k = 0; k < nd; ++k)
    Xd.row(k) = moved(sets.derived[static_cast<size_t>(k)], theta(sets.derived[static_cast<size_t>(k)]));
  if (!Xa.allFinite() || !Xd.allFinite())
    throw Error(ErrorCode::NonFinite, "the edit moves control points to non-finite positions");

  // Step 4: the least-squares positions subject to the independent conditions.
  std::unordered_map<Index, Index> dcol, acol;
  for (Index k = 0; k < nd; ++k)
    dcol[sets.derived[static_cast<size_t>(k)]] = k;
  for (size_t k = 0; k < sets.anchors.size(); ++k)
    acol[sets.anchors[k]] = static_cast<Index>(k);
  const Index mr = static_cast<Index>(sets.independent.size());
  if (mr > 0)
  {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(mr, m);
    for (Index r = 0; r < mr; ++r)
    {
      const QuadCondition& c = net.conditions()[static_cast<size_t>(sets.independent[static_cast<size_t>(r)])];
      for (int k = 0; k < 4; ++k)
      {
        const Index p = c.point[static_cast<size_t>(k)];
        const double w = c.coefficient[static_cast<size_t>(k)];
        if (auto it = dcol.find(p); it != dcol.end())
          trip.emplace_back(r, it->second, w);
        else if (auto ia = acol.find(p); ia != acol.end())
          b.row(r) -= w * Xa.row(ia->second);
        else
          b.row(r) -= w * X.row(p);
      }
    }
    Eigen::SparseMatrix<double> A(mr, nd);
    A.setFromTriplets(trip.begin(), trip.end());
    const Eigen::SparseMatrix<double> AAt = A * A.transpose();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(AAt);
    if (ldlt.info() != Eigen::Success)
      throw Error(ErrorCode::Internal, "the spline editor's normal equations could not be factored");
    const Eigen::MatrixXd y = ldlt.solve(Eigen::MatrixXd(A * Xd - b));
    Xd -= A.transpose() * y;
    if (!Xd.allFinite())
      throw Error(ErrorCode::Internal, "the spline editor's least-squares solve failed");
  }

  // Step 5: commit (with the undo record), then measure E's residual.
  Change ch;
  ch.edit = edit;
  ch.points = sets.anchors;
  ch.points.insert(ch.points.end(), sets.derived.begin(), sets.derived.end());
  ch.before.resize(static_cast<Index>(ch.points.size()), m);
  ch.after.resize(static_cast<Index>(ch.points.size()), m);
  for (size_t k = 0; k < ch.points.size(); ++k)
  {
    ch.before.row(static_cast<Index>(k)) = X.row(ch.points[k]);
    ch.after.row(static_cast<Index>(k)) =
      k < sets.anchors.size() ? Eigen::RowVectorXd(Xa.row(static_cast<Index>(k)))
                              : Eigen::RowVectorXd(Xd.row(static_cast<Index>(k - sets.anchors.size())));
  }
  for (size_t k = 0; k < ch.points.size(); ++k)
  {
    rep.max_move = std::max(rep.max_move, (ch.after.row(static_cast<Index>(k)) - ch.before.row(static_cast<Index>(k))).norm());
    spline_.values().row(ch.points[k]) = ch.after.row(static_cast<Index>(k));
  }
  history_.resize(done_);
  history_.push_back(std::move(ch));
  ++done_;
  for (Index c : sets.constraints)
  {
    const QuadCondition& q = net.conditions()[static_cast<size_t>(c)];
    Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(m);
    for (int k = 0; k < 4; ++k)
      r += q.coefficient[static_cast<size_t>(k)] * spline_.values().row(q.point[static_cast<size_t>(k)]);
    rep.residual = std::max(rep.residual, r.cwiseAbs().maxCoeff());
  }
  rep.seconds = seconds_since(t0);
  return rep;
}

bool SplineEditor::undo()
{
  if (done_ == 0)
    return false;
  const Change& ch = history_[--done_];
  for (size_t k = 0; k < ch.points.size(); ++k)
    spline_.values().row(ch.points[k]) = ch.before.row(static_cast<Index>(k));
  return true;
}

bool SplineEditor::redo()
{
  if (done_ >= history_.size())
    return false;
  const Change& ch = history_[done_++];
  for (size_t k = 0; k < ch.points.size(); ++k)
    spline_.values().row(ch.points[k]) = ch.after.row(static_cast<Index>(k));
  return true;
}

std::vector<SplineEdit> SplineEditor::log() const
{
  std::vector<SplineEdit> out;
  for (size_t k = 0; k < done_; ++k)
    out.push_back(history_[k].edit);
  return out;
}

Index SplineEditor::nearest_point(const Eigen::Vector2d& x) const
{
  const Eigen::MatrixXd& P = spline_.dimension() == 2 ? spline_.values() : spline_.net().nominal();
  Index best = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (Index p = 0; p < P.rows(); ++p)
  {
    const double d2 = (P.row(p).transpose() - x).squaredNorm();
    if (d2 < bd)
    {
      bd = d2;
      best = p;
    }
  }
  return best;
}

} // namespace bary
