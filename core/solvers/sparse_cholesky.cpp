#include "core/solvers/sparse_cholesky.h"

#include "core/detail/format.h"
#include "core/common/error.h"
#include "core/detail/huge_pages.h"
#include "core/detail/simd.h"

#include <Eigen/Dense>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#ifdef BARYLAB_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

#if BARY_HAVE_AVX2_DISPATCH
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <mutex>
#include <type_traits>
#include <utility>
#include <string>
#include <vector>

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

[[noreturn]] void throw_not_positive_definite(const std::string& detail)
{
  throw Error(ErrorCode::InvalidArgument,
    "the matrix is not positive definite: " + detail +
      ". A Laplacian or stiffness matrix needs at least one fixed (known) vertex in every "
      "connected component, and every vertex must belong to an element");
}

/// Makes Eigen's matrix products single-threaded in the calling thread while it lives: Eigen
/// parallelizes large products with OpenMP when called outside a parallel region (or inside one
/// of a single thread), with cache blocking that depends on the thread count, so the rounding of
/// a factorization would depend on it. Sets the calling thread's OpenMP nthreads ICV to 1 (other
/// threads are unaffected) and restores it. sequential() is false only when the application
/// forced Eigen's thread count (Eigen::setNbThreads); the callers then use coefficient-based
/// products, which never run in parallel.
class SingleThreadedProducts
{
public:
  SingleThreadedProducts()
  {
#ifdef _OPENMP
    saved_ = omp_get_max_threads();
    omp_set_num_threads(1);
#endif
    sequential_ = Eigen::nbThreads() == 1;
  }
  ~SingleThreadedProducts()
  {
#ifdef _OPENMP
    omp_set_num_threads(saved_);
#endif
  }
  SingleThreadedProducts(const SingleThreadedProducts&) = delete;
  SingleThreadedProducts& operator=(const SingleThreadedProducts&) = delete;
  bool sequential() const noexcept { return sequential_; }

private:
  int saved_ = 1;
  bool sequential_ = true;
};

#ifdef BARYLAB_HAVE_CHOLMOD
/// cholmod_start / cholmod_finish around one call.
class CholmodCommon
{
public:
  CholmodCommon()
  {
    cholmod_start(&common_);
    common_.print = 0;
  }
  ~CholmodCommon() { cholmod_finish(&common_); }
  CholmodCommon(const CholmodCommon&) = delete;
  CholmodCommon& operator=(const CholmodCommon&) = delete;
  cholmod_common* get() { return &common_; }

private:
  cholmod_common common_;
};
#endif

