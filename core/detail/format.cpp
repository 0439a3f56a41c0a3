#include "core/detail/format.h"

#include <sstream>

namespace bary::detail
{

std::string format_number(double x, int precision)
{
  std::ostringstream s;
  s.precision(precision);
  s << x;
  return s.str();
}

std::string format_point(const double* x, Index n, int precision)
{
  std::ostringstream s;
  s.precision(precision);
  s << "(";
  for (Index k = 0; k < n; ++k)
    s << (k ? ", " : "") << x[k];
  s << ")";
  return s.str();
}

std::string format_row(const Eigen::MatrixXd& V, Index i, int precision)
{
  std::ostringstream s;
  s.precision(precision);
  s << "(";
  for (Index k = 0; k < V.cols(); ++k)
    s << (k ? ", " : "") << V(i, k);
  s << ")";
  return s.str();
}

std::string format_index_row(const Eigen::MatrixXi& T, Index i)
{
  std::ostringstream s;
  for (Index k = 0; k < T.cols(); ++k)
    s << (k ? ", " : "") << T(i, k);
  return s.str();
}

} // namespace bary::detail
