// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// The lane kernels of the batched local step (no include guard on purpose): included by
// batched_transforms.h once per instruction set, inside namespace
// CGAL::Laplacian_deformation::internal::batched, with
//   CGAL_LAPDEF_KERNEL_NS    the namespace of this copy (portable, avx2, avx512),
//   CGAL_LAPDEF_KERNEL_ATTR  its function attributes (a target attribute, or nothing),
//   CGAL_LAPDEF_KERNEL_ISA   0 portable C++, 1 SSE2, 2 AVX2, 3 AVX-512 (for the square roots).
// Every kernel works on `lanes` cells at once, in structure-of-arrays form (`Lanes`): plain loops
// over the lanes, branch-free (selects), that the compiler vectorises, and for the Jacobi
// rotations with AVX2 and AVX-512 explicit vector types (GCC / Clang vector extensions). Each lane
// performs exactly
// the floating-point operations of the scalar code (closest_rotation(), Scale_fit, the policies),
// in the order in which Eigen evaluates them there (a 3x3 product: rows 0 and 1 summed left to
// right, row 2 as a0 + (a1 + a2); transposed products, dot products and norms left to right);
// floating-point contraction is off, so the results are bitwise those of the scalar code compiled
// without FMA contraction.
// The sums over spokes run over the largest degree of the lanes, without masks: the spokes past a
// lane's degree are zeros (rest, current and weight), whose terms are +-0, and adding +-0 to a sum
// that starts at +0 never changes it (a sum that starts at +0 is never -0), so every lane's sums
// are bitwise those of its own spokes.

