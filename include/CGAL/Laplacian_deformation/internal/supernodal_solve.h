// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_SUPERNODAL_SOLVE_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_SUPERNODAL_SOLVE_H

// The forward and backward substitutions of a supernodal Cholesky factor L (CHOLMOD's layout:
// supernode s holds the columns super[s] .. super[s+1]-1 as one dense column-major block of
// pi[s+1]-pi[s] rows, its row indices at s[pi[s]..], its values at x[px[s]..]) for three
// right-hand sides at once, kept interleaved (row i of the solution is y[3i], y[3i+1], y[3i+2]):
// every value of L is read once per substitution, and a row update touches one cache line.
//
// The supernodes are in a topological order of the supernodal elimination tree (children before
// parents), and in CHOLMOD's postordered factors every subtree is a contiguous range of them. The
// schedule cuts the tree into disjoint subtrees of about equal work, handed out to a fixed number of
// bins; the bins run on TBB's threads. The supernodes above them are cut again the same way, level
// after level (a nested-dissection factor holds about the same share of its values on every level
// of separators, so one level of subtrees would leave a large top to one thread), until what
// remains (the top) is too small to pay for another barrier; the top runs alone. In the forward
// substitution a bin writes the updates its subtrees send to later levels into a buffer of its
// own, summed in bin order after its level (the result does not depend on the threads' timing); in
// the backward substitution the top is done first, then the levels in reverse order, and each
// subtree reads only its ancestors.

#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/parallel.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/parallel_for.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// a read-only view of a supernodal LL^T factor with 32-bit indices
struct Supernodal_factor_view
{
  int n = 0, nsuper = 0;
  const int* super = nullptr;   // nsuper + 1 first columns
  const int* pi = nullptr;      // nsuper + 1 offsets into rows
  const int* px = nullptr;      // nsuper + 1 offsets into values
  const int* rows = nullptr;    // row indices: the nc columns of a supernode, then the rows below
  const double* values = nullptr;
};

