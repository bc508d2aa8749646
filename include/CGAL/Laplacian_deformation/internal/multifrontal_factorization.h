// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_MULTIFRONTAL_FACTORIZATION_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_MULTIFRONTAL_FACTORIZATION_H

// The numeric Cholesky factorisation of a supernodal symbolic factor (CHOLMOD's layout, see
// internal/supernodal_solve.h), multifrontal: supernode s assembles its front (its own columns of
// P N P^T and the update matrices of its children, added in the children's order), factors the
// diagonal block (LAPACK dpotrf), solves the block below it (BLAS dtrsm) and leaves the update
// matrix of its ancestors (BLAS dsyrk): one call of each per supernode, on blocks as large as the
// supernode, instead of one pair of calls per (descendant, supernode) pair. Disjoint subtrees of
// the supernodal elimination tree are factored on TBB's threads; the supernodes above them (the
// top, whose blocks are the largest) one after the other, each large one's dtrsm split into blocks
// of rows and its dsyrk into panels of columns (dsyrk on the panel's diagonal block, dgemm below
// it), the pieces on TBB's threads. The BLAS itself always runs on the calling thread: OpenBLAS's
// own threads, once used, spin (sched_yield) for about 2^28 cycles after each call, taking a core
// from the TBB threads of the deform() calls that follow a preprocess() on a machine with few
// cores (see Cholmod_supernodal_llt). Each supernode's arithmetic is fixed (its children are assembled in
// index order, the pieces' bounds depend on the sizes only), so the factor does not depend on the
// threads' timing.
//
// The BLAS and LAPACK routines are those already loaded with CHOLMOD, found at run time (dlsym);
// where they are not found (or on systems without dlsym) `available()` is false and the caller uses
// CHOLMOD's own factorisation. With OpenBLAS, its thread count is set to 1 during the factorisation
// and restored afterwards (a process-wide setting of OpenBLAS).

#include <CGAL/Laplacian_deformation/internal/huge_pages.h>
#include <CGAL/Laplacian_deformation/internal/parallel.h>
#include <CGAL/Laplacian_deformation/internal/supernodal_solve.h>
#include <CGAL/use.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/parallel_for.h>
#endif

#if defined(__unix__) || defined(__APPLE__)
#include <dlfcn.h>
#define CGAL_LAPDEF_HAS_DLSYM 1
#else
#define CGAL_LAPDEF_HAS_DLSYM 0
#endif

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <queue>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// the dense kernels (Fortran BLAS / LAPACK calling convention), found once per process
struct Dense_kernels
{
  typedef void (*Potrf)(const char*, const int*, double*, const int*, int*);
  typedef void (*Trsm)(const char*, const char*, const char*, const char*, const int*, const int*,
                       const double*, const double*, const int*, double*, const int*);
  typedef void (*Syrk)(const char*, const char*, const int*, const int*, const double*, const double*,
                       const int*, const double*, double*, const int*);
  typedef void (*Gemm)(const char*, const char*, const int*, const int*, const int*, const double*,
                       const double*, const int*, const double*, const int*, const double*, double*, const int*);
  typedef void (*Set_threads)(int);
  typedef int (*Get_threads)();
  Potrf potrf = nullptr;
  Trsm trsm = nullptr;
  Syrk syrk = nullptr;
  Gemm gemm = nullptr;                 // only for the top's split updates (none: not split)
  Set_threads set_threads = nullptr;   // OpenBLAS's, when it is the BLAS
  Get_threads get_threads = nullptr;

  bool available() const { return potrf != nullptr && trsm != nullptr && syrk != nullptr; }

  static const Dense_kernels& instance()
  {
    static const Dense_kernels k = [] {
      Dense_kernels d;
#if CGAL_LAPDEF_HAS_DLSYM
      d.potrf = reinterpret_cast<Potrf>(dlsym(RTLD_DEFAULT, "dpotrf_"));
      d.trsm = reinterpret_cast<Trsm>(dlsym(RTLD_DEFAULT, "dtrsm_"));
      d.syrk = reinterpret_cast<Syrk>(dlsym(RTLD_DEFAULT, "dsyrk_"));
      d.gemm = reinterpret_cast<Gemm>(dlsym(RTLD_DEFAULT, "dgemm_"));
      d.set_threads = reinterpret_cast<Set_threads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
      d.get_threads = reinterpret_cast<Get_threads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
      if(d.set_threads == nullptr || d.get_threads == nullptr)
        d.set_threads = nullptr, d.get_threads = nullptr;
#endif
      return d;
    }();
    return k;
  }
};

