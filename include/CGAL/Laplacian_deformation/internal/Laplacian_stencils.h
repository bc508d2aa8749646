// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_LAPLACIAN_STENCILS_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_LAPLACIAN_STENCILS_H

#include <CGAL/Laplacian_deformation/internal/huge_pages.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/internal/parallel.h>
#include <CGAL/Laplacian_deformation/internal/Policy_variant.h>

#include <CGAL/assertions.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// The index type of the stencils' arrays: 32 bits (half the memory and cache traffic of
// std::size_t in the local step's gathers). Every count fits: D's sparse storage (Eigen's int
// indices) already limits a mesh to fewer than 2^31 operator entries, and build_stencils() checks
// its own counts (std::length_error beyond 2^32 - 1).
typedef std::uint32_t Stencil_index;

// The flat (CSR) description of a representation on a mesh, in dense node and vertex indices.
// It is the only thing the assembly, the transform fits and the solver ever see of a
// representation: the vertex- and the edge-based paths share everything below.
struct Laplacian_stencils
{
  std::size_t number_of_nodes = 0;
  std::size_t number_of_vertices = 0;
  // x_a = sum_k combination_coefficient[k] p_{combination_vertex[k]}, k in [combination_start[a], combination_start[a+1])
  std::vector<Stencil_index> combination_start;
  std::vector<Stencil_index> combination_vertex;
  std::vector<double> combination_coefficient;
  // N(a) = neighbor[k], k in [neighbor_start[a], neighbor_start[a+1]); weight[k] = w_ab
  std::vector<Stencil_index> neighbor_start;
  std::vector<Stencil_index> neighbor;
  std::vector<double> weight;
  // fan triangles (x_a, x_b, x_c) as local positions of b and c in the neighbour slice of a (only
  // compute_weights() reads them; Mesh_deformer frees them afterwards). 32-bit positions (a slice
  // holds at most 2^32 - 1 neighbours): the largest array of a build, written afresh, half the
  // memory of std::size_t pairs
  std::vector<std::size_t> fan_start;
  std::vector<std::array<Stencil_index, 2>> fan;

  // the node index of each local node (increasing) when the stencils cover part of the mesh
  // (laplacian_stencils_near()); empty when local index = node index (every node)
  std::vector<Stencil_index> global_node;

  std::size_t degree(std::size_t a) const { return neighbor_start[a + 1] - neighbor_start[a]; }
  std::size_t node_index(std::size_t a) const { return global_node.empty() ? a : global_node[a]; }
};

// Whether `Nodes` has the optional member `incident_nodes(v, f)` of DeformationNodes (calls `f(a)`
// for each node whose combination involves the mesh vertex `v`).
template <class Nodes, class = void>
struct has_incident_nodes : std::false_type {};
template <class Nodes>
struct has_incident_nodes<Nodes, std::void_t<decltype(std::declval<const Nodes&>().incident_nodes(
    std::declval<typename Nodes::vertex_descriptor>(), std::declval<void (*)(typename Nodes::node_descriptor)>()))>>
  : std::true_type {};

