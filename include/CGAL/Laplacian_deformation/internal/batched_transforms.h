// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_BATCHED_TRANSFORMS_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_BATCHED_TRANSFORMS_H

// The batched (vectorised) local step of the package's transform policies: `lanes` cells at a
// time in structure-of-arrays form, the closest rotation (S^T S, cyclic Jacobi, sort,
// u3 = u1 x u2) and the scale fits computed lane-parallel with the operations of the scalar code
// (see batched_transforms_kernels.h), so that every result is the one of the policy's
// transform(cell). Lanes that the scalar code sends to the SVD (nearly collinear cells) or whose
// covariance is not finite are recomputed by transform(cell). The package's policies also take
// lanes that the caller has filled (transform_lanes(): the local step gathers and scales a node's
// spokes straight into them, see begin_lanes() and fit_lanes()).
//
// The kernels are compiled three times on x86 with GCC or Clang: for the compilation's own
// instruction set (SSE2 for a default x86-64 build), for AVX2 and for AVX-512 (function target
// attributes); the first call picks the best one the processor has (__builtin_cpu_supports), once
// per process. The environment variable CGAL_LAPLACIAN_DEFORMATION_SIMD (scalar, portable, avx2,
// avx512) read at that first call, or set_batch_target(), overrides the choice; `scalar` turns
// the batched path off (transform(cell) per cell). Defining
// CGAL_LAPLACIAN_DEFORMATION_NO_MULTIVERSIONING compiles only the portable kernels.

#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

#include <Eigen/Core>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && !defined(CGAL_LAPLACIAN_DEFORMATION_NO_MULTIVERSIONING)
#define CGAL_LAPDEF_MULTIVERSIONING 1
#else
#define CGAL_LAPDEF_MULTIVERSIONING 0
#endif

#if CGAL_LAPDEF_MULTIVERSIONING || (defined(__SSE2__) && defined(__GNUC__))
#include <immintrin.h>
#endif

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// A policy may compute the transforms of many cells at once:
// `void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const`.
template <class Policy, class = void>
struct Has_transform_block : std::false_type {};
template <class Policy>
struct Has_transform_block<Policy, std::void_t<decltype(std::declval<const Policy&>().transform_block(
                                       std::declval<const Transform_cell*>(), std::size_t(0),
                                       std::declval<Eigen::Matrix3d*>()))>> : std::true_type {};

// out[i] = policy.transform(cells[i]) for i < n, batched where the policy can
template <class Policy>
void transform_cells(const Policy& policy, const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out)
{
  if constexpr(Has_transform_block<Policy>::value)
    policy.transform_block(cells, n, out);
  else
    for(std::size_t i = 0; i < n; ++i)
      out[i] = policy.transform(cells[i]);
}

