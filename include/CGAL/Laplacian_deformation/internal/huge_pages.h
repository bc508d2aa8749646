// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_HUGE_PAGES_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_HUGE_PAGES_H

// Transparent huge pages for the large arrays of a preprocess. Fresh memory costs a page fault per
// 4 KiB page when it is first written, measured at 1.8 to 11 us per page on the virtual machines
// here (0.4 to 2.7 ms per MB), which was a large part of an edge-based preprocess. Where Linux
// offers transparent huge pages on request (/sys/kernel/mm/transparent_hugepage/enabled:
// "madvise" or "always"), madvise(MADV_HUGEPAGE) on a fresh, not yet written region makes its
// first writes fault 2 MiB at a time. Only the whole 2 MiB pages inside a region of at least
// 4 MiB are advised; elsewhere (other systems, older kernels, a refused request) nothing changes.
// The environment variable CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0, read once, turns it off;
// the macro CGAL_LAPLACIAN_DEFORMATION_NO_HUGE_PAGES compiles it out.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <new>
#include <vector>

#if defined(__linux__) && !defined(CGAL_LAPLACIAN_DEFORMATION_NO_HUGE_PAGES)
#include <sys/mman.h>
#if defined(MADV_HUGEPAGE)
#define CGAL_LAPDEF_HUGE_PAGES 1
#endif
#endif
#ifndef CGAL_LAPDEF_HUGE_PAGES
#define CGAL_LAPDEF_HUGE_PAGES 0
#endif

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

constexpr std::size_t huge_page_bytes = std::size_t(2) << 20;

// whether the environment variable `name` leaves a switch on (unset, or anything but "0")
inline bool environment_switch_on(const char* name)
{
  const char* e = std::getenv(name);
  return e == nullptr || std::strcmp(e, "0") != 0;
}

// whether regions are advised (false when compiled out or CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0)
inline bool huge_pages_enabled()
{
#if CGAL_LAPDEF_HUGE_PAGES
  static const bool enabled = environment_switch_on("CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES");
  return enabled;
#else
  return false;
#endif
}

#if CGAL_LAPDEF_HUGE_PAGES
// madvise(advice) on the whole pages of `page` bytes (a power of two) inside [address, address + bytes)
inline bool madvise_whole_pages(std::uintptr_t address, std::size_t bytes, std::uintptr_t page, int advice)
{
  const std::uintptr_t begin = (address + page - 1) & ~(page - 1);
  const std::uintptr_t end = (address + bytes) & ~(page - 1);
  return end > begin && madvise(reinterpret_cast<void*>(begin), end - begin, advice) == 0;
}
#endif

// advises the whole huge pages inside [address, address + bytes) for regions of at least 4 MiB;
// returns whether a request was made and accepted (an address, not a pointer: a fresh block is
// not written yet, and some compilers warn when a pointer to it is passed as `const void*`)
inline bool advise_huge_pages_at(std::uintptr_t address, std::size_t bytes)
{
#if CGAL_LAPDEF_HUGE_PAGES
  if(address == 0 || bytes < 2 * huge_page_bytes || !huge_pages_enabled())
    return false;
  return madvise_whole_pages(address, bytes, huge_page_bytes, MADV_HUGEPAGE);
#else
  (void)address;
  (void)bytes;
  return false;
#endif
}

// advise_huge_pages_at() for the block at p
inline bool advise_huge_pages(const void* p, std::size_t bytes)
{
  return advise_huge_pages_at(reinterpret_cast<std::uintptr_t>(p), bytes);
}

// Prefaulting. Where huge pages are not given (regions under 4 MiB, the parts of a region outside
// its whole 2 MiB pages, or no transparent huge pages at all), each fresh 4 KiB page still costs a
// page fault at its first write, and on the virtual machines here a fault is an exit to the
// hypervisor: about 10 to 20 us each. madvise(MADV_POPULATE_WRITE) (Linux 5.14 and later) maps the
// pages of a region at once, as writes would, in one system call: the same pages, the same memory,
// without a fault per page. It is asked only for regions about to be written in full (so that the
// memory used does not change), of at least 64 KiB; elsewhere (other systems, older kernels: the
// call fails, and nothing changes) the first writes fault as before. The environment variable
// CGAL_LAPLACIAN_DEFORMATION_PREFAULT=0, read once, turns it off.
#if CGAL_LAPDEF_HUGE_PAGES && defined(__linux__)
#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23   // Linux's value, for C libraries older than the kernel
#endif
#define CGAL_LAPDEF_PREFAULT 1
#else
#define CGAL_LAPDEF_PREFAULT 0
#endif

