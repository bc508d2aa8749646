// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// Least_squares_solver: factor once (A^T A), solve three columns at once, failure reporting, and
// the per-column fallback for traits that only model SparseLinearAlgebraWithFactorTraits_d.

#include <CGAL/Laplacian_deformation/Least_squares_solver.h>

#include <CGAL/Laplacian_deformation/internal/normal_matrix.h>
#include <CGAL/Laplacian_deformation/internal/huge_pages.h>

#include <gtest/gtest.h>

#include <utility>

#include <Eigen/Core>
#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <random>
#include <vector>
#include "least_squares_helpers.h"

namespace {

namespace LD = CGAL::Laplacian_deformation;


// dense least-squares reference
Eigen::MatrixX3d dense_least_squares(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixX3d& b)
{
  const Eigen::MatrixXd dense(a);
  return dense.colPivHouseholderQr().solve(b);
}

double relative_error(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& reference)
{
  return (x - reference).norm() / reference.norm();
}

const double nan = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// A traits archetype with only the SparseLinearAlgebraWithFactorTraits_d members used by
// Least_squares_solver (no `solver()`), so the per-column path is taken. Implemented with
// Eigen::SimplicialLDLT.
//
// Vector models SparseLinearAlgebraTraits_d::Vector: Vector(Index), copy, dimension() and
// operator[] only (nothing more than the concept), so this also proves the per-column path
// uses nothing beyond it.
struct Archetype_vector
{
  typedef double NT;
  typedef Eigen::Index Index;

  Archetype_vector() = default;
  explicit Archetype_vector(Index rows) : m_data(Eigen::VectorXd::Zero(rows)) {}
  Index dimension() const { return m_data.size(); }
  NT operator[](Index row) const { return m_data[row]; }
  NT& operator[](Index row) { return m_data[row]; }

  Eigen::VectorXd m_data;
};

struct Archetype_matrix
{
  typedef double NT;
  Archetype_matrix() = default;
  explicit Archetype_matrix(const Eigen::SparseMatrix<double>& m) : m_data(m) {}
  Eigen::SparseMatrix<double> m_data;
};

struct Archetype_factor_traits
{
  typedef double NT;
  typedef Archetype_matrix Matrix;
  typedef Archetype_vector Vector;

  bool factor(const Matrix& a, NT& d)
  {
    d = 1;
    m_solver = std::make_shared<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double> > >(a.m_data);
    ++number_of_factor_calls;
    return m_solver->info() == Eigen::Success;
  }

  bool linear_solver(const Vector& b, Vector& x)
  {
    ++number_of_linear_solver_calls;
    if(!m_solver)
      return false;
    x.m_data = m_solver->solve(b.m_data);
    return m_solver->info() == Eigen::Success;
  }

