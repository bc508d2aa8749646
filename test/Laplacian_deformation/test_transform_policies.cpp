// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// Transform policies (DESIGN.md section 4) on synthetic cells: random rest edge vectors
// (fixed seeds, 6 to 12 spokes, random positive weights) and current vectors obtained by a known
// linear map, so that the expected transform is known in closed form.

#include <CGAL/Laplacian_deformation/Fixed_transform.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/Principal_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_scale_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace {

namespace LD = CGAL::Laplacian_deformation;

// Owns the arrays a Transform_cell views.
struct Cell_data
{
  std::vector<Eigen::Vector3d> rest, current;
  std::vector<double> weights;

  std::size_t size() const { return rest.size(); }

  LD::Transform_cell cell() const
  {
    return LD::Transform_cell(rest.data(), current.data(), weights.data(), rest.size());
  }

  // current = m * rest
  void map(const Eigen::Matrix3d& m)
  {
    current.resize(rest.size());
    for(std::size_t i = 0; i < rest.size(); ++i)
      current[i] = m * rest[i];
  }

  // the same problem seen after a rotation g of the whole space
  Cell_data rotated(const Eigen::Matrix3d& g) const
  {
    Cell_data r = *this;
    for(std::size_t i = 0; i < size(); ++i)
    {
      r.rest[i] = g * rest[i];
      r.current[i] = g * current[i];
    }
    return r;
  }

  // sum c |e' - T e|^2
  double residual(const Eigen::Matrix3d& t) const
  {
    double r = 0;
    for(std::size_t i = 0; i < size(); ++i)
      r += weights[i] * (current[i] - t * rest[i]).squaredNorm();
    return r;
  }
};

double uniform(std::mt19937& rng, double lo, double hi)
{
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// 6 to 12 spokes with coordinates in [-1, 1] and weights in [0.1, 2]; current = rest.
Cell_data random_cell(unsigned seed)
{
  std::mt19937 rng(seed);
  const std::size_t n = std::uniform_int_distribution<std::size_t>(6, 12)(rng);
  Cell_data d;
  for(std::size_t i = 0; i < n; ++i)
  {
    d.rest.emplace_back(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    d.weights.push_back(uniform(rng, 0.1, 2));
  }
  d.current = d.rest;
  return d;
}

// A flat cell: every rest vector in the xy plane.
Cell_data random_flat_cell(unsigned seed)
{
  Cell_data d = random_cell(seed);
  for(Eigen::Vector3d& e : d.rest)
    e.z() = 0;
  d.current = d.rest;
  return d;
}

// A 3D cell whose weighted rest covariance sum c e e^T is diagonal (with distinct entries), yet
// whose spokes are in general position: each random vector (x,y,z) comes with its images
// (x,-y,-z), (-x,y,-z), (-x,-y,z) under the half-turns about the axes, with equal weights; two
// such groups plus two random axis spokes give 10 spokes.
Cell_data axis_symmetric_cell(unsigned seed)
{
  std::mt19937 rng(seed);
  Cell_data d;
  for(int g = 0; g < 2; ++g)
  {
    const Eigen::Vector3d v(uniform(rng, 0.2, 1), uniform(rng, 0.2, 1), uniform(rng, 0.2, 1));
    const double w = uniform(rng, 0.1, 2);
    for(const Eigen::Vector3d& s : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, -1, -1),
                                    Eigen::Vector3d(-1, 1, -1), Eigen::Vector3d(-1, -1, 1)})
    {
      d.rest.push_back(v.cwiseProduct(s));
      d.weights.push_back(w);
    }
  }
  d.rest.emplace_back(uniform(rng, 0.2, 1), 0, 0);
  d.weights.push_back(uniform(rng, 0.1, 2));
  d.rest.emplace_back(0, 0, uniform(rng, 0.2, 1));
  d.weights.push_back(uniform(rng, 0.1, 2));
  d.current = d.rest;
  return d;
}

