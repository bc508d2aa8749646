// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// Least_squares_solver with CHOLMOD's supernodal Cholesky: same results as the default solver.

#include <CGAL/Laplacian_deformation/Cholmod_solver_traits.h>
#include <CGAL/Laplacian_deformation/Least_squares_solver.h>
#include <CGAL/Laplacian_deformation/internal/normal_matrix.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <Eigen/Core>
#include <Eigen/QR>
#include <Eigen/SparseCore>

#include <limits>
#include <random>
#include <vector>
#include "least_squares_helpers.h"

namespace {

namespace LD = CGAL::Laplacian_deformation;

typedef LD::Least_squares_solver<LD::Cholmod_solver_traits> Cholmod_solver;
typedef LD::Least_squares_solver<> Default_solver;


double relative_error(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& reference)
{
  return (x - reference).norm() / reference.norm();
}

// CHOLMOD's Cholesky reads only the lower triangle: Least_squares_solver forms only that half of A^T A
static_assert(LD::internal::Solver_traits_read_lower_triangle<LD::Cholmod_solver_traits>::value,
              "CholmodSupernodalLLT<Lower> reads the lower triangle only");
static_assert(!LD::internal::Solver_traits_read_lower_triangle<
                  CGAL::Eigen_solver_traits<Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>>>::value,
              "an upper-triangle factorisation needs the upper triangle");

// The normal matrix of a 2D grid Laplacian: large enough for supernodes of many columns with rows
// below their diagonal block, the layout solve_columns() walks.
Eigen::SparseMatrix<double> grid_normal_matrix(int side)
{
  std::vector<Eigen::Triplet<double>> t;
  auto id = [side](int i, int j) { return i * side + j; };
  int row = 0;
  for(int i = 0; i < side; ++i)
    for(int j = 0; j < side; ++j, ++row)
    {
      t.emplace_back(row, id(i, j), 4.5);
      if(i > 0) t.emplace_back(row, id(i - 1, j), -1.);
      if(i + 1 < side) t.emplace_back(row, id(i + 1, j), -1.);
      if(j > 0) t.emplace_back(row, id(i, j - 1), -1.);
      if(j + 1 < side) t.emplace_back(row, id(i, j + 1), -1.2);
    }
  Eigen::SparseMatrix<double> a(side * side, side * side);
  a.setFromTriplets(t.begin(), t.end());
  const Eigen::SparseMatrix<double> at = a.transpose();
  return LD::internal::normal_matrix(a, at, true);
}

// Cholmod_supernodal_llt::solve_columns (own supernodal substitutions) == CHOLMOD's solve, for 1, 3
// and 5 columns; bad calls return false
TEST(CholmodSupernodalLlt, SolveColumnsMatchesCholmodSolve)
{
  const Eigen::SparseMatrix<double> n = grid_normal_matrix(60);
  LD::Cholmod_supernodal_llt llt;
  Eigen::MatrixX3d x3;
  EXPECT_FALSE(llt.solve_columns(Eigen::MatrixX3d::Ones(n.rows(), 3), x3));      // not factored
  llt.compute(n);
  ASSERT_EQ(llt.info(), Eigen::Success);
  ASSERT_NE(llt.factor(), nullptr);
  EXPECT_TRUE(llt.factor()->is_super);
  EXPECT_LT(llt.factor()->nsuper, n.rows() / 2);                 // real supernodes ...
  EXPECT_GT(llt.factor()->maxesize, 0u);                         // ... with rows below the diagonal
  const Eigen::SparseMatrix<double> full = n.selfadjointView<Eigen::Lower>();
  for(int columns : {1, 3, 5})
  {
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n.rows(), columns);
    Eigen::MatrixXd x;
    ASSERT_TRUE(llt.solve_columns(b, x));
    const Eigen::MatrixXd reference = llt.solve(b);
    EXPECT_LE((x - reference).norm(), 1e-12 * reference.norm()) << columns << " columns";
    EXPECT_LE((full * x - b).norm(), 1e-10 * b.norm()) << columns << " columns";
  }
  EXPECT_FALSE(llt.solve_columns(Eigen::MatrixX3d::Ones(n.rows() - 1, 3), x3));  // wrong size
  // a non-finite solution is returned, not refused: Least_squares_solver reports it as NOT_FINITE
  EXPECT_TRUE(llt.solve_columns(Eigen::MatrixX3d::Constant(n.rows(), 3, std::numeric_limits<double>::infinity()), x3));
  EXPECT_FALSE(x3.allFinite());
}