// The column kernels of the substitutions: z_k[i] -= c[i] a_k (the forward substitution's update
// by one column of L) and s_k = sum_i c[i] z_k[i] (the backward substitution's dot product with one
// column), for the three right-hand sides k = 0, 1, 2 kept as three arrays; and the same for two
// adjacent columns c, d of a supernode at once (update2: z_k[i] -= c[i] a_k, then -= d[i] a_{3+k};
// dot2: the six dot products), which a supernode's sweep uses for its pairs of columns: every z_k[i]
// is then loaded and stored once per pair instead of once per column (the one-column update is
// bound by its three stores per row), and the six sums of dot2 are twelve independent chains (the
// one-column dot product's six chains wait on the FMA's latency). `portable` is compiled for the
// build's instruction set (its update2 subtracts in the order of two update() calls, its dot2 is two
// dot() calls); `avx2` (AVX2 and FMA, chosen at run time on x86 with GCC or Clang) does four rows per
// instruction; its scalar tails (the rows past the last multiple of four or eight) are explicit
// fused multiply-adds like its vector part. Each fixes its order of summation and its roundings, so
// a solve is reproducible for a given kernel at any optimisation level; the two differ by
// round-off. (The tails were plain a * b + c before: GCC contracts such expressions into FMAs in a
// function compiled for FMA where it finds them, which depended on the inlining, so a program built
// at -O2 and one built at -O3 differed in the last bits: 465 of the cactus task's 465 moved
// vertices, by the tests that compare the laplacian_deform tool with the library.)
namespace supernodal_kernels {

inline void update_portable(const double* c, int len, const double* a, double* z0, double* z1, double* z2)
{
  const double a0 = a[0], a1 = a[1], a2 = a[2];
  for(int i = 0; i < len; ++i)
  {
    z0[i] -= c[i] * a0;
    z1[i] -= c[i] * a1;
    z2[i] -= c[i] * a2;
  }
}

// four partial sums per right-hand side: a fixed order, vectorisable without reassociation
inline void dot_portable(const double* c, int len, const double* z0, const double* z1, const double* z2, double* s)
{
  double p0[4] = {0, 0, 0, 0}, p1[4] = {0, 0, 0, 0}, p2[4] = {0, 0, 0, 0};
  int i = 0;
  for(; i + 3 < len; i += 4)
    for(int q = 0; q < 4; ++q)
    {
      p0[q] += c[i + q] * z0[i + q];
      p1[q] += c[i + q] * z1[i + q];
      p2[q] += c[i + q] * z2[i + q];
    }
  for(; i < len; ++i)
  {
    p0[0] += c[i] * z0[i];
    p1[0] += c[i] * z1[i];
    p2[0] += c[i] * z2[i];
  }
  s[0] = (p0[0] + p0[1]) + (p0[2] + p0[3]);
  s[1] = (p1[0] + p1[1]) + (p1[2] + p1[3]);
  s[2] = (p2[0] + p2[1]) + (p2[2] + p2[3]);
}

inline void update2_portable(const double* c, const double* d, int len, const double*, const double*, const double* a,
                             double* z0, double* z1, double* z2)
{
  for(int i = 0; i < len; ++i)
  {
    z0[i] = (z0[i] - c[i] * a[0]) - d[i] * a[3];
    z1[i] = (z1[i] - c[i] * a[1]) - d[i] * a[4];
    z2[i] = (z2[i] - c[i] * a[2]) - d[i] * a[5];
  }
}

inline void dot2_portable(const double* c, const double* d, int len, const double*, const double*, const double* z0,
                          const double* z1, const double* z2, double* s)
{
  dot_portable(c, len, z0, z1, z2, s);
  dot_portable(d, len, z0, z1, z2, s + 3);
}

#if CGAL_LAPDEF_MULTIVERSIONING
__attribute__((target("avx2,fma"))) inline double sum_avx2(__m256d v)
{
  const __m128d s = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
}

__attribute__((target("avx2,fma"))) inline void update_avx2(const double* c, int len, const double* a, double* z0,
                                                            double* z1, double* z2)
{
  const __m256d a0 = _mm256_set1_pd(a[0]), a1 = _mm256_set1_pd(a[1]), a2 = _mm256_set1_pd(a[2]);
  int i = 0;
  for(; i + 3 < len; i += 4)
  {
    const __m256d u = _mm256_loadu_pd(c + i);
    _mm256_storeu_pd(z0 + i, _mm256_fnmadd_pd(u, a0, _mm256_loadu_pd(z0 + i)));
    _mm256_storeu_pd(z1 + i, _mm256_fnmadd_pd(u, a1, _mm256_loadu_pd(z1 + i)));
    _mm256_storeu_pd(z2 + i, _mm256_fnmadd_pd(u, a2, _mm256_loadu_pd(z2 + i)));
  }
  for(; i < len; ++i)
  {
    z0[i] = std::fma(-c[i], a[0], z0[i]);
    z1[i] = std::fma(-c[i], a[1], z1[i]);
    z2[i] = std::fma(-c[i], a[2], z2[i]);
  }
}

// eight rows per step in two sets of accumulators (six independent chains)
__attribute__((target("avx2,fma"))) inline void dot_avx2(const double* c, int len, const double* z0,
                                                         const double* z1, const double* z2, double* s)
{
  __m256d s0 = _mm256_setzero_pd(), s1 = s0, s2 = s0, t0 = s0, t1 = s0, t2 = s0;
  int i = 0;
  for(; i + 7 < len; i += 8)
  {
    const __m256d u = _mm256_loadu_pd(c + i), v = _mm256_loadu_pd(c + i + 4);
    s0 = _mm256_fmadd_pd(u, _mm256_loadu_pd(z0 + i), s0);
    s1 = _mm256_fmadd_pd(u, _mm256_loadu_pd(z1 + i), s1);
    s2 = _mm256_fmadd_pd(u, _mm256_loadu_pd(z2 + i), s2);
    t0 = _mm256_fmadd_pd(v, _mm256_loadu_pd(z0 + i + 4), t0);
    t1 = _mm256_fmadd_pd(v, _mm256_loadu_pd(z1 + i + 4), t1);
    t2 = _mm256_fmadd_pd(v, _mm256_loadu_pd(z2 + i + 4), t2);
  }
  if(i + 3 < len)
  {
    const __m256d u = _mm256_loadu_pd(c + i);
    s0 = _mm256_fmadd_pd(u, _mm256_loadu_pd(z0 + i), s0);
    s1 = _mm256_fmadd_pd(u, _mm256_loadu_pd(z1 + i), s1);
    s2 = _mm256_fmadd_pd(u, _mm256_loadu_pd(z2 + i), s2);
    i += 4;
  }
  double r0 = sum_avx2(_mm256_add_pd(s0, t0)), r1 = sum_avx2(_mm256_add_pd(s1, t1)),
         r2 = sum_avx2(_mm256_add_pd(s2, t2));
  for(; i < len; ++i)
  {
    r0 = std::fma(c[i], z0[i], r0);
    r1 = std::fma(c[i], z1[i], r1);
    r2 = std::fma(c[i], z2[i], r2);
  }
  s[0] = r0;
  s[1] = r1;
  s[2] = r2;
}
__attribute__((target("avx2,fma"))) inline void update2_avx2(const double* c, const double* d, int len,
                                                             const double* ahead0, const double* ahead1,
                                                             const double* a, double* z0, double* z1, double* z2)
{
  const __m256d a0 = _mm256_set1_pd(a[0]), a1 = _mm256_set1_pd(a[1]), a2 = _mm256_set1_pd(a[2]),
                b0 = _mm256_set1_pd(a[3]), b1 = _mm256_set1_pd(a[4]), b2 = _mm256_set1_pd(a[5]);
  int i = 0;
  for(; i + 3 < len; i += 4)
  {
    if((i & 7) == 0)
    {
      _mm_prefetch(reinterpret_cast<const char*>(ahead0 + i), _MM_HINT_T0);
      _mm_prefetch(reinterpret_cast<const char*>(ahead1 + i), _MM_HINT_T0);
    }
    const __m256d u = _mm256_loadu_pd(c + i), v = _mm256_loadu_pd(d + i);
    _mm256_storeu_pd(z0 + i, _mm256_fnmadd_pd(v, b0, _mm256_fnmadd_pd(u, a0, _mm256_loadu_pd(z0 + i))));
    _mm256_storeu_pd(z1 + i, _mm256_fnmadd_pd(v, b1, _mm256_fnmadd_pd(u, a1, _mm256_loadu_pd(z1 + i))));
    _mm256_storeu_pd(z2 + i, _mm256_fnmadd_pd(v, b2, _mm256_fnmadd_pd(u, a2, _mm256_loadu_pd(z2 + i))));
  }
  for(; i < len; ++i)
  {
    z0[i] = std::fma(-d[i], a[3], std::fma(-c[i], a[0], z0[i]));
    z1[i] = std::fma(-d[i], a[4], std::fma(-c[i], a[1], z1[i]));
    z2[i] = std::fma(-d[i], a[5], std::fma(-c[i], a[2], z2[i]));
  }
}

// eight rows per step: two sets of six accumulators (twelve independent chains)
__attribute__((target("avx2,fma"))) inline void dot2_avx2(const double* c, const double* d, int len,
                                                          const double* ahead0, const double* ahead1,
                                                          const double* z0, const double* z1, const double* z2,
                                                          double* s)
{
  __m256d p0 = _mm256_setzero_pd(), p1 = p0, p2 = p0, q0 = p0, q1 = p0, q2 = p0;   // c, d: rows i..i+3
  __m256d r0 = p0, r1 = p0, r2 = p0, t0 = p0, t1 = p0, t2 = p0;                    // c, d: rows i+4..i+7
  int i = 0;
  for(; i + 7 < len; i += 8)
  {
    _mm_prefetch(reinterpret_cast<const char*>(ahead0 + i), _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(ahead1 + i), _MM_HINT_T0);
    __m256d u = _mm256_loadu_pd(c + i), v = _mm256_loadu_pd(d + i), w = _mm256_loadu_pd(z0 + i);
    p0 = _mm256_fmadd_pd(u, w, p0);
    q0 = _mm256_fmadd_pd(v, w, q0);
    w = _mm256_loadu_pd(z1 + i);
    p1 = _mm256_fmadd_pd(u, w, p1);
    q1 = _mm256_fmadd_pd(v, w, q1);
    w = _mm256_loadu_pd(z2 + i);
    p2 = _mm256_fmadd_pd(u, w, p2);
    q2 = _mm256_fmadd_pd(v, w, q2);
    u = _mm256_loadu_pd(c + i + 4);
    v = _mm256_loadu_pd(d + i + 4);
    w = _mm256_loadu_pd(z0 + i + 4);
    r0 = _mm256_fmadd_pd(u, w, r0);
    t0 = _mm256_fmadd_pd(v, w, t0);
    w = _mm256_loadu_pd(z1 + i + 4);
    r1 = _mm256_fmadd_pd(u, w, r1);
    t1 = _mm256_fmadd_pd(v, w, t1);
    w = _mm256_loadu_pd(z2 + i + 4);
    r2 = _mm256_fmadd_pd(u, w, r2);
    t2 = _mm256_fmadd_pd(v, w, t2);
  }
  if(i + 3 < len)
  {
    const __m256d u = _mm256_loadu_pd(c + i), v = _mm256_loadu_pd(d + i);
    __m256d w = _mm256_loadu_pd(z0 + i);
    p0 = _mm256_fmadd_pd(u, w, p0);
    q0 = _mm256_fmadd_pd(v, w, q0);
    w = _mm256_loadu_pd(z1 + i);
    p1 = _mm256_fmadd_pd(u, w, p1);
    q1 = _mm256_fmadd_pd(v, w, q1);
    w = _mm256_loadu_pd(z2 + i);
    p2 = _mm256_fmadd_pd(u, w, p2);
    q2 = _mm256_fmadd_pd(v, w, q2);
    i += 4;
  }
  double e[6] = {sum_avx2(_mm256_add_pd(p0, r0)), sum_avx2(_mm256_add_pd(p1, r1)), sum_avx2(_mm256_add_pd(p2, r2)),
                 sum_avx2(_mm256_add_pd(q0, t0)), sum_avx2(_mm256_add_pd(q1, t1)), sum_avx2(_mm256_add_pd(q2, t2))};
  for(; i < len; ++i)
  {
    e[0] = std::fma(c[i], z0[i], e[0]);
    e[1] = std::fma(c[i], z1[i], e[1]);
    e[2] = std::fma(c[i], z2[i], e[2]);
    e[3] = std::fma(d[i], z0[i], e[3]);
    e[4] = std::fma(d[i], z1[i], e[4]);
    e[5] = std::fma(d[i], z2[i], e[5]);
  }
  for(int k = 0; k < 6; ++k)
    s[k] = e[k];
}
#endif

struct Kernels
{
  void (*update)(const double*, int, const double*, double*, double*, double*) = &update_portable;
  void (*dot)(const double*, int, const double*, const double*, const double*, double*) = &dot_portable;
  void (*update2)(const double*, const double*, int, const double*, const double*, const double*, double*, double*,
                  double*) = &update2_portable;
  void (*dot2)(const double*, const double*, int, const double*, const double*, const double*, const double*,
               const double*, double*) = &dot2_portable;
  const char* name = "portable";
};

// the kernels of this process: AVX2 + FMA where the processor has them, unless the SIMD target of
// the batched transforms (CGAL_LAPLACIAN_DEFORMATION_SIMD, set_batch_target()) is below AVX2
inline Kernels kernels()
{
  Kernels k;
#if CGAL_LAPDEF_MULTIVERSIONING
  if(int(batched::batch_target()) >= int(batched::Batch_target::avx2) && __builtin_cpu_supports("avx2") &&
     __builtin_cpu_supports("fma"))
  {
    k.update = &update_avx2;
    k.dot = &dot_avx2;
    k.update2 = &update2_avx2;
    k.dot2 = &dot2_avx2;
    k.name = "avx2";
  }
#endif
  return k;
}

} // namespace supernodal_kernels