// Uniformly distributed proper rotation (normalised Gaussian quaternion).
Eigen::Matrix3d random_rotation(std::mt19937& rng)
{
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

Eigen::Matrix3d random_rotation(unsigned seed)
{
  std::mt19937 rng(seed);
  return random_rotation(rng);
}

// A generic (anisotropic, non-symmetric) map close enough to I to keep det > 0.
Eigen::Matrix3d random_general_map(unsigned seed)
{
  std::mt19937 rng(seed);
  Eigen::Matrix3d m;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      m(i, j) = (i == j ? 1 : 0) + uniform(rng, -0.35, 0.35);
  return m;
}

// |a - b|_F <= tol * max(1, |b|_F), with a readable message.
::testing::AssertionResult matrix_near(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b,
                                       double tol = 1e-12)
{
  if(!a.allFinite())
    return ::testing::AssertionFailure() << "not finite:\n" << a;
  const double d = (a - b).norm();
  const double bound = tol * std::max(1., b.norm());
  if(d <= bound)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "|a - b| = " << d << " > " << bound << "\na =\n"
                                       << a << "\nb =\n" << b;
}

::testing::AssertionResult is_rotation(const Eigen::Matrix3d& r, double tol = 1e-12)
{
  const double orth = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
  const double det = r.determinant();
  if(orth <= tol && std::abs(det - 1) <= tol)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "|R^T R - I| = " << orth << ", det = " << det << "\n" << r;
}

const unsigned seeds[] = {1u, 2u, 3u, 17u, 42u, 1234u, 98765u, 31337u};

// ---------------------------------------------------------------------------------------------
// Typed tests

template <class Policy>
struct Policy_name;
template <> struct Policy_name<LD::Fixed_transform> { static const char* get() { return "Fixed"; } };
template <> struct Policy_name<LD::Rotation_transform> { static const char* get() { return "Rotation"; } };
template <> struct Policy_name<LD::Similarity_transform> { static const char* get() { return "Similarity"; } };
template <> struct Policy_name<LD::Scaled_rotation_transform> { static const char* get() { return "SR1"; } };
template <> struct Policy_name<LD::Principal_scaled_rotation_transform> { static const char* get() { return "Principal"; } };
template <> struct Policy_name<LD::Rotation_scale_rotation_transform> { static const char* get() { return "R2SR1"; } };

struct Policy_names
{
  template <class Policy>
  static std::string GetName(int) { return Policy_name<Policy>::get(); }
};

template <class Policy>
struct TransformPoliciesAll : ::testing::Test {};
template <class Policy>
struct TransformPoliciesRigid : ::testing::Test {};
template <class Policy>
struct TransformPoliciesScaled : ::testing::Test {};

typedef ::testing::Types<LD::Fixed_transform, LD::Rotation_transform, LD::Similarity_transform,
                         LD::Scaled_rotation_transform, LD::Principal_scaled_rotation_transform,
                         LD::Rotation_scale_rotation_transform>
    All_policies;
// every policy that must reproduce a rigid motion of the cell
typedef ::testing::Types<LD::Rotation_transform, LD::Similarity_transform,
                         LD::Scaled_rotation_transform, LD::Principal_scaled_rotation_transform,
                         LD::Rotation_scale_rotation_transform>
    Rigid_policies;
// every policy that must reproduce a uniform scaling of the cell
typedef ::testing::Types<LD::Similarity_transform, LD::Scaled_rotation_transform,
                         LD::Principal_scaled_rotation_transform,
                         LD::Rotation_scale_rotation_transform>
    Scaled_policies;

TYPED_TEST_SUITE(TransformPoliciesAll, All_policies, Policy_names);
TYPED_TEST_SUITE(TransformPoliciesRigid, Rigid_policies, Policy_names);
TYPED_TEST_SUITE(TransformPoliciesScaled, Scaled_policies, Policy_names);

// e' = e: every policy returns I.
TYPED_TEST(TransformPoliciesAll, RestCellGivesIdentity)
{
  for(unsigned seed : seeds)
  {
    const Cell_data d = random_cell(seed);
    EXPECT_TRUE(matrix_near(TypeParam().transform(d.cell()), Eigen::Matrix3d::Identity()))
        << "seed " << seed;
  }
}

// Degenerate cells never give NaN or infinity.
TYPED_TEST(TransformPoliciesAll, DegenerateCellsGiveFiniteResults)
{
  const TypeParam policy;
  for(unsigned seed : seeds)
  {
    std::mt19937 rng(seed);
    const Cell_data base = random_cell(seed);

    Cell_data zero_weights = base;
    zero_weights.map(random_rotation(rng));
    std::fill(zero_weights.weights.begin(), zero_weights.weights.end(), 0.);
    const Eigen::Matrix3d t0 = policy.transform(zero_weights.cell());
    EXPECT_TRUE(t0.allFinite()) << "all-zero weights, seed " << seed << "\n" << t0;

    Cell_data zero_rest = base;
    for(Eigen::Vector3d& e : zero_rest.rest)
      e.setZero();
    const Eigen::Matrix3d t1 = policy.transform(zero_rest.cell());
    EXPECT_TRUE(t1.allFinite()) << "zero-length rest vectors, seed " << seed << "\n" << t1;

    Cell_data zero_current = base;
    for(Eigen::Vector3d& e : zero_current.current)
      e.setZero();
    const Eigen::Matrix3d t2 = policy.transform(zero_current.cell());
    EXPECT_TRUE(t2.allFinite()) << "zero-length current vectors, seed " << seed << "\n" << t2;

    Cell_data all_zero = base;
    for(std::size_t i = 0; i < all_zero.size(); ++i)
      all_zero.rest[i].setZero(), all_zero.current[i].setZero();
    const Eigen::Matrix3d t3 = policy.transform(all_zero.cell());
    EXPECT_TRUE(t3.allFinite()) << "all vectors zero, seed " << seed << "\n" << t3;

    // a collinear cell moved by a random map
    Cell_data collinear = base;
    const Eigen::Vector3d dir = Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), 1).normalized();
    for(Eigen::Vector3d& e : collinear.rest)
      e = uniform(rng, -1, 1) * dir;
    collinear.map(random_general_map(seed));
    const Eigen::Matrix3d t4 = policy.transform(collinear.cell());
    EXPECT_TRUE(t4.allFinite()) << "collinear cell, seed " << seed << "\n" << t4;

    // an empty cell
    const LD::Transform_cell empty(nullptr, nullptr, nullptr, 0);
    const Eigen::Matrix3d t5 = policy.transform(empty);
    EXPECT_TRUE(t5.allFinite()) << "empty cell\n" << t5;
  }
}