// solve_columns() keeps the inverse of CHOLMOD's fill-reducing permutation between solves: a new
// factorisation of another matrix of the same size, whose permutation differs, gets its own (a stale
// inverse would put b's rows in the wrong places), and three and five columns still match CHOLMOD's
// solve after it
TEST(CholmodSupernodalLlt, SolveColumnsFollowsANewPermutation)
{
  const Eigen::SparseMatrix<double> n = grid_normal_matrix(40);
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> q(n.rows());
  q.setIdentity();
  std::mt19937 g(3);
  std::shuffle(q.indices().data(), q.indices().data() + q.size(), g);
  Eigen::SparseMatrix<double> shuffled_full;
  shuffled_full = n.selfadjointView<Eigen::Lower>().twistedBy(q);
  const Eigen::SparseMatrix<double> shuffled = shuffled_full.triangularView<Eigen::Lower>();
  LD::Cholmod_supernodal_llt llt;
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n.rows(), 3);
  std::vector<std::vector<int>> permutations;
  for(const Eigen::SparseMatrix<double>* m : {&n, &shuffled, &n})
  {
    llt.compute(*m);
    ASSERT_EQ(llt.info(), Eigen::Success);
    const int* perm = static_cast<const int*>(llt.factor()->Perm);
    ASSERT_NE(perm, nullptr);
    permutations.emplace_back(perm, perm + n.rows());
    Eigen::MatrixX3d x;
    ASSERT_TRUE(llt.solve_columns(b, x));
    const Eigen::MatrixXd reference = llt.solve(b);
    EXPECT_LE((x - reference).norm(), 1e-12 * reference.norm());
    Eigen::MatrixXd x5;
    const Eigen::MatrixXd b5 = Eigen::MatrixXd::Random(n.rows(), 5);
    ASSERT_TRUE(llt.solve_columns(b5, x5));
    EXPECT_LE((x5 - llt.solve(b5)).norm(), 1e-12 * x5.norm());
  }
  EXPECT_NE(permutations[0], permutations[1]) << "the test needs two different permutations";
}

// The three-column substitutions (interleaved columns, column kernels, subtrees of the elimination
// tree on several threads) against CHOLMOD's own solve, for every kernel this processor runs and
// both schedules; the parallel schedule is deterministic and differs from the sequential one by
// round-off only (the subtrees, cut level after level of the elimination tree, send their updates
// to later levels in another order; the top's large supernodes are swept by panels cut into
// pieces on several threads); a new analysis (another pattern) gets a new schedule.
TEST(CholmodSupernodalLlt, ThreeColumnSolveMatchesCholmodForEveryKernelAndSchedule)
{
  namespace B = LD::internal::batched;
  const B::Batch_target initial = B::batch_target();
  for(int side : {150, 131})
  {
    const Eigen::SparseMatrix<double> n = grid_normal_matrix(side);
    LD::Cholmod_supernodal_llt llt;
    llt.compute(n);
    ASSERT_EQ(llt.info(), Eigen::Success);
    ASSERT_GT(llt.factor()->xsize, 200000u) << "large enough for the parallel schedule";
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n.rows(), 3);
    const Eigen::MatrixXd reference = llt.solve(b);
    for(B::Batch_target target : {B::Batch_target::portable, B::Batch_target::avx2})
    {
      B::set_batch_target(target);
      Eigen::MatrixX3d sequential, parallel, again;
      llt.set_parallel(false);
      ASSERT_TRUE(llt.solve_columns(b, sequential));
      EXPECT_EQ(llt.number_of_parallel_groups(), 1u);
      EXPECT_EQ(llt.number_of_parallel_levels(), 0u);
      EXPECT_EQ(llt.sequential_share(), 1.);
      llt.set_parallel(true);
      ASSERT_TRUE(llt.solve_columns(b, parallel));
      ASSERT_TRUE(llt.solve_columns(b, again));
#ifdef CGAL_LINKED_WITH_TBB
      EXPECT_GT(llt.number_of_parallel_groups(), 1u);
      EXPECT_GE(llt.number_of_parallel_levels(), 2u) << "the supernodes above the first level's subtrees are cut again";
      EXPECT_LT(llt.sequential_share(), 0.5);
      EXPECT_GE(llt.number_of_split_supernodes(), 1u) << "the top's largest supernodes are substituted in pieces";
#endif
      EXPECT_TRUE(parallel == again) << "the parallel substitutions do not depend on the threads' timing";
      EXPECT_LE((sequential - reference).norm(), 1e-12 * reference.norm()) << int(target);
      EXPECT_LE((parallel - reference).norm(), 1e-12 * reference.norm()) << int(target);
      EXPECT_LE((parallel - sequential).norm(), 1e-12 * sequential.norm()) << int(target);
    }
    B::set_batch_target(initial);
  }
}

