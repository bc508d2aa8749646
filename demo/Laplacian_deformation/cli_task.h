// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform command-line tool (not part of the package's API): the
// deformation task (the mesh through the tools' checked reader of tool_mesh_io.h, a Botsch08
// selection and transformation or --handle with a region grown by tool_regions.h, the handle
// motion), and the checks of the outputs before anything is written (tool_files.h writes them).

#ifndef LAPLACIAN_DEFORM_CLI_TASK_H
#define LAPLACIAN_DEFORM_CLI_TASK_H

#include "cli_options.h"
#include "tool_files.h"
#include "tool_mesh_io.h"
#include "tool_regions.h"

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace laplacian_deform {

namespace tools = Laplacian_deformation_tools;
// the tools' files (tool_files.h, tool_mesh_io.h), under the names the tool has always used
using tools::quoted;
using tools::extension_of;
using tools::is_mesh_extension;
using tools::non_finite_number_in;
using tools::write_atomically;
using tools::write_text_atomically;
using tools::write_mesh_atomically;

/// a deformation task: the rest mesh, the status of every vertex and the handle transformation
struct Task
{
  fs::path mesh_file, selection_file, transform_file;
  Mesh mesh;
  std::size_t triangulated_faces = 0;        // faces that --triangulate split
  std::vector<int> status;                   // LD::IO::Botsch08_status per vertex index
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  // --rotate: the handles' rotation as given (so that the rotation-aware start keeps its winding)
  bool has_rotation = false;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d rotation_center = Eigen::Vector3d::Zero(), translation = Eigen::Vector3d::Zero();
  std::string selection_description, motion_description;

  std::size_t count(int s) const { return std::size_t(std::count(status.begin(), status.end(), s)); }
};

/// Reads a mesh with the tools' checked reader (tool_mesh_io.h); refuses non-triangle faces unless
/// `triangulate`, then splits them (`triangulated`: how many).
inline bool read_mesh(const fs::path& file, bool triangulate, Mesh& mesh, std::size_t& triangulated, std::string& error)
{
  if(!tools::read_mesh_file(file, mesh, error))
    return false;
  const std::size_t non_triangles = tools::non_triangle_faces(mesh);
  triangulated = 0;
  if(non_triangles > 0)
  {
    if(!triangulate)
      return error = "the mesh " + quoted(file) + " has " + std::to_string(non_triangles) + " non-triangle face" +
                     (non_triangles > 1 ? "s" : "") + " (of " + std::to_string(num_faces(mesh)) +
                     "); the deformation needs triangles: pass --triangulate to split them with "
                     "CGAL::Polygon_mesh_processing::triangulate_faces", false;
    if(!CGAL::Polygon_mesh_processing::triangulate_faces(mesh) || !CGAL::is_triangle_mesh(mesh))
      return error = "could not triangulate every face of " + quoted(file), false;
    triangulated = non_triangles;
  }
  return true;
}

/// the vertices at most `rings` edges away from `sources` (tool_regions.h), as a mask by index
inline std::vector<bool> k_ring_region(const Mesh& mesh, const std::vector<std::size_t>& sources, std::size_t rings)
{
  std::vector<vertex_descriptor> s;
  for(std::size_t v : sources)
    s.push_back(vertex_descriptor(Mesh::size_type(v)));
  return tools::region_mask(num_vertices(mesh), tools::k_ring_vertices(mesh, s, rings));
}

/// the vertices at distance at most `radius` from `sources` along mesh edges (tool_regions.h:
/// Dijkstra), as a mask by index
inline std::vector<bool> radius_region(const Mesh& mesh, const std::vector<std::size_t>& sources, double radius)
{
  std::vector<vertex_descriptor> s;
  for(std::size_t v : sources)
    s.push_back(vertex_descriptor(Mesh::size_type(v)));
  return tools::region_mask(num_vertices(mesh), tools::geodesic_vertices(mesh, s, radius));
}

/// the affine map of --rotate (about the centre) followed by --translate
inline Eigen::Matrix4d motion_matrix(const Options& o, const Eigen::Vector3d& default_center)
{
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if(o.has_rotate)
  {
    const Eigen::Vector3d axis = Eigen::Vector3d(o.axis[0], o.axis[1], o.axis[2]).normalized();
    const Eigen::Matrix3d r = Eigen::AngleAxisd(o.angle_degrees * 3.14159265358979323846 / 180., axis).toRotationMatrix();
    const Eigen::Vector3d c = o.has_center ? Eigen::Vector3d(o.center[0], o.center[1], o.center[2]) : default_center;
    m.topLeftCorner<3, 3>() = r;
    m.topRightCorner<3, 1>() = c - r * c;
  }
  if(o.has_translate)
    m.topRightCorner<3, 1>() += Eigen::Vector3d(o.translate[0], o.translate[1], o.translate[2]);
  return m;
}

/// Loads the task the options describe (the cactus when no MESH is given). Returns `false`
/// with a message in `error` on any bad input.
inline bool load_task(const Options& o, const fs::path& data_dir, Task& task, std::string& error)
{
  task.mesh_file = o.main_job() ? data_dir / "cactus.off" : fs::path(o.mesh);
  task.selection_file = o.main_job() ? data_dir / "cactus.sel" : fs::path(o.selection);
  task.transform_file = o.main_job() ? data_dir / "cactus.def" : fs::path(o.transform_file);
  if(o.main_job() && !fs::exists(task.mesh_file))
    return error = "the default task needs CGAL's cactus in " + quoted(data_dir) +
                   ": run scripts/setup.sh (it unpacks the data from Debian's libcgal-demo)", false;
  if(!read_mesh(task.mesh_file, o.triangulate, task.mesh, task.triangulated_faces, error))
    return false;
  const std::size_t n = num_vertices(task.mesh);

  if(!task.selection_file.empty())
  {
    std::ifstream in(task.selection_file);
    if(!in)
      return error = "cannot open the selection " + quoted(task.selection_file) +
                     (fs::exists(task.selection_file) ? "" : ": no such file"), false;
    std::string why;
    if(!LD::IO::read_botsch08_selection(in, task.status, why, n))
      return error = "bad selection " + quoted(task.selection_file) + ": " + why, false;
    task.selection_description = task.selection_file.string();
  }
  else
  {
    std::vector<std::size_t> handles;
    for(const std::pair<std::size_t, std::size_t>& range : o.handles)
      if(range.second >= n)
        return error = "handle vertex " + std::to_string(range.second) + " does not exist: the mesh has " +
                       std::to_string(n) + " vertices (ids 0 to " + std::to_string(n - 1) + ")", false;
    for(const std::pair<std::size_t, std::size_t>& range : o.handles)
      for(std::size_t h = range.first; h <= range.second; ++h)
        handles.push_back(h);
    const std::vector<bool> roi = o.roi_rings >= 0 ? k_ring_region(task.mesh, handles, std::size_t(o.roi_rings))
                                                   : radius_region(task.mesh, handles, o.roi_radius);
    task.status.assign(n, LD::IO::BOTSCH08_FIXED);
    for(std::size_t v = 0; v < n; ++v)
      if(roi[v])
        task.status[v] = LD::IO::BOTSCH08_REGION_OF_INTEREST;
    for(std::size_t h : handles)
      task.status[h] = LD::IO::BOTSCH08_HANDLE;
    std::ostringstream d;
    d << handles.size() << " handle id" << (handles.size() > 1 ? "s" : "") << ", ";
    if(o.roi_rings >= 0)
      d << o.roi_rings << "-ring region of interest";
    else
      d << "region of interest within distance " << o.roi_radius << " along edges";
    task.selection_description = d.str();
  }
  if(task.count(LD::IO::BOTSCH08_HANDLE) == 0)
    return error = "the selection " + quoted(task.selection_file) + " has no handle vertex (status 2)", false;

  if(!task.transform_file.empty())
  {
    std::ifstream in(task.transform_file);
    if(!in)
      return error = "cannot open the handle transformation " + quoted(task.transform_file) +
                     (fs::exists(task.transform_file) ? "" : ": no such file"), false;
    std::string why;
    if(!LD::IO::read_botsch08_transform(in, task.transform, why))
      return error = "bad handle transformation " + quoted(task.transform_file) + ": " + why, false;
    task.motion_description = task.transform_file.string();
  }
  else
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for(std::size_t v = 0; v < n; ++v)
      if(task.status[v] == LD::IO::BOTSCH08_HANDLE)
      {
        const Point_3& p = task.mesh.point(vertex_descriptor(Mesh::size_type(v)));
        centroid += Eigen::Vector3d(p.x(), p.y(), p.z());
      }
    centroid /= double(task.count(LD::IO::BOTSCH08_HANDLE));
    task.transform = motion_matrix(o, centroid);
    if(o.has_rotate)
    {
      task.has_rotation = true;
      task.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(o.angle_degrees * 3.14159265358979323846 / 180.,
                                         Eigen::Vector3d(o.axis[0], o.axis[1], o.axis[2]).normalized()));
      task.rotation_center = o.has_center ? Eigen::Vector3d(o.center[0], o.center[1], o.center[2]) : centroid;
      if(o.has_translate)
        task.translation = Eigen::Vector3d(o.translate[0], o.translate[1], o.translate[2]);
    }
    std::ostringstream d;
    d.precision(6);
    if(o.has_rotate)
      d << "rotate " << o.angle_degrees << " deg about (" << o.axis[0] << ", " << o.axis[1] << ", " << o.axis[2] << ")";
    if(o.has_rotate && o.has_translate)
      d << ", then ";
    if(o.has_translate)
      d << "translate (" << o.translate[0] << ", " << o.translate[1] << ", " << o.translate[2] << ")";
    task.motion_description = d.str();
  }
  return true;
}

