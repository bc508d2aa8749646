// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// The tools' one mesh reader and mesh writer (not part of the package's API), used by the
// laplacian_deform command line, the editor's server (laplacian_deform --serve) and the
// comparison harness (compare_deformations): OFF, OBJ and PLY through the library's checked
// reader CGAL::Laplacian_deformation::IO::read_triangle_mesh() (which refuses malformed,
// non-manifold or inconsistently oriented input with a message), STL through CGAL's reader; the
// deformed meshes written atomically (tool_files.h) with 17 significant digits.

#ifndef LAPLACIAN_DEFORMATION_TOOL_MESH_IO_H
#define LAPLACIAN_DEFORMATION_TOOL_MESH_IO_H

#include "tool_files.h"

#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>
#include <CGAL/Laplacian_deformation/IO/read_triangle_mesh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace Laplacian_deformation_tools {

/// the kind of a file, from its extension (lower case, without the dot)
inline std::string extension_of(const fs::path& p)
{
  std::string e = p.extension().string();
  if(!e.empty())
    e = e.substr(1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

/// the mesh formats the tools read and write (by extension)
inline bool is_mesh_extension(const std::string& e) { return e == "off" || e == "obj" || e == "ply" || e == "stl"; }

/// In a text mesh file (OFF, OBJ, ASCII PLY), the first token that reads as a number but is NaN or
/// infinite ("nan", "inf", "1e999"), as "line N: the coordinate 'TOKEN' is not a finite number"
/// (the token quoted with non-printable bytes escaped, cut after 40 bytes); empty if there is none
/// or the file is binary.
inline std::string non_finite_number_in(const fs::path& file)
{
  const std::string ext = extension_of(file);
  if(ext != "off" && ext != "obj" && ext != "ply")
    return "";
  std::ifstream in(file, std::ios::binary);
  std::string line, token;
  for(std::size_t number = 1; std::getline(in, line); ++number)
  {
    if(ext == "ply" && line.compare(0, 7, "format ") == 0 && line.compare(0, 12, "format ascii") != 0)
      return "";
    const std::size_t first = line.find_first_not_of(" \t\r");
    if(first == std::string::npos || line[first] == '#' || line.compare(first, 7, "comment") == 0)
      continue;
    std::istringstream tokens(line);
    while(tokens >> token)
    {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      if(end != token.c_str() && *end == '\0' && !std::isfinite(x))
        return "line " + std::to_string(number) + ": the coordinate " +
               CGAL::Laplacian_deformation::IO::internal::quoted_excerpt(token) + " is not a finite number";
    }
  }
  return "";
}

/// Reads the mesh to deform from `file` (.off, .obj, .ply: the library's checked reader; .stl:
/// CGAL::IO::read_polygon_mesh), keeping its faces as they are (polygons too: count them with
/// `non_triangle_faces()`). On failure returns `false` with, in `error`, a message naming the file
/// ("cannot open 'F': no such file", "cannot read a mesh from 'F': REASON") and, in `reason` if
/// given, the same without the file ("no such file", "REASON"). `mesh` holds only the geometry
/// and the faces of the file.
template <class Mesh>
bool read_mesh_file(const fs::path& file, Mesh& mesh, std::string& error, std::string* reason = nullptr)
{
  auto fail = [&](bool opening, const std::string& why) {
    error = (opening ? "cannot open " : "cannot read a mesh from ") + quoted(file) + ": " + why;
    if(reason != nullptr)
      *reason = why;
    return false;
  };
  std::error_code ec;
  if(!fs::exists(file, ec))
    return fail(true, "no such file");
  if(!fs::is_regular_file(file, ec))
    return fail(false, "not a regular file");
  const std::string ext = extension_of(file);
  if(!is_mesh_extension(ext))
    return fail(false, "unknown extension '" + ext + "' (expected .off, .obj, .ply or .stl)");
  if(!std::ifstream(file, std::ios::binary))
    return fail(true, "permission denied or unreadable");
  // NaN or infinite coordinates are a common cause of refusal: name the line and the value
  auto non_finite = [&file]() {
    const std::string where = non_finite_number_in(file);
    return where.empty() ? where : where + " (NaN and infinite coordinates cannot be deformed)";
  };
  Mesh m;
  if(ext != "stl")
  {
    std::string why;
    if(!CGAL::Laplacian_deformation::IO::read_triangle_mesh(file.string(), m, why, false))
    {
      const std::string token = non_finite();
      if(!token.empty())
        return fail(false, token);
      const std::string prefix = quoted(file) + ": ";   // the library's message names the file first
      return fail(false, why.compare(0, prefix.size(), prefix) == 0 ? why.substr(prefix.size()) : why);
    }
  }
  else
  {
    const bool read = CGAL::IO::read_polygon_mesh(file.string(), m);
    bool finite = true;
    for(auto v : vertices(m))
      finite = finite && std::isfinite(m.point(v).x()) && std::isfinite(m.point(v).y()) && std::isfinite(m.point(v).z());
    if(!finite)
      return fail(false, "a vertex has a NaN or infinite coordinate");
    if(!read)
      return fail(false, "not a valid stl polygon mesh (malformed file, or faces that do not form a manifold mesh)");
    if(is_empty(m) || num_faces(m) == 0)
      return fail(false, "the file has no face");
  }
  mesh = std::move(m);
  return true;
}

/// the number of faces of `mesh` that are not triangles
template <class Mesh>
std::size_t non_triangle_faces(const Mesh& mesh)
{
  std::size_t n = 0;
  for(auto f : faces(mesh))
    if(CGAL::halfedges_around_face(halfedge(f, mesh), mesh).size() != 3)
      ++n;
  return n;
}

/// writes `mesh` to `path` atomically, in the format of its extension, with 17 significant digits
/// (the coordinates round-trip exactly)
template <class Mesh>
bool write_mesh_atomically(const fs::path& path, const Mesh& mesh, std::string& error)
{
  return write_atomically(path, [&](const fs::path& tmp) {
    return CGAL::IO::write_polygon_mesh(tmp.string(), mesh, CGAL::parameters::stream_precision(17));
  }, error);
}

} // namespace Laplacian_deformation_tools

#endif // LAPLACIAN_DEFORMATION_TOOL_MESH_IO_H
