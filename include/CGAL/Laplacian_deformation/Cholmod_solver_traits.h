// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H
#define CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H

// Needs SuiteSparse's CHOLMOD: link the CMake target CGAL::Laplacian_deformation_cholmod.
#include <CGAL/Eigen_solver_traits.h>
#include <CGAL/Laplacian_deformation/internal/normal_matrix.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <type_traits>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationSolver
\brief `Eigen::CholmodSupernodalLLT` (lower triangle) with a solve of its own for a few right-hand sides.

CHOLMOD factors; `solve_columns()` then runs the forward and backward substitutions itself on
CHOLMOD's supernodal factor, supernode by supernode, with \eigen's dense matrix-vector kernels and
no BLAS call, so that OpenBLAS's threads stay idle while the transforms are fitted on \tbb's
threads. In an ad-hoc timing on the armadillo it was as fast as CHOLMOD's own solve with the
default x86-64 code and 1.4 to 1.9 times faster with `-march=native`. Both compute the same
solution up to round-off.
Everything else (`compute()`, `solve()`, `info()`, `cholmod()`) is `Eigen::CholmodSupernodalLLT`'s.
*/
class Cholmod_supernodal_llt
  : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>
{
public:
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

private:
  mutable Eigen::MatrixXd m_y, m_w;      // workspace, kept across solves
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