  static std::size_t number_of_factor_calls;
  static std::size_t number_of_linear_solver_calls;

private:
  std::shared_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double> > > m_solver;
};

std::size_t Archetype_factor_traits::number_of_factor_calls = 0;
std::size_t Archetype_factor_traits::number_of_linear_solver_calls = 0;

// ---------------------------------------------------------------------------------------------

// the huge-page helpers change where memory comes from, never what is in it: the transpose that
// factor() forms is Eigen's bitwise (same order of entries), the vector helpers are reserve/assign
TEST(HugePages, HelpersKeepTheValues)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1., 1.);
  for(int rows : {1, 37, 3000})
  {
    Eigen::SparseMatrix<double> a(rows, 257);
    std::vector<Eigen::Triplet<double>> t;
    for(int k = 0; k < 20 * rows; ++k)
      t.emplace_back(int(rng() % unsigned(rows)), int(rng() % 257u), u(rng));
    a.setFromTriplets(t.begin(), t.end());
    a.makeCompressed();
    const Eigen::SparseMatrix<double> expected = a.transpose();
    const Eigen::SparseMatrix<double> at = LD::internal::transposed_advised(a);
    ASSERT_TRUE(at.isCompressed());
    ASSERT_EQ(at.rows(), expected.rows());
    ASSERT_EQ(at.cols(), expected.cols());
    ASSERT_EQ(at.nonZeros(), expected.nonZeros());
    EXPECT_TRUE(std::equal(at.outerIndexPtr(), at.outerIndexPtr() + at.cols() + 1, expected.outerIndexPtr()));
    EXPECT_TRUE(std::equal(at.innerIndexPtr(), at.innerIndexPtr() + at.nonZeros(), expected.innerIndexPtr()));
    EXPECT_TRUE(std::equal(at.valuePtr(), at.valuePtr() + at.nonZeros(), expected.valuePtr()));
  }
  EXPECT_FALSE(LD::internal::advise_huge_pages(nullptr, std::size_t(64) << 20));
  std::vector<double> small(100);
  EXPECT_FALSE(LD::internal::advise_huge_pages(small.data(), small.size() * sizeof(double))) << "below 4 MiB";
  std::vector<double> v{1., 2.};
  LD::internal::reserve_huge(v, std::size_t(1) << 20);     // not empty: kept as it is
  EXPECT_EQ(v, (std::vector<double>{1., 2.}));
  EXPECT_GE(v.capacity(), std::size_t(1) << 20);
  LD::internal::assign_huge(v, std::size_t(1) << 20, 3.);
  EXPECT_EQ(v.size(), std::size_t(1) << 20);
  EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](double x) { return x == 3.; }));
  // resize_huge keeps the values (growing past the capacity moves them to fresh storage)
  std::vector<double> w{4., 5., 6.};
  LD::internal::resize_huge(w, std::size_t(1) << 20);
  ASSERT_EQ(w.size(), std::size_t(1) << 20);
  EXPECT_EQ(w[0], 4.);
  EXPECT_EQ(w[1], 5.);
  EXPECT_EQ(w[2], 6.);
  EXPECT_EQ(w.back(), 0.);
  LD::internal::resize_huge(w, 2);
  EXPECT_EQ(w, (std::vector<double>{4., 5.}));
  // resize_dense_huge: Eigen's resize (a same-sized resize keeps the values)
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> m;
  LD::internal::resize_dense_huge(m, 200000, 3);
  ASSERT_EQ(m.rows(), 200000);
  ASSERT_EQ(m.cols(), 3);
  m.setConstant(7.);
  LD::internal::resize_dense_huge(m, 200000, 3);
  EXPECT_TRUE((m.array() == 7.).all());
  LD::internal::resize_dense_huge(m, 5, 3);
  EXPECT_EQ(m.rows(), 5);
  // Huge_vector: a std::vector whose large blocks are advised; growth keeps the values
  LD::internal::Huge_vector<int> h;
  for(int i = 0; i < (1 << 21); ++i)
    h.push_back(i);
  EXPECT_EQ(h.size(), std::size_t(1) << 21);
  EXPECT_EQ(h[12345], 12345);
  EXPECT_EQ(h.back(), (1 << 21) - 1);
  LD::internal::Huge_vector<int>().swap(h);
  EXPECT_EQ(h.capacity(), 0u);
}

// prefaulting (MADV_POPULATE_WRITE) maps pages, never changes what is in them: written memory keeps
// its values, fresh memory reads as zeros; it is refused for null and small regions; Fresh_vector
// is a std::vector whose blocks are prepared
TEST(HugePages, PrefaultKeepsTheValues)
{
  EXPECT_FALSE(LD::internal::prefault_at(0, std::size_t(64) << 20));
  std::vector<char> small(LD::internal::prefault_min_bytes - 1, 1);
  EXPECT_FALSE(LD::internal::prefault_at(reinterpret_cast<std::uintptr_t>(small.data()), small.size()))
      << "below 64 KiB";
  const std::size_t n = std::size_t(3) << 20;   // 24 MiB of doubles, from a fresh mapping
  std::unique_ptr<double, void (*)(void*)> written(static_cast<double*>(std::malloc(n * sizeof(double))), std::free);
  ASSERT_TRUE(written);
  for(std::size_t i = 0; i < n; i += 97)
    written.get()[i] = double(i) + 0.5;
  LD::internal::prefault_at(reinterpret_cast<std::uintptr_t>(written.get()), n * sizeof(double));
  bool same = true;
  for(std::size_t i = 0; i < n; i += 97)
    same = same && written.get()[i] == double(i) + 0.5;
  EXPECT_TRUE(same);
  std::unique_ptr<double, void (*)(void*)> fresh(static_cast<double*>(std::calloc(n, sizeof(double))), std::free);
  ASSERT_TRUE(fresh);
  LD::internal::prepare_fresh_at(reinterpret_cast<std::uintptr_t>(fresh.get()) + 3, n * sizeof(double) - 3);
  EXPECT_TRUE(std::all_of(fresh.get(), fresh.get() + n, [](double x) { return x == 0.; }));
  LD::internal::Fresh_vector<double> v(n, 2.5);
  EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](double x) { return x == 2.5; }));
  LD::internal::Fresh_vector<std::atomic<unsigned char>> marks(std::size_t(1) << 20);
  EXPECT_TRUE(std::all_of(marks.begin(), marks.end(), [](const std::atomic<unsigned char>& m) { return m.load() == 0; }));
}

