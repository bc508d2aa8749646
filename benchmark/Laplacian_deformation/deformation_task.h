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
//   mesh FILE                               a mesh of the data folder (OFF, OBJ, PLY, STL), or
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

#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <sstream>
#include <string>
#include <vector>

namespace Laplacian_deformation_benchmark {

typedef CGAL::Simple_cartesian<double>                  Kernel;
typedef Kernel::Point_3                                 Point_3;
typedef CGAL::Surface_mesh<Point_3>                     Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor    vertex_descriptor;

/// A loaded task: the rest mesh, the ROI (handle included), the handle and its targets.
struct Task
{
  std::string name, title, mesh_description;
  Mesh mesh;
  std::vector<vertex_descriptor> roi, handle;
  std::vector<Point_3> targets;                 // one per handle vertex
  // "measure bend" (bend_axis >= 0): the tube's axis and direction, the ideal arc
  int bend_axis = -1;
  double bend_sign = 1, bend_tube_radius = 1, bend_radius = 1;
  Eigen::Vector3d bend_centre = Eigen::Vector3d::Zero(), bend_normal = Eigen::Vector3d::UnitY();
  // "measure twist" (twist_axis >= 0): the axis, direction, rest coordinate of the slice, ideal angle
  int twist_axis = -1;
  double twist_sign = 1, twist_position = 0, twist_ideal = 0;
};

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

typedef std::vector<std::array<double, 3> > Points;
typedef std::vector<std::vector<std::size_t> > Faces;

inline bool soup_to_mesh(Points points, Faces faces, Mesh& mesh, std::string& error)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<Point_3> p;
  for(const auto& q : points)
    p.emplace_back(q[0], q[1], q[2]);
  PMP::orient_polygon_soup(p, faces);
  mesh.clear();
  PMP::polygon_soup_to_polygon_mesh(p, faces, mesh);
  if(is_empty(mesh) || !CGAL::is_triangle_mesh(mesh))
    return error = "the generated mesh is not a triangle mesh", false;
  if(CGAL::is_closed(mesh) && !PMP::is_outward_oriented(mesh))
    PMP::reverse_face_orientations(mesh);
  return true;
}

// closed box [0,length]x[0,1]x[0,1], cells per unit length, every quad split in two triangles
inline bool bar_mesh(double length, int cells, Mesh& mesh, std::string& error)
{
  const int n[3] = {std::max(1, int(std::lround(length * cells))), cells, cells};
  const double step[3] = {length / n[0], 1. / n[1], 1. / n[2]};
  std::map<std::array<int, 3>, std::size_t> index;
  Points points;
  auto id = [&](std::array<int, 3> c) {
    const auto it = index.find(c);
    if(it != index.end())
      return it->second;
    points.push_back({{c[0] * step[0], c[1] * step[1], c[2] * step[2]}});
    return index[c] = points.size() - 1;
  };
  Faces faces;
  for(int axis = 0; axis < 3; ++axis)
  {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for(int side : {0, n[axis]})
      for(int i = 0; i < n[u]; ++i)
        for(int j = 0; j < n[v]; ++j)
        {
          std::array<int, 3> c00, c10, c11, c01;
          c00[axis] = c10[axis] = c11[axis] = c01[axis] = side;
          c00[u] = i; c00[v] = j; c10[u] = i + 1; c10[v] = j;
          c11[u] = i + 1; c11[v] = j + 1; c01[u] = i; c01[v] = j + 1;
          const std::size_t a = id(c00), b = id(c10), c = id(c11), d = id(c01);
          faces.push_back({a, b, c});
          faces.push_back({a, c, d});
        }
  }
  return soup_to_mesh(points, faces, mesh, error);
}

