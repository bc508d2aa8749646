// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// The batched local step (internal/batched_transforms.h) against the policies' scalar
// transform(cell): 10^5 random cells, degenerate ones included (rank 1 and 2, reflections, zero
// cells, tiny and huge magnitudes, NaN and infinite entries), for every built-in policy with a
// transform_block() and every kernel target this processor runs.

#include <CGAL/Laplacian_deformation/Anchored_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Fixed_transform.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/Principal_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_scale_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

namespace LD = CGAL::Laplacian_deformation;
namespace B = CGAL::Laplacian_deformation::internal::batched;

// all cells' spokes in three arrays; cells view them
struct Cell_set
{
  std::vector<Eigen::Vector3d> rest, current;
  std::vector<double> weights;
  std::vector<std::size_t> start{0};
  std::vector<int> kind;

  std::vector<LD::Transform_cell> cells() const
  {
    std::vector<LD::Transform_cell> c;
    for(std::size_t k = 0; k + 1 < start.size(); ++k)
      c.emplace_back(rest.data() + start[k], current.data() + start[k], weights.data() + start[k],
                     start[k + 1] - start[k]);
    return c;
  }
};

Eigen::Matrix3d random_rotation(std::mt19937_64& g)
{
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(g), n(g), n(g), n(g));
  return q.normalized().toRotationMatrix();
}

// kinds: 0-2 general (rotation, scales, shear, noise), 3 rank 1 (collinear, with or without a
// little noise), 4 rank 2 (coplanar), 5 reflection (det < 0), 6 zero cells and zero weights,
// 7 tiny and huge magnitudes, 8 NaN and infinite entries, 9 degree 0 to 2 and exact maps
Cell_set random_cells(std::size_t count, unsigned seed)
{
  std::mt19937_64 g(seed);
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<int> degree_of(3, 16);
  Cell_set set;
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for(std::size_t k = 0; k < count; ++k)
  {
    const int kind = int(k % 10);
    int degree = degree_of(g);
    if(kind == 9)
      degree = int(k / 10 % 3);
    Eigen::Matrix3d m = random_rotation(g);
    Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
    for(int i = 0; i < 3; ++i)
    {
      shear(i, i) = std::exp(n(g) * 0.5);
      for(int j = i + 1; j < 3; ++j)
        shear(i, j) = 0.3 * n(g);
    }
    if(kind != 9)
      m = m * shear;
    if(kind == 5)
      m = m * Eigen::Vector3d(1, 1, -1).asDiagonal();
    const double noise = (kind == 3 || kind == 4) ? std::pow(10., -1 - 8 * u(g)) * (u(g) < 0.3 ? 0 : 1)
                                                  : 0.05 * u(g);
    const Eigen::Vector3d dir = Eigen::Vector3d(n(g), n(g), n(g)).normalized();
    const Eigen::Vector3d p1 = Eigen::Vector3d(n(g), n(g), n(g)).normalized();
    const Eigen::Vector3d p2 = dir.cross(p1).normalized();
    double magnitude = 1;
    if(kind == 7)
    {
      const double exps[] = {-300, -200, -150, -100, 100, 150, 200, 300};
      magnitude = std::pow(10., exps[k / 10 % 8]);
    }
    for(int i = 0; i < degree; ++i)
    {
      Eigen::Vector3d e(n(g), n(g), n(g));
      if(kind == 3)
        e = n(g) * dir;
      else if(kind == 4)
        e = n(g) * dir + n(g) * p2;
      Eigen::Vector3d c = m * e + noise * Eigen::Vector3d(n(g), n(g), n(g));
      double w = u(g) < 0.2 ? 0. : 2 * u(g);   // zero: a clamped negative weight
      if(kind == 6)
      {
        const int z = int(k / 10 % 4);
        if(z == 0)
          e = c = Eigen::Vector3d::Zero();
        else if(z == 1)
          w = 0;
        else if(z == 2)
          c = Eigen::Vector3d::Zero();
        else
          e = Eigen::Vector3d::Zero();
      }
      if(kind == 7)
      {
        e *= magnitude;
        c *= (k / 80 % 2) ? magnitude : 1.;
      }
      set.rest.push_back(e);
      set.current.push_back(c);
      set.weights.push_back(w);
    }
    if(kind == 8 && degree > 0)
    {
      const std::size_t i = set.rest.size() - 1 - std::size_t(k / 10) % std::size_t(degree);
      const double bad = (k / 10 % 3 == 0) ? nan : ((k / 10 % 3 == 1) ? inf : -inf);
      switch(k / 30 % 3)
      {
      case 0: set.rest[i][int(k % 3)] = bad; break;
      case 1: set.current[i][int(k / 7 % 3)] = bad; break;
      default: set.weights[i] = (bad == bad) ? inf : nan; break;
      }
    }
    set.start.push_back(set.rest.size());
    set.kind.push_back(kind);
  }
  return set;
}