// e' = G e for a proper rotation G: the policy returns G (a rigid motion is a fixed point).
TYPED_TEST(TransformPoliciesRigid, RigidMotionReturnsTheRotation)
{
  const TypeParam policy;
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    const Eigen::Matrix3d g = random_rotation(seed + 1000);
    d.map(g);
    EXPECT_TRUE(matrix_near(policy.transform(d.cell()), g)) << "random cell, seed " << seed;

    Cell_data flat = random_flat_cell(seed);
    flat.map(g);
    EXPECT_TRUE(matrix_near(policy.transform(flat.cell()), g)) << "flat cell, seed " << seed;
  }
}

// e' = s G e: Similarity, S*R1, Principal and R2*S*R1 return s G.
TYPED_TEST(TransformPoliciesScaled, UniformScaleReturnsScaledRotation)
{
  const TypeParam policy;
  for(double s : {1.5, 0.7})
    for(unsigned seed : seeds)
    {
      Cell_data d = random_cell(seed);
      const Eigen::Matrix3d g = random_rotation(seed + 2000);
      d.map(s * g);
      EXPECT_TRUE(matrix_near(policy.transform(d.cell()), s * g)) << "s = " << s << ", seed " << seed;
    }
}

// Flat cell (rest vectors in the xy plane), e' = 2 e: the unseen z axis takes the isotropic
// scale 2, not 1, so the result is 2 I.
TYPED_TEST(TransformPoliciesScaled, FlatCellUniformScaleFallsBackToIsotropicScale)
{
  const TypeParam policy;
  for(unsigned seed : seeds)
  {
    Cell_data d = random_flat_cell(seed);
    d.map(2 * Eigen::Matrix3d::Identity());
    const Eigen::Matrix3d t = policy.transform(d.cell());
    EXPECT_TRUE(matrix_near(t, 2 * Eigen::Matrix3d::Identity())) << "seed " << seed;
    EXPECT_NEAR(t(2, 2), 2., 1e-12) << "seed " << seed;
  }
}

// e' = 1e4 e: every scale is clamped to 1e2.
TYPED_TEST(TransformPoliciesScaled, LargeScaleIsClamped)
{
  const TypeParam policy;
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(1e4 * Eigen::Matrix3d::Identity());
    EXPECT_TRUE(matrix_near(policy.transform(d.cell()), 1e2 * Eigen::Matrix3d::Identity()))
        << "seed " << seed;

    // the same through a rotation: 1e2 G
    const Eigen::Matrix3d g = random_rotation(seed + 3000);
    d.map(1e4 * g);
    EXPECT_TRUE(matrix_near(policy.transform(d.cell()), 1e2 * g)) << "rotated, seed " << seed;
  }
}

