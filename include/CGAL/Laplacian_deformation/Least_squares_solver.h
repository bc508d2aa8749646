// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_LEAST_SQUARES_SOLVER_H
#define CGAL_LAPLACIAN_DEFORMATION_LEAST_SQUARES_SOLVER_H

#include <CGAL/Default.h>
#include <CGAL/tags.h>
#include <CGAL/Eigen_solver_traits.h>
#include <CGAL/Eigen_sparse_matrix.h>
#include <CGAL/Laplacian_deformation/internal/normal_matrix.h>
#ifdef CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD
#include <CGAL/Laplacian_deformation/Cholmod_solver_traits.h>
#endif

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {
// overload priorities: a Priority_2 argument prefers the overload taking Priority_2, then Priority_1, ...
struct Priority_0 {};
struct Priority_1 : Priority_0 {};
struct Priority_2 : Priority_1 {};
} // namespace internal

/*!
\ingroup PkgLaplacianDeformationSolver
\brief \eigen's simplicial sparse Cholesky (`Eigen::SimplicialLLT`, AMD ordering) wrapped in
\cgal's `Eigen_solver_traits`: the default solver traits when CHOLMOD is not available.
*/
typedef CGAL::Eigen_solver_traits<Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>>
    Eigen_simplicial_solver_traits;

#if defined(CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD) || defined(DOXYGEN_RUNNING)
/*!
\ingroup PkgLaplacianDeformationSolver
\brief The default solver traits: `Cholmod_solver_traits` (SuiteSparse's supernodal CHOLMOD, with
its own choice of fill-reducing ordering) when the macro `CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD`
is defined, `Eigen_simplicial_solver_traits` otherwise.

The CMake target `CGAL::Laplacian_deformation` defines the macro and links CHOLMOD when SuiteSparse
is found (CMake option `LAPLACIAN_DEFORMATION_USE_CHOLMOD`, on by default). With an optimised
BLAS, CHOLMOD's block solve of the three columns is faster than `Eigen::SimplicialLLT`'s
(see `benchmark/RESULTS.md`).
*/
typedef Cholmod_solver_traits Default_solver_traits;
#else
typedef Eigen_simplicial_solver_traits Default_solver_traits;
#endif

/*!
\ingroup PkgLaplacianDeformationSolver

\brief Factor once, solve many: the least-squares solve shared by every representation and policy.

`factor(A)` forms the normal matrix `N = A^T A` of the sparse system matrix `A`, keeps `A` and
`N` (the wrapper owns everything the factorisation refers to) and factors `N`; `A^T` exists only
while `N` is formed. For traits that
factor only the lower triangle (`Eigen_solver_traits` of `Eigen::SimplicialLLT`,
`Eigen::SimplicialLDLT` or a CHOLMOD Cholesky with `Eigen::Lower`, such as
`Cholmod_solver_traits`) only that triangle of `N` is formed and kept.
`solve(B, X)` then minimises `|A X - B|^2` for the three columns of `B` at once:
`X = N^{-1} A^T B`. Nothing is refactored when only `B` changes.

\tparam SolverTraits a model of `SparseLinearAlgebraWithFactorTraits_d` whose `Matrix` is
constructible from an `Eigen::SparseMatrix<double>` (as CGAL's `Eigen_solver_traits`).
When it also exposes `solver()` returning an Eigen solver (as `Eigen_solver_traits` does), the
three columns go through one block solve; otherwise through `linear_solver()` per column.
`CGAL::Default` means `Default_solver_traits`; see also `Cholmod_solver_traits`.
\tparam ConcurrencyTag `CGAL::Sequential_tag`, `CGAL::Parallel_tag` or
`CGAL::Parallel_if_available_tag`: whether `factor()` forms `A^T A` on \tbb's threads (the
entries are the same either way), and whether a solver with `set_parallel()` (as
`Cholmod_supernodal_llt`) may run its substitutions on them (the solution then differs by
round-off only, and does not depend on the threads' timing).
*/
template <class SolverTraits = CGAL::Default, class ConcurrencyTag = CGAL::Sequential_tag>
class Least_squares_solver
{
public:
  /// The solver traits.
  typedef typename CGAL::Default::Get<SolverTraits, Default_solver_traits>::type Solver_traits;

