// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_DEFORMATION_CORE_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_DEFORMATION_CORE_H

#include <CGAL/Laplacian_deformation/internal/huge_pages.h>
#include <CGAL/Laplacian_deformation/Deformation_result.h>
#include <CGAL/Laplacian_deformation/Least_squares_solver.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/internal/Laplacian_stencils.h>
#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>
#include <CGAL/Laplacian_deformation/internal/normal_matrix.h>
#include <CGAL/Laplacian_deformation/internal/parallel.h>
#include <CGAL/Laplacian_deformation/internal/Policy_variant.h>

#include <CGAL/tags.h>

#include <chrono>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

enum Vertex_role : unsigned char
{
  FIXED_VERTEX = 0,      // outside the region of interest, held at its rest position
  FREE_VERTEX,           // in the region of interest, unknown
  HARD_CONTROL_VERTEX,   // known: at its target
  SOFT_CONTROL_VERTEX    // unknown, pulled towards its target by a soft row
};

inline bool is_unknown(unsigned char role) { return role == FREE_VERTEX || role == SOFT_CONTROL_VERTEX; }

// The representation-agnostic heart of Mesh_deformer: region of solution, rows, the factored
// least-squares system, the parallel local step and the iterations. It sees a representation
// only through its stencils and operator D.
template <class TransformPolicy, class SolverTraits, class ConcurrencyTag>
class Deformation_core
{
public:
  typedef Eigen::SparseMatrix<double, Eigen::RowMajor> Operator;
  typedef Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Rows3;

  // the transform policy: default-constructed, or a copy of `policy`
  Deformation_core() = default;
  explicit Deformation_core(const TransformPolicy& policy) : m_policy(policy) {}
  // the policy of the next local steps (the system does not depend on it)
  void set_policy(const TransformPolicy& policy) { m_policy = policy; }
  const TransformPolicy& policy() const { return m_policy; }

