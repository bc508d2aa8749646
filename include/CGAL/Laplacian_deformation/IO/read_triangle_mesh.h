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
#include <cstdint>
#include <limits>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace IO {
namespace internal {

// The answer of CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(faces) for a soup
// whose polygons have at least three vertices, none twice, all below `number_of_points`: no
// directed edge twice (so every edge has at most two polygons, in opposite directions) and, around
// every vertex, one fan (the polygons around it, linked through the edges they share, form a
// single path or a single cycle). The same checks as CGAL's, on sorted arrays instead of a
// std::set of edges and a set per vertex (CGAL's was about 40% of a command-line run on a mesh of
// 832k faces, 4 of 10 s; test_robustness compares the two on random soups).
template <class Faces>
bool is_oriented_manifold_soup(const Faces& faces, std::size_t number_of_points)
{
  typedef std::uint32_t Id;
  if(number_of_points >= std::size_t(std::numeric_limits<Id>::max()) ||
     faces.size() >= std::size_t(std::numeric_limits<Id>::max()))
    return CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(faces);
  // the directed edges (u -> w, polygon) by source u: w and the polygon, sorted by w
  std::vector<std::size_t> start(number_of_points + 1, 0);
  for(const auto& f : faces)
    for(std::size_t u : f)
      ++start[u + 1];
  for(std::size_t v = 0; v < number_of_points; ++v)
    start[v + 1] += start[v];
  std::vector<std::pair<Id, Id> > out(start[number_of_points]);   // (w, polygon)
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for(std::size_t i = 0; i < faces.size(); ++i)
    {
      const auto& f = faces[i];
      for(std::size_t j = 0; j < f.size(); ++j)
        out[fill[f[j]]++] = std::make_pair(Id(f[(j + 1) % f.size()]), Id(i));
    }
  }
  for(std::size_t v = 0; v < number_of_points; ++v)
  {
    std::sort(out.begin() + std::ptrdiff_t(start[v]), out.begin() + std::ptrdiff_t(start[v + 1]));
    for(std::size_t k = start[v] + 1; k < start[v + 1]; ++k)
      if(out[k].first == out[k - 1].first)
        return false;   // the directed edge v -> w twice
  }
  // the polygon with the directed edge u -> w, or none
  const Id none = std::numeric_limits<Id>::max();
  auto owner = [&](std::size_t u, Id w) -> Id {
    const auto first = out.begin() + std::ptrdiff_t(start[u]), last = out.begin() + std::ptrdiff_t(start[u + 1]);
    const auto it = std::lower_bound(first, last, std::make_pair(w, Id(0)));
    return it != last && it->first == w ? it->second : none;
  };
  // the neighbours of v in polygon p: its predecessor and successor
  auto around = [&](Id p, std::size_t v) {
    const auto& f = faces[p];
    std::size_t j = 0;
    while(std::size_t(f[j]) != v)
      ++j;
    return std::make_pair(Id(f[(j + f.size() - 1) % f.size()]), Id(f[(j + 1) % f.size()]));
  };
  for(std::size_t v = 0; v < number_of_points; ++v)
  {
    const std::size_t k = start[v + 1] - start[v];   // the polygons around v (each has v once)
    if(k < 2)
      continue;
    // next(p): the polygon across the edge from v to its successor in p (it holds that edge
    // the other way); prev(p): the polygon across the edge from v's predecessor in p to v (it
    // holds the edge from v to that predecessor). A polygon without a previous one starts a path.
    std::size_t links = 0;
    Id first = out[start[v]].second;
    for(std::size_t e = start[v]; e < start[v + 1]; ++e)
    {
      const Id p = out[e].second;
      if(owner(out[e].first, Id(v)) != none)
        ++links;
      if(owner(v, around(p, v).first) == none)
        first = p;
    }
    if(k - links >= 2)
      return false;   // two paths or more: several fans
    // walk from the start of the path (or anywhere on the cycle) and count the polygons met
    std::size_t met = 1;
    Id p = first;
    for(;;)
    {
      const Id q = owner(around(p, v).second, Id(v));
      if(q == none || q == first)
        break;
      p = q;
      if(++met > k)
        return false;
    }
    if(met != k)
      return false;   // a path and a cycle, or several cycles
  }
  return true;
}

} // namespace internal

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
(the answer of `CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh()`, computed on
sorted arrays: a non-manifold edge or vertex, or inconsistent orientations;
`CGAL::Polygon_mesh_processing::IO::read_polygon_mesh()` can repair such files). Otherwise the
soup becomes `tm` (its previous content is replaced).
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
  if(!internal::is_oriented_manifold_soup(faces, points.size()))
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
