// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_IO_READ_TRIANGLE_MESH_H
#define CGAL_LAPLACIAN_DEFORMATION_IO_READ_TRIANGLE_MESH_H

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/properties.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace IO {

/*!
\ingroup PkgLaplacianDeformationIO
\brief reads a mesh to deform from an OFF, PLY or OBJ file (chosen by the extension), checking
everything the deformer needs; returns `false` and explains in `error` otherwise, leaving `tm`
unchanged.

The file is read as a polygon soup with `CGAL::IO::read_polygon_soup()`, then refused when it
cannot be parsed (malformed or truncated), has no vertex or no face, has a coordinate that is
NaN or infinite, a face with fewer than three vertices, a repeated vertex or a vertex index out
of range, a face that is not a triangle (unless `triangles_only` is `false`), or when its faces
do not form a manifold, consistently oriented surface
(`CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh()`: a non-manifold edge or
vertex, or inconsistent orientations; `CGAL::Polygon_mesh_processing::IO::read_polygon_mesh()`
can repair such files). Otherwise the soup becomes `tm` (its previous content is replaced).
Vertices referenced by no face are kept as isolated vertices.

\tparam TriangleMesh a model of `MutableFaceGraph` with an internal vertex point map, move-assignable
*/
template <class TriangleMesh>
bool read_triangle_mesh(const std::string& file_name, TriangleMesh& tm, std::string& error,
                        bool triangles_only = true)
{
  typedef typename boost::property_traits<
      typename boost::property_map<TriangleMesh, CGAL::vertex_point_t>::type>::value_type Point;
  std::string extension = file_name.substr(std::min(file_name.size(), file_name.find_last_of('.') + 1));
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if(file_name.find_last_of('.') == std::string::npos ||
     (extension != "off" && extension != "ply" && extension != "obj"))
  {
    error = "'" + file_name + "': unsupported file extension (OFF, PLY or OBJ expected)";
    return false;
  }
  if(!std::ifstream(file_name))
  {
    error = "cannot open '" + file_name + "'";
    return false;
  }
  std::vector<Point> points;
  std::vector<std::vector<std::size_t> > faces;
  bool parsed = false;
  try
  {
    parsed = CGAL::IO::read_polygon_soup(file_name, points, faces, CGAL::parameters::verbose(false));
  }
  catch(...)
  {
    parsed = false;
  }
  const std::string where = "'" + file_name + "': ";
  if(!parsed)
  {
    error = where + "not a valid " + extension + " file (malformed or truncated)";
    return false;
  }
  if(points.empty() || faces.empty())
  {
    error = where + (points.empty() ? "the file has no vertex" : "the file has no face");
    return false;
  }
  for(std::size_t i = 0; i < points.size(); ++i)
    if(!std::isfinite(CGAL::to_double(points[i].x())) || !std::isfinite(CGAL::to_double(points[i].y())) ||
       !std::isfinite(CGAL::to_double(points[i].z())))
    {
      error = where + "vertex " + std::to_string(i) + " has a coordinate that is NaN or infinite";
      return false;
    }
  for(std::size_t k = 0; k < faces.size(); ++k)
  {
    const std::vector<std::size_t>& f = faces[k];
    const std::string face = "face " + std::to_string(k);
    if(f.size() < 3 || (triangles_only && f.size() != 3))
    {
      error = where + face + " has " + std::to_string(f.size()) + " vertices" +
              (triangles_only ? " (only triangles can be deformed)" : " (fewer than three)");
      return false;
    }
    for(std::size_t j = 0; j < f.size(); ++j)
    {
      if(f[j] >= points.size())
      {
        error = where + face + " refers to vertex " + std::to_string(f[j]) + " but the file has " +
                std::to_string(points.size()) + " vertices";
        return false;
      }
      if(std::find(f.begin(), f.begin() + std::ptrdiff_t(j), f[j]) != f.begin() + std::ptrdiff_t(j))
      {
        error = where + face + " repeats vertex " + std::to_string(f[j]);
        return false;
      }
    }
  }
  if(!CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(faces))
  {
    error = where + "the faces do not form a manifold, consistently oriented surface (a non-manifold "
                    "edge or vertex, or inconsistent orientations)";
    return false;
  }
  TriangleMesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, faces, mesh);
  if(!CGAL::is_valid_polygon_mesh(mesh) || num_faces(mesh) != faces.size())
  {
    error = where + "the faces could not be assembled into a valid mesh";
    return false;
  }
  tm = std::move(mesh);
  return true;
}

} // namespace IO
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_IO_READ_TRIANGLE_MESH_H
