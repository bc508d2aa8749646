// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform_figure: turns a rest mesh and deformed copies of it (same vertices, same order:
// what laplacian_deform writes) into a figure folder of the viewer (viewer/render.mjs draws it
// side by side with one colour bar): OUT/task.json and OUT/<panel>.ply, each vertex coloured by
// CGAL::Laplacian_deformation::vertex_distortion_field() against the rest mesh (0 on the rest).
//
//   usage: laplacian_deform_figure [--task NAME] [--title TEXT] REST PANEL=MESH... OUT_DIR
//   e.g.   laplacian_deform_figure --task cactus data/cactus.off vertex=out/cactus_vertex-based.off
//                                  edge=out/cactus_edge-based.off out/figure
// Exit status 0 on success, 1 when a mesh cannot be read or does not match the rest mesh, or a file
// cannot be written, 2 for bad arguments. Never overwrites a mesh it reads (OUT_DIR holds new files).

#include "viewer_files.h"

#include <CGAL/Laplacian_deformation/IO/read_triangle_mesh.h>
#include <CGAL/Laplacian_deformation/metrics.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/property_map.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
namespace fs = std::filesystem;
typedef CGAL::Simple_cartesian<double> Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;
using laplacian_deform::json_string;
using laplacian_deform::task_json;
using laplacian_deform::write_viewer_ply;

namespace {

int usage(const std::string& error)
{
  std::cerr << "error: " << error << "\n"
            << "usage: laplacian_deform_figure [--task NAME] [--title TEXT] REST PANEL=MESH... OUT_DIR\n";
  return 2;
}

} // namespace

int main(int argc, char** argv)
{
  std::string task = "deformation", title;
  std::vector<std::string> positional;
  for(int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if((a == "--task" || a == "--title") && i + 1 < argc)
      (a == "--task" ? task : title) = argv[++i];
    else if(a == "-h" || a == "--help")
      return std::cout << "usage: laplacian_deform_figure [--task NAME] [--title TEXT] REST PANEL=MESH... OUT_DIR\n", 0;
    else if(a.rfind("--", 0) == 0)
      return usage("unknown option '" + a + "'");
    else
      positional.push_back(a);
  }
  if(positional.size() < 3)
    return usage("expected a rest mesh, at least one PANEL=MESH and an output folder");
  const std::string rest_file = positional.front();
  const fs::path out_dir = positional.back();
  std::vector<std::pair<std::string, std::string>> panels;
  for(std::size_t i = 1; i + 1 < positional.size(); ++i)
  {
    const std::size_t eq = positional[i].find('=');
    if(eq == std::string::npos || eq == 0 || eq + 1 == positional[i].size())
      return usage("'" + positional[i] + "' is not PANEL=MESH");
    const std::string name = positional[i].substr(0, eq);
    if(name == "rest" || name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") != std::string::npos)
      return usage("panel name '" + name + "': use lower-case letters, digits, '_' or '-' (and not 'rest')");
    panels.emplace_back(name, positional[i].substr(eq + 1));
  }

  Mesh rest;
  std::string error;
  if(!LD::IO::read_triangle_mesh(rest_file, rest, error))
    return std::cerr << "error: " << rest_file << ": " << error << "\n", 1;
  std::vector<Mesh> meshes(panels.size());
  for(std::size_t k = 0; k < panels.size(); ++k)
  {
    if(!LD::IO::read_triangle_mesh(panels[k].second, meshes[k], error))
      return std::cerr << "error: " << panels[k].second << ": " << error << "\n", 1;
    if(num_vertices(meshes[k]) != num_vertices(rest) || num_faces(meshes[k]) != num_faces(rest))
      return std::cerr << "error: " << panels[k].second << " has " << num_vertices(meshes[k]) << " vertices and "
                       << num_faces(meshes[k]) << " faces, the rest mesh " << num_vertices(rest) << " and "
                       << num_faces(rest) << ": not a deformed copy of it\n", 1;
  }
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if(ec)
    return std::cerr << "error: cannot create " << out_dir << ": " << ec.message() << "\n", 1;
  if(!write_viewer_ply(out_dir / "rest.ply", rest, std::vector<double>(num_vertices(rest), 0.)))
    return std::cerr << "error: cannot write " << (out_dir / "rest.ply") << "\n", 1;
  std::vector<std::string> panel_list = {"rest"};
  for(std::size_t k = 0; k < panels.size(); ++k)
  {
    std::vector<double> field(num_vertices(rest), 0.);
    LD::vertex_distortion_field(meshes[k], get(CGAL::vertex_point, rest), CGAL::make_property_map(field));
    const fs::path ply = out_dir / (panels[k].first + ".ply");
    if(!write_viewer_ply(ply, meshes[k], field))
      return std::cerr << "error: cannot write " << ply << "\n", 1;
    panel_list.push_back(panels[k].first);
  }
  if(!Laplacian_deformation_tools::write_text_atomically(out_dir / "task.json", task_json(task, title, panel_list), error))
    return std::cerr << "error: " << error << "\n", 1;
  std::cout << "wrote       " << out_dir.string() << "/{task.json,rest.ply";
  for(const auto& p : panels)
    std::cout << ',' << p.first << ".ply";
  std::cout << "}\n";
  return 0;
}