/// whether `a` and `b` name the same file (existing or not)
inline bool same_file(const fs::path& a, const fs::path& b)
{
  std::error_code ec1, ec2;
  if(fs::exists(a, ec1) && fs::exists(b, ec2))
    return fs::equivalent(a, b, ec1);
  return fs::weakly_canonical(a, ec1) == fs::weakly_canonical(b, ec2);
}

/// Checks that every output can be written and overwrites no input (unless `force`).
inline bool check_outputs(const std::vector<fs::path>& outputs, const std::vector<fs::path>& inputs, bool force,
                          std::string& error)
{
  for(std::size_t i = 0; i < outputs.size(); ++i)
  {
    const fs::path& out = outputs[i];
    for(const fs::path& in : inputs)
      if(!in.empty() && !force && same_file(out, in))
        return error = "the output " + quoted(out) + " is the input " + quoted(in) +
                       ": refusing to overwrite it (pass --force to allow it)", false;
    for(std::size_t j = 0; j < i; ++j)
      if(same_file(out, outputs[j]))
        return error = "two outputs are the same file " + quoted(out), false;
    std::error_code ec;
    if(fs::is_directory(out, ec))
      return error = "the output " + quoted(out) + " is a folder", false;
    const fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    if(!fs::is_directory(parent, ec))
      return error = "cannot write " + quoted(out) + ": the folder " + quoted(parent) + " does not exist", false;
  }
  return true;
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_CLI_TASK_H