TEST(LeastSquaresSolver, MatchesDenseQR)
{
  for(unsigned seed : {1u, 2u, 3u})
  {
    const Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, seed);
    const Eigen::MatrixX3d b = random_rhs(200, seed + 100);
    LD::Least_squares_solver<> solver;
    ASSERT_TRUE(solver.factor(a)) << "seed " << seed;
    EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::SUCCESS);
    EXPECT_TRUE(solver.is_factored());
    EXPECT_EQ(solver.number_of_unknowns(), 60);
    Eigen::MatrixX3d x;
    ASSERT_TRUE(solver.solve(b, x)) << "seed " << seed;
    EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::SUCCESS);
    ASSERT_EQ(x.rows(), 60);
    EXPECT_LE(relative_error(x, dense_least_squares(a, b)), 1e-9) << "seed " << seed;
    // the residual is orthogonal to the columns of A (normal equations)
    EXPECT_LE((Eigen::MatrixX3d(a.transpose() * (a * x - b))).norm(), 1e-9 * b.norm());
  }
}

TEST(LeastSquaresSolver, ReusesTheFactorization)
{
  const Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 7);
  LD::Least_squares_solver<> solver;
  ASSERT_TRUE(solver.factor(a));
  EXPECT_EQ(solver.number_of_factorizations(), 1u);
  for(unsigned seed : {10u, 11u, 12u})
  {
    const Eigen::MatrixX3d b = random_rhs(200, seed);
    Eigen::MatrixX3d x;
    ASSERT_TRUE(solver.solve(b, x));
    EXPECT_LE(relative_error(x, dense_least_squares(a, b)), 1e-9) << "seed " << seed;
    EXPECT_EQ(solver.number_of_factorizations(), 1u);
  }

  // a new matrix: refactored, and the new system is solved
  const Eigen::SparseMatrix<double> a2 = random_sparse_matrix(150, 40, 0.08, 8);
  ASSERT_TRUE(solver.factor(a2));
  EXPECT_EQ(solver.number_of_factorizations(), 2u);
  const Eigen::MatrixX3d b2 = random_rhs(150, 13);
  Eigen::MatrixX3d x2;
  ASSERT_TRUE(solver.solve(b2, x2));
  EXPECT_LE(relative_error(x2, dense_least_squares(a2, b2)), 1e-9);
}

// New values on the same pattern: only the numeric factorisation is redone (the symbolic analysis
// is reused), and the solution is the new system's; a new pattern is analysed again. For the
// default traits and the simplicial ones; the per-column archetype below analyses every time.
TEST(LeastSquaresSolver, ReusesTheSymbolicAnalysisWhenOnlyValuesChange)
{
  auto check = [](auto solver) {
    const Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 21);
    ASSERT_TRUE(solver.factor(a));
    EXPECT_EQ(solver.number_of_analyses(), 1u);
    Eigen::SparseMatrix<double> scaled = a;
    for(Eigen::Index k = 0; k < scaled.outerSize(); ++k)
      for(Eigen::SparseMatrix<double>::InnerIterator it(scaled, k); it; ++it)
        it.valueRef() *= 1. + 0.5 * double((it.row() + 3 * it.col()) % 5);   // other values, same pattern
    ASSERT_TRUE(solver.factor(scaled));
    EXPECT_EQ(solver.number_of_factorizations(), 2u);
    EXPECT_EQ(solver.number_of_analyses(), 1u);
    const Eigen::MatrixX3d b = random_rhs(200, 22);
    Eigen::MatrixX3d x;
    ASSERT_TRUE(solver.solve(b, x));
    EXPECT_LE(relative_error(x, dense_least_squares(scaled, b)), 1e-9);
    const Eigen::SparseMatrix<double> other = random_sparse_matrix(200, 60, 0.06, 23);
    ASSERT_TRUE(solver.factor(other));
    EXPECT_EQ(solver.number_of_analyses(), 2u);
    ASSERT_TRUE(solver.solve(b, x));
    EXPECT_LE(relative_error(x, dense_least_squares(other, b)), 1e-9);
  };
  check(LD::Least_squares_solver<>());
  check(LD::Least_squares_solver<LD::Eigen_simplicial_solver_traits>());
}

// The solver owns everything its factorisation refers to: the caller's A may go away.
TEST(LeastSquaresSolver, DoesNotReferToTheCallersMatrix)
{
  LD::Least_squares_solver<> solver;
  Eigen::MatrixX3d reference;
  const Eigen::MatrixX3d b = random_rhs(200, 21);
  {
    Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 20);
    reference = dense_least_squares(a, b);
    ASSERT_TRUE(solver.factor(a));
    a = Eigen::SparseMatrix<double>(1, 1);
  }
  Eigen::MatrixX3d x;
  ASSERT_TRUE(solver.solve(b, x));
  EXPECT_LE(relative_error(x, reference), 1e-9);
}

