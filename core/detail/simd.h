#pragma once
/// @file detail/simd.h
/// Runtime choice of an instruction set for core's hot per-query kernels (weighted averages on
/// surfaces): the build has no -march flag, so a kernel is written once as an always-inline
/// template over the vector types below (structure-of-arrays data, sums in a fixed order) and
/// instantiated twice, in a function compiled for AVX2 and FMA (BARY_TARGET_AVX2) and in a
/// portable one; simd_level() picks one per call. Both run the same operations in the same
/// order, except that the AVX2 functions contract a * b + c into one fused multiply-add (one
/// rounding instead of two: GCC's fp-contract=fast for these functions only, C++17 mode keeps
/// it off elsewhere), so their results agree to rounding (tested to 1e-12); the portable path
/// is the reference and what non-x86 machines and x86 ones without AVX2 or FMA run.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define BARY_HAVE_AVX2_DISPATCH 1
/// Compiles a function for AVX2 and FMA, fusing a * b + c (it must only run where simd_level()
/// says so).
#define BARY_TARGET_AVX2 __attribute__((target("avx2,fma"), optimize("fp-contract=fast")))
/// Compiles a function for AVX2 without FMA: plain loops vectorised four doubles wide, the
/// same IEEE operations in the same order as the portable build, so bitwise the same results
/// (for element-wise loops; it must only run where simd_level() says so).
#define BARY_TARGET_AVX2_EXACT __attribute__((target("avx2")))
/// Compiles a function for AVX-512 (F and VL) with AVX2 and FMA, fusing a * b + c (it must only
/// run where avx512_enabled() says so).
#define BARY_TARGET_AVX512                                                                       \
  __attribute__((target("avx512f,avx512vl,avx2,fma"), optimize("fp-contract=fast")))
#else
#define BARY_HAVE_AVX2_DISPATCH 0
#define BARY_TARGET_AVX2
#define BARY_TARGET_AVX2_EXACT
#define BARY_TARGET_AVX512
#endif

#if defined(__GNUC__)
/// Inlined into its caller, so a kernel is compiled for the caller's instruction set.
#define BARY_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define BARY_ALWAYS_INLINE inline
#endif

#if defined(__GNUC__)
/// Compiled as a function of its own (a kernel with its own registers, called from a larger one).
#define BARY_NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define BARY_NOINLINE __declspec(noinline)
#else
#define BARY_NOINLINE
#endif

namespace bary::detail
{

/// Instruction sets of the dispatched kernels.
enum class SimdLevel : int
{
  Portable = 0, ///< whatever the build's flags allow (SSE2 on x86-64)
  AVX2 = 1      ///< 256-bit vectors (four doubles) and FMA, chosen at run time
};

/// The best level this CPU runs (AVX2 and FMA: the CPU and the operating system support them).
inline SimdLevel supported_simd_level()
{
#if BARY_HAVE_AVX2_DISPATCH
  static const SimdLevel level = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? SimdLevel::AVX2
                                                                         : SimdLevel::Portable;
  }();
  return level;
#else
  return SimdLevel::Portable;
#endif
}

namespace simd_internal
{
/// -1: not chosen yet; otherwise the level in use.
inline std::atomic<int> chosen{ -1 };
/// -1: not chosen yet; 0 / 1: the 512-bit variants off / on.
inline std::atomic<int> avx512_chosen{ -1 };
/// The value in @p slot, set by @p choose() when it is still -1 (the first call).
template<class Choose>
inline int chosen_once(std::atomic<int>& slot, const Choose& choose)
{
  int value = slot.load(std::memory_order_relaxed);
  if (value < 0)
  {
    value = choose();
    slot.store(value, std::memory_order_relaxed);
  }
  return value;
}
/// True when the environment variable BARYLAB_SIMD is @p a or @p b.
inline bool environment_asks(const char* a, const char* b = nullptr)
{
  const char* env = std::getenv("BARYLAB_SIMD");
  return env && (std::strcmp(env, a) == 0 || (b && std::strcmp(env, b) == 0));
}
} // namespace simd_internal

/// The level the kernels use: the supported one, unless the environment variable BARYLAB_SIMD
/// is "0" or "portable" (then Portable), or set_simd_level chose a lower one.
inline SimdLevel simd_level()
{
  return static_cast<SimdLevel>(simd_internal::chosen_once(simd_internal::chosen, [] {
    return simd_internal::environment_asks("0", "portable") ? static_cast<int>(SimdLevel::Portable)
                                                             : static_cast<int>(supported_simd_level());
  }));
}

/// Chooses the kernels' level (at most the supported one; for tests and benchmarks that compare
/// the paths). Returns the level now in use. Not meant to be called while kernels run.
inline SimdLevel set_simd_level(SimdLevel level)
{
  const int used = std::min(static_cast<int>(level), static_cast<int>(supported_simd_level()));
  simd_internal::chosen.store(used, std::memory_order_relaxed);
  return static_cast<SimdLevel>(used);
}