// The stencils of the nodes `sequence[i]` (node descriptors, in local index order i): the cells
// (neighbours, fans) of the nodes with `is_row(i)`, the combination only of the others;
// `local(b)` is the local index of a neighbour `b` of a row node. Two passes over the nodes, on
// TBB's threads with `parallel` (then `nodes`, `vertex_index` and `local_of` are read concurrently):
// the first counts each node's entries, the second writes them in place, so that every array is
// allocated once at its final size (growing them would touch about twice the memory, and first
// touches of fresh pages are slow on some machines). The stencils do not depend on `parallel`.
template <class Nodes, class VertexIndexMap, class Sequence, class IsRow, class Local>
Laplacian_stencils build_stencils(const Nodes& nodes, std::size_t number_of_vertices, const VertexIndexMap& vertex_index,
                                  const Sequence& sequence, const IsRow& is_row, const Local& local_of,
                                  bool parallel = false)
{
  typedef typename Nodes::node_descriptor node_descriptor;
  Laplacian_stencils s;
  const std::size_t m = sequence.size();
  s.number_of_nodes = m;
  s.number_of_vertices = number_of_vertices;
  const std::size_t largest_index = (std::numeric_limits<Stencil_index>::max)();
  if((std::max)(m, number_of_vertices) > largest_index)
    throw std::length_error("Laplacian_deformation: the mesh is too large for the stencils' 32-bit indices "
                            "(more than 2^32 - 1 nodes, vertices or stencil entries)");

  // the counts of node i at i + 1 (fans: all of its fan triangles, an upper bound of those kept)
  resize_huge(s.combination_start, m + 1);
  resize_huge(s.neighbor_start, m + 1);
  resize_huge(s.fan_start, m + 1);
  s.combination_start[0] = s.neighbor_start[0] = 0;
  s.fan_start[0] = 0;
  for_each_block(m, parallel, [&](std::size_t begin, std::size_t end) {
    for(std::size_t i = begin; i < end; ++i)
    {
      const node_descriptor& a = sequence[i];
      std::size_t combination = 0, neighbors = 0, fans = 0;
      nodes.combination(a, [&](auto, double) { ++combination; });
      if(is_row(i))
      {
        for(node_descriptor b : nodes.neighbors(a))
        {
          (void)b;
          ++neighbors;
        }
        nodes.fan_triangles(a, [&](node_descriptor, node_descriptor) { ++fans; });
      }
      if((std::max)(combination, neighbors) > largest_index)
        throw std::length_error("Laplacian_deformation: a node has more than 2^32 - 1 stencil entries");
      s.combination_start[i + 1] = static_cast<Stencil_index>(combination);
      s.neighbor_start[i + 1] = static_cast<Stencil_index>(neighbors);
      s.fan_start[i + 1] = fans;
    }
  }, 1024);
  {
    std::size_t combination = 0, neighbors = 0;
    for(std::size_t i = 0; i < m; ++i)
    {
      combination += s.combination_start[i + 1];
      neighbors += s.neighbor_start[i + 1];
      if((std::max)(combination, neighbors) > largest_index)
        throw std::length_error("Laplacian_deformation: the mesh is too large for the stencils' 32-bit indices "
                                "(more than 2^32 - 1 nodes, vertices or stencil entries)");
      s.combination_start[i + 1] = static_cast<Stencil_index>(combination);
      s.neighbor_start[i + 1] = static_cast<Stencil_index>(neighbors);
      s.fan_start[i + 1] += s.fan_start[i];
    }
  }
  resize_huge(s.combination_vertex, s.combination_start[m]);
  resize_huge(s.combination_coefficient, s.combination_start[m]);
  resize_huge(s.neighbor, s.neighbor_start[m]);
  resize_huge(s.fan, s.fan_start[m]);
  std::vector<std::size_t> fans_kept(m, 0);   // per node: its fan triangles whose vertices are neighbours
  for_each_block(m, parallel, [&](std::size_t begin, std::size_t end) {
    std::vector<std::size_t> neighbor_index;   // the node indices of the current row's neighbours
    for(std::size_t i = begin; i < end; ++i)
    {
      const node_descriptor& a = sequence[i];
      std::size_t k = s.combination_start[i];
      nodes.combination(a, [&](auto v, double c) {
        s.combination_vertex[k] = static_cast<Stencil_index>(get(vertex_index, v));
        s.combination_coefficient[k++] = c;
      });
      if(!is_row(i))
        continue;
      const std::size_t first = s.neighbor_start[i], last = s.neighbor_start[i + 1];
      neighbor_index.clear();
      k = first;
      for(node_descriptor b : nodes.neighbors(a))
      {
        s.neighbor[k++] = static_cast<Stencil_index>(local_of(b));
        neighbor_index.push_back(nodes.index(b));
      }
      // the position of a fan vertex among the neighbours, found by its node index (local_of() may
      // be a binary search; a fan triangle has two vertices and a cell about twenty triangles)
      auto local = [&](node_descriptor b) {
        const std::size_t ib = nodes.index(b);
        for(std::size_t j = 0; j < neighbor_index.size(); ++j)
          if(neighbor_index[j] == ib)
            return j;
        CGAL_assertion_msg(false, "a fan triangle vertex is not a neighbour of the node");
        return last - first;
      };
      std::size_t f = s.fan_start[i];
      nodes.fan_triangles(a, [&](node_descriptor b, node_descriptor c) {
        const std::size_t tb = local(b), tc = local(c);
        if(tb < last - first && tc < last - first)
          s.fan[f++] = {static_cast<Stencil_index>(tb), static_cast<Stencil_index>(tc)};
      });
      fans_kept[i] = f - s.fan_start[i];
    }
  }, 1024);
  // the fan triangles left out (a vertex that is not a neighbour): close the gaps
  if(std::accumulate(fans_kept.begin(), fans_kept.end(), std::size_t(0)) != s.fan_start[m])
  {
    std::size_t next = 0;
    for(std::size_t i = 0; i < m; ++i)
    {
      const std::size_t begin = s.fan_start[i];
      s.fan_start[i] = next;
      std::copy(s.fan.begin() + std::ptrdiff_t(begin), s.fan.begin() + std::ptrdiff_t(begin + fans_kept[i]),
                s.fan.begin() + std::ptrdiff_t(next));
      next += fans_kept[i];
    }
    s.fan_start[m] = next;
    s.fan.resize(next);
  }
  assign_huge(s.weight, s.neighbor.size(), 0.);
  return s;
}

