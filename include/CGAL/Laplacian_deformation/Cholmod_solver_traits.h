// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H
#define CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H

// Needs SuiteSparse's CHOLMOD: link the CMake target CGAL::Laplacian_deformation_cholmod.
#include <CGAL/Eigen_solver_traits.h>
#include <CGAL/Laplacian_deformation/internal/normal_matrix.h>
#include <CGAL/Laplacian_deformation/internal/huge_pages.h>
#include <CGAL/Laplacian_deformation/internal/multifrontal_factorization.h>
#include <CGAL/Laplacian_deformation/internal/supernodal_solve.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <thread>
#include <type_traits>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// Once per process: SuiteSparse's allocation functions (used by CHOLMOD for its factor) replaced by
// the C library's with a transparent-huge-page advice for large blocks (internal/huge_pages.h), as
// long as they are still the C library's own (a user's allocator is kept). Returns whether they are.
inline bool use_huge_pages_in_suitesparse()
{
#if CGAL_LAPDEF_HUGE_PAGES && defined(SUITESPARSE_MAIN_VERSION) && SUITESPARSE_MAIN_VERSION == 5
  static const bool installed = [] {
    if(!huge_pages_enabled())
      return false;
    SuiteSparse_config_struct& c = SuiteSparse_config;
    if(c.malloc_func != &std::malloc || c.calloc_func != &std::calloc || c.realloc_func != &std::realloc ||
       c.free_func != &std::free)
      return false;
    c.malloc_func = &huge_malloc;
    c.calloc_func = &huge_calloc;
    c.realloc_func = &huge_realloc;
    return true;
  }();
  return installed;
#else
  return false;
#endif
}

} // namespace internal