inline bool cylinder_mesh(int around, int along, double radius, double height, Mesh& mesh, std::string& error)
{
  const double pi = 3.14159265358979323846;
  Points points;
  Faces faces;
  for(int j = 0; j <= along; ++j)
    for(int i = 0; i < around; ++i)
      points.push_back({{radius * std::cos(2 * pi * i / around), radius * std::sin(2 * pi * i / around),
                         height * j / along}});
  auto id = [around](int i, int j) { return std::size_t(j) * std::size_t(around) + std::size_t(i % around); };
  for(int j = 0; j < along; ++j)
    for(int i = 0; i < around; ++i)
    {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return soup_to_mesh(points, faces, mesh, error);
}

inline bool bumpy_plane_mesh(int cells, double amplitude, double waves, Mesh& mesh, std::string& error)
{
  const double pi = 3.14159265358979323846;
  Points points;
  Faces faces;
  for(int j = 0; j <= cells; ++j)
    for(int i = 0; i <= cells; ++i)
    {
      const double x = double(i) / cells, y = double(j) / cells;
      points.push_back({{x, y, amplitude * std::sin(2 * pi * waves * x) * std::sin(2 * pi * waves * y)}});
    }
  auto id = [cells](int i, int j) { return std::size_t(j) * std::size_t(cells + 1) + std::size_t(i); };
  for(int j = 0; j < cells; ++j)
    for(int i = 0; i < cells; ++i)
    {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return soup_to_mesh(points, faces, mesh, error);
}

inline Eigen::Vector3d vec(const Point_3& p) { return Eigen::Vector3d(p.x(), p.y(), p.z()); }

inline bool parse_direction(const std::string& s, int& axis, double& sign)
{
  if(s.size() != 2 || (s[0] != '+' && s[0] != '-') || s[1] < 'x' || s[1] > 'z')
    return false;
  axis = s[1] - 'x';
  sign = s[0] == '+' ? 1. : -1.;
  return true;
}

} // namespace internal

/// Reads the task file `path`; meshes, .sel and .def files are looked up in `data_dir`.
/// Returns `false` with a message naming the file and line on any error.
inline bool read_task(const std::string& path, const std::string& data_dir, Task& task, std::string& error)
{
  std::ifstream in(path);
  if(!in)
    return error = path + ": cannot open", false;
  task = Task();
  {
    const std::size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    task.name = path.substr(slash == std::string::npos ? 0 : slash + 1);
    if(dot != std::string::npos && dot > (slash == std::string::npos ? 0 : slash))
      task.name = path.substr(slash == std::string::npos ? 0 : slash + 1, dot - (slash == std::string::npos ? 0 : slash + 1));
  }
  std::vector<int> selection;
  std::vector<std::vector<std::string> > handle_rules, roi_rules, transform_rules;
  std::vector<int> rule_lines[3];
  std::string line;
  int line_number = 0, mesh_line = 0;
  auto fail = [&](int number, const std::string& message) {
    error = path + ":" + std::to_string(number) + ": " + message;
    return false;
  };
  while(std::getline(in, line))
  {
    ++line_number;
    const std::size_t hash = line.find('#');
    if(hash != std::string::npos)
      line.erase(hash);
    std::istringstream words(line);
    std::string keyword;
    if(!(words >> keyword))
      continue;
    std::vector<std::string> args;
    for(std::string w; words >> w;)
      args.push_back(w);
    if(keyword == "title")
    {
      const std::size_t start = line.find("title") + 5;
      task.title = line.substr(line.find_first_not_of(" \t", start));
      task.title.erase(task.title.find_last_not_of(" \t\r") + 1);
    }
    else if(keyword == "mesh" || keyword == "generate")
    {
      if(args.empty())
        return fail(line_number, keyword + " needs an argument");
      bool ok = true;
      auto number = [&](std::size_t i) { return i < args.size() ? std::stod(args[i]) : (ok = false, 0.); };
      try
      {
        if(keyword == "mesh")
        {
          if(!CGAL::IO::read_polygon_mesh(data_dir + "/" + args[0], task.mesh) || is_empty(task.mesh))
            return fail(line_number, "cannot read the mesh " + data_dir + "/" + args[0] + " (run scripts/setup.sh)");
          if(!CGAL::is_triangle_mesh(task.mesh))
            return fail(line_number, args[0] + " is not a triangle mesh");
        }
        else if(args[0] == "bar")
          ok = args.size() == 3 && internal::bar_mesh(number(1), int(number(2)), task.mesh, error);
        else if(args[0] == "cylinder")
          ok = args.size() == 5 && internal::cylinder_mesh(int(number(1)), int(number(2)), number(3), number(4), task.mesh, error);
        else if(args[0] == "bumpy_plane")
          ok = args.size() == 4 && internal::bumpy_plane_mesh(int(number(1)), number(2), number(3), task.mesh, error);
        else
          return fail(line_number, "unknown generator " + args[0] + " (bar, cylinder, bumpy_plane)");
      }
      catch(const std::exception&)
      {
        ok = false;
      }
      if(!ok)
        return fail(line_number, "bad arguments for " + keyword + " " + args[0]);
      task.mesh_description = keyword == "mesh" ? args[0] : line.substr(line.find(args[0]));
      task.mesh_description.erase(task.mesh_description.find_last_not_of(" \t\r") + 1);
      mesh_line = line_number;
    }
    else if(keyword == "selection")
    {
      if(args.size() != 1 || !mesh_line)
        return fail(line_number, "selection needs one file, after the mesh");
      std::ifstream sel(data_dir + "/" + args[0]);
      std::string message;
      if(!sel || !CGAL::Laplacian_deformation::IO::read_botsch08_selection(sel, selection, message, num_vertices(task.mesh)))
        return fail(line_number, "cannot read the selection " + args[0] + (message.empty() ? "" : ": " + message));
    }
    else if(keyword == "handle" || keyword == "roi" || keyword == "transform")
    {
      if(args.empty())
        return fail(line_number, keyword + " needs a rule");
      const int k = keyword == "handle" ? 0 : keyword == "roi" ? 1 : 2;
      (k == 0 ? handle_rules : k == 1 ? roi_rules : transform_rules).push_back(args);
      rule_lines[k].push_back(line_number);
    }
    else if(keyword == "measure")
    {
      std::vector<double> x;
      try
      {
        for(std::size_t i = 2; i < args.size(); ++i)
          x.push_back(std::stod(args[i]));
      }
      catch(const std::exception&)
      {
        return fail(line_number, "bad number in measure");
      }
      int axis;
      double sign;
      if(args.size() < 2 || !internal::parse_direction(args[1], axis, sign))
        return fail(line_number, "expected measure bend|twist DIR ... with DIR in +x -x +y -y +z -z");
      if(args[0] == "bend")
      {
        if(x.size() != 8 || !(x[0] > 0) || !(x[4] > 0))
          return fail(line_number, "expected measure bend DIR TUBE_RADIUS CX CY CZ RADIUS NX NY NZ (radii > 0)");
        const Eigen::Vector3d normal(x[5], x[6], x[7]);
        if(!(normal.norm() > 0))
          return fail(line_number, "the normal of the bend's plane is zero");
        task.bend_axis = axis;
        task.bend_sign = sign;
        task.bend_tube_radius = x[0];
        task.bend_centre = Eigen::Vector3d(x[1], x[2], x[3]);
        task.bend_radius = x[4];
        task.bend_normal = normal.normalized();
      }
      else if(args[0] == "twist")
      {
        if(x.size() != 2)
          return fail(line_number, "expected measure twist DIR POSITION IDEAL_DEGREES");
        task.twist_axis = axis;
        task.twist_sign = sign;
        task.twist_position = x[0];
        task.twist_ideal = x[1];
      }
      else
        return fail(line_number, "unknown measure " + args[0] + " (bend, twist)");
    }
    else
      return fail(line_number, "unknown directive " + keyword);
  }
  if(!mesh_line)
    return fail(line_number, "no mesh or generate directive");
  if(handle_rules.empty() || roi_rules.empty() || transform_rules.empty())
    return fail(line_number, "a task needs handle, roi and transform directives");
  if(task.title.empty())
    task.title = task.name;

  const Mesh& m = task.mesh;
  Eigen::Vector3d lo = internal::vec(m.point(*vertices(m).begin())), hi = lo;
  for(vertex_descriptor v : vertices(m))
  {
    lo = lo.cwiseMin(internal::vec(m.point(v)));
    hi = hi.cwiseMax(internal::vec(m.point(v)));
  }
  const double diagonal = (hi - lo).norm();
  std::vector<unsigned char> in_handle(num_vertices(m), 0), in_roi(num_vertices(m), 0);

  auto numbers = [](const std::vector<std::string>& args, std::size_t first, std::vector<double>& out) {
    out.clear();
    try
    {
      for(std::size_t i = first; i < args.size(); ++i)
        out.push_back(std::stod(args[i]));
    }
    catch(const std::exception&)
    {
      return false;
    }
    return true;
  };
  std::vector<double> x;
  // "extreme DIR F" / "all_but DIR F": vertices within F * extent of the extreme in DIR
  auto near_extreme = [&](const std::vector<std::string>& args, int number, std::vector<unsigned char>& out,
                          bool complement) {
    int axis;
    double sign;
    if(args.size() != 3 || !internal::parse_direction(args[1], axis, sign) || !numbers(args, 2, x))
      return fail(number, "expected " + args[0] + " DIR FRACTION with DIR in +x -x +y -y +z -z");
    const double extreme = sign > 0 ? hi[axis] : -lo[axis];
    const double band = x[0] * (hi[axis] - lo[axis]);
    for(vertex_descriptor v : vertices(m))
      if((sign * m.point(v)[axis] >= extreme - band) != complement)
        out[v] = 1;
    return true;
  };
  for(std::size_t r = 0; r < handle_rules.size(); ++r)
  {
    const std::vector<std::string>& a = handle_rules[r];
    const int number = rule_lines[0][r];
    if(a[0] == "selection")
    {
      if(selection.empty())
        return fail(number, "handle selection needs a selection directive");
      for(vertex_descriptor v : vertices(m))
        if(selection[v] == CGAL::Laplacian_deformation::IO::BOTSCH08_HANDLE)
          in_handle[v] = 1;
    }
    else if(a[0] == "extreme")
    {
      if(!near_extreme(a, number, in_handle, false))
        return false;
    }
    else if(a[0] == "sphere")
    {
      if(a.size() != 5 || !numbers(a, 1, x))
        return fail(number, "expected sphere X Y Z RADIUS");
      for(vertex_descriptor v : vertices(m))
        if((internal::vec(m.point(v)) - Eigen::Vector3d(x[0], x[1], x[2])).norm() <= x[3])
          in_handle[v] = 1;
    }
    else
      return fail(number, "unknown handle rule " + a[0] + " (selection, extreme, sphere)");
  }
  for(vertex_descriptor v : vertices(m))
    if(in_handle[v])
      task.handle.push_back(v);
  if(task.handle.empty())
    return fail(rule_lines[0].front(), "the handle rules select no vertex");

  for(std::size_t r = 0; r < roi_rules.size(); ++r)
  {
    const std::vector<std::string>& a = roi_rules[r];
    const int number = rule_lines[1][r];
    if(a[0] == "selection")
    {
      if(selection.empty())
        return fail(number, "roi selection needs a selection directive");
      for(vertex_descriptor v : vertices(m))
        if(selection[v] != CGAL::Laplacian_deformation::IO::BOTSCH08_FIXED)
          in_roi[v] = 1;
    }
    else if(a[0] == "all")
      std::fill(in_roi.begin(), in_roi.end(), 1);
    else if(a[0] == "all_but")
    {
      if(!near_extreme(a, number, in_roi, true))
        return false;
    }
    else if(a[0] == "geodesic")
    {
      if(a.size() != 2 || !numbers(a, 1, x))
        return fail(number, "expected geodesic RADIUS (times the bounding-box diagonal)");
      const double radius = x[0] * diagonal;
      std::vector<double> distance(num_vertices(m), std::numeric_limits<double>::infinity());
      typedef std::pair<double, vertex_descriptor> Item;
      std::priority_queue<Item, std::vector<Item>, std::greater<Item> > queue;
      for(vertex_descriptor v : task.handle)
        queue.emplace(distance[v] = 0., v);
      while(!queue.empty())
      {
        const Item item = queue.top();
        queue.pop();
        if(item.first > distance[item.second] || item.first > radius)
          continue;
        in_roi[item.second] = 1;
        for(vertex_descriptor w : CGAL::vertices_around_target(item.second, m))
        {
          const double d = item.first + std::sqrt(CGAL::squared_distance(m.point(item.second), m.point(w)));
          if(d < distance[w])
            queue.emplace(distance[w] = d, w);
        }
      }
    }
    else
      return fail(number, "unknown roi rule " + a[0] + " (selection, all, all_but, geodesic)");
  }
  for(vertex_descriptor v : vertices(m))
    if(in_roi[v] || in_handle[v])
      task.roi.push_back(v);

  std::vector<Eigen::Vector3d> targets;
  for(vertex_descriptor v : task.handle)
    targets.push_back(internal::vec(m.point(v)));
  for(std::size_t r = 0; r < transform_rules.size(); ++r)
  {
    const std::vector<std::string>& a = transform_rules[r];
    const int number = rule_lines[2][r];
    Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
    if(a[0] == "def")
    {
      std::ifstream def(data_dir + "/" + (a.size() > 1 ? a[1] : std::string()));
      std::string message;
      if(a.size() != 2 || !def || !CGAL::Laplacian_deformation::IO::read_botsch08_transform(def, t, message))
        return fail(number, "cannot read the transformation " + (a.size() > 1 ? a[1] : std::string()) + " " + message);
    }
    else if(a[0] == "translate" || a[0] == "translate_diagonal")
    {
      if(a.size() != 4 || !numbers(a, 1, x))
        return fail(number, "expected " + a[0] + " DX DY DZ");
      t.block<3, 1>(0, 3) = Eigen::Vector3d(x[0], x[1], x[2]) * (a[0] == "translate" ? 1. : diagonal);
    }
    else if(a[0] == "rotate")
    {
      if((a.size() != 5 && a.size() != 8) || !numbers(a, 1, x))
        return fail(number, "expected rotate AX AY AZ DEGREES [CX CY CZ]");
      Eigen::Vector3d center = Eigen::Vector3d::Zero();
      if(a.size() == 8)
        center = Eigen::Vector3d(x[4], x[5], x[6]);
      else
      {
        for(const Eigen::Vector3d& p : targets)
          center += p;
        center /= double(targets.size());
      }
      const Eigen::Vector3d axis(x[0], x[1], x[2]);
      if(!(axis.norm() > 0))
        return fail(number, "the rotation axis is zero");
      const Eigen::Matrix3d rotation =
          Eigen::AngleAxisd(x[3] * 3.14159265358979323846 / 180., axis.normalized()).toRotationMatrix();
      t.block<3, 3>(0, 0) = rotation;
      t.block<3, 1>(0, 3) = center - rotation * center;
    }
    else
      return fail(number, "unknown transform rule " + a[0] + " (def, translate, translate_diagonal, rotate)");
    for(Eigen::Vector3d& p : targets)
      p = (t * p.homogeneous()).head<3>();
  }
  for(const Eigen::Vector3d& p : targets)
    task.targets.emplace_back(p.x(), p.y(), p.z());
  return true;
}

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
