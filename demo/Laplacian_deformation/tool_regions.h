// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// The tools' one way of growing a region of interest around handle vertices (not part of the
// package's API): by rings (laplacian_deform --roi-rings, the editor's "grow") and by distance
// along the mesh's edges (laplacian_deform --roi-radius, the harness's "roi geodesic").

#ifndef LAPLACIAN_DEFORMATION_TOOL_REGIONS_H
#define LAPLACIAN_DEFORMATION_TOOL_REGIONS_H

#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/properties.h>

#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace Laplacian_deformation_tools {

// `Mesh` below: a CGAL::Surface_mesh (its vertex descriptors are indices in [0, num_vertices)).
// The sources must be vertices of the mesh; isolated vertices have no neighbour.

/// The vertices at most `rings` edges away from `sources`, in breadth-first order: the sources
/// first (each once, in their order), then ring after ring, each vertex's neighbours in the order
/// of `vertices_around_target()`.
template <class Mesh>
std::vector<typename boost::graph_traits<Mesh>::vertex_descriptor>
k_ring_vertices(const Mesh& mesh, const std::vector<typename boost::graph_traits<Mesh>::vertex_descriptor>& sources,
                std::size_t rings)
{
  typedef typename boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;
  const std::size_t unseen = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> depth(num_vertices(mesh), unseen);
  std::vector<vertex_descriptor> order;
  for(vertex_descriptor s : sources)
    if(depth[std::size_t(s)] == unseen)
    {
      depth[std::size_t(s)] = 0;
      order.push_back(s);
    }
  for(std::size_t next = 0; next < order.size(); ++next)
  {
    const vertex_descriptor v = order[next];
    const std::size_t d = depth[std::size_t(v)];
    if(d == rings || halfedge(v, mesh) == boost::graph_traits<Mesh>::null_halfedge())
      continue;
    for(vertex_descriptor w : CGAL::vertices_around_target(halfedge(v, mesh), mesh))
      if(depth[std::size_t(w)] == unseen)
      {
        depth[std::size_t(w)] = d + 1;
        order.push_back(w);
      }
  }
  return order;
}

/// The vertices whose shortest path along the mesh's edges to `sources` is at most `radius` long
/// (Dijkstra over the edge lengths: an upper bound of the geodesic distance), in order of
/// increasing distance (the sources first, each once, whatever `radius`). `distances`, if given,
/// receives the distance of every vertex (by index; infinity for the vertices not returned).
template <class Mesh>
std::vector<typename boost::graph_traits<Mesh>::vertex_descriptor>
geodesic_vertices(const Mesh& mesh, const std::vector<typename boost::graph_traits<Mesh>::vertex_descriptor>& sources,
                  double radius, std::vector<double>* distances = nullptr)
{
  typedef typename boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;
  const auto points = get(CGAL::vertex_point, mesh);
  std::vector<double> distance(num_vertices(mesh), std::numeric_limits<double>::infinity());
  std::vector<bool> settled(distance.size(), false);
  typedef std::pair<double, std::size_t> Entry;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for(vertex_descriptor s : sources)
    if(distance[std::size_t(s)] != 0)
    {
      distance[std::size_t(s)] = 0;
      queue.push(Entry(0., std::size_t(s)));
    }
  std::vector<vertex_descriptor> order;
  while(!queue.empty())
  {
    const Entry top = queue.top();
    queue.pop();
    if(top.first > distance[top.second] || settled[top.second])
      continue;
    settled[top.second] = true;
    const vertex_descriptor v(static_cast<typename Mesh::size_type>(top.second));
    order.push_back(v);
    if(halfedge(v, mesh) == boost::graph_traits<Mesh>::null_halfedge())
      continue;
    for(vertex_descriptor w : CGAL::vertices_around_target(halfedge(v, mesh), mesh))
    {
      // squared_distance: the kernel's, found by ADL
      const double d = top.first + std::sqrt(squared_distance(get(points, v), get(points, w)));
      if(d <= radius && d < distance[std::size_t(w)])
      {
        distance[std::size_t(w)] = d;
        queue.push(Entry(d, std::size_t(w)));
      }
    }
  }
  if(distances != nullptr)
    distances->swap(distance);
  return order;
}

/// `members` as a membership mask over the `n` vertex indices
template <class Vertex>
std::vector<bool> region_mask(std::size_t n, const std::vector<Vertex>& members)
{
  std::vector<bool> in(n, false);
  for(const Vertex& v : members)
    in[std::size_t(v)] = true;
  return in;
}

} // namespace Laplacian_deformation_tools

#endif // LAPLACIAN_DEFORMATION_TOOL_REGIONS_H