class Supernodal_schedule
{
public:
  // builds the schedule of `l` for up to `bins` bins; a factor whose supernodes are not postordered
  // (every subtree contiguous) gets a sequential schedule
  void build(const Supernodal_factor_view& l, int bins)
  {
    m_levels.clear();
    m_top.clear();
    m_top_split.clear();
    m_n = l.n;
    m_nsuper = l.nsuper;
    const int ns = l.nsuper;
    const std::size_t nn = std::size_t(l.n), nsn = std::size_t(l.nsuper);
    std::vector<int> column_super(nn);
    for(int s = 0; s < ns; ++s)
      for(int c = l.super[s]; c < l.super[s + 1]; ++c)
        column_super[std::size_t(c)] = s;
    std::vector<int> parent(nsn, -1), first(nsn), size(nsn, 1);
    std::vector<double> own(nsn);    // the work of a supernode: values read, and a fixed cost
    double total = 0;
    bool postordered = true;
    for(int s = 0; s < ns; ++s)
    {
      const int nc = l.super[s + 1] - l.super[s], nr = l.pi[s + 1] - l.pi[s];
      own[std::size_t(s)] = double(nr) * double(nc) + 8.;
      total += own[std::size_t(s)];
      first[std::size_t(s)] = s;
      int lowest = l.n;
      for(int k = l.pi[s] + nc; k < l.pi[s + 1]; ++k)
        lowest = (std::min)(lowest, l.rows[k]);
      if(lowest < l.n)
      {
        const int p = column_super[std::size_t(lowest)];
        postordered = postordered && p > s;
        parent[std::size_t(s)] = p;
      }
    }
    for(int s = 0; postordered && s < ns; ++s)   // children before parents: the subtree of s is [first, s]
    {
      const int p = parent[std::size_t(s)];
      postordered = first[std::size_t(s)] == s + 1 - size[std::size_t(s)];
      if(p >= 0)
      {
        first[std::size_t(p)] = (std::min)(first[std::size_t(p)], first[std::size_t(s)]);
        size[std::size_t(p)] += size[std::size_t(s)];
      }
    }
    m_sequential_share = 1.;
    std::vector<char> remaining(nsn, 1);   // not yet in a level
    if(postordered && bins >= 2 && ns >= 2)
    {
      std::vector<std::vector<int>> children(nsn);
      for(int s = 0; s < ns; ++s)
        if(parent[std::size_t(s)] >= 0)
          children[std::size_t(parent[std::size_t(s)])].push_back(s);
      double left = total;
      std::vector<double> work(nsn);
      // Level after level: the remaining tree is cut into subtrees, the heaviest split until
      // none holds more than left / (4 bins) (left / (2 bins) above the first level, where the
      // subtrees are few and large), then packed into the bins. A level ends with a barrier; the
      // supernodes above its subtrees are left to the next level, until too few remain.
      for(int level = 0; level < 8; ++level)
      {
        for(int s = 0; s < ns; ++s)   // subtree work within the remaining tree, children first
          if(remaining[std::size_t(s)])
          {
            work[std::size_t(s)] = own[std::size_t(s)];
            for(int c : children[std::size_t(s)])
              if(remaining[std::size_t(c)])
                work[std::size_t(s)] += work[std::size_t(c)];
          }
        std::priority_queue<std::pair<double, int>> heap;
        for(int s = 0; s < ns; ++s)
          if(remaining[std::size_t(s)] && parent[std::size_t(s)] < 0)
            heap.push({work[std::size_t(s)], s});
        const double limit = left / ((level == 0 ? 4. : 1.) * bins);
        while(!heap.empty() && heap.top().first > limit)
        {
          const int s = heap.top().second;
          heap.pop();
          for(int c : children[std::size_t(s)])
            if(remaining[std::size_t(c)])
              heap.push({work[std::size_t(c)], c});
        }
        std::vector<std::pair<double, int>> subtrees;
        double taken = 0;
        while(!heap.empty())
        {
          subtrees.push_back(heap.top());
          taken += heap.top().first;
          heap.pop();
        }
        if(subtrees.size() < 2 || taken < 0.005 * total)
          break;                                     // nothing left worth a barrier
        std::sort(subtrees.begin(), subtrees.end(),  // heaviest first, each to the lightest bin
                  [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
                    return a.first > b.first || (a.first == b.first && a.second < b.second);
                  });
        Level lv;
        lv.bins.assign(std::size_t(bins), Bin());
        std::vector<double> load(std::size_t(bins), 0.);
        auto roots = std::vector<std::vector<int>>(std::size_t(bins));
        for(const auto& t : subtrees)
        {
          const std::size_t b = std::size_t(std::min_element(load.begin(), load.end()) - load.begin());
          load[b] += t.first;
          roots[b].push_back(t.second);
        }
        for(std::size_t b = 0; b < roots.size(); ++b)
        {
          std::sort(roots[b].begin(), roots[b].end());
          Bin& bin = lv.bins[b];
          for(int t : roots[b])
          {
            bin.start.push_back(int(bin.supernodes.size()));
            for(int s = first[std::size_t(t)]; s <= t; ++s)   // the remaining ones, increasing
              if(remaining[std::size_t(s)])
              {
                bin.supernodes.push_back(s);
                remaining[std::size_t(s)] = 0;
                bin.max_rows = (std::max)(bin.max_rows, std::size_t(l.pi[s + 1] - l.pi[s]));
              }
            bin.column_end.push_back(l.super[t + 1]);
          }
          bin.start.push_back(int(bin.supernodes.size()));
        }
        lv.bins.erase(std::remove_if(lv.bins.begin(), lv.bins.end(),
                                     [](const Bin& b) { return b.supernodes.empty(); }),
                      lv.bins.end());
        // the columns still to come, each with its index in the bins' buffers
        lv.later_index.assign(nn, -1);
        for(int s = 0; s < ns; ++s)
          if(remaining[std::size_t(s)])
            for(int c = l.super[s]; c < l.super[s + 1]; ++c)
            {
              lv.later_index[std::size_t(c)] = int(lv.later_columns.size());
              lv.later_columns.push_back(c);
            }
        m_levels.push_back(std::move(lv));
        left -= taken;
      }
    }
    double top_work = 0;
    m_chunks = m_levels.empty() ? 1 : (std::max)(2, bins / 2);
    for(int s = 0; s < ns; ++s)
      if(remaining[std::size_t(s)])
      {
        const int nc = l.super[s + 1] - l.super[s], nr = l.pi[s + 1] - l.pi[s];
        const bool split = m_chunks > 1 && double(nr) * double(nc) >= split_values;
        m_top.push_back(s);
        m_top_split.push_back(split ? 1 : 0);
        if(!split)
          top_work += double(nr) * double(nc);
        else   // only the panels' diagonal triangles are left to one thread
          for(int p = 0; p < nc; p += panel_columns)
          {
            const double w = double((std::min)(p + panel_columns, nc) - p);
            top_work += w * (w + 1.) / 2.;
          }
      }
    m_split_supernodes = std::size_t(std::count(m_top_split.begin(), m_top_split.end(), char(1)));
    m_sequential_share = m_levels.empty() ? 1. : (total > 0 ? top_work / total : 1.);
  }

