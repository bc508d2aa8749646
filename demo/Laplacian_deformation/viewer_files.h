// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// The files of a viewer figure folder (viewer/README.md), shared by the tools that write them
// (laplacian_deform_figure, the comparison harness): a PLY per panel with the positions and one
// scalar field per vertex, and task.json; written atomically (tool_files.h).

#ifndef LAPLACIAN_DEFORM_VIEWER_FILES_H
#define LAPLACIAN_DEFORM_VIEWER_FILES_H

#include "tool_files.h"

#include <CGAL/boost/graph/iterator.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace laplacian_deform {

/// `s` as a JSON string literal (quotes, backslashes and control characters escaped).
inline std::string json_string(const std::string& s)
{
  std::ostringstream out;
  out << '"';
  for(unsigned char c : s)
  {
    if(c == '"' || c == '\\')
      out << '\\' << c;
    else if(c < 0x20)
      out << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec << std::setfill(' ');
    else
      out << c;
  }
  out << '"';
  return out.str();
}

/// the text of a figure folder's task.json: the task's name and title, the field the PLYs carry
/// and the panels in order ("rest" first)
inline std::string task_json(const std::string& task, const std::string& title, const std::vector<std::string>& panels)
{
  std::string list;
  for(std::size_t k = 0; k < panels.size(); ++k)
    list += (k == 0 ? "" : ", ") + json_string(panels[k]);
  return "{\"task\": " + json_string(task) + ", \"title\": " + json_string(title) +
         ", \"field\": \"one_ring_rigidity_error\", \"panels\": [" + list + "]}\n";
}

/// writes the viewer's ASCII PLY of `m` (a `Surface_mesh` of triangles): x, y, z and `distortion`
/// (`field`, by vertex index) per vertex, the faces by vertex index; atomically (tool_files.h).
/// Returns `false` if writing failed.
template <class Mesh>
bool write_viewer_ply(const std::filesystem::path& path, const Mesh& m, const std::vector<double>& field)
{
  std::string error;
  return Laplacian_deformation_tools::write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << "ply\nformat ascii 1.0\nelement vertex " << num_vertices(m)
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty float distortion\nelement face "
        << num_faces(m) << "\nproperty list uchar int vertex_indices\nend_header\n"
        << std::setprecision(9);
    for(auto v : vertices(m))
      out << m.point(v).x() << ' ' << m.point(v).y() << ' ' << m.point(v).z() << ' ' << field[std::size_t(v)] << '\n';
    for(auto f : faces(m))
    {
      out << 3;
      for(auto v : CGAL::vertices_around_face(halfedge(f, m), m))
        out << ' ' << std::size_t(v);
      out << '\n';
    }
    out.close();
    return bool(out);
  }, error);
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_VIEWER_FILES_H