/*!
\ingroup PkgLaplacianDeformationSolver
\brief `Eigen::CholmodSupernodalLLT` (lower triangle) with a solve of its own for a few right-hand sides.

The analysis orders the unknowns with AMD alone (`AMD_ORDERING`, the default) or as CHOLMOD does by
default (`CHOLMOD_DEFAULT_ORDERING`: AMD, then METIS when AMD's factor is large, keeping the smaller
factor); see `set_ordering()`. The numeric factorisation is multifrontal (`set_multifrontal()`,
on by default): each supernode of CHOLMOD's symbolic factor assembles its front (its columns of
the permuted matrix and its children's update matrices, in the children's order), factors its
diagonal block with LAPACK's `dpotrf`, the block below with BLAS `dtrsm`, and leaves its
ancestors' update with `dsyrk`: one call of each per supernode, where CHOLMOD's own supernodal
factorisation makes a pair of BLAS calls per (descendant, supernode) pair, most of them on small
blocks. With \tbb, disjoint subtrees of the elimination tree are factored concurrently, then the
supernodes above them one after the other, a large one's `dtrsm` split into blocks of rows and its
`dsyrk` into panels of columns (`dsyrk` and `dgemm`) on \tbb's threads. The BLAS always runs on the
thread that calls it: with OpenBLAS, its process-wide thread count is set to 1 during the
factorisation and restored after it, since OpenBLAS's own threads, once used, spin for about
2^28 processor cycles after each call (about 0.1 s), taking a core from the iterations that
follow on a machine with few cores (see \ref LapDefParallel). The factor lands in CHOLMOD's layout (the same symbolic factor, `factor()`), equal to
CHOLMOD's own factorisation up to round-off, and does not depend on the threads' timing. The BLAS
and LAPACK routines are the ones loaded with CHOLMOD, found at run time; where they are not found
(or a shift is set), `factorize()` is CHOLMOD's. A pivot that is not positive, NaN included, gives
`Eigen::NumericalIssue` (CHOLMOD's own factorisation lets a NaN pivot through with OpenBLAS).

`solve_columns()` runs the forward and backward substitutions itself on
CHOLMOD's supernodal factor, supernode by supernode, without BLAS calls (OpenBLAS's threads stay
idle while the transforms are fitted on \tbb's threads). For three right-hand sides (the
deformation's x, y, z) the columns are kept interleaved, every value of the factor is read once per
substitution, and, with \tbb, disjoint subtrees of the supernodal elimination tree are substituted
on several threads (`set_parallel()`), level after level of the tree, then the last supernodes (the
top) one after the other; the top's large supernodes (64k values and more) are swept by panels of
64 columns, each panel's rows below its diagonal block (forward) or its columns' dot products with
the rows after it (backward) cut into pieces on \tbb's threads. The result does not depend on the
threads' timing or their number, and differs from the sequential one only by round-off (the
updates that several subtrees send to the same ancestor are summed in another order, and a split
supernode's backward dot products are summed in two parts). Other numbers of columns go through one supernode at a
time with \eigen's matrix-vector kernels. Both compute CHOLMOD's solution up to round-off.
Everything else (`compute()`, `solve()`, `info()`, `cholmod()`) is `Eigen::CholmodSupernodalLLT`'s.

On Linux with SuiteSparse 5 (Debian 12's; later versions are left alone), the first construction
sets SuiteSparse's allocation functions (the global `SuiteSparse_config`, process-wide) to the C
library's `malloc`, `calloc` and `realloc` followed
by `madvise(MADV_HUGEPAGE)` on blocks of 4 MiB and more, so that the factor's pages are faulted in
2 MiB at a time where the kernel offers transparent huge pages; `free` stays the C library's, and
allocation functions that are not the C library's (a user's own) are left alone. The environment
variable `CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0` or the macro
`CGAL_LAPLACIAN_DEFORMATION_NO_HUGE_PAGES` turns this off.
*/
class Cholmod_supernodal_llt
  : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>
{
public:
  typedef Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> Base;

  /// the fill-reducing orderings of `analyzePattern()`
  enum Ordering
  {
    AMD_ORDERING,               ///< AMD alone: the fastest analysis (the default)
    CHOLMOD_DEFAULT_ORDERING    ///< CHOLMOD's default: AMD, then METIS when AMD's factor is large; the smaller factor
  };

  /// as the base class, with `AMD_ORDERING` (and see above for SuiteSparse's allocation functions)
  Cholmod_supernodal_llt()
  {
    internal::use_huge_pages_in_suitesparse();
    set_ordering(AMD_ORDERING);
  }

  /// sets the fill-reducing ordering of the next `analyzePattern()`. On the normal matrices of the
  /// edge-based operator of meshes of 100k and 400k vertices, AMD alone analyses 5 to 6 times faster
  /// than CHOLMOD's default (which there runs METIS), for a factor 15 to 22% larger (so that much more
  /// memory and time per substitution); on 26k vertices both choose AMD. See the manual's
  /// performance section.
  void set_ordering(Ordering ordering)
  {
    m_ordering = ordering;
    cholmod_common& c = cholmod();
    if(ordering == AMD_ORDERING)
    {
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_AMD;
      c.postorder = 1;
    }
    else
    {
      c.nmethods = 0;            // CHOLMOD's defaults (cholmod_defaults())
      c.method[0].ordering = CHOLMOD_GIVEN;
      c.postorder = 1;
    }
  }
  /// see `set_ordering()`
  Ordering ordering() const { return m_ordering; }

  /// analyses the pattern of `matrix` (as the base class; also forgets the parallel schedule of
  /// the previous factor's substitutions)
  void analyzePattern(const Eigen::SparseMatrix<double>& matrix)
  {
    Base::analyzePattern(matrix);
    m_schedule_valid = false;
    m_multifrontal_valid = false;
  }
  /// factors `matrix` (the pattern given to `analyzePattern()`), by the multifrontal factorisation
  /// described above when it applies, otherwise by CHOLMOD's (as the base class)
  void factorize(const Eigen::SparseMatrix<double>& matrix)
  {
    m_last_multifrontal = false;
    cholmod_factor* l = m_cholmodFactor;
    if(!m_multifrontal || !m_analysisIsOk || l == nullptr || !l->is_super || l->itype != CHOLMOD_INT ||
       l->dtype != CHOLMOD_DOUBLE || m_shiftOffset[0] != 0. || !matrix.isCompressed() ||
       matrix.rows() != matrix.cols() || matrix.rows() != Eigen::Index(l->n) ||
       !internal::Dense_kernels::instance().available())
      return Base::factorize(matrix);
    if(l->xtype == CHOLMOD_PATTERN)
    {
      if(!cholmod_change_factor(CHOLMOD_REAL, 1, 1, 1, 1, l, &cholmod()))   // allocates the values
        return Base::factorize(matrix);
      // fresh, and written in full by the factorisation below: mapped at once (internal/huge_pages.h)
      if(l->xtype == CHOLMOD_REAL && l->x != nullptr)
        internal::prefault_at(reinterpret_cast<std::uintptr_t>(l->x), l->xsize * sizeof(double));
    }
    if(l->xtype != CHOLMOD_REAL || !l->is_ll)
      return Base::factorize(matrix);
    const int n = int(l->n);
    const int* outer = matrix.outerIndexPtr();
    const int* inner = matrix.innerIndexPtr();
    const bool same_pattern = m_multifrontal_valid && m_pattern_outer.size() == std::size_t(n) + 1 &&
                              std::equal(outer, outer + n + 1, m_pattern_outer.begin()) &&
                              std::equal(inner, inner + outer[n], m_pattern_inner.begin(), m_pattern_inner.end());
    const internal::Supernodal_factor_target target = factor_target();
    const bool parallel = internal::runs_in_parallel<CGAL::Parallel_tag>() && m_parallel;
    if(!same_pattern)
    {
      m_multifrontal_valid = false;
      const int bins = parallel ? 2 * int((std::max)(2u, std::thread::hardware_concurrency())) : 1;
      if(!m_multifrontal_engine.analyse(target, static_cast<const int*>(l->Perm), n, outer, inner, bins))
        return Base::factorize(matrix);
      m_pattern_outer.assign(outer, outer + n + 1);
      m_pattern_inner.assign(inner, inner + outer[n]);
      m_multifrontal_valid = true;
    }
    m_factorizationIsOk = false;          // until the values are complete (an exception may leave them half done)
    m_info = Eigen::NumericalIssue;
    const int minor = m_multifrontal_engine.factor(target, matrix.valuePtr(), parallel);
    l->minor = std::size_t(minor);
    m_info = minor == n ? Eigen::Success : Eigen::NumericalIssue;
    m_factorizationIsOk = true;
    m_last_multifrontal = true;
  }
  /// analyses and factors `matrix` (as the base class)
  Cholmod_supernodal_llt& compute(const Eigen::SparseMatrix<double>& matrix)
  {
    analyzePattern(matrix);
    factorize(matrix);
    return *this;
  }

  /// whether `factorize()` may use the multifrontal factorisation (default: `true`)
  void set_multifrontal(bool multifrontal)
  {
    m_multifrontal = multifrontal;
    m_multifrontal_valid = false;
  }
  /// see `set_multifrontal()`
  bool is_multifrontal() const { return m_multifrontal; }
  /// whether the last `factorize()` was the multifrontal one (`false`: CHOLMOD's)
  bool last_factorization_was_multifrontal() const { return m_last_multifrontal; }
  /// the number of subtrees the last multifrontal factorisation factored concurrently (0: none)
  std::size_t number_of_concurrent_subtrees() const
  {
    return m_last_multifrontal ? m_multifrontal_engine.number_of_subtrees() : 0;
  }
  /// the number of supernodes whose `dtrsm` and `dsyrk` the last multifrontal factorisation split
  /// on \tbb's threads (0: none)
  std::size_t number_of_split_fronts() const
  {
    return m_last_multifrontal ? m_multifrontal_engine.number_of_split_fronts() : 0;
  }

  /// whether `solve_columns()` may run the substitutions of three columns, and `factorize()` its
  /// multifrontal factorisation (subtrees, split fronts), on \tbb's threads (default: `true`;
  /// without \tbb they never do; with `false` the whole factorisation runs on the calling thread,
  /// OpenBLAS included)
  void set_parallel(bool parallel) { m_parallel = parallel; }
  /// see `set_parallel()`
  bool is_parallel() const { return m_parallel; }

  /// solves `A X = B` with the current factorisation, for any number of columns (`Matrix`: a
  /// resizable dense \eigen matrix such as `Eigen::MatrixX3d`). Returns `false` when there is no
  /// successful factorisation or `B` has the wrong number of rows; a solution that is not finite
  /// is returned as it is (the caller checks it, as `Least_squares_solver` does).
  template <class Matrix>
  bool solve_columns(const Eigen::Ref<const Eigen::MatrixXd>& b, Matrix& x) const
  {
    const cholmod_factor* l = m_cholmodFactor;
    if(l == nullptr || !m_factorizationIsOk || info() != Eigen::Success || b.rows() != Eigen::Index(l->n))
      return false;
    if(!l->is_super || !l->is_ll || l->xtype != CHOLMOD_REAL || l->itype != CHOLMOD_INT ||
       l->dtype != CHOLMOD_DOUBLE)
    {
      x = solve(b);          // not the layout below: CHOLMOD's own solve
      return info() == Eigen::Success;
    }
    if(b.cols() == 3)
      return solve_three_columns(b, x);
    typedef Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> Block;
    const int n = int(l->n), nsuper = int(l->nsuper);
    const int* perm = static_cast<const int*>(l->Perm);
    const int* super = static_cast<const int*>(l->super);
    const int* pi = static_cast<const int*>(l->pi);
    const int* px = static_cast<const int*>(l->px);
    const int* rows = static_cast<const int*>(l->s);
    const double* values = static_cast<const double*>(l->x);
    const Eigen::Index k = b.cols();
    // y = P b (row k of y is row perm[k] of b), then L z = y, L^T w = z, x = P^T w
    Eigen::MatrixXd& y = m_y;
    y.resize(n, k);
    for(int i = 0; i < n; ++i)
      y.row(i) = b.row(perm ? perm[i] : i);
    m_w.resize(Eigen::Index(l->maxesize), k);
    for(int s = 0; s < nsuper; ++s)
    {
      const int k0 = super[s], nc = super[s + 1] - k0, nr = pi[s + 1] - pi[s], m = nr - nc;
      const double* block = values + px[s];
      const Block diagonal(block, nc, nc, Eigen::OuterStride<>(nr));
      auto ys = y.middleRows(k0, nc);
      diagonal.triangularView<Eigen::Lower>().solveInPlace(ys);
      if(m == 0)
        continue;
      const Block below(block + nc, m, nc, Eigen::OuterStride<>(nr));
      auto w = m_w.topRows(m);
      for(Eigen::Index j = 0; j < k; ++j)  // matrix-vector products: no packing of the block
        w.col(j).noalias() = below * ys.col(j);
      const int* r = rows + pi[s] + nc;
      for(int i = 0; i < m; ++i)
        y.row(r[i]) -= w.row(i);
    }
    for(int s = nsuper - 1; s >= 0; --s)
    {
      const int k0 = super[s], nc = super[s + 1] - k0, nr = pi[s + 1] - pi[s], m = nr - nc;
      const double* block = values + px[s];
      auto ys = y.middleRows(k0, nc);
      if(m > 0)
      {
        const Block below(block + nc, m, nc, Eigen::OuterStride<>(nr));
        auto w = m_w.topRows(m);
        const int* r = rows + pi[s] + nc;
        for(int i = 0; i < m; ++i)
          w.row(i) = y.row(r[i]);
        for(Eigen::Index j = 0; j < k; ++j)
          ys.col(j).noalias() -= below.transpose() * w.col(j);
      }
      const Block diagonal(block, nc, nc, Eigen::OuterStride<>(nr));
      diagonal.transpose().triangularView<Eigen::Upper>().solveInPlace(ys);
    }
    x.resize(n, k);
    for(int i = 0; i < n; ++i)
      x.row(perm ? perm[i] : i) = y.row(i);
    return true;
  }

  /// the CHOLMOD factor (`nullptr` before the first `compute()` or `analyzePattern()`).
  const cholmod_factor* factor() const { return m_cholmodFactor; }

  /// the number of groups of subtrees of the elimination tree that the last three-column solve
  /// substituted concurrently (1: sequential)
  std::size_t number_of_parallel_groups() const { return m_parallel_groups; }
  /// the number of levels of concurrent subtrees of the last three-column solve (0: sequential;
  /// each level ends with a barrier, see `solve_columns()`)
  std::size_t number_of_parallel_levels() const { return m_parallel_groups > 1 ? m_schedule.number_of_levels() : 0; }
  /// the share of the factor's values that the last three-column solve substituted on one thread
  /// (the supernodes above the concurrent subtrees, but for the parts of the split ones substituted
  /// in pieces; 1 when sequential)
  double sequential_share() const { return m_parallel_groups > 1 ? m_schedule.sequential_share() : 1.; }
  /// the number of supernodes above the concurrent subtrees (the top) that the last three-column
  /// solve split between the threads (see `solve_columns()`; 0 when sequential)
  std::size_t number_of_split_supernodes() const
  {
    return m_parallel_groups > 1 ? m_schedule.number_of_split_supernodes() : 0;
  }

private:
  internal::Supernodal_factor_target factor_target() const
  {
    internal::Supernodal_factor_target t;
    static_cast<internal::Supernodal_factor_view&>(t) = view();
    t.writable_values = static_cast<double*>(m_cholmodFactor->x);
    return t;
  }

  internal::Supernodal_factor_view view() const
  {
    const cholmod_factor* l = m_cholmodFactor;
    internal::Supernodal_factor_view v;
    v.n = int(l->n);
    v.nsuper = int(l->nsuper);
    v.super = static_cast<const int*>(l->super);
    v.pi = static_cast<const int*>(l->pi);
    v.px = static_cast<const int*>(l->px);
    v.rows = static_cast<const int*>(l->s);
    v.values = static_cast<const double*>(l->x);
    return v;
  }

  template <class Matrix>
  bool solve_three_columns(const Eigen::Ref<const Eigen::MatrixXd>& b, Matrix& x) const
  {
    const internal::Supernodal_factor_view l = view();
    const int* perm = static_cast<const int*>(m_cholmodFactor->Perm);
    // parallel when TBB is there, allowed, and the factor is large enough to pay for the tasks
    const bool parallel = internal::runs_in_parallel<CGAL::Parallel_tag>() && m_parallel &&
                          m_cholmodFactor->xsize > 200000;
    const int bins = parallel ? 2 * int((std::max)(2u, std::thread::hardware_concurrency())) : 1;
    if(!m_schedule_valid || !m_schedule.matches(l) || m_schedule_bins != bins)
    {
      m_schedule.build(l, bins);
      m_schedule_bins = bins;
      m_schedule_valid = true;
    }
    // the position of row k of b in y (the inverse of CHOLMOD's permutation, kept while it is the
    // same): y = P b and x = P^T y then go through b and x in order, three columns at once, and
    // reach y (three interleaved values: one cache line) at scattered places, instead of reaching
    // each of b's and x's three columns at scattered places; on TBB's threads when parallel
    if(perm != nullptr && (m_permutation.size() != std::size_t(l.n) ||
                           !std::equal(m_permutation.begin(), m_permutation.end(), perm)))
    {
      m_permutation.assign(perm, perm + l.n);
      m_inverse_permutation.resize(std::size_t(l.n));
      for(int i = 0; i < l.n; ++i)
        m_inverse_permutation[std::size_t(perm[i])] = i;
    }
    const int* const position = perm ? m_inverse_permutation.data() : nullptr;
    // fresh at the first solve: advised for huge pages (first touches, see internal/huge_pages.h)
    internal::resize_huge(m_interleaved, 3 * std::size_t(l.n));
    double* y = m_interleaved.data();
    internal::for_each_block(std::size_t(l.n), parallel, [&](std::size_t begin, std::size_t end) {
      for(std::size_t k = begin; k < end; ++k)   // y = P b
      {
        double* const yi = y + 3 * std::size_t(position ? position[k] : int(k));
        yi[0] = b(Eigen::Index(k), 0);
        yi[1] = b(Eigen::Index(k), 1);
        yi[2] = b(Eigen::Index(k), 2);
      }
    }, 4096);
    m_schedule.solve(l, y, parallel);
    m_parallel_groups = parallel ? (std::max)(std::size_t(1), m_schedule.number_of_bins()) : 1;
    internal::resize_dense_huge(x, l.n, 3);
    internal::for_each_block(std::size_t(l.n), parallel, [&](std::size_t begin, std::size_t end) {
      for(std::size_t k = begin; k < end; ++k)   // x = P^T y
      {
        const double* const yi = y + 3 * std::size_t(position ? position[k] : int(k));
        x(Eigen::Index(k), 0) = yi[0];
        x(Eigen::Index(k), 1) = yi[1];
        x(Eigen::Index(k), 2) = yi[2];
      }
    }, 4096);
    return true;
  }

  mutable Eigen::MatrixXd m_y, m_w;      // workspace, kept across solves
  mutable std::vector<double> m_interleaved;
  mutable std::vector<int> m_permutation, m_inverse_permutation;   // CHOLMOD's P at the last solve, and its inverse
  mutable internal::Supernodal_schedule m_schedule;   // of the current symbolic factor
  mutable bool m_schedule_valid = false;
  mutable int m_schedule_bins = 0;
  mutable std::size_t m_parallel_groups = 1;
  bool m_parallel = true;
  internal::Multifrontal_factorization m_multifrontal_engine;
  std::vector<int> m_pattern_outer, m_pattern_inner;   // the pattern m_multifrontal_engine was prepared for
  bool m_multifrontal = true, m_multifrontal_valid = false, m_last_multifrontal = false;
  Ordering m_ordering = AMD_ORDERING;
};