// a finite right-hand side whose solution overflows: Least_squares_solver reports NOT_FINITE (the
// solution is checked after solve_columns(), which returns it as it is)
// The multifrontal factorisation (Cholmod_supernodal_llt::factorize(): fronts factored by LAPACK /
// BLAS, subtrees on several threads) against CHOLMOD's own supernodal factorisation of the same
// analysis: the same values of L within round-off, sequential and parallel, at the first
// factorisation and at a refactorisation of new values on the same pattern; the parallel factor
// (whose largest fronts at the top split their dtrsm into blocks of rows and their dsyrk into
// panels of dsyrk and dgemm) does not depend on the threads' timing.
TEST(CholmodSupernodalLlt, MultifrontalFactorMatchesCholmodFactor)
{
  const LD::internal::Dense_kernels& blas = LD::internal::Dense_kernels::instance();
  ASSERT_TRUE(blas.available()) << "LAPACK and BLAS come with CHOLMOD";
  const int blas_threads = blas.get_threads ? blas.get_threads() : 0;   // OpenBLAS's, restored after each factorisation
  for(int side : {110, 61, 7})
  {
    Eigen::SparseMatrix<double> n = grid_normal_matrix(side);
    for(int round = 0; round < 2; ++round)
    {
      if(round == 1)   // new values, same pattern
        for(int k = 0; k < n.outerSize(); ++k)
          for(Eigen::SparseMatrix<double>::InnerIterator it(n, k); it; ++it)
            it.valueRef() *= it.row() == it.col() ? 1.5 + 0.001 * double(k % 7) : 0.9;
      LD::Cholmod_supernodal_llt reference, sequential, parallel, again;
      reference.set_multifrontal(false);
      sequential.set_parallel(false);
      for(LD::Cholmod_supernodal_llt* llt : {&reference, &sequential, &parallel, &again})
      {
        llt->compute(n);
        ASSERT_EQ(llt->info(), Eigen::Success);
      }
      EXPECT_FALSE(reference.last_factorization_was_multifrontal());
      EXPECT_TRUE(sequential.last_factorization_was_multifrontal());
      EXPECT_TRUE(parallel.last_factorization_was_multifrontal());
      EXPECT_EQ(sequential.number_of_concurrent_subtrees(), 0u);
      EXPECT_EQ(sequential.number_of_split_fronts(), 0u);
#ifdef CGAL_LINKED_WITH_TBB
      if(side > 100)
      {
        EXPECT_GE(parallel.number_of_concurrent_subtrees(), 2u);
        // the largest fronts of the top have their dtrsm and dsyrk split on TBB's threads
        EXPECT_GE(parallel.number_of_split_fronts(), 1u);
      }
#endif
      if(blas.get_threads)
      {
        EXPECT_EQ(blas.get_threads(), blas_threads);
      }
      const cholmod_factor& r = *reference.factor();
      ASSERT_TRUE(r.is_super);
      typedef Eigen::Map<const Eigen::VectorXd> Values;
      const Values rx(static_cast<const double*>(r.x), Eigen::Index(r.xsize));
      for(const LD::Cholmod_supernodal_llt* llt : {&sequential, &parallel, &again})
      {
        const cholmod_factor& l = *llt->factor();
        ASSERT_EQ(l.xsize, r.xsize);
        ASSERT_EQ(l.nsuper, r.nsuper);
        ASSERT_EQ(l.minor, l.n);
        const Values lx(static_cast<const double*>(l.x), Eigen::Index(l.xsize));
        EXPECT_LE((lx - rx).norm(), 1e-13 * rx.norm()) << "side " << side << ", round " << round;
      }
      const Values px(static_cast<const double*>(parallel.factor()->x), Eigen::Index(r.xsize));
      const Values ax(static_cast<const double*>(again.factor()->x), Eigen::Index(r.xsize));
      EXPECT_TRUE(px == ax) << "the parallel factor does not depend on the threads' timing";
      // solutions agree too, and refactoring through factorize() on the same pattern reuses the
      // multifrontal preparation and gives the same factor again
      const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n.rows(), 3);
      Eigen::MatrixXd x, y;
      ASSERT_TRUE(parallel.solve_columns(b, x));
      y = reference.solve(b);
      EXPECT_LE((x - y).norm(), 1e-12 * y.norm());
      again.factorize(n);
      ASSERT_EQ(again.info(), Eigen::Success);
      EXPECT_TRUE(px == Values(static_cast<const double*>(again.factor()->x), Eigen::Index(r.xsize)));
    }
  }
}