  bool matches(const Supernodal_factor_view& l) const { return m_n == l.n && m_nsuper == l.nsuper; }
  // the largest number of bins of a level (1: sequential)
  std::size_t number_of_bins() const
  {
    std::size_t b = 1;
    for(const Level& lv : m_levels)
      b = (std::max)(b, lv.bins.size());
    return b;
  }
  // the number of levels that run in parallel (each ends with a barrier)
  std::size_t number_of_levels() const { return m_levels.size(); }
  // the share of the factor's values substituted by one thread: the top's supernodes, but for the
  // diagonal triangles of the panels of its split ones
  double sequential_share() const { return m_sequential_share; }
  // the number of the top's supernodes whose substitutions are split between the threads
  std::size_t number_of_split_supernodes() const { return m_split_supernodes; }

  // L Y = Y (forward) then L^T Y = Y (backward), Y interleaved (3 doubles per row)
  void solve(const Supernodal_factor_view& l, double* y, bool parallel) const
  {
    m_kernels = supernodal_kernels::kernels();
    forward(l, y, parallel);
    backward(l, y, parallel);
  }

private:
  struct Bin
  {
    std::vector<int> supernodes;   // subtree after subtree, each increasing
    std::vector<int> start;        // per subtree: its first position in supernodes (and the end)
    std::vector<int> column_end;   // per subtree: one past the column of its root
    std::size_t max_rows = 0;
  };
  struct Level
  {
    std::vector<Bin> bins;
    std::vector<int> later_index;     // per column: its index among the later levels' columns, or -1
    std::vector<int> later_columns;   // those columns, increasing
  };
  struct Workspace
  {
    std::vector<double> w, later;
  };