std::vector<B::Batch_target> available_targets()
{
  std::vector<B::Batch_target> t;
  for(B::Batch_target x : {B::Batch_target::per_cell, B::Batch_target::portable, B::Batch_target::avx2,
                           B::Batch_target::avx512})
    if(B::batch_target_supported(x))
      t.push_back(x);
  return t;
}

// The kernels are compiled without floating-point contraction and follow the scalar code's order
// of operations: with the default flags the two are bitwise equal. When the test is compiled with
// FMA (e.g. -march=native), the compiler contracts the scalar code (Eigen included) but not the
// kernels, and the two agree to round-off amplified by the cell's conditioning (1.06e-12 measured
// with GCC 12 -march=native, a nearly coplanar cell of Rotation_scale_rotation_transform).
#if defined(__FMA__)
constexpr double tolerance = 1e-11;
#else
constexpr double tolerance = 1e-12;
#endif

// |b - s|_max <= tolerance max(1, |s|_max), or both not finite
bool agrees(const Eigen::Matrix3d& b, const Eigen::Matrix3d& s)
{
  if(!s.allFinite() || !b.allFinite())
    return !s.allFinite() && !b.allFinite();
  return (b - s).cwiseAbs().maxCoeff() <= tolerance * (std::max)(1., s.cwiseAbs().maxCoeff());
}

template <class Policy>
void check_policy(const char* name)
{
  const Cell_set set = random_cells(100000, 20261201);
  const std::vector<LD::Transform_cell> cells = set.cells();
  const Policy policy;
  std::vector<Eigen::Matrix3d> scalar(cells.size());
  for(std::size_t i = 0; i < cells.size(); ++i)
    scalar[i] = policy.transform(cells[i]);
  std::size_t non_finite = 0;
  for(const Eigen::Matrix3d& s : scalar)
    non_finite += !s.allFinite();
  EXPECT_GT(non_finite, 0u) << "the NaN and infinite cells must come out non-finite";

  const B::Batch_target saved = B::batch_target();
  std::vector<std::vector<Eigen::Matrix3d>> per_target;
  for(B::Batch_target target : available_targets())
  {
    B::set_batch_target(target);
    ASSERT_EQ(B::batch_target(), target);
    std::vector<Eigen::Matrix3d> batched(cells.size());
    // odd block sizes, so that partial lane groups are covered
    for(std::size_t first = 0, size = 1; first < cells.size(); first += size, size = size % 37 + 1)
    {
      const std::size_t count = (std::min)(size, cells.size() - first);
      policy.transform_block(cells.data() + first, count, batched.data() + first);
    }
    std::size_t bad = 0, bitwise_different = 0;
    double worst = 0;
    for(std::size_t i = 0; i < cells.size(); ++i)
    {
      if(!agrees(batched[i], scalar[i]))
      {
        if(++bad <= 5)
          ADD_FAILURE() << name << " target " << B::batch_target_name(target) << " cell " << i << " (kind "
                        << set.kind[i] << ")\nscalar\n" << scalar[i] << "\nbatched\n" << batched[i];
      }
      if(scalar[i].allFinite() && !(batched[i].array() == scalar[i].array()).all())
        ++bitwise_different;
      if(scalar[i].allFinite() && batched[i].allFinite())
        worst = (std::max)(worst, (batched[i] - scalar[i]).cwiseAbs().maxCoeff() /
                                      (std::max)(1., scalar[i].cwiseAbs().maxCoeff()));
    }
    EXPECT_EQ(bad, 0u) << name << " target " << B::batch_target_name(target);
    std::cout << name << " [" << B::batch_target_name(target) << "]: " << cells.size() << " cells, "
              << non_finite << " not finite (in both), " << bitwise_different
              << " finite ones not bitwise equal to transform(), largest relative difference "
              << worst << std::endl;
    per_target.push_back(std::move(batched));
  }
  B::set_batch_target(saved);
  // every target gives the same results
  for(std::size_t t = 1; t < per_target.size(); ++t)
  {
    std::size_t bad = 0;
    for(std::size_t i = 0; i < cells.size(); ++i)
      bad += !agrees(per_target[t][i], per_target[0][i]);
    EXPECT_EQ(bad, 0u) << name << ": target " << t << " against the first";
  }
}