// Builds the stencils of every node of `nodes` (a model of DeformationNodes), local index = node
// index; `vertex_index` maps mesh vertices to [0, number_of_vertices).
template <class Nodes, class VertexIndexMap>
Laplacian_stencils laplacian_stencils(const Nodes& nodes, std::size_t number_of_vertices,
                                      const VertexIndexMap& vertex_index, bool parallel = false)
{
  typedef typename Nodes::node_descriptor node_descriptor;
  std::vector<node_descriptor> by_index(nodes.number_of_nodes());
  for(node_descriptor a : nodes.nodes())
    by_index[nodes.index(a)] = a;
  return build_stencils(nodes, number_of_vertices, vertex_index, by_index, [](std::size_t) { return true; },
                        [&nodes](const node_descriptor& b) { return nodes.index(b); }, parallel);
}

// The number of bits set in `x`, without a call: the default compile flags have no popcnt
// instruction, and std::bitset::count() then calls a library function per word.
inline std::size_t population_count(std::uint64_t x)
{
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return std::size_t((x * 0x0101010101010101ull) >> 56);
}

// Sorts `entries` by their first member (distinct keys below `bound`): a least-significant-digit
// radix sort, one pass per 8 bits of `bound` (stable; the same order as a comparison sort on the
// keys, which are distinct).
template <class Entry>
void sort_by_index(std::vector<Entry>& entries, std::size_t bound)
{
  std::vector<Entry> other(entries.size());
  for(unsigned shift = 0; shift < 64 && (bound - 1) >> shift != 0; shift += 8)
  {
    std::size_t start[257] = {};
    for(const Entry& e : entries)
      ++start[((e.first >> shift) & 255) + 1];
    for(int d = 0; d < 256; ++d)
      start[d + 1] += start[d];
    for(const Entry& e : entries)
      other[start[(e.first >> shift) & 255]++] = e;
    entries.swap(other);
  }
}