// a supernodal factor to be filled: the symbolic part read-only (the view's), the values written
struct Supernodal_factor_target : Supernodal_factor_view
{
  double* writable_values = nullptr;   // the same array as `values`
};

class Multifrontal_factorization
{
public:
  // Prepares the factorisation of the symmetric matrix N given by its lower triangle in compressed
  // column storage (`outer`: n + 1 offsets, `inner`: row indices; entries above the diagonal, if
  // any, are ignored) into the symbolic factor `l` of P N P^T, P given by `perm` (row k of P N P^T
  // is row perm[k] of N; nullptr: identity), for up to `bins` concurrent groups of subtrees (1:
  // sequential). Returns false when an entry of N falls outside the pattern of L (`l` is not the
  // analysis of this pattern) or `l` is not a supernodal elimination tree.
  bool analyse(const Supernodal_factor_target& l, const int* perm, int n, const int* outer, const int* inner,
               int bins)
  {
    m_valid = false;
    m_n = n;
    m_nsuper = l.nsuper;
    if(l.n != n)
      return false;
    const std::size_t nn = std::size_t(n), ns = std::size_t(l.nsuper);
    std::vector<int> inverse(nn);
    for(int k = 0; k < n; ++k)
      inverse[std::size_t(perm ? perm[k] : k)] = k;
    std::vector<int> column_super(nn);
    for(int s = 0; s < l.nsuper; ++s)
      for(int c = l.super[s]; c < l.super[s + 1]; ++c)
        column_super[std::size_t(c)] = s;
    // the tree: parent = the supernode of the first row below the diagonal block
    m_parent.assign(ns, -1);
    for(int s = 0; s < l.nsuper; ++s)
    {
      const int nc = l.super[s + 1] - l.super[s];
      if(l.pi[s] + nc < l.pi[s + 1])
      {
        const int p = column_super[std::size_t(l.rows[l.pi[s] + nc])];
        if(p <= s)
          return false;
        m_parent[std::size_t(s)] = p;
      }
    }
    m_child_start.assign(ns + 1, 0);
    for(int s = 0; s < l.nsuper; ++s)
      if(m_parent[std::size_t(s)] >= 0)
        ++m_child_start[std::size_t(m_parent[std::size_t(s)]) + 1];
    for(std::size_t s = 0; s < ns; ++s)
      m_child_start[s + 1] += m_child_start[s];
    m_children.assign(std::size_t(m_child_start[ns]), 0);
    {
      std::vector<int> fill(m_child_start.begin(), m_child_start.end() - 1);
      for(int s = 0; s < l.nsuper; ++s)   // increasing: each child list sorted
        if(m_parent[std::size_t(s)] >= 0)
          m_children[std::size_t(fill[std::size_t(m_parent[std::size_t(s)])]++)] = s;
    }
    // N's entries grouped by the supernode of their column in P N P^T, each with its offset in the
    // supernode's block
    const std::size_t nnz = std::size_t(outer[n]);
    Huge_vector<int> entry_row, entry_col;   // fresh arrays of N's size: advised (first touches)
    assign_huge(entry_row, nnz, -1);
    assign_huge(entry_col, nnz, -1);
    m_entry_start.assign(ns + 1, 0);
    for(int j = 0; j < n; ++j)
      for(int k = outer[j]; k < outer[j + 1]; ++k)
      {
        const int i = inner[k];
        if(i < j)
          continue;
        const int pi = inverse[std::size_t(i)], pj = inverse[std::size_t(j)];
        entry_row[std::size_t(k)] = (std::max)(pi, pj);
        entry_col[std::size_t(k)] = (std::min)(pi, pj);
        ++m_entry_start[std::size_t(column_super[std::size_t(entry_col[std::size_t(k)])]) + 1];
      }
    for(std::size_t s = 0; s < ns; ++s)
      m_entry_start[s + 1] += m_entry_start[s];
    assign_huge(m_entry_source, std::size_t(m_entry_start[ns]), 0);
    assign_huge(m_entry_offset, std::size_t(m_entry_start[ns]), 0);
    {
      std::vector<int> fill(m_entry_start.begin(), m_entry_start.end() - 1);
      for(std::size_t k = 0; k < nnz; ++k)
        if(entry_col[k] >= 0)
          m_entry_source[std::size_t(fill[std::size_t(column_super[std::size_t(entry_col[k])])]++)] = int(k);
    }
    std::vector<int> local(nn, -1);   // row -> position in the current supernode's rows
    for(int s = 0; s < l.nsuper; ++s)
    {
      const int nr = l.pi[s + 1] - l.pi[s];
      for(int r = 0; r < nr; ++r)
        local[std::size_t(l.rows[l.pi[s] + r])] = r;
      for(int e = m_entry_start[std::size_t(s)]; e < m_entry_start[std::size_t(s) + 1]; ++e)
      {
        const std::size_t k = std::size_t(m_entry_source[std::size_t(e)]);
        const int r = local[std::size_t(entry_row[k])];
        if(r < 0)
          return false;    // outside the pattern of L
        m_entry_offset[std::size_t(e)] = (entry_col[k] - l.super[s]) * nr + r;
      }
      for(int r = 0; r < nr; ++r)
        local[std::size_t(l.rows[l.pi[s] + r])] = -1;
    }
    // a postorder of the tree (roots and children in increasing index): the order of the sequential
    // factorisation, in which a supernode's children's update matrices are the last ones on the
    // stack. CHOLMOD's factors are postordered (then it is 0, 1, ...) unless its `postorder` is
    // turned off; any order with children before parents gives the same factor
    m_order.clear();
    m_order.reserve(ns);
    {
      std::vector<int> path, next(m_child_start.begin(), m_child_start.end() - 1);
      for(int root = 0; root < l.nsuper; ++root)
      {
        if(m_parent[std::size_t(root)] >= 0)
          continue;
        path.push_back(root);
        while(!path.empty())
        {
          const int s = path.back();
          if(next[std::size_t(s)] < m_child_start[std::size_t(s) + 1])
            path.push_back(m_children[std::size_t(next[std::size_t(s)]++)]);
          else
          {
            m_order.push_back(s);
            path.pop_back();
          }
        }
      }
    }
    build_schedule(l, bins);
    m_valid = true;
    return true;
  }