TEST(LeastSquaresSolver, SolveBeforeFactorFails)
{
  LD::Least_squares_solver<> solver;
  EXPECT_EQ(solver.number_of_factorizations(), 0u);
  EXPECT_FALSE(solver.is_factored());
  Eigen::MatrixX3d x;
  EXPECT_FALSE(solver.solve(random_rhs(200, 1), x));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::NOT_FACTORED);
}

TEST(LeastSquaresSolver, RankDeficientMatrixFailsToFactor)
{
  Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 3);
  a.prune([](Eigen::Index, Eigen::Index col, double) { return col != 17; }); // zero column 17
  ASSERT_EQ(Eigen::VectorXd(a.col(17)).norm(), 0.);
  LD::Least_squares_solver<> solver;
  EXPECT_FALSE(solver.factor(a));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::FACTORIZATION_FAILED);
  EXPECT_FALSE(solver.is_factored());

  // a failed factor() after a good one leaves the solver unfactored
  ASSERT_TRUE(solver.factor(random_sparse_matrix(200, 60, 0.05, 4)));
  EXPECT_FALSE(solver.factor(a));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::FACTORIZATION_FAILED);
  Eigen::MatrixX3d x;
  EXPECT_FALSE(solver.solve(random_rhs(200, 5), x));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::NOT_FACTORED);
}

TEST(LeastSquaresSolver, NonFiniteRightHandSideIsReported)
{
  const Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 5);
  LD::Least_squares_solver<> solver;
  ASSERT_TRUE(solver.factor(a));
  Eigen::MatrixX3d x;
  for(double bad : {nan, std::numeric_limits<double>::infinity()})
  {
    Eigen::MatrixX3d b = random_rhs(200, 6);
    b(123, 1) = bad;
    EXPECT_FALSE(solver.solve(b, x));
    EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::NOT_FINITE);
  }
  // the factorisation survives a bad right-hand side
  const Eigen::MatrixX3d b = random_rhs(200, 7);
  ASSERT_TRUE(solver.solve(b, x));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::SUCCESS);
  EXPECT_LE(relative_error(x, dense_least_squares(a, b)), 1e-9);
  EXPECT_EQ(solver.number_of_factorizations(), 1u);
}

TEST(LeastSquaresSolver, NonFiniteMatrixIsReported)
{
  for(double bad : {nan, std::numeric_limits<double>::infinity()})
  {
    Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 8);
    a.coeffRef(30, 30) = bad; // on the diagonal block, so an existing entry
    ASSERT_TRUE(a.isCompressed());
    LD::Least_squares_solver<> solver;
    EXPECT_FALSE(solver.factor(a));
    EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::NOT_FINITE);
    EXPECT_FALSE(solver.is_factored());
  }
}

// An Eigen::SparseMatrix in uncompressed mode (after insert()) is a valid input too.
// Disabled: Least_squares_solver::factor() checks `Map(valuePtr(), nonZeros())`, which for an
// uncompressed matrix skips entries stored beyond nonZeros() (and reads the unused slack between
// inner vectors), so the NaN below is not seen: factor() returns true / SUCCESS, and the NaN only
// surfaces later as NOT_FINITE from solve(). See the report.
TEST(LeastSquaresSolver, NonFiniteUncompressedMatrixIsReported)
{
  Eigen::SparseMatrix<double> a(3, 2);
  a.reserve(Eigen::VectorXi::Constant(2, 4));
  a.insert(0, 0) = 1;
  a.insert(2, 0) = 1;
  a.insert(1, 1) = nan;
  ASSERT_FALSE(a.isCompressed());
  LD::Least_squares_solver<> solver;
  EXPECT_FALSE(solver.factor(a));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::NOT_FINITE);
}

// Uncompressed but finite input is solved correctly.
TEST(LeastSquaresSolver, AcceptsUncompressedMatrix)
{
  const Eigen::SparseMatrix<double> compressed = random_sparse_matrix(200, 60, 0.05, 9);
  Eigen::SparseMatrix<double> a(200, 60);
  a.reserve(Eigen::VectorXi::Constant(60, 40));
  for(int k = 0; k < compressed.outerSize(); ++k)
    for(Eigen::SparseMatrix<double>::InnerIterator it(compressed, k); it; ++it)
      a.insert(it.row(), it.col()) = it.value();
  ASSERT_FALSE(a.isCompressed());
  const Eigen::MatrixX3d b = random_rhs(200, 10);
  LD::Least_squares_solver<> solver;
  ASSERT_TRUE(solver.factor(a));
  Eigen::MatrixX3d x;
  ASSERT_TRUE(solver.solve(b, x));
  EXPECT_LE(relative_error(x, dense_least_squares(compressed, b)), 1e-9);
}