  // f(b) for the bins of a level, in parallel (or in order)
  template <class F>
  void for_each_bin(const Level& lv, bool parallel, const F& f) const
  {
#ifdef CGAL_LINKED_WITH_TBB
    if(parallel && lv.bins.size() > 1)
    {
      tbb::parallel_for(std::size_t(0), lv.bins.size(), [&](std::size_t b) { f(b); }, tbb::simple_partitioner());
      return;
    }
#else
    (void)parallel;
#endif
    for(std::size_t b = 0; b < lv.bins.size(); ++b)
      f(b);
  }

  static std::size_t max_rows(const Supernodal_factor_view& l, int s0, int s1)
  {
    std::size_t m = 0;
    for(int s = s0; s <= s1; ++s)
      m = (std::max)(m, std::size_t(l.pi[s + 1] - l.pi[s]));
    return m;
  }

  void forward(const Supernodal_factor_view& l, double* y, bool parallel) const
  {
    std::size_t most = 1;
    for(const Level& lv : m_levels)
      most = (std::max)(most, lv.bins.size());
    m_workspaces.resize(most);
    for(const Level& lv : m_levels)
    {
      for_each_bin(lv, parallel, [&](std::size_t b) {
        const Bin& bin = lv.bins[b];
        Workspace& ws = m_workspaces[b];
        ws.later.assign(3 * lv.later_columns.size(), 0.);
        ws.w.resize(3 * bin.max_rows);
        for(std::size_t t = 0; t + 1 < bin.start.size(); ++t)
          for(int k = bin.start[t]; k < bin.start[t + 1]; ++k)
            forward_supernode(l, bin.supernodes[std::size_t(k)],
                              std::size_t(k) + 1 < bin.supernodes.size() ? bin.supernodes[std::size_t(k) + 1] : -1,
                              y, ws.w.data(), bin.column_end[t], lv.later_index.data(), ws.later.data());
      });
      for(std::size_t b = 0; b < lv.bins.size(); ++b)   // the updates sent to later levels, in bin order
      {
        const double* u = m_workspaces[b].later.data();
        for(int c : lv.later_columns)
        {
          double* yc = y + 3 * std::size_t(c);
          yc[0] -= u[0];
          yc[1] -= u[1];
          yc[2] -= u[2];
          u += 3;
        }
      }
    }
    Workspace& ws = m_workspaces[0];
    ws.w.resize(3 * max_rows(l, 0, l.nsuper - 1));
    for(std::size_t k = 0; k < m_top.size(); ++k)
      if(parallel && m_top_split[k])
        forward_split_supernode(l, m_top[k], y, ws.w.data());
      else
        forward_supernode(l, m_top[k], k + 1 < m_top.size() ? m_top[k + 1] : -1, y, ws.w.data(), l.n, nullptr,
                          nullptr);
  }

  void backward(const Supernodal_factor_view& l, double* y, bool parallel) const
  {
    {
      Workspace& ws = m_workspaces[0];
      ws.w.resize(3 * max_rows(l, 0, l.nsuper - 1));
      for(std::size_t k = m_top.size(); k-- > 0;)
        if(parallel && m_top_split[k])
          backward_split_supernode(l, m_top[k], y, ws.w.data());
        else
          backward_supernode(l, m_top[k], k > 0 ? m_top[k - 1] : -1, y, ws.w.data());
    }
    for(auto lv = m_levels.rbegin(); lv != m_levels.rend(); ++lv)
      for_each_bin(*lv, parallel, [&](std::size_t b) {
        const Bin& bin = lv->bins[b];
        Workspace& ws = m_workspaces[b];
        ws.w.resize(3 * bin.max_rows);
        for(std::size_t k = bin.supernodes.size(); k-- > 0;)   // parents before children
          backward_supernode(l, bin.supernodes[k], k > 0 ? bin.supernodes[k - 1] : -1, y, ws.w.data());
      });
  }

