// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_ROTATION_START_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_ROTATION_START_H

#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// log of a unit quaternion as an axis-angle vector with the angle 2 atan2(|v|, w) in [0, 2 pi]:
// a quaternion keeps the winding of turns up to 360 degrees (a 270-degree turn stays 270)
inline Eigen::Vector3d quaternion_log(Eigen::Quaterniond q)
{
  q.normalize();
  const Eigen::Vector3d v = q.vec();
  const double n = v.norm();
  if(n == 0)
    return Eigen::Vector3d::Zero();
  return (2 * std::atan2(n, q.w()) / n) * v;
}

// log of a rotation matrix, angle in [0, pi]
inline Eigen::Vector3d rotation_log(const Eigen::Matrix3d& r)
{
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

// exp of an axis-angle vector; exactly the identity for the zero vector
inline Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& w)
{
  const double angle = w.norm();
  if(angle == 0)
    return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

// below this angle (radians) a group's rotation is taken as exactly none, so that a pure
// translation of the controls gives bitwise the identity start
constexpr double start_rotation_snap = 1e-12;

// The rotation of one control group from its rest and target positions: the closest rotation
// of sum_v (t_v - c')(p_v - c)^T (unit weights), as an axis-angle vector. A group whose
// covariance has rank below 2 (one vertex, collinear vertices) does not determine a rotation:
// zero. Returns false if the positions are not finite.
inline bool group_rotation_log(const std::vector<std::size_t>& group, const std::vector<Eigen::Vector3d>& rest,
                               const std::vector<Eigen::Vector3d>& target, Eigen::Vector3d& omega)
{
  omega.setZero();
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for(std::size_t v : group)
  {
    c += rest[v];
    ct += target[v];
  }
  c /= double(group.size());
  ct /= double(group.size());
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for(std::size_t v : group)
    s += (target[v] - ct) * (rest[v] - c).transpose();
  if(!s.allFinite())
    return false;
  const double scale = s.cwiseAbs().maxCoeff();
  if(!(scale > 0))
    return true;
  s /= scale;                                      // the rotation is scale-invariant; keeps S^T S finite
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s);
  const Eigen::Vector3d sigma = svd.singularValues();
  if(!(sigma[1] > 1e-9 * sigma[0]))
    return true;
  omega = rotation_log(closest_rotation_svd(s));
  if(!(omega.norm() > start_rotation_snap))
    omega.setZero();
  return true;
}

// The harmonic fields of the rotation-aware start: per control group g (a connected component of
// the control vertices), phi_g with L phi_g = 0 at the free vertices of the region of interest,
// phi_g = 1 on group g, 0 on the other groups and on the fixed vertices. L has non-negative
// weights (clamped cotangent weights of the rest mesh, floored at 1e-3 of their mean so that
// every mesh edge couples its vertices), so 0 <= phi_g <= 1 and sum_g phi_g <= 1. The matrix
// depends only on the region and the controls: it is factored once in build(). By linearity the
// blended log-rotation field sum_g phi_g omega_g is one solve with three right-hand sides.
class Rotation_start_field
{
public:
  static constexpr double weight_floor = 1e-3;   // relative to the mean positive edge weight
  static constexpr double cotangent_bound = 1e5; // |cot| clamp for degenerate triangles