// solver_traits() is documented as the way to tune the underlying solver. Disabled:
// factor() assigns a fresh `Solver_traits()` before factoring, so every setting made before the
// first factor() (shift, ordering, CHOLMOD parameters...) is discarded. See the report.
TEST(LeastSquaresSolver, TuningBeforeFactorIsKept)
{
  // A^T A = diag(1, 0) is singular; with a shift of 1 Eigen's SimplicialLLT factors it.
  Eigen::SparseMatrix<double> a(2, 2);
  a.insert(0, 0) = 1;
  a.makeCompressed();
  LD::Least_squares_solver<> solver;
  solver.solver_traits().solver().setShift(1.);
  EXPECT_TRUE(solver.factor(a));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::SUCCESS);
}

// Traits without `solver()`: three linear_solver() calls per solve, same X as the default.
TEST(LeastSquaresSolver, PerColumnFallbackWithFactorTraitsArchetype)
{
  typedef LD::Least_squares_solver<Archetype_factor_traits> Solver;
  const Eigen::SparseMatrix<double> a = random_sparse_matrix(200, 60, 0.05, 11);
  Archetype_factor_traits::number_of_factor_calls = 0;
  Archetype_factor_traits::number_of_linear_solver_calls = 0;

  Solver solver;
  Eigen::MatrixX3d x;
  EXPECT_FALSE(solver.solve(random_rhs(200, 1), x));
  EXPECT_EQ(solver.info(), Solver::NOT_FACTORED);

  ASSERT_TRUE(solver.factor(a));
  EXPECT_EQ(Archetype_factor_traits::number_of_factor_calls, 1u);

  LD::Least_squares_solver<> reference_solver;
  ASSERT_TRUE(reference_solver.factor(a));
  for(unsigned seed : {12u, 13u})
  {
    const Eigen::MatrixX3d b = random_rhs(200, seed);
    ASSERT_TRUE(solver.solve(b, x));
    EXPECT_EQ(solver.info(), Solver::SUCCESS);
    Eigen::MatrixX3d reference;
    ASSERT_TRUE(reference_solver.solve(b, reference));
    EXPECT_LE(relative_error(x, reference), 1e-12) << "seed " << seed;
    EXPECT_LE(relative_error(x, dense_least_squares(a, b)), 1e-9) << "seed " << seed;
  }
  EXPECT_EQ(Archetype_factor_traits::number_of_linear_solver_calls, 6u);
  EXPECT_EQ(Archetype_factor_traits::number_of_factor_calls, 1u);
  EXPECT_EQ(solver.number_of_factorizations(), 1u);

  // failures are reported the same way
  Eigen::MatrixX3d b = random_rhs(200, 14);
  b(0, 0) = nan;
  EXPECT_FALSE(solver.solve(b, x));
  EXPECT_EQ(solver.info(), Solver::NOT_FINITE);
  Eigen::SparseMatrix<double> singular = a;
  singular.prune([](Eigen::Index, Eigen::Index col, double) { return col != 5; });
  EXPECT_FALSE(solver.factor(singular));
  EXPECT_EQ(solver.info(), Solver::FACTORIZATION_FAILED);
}

} // namespace

