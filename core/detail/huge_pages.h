#pragma once
/// @file detail/huge_pages.h
/// A hint to Linux to back a large, new array with transparent huge pages (2 MiB) before its
/// first touch: the batch calls' weight matrices (#P x #C doubles, hundreds of MB) are new on
/// every call, and with 4 KiB pages their first touch costs a page fault every 4 KiB (a fifth of
/// a one-thread 3D mean value call once its kernel was vectorised) and, where rows are written
/// in no particular order, a TLB miss nearly every row. A hint only: the kernel's madvise
/// setting decides, and elsewhere it does nothing.

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace bary::detail
{

/// Advises huge pages for the whole 2 MiB pages inside [data, data + bytes).
inline void advise_huge_pages(void* data, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::uintptr_t huge = std::uintptr_t(1) << 21;
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (at + huge - 1) & ~(huge - 1), end = (at + bytes) & ~(huge - 1);
  if (end > begin)
    madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

/// v = n copies of value. When v's capacity is short, in new storage advised as above before
/// its first touch (for the per-point arrays of the batch calls: on the 2-vCPU virtual machines
/// this project is measured on, a first touch of a 4 KiB page costs ~11 us (60 MB: 170 ms), of
/// a 2 MiB page ~15 us once the host has backed it); otherwise in v's storage.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& value = T())
{
  if (v.capacity() >= n)
  {
    v.assign(n, value);
    return;
  }
  std::vector<T> fresh;
  fresh.reserve(n);
  advise_huge_pages(fresh.data(), n * sizeof(T));
  fresh.assign(n, value);
  v.swap(fresh);
}

} // namespace bary::detail