  /// Why the last call failed.
  enum Info
  {
    SUCCESS = 0,            ///< the last call succeeded
    NOT_FACTORED,           ///< `solve()` was called before a successful `factor()`
    FACTORIZATION_FAILED,   ///< the normal matrix is not (numerically) positive definite
    SOLVE_FAILED,           ///< the back-substitution failed
    NOT_FINITE              ///< the input or the solution contains NaN or infinity
  };

  /// factors `A^T A`. Returns `false` (and `info()` says why) on failure.
  bool factor(const Eigen::SparseMatrix<double>& a)
  {
    Eigen::SparseMatrix<double> copy(a);
    return factor(std::move(copy));
  }
  /// factors `A^T A`, taking `a` over (it is left empty): no copy of `A` is made. `A^T` exists only
  /// while `A^T A` is formed, and is freed before the factorisation (whose memory is the peak).
  bool factor(Eigen::SparseMatrix<double>&& a)
  {
    if(!take_matrix(a))
      return false;
    Eigen::SparseMatrix<double> n;
    {
      const Eigen::SparseMatrix<double> at = internal::transposed_advised(m_a);
      // only the lower triangle when the traits read no more of it (Cholesky factorisations)
      n = internal::normal_matrix(m_a, at, internal::Solver_traits_read_lower_triangle<Solver_traits>::value,
                                  internal::runs_in_parallel<ConcurrencyTag>());
    }
    return factor_normal_matrix(n);
  }
  /// \cond SKIP_IN_MANUAL
  // factor(a) for a caller that has A by rows in another form (Mesh_deformer: the operator A was
  // taken from): `rows(r, j, f)` calls f(i, A(r, i)) for the entries i >= j of row r, in
  // increasing i, with exactly `a`'s values. A^T is then never formed (its memory and its
  // scattered copy are saved); the normal matrix is the same, bit for bit.
  // `prefetch(r, stage)`: see internal::normal_matrix_from_rows().
  template <class Rows, class Prefetch = internal::No_row_prefetch>
  bool factor_with_rows(Eigen::SparseMatrix<double>&& a, const Rows& rows, const Prefetch& prefetch = Prefetch())
  {
    if(!take_matrix(a))
      return false;
    Eigen::SparseMatrix<double> n = internal::normal_matrix_from_rows(
        m_a, rows, internal::Solver_traits_read_lower_triangle<Solver_traits>::value,
        internal::runs_in_parallel<ConcurrencyTag>(), prefetch);
    return factor_normal_matrix(n);
  }
  /// \endcond

  /// solves `min |A X - B|^2` for the three columns of `B` at once.
  bool solve(const Eigen::MatrixX3d& b, Eigen::MatrixX3d& x)
  {
    if(!m_factored)
      return fail(NOT_FACTORED);
    if(!b.allFinite())
      return fail(NOT_FINITE);
    return solve_normal_equations(m_a.transpose() * b, x);
  }

  /// solves `A^T A X = R` for a right-hand side `R = A^T B` the caller has already formed
  /// (for example in parallel, or once for the parts of `B` that do not change).
  /// A `R` whose number of rows is not `number_of_unknowns()` fails with `SOLVE_FAILED`.
  bool solve_normal_equations(const Eigen::MatrixX3d& r, Eigen::MatrixX3d& x)
  {
    if(!m_factored)
      return fail(NOT_FACTORED);
    if(r.rows() != number_of_unknowns())
      return fail(SOLVE_FAILED);
    if(!r.allFinite())
      return fail(NOT_FINITE);
    if(!block_solve(r, x, internal::Priority_2()))
      return fail(SOLVE_FAILED);
    if(!x.allFinite())
      return fail(NOT_FINITE);
    return fail(SUCCESS), true;
  }