// e' = 0: finite, every scale clamped to 1e-2 (the rotation of a zero covariance is I).
TYPED_TEST(TransformPoliciesScaled, ZeroCurrentCellIsClampedToMinimumScale)
{
  const TypeParam policy;
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(Eigen::Matrix3d::Zero());
    const Eigen::Matrix3d t = policy.transform(d.cell());
    ASSERT_TRUE(t.allFinite()) << t;
    EXPECT_TRUE(matrix_near(t, 1e-2 * Eigen::Matrix3d::Identity())) << "seed " << seed;
  }
}

// ---------------------------------------------------------------------------------------------
// Single-policy properties

TEST(TransformPolicies, FixedReturnsIdentity)
{
  const LD::Fixed_transform policy;
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(random_general_map(seed) * 3.);
    EXPECT_EQ(policy.transform(d.cell()), Eigen::Matrix3d::Identity()) << "seed " << seed;
  }
}

// e' = s G e: Rotation ignores the scale.
TEST(TransformPolicies, RotationIgnoresUniformScale)
{
  const LD::Rotation_transform policy;
  for(double s : {1.5, 0.7})
    for(unsigned seed : seeds)
    {
      Cell_data d = random_cell(seed);
      const Eigen::Matrix3d g = random_rotation(seed + 4000);
      d.map(s * g);
      EXPECT_TRUE(matrix_near(policy.transform(d.cell()), g)) << "s = " << s << ", seed " << seed;
    }
}

// e' = M e with det(M) < 0: the result is still a proper rotation (reflection fix), and no
// nearby rotation fits the cell better.
TEST(TransformPolicies, RotationFixesReflections)
{
  const LD::Rotation_transform policy;
  for(unsigned seed : seeds)
  {
    std::mt19937 rng(seed + 5000);
    Cell_data d = random_cell(seed);
    const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();
    for(const Eigen::Matrix3d& m : {Eigen::Matrix3d(random_rotation(rng) * mirror),
                                    Eigen::Matrix3d(random_general_map(seed) * mirror * random_rotation(rng)),
                                    Eigen::Matrix3d(-Eigen::Matrix3d::Identity())})
    {
      ASSERT_LT(m.determinant(), 0);
      d.map(m);
      const Eigen::Matrix3d r = policy.transform(d.cell());
      EXPECT_TRUE(is_rotation(r)) << "seed " << seed;
      EXPECT_NEAR(r.determinant(), 1., 1e-12) << "seed " << seed;

      // local optimality over proper rotations: small perturbations R exp([w]x) never fit better
      const double best = d.residual(r);
      for(int k = 0; k < 20; ++k)
      {
        const Eigen::Vector3d axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        const Eigen::Matrix3d p = r * Eigen::AngleAxisd(1e-3, axis.normalized()).toRotationMatrix();
        EXPECT_GE(d.residual(p), best - 1e-12 * std::max(1., best)) << "seed " << seed;
      }
    }
  }
}

// Rotation returns a proper rotation for a general (non-rigid) deformation.
TEST(TransformPolicies, RotationOfGeneralCellIsProper)
{
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(random_general_map(seed + 6000) * random_rotation(seed + 7000));
    EXPECT_TRUE(is_rotation(LD::Rotation_transform().transform(d.cell()))) << "seed " << seed;
  }
}

// e' = diag(s) e on a 3D cell whose rest covariance is diagonal: R1 = I, and S*R1 returns
// exactly diag(s). On such a cell S*R1 fits the cell exactly.
TEST(TransformPolicies, ScaledRotationRecoversAxisAlignedScaling)
{
  const LD::Scaled_rotation_transform policy;
  const Eigen::Vector3d scales[] = {Eigen::Vector3d(1.5, 0.8, 1.2), Eigen::Vector3d(0.3, 2.5, 1.),
                                    Eigen::Vector3d(4., 0.5, 0.25)};
  for(unsigned seed : seeds)
    for(const Eigen::Vector3d& s : scales)
    {
      Cell_data d = axis_symmetric_cell(seed);
      d.map(s.asDiagonal());
      const Eigen::Matrix3d r1 = LD::Rotation_transform().transform(d.cell());
      EXPECT_TRUE(matrix_near(r1, Eigen::Matrix3d::Identity())) << "R1, seed " << seed;
      const Eigen::Matrix3d t = policy.transform(d.cell());
      EXPECT_TRUE(matrix_near(t, Eigen::Matrix3d(s.asDiagonal()))) << "seed " << seed;
      EXPECT_LE(d.residual(t), 1e-24) << "seed " << seed;
      // R2*S*R1 adds nothing here
      EXPECT_TRUE(matrix_near(LD::Rotation_scale_rotation_transform().transform(d.cell()),
                              Eigen::Matrix3d(s.asDiagonal())))
          << "R2SR1, seed " << seed;
    }
}