// The stencils of the nodes near the mesh vertices `region` (needs `incident_nodes()`, see
// has_incident_nodes): the rows are the nodes whose combination involves a vertex of `region` or
// one of whose neighbours' does (every row of D = L_w P that touches `region`), with their cells;
// the neighbours of the rows get their combination only (degree 0: their positions serve the
// weights and the local step). The local indices follow the node indices (`global_node`
// increasing), so the rows of D come in the same order as in the whole-mesh stencils and every
// entry of a row is computed from the same cell in the same order: D restricted to the rows that
// touch `region` is bitwise the whole-mesh one's. The cost is proportional to the region's
// neighbourhood, not to the mesh (but for one byte per node of the mesh, zeroed, to meet each
// node once, and a bit per node with a count per 64 nodes to find the local indices; when the
// region is a large part of the mesh, a walk over all nodes, a descriptor per node and a table of
// the local indices). Both walks run on TBB's threads with `parallel`.
template <class Nodes, class VertexIndexMap, class VertexRange>
Laplacian_stencils laplacian_stencils_near(const Nodes& nodes, std::size_t number_of_vertices,
                                           const VertexIndexMap& vertex_index, const VertexRange& region,
                                           bool parallel = false)
{
  typedef typename Nodes::node_descriptor node_descriptor;
  typedef std::pair<std::size_t, node_descriptor> Entry;
  if(nodes.number_of_nodes() > std::size_t((std::numeric_limits<Stencil_index>::max)()))
    throw std::length_error("Laplacian_deformation: the mesh is too large for the stencils' 32-bit indices "
                            "(more than 2^32 - 1 nodes)");
  std::vector<char> is_row;
  std::vector<node_descriptor> sequence;
  std::vector<Stencil_index> global_node;
  const std::size_t region_size = std::size_t(std::distance(region.begin(), region.end()));
  typedef typename std::iterator_traits<decltype(region.begin())>::iterator_category Region_category;
  if(16 * region_size > number_of_vertices &&
     std::is_base_of<std::random_access_iterator_tag, Region_category>::value)
  {
    // a region that is a large part of the mesh: every node's mark in a dense array, set in three
    // phases over all nodes (on TBB's threads with `parallel`; the marks are atomic bytes, and a
    // phase only turns unmarked nodes into its own mark): 1 for the region's nodes, 3 for their
    // other neighbours (both rows), 2 for the rows' other neighbours. The same sets as the
    // walk below, then listed in node order without a sort.
    const std::size_t n = nodes.number_of_nodes();
    Fresh_vector<node_descriptor> by_index(n);   // fresh arrays written in full: prepared (huge_pages.h)
    for(node_descriptor a : nodes.nodes())
      by_index[nodes.index(a)] = a;
    Fresh_vector<std::atomic<unsigned char>> mark(n);   // value-initialised: 0
    auto meet = [&](const node_descriptor& b, unsigned char level) {
      std::atomic<unsigned char>& m = mark[nodes.index(b)];
      if(m.load(std::memory_order_relaxed) == 0)
        m.store(level, std::memory_order_relaxed);   // several threads may store the same level
    };
    for_each_block(region_size, parallel, [&](std::size_t begin, std::size_t end) {
      auto v = region.begin();
      std::advance(v, std::ptrdiff_t(begin));
      for(std::size_t i = begin; i < end; ++i, ++v)
        nodes.incident_nodes(*v, [&](const node_descriptor& a) { mark[nodes.index(a)].store(1, std::memory_order_relaxed); });
    }, 1024);
    for(unsigned char from : {1, 3})
      for_each_block(n, parallel, [&](std::size_t begin, std::size_t end) {
        for(std::size_t a = begin; a < end; ++a)
          if(mark[a].load(std::memory_order_relaxed) == from)
            for(node_descriptor b : nodes.neighbors(by_index[a]))
              meet(b, from == 1 ? 3 : 2);
      }, 1024);
    std::size_t met = 0;
    for(std::size_t a = 0; a < n; ++a)
      met += mark[a].load(std::memory_order_relaxed) != 0;
    is_row.reserve(met);
    sequence.reserve(met);
    global_node.reserve(met);
    for(std::size_t a = 0; a < n; ++a)
      if(const unsigned char m = mark[a].load(std::memory_order_relaxed))
      {
        is_row.push_back(m != 2);
        sequence.push_back(by_index[a]);
        global_node.push_back(static_cast<Stencil_index>(a));
      }
  }
  else
  {
    // each node once (a byte per node of the mesh marks the nodes met): 1 for the rows (the
    // region's nodes, then their other neighbours), 2 for the rows' other neighbours. Each phase
    // walks its list in blocks (on TBB's threads with `parallel` and a random-access region): a
    // block lists the nodes it meets that no earlier phase marked (the marks are only read
    // meanwhile); the lists are then joined in block order, each node kept at its first occurrence,
    // with the descriptor met there. The nodes, their descriptors (a node may have several, such
    // as the two halfedges of an edge, and its cell's order follows the one kept) and their order
    // are a sequential walk's, whatever the threads.
    std::vector<unsigned char> mark(nodes.number_of_nodes(), 0);
    std::vector<Entry> all;
    all.reserve((std::min)(nodes.number_of_nodes(), 8 * region_size + 64));
    constexpr std::size_t block = 1024;
    // f(i, meet) for i in [first, last); the nodes met are kept with `level`
    auto walk = [&](std::size_t first, std::size_t last, bool in_parallel, unsigned char level, const auto& f) {
      const std::size_t blocks = (last - first + block - 1) / block;
      std::vector<std::vector<Entry>> found(blocks);
      for_each_block(blocks, in_parallel, [&](std::size_t b0, std::size_t b1) {
        for(std::size_t b = b0; b < b1; ++b)
        {
          std::vector<Entry>& list = found[b];
          auto meet = [&](const node_descriptor& a) {
            const std::size_t g = nodes.index(a);
            if(mark[g] == 0)
              list.emplace_back(g, a);
          };
          for(std::size_t i = first + b * block; i < (std::min)(last, first + (b + 1) * block); ++i)
            f(i, meet);
        }
      }, 1);
      for(const std::vector<Entry>& list : found)
        for(const Entry& e : list)
          if(mark[e.first] == 0)
          {
            mark[e.first] = level;
            all.push_back(e);
          }
    };
    if constexpr(std::is_base_of<std::random_access_iterator_tag, Region_category>::value)
      walk(0, region_size, parallel, 1, [&](std::size_t i, const auto& meet) {
        nodes.incident_nodes(*(region.begin() + std::ptrdiff_t(i)), meet);
      });
    else
      walk(0, 1, false, 1, [&](std::size_t, const auto& meet) {
        for(const auto& v : region)
          nodes.incident_nodes(v, meet);
      });
    const std::size_t number_of_seeds = all.size();
    walk(0, number_of_seeds, parallel, 1, [&](std::size_t i, const auto& meet) {
      for(node_descriptor b : nodes.neighbors(all[i].second))
        meet(b);
    });
    const std::size_t number_of_rows = all.size();
    walk(number_of_seeds, number_of_rows, parallel, 2, [&](std::size_t i, const auto& meet) {
      for(node_descriptor b : nodes.neighbors(all[i].second))
        meet(b);
    });
    sort_by_index(all, nodes.number_of_nodes());
    is_row.assign(all.size(), 0);
    sequence.reserve(all.size());
    global_node.reserve(all.size());
    for(std::size_t i = 0; i < all.size(); ++i)
    {
      is_row[i] = mark[all[i].first] == 1;
      sequence.push_back(all[i].second);
      global_node.push_back(static_cast<Stencil_index>(all[i].first));
    }
  }
  // the local index of a node: a table by node index when the neighbourhood is a large part of
  // the mesh; otherwise the rank of its bit among the listed nodes' bits, one bit per node of the
  // mesh and a running count per 64 nodes (12 bytes per 64 nodes; a binary search over the list,
  // as before, cost about 16 dependent loads per spoke)
  std::vector<unsigned int> table;
  std::vector<std::uint64_t> listed;
  std::vector<Stencil_index> listed_before;
  if(16 * global_node.size() > nodes.number_of_nodes())
  {
    table.assign(nodes.number_of_nodes(), 0);
    for(std::size_t i = 0; i < global_node.size(); ++i)
      table[global_node[i]] = static_cast<unsigned int>(i);
  }
  else
  {
    const std::size_t words = (nodes.number_of_nodes() + 63) / 64;
    listed.assign(words, 0);
    listed_before.assign(words, 0);
    for(Stencil_index g : global_node)
      listed[g / 64] |= std::uint64_t(1) << (g % 64);
    Stencil_index count = 0;
    for(std::size_t w = 0; w < words; ++w)
    {
      listed_before[w] = count;
      count += static_cast<Stencil_index>(population_count(listed[w]));
    }
  }
  auto local_of = [&](const node_descriptor& b) -> std::size_t {
    const std::size_t g = nodes.index(b);
    if(!table.empty())
      return table[g];
    const std::uint64_t below = listed[g / 64] & ((std::uint64_t(1) << (g % 64)) - 1);
    return std::size_t(listed_before[g / 64]) + population_count(below);
  };
  Laplacian_stencils s = build_stencils(nodes, number_of_vertices, vertex_index, sequence,
                                        [&is_row](std::size_t i) { return is_row[i] != 0; }, local_of, parallel);
  s.global_node.swap(global_node);
  return s;
}

