// Random least-squares problems shared by the solver tests.
#ifndef LAPLACIAN_DEFORMATION_TEST_LEAST_SQUARES_HELPERS_H
#define LAPLACIAN_DEFORMATION_TEST_LEAST_SQUARES_HELPERS_H

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <random>
#include <vector>

// A random sparse overdetermined full-rank matrix: about `density` of random entries in
// [-1, 1], plus a diagonal block with entries in [1, 2] on the first `cols` rows (full column rank).
inline Eigen::SparseMatrix<double> random_sparse_matrix(Eigen::Index rows, Eigen::Index cols,
                                                 double density, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1, 1), diag(1, 2), coin(0, 1);
  std::vector<Eigen::Triplet<double> > triplets;
  for(Eigen::Index i = 0; i < rows; ++i)
    for(Eigen::Index j = 0; j < cols; ++j)
      if(coin(rng) < density)
        triplets.emplace_back(int(i), int(j), value(rng));
  for(Eigen::Index j = 0; j < cols; ++j)
    triplets.emplace_back(int(j), int(j), diag(rng));
  Eigen::SparseMatrix<double> a(rows, cols);
  a.setFromTriplets(triplets.begin(), triplets.end());
  return a;
}

inline Eigen::MatrixX3d random_rhs(Eigen::Index rows, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-10, 10);
  Eigen::MatrixX3d b(rows, 3);
  for(Eigen::Index i = 0; i < rows; ++i)
    for(int c = 0; c < 3; ++c)
      b(i, c) = value(rng);
  return b;
}

#endif // LAPLACIAN_DEFORMATION_TEST_LEAST_SQUARES_HELPERS_H