// transform_lanes() on lanes gathered by the caller (as the local step gathers them) gives bitwise
// transform_block()'s results, for every target and partial lane groups; the lanes the scalar code
// computes get their cell rebuilt from the lanes (Lane_cells)
template <class Policy>
void check_lanes(const char* name)
{
  static_assert(B::Has_transform_lanes<Policy>::value, "");
  const Cell_set set = random_cells(20000, 20261205);
  const std::vector<LD::Transform_cell> cells = set.cells();
  const Policy policy;
  const B::Batch_target saved = B::batch_target();
  for(B::Batch_target target : available_targets())
  {
    if(target == B::Batch_target::per_cell)
      continue;
    B::set_batch_target(target);
    std::vector<Eigen::Matrix3d> by_block(cells.size()), by_lanes(cells.size());
    policy.transform_block(cells.data(), cells.size(), by_block.data());
    B::Lanes b;
    std::vector<double> spokes;
    for(std::size_t first = 0, size = 1; first < cells.size(); first += std::size_t(size), size = size % B::lanes + 1)
    {
      const int m = int((std::min)(std::size_t(size), cells.size() - first));
      std::size_t d = 0;
      for(int l = 0; l < m; ++l)
        d = (std::max)(d, cells[first + std::size_t(l)].size());
      spokes.assign(7 * d * B::lanes, -7.);   // garbage that begin_lanes() and the gather must overwrite
      B::begin_lanes(b, m, d, spokes.data());
      for(int l = 0; l < m; ++l)
      {
        const LD::Transform_cell& cell = cells[first + std::size_t(l)];
        b.degree[l] = std::int64_t(cell.size());
        for(std::size_t i = 0; i < d; ++i)
        {
          const bool on = i < cell.size();
          for(int c = 0; c < 3; ++c)
          {
            spokes[(3 * i + std::size_t(c)) * B::lanes + std::size_t(l)] = on ? cell.rest(i)[c] : 0.;
            spokes[(3 * (d + i) + std::size_t(c)) * B::lanes + std::size_t(l)] = on ? cell.current(i)[c] : 0.;
          }
          spokes[(6 * d + i) * B::lanes + std::size_t(l)] = on ? cell.weight(i) : 0.;
        }
      }
      policy.transform_lanes(b, m, by_lanes.data() + first);
    }
    std::size_t different = 0, non_finite = 0;
    for(std::size_t i = 0; i < cells.size(); ++i)
    {
      if(!by_block[i].allFinite())
      {
        ++non_finite;
        different += by_lanes[i].allFinite();
      }
      else
        different += !(by_lanes[i].array() == by_block[i].array()).all();
    }
    EXPECT_EQ(different, 0u) << name << " target " << B::batch_target_name(target);
    EXPECT_GT(non_finite, 0u);
  }
  B::set_batch_target(saved);
}

TEST(BatchedTransforms, GatheredLanesGiveBitwiseTheBlockResults)
{
  check_lanes<LD::Rotation_transform>("Rotation_transform");
  check_lanes<LD::Similarity_transform>("Similarity_transform");
  check_lanes<LD::Scaled_rotation_transform>("Scaled_rotation_transform");
  check_lanes<LD::Anchored_scaled_rotation_transform>("Anchored_scaled_rotation_transform");
  check_lanes<LD::Principal_scaled_rotation_transform>("Principal_scaled_rotation_transform");
  check_lanes<LD::Rotation_scale_rotation_transform>("Rotation_scale_rotation_transform");
}