// e' = diag(s) e on a generic random cell (rest covariance C not diagonal): R1 is the polar
// factor of diag(s) C, which is not I, so S*R1 does NOT return diag(s): the fit is sequential
// (R1 first, then S), not joint. This documents the paper's method; it is not a defect.
TEST(TransformPolicies, ScaledRotationOnGenericCellIsOnlyApproximatelyAxisAligned)
{
  const LD::Scaled_rotation_transform policy;
  const Eigen::Matrix3d s = Eigen::Vector3d(1.5, 0.8, 1.2).asDiagonal();
  double max_defect = 0, min_defect = std::numeric_limits<double>::infinity();
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(s);
    const Eigen::Matrix3d t = policy.transform(d.cell());
    ASSERT_TRUE(t.allFinite());
    const double defect = (t - s).norm() / s.norm();
    max_defect = std::max(max_defect, defect);
    min_defect = std::min(min_defect, defect);
    EXPECT_GT(defect, 1e-3) << "seed " << seed;
    // still better than no transform at all
    EXPECT_LT(d.residual(t), d.residual(Eigen::Matrix3d::Identity())) << "seed " << seed;
  }
  RecordProperty("min_relative_defect", std::to_string(min_defect));
  RecordProperty("max_relative_defect", std::to_string(max_defect));
}

// S*R1 is not rotation-invariant: for the anisotropic problem above (exact on an axis-symmetric
// cell), rotating the whole problem by G gives T(G cell) != G T(cell) G^T.
TEST(TransformPolicies, ScaledRotationIsNotRotationInvariant)
{
  const LD::Scaled_rotation_transform policy;
  const Eigen::Matrix3d s = Eigen::Vector3d(1.5, 0.8, 1.2).asDiagonal();
  double min_defect = std::numeric_limits<double>::infinity();
  for(unsigned seed : seeds)
  {
    Cell_data d = axis_symmetric_cell(seed);
    d.map(s);
    const Eigen::Matrix3d g = random_rotation(seed + 8000);
    const Cell_data rd = d.rotated(g);
    const Eigen::Matrix3d t = policy.transform(d.cell());
    const Eigen::Matrix3d tg = policy.transform(rd.cell());
    ASSERT_TRUE(tg.allFinite());
    const double defect = (tg - g * t * g.transpose()).norm() / t.norm();
    min_defect = std::min(min_defect, defect);
    EXPECT_GT(defect, 1e-3) << "seed " << seed;
    // the rotated problem is still fitted exactly by G diag(s) G^T, which S*R1 misses
    EXPECT_GT(rd.residual(tg), 1e-6) << "seed " << seed;
  }
  RecordProperty("min_relative_rotation_defect", std::to_string(min_defect));
}

// Principal_scaled_rotation_transform is rotation-invariant: T(G e, G e') = G T(e, e') G^T,
// and so are Rotation and Similarity.
TEST(TransformPolicies, PrincipalScaledRotationIsRotationInvariant)
{
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(random_general_map(seed + 9000) * random_rotation(seed + 10000));
    const Eigen::Matrix3d g = random_rotation(seed + 11000);
    const Cell_data rd = d.rotated(g);

    const LD::Principal_scaled_rotation_transform principal;
    const Eigen::Matrix3d t = principal.transform(d.cell());
    EXPECT_TRUE(matrix_near(principal.transform(rd.cell()), g * t * g.transpose()))
        << "Principal, seed " << seed;
    // the result is anisotropic (otherwise the check above would be trivial)
    EXPECT_GT((t - Eigen::Matrix3d(LD::Similarity_transform().transform(d.cell()))).norm(), 1e-3)
        << "seed " << seed;

    const LD::Rotation_transform rotation;
    EXPECT_TRUE(matrix_near(rotation.transform(rd.cell()),
                            g * rotation.transform(d.cell()) * g.transpose()))
        << "Rotation, seed " << seed;
    const LD::Similarity_transform similarity;
    EXPECT_TRUE(matrix_near(similarity.transform(rd.cell()),
                            g * similarity.transform(d.cell()) * g.transpose()))
        << "Similarity, seed " << seed;
  }
}

