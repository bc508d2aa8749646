// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_PARALLEL_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_PARALLEL_H

#include <CGAL/tags.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#endif

#include <cstddef>
#include <type_traits>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// whether ConcurrencyTag asks for TBB's threads and TBB is linked
template <class ConcurrencyTag>
constexpr bool runs_in_parallel()
{
#ifdef CGAL_LINKED_WITH_TBB
  return std::is_convertible<ConcurrencyTag, CGAL::Parallel_tag>::value;
#else
  return false;
#endif
}

#ifdef CGAL_LINKED_WITH_TBB
// the parallel loop of for_each_block(): `call(f, begin, end)` per block of about `grain` on TBB's
// threads. Not a template, so that TBB's parallel_for is instantiated once for every body of the
// package (a body is called through a function pointer, once per block)
inline void parallel_blocks(std::size_t n, std::size_t grain, void (*call)(const void*, std::size_t, std::size_t),
                            const void* f)
{
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [call, f](const tbb::blocked_range<std::size_t>& range) { call(f, range.begin(), range.end()); });
}
#endif

// f(begin, end) over [0, n) in blocks of about `grain`, on TBB's threads when `parallel`
template <class F>
void for_each_block(std::size_t n, bool parallel, const F& f, std::size_t grain = 256)
{
#ifdef CGAL_LINKED_WITH_TBB
  if(parallel)
  {
    parallel_blocks(n, grain, [](const void* body, std::size_t begin, std::size_t end) {
      (*static_cast<const F*>(body))(begin, end);
    }, &f);
    return;
  }
#else
  (void)parallel;
  (void)grain;
#endif
  f(std::size_t(0), n);
}

// One `Workspace` per thread (only one when sequential), for for_each_block bodies that need
// scratch arrays: `local()` returns the calling thread's.
template <class Workspace>
class Per_thread
{
public:
  explicit Per_thread(bool parallel) : m_parallel(parallel) {}
  Workspace& local()
  {
#ifdef CGAL_LINKED_WITH_TBB
    if(m_parallel)
      return m_per_thread.local();
#endif
    return m_single;
  }

private:
  bool m_parallel;
  Workspace m_single;
#ifdef CGAL_LINKED_WITH_TBB
  tbb::enumerable_thread_specific<Workspace> m_per_thread;
#endif
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_PARALLEL_H