  /// the outcome of the last `factor()` or `solve()`.
  Info info() const { return m_info; }
  /// whether a factorisation is available.
  bool is_factored() const { return m_factored; }
  /// the number of factorisations performed since construction.
  std::size_t number_of_factorizations() const { return m_number_of_factorizations; }
  /// the number of symbolic analyses (fill-reducing ordering and symbolic factorisation) performed
  /// since construction: with traits that expose an \eigen solver (`solver()` with `analyzePattern()`
  /// and `factorize()`, as `Eigen_solver_traits`), `factor()` reuses the previous analysis when the
  /// pattern of `A^T A` is the previous one's (only the values changed); otherwise one per factorisation.
  std::size_t number_of_analyses() const { return m_number_of_analyses; }
  /// `A` (compressed, sorted by columns), as kept since the last `factor()` that got past its input
  /// check: its column `j` holds the coefficients of unknown `j` (`solve()` forms `A^T B` from it).
  const Eigen::SparseMatrix<double>& matrix() const { return m_a; }
  /// the number of unknowns per coordinate.
  Eigen::Index number_of_unknowns() const { return m_a.cols(); }
  /// the solver traits (for example to tune the underlying solver; settings are kept across factorisations).
  Solver_traits& solver_traits() { return m_traits; }

private:
  typedef typename Solver_traits::Matrix Matrix;
  typedef typename Solver_traits::Vector Vector;

  bool fail(Info info) { m_info = info; return false; }

  // the input check of factor(): A finite, then taken over (compressed)
  bool take_matrix(Eigen::SparseMatrix<double>& a)
  {
    m_factored = false;
    for(Eigen::Index k = 0; k < a.outerSize(); ++k)      // also right for uncompressed matrices
      for(Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it)
        if(!std::isfinite(it.value()))
          return fail(NOT_FINITE);
    a.makeCompressed();
    m_a.swap(a);
    return true;
  }
  // factors the normal matrix `n` (taken over: the traits keep it)
  bool factor_normal_matrix(Eigen::SparseMatrix<double>& n)
  {
    set_matrix(m_matrix, n);     // owned: the traits keep a pointer to it
    ++m_number_of_factorizations;
    set_solver_parallel(internal::Priority_1());
    if(!factor_matrix(internal::Priority_1()))
      return fail(FACTORIZATION_FAILED);
    m_factored = true;
    return fail(SUCCESS), true;
  }

  // m = n without a copy of n when the traits' matrix wraps an Eigen matrix (Eigen 3.4's sparse
  // matrices have no move assignment: a plain assignment copies)
  static void set_matrix(CGAL::Eigen_sparse_matrix<double>& m, Eigen::SparseMatrix<double>& n)
  {
    // constructed from an (empty) Eigen matrix: every member set (the default constructor of
    // CGAL 5.5's Eigen_sparse_matrix leaves its symmetry flag uninitialised, which swap() reads)
    CGAL::Eigen_sparse_matrix<double> fresh{Eigen::SparseMatrix<double>()};
    fresh.eigen_object().swap(n);
    m.swap(fresh);
  }
  template <class M>
  static void set_matrix(M& m, Eigen::SparseMatrix<double>& n) { m = M(n); }

  // a solver whose substitutions may run on several threads (Cholmod_supernodal_llt) follows ConcurrencyTag
  template <class T = Solver_traits>
  auto set_solver_parallel(internal::Priority_1)
      -> decltype(std::declval<T&>().solver().set_parallel(true), void())
  {
    m_traits.solver().set_parallel(internal::runs_in_parallel<ConcurrencyTag>());
  }
  void set_solver_parallel(internal::Priority_0) {}

