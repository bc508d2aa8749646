// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_TASK_MESHES_H
#define CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_TASK_MESHES_H

// The comparison harness's mesh type and the meshes its task files generate ("generate bar",
// "generate cylinder", "generate bumpy_plane"; see deformation_task.h and tasks/README.md).

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace Laplacian_deformation_benchmark {

typedef CGAL::Simple_cartesian<double>                  Kernel;
typedef Kernel::Point_3                                 Point_3;
typedef CGAL::Surface_mesh<Point_3>                     Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor    vertex_descriptor;

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

} // namespace Laplacian_deformation_benchmark

#endif // CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_TASK_MESHES_H