/// True when the CPU and the operating system support AVX-512 F and VL.
inline bool avx512_supported()
{
#if BARY_HAVE_AVX2_DISPATCH
  static const bool supported = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
  }();
  return supported;
#else
  return false;
#endif
}
/// True when the kernels that have a 512-bit variant (the dense blocks of the supernodal
/// Cholesky factorization, core/solvers/sparse_cholesky.cpp) use it: simd_level() is AVX2 and
/// avx512_supported(), unless the environment variable BARYLAB_SIMD is "avx2" (256-bit vectors
/// only) or set_avx512_enabled(false) was called. The 512-bit variants run the same operations in
/// the same order per entry as the AVX2 ones, only more entries per instruction, so their
/// results are the same bit for bit (tested).
inline bool avx512_enabled()
{
  return simd_internal::chosen_once(simd_internal::avx512_chosen, [] {
    return avx512_supported() && !simd_internal::environment_asks("avx2") ? 1 : 0;
  }) == 1 && simd_level() == SimdLevel::AVX2;
}
/// Allows or forbids the 512-bit variants (allowed only where avx512_supported(); for tests and
/// benchmarks that compare the paths). Returns whether they are allowed now.
inline bool set_avx512_enabled(bool on)
{
  const bool used = on && avx512_supported();
  simd_internal::avx512_chosen.store(used ? 1 : 0, std::memory_order_relaxed);
  return used;
}

/// A std::allocator that aligns to 64 bytes (a cache line, an AVX-512 vector): the kernels'
/// blocks then never straddle a line.
template<class T>
struct AlignedAllocator
{
  using value_type = T;
  static constexpr std::align_val_t alignment{ 64 };
  AlignedAllocator() noexcept = default;
  template<class U>
  AlignedAllocator(const AlignedAllocator<U>&) noexcept
  {
  }
  T* allocate(std::size_t n)
  {
    if (n > std::numeric_limits<std::size_t>::max() / sizeof(T))
      throw std::bad_array_new_length();
    return static_cast<T*>(::operator new(n * sizeof(T), alignment));
  }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, alignment); }
  template<class U>
  bool operator==(const AlignedAllocator<U>&) const noexcept
  {
    return true;
  }
  template<class U>
  bool operator!=(const AlignedAllocator<U>&) const noexcept
  {
    return false;
  }
};

