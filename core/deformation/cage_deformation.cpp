#include "core/deformation/cage_deformation.h"

#include "core/common/error.h"

#include <string>
#include <vector>

namespace bary
{
namespace
{
void check(Index weight_cols, const Eigen::MatrixXd& C)
{
  if (C.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the deformed control points are empty");
  if (weight_cols != C.rows())
    throw Error(ErrorCode::SizeMismatch,
      "the weights have " + std::to_string(weight_cols) + " columns (control points) but " +
        std::to_string(C.rows()) + " deformed control points were given");
  if (!C.allFinite())
    throw Error(ErrorCode::NonFinite, "the deformed control points contain NaN or infinity");
}
} // namespace

Points deform_points(const DenseWeights& W, const Eigen::MatrixXd& C)
{
  check(W.cols(), C);
  return W * C;
}

Points deform_points(const SparseWeights& W, const Eigen::MatrixXd& C)
{
  check(W.cols(), C);
  return W * C;
}

SparseWeights sparsify_weights(const DenseWeights& W, double threshold, bool renormalize,
  Index* empty_rows)
{
  std::vector<Eigen::Triplet<double>> entries;
  Index empty = 0;
  for (Index p = 0; p < W.rows(); ++p)
  {
    double sum = 0.0;
    const std::size_t first = entries.size();
    for (Index i = 0; i < W.cols(); ++i)
      if (W(p, i) > threshold)
      {
        entries.emplace_back(static_cast<int>(p), static_cast<int>(i), W(p, i));
        sum += W(p, i);
      }
    if (entries.size() == first)
      ++empty;
    else if (renormalize)
      for (std::size_t k = first; k < entries.size(); ++k)
        entries[k] = Eigen::Triplet<double>(entries[k].row(), entries[k].col(), entries[k].value() / sum);
  }
  SparseWeights S(W.rows(), W.cols());
  S.setFromTriplets(entries.begin(), entries.end());
  if (empty_rows)
    *empty_rows = empty;
  return S;
}

} // namespace bary