// x = P p for every node.
inline void node_positions(const Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& vertex_positions,
                           std::vector<Eigen::Vector3d>& x)
{
  assign_huge(x, s.number_of_nodes, Eigen::Vector3d(Eigen::Vector3d::Zero()));
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
    for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
      x[a] += s.combination_coefficient[k] * vertex_positions[s.combination_vertex[k]];
}

// Fills s.weight with the weight policy evaluated on every rest cell; with `parallel` (and TBB)
// the nodes are shared among TBB's threads (each cell is independent). `policy` is a concrete
// policy (see compute_weights()).
template <class WeightPolicy, class GeomTraits>
void compute_weights_with(Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& x,
                          const WeightPolicy& policy, const GeomTraits& gt, bool parallel)
{
  typedef typename GeomTraits::Point_3 Point_3;
  auto point = [](const Eigen::Vector3d& p) { return Point_3(p.x(), p.y(), p.z()); };
  for_each_block(s.number_of_nodes, parallel, [&](std::size_t begin, std::size_t end) {
    std::vector<Point_3> neighbors;
    std::vector<std::array<std::size_t, 2>> fans;   // the cell's fan triangles as Node_cell takes them
    std::vector<double> w;
    for(std::size_t a = begin; a < end; ++a)
    {
      const std::size_t first = s.neighbor_start[a], n = s.degree(a);
      if(n == 0)
        continue;                        // no spoke (or a node outside the rows: no cell)
      neighbors.clear();
      for(std::size_t k = first; k < first + n; ++k)
        neighbors.push_back(point(x[s.neighbor[k]]));
      fans.clear();
      for(std::size_t t = s.fan_start[a]; t < s.fan_start[a + 1]; ++t)
        fans.push_back({std::size_t(s.fan[t][0]), std::size_t(s.fan[t][1])});
      const Point_3 center = point(x[a]);
      const Node_cell<GeomTraits> cell(center, neighbors.data(), n, fans.data(), fans.size(), gt);
      policy.weights(cell, w);
      CGAL_assertion(w.size() == n);
      std::copy(w.begin(), w.end(), s.weight.begin() + first);
    }
  }, 1024);
}