// whether fresh regions are prefaulted (false when compiled out or CGAL_LAPLACIAN_DEFORMATION_PREFAULT=0)
inline bool prefault_enabled()
{
#if CGAL_LAPDEF_PREFAULT
  static const bool enabled = environment_switch_on("CGAL_LAPLACIAN_DEFORMATION_PREFAULT");
  return enabled;
#else
  return false;
#endif
}

constexpr std::size_t prefault_min_bytes = std::size_t(64) << 10;

// maps the whole 4 KiB pages inside [address, address + bytes), a region of at least 64 KiB that
// the caller writes in full next; returns whether the request was made and accepted
inline bool prefault_at(std::uintptr_t address, std::size_t bytes)
{
#if CGAL_LAPDEF_PREFAULT
  if(address == 0 || bytes < prefault_min_bytes || !prefault_enabled())
    return false;
  return madvise_whole_pages(address, bytes, 4096, MADV_POPULATE_WRITE);   // Linux's smallest page (x86, ARM)
#else
  (void)address;
  (void)bytes;
  return false;
#endif
}

// a fresh region about to be written in full: huge pages advised (see above), then prefaulted
inline void prepare_fresh_at(std::uintptr_t address, std::size_t bytes)
{
  advise_huge_pages_at(address, bytes);
  prefault_at(address, bytes);
}

// v.reserve(n), the fresh storage prepared (prepare_fresh_at()) before it is written (v empty: nothing
// written yet); the caller writes its n elements
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n)
{
  const bool fresh = v.capacity() < n;
  v.reserve(n);
  if(fresh && v.empty())
    prepare_fresh_at(reinterpret_cast<std::uintptr_t>(v.data()), n * sizeof(T));
}

// v.assign(n, value) with the storage advised first when it is fresh
template <class T, class A>
void assign_huge(std::vector<T, A>& v, std::size_t n, const T& value)
{
  if(v.capacity() < n)
  {
    std::vector<T, A>().swap(v);
    reserve_huge(v, n);
  }
  v.assign(n, value);
}

// v.resize(n) with the storage advised first when it is fresh (the values are kept as resize()
// keeps them)
template <class T, class A>
void resize_huge(std::vector<T, A>& v, std::size_t n)
{
  if(v.capacity() < n)
  {
    std::vector<T, A> fresh;
    reserve_huge(fresh, n);
    fresh.assign(v.begin(), v.end());
    v.swap(fresh);
  }
  v.resize(n);
}

// m.resize(rows, cols) for a dense Eigen matrix, its storage prepared when the resize allocates it
// afresh (the values are then uninitialised, as after Eigen's resize)
template <class Dense>
void resize_dense_huge(Dense& m, std::ptrdiff_t rows, std::ptrdiff_t cols)
{
  const bool fresh = m.size() != rows * cols;
  m.resize(rows, cols);
  if(fresh)
    prepare_fresh_at(reinterpret_cast<std::uintptr_t>(m.data()), std::size_t(m.size()) * sizeof(*m.data()));
}

// the value and index arrays of a compressed sparse matrix just sized by resizeNonZeros(), prepared
// (prepare_fresh_at()) before the caller writes them
template <class SparseMatrix>
void advise_sparse_storage(SparseMatrix& m)
{
  prepare_fresh_at(reinterpret_cast<std::uintptr_t>(m.valuePtr()), std::size_t(m.nonZeros()) * sizeof(*m.valuePtr()));
  prepare_fresh_at(reinterpret_cast<std::uintptr_t>(m.innerIndexPtr()),
                   std::size_t(m.nonZeros()) * sizeof(*m.innerIndexPtr()));
}