  // the supernode's rows as three arrays z (of nr) in `w`, swept column by column: z[j] /= L(j,j),
  // then z[j+1..nr) -= L(j+1..nr, j) z[j]. The rows below the block hold minus the update they send
  // (added to y for the rows < `column_end`, the running subtree; subtracted from `later`, the bin's
  // buffer of the later levels' columns (index `later_index`), for the others; `later` null:
  // everything to y)
  // (`next`: the supernode substituted after this one by the same thread, or -1: the pairs of
  // columns prefetch the next pair's columns, the last pair the next supernode's first two)
  void forward_supernode(const Supernodal_factor_view& l, int s, int next, double* y, double* w, int column_end,
                         const int* later_index, double* later) const
  {
    const int k0 = l.super[s], nc = l.super[s + 1] - k0, nr = l.pi[s + 1] - l.pi[s];
    const double* block = l.values + l.px[s];
    double* ys = y + 3 * std::size_t(k0);
    double* z0 = w;
    double* z1 = w + nr;
    double* z2 = w + 2 * std::size_t(nr);
    for(int i = 0; i < nc; ++i)
    {
      z0[i] = ys[3 * i];
      z1[i] = ys[3 * i + 1];
      z2[i] = ys[3 * i + 2];
    }
    std::fill(z0 + nc, z0 + nr, 0.);
    std::fill(z1 + nc, z1 + nr, 0.);
    std::fill(z2 + nc, z2 + nr, 0.);
    int j = 0;
    for(; j + 1 < nc; j += 2)   // two columns c, d at a time: solve rows j, j + 1, then update the rows below
    {
      const double* c = block + std::size_t(j) * std::size_t(nr);
      const double* d = c + nr;
      const double ic = 1. / c[j];
      double a[6];
      a[0] = z0[j] * ic;
      a[1] = z1[j] * ic;
      a[2] = z2[j] * ic;
      const double id = 1. / d[j + 1];
      a[3] = (z0[j + 1] - c[j + 1] * a[0]) * id;
      a[4] = (z1[j + 1] - c[j + 1] * a[1]) * id;
      a[5] = (z2[j + 1] - c[j + 1] * a[2]) * id;
      z0[j] = a[0];
      z1[j] = a[1];
      z2[j] = a[2];
      z0[j + 1] = a[3];
      z1[j + 1] = a[4];
      z2[j + 1] = a[5];
      const double* ahead = j + 3 < nc ? d + nr + j + 2 : next >= 0 ? l.values + l.px[next] : c;
      const int ahead_stride = j + 3 < nc ? nr : next >= 0 ? l.pi[next + 1] - l.pi[next] : 0;
      m_kernels.update2(c + j + 2, d + j + 2, nr - j - 2, ahead, ahead + ahead_stride, a, z0 + j + 2, z1 + j + 2,
                        z2 + j + 2);
    }
    if(j < nc)   // the last column of an odd count
    {
      const double* c = block + std::size_t(j) * std::size_t(nr);
      const double inverse = 1. / c[j];
      const double a[3] = {z0[j] * inverse, z1[j] * inverse, z2[j] * inverse};
      z0[j] = a[0];
      z1[j] = a[1];
      z2[j] = a[2];
      m_kernels.update(c + j + 1, nr - j - 1, a, z0 + j + 1, z1 + j + 1, z2 + j + 1);
    }
    for(int i = 0; i < nc; ++i)
    {
      ys[3 * i] = z0[i];
      ys[3 * i + 1] = z1[i];
      ys[3 * i + 2] = z2[i];
    }
    const int* r = l.rows + l.pi[s];
    for(int i = nc; i < nr; ++i)
      if(later == nullptr || r[i] < column_end)
      {
        double* t = y + 3 * std::size_t(r[i]);
        t[0] += z0[i];
        t[1] += z1[i];
        t[2] += z2[i];
      }
      else
      {
        double* t = later + 3 * std::size_t(later_index[std::size_t(r[i])]);
        t[0] -= z0[i];
        t[1] -= z1[i];
        t[2] -= z2[i];
      }
  }

  // z[nc..nr) = the solved rows below the block; first every column's dot product with them (the
  // columns in ascending order: one stream), then the diagonal block, transposed, from its last column
  void backward_supernode(const Supernodal_factor_view& l, int s, int next, double* y, double* w) const
  {
    const int k0 = l.super[s], nc = l.super[s + 1] - k0, nr = l.pi[s + 1] - l.pi[s], m = nr - nc;
    const double* block = l.values + l.px[s];
    double* ys = y + 3 * std::size_t(k0);
    double* z0 = w;
    double* z1 = w + nr;
    double* z2 = w + 2 * std::size_t(nr);
    const int* r = l.rows + l.pi[s];
    for(int i = nc; i < nr; ++i)
    {
      const double* yr = y + 3 * std::size_t(r[i]);
      z0[i] = yr[0];
      z1[i] = yr[1];
      z2[i] = yr[2];
    }
    int j = 0;
    for(; m > 0 && j + 1 < nc; j += 2)   // two columns at a time
    {
      double t[6];
      const double* c = block + std::size_t(j) * std::size_t(nr) + nc;
      const int next_nr = next >= 0 ? l.pi[next + 1] - l.pi[next] : 0,
                next_nc = next >= 0 ? l.super[next + 1] - l.super[next] : 0;
      const double* ahead = j + 3 < nc ? c + 2 * nr : next >= 0 ? l.values + l.px[next] + next_nc : c;
      const int ahead_stride = j + 3 < nc ? nr : next_nr;
      m_kernels.dot2(c, c + nr, m, ahead, ahead + ahead_stride, z0 + nc, z1 + nc, z2 + nc, t);
      z0[j] = ys[3 * j] - t[0];
      z1[j] = ys[3 * j + 1] - t[1];
      z2[j] = ys[3 * j + 2] - t[2];
      z0[j + 1] = ys[3 * j + 3] - t[3];
      z1[j + 1] = ys[3 * j + 4] - t[4];
      z2[j + 1] = ys[3 * j + 5] - t[5];
    }
    for(; j < nc; ++j)
    {
      double t[3] = {0, 0, 0};
      if(m > 0)
        m_kernels.dot(block + std::size_t(j) * std::size_t(nr) + nc, m, z0 + nc, z1 + nc, z2 + nc, t);
      z0[j] = ys[3 * j] - t[0];
      z1[j] = ys[3 * j + 1] - t[1];
      z2[j] = ys[3 * j + 2] - t[2];
    }
    for(int j = nc - 1; j >= 0; --j)
    {
      const double* c = block + std::size_t(j) * std::size_t(nr);
      double t[3];
      m_kernels.dot(c + j + 1, nc - j - 1, z0 + j + 1, z1 + j + 1, z2 + j + 1, t);
      const double inverse = 1. / c[j];
      z0[j] = (z0[j] - t[0]) * inverse;
      z1[j] = (z1[j] - t[1]) * inverse;
      z2[j] = (z2[j] - t[2]) * inverse;
    }
    for(int i = 0; i < nc; ++i)
    {
      ys[3 * i] = z0[i];
      ys[3 * i + 1] = z1[i];
      ys[3 * i + 2] = z2[i];
    }
  }