namespace CGAL_LAPDEF_KERNEL_NS {

// the lanes of a kernel are processed `sub` at a time where that keeps the working set in registers
#if CGAL_LAPDEF_KERNEL_ISA == 3
constexpr int sub = 8;
#elif CGAL_LAPDEF_KERNEL_ISA == 2
constexpr int sub = 4;
#else
constexpr int sub = lanes;
#endif
static_assert(lanes % sub == 0, "");
// the Jacobi rotations of closest_rotation() run on groups of `jsub` lanes, the groups' rotations
// issued one after the other so that their chains of divisions and square roots overlap (with
// AVX-512 two four-lane groups: a rotation's chain is shorter on 256-bit registers, and the two
// chains together keep the divider busy)
#if CGAL_LAPDEF_KERNEL_ISA >= 2
constexpr int jsub = 4;
#else
constexpr int jsub = sub;
#endif
static_assert(lanes % jsub == 0, "");

// in-place square roots of x[0], ..., x[sub - 1] (aligned to 8 sub bytes)
CGAL_LAPDEF_KERNEL_ATTR inline void sqrt_sub(double* x)
{
  CGAL_LAPDEF_NO_CONTRACT
#if CGAL_LAPDEF_KERNEL_ISA == 3
  for(int l = 0; l < sub; l += 8)
    _mm512_store_pd(x + l, _mm512_maskz_sqrt_pd(__mmask8(0xFF), _mm512_load_pd(x + l)));
#elif CGAL_LAPDEF_KERNEL_ISA == 2
  for(int l = 0; l < sub; l += 4)
    _mm256_store_pd(x + l, _mm256_sqrt_pd(_mm256_load_pd(x + l)));
#elif CGAL_LAPDEF_KERNEL_ISA == 1
  for(int l = 0; l < sub; l += 2)
    _mm_store_pd(x + l, _mm_sqrt_pd(_mm_load_pd(x + l)));
#else
  for(int l = 0; l < sub; ++l)
    x[l] = std::sqrt(x[l]);
#endif
}

// in-place square roots of x[0], ..., x[jsub - 1] (aligned to 8 jsub bytes)
CGAL_LAPDEF_KERNEL_ATTR inline void sqrt_jsub(double* x)
{
  CGAL_LAPDEF_NO_CONTRACT
#if CGAL_LAPDEF_KERNEL_ISA >= 2
  for(int l = 0; l < jsub; l += 4)
    _mm256_store_pd(x + l, _mm256_sqrt_pd(_mm256_load_pd(x + l)));
#else
  sqrt_sub(x);
#endif
}

// Scale_fit::clamp(x) (std::clamp: NaN kept)
#define CGAL_LAPDEF_CLAMP(x)                                                                       \
  ((x) < Scale_fit::min_scale ? Scale_fit::min_scale : (Scale_fit::max_scale < (x) ? Scale_fit::max_scale : (x)))

// the working arrays of closest_rotation(), in one object so that the compiler sees that they
// do not overlap
struct Jacobi_work
{
  alignas(64) double a[9][lanes], v[9][lanes];
  alignas(64) double x1[lanes], x2[lanes], th[lanes], tt[lanes];
  alignas(64) std::int64_t done[lanes];
  alignas(64) double e1[3][lanes], e2[3][lanes], b1[3][lanes], b2[3][lanes];
};

// one Jacobi rotation (p, q) of symmetric_eigen_jacobi_3() in lanes l0, ..., l0 + jsub - 1 that
// are not done
#if defined(__GNUC__) && CGAL_LAPDEF_KERNEL_ISA >= 2
// (AVX2 and AVX-512 with GCC or Clang: vector types of `jsub` lanes, one register each; the plain
// loops of the #else branch are faster for SSE2, where GCC vectorises them well)
typedef double Vd __attribute__((vector_size(8 * jsub)));
typedef std::int64_t Vm __attribute__((vector_size(8 * jsub)));
#define CGAL_LAPDEF_LOAD(v, p) std::memcpy(&(v), (p), sizeof(Vd))
#define CGAL_LAPDEF_STORE(p, v) std::memcpy((p), &(v), sizeof(Vd))
#define CGAL_LAPDEF_SELECT(m, x, y) ((Vd)((((Vm)(x)) & (m)) | (((Vm)(y)) & ~(m))))

template <int p, int q>
CGAL_LAPDEF_KERNEL_ATTR inline void jacobi_rotation(Jacobi_work& w, int l0)
{
  CGAL_LAPDEF_NO_CONTRACT
  constexpr int o = 3 - p - q;
  constexpr int pp = 4 * p, qq = 4 * q, pq = 3 * p + q, qp = 3 * q + p;
  constexpr int op = 3 * o + p, po = 3 * p + o, oq = 3 * o + q, qo = 3 * q + o;
  Vd app, aqq, apq, g, hh, x1, x2;
  Vm done;
  CGAL_LAPDEF_LOAD(app, w.a[pp] + l0);
  CGAL_LAPDEF_LOAD(aqq, w.a[qq] + l0);
  CGAL_LAPDEF_LOAD(apq, w.a[pq] + l0);
  CGAL_LAPDEF_LOAD(g, w.a[op] + l0);
  CGAL_LAPDEF_LOAD(hh, w.a[oq] + l0);
  CGAL_LAPDEF_LOAD(done, w.done + l0);
  const Vd d = aqq - app;
  x1 = d * d + 4 * apq * apq;
  CGAL_LAPDEF_STORE(w.x1 + l0, x1);
  sqrt_jsub(w.x1 + l0);
  CGAL_LAPDEF_LOAD(x1, w.x1 + l0);
  const Vd ad = (Vd)((Vm)d & 0x7fffffffffffffffLL);
  const Vd zero = {};
  const Vd t0 = (2 * apq) / (ad + x1);
  const Vd t = CGAL_LAPDEF_SELECT(d < 0, -t0, t0);
  x2 = t * t + 1.;
  CGAL_LAPDEF_STORE(w.x2 + l0, x2);
  sqrt_jsub(w.x2 + l0);
  CGAL_LAPDEF_LOAD(x2, w.x2 + l0);
  const Vm apply = (done == 0) & (apq != 0);
  const Vd c = 1. / x2, sn = t * c, tau = t / (x2 + 1.), h = t * apq;
  const Vd new_pp = app - h, new_qq = aqq + h;
  const Vd new_op = g - sn * (hh + g * tau), new_oq = hh + sn * (g - hh * tau);
  const Vd r_pp = CGAL_LAPDEF_SELECT(apply, new_pp, app), r_qq = CGAL_LAPDEF_SELECT(apply, new_qq, aqq),
           r_pq = CGAL_LAPDEF_SELECT(apply, zero, apq), r_op = CGAL_LAPDEF_SELECT(apply, new_op, g),
           r_oq = CGAL_LAPDEF_SELECT(apply, new_oq, hh);
  CGAL_LAPDEF_STORE(w.a[pp] + l0, r_pp);
  CGAL_LAPDEF_STORE(w.a[qq] + l0, r_qq);
  CGAL_LAPDEF_STORE(w.a[pq] + l0, r_pq);
  CGAL_LAPDEF_STORE(w.a[qp] + l0, r_pq);
  CGAL_LAPDEF_STORE(w.a[op] + l0, r_op);
  CGAL_LAPDEF_STORE(w.a[po] + l0, r_op);
  CGAL_LAPDEF_STORE(w.a[oq] + l0, r_oq);
  CGAL_LAPDEF_STORE(w.a[qo] + l0, r_oq);
  for(int j = 0; j < 3; ++j)
  {
    Vd vg, vh;
    CGAL_LAPDEF_LOAD(vg, w.v[3 * j + p] + l0);
    CGAL_LAPDEF_LOAD(vh, w.v[3 * j + q] + l0);
    const Vd ng = vg - sn * (vh + vg * tau), nh = vh + sn * (vg - vh * tau);
    const Vd rg = CGAL_LAPDEF_SELECT(apply, ng, vg), rh = CGAL_LAPDEF_SELECT(apply, nh, vh);
    CGAL_LAPDEF_STORE(w.v[3 * j + p] + l0, rg);
    CGAL_LAPDEF_STORE(w.v[3 * j + q] + l0, rh);
  }
}
#undef CGAL_LAPDEF_LOAD
#undef CGAL_LAPDEF_STORE
#undef CGAL_LAPDEF_SELECT
#else
template <int p, int q>
CGAL_LAPDEF_KERNEL_ATTR inline void jacobi_rotation(Jacobi_work& w, int l0)
{
  CGAL_LAPDEF_NO_CONTRACT
  double(&a)[9][lanes] = w.a;
  double(&v)[9][lanes] = w.v;
  double(&th)[lanes] = w.th;
  double(&tt)[lanes] = w.tt;
  double(&x1)[lanes] = w.x1;
  double(&x2)[lanes] = w.x2;
  const std::int64_t(&done)[lanes] = w.done;
  constexpr int o = 3 - p - q;
  constexpr int pp = 4 * p, qq = 4 * q, pq = 3 * p + q, qp = 3 * q + p;
  constexpr int op = 3 * o + p, po = 3 * p + o, oq = 3 * o + q, qo = 3 * q + o;
  for(int l = l0; l < l0 + jsub; ++l)
  {
    const double d = a[qq][l] - a[pp][l], apq = a[pq][l];
    th[l] = d;
    x1[l] = d * d + 4 * apq * apq;
  }
  sqrt_jsub(x1 + l0);
  for(int l = l0; l < l0 + jsub; ++l)
  {
    const double d = th[l];
    const double t = (2 * a[pq][l]) / (CGAL_LAPDEF_FABS(d) + x1[l]);
    const double signed_t = d < 0 ? -t : t;
    tt[l] = signed_t;
    x2[l] = signed_t * signed_t + 1.;
  }
  sqrt_jsub(x2 + l0);
  for(int l = l0; l < l0 + jsub; ++l)
  {
    const double apq = a[pq][l], t = tt[l];
    const bool apply = done[l] == 0 && apq != 0;
    const double c = 1. / x2[l], sn = t * c, tau = t / (x2[l] + 1.), h = t * apq;
    const double app = a[pp][l], aqq = a[qq][l], g = a[op][l], hh = a[oq][l];
    const double new_pp = app - h, new_qq = aqq + h;
    const double new_op = g - sn * (hh + g * tau), new_oq = hh + sn * (g - hh * tau);
    a[pp][l] = apply ? new_pp : app;
    a[qq][l] = apply ? new_qq : aqq;
    a[pq][l] = apply ? 0. : apq;
    a[qp][l] = apply ? 0. : apq;
    a[op][l] = apply ? new_op : g;
    a[po][l] = apply ? new_op : g;
    a[oq][l] = apply ? new_oq : hh;
    a[qo][l] = apply ? new_oq : hh;
    const double vg0 = v[p][l], vh0 = v[q][l], vg1 = v[3 + p][l], vh1 = v[3 + q][l],
                 vg2 = v[6 + p][l], vh2 = v[6 + q][l];
    const double ng0 = vg0 - sn * (vh0 + vg0 * tau), nh0 = vh0 + sn * (vg0 - vh0 * tau);
    const double ng1 = vg1 - sn * (vh1 + vg1 * tau), nh1 = vh1 + sn * (vg1 - vh1 * tau);
    const double ng2 = vg2 - sn * (vh2 + vg2 * tau), nh2 = vh2 + sn * (vg2 - vh2 * tau);
    v[p][l] = apply ? ng0 : vg0;
    v[q][l] = apply ? nh0 : vh0;
    v[3 + p][l] = apply ? ng1 : vg1;
    v[3 + q][l] = apply ? nh1 : vh1;
    v[6 + p][l] = apply ? ng2 : vg2;
    v[6 + q][l] = apply ? nh2 : vh2;
  }
}
#endif

// r = closest_rotation(s) for every lane whose s is finite and scaled into [1/2, 1) (the caller
// does the scaling); lanes that closest_rotation() sends to the SVD get fallback != 0
CGAL_LAPDEF_KERNEL_ATTR inline void closest_rotation(const double (&s)[9][lanes], double (&r)[9][lanes],
                                                     std::int64_t (&fallback)[lanes])
{
  CGAL_LAPDEF_NO_CONTRACT
  Jacobi_work w;
  double(&a)[9][lanes] = w.a;
  double(&v)[9][lanes] = w.v;
  double(&x1)[lanes] = w.x1;
  double(&x2)[lanes] = w.x2;
  std::int64_t(&done)[lanes] = w.done;
  double(&e1)[3][lanes] = w.e1;
  double(&e2)[3][lanes] = w.e2;
  double(&b1)[3][lanes] = w.b1;
  double(&b2)[3][lanes] = w.b2;
  // a = s^T s
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      for(int l = 0; l < lanes; ++l)
        a[3 * i + j][l] = (s[i][l] * s[j][l] + s[3 + i][l] * s[3 + j][l]) + s[6 + i][l] * s[6 + j][l];
  for(int k = 0; k < 9; ++k)
    for(int l = 0; l < lanes; ++l)
      v[k][l] = (k % 4 == 0) ? 1. : 0.;
  for(int l = 0; l < lanes; ++l)
    done[l] = 0;
  // symmetric_eigen_jacobi_3(a, v): a lane stops where the scalar loop returns (a lane that is
  // done is left as it is while the others go on); each rotation for every group of jsub lanes
  for(int sweep = 0; sweep < 24; ++sweep)
  {
    for(int l = 0; l < lanes; ++l)
    {
      const double off = a[1][l] * a[1][l] + a[2][l] * a[2][l] + a[5][l] * a[5][l];
      const double diag = a[0][l] * a[0][l] + a[4][l] * a[4][l] + a[8][l] * a[8][l];
      done[l] = (done[l] != 0 || !(off > 1e-32 * diag)) ? 1 : 0;
    }
    std::int64_t all_done = 1;
    for(int l = 0; l < lanes; ++l)
      all_done &= done[l];
    if(all_done)
      break;
    for(int l0 = 0; l0 < lanes; l0 += jsub)
      jacobi_rotation<0, 1>(w, l0);
    for(int l0 = 0; l0 < lanes; l0 += jsub)
      jacobi_rotation<0, 2>(w, l0);
    for(int l0 = 0; l0 < lanes; l0 += jsub)
      jacobi_rotation<1, 2>(w, l0);
  }

  // `sub` lanes at a time (as many as one vector register holds)
  for(int l0 = 0; l0 < lanes; l0 += sub)
  {
    // the eigenvectors of the two largest eigenvalues, then u1 = s v1 / |s v1|
    for(int l = l0; l < l0 + sub; ++l)
    {
      double d0 = a[0][l], d1 = a[4][l], d2 = a[8][l];
      double c0[3] = {v[0][l], v[3][l], v[6][l]}, c1[3] = {v[1][l], v[4][l], v[7][l]},
             c2[3] = {v[2][l], v[5][l], v[8][l]};
      bool m = d0 < d1;
      double y = m ? d0 : d1;
      d0 = m ? d1 : d0;
      d1 = y;
      for(int j = 0; j < 3; ++j)
      {
        const double z = m ? c0[j] : c1[j];
        c0[j] = m ? c1[j] : c0[j];
        c1[j] = z;
      }
      m = d1 < d2;
      y = m ? d1 : d2;
      d1 = m ? d2 : d1;
      d2 = y;
      for(int j = 0; j < 3; ++j)
      {
        const double z = m ? c1[j] : c2[j];
        c1[j] = m ? c2[j] : c1[j];
        c2[j] = z;
      }
      m = d0 < d1;
      for(int j = 0; j < 3; ++j)
      {
        const double z = m ? c0[j] : c1[j];
        c0[j] = m ? c1[j] : c0[j];
        c1[j] = z;
      }
      for(int j = 0; j < 3; ++j)
      {
        e1[j][l] = c0[j];
        e2[j][l] = c1[j];
      }
      b1[0][l] = (s[0][l] * c0[0] + s[1][l] * c0[1]) + s[2][l] * c0[2];
      b1[1][l] = (s[3][l] * c0[0] + s[4][l] * c0[1]) + s[5][l] * c0[2];
      b1[2][l] = s[6][l] * c0[0] + (s[7][l] * c0[1] + s[8][l] * c0[2]);
      x1[l] = (b1[0][l] * b1[0][l] + b1[1][l] * b1[1][l]) + b1[2][l] * b1[2][l];
    }
    sqrt_sub(x1 + l0);
    // u2 = the part of s v2 orthogonal to u1, normalised
    for(int l = l0; l < l0 + sub; ++l)
    {
      const double n1 = x1[l];
      for(int j = 0; j < 3; ++j)
        b1[j][l] = b1[j][l] / n1;
      const double c0 = e2[0][l], c1 = e2[1][l], c2 = e2[2][l];
      double y0 = (s[0][l] * c0 + s[1][l] * c1) + s[2][l] * c2;
      double y1 = (s[3][l] * c0 + s[4][l] * c1) + s[5][l] * c2;
      double y2 = s[6][l] * c0 + (s[7][l] * c1 + s[8][l] * c2);
      const double d = (b1[0][l] * y0 + b1[1][l] * y1) + b1[2][l] * y2;
      y0 = y0 - d * b1[0][l];
      y1 = y1 - d * b1[1][l];
      y2 = y2 - d * b1[2][l];
      b2[0][l] = y0;
      b2[1][l] = y1;
      b2[2][l] = y2;
      x2[l] = (y0 * y0 + y1 * y1) + y2 * y2;
    }
    sqrt_sub(x2 + l0);
    // R = [u1 u2 u1 x u2] [v1 v2 v1 x v2]^T; identity where s v1 = 0
    for(int l = l0; l < l0 + sub; ++l)
    {
      const double n1 = x1[l], n2 = x2[l];
      const bool zero = n1 == 0;
      const bool svd = !(n2 > 1e-2 * n1) || !(n1 <= 1.7976931348623157e308);
      fallback[l] = (fallback[l] != 0 || (!zero && svd)) ? 1 : 0;
      double u[3][3], w[3][3];   // u[i][k] = U(i, k), w[j][k] = W(j, k)
      for(int j = 0; j < 3; ++j)
      {
        u[j][0] = b1[j][l];
        u[j][1] = b2[j][l] / n2;
        w[j][0] = e1[j][l];
        w[j][1] = e2[j][l];
      }
      u[0][2] = u[1][0] * u[2][1] - u[2][0] * u[1][1];
      u[1][2] = u[2][0] * u[0][1] - u[0][0] * u[2][1];
      u[2][2] = u[0][0] * u[1][1] - u[1][0] * u[0][1];
      w[0][2] = w[1][0] * w[2][1] - w[2][0] * w[1][1];
      w[1][2] = w[2][0] * w[0][1] - w[0][0] * w[2][1];
      w[2][2] = w[0][0] * w[1][1] - w[1][0] * w[0][1];
      for(int j = 0; j < 3; ++j)
      {
        const double r0 = (u[0][0] * w[j][0] + u[0][1] * w[j][1]) + u[0][2] * w[j][2];
        const double r1 = (u[1][0] * w[j][0] + u[1][1] * w[j][1]) + u[1][2] * w[j][2];
        const double r2 = u[2][0] * w[j][0] + (u[2][1] * w[j][1] + u[2][2] * w[j][2]);
        r[j][l] = zero ? (j == 0 ? 1. : 0.) : r0;
        r[3 + j][l] = zero ? (j == 1 ? 1. : 0.) : r1;
        r[6 + j][l] = zero ? (j == 2 ? 1. : 0.) : r2;
      }
    }
  }
}

// c = a * b (3x3, Eigen's order)
CGAL_LAPDEF_KERNEL_ATTR inline void multiply(const double (&a)[9][lanes], const double (&b)[9][lanes],
                                             double (&c)[9][lanes])
{
  CGAL_LAPDEF_NO_CONTRACT
  for(int l = 0; l < lanes; ++l)
    for(int j = 0; j < 3; ++j)
    {
      const double c0 = (a[0][l] * b[j][l] + a[1][l] * b[3 + j][l]) + a[2][l] * b[6 + j][l];
      const double c1 = (a[3][l] * b[j][l] + a[4][l] * b[3 + j][l]) + a[5][l] * b[6 + j][l];
      const double c2 = a[6][l] * b[j][l] + (a[7][l] * b[3 + j][l] + a[8][l] * b[6 + j][l]);
      c[j][l] = c0;
      c[3 + j][l] = c1;
      c[6 + j][l] = c2;
    }
}

// f = m e for spoke i of every lane (Eigen's order for a 3x3 matrix times a vector)
#define CGAL_LAPDEF_MAT_VEC(m, e0, e1, e2, f0, f1, f2)                                         \
  const double f0 = ((m)[0][l] * (e0) + (m)[1][l] * (e1)) + (m)[2][l] * (e2);                  \
  const double f1 = ((m)[3][l] * (e0) + (m)[4][l] * (e1)) + (m)[5][l] * (e2);                  \
  const double f2 = (m)[6][l] * (e0) + ((m)[7][l] * (e1) + (m)[8][l] * (e2))

// t = Scale_fit::isotropic(cell, r) * r
CGAL_LAPDEF_KERNEL_ATTR inline void similarity(Lanes& b)
{
  CGAL_LAPDEF_NO_CONTRACT
  alignas(64) double num[lanes], den[lanes];
  for(int l = 0; l < lanes; ++l)
    num[l] = den[l] = 0.;
  const std::size_t d = b.max_degree;
  for(std::size_t i = 0; i < d; ++i)
  {
    const double *e = b.rest + 3 * i * lanes, *ep = b.current + 3 * i * lanes, *c = b.weight + i * lanes;
    for(int l = 0; l < lanes; ++l)
    {
      CGAL_LAPDEF_MAT_VEC(b.r, e[l], e[lanes + l], e[2 * lanes + l], f0, f1, f2);
      const double dn = c[l] * ((ep[l] * f0 + ep[lanes + l] * f1) + ep[2 * lanes + l] * f2);
      const double dd = c[l] * ((f0 * f0 + f1 * f1) + f2 * f2);
      num[l] = num[l] + dn;
      den[l] = den[l] + dd;
    }
  }
  for(int l = 0; l < lanes; ++l)
  {
    const double q = num[l] / den[l];
    const double k = den[l] > 0 ? CGAL_LAPDEF_CLAMP(q) : 1.;
    for(int j = 0; j < 9; ++j)
      b.t[j][l] = k * b.r[j][l];
  }
}

// sc = Scale_fit::along_axes(cell, r, axes) (along_world_axes(cell, r) without `axes`)
CGAL_LAPDEF_KERNEL_ATTR inline void scales_along_axes(Lanes& b, const double (*axes)[lanes], double (&sc)[3][lanes])
{
  CGAL_LAPDEF_NO_CONTRACT
  alignas(64) double num[3][lanes], den[3][lanes], total[lanes], iso_num[lanes];
  for(int l = 0; l < lanes; ++l)
  {
    for(int k = 0; k < 3; ++k)
      num[k][l] = den[k][l] = 0.;
    total[l] = iso_num[l] = 0.;
  }
  const std::size_t d = b.max_degree;
  for(std::size_t i = 0; i < d; ++i)
  {
    const double *e = b.rest + 3 * i * lanes, *ep = b.current + 3 * i * lanes, *c = b.weight + i * lanes;
    for(int l = 0; l < lanes; ++l)
    {
      const double p0 = ep[l], p1 = ep[lanes + l], p2 = ep[2 * lanes + l];
      CGAL_LAPDEF_MAT_VEC(b.r, e[l], e[lanes + l], e[2 * lanes + l], f0, f1, f2);
      double fa[3] = {f0, f1, f2}, ea[3] = {p0, p1, p2};
      if(axes != nullptr)
        for(int k = 0; k < 3; ++k)
        {
          fa[k] = (axes[k][l] * f0 + axes[3 + k][l] * f1) + axes[6 + k][l] * f2;
          ea[k] = (axes[k][l] * p0 + axes[3 + k][l] * p1) + axes[6 + k][l] * p2;
        }
      for(int k = 0; k < 3; ++k)
      {
        const double dn = c[l] * (ea[k] * fa[k]), dd = c[l] * (fa[k] * fa[k]);
        num[k][l] = num[k][l] + dn;
        den[k][l] = den[k][l] + dd;
      }
      const double dt = c[l] * ((f0 * f0 + f1 * f1) + f2 * f2);
      const double di = c[l] * ((p0 * f0 + p1 * f1) + p2 * f2);
      total[l] = total[l] + dt;
      iso_num[l] = iso_num[l] + di;
    }
  }
  for(int l = 0; l < lanes; ++l)
  {
    const bool seen = total[l] > 0;
    const double iq = iso_num[l] / total[l];
    const double iso = CGAL_LAPDEF_CLAMP(iq);
    for(int k = 0; k < 3; ++k)
    {
      const double q = num[k][l] / den[k][l];
      const double cq = CGAL_LAPDEF_CLAMP(q);
      const double sk = den[k][l] > Scale_fit::axis_guard * total[l] ? cq : iso;
      sc[k][l] = seen ? sk : 1.;
    }
  }
}

// t = Scale_fit::along_world_axes(cell, r).asDiagonal() * r
CGAL_LAPDEF_KERNEL_ATTR inline void scaled_rotation(Lanes& b)
{
  CGAL_LAPDEF_NO_CONTRACT
  alignas(64) double sc[3][lanes];
  scales_along_axes(b, nullptr, sc);
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      for(int l = 0; l < lanes; ++l)
        b.t[3 * i + j][l] = sc[i][l] * b.r[3 * i + j][l];
}

// Anchored_scaled_rotation_transform: t = diag(s) r, s anchored at 1
CGAL_LAPDEF_KERNEL_ATTR inline void anchored_scaled_rotation(Lanes& b, double anchor)
{
  CGAL_LAPDEF_NO_CONTRACT
  alignas(64) double num[3][lanes], den[3][lanes];
  for(int k = 0; k < 3; ++k)
    for(int l = 0; l < lanes; ++l)
      num[k][l] = den[k][l] = 0.;
  const std::size_t d = b.max_degree;
  for(std::size_t i = 0; i < d; ++i)
  {
    const double *e = b.rest + 3 * i * lanes, *ep = b.current + 3 * i * lanes, *c = b.weight + i * lanes;
    for(int l = 0; l < lanes; ++l)
    {
      CGAL_LAPDEF_MAT_VEC(b.r, e[l], e[lanes + l], e[2 * lanes + l], f0, f1, f2);
      const double fa[3] = {f0, f1, f2};
      for(int k = 0; k < 3; ++k)
      {
        const double dn = c[l] * (ep[k * lanes + l] * fa[k]), dd = c[l] * (fa[k] * fa[k]);
        num[k][l] = num[k][l] + dn;
        den[k][l] = den[k][l] + dd;
      }
    }
  }
  for(int l = 0; l < lanes; ++l)
  {
    const double prior = anchor * ((den[0][l] + den[1][l]) + den[2][l]) / 3;
    const bool keep = !(prior > 0);
    for(int i = 0; i < 3; ++i)
    {
      const double q = (num[i][l] + prior) / (den[i][l] + prior);
      const double si = CGAL_LAPDEF_CLAMP(q);
      for(int j = 0; j < 3; ++j)
      {
        const double scaled = si * b.r[3 * i + j][l];
        b.t[3 * i + j][l] = keep ? b.r[3 * i + j][l] : scaled;
      }
    }
  }
}

// Principal_scaled_rotation_transform: t = U diag(s) U^T r with U = r q (q: the rest axes)
CGAL_LAPDEF_KERNEL_ATTR inline void principal_scaled_rotation(Lanes& b)
{
  CGAL_LAPDEF_NO_CONTRACT
  alignas(64) double u[9][lanes], sc[3][lanes];
  multiply(b.r, b.q, u);
  scales_along_axes(b, u, sc);
  for(int l = 0; l < lanes; ++l)
  {
    const double p = sc[0][l] * sc[1][l];
    sc[2][l] = p;
  }
  for(int l0 = 0; l0 < lanes; l0 += sub)
    sqrt_sub(sc[2] + l0);
  // t = ((u diag(s)) u^T) r; in this chain Eigen sums the inner product as a0 + (a1 + a2) and
  // the outer one left to right, in every row
  for(int l = 0; l < lanes; ++l)
  {
    double us[3][3], m[3][3];
    for(int i = 0; i < 3; ++i)
      for(int k = 0; k < 3; ++k)
        us[i][k] = u[3 * i + k][l] * sc[k][l];
    for(int i = 0; i < 3; ++i)
      for(int j = 0; j < 3; ++j)
        m[i][j] = us[i][0] * u[3 * j][l] + (us[i][1] * u[3 * j + 1][l] + us[i][2] * u[3 * j + 2][l]);
    for(int i = 0; i < 3; ++i)
      for(int j = 0; j < 3; ++j)
        b.t[3 * i + j][l] = (m[i][0] * b.r[j][l] + m[i][1] * b.r[3 + j][l]) + m[i][2] * b.r[6 + j][l];
  }
}

// Rotation_scale_rotation_transform, first half: s = sum c e' (t e)^T with t = S R1 (in b.t)
CGAL_LAPDEF_KERNEL_ATTR inline void second_covariance(Lanes& b)
{
  CGAL_LAPDEF_NO_CONTRACT
  for(int k = 0; k < 9; ++k)
    for(int l = 0; l < lanes; ++l)
      b.s[k][l] = 0.;
  const std::size_t d = b.max_degree;
  for(std::size_t i = 0; i < d; ++i)
  {
    const double *e = b.rest + 3 * i * lanes, *ep = b.current + 3 * i * lanes, *c = b.weight + i * lanes;
    for(int l = 0; l < lanes; ++l)
    {
      CGAL_LAPDEF_MAT_VEC(b.t, e[l], e[lanes + l], e[2 * lanes + l], f0, f1, f2);
      const double fa[3] = {f0, f1, f2};
      for(int x = 0; x < 3; ++x)
      {
        const double cx = c[l] * ep[x * lanes + l];
        for(int y = 0; y < 3; ++y)
        {
          b.s[3 * x + y][l] = b.s[3 * x + y][l] + cx * fa[y];
        }
      }
    }
  }
}

// s = Transform_cell::covariance() = sum c e' e^T, in the same order
CGAL_LAPDEF_KERNEL_ATTR inline void covariance(Lanes& b)
{
  CGAL_LAPDEF_NO_CONTRACT
  for(int k = 0; k < 9; ++k)
    for(int l = 0; l < lanes; ++l)
      b.s[k][l] = 0.;
  const std::size_t d = b.max_degree;
  for(std::size_t i = 0; i < d; ++i)
  {
    const double *e = b.rest + 3 * i * lanes, *ep = b.current + 3 * i * lanes, *c = b.weight + i * lanes;
    for(int l = 0; l < lanes; ++l)
    {
      for(int x = 0; x < 3; ++x)
      {
        const double cx = c[l] * ep[x * lanes + l];
        for(int y = 0; y < 3; ++y)
        {
          b.s[3 * x + y][l] = b.s[3 * x + y][l] + cx * e[y * lanes + l];
        }
      }
    }
  }
}

// The spokes of the cells of the nodes node[0], ..., node[m - 1] (m <= lanes) into the lanes of
// `b`, set up by begin_lanes(b, m, d, spokes): for lane l and spoke i below the cell's degree,
// e = rest(a) - rest(n_i) and e' = current(a) - current(n_i), both multiplied by the power of two
// of the lane's largest coordinate (normalizing_power_of_two(), NaN coordinates skipped), and the
// weight max(w_i, 0) unscaled; zeros (+0) past the lane's degree and in the lanes from m on.
// Sets b.degree. Bitwise what Deformation_core::gather_cell() computes for each cell (test
// BatchedTransforms.GatherLanesMatchesTheCellGather). `scratch`: 8 d lanes doubles.
// With AVX2 and AVX-512, each spoke is one vector subtraction of two node records
// (current and rest together), written to `scratch` cell by cell; the lanes' rows are then
// transposed from it 8 lanes at a time (shuffles, no gather instruction: vector gathers were
// slower than scalar loads on the Intel Xeon where this was measured).
CGAL_LAPDEF_KERNEL_ATTR inline void gather_lanes(const Gather_input& in, const std::size_t* node, int m, Lanes& b,
                                                 double* spokes, double* scratch)
{
  CGAL_LAPDEF_NO_CONTRACT
  const std::size_t d = b.max_degree;
  double *rest = spokes, *current = spokes + 3 * d * lanes, *weight = spokes + 6 * d * lanes;
  constexpr std::size_t rec = Gather_input::record;
#if CGAL_LAPDEF_KERNEL_ISA >= 2
#if CGAL_LAPDEF_KERNEL_ISA == 3
  // the masked forms with a full mask: GCC 12 warns (-Wmaybe-uninitialized) on the plain
  // unpack and max intrinsics, which start from _mm512_undefined_pd()
  const __mmask8 all = 0xFF;
#endif
  static_assert(lanes == 8 && rec == 8, "one AVX-512 register (two AVX2 registers) per record and per lane row");
  // pass 1, cell by cell: scratch[(l d + i) 8 + k] = record(a) - record(n_i), k < 6 (current,
  // then rest; 0 at k = 6, 7 and past the degree), and the lane's power of two
  alignas(64) double unit[lanes];
  for(int l = 0; l < lanes; ++l)
  {
    double* g = scratch + std::size_t(l) * d * rec;
    std::size_t degree = 0, first = 0, a = 0;
    if(l < m)
    {
      a = node[l];
      first = in.neighbor_start[a];
      degree = in.neighbor_start[a + 1] - first;
    }
    b.degree[l] = std::int64_t(degree);
    double largest = 0;
#if CGAL_LAPDEF_KERNEL_ISA == 3
    const __m512d zero = _mm512_setzero_pd();
    if(degree > 0)
    {
      const __m512d xa = _mm512_maskz_loadu_pd(0x3F, in.node + a * rec);
      __m512d big = zero;
      for(std::size_t i = 0; i < degree; ++i)
      {
        const std::size_t nb = in.neighbor[first + i];
        const __m512d dn = _mm512_maskz_sub_pd(0x3F, xa, _mm512_maskz_loadu_pd(0x3F, in.node + nb * rec));
        // max(|x|, largest): largest where x is NaN, as std::max(largest, |x|)
        big = _mm512_maskz_max_pd(all, _mm512_abs_pd(dn), big);
        _mm512_storeu_pd(g + i * rec, dn);
        {
          const double w = in.weight[first + i];   // std::max(w, 0.) (not a call: see CGAL_LAPDEF_MAX)
          weight[i * lanes + std::size_t(l)] = w < 0. ? 0. : w;
        }
      }
      alignas(64) double m8[8];   // of non-negative numbers: any order gives the same maximum
      _mm512_store_pd(m8, big);
      largest = CGAL_LAPDEF_MAX(CGAL_LAPDEF_MAX(CGAL_LAPDEF_MAX(m8[0], m8[1]), CGAL_LAPDEF_MAX(m8[2], m8[3])),
                                CGAL_LAPDEF_MAX(m8[4], m8[5]));
    }
    for(std::size_t i = degree; i < d; ++i)
    {
      _mm512_storeu_pd(g + i * rec, zero);
      weight[i * lanes + std::size_t(l)] = 0.;
    }
#else
    const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.);
    const __m256i low_two = _mm256_setr_epi64x(-1, -1, 0, 0);
    if(degree > 0)
    {
      const __m256d xa0 = _mm256_loadu_pd(in.node + a * rec), xa1 = _mm256_maskload_pd(in.node + a * rec + 4, low_two);
      __m256d big0 = zero, big1 = zero;
      for(std::size_t i = 0; i < degree; ++i)
      {
        const double* n = in.node + std::size_t(in.neighbor[first + i]) * rec;
        const __m256d d0 = _mm256_sub_pd(xa0, _mm256_loadu_pd(n)),
                      d1 = _mm256_sub_pd(xa1, _mm256_maskload_pd(n + 4, low_two));
        // max(|x|, largest): largest where x is NaN, as std::max(largest, |x|)
        big0 = _mm256_max_pd(_mm256_andnot_pd(sign, d0), big0);
        big1 = _mm256_max_pd(_mm256_andnot_pd(sign, d1), big1);
        _mm256_storeu_pd(g + i * rec, d0);
        _mm256_storeu_pd(g + i * rec + 4, d1);
        {
          const double w = in.weight[first + i];   // std::max(w, 0.) (not a call: see CGAL_LAPDEF_MAX)
          weight[i * lanes + std::size_t(l)] = w < 0. ? 0. : w;
        }
      }
      alignas(32) double m0[4], m1[4];
      _mm256_store_pd(m0, big0);
      _mm256_store_pd(m1, big1);
      largest = CGAL_LAPDEF_MAX(CGAL_LAPDEF_MAX(CGAL_LAPDEF_MAX(m0[0], m0[1]), CGAL_LAPDEF_MAX(m0[2], m0[3])),
                                CGAL_LAPDEF_MAX(m1[0], m1[1]));
    }
    for(std::size_t i = degree; i < d; ++i)
    {
      _mm256_storeu_pd(g + i * rec, zero);
      _mm256_storeu_pd(g + i * rec + 4, zero);
      weight[i * lanes + std::size_t(l)] = 0.;
    }
#endif
    unit[l] = normalizing_power_of_two(largest);
  }
  // pass 2, spoke by spoke: the 8 lanes' differences transposed into rows (coordinate k of every
  // lane), multiplied by the lanes' powers of two; rows 0-2 are e', rows 3-5 e
#if CGAL_LAPDEF_KERNEL_ISA == 3
  const __m512d u = _mm512_load_pd(unit);
  const __m512i ia = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13), ib = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15),
                ic = _mm512_setr_epi64(0, 1, 2, 3, 8, 9, 10, 11), id = _mm512_setr_epi64(4, 5, 6, 7, 12, 13, 14, 15);
  const std::size_t lane_stride = d * rec;
  for(std::size_t i = 0; i < d; ++i)
  {
    const double* g = scratch + i * rec;
    __m512d r[8];
    for(int l = 0; l < 8; ++l)
      r[l] = _mm512_loadu_pd(g + std::size_t(l) * lane_stride);
    const __m512d t0 = _mm512_maskz_unpacklo_pd(all, r[0], r[1]), t1 = _mm512_maskz_unpackhi_pd(all, r[0], r[1]),
                  t2 = _mm512_maskz_unpacklo_pd(all, r[2], r[3]), t3 = _mm512_maskz_unpackhi_pd(all, r[2], r[3]),
                  t4 = _mm512_maskz_unpacklo_pd(all, r[4], r[5]), t5 = _mm512_maskz_unpackhi_pd(all, r[4], r[5]),
                  t6 = _mm512_maskz_unpacklo_pd(all, r[6], r[7]), t7 = _mm512_maskz_unpackhi_pd(all, r[6], r[7]);
    // u_k: coordinates k and k + 4 of lanes 0-3 (u0-u3) and 4-7 (u4-u7)
    const __m512d u0 = _mm512_permutex2var_pd(t0, ia, t2), u1 = _mm512_permutex2var_pd(t1, ia, t3),
                  u2 = _mm512_permutex2var_pd(t0, ib, t2), u3 = _mm512_permutex2var_pd(t1, ib, t3),
                  u4 = _mm512_permutex2var_pd(t4, ia, t6), u5 = _mm512_permutex2var_pd(t5, ia, t7),
                  u6 = _mm512_permutex2var_pd(t4, ib, t6), u7 = _mm512_permutex2var_pd(t5, ib, t7);
    const __m512d row[6] = {_mm512_permutex2var_pd(u0, ic, u4), _mm512_permutex2var_pd(u1, ic, u5),
                            _mm512_permutex2var_pd(u2, ic, u6), _mm512_permutex2var_pd(u3, ic, u7),
                            _mm512_permutex2var_pd(u0, id, u4), _mm512_permutex2var_pd(u1, id, u5)};
    for(std::size_t c = 0; c < 3; ++c)
    {
      _mm512_storeu_pd(current + (3 * i + c) * lanes, _mm512_mul_pd(row[c], u));
      _mm512_storeu_pd(rest + (3 * i + c) * lanes, _mm512_mul_pd(row[3 + c], u));
    }
  }