  // `roi`: the ROI's vertex descriptors; `is_control[i]`, `rest[i]` per vertex index.
  template <class TriangleMesh, class VertexIndexMap, class VertexRange>
  bool build(const TriangleMesh& tm, const VertexIndexMap& vim, const VertexRange& roi,
             const std::vector<unsigned char>& is_control, const std::vector<Eigen::Vector3d>& rest)
  {
    typedef boost::graph_traits<TriangleMesh> GT;
    typedef typename GT::halfedge_descriptor halfedge_descriptor;
    const std::size_t n = rest.size();
    m_ready = false;
    // the per-vertex arrays are kept from build to build, -1 but at the vertices the last build
    // wrote (listed in m_written, cleared here): a build costs what the ROI costs, not the mesh
    if(m_group.size() != n)
    {
      m_group.assign(n, -1);
      m_unknown.assign(n, -1);
    }
    else
      for(std::size_t i : m_written)
        m_group[i] = m_unknown[i] = -1;
    m_written.clear();
    m_groups.clear();
    m_unknowns.clear();
    m_couplings.clear();
    auto idx = [&](auto v) { return std::size_t(get(vim, v)); };

    // the ROI's unknowns, and its controls numbered in ROI order (their number in m_group until
    // the groups replace it)
    std::vector<typename GT::vertex_descriptor> roi_vertices, controls;
    for(auto v : roi)
      roi_vertices.push_back(v);
    for(auto v : roi_vertices)
    {
      const std::size_t i = idx(v);
      m_written.push_back(i);
      if(is_control[i])
      {
        m_group[i] = long(controls.size());
        controls.push_back(v);
      }
      else
      {
        m_unknown[i] = long(m_unknowns.size());
        m_unknowns.push_back(i);
      }
    }
    // control groups: connected components of the controls along mesh edges (the controls are ROI
    // vertices), found over the controls' numbers
    std::vector<std::size_t> parent(controls.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    auto find = [&parent](std::size_t k) {
      while(parent[k] != k)
        k = parent[k] = parent[parent[k]];
      return k;
    };
    for(std::size_t k = 0; k < controls.size(); ++k)
    {
      const auto v = controls[k];
      if(halfedge(v, tm) == GT::null_halfedge())
        continue;
      for(halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
      {
        const std::size_t j = idx(source(h, tm));
        if(is_control[j] && m_group[j] >= 0)
          parent[find(k)] = find(std::size_t(m_group[j]));
      }
    }
    // the groups, numbered in the ROI order of their first control
    std::vector<long> root_group(controls.size(), -1);
    for(std::size_t k = 0; k < controls.size(); ++k)
    {
      long& g = root_group[find(k)];
      if(g < 0)
      {
        g = long(m_groups.size());
        m_groups.emplace_back();
      }
      m_groups[std::size_t(g)].push_back(idx(controls[k]));
    }
    for(std::size_t k = 0; k < controls.size(); ++k)
      m_group[idx(controls[k])] = root_group[find(k)];

    // edge weights around the unknowns: (cot of the angles opposite the edge) / 2, clamped at 0
    auto cot_opposite = [&](halfedge_descriptor h) {
      if(is_border(h, tm) || next(next(next(h, tm), tm), tm) != h)
        return 0.;                                       // border or polygon face: no angle
      const Eigen::Vector3d &a = rest[idx(source(h, tm))], &b = rest[idx(target(h, tm))],
                            &c = rest[idx(target(next(h, tm), tm))];
      Eigen::Vector3d u = a - c, w = b - c;
      const double extent = (std::max)(u.cwiseAbs().maxCoeff(), w.cwiseAbs().maxCoeff());
      if(extent > 0 && std::isfinite(extent))
      {
        u /= extent;                                    // the cotangent is scale-invariant
        w /= extent;
      }
      const double cross = u.cross(w).norm(), dot = u.dot(w);
      if(!(cross > 0))
        return dot > 0 ? cotangent_bound : (dot < 0 ? -cotangent_bound : 0.);
      return std::clamp(dot / cross, -cotangent_bound, cotangent_bound);
    };
    struct Spoke { std::size_t row, vertex; double weight; };
    std::vector<Spoke> spokes;
    double sum = 0;
    std::size_t positive = 0;
    for(auto v : roi_vertices)
    {
      const long r = m_unknown[idx(v)];
      if(r < 0 || halfedge(v, tm) == GT::null_halfedge())
        continue;
      for(halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
      {
        const double w = (std::max)(0.5 * (cot_opposite(h) + cot_opposite(opposite(h, tm))), 0.);
        if(!std::isfinite(w))
          return false;
        spokes.push_back({std::size_t(r), idx(source(h, tm)), w});
        if(w > 0)
        {
          sum += w;
          ++positive;
        }
      }
    }
    const double floor = positive > 0 ? weight_floor * sum / double(positive) : 1.;
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(spokes.size() + m_unknowns.size());
    std::vector<double> diagonal(m_unknowns.size(), 0.);
    for(const Spoke& s : spokes)
    {
      const double w = (std::max)(s.weight, floor);
      diagonal[s.row] += w;
      const long j = m_unknown[s.vertex];
      if(j >= 0)
        triplets.emplace_back(Eigen::Index(s.row), Eigen::Index(j), -w);
      else if(m_group[s.vertex] >= 0)
        m_couplings.push_back({s.row, std::size_t(m_group[s.vertex]), w});
    }
    for(std::size_t r = 0; r < m_unknowns.size(); ++r)
      triplets.emplace_back(Eigen::Index(r), Eigen::Index(r), diagonal[r] > 0 ? diagonal[r] : 1.);   // isolated: 0
    const Eigen::Index nu = Eigen::Index(m_unknowns.size());
    Eigen::SparseMatrix<double> l(nu, nu);
    l.setFromTriplets(triplets.begin(), triplets.end());
    if(nu > 0)
    {
      m_ldlt.compute(l);
      ++m_factorizations;
      if(m_ldlt.info() != Eigen::Success)
        return false;
    }
    m_ready = true;
    return true;
  }

  bool is_ready() const { return m_ready; }
  std::size_t number_of_groups() const { return m_groups.size(); }
  const std::vector<std::vector<std::size_t> >& groups() const { return m_groups; }
  std::size_t number_of_factorizations() const { return m_factorizations; }
  long group_of(std::size_t vertex) const { return m_group[vertex]; }
  // sets the ROI's entries of `values` back to 0 (after propagate())
  void clear_values(std::vector<Eigen::Vector3d>& values) const
  {
    for(std::size_t i : m_written)
      values[i] = Eigen::Vector3d::Zero();
  }

  // the vertex values of sum_g phi_g omega_g at the ROI's vertices, written into `values` (one
  // entry per vertex of the mesh; the others are left as they are: the caller keeps them 0, and
  // clear_values() sets the ROI's back to 0); false if the solve fails
  bool propagate(const std::vector<Eigen::Vector3d>& omega, std::vector<Eigen::Vector3d>& values) const
  {
    CGAL_precondition(values.size() == m_group.size());
    for(std::size_t g = 0; g < m_groups.size(); ++g)
      for(std::size_t v : m_groups[g])
        values[v] = omega[g];
    if(m_unknowns.empty())
      return true;
    Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(Eigen::Index(m_unknowns.size()), 3);
    for(const Coupling& c : m_couplings)
      rhs.row(Eigen::Index(c.row)) += c.weight * omega[c.group].transpose();
    const Eigen::MatrixX3d x = m_ldlt.solve(rhs);
    if(m_ldlt.info() != Eigen::Success || !x.allFinite())
      return false;
    for(std::size_t r = 0; r < m_unknowns.size(); ++r)
      values[m_unknowns[r]] = x.row(Eigen::Index(r)).transpose();
    return true;
  }

  // phi_g on every vertex (0 outside the ROI); false if the solve fails
  bool field(std::size_t g, std::vector<double>& phi) const
  {
    std::vector<Eigen::Vector3d> omega(m_groups.size(), Eigen::Vector3d::Zero()),
        values(m_group.size(), Eigen::Vector3d::Zero());
    omega[g] = Eigen::Vector3d::UnitX();
    if(!propagate(omega, values))
      return false;
    phi.resize(values.size());
    for(std::size_t v = 0; v < values.size(); ++v)
      phi[v] = values[v].x();
    return true;
  }

private:
  struct Coupling { std::size_t row, group; double weight; };
  std::vector<long> m_group;                        // per vertex: its control group, or -1
  std::vector<std::vector<std::size_t> > m_groups;  // per group: its vertex indices
  std::vector<long> m_unknown;                      // per vertex: its unknown index, or -1
  std::vector<std::size_t> m_written;               // the vertices whose m_group or m_unknown the last build set (the ROI)
  std::vector<std::size_t> m_unknowns;              // the ROI's non-control vertices
  std::vector<Coupling> m_couplings;                // unknown row -- control neighbour, weight
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double> > m_ldlt;
  std::size_t m_factorizations = 0;
  bool m_ready = false;
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_ROTATION_START_H
