// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_NORMAL_MATRIX_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_NORMAL_MATRIX_H

#include <CGAL/assertions.h>
#include <CGAL/Eigen_solver_traits.h>
#include <CGAL/Laplacian_deformation/internal/huge_pages.h>
#include <CGAL/Laplacian_deformation/internal/parallel.h>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// Whether an Eigen sparse solver reads only the lower triangle of the matrix it factors; the
// CHOLMOD wrappers are added by Cholmod_solver_traits.h.
template <class EigenSolver, class = void>
struct Eigen_solver_reads_lower_triangle : std::false_type {};
template <class M, class O>
struct Eigen_solver_reads_lower_triangle<Eigen::SimplicialLLT<M, Eigen::Lower, O>> : std::true_type {};
template <class M, class O>
struct Eigen_solver_reads_lower_triangle<Eigen::SimplicialLDLT<M, Eigen::Lower, O>> : std::true_type {};

// Whether the solver traits factor only the lower triangle (then the normal matrix is formed
// for i >= j only: half the work and half the memory); any other traits get the full matrix.
template <class SolverTraits>
struct Solver_traits_read_lower_triangle : std::false_type {};
template <class S>
struct Solver_traits_read_lower_triangle<CGAL::Eigen_solver_traits<S>> : Eigen_solver_reads_lower_triangle<S> {};

// The first element of the sorted range [first, last) that is not less than `key` (as
// std::lower_bound), by a binary search whose steps are conditional moves, not branches: the rows
// of A^T A's assembly are a dozen entries long and searched once per term of a column, where
// std::lower_bound's mispredicted branches were the assembly's largest cost.
template <class Index>
const Index* branchless_lower_bound(const Index* first, const Index* last, Index key)
{
  std::size_t length = std::size_t(last - first);
  if(length == 0)
    return first;
  while(length > 1)
  {
    const std::size_t half = length / 2;
    first = first[half] < key ? first + half : first;
    length -= half;
  }
  return first + (*first < key);
}

// N = A^T A, column by column: N(:, j) = sum over the rows r of column j of A of
// A(r, j) * A(r, :)^T. `a` is A (compressed, sorted columns); `rows(r, j, f)` calls f(i, A(r, i))
// for the entries i >= j of row r of A, in increasing i (the same values as `a`'s: A by rows in
// any form, such as A^T's columns or the operator the caller assembled A from, so that A^T need
// not be formed). With `lower_only`, only the entries i >= j of N. The result is compressed with
// sorted columns; every structural entry is kept (also a sum that cancels to zero). Each term is
// visited once: a dense accumulator and a marker per thread replace the general sparse product's
// sorting of the whole result, and the columns' entries are gathered in chunks, then copied into
// the result allocated once. With `parallel` (and TBB), columns are processed on TBB's threads;
// every entry is the same sum in the same order.
//
// The rows of a column are scattered through A's rows (on a mesh, the rows that touch a vertex
// lie far apart: on the armadillo's Loop subdivision, half of its columns' rows spread over more
// than two thirds of the rows), so each row is a cache miss behind one or two dependent loads.
// `prefetch(r, stage)` lets the caller fetch row r ahead of its use, in stages: it is called with
// stage 0 for the rows of the column `prefetch_columns_ahead` columns ahead (fetch whatever
// locates the row), then with stage 2 (the row's indices and values) for the rows of the column
// half as far ahead (stage 1, the indices alone, served a symbolic pass that no longer exists; a
// functor may still treat it). The default does nothing.
struct No_row_prefetch
{
  template <class Index>
  void operator()(Index, int) const {}
};
constexpr std::ptrdiff_t prefetch_columns_ahead = 4;

// A hint to fetch the cache line of `p`. GCC takes a function whose only effect is
// __builtin_prefetch for one without side effects and drops its calls (GCC 12 removed every
// prefetch of normal_matrix_from_rows() that way): the empty asm statement that "uses" p gives it
// an effect that the optimiser keeps, at no cost (it emits no instruction).
inline void prefetch_line(const void* p)
{
#if defined(__GNUC__)
  __builtin_prefetch(p);
  __asm__ __volatile__("" : : "r"(p));
#else
  (void)p;
#endif
}