// Lane_cells rebuilds a lane's cell with the very numbers it was gathered from
TEST(BatchedTransforms, LaneCellsRebuildTheGatheredCell)
{
  const Cell_set set = random_cells(8, 11);
  const std::vector<LD::Transform_cell> cells = set.cells();
  B::Lanes b;
  std::size_t d = 0;
  for(const LD::Transform_cell& c : cells)
    d = (std::max)(d, c.size());
  std::vector<double> spokes(7 * d * B::lanes);
  B::begin_lanes(b, 8, d, spokes.data());
  for(int l = 0; l < 8; ++l)
  {
    b.degree[l] = std::int64_t(cells[std::size_t(l)].size());
    for(std::size_t i = 0; i < cells[std::size_t(l)].size(); ++i)
    {
      for(int c = 0; c < 3; ++c)
      {
        spokes[(3 * i + std::size_t(c)) * B::lanes + std::size_t(l)] = cells[std::size_t(l)].rest(i)[c];
        spokes[(3 * (d + i) + std::size_t(c)) * B::lanes + std::size_t(l)] = cells[std::size_t(l)].current(i)[c];
      }
      spokes[(6 * d + i) * B::lanes + std::size_t(l)] = cells[std::size_t(l)].weight(i);
    }
  }
  const B::Lane_cells at(b);
  for(int l = 0; l < 8; ++l)
  {
    const LD::Transform_cell c = at(l);
    const LD::Transform_cell& e = cells[std::size_t(l)];
    ASSERT_EQ(c.size(), e.size());
    for(std::size_t i = 0; i < c.size(); ++i)
    {
      EXPECT_TRUE((c.rest(i).array() == e.rest(i).array()).all() || !e.rest(i).allFinite()) << l << " " << i;
      EXPECT_TRUE((c.current(i).array() == e.current(i).array()).all() || !e.current(i).allFinite()) << l << " " << i;
      EXPECT_TRUE(c.weight(i) == e.weight(i) || std::isnan(e.weight(i)));
    }
  }
}

TEST(BatchedTransforms, RotationMatchesScalar) { check_policy<LD::Rotation_transform>("Rotation_transform"); }
TEST(BatchedTransforms, SimilarityMatchesScalar) { check_policy<LD::Similarity_transform>("Similarity_transform"); }
TEST(BatchedTransforms, ScaledRotationMatchesScalar)
{
  check_policy<LD::Scaled_rotation_transform>("Scaled_rotation_transform");
}
TEST(BatchedTransforms, AnchoredScaledRotationMatchesScalar)
{
  check_policy<LD::Anchored_scaled_rotation_transform>("Anchored_scaled_rotation_transform");
}
TEST(BatchedTransforms, PrincipalScaledRotationMatchesScalar)
{
  check_policy<LD::Principal_scaled_rotation_transform>("Principal_scaled_rotation_transform");
}
TEST(BatchedTransforms, RotationScaleRotationMatchesScalar)
{
  check_policy<LD::Rotation_scale_rotation_transform>("Rotation_scale_rotation_transform");
}

// the core's helper: batched where a policy has transform_block(), transform(cell) otherwise
struct Counting_policy
{
  Eigen::Matrix3d transform(const LD::Transform_cell& cell) const { return double(cell.size()) * Eigen::Matrix3d::Identity(); }
};

TEST(BatchedTransforms, PoliciesWithoutABlockMethodArePerCell)
{
  static_assert(!LD::internal::Has_transform_block<Counting_policy>::value, "");
  static_assert(!LD::internal::Has_transform_block<LD::Fixed_transform>::value, "");
  static_assert(LD::internal::Has_transform_block<LD::Rotation_transform>::value, "");
  static_assert(LD::internal::Has_transform_block<LD::Principal_scaled_rotation_transform>::value, "");
  const Cell_set set = random_cells(20, 3);
  const std::vector<LD::Transform_cell> cells = set.cells();
  std::vector<Eigen::Matrix3d> out(cells.size());
  LD::internal::transform_cells(Counting_policy(), cells.data(), cells.size(), out.data());
  for(std::size_t i = 0; i < cells.size(); ++i)
    EXPECT_EQ(out[i], double(cells[i].size()) * Eigen::Matrix3d::Identity());
}