/// An allocator that leaves new elements uninitialized (default-initialized): the factor's
/// values are first written by the numeric factorization, supernode by supernode, so zeroing
/// the whole array beforehand only costs a pass over memory (and its page faults) up front.
template<class T>
struct UninitializedAllocator : std::allocator<T>
{
  template<class U>
  struct rebind
  {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() noexcept = default;
  template<class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept
  {
  }
  template<class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>)
  {
    ::new (static_cast<void*>(p)) U;
  }
  template<class U, class... Args>
  void construct(U* p, Args&&... args)
  {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

using FactorValues = std::vector<double, UninitializedAllocator<double>>;

using DenseBlock = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
using ConstDenseBlock = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

/// A supernodal LL^T factor of P M~ P^T, where M is the factored matrix (A, or a principal
/// submatrix of A) and M~ = S M S its scaling to unit diagonal. Supernode s holds the columns
/// super[s] .. super[s+1]-1; its rows (the columns' own rows first, then the rows below in
/// increasing order) are rows[row_start[s] .. row_start[s+1]), and its values a dense
/// column-major block of (#rows) x (#columns) at values + value_start[s] (the upper triangle of
/// the diagonal block is unused). perm[k] is the row of M eliminated k-th.
struct SupernodalFactor
{
  Index n = 0;
  int supernodes = 0;
  std::vector<int> super, row_start, rows, perm;
  std::vector<std::ptrdiff_t> value_start;
  FactorValues values;        ///< written by supernodal_numeric
  std::size_t max_update = 0; ///< bound on the entries of one descendant's update
  double flops = 0.0;         ///< sum of the squared column counts
};

/// How the factor's columns relate to the matrix A whose (principal sub)matrix is factored:
/// column k of the factor is A's column source[k].
struct FactorColumns
{
  std::vector<int> source;
  /// The entries of P M P^T on and below the diagonal, column by column: those of factor column
  /// k are entry_row / entry_value[entry_start[k] .. entry_start[k + 1]), its factor row and the
  /// index of its value in A's value array, the diagonal first (built by the symbolic analysis,
  /// read by the numeric factorization's assembly).
  std::vector<int> entry_start;
  std::vector<int, UninitializedAllocator<int>> entry_row, entry_value;
};

/// Relaxed supernode amalgamation parameters (CHOLMOD's defaults): supernodes of up to
/// relax_columns[0] columns always merge with their parent; up to relax_columns[1] / [2] columns
/// when at most relax_zeros[0] / [1] of the merged entries are explicit zeros; any size below
/// relax_zeros[2].
constexpr int relax_columns[3] = { 4, 16, 48 };
constexpr double relax_zeros[3] = { 0.8, 0.1, 0.05 };

/// Symbolic analysis of the supernodal factorization of M = A(sub, sub) (M = A when @p sub is
/// empty) with the elimination order @p order (order[k]: the row of M eliminated k-th; m
/// entries), which is then postordered: elimination tree (Liu's algorithm), postorder, column
/// counts (Gilbert, Ng & Peyton 1994, as in Davis's CSparse), fundamental supernodes, relaxed
/// amalgamation (as in CHOLMOD) and the supernodes' row structures; @p columns receives each
/// factor column's A column and its entries on and below the diagonal. A must store both
/// triangles of a symmetric pattern (an entry stored on one side only is used where it falls on
/// or below the diagonal of P M P^T).
SupernodalFactor supernodal_symbolic(const SparseMatrix& A, const std::vector<int>& sub,
  const int* order, Index m, FactorColumns& columns, FactorValues&& recycled)
{
  const Index nA = A.rows();
  const auto mu = static_cast<std::size_t>(m);
  // Nodes in elimination order: node k is A's row source0[k].
  std::vector<int> source0(mu), node0(static_cast<std::size_t>(nA), -1);
  for (Index k = 0; k < m; ++k)
  {
    const int r = order[k];
    const int a = sub.empty() ? r : sub[static_cast<std::size_t>(r)];
    source0[static_cast<std::size_t>(k)] = a;
    node0[static_cast<std::size_t>(a)] = static_cast<int>(k);
  }
  // M's graph in node numbering, read from A once (the passes below read it several times),
  // split into the neighbours eliminated before each node (the elimination tree reads those) and
  // after it (the column counts and the row structures read those).
  // Written without branches (which neighbour goes where is unpredictable) into per-thread
  // buffers that only grow (A's nonzeros bound either half, even for a pattern stored on one
  // side only).
  // The later neighbours' values (their index in A's value array) and each node's diagonal
  // entry are recorded too, for the numeric factorization's assembly.
  thread_local std::vector<int, UninitializedAllocator<int>> lower, upper, upper_value;
  const auto bound = static_cast<std::size_t>(A.nonZeros()) + 1;
  if (lower.size() < bound)
  {
    lower.resize(bound);
    upper.resize(bound);
    upper_value.resize(bound);
  }
  std::vector<int> lower_start(mu + 1), upper_start(mu + 1), diagonal_value(mu, -1);
  {
    int nl = 0, nu = 0;
    int* lo = lower.data();
    int* up = upper.data();
    int* up_value = upper_value.data();
    const double* values = A.valuePtr();
    for (Index k = 0; k < m; ++k)
    {
      lower_start[static_cast<std::size_t>(k)] = nl;
      upper_start[static_cast<std::size_t>(k)] = nu;
      const int kk = static_cast<int>(k);
      for (SparseMatrix::InnerIterator it(A, source0[static_cast<std::size_t>(k)]); it; ++it)
      {
        const int i = node0[static_cast<std::size_t>(it.row())]; // -1 outside M
        const int q = static_cast<int>(&it.value() - values);
        lo[nl] = i;
        up[nu] = i;
        up_value[nu] = q;
        nl += (i >= 0) & (i < kk);
        nu += i > kk;
        if (i == kk)
          diagonal_value[static_cast<std::size_t>(k)] = q;
      }
    }
    lower_start[mu] = nl;
    upper_start[mu] = nu;
  }
  auto for_each_earlier = [&](int k, auto&& visit) {
    const int end = lower_start[static_cast<std::size_t>(k) + 1];
    for (int q = lower_start[static_cast<std::size_t>(k)]; q < end; ++q)
      visit(lower[static_cast<std::size_t>(q)]);
  };
  auto for_each_later = [&](int k, auto&& visit) {
    const int end = upper_start[static_cast<std::size_t>(k) + 1];
    for (int q = upper_start[static_cast<std::size_t>(k)]; q < end; ++q)
      visit(upper[static_cast<std::size_t>(q)]);
  };

  // 1. Elimination tree.
  std::vector<int> parent(mu, -1), ancestor(mu, -1);
  for (int k = 0; k < static_cast<int>(m); ++k)
    for_each_earlier(k, [&](int i) {
      while (i != -1 && i < k)
      {
        const int next = ancestor[static_cast<std::size_t>(i)];
        ancestor[static_cast<std::size_t>(i)] = k;
        if (next == -1)
          parent[static_cast<std::size_t>(i)] = k;
        i = next;
      }
    });

  // 2. Postorder (children visited in increasing order).
  std::vector<int> head(mu, -1), next(mu, -1), post(mu), stack(mu);
  for (int j = static_cast<int>(m) - 1; j >= 0; --j)
  {
    const int p = parent[static_cast<std::size_t>(j)];
    if (p != -1)
    {
      next[static_cast<std::size_t>(j)] = head[static_cast<std::size_t>(p)];
      head[static_cast<std::size_t>(p)] = j;
    }
  }
  {
    int t = 0;
    for (int root = 0; root < static_cast<int>(m); ++root)
    {
      if (parent[static_cast<std::size_t>(root)] != -1)
        continue;
      int top = 0;
      stack[0] = root;
      while (top >= 0)
      {
        const int p = stack[static_cast<std::size_t>(top)];
        const int child = head[static_cast<std::size_t>(p)];
        if (child == -1)
        {
          --top;
          post[static_cast<std::size_t>(t++)] = p;
        }
        else
        {
          head[static_cast<std::size_t>(p)] = next[static_cast<std::size_t>(child)];
          stack[static_cast<std::size_t>(++top)] = child;
        }
      }
    }
  }

  // 3. Column counts (CSparse's cs_counts for L L^T = A).
  std::vector<int> count(mu), first(mu, -1), max_first(mu, -1), previous_leaf(mu, -1), set(mu);
  for (Index k = 0; k < m; ++k)
  {
    int j = post[static_cast<std::size_t>(k)];
    count[static_cast<std::size_t>(j)] = first[static_cast<std::size_t>(j)] == -1 ? 1 : 0;
    for (; j != -1 && first[static_cast<std::size_t>(j)] == -1; j = parent[static_cast<std::size_t>(j)])
      first[static_cast<std::size_t>(j)] = static_cast<int>(k);
  }
  for (Index i = 0; i < m; ++i)
    set[static_cast<std::size_t>(i)] = static_cast<int>(i);
  for (Index k = 0; k < m; ++k)
  {
    const int j = post[static_cast<std::size_t>(k)];
    const auto ju = static_cast<std::size_t>(j);
    if (parent[ju] != -1)
      --count[static_cast<std::size_t>(parent[ju])];
    for_each_later(j, [&](int i) {
      const auto iu = static_cast<std::size_t>(i);
      // Is j a leaf of the i-th row subtree?
      if (first[ju] <= max_first[iu])
        return;
      max_first[iu] = first[ju];
      const int previous = previous_leaf[iu];
      previous_leaf[iu] = j;
      ++count[ju];
      if (previous == -1)
        return;
      // Subsequent leaf: the least common ancestor of the previous leaf and j overlaps.
      int q = previous;
      while (q != set[static_cast<std::size_t>(q)])
        q = set[static_cast<std::size_t>(q)];
      for (int v = previous; v != q;)
      {
        const int up = set[static_cast<std::size_t>(v)];
        set[static_cast<std::size_t>(v)] = q;
        v = up;
      }
      --count[static_cast<std::size_t>(q)];
    });
    if (parent[ju] != -1)
      set[ju] = parent[ju];
  }
  for (Index k = 0; k < m; ++k)
  {
    const int j = post[static_cast<std::size_t>(k)];
    const int p = parent[static_cast<std::size_t>(j)];
    if (p != -1)
      count[static_cast<std::size_t>(p)] += count[static_cast<std::size_t>(j)];
  }

  // 4. Relabel in postorder: factor column t is node post[t].
  std::vector<int> relabel(mu);
  for (Index t = 0; t < m; ++t)
    relabel[static_cast<std::size_t>(post[static_cast<std::size_t>(t)])] = static_cast<int>(t);
  SupernodalFactor f;
  f.n = m;
  f.perm.resize(mu);
  columns.source.resize(mu);
  std::vector<int> tparent(mu), tcount(mu), children(mu, 0);
  for (Index t = 0; t < m; ++t)
  {
    const int j = post[static_cast<std::size_t>(t)];
    const auto ju = static_cast<std::size_t>(j);
    f.perm[static_cast<std::size_t>(t)] = order[j];
    columns.source[static_cast<std::size_t>(t)] = source0[ju];
    tparent[static_cast<std::size_t>(t)] = parent[ju] == -1 ? -1 : relabel[static_cast<std::size_t>(parent[ju])];
    tcount[static_cast<std::size_t>(t)] = count[ju];
    f.flops += static_cast<double>(count[ju]) * count[ju];
  }
  for (Index t = 0; t < m; ++t)
    if (tparent[static_cast<std::size_t>(t)] != -1)
      ++children[static_cast<std::size_t>(tparent[static_cast<std::size_t>(t)])];
  // The entries on and below the diagonal per factor column (the later neighbours, relabelled).
  columns.entry_start.resize(mu + 1);
  const std::size_t listed = static_cast<std::size_t>(upper_start[mu]) + mu;
  if (columns.entry_row.size() < listed)
  {
    columns.entry_row.resize(listed);
    columns.entry_value.resize(listed);
  }
  {
    int e = 0;
    int* entry_row = columns.entry_row.data();
    int* entry_value = columns.entry_value.data();
    for (Index t = 0; t < m; ++t)
    {
      const int j = post[static_cast<std::size_t>(t)];
      columns.entry_start[static_cast<std::size_t>(t)] = e;
      const int diagonal = diagonal_value[static_cast<std::size_t>(j)];
      if (diagonal >= 0)
      {
        entry_row[e] = static_cast<int>(t);
        entry_value[e++] = diagonal;
      }
      const int end = upper_start[static_cast<std::size_t>(j) + 1];
      for (int q = upper_start[static_cast<std::size_t>(j)]; q < end; ++q)
      {
        entry_row[e] = relabel[static_cast<std::size_t>(upper[static_cast<std::size_t>(q)])];
        entry_value[e++] = upper_value[static_cast<std::size_t>(q)];
      }
    }
    columns.entry_start[mu] = e;
  }

  // 5. Fundamental supernodes: chains t -> t+1 (only child) with nested column structures.
  std::vector<int> fsuper;
  for (Index t = 0; t < m; ++t)
  {
    const auto tu = static_cast<std::size_t>(t);
    const bool continues = t > 0 && tparent[tu - 1] == static_cast<int>(t) &&
      tcount[tu - 1] == tcount[tu] + 1 && children[tu] == 1;
    if (!continues)
      fsuper.push_back(static_cast<int>(t));
  }
  const int nf = static_cast<int>(fsuper.size());
  fsuper.push_back(static_cast<int>(m));
  std::vector<int> fsuper_of(mu);
  for (int s = 0; s < nf; ++s)
    for (int t = fsuper[static_cast<std::size_t>(s)]; t < fsuper[static_cast<std::size_t>(s) + 1]; ++t)
      fsuper_of[static_cast<std::size_t>(t)] = s;

  // 6. Relaxed amalgamation: merge a supernode into the next one when that is its parent and
  //    the merged block has few explicit zeros.
  std::vector<int> merged(static_cast<std::size_t>(nf), -1), width(static_cast<std::size_t>(nf)),
    height(static_cast<std::size_t>(nf)), sparent(static_cast<std::size_t>(nf));
  std::vector<double> zeros(static_cast<std::size_t>(nf), 0.0);
  for (int s = 0; s < nf; ++s)
  {
    const auto su = static_cast<std::size_t>(s);
    width[su] = fsuper[su + 1] - fsuper[su];
    height[su] = tcount[static_cast<std::size_t>(fsuper[su])];
    const int p = tparent[static_cast<std::size_t>(fsuper[su + 1] - 1)];
    sparent[su] = p == -1 ? -1 : fsuper_of[static_cast<std::size_t>(p)];
  }
  for (int s = nf - 2; s >= 0; --s)
  {
    const auto su = static_cast<std::size_t>(s);
    int p = sparent[su];
    if (p == -1)
      continue;
    while (merged[static_cast<std::size_t>(p)] != -1)
      p = merged[static_cast<std::size_t>(p)];
    if (p != s + 1)
      continue;
    const auto pu = static_cast<std::size_t>(p);
    const int w = width[su] + width[pu];
    const double new_zeros = static_cast<double>(width[su]) * (height[pu] + width[su] - height[su]);
    const double total_zeros = zeros[su] + zeros[pu] + new_zeros;
    bool merge = w <= relax_columns[0] || new_zeros == 0.0;
    if (!merge)
    {
      const double xw = w;
      const double z = total_zeros / (xw * (xw + 1.0) / 2.0 + xw * (height[pu] - width[pu]));
      merge = (w <= relax_columns[1] && z < relax_zeros[0]) ||
        (w <= relax_columns[2] && z < relax_zeros[1]) || z < relax_zeros[2];
    }
    if (merge)
    {
      zeros[su] = total_zeros;
      merged[pu] = s;
      height[su] = width[su] + height[pu];
      width[su] = w;
    }
  }
  std::vector<int> super_of(mu);
  std::size_t structure = 0; // entries of the supernodes' row structures
  for (int s = 0; s < nf; ++s)
    if (merged[static_cast<std::size_t>(s)] == -1)
    {
      structure += static_cast<std::size_t>(height[static_cast<std::size_t>(s)]);
      const int begin = fsuper[static_cast<std::size_t>(s)];
      const int end = begin + width[static_cast<std::size_t>(s)];
      for (int t = begin; t < end; ++t)
        super_of[static_cast<std::size_t>(t)] = f.supernodes;
      f.super.push_back(begin);
      ++f.supernodes;
    }
  f.super.push_back(static_cast<int>(m));

  // 7. Row structures, by the row subtrees of L (as CHOLMOD's super_symbolic does): row k of L
  //    is nonzero in the columns on the etree paths from each earlier neighbour of k up to k,
  //    so walking up the supernodal tree from the supernode of each earlier neighbour until a
  //    supernode already met for k (k's own is met first) lists every supernode whose
  //    structure holds k, once. Rows k taken in increasing order come out sorted, and the
  //    sizes are known: a fundamental supernode's height is its first column's count, and a
  //    merge adds the child's columns to the parent's structure (step 6).
  const int ns = f.supernodes;
  f.row_start.assign(static_cast<std::size_t>(ns) + 1, 0);
  f.value_start.assign(static_cast<std::size_t>(ns) + 1, 0);
  {
    int t = 0;
    for (int s = 0; s < nf; ++s)
      if (merged[static_cast<std::size_t>(s)] == -1)
      {
        const auto tu = static_cast<std::size_t>(t);
        const int h = height[static_cast<std::size_t>(s)], w = width[static_cast<std::size_t>(s)];
        f.row_start[tu + 1] = f.row_start[tu] + h;
        f.value_start[tu + 1] = f.value_start[tu] + static_cast<std::ptrdiff_t>(h) * w;
        const auto b = static_cast<std::size_t>(h - w);
        f.max_update = std::max(f.max_update, b * b);
        ++t;
      }
  }
  f.rows.resize(structure);
  {
    std::vector<int> up(static_cast<std::size_t>(ns)), met(static_cast<std::size_t>(ns), -1),
      fill(static_cast<std::size_t>(ns));
    int* rows = f.rows.data();
    for (int s = 0; s < ns; ++s)
    {
      const auto su = static_cast<std::size_t>(s);
      const int p = tparent[static_cast<std::size_t>(f.super[su + 1] - 1)];
      up[su] = p == -1 ? -1 : super_of[static_cast<std::size_t>(p)];
      int at = f.row_start[su];
      for (int c = f.super[su]; c < f.super[su + 1]; ++c)
        rows[at++] = c;
      fill[su] = at;
    }
    for (int k = 0; k < static_cast<int>(m); ++k)
    {
      met[static_cast<std::size_t>(super_of[static_cast<std::size_t>(k)])] = k;
      for_each_earlier(post[static_cast<std::size_t>(k)], [&](int i) {
        int s = super_of[static_cast<std::size_t>(relabel[static_cast<std::size_t>(i)])];
        while (s != -1 && met[static_cast<std::size_t>(s)] != k)
        {
          met[static_cast<std::size_t>(s)] = k;
          int& at = fill[static_cast<std::size_t>(s)];
          if (at < f.row_start[static_cast<std::size_t>(s) + 1])
            rows[at] = k;
          ++at;
          s = up[static_cast<std::size_t>(s)];
        }
      });
    }
    for (int s = 0; s < ns; ++s)
      if (fill[static_cast<std::size_t>(s)] != f.row_start[static_cast<std::size_t>(s) + 1])
        throw Error(ErrorCode::Internal,
          "the supernodal symbolic analysis found a row structure of another size than its "
          "column counts");
  }
  // Uninitialized: in the storage of a factor this one replaces when it is large enough (its
  // pages already mapped), else new, advised huge pages before the numeric factorization's
  // first touch.
  const auto entries = static_cast<std::size_t>(f.value_start[static_cast<std::size_t>(ns)]);
  if (recycled.capacity() >= entries)
    f.values = std::move(recycled);
  else
  {
    // With room to grow by a quarter when it is recycled (an active set's free set grows): the
    // room is address space only, its pages untouched.
    const std::size_t capacity = recycled.capacity() > 0 ? entries + entries / 4 : entries;
    recycled = FactorValues();
    f.values.reserve(capacity);
    detail::advise_huge_pages(f.values.data(), capacity * sizeof(double));
  }
  f.values.resize(entries);
  return f;
}

#if BARY_HAVE_AVX2_DISPATCH
/// Four rows at @p p: all of them (Full), or the lanes @p mask selects (the others are neither
/// read nor written).
template<bool Full>
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE __m256d load_rows(const double* p, __m256i mask)
{
  if constexpr (Full)
  {
    (void)mask;
    return _mm256_loadu_pd(p);
  }
  else
    return _mm256_maskload_pd(p, mask);
}
template<bool Full>
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void store_rows(double* p, __m256i mask, __m256d v)
{
  if constexpr (Full)
  {
    (void)mask;
    _mm256_storeu_pd(p, v);
  }
  else
    _mm256_maskstore_pd(p, mask, v);
}

/// One panel of C = X Y^T (or C -= X Y^T when @p Subtract): 8 rows starting at X and C (Full),
/// or the rows that @p m0 (first four) and @p m1 (last four) select, and the W <= 4 columns
/// starting at Y, C (X, Y column-major with k columns). Products summed over k in order with
/// FMA in registers, then stored (or subtracted from C once).
template<int W, bool Subtract, bool Full>
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void nt_panel_avx2(const double* X, std::ptrdiff_t ldx,
  const double* Y, std::ptrdiff_t ldy, __m256i m0, __m256i m1, int k, double* C, std::ptrdiff_t ldc)
{
  __m256d lo[W], hi[W];
  for (int q = 0; q < W; ++q)
    lo[q] = hi[q] = _mm256_setzero_pd();
  for (int p = 0; p < k; ++p, X += ldx, Y += ldy)
  {
    const __m256d a0 = load_rows<Full>(X, m0), a1 = load_rows<Full>(X + 4, m1);
    for (int q = 0; q < W; ++q)
    {
      const __m256d b = _mm256_broadcast_sd(Y + q);
      lo[q] = _mm256_fmadd_pd(a0, b, lo[q]);
      hi[q] = _mm256_fmadd_pd(a1, b, hi[q]);
    }
  }
  for (int q = 0; q < W; ++q)
  {
    double* c = C + q * ldc;
    if (Subtract)
    {
      lo[q] = _mm256_sub_pd(load_rows<Full>(c, m0), lo[q]);
      hi[q] = _mm256_sub_pd(load_rows<Full>(c + 4, m1), hi[q]);
    }
    store_rows<Full>(c, m0, lo[q]);
    store_rows<Full>(c + 4, m1, hi[q]);
  }
}

/// Rows [i0, m) of C = X Y^T (Subtract: C -= X Y^T) for the W <= 4 columns at Y and C, in
/// panels of 8 rows.
template<int W, bool Subtract>
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void nt_columns_avx2(const double* X, std::ptrdiff_t ldx,
  const double* Y, std::ptrdiff_t ldy, int i0, int m, int k, double* C, std::ptrdiff_t ldc)
{
  const __m256i all = _mm256_set1_epi64x(-1);
  int i = i0;
  for (; i + 8 <= m; i += 8)
    nt_panel_avx2<W, Subtract, true>(X + i, ldx, Y, ldy, all, all, k, C + i, ldc);
  if (i < m)
  {
    // 1-7 rows left: lanes below the count.
    const int rows = m - i;
    const __m256i lane = _mm256_set_epi64x(3, 2, 1, 0);
    const __m256i m0 = _mm256_cmpgt_epi64(_mm256_set1_epi64x(rows), lane);
    const __m256i m1 = _mm256_cmpgt_epi64(_mm256_set1_epi64x(rows - 4), lane);
    nt_panel_avx2<W, Subtract, false>(X + i, ldx, Y, ldy, m0, m1, k, C + i, ldc);
  }
}

/// The update of a descendant supernode, C = X X1^T: X is m2 x k (column-major, leading
/// dimension ldx), X1 its first m1 rows, C m2 x m1 (leading dimension m2). Only the entries
/// C(i, j) with i >= j rounded down to a multiple of 4 are computed (the scatter reads i >= j).
/// Compiled for AVX2 + FMA: it must only run where simd_level() says so.
BARY_TARGET_AVX2 BARY_NOINLINE void descendant_update_avx2(
  const double* X, std::ptrdiff_t ldx, int m2, int m1, int k, double* C)
{
  int j = 0;
  for (; j + 4 <= m1; j += 4)
    nt_columns_avx2<4, false>(X, ldx, X + j, ldx, j, m2, k, C + j * std::ptrdiff_t{ m2 }, m2);
  for (; j < m1; ++j)
    nt_columns_avx2<1, false>(X, ldx, X + j, ldx, j, m2, k, C + j * std::ptrdiff_t{ m2 }, m2);
}

/// The columns [j, j + jb) of a supernode's panel P (h rows, leading dimension h) once the
/// finished columns' product has been subtracted: each minus its block's earlier columns, then
/// its pivot's square root and the rows below divided by it. Returns -1, or the column whose
/// pivot is not positive (or NaN). Inlined into each instruction set's panel_cholesky.
BARY_ALWAYS_INLINE int factor_block_columns(double* P, int h, int j, int jb)
{
  const std::ptrdiff_t ld = h;
  for (int c = j; c < j + jb; ++c)
  {
    double* column = P + c * ld;
    for (int q = j; q < c; ++q)
    {
      const double* finished = P + q * ld;
      const double lcq = finished[c];
      for (int i = c; i < h; ++i)
        column[i] -= finished[i] * lcq;
    }
    const double pivot = column[c];
    if (!(pivot > 0.0))
      return c;
    const double diagonal = std::sqrt(pivot);
    column[c] = diagonal;
    for (int i = c + 1; i < h; ++i)
      column[i] /= diagonal;
  }
  return -1;
}

/// Cholesky factorization of a supernode's panel in place: P is h x w (column-major, leading
/// dimension h, h >= w) holding the updated columns; on return its top w x w block is L11 (lower
/// triangle) and the rows below are L21 = P21 L11^-T. Left-looking by blocks of 4 columns: the
/// block's columns minus the product of the finished columns (COLUMNS: an instruction set's
/// FMA panels, nt_columns_avx2 or nt_columns_avx512), then the block itself column by column.
/// The function NAME returns -1, or the column whose pivot is not positive (or NaN); it is
/// compiled for TARGET and must only run where that instruction set is enabled. (A macro: one
/// body, one function per instruction set, since GCC's target attribute cannot vary with a
/// template argument.)
#define BARY_DEFINE_PANEL_CHOLESKY(NAME, TARGET, COLUMNS)                                          \
  TARGET BARY_NOINLINE int NAME(double* P, int h, int w)                                          \
  {                                                                                               \
    const std::ptrdiff_t ld = h;                                                                  \
    for (int j = 0; j < w; j += 4)                                                                \
    {                                                                                             \
      const int jb = std::min(4, w - j);                                                          \
      double* block = P + j * ld;                                                                 \
      if (j > 0)                                                                                  \
        switch (jb)                                                                               \
        {                                                                                         \
          case 4: COLUMNS<4, true>(P, ld, P + j, ld, j, h, j, block, ld); break;                  \
          case 3: COLUMNS<3, true>(P, ld, P + j, ld, j, h, j, block, ld); break;                  \
          case 2: COLUMNS<2, true>(P, ld, P + j, ld, j, h, j, block, ld); break;                  \
          default: COLUMNS<1, true>(P, ld, P + j, ld, j, h, j, block, ld); break;                 \
        }                                                                                         \
      const int failed = factor_block_columns(P, h, j, jb);                                       \
      if (failed >= 0)                                                                            \
        return failed;                                                                            \
    }                                                                                             \
    return -1;                                                                                    \
  }
BARY_DEFINE_PANEL_CHOLESKY(panel_cholesky_avx2, BARY_TARGET_AVX2, nt_columns_avx2)
#endif

#if BARY_HAVE_AVX2_DISPATCH
/// The AVX-512 variants of the kernels above (used where detail::avx512_enabled()): panels of
/// 16 rows (two 8-lane vectors) by W <= 8 columns, tails by lane masks. Each entry is summed over
/// k in the same order with the same FMAs as in nt_panel_avx2, so the results are the same bit
/// for bit; only more entries share an instruction.
template<int R, int W, bool Subtract, bool Full>
BARY_TARGET_AVX512 BARY_ALWAYS_INLINE void nt_panel_avx512(const double* X, std::ptrdiff_t ldx,
  const double* Y, std::ptrdiff_t ldy, __mmask8 m0, __mmask8 m1, int k, double* C, std::ptrdiff_t ldc)
{
  __m512d acc[R][W];
  for (int r = 0; r < R; ++r)
    for (int q = 0; q < W; ++q)
      acc[r][q] = _mm512_setzero_pd();
  const __mmask8 mask[2] = { m0, m1 };
  for (int p = 0; p < k; ++p, X += ldx, Y += ldy)
  {
    __m512d a[R];
    for (int r = 0; r < R; ++r)
      a[r] = Full ? _mm512_loadu_pd(X + 8 * r) : _mm512_maskz_loadu_pd(mask[r], X + 8 * r);
    for (int q = 0; q < W; ++q)
    {
      const __m512d b = _mm512_set1_pd(Y[q]);
      for (int r = 0; r < R; ++r)
        acc[r][q] = _mm512_fmadd_pd(a[r], b, acc[r][q]);
    }
  }
  for (int q = 0; q < W; ++q)
  {
    double* c = C + q * ldc;
    for (int r = 0; r < R; ++r)
    {
      __m512d v = acc[r][q];
      if (Subtract)
        v = _mm512_sub_pd(
          Full ? _mm512_loadu_pd(c + 8 * r) : _mm512_maskz_loadu_pd(mask[r], c + 8 * r), v);
      if (Full)
        _mm512_storeu_pd(c + 8 * r, v);
      else
        _mm512_mask_storeu_pd(c + 8 * r, mask[r], v);
    }
  }
}

/// Rows [i0, m) of C = X Y^T (Subtract: C -= X Y^T) for the W <= 8 columns at Y and C, in
/// panels of 16 rows, the last 1-15 rows by masks.
template<int W, bool Subtract>
BARY_TARGET_AVX512 BARY_ALWAYS_INLINE void nt_columns_avx512(const double* X, std::ptrdiff_t ldx,
  const double* Y, std::ptrdiff_t ldy, int i0, int m, int k, double* C, std::ptrdiff_t ldc)
{
  int i = i0;
  for (; i + 16 <= m; i += 16)
    nt_panel_avx512<2, W, Subtract, true>(X + i, ldx, Y, ldy, 0xFF, 0xFF, k, C + i, ldc);
  const int rows = m - i;
  if (rows > 8)
    nt_panel_avx512<2, W, Subtract, false>(X + i, ldx, Y, ldy, 0xFF,
      static_cast<__mmask8>((1u << (rows - 8)) - 1u), k, C + i, ldc);
  else if (rows > 0)
    nt_panel_avx512<1, W, Subtract, false>(X + i, ldx, Y, ldy,
      static_cast<__mmask8>((1u << rows) - 1u), 0, k, C + i, ldc);
}

/// descendant_update_avx2 with the 512-bit panels, 8 columns at a time (the entries C(i, j) with
/// i >= j rounded down to a multiple of 8 are computed).
BARY_TARGET_AVX512 BARY_NOINLINE void descendant_update_avx512(
  const double* X, std::ptrdiff_t ldx, int m2, int m1, int k, double* C)
{
  int j = 0;
  for (; j + 8 <= m1; j += 8)
    nt_columns_avx512<8, false>(X, ldx, X + j, ldx, j, m2, k, C + j * std::ptrdiff_t{ m2 }, m2);
  double* Cj = C + j * std::ptrdiff_t{ m2 };
  const double* Xj = X + j;
  switch (m1 - j)
  {
    case 7: nt_columns_avx512<7, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    case 6: nt_columns_avx512<6, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    case 5: nt_columns_avx512<5, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    case 4: nt_columns_avx512<4, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    case 3: nt_columns_avx512<3, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    case 2: nt_columns_avx512<2, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    case 1: nt_columns_avx512<1, false>(X, ldx, Xj, ldx, j, m2, k, Cj, m2); break;
    default: break;
  }
}

/// The panel's LL^T with the 512-bit panels for the finished columns' product (the same blocks
/// of 4 columns, so the same operations in the same order as panel_cholesky_avx2).
BARY_DEFINE_PANEL_CHOLESKY(panel_cholesky_avx512, BARY_TARGET_AVX512, nt_columns_avx512)
#undef BARY_DEFINE_PANEL_CHOLESKY
#endif

/// Left-looking supernodal numeric factorization of P M~ P^T, M~ = S M S with the scaling
/// given per row of A (@p scale), M's entries read from A through @p columns (A: both
/// triangles, a symmetric pattern). Returns -1, or the factor column whose pivot was not
/// positive.
Index supernodal_numeric(SupernodalFactor& f, const SparseMatrix& A, const FactorColumns& columns,
  const Eigen::VectorXd& scale)
{
  const Index n = f.n;
  const int ns = f.supernodes;
  std::vector<int> supernode_of(static_cast<std::size_t>(n));
  for (int s = 0; s < ns; ++s)
    for (int k = f.super[static_cast<std::size_t>(s)]; k < f.super[static_cast<std::size_t>(s) + 1]; ++k)
      supernode_of[static_cast<std::size_t>(k)] = s;
  // relative[r]: position of row r in the current supernode's rows, -1 for rows outside it.
  std::vector<int> relative(static_cast<std::size_t>(n), -1), map;
  // Descendants waiting to update supernode s: linked lists head[s] -> next[d] -> ...; next_row[d]
  // is the offset of d's first row not yet used for an update.
  std::vector<int> head(static_cast<std::size_t>(ns), -1), next(static_cast<std::size_t>(ns), -1),
    next_row(static_cast<std::size_t>(ns), 0);
  // A descendant's update, written before it is read (only its lower part is read): per thread,
  // uninitialized, only growing (not a new zeroed buffer per factorization: a memset and its
  // page faults).
  thread_local FactorValues update;
  if (update.size() < std::max<std::size_t>(f.max_update, 1))
    update.resize(std::max<std::size_t>(f.max_update, 1));
  const SingleThreadedProducts single_threaded;
  const bool blocked = single_threaded.sequential();
  [[maybe_unused]] const bool avx2 = detail::simd_level() == detail::SimdLevel::AVX2;
  [[maybe_unused]] const bool avx512 = detail::avx512_enabled();
  const int* rows = f.rows.data();
  const int* source = columns.source.data();
  const int* entry_row = columns.entry_row.data();
  const int* entry_value = columns.entry_value.data();
  const double* values = A.valuePtr();

  for (int s = 0; s < ns; ++s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], k2 = f.super[su + 1], width = k2 - k1;
    const int r0 = f.row_start[su], height = f.row_start[su + 1] - r0;
    double* Ls = f.values.data() + f.value_start[su];
    for (int k = 0; k < height; ++k)
      relative[static_cast<std::size_t>(rows[r0 + k])] = k;
    std::fill(Ls, Ls + static_cast<std::ptrdiff_t>(height) * width, 0.0);
    // The columns of P M~ P^T on and below the diagonal (listed by the symbolic analysis; each
    // position receives one entry).
    for (int k = k1; k < k2; ++k)
    {
      const double sk = scale(source[k]);
      double* column = Ls + static_cast<std::ptrdiff_t>(k - k1) * height;
      const int end = columns.entry_start[static_cast<std::size_t>(k) + 1];
      for (int q = columns.entry_start[static_cast<std::size_t>(k)]; q < end; ++q)
      {
        const int r = entry_row[q];
        const int at = relative[static_cast<std::size_t>(r)];
        if (at < 0)
          throw Error(ErrorCode::Internal,
            "the supernodal factorization met an entry outside the symbolic pattern");
        column[at] += values[entry_value[q]] * scale(source[r]) * sk;
      }
    }
    // Updates from the descendants: C = L_d(rows >= k1) L_d(rows in [k1, k2))^T, scattered.
    for (int d = head[su]; d != -1;)
    {
      const auto du = static_cast<std::size_t>(d);
      const int following = next[du];
      const int d0 = f.row_start[du], d_end = f.row_start[du + 1];
      const int d_height = d_end - d0, d_columns = f.super[du + 1] - f.super[du];
      const int p1 = d0 + next_row[du];
      int p2 = p1;
      while (p2 < d_end && rows[p2] < k2)
        ++p2;
      const int m1 = p2 - p1, m2 = d_end - p1;
      const ConstDenseBlock Ld(f.values.data() + f.value_start[du], d_height, d_columns,
        Eigen::OuterStride<>(d_height));
      DenseBlock C(update.data(), m2, m1, Eigen::OuterStride<>(m2));
#if BARY_HAVE_AVX2_DISPATCH
      if (avx512)
        descendant_update_avx512(
          f.values.data() + f.value_start[du] + (p1 - d0), d_height, m2, m1, d_columns, update.data());
      else if (avx2)
        descendant_update_avx2(
          f.values.data() + f.value_start[du] + (p1 - d0), d_height, m2, m1, d_columns, update.data());
      else
#endif
      {
        const auto within = Ld.middleRows(p1 - d0, m1);
        const auto further = Ld.middleRows(p2 - d0, m2 - m1);
        // The lower triangle of the top m1 x m1 block (symmetric rank-k update), then the rows
        // below it (GEMM).
        auto top = C.topRows(m1);
        top.triangularView<Eigen::Lower>().setZero();
        top.selfadjointView<Eigen::Lower>().rankUpdate(within);
        if (m2 > m1)
        {
          if (blocked)
            C.bottomRows(m2 - m1).noalias() = further * within.transpose();
          else
            C.bottomRows(m2 - m1).noalias() = further.lazyProduct(within.transpose());
        }
      }
      map.resize(static_cast<std::size_t>(m2));
      for (int i = 0; i < m2; ++i)
        map[static_cast<std::size_t>(i)] = relative[static_cast<std::size_t>(rows[p1 + i])];
      for (int j = 0; j < m1; ++j)
      {
        double* column = Ls + static_cast<std::ptrdiff_t>(rows[p1 + j] - k1) * height;
        const double* c = update.data() + static_cast<std::ptrdiff_t>(j) * m2;
        for (int i = j; i < m2; ++i)
          column[map[static_cast<std::size_t>(i)]] -= c[i];
      }
      next_row[du] = p2 - d0;
      if (p2 < d_end)
      {
        const auto target = static_cast<std::size_t>(supernode_of[static_cast<std::size_t>(rows[p2])]);
        next[du] = head[target];
        head[target] = d;
      }
      d = following;
    }
    head[su] = -1;
    // Factor the diagonal block, then the rows below it: L21 = A21 L11^-T.
    DenseBlock block(Ls, height, width, Eigen::OuterStride<>(height));
#if BARY_HAVE_AVX2_DISPATCH
    if (avx2)
    {
      const int failed =
        avx512 ? panel_cholesky_avx512(Ls, height, width) : panel_cholesky_avx2(Ls, height, width);
      if (failed >= 0)
        return k1 + failed;
    }
    else
#endif
    {
      Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> diagonal = block.topRows(width);
      const Index failed = Eigen::internal::llt_inplace<double, Eigen::Lower>::blocked(diagonal);
      if (failed >= 0)
        return k1 + failed;
    }
    if (height > width)
    {
      if (!avx2)
        block.topRows(width).transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(
          block.bottomRows(height - width));
      next_row[su] = width;
      const auto target = static_cast<std::size_t>(supernode_of[static_cast<std::size_t>(rows[r0 + width])]);
      next[su] = head[target];
      head[target] = s;
    }
    for (int k = 0; k < height; ++k)
      relative[static_cast<std::size_t>(rows[r0 + k])] = -1;
  }
  return -1;
}

#if BARY_HAVE_AVX2_DISPATCH
/// sum_i a[i] b[i] over n entries, four FMA lanes twice over.
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE double dot_avx2(const double* a, const double* b, int n)
{
  __m256d s0 = _mm256_setzero_pd(), s1 = _mm256_setzero_pd();
  int i = 0;
  for (; i + 8 <= n; i += 8)
  {
    s0 = _mm256_fmadd_pd(_mm256_loadu_pd(a + i), _mm256_loadu_pd(b + i), s0);
    s1 = _mm256_fmadd_pd(_mm256_loadu_pd(a + i + 4), _mm256_loadu_pd(b + i + 4), s1);
  }
  if (i + 4 <= n)
  {
    s0 = _mm256_fmadd_pd(_mm256_loadu_pd(a + i), _mm256_loadu_pd(b + i), s0);
    i += 4;
  }
  s0 = _mm256_add_pd(s0, s1);
  const __m128d h = _mm_add_pd(_mm256_castpd256_pd128(s0), _mm256_extractf128_pd(s0, 1));
  double sum = _mm_cvtsd_f64(_mm_add_sd(h, _mm_unpackhi_pd(h, h)));
  for (; i < n; ++i)
    sum += a[i] * b[i];
  return sum;
}

/// y[i] -= a[i] t over n entries.
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void axpy_avx2(double* y, const double* a, double t, int n)
{
  const __m256d tv = _mm256_set1_pd(t);
  int i = 0;
  for (; i + 4 <= n; i += 4)
    _mm256_storeu_pd(y + i, _mm256_fnmadd_pd(_mm256_loadu_pd(a + i), tv, _mm256_loadu_pd(y + i)));
  for (; i < n; ++i)
    y[i] -= a[i] * t;
}

/// Solves (L L^T) x = b in place for one right-hand side (x in the factor's order): per
/// supernode, the columns of its panel once forward (x_s = L11^-1 x_s, then x_below -= L21 x_s,
/// column by column) and once backward (dot products of each column with the gathered x).
/// @p y: scratch of the largest supernode height. Compiled for AVX2 + FMA: it must only run where
/// simd_level() says so.
BARY_TARGET_AVX2 BARY_NOINLINE void supernodal_solve_vector_avx2(
  const SupernodalFactor& f, double* x, double* y)
{
  const int* rows = f.rows.data();
  for (int s = 0; s < f.supernodes; ++s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], w = f.super[su + 1] - k1;
    const int r0 = f.row_start[su], h = f.row_start[su + 1] - r0;
    const double* L = f.values.data() + f.value_start[su];
    for (int i = 0; i < w; ++i)
      y[i] = x[k1 + i];
    std::fill(y + w, y + h, 0.0);
    for (int j = 0; j < w; ++j)
    {
      const double* column = L + static_cast<std::ptrdiff_t>(j) * h;
      const double xj = y[j] / column[j];
      y[j] = xj;
      axpy_avx2(y + j + 1, column + j + 1, xj, h - j - 1);
    }
    for (int i = 0; i < w; ++i)
      x[k1 + i] = y[i];
    for (int i = w; i < h; ++i)
      x[rows[r0 + i]] += y[i];
  }
  for (int s = f.supernodes - 1; s >= 0; --s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], w = f.super[su + 1] - k1;
    const int r0 = f.row_start[su], h = f.row_start[su + 1] - r0;
    const double* L = f.values.data() + f.value_start[su];
    for (int i = 0; i < w; ++i)
      y[i] = x[k1 + i];
    for (int i = w; i < h; ++i)
      y[i] = x[rows[r0 + i]];
    for (int j = w - 1; j >= 0; --j)
    {
      const double* column = L + static_cast<std::ptrdiff_t>(j) * h;
      y[j] = (y[j] - dot_avx2(column + j + 1, y + j + 1, h - j - 1)) / column[j];
    }
    for (int i = 0; i < w; ++i)
      x[k1 + i] = y[i];
  }
}
#endif