// A factor whose supernodes are not in a postorder (CHOLMOD's postorder turned off, natural
// ordering, two independent grids with interleaved unknowns: the two subtrees interleave): the
// multifrontal factorisation, whose update matrices live on a stack, factors in a postorder of its
// own and gives CHOLMOD's factor
TEST(CholmodSupernodalLlt, MultifrontalFactorsSupernodesThatAreNotPostordered)
{
  const Eigen::SparseMatrix<double> grid = grid_normal_matrix(30);
  const Eigen::Index g = grid.rows();
  std::vector<Eigen::Triplet<double>> t;
  for(int copy = 0; copy < 2; ++copy)
    for(int k = 0; k < grid.outerSize(); ++k)
      for(Eigen::SparseMatrix<double>::InnerIterator it(grid, k); it; ++it)
        t.emplace_back(2 * int(it.row()) + copy, 2 * int(it.col()) + copy, it.value() * (copy == 0 ? 1. : 1.3));
  Eigen::SparseMatrix<double> n(2 * g, 2 * g);
  n.setFromTriplets(t.begin(), t.end());
  LD::Cholmod_supernodal_llt reference, multifrontal;
  reference.set_multifrontal(false);
  for(LD::Cholmod_supernodal_llt* llt : {&reference, &multifrontal})
  {
    cholmod_common& c = llt->cholmod();
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_NATURAL;
    c.postorder = 0;
    llt->compute(n);
    ASSERT_EQ(llt->info(), Eigen::Success);
  }
  EXPECT_TRUE(multifrontal.last_factorization_was_multifrontal());
  const cholmod_factor& r = *reference.factor();
  const cholmod_factor& l = *multifrontal.factor();
  ASSERT_TRUE(l.is_super);
  ASSERT_EQ(l.nsuper, r.nsuper);
  ASSERT_EQ(l.xsize, r.xsize);
  // the supernodes are not postordered: some subtree is not a contiguous range ending at its root
  const int ns = int(l.nsuper);
  const int* super = static_cast<const int*>(l.super);
  const int* pi = static_cast<const int*>(l.pi);
  const int* rows = static_cast<const int*>(l.s);
  std::vector<int> column_super(l.n), size(std::size_t(ns), 1), first(std::size_t(ns), 0);
  for(int s = 0; s < ns; ++s)
  {
    first[std::size_t(s)] = s;
    for(int c = super[s]; c < super[s + 1]; ++c)
      column_super[std::size_t(c)] = s;
  }
  bool postordered = true;
  for(int s = 0; s < ns; ++s)
  {
    postordered = postordered && first[std::size_t(s)] == s + 1 - size[std::size_t(s)];
    const int nc = super[s + 1] - super[s];
    if(pi[s] + nc < pi[s + 1])
    {
      const int p = column_super[std::size_t(rows[pi[s] + nc])];
      size[std::size_t(p)] += size[std::size_t(s)];
      first[std::size_t(p)] = (std::min)(first[std::size_t(p)], first[std::size_t(s)]);
    }
  }
  EXPECT_FALSE(postordered) << "the test needs supernodes that are not in a postorder";
  typedef Eigen::Map<const Eigen::VectorXd> Values;
  const Values rx(static_cast<const double*>(r.x), Eigen::Index(r.xsize));
  const Values lx(static_cast<const double*>(l.x), Eigen::Index(l.xsize));
  EXPECT_LE((lx - rx).norm(), 1e-13 * rx.norm());
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n.rows(), 3);
  Eigen::MatrixXd x;
  ASSERT_TRUE(multifrontal.solve_columns(b, x));
  const Eigen::MatrixXd y = reference.solve(b);
  EXPECT_LE((x - y).norm(), 1e-12 * y.norm());
}

