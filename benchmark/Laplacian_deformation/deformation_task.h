// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_DEFORMATION_TASK_H
#define CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_DEFORMATION_TASK_H

// Deformation tasks of the comparison harness (benchmark/Laplacian_deformation/tasks/*.task):
// a mesh (a file of the data folder or a generated one), a region of interest (ROI), a handle and
// a transformation of the handle. The format is described in tasks/README.md; in short, one
// directive per line, '#' starts a comment:
//
//   title TEXT                              the caption of tables and figures
//   mesh FILE                               a mesh of the data folder (OFF, OBJ, PLY: the library's
//                                           checked reader; STL), or
//   generate bar LENGTH CELLS               box [0,LENGTH]x[0,1]x[0,1], CELLS cells per unit length
//   generate cylinder AROUND ALONG RADIUS HEIGHT   open tube around the z axis from z = 0 to HEIGHT
//   generate bumpy_plane CELLS AMPLITUDE WAVES     [0,1]^2, z = AMPLITUDE sin(2 pi WAVES x) sin(2 pi WAVES y)
//   selection FILE.sel                      Botsch08 selection of the data folder (ROI and handle)
//   handle selection | extreme DIR FRACTION | sphere X Y Z RADIUS
//   roi selection | all | all_but DIR FRACTION | geodesic RADIUS
//   transform def FILE.def | translate DX DY DZ | translate_diagonal DX DY DZ
//             | rotate AX AY AZ DEGREES [CX CY CZ]
//   measure bend DIR TUBE_RADIUS CX CY CZ RADIUS NX NY NZ
//   measure twist DIR POSITION IDEAL_DEGREES
//
// DIR is one of +x -x +y -y +z -z. "extreme DIR F": the vertices within F times the bounding-box
// extent along DIR of the extreme vertex in direction DIR. "all_but DIR F": every vertex but the
// ones within F times the extent of the extreme in direction DIR (all_but -y 0.05: all but the
// bottom 5%). "geodesic R": the vertices whose shortest edge path to the handle is at most R times
// the bounding-box diagonal. The handle is always part of the ROI. Transform directives compose in
// order; "rotate" turns about the centroid of the (already transformed) handle unless a centre is
// given; "translate_diagonal" is in units of the bounding-box diagonal.
//
// Task metrics (task_metrics() below), computed on slices: the vertices of equal rest coordinate
// along an axis (equal up to 1e-9 times the bounding-box diagonal).
//   measure bend DIR TUBE_RADIUS CX CY CZ RADIUS NX NY NZ: a tube along DIR (+z: the slices in
//     increasing z, the first one at the fixed end) meant to bend along the ideal arc of radius
//     RADIUS about the centre C in the plane through C normal to N, N oriented so that the
//     intended bend turns counter-clockwise about it (right-hand rule). The arc starts at the
//     rest centroid of the first slice and spans (rest length of the tube along DIR) / RADIUS
//     radians. bend_arc_error = the largest distance of the deformed slice centroids from that
//     arc, in units of TUBE_RADIUS; bend_min_turn_deg = the smallest signed angle about N
//     between successive centroid segments, in degrees (the intended bend is positive, a
//     negative value is an S).
//   measure twist DIR POSITION IDEAL_DEGREES: the slice of rest coordinate POSITION along DIR
//     (the one nearest to it). twist_mid_deg = the mean signed angle about DIR (right-hand rule)
//     from each slice vertex's rest offset to its deformed offset from the slice centroid (both
//     projected on the plane normal to DIR; vertices at the centroid skipped), in degrees in
//     (-180, 180]: the circular mean (the angle of the sum of the angles' unit vectors: the plain
//     mean when they agree, and no cancellation where they wrap at 180 degrees);
//     IDEAL_DEGREES is the intended angle (reported as twist_ideal_deg).
//     twist_mid_radius_ratio = the mean distance of the slice vertices from their centroid,
//     deformed / rest.
// volume_change = (V' - V) / V, the relative change of the enclosed volume, is computed for every
// closed mesh (no directive) and left empty for open ones.
//
// The parts: task_meshes.h (the mesh type, the generated meshes), task_reader.h (Task,
// read_task()), this header (Task_metrics, task_metrics()).