/*!
\ingroup PkgLaplacianDeformationSolver
\brief Solver traits for CHOLMOD's supernodal sparse Cholesky (SuiteSparse, through Eigen's
`CholmodSupport`), to be passed as the `SolverTraits` parameter of `Mesh_deformer` or
`Least_squares_solver`. The solver is `Cholmod_supernodal_llt`, whose `solve_columns()`
`Least_squares_solver` uses for the three columns.
Include this header only when CHOLMOD is available and link `CGAL::Laplacian_deformation_cholmod`.
*/
typedef CGAL::Eigen_solver_traits<Cholmod_supernodal_llt> Cholmod_solver_traits;

namespace internal {
// CHOLMOD's Cholesky factorisations read only the triangle they are given
template <class S>    // also classes derived from it
struct Eigen_solver_reads_lower_triangle<S, std::enable_if_t<std::is_base_of<Cholmod_supernodal_llt, S>::value>>
    : std::true_type {};
template <class M>
struct Eigen_solver_reads_lower_triangle<Eigen::CholmodSupernodalLLT<M, Eigen::Lower>> : std::true_type {};
template <class M>
struct Eigen_solver_reads_lower_triangle<Eigen::CholmodSimplicialLLT<M, Eigen::Lower>> : std::true_type {};
template <class M>
struct Eigen_solver_reads_lower_triangle<Eigen::CholmodSimplicialLDLT<M, Eigen::Lower>> : std::true_type {};
template <class M>
struct Eigen_solver_reads_lower_triangle<Eigen::CholmodDecomposition<M, Eigen::Lower>> : std::true_type {};
} // namespace internal

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H