template <class Rows, class Prefetch = No_row_prefetch>
Eigen::SparseMatrix<double> normal_matrix_from_rows(const Eigen::SparseMatrix<double>& a, const Rows& rows,
                                                    bool lower_only, bool parallel = false,
                                                    const Prefetch& prefetch = Prefetch())
{
  typedef Eigen::SparseMatrix<double>::StorageIndex Index;
  CGAL_precondition(a.isCompressed());
  const Eigen::Index n = a.cols();
  const Index* const a_outer = a.outerIndexPtr();
  const Index* const a_inner = a.innerIndexPtr();
  const double* const a_value = a.valuePtr();
  // f(i, A(r, j), A(r, i)) for every term of column j
  auto for_each_term = [a_outer, a_inner, a_value, &rows, lower_only](Index j, auto&& f) {
    for(Index k = a_outer[j]; k < a_outer[j + 1]; ++k)
    {
      const double arj = a_value[k];
      rows(a_inner[k], lower_only ? j : Index(0), [&](Index i, double ari) { f(i, arj, ari); });
    }
  };
  // before column j of [0, end): the rows of the columns ahead, in two stages
  auto fetch_ahead = [a_outer, a_inner, &prefetch](Index j, Index end, int stage) {
    const Index far = j + Index(prefetch_columns_ahead), near = j + Index(prefetch_columns_ahead / 2);
    if(far < end)
      for(Index k = a_outer[far]; k < a_outer[far + 1]; ++k)
        prefetch(a_inner[k], 0);
    if(near < end)
      for(Index k = a_outer[near]; k < a_outer[near + 1]; ++k)
        prefetch(a_inner[k], stage);
  };
  // One pass over the columns, in chunks of `chunk` columns: each chunk appends its columns'
  // entries (sorted rows, then values) to buffers of its own and records their counts; the
  // counts' prefix sums then place every chunk's entries in the result, copied chunk by chunk. The
  // result does not depend on the threads: a column's entries are those of a sequential pass.
  // (Until 2026-12-07 a first, symbolic pass counted each column's entries so that the result
  // could be written in place: every term was visited twice. The price of one pass: the entries
  // are written twice, and twice into fresh memory, the buffers and then the result (6.3 MB each
  // for the edge-based system of the 26k armadillo). The buffers are freed once copied, before any
  // factorisation's memory exists, so the peak does not change.)
  // The inner loops work on raw pointers held in locals: a write through a vector (a push_back)
  // would make the compiler reload every captured pointer at each term. One workspace per
  // thread: the marks (-(j + 2) for column j, -1: never marked; only the marks are initialised:
  // an accumulator entry is written before it is read, and the list of touched rows is a prefix).
  struct Workspace
  {
    std::vector<Index> mark;
    std::unique_ptr<Index[]> touched;
    std::unique_ptr<double[]> accumulator;
    std::size_t per_column = 0;   // entries per column of the thread's last chunk (its buffers' estimate)
  };
  auto workspace = [n](Per_thread<Workspace>& per_thread) -> Workspace& {
    Workspace& w = per_thread.local();
    if(w.mark.size() != std::size_t(n))
    {
      w.mark.assign(std::size_t(n), -1);
      w.touched.reset(new Index[std::size_t(n)]);
      w.accumulator.reset(new double[std::size_t(n)]);
    }
    return w;
  };
  struct Chunk
  {
    std::vector<Index> rows;
    std::vector<double> values;
  };
  constexpr std::size_t chunk = 512;
  const std::size_t chunks = (std::size_t(n) + chunk - 1) / chunk;
  std::vector<Chunk> buffers(chunks);

  Eigen::SparseMatrix<double> result(n, n);
  Index* outer = result.outerIndexPtr();
  Per_thread<Workspace> per_thread(parallel);
  outer[0] = 0;
  for_each_block(chunks, parallel, [&](std::size_t first_chunk, std::size_t last_chunk) {
    Workspace& w = workspace(per_thread);
    Index* const mark = w.mark.data();
    Index* const touched = w.touched.get();
    double* const accumulator = w.accumulator.get();
    for(std::size_t c = first_chunk; c < last_chunk; ++c)
    {
      const Index begin = Index(c * chunk), end = Index((std::min)((c + 1) * chunk, std::size_t(n)));
      Chunk& out = buffers[c];
      // sized by the thread's last chunk, an eighth more: one allocation per buffer in general
      const std::size_t expected = std::size_t(end - begin) * (w.per_column > 0 ? w.per_column + w.per_column / 8 + 1 : 32);
      out.rows.reserve(expected);
      out.values.reserve(expected);
      for(Index j = begin; j < end; ++j)
      {
        fetch_ahead(j, Index(n), 2);   // also across the chunk's end
        const Index stamp = Index(-2) - j;
        Index number_touched = 0;
        for_each_term(j, [mark, touched, accumulator, stamp, &number_touched](Index i, double arj, double ari) {
          if(mark[i] != stamp)
          {
            mark[i] = stamp;
            accumulator[i] = 0.;
            touched[number_touched++] = i;
          }
          accumulator[i] += arj * ari;
        });
        std::sort(touched, touched + number_touched);
        outer[j + 1] = number_touched;
        out.rows.insert(out.rows.end(), touched, touched + number_touched);
        for(Index t = 0; t < number_touched; ++t)
          out.values.push_back(accumulator[touched[t]]);
      }
      w.per_column = (out.rows.size() + std::size_t(end - begin) - 1) / std::size_t(end - begin);
    }
  }, 1);
  for(Eigen::Index j = 0; j < n; ++j)
    outer[j + 1] += outer[j];
  result.resizeNonZeros(outer[n]);
  advise_sparse_storage(result);   // fresh: not written yet
  Index* const inner = result.innerIndexPtr();
  double* const values = result.valuePtr();
  for_each_block(chunks, parallel, [&](std::size_t first_chunk, std::size_t last_chunk) {
    for(std::size_t c = first_chunk; c < last_chunk; ++c)
    {
      Chunk& in = buffers[c];
      const Index at = outer[c * chunk];
      std::copy(in.rows.begin(), in.rows.end(), inner + at);
      std::copy(in.values.begin(), in.values.end(), values + at);
      std::vector<Index>().swap(in.rows);
      std::vector<double>().swap(in.values);
    }
  }, 1);
  return result;
}