/// Solves (L L^T) X = B in place for X, B in the factor's (permuted) order.
void supernodal_solve(const SupernodalFactor& f, Eigen::MatrixXd& X)
{
#if BARY_HAVE_AVX2_DISPATCH
  if (X.cols() == 1 && detail::simd_level() == detail::SimdLevel::AVX2)
  {
    int tallest = 0;
    for (int s = 0; s < f.supernodes; ++s)
      tallest = std::max(tallest, f.row_start[static_cast<std::size_t>(s) + 1] - f.row_start[static_cast<std::size_t>(s)]);
    std::vector<double> y(static_cast<std::size_t>(tallest));
    supernodal_solve_vector_avx2(f, X.data(), y.data());
    return;
  }
#endif
  const SingleThreadedProducts single_threaded;
  const bool blocked = single_threaded.sequential();
  const Index k = X.cols();
  Eigen::MatrixXd T;
  const int* rows = f.rows.data();
  for (int s = 0; s < f.supernodes; ++s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], columns = f.super[su + 1] - k1;
    const int r0 = f.row_start[su], height = f.row_start[su + 1] - r0, below = height - columns;
    const ConstDenseBlock Ls(f.values.data() + f.value_start[su], height, columns,
      Eigen::OuterStride<>(height));
    auto Xs = X.middleRows(k1, columns);
    Ls.topRows(columns).triangularView<Eigen::Lower>().solveInPlace(Xs);
    if (below > 0)
    {
      if (blocked)
        T.noalias() = Ls.bottomRows(below) * Xs;
      else
        T.noalias() = Ls.bottomRows(below).lazyProduct(Xs);
      for (int i = 0; i < below; ++i)
        X.row(rows[r0 + columns + i]) -= T.row(i);
    }
  }
  for (int s = f.supernodes - 1; s >= 0; --s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], columns = f.super[su + 1] - k1;
    const int r0 = f.row_start[su], height = f.row_start[su + 1] - r0, below = height - columns;
    const ConstDenseBlock Ls(f.values.data() + f.value_start[su], height, columns,
      Eigen::OuterStride<>(height));
    auto Xs = X.middleRows(k1, columns);
    if (below > 0)
    {
      T.resize(below, k);
      for (int i = 0; i < below; ++i)
        T.row(i) = X.row(rows[r0 + columns + i]);
      if (blocked)
        Xs.noalias() -= Ls.bottomRows(below).transpose() * T;
      else
        Xs.noalias() -= Ls.bottomRows(below).transpose().lazyProduct(T);
    }
    Ls.topRows(columns).transpose().triangularView<Eigen::Upper>().solveInPlace(Xs);
  }
}