  // `d`: the full operator (rows x vertices, by rows); `delta` = D p_rest; `rest_nodes` = P p_rest.
  // Row r of D uses the transform of node `owner[r]` (b_r = T_owner delta_r); without `owner`,
  // the rows are the nodes themselves (row a is node a's Laplacian row). `role` is per vertex of
  // the mesh; `roi`: the vertices whose role is not FIXED_VERTEX, increasing (no loop of this
  // call runs over the vertices of the mesh).
  Deformation_result preprocess(const Laplacian_stencils& s, const Operator& d,
                                const Eigen::MatrixX3d& delta,
                                const std::vector<Eigen::Vector3d>& rest_nodes,
                                const std::vector<unsigned char>& role, const std::vector<std::size_t>& roi,
                                double soft_weight, const std::vector<std::size_t>* owner = nullptr)
  {
    Deformation_result result;
    m_ready = false;
    m_stencils = &s;
    m_operator = &d;
    const std::size_t n = s.number_of_vertices;

    // unknowns
    if(n > std::size_t((std::numeric_limits<int>::max)()))
      throw std::length_error("Laplacian_deformation: the mesh is too large for the system's 32-bit indices "
                              "(more than 2^31 - 1 vertices)");
    // the unknown index per vertex persists across calls: -1 but at the last call's unknowns,
    // which are cleared (a new selection on a large mesh does not rewrite an array of the mesh's size)
    if(m_unknown_index.size() != n)
      assign_huge(m_unknown_index, n, -1);
    else
      for(std::size_t v : m_unknowns)
        m_unknown_index[v] = -1;
    m_unknowns.clear();
    CGAL_assertion(std::is_sorted(roi.begin(), roi.end()));
    for(std::size_t v : roi)
      if(is_unknown(role[v]))
      {
        m_unknown_index[v] = static_cast<int>(m_unknowns.size());
        m_unknowns.push_back(v);
      }
    const Eigen::Index nu = static_cast<Eigen::Index>(m_unknowns.size());

    // rows: every row of D that touches an unknown vertex, in increasing order; the nodes whose
    // transforms they use (the fitted nodes), increasing, and each row's fitted node
    typedef Eigen::SparseMatrix<double>::StorageIndex Index;
    const Index* d_outer = d.outerIndexPtr();
    const Index* d_inner = d.innerIndexPtr();
    const double* d_value = d.valuePtr();
    const Index* d_nonzeros = d.innerNonZeroPtr();   // null when compressed
    auto row_end = [&](std::size_t a) { return d_nonzeros ? d_outer[a] + d_nonzeros[a] : d_outer[a + 1]; };
    {
      Fresh_vector<unsigned char> touches(std::size_t(d.rows()), 0);
      for_each_block(touches.size(), [&](std::size_t begin, std::size_t end) {
        for(std::size_t a = begin; a < end; ++a)
          for(Index k = d_outer[a]; k < row_end(a) && !touches[a]; ++k)
            touches[a] = m_unknown_index[std::size_t(d_inner[k])] >= 0;
      });
      m_rows.clear();
      reserve_huge(m_rows, std::size_t(std::count(touches.begin(), touches.end(), 1)));
      for(std::size_t a = 0; a < touches.size(); ++a)
        if(touches[a])
          m_rows.push_back(a);
    }
    const Eigen::Index nr = static_cast<Eigen::Index>(m_rows.size());
    if(owner == nullptr)   // each row is its own node's: the fitted nodes are the rows
    {
      m_fit_nodes.assign(m_rows.begin(), m_rows.end());
      m_row_fit.resize(m_rows.size());
      std::iota(m_row_fit.begin(), m_row_fit.end(), std::size_t(0));
    }
    else
    {
      Fresh_vector<long> fit_index(s.number_of_nodes, -1);
      for(std::size_t r : m_rows)
        fit_index[(*owner)[r]] = 0;
      m_fit_nodes.clear();
      for(std::size_t a = 0; a < s.number_of_nodes; ++a)
        if(fit_index[a] == 0)
        {
          fit_index[a] = long(m_fit_nodes.size());
          m_fit_nodes.push_back(a);
        }
      m_row_fit.resize(m_rows.size());
      for(std::size_t r = 0; r < m_rows.size(); ++r)
        m_row_fit[r] = std::size_t(fit_index[(*owner)[m_rows[r]]]);
    }

    // split D[rows, :] into the unknown block A (by columns: the solver's) and the known block K
    // (by rows: K p_known row by row), both in the order of D's rows and columns. A is a
    // transposition, done in a few blocks of rows: each block counts its entries per column, the
    // counts give each block its own range in every column, and the blocks fill them at once
    // (the same matrix as a sequential pass: each column's rows increase).
    m_soft.clear();
    Fresh_vector<char> soft_column(m_unknowns.size(), 0);
    for(std::size_t j = 0; j < m_unknowns.size(); ++j)
      if(role[m_unknowns[j]] == SOFT_CONTROL_VERTEX)
      {
        m_soft.push_back(j);
        soft_column[j] = 1;
      }
    const bool parallel = runs_in_parallel<ConcurrencyTag>();
    const std::size_t blocks = parallel && m_rows.size() > 16384 ? 4 : 1;
    auto block_rows = [&](std::size_t block) { return m_rows.size() * block / blocks; };
    std::vector<Fresh_vector<Index>> next_a(blocks, Fresh_vector<Index>(std::size_t(nu), 0));
    Fresh_vector<Index> a_outer(std::size_t(nu) + 1, 0), k_outer(m_rows.size() + 1, 0);
    internal::for_each_block(blocks, parallel, [&](std::size_t first, std::size_t last) {
      for(std::size_t block = first; block < last; ++block)
        for(std::size_t r = block_rows(block); r < block_rows(block + 1); ++r)
          for(Index k = d_outer[m_rows[r]]; k < row_end(m_rows[r]); ++k)
          {
            const long j = m_unknown_index[std::size_t(d_inner[k])];
            ++(j >= 0 ? next_a[block][std::size_t(j)] : k_outer[r + 1]);
          }
    }, 1);
    for_each_block(std::size_t(nu), [&](std::size_t begin, std::size_t end) {
      for(std::size_t j = begin; j < end; ++j)
      {
        Index count = soft_column[j];
        for(std::size_t block = 0; block < blocks; ++block)
          count += next_a[block][j];
        a_outer[j + 1] = count;
      }
    });
    std::partial_sum(a_outer.begin(), a_outer.end(), a_outer.begin());
    std::partial_sum(k_outer.begin(), k_outer.end(), k_outer.begin());
    for_each_block(std::size_t(nu), [&](std::size_t begin, std::size_t end) {
      for(std::size_t j = begin; j < end; ++j)
        for(std::size_t block = 0, next = std::size_t(a_outer[j]); block < blocks; ++block)
        {
          const std::size_t count = std::size_t(next_a[block][j]);
          next_a[block][j] = Index(next);
          next += count;
        }
    });
    m_a.resize(nr + Eigen::Index(m_soft.size()), nu);
    m_a.resizeNonZeros(a_outer.back());
    advise_sparse_storage(m_a);
    m_known.resize(nr, Eigen::Index(n));
    m_known.resizeNonZeros(k_outer.back());
    advise_sparse_storage(m_known);
    std::copy(a_outer.begin(), a_outer.end(), m_a.outerIndexPtr());
    std::copy(k_outer.begin(), k_outer.end(), m_known.outerIndexPtr());
    internal::for_each_block(blocks, parallel, [&](std::size_t first, std::size_t last) {
      for(std::size_t block = first; block < last; ++block)
      {
        Fresh_vector<Index>& next = next_a[block];
        for(std::size_t r = block_rows(block); r < block_rows(block + 1); ++r)
        {
          Index known = k_outer[r];
          for(Index k = d_outer[m_rows[r]]; k < row_end(m_rows[r]); ++k)
          {
            const long j = m_unknown_index[std::size_t(d_inner[k])];
            if(j >= 0)
            {
              const Index position = next[std::size_t(j)]++;
              m_a.innerIndexPtr()[position] = Index(r);
              m_a.valuePtr()[position] = d_value[k];
            }
            else
            {
              m_known.innerIndexPtr()[known] = d_inner[k];
              m_known.valuePtr()[known++] = d_value[k];
            }
          }
        }
      }
    }, 1);
    std::vector<Fresh_vector<Index>>().swap(next_a);

    // the connected parts of the unknowns (rows join their unknowns), the sum of the squares of
    // A's entries and their finiteness: one pass in row order; the diagonal of A^T A per column
    Fresh_vector<long> first_unknown(m_rows.size(), -1);
    Union_find components(m_unknowns.size());
    double sum_squares = 0;
    bool operator_finite = true;
    for(std::size_t r = 0; r < m_rows.size(); ++r)
    {
      long& first = first_unknown[r];
      for(Index k = d_outer[m_rows[r]]; k < row_end(m_rows[r]); ++k)
      {
        const long j = m_unknown_index[std::size_t(d_inner[k])];
        if(j < 0)
          continue;
        const double value = d_value[k];
        sum_squares += value * value;
        operator_finite = operator_finite && std::isfinite(value);
        if(first < 0)
          first = j;
        else
          components.join(std::size_t(first), std::size_t(j));
      }
    }
    Fresh_vector<double> column_squares(m_unknowns.size(), 0.);   // the diagonal of A^T A
    for_each_block(std::size_t(nu), [&](std::size_t begin, std::size_t end) {
      for(std::size_t j = begin; j < end; ++j)
        for(Index k = a_outer[j]; k < a_outer[j + 1] - soft_column[j]; ++k)
          column_squares[j] += m_a.valuePtr()[k] * m_a.valuePtr()[k];
    });
    auto row_has_known = [&](std::size_t r) { return k_outer[r + 1] > k_outer[r]; };

    // singular configurations: a connected part of the unknowns with no anchor
    Fresh_vector<char> anchored(m_unknowns.size(), 0);
    for(std::size_t r = 0; r < m_rows.size(); ++r)
      if(row_has_known(r) && first_unknown[r] >= 0)
        anchored[components.find(std::size_t(first_unknown[r]))] = 1;
    for(std::size_t j = 0; j < m_unknowns.size(); ++j)
      if(role[m_unknowns[j]] == SOFT_CONTROL_VERTEX)
        anchored[components.find(j)] = 1;
    Fresh_vector<std::size_t> unanchored_size(m_unknowns.size(), 0);
    for(std::size_t j = 0; j < m_unknowns.size(); ++j)
      if(!anchored[components.find(j)])
        result.unanchored_size = (std::max)(result.unanchored_size, ++unanchored_size[components.find(j)]);
    if(result.unanchored_size > 0)
    {
      result.status = UNANCHORED_REGION;
      // free vertices without any entry in D although they belong to a node with neighbours:
      // every weight of their cells vanished (D drops exact zeros)
      std::vector<char> in_stencil(n, 0);
      for(std::size_t a = 0; a < s.number_of_nodes; ++a)
        if(s.degree(a) > 0)
          for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
            in_stencil[s.combination_vertex[k]] = 1;
      std::size_t zero = 0;
      for(std::size_t j = 0; j < m_unknowns.size(); ++j)
        zero += role[m_unknowns[j]] == FREE_VERTEX && in_stencil[m_unknowns[j]] &&
                a_outer[j + 1] == a_outer[j];
      if(zero > 0)
        result.message = "the Laplacian operator is zero at " + std::to_string(zero) +
                         " free vertices: every weight of their cells vanishes (collinear or degenerate "
                         "cells, or coordinates too large or too small for the number type of the mesh's "
                         "kernel), so nothing determines them: the system is singular";
      else
        result.message = "a connected part of " + std::to_string(result.unanchored_size) +
                         " free vertices touches no fixed or control vertex: the system is singular";
      return result;
    }
    // weights far from 1 (cotangent weights scale like 1 / length^2) overflow or underflow when
    // squared: the diagonal of A^T A must be finite, and positive in every non-empty column
    for(std::size_t j = 0; operator_finite && j < m_unknowns.size(); ++j)
      if(!(column_squares[j] < HUGE_VAL) ||
         (column_squares[j] == 0 && a_outer[j + 1] > a_outer[j] + int(role[m_unknowns[j]] == SOFT_CONTROL_VERTEX)))
      {
        result.status = FACTORIZATION_FAILED;
        result.message = column_squares[j] == 0
                             ? "the normal matrix underflows: the Laplacian weights are too small to be squared "
                               "(coordinates too large for the weight policy: cotangent weights decrease like "
                               "1 / length^2)"
                             : "the normal matrix overflows: the Laplacian weights are too large to be squared "
                               "(coordinates too small for the weight policy: cotangent weights grow like "
                               "1 / length^2)";
        return result;
      }

    // soft rows lambda (p_c - t_c), lambda^2 = soft_weight * mean diagonal of A^T A: the last
    // entry of each soft control's column
    m_lambda = nu > 0 ? std::sqrt(soft_weight * sum_squares / double(nu)) : 0.;
    for(std::size_t k = 0; k < m_soft.size(); ++k)
    {
      const int last = a_outer[m_soft[k] + 1] - 1;
      m_a.innerIndexPtr()[last] = int(nr) + int(k);
      m_a.valuePtr()[last] = m_lambda;
    }
    const Eigen::Index a_rows = m_a.rows();
    // A by rows for A^T A: the rows of D restricted to the unknown columns (the unknowns increase
    // with the vertex index: the entries of unknown index >= j are those of vertex >= m_unknowns[j]),
    // then the soft rows
    const int* const unknown_index = m_unknown_index.data();
    const std::size_t* const unknowns = m_unknowns.data();
    const std::size_t* const soft = m_soft.data();
    const double lambda = m_lambda;
    // where each system row's entries lie in D: one record per row, so that a row is reached
    // through one scattered load instead of two (the rows of a column are far apart)
    struct Row_range
    {
      Index begin, end;
    };
    Fresh_vector<Row_range> row_range(m_rows.size());
    for_each_block(m_rows.size(), [&](std::size_t begin, std::size_t end) {
      for(std::size_t r = begin; r < end; ++r)
        row_range[r] = Row_range{d_outer[m_rows[r]], Index(row_end(m_rows[r]))};
    });
    const Row_range* const ranges = row_range.data();
    auto rows = [=](Index r, Index j, auto&& f) {
      if(r >= Index(nr))
      {
        const std::size_t column = soft[std::size_t(r - Index(nr))];
        if(Index(column) >= j)
          f(Index(column), lambda);
        return;
      }
      const Index* begin = d_inner + ranges[r].begin;
      const Index* const end = d_inner + ranges[r].end;
      if(j > 0)
        begin = branchless_lower_bound(begin, end, Index(unknowns[std::size_t(j)]));
      for(const Index* p = begin; p != end; ++p)
      {
        const long u = unknown_index[*p];
        if(u >= 0)
          f(Index(u), d_value[p - d_inner]);
      }
    };
    auto prefetch_row = [=](Index r, int stage) {
      if(r >= Index(nr))
        return;
      if(stage == 0)
        prefetch_line(ranges + r);
      else
      {
        prefetch_line(d_inner + ranges[r].begin);
        prefetch_line(d_inner + ranges[r].end - 1);
        if(stage == 2)
        {
          prefetch_line(d_value + ranges[r].begin);
          prefetch_line(d_value + ranges[r].end - 1);
        }
      }
    };
    if(nu > 0 && !m_solver.factor_with_rows(std::move(m_a), rows, prefetch_row))   // the solver keeps A: no copy
    {
      result.status = m_solver.info() == m_solver.NOT_FINITE ? NON_FINITE_INPUT : FACTORIZATION_FAILED;
      result.message = m_solver.info() == m_solver.NOT_FINITE
                           ? "the Laplacian operator is not finite: a weight is NaN or infinite "
                             "(the weight policy failed on the rest positions)"
                           : "the normal matrix could not be factored (numerically singular)";
      return result;
    }

    // per-row data for the local step: delta; the cells (rest and current edges, fit weights)
    // are gathered per row in the local step, from m_nodes (rest and current positions) and the stencils
    resize_dense_huge(m_delta, nr, 3);
    for(std::size_t r = 0; r < m_rows.size(); ++r)
      m_delta.row(Eigen::Index(r)) = delta.row(Eigen::Index(m_rows[r]));
    m_max_degree = 0;
    for(std::size_t a : m_fit_nodes)
      m_max_degree = (std::max)(m_max_degree, s.degree(a));
    // the nodes the local step evaluates: the fitted nodes and their neighbours, each once
    Fresh_vector<char> needed(s.number_of_nodes, 0);
    for(std::size_t a : m_fit_nodes)
    {
      needed[a] = 1;
      for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
        needed[s.neighbor[k]] = 1;
    }
    m_needed_nodes.clear();
    m_needed_nodes.reserve(std::size_t(std::count(needed.begin(), needed.end(), 1)));
    for(std::size_t a = 0; a < s.number_of_nodes; ++a)
      if(needed[a])
        m_needed_nodes.push_back(a);
    // each needed node's rest position next to its current one (filled by the local step)
    assign_huge(m_nodes, s.number_of_nodes, Node_positions());
    for(std::size_t a : m_needed_nodes)
      m_nodes[a].rest = rest_nodes[a];
    assign_huge(m_transforms, m_fit_nodes.size(), Eigen::Matrix3d(Eigen::Matrix3d::Identity()));
    // the known vertices with a column in K, each once, increasing: marked -2 in the unknown index
    // (-1 at every known vertex) while listed, then sorted. On a small ROI they are about a tenth of
    // K's entries; sorting all the entries took 1.3 to 1.4 ms per call at 416k vertices.
    m_known_vertices.clear();
    for(Eigen::Index k = 0; k < m_known.nonZeros(); ++k)
    {
      const std::size_t v = std::size_t(m_known.innerIndexPtr()[k]);
      if(m_unknown_index[v] == -1)
      {
        m_known_vertices.push_back(v);   // before the mark: an exception leaves no mark behind
        m_unknown_index[v] = -2;
      }
    }
    for(std::size_t v : m_known_vertices)
      m_unknown_index[v] = -1;
    std::sort(m_known_vertices.begin(), m_known_vertices.end());
    m_known_positions.clear();
    resize_dense_huge(m_known_part, nr, 3);
    m_known_part.setZero();
    assign_huge(m_row_energy, std::size_t(a_rows), 0.);
    m_has_solution = false;
    m_ready = true;
    return result;
  }