namespace {

Eigen::SparseMatrix<double> random_sparse(Eigen::Index rows, Eigen::Index cols, int per_row, unsigned seed)
{
  std::mt19937 g(seed);
  std::uniform_int_distribution<int> col(0, int(cols) - 1);
  std::normal_distribution<double> value;
  std::vector<Eigen::Triplet<double>> t;
  for(Eigen::Index r = 0; r < rows; ++r)
    for(int k = 0; k < per_row; ++k)
      t.emplace_back(int(r), col(g), value(g));          // duplicates are summed
  Eigen::SparseMatrix<double> a(rows, cols);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

// internal::normal_matrix: the same numbers as Eigen's A^T A, in full or as its lower triangle,
// also for an uncompressed A
TEST(NormalMatrix, MatchesEigenProductFullAndLower)
{
  for(unsigned seed : {4u, 5u})
  {
    Eigen::SparseMatrix<double> a = random_sparse(3000, 1200, 4, seed);
    const Eigen::SparseMatrix<double> at = a.transpose();
    const Eigen::SparseMatrix<double> reference = Eigen::SparseMatrix<double>(at * a);
    const Eigen::SparseMatrix<double> full = LD::internal::normal_matrix(a, at, false);
    const Eigen::SparseMatrix<double> lower = LD::internal::normal_matrix(a, at, true);
    EXPECT_TRUE(full.isCompressed());
    EXPECT_EQ(full.nonZeros(), reference.nonZeros());
    EXPECT_LE((full - reference).norm(), 1e-14 * reference.norm());
    const Eigen::SparseMatrix<double> reference_lower = reference.triangularView<Eigen::Lower>();
    EXPECT_EQ(lower.nonZeros(), reference_lower.nonZeros());
    EXPECT_LE((lower - reference_lower).norm(), 1e-14 * reference.norm());
    // on TBB's threads (when linked): the same entries, bit for bit
    const Eigen::SparseMatrix<double> parallel = LD::internal::normal_matrix(a, at, true, true);
    ASSERT_EQ(parallel.nonZeros(), lower.nonZeros());
    EXPECT_TRUE(std::equal(lower.valuePtr(), lower.valuePtr() + lower.nonZeros(), parallel.valuePtr()));
    EXPECT_TRUE(std::equal(lower.innerIndexPtr(), lower.innerIndexPtr() + lower.nonZeros(), parallel.innerIndexPtr()));
    for(Eigen::Index j = 0; j < lower.outerSize(); ++j)       // sorted columns, lower triangle only
      for(Eigen::SparseMatrix<double>::InnerIterator it(lower, j); it; ++it)
        EXPECT_GE(it.row(), j);
    a.coeffRef(0, 0) += 1.;                                   // may uncompress
    a.uncompress();
    const Eigen::SparseMatrix<double> at2 = a.transpose();
    EXPECT_LE((LD::internal::normal_matrix(a, at2, false) - Eigen::SparseMatrix<double>(at2 * a)).norm(),
              1e-14 * reference.norm());
  }
}

// internal::normal_matrix(): the edges of its chunked single pass (512 columns a chunk): no
// column, one column, empty columns, and a count of columns just past a chunk, sequential and on
// TBB's threads (bit for bit the same), against Eigen's A^T A
TEST(NormalMatrix, EmptyColumnsAndChunkEdges)
{
  for(Eigen::Index cols : {Eigen::Index(0), Eigen::Index(1), Eigen::Index(513), Eigen::Index(1024)})
  {
    Eigen::SparseMatrix<double> a = cols > 0 ? random_sparse(3 * cols, cols, 3, unsigned(cols)) : Eigen::SparseMatrix<double>(5, 0);
    for(Eigen::Index j = 0; j < cols; j += 7)   // every seventh column empty
      for(Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it)
        it.valueRef() = 0.;
    a.prune(0.);
    a.makeCompressed();
    const Eigen::SparseMatrix<double> at = a.transpose();
    const Eigen::SparseMatrix<double> reference = Eigen::SparseMatrix<double>(at * a).triangularView<Eigen::Lower>();
    const Eigen::SparseMatrix<double> lower = LD::internal::normal_matrix(a, at, true);
    const Eigen::SparseMatrix<double> parallel = LD::internal::normal_matrix(a, at, true, true);
    ASSERT_EQ(lower.rows(), cols);
    ASSERT_EQ(lower.nonZeros(), reference.nonZeros());
    if(cols > 0)   // (Eigen's norm() asserts on an empty matrix)
    {
      EXPECT_LE((lower - reference).norm(), 1e-14 * (reference.norm() + 1.));
    }
    for(Eigen::Index j = 0; j < cols; j += 7)
      EXPECT_EQ(lower.outerIndexPtr()[j + 1], lower.outerIndexPtr()[j]);   // the empty columns stay empty
    ASSERT_EQ(parallel.nonZeros(), lower.nonZeros());
    EXPECT_TRUE(std::equal(lower.outerIndexPtr(), lower.outerIndexPtr() + cols + 1, parallel.outerIndexPtr()));
    EXPECT_TRUE(std::equal(lower.innerIndexPtr(), lower.innerIndexPtr() + lower.nonZeros(), parallel.innerIndexPtr()));
    EXPECT_TRUE(std::equal(lower.valuePtr(), lower.valuePtr() + lower.nonZeros(), parallel.valuePtr()));
  }
}

// internal::normal_matrix_from_rows() with a prefetch hook (the one Mesh_deformer passes): the same
// matrix bit for bit as without it; the hook is called for the rows of the columns ahead, every row
// index valid: stage 0 for the rows of column j + prefetch_columns_ahead, stage 2 for the rows of
// the column half as far ahead, each once (one pass over the terms; stage 1 is no longer used)
TEST(NormalMatrix, PrefetchHookFetchesTheRowsAheadAndChangesNothing)
{
  typedef Eigen::SparseMatrix<double>::StorageIndex Index;
  const Eigen::SparseMatrix<double> a = random_sparse(2000, 700, 5, 12);
  const Eigen::SparseMatrix<double> at = a.transpose();
  auto rows = [&at](Index r, Index j, auto&& f) {
    for(Eigen::SparseMatrix<double>::InnerIterator it(at, r); it; ++it)
      if(Index(it.index()) >= j)
        f(Index(it.index()), it.value());
  };
  std::size_t calls[3] = {0, 0, 0};
  bool valid = true;
  auto record = [&](Index r, int stage) {
    valid = valid && r >= 0 && r < Index(a.rows()) && stage >= 0 && stage <= 2;
    ++calls[stage >= 0 && stage <= 2 ? stage : 0];
  };
  const Eigen::SparseMatrix<double> plain = LD::internal::normal_matrix_from_rows(a, rows, true);
  const Eigen::SparseMatrix<double> fetched = LD::internal::normal_matrix_from_rows(a, rows, true, false, record);
  ASSERT_EQ(fetched.nonZeros(), plain.nonZeros());
  EXPECT_TRUE(std::equal(plain.valuePtr(), plain.valuePtr() + plain.nonZeros(), fetched.valuePtr()));
  EXPECT_TRUE(std::equal(plain.innerIndexPtr(), plain.innerIndexPtr() + plain.nonZeros(), fetched.innerIndexPtr()));
  EXPECT_TRUE(valid);
  const std::ptrdiff_t far = LD::internal::prefetch_columns_ahead, near = far / 2;
  const std::size_t nnz = std::size_t(a.nonZeros());
  auto first_columns = [&a](std::ptrdiff_t k) { return std::size_t(a.outerIndexPtr()[k]); };
  EXPECT_EQ(calls[0], nnz - first_columns(far));
  EXPECT_EQ(calls[1], 0u);
  EXPECT_EQ(calls[2], nnz - first_columns(near));
}

// internal::branchless_lower_bound (the row search of A^T A's assembly): std::lower_bound's
// answer on every key of sorted ranges of every length up to 40, duplicates and empty ranges included
TEST(NormalMatrix, BranchlessLowerBoundIsLowerBound)
{
  std::mt19937 g(11);
  std::size_t checked = 0;
  for(int length = 0; length <= 40; ++length)
    for(int trial = 0; trial < 20; ++trial)
    {
      std::vector<int> v(static_cast<std::size_t>(length));
      std::uniform_int_distribution<int> value(0, 2 * length);
      for(int& x : v)
        x = value(g);
      std::sort(v.begin(), v.end());
      for(int key = -1; key <= 2 * length + 1; ++key)
      {
        const int* first = v.data();
        const int* last = v.data() + v.size();
        EXPECT_EQ(LD::internal::branchless_lower_bound(first, last, key), std::lower_bound(first, last, key))
            << "length " << length << " key " << key;
        ++checked;
      }
    }
  EXPECT_GT(checked, std::size_t(10000));
}

// which traits get only the lower triangle
static_assert(LD::internal::Solver_traits_read_lower_triangle<LD::Eigen_simplicial_solver_traits>::value,
              "SimplicialLLT reads the lower triangle only");
static_assert(LD::internal::Solver_traits_read_lower_triangle<
                  CGAL::Eigen_solver_traits<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>>::value,
              "SimplicialLDLT reads the lower triangle only");
static_assert(!LD::internal::Solver_traits_read_lower_triangle<CGAL::Eigen_solver_traits<>>::value,
              "BiCGSTAB needs the full matrix");
static_assert(!LD::internal::Solver_traits_read_lower_triangle<
                  CGAL::Eigen_solver_traits<Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Upper>>>::value,
              "an upper-triangle factorisation needs the upper triangle");
static_assert(!LD::internal::Solver_traits_read_lower_triangle<Archetype_factor_traits>::value,
              "unknown traits get the full matrix");

// solve_normal_equations(A^T B) == solve(B); a wrong number of rows fails with SOLVE_FAILED; a solver
// that reads the whole matrix (SparseLU) and the lower-triangle default give the same solution
TEST(LeastSquaresSolver, SolveNormalEquationsMatchesSolve)
{
  const Eigen::SparseMatrix<double> a = random_sparse(200, 60, 5, 7);
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(200, 3);
  LD::Least_squares_solver<> solver;
  ASSERT_TRUE(solver.factor(a));
  Eigen::MatrixX3d x, y, z;
  ASSERT_TRUE(solver.solve(b, x));
  EXPECT_TRUE(solver.matrix().isApprox(a));   // kept as given (the rvalue factor() takes it over)
  ASSERT_TRUE(solver.solve_normal_equations(Eigen::MatrixX3d(solver.matrix().transpose() * b), y));
  EXPECT_EQ(x, y);
  Eigen::SparseMatrix<double> moved = a;
  LD::Least_squares_solver<> taker;
  ASSERT_TRUE(taker.factor(std::move(moved)));
  ASSERT_TRUE(taker.solve(b, z));
  EXPECT_EQ(z, x);
  EXPECT_EQ(taker.matrix().nonZeros(), a.nonZeros());
  EXPECT_FALSE(solver.solve_normal_equations(Eigen::MatrixX3d::Zero(59, 3), z));
  EXPECT_EQ(solver.info(), LD::Least_squares_solver<>::SOLVE_FAILED);

  typedef CGAL::Eigen_solver_traits<Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>> Lu;
  static_assert(!LD::internal::Solver_traits_read_lower_triangle<Lu>::value, "SparseLU reads the whole matrix");
  LD::Least_squares_solver<Lu> lu;
  ASSERT_TRUE(lu.factor(a));
  ASSERT_TRUE(lu.solve(b, z));
  EXPECT_LE((z - x).norm(), 1e-10 * x.norm());
}

// factor_with_rows(): A by rows read from an operator D (rows x vertices, by rows) restricted to the
// unknown columns, as Mesh_deformer's core does, instead of A^T: the same normal matrix bit for bit
// (sequential and on TBB's threads), hence the same solution
TEST(LeastSquaresSolver, FactorWithRowsFromAnOperatorEqualsFactor)
{
  typedef Eigen::SparseMatrix<double>::StorageIndex Index;
  const Eigen::SparseMatrix<double> dc = random_sparse(2500, 900, 6, 11);
  const Eigen::SparseMatrix<double, Eigen::RowMajor> d(dc);
  std::vector<long> unknown_index(900, -1);
  std::vector<Index> unknowns;
  for(Index v = 0; v < 900; ++v)
    if(v % 5 != 0)
    {
      unknown_index[std::size_t(v)] = long(unknowns.size());
      unknowns.push_back(v);
    }
  // A: the unknown columns of D, by columns
  std::vector<Eigen::Triplet<double>> t;
  for(Index r = 0; r < Index(d.rows()); ++r)
    for(Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(d, r); it; ++it)
      if(unknown_index[std::size_t(it.col())] >= 0)
        t.emplace_back(r, int(unknown_index[std::size_t(it.col())]), it.value());
  Eigen::SparseMatrix<double> a(d.rows(), Eigen::Index(unknowns.size()));
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  auto rows = [&](Index r, Index j, auto&& f) {
    const Index* begin = d.innerIndexPtr() + d.outerIndexPtr()[r];
    const Index* end = d.innerIndexPtr() + d.outerIndexPtr()[r + 1];
    if(j > 0)
      begin = std::lower_bound(begin, end, unknowns[std::size_t(j)]);
    for(const Index* p = begin; p != end; ++p)
      if(unknown_index[std::size_t(*p)] >= 0)
        f(Index(unknown_index[std::size_t(*p)]), d.valuePtr()[p - d.innerIndexPtr()]);
  };
  const Eigen::SparseMatrix<double> at = a.transpose();
  for(bool lower : {false, true})
    for(bool parallel : {false, true})
    {
      const Eigen::SparseMatrix<double> expected = LD::internal::normal_matrix(a, at, lower);
      const Eigen::SparseMatrix<double> n = LD::internal::normal_matrix_from_rows(a, rows, lower, parallel);
      ASSERT_EQ(n.nonZeros(), expected.nonZeros());
      EXPECT_TRUE(std::equal(n.outerIndexPtr(), n.outerIndexPtr() + n.cols() + 1, expected.outerIndexPtr()));
      EXPECT_TRUE(std::equal(n.innerIndexPtr(), n.innerIndexPtr() + n.nonZeros(), expected.innerIndexPtr()));
      EXPECT_TRUE(std::equal(n.valuePtr(), n.valuePtr() + n.nonZeros(), expected.valuePtr()));
    }
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(d.rows(), 3);
  LD::Least_squares_solver<> by_columns, by_rows;
  ASSERT_TRUE(by_columns.factor(a));
  Eigen::SparseMatrix<double> taken = a;
  ASSERT_TRUE(by_rows.factor_with_rows(std::move(taken), rows));
  Eigen::MatrixX3d x, y;
  ASSERT_TRUE(by_columns.solve(b, x));
  ASSERT_TRUE(by_rows.solve(b, y));
  EXPECT_EQ(x, y);
  EXPECT_GT(x.norm(), 0.);
  // a non-finite entry is refused as by factor()
  Eigen::SparseMatrix<double> bad = a;
  bad.valuePtr()[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(by_rows.factor_with_rows(std::move(bad), rows));
  EXPECT_EQ(by_rows.info(), LD::Least_squares_solver<>::NOT_FINITE);
}

} // namespace