/// A given fill-reducing ordering must be a permutation of 0 .. n-1.
void check_ordering(const Eigen::VectorXi& ordering, Index n)
{
  if (ordering.size() != n)
    throw Error(ErrorCode::SizeMismatch,
      "the ordering has " + std::to_string(ordering.size()) + " entries for a matrix of size " +
        std::to_string(n) + " (give n entries or none)");
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (Index k = 0; k < n; ++k)
  {
    const int o = ordering(k);
    if (o < 0 || o >= n || seen[static_cast<std::size_t>(o)])
      throw Error(ErrorCode::InvalidArgument,
        "the ordering is not a permutation of 0 .. " + std::to_string(n - 1) + ": entry " +
          std::to_string(k) + " is " + std::to_string(o) +
          (o >= 0 && o < n ? " again" : ", out of range"));
    seen[static_cast<std::size_t>(o)] = 1;
  }
}

/// Symbolic and numeric supernodal factorization of M = A(sub, sub) (M = A for an empty
/// @p sub) in the elimination order @p order (over M's rows) with M's scaling @p scale (per row
/// of M); reports the entries, flops and the smallest pivot with its row of M. Throws "not
/// positive definite" naming the row (through @p id) where the factorization failed.
template<typename Id>
std::unique_ptr<SupernodalFactor> factor_supernodal(const SparseMatrix& A,
  const std::vector<int>& sub, const Eigen::VectorXi& order, const Eigen::VectorXd& scale,
  const Id& id, double& entries, double& flops, double& min_pivot, Index& min_row,
  FactorValues&& recycled = FactorValues())
{
  thread_local FactorColumns columns; // per-thread buffers that only grow
  auto f = std::make_unique<SupernodalFactor>(
    supernodal_symbolic(A, sub, order.data(), order.size(), columns, std::move(recycled)));
  // The scaling per row of A (only M's rows are read).
  Eigen::VectorXd scale_of_a;
  if (!sub.empty())
  {
    scale_of_a = Eigen::VectorXd::Zero(A.rows());
    for (std::size_t i = 0; i < sub.size(); ++i)
      scale_of_a(sub[i]) = scale(static_cast<Index>(i));
  }
  const Index failed = supernodal_numeric(*f, A, columns, sub.empty() ? scale : scale_of_a);
  if (failed >= 0)
    throw_not_positive_definite("the supernodal LL^T factorization failed at row " +
      id(f->perm[static_cast<std::size_t>(failed)]));
  for (int sn = 0; sn < f->supernodes; ++sn)
  {
    const auto su = static_cast<std::size_t>(sn);
    const int k1 = f->super[su], width = f->super[su + 1] - k1;
    const int height = f->row_start[su + 1] - f->row_start[su];
    const double* block = f->values.data() + f->value_start[su];
    for (int j = 0; j < width; ++j)
    {
      const double l = block[static_cast<std::ptrdiff_t>(j) * (height + 1)];
      if (l * l < min_pivot)
      {
        min_pivot = l * l;
        min_row = f->perm[static_cast<std::size_t>(k1 + j)];
      }
    }
  }
  entries = static_cast<double>(f->values.size());
  flops = f->flops;
  return f;
}

} // namespace