// normal_matrix_from_rows() with the rows of A read from `at` = A^T (compressed, sorted columns).
inline Eigen::SparseMatrix<double> normal_matrix(const Eigen::SparseMatrix<double>& a,
                                                 const Eigen::SparseMatrix<double>& at, bool lower_only,
                                                 bool parallel = false)
{
  typedef Eigen::SparseMatrix<double>::StorageIndex Index;
  if(!a.isCompressed() || !at.isCompressed())
  {
    Eigen::SparseMatrix<double> a_compressed(a), at_compressed(at);
    a_compressed.makeCompressed();
    at_compressed.makeCompressed();
    return normal_matrix(a_compressed, at_compressed, lower_only, parallel);
  }
  const Index* t_outer = at.outerIndexPtr();
  const Index* t_inner = at.innerIndexPtr();
  const double* t_value = at.valuePtr();
  auto rows = [t_outer, t_inner, t_value](Index r, Index j, auto&& f) {
    const Index* begin = t_inner + t_outer[r];
    const Index* end = t_inner + t_outer[r + 1];
    for(const Index* p = j > 0 ? branchless_lower_bound(begin, end, j) : begin; p != end; ++p)
      f(*p, t_value[p - t_inner]);
  };
  auto prefetch = [t_outer, t_inner, t_value](Index r, int stage) {
    if(stage == 0)
      prefetch_line(t_outer + r);
    else
    {
      prefetch_line(t_inner + t_outer[r]);
      if(stage == 2)
        prefetch_line(t_value + t_outer[r]);
    }
  };
  return normal_matrix_from_rows(a, rows, lower_only, parallel, prefetch);
}

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_NORMAL_MATRIX_H