#else
  const std::size_t lane_stride = d * rec;
  for(int h = 0; h < 2; ++h)   // lanes 0-3, then 4-7
  {
    const __m256d u = _mm256_load_pd(unit + 4 * h);
    for(std::size_t i = 0; i < d; ++i)
    {
      const double* g = scratch + std::size_t(4 * h) * lane_stride + i * rec;
      __m256d r0[4], r1[4];   // coordinates 0-3 and 4-7 of the four lanes
      for(int l = 0; l < 4; ++l)
      {
        r0[l] = _mm256_loadu_pd(g + std::size_t(l) * lane_stride);
        r1[l] = _mm256_loadu_pd(g + std::size_t(l) * lane_stride + 4);
      }
      const __m256d t0 = _mm256_unpacklo_pd(r0[0], r0[1]), t1 = _mm256_unpackhi_pd(r0[0], r0[1]),
                    t2 = _mm256_unpacklo_pd(r0[2], r0[3]), t3 = _mm256_unpackhi_pd(r0[2], r0[3]),
                    s0 = _mm256_unpacklo_pd(r1[0], r1[1]), s1 = _mm256_unpackhi_pd(r1[0], r1[1]),
                    s2 = _mm256_unpacklo_pd(r1[2], r1[3]), s3 = _mm256_unpackhi_pd(r1[2], r1[3]);
      const __m256d row[6] = {_mm256_permute2f128_pd(t0, t2, 0x20), _mm256_permute2f128_pd(t1, t3, 0x20),
                              _mm256_permute2f128_pd(t0, t2, 0x31), _mm256_permute2f128_pd(t1, t3, 0x31),
                              _mm256_permute2f128_pd(s0, s2, 0x20), _mm256_permute2f128_pd(s1, s3, 0x20)};
      for(std::size_t c = 0; c < 3; ++c)
      {
        _mm256_storeu_pd(current + (3 * i + c) * lanes + std::size_t(4 * h), _mm256_mul_pd(row[c], u));
        _mm256_storeu_pd(rest + (3 * i + c) * lanes + std::size_t(4 * h), _mm256_mul_pd(row[3 + c], u));
      }
    }
  }
