// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_TEST_HELPERS_H
#define CGAL_LAPLACIAN_DEFORMATION_TEST_HELPERS_H

// Shared by all tests of the package: small meshes built in code (as polygon soups, then
// converted to any FaceGraph), the real meshes unpacked by scripts/setup.sh, and
// `points_near()` for comparing point sets with a message naming the first offending index.

#include <CGAL/boost/graph/IO/OFF.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#ifndef LAPLACIAN_DEFORMATION_DATA_DIR
#error "LAPLACIAN_DEFORMATION_DATA_DIR must be defined (by CMake) as the folder holding the real meshes"
#endif

namespace Laplacian_deformation_test {

typedef CGAL::Simple_cartesian<double>                                 Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3>                            Surface_mesh;
typedef CGAL::Polyhedron_3<Kernel, CGAL::Polyhedron_items_with_id_3>   Polyhedron;

/// A polygon soup: points and faces given by point indices (counterclockwise seen from outside).
struct Soup
{
  std::vector<std::array<double, 3> > points;
  std::vector<std::vector<std::size_t> > faces;
};

namespace internal {

inline std::size_t grid_index(int i, int j, int nx) { return std::size_t(j) * std::size_t(nx + 1) + std::size_t(i); }

// (nx+1) x (ny+1) points on z = 0.
inline Soup grid_points(int nx, int ny, double spacing)
{
  Soup s;
  for(int j = 0; j <= ny; ++j)
    for(int i = 0; i <= nx; ++i)
      s.points.push_back({{i * spacing, j * spacing, 0.}});
  return s;
}

template <class Mesh>
void set_ids(Mesh&) {}

template <class Gt, template <class, class, class> class HDS, class Alloc>
void set_ids(CGAL::Polyhedron_3<Gt, CGAL::Polyhedron_items_with_id_3, HDS, Alloc>& p)
{
  CGAL::set_halfedgeds_items_id(p);
}

} // namespace internal

/// Planar grid on z = 0 with (nx+1) x (ny+1) vertices; every quad is split along the same
/// diagonal, so every interior one-ring is a strictly convex hexagon. With `perturbation > 0`
/// each vertex moves in x and y by a uniform random offset of at most `perturbation * spacing`
/// (deterministic for a given `seed`).
inline Soup grid_soup(int nx, int ny, double spacing = 1., double perturbation = 0., unsigned seed = 1)
{
  Soup s = internal::grid_points(nx, ny, spacing);
  if(perturbation > 0.)
  {
    std::mt19937 generator(seed);
    std::uniform_real_distribution<double> offset(-perturbation * spacing, perturbation * spacing);
    for(std::array<double, 3>& p : s.points)
    {
      p[0] += offset(generator);
      p[1] += offset(generator);
    }
  }
  for(int j = 0; j < ny; ++j)
    for(int i = 0; i < nx; ++i)
    {
      const std::size_t a = internal::grid_index(i, j, nx), b = internal::grid_index(i + 1, j, nx),
                        c = internal::grid_index(i + 1, j + 1, nx), d = internal::grid_index(i, j + 1, nx);
      s.faces.push_back({a, b, c});
      s.faces.push_back({a, c, d});
    }
  return s;
}

/// Planar grid of nx x ny quads (not triangulated).
inline Soup quad_grid_soup(int nx, int ny, double spacing = 1.)
{
  Soup s = internal::grid_points(nx, ny, spacing);
  for(int j = 0; j < ny; ++j)
    for(int i = 0; i < nx; ++i)
      s.faces.push_back({internal::grid_index(i, j, nx), internal::grid_index(i + 1, j, nx),
                         internal::grid_index(i + 1, j + 1, nx), internal::grid_index(i, j + 1, nx)});
  return s;
}

/// Icosahedron subdivided `subdivisions` times (each triangle into four), projected on the
/// sphere of radius `radius` centred at the origin: closed, genus 0.
inline Soup icosphere_soup(int subdivisions, double radius = 1.)
{
  const double t = (1. + std::sqrt(5.)) / 2.;
  std::vector<std::array<double, 3> > p = {
    {{-1, t, 0}}, {{1, t, 0}}, {{-1, -t, 0}}, {{1, -t, 0}}, {{0, -1, t}}, {{0, 1, t}},
    {{0, -1, -t}}, {{0, 1, -t}}, {{t, 0, -1}}, {{t, 0, 1}}, {{-t, 0, -1}}, {{-t, 0, 1}}};
  std::vector<std::array<std::size_t, 3> > f = {
    {{0, 11, 5}}, {{0, 5, 1}}, {{0, 1, 7}}, {{0, 7, 10}}, {{0, 10, 11}}, {{1, 5, 9}}, {{5, 11, 4}},
    {{11, 10, 2}}, {{10, 7, 6}}, {{7, 1, 8}}, {{3, 9, 4}}, {{3, 4, 2}}, {{3, 2, 6}}, {{3, 6, 8}},
    {{3, 8, 9}}, {{4, 9, 5}}, {{2, 4, 11}}, {{6, 2, 10}}, {{8, 6, 7}}, {{9, 8, 1}}};
  for(int level = 0; level < subdivisions; ++level)
  {
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> midpoints;
    auto midpoint = [&](std::size_t a, std::size_t b) {
      const std::pair<std::size_t, std::size_t> key(std::min(a, b), std::max(a, b));
      const auto it = midpoints.find(key);
      if(it != midpoints.end())
        return it->second;
      p.push_back({{(p[a][0] + p[b][0]) / 2, (p[a][1] + p[b][1]) / 2, (p[a][2] + p[b][2]) / 2}});
      midpoints[key] = p.size() - 1;
      return p.size() - 1;
    };
    std::vector<std::array<std::size_t, 3> > refined;
    for(const std::array<std::size_t, 3>& t3 : f)
    {
      const std::size_t ab = midpoint(t3[0], t3[1]), bc = midpoint(t3[1], t3[2]), ca = midpoint(t3[2], t3[0]);
      refined.push_back({{t3[0], ab, ca}});
      refined.push_back({{t3[1], bc, ab}});
      refined.push_back({{t3[2], ca, bc}});
      refined.push_back({{ab, bc, ca}});
    }
    f.swap(refined);
  }
  Soup s;
  for(const std::array<double, 3>& q : p)
  {
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    s.points.push_back({{radius * q[0] / n, radius * q[1] / n, radius * q[2] / n}});
  }
  for(const std::array<std::size_t, 3>& t3 : f)
    s.faces.push_back({t3[0], t3[1], t3[2]});
  return s;
}

/// Planar mesh of nx x ny cells on z = 0 mixing triangles, quads and pentagons, every face
/// convex and every interior one-ring strictly convex. In rows j = 0, 2, 4, ... (below the last
/// row), every even cell i is a pentagon whose top edge is bent up by a "roof" vertex at
/// ((i + 1/2), (j + 1.2)) * spacing; the cell above it is split into three triangles at that roof
/// vertex. Other cells with (i + j) % 3 == 0 are split into two triangles, the rest are quads.
inline Soup mixed_polygon_soup(int nx, int ny, double spacing = 1.)
{
  Soup s = internal::grid_points(nx, ny, spacing);
  std::map<std::pair<int, int>, std::size_t> roof;   // cell -> roof vertex above it
  for(int j = 0; j + 1 < ny; j += 2)
    for(int i = 0; i < nx; i += 2)
    {
      roof[std::make_pair(i, j)] = s.points.size();
      s.points.push_back({{(i + 0.5) * spacing, (j + 1.2) * spacing, 0.}});
    }
  for(int j = 0; j < ny; ++j)
    for(int i = 0; i < nx; ++i)
    {
      const std::size_t a = internal::grid_index(i, j, nx), b = internal::grid_index(i + 1, j, nx),
                        c = internal::grid_index(i + 1, j + 1, nx), d = internal::grid_index(i, j + 1, nx);
      const auto below = roof.find(std::make_pair(i, j)), above = roof.find(std::make_pair(i, j - 1));
      if(below != roof.end())
        s.faces.push_back({a, b, c, below->second, d});
      else if(above != roof.end())
      {
        const std::size_t m = above->second;
        s.faces.push_back({a, m, d});
        s.faces.push_back({m, b, c});
        s.faces.push_back({m, c, d});
      }
      else if((i + j) % 3 == 0)
      {
        s.faces.push_back({a, b, c});
        s.faces.push_back({a, c, d});
      }
      else
        s.faces.push_back({a, b, c, d});
    }
  return s;
}

/// Open triangulated tube around the z axis: `around` vertices per ring, `along` rows of
/// quads (each split in two triangles), from z = 0 to z = height; two boundary loops.
inline Soup cylinder_soup(int around, int along, double radius = 1., double height = 2.)
{
  const double pi = 3.14159265358979323846;
  Soup s;
  for(int j = 0; j <= along; ++j)
    for(int i = 0; i < around; ++i)
    {
      const double angle = 2. * pi * i / around;
      s.points.push_back({{radius * std::cos(angle), radius * std::sin(angle), height * j / along}});
    }
  auto index = [around](int i, int j) { return std::size_t(j) * std::size_t(around) + std::size_t(i % around); };
  for(int j = 0; j < along; ++j)
    for(int i = 0; i < around; ++i)
    {
      s.faces.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      s.faces.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  return s;
}

/// Grid of n x n cells on [0,1]^2 with z = amplitude * sin(2 pi x) * cos(2 pi y).
inline Soup bumpy_plane_soup(int n, double amplitude = 0.1)
{
  const double pi = 3.14159265358979323846;
  Soup s = grid_soup(n, n, 1. / n);
  for(std::array<double, 3>& p : s.points)
    p[2] = amplitude * std::sin(2. * pi * p[0]) * std::cos(2. * pi * p[1]);
  return s;
}

/// Two disjoint icospheres (one subdivision), the second translated by (3, 0, 0).
inline Soup two_components_soup()
{
  Soup s = icosphere_soup(1);
  const Soup other = icosphere_soup(1);
  const std::size_t offset = s.points.size();
  for(const std::array<double, 3>& p : other.points)
    s.points.push_back({{p[0] + 3., p[1], p[2]}});
  for(const std::vector<std::size_t>& f : other.faces)
    s.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  return s;
}

/// Small disk-like triangle mesh (z = 0.05 x y) with one zero-area triangle (0, 1, 2), whose
/// three points are collinear, around the interior vertex 1, and one needle triangle (3, 2, 5)
/// whose angle at vertex 2 is about 7e-8 rad. Consistently oriented manifold with one boundary.
inline Soup degenerate_soup()
{
  const double tiny = 1e-7 / std::sqrt(2.);
  Soup s;
  s.points = {{{0., 0., 0.}}, {{1., 0., 0.}}, {{2., 0., 0.}}, {{1., 1., 0.}},
              {{1., -1., 0.}}, {{1. + tiny, 1. + tiny, 0.}}, {{2.5, -1., 0.}}};
  for(std::array<double, 3>& p : s.points)
    p[2] = 0.05 * p[0] * p[1];
  s.faces = {{0, 1, 2}, {0, 2, 3}, {1, 0, 4}, {2, 1, 4}, {3, 2, 5}, {2, 4, 6}};
  return s;
}

/// Converts a soup to a mesh (ids are set for a `Polyhedron_3` with ids).
template <class Mesh>
Mesh to_mesh(const Soup& s)
{
  typedef typename boost::property_traits<
    typename boost::property_map<Mesh, CGAL::vertex_point_t>::type>::value_type Point;
  std::vector<Point> points;
  points.reserve(s.points.size());
  for(const std::array<double, 3>& p : s.points)
    points.push_back(Point(p[0], p[1], p[2]));
  Mesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, s.faces, mesh);
  internal::set_ids(mesh);
  return mesh;
}

/// The full path of a file of the data folder (`LAPLACIAN_DEFORMATION_DATA_DIR`).
inline std::string data_path(const std::string& file_name)
{
  return std::string(LAPLACIAN_DEFORMATION_DATA_DIR) + "/" + file_name;
}

/// Reads an OFF mesh of the data folder; returns `false` if it is missing or unreadable. (OFF
/// only: the generic reader would compile every format's reader into every test.)
template <class Mesh>
bool read_data_mesh(const std::string& file_name, Mesh& m)
{
  clear(m);
  if(!CGAL::IO::read_OFF(data_path(file_name), m) || is_empty(m))
    return false;
  internal::set_ids(m);
  return true;
}

namespace internal {

inline double point_distance(const std::array<double, 3>& a, const std::array<double, 3>& b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

template <class Point>
double point_distance(const Point& a, const Point& b)
{
  return std::sqrt(CGAL::to_double(CGAL::squared_distance(a, b)));
}

} // namespace internal

/// Succeeds when `a` and `b` have the same size and `|a[i] - b[i]| <= tolerance` for all `i`;
/// otherwise names the first offending index and its distance.
template <class Point>
::testing::AssertionResult points_near(const std::vector<Point>& a, const std::vector<Point>& b, double tolerance)
{
  if(a.size() != b.size())
    return ::testing::AssertionFailure() << "sizes differ: " << a.size() << " vs " << b.size();
  for(std::size_t i = 0; i < a.size(); ++i)
  {
    const double d = internal::point_distance(a[i], b[i]);
    if(!(d <= tolerance))
      return ::testing::AssertionFailure() << "point " << i << " is at distance " << d
                                           << " (tolerance " << tolerance << ")";
  }
  return ::testing::AssertionSuccess();
}

} // namespace Laplacian_deformation_test

#endif // CGAL_LAPLACIAN_DEFORMATION_TEST_HELPERS_H