// a^T (compressed, sorted), its fresh storage advised before it is written: what Eigen's
// transpose assignment computes, in the same order
template <class SparseMatrix>
SparseMatrix transposed_advised(const SparseMatrix& a)
{
  typedef typename SparseMatrix::StorageIndex Index;
  SparseMatrix t(a.cols(), a.rows());
  t.resizeNonZeros(a.nonZeros());
  advise_sparse_storage(t);
  Index* outer = t.outerIndexPtr();
  std::fill(outer, outer + t.outerSize() + 1, Index(0));
  for(Index k = 0; k < Index(a.outerSize()); ++k)
    for(typename SparseMatrix::InnerIterator it(a, k); it; ++it)
      ++outer[it.index() + 1];
  for(Index k = 0; k < Index(t.outerSize()); ++k)
    outer[k + 1] += outer[k];
  std::vector<Index> position(outer, outer + t.outerSize());
  for(Index k = 0; k < Index(a.outerSize()); ++k)
    for(typename SparseMatrix::InnerIterator it(a, k); it; ++it)
    {
      const Index p = position[std::size_t(it.index())]++;
      t.innerIndexPtr()[p] = k;
      t.valuePtr()[p] = it.value();
    }
  return t;
}

// An allocator for standard containers whose blocks are given to `Prepare::at(address, bytes)`
// before they are written (the C library's malloc and free).
template <class T, class Prepare>
struct Prepared_allocator
{
  typedef T value_type;
  Prepared_allocator() = default;
  template <class U>
  Prepared_allocator(const Prepared_allocator<U, Prepare>&) {}
  T* allocate(std::size_t n)
  {
    if(n > std::size_t(-1) / sizeof(T))
      throw std::bad_alloc();
    void* p = std::malloc(n * sizeof(T) + (n == 0));
    if(p == nullptr)
      throw std::bad_alloc();
    Prepare::at(reinterpret_cast<std::uintptr_t>(p), n * sizeof(T));
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <class U>
  bool operator==(const Prepared_allocator<U, Prepare>&) const { return true; }
  template <class U>
  bool operator!=(const Prepared_allocator<U, Prepare>&) const { return false; }
};
struct Advise_huge_pages
{
  static void at(std::uintptr_t address, std::size_t bytes) { advise_huge_pages_at(address, bytes); }
};
struct Prepare_fresh
{
  static void at(std::uintptr_t address, std::size_t bytes) { prepare_fresh_at(address, bytes); }
};

// An allocator whose large blocks (4 MiB and more) are advised before they are written: the
// vectors of a preprocess that grow or are sized at run time (blocks that may stay partly
// unwritten are not prefaulted).
template <class T>
using Huge_allocator = Prepared_allocator<T, Advise_huge_pages>;
template <class T>
using Huge_vector = std::vector<T, Huge_allocator<T>>;

// An allocator for the vectors of a preprocess that are written in full once sized (constructed
// with their size, or assign()ed, and not grown later): each fresh block is prepared
// (prepare_fresh_at(): huge pages advised, pages mapped at once) before it is written.
template <class T>
using Fresh_allocator = Prepared_allocator<T, Prepare_fresh>;
template <class T>
using Fresh_vector = std::vector<T, Fresh_allocator<T>>;

// Allocation functions for SuiteSparse (CHOLMOD's factor is the largest array of a preprocess):
// the C library's, and an advice for large blocks. free() is the C library's.
inline void* huge_malloc(std::size_t size)
{
  void* p = std::malloc(size);
  advise_huge_pages_at(reinterpret_cast<std::uintptr_t>(p), size);
  return p;
}
inline void* huge_calloc(std::size_t n, std::size_t size)
{
  void* p = std::calloc(n, size);   // large blocks are fresh mappings, not written by calloc
  if(p != nullptr && size != 0 && n <= std::size_t(-1) / size)
    advise_huge_pages_at(reinterpret_cast<std::uintptr_t>(p), n * size);
  return p;
}
inline void* huge_realloc(void* q, std::size_t size)
{
  void* p = std::realloc(q, size);
  advise_huge_pages_at(reinterpret_cast<std::uintptr_t>(p), size);
  return p;
}

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_HUGE_PAGES_H