// gather_lanes() (the local step's gather of 8 cells into the lanes, vectorised with AVX2 and
// AVX-512) against a plain per-cell gather written here as Deformation_core::gather_cell() does
// it: every spoke's e = rest(a) - rest(n), e' = current(a) - current(n), scaled by the power of two
// of the cell's largest finite coordinate, the weight max(w, 0), zeros past the degree and in the
// lanes from m on, bitwise (zero signs included; NaN where the reference has NaN), for every
// target, every group size 1 to 8, degrees 0 to 17, coordinates from 1e-300 to 1e300, NaN and
// infinite coordinates, negative, -0 and NaN weights, and node records whose two unused doubles
// are NaN (never read into a spoke).
TEST(BatchedTransforms, GatherLanesMatchesTheCellGather)
{
  constexpr std::size_t rec = B::Gather_input::record;
  const std::size_t n = 3000;
  std::mt19937_64 g(20261207);
  std::normal_distribution<double> normal(0, 1);
  std::uniform_int_distribution<int> pick(0, 99);
  std::vector<double> records(n * rec);
  for(std::size_t a = 0; a < n; ++a)
  {
    const int kind = pick(g);
    const double scale = kind < 5 ? 1e-300 : kind < 10 ? 1e300 : kind < 15 ? 1e-160 : kind < 20 ? 1e150 : 1.;
    for(std::size_t k = 0; k < 6; ++k)
      records[a * rec + k] = scale * normal(g);
    if(kind == 20)
      records[a * rec + std::size_t(pick(g) % 6)] = std::numeric_limits<double>::quiet_NaN();
    if(kind == 21)
      records[a * rec + std::size_t(pick(g) % 6)] = -std::numeric_limits<double>::infinity();
    records[a * rec + 6] = records[a * rec + 7] = std::numeric_limits<double>::quiet_NaN();
  }
  std::vector<std::uint32_t> start(1, 0), neighbor;
  std::vector<double> weight;
  for(std::size_t a = 0; a < n; ++a)
  {
    const int degree = pick(g) % 18;
    for(int i = 0; i < degree; ++i)
    {
      neighbor.push_back(std::uint32_t(std::size_t(g()) % n));
      const int w = pick(g);
      weight.push_back(w < 10 ? -std::abs(normal(g)) : w < 13 ? -0. : w == 13 ? std::numeric_limits<double>::quiet_NaN() :
                       std::abs(normal(g)));
    }
    start.push_back(std::uint32_t(neighbor.size()));
  }
  B::Gather_input in;
  in.node = records.data();
  in.neighbor_start = start.data();
  in.neighbor = neighbor.data();
  in.weight = weight.data();
  // same bits, or NaN in both
  auto same = [](double x, double y) {
    return std::isnan(y) ? std::isnan(x) : std::memcmp(&x, &y, sizeof x) == 0;
  };
  const double zero = 0.;
  const B::Batch_target saved = B::batch_target();
  std::size_t checked = 0, scaled = 0, with_nan = 0;
  for(B::Batch_target target : available_targets())
  {
    if(target == B::Batch_target::per_cell)
      continue;
    std::vector<std::size_t> nodes(B::lanes);
    for(std::size_t group = 0; group < 600; ++group)
    {
      const int m = int(group % B::lanes) + 1;
      std::size_t d = 0;
      for(int l = 0; l < m; ++l)
      {
        nodes[std::size_t(l)] = std::size_t(g()) % n;
        d = (std::max)(d, std::size_t(start[nodes[std::size_t(l)] + 1] - start[nodes[std::size_t(l)]]));
      }
      std::vector<double> spokes(7 * d * B::lanes, -7.), scratch(8 * d * B::lanes, -7.);   // garbage to overwrite
      B::Lanes b;
      B::gather_lanes(target, in, nodes.data(), m, b, spokes.data(), scratch.data());
      ASSERT_EQ(b.max_degree, d);
      const double *rest = spokes.data(), *current = rest + 3 * d * B::lanes, *w = current + 3 * d * B::lanes;
      for(int l = 0; l < B::lanes; ++l)
      {
        const std::size_t a = nodes[std::size_t(l)];
        const std::size_t first = l < m ? start[a] : 0, degree = l < m ? start[a + 1] - first : 0;
        ASSERT_EQ(b.degree[l], std::int64_t(degree)) << B::batch_target_name(target) << " lane " << l;
        double largest = 0;
        for(std::size_t i = 0; i < degree; ++i)
          for(std::size_t k = 0; k < 6; ++k)
            largest = (std::max)(largest, std::abs(records[a * rec + k] - records[neighbor[first + i] * rec + k]));
        const double unit = LD::internal::normalizing_power_of_two(largest);
        scaled += unit != 1.;
        for(std::size_t i = 0; i < d; ++i)
        {
          const bool on = i < degree;
          for(std::size_t c = 0; c < 3; ++c)
          {
            const std::size_t nb = on ? neighbor[first + i] * rec : 0;
            const double e = on ? (records[a * rec + 3 + c] - records[nb + 3 + c]) * unit : zero;
            const double f = on ? (records[a * rec + c] - records[nb + c]) * unit : zero;
            with_nan += std::isnan(e) || std::isnan(f);
            ASSERT_TRUE(same(rest[(3 * i + c) * B::lanes + std::size_t(l)], e))
                << B::batch_target_name(target) << " lane " << l << " spoke " << i << " rest " << c;
            ASSERT_TRUE(same(current[(3 * i + c) * B::lanes + std::size_t(l)], f))
                << B::batch_target_name(target) << " lane " << l << " spoke " << i << " current " << c;
          }
          const double wi = on ? (std::max)(weight[first + i], 0.) : zero;
          ASSERT_TRUE(same(w[i * B::lanes + std::size_t(l)], wi))
              << B::batch_target_name(target) << " lane " << l << " spoke " << i << " weight";
          ++checked;
        }
      }
    }
  }
  B::set_batch_target(saved);
  EXPECT_GT(checked, 10000u);
  EXPECT_GT(scaled, 100u) << "cells far from magnitude 1 must be covered";
  EXPECT_GT(with_nan, 10u) << "NaN coordinates must be covered";
}