// compute_weights_with() with the policy held by a run-time policy (one dispatch for all the
// cells), or with `policy` itself
template <class WeightPolicy, class GeomTraits>
void compute_weights(Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& x,
                     const WeightPolicy& policy, const GeomTraits& gt, bool parallel = false)
{
  visit_policy(policy, [&](const auto& p) { compute_weights_with(s, x, p, gt, parallel); });
}

// P: nodes x vertices, x = P p.
inline Eigen::SparseMatrix<double> combination_matrix(const Laplacian_stencils& s)
{
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(s.combination_vertex.size());
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
    for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
      t.emplace_back(int(a), int(s.combination_vertex[k]), s.combination_coefficient[k]);
  Eigen::SparseMatrix<double> p(int(s.number_of_nodes), int(s.number_of_vertices));
  p.setFromTriplets(t.begin(), t.end());
  return p;
}

// The terms of row a of D = L_w P (see laplacian_operator()) merged by vertex: f(v, D(a, v)) in
// increasing v (in no particular order with `Sorted` = false, for a caller that only counts them:
// the sums do not depend on it), exact zeros dropped; `terms` is scratch. The terms, in the order
// neighbours then x_a, are summed per vertex in that order (0 + t1 + t2 + ...: what a stable sort
// by vertex and a sum in sorted order give, bitwise) into a list of the distinct vertices, which is
// then sorted: a row has a few dozen terms on a dozen vertices, so that sorting the distinct
// vertices only (and finding a term's vertex by a scan of them) moves far fewer entries than
// sorting every term.
template <bool Sorted = true, class F>
void laplacian_operator_row(const Laplacian_stencils& s, std::size_t a,
                            std::vector<std::pair<std::size_t, double>>& terms, const F& f)
{
  terms.clear();
  auto add = [&terms](std::size_t v, double t) {
    for(std::pair<std::size_t, double>& e : terms)
      if(e.first == v)
      {
        e.second += t;
        return;
      }
    terms.emplace_back(v, 0. + t);
  };
  double diagonal = 0;
  for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
  {
    const std::size_t b = s.neighbor[k];
    diagonal += s.weight[k];
    for(std::size_t j = s.combination_start[b]; j < s.combination_start[b + 1]; ++j)
      add(s.combination_vertex[j], -s.weight[k] * s.combination_coefficient[j]);
  }
  if(s.neighbor_start[a + 1] > s.neighbor_start[a])
    for(std::size_t j = s.combination_start[a]; j < s.combination_start[a + 1]; ++j)
      add(s.combination_vertex[j], diagonal * s.combination_coefficient[j]);
  // an insertion sort of the distinct vertices (std::sort would not be faster on a dozen)
  if constexpr(Sorted)
    for(std::size_t i = 1; i < terms.size(); ++i)
    {
      const std::pair<std::size_t, double> t = terms[i];
      std::size_t j = i;
      for(; j > 0 && terms[j - 1].first > t.first; --j)
        terms[j] = terms[j - 1];
      terms[j] = t;
    }
  for(const std::pair<std::size_t, double>& e : terms)
    if(e.second != 0)
      f(e.first, e.second);
}