#include "task_reader.h"

#include <CGAL/boost/graph/helpers.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace Laplacian_deformation_benchmark {

/// The task metrics of a deformed mesh (NaN where not applicable; see the header comment).
struct Task_metrics
{
  double bend_arc_error = std::numeric_limits<double>::quiet_NaN();
  double bend_min_turn_deg = std::numeric_limits<double>::quiet_NaN();
  double twist_mid_deg = std::numeric_limits<double>::quiet_NaN();
  double twist_ideal_deg = std::numeric_limits<double>::quiet_NaN();
  double twist_mid_radius_ratio = std::numeric_limits<double>::quiet_NaN();
  double volume_change = std::numeric_limits<double>::quiet_NaN();
};

namespace internal {

// the slices of `m` along `axis`: groups of vertices of equal rest coordinate (up to `tolerance`),
// in increasing coordinate; `coordinate` receives each slice's rest coordinate
inline std::vector<std::vector<vertex_descriptor> > slices(const Mesh& m, int axis, double tolerance,
                                                           std::vector<double>& coordinate)
{
  std::vector<vertex_descriptor> order(vertices(m).begin(), vertices(m).end());
  std::sort(order.begin(), order.end(), [&](vertex_descriptor a, vertex_descriptor b) {
    return m.point(a)[axis] < m.point(b)[axis];
  });
  std::vector<std::vector<vertex_descriptor> > out;
  coordinate.clear();
  for(vertex_descriptor v : order)
  {
    const double c = m.point(v)[axis];
    if(out.empty() || c - coordinate.back() > tolerance)
    {
      out.emplace_back();
      coordinate.push_back(c);
    }
    out.back().push_back(v);
  }
  return out;
}

inline Eigen::Vector3d centroid(const Mesh& m, const std::vector<vertex_descriptor>& slice)
{
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for(vertex_descriptor v : slice)
    c += vec(m.point(v));
  return c / double(slice.size());
}

// signed angle from a to b about the unit vector n (right-hand rule), in radians
inline double signed_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& n)
{
  return std::atan2(a.cross(b).dot(n), a.dot(b));
}

// 6 x the signed volume enclosed by the triangles of m
inline double six_volume(const Mesh& m)
{
  double v = 0;
  for(auto f : faces(m))
  {
    std::vector<Eigen::Vector3d> p;
    for(vertex_descriptor w : CGAL::vertices_around_face(halfedge(f, m), m))
      p.push_back(vec(m.point(w)));
    for(std::size_t i = 1; i + 1 < p.size(); ++i)
      v += p[0].dot(p[i].cross(p[i + 1]));
  }
  return v;
}

} // namespace internal