#ifdef BARYLAB_HAVE_CHOLMOD
/// A principal submatrix factorization that rows can be added to or deleted from: CHOLMOD's
/// simplicial LDL^T of P A~ P^T with A~ = S A S for all of A's rows, the rows outside the
/// factored submatrix M being rows of the identity (Davis & Hager, "Row modifications of a
/// sparse Cholesky factorization", SIAM J. Matrix Anal. Appl. 26(3), 2005: cholmod_rowadd and
/// cholmod_rowdel need exactly this form). Factor position k holds A's row Perm[k].
struct ModifiableFactor
{
  CholmodCommon common;
  cholmod_factor* L = nullptr;
  std::vector<int> position; ///< A's row -> factor position
  std::vector<char> inside;  ///< A's row is a row of M
  ModifiableFactor() = default;
  ModifiableFactor(const ModifiableFactor&) = delete;
  ModifiableFactor& operator=(const ModifiableFactor&) = delete;
  ~ModifiableFactor()
  {
    if (L)
      cholmod_free_factor(&L, common.get());
  }
};

/// The modifiable form of the supernodal factor @p f of M = A(rows, rows): factor positions
/// 0 .. m-1 are f's columns (LL^T turned into LDL^T), then the other rows of A in increasing
/// order as identity rows.
std::unique_ptr<ModifiableFactor> to_modifiable(
  const SupernodalFactor& f, const std::vector<int>& rows, Index nA)
{
  auto mf = std::make_unique<ModifiableFactor>();
  cholmod_common* c = mf->common.get();
  const auto N = static_cast<std::size_t>(nA);
  const Index m = f.n;
  mf->L = cholmod_allocate_factor(N, c);
  if (mf->L == nullptr)
    throw Error(ErrorCode::InvalidArgument, "out of memory allocating a modifiable factor");
  int* perm = static_cast<int*>(mf->L->Perm);
  int* count = static_cast<int*>(mf->L->ColCount);
  mf->position.assign(N, -1);
  mf->inside.assign(N, 0);
  for (int s = 0; s < f.supernodes; ++s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], k2 = f.super[su + 1];
    const int height = f.row_start[su + 1] - f.row_start[su];
    for (int k = k1; k < k2; ++k)
    {
      perm[k] = rows[static_cast<std::size_t>(f.perm[static_cast<std::size_t>(k)])];
      count[k] = height - (k - k1);
    }
  }
  Index k = m;
  for (int a = 0; a < static_cast<int>(nA); ++a)
    mf->inside[static_cast<std::size_t>(a)] = 0;
  for (Index i = 0; i < m; ++i)
    mf->inside[static_cast<std::size_t>(rows[static_cast<std::size_t>(i)])] = 1;
  for (int a = 0; a < static_cast<int>(nA); ++a)
    if (!mf->inside[static_cast<std::size_t>(a)])
    {
      perm[k] = a;
      count[k] = 1;
      ++k;
    }
  for (std::size_t q = 0; q < N; ++q)
    mf->position[static_cast<std::size_t>(perm[q])] = static_cast<int>(q);
  // Not CHOLMOD_NATURAL, which would make the solves ignore Perm.
  mf->L->ordering = CHOLMOD_GIVEN;
  // Numeric simplicial LDL^T, initialized to the identity, columns with room to grow. Row
  // additions lengthen the columns they touch: a column that outgrows its room moves to the
  // end of the factor, and when that is full the whole factor is reallocated and copied (on
  // libigl's hand with CHOLMOD's defaults, 1.2 x count + 5 room and 1.2 x growth, those copies
  // took most of the modifications' page faults). More room per column and a doubling instead.
  c->grow0 = 2.0;
  c->grow1 = 1.5;
  c->grow2 = 16;
  if (!cholmod_change_factor(CHOLMOD_REAL, 0, 0, 0, 1, mf->L, c) || c->status < CHOLMOD_OK)
    throw Error(ErrorCode::InvalidArgument, "out of memory allocating a modifiable factor");
  int* Lp = static_cast<int*>(mf->L->p);
  int* Li = static_cast<int*>(mf->L->i);
  int* Lnz = static_cast<int*>(mf->L->nz);
  double* Lx = static_cast<double*>(mf->L->x);
  for (int s = 0; s < f.supernodes; ++s)
  {
    const auto su = static_cast<std::size_t>(s);
    const int k1 = f.super[su], k2 = f.super[su + 1];
    const int r0 = f.row_start[su], height = f.row_start[su + 1] - r0;
    const double* block = f.values.data() + f.value_start[su];
    for (int kk = k1; kk < k2; ++kk)
    {
      const double* column = block + static_cast<std::ptrdiff_t>(kk - k1) * height;
      const double diagonal = column[kk - k1];
      int q = Lp[kk];
      Li[q] = kk;
      Lx[q] = diagonal * diagonal;
      ++q;
      for (int r = kk - k1 + 1; r < height; ++r, ++q)
      {
        Li[q] = f.rows[static_cast<std::size_t>(r0 + r)];
        Lx[q] = column[r] / diagonal;
      }
      Lnz[kk] = q - Lp[kk];
    }
  }
  return mf;
}
#endif