  // Runs up to `iterations` iterations. `positions` holds every vertex: the known ones at their
  // prescribed positions, the soft controls at their targets, the free ones at their current
  // positions; it is updated in place (the unknowns' entries; on failure they are unspecified),
  // and on success it holds the solution. `diagonal` scales the change criterion. Without
  // `track_energy`, the energy of each iteration is not computed (result.energies stays empty).
  Deformation_result iterate(std::vector<Eigen::Vector3d>& positions, std::size_t iterations,
                             double tolerance, double diagonal, bool track_energy = true)
  {
    Deformation_result result;
    const Eigen::Index nr = Eigen::Index(m_rows.size()), nu = Eigen::Index(m_unknowns.size());
    if(nu == 0)
      return result;

    update_known_part(positions);
    // b, rhs and x are kept across calls: the CLI and the editor call deform(1) per iteration
    Rows3& b = m_b;
    Eigen::MatrixX3d &rhs = m_rhs, &x = m_x;
    // fresh at the first call: advised for huge pages (first touches, see internal/huge_pages.h)
    resize_dense_huge(b, Eigen::Index(m_row_energy.size()), 3);
    resize_dense_huge(rhs, nu, 3);
    m_soft_targets.resize(m_soft.size());
    for(std::size_t k = 0; k < m_soft.size(); ++k)
    {
      m_soft_targets[k] = positions[m_unknowns[m_soft[k]]];
      b.row(nr + Eigen::Index(k)) = m_lambda * m_soft_targets[k].transpose();
    }

    // the current solution, or the rest-start positions, as the reference for the change
    // (in place: no copy of the positions, which cover the whole mesh)
    std::vector<Eigen::Vector3d>& current = positions;
    if(m_has_solution)
      for(Eigen::Index j = 0; j < nu; ++j)
        current[m_unknowns[std::size_t(j)]] = m_solution.row(j).transpose();

    typedef std::chrono::steady_clock Clock;
    auto seconds_since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    for(std::size_t iteration = 0; iteration < iterations; ++iteration)
    {
      Clock::time_point t0 = Clock::now();
      const std::size_t failed_fits = m_has_solution ? local_step(current) : 0;
      result.local_step_seconds += seconds_since(t0);
      if(failed_fits > 0)
      {
        result.status = NON_FINITE_RESULT;
        result.message = "the transform fit of " + std::to_string(failed_fits) +
                         " node(s) is not finite (NaN or infinity); nothing was written";
        return result;
      }
      t0 = Clock::now();
      right_hand_side(b, rhs);
      result.right_hand_side_seconds += seconds_since(t0);
      t0 = Clock::now();
      const bool solved = m_solver.solve_normal_equations(rhs, x);
      result.solve_seconds += seconds_since(t0);
      if(!solved)
      {
        result.status = m_solver.info() == m_solver.NOT_FINITE ? NON_FINITE_RESULT : SOLVE_FAILED;
        result.message = result.status == NON_FINITE_RESULT ? "the solution is not finite; nothing was written"
                                                            : "the back-substitution failed; nothing was written";
        return result;
      }
      // displacements scaled by a power of two (exact): their norms neither overflow nor underflow;
      // the largest squared norm, then its square root (the largest norm: the square root is
      // monotonic and correctly rounded)
      const double unit = normalizing_power_of_two(diagonal);
      double change = 0;
      for(Eigen::Index j = 0; j < nu; ++j)
      {
        Eigen::Vector3d& p = current[m_unknowns[std::size_t(j)]];
        change = (std::max)(change, (unit * (x.row(j).transpose() - p)).squaredNorm());
        p = x.row(j).transpose();
      }
      change = std::sqrt(change);
      m_solution = x;
      m_has_solution = true;
      if(track_energy)
        result.energies.push_back(energy(current, b));
      result.last_change = diagonal > 0 ? change / (unit * diagonal) : change / unit;
      ++result.iterations;
      if(result.last_change <= tolerance)
        break;
    }
    result.energy = result.energies.empty() ? 0. : result.energies.back();
    for(std::size_t k = 0; k < m_soft.size(); ++k)
    {
      const Eigen::Vector3d d = current[m_unknowns[m_soft[k]]] - m_soft_targets[k];
      const double unit = normalizing_power_of_two(d.cwiseAbs().maxCoeff());
      result.max_constraint_residual = (std::max)(result.max_constraint_residual, (unit * d).norm() / unit);
    }
    return result;
  }