  bool valid() const { return m_valid; }

  // Factors: fills l.writable_values (every value of every supernode's block). Returns n on success, or the
  // first column (in P N P^T's order) whose pivot was not positive (or not a number).
  int factor(const Supernodal_factor_target& l, const double* values, bool parallel)
  {
    const Dense_kernels& blas = Dense_kernels::instance();
    release();   // also what an exception (std::bad_alloc) left
    const std::size_t ns = std::size_t(l.nsuper);
    m_update.assign(ns, nullptr);
    m_on_stack.assign(ns, 0);
    m_exported.resize(ns);
    m_failed_column = l.n;
    m_split_fronts = 0;
    One_blas_thread guard(blas);   // restored on leaving, also by an exception
#ifdef CGAL_LINKED_WITH_TBB
    if(parallel && m_subtrees.size() >= 2)
    {
      std::vector<int> failed(m_subtrees.size(), l.n);
      // every subtree's stack fits the largest subtree's peak; the top's children that are
      // subtree roots are kept off the stack (their update matrices are moved out by the subtree)
      std::size_t subtree_peak = 0;
      for(int root : m_subtrees)
        subtree_peak = (std::max)(subtree_peak, stack_peak(l, m_first[std::size_t(root)], root + 1, nullptr, root));
      {
        Per_thread<Workspace> per_thread(true);
        tbb::parallel_for(std::size_t(0), m_subtrees.size(), [&](std::size_t t) {
          Workspace& w = per_thread.local();   // one per thread, not per subtree (first touches)
          w.reserve(std::size_t(l.n), subtree_peak);
          const int root = m_subtrees[t];
          for(int s = m_first[std::size_t(root)]; s <= root && failed[t] == l.n; ++s)
            failed[t] = front(l, values, s, w, blas, false);
          if(failed[t] == l.n)
            export_update(l, root, w);
        }, tbb::simple_partitioner());
      }
      for(int f : failed)
        m_failed_column = (std::min)(m_failed_column, f);
      if(m_failed_column != l.n)
        return release(), m_failed_column;
      Workspace w;
      w.reserve(std::size_t(l.n), stack_peak(l, 0, 0, &m_top, -1));
      for(int s : m_top)
        if((m_failed_column = front(l, values, s, w, blas, true)) != l.n)
          break;
      return release(), m_failed_column;
    }
#endif
    Workspace w;
    w.reserve(std::size_t(l.n), stack_peak(l, 0, 0, &m_order, -1));
    for(int s : m_order)
      if((m_failed_column = front(l, values, s, w, blas, parallel)) != l.n)
        break;
    return release(), m_failed_column;
  }