struct SparseCholesky::Impl
{
  Index n = 0;
  Eigen::VectorXd scale; ///< S = diag(A)^-1/2
  double min_pivot = 0.0;
  double entries = 0.0, flops = 0.0;
  /// A given ordering (Eigen and Cholmod backends factor P A~ P^T themselves): ordering(k) is
  /// the row eliminated k-th; empty when the backend ordered.
  Eigen::VectorXi ordering;
  std::unique_ptr<Eigen::SimplicialLDLT<SparseMatrix>> eigen;
  std::unique_ptr<Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>>>
    eigen_natural;
  std::unique_ptr<SupernodalFactor> supernodal;
  /// compute_principal: A's row of each row of M (the supernodal factor's sub) and A's size.
  std::vector<int> rows;
  Index principal_of = 0;
#ifdef BARYLAB_HAVE_CHOLMOD
  std::unique_ptr<CholmodFactor> cholmod;
  std::unique_ptr<ModifiableFactor> modifiable; ///< after modify_principal()
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
      "the CHOLMOD backend was requested but BaryLab was built without CHOLMOD",
      "use Backend::Automatic or Backend::Eigen, or rebuild with SuiteSparse's CHOLMOD "
      "installed (BARYLAB_USE_CHOLMOD=ON)");
  else if (backend_ != Backend::Cholmod && backend_ != Backend::Eigen &&
    backend_ != Backend::Supernodal)
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
    case SparseCholesky::Backend::Supernodal:
      return "supernodal";
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

double SparseCholesky::factor_entries() const noexcept
{
  return impl_ ? impl_->entries : 0.0;
}

double SparseCholesky::factor_flops() const noexcept
{
  return impl_ ? impl_->flops : 0.0;
}

void SparseCholesky::compute(const SparseMatrix& A, const Eigen::VectorXi& row_ids)
{
  compute(A, row_ids, SparseCholeskySettings());
}

void SparseCholesky::compute(
  const SparseMatrix& A, const Eigen::VectorXi& row_ids, const SparseCholeskySettings& settings)
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

  // The given ordering must be a permutation of 0 .. n-1.
  const Eigen::VectorXi& ordering = settings.ordering;
  const bool ordered = ordering.size() != 0;
  if (ordered)
    check_ordering(ordering, n);

  // Finite entries (unless trusted) and a positive diagonal.
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  for (Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
    {
      if (!settings.trusted && !std::isfinite(it.value()))
        throw Error(ErrorCode::NonFinite,
          "the matrix has a non-finite entry at (" + id(it.row()) + ", " + id(it.col()) + ")");
      if (it.row() == it.col())
        diagonal(it.row()) += it.value();
    }
  for (Index i = 0; i < n; ++i)
    if (!(diagonal(i) > 0.0))
      throw_not_positive_definite(
        "its diagonal entry (" + id(i) + ", " + id(i) + ") is " + detail::format_number(diagonal(i)) + ", not > 0");

  // Symmetry, relative to sqrt(A_ii A_jj) (which bounds |A_ij| for an SPD matrix). The
  // supernodal backend reads both triangles and needs a symmetric pattern: it factors
  // (A + A^T) / 2 unless the caller vouches for A.
  SparseMatrix symmetrized;
  if (!settings.trusted)
  {
    const SparseMatrix transposed = A.transpose();
    const SparseMatrix asymmetry = A - transposed;
    for (Index j = 0; j < asymmetry.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(asymmetry, j); it; ++it)
        if (std::abs(it.value()) > 1e-10 * std::sqrt(diagonal(it.row()) * diagonal(it.col())))
          throw Error(ErrorCode::InvalidArgument,
            "the matrix is not symmetric: entries (" + id(it.row()) + ", " + id(it.col()) +
              ") and (" + id(it.col()) + ", " + id(it.row()) + ") differ by " + detail::format_number(it.value()) +
              "; a Cholesky factorization needs a symmetric matrix");
    if (backend_ == Backend::Supernodal)
      symmetrized = 0.5 * (A + transposed);
  }
  else if (backend_ == Backend::Supernodal && !A.isCompressed())
    symmetrized = A;
  const SparseMatrix& symmetric = symmetrized.nonZeros() > 0 ? symmetrized : A;

  auto impl = std::make_shared<Impl>();
  impl->n = n;
  impl->scale = diagonal.cwiseSqrt().cwiseInverse();

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

  if (backend_ == Backend::Supernodal)
  {
    const Eigen::VectorXi own =
      ordered ? Eigen::VectorXi() : fill_reducing_ordering(symmetric, FillReducingOrdering::Amd);
    impl->supernodal = factor_supernodal(symmetric, {}, ordered ? ordering : own, impl->scale,
      [&](Index k) { return id(k); }, impl->entries, impl->flops, min_pivot, min_row);
  }
  else
  {
    SparseMatrix scaled = impl->scale.asDiagonal() * A * impl->scale.asDiagonal();
    if (ordered)
    {
      // Factor P A~ P^T with P moving row ordering(k) to k, in the backend's natural order.
      Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(n);
      for (Index k = 0; k < n; ++k)
        P.indices()(ordering(k)) = static_cast<int>(k);
      SparseMatrix permuted;
      permuted = scaled.twistedBy(P);
      scaled = std::move(permuted);
      impl->ordering = ordering;
    }
    // The row of A behind row k of the matrix the backend factored.
    auto original = [&](Index k) -> Index { return ordered ? Index(ordering(k)) : k; };
    if (backend_ == Backend::Eigen && ordered)
    {
      impl->eigen_natural = std::make_unique<
        Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>>>();
      impl->eigen_natural->compute(scaled);
      if (impl->eigen_natural->info() != Eigen::Success)
        throw_not_positive_definite("the LDL^T factorization met a zero pivot");
      const Eigen::VectorXd& D = impl->eigen_natural->vectorD();
      for (Index k = 0; k < n; ++k)
        record(D(k), original(k));
      impl->entries = static_cast<double>(impl->eigen_natural->matrixL().nestedExpression().nonZeros()) + n;
    }
    else if (backend_ == Backend::Eigen)
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
      impl->entries = static_cast<double>(impl->eigen->matrixL().nestedExpression().nonZeros()) + n;
    }
#ifdef BARYLAB_HAVE_CHOLMOD
    else
    {
      impl->cholmod = std::make_unique<CholmodFactor>();
      if (ordered)
      {
        impl->cholmod->cholmod().nmethods = 1;
        impl->cholmod->cholmod().method[0].ordering = CHOLMOD_NATURAL;
      }
      impl->cholmod->compute(scaled);
      const cholmod_factor* L = impl->cholmod->factor();
      const int status = impl->cholmod->cholmod().status;
      if (status < 0 || L == nullptr)
        throw Error(status == CHOLMOD_OUT_OF_MEMORY ? ErrorCode::InvalidArgument : ErrorCode::Internal,
          "CHOLMOD failed to factor a " + std::to_string(n) + " by " + std::to_string(n) +
            " matrix (status " + std::to_string(status) +
            (status == CHOLMOD_OUT_OF_MEMORY ? ", out of memory)" : ")"));
      const int* perm = static_cast<const int*>(L->Perm);
      auto original_row = [&](Index k) -> Index { return original(perm ? perm[k] : k); };
      if (impl->cholmod->info() != Eigen::Success)
      {
        const Index minor = static_cast<Index>(L->minor);
        throw_not_positive_definite("CHOLMOD's LL^T factorization failed at row " +
          (minor < n ? id(original_row(minor)) : std::to_string(minor)));
      }
      impl->entries = static_cast<double>(impl->cholmod->cholmod().lnz);
      impl->flops = impl->cholmod->cholmod().fl;
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
  }

  const double tolerance = 16.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon();
  if (!(min_pivot > tolerance))
    throw_not_positive_definite("its smallest pivot (after scaling to unit diagonal) is " +
      detail::format_number(min_pivot) + " at row " + id(min_row) + ", not above 16 n eps = " +
      detail::format_number(tolerance) + " (singular or numerically singular)");
  impl->min_pivot = min_pivot;
  impl_ = std::move(impl);
}