// The Laplacian operator D = L_w P (rows: nodes, columns: vertices; stored by rows),
// delta_a = sum_b w_ab (x_a - x_b) = (D p)_a. Assembled row by row (row a combines the
// vertices of x_a and of its neighbours) without forming L_w and the sparse product: each entry
// is the sum of its vertex's terms in the row's order of terms (neighbours, then x_a), the
// entries in increasing vertex order; exact zeros (cancellations) are dropped. Two passes over the
// rows, on TBB's threads with `parallel`: the first counts each row's entries, the second writes
// them in place (the matrix is allocated once at its size and written once: no copy, and fresh
// memory is slow to touch on some machines). No other memory proportional to the mesh.
inline Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian_operator(const Laplacian_stencils& s,
                                                                       bool parallel = false)
{
  typedef Eigen::SparseMatrix<double, Eigen::RowMajor> Row_major;
  typedef Row_major::StorageIndex Index;
  Row_major d(Eigen::Index(s.number_of_nodes), Eigen::Index(s.number_of_vertices));
  Index* outer = d.outerIndexPtr();
  outer[0] = 0;
  for_each_block(s.number_of_nodes, parallel, [&](std::size_t begin, std::size_t end) {
    std::vector<std::pair<std::size_t, double>> terms;
    for(std::size_t a = begin; a < end; ++a)
    {
      Index count = 0;
      laplacian_operator_row<false>(s, a, terms, [&count](std::size_t, double) { ++count; });   // no sort to count
      outer[a + 1] = count;
    }
  }, 1024);
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
  {
    if(std::size_t(outer[a]) + std::size_t(outer[a + 1]) > std::size_t((std::numeric_limits<Index>::max)()))
      throw std::length_error("Laplacian_deformation: the operator has more entries than its sparse storage's "
                              "indices can count (2^31 - 1)");
    outer[a + 1] += outer[a];
  }
  d.resizeNonZeros(Eigen::Index(outer[s.number_of_nodes]));
  advise_sparse_storage(d);   // fresh storage, advised before it is written
  Index* inner = d.innerIndexPtr();
  double* values = d.valuePtr();
  for_each_block(s.number_of_nodes, parallel, [&](std::size_t begin, std::size_t end) {
    std::vector<std::pair<std::size_t, double>> terms;
    for(std::size_t a = begin; a < end; ++a)
    {
      Index next = outer[a];
      laplacian_operator_row(s, a, terms, [&](std::size_t v, double value) {
        inner[next] = Index(v);
        values[next++] = value;
      });
    }
  }, 1024);
  return d;
}

// delta = D p for the vertex positions `p`, row by row (no dense copy of `p`), on TBB's threads
// with `parallel` (each row is its own sum: the same values either way).
inline Eigen::MatrixX3d operator_times_positions(const Eigen::SparseMatrix<double, Eigen::RowMajor>& d,
                                                 const std::vector<Eigen::Vector3d>& p, bool parallel = false)
{
  Eigen::MatrixX3d delta;
  resize_dense_huge(delta, d.rows(), 3);
  for_each_block(std::size_t(d.rows()), parallel, [&](std::size_t begin, std::size_t end) {
    for(Eigen::Index r = Eigen::Index(begin); r < Eigen::Index(end); ++r)
    {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for(Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(d, r); it; ++it)
        sum += it.value() * p[std::size_t(it.col())];
      delta.row(r) = sum.transpose();
    }
  }, 1024);
  return delta;
}

