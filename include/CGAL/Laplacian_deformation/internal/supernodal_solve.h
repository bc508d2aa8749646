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
// remains (the top) is too small to pay for another barrier; the top's supernodes follow one after
// the other, each large one split into pieces on TBB's threads panel by panel
// (forward_split_supernode(), backward_split_supernode()). In the forward
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

  // a supernode's block (nr rows, nc columns, column-major), y's rows of its columns (`ys`,
  // interleaved) and the workspace's three arrays z of nr rows
  struct Sweep
  {
    const double* block;
    int nc, nr;
    const int* rows;
    double* ys;
    double *z0, *z1, *z2;
    const double* column(int j) const { return block + std::size_t(j) * std::size_t(nr); }
  };
  static Sweep sweep(const Supernodal_factor_view& l, int s, double* y, double* w)
  {
    const int nr = l.pi[s + 1] - l.pi[s];
    return Sweep{l.values + l.px[s], l.super[s + 1] - l.super[s], nr, l.rows + l.pi[s],
                 y + 3 * std::size_t(l.super[s]), w, w + nr, w + 2 * std::size_t(nr)};
  }
  // forward: z = the block's rows of y, zeros below
  static void load_columns(const Sweep& x)
  {
    for(int i = 0; i < x.nc; ++i)
    {
      x.z0[i] = x.ys[3 * i];
      x.z1[i] = x.ys[3 * i + 1];
      x.z2[i] = x.ys[3 * i + 2];
    }
    std::fill(x.z0 + x.nc, x.z0 + x.nr, 0.);
    std::fill(x.z1 + x.nc, x.z1 + x.nr, 0.);
    std::fill(x.z2 + x.nc, x.z2 + x.nr, 0.);
  }
  static void store_columns(const Sweep& x)
  {
    for(int i = 0; i < x.nc; ++i)
    {
      x.ys[3 * i] = x.z0[i];
      x.ys[3 * i + 1] = x.z1[i];
      x.ys[3 * i + 2] = x.z2[i];
    }
  }
  // forward: rows j and j + 1 solved (a[0..5], also into z), their columns' entries below them not
  // applied yet
  static void solve_pair(const Sweep& x, int j, double* a)
  {
    const double* c = x.column(j);
    const double* d = c + x.nr;
    const double ic = 1. / c[j];
    a[0] = x.z0[j] * ic;
    a[1] = x.z1[j] * ic;
    a[2] = x.z2[j] * ic;
    const double id = 1. / d[j + 1];
    a[3] = (x.z0[j + 1] - c[j + 1] * a[0]) * id;
    a[4] = (x.z1[j + 1] - c[j + 1] * a[1]) * id;
    a[5] = (x.z2[j + 1] - c[j + 1] * a[2]) * id;
    x.z0[j] = a[0];
    x.z1[j] = a[1];
    x.z2[j] = a[2];
    x.z0[j + 1] = a[3];
    x.z1[j + 1] = a[4];
    x.z2[j + 1] = a[5];
  }
  // forward: row j alone solved (a[0..2], also into z)
  static void solve_single(const Sweep& x, int j, double* a)
  {
    const double inverse = 1. / x.column(j)[j];
    a[0] = x.z0[j] * inverse;
    a[1] = x.z1[j] * inverse;
    a[2] = x.z2[j] * inverse;
    x.z0[j] = a[0];
    x.z1[j] = a[1];
    x.z2[j] = a[2];
  }
  // forward: the rows below the block hold minus the update they send: added to y for the rows <
  // `column_end` (the running subtree), subtracted from `later` (the bin's buffer of the later
  // levels' columns, index `later_index`) for the others; `later` null: everything to y
  static void scatter_below(const Sweep& x, double* y, int column_end, const int* later_index, double* later)
  {
    for(int i = x.nc; i < x.nr; ++i)
    {
      const int r = x.rows[i];
      if(later == nullptr || r < column_end)
      {
        double* t = y + 3 * std::size_t(r);
        t[0] += x.z0[i];
        t[1] += x.z1[i];
        t[2] += x.z2[i];
      }
      else
      {
        double* t = later + 3 * std::size_t(later_index[std::size_t(r)]);
        t[0] -= x.z0[i];
        t[1] -= x.z1[i];
        t[2] -= x.z2[i];
      }
    }
  }
  // backward: z[nc..nr) = y's rows below the block (solved)
  static void gather_below(const Sweep& x, const double* y)
  {
    for(int i = x.nc; i < x.nr; ++i)
    {
      const double* yr = y + 3 * std::size_t(x.rows[i]);
      x.z0[i] = yr[0];
      x.z1[i] = yr[1];
      x.z2[i] = yr[2];
    }
  }
  // backward: for the columns [j0, j1) (j0 even; pairs of columns, then the last one of an odd
  // count), z[j] = (FromY ? y's row j : z[j]) minus the dot products of column j's rows
  // [from, to) with z[from, to). A pair prefetches the next pair's rows, the last pair those at
  // `last_ahead` (two columns `last_stride` apart; null: none)
  template <bool FromY>
  void subtract_dots(const Sweep& x, int j0, int j1, int from, int to, const double* last_ahead,
                     int last_stride) const
  {
    const int len = to - from;
    int j = j0;
    for(; len > 0 && j + 1 < j1; j += 2)
    {
      double t[6];
      const double* c = x.column(j) + from;
      const bool more = j + 3 < j1;
      const double* ahead = more ? c + 2 * std::size_t(x.nr) : last_ahead ? last_ahead : c;
      m_kernels.dot2(c, c + x.nr, len, ahead, ahead + (more || !last_ahead ? x.nr : last_stride), x.z0 + from,
                     x.z1 + from, x.z2 + from, t);
      for(int q = 0; q < 2; ++q)
      {
        const int i = j + q;
        x.z0[i] = (FromY ? x.ys[3 * i] : x.z0[i]) - t[3 * q];
        x.z1[i] = (FromY ? x.ys[3 * i + 1] : x.z1[i]) - t[3 * q + 1];
        x.z2[i] = (FromY ? x.ys[3 * i + 2] : x.z2[i]) - t[3 * q + 2];
      }
    }
    for(; j < j1; ++j)
    {
      double t[3] = {0, 0, 0};
      if(len > 0)
        m_kernels.dot(x.column(j) + from, len, x.z0 + from, x.z1 + from, x.z2 + from, t);
      x.z0[j] = (FromY ? x.ys[3 * j] : x.z0[j]) - t[0];
      x.z1[j] = (FromY ? x.ys[3 * j + 1] : x.z1[j]) - t[1];
      x.z2[j] = (FromY ? x.ys[3 * j + 2] : x.z2[j]) - t[2];
    }
  }
  // backward: the block's columns [p, e) against its rows [p, e) (transposed), from column e - 1:
  // z[j] = (z[j] - L(j+1..e, j) z[j+1..e)) / L(j,j)
  void solve_triangle_transposed(const Sweep& x, int p, int e) const
  {
    for(int j = e - 1; j >= p; --j)
    {
      const double* c = x.column(j);
      double t[3];
      m_kernels.dot(c + j + 1, e - j - 1, x.z0 + j + 1, x.z1 + j + 1, x.z2 + j + 1, t);
      const double inverse = 1. / c[j];
      x.z0[j] = (x.z0[j] - t[0]) * inverse;
      x.z1[j] = (x.z1[j] - t[1]) * inverse;
      x.z2[j] = (x.z2[j] - t[2]) * inverse;
    }
  }

  // the supernode's rows as three arrays z (of nr) in `w`, swept column by column: z[j] /= L(j,j),
  // then z[j+1..nr) -= L(j+1..nr, j) z[j]; the rows below the block then go to y or `later` (see
  // scatter_below()).
  // (`next`: the supernode substituted after this one by the same thread, or -1: the pairs of
  // columns prefetch the next pair's columns, the last pair the next supernode's first two)
  void forward_supernode(const Supernodal_factor_view& l, int s, int next, double* y, double* w, int column_end,
                         const int* later_index, double* later) const
  {
    const Sweep x = sweep(l, s, y, w);
    const int nc = x.nc, nr = x.nr;
    load_columns(x);
    int j = 0;
    for(; j + 1 < nc; j += 2)   // two columns c, d at a time: solve rows j, j + 1, then update the rows below
    {
      const double* c = x.column(j);
      const double* d = c + nr;
      double a[6];
      solve_pair(x, j, a);
      const double* ahead = j + 3 < nc ? d + nr + j + 2 : next >= 0 ? l.values + l.px[next] : c;
      const int ahead_stride = j + 3 < nc ? nr : next >= 0 ? l.pi[next + 1] - l.pi[next] : 0;
      m_kernels.update2(c + j + 2, d + j + 2, nr - j - 2, ahead, ahead + ahead_stride, a, x.z0 + j + 2,
                        x.z1 + j + 2, x.z2 + j + 2);
    }
    if(j < nc)   // the last column of an odd count
    {
      double a[3];
      solve_single(x, j, a);
      m_kernels.update(x.column(j) + j + 1, nr - j - 1, a, x.z0 + j + 1, x.z1 + j + 1, x.z2 + j + 1);
    }
    store_columns(x);
    scatter_below(x, y, column_end, later_index, later);
  }

  // z[nc..nr) = the solved rows below the block; first every column's dot product with them (the
  // columns in ascending order: one stream), then the diagonal block, transposed, from its last column
  void backward_supernode(const Supernodal_factor_view& l, int s, int next, double* y, double* w) const
  {
    const Sweep x = sweep(l, s, y, w);
    gather_below(x, y);
    // the last pair prefetches the next supernode's first two columns below its block
    const double* next_ahead = next >= 0 ? l.values + l.px[next] + (l.super[next + 1] - l.super[next]) : nullptr;
    subtract_dots<true>(x, 0, x.nc, x.nc, x.nr, next_ahead, next >= 0 ? l.pi[next + 1] - l.pi[next] : 0);
    solve_triangle_transposed(x, 0, x.nc);
    store_columns(x);
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
    const Sweep x = sweep(l, s, y, w);
    const int nc = x.nc, nr = x.nr;
    load_columns(x);
    double a[3 * panel_columns];   // the panel's solved rows: per pair a[0..5] as in forward_supernode()
    for(int p = 0; p < nc; p += panel_columns)
    {
      const int e = (std::min)(p + panel_columns, nc);
      int j = p;
      for(; j + 1 < e; j += 2)
      {
        const double* c = x.column(j);
        double* aj = a + 3 * (j - p);
        solve_pair(x, j, aj);
        m_kernels.update2(c + j + 2, c + nr + j + 2, e - j - 2, c, c + nr, aj, x.z0 + j + 2, x.z1 + j + 2,
                          x.z2 + j + 2);
      }
      if(j < e)   // the last column of an odd count
      {
        double* aj = a + 3 * (j - p);
        solve_single(x, j, aj);
        m_kernels.update(x.column(j) + j + 1, e - j - 1, aj, x.z0 + j + 1, x.z1 + j + 1, x.z2 + j + 1);
      }
      for_each_chunk(e, nr, split_rows, 8, [&](int r0, int r1) {
        int q = p;
        for(; q + 1 < e; q += 2)
        {
          const double* c = x.column(q);
          const double* ahead = q + 3 < nc ? c + 2 * std::size_t(nr) : c;
          m_kernels.update2(c + r0, c + nr + r0, r1 - r0, ahead + r0, ahead + nr + r0, a + 3 * (q - p), x.z0 + r0,
                            x.z1 + r0, x.z2 + r0);
        }
        if(q < e)
          m_kernels.update(x.column(q) + r0, r1 - r0, a + 3 * (q - p), x.z0 + r0, x.z1 + r0, x.z2 + r0);
      });
    }
    store_columns(x);
    scatter_below(x, y, l.n, nullptr, nullptr);
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
    const Sweep x = sweep(l, s, y, w);
    const int nc = x.nc, m = x.nr - x.nc;
    gather_below(x, y);
    // pieces of columns that hold at least as many values as a piece of forward_split_supernode()
    const auto column_grain = [](int len) {
      const int g = (split_rows * panel_columns + len - 1) / (std::max)(1, len);
      return (std::max)(2, g + (g & 1));
    };
    for_each_chunk(0, nc, m > 0 ? column_grain(m) : nc, 2,
                   [&](int j0, int j1) { subtract_dots<true>(x, j0, j1, nc, x.nr, nullptr, 0); });
    for(int p = (nc - 1) / panel_columns * panel_columns; p >= 0; p -= panel_columns)
    {
      const int e = (std::min)(p + panel_columns, nc);
      if(e < nc)   // the rows after the panel: [e, nc)
        for_each_chunk(p, e, column_grain(nc - e), 2,
                       [&](int j0, int j1) { subtract_dots<false>(x, j0, j1, e, nc, nullptr, 0); });
      solve_triangle_transposed(x, p, e);
    }
    store_columns(x);
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
