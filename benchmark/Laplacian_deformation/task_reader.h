// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_TASK_READER_H
#define CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_TASK_READER_H

// The comparison harness's task files (the format: deformation_task.h and tasks/README.md): a
// loaded task and read_task(). The meshes are read with the tools' checked reader and the
// "geodesic" regions grown by the tools' grower (demo/Laplacian_deformation/tool_mesh_io.h,
// tool_regions.h), as by laplacian_deform.

#include "task_meshes.h"

#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>

#include "tool_mesh_io.h"
#include "tool_regions.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace Laplacian_deformation_benchmark {

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
          // the tools' checked reader (tool_mesh_io.h, as laplacian_deform's and the editor's)
          const std::string file = data_dir + "/" + args[0];
          std::string message, reason;
          if(!Laplacian_deformation_tools::read_mesh_file(file, task.mesh, message, &reason))
            return fail(line_number, "cannot read the mesh " + file + ": " + reason +
                                     (std::filesystem::exists(file) ? "" : " (run scripts/setup.sh)"));
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
      // the tools' geodesic region (tool_regions.h, as laplacian_deform --roi-radius)
      for(vertex_descriptor v : Laplacian_deformation_tools::geodesic_vertices(m, task.handle, x[0] * diagonal))
        in_roi[v] = 1;
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

} // namespace Laplacian_deformation_benchmark

#endif // CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_TASK_READER_H