// The weights of the rest cells far from unit size: beyond coordinates 2^+-30 they are computed on
// a copy of the node positions scaled by a power of two (exact), since a weight policy's
// intermediate products (squared lengths, areas) would overflow or underflow otherwise. The
// operator is then a power of two times the true one, which leaves a least-squares solution
// unchanged (only reported energies scale). `largest` is the largest rest coordinate (of the whole
// mesh, so that the decision does not depend on the region).
template <class WeightPolicy, class GeomTraits>
void compute_scale_safe_weights(Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& x, double largest,
                                const WeightPolicy& policy, const GeomTraits& gt, bool parallel)
{
  const int exponent = largest > 0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
  if(exponent > 30 || exponent < -30)
  {
    std::vector<Eigen::Vector3d> scaled(x);
    for(Eigen::Vector3d& y : scaled)
      y *= std::ldexp(1., -exponent);
    compute_weights(s, scaled, policy, gt, parallel);
  }
  else
    compute_weights(s, x, policy, gt, parallel);
}

// The rest operator of a representation: the one builder behind Mesh_deformer, laplacian_matrix()
// and the metrics' Laplacian errors. Stencils (of every node, or with `region` of the nodes near
// those vertices: laplacian_stencils_near()), rest node positions, scale-safe weights, D and
// delta = D p_rest. The fan triangles are freed once the weights are computed. With `largest` > 0
// (the largest rest coordinate of the whole mesh: largest_coordinate(), kept by a caller that
// builds several operators of one rest geometry) the weights of far-from-unit meshes come from a
// power-of-two scaled copy (see compute_scale_safe_weights(): right for least squares and for
// relative errors, not for a caller that wants the operator's own values, as laplacian_matrix(),
// which passes 0).
// the largest absolute coordinate of `rest` (build_rest_operator()'s `largest`)
inline double largest_coordinate(const std::vector<Eigen::Vector3d>& rest)
{
  double largest = 0;
  for(const Eigen::Vector3d& p : rest)
    largest = (std::max)(largest, p.cwiseAbs().maxCoeff());
  return largest;
}

struct Rest_operator
{
  Laplacian_stencils stencils;
  std::vector<Eigen::Vector3d> rest_nodes;
  Eigen::SparseMatrix<double, Eigen::RowMajor> d;
  Eigen::MatrixX3d delta;
};

// the first half of build_rest_operator(): the stencils (fan triangles kept), the rest node
// positions and the weights
template <class Nodes, class VertexIndexMap, class WeightPolicy, class GeomTraits,
          class VertexRange = std::vector<typename Nodes::vertex_descriptor>>
void build_weighted_stencils(Laplacian_stencils& s, std::vector<Eigen::Vector3d>& rest_nodes, const Nodes& nodes,
                             const VertexIndexMap& vertex_index, const std::vector<Eigen::Vector3d>& rest,
                             const WeightPolicy& weights, const GeomTraits& gt, bool parallel, double largest,
                             const VertexRange* region = nullptr)
{
  if constexpr(has_incident_nodes<Nodes>::value)
  {
    if(region != nullptr)
      s = laplacian_stencils_near(nodes, rest.size(), vertex_index, *region, parallel);
    else
      s = laplacian_stencils(nodes, rest.size(), vertex_index, parallel);
  }
  else
    s = laplacian_stencils(nodes, rest.size(), vertex_index, parallel);
  node_positions(s, rest, rest_nodes);
  compute_scale_safe_weights(s, rest_nodes, largest, weights, gt, parallel);   // largest 0: as they are
}

template <class Nodes, class VertexIndexMap, class WeightPolicy, class GeomTraits,
          class VertexRange = std::vector<typename Nodes::vertex_descriptor>>
void build_rest_operator(Rest_operator& r, const Nodes& nodes, const VertexIndexMap& vertex_index,
                         const std::vector<Eigen::Vector3d>& rest, const WeightPolicy& weights, const GeomTraits& gt,
                         bool parallel, double largest, const VertexRange* region = nullptr)
{
  build_weighted_stencils(r.stencils, r.rest_nodes, nodes, vertex_index, rest, weights, gt, parallel, largest, region);
  // the fan triangles serve the weights only: free them before a factorisation (its peak)
  std::vector<std::array<Stencil_index, 2>>().swap(r.stencils.fan);
  std::vector<std::size_t>().swap(r.stencils.fan_start);
  {
    Eigen::SparseMatrix<double, Eigen::RowMajor> d = laplacian_operator(r.stencils, parallel);
    r.d.swap(d);   // an assignment would copy it (no move assignment in Eigen 3.4)
  }
  r.delta = operator_times_positions(r.d, rest, parallel);
}

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_LAPLACIAN_STENCILS_H