  // f(begin, end) over [begin, end) cut into up to m_chunks pieces of at least `grain` (their
  // bounds multiples of `align` from `begin`), on TBB's threads
  template <class F>
  void for_each_chunk(int begin, int end, int grain, int align, const F& f) const
  {
#ifdef CGAL_LINKED_WITH_TBB
    const int count = (std::min)(m_chunks, (std::max)(1, (end - begin) / grain));
    if(count > 1)
    {
      const int units = (end - begin + align - 1) / align;
      tbb::parallel_for(0, count, [&](int k) {
        const int b = begin + align * int(std::int64_t(units) * k / count);
        const int e = k + 1 == count ? end : begin + align * int(std::int64_t(units) * (k + 1) / count);
        if(b < e)
          f(b, e);
      }, tbb::simple_partitioner());
      return;
    }
#else
    (void)grain;
    (void)align;
#endif
    f(begin, end);
  }

  // forward_supernode() for a large supernode of the top (parallel schedules only), by panels of
  // `panel_columns` columns (even, so that the pairs of columns are those of forward_supernode()):
  // a panel's pairs are solved and update the panel's own rows on one thread, then they update the
  // rows below the panel, cut into pieces on TBB's threads. Every row sees the same updates in the
  // same order through the same kernels as in forward_supernode(): the same result, bit for bit.
  void forward_split_supernode(const Supernodal_factor_view& l, int s, double* y, double* w) const
  {
    const int k0 = l.super[s], nc = l.super[s + 1] - k0, nr = l.pi[s + 1] - l.pi[s];
    const double* block = l.values + l.px[s];
    double* ys = y + 3 * std::size_t(k0);
    double* z0 = w;
    double* z1 = w + nr;
    double* z2 = w + 2 * std::size_t(nr);
    for(int i = 0; i < nc; ++i)
    {
      z0[i] = ys[3 * i];
      z1[i] = ys[3 * i + 1];
      z2[i] = ys[3 * i + 2];
    }
    std::fill(z0 + nc, z0 + nr, 0.);
    std::fill(z1 + nc, z1 + nr, 0.);
    std::fill(z2 + nc, z2 + nr, 0.);
    double a[3 * panel_columns];   // the panel's solved rows: per pair a[0..5] as in forward_supernode()
    for(int p = 0; p < nc; p += panel_columns)
    {
      const int e = (std::min)(p + panel_columns, nc);
      int j = p;
      for(; j + 1 < e; j += 2)
      {
        const double* c = block + std::size_t(j) * std::size_t(nr);
        const double* d = c + nr;
        double* aj = a + 3 * (j - p);
        const double ic = 1. / c[j];
        aj[0] = z0[j] * ic;
        aj[1] = z1[j] * ic;
        aj[2] = z2[j] * ic;
        const double id = 1. / d[j + 1];
        aj[3] = (z0[j + 1] - c[j + 1] * aj[0]) * id;
        aj[4] = (z1[j + 1] - c[j + 1] * aj[1]) * id;
        aj[5] = (z2[j + 1] - c[j + 1] * aj[2]) * id;
        z0[j] = aj[0];
        z1[j] = aj[1];
        z2[j] = aj[2];
        z0[j + 1] = aj[3];
        z1[j + 1] = aj[4];
        z2[j + 1] = aj[5];
        m_kernels.update2(c + j + 2, d + j + 2, e - j - 2, c, d, aj, z0 + j + 2, z1 + j + 2, z2 + j + 2);
      }
      if(j < e)   // the last column of an odd count
      {
        const double* c = block + std::size_t(j) * std::size_t(nr);
        double* aj = a + 3 * (j - p);
        const double inverse = 1. / c[j];
        aj[0] = z0[j] * inverse;
        aj[1] = z1[j] * inverse;
        aj[2] = z2[j] * inverse;
        z0[j] = aj[0];
        z1[j] = aj[1];
        z2[j] = aj[2];
        m_kernels.update(c + j + 1, e - j - 1, aj, z0 + j + 1, z1 + j + 1, z2 + j + 1);
      }
      for_each_chunk(e, nr, split_rows, 8, [&](int r0, int r1) {
        int q = p;
        for(; q + 1 < e; q += 2)
        {
          const double* c = block + std::size_t(q) * std::size_t(nr);
          const double* ahead = q + 3 < nc ? c + 2 * std::size_t(nr) : c;
          m_kernels.update2(c + r0, c + nr + r0, r1 - r0, ahead + r0, ahead + nr + r0, a + 3 * (q - p), z0 + r0,
                            z1 + r0, z2 + r0);
        }
        if(q < e)
          m_kernels.update(block + std::size_t(q) * std::size_t(nr) + r0, r1 - r0, a + 3 * (q - p), z0 + r0,
                           z1 + r0, z2 + r0);
      });
    }
    for(int i = 0; i < nc; ++i)
    {
      ys[3 * i] = z0[i];
      ys[3 * i + 1] = z1[i];
      ys[3 * i + 2] = z2[i];
    }
    const int* r = l.rows + l.pi[s];
    for(int i = nc; i < nr; ++i)
    {
      double* t = y + 3 * std::size_t(r[i]);
      t[0] += z0[i];
      t[1] += z1[i];
      t[2] += z2[i];
    }
  }

