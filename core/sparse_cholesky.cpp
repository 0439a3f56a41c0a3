#include "sparse_cholesky.h"

#include "error.h"

#include <Eigen/SparseCholesky>
#ifdef BARYLAB_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>

namespace bary
{
namespace
{

using SparseMatrix = Eigen::SparseMatrix<double>;

#ifdef BARYLAB_HAVE_CHOLMOD
/// Eigen's wrapper with access to the factor, to read its pivots.
class CholmodFactor : public Eigen::CholmodSupernodalLLT<SparseMatrix>
{
public:
  CholmodFactor()
  {
    cholmod().print = 0; // the library never prints; failures are reported by Error
  }
  const cholmod_factor* factor() const { return m_cholmodFactor; }
};
#endif

std::string fmt(double x)
{
  std::ostringstream s;
  s << x;
  return s.str();
}

[[noreturn]] void throw_not_positive_definite(const std::string& detail)
{
  throw Error(ErrorCode::InvalidArgument,
    "the matrix is not positive definite: " + detail +
      ". A Laplacian or stiffness matrix needs at least one fixed (known) vertex in every "
      "connected component, and every vertex must belong to an element");
}

} // namespace

struct SparseCholesky::Impl
{
  Index n = 0;
  Eigen::VectorXd scale; ///< S = diag(A)^-1/2
  double min_pivot = 0.0;
  std::unique_ptr<Eigen::SimplicialLDLT<SparseMatrix>> eigen;
#ifdef BARYLAB_HAVE_CHOLMOD
  std::unique_ptr<CholmodFactor> cholmod;
  mutable std::mutex cholmod_mutex; ///< CHOLMOD's common workspace is not re-entrant
#endif
};

SparseCholesky::SparseCholesky(Backend backend)
  : backend_(backend)
{
  if (backend_ == Backend::Automatic)
    backend_ = cholmod_available() ? Backend::Cholmod : Backend::Eigen;
  else if (backend_ == Backend::Cholmod && !cholmod_available())
    throw Error(ErrorCode::InvalidArgument,
      "the CHOLMOD backend was requested but BaryLab was built without CHOLMOD; use "
      "Backend::Automatic or Backend::Eigen, or rebuild with SuiteSparse's CHOLMOD installed "
      "(BARYLAB_USE_CHOLMOD=ON)");
  else if (backend_ != Backend::Cholmod && backend_ != Backend::Eigen)
    throw Error(ErrorCode::InvalidArgument, "unknown SparseCholesky backend");
}

const char* to_string(SparseCholesky::Backend backend) noexcept
{
  switch (backend)
  {
    case SparseCholesky::Backend::Automatic:
      return "automatic";
    case SparseCholesky::Backend::Cholmod:
      return "cholmod";
    case SparseCholesky::Backend::Eigen:
      return "eigen";
  }
  return "unknown";
}

bool SparseCholesky::cholmod_available() noexcept
{
#ifdef BARYLAB_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

Index SparseCholesky::rows() const noexcept
{
  return impl_ ? impl_->n : 0;
}

double SparseCholesky::min_pivot() const noexcept
{
  return impl_ ? impl_->min_pivot : 0.0;
}

void SparseCholesky::compute(const SparseMatrix& A, const Eigen::VectorXi& row_ids)
{
  impl_.reset();
  if (A.rows() != A.cols())
    throw Error(ErrorCode::SizeMismatch,
      "a Cholesky factorization needs a square matrix, got " + std::to_string(A.rows()) +
        " by " + std::to_string(A.cols()));
  const Index n = A.rows();
  if (n == 0)
    throw Error(ErrorCode::EmptyInput, "the matrix to factor is empty (0 by 0)");
  if (row_ids.size() != 0 && row_ids.size() != n)
    throw Error(ErrorCode::SizeMismatch,
      "row_ids has " + std::to_string(row_ids.size()) + " entries for a matrix of size " +
        std::to_string(n) + " (give n ids or none)");
  // The number messages use for row i.
  auto id = [&row_ids](Index i) {
    return std::to_string(row_ids.size() != 0 ? Index(row_ids(i)) : i);
  };

  // Finite entries and a positive diagonal.
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  for (Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
    {
      if (!std::isfinite(it.value()))
        throw Error(ErrorCode::NonFinite,
          "the matrix has a non-finite entry at (" + id(it.row()) + ", " + id(it.col()) + ")");
      if (it.row() == it.col())
        diagonal(it.row()) += it.value();
    }
  for (Index i = 0; i < n; ++i)
    if (!(diagonal(i) > 0.0))
      throw_not_positive_definite(
        "its diagonal entry (" + id(i) + ", " + id(i) + ") is " + fmt(diagonal(i)) + ", not > 0");

  // Symmetry, relative to sqrt(A_ii A_jj) (which bounds |A_ij| for an SPD matrix).
  {
    const SparseMatrix asymmetry = A - SparseMatrix(A.transpose());
    for (Index j = 0; j < asymmetry.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(asymmetry, j); it; ++it)
        if (std::abs(it.value()) > 1e-10 * std::sqrt(diagonal(it.row()) * diagonal(it.col())))
          throw Error(ErrorCode::InvalidArgument,
            "the matrix is not symmetric: entries (" + id(it.row()) + ", " + id(it.col()) +
              ") and (" + id(it.col()) + ", " + id(it.row()) + ") differ by " + fmt(it.value()) +
              "; a Cholesky factorization needs a symmetric matrix");
  }

  auto impl = std::make_shared<Impl>();
  impl->n = n;
  impl->scale = diagonal.cwiseSqrt().cwiseInverse();
  const SparseMatrix scaled = impl->scale.asDiagonal() * A * impl->scale.asDiagonal();

  // Pivots of the scaled matrix: min_pivot and the (original) row it belongs to.
  double min_pivot = std::numeric_limits<double>::infinity();
  Index min_row = 0;
  auto record = [&](double pivot, Index row) {
    if (pivot < min_pivot)
    {
      min_pivot = pivot;
      min_row = row;
    }
  };

  if (backend_ == Backend::Eigen)
  {
    impl->eigen = std::make_unique<Eigen::SimplicialLDLT<SparseMatrix>>();
    impl->eigen->compute(scaled);
    if (impl->eigen->info() != Eigen::Success)
      throw_not_positive_definite("the LDL^T factorization met a zero pivot");
    const Eigen::VectorXd& D = impl->eigen->vectorD();
    // Eigen factors P A P^-1: pivot k belongs to the original row Pinv(k).
    const auto& pinv = impl->eigen->permutationPinv().indices();
    for (Index k = 0; k < n; ++k)
      record(D(k), pinv.size() == n ? pinv(k) : k);
  }
#ifdef BARYLAB_HAVE_CHOLMOD
  else
  {
    impl->cholmod = std::make_unique<CholmodFactor>();
    impl->cholmod->compute(scaled);
    const cholmod_factor* L = impl->cholmod->factor();
    const int status = impl->cholmod->cholmod().status;
    if (status < 0 || L == nullptr)
      throw Error(status == CHOLMOD_OUT_OF_MEMORY ? ErrorCode::InvalidArgument : ErrorCode::Internal,
        "CHOLMOD failed to factor a " + std::to_string(n) + " by " + std::to_string(n) +
          " matrix (status " + std::to_string(status) +
          (status == CHOLMOD_OUT_OF_MEMORY ? ", out of memory)" : ")"));
    const int* perm = static_cast<const int*>(L->Perm);
    auto original_row = [&](Index k) -> Index { return perm ? perm[k] : k; };
    if (impl->cholmod->info() != Eigen::Success)
    {
      const Index minor = static_cast<Index>(L->minor);
      throw_not_positive_definite("CHOLMOD's LL^T factorization failed at row " +
        (minor < n ? id(original_row(minor)) : std::to_string(minor)));
    }
    const double* x = static_cast<const double*>(L->x);
    if (L->is_super)
    {
      // Supernode s: columns super[s] .. super[s+1]-1 stored as a dense column-major block of
      // pi[s+1]-pi[s] rows at x + px[s]; its diagonal has stride nrows + 1.
      const int* super = static_cast<const int*>(L->super);
      const int* pi = static_cast<const int*>(L->pi);
      const int* px = static_cast<const int*>(L->px);
      for (std::size_t s = 0; s < L->nsuper; ++s)
      {
        const int ncols = super[s + 1] - super[s];
        const int nrows = pi[s + 1] - pi[s];
        for (int j = 0; j < ncols; ++j)
        {
          const double l = x[px[s] + j * (nrows + 1)];
          record(l * l, original_row(super[s] + j));
        }
      }
    }
    else
    {
      const int* p = static_cast<const int*>(L->p);
      for (Index k = 0; k < n; ++k)
      {
        const double l = x[p[k]];
        record(L->is_ll ? l * l : l, original_row(k));
      }
    }
  }
#endif

  const double tolerance = 16.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon();
  if (!(min_pivot > tolerance))
    throw_not_positive_definite("its smallest pivot (after scaling to unit diagonal) is " +
      fmt(min_pivot) + " at row " + id(min_row) + ", not above 16 n eps = " +
      fmt(tolerance) + " (singular or numerically singular)");
  impl->min_pivot = min_pivot;
  impl_ = std::move(impl);
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const
{
  if (!impl_)
    throw Error(ErrorCode::InvalidArgument,
      "SparseCholesky::solve called before a successful compute(A)");
  const Impl& impl = *impl_;
  if (B.rows() != impl.n)
    throw Error(ErrorCode::SizeMismatch,
      "the right-hand side has " + std::to_string(B.rows()) + " rows but the matrix is " +
        std::to_string(impl.n) + " by " + std::to_string(impl.n));
  if (!B.allFinite())
    throw Error(ErrorCode::NonFinite, "the right-hand side contains NaN or infinity");
  if (B.cols() == 0)
    return Eigen::MatrixXd(impl.n, 0);

  const Eigen::MatrixXd scaled_B = impl.scale.asDiagonal() * B;
  Eigen::MatrixXd X;
  if (impl.eigen)
    X = impl.eigen->solve(scaled_B);
#ifdef BARYLAB_HAVE_CHOLMOD
  else
  {
    std::lock_guard<std::mutex> lock(impl.cholmod_mutex);
    X = impl.cholmod->solve(scaled_B);
    if (impl.cholmod->info() != Eigen::Success)
      throw Error(ErrorCode::Internal, "CHOLMOD's triangular solve failed (out of memory?)");
  }
#endif
  return impl.scale.asDiagonal() * X;
}

} // namespace bary