  // the number of subtrees factored concurrently (0: sequential), and the top's share of the work
  std::size_t number_of_subtrees() const { return m_subtrees.size() >= 2 ? m_subtrees.size() : 0; }
  double top_share() const { return m_top_share; }
  // the fronts whose update the last factor() split on TBB's threads
  std::size_t number_of_split_fronts() const { return m_split_fronts; }

private:
  // The update matrices live on a stack: the supernodes are factored in a postorder of the
  // elimination tree (m_order; with concurrent subtrees, which exist only when the supernodes'
  // order is a postorder, each subtree and the top in increasing index), so that the update matrices
  // of a supernode's children are the last ones left on the stack when it is factored. Its own is
  // formed above them, then moved down over them once they are added (one copy of it). The stack
  // is allocated once at its peak (stack_peak()), instead of a fresh block per supernode: the sum
  // of the update matrices' sizes is several times their peak, and fresh memory costs a page
  // fault per 4 KiB page at its first write (the largest part of a factorisation's page faults
  // when each was a fresh calloc).
  struct Free
  {
    void operator()(double* p) const { std::free(p); }
  };
  struct Workspace
  {
    void reserve(std::size_t n, std::size_t stack_size)
    {
      if(local.size() != n)
        local.assign(n, -1);
      if(capacity < stack_size)
      {
        stack.reset();
        stack.reset(static_cast<double*>(huge_malloc(stack_size * sizeof(double))));
        if(!stack)
          throw std::bad_alloc();
        prefault_at(reinterpret_cast<std::uintptr_t>(stack.get()), stack_size * sizeof(double));   // used in full at its peak
        capacity = stack_size;
      }
      top = 0;
    }
    std::vector<int> local;       // row -> position in the current front (-1 between fronts)
    std::vector<int> relative;    // a child's rows -> positions in the front
    std::unique_ptr<double, Free> stack;   // update matrices, [0, top) in use
    std::size_t capacity = 0, top = 0;
  };

  static std::size_t update_size(const Supernodal_factor_target& l, int s)
  {
    const std::size_t m = std::size_t(l.pi[s + 1] - l.pi[s] - (l.super[s + 1] - l.super[s]));
    return m * m;
  }
  // the largest size of a stack on which the supernodes [first, last) (or those of `order`) are
  // factored in that order, as front() and export_update() use it: a child's update matrix is on
  // the stack when the child was factored on it and is not `exported` (a subtree root)
  std::size_t stack_peak(const Supernodal_factor_target& l, int first, int last, const std::vector<int>* order,
                         int exported) const
  {
    std::vector<std::size_t> at(std::size_t(l.nsuper), std::size_t(-1));   // stack offsets
    std::size_t top = 0, peak = 0;
    auto visit = [&](int s) {
      std::size_t base = top;   // the children on this stack (factored on it, not empty, not exported)
      for(int k = m_child_start[std::size_t(s)]; k < m_child_start[std::size_t(s) + 1]; ++k)
        base = (std::min)(base, at[std::size_t(m_children[std::size_t(k)])]);
      const std::size_t size = update_size(l, s);
      peak = (std::max)(peak, top + size);
      top = base + size;
      if(size > 0 && s != exported)
        at[std::size_t(s)] = base;
      if(s == exported)
        top = base;
    };
    if(order != nullptr)
      for(int s : *order)
        visit(s);
    else
      for(int s = first; s < last; ++s)
        visit(s);
    return peak;
  }
  // moves the update matrix of the subtree root `s` off the stack of `w` (the top adds it later)
  void export_update(const Supernodal_factor_target& l, int s, Workspace& w)
  {
    const std::size_t size = update_size(l, s);
    if(size == 0)
      return;
    double* p = static_cast<double*>(huge_malloc(size * sizeof(double)));
    if(p == nullptr)
      throw std::bad_alloc();
    prefault_at(reinterpret_cast<std::uintptr_t>(p), size * sizeof(double));   // written in full below
    m_exported[std::size_t(s)].reset(p);
    std::memcpy(p, m_update[std::size_t(s)], size * sizeof(double));
    m_update[std::size_t(s)] = p;
    m_on_stack[std::size_t(s)] = 0;
    w.top -= size;
  }