/// The kernels' vectors: four doubles (v4d) and eight floats (v8f), 32 bytes each. GCC / Clang
/// vector extensions (one AVX register in an AVX2 function, two SSE2 registers in a portable
/// one; the operations are element-wise IEEE operations either way), or a plain struct
/// elsewhere. Loads and stores through BARY_LOAD4 / BARY_STORE4 (doubles) and BARY_LOAD8F /
/// BARY_STORE8F (floats), any alignment of the element type. Kernels keep vectors in local
/// variables (never as a parameter or return value, whose ABI differs between the two
/// instruction sets).
#if defined(__GNUC__)
typedef double v4d __attribute__((vector_size(32)));
typedef double v4d_unaligned __attribute__((vector_size(32), aligned(8), may_alias));
typedef float v8f __attribute__((vector_size(32)));
typedef float v8f_unaligned __attribute__((vector_size(32), aligned(4), may_alias));
typedef int v8i __attribute__((vector_size(32)));
typedef int v8i_unaligned __attribute__((vector_size(32), aligned(4), may_alias));
#define BARY_LOAD4(p) (*reinterpret_cast<const ::bary::detail::v4d_unaligned*>(p))
#define BARY_STORE4(p, ...) (*reinterpret_cast<::bary::detail::v4d_unaligned*>(p) = (__VA_ARGS__))
#define BARY_LOAD8F(p) (*reinterpret_cast<const ::bary::detail::v8f_unaligned*>(p))
#define BARY_STORE8F(p, ...) (*reinterpret_cast<::bary::detail::v8f_unaligned*>(p) = (__VA_ARGS__))
#define BARY_LOAD8I(p) (*reinterpret_cast<const ::bary::detail::v8i_unaligned*>(p))
#define BARY_STORE8I(p, ...) (*reinterpret_cast<::bary::detail::v8i_unaligned*>(p) = (__VA_ARGS__))
/// Element-wise choice: lanes of a where mask m (a comparison's result) is set, else of b.
#define BARY_SELECT(m, a, b) ((m) ? (a) : (b))
#else
template<class T, int N>
struct Vector
{
  T x[N];
  T& operator[](int i) { return x[i]; }
  T operator[](int i) const { return x[i]; }
#define BARY_VECTOR_OP(op)                                                                     \
  friend Vector operator op(Vector a, const Vector& b)                                         \
  {                                                                                            \
    for (int i = 0; i < N; ++i)                                                                \
      a.x[i] = a.x[i] op b.x[i];                                                               \
    return a;                                                                                  \
  }                                                                                            \
  friend Vector operator op(Vector a, T b)                                                     \
  {                                                                                            \
    for (int i = 0; i < N; ++i)                                                                \
      a.x[i] = a.x[i] op b;                                                                    \
    return a;                                                                                  \
  }                                                                                            \
  Vector& operator op##=(const Vector& b) { return *this = *this op b; }
  BARY_VECTOR_OP(+)
  BARY_VECTOR_OP(-)
  BARY_VECTOR_OP(*)
  BARY_VECTOR_OP(/)
#undef BARY_VECTOR_OP
#define BARY_VECTOR_CMP(op)                                                                    \
  friend Vector<int, N> operator op(const Vector& a, const Vector& b)                          \
  {                                                                                            \
    Vector<int, N> m;                                                                          \
    for (int i = 0; i < N; ++i)                                                                \
      m.x[i] = a.x[i] op b.x[i] ? -1 : 0;                                                      \
    return m;                                                                                  \
  }
  BARY_VECTOR_CMP(<)
  BARY_VECTOR_CMP(>)
#undef BARY_VECTOR_CMP
  static Vector load(const T* p)
  {
    Vector v;
    for (int i = 0; i < N; ++i)
      v.x[i] = p[i];
    return v;
  }
  void store(T* p) const
  {
    for (int i = 0; i < N; ++i)
      p[i] = x[i];
  }
};
using v4d = Vector<double, 4>;
using v8f = Vector<float, 8>;
using v8i = Vector<int, 8>;
template<class M, class V>
V select(const M& m, const V& a, const V& b)
{
  V r;
  for (int i = 0; i < static_cast<int>(sizeof(r.x) / sizeof(r.x[0])); ++i)
    r.x[i] = m.x[i] ? a.x[i] : b.x[i];
  return r;
}
#define BARY_SELECT(m, a, b) (::bary::detail::select((m), (a), (b)))
#define BARY_LOAD4(p) (::bary::detail::v4d::load(p))
#define BARY_STORE4(p, ...) ((__VA_ARGS__).store(p))
#define BARY_LOAD8F(p) (::bary::detail::v8f::load(p))
#define BARY_STORE8F(p, ...) ((__VA_ARGS__).store(p))
#define BARY_LOAD8I(p) (::bary::detail::v8i::load(p))
#define BARY_STORE8I(p, ...) ((__VA_ARGS__).store(p))
#endif

/// The smallest of eight floats and its lane: a tournament (lanes l and l + 4, then l and l + 2,
/// then 0 and 1; the later lane wins only when strictly smaller), the same in every instruction
/// set. @p index: the lanes' labels; the winner's label into @p at.
BARY_ALWAYS_INLINE void lane_min(const v8f& d, const v8i& index, float& value, int& at)
{
#if defined(__GNUC__) && !defined(__clang__)
  v8f x = d;
  v8i i = index;
  {
    const v8i p = { 4, 5, 6, 7, 0, 1, 2, 3 };
    const v8f y = __builtin_shuffle(x, p);
    const v8i j = __builtin_shuffle(i, p);
    const v8i m = y < x;
    x = m ? y : x;
    i = m ? j : i;
  }
  {
    const v8i p = { 2, 3, 0, 1, 6, 7, 4, 5 };
    const v8f y = __builtin_shuffle(x, p);
    const v8i j = __builtin_shuffle(i, p);
    const v8i m = y < x;
    x = m ? y : x;
    i = m ? j : i;
  }
  {
    // the last round in the vector too (a select, not a branch: the winner is data, a branch
    // on it would be mispredicted half the time)
    const v8i p = { 1, 0, 3, 2, 5, 4, 7, 6 };
    const v8f y = __builtin_shuffle(x, p);
    const v8i j = __builtin_shuffle(i, p);
    const v8i m = y < x;
    x = m ? y : x;
    i = m ? j : i;
  }
  value = x[0];
  at = i[0];
#else
  float x[8];
  int i[8];
  for (int l = 0; l < 8; ++l)
  {
    x[l] = d[l];
    i[l] = index[l];
  }
  for (int half = 4; half >= 1; half /= 2)
    for (int l = 0; l < half; ++l)
      if (x[l + half] < x[l])
      {
        x[l] = x[l + half];
        i[l] = i[l + half];
      }
  value = x[0];
  at = i[0];
#endif
}

/// r[l] = x[p[l]] for eight lanes (p in [0, 8)).
BARY_ALWAYS_INLINE void permute8(const v8f& x, const v8i& p, float* r)
{
#if defined(__GNUC__) && !defined(__clang__)
  BARY_STORE8F(r, __builtin_shuffle(x, p));
#else
  for (int l = 0; l < 8; ++l)
    r[l] = x[p[l]];
#endif
}

} // namespace bary::detail