  // backward_supernode() for a large supernode of the top (parallel schedules only): the dot
  // products of the columns with the rows below the block as there, the pairs of columns cut into
  // pieces on TBB's threads (the same result); then the diagonal block by panels of
  // `panel_columns` columns from the last: the dot products of a panel's columns with the rows after
  // the panel (already solved) on TBB's threads, then the panel's own triangle on one thread. A
  // column's dot product with the block's rows is then two sums instead of one: the result differs
  // from backward_supernode()'s by round-off, and does not depend on the number of threads.
  void backward_split_supernode(const Supernodal_factor_view& l, int s, double* y, double* w) const
  {
    const int k0 = l.super[s], nc = l.super[s + 1] - k0, nr = l.pi[s + 1] - l.pi[s], m = nr - nc;
    const double* block = l.values + l.px[s];
    double* ys = y + 3 * std::size_t(k0);
    double* z0 = w;
    double* z1 = w + nr;
    double* z2 = w + 2 * std::size_t(nr);
    const int* r = l.rows + l.pi[s];
    for(int i = nc; i < nr; ++i)
    {
      const double* yr = y + 3 * std::size_t(r[i]);
      z0[i] = yr[0];
      z1[i] = yr[1];
      z2[i] = yr[2];
    }
    // z[j] = y[j] minus the dot products of the columns [j0, j1) (j0 even) with the rows below the
    // block, as in backward_supernode()
    const auto below = [&](int j0, int j1) {
      int j = j0;
      for(; m > 0 && j + 1 < j1; j += 2)
      {
        double t[6];
        const double* c = block + std::size_t(j) * std::size_t(nr) + nc;
        const double* ahead = j + 3 < j1 ? c + 2 * std::size_t(nr) : c;
        m_kernels.dot2(c, c + nr, m, ahead, ahead + nr, z0 + nc, z1 + nc, z2 + nc, t);
        z0[j] = ys[3 * j] - t[0];
        z1[j] = ys[3 * j + 1] - t[1];
        z2[j] = ys[3 * j + 2] - t[2];
        z0[j + 1] = ys[3 * j + 3] - t[3];
        z1[j + 1] = ys[3 * j + 4] - t[4];
        z2[j + 1] = ys[3 * j + 5] - t[5];
      }
      for(; j < j1; ++j)
      {
        double t[3] = {0, 0, 0};
        if(m > 0)
          m_kernels.dot(block + std::size_t(j) * std::size_t(nr) + nc, m, z0 + nc, z1 + nc, z2 + nc, t);
        z0[j] = ys[3 * j] - t[0];
        z1[j] = ys[3 * j + 1] - t[1];
        z2[j] = ys[3 * j + 2] - t[2];
      }
    };
    // pieces of columns that hold at least as many values as a piece of forward_split_supernode()
    const auto column_grain = [](int len) {
      const int g = (split_rows * panel_columns + len - 1) / (std::max)(1, len);
      return (std::max)(2, g + (g & 1));
    };
    for_each_chunk(0, nc, m > 0 ? column_grain(m) : nc, 2, below);
    const int last = (nc - 1) / panel_columns * panel_columns;
    for(int p = last; p >= 0; p -= panel_columns)
    {
      const int e = (std::min)(p + panel_columns, nc), after = nc - e;
      if(after > 0)
        for_each_chunk(p, e, column_grain(after), 2, [&](int j0, int j1) {   // the rows [e, nc) only
          const int len = after;
          int j = j0;
          for(; j + 1 < j1; j += 2)
          {
            double t[6];
            const double* c = block + std::size_t(j) * std::size_t(nr) + e;
            const double* ahead = j + 3 < j1 ? c + 2 * std::size_t(nr) : c;
            m_kernels.dot2(c, c + nr, len, ahead, ahead + nr, z0 + e, z1 + e, z2 + e, t);
            z0[j] -= t[0];
            z1[j] -= t[1];
            z2[j] -= t[2];
            z0[j + 1] -= t[3];
            z1[j + 1] -= t[4];
            z2[j + 1] -= t[5];
          }
          for(; j < j1; ++j)
          {
            double t[3];
            m_kernels.dot(block + std::size_t(j) * std::size_t(nr) + e, len, z0 + e, z1 + e, z2 + e, t);
            z0[j] -= t[0];
            z1[j] -= t[1];
            z2[j] -= t[2];
          }
        });
      for(int j = e - 1; j >= p; --j)
      {
        const double* c = block + std::size_t(j) * std::size_t(nr);
        double t[3];
        m_kernels.dot(c + j + 1, e - j - 1, z0 + j + 1, z1 + j + 1, z2 + j + 1, t);
        const double inverse = 1. / c[j];
        z0[j] = (z0[j] - t[0]) * inverse;
        z1[j] = (z1[j] - t[1]) * inverse;
        z2[j] = (z2[j] - t[2]) * inverse;
      }
    }
    for(int i = 0; i < nc; ++i)
    {
      ys[3 * i] = z0[i];
      ys[3 * i + 1] = z1[i];
      ys[3 * i + 2] = z2[i];
    }
  }

  // a supernode of the top with at least split_values values is split (parallel schedules); its
  // pieces hold at least split_rows rows of a panel (or as many values)
  static constexpr int panel_columns = 64;
  static constexpr double split_values = 65536.;
  static constexpr int split_rows = 256;

  std::vector<Level> m_levels;
  std::vector<int> m_top;         // the supernodes above the levels' subtrees, increasing
  std::vector<char> m_top_split;  // per supernode of m_top: substituted by forward_split_supernode() / backward_...
  int m_chunks = 1;               // the pieces of a split supernode's panel: up to this many
  std::size_t m_split_supernodes = 0;
  int m_n = -1, m_nsuper = -1;
  double m_sequential_share = 1.;
  mutable std::vector<Workspace> m_workspaces;
  mutable supernodal_kernels::Kernels m_kernels;
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_SUPERNODAL_SOLVE_H