#endif
#else
  // one lane at a time: the cell's differences into `scratch` (contiguous) with its largest
  // coordinate, then written once, scaled, into the lanes; the lanes from m on were emptied by
  // begin_lanes()
  for(int l = 0; l < m; ++l)
  {
    const std::size_t a = node[l], first = in.neighbor_start[a], degree = in.neighbor_start[a + 1] - first;
    b.degree[l] = std::int64_t(degree);
    const double* xa = in.node + a * rec;
    double largest[6] = {0, 0, 0, 0, 0, 0};
    for(std::size_t i = 0; i < degree; ++i)
    {
      const double* n = in.node + std::size_t(in.neighbor[first + i]) * rec;
      for(std::size_t k = 0; k < 6; ++k)
      {
        const double x = xa[k] - n[k];
        scratch[6 * i + k] = x;
        largest[k] = CGAL_LAPDEF_MAX(largest[k], CGAL_LAPDEF_FABS(x));
      }
      {
          const double w = in.weight[first + i];   // std::max(w, 0.) (not a call: see CGAL_LAPDEF_MAX)
          weight[i * lanes + std::size_t(l)] = w < 0. ? 0. : w;
        }
    }
    const double unit = normalizing_power_of_two(CGAL_LAPDEF_MAX(
        CGAL_LAPDEF_MAX(CGAL_LAPDEF_MAX(largest[0], largest[1]), CGAL_LAPDEF_MAX(largest[2], largest[3])),
        CGAL_LAPDEF_MAX(largest[4], largest[5])));
    for(std::size_t i = 0; i < d; ++i)
    {
      const bool on = i < degree;
      for(std::size_t c = 0; c < 3; ++c)
      {
        current[(3 * i + c) * lanes + std::size_t(l)] = on ? scratch[6 * i + c] * unit : 0.;
        rest[(3 * i + c) * lanes + std::size_t(l)] = on ? scratch[6 * i + 3 + c] * unit : 0.;
      }
      if(!on)
        weight[i * lanes + std::size_t(l)] = 0.;
    }
  }