// Flat cell scaled anisotropically within its plane: the two tangential scales are recovered
// and the normal one is their geometric mean.
TEST(TransformPolicies, PrincipalScaledRotationTiesNormalScale)
{
  for(unsigned seed : seeds)
  {
    // an in-plane axis-symmetric cell: rest covariance diag(a, b, 0) with a != b
    Cell_data d = axis_symmetric_cell(seed);
    for(Eigen::Vector3d& e : d.rest)
      e.z() = 0;
    const Eigen::Vector3d s(1.6, 0.9, 1.);
    d.map(s.asDiagonal());
    const Eigen::Matrix3d expected = Eigen::Vector3d(1.6, 0.9, std::sqrt(1.6 * 0.9)).asDiagonal();
    EXPECT_TRUE(matrix_near(LD::Principal_scaled_rotation_transform().transform(d.cell()), expected))
        << "seed " << seed;
  }
}

// Scales are clamped per axis: x stretched by 1e4, y flattened to 0, z kept.
TEST(TransformPolicies, ScaledRotationClampsEachAxis)
{
  for(unsigned seed : seeds)
  {
    Cell_data d = axis_symmetric_cell(seed);
    d.map(Eigen::Vector3d(1e4, 0, 1).asDiagonal());
    const Eigen::Matrix3d t = LD::Scaled_rotation_transform().transform(d.cell());
    ASSERT_TRUE(t.allFinite()) << t;
    EXPECT_TRUE(matrix_near(t, Eigen::Matrix3d(Eigen::Vector3d(1e2, 1e-2, 1).asDiagonal())))
        << "seed " << seed;
  }
}

// A cell that only spans the x axis: y and z fall back to the isotropic scale.
TEST(TransformPolicies, ScaledRotationCollinearCellUsesIsotropicScale)
{
  for(unsigned seed : seeds)
  {
    std::mt19937 rng(seed);
    Cell_data d = random_cell(seed);
    for(Eigen::Vector3d& e : d.rest)
      e = Eigen::Vector3d(uniform(rng, -1, 1), 0, 0);
    d.map(3 * Eigen::Matrix3d::Identity());
    EXPECT_TRUE(matrix_near(LD::Scaled_rotation_transform().transform(d.cell()),
                            3 * Eigen::Matrix3d::Identity()))
        << "seed " << seed;
  }
}