TEST(BatchedTransforms, TargetCanBeForced)
{
  const B::Batch_target saved = B::batch_target();
  EXPECT_EQ(B::set_batch_target(B::Batch_target::per_cell), saved);
  EXPECT_EQ(B::batch_target(), B::Batch_target::per_cell);
  B::set_batch_target(B::Batch_target::avx512);   // lowered to what the processor has
  EXPECT_TRUE(B::batch_target_supported(B::batch_target()));
  B::set_batch_target(saved);
  EXPECT_EQ(B::batch_target(), saved);
}

} // namespace

// The local step's power-of-two normalisation, computed from the bits, is bitwise the C library's
// frexp/ldexp value for every class of input: zero, negative, NaN, infinity, subnormals, the
// extremes of the exponent range and random magnitudes over the whole range.
namespace {
// the normalisation through the C library, as the library computed it before
double reference_normalizing_power_of_two(double largest)
{
  if(!(largest > 0) || !std::isfinite(largest))
    return 1.;
  int exponent = 0;
  std::frexp(largest, &exponent);
  return std::ldexp(1., -(std::max)(exponent, -1000));
}
} // namespace

TEST(NormalizingPowerOfTwo, BitwiseTheLibraryValue)
{
  namespace LDI = CGAL::Laplacian_deformation::internal;
  typedef std::numeric_limits<double> L;
  std::vector<double> values = {0., -0., -1., -L::infinity(), L::infinity(), L::quiet_NaN(), L::denorm_min(),
                                2 * L::denorm_min(), L::min(), L::min() / 3, std::nextafter(L::min(), 0.), L::max(),
                                std::nextafter(L::max(), 0.), 0.5, 1., 2., 0.75, 1e-300, 1e300, std::ldexp(1., -1000),
                                std::ldexp(1., -1001), std::ldexp(1., 1023), std::ldexp(1.5, 1023)};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mantissa(1., 2.);
  std::uniform_int_distribution<int> exponent(-1074, 1023);
  for(int k = 0; k < 200000; ++k)
    values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  for(double x : values)
  {
    const double fast = LDI::normalizing_power_of_two(x), reference = reference_normalizing_power_of_two(x);
    ASSERT_EQ(std::memcmp(&fast, &reference, sizeof fast), 0) << x << ": " << fast << " against " << reference;
  }
}