#endif
}

#undef CGAL_LAPDEF_MAT_VEC
#undef CGAL_LAPDEF_CLAMP

// the stages the driver calls through dispatch()
CGAL_LAPDEF_KERNEL_ATTR inline void run_stage(Stage stage, Lanes& b)
{
  CGAL_LAPDEF_NO_CONTRACT
  switch(stage)
  {
  case Stage::covariance:
    covariance(b);
    break;
  case Stage::rotation:
    closest_rotation(b.s, b.r, b.fallback);
    for(int k = 0; k < 9; ++k)
      for(int l = 0; l < lanes; ++l)
        b.t[k][l] = b.r[k][l];
    break;
  case Stage::similarity:
    closest_rotation(b.s, b.r, b.fallback);
    similarity(b);
    break;
  case Stage::scaled_rotation:
    closest_rotation(b.s, b.r, b.fallback);
    scaled_rotation(b);
    break;
  case Stage::anchored_scaled_rotation:
    closest_rotation(b.s, b.r, b.fallback);
    anchored_scaled_rotation(b, b.anchor);
    break;
  case Stage::principal_scaled_rotation:
    closest_rotation(b.s, b.r, b.fallback);
    principal_scaled_rotation(b);
    break;
  case Stage::scaled_rotation_then_covariance:
    closest_rotation(b.s, b.r, b.fallback);
    scaled_rotation(b);
    second_covariance(b);
    break;
  case Stage::rotation_times_t:
    closest_rotation(b.s, b.r, b.fallback);
    {
      alignas(64) double rt[9][lanes];
      multiply(b.r, b.t, rt);
      for(int k = 0; k < 9; ++k)
        for(int l = 0; l < lanes; ++l)
          b.t[k][l] = rt[k][l];
    }
    break;
  }
}

} // namespace CGAL_LAPDEF_KERNEL_NS