  // forget the previous solution: the next iteration starts with T = I (or set_start_transforms())
  void restart()
  {
    m_has_solution = false;
    std::fill(m_transforms.begin(), m_transforms.end(), Eigen::Matrix3d::Identity());
  }

  // the next iteration fits the transforms to `positions` instead of starting with T = I
  void start_from(const std::vector<Eigen::Vector3d>& positions)
  {
    m_solution.resize(Eigen::Index(m_unknowns.size()), 3);
    for(std::size_t j = 0; j < m_unknowns.size(); ++j)
      m_solution.row(Eigen::Index(j)) = positions[m_unknowns[j]].transpose();
    m_has_solution = true;
  }

  // whether the next iteration continues from a solution (otherwise it starts with the transforms
  // set by restart() or set_start_transforms())
  bool has_solution() const { return m_has_solution; }
  // the transforms of the first solve: `f(a)` for the row node `a` (before the first iteration only)
  template <class F>
  void set_start_transforms(const F& f)
  {
    for(std::size_t i = 0; i < m_fit_nodes.size(); ++i)
      m_transforms[i] = f(m_fit_nodes[i]);
  }

  bool is_ready() const { return m_ready; }
  // the nodes whose transforms are fitted (the owners of the rows), increasing; `transforms()` is parallel to it
  const std::vector<std::size_t>& rows() const { return m_fit_nodes; }
  const std::vector<Eigen::Matrix3d>& transforms() const { return m_transforms; }
  std::size_t number_of_factorizations() const { return m_solver.number_of_factorizations(); }

private:
  struct Union_find
  {
    explicit Union_find(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t(0)); }
    std::size_t find(std::size_t i)
    {
      while(parent[i] != i)
        i = parent[i] = parent[parent[i]];
      return i;
    }
    void join(std::size_t i, std::size_t j) { parent[find(i)] = find(j); }
    Fresh_vector<std::size_t> parent;   // written in full at construction
  };

  // f(begin, end) over [0, n) in blocks, in parallel when ConcurrencyTag and TBB allow it
  template <class F>
  static void for_each_block(std::size_t n, const F& f)
  {
    internal::for_each_block(n, runs_in_parallel<ConcurrencyTag>(), f);
  }

  // K p_known, recomputed only when a known position differs from the last call's (the CLI and
  // the editor call deform(1) once per iteration; the targets move only between drags)
  void update_known_part(const std::vector<Eigen::Vector3d>& positions)
  {
    bool same = m_known_positions.size() == m_known_vertices.size();
    for(std::size_t i = 0; same && i < m_known_vertices.size(); ++i)
      same = m_known_positions[i] == positions[m_known_vertices[i]];
    if(same)
      return;
    m_known_positions.resize(m_known_vertices.size());
    for(std::size_t i = 0; i < m_known_vertices.size(); ++i)
      m_known_positions[i] = positions[m_known_vertices[i]];
    // each row's known entries in increasing vertex order
    for_each_block(std::size_t(m_known.rows()), [&](std::size_t begin, std::size_t end) {
      for(std::size_t r = begin; r < end; ++r)
      {
        Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
        for(Known::InnerIterator it(m_known, Eigen::Index(r)); it; ++it)
          sum += it.value() * positions[std::size_t(it.col())].transpose();
        m_known_part.row(Eigen::Index(r)) = sum;
      }
    });
  }

  // b = T delta - K p_known on the Laplacian rows (the soft rows of b are set once per call),
  // and A^T b, one unknown (a column of A) per task: no two tasks write the same entry
  void right_hand_side(Rows3& b, Eigen::MatrixX3d& rhs) const
  {
    for_each_block(m_rows.size(), [&](std::size_t begin, std::size_t end) {
      for(std::size_t r = begin; r < end; ++r)
        b.row(Eigen::Index(r)) = (m_transforms[m_row_fit[r]] * m_delta.row(Eigen::Index(r)).transpose()).transpose() -
                                 m_known_part.row(Eigen::Index(r));
    });
    const Eigen::SparseMatrix<double>& a = m_solver.matrix();
    // a column's rows of b are scattered: those of the column `lookahead` columns ahead are
    // prefetched while a column is summed
    constexpr std::size_t lookahead = 8;
    for_each_block(std::size_t(a.cols()), [&](std::size_t begin, std::size_t end) {
      for(std::size_t j = begin; j < end; ++j)
      {
        if(j + lookahead < end)
          for(Eigen::SparseMatrix<double>::InnerIterator it(a, Eigen::Index(j + lookahead)); it; ++it)
            prefetch_line(&b(it.row(), 0));
        Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
        for(Eigen::SparseMatrix<double>::InnerIterator it(a, Eigen::Index(j)); it; ++it)
          sum += it.value() * b.row(it.row());
        rhs.row(Eigen::Index(j)) = sum;
      }
    });
  }

  // |A x - b|^2 from the operator's rows (no copy of A by rows is kept): row r of A x is the sum
  // over the unknown columns of D_r (the same terms in the same order as A's row r) with p the
  // positions, the unknowns at x; the soft rows are lambda x_c. One row per task, summed in row
  // order (deterministic).
  double energy(const std::vector<Eigen::Vector3d>& p, const Rows3& b)
  {
    const Operator& d = *m_operator;
    const std::size_t nr = m_rows.size();
    // a row's positions and unknown indices are scattered: those of the row `lookahead` rows
    // ahead are prefetched while a row is summed
    constexpr std::size_t lookahead = 8;
    for_each_block(nr, [&](std::size_t begin, std::size_t end) {
      for(std::size_t r = begin; r < end; ++r)
      {
        if(r + lookahead < end)
          for(Operator::InnerIterator it(d, Eigen::Index(m_rows[r + lookahead])); it; ++it)
          {
            prefetch_line(&p[std::size_t(it.col())]);
            prefetch_line(&m_unknown_index[std::size_t(it.col())]);
          }
        Eigen::RowVector3d residual = -b.row(Eigen::Index(r));
        for(Operator::InnerIterator it(d, Eigen::Index(m_rows[r])); it; ++it)
          if(m_unknown_index[std::size_t(it.col())] >= 0)
            residual += it.value() * p[std::size_t(it.col())].transpose();
        m_row_energy[r] = residual.squaredNorm();
      }
    });
    for(std::size_t k = 0; k < m_soft.size(); ++k)
      m_row_energy[nr + k] =
          (m_lambda * p[m_unknowns[m_soft[k]]].transpose() - b.row(Eigen::Index(nr + k))).squaredNorm();
    return std::accumulate(m_row_energy.begin(), m_row_energy.end(), 0.);
  }

  // local_step_with() with the policy held by a run-time policy (one dispatch per iteration, the
  // loops over the nodes call the held policy itself), or with m_policy
  std::size_t local_step(const std::vector<Eigen::Vector3d>& p)
  {
    return visit_policy(m_policy, [&](const auto& policy) { return local_step_with(policy, p); });
  }

  // fits T_a for every fitted node, in parallel when ConcurrencyTag allows it; each block of rows
  // gathers its cells into buffers of its own (one allocation per block, none per row). Returns
  // the number of nodes whose fit is not finite (their transforms are left as they were).
  // `policy` is a concrete policy.
  template <class Policy>
  std::size_t local_step_with(const Policy& policy, const std::vector<Eigen::Vector3d>& p)
  {
    std::atomic<std::size_t> failed(0);
    const Laplacian_stencils& s = *m_stencils;
    constexpr std::size_t lookahead = 6;
    for_each_block(m_needed_nodes.size(), [&](std::size_t begin, std::size_t end) {
      for(std::size_t i = begin; i < end; ++i)
      {
        if(i + lookahead < end)   // the vertices of the node `lookahead` nodes ahead
        {
          const std::size_t ahead = m_needed_nodes[i + lookahead];
          for(std::size_t k = s.combination_start[ahead]; k < s.combination_start[ahead + 1]; ++k)
            prefetch_line(&p[s.combination_vertex[k]]);
        }
        const std::size_t a = m_needed_nodes[i];
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
          x += s.combination_coefficient[k] * p[s.combination_vertex[k]];
        m_nodes[a].current = x;
      }
    });
    // the fits: each cell gathered by gather_cell()
    if constexpr(batched::Has_transform_lanes<Policy>::value)
    {
      if(batched::batch_target() != batched::Batch_target::per_cell)
      {
        fit_lanes(policy, failed);
        return failed;
      }
    }
    for_each_block(m_fit_nodes.size(), [&](std::size_t begin, std::size_t end) {
      // the cells are fitted `group` at a time: by the policy's transform_block() (vectorised)
      // where it has one, by transform(cell) otherwise (group 1)
      const std::size_t group = Has_transform_block<Policy>::value ? 32 : 1;
      std::vector<Eigen::Vector3d> rest_edges(m_max_degree * group), current_edges(m_max_degree * group);
      std::vector<double> fit_weights(m_max_degree * group);
      std::vector<Transform_cell> cells;
      cells.reserve(group);
      std::vector<Eigen::Matrix3d> fitted(group);
      for(std::size_t r = begin; r < end; ++r)
      {
        Eigen::Vector3d *re = rest_edges.data() + cells.size() * m_max_degree,
                        *ce = current_edges.data() + cells.size() * m_max_degree;
        double* fw = fit_weights.data() + cells.size() * m_max_degree;
        const std::size_t degree = gather_cell(r, end, [&](std::size_t i, const Eigen::Vector3d& e,
                                                           const Eigen::Vector3d& f, double w) {
          re[i] = e;
          ce[i] = f;
          fw[i] = w;
        }, [&](std::size_t n, double unit) {
          for(std::size_t i = 0; i < n; ++i)
          {
            re[i] *= unit;
            ce[i] *= unit;
          }
        });
        cells.emplace_back(re, ce, fw, degree);
        if(cells.size() < group && r + 1 < end)
          continue;
        transform_cells(policy, cells.data(), cells.size(), fitted.data());
        const std::size_t r0 = r + 1 - cells.size();
        for(std::size_t j = 0; j < cells.size(); ++j)
          if(fitted[j].allFinite())
            m_transforms[r0 + j] = fitted[j];
          else
            ++failed;
        cells.clear();
      }
    });
    return failed;
  }

  // Gathers the cell of fitted row r (of a block ending at `end`): put(i, e, e', c) for each spoke i
  // (rest and current edge vectors, fit weight max(w, 0)), then scale(degree, unit) with the power
  // of two that brings the cell's largest coordinate near 1 (the fits are homogeneous in the
  // edges: exact, and away from overflow and underflow at any model size); returns the degree.
  // The spokes reach scattered nodes: the nodes of the cell `lookahead` rows ahead are prefetched
  // (one cache line per node: its current and rest positions).
  template <class Put, class Scale>
  std::size_t gather_cell(std::size_t r, std::size_t end, const Put& put, const Scale& scale) const
  {
    constexpr std::size_t lookahead = 6;
    const Laplacian_stencils& s = *m_stencils;
    const Node_positions* nodes = m_nodes.data();
    if(r + lookahead < end)
    {
      const std::size_t ahead = m_fit_nodes[r + lookahead];
      for(std::size_t k = s.neighbor_start[ahead]; k < s.neighbor_start[ahead + 1]; ++k)
        prefetch_line(nodes + s.neighbor[k]);
    }
    const std::size_t a = m_fit_nodes[r], first = s.neighbor_start[a], degree = s.neighbor_start[a + 1] - first;
    const Eigen::Vector3d &xa = nodes[a].current, &ra = nodes[a].rest;
    // the largest coordinate, found while the spokes are gathered (a running maximum per
    // coordinate: six independent chains; a NaN is skipped)
    double largest[6] = {0, 0, 0, 0, 0, 0};
    for(std::size_t i = 0; i < degree; ++i)
    {
      const std::size_t nb = s.neighbor[first + i];
      const Eigen::Vector3d e = ra - nodes[nb].rest, f = xa - nodes[nb].current;
      put(i, e, f, (std::max)(s.weight[first + i], 0.));
      for(int c = 0; c < 3; ++c)
      {
        largest[c] = (std::max)(largest[c], std::abs(e[c]));
        largest[3 + c] = (std::max)(largest[3 + c], std::abs(f[c]));
      }
    }
    scale(degree, normalizing_power_of_two((std::max)({largest[0], largest[1], largest[2], largest[3], largest[4],
                                                       largest[5]})));
    return degree;
  }

  // the fits of local_step_with() for a policy with transform_lanes(): batched::gather_lanes()
  // puts the spokes of `lanes` cells at a time straight into the kernels' structure-of-arrays
  // buffers (the numbers of gather_cell(), so the same transforms, bit for bit), without the
  // general path's copy of every cell
  template <class Policy>
  void fit_lanes(const Policy& policy, std::atomic<std::size_t>& failed)
  {
    const Laplacian_stencils& s = *m_stencils;
    constexpr int lanes = batched::lanes;
    static_assert(std::is_same<Stencil_index, std::uint32_t>::value, "the gather reads 32-bit indices");
    static_assert(sizeof(Node_positions) == batched::Gather_input::record * sizeof(double), "");
    if(m_fit_nodes.empty())
      return;
    batched::Gather_input in;
    in.node = m_nodes.front().current.data();
    CGAL_assertion(m_nodes.front().rest.data() == in.node + 3);
    in.neighbor_start = s.neighbor_start.data();
    in.neighbor = s.neighbor.data();
    in.weight = s.weight.data();
    const batched::Batch_target target = batched::batch_target();
    for_each_block(m_fit_nodes.size(), [&](std::size_t begin, std::size_t end) {
      batched::Lanes b;
      std::vector<double> spokes(7 * m_max_degree * std::size_t(lanes)), scratch(8 * m_max_degree * std::size_t(lanes));
      Eigen::Matrix3d fitted[lanes];
      for(std::size_t r0 = begin; r0 < end; r0 += std::size_t(lanes))
      {
        const int m = int((std::min)(std::size_t(lanes), end - r0));
        // the node records of the next group's cells (scattered; one cache line each)
        for(std::size_t r = r0 + std::size_t(lanes); r < (std::min)(r0 + 2 * std::size_t(lanes), end); ++r)
        {
          const std::size_t a = m_fit_nodes[r];
          for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
            prefetch_line(m_nodes.data() + s.neighbor[k]);
        }
        batched::gather_lanes(target, in, m_fit_nodes.data() + r0, m, b, spokes.data(), scratch.data());
        policy.transform_lanes(b, m, fitted);
        for(int l = 0; l < m; ++l)
          if(fitted[l].allFinite())
            m_transforms[r0 + std::size_t(l)] = fitted[l];
          else
            ++failed;
      }
    });
  }

  const Laplacian_stencils* m_stencils = nullptr;
  const Operator* m_operator = nullptr;   // D (its rows m_rows are the system's), owned by the caller
  TransformPolicy m_policy;
  Least_squares_solver<SolverTraits, ConcurrencyTag> m_solver;
  std::vector<int> m_unknown_index;   // per vertex of the mesh: its unknown, or -1 (32-bit: A's column indices are int)
  std::vector<std::size_t> m_unknowns, m_rows, m_needed_nodes, m_soft;
  std::vector<std::size_t> m_fit_nodes, m_row_fit;   // the fitted nodes; per row, its fitted node
  std::size_t m_max_degree = 0;
  // a node's current position (computed by the local step) and rest position, in one cache line
  struct alignas(64) Node_positions
  {
    Eigen::Vector3d current = Eigen::Vector3d::Zero(), rest = Eigen::Vector3d::Zero();
  };
  typedef Eigen::SparseMatrix<double, Eigen::RowMajor> Known;
  Eigen::SparseMatrix<double> m_a;   // A (handed to m_solver by preprocess())
  Known m_known;                     // K (by rows)
  double m_lambda = 0;
  Eigen::MatrixX3d m_delta, m_solution;
  std::vector<Node_positions> m_nodes;   // per node of the mesh (only the needed ones are used)
  std::vector<Eigen::Matrix3d> m_transforms;
  std::vector<std::size_t> m_known_vertices;        // the vertices with a column in K
  std::vector<Eigen::Vector3d> m_known_positions;   // their positions when m_known_part was computed
  Eigen::MatrixX3d m_known_part;                    // K p_known
  Rows3 m_b;                                        // right-hand side (by rows: A^T b gathers rows of it)
  Eigen::MatrixX3d m_rhs, m_x;                      // A^T b, solution
  std::vector<Eigen::Vector3d> m_soft_targets;      // the soft controls' targets of the current call
  std::vector<double> m_row_energy;
  bool m_has_solution = false;
  bool m_ready = false;
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_DEFORMATION_CORE_H