// A matrix that is not positive definite: the multifrontal factorisation reports it as CHOLMOD does
// (NumericalIssue, minor < n), with an indefinite and with a NaN pivot (which CHOLMOD's own
// factorisation, through OpenBLAS's dpotrf, does not report)
TEST(CholmodSupernodalLlt, MultifrontalReportsAMatrixThatIsNotPositiveDefinite)
{
  for(double bad : {-3., std::numeric_limits<double>::quiet_NaN()})
  {
    Eigen::SparseMatrix<double> n = grid_normal_matrix(40);
    n.coeffRef(700, 700) = bad;
    LD::Cholmod_supernodal_llt multifrontal, reference;
    reference.set_multifrontal(false);
    multifrontal.compute(n);
    reference.compute(n);
    EXPECT_TRUE(multifrontal.last_factorization_was_multifrontal());
    EXPECT_EQ(multifrontal.info(), Eigen::NumericalIssue);
    if(!std::isnan(bad))   // CHOLMOD's own factorisation (OpenBLAS's dpotrf) lets a NaN pivot through
    {
      EXPECT_EQ(reference.info(), Eigen::NumericalIssue);
    }
    EXPECT_LT(multifrontal.factor()->minor, multifrontal.factor()->n);
    Eigen::MatrixX3d x;
    EXPECT_FALSE(multifrontal.solve_columns(Eigen::MatrixX3d::Ones(n.rows(), 3), x));
    // a good matrix of the same pattern afterwards: factored again
    multifrontal.factorize(grid_normal_matrix(40));
    EXPECT_EQ(multifrontal.info(), Eigen::Success);
  }
}

TEST(CholmodSolverTraits, OverflowingSolutionIsNotFinite)
{
  Eigen::SparseMatrix<double> a(4, 3);
  for(int i = 0; i < 3; ++i)
    a.insert(i, i) = 1e-150;                // A^T A = 1e-300 I: factorable, x = 1e300 * A^T b
  a.insert(3, 0) = 1e-150;
  Cholmod_solver solver;
  ASSERT_TRUE(solver.factor(a));
  Eigen::MatrixX3d x;
  EXPECT_FALSE(solver.solve(Eigen::MatrixX3d::Constant(4, 3, 1e200), x));
  EXPECT_EQ(solver.info(), Cholmod_solver::NOT_FINITE);
  ASSERT_TRUE(solver.solve(Eigen::MatrixX3d::Constant(4, 3, 1e-200), x));   // the same system, small data
  EXPECT_TRUE(x.allFinite());
}

TEST(CholmodSolverTraits, MatchesDefaultSolver)
{
  for(unsigned seed : {1u, 2u, 3u})
  {
    const Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, seed);
    Cholmod_solver cholmod;
    Default_solver reference;
    ASSERT_TRUE(cholmod.factor(a)) << "seed " << seed;
    EXPECT_EQ(cholmod.info(), Cholmod_solver::SUCCESS);
    ASSERT_TRUE(reference.factor(a)) << "seed " << seed;
    for(unsigned rhs_seed : {seed + 100, seed + 200})
    {
      const Eigen::MatrixX3d b = random_rhs(200, rhs_seed);
      Eigen::MatrixX3d x, x_reference;
      ASSERT_TRUE(cholmod.solve(b, x)) << "seed " << seed;
      EXPECT_EQ(cholmod.info(), Cholmod_solver::SUCCESS);
      ASSERT_TRUE(reference.solve(b, x_reference)) << "seed " << seed;
      EXPECT_LE(relative_error(x, x_reference), 1e-10) << "seed " << seed;
      const Eigen::MatrixX3d x_dense = Eigen::MatrixXd(a).colPivHouseholderQr().solve(b);
      EXPECT_LE(relative_error(x, x_dense), 1e-9) << "seed " << seed;
    }
    EXPECT_EQ(cholmod.number_of_factorizations(), 1u);
  }
}