namespace batched {

/// The code that computes the batched transforms: `per_cell` is the scalar `transform(cell)` per
/// cell; `portable` the lane kernels compiled for the compilation's own instruction set (SSE2 on
/// a default x86-64 build); `avx2` and `avx512` the same kernels compiled for those (x86 with GCC
/// or Clang only).
enum class Batch_target : int { per_cell = 0, portable = 1, avx2 = 2, avx512 = 3 };

inline const char* batch_target_name(Batch_target t)
{
  switch(t)
  {
  case Batch_target::per_cell: return "scalar";
  case Batch_target::portable: return "portable";
  case Batch_target::avx2: return "avx2";
  case Batch_target::avx512: return "avx512";
  }
  return "?";
}

// whether `t` can run on this processor (and was compiled)
inline bool batch_target_supported(Batch_target t)
{
  switch(t)
  {
  case Batch_target::per_cell:
  case Batch_target::portable:
    return true;
#if CGAL_LAPDEF_MULTIVERSIONING
  case Batch_target::avx2:
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2");
  case Batch_target::avx512:
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl");
#else
  default:
    return false;
#endif
  }
  return false;
}

// the best supported target not above `t`
inline Batch_target supported_batch_target(Batch_target t)
{
  while(!batch_target_supported(t))
    t = Batch_target(int(t) - 1);
  return t;
}

inline std::atomic<int>& batch_target_state()
{
  static std::atomic<int> state(-1);
  return state;
}

// the target of this process: chosen at the first call (environment variable
// CGAL_LAPLACIAN_DEFORMATION_SIMD, else the best the processor has), then cached
inline Batch_target batch_target()
{
  int v = batch_target_state().load(std::memory_order_relaxed);
  if(v >= 0)
    return Batch_target(v);
  Batch_target t = Batch_target::avx512;
  if(const char* env = std::getenv("CGAL_LAPLACIAN_DEFORMATION_SIMD"))
  {
    if(!std::strcmp(env, "scalar") || !std::strcmp(env, "off") || !std::strcmp(env, "0"))
      t = Batch_target::per_cell;
    else if(!std::strcmp(env, "portable") || !std::strcmp(env, "sse2"))
      t = Batch_target::portable;
    else if(!std::strcmp(env, "avx2"))
      t = Batch_target::avx2;
  }
  t = supported_batch_target(t);
  batch_target_state().store(int(t), std::memory_order_relaxed);
  return t;
}

// forces the target (lowered to the best supported one not above it); returns the previous one
inline Batch_target set_batch_target(Batch_target t)
{
  const Batch_target previous = batch_target();
  batch_target_state().store(int(supported_batch_target(t)), std::memory_order_relaxed);
  return previous;
}

constexpr int lanes = 8;

// what a kernel call computes (each from s, the scaled covariance, and the cells' spokes)
enum class Stage
{
  covariance,                        // s = sum c e' e^T (not scaled)
  rotation,                          // t = closest_rotation(s)
  similarity,                        // t = s_iso r
  scaled_rotation,                   // t = diag(s_world) r
  anchored_scaled_rotation,          // t = diag(s_anchored) r
  principal_scaled_rotation,         // t = U diag(s) U^T r, U = r q
  scaled_rotation_then_covariance,   // t = diag(s_world) r, then s = sum c e' (t e)^T
  rotation_times_t                   // t = closest_rotation(s) t
};

// `lanes` cells in structure-of-arrays form; matrices by rows, m[3 * i + j][lane] = M(i, j)
struct Lanes
{
  alignas(64) double s[9][lanes];     // the input of the closest rotation, scaled into [1/2, 1)
  alignas(64) double r[9][lanes];     // the rotation
  alignas(64) double t[9][lanes];     // the transform
  alignas(64) double q[9][lanes];     // principal axes of the rest cell (columns)
  alignas(64) std::int64_t fallback[lanes];   // nonzero: the lane is computed by transform(cell)
  alignas(64) std::int64_t degree[lanes];
  std::size_t max_degree = 0;
  const double* rest = nullptr;       // rest[(3 * i + c) * lanes + lane]: coordinate c of spoke i
  const double* current = nullptr;
  const double* weight = nullptr;     // weight[i * lanes + lane]
  double anchor = 0;
};

// Where gather_lanes() reads the cells of the local step: node n's record of 8 doubles at
// node + 8 n (its current position, its rest position, two unused doubles), its neighbours
// neighbor[k] with weights weight[k] for k in [neighbor_start[n], neighbor_start[n + 1]).
struct Gather_input
{
  static constexpr std::size_t record = 8;   // doubles per node record
  const double* node = nullptr;
  const std::uint32_t* neighbor_start = nullptr;
  const std::uint32_t* neighbor = nullptr;
  const double* weight = nullptr;
};

#if defined(__clang__)
#define CGAL_LAPDEF_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define CGAL_LAPDEF_NO_CONTRACT
#endif
// std::max(a, b) without a call: under the kernels' optimisation pragma GCC does not inline
// std::max<double> into the target functions (a call per spoke, 5% of an iteration)
#define CGAL_LAPDEF_MAX(a, b) ((a) < (b) ? (b) : (a))
#if defined(__GNUC__)
#define CGAL_LAPDEF_FABS(x) __builtin_fabs(x)
#else
#define CGAL_LAPDEF_FABS(x) std::fabs(x)
#endif
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off", "no-trapping-math")   // no FMA; selects may evaluate both sides
#endif

#define CGAL_LAPDEF_KERNEL_NS portable
#define CGAL_LAPDEF_KERNEL_ATTR
#if defined(__SSE2__) && defined(__GNUC__)
#define CGAL_LAPDEF_KERNEL_ISA 1
#else
#define CGAL_LAPDEF_KERNEL_ISA 0
#endif
#include <CGAL/Laplacian_deformation/internal/batched_transforms_kernels.h>
#undef CGAL_LAPDEF_KERNEL_NS
#undef CGAL_LAPDEF_KERNEL_ATTR
#undef CGAL_LAPDEF_KERNEL_ISA

#if CGAL_LAPDEF_MULTIVERSIONING
#define CGAL_LAPDEF_KERNEL_NS avx2
#define CGAL_LAPDEF_KERNEL_ATTR __attribute__((target("avx2")))
#define CGAL_LAPDEF_KERNEL_ISA 2
#include <CGAL/Laplacian_deformation/internal/batched_transforms_kernels.h>
#undef CGAL_LAPDEF_KERNEL_NS
#undef CGAL_LAPDEF_KERNEL_ATTR
#undef CGAL_LAPDEF_KERNEL_ISA

#define CGAL_LAPDEF_KERNEL_NS avx512
#define CGAL_LAPDEF_KERNEL_ATTR __attribute__((target("avx2,avx512f,avx512dq,avx512vl")))
#define CGAL_LAPDEF_KERNEL_ISA 3
#include <CGAL/Laplacian_deformation/internal/batched_transforms_kernels.h>
#undef CGAL_LAPDEF_KERNEL_NS
#undef CGAL_LAPDEF_KERNEL_ATTR
#undef CGAL_LAPDEF_KERNEL_ISA
#endif

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif
#undef CGAL_LAPDEF_NO_CONTRACT
#undef CGAL_LAPDEF_FABS
#undef CGAL_LAPDEF_MAX

inline void run_stage(Batch_target target, Stage stage, Lanes& b)
{
#if CGAL_LAPDEF_MULTIVERSIONING
  if(target == Batch_target::avx512)
    return avx512::run_stage(stage, b);
  if(target == Batch_target::avx2)
    return avx2::run_stage(stage, b);
#endif
  (void)target;
  portable::run_stage(stage, b);
}

// lane `l` of b.s = s_in scaled as closest_rotation() scales it, or a fallback lane
inline void set_rotation_input(Lanes& b, int l, const Eigen::Matrix3d& s_in)
{
  const double largest = s_in.cwiseAbs().maxCoeff();
  if(!std::isfinite(largest))
  {
    b.fallback[l] = 1;
    for(int k = 0; k < 9; ++k)
      b.s[k][l] = 0.;
    return;
  }
  const Eigen::Matrix3d s = normalizing_power_of_two(largest) * s_in;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      b.s[3 * i + j][l] = s(i, j);
}

struct No_axes
{
  Eigen::Matrix3d operator()(const Transform_cell&) const { return Eigen::Matrix3d::Identity(); }
};

// Prepares `b` for m <= lanes cells whose spokes (at most d each) go into `spokes` (7 d lanes
// doubles): no lane is a fallback yet, the lanes from m on are empty (no spoke, zero matrices).
// The caller then writes, for every lane l < m, b.degree[l] and the spokes i < d (zeros from the
// lane's degree on): rest[(3 i + c) lanes + l], current[...], weight[i lanes + l].
inline void begin_lanes(Lanes& b, int m, std::size_t d, double* spokes)
{
  b.rest = spokes;
  b.current = spokes + 3 * d * lanes;
  b.weight = spokes + 6 * d * lanes;
  b.max_degree = d;
  for(int l = 0; l < lanes; ++l)
  {
    b.fallback[l] = 0;
    if(l < m)
      continue;
    b.degree[l] = 0;
    for(int k = 0; k < 9; ++k)
      b.s[k][l] = b.q[k][l] = 0.;
    for(std::size_t i = 0; i < 7 * d; ++i)
      spokes[i * lanes + std::size_t(l)] = 0.;
  }
}

// Gathers the cells of the nodes node[0], ..., node[m - 1] (m <= lanes) read from `in` into `b`:
// begin_lanes() with the largest of their degrees d, then the kernels' gather_lanes() (the
// spokes scaled as Deformation_core::gather_cell() scales them). `spokes` holds at least
// 7 d lanes doubles, `scratch` at least 8 d lanes. `target` is not per_cell.
inline void gather_lanes(Batch_target target, const Gather_input& in, const std::size_t* node, int m, Lanes& b,
                         double* spokes, double* scratch)
{
  std::size_t d = 0;
  for(int l = 0; l < m; ++l)
    d = (std::max)(d, std::size_t(in.neighbor_start[node[l] + 1] - in.neighbor_start[node[l]]));
  begin_lanes(b, m, d, spokes);
#if CGAL_LAPDEF_MULTIVERSIONING
  if(target == Batch_target::avx512)
    return avx512::gather_lanes(in, node, m, b, spokes, scratch);
  if(target == Batch_target::avx2)
    return avx2::gather_lanes(in, node, m, b, spokes, scratch);
#endif
  (void)target;
  portable::gather_lanes(in, node, m, b, spokes, scratch);
}

// The cell of lane `l` of `b`, rebuilt from its spokes (the same numbers as the cell the lane was
// filled from); the view is valid until the next call.
class Lane_cells
{
public:
  explicit Lane_cells(const Lanes& b) : m_b(b) {}
  Transform_cell operator()(int l) const
  {
    const std::size_t d = std::size_t(m_b.degree[l]);
    m_rest.resize(d);
    m_current.resize(d);
    m_weight.resize(d);
    for(std::size_t i = 0; i < d; ++i)
    {
      for(int c = 0; c < 3; ++c)
      {
        m_rest[i][c] = m_b.rest[(3 * i + std::size_t(c)) * lanes + std::size_t(l)];
        m_current[i][c] = m_b.current[(3 * i + std::size_t(c)) * lanes + std::size_t(l)];
      }
      m_weight[i] = m_b.weight[i * lanes + std::size_t(l)];
    }
    return Transform_cell(m_rest.data(), m_current.data(), m_weight.data(), d);
  }

private:
  const Lanes& m_b;
  mutable std::vector<Eigen::Vector3d> m_rest, m_current;
  mutable std::vector<double> m_weight;
};

// What follows the gather of m <= lanes cells into `b` (begin_lanes()): their covariances, the fits
// of `stage`, and out[l] = policy.transform(cell l) for l < m, batched; `cell_at(l)` gives the
// cell of lane l for the lanes that the scalar code computes (and for the axes of
// Stage::principal_scaled_rotation, given by `axes(cell)`). `target` is not per_cell.
template <Stage stage, class Policy, class CellAt, class Axes = No_axes>
void fit_lanes(Batch_target target, const Policy& policy, Lanes& b, int m, const CellAt& cell_at,
               Eigen::Matrix3d* out, const Axes& axes = Axes())
{
  if constexpr(stage == Stage::anchored_scaled_rotation)
    b.anchor = Policy::anchor;
  // the covariances (as Transform_cell::covariance() computes them), scaled as closest_rotation() does
  run_stage(target, Stage::covariance, b);
  for(int l = 0; l < m; ++l)
  {
    Eigen::Matrix3d s;
    for(int i = 0; i < 3; ++i)
      for(int j = 0; j < 3; ++j)
        s(i, j) = b.s[3 * i + j][l];
    set_rotation_input(b, l, s);
    if constexpr(stage == Stage::principal_scaled_rotation)
    {
      if(!b.fallback[l])
      {
        const Eigen::Matrix3d q = axes(cell_at(l));
        for(int i = 0; i < 3; ++i)
          for(int j = 0; j < 3; ++j)
            b.q[3 * i + j][l] = q(i, j);
      }
    }
  }
  run_stage(target, stage, b);
  if constexpr(stage == Stage::scaled_rotation_then_covariance)
  {
    // R2 = closest_rotation(sum c e' (S R1 e)^T), then t = R2 S R1
    for(int l = 0; l < lanes; ++l)
    {
      if(b.fallback[l] || l >= m)
      {
        for(int k = 0; k < 9; ++k)
          b.s[k][l] = 0.;
        continue;
      }
      Eigen::Matrix3d s2;
      for(int i = 0; i < 3; ++i)
        for(int j = 0; j < 3; ++j)
          s2(i, j) = b.s[3 * i + j][l];
      set_rotation_input(b, l, s2);
    }
    run_stage(target, Stage::rotation_times_t, b);
  }
  for(int l = 0; l < m; ++l)
  {
    Eigen::Matrix3d& o = out[l];
    if(b.fallback[l])
      o = policy.transform(cell_at(l));
    else
      for(int i = 0; i < 3; ++i)
        for(int j = 0; j < 3; ++j)
          o(i, j) = b.t[3 * i + j][l];
  }
}

// out[i] = policy.transform(cells[i]), i < n, through the kernels of `stage`; `axes(cell)` gives
// the principal rest axes for Stage::principal_scaled_rotation
template <Stage stage, class Policy, class Axes = No_axes>
void transform_cells(const Policy& policy, const Transform_cell* cells, std::size_t n,
                     Eigen::Matrix3d* out, const Axes& axes = Axes())
{
  const Batch_target target = batch_target();
  if(target == Batch_target::per_cell)
  {
    for(std::size_t i = 0; i < n; ++i)
      out[i] = policy.transform(cells[i]);
    return;
  }
  Lanes b;
  static thread_local std::vector<double> spokes;   // the lanes' spokes, reused
  for(std::size_t first = 0; first < n; first += lanes)
  {
    const int m = int((std::min)(std::size_t(lanes), n - first));
    std::size_t d = 0;
    for(int l = 0; l < m; ++l)
      d = (std::max)(d, cells[first + std::size_t(l)].size());
    if(spokes.size() < 7 * d * lanes)
      spokes.resize(7 * d * lanes);
    begin_lanes(b, m, d, spokes.data());
    double *rest = spokes.data(), *current = rest + 3 * d * lanes, *weight = current + 3 * d * lanes;
    for(int l = 0; l < m; ++l)
    {
      const Transform_cell& cell = cells[first + std::size_t(l)];
      b.degree[l] = std::int64_t(cell.size());
      for(std::size_t i = 0; i < d; ++i)   // spokes past the cell's degree: zeros (masked)
      {
        const bool on = i < cell.size();
        for(int c = 0; c < 3; ++c)
        {
          rest[(3 * i + std::size_t(c)) * lanes + std::size_t(l)] = on ? cell.rest(i)[c] : 0.;
          current[(3 * i + std::size_t(c)) * lanes + std::size_t(l)] = on ? cell.current(i)[c] : 0.;
        }
        weight[i * lanes + std::size_t(l)] = on ? cell.weight(i) : 0.;
      }
    }
    fit_lanes<stage>(target, policy, b, m, [&](int l) -> const Transform_cell& { return cells[first + std::size_t(l)]; },
                     out + first, axes);
  }
}

// A policy whose fits run on lanes gathered by the caller (the local step gathers a node's
// spokes straight into them):
// `void transform_lanes(batched::Lanes& b, int m, Eigen::Matrix3d* out) const`, called after
// begin_lanes() and the gather, with a target that is not per_cell.
template <class Policy, class = void>
struct Has_transform_lanes : std::false_type {};
template <class Policy>
struct Has_transform_lanes<Policy, std::void_t<decltype(std::declval<const Policy&>().transform_lanes(
                                       std::declval<Lanes&>(), 0, std::declval<Eigen::Matrix3d*>()))>> : std::true_type {};

} // namespace batched
} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_BATCHED_TRANSFORMS_H