void SparseCholesky::compute_principal(
  const SparseMatrix& A, const Eigen::VectorXi& rows, const SparseCholeskySettings& settings)
{
  // The values' storage of the factor this one replaces, unless a copy still shares it: an
  // active-set solver refactors every iteration, and new storage costs a page fault every
  // 4 KiB at its first touch (~11 us each on the project's virtual machines).
  FactorValues recycled;
  if (impl_ && impl_.use_count() == 1 && impl_->supernodal)
    recycled = std::move(impl_->supernodal->values);
  impl_.reset();
  if (A.rows() != A.cols())
    throw Error(ErrorCode::SizeMismatch,
      "a Cholesky factorization needs a square matrix, got " + std::to_string(A.rows()) +
        " by " + std::to_string(A.cols()));
  const Index nA = A.rows(), m = rows.size();
  if (m == 0)
    throw Error(ErrorCode::EmptyInput, "the principal submatrix to factor is empty (no rows)");
  std::vector<int> position(static_cast<std::size_t>(nA), -1);
  for (Index i = 0; i < m; ++i)
  {
    const int r = rows(i);
    if (r < 0 || r >= nA)
      throw Error(ErrorCode::InvalidArgument,
        "rows(" + std::to_string(i) + ") = " + std::to_string(r) + " is outside [0, " +
          std::to_string(nA) + ")");
    if (position[static_cast<std::size_t>(r)] >= 0)
      throw Error(ErrorCode::InvalidArgument,
        "row " + std::to_string(r) + " is listed twice in rows (at " +
          std::to_string(position[static_cast<std::size_t>(r)]) + " and " + std::to_string(i) + ")");
    position[static_cast<std::size_t>(r)] = static_cast<int>(i);
  }
  auto form = [&]() {
    std::vector<Eigen::Triplet<double>> triplets;
    for (Index i = 0; i < m; ++i)
      for (SparseMatrix::InnerIterator it(A, rows(i)); it; ++it)
      {
        const int r = position[static_cast<std::size_t>(it.row())];
        if (r >= 0)
          triplets.emplace_back(r, static_cast<int>(i), it.value());
      }
    SparseMatrix M(m, m);
    M.setFromTriplets(triplets.begin(), triplets.end());
    return M;
  };
  if (backend_ != Backend::Supernodal || !settings.trusted || !A.isCompressed())
  {
    compute(form(), rows, settings);
    impl_->rows.assign(rows.data(), rows.data() + m);
    return;
  }

  // Supernodal backend on a trusted A: M is read from A.
  const Eigen::VectorXi& ordering = settings.ordering;
  if (ordering.size() != 0)
    check_ordering(ordering, m);
  auto id = [&rows](Index i) { return std::to_string(rows(i)); };
  auto impl = std::make_shared<Impl>();
  impl->n = m;
  impl->scale.resize(m);
  // A is compressed: each diagonal entry by bisection of its column rather than a pass over it
  // (a column whose rows are not sorted, where bisection may miss it, is scanned).
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  for (Index i = 0; i < m; ++i)
  {
    const int r = rows(i);
    const int* begin = inner + outer[r];
    const int* end = inner + outer[r + 1];
    const int* at = std::lower_bound(begin, end, r);
    double d = 0.0;
    if (at != end && *at == r)
      d = value[at - inner];
    else
      for (const int* q = begin; q != end; ++q)
        d += *q == r ? value[q - inner] : 0.0;
    if (!(d > 0.0))
      throw_not_positive_definite(
        "its diagonal entry (" + id(i) + ", " + id(i) + ") is " + detail::format_number(d) + ", not > 0");
    impl->scale(i) = 1.0 / std::sqrt(d);
  }
  const Eigen::VectorXi own =
    ordering.size() != 0 ? Eigen::VectorXi() : fill_reducing_ordering(form(), FillReducingOrdering::Amd);
  const std::vector<int> sub(rows.data(), rows.data() + m);
  double min_pivot = std::numeric_limits<double>::infinity();
  Index min_row = 0;
  impl->supernodal = factor_supernodal(A, sub, ordering.size() != 0 ? ordering : own, impl->scale,
    id, impl->entries, impl->flops, min_pivot, min_row, std::move(recycled));
  impl->rows = sub;
  impl->principal_of = nA;
  const double tolerance = 16.0 * static_cast<double>(m) * std::numeric_limits<double>::epsilon();
  if (!(min_pivot > tolerance))
    throw_not_positive_definite("its smallest pivot (after scaling to unit diagonal) is " +
      detail::format_number(min_pivot) + " at row " + id(min_row) + ", not above 16 n eps = " +
      detail::format_number(tolerance) + " (singular or numerically singular)");
  impl->min_pivot = min_pivot;
  impl_ = std::move(impl);
}

bool SparseCholesky::modifiable() const noexcept
{
#ifdef BARYLAB_HAVE_CHOLMOD
  return impl_ && impl_->principal_of > 0 && (impl_->supernodal || impl_->modifiable);
#else
  return false;
#endif
}