  // factors m_matrix through the Eigen solver, analysing its pattern only when it changed ...
  template <class T = Solver_traits>
  auto factor_matrix(internal::Priority_1)
      -> decltype(std::declval<T&>().solver().analyzePattern(std::declval<const Eigen::SparseMatrix<double>&>()),
                  std::declval<T&>().solver().factorize(std::declval<const Eigen::SparseMatrix<double>&>()),
                  std::declval<T&>().solver().info(), std::declval<typename T::Matrix&>().eigen_object(), bool())
  {
    const Eigen::SparseMatrix<double>& n = m_matrix.eigen_object();
    const bool same = m_analysed && n.isCompressed() && n.rows() == m_pattern_size && n.cols() == m_pattern_size &&
                      std::equal(n.outerIndexPtr(), n.outerIndexPtr() + n.cols() + 1, m_pattern_outer.begin(),
                                 m_pattern_outer.end()) &&
                      std::equal(n.innerIndexPtr(), n.innerIndexPtr() + n.nonZeros(), m_pattern_inner.begin(),
                                 m_pattern_inner.end());
    if(!same)
    {
      // the traits' own factor() (it records the matrix for linear_solver()); it analyses the pattern
      typename Solver_traits::NT d;
      ++m_number_of_analyses;
      m_analysed = false;
      if(!m_traits.factor(m_matrix, d))
        return false;
      if(!n.isCompressed())
        return true;
      m_pattern_size = n.rows();
      m_pattern_outer.assign(n.outerIndexPtr(), n.outerIndexPtr() + n.cols() + 1);
      m_pattern_inner.assign(n.innerIndexPtr(), n.innerIndexPtr() + n.nonZeros());
      m_analysed = true;
      return true;
    }
    m_traits.solver().factorize(n);          // the same pattern: numeric factorisation only
    return m_traits.solver().info() == Eigen::Success;
  }
  // ... or the traits' factor()
  bool factor_matrix(internal::Priority_0)
  {
    typename Solver_traits::NT d;
    ++m_number_of_analyses;
    return m_traits.factor(m_matrix, d);
  }

  // the solver's own multi-column solve (Cholmod_supernodal_llt::solve_columns()) ...
  template <class T = Solver_traits>
  auto block_solve(const Eigen::MatrixX3d& rhs, Eigen::MatrixX3d& x, internal::Priority_2)
      -> decltype(std::declval<T&>().solver().solve_columns(rhs, x), bool())
  {
    return m_traits.solver().solve_columns(rhs, x);
  }
  // ... or one block solve when the traits expose an Eigen solver ...
  template <class T = Solver_traits>
  auto block_solve(const Eigen::MatrixX3d& rhs, Eigen::MatrixX3d& x, internal::Priority_1)
      -> decltype(std::declval<T&>().solver().solve(rhs), bool())
  {
    x = m_traits.solver().solve(rhs);
    return m_traits.solver().info() == Eigen::Success;
  }
  // ... otherwise one linear_solver() call per column
  bool block_solve(const Eigen::MatrixX3d& rhs, Eigen::MatrixX3d& x, internal::Priority_0)
  {
    x.resize(rhs.rows(), 3);
    for(int c = 0; c < 3; ++c)
    {
      Vector b(rhs.rows()), xc(rhs.rows());
      for(Eigen::Index i = 0; i < rhs.rows(); ++i)
        b[i] = rhs(i, c);
      if(!m_traits.linear_solver(b, xc))
        return false;
      for(Eigen::Index i = 0; i < rhs.rows(); ++i)
        x(i, c) = xc[i];
    }
    return true;
  }

  Eigen::SparseMatrix<double> m_a;
  Matrix m_matrix{Eigen::SparseMatrix<double>()};   // not default-constructed: see set_matrix()
  std::vector<int> m_pattern_outer, m_pattern_inner;   // the pattern of the last analysed N
  Eigen::Index m_pattern_size = -1;
  bool m_analysed = false;
  std::size_t m_number_of_analyses = 0;
  Solver_traits m_traits;
  Info m_info = NOT_FACTORED;
  bool m_factored = false;
  std::size_t m_number_of_factorizations = 0;
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_LEAST_SQUARES_SOLVER_H