/// The task metrics of `deformed` (the task's mesh with moved points; same vertices) against the
/// task's rest mesh: the bend and twist metrics of the task's "measure" directives and, for a
/// closed mesh, the relative volume change (see the header comment). NaN where not applicable.
inline Task_metrics task_metrics(const Task& task, const Mesh& deformed)
{
  using internal::vec;
  const double pi = 3.14159265358979323846;
  const Mesh& rest = task.mesh;
  Task_metrics out;
  Eigen::Vector3d lo = vec(rest.point(*vertices(rest).begin())), hi = lo;
  for(vertex_descriptor v : vertices(rest))
  {
    lo = lo.cwiseMin(vec(rest.point(v)));
    hi = hi.cwiseMax(vec(rest.point(v)));
  }
  const double tolerance = 1e-9 * (hi - lo).norm();
  if(task.bend_axis >= 0)
  {
    std::vector<double> coordinate;
    std::vector<std::vector<vertex_descriptor> > s = internal::slices(rest, task.bend_axis, tolerance, coordinate);
    if(task.bend_sign < 0)
    {
      std::reverse(s.begin(), s.end());
      std::reverse(coordinate.begin(), coordinate.end());
    }
    const Eigen::Vector3d& n = task.bend_normal;
    const Eigen::Vector3d& c = task.bend_centre;
    const double radius = task.bend_radius;
    // the ideal arc: from the first slice's rest centroid (projected on the plane), counter-clockwise about n
    Eigen::Vector3d u0 = internal::centroid(rest, s.front()) - c;
    u0 -= u0.dot(n) * n;
    u0.normalize();
    const double sweep = std::abs(coordinate.back() - coordinate.front()) / radius;
    const Eigen::Vector3d a = c + radius * u0;
    const Eigen::Vector3d b = c + radius * (std::cos(sweep) * u0 + std::sin(sweep) * n.cross(u0));
    std::vector<Eigen::Vector3d> centroids;
    double error = 0;
    for(const std::vector<vertex_descriptor>& slice : s)
    {
      const Eigen::Vector3d p = internal::centroid(deformed, slice);
      centroids.push_back(p);
      const Eigen::Vector3d q = p - c;
      const double h = q.dot(n);
      const Eigen::Vector3d in_plane = q - h * n;
      double theta = internal::signed_angle(u0, in_plane, n);
      if(theta < 0 && theta + 2 * pi <= sweep + 1e-12)
        theta += 2 * pi;
      double d;
      if(theta >= -1e-12 && theta <= sweep + 1e-12 && in_plane.norm() > 0)
        d = std::hypot(in_plane.norm() - radius, h);
      else
        d = std::min((p - a).norm(), (p - b).norm());
      error = std::max(error, d);
    }
    out.bend_arc_error = error / task.bend_tube_radius;
    double turn = std::numeric_limits<double>::infinity();
    for(std::size_t i = 0; i + 2 < centroids.size(); ++i)
      turn = std::min(turn, internal::signed_angle(centroids[i + 1] - centroids[i], centroids[i + 2] - centroids[i + 1], n));
    if(turn < std::numeric_limits<double>::infinity())
      out.bend_min_turn_deg = turn * 180. / pi;
  }
  if(task.twist_axis >= 0)
  {
    std::vector<double> coordinate;
    const std::vector<std::vector<vertex_descriptor> > s = internal::slices(rest, task.twist_axis, tolerance, coordinate);
    std::size_t k = 0;
    for(std::size_t i = 1; i < s.size(); ++i)
      if(std::abs(coordinate[i] - task.twist_position) < std::abs(coordinate[k] - task.twist_position))
        k = i;
    const std::vector<vertex_descriptor>& slice = s[k];
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    axis[task.twist_axis] = task.twist_sign;
    const Eigen::Vector3d c0 = internal::centroid(rest, slice), c1 = internal::centroid(deformed, slice);
    double sum_sin = 0, sum_cos = 0, r0 = 0, r1 = 0;
    std::size_t counted = 0;
    for(vertex_descriptor v : slice)
    {
      const Eigen::Vector3d a = vec(rest.point(v)) - c0, b = vec(deformed.point(v)) - c1;
      r0 += a.norm();
      r1 += b.norm();
      const Eigen::Vector3d pa = a - a.dot(axis) * axis, pb = b - b.dot(axis) * axis;
      if(pa.norm() > tolerance && pb.norm() > tolerance)
      {
        const double angle = internal::signed_angle(pa, pb, axis);
        sum_sin += std::sin(angle);
        sum_cos += std::cos(angle);
        ++counted;
      }
    }
    if(counted)
      out.twist_mid_deg = std::atan2(sum_sin, sum_cos) * 180. / pi;   // the circular mean
    out.twist_ideal_deg = task.twist_ideal;
    if(r0 > 0)
      out.twist_mid_radius_ratio = r1 / r0;
  }
  if(CGAL::is_closed(rest))
  {
    const double v0 = internal::six_volume(rest);
    if(v0 != 0)
      out.volume_change = (internal::six_volume(deformed) - v0) / v0;
  }
  return out;
}

} // namespace Laplacian_deformation_benchmark

#endif // CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_DEFORMATION_TASK_H