void SparseCholesky::modify_principal(
  const SparseMatrix& A, const Eigen::VectorXi& add, const Eigen::VectorXi& remove)
{
#ifdef BARYLAB_HAVE_CHOLMOD
  if (!modifiable())
    throw Error(ErrorCode::InvalidArgument,
      "SparseCholesky::modify_principal needs a factorization by compute_principal() with the "
      "Supernodal backend and trusted settings (and BaryLab built with CHOLMOD)");
  const Index nA = impl_->principal_of;
  if (A.rows() != nA || A.cols() != nA)
    throw Error(ErrorCode::SizeMismatch,
      "modify_principal got a " + std::to_string(A.rows()) + " by " + std::to_string(A.cols()) +
        " matrix, but the factorization is of a principal submatrix of a " + std::to_string(nA) +
        " by " + std::to_string(nA) + " one");
  {
    std::vector<char> member(static_cast<std::size_t>(nA), 0);
    for (const int a : impl_->rows)
      member[static_cast<std::size_t>(a)] = 1;
    auto check = [&](const Eigen::VectorXi& list, const char* name, bool in) {
      for (Index q = 0; q < list.size(); ++q)
      {
        const int a = list(q);
        if (a < 0 || a >= nA)
          throw Error(ErrorCode::InvalidArgument,
            std::string(name) + "(" + std::to_string(q) + ") = " + std::to_string(a) +
              " is outside [0, " + std::to_string(nA) + ")");
        if (static_cast<bool>(member[static_cast<std::size_t>(a)]) != in)
          throw Error(ErrorCode::InvalidArgument,
            "row " + std::to_string(a) + (in ? " is not a row of the factored submatrix"
                                             : " is already a row of the factored submatrix") +
              (in ? "" : " (or is listed twice in add)"));
        member[static_cast<std::size_t>(a)] = !in ? 1 : 0;
      }
    };
    check(remove, "remove", true);
    check(add, "add", false);
  }
  // Copy on write: copies made before keep their factorization.
  const bool shared = impl_.use_count() > 1;
  std::shared_ptr<Impl> impl = impl_;
  if (shared || !impl->modifiable)
  {
    auto fresh = std::make_shared<Impl>();
    fresh->rows = impl->rows;
    fresh->principal_of = nA;
    fresh->entries = impl->entries;
    fresh->flops = impl->flops;
    fresh->min_pivot = impl->min_pivot;
    if (impl->modifiable)
    {
      fresh->modifiable = std::make_unique<ModifiableFactor>();
      fresh->modifiable->position = impl->modifiable->position;
      fresh->modifiable->inside = impl->modifiable->inside;
      std::lock_guard<std::mutex> lock(impl->cholmod_mutex);
      fresh->modifiable->L = cholmod_copy_factor(impl->modifiable->L, fresh->modifiable->common.get());
      if (fresh->modifiable->L == nullptr)
        throw Error(ErrorCode::InvalidArgument, "out of memory copying a modifiable factor");
    }
    else
      fresh->modifiable = to_modifiable(*impl->supernodal, impl->rows, nA);
    impl = std::move(fresh);
  }
  // A failure part way leaves the factor half modified: forget it, like a failed compute().
  impl_.reset();
  ModifiableFactor& mf = *impl->modifiable;
  cholmod_common* c = mf.common.get();
  std::vector<char>& inside = mf.inside;
  auto scale_of = [&](int a) {
    const double d = A.coeff(a, a); // a binary search in column a (called per entry of a new row)
    if (!(d > 0.0))
      throw_not_positive_definite(
        "its diagonal entry (" + std::to_string(a) + ", " + std::to_string(a) + ") is " + detail::format_number(d) + ", not > 0");
    return 1.0 / std::sqrt(d);
  };
  auto fail = [&](const std::string& what, int a) {
    if (c->status == CHOLMOD_NOT_POSDEF)
      throw_not_positive_definite("adding row " + std::to_string(a) + " made a pivot non-positive");
    throw Error(ErrorCode::Internal,
      "CHOLMOD's " + what + " of row " + std::to_string(a) + " failed (status " +
        std::to_string(c->status) + ")");
  };
  for (Index q = 0; q < remove.size(); ++q)
  {
    const int a = remove(q);
    if (!cholmod_rowdel(static_cast<std::size_t>(mf.position[static_cast<std::size_t>(a)]), nullptr, mf.L, c) ||
      c->status < CHOLMOD_OK)
      fail("row deletion", a);
    inside[static_cast<std::size_t>(a)] = 0;
  }
  // The new rows one at a time, each with its entries in the rows present so far.
  cholmod_sparse* R = nullptr;
  for (Index q = 0; q < add.size(); ++q)
  {
    const int a = add(q);
    inside[static_cast<std::size_t>(a)] = 1;
    const double sa = scale_of(a);
    std::size_t entries = 0;
    for (SparseMatrix::InnerIterator it(A, a); it; ++it)
      entries += inside[static_cast<std::size_t>(it.row())] != 0;
    if (R == nullptr || R->nzmax < entries)
    {
      if (R)
        cholmod_free_sparse(&R, c);
      R = cholmod_allocate_sparse(static_cast<std::size_t>(nA), 1, std::max<std::size_t>(entries, 64),
        0, 1, 0, CHOLMOD_REAL, c);
      if (R == nullptr)
        throw Error(ErrorCode::InvalidArgument, "out of memory in a row addition");
    }
    int* Rp = static_cast<int*>(R->p);
    int* Ri = static_cast<int*>(R->i);
    double* Rx = static_cast<double*>(R->x);
    std::size_t e = 0;
    for (SparseMatrix::InnerIterator it(A, a); it; ++it)
    {
      const int r = static_cast<int>(it.row());
      if (!inside[static_cast<std::size_t>(r)])
        continue;
      Ri[e] = mf.position[static_cast<std::size_t>(r)];
      Rx[e] = (r == a ? sa : scale_of(r)) * it.value() * sa;
      ++e;
    }
    Rp[0] = 0;
    Rp[1] = static_cast<int>(e);
    if (!cholmod_rowadd(static_cast<std::size_t>(mf.position[static_cast<std::size_t>(a)]), R, mf.L, c) ||
      c->status < CHOLMOD_OK)
    {
      cholmod_free_sparse(&R, c);
      fail("row addition", a);
    }
  }
  if (R)
    cholmod_free_sparse(&R, c);
  // The definiteness test of compute() on the new pivots (D of the LDL^T; CHOLMOD accepts
  // negative ones).
  {
    const int* Lp = static_cast<const int*>(mf.L->p);
    const double* Lx = static_cast<const double*>(mf.L->x);
    const int* perm = static_cast<const int*>(mf.L->Perm);
    double min_pivot = std::numeric_limits<double>::infinity();
    int min_row = -1;
    Index m = 0;
    for (std::size_t k = 0; k < mf.position.size(); ++k)
      if (inside[static_cast<std::size_t>(perm[k])])
      {
        ++m;
        if (Lx[Lp[k]] < min_pivot)
        {
          min_pivot = Lx[Lp[k]];
          min_row = perm[k];
        }
      }
    const double tolerance = 16.0 * static_cast<double>(m) * std::numeric_limits<double>::epsilon();
    if (m > 0 && !(min_pivot > tolerance))
      throw_not_positive_definite("after the row changes its smallest pivot (after scaling to unit "
        "diagonal) is " + detail::format_number(min_pivot) + " at row " + std::to_string(min_row) +
        ", not above 16 n eps = " + detail::format_number(tolerance) + " (singular or numerically singular)");
    impl->min_pivot = min_pivot;
  }
  // The rows of M: the remaining ones in their previous order, then the added ones.
  std::vector<int> rows;
  rows.reserve(impl->rows.size() + static_cast<std::size_t>(add.size()));
  for (const int a : impl->rows)
    if (inside[static_cast<std::size_t>(a)])
      rows.push_back(a);
  for (Index q = 0; q < add.size(); ++q)
    rows.push_back(add(q));
  impl->rows = std::move(rows);
  impl->n = static_cast<Index>(impl->rows.size());
  impl->scale.resize(impl->n);
  for (Index i = 0; i < impl->n; ++i)
    impl->scale(i) = scale_of(impl->rows[static_cast<std::size_t>(i)]);
  impl->supernodal.reset();
  impl_ = std::move(impl);
#else
  (void)A;
  (void)add;
  (void)remove;
  throw Error(ErrorCode::InvalidArgument,
    "SparseCholesky::modify_principal needs BaryLab built with CHOLMOD");
#endif
}

const std::vector<int>& SparseCholesky::principal_rows() const noexcept
{
  static const std::vector<int> none;
  return impl_ ? impl_->rows : none;
}

Eigen::VectorXi fill_reducing_ordering(const SparseMatrix& A, FillReducingOrdering method)
{
  if (A.rows() != A.cols())
    throw Error(ErrorCode::SizeMismatch,
      "a fill-reducing ordering needs a square matrix, got " + std::to_string(A.rows()) + " by " +
        std::to_string(A.cols()));
  const Index n = A.rows();
  if (n == 0)
    return Eigen::VectorXi();
#ifdef BARYLAB_HAVE_CHOLMOD
  if (method != FillReducingOrdering::Amd)
  {
    SparseMatrix compressed;
    const SparseMatrix* pattern = &A;
    if (!A.isCompressed())
    {
      compressed = A;
      compressed.makeCompressed();
      pattern = &compressed;
    }
    CholmodCommon common;
    cholmod_common* c = common.get();
    cholmod_sparse view;
    view.nrow = view.ncol = static_cast<std::size_t>(n);
    view.nzmax = static_cast<std::size_t>(pattern->nonZeros());
    view.p = const_cast<int*>(pattern->outerIndexPtr());
    view.i = const_cast<int*>(pattern->innerIndexPtr());
    view.x = nullptr;
    view.z = nullptr;
    view.nz = nullptr;
    view.stype = 1;
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_PATTERN;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = 1;
    Eigen::VectorXi perm(n);
    int ok = 0;
    if (method == FillReducingOrdering::Metis)
      ok = cholmod_metis(&view, nullptr, 0, 1, perm.data(), c);
    else
    {
      std::vector<int> cparent(static_cast<std::size_t>(n)), cmember(static_cast<std::size_t>(n));
      ok = cholmod_nested_dissection(&view, nullptr, 0, perm.data(), cparent.data(),
             cmember.data(), c) >= 0;
    }
    if (!ok || c->status < CHOLMOD_OK)
      throw Error(ErrorCode::Internal,
        "CHOLMOD's fill-reducing ordering failed (status " + std::to_string(c->status) + ")");
    return perm;
  }
#endif
  Eigen::AMDOrdering<int> amd;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P;
  amd(A, P);
  return P.indices();
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

#ifdef BARYLAB_HAVE_CHOLMOD
  if (impl.modifiable)
  {
    // X = S (L D L^T)^-1 S B in A's row space, B's rows placed at A's rows of M.
    std::lock_guard<std::mutex> lock(impl.cholmod_mutex);
    ModifiableFactor& mf = *impl.modifiable;
    const auto N = static_cast<std::size_t>(impl.principal_of);
    cholmod_dense* D = cholmod_zeros(N, static_cast<std::size_t>(B.cols()), CHOLMOD_REAL, mf.common.get());
    if (D == nullptr)
      throw Error(ErrorCode::Internal, "CHOLMOD's triangular solve failed (out of memory?)");
    double* d = static_cast<double*>(D->x);
    for (Index j = 0; j < B.cols(); ++j)
      for (Index i = 0; i < impl.n; ++i)
        d[static_cast<std::size_t>(j) * N + static_cast<std::size_t>(impl.rows[static_cast<std::size_t>(i)])] =
          impl.scale(i) * B(i, j);
    cholmod_dense* Xd = cholmod_solve(CHOLMOD_A, mf.L, D, mf.common.get());
    cholmod_free_dense(&D, mf.common.get());
    if (Xd == nullptr)
      throw Error(ErrorCode::Internal, "CHOLMOD's triangular solve failed (out of memory?)");
    const double* x = static_cast<const double*>(Xd->x);
    Eigen::MatrixXd X(impl.n, B.cols());
    for (Index j = 0; j < B.cols(); ++j)
      for (Index i = 0; i < impl.n; ++i)
        X(i, j) = impl.scale(i) *
          x[static_cast<std::size_t>(j) * N + static_cast<std::size_t>(impl.rows[static_cast<std::size_t>(i)])];
    cholmod_free_dense(&Xd, mf.common.get());
    return X;
  }
#endif
  if (impl.supernodal)
  {
    // X = S P^T (L L^T)^-1 P S B.
    const SupernodalFactor& f = *impl.supernodal;
    Eigen::MatrixXd X(impl.n, B.cols());
    for (Index k = 0; k < impl.n; ++k)
    {
      const int i = f.perm[static_cast<std::size_t>(k)];
      X.row(k) = impl.scale(i) * B.row(i);
    }
    supernodal_solve(f, X);
    Eigen::MatrixXd Y(impl.n, B.cols());
    for (Index k = 0; k < impl.n; ++k)
    {
      const int i = f.perm[static_cast<std::size_t>(k)];
      Y.row(i) = impl.scale(i) * X.row(k);
    }
    return Y;
  }

  const bool ordered = impl.ordering.size() != 0;
  Eigen::MatrixXd scaled_B(impl.n, B.cols());
  for (Index k = 0; k < impl.n; ++k)
  {
    const Index i = ordered ? Index(impl.ordering(k)) : k;
    scaled_B.row(k) = impl.scale(i) * B.row(i);
  }
  Eigen::MatrixXd X;
  if (impl.eigen)
    X = impl.eigen->solve(scaled_B);
  else if (impl.eigen_natural)
    X = impl.eigen_natural->solve(scaled_B);
#ifdef BARYLAB_HAVE_CHOLMOD
  else
  {
    std::lock_guard<std::mutex> lock(impl.cholmod_mutex);
    X = impl.cholmod->solve(scaled_B);
    if (impl.cholmod->info() != Eigen::Success)
      throw Error(ErrorCode::Internal, "CHOLMOD's triangular solve failed (out of memory?)");
  }
#endif
  Eigen::MatrixXd Y(impl.n, B.cols());
  for (Index k = 0; k < impl.n; ++k)
  {
    const Index i = ordered ? Index(impl.ordering(k)) : k;
    Y.row(i) = impl.scale(i) * X.row(k);
  }
  return Y;
}

} // namespace bary