  void release()
  {
    m_update.clear();
    m_on_stack.clear();
    m_exported.clear();
  }

  // OpenBLAS's process-wide thread count set to 1 for a scope (nothing with another BLAS)
  struct One_blas_thread
  {
    explicit One_blas_thread(const Dense_kernels& blas)
      : m_blas(blas), m_threads(blas.set_threads ? blas.get_threads() : 1)
    {
      if(m_threads != 1)
        m_blas.set_threads(1);
    }
    ~One_blas_thread()
    {
      if(m_threads != 1)
        m_blas.set_threads(m_threads);
    }
    One_blas_thread(const One_blas_thread&) = delete;
    One_blas_thread& operator=(const One_blas_thread&) = delete;
    const Dense_kernels& m_blas;
    int m_threads;
  };

  static double work_of(double nc, double m) { return nc * nc * nc / 3. + nc * nc * m + nc * m * m + 64.; }

  void build_schedule(const Supernodal_factor_target& l, int bins)
  {
    const std::size_t ns = std::size_t(l.nsuper);
    m_first.assign(ns, 0);
    std::vector<double> work(ns);
    double total = 0;
    for(int s = 0; s < l.nsuper; ++s)
    {
      m_first[std::size_t(s)] = s;
      const int nc = l.super[s + 1] - l.super[s], m = l.pi[s + 1] - l.pi[s] - nc;
      work[std::size_t(s)] += work_of(nc, m);
    }
    bool postordered = true;
    for(int s = 0; s < l.nsuper; ++s)
    {
      const int p = m_parent[std::size_t(s)];
      total += work_of(l.super[s + 1] - l.super[s], l.pi[s + 1] - l.pi[s] - (l.super[s + 1] - l.super[s]));
      if(p >= 0)
      {
        work[std::size_t(p)] += work[std::size_t(s)];
        m_first[std::size_t(p)] = (std::min)(m_first[std::size_t(p)], m_first[std::size_t(s)]);
      }
    }
    // every subtree contiguous: [first[s], s] holds exactly the subtree of s
    std::vector<int> size(ns, 1);
    for(int s = 0; s < l.nsuper; ++s)
    {
      postordered = postordered && m_first[std::size_t(s)] == s + 1 - size[std::size_t(s)];
      if(m_parent[std::size_t(s)] >= 0)
        size[std::size_t(m_parent[std::size_t(s)])] += size[std::size_t(s)];
    }
    m_subtrees.clear();
    m_top.clear();
    m_top_share = 1;
    if(!postordered || bins < 2 || total < 2e6)
      return;
    // the heaviest subtree split until none holds more than total / (4 bins)
    std::priority_queue<std::pair<double, int>> heap;
    for(int s = 0; s < l.nsuper; ++s)
      if(m_parent[std::size_t(s)] < 0)
        heap.push({work[std::size_t(s)], s});
    std::vector<char> in_top(ns, 0);
    const double limit = total / (4. * bins);
    while(!heap.empty() && heap.top().first > limit)
    {
      const int s = heap.top().second;
      heap.pop();
      in_top[std::size_t(s)] = 1;
      for(int k = m_child_start[std::size_t(s)]; k < m_child_start[std::size_t(s) + 1]; ++k)
        heap.push({work[std::size_t(m_children[std::size_t(k)])], m_children[std::size_t(k)]});
    }
    std::vector<std::pair<double, int>> subtrees;
    while(!heap.empty())
      subtrees.push_back(heap.top()), heap.pop();
    if(subtrees.size() < 2)
      return;
    std::sort(subtrees.begin(), subtrees.end(), [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    double top = total;
    for(const auto& t : subtrees)
      m_subtrees.push_back(t.second), top -= t.first;
    for(int s = 0; s < l.nsuper; ++s)
      if(in_top[std::size_t(s)])
        m_top.push_back(s);
    m_top_share = top / total;
  }

  // The update of a large front on TBB's threads: X21 := X21 L11^-T by blocks of rows (independent
  // rows), then U -= X21 X21^T by panels of columns of U's lower triangle, each dsyrk on the
  // panel's diagonal block and dgemm below it, the panels' bounds chosen for about equal work
  // (equal areas of the triangle). The pieces depend on m and nc only: the same arithmetic
  // whichever thread runs them. False (nothing done) when the front is too small to gain from it
  // (or dgemm was not found, or without TBB).
  static bool split_update(const Dense_kernels& blas, double* x, int nr, int nc, int m, double* u)
  {
#ifdef CGAL_LINKED_WITH_TBB
    // below about 4e6 multiply-adds (m nc (m + nc): well under a millisecond on one thread) the
    // tasks' overhead would eat the gain
    if(blas.gemm == nullptr || m < 128 || double(m) * double(nc) * double(m + nc) < 4e6)
      return false;
    const double one = 1., minus_one = -1.;
    const int pieces = (std::min)(16, m / 64);
    double* const x21 = x + nc;
    tbb::parallel_for(0, pieces, [&](int p) {
      const int r0 = int(std::int64_t(m) * p / pieces), r1 = int(std::int64_t(m) * (p + 1) / pieces), mr = r1 - r0;
      blas.trsm("R", "L", "T", "N", &mr, &nc, &one, x, &nr, x21 + r0, &nr);
    }, tbb::simple_partitioner());
    // panel p holds columns [a_p, a_{p+1}) with (m - a_p)^2 = m^2 (1 - p / pieces)
    std::vector<int> bound(std::size_t(pieces) + 1);
    for(int p = 0; p <= pieces; ++p)
      bound[std::size_t(p)] = m - int(std::lround(double(m) * std::sqrt(1. - double(p) / double(pieces))));
    tbb::parallel_for(0, pieces, [&](int p) {
      const int a = bound[std::size_t(p)], b = bound[std::size_t(p) + 1], w = b - a, below = m - b;
      if(w <= 0)
        return;
      double* const panel = u + std::size_t(a) * std::size_t(m);
      blas.syrk("L", "N", &w, &nc, &minus_one, x21 + a, &nr, &one, panel + a, &m);
      if(below > 0)
        blas.gemm("N", "T", &below, &w, &nc, &minus_one, x21 + b, &nr, x21 + a, &nr, &one, panel + b, &m);
    }, tbb::simple_partitioner());
    return true;
#else
    CGAL_USE(blas); CGAL_USE(x); CGAL_USE(nr); CGAL_USE(nc); CGAL_USE(m); CGAL_USE(u);
    return false;
#endif
  }

  // assembles, factors and leaves the update matrix of supernode s; returns n or the failed column.
  // `split`: a large front's update is split on TBB's threads (split_update())
  int front(const Supernodal_factor_target& l, const double* values, int s, Workspace& w, const Dense_kernels& blas,
            bool split)
  {
    const int k0 = l.super[s], nc = l.super[s + 1] - k0, nr = l.pi[s + 1] - l.pi[s], m = nr - nc;
    const int* rows = l.rows + l.pi[s];
    double* x = l.writable_values + l.px[s];
    std::fill(x, x + std::size_t(nr) * std::size_t(nc), 0.);
    for(int e = m_entry_start[std::size_t(s)]; e < m_entry_start[std::size_t(s) + 1]; ++e)
      x[m_entry_offset[std::size_t(e)]] += values[m_entry_source[std::size_t(e)]];
    // the children's update matrices, in index order: those on the stack are its last ones
    const int c0 = m_child_start[std::size_t(s)], c1 = m_child_start[std::size_t(s) + 1];
    std::size_t base = w.top;
    for(int k = c0; k < c1; ++k)
    {
      const int c = m_children[std::size_t(k)];
      if(m_on_stack[std::size_t(c)])
        base = (std::min)(base, std::size_t(m_update[std::size_t(c)] - w.stack.get()));
    }
    // this one (zeroed) above them
    const std::size_t size = std::size_t(m) * std::size_t(m);
    CGAL_assertion(w.top + size <= w.capacity);
    double* const u = m > 0 ? w.stack.get() + w.top : nullptr;
    if(m > 0)
      std::memset(u, 0, size * sizeof(double));
    if(c0 < c1)
    {
      for(int r = 0; r < nr; ++r)
        w.local[std::size_t(rows[r])] = r;
      for(int k = c0; k < c1; ++k)
      {
        const int c = m_children[std::size_t(k)];
        const int cnc = l.super[c + 1] - l.super[c], cm = l.pi[c + 1] - l.pi[c] - cnc;
        const int* crows = l.rows + l.pi[c] + cnc;
        const double* cu = m_update[std::size_t(c)];
        w.relative.resize(std::size_t(cm));
        for(int i = 0; i < cm; ++i)
          w.relative[std::size_t(i)] = w.local[std::size_t(crows[i])];
        const int* rel = w.relative.data();
        for(int j = 0; j < cm; ++j)
        {
          const int tj = rel[j];
          const double* col = cu + std::size_t(j) * std::size_t(cm);
          if(tj < nc)
          {
            double* target = x + std::size_t(tj) * std::size_t(nr);
            for(int i = j; i < cm; ++i)
              target[rel[i]] += col[i];
          }
          else
          {
            double* target = u + std::size_t(tj - nc) * std::size_t(m);
            for(int i = j; i < cm; ++i)
              target[rel[i] - nc] += col[i];
          }
        }
        m_update[std::size_t(c)] = nullptr;
        m_exported[std::size_t(c)].reset();   // a subtree root's (nothing for one on the stack)
      }
      for(int r = 0; r < nr; ++r)
        w.local[std::size_t(rows[r])] = -1;
    }
    int info = 0;
    blas.potrf("L", &nc, x, &nr, &info);
    if(info != 0)
      return info > 0 ? k0 + info - 1 : k0;
    for(int j = 0; j < nc; ++j)   // a NaN pivot (LAPACK implementations differ on reporting it)
      if(!(x[std::size_t(j) * std::size_t(nr) + std::size_t(j)] > 0.))
        return k0 + j;
    if(m > 0)
    {
      const double one = 1., minus_one = -1.;
      if(split && split_update(blas, x, nr, nc, m, u))
        ++m_split_fronts;   // only the top's fronts, one after the other
      else
      {
        blas.trsm("R", "L", "T", "N", &m, &nc, &one, x, &nr, x + nc, &nr);
        blas.syrk("L", "N", &m, &nc, &minus_one, x + nc, &nr, &one, u, &m);
      }
    }
    // the children's are added: this one takes their place on the stack
    m_update[std::size_t(s)] = nullptr;
    if(m > 0)
    {
      double* const moved = w.stack.get() + base;
      if(moved != u)
        std::memmove(moved, u, size * sizeof(double));
      m_update[std::size_t(s)] = moved;
    }
    m_on_stack[std::size_t(s)] = m > 0;
    w.top = base + size;
    return l.n;
  }

  bool m_valid = false;
  int m_n = 0, m_nsuper = 0;
  std::vector<int> m_parent, m_child_start, m_children, m_first;
  std::vector<int> m_entry_start;
  Huge_vector<int> m_entry_source, m_entry_offset;
  std::vector<int> m_order;             // the supernodes in a postorder (the sequential factorisation's)
  std::vector<int> m_subtrees, m_top;   // concurrent subtrees (their roots), then the top in order
  double m_top_share = 1;
  std::vector<double*> m_update;   // per supernode: its update matrix until its parent has added it
  std::vector<char> m_on_stack;    // whether it is on a stack (otherwise in m_exported, or none)
  std::vector<std::unique_ptr<double, Free>> m_exported;   // the subtree roots' (parallel factorisation)
  int m_failed_column = 0;
  std::size_t m_split_fronts = 0;
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_MULTIFRONTAL_FACTORIZATION_H