// A larger, sparser problem (1000 unknowns, 3000 rows); kept small since the fill-in of random
// sparse normal matrices grows fast.
TEST(CholmodSolverTraits, MatchesDefaultSolverOnLargerProblem)
{
  const Eigen::SparseMatrix<double> a = random_sparse_matrix(3000, 1000, 0.002, 4);
  const Eigen::MatrixX3d b = random_rhs(3000, 5);
  Cholmod_solver cholmod;
  Default_solver reference;
  ASSERT_TRUE(cholmod.factor(a));
  ASSERT_TRUE(reference.factor(a));
  Eigen::MatrixX3d x, x_reference;
  ASSERT_TRUE(cholmod.solve(b, x));
  ASSERT_TRUE(reference.solve(b, x_reference));
  EXPECT_LE(relative_error(x, x_reference), 1e-10);
}

TEST(CholmodSolverTraits, ReportsFailures)
{
  Cholmod_solver solver;
  Eigen::MatrixX3d x;
  EXPECT_FALSE(solver.solve(random_rhs(200, 1), x));
  EXPECT_EQ(solver.info(), Cholmod_solver::NOT_FACTORED);

  Eigen::SparseMatrix<double> singular = random_sparse_matrix(200, 60, 0.05, 6);
  singular.prune([](Eigen::Index, Eigen::Index col, double) { return col != 17; });
  EXPECT_FALSE(solver.factor(singular));
  EXPECT_EQ(solver.info(), Cholmod_solver::FACTORIZATION_FAILED);

  Eigen::SparseMatrix<double> bad = random_sparse_matrix(200, 60, 0.05, 7);
  bad.coeffRef(3, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(solver.factor(bad));
  EXPECT_EQ(solver.info(), Cholmod_solver::NOT_FINITE);

  ASSERT_TRUE(solver.factor(random_sparse_matrix(200, 60, 0.05, 8)));
  Eigen::MatrixX3d b = random_rhs(200, 9);
  b(7, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(solver.solve(b, x));
  EXPECT_EQ(solver.info(), Cholmod_solver::NOT_FINITE);
}

} // namespace

// On Linux with SuiteSparse 5, constructing the solver routes SuiteSparse's allocations through the
// huge-page advice (the C library's functions with an madvise); free() stays the C library's, and
// the factorisations above (which ran through it) are checked against CHOLMOD's own solve.
TEST(CholmodSupernodalLlt, SuiteSparseAllocatesThroughTheHugePageAdvice)
{
  LD::Cholmod_supernodal_llt llt;
  const bool installed = LD::internal::use_huge_pages_in_suitesparse();
#if CGAL_LAPDEF_HUGE_PAGES && defined(SUITESPARSE_MAIN_VERSION) && SUITESPARSE_MAIN_VERSION == 5
  EXPECT_EQ(installed, LD::internal::huge_pages_enabled());
  if(installed)
  {
    EXPECT_TRUE(SuiteSparse_config.malloc_func == &LD::internal::huge_malloc);
    EXPECT_TRUE(SuiteSparse_config.calloc_func == &LD::internal::huge_calloc);
    EXPECT_TRUE(SuiteSparse_config.realloc_func == &LD::internal::huge_realloc);
  }
  EXPECT_TRUE(SuiteSparse_config.free_func == &std::free);
#else
  EXPECT_FALSE(installed);
#endif
  void* p = LD::internal::huge_calloc(std::size_t(1) << 20, 8);   // 8 MiB, zeroed
  ASSERT_NE(p, nullptr);
  const unsigned char* bytes = static_cast<const unsigned char*>(p);
  EXPECT_TRUE(std::all_of(bytes, bytes + (std::size_t(8) << 20), [](unsigned char b) { return b == 0; }));
  std::free(p);
}