// Zero weights on some spokes: those spokes are ignored.
TEST(TransformPolicies, ZeroWeightSpokesAreIgnored)
{
  for(unsigned seed : seeds)
  {
    Cell_data d = random_cell(seed);
    d.map(random_general_map(seed + 12000));
    Cell_data padded = d;
    std::mt19937 rng(seed);
    for(int k = 0; k < 3; ++k)
    {
      padded.rest.emplace_back(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
      padded.current.emplace_back(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
      padded.weights.push_back(0.);
    }
    EXPECT_TRUE(matrix_near(LD::Scaled_rotation_transform().transform(padded.cell()),
                            LD::Scaled_rotation_transform().transform(d.cell())))
        << "seed " << seed;
    EXPECT_TRUE(matrix_near(LD::Principal_scaled_rotation_transform().transform(padded.cell()),
                            LD::Principal_scaled_rotation_transform().transform(d.cell())))
        << "seed " << seed;
  }
}

// R2 is the best rotation after S*R1, and I is a candidate: R2*S*R1 fits every cell at least as
// well as S*R1.
TEST(TransformPolicies, RotationScaleRotationFitsAtLeastAsWellAsScaledRotation)
{
  double max_gain = 0;
  for(unsigned seed : seeds)
    for(int variant = 0; variant < 3; ++variant)
    {
      Cell_data d = random_cell(seed);
      std::mt19937 rng(seed * 7 + unsigned(variant));
      d.map(random_general_map(seed + 13000 + unsigned(variant)) * random_rotation(rng));
      if(variant == 2) // plus noise, so that no linear map fits exactly
        for(Eigen::Vector3d& e : d.current)
          e += 0.1 * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      const double sr = d.residual(LD::Scaled_rotation_transform().transform(d.cell()));
      const double rsr = d.residual(LD::Rotation_scale_rotation_transform().transform(d.cell()));
      EXPECT_LE(rsr, sr + 1e-12) << "seed " << seed << ", variant " << variant;
      max_gain = std::max(max_gain, (sr - rsr) / std::max(sr, 1e-300));
    }
  RecordProperty("max_relative_residual_gain_of_R2", std::to_string(max_gain));
}

} // namespace

// The fast closest rotation (Jacobi eigenvectors of S^T S) agrees with the SVD reference on
// general, rank-2 (flat cells), rank-1, reflected, symmetric and repeated-singular-value matrices.
TEST(TransformPolicies, FastClosestRotationMatchesSvd)
{
  using LD::internal::closest_rotation;
  using LD::internal::closest_rotation_svd;
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  auto random_matrix = [&] {
    Eigen::Matrix3d m;
    for(int i = 0; i < 9; ++i)
      m(i / 3, i % 3) = u(rng);
    return m;
  };
  std::vector<Eigen::Matrix3d> cases;
  for(int k = 0; k < 2000; ++k)
  {
    const Eigen::Matrix3d m = random_matrix();
    cases.push_back(m);                                                    // general
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    cases.push_back(a * b.transpose() + c * a.cross(b).cross(c).transpose());   // rank 2
    cases.push_back(m * Eigen::Vector3d(1, 1, 0).asDiagonal() * random_matrix()); // rank 2
    cases.push_back(m * Eigen::Vector3d(1, 1, -1).asDiagonal());                 // reflection
    cases.push_back(m + m.transpose());                                          // symmetric
    const Eigen::Matrix3d q = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    cases.push_back(q * Eigen::Vector3d(2, 2, 0.5 + u(rng) * 0.4).asDiagonal()); // repeated sigma
    cases.push_back(q * Eigen::Vector3d(0.3, 1e-12, 1e-12).asDiagonal());        // rank ~1
    cases.push_back(1e-30 * m);
    cases.push_back(1e30 * m);
  }
  cases.push_back(Eigen::Matrix3d::Zero());
  cases.push_back(Eigen::Matrix3d::Identity());
  cases.push_back(-Eigen::Matrix3d::Identity());
  double worst = 0;
  for(const Eigen::Matrix3d& s : cases)
  {
    const Eigen::Matrix3d r = closest_rotation(s), ref = closest_rotation_svd(s);
    ASSERT_NEAR((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 0., 1e-13);
    ASSERT_NEAR(r.determinant(), 1., 1e-13);
    // where the SVD's answer is unique (distinct two largest directions), both must agree
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s);
    const Eigen::Vector3d sigma = svd.singularValues();
    if(sigma(1) > 1e-2 * sigma(0) && sigma(1) - sigma(2) > 1e-3 * sigma(0))
      worst = (std::max)(worst, (r - ref).norm());
    // optimality: trace(R^T S) at least the reference's (up to round-off)
    EXPECT_GE((r.transpose() * s).trace(), (ref.transpose() * s).trace() - 1e-12 * s.norm());
  }
  std::cout << "[measured] fast vs SVD closest rotation, worst Frobenius difference " << worst << "\n";
  EXPECT_LE(worst, 1e-11);
}

// The closest rotation does not depend on the magnitude of S: S^T S used to underflow below
// about 1e-154 (the identity came back) and overflow above 1e154 (S is a sum of products of two
// edge vectors, so that is coordinates beyond 1e+-77). Powers of two give bitwise the same
// rotation; powers of ten the same up to round-off.
TEST(TransformPolicies, FastClosestRotationIsScaleInvariant)
{
  using LD::internal::closest_rotation;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for(int k = 0; k < 200; ++k)
  {
    Eigen::Matrix3d m;
    for(int i = 0; i < 9; ++i)
      m(i / 3, i % 3) = u(rng);
    const Eigen::Matrix3d r = closest_rotation(m);
    for(int e : {-1000, -600, -300, 300, 600, 1000})
      EXPECT_TRUE(closest_rotation(std::ldexp(1., e) * m) == r) << "2^" << e << ", case " << k;
    for(double scale : {1e-300, 1e-250, 1e-200, 1e-160, 1e-100, 1e100, 1e160, 1e200, 1e250, 1e300})
      EXPECT_LE((closest_rotation(scale * m) - r).norm(), 1e-12) << "scale " << scale << ", case " << k;
  }
}
