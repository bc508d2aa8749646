// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_MESH_DEFORMER_H
#define CGAL_LAPLACIAN_DEFORMATION_MESH_DEFORMER_H

#include <CGAL/Laplacian_deformation/Deformation_result.h>
#include <CGAL/Laplacian_deformation/Deformation_start.h>
#include <CGAL/Laplacian_deformation/Fixed_transform.h>
#include <CGAL/Laplacian_deformation/laplacian_matrix.h>
#include <CGAL/Laplacian_deformation/internal/Deformation_core.h>
#include <CGAL/Laplacian_deformation/internal/Deformation_types.h>
#include <CGAL/Laplacian_deformation/internal/Policy_variant.h>
#include <CGAL/Laplacian_deformation/internal/Rotation_start.h>

#include <CGAL/Iterator_range.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/tags.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <numeric>
#include <cmath>
#include <cstdint>
#include <optional>
#include <atomic>
#include <chrono>
#include <type_traits>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationRef

\brief Interactive Laplacian deformation of a triangle mesh, in CGAL `Surface_mesh_deformation`'s
vocabulary: a region of interest (ROI), control vertices with target positions, `preprocess()`
(factor once) and `deform()` (iterate: fit a transform per node in parallel, then solve).

Vertices outside the ROI are fixed at their rest positions. Control vertices are in the ROI;
with hard constraints (the default) they are placed exactly at their targets, with soft
constraints they are pulled there by the term <code>lambda^2 |p'_c - t_c|^2</code>, `lambda^2` being
`soft_constraint_weight()` times the mean diagonal of the normal matrix (so that a uniform
scaling of the problem does not change the result). The unknowns are the free vertices; the
rows are every node whose Laplacian stencil touches a free vertex. The normal matrix does not
depend on the transforms: it is factored once per ROI / control set / constraint mode, and
moving targets never refactors it.

The first iteration after `preprocess()` or `reset()` is one solve with the start transforms
(`start()`: by default `IDENTITY_START`, `T = I`; `ROTATION_START`: each control group's
rotation propagated by a harmonic field, see \ref LapDefStart); later iterations (also in later
`deform()` calls) continue from the previous solution, so `deform(7, 0)` equals seven
`deform(1, 0)` calls. Iterations stop after `iterations` or when the largest vertex
displacement of an iteration, relative to the ROI's bounding-box diagonal, is at most `tolerance`.

A failed `preprocess()` or `deform()` leaves the mesh exactly as it was; its reason is in
`last_result()`. A vertex descriptor that is not a vertex of the mesh (its index is not below
`num_vertices(tm)`, for example `null_vertex()`, or it is a vertex of another mesh: the deformer
keeps the mesh's descriptors by index, built at construction, and checks that the index of `v`
names `v` itself) is never stored: the insertion returns `false` and the next `preprocess()` or
`deform()` fails with `INVALID_PARAMETER`. (With index descriptors, as `Surface_mesh`'s, a vertex of
another mesh whose index is in range is indistinguishable from the vertex of this mesh with that index.)

\tparam TriangleMesh a model of `FaceGraph`; its faces may be polygons (see \ref LapDefPolygons)
\tparam Representation a model of `DeformationRepresentation`; `CGAL::Default`: `Edge_based_representation`
\tparam WeightPolicy a model of `DeformationWeightPolicy`; `CGAL::Default`: `Cotangent_weights`; `Any_weights` to choose it at run time (see \ref LapDefRunTime)
\tparam TransformPolicy a model of `DeformationTransformPolicy`; `CGAL::Default`: `Scaled_rotation_transform`; `Any_transform` to choose it at run time
\tparam SolverTraits a model of `SparseLinearAlgebraWithFactorTraits_d` (see `Least_squares_solver`); `CGAL::Default`: `Default_solver_traits`
\tparam VertexPointMap a model of `ReadWritePropertyMap` from vertices to points; `CGAL::Default`: the internal point map
\tparam ConcurrencyTag `CGAL::Sequential_tag`, `CGAL::Parallel_tag` or `CGAL::Parallel_if_available_tag`: whether the local step, the right-hand sides, the rest-cell weights and the assembly (stencils, operator, `A^T A`, the checks' face data) use \tbb's threads (then the weight and transform policies, the representation's nodes, the mesh and its property maps are called or read from several threads at once; the operator and the system are the same bit for bit, the results do not depend on it up to round-off, see \ref LapDefPerformance)
*/
template <class TriangleMesh, class Representation = CGAL::Default, class WeightPolicy = CGAL::Default,
          class TransformPolicy = CGAL::Default, class SolverTraits = CGAL::Default,
          class VertexPointMap = CGAL::Default, class ConcurrencyTag = CGAL::Parallel_if_available_tag>
class Mesh_deformer
{
  typedef internal::Deformation_types<TriangleMesh, Representation, WeightPolicy, TransformPolicy,
                                      SolverTraits, VertexPointMap> Types;

public:
  /// \name Types
  /// @{
  typedef TriangleMesh Triangle_mesh;                                  ///< the mesh type
  typedef typename Types::Representation_type Representation_type;     ///< the representation
  typedef typename Types::Weight_policy Weight_policy;                 ///< the weight policy
  typedef typename Types::Transform_policy Transform_policy;           ///< the transform policy
  typedef typename Types::Solver_traits Solver_traits;                 ///< the solver traits
  typedef typename Types::Vertex_point_map Vertex_point_map;           ///< the vertex point map
  typedef typename Types::Point Point;                                 ///< the point type
  typedef typename Types::Geom_traits Geom_traits;                     ///< the kernel of `Point`
  typedef typename Types::Nodes Nodes;                                 ///< the representation's nodes on `Triangle_mesh`
  typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor vertex_descriptor; ///< a vertex
  typedef CGAL::Iterator_range<typename std::vector<vertex_descriptor>::const_iterator> Roi_vertex_range; ///< the ROI
  /// @}

  /// \name Construction
  /// @{

  /// creates a deformer for `tm`, whose current positions become the rest positions, with
  /// default-constructed policies. `tm` must outlive the deformer, and its topology must not change.
  /// Every constructor makes one pass over the vertices and one over the halfedges of `tm` (it
  /// copies the rest positions, notes whether they are finite, and counts the halfedges pointing to
  /// each vertex); the calls after it cost what their region of interest costs (see \ref LapDefSolve).
  explicit Mesh_deformer(Triangle_mesh& tm)
    : Mesh_deformer(Construct(), tm, get(CGAL::vertex_point, tm), internal::Default_policy()) {}
  /// creates a deformer for `tm` whose points are given by `vpm`, with default-constructed policies.
  Mesh_deformer(Triangle_mesh& tm, Vertex_point_map vpm)
    : Mesh_deformer(Construct(), tm, vpm, internal::Default_policy()) {}
  /// creates a deformer for `tm` with a copy of `weights` (which must then be `CopyConstructible`)
  /// and of `transform` (a default-constructed one if not given), used by every call of the
  /// deformer, e.g. an `Any_weights` and an `Any_transform` chosen at run time (see \ref LapDefRunTime).
  Mesh_deformer(Triangle_mesh& tm, const Weight_policy& weights)
    : Mesh_deformer(Construct(), tm, get(CGAL::vertex_point, tm), weights) {}
  /// \copydoc Mesh_deformer(Triangle_mesh&, const Weight_policy&)
  Mesh_deformer(Triangle_mesh& tm, const Weight_policy& weights, const Transform_policy& transform)
    : Mesh_deformer(Construct(), tm, get(CGAL::vertex_point, tm), weights, transform) {}
  /// the same with the points given by `vpm`.
  Mesh_deformer(Triangle_mesh& tm, Vertex_point_map vpm, const Weight_policy& weights)
    : Mesh_deformer(Construct(), tm, vpm, weights) {}
  /// the same with the points given by `vpm`.
  Mesh_deformer(Triangle_mesh& tm, Vertex_point_map vpm, const Weight_policy& weights,
                const Transform_policy& transform)
    : Mesh_deformer(Construct(), tm, vpm, weights, transform) {}
  Mesh_deformer(const Mesh_deformer&) = delete;
  Mesh_deformer& operator=(const Mesh_deformer&) = delete;
  /// @}

  /// \name Policies
  /// @{

  /// the weight policy (given at construction or by `set_weight_policy()`).
  const Weight_policy& weight_policy() const { return m_weights; }
  /// the transform policy (given at construction or by `set_transform_policy()`).
  const Transform_policy& transform_policy() const { return m_core.policy(); }
  /// replaces the weight policy (`Weight_policy` must be `CopyAssignable`): the Laplacian operator
  /// is rebuilt and the system refactored at the next call.
  void set_weight_policy(const Weight_policy& weights)
  {
    m_weights = weights;
    m_operator_ready = false;
    m_need_preprocess = true;
  }
  /// replaces the transform policy (`Transform_policy` must be `CopyAssignable`): the next
  /// iterations fit their transforms with it, from the current solution (call `reset()` to start
  /// over). Never refactors.
  void set_transform_policy(const Transform_policy& transform) { m_core.set_policy(transform); }
  /// @}

private:
  struct Construct {};
  // the constructor of all the others: `weights` is a Weight_policy or internal::Default_policy,
  // `transform` is empty (default-constructed) or a Transform_policy
  template <class Weights, class... Transform>
  Mesh_deformer(Construct, Triangle_mesh& tm, Vertex_point_map vpm, const Weights& weights,
                const Transform&... transform)
    : m_tm(tm), m_vpm(vpm), m_vim(CGAL::get_initialized_vertex_index_map(tm)),
      m_number_of_vertices(num_vertices(tm)), m_number_of_edges(num_edges(tm)),
      m_is_roi(m_number_of_vertices, 0), m_is_control(m_number_of_vertices, 0),
      m_moved(m_number_of_vertices, 0), m_target(m_number_of_vertices),
      m_weights(internal::make_policy<Weight_policy>(weights)), m_core(transform...),
      m_target_rotation(m_number_of_vertices, Eigen::Quaterniond::Identity()),
      m_rotation_known(m_number_of_vertices, 0)
  {
    m_rest = internal::vertex_positions(m_tm, m_vpm, m_vim);
    m_positions = m_rest;
    m_vertex_at_index.resize(m_number_of_vertices);
    for(vertex_descriptor v : vertices(m_tm))
      if(index(v) < m_number_of_vertices)
        m_vertex_at_index[index(v)] = v;
    scan_rest_positions();
    // the number of halfedges pointing to each vertex (one sequential pass over the halfedges), for
    // check_umbrellas() (polygon faces are fine: LapDefPolygons); the topology never changes
    m_pointing.assign(m_number_of_vertices, 0);
    for(auto h : halfedges(m_tm))
    {
      const std::size_t i = index(target(h, m_tm));
      if(i < m_number_of_vertices)
        ++m_pointing[i];
    }
    m_umbrella_checked.assign(m_number_of_vertices, 0);
  }

public:

  /// \name Region of interest and control vertices
  /// @{

  /// inserts `v` in the ROI; returns `false` if it was already there, or if `v` is not a vertex
  /// of the mesh (then the next `preprocess()` or `deform()` fails with `INVALID_PARAMETER`).
  bool insert_roi_vertex(vertex_descriptor v)
  {
    if(!is_vertex(v))
      return m_foreign_vertex = true, false;
    if(is_roi_vertex(v))
      return false;
    m_is_roi[index(v)] = 1;
    m_roi.push_back(v);
    return m_need_preprocess = true;
  }
  /// inserts the vertices of `[begin, end)` in the ROI.
  template <class InputIterator>
  void insert_roi_vertices(InputIterator begin, InputIterator end)
  {
    for(; begin != end; ++begin)
      insert_roi_vertex(*begin);
  }
  /// removes `v` from the ROI (and from the controls); returns `false` if it was not in the ROI.
  /// At the next successful `preprocess()` or `deform()`, a vertex no longer in the ROI goes back to its rest position.
  bool erase_roi_vertex(vertex_descriptor v)
  {
    if(!is_roi_vertex(v))
      return false;
    erase_control_vertex(v);
    m_is_roi[index(v)] = 0;
    m_roi.erase(std::find(m_roi.begin(), m_roi.end(), v));
    return m_need_preprocess = true;
  }
  /// empties the ROI and the set of controls (and forgets any rejected foreign descriptor).
  void clear_roi_vertices()
  {
    m_foreign_vertex = false;
    for(vertex_descriptor v : m_roi)
      m_is_roi[index(v)] = m_is_control[index(v)] = 0;
    m_roi.clear();
    m_need_preprocess = true;
  }
  /// makes `v` a control vertex (inserting it in the ROI if needed), with its current position
  /// as target; returns `false` if it already was a control vertex, or if `v` is not a vertex of
  /// the mesh (then the next `preprocess()` or `deform()` fails with `INVALID_PARAMETER`).
  bool insert_control_vertex(vertex_descriptor v)
  {
    if(!is_vertex(v))
      return m_foreign_vertex = true, false;
    if(is_control_vertex(v))
      return false;
    insert_roi_vertex(v);
    m_is_control[index(v)] = 1;
    m_target[index(v)] = get(m_vpm, v);
    // the rotation given by rotate() is tracked from the rest position only
    m_target_rotation[index(v)] = Eigen::Quaterniond::Identity();
    m_rotation_known[index(v)] = to_vector(m_target[index(v)]) == m_rest[index(v)];
    return m_need_preprocess = true;
  }
  /// makes every vertex of `[begin, end)` a control vertex.
  template <class InputIterator>
  void insert_control_vertices(InputIterator begin, InputIterator end)
  {
    for(; begin != end; ++begin)
      insert_control_vertex(*begin);
  }
  /// `v` stops being a control vertex but stays in the ROI; returns `false` if it was not a control.
  bool erase_control_vertex(vertex_descriptor v)
  {
    if(!is_control_vertex(v))
      return false;
    m_is_control[index(v)] = 0;
    return m_need_preprocess = true;
  }
  /// no vertex is a control vertex any more (they stay in the ROI).
  void clear_control_vertices()
  {
    for(vertex_descriptor v : m_roi)
      m_is_control[index(v)] = 0;
    m_need_preprocess = true;
  }
  /// the ROI, in insertion order.
  Roi_vertex_range roi_vertices() const { return Roi_vertex_range(m_roi.begin(), m_roi.end()); }
  /// whether `v` is in the ROI.
  bool is_roi_vertex(vertex_descriptor v) const { return is_vertex(v) && m_is_roi[index(v)] != 0; }
  /// whether `v` is a control vertex.
  bool is_control_vertex(vertex_descriptor v) const { return is_vertex(v) && m_is_control[index(v)] != 0; }
  /// @}

  /// \name Targets
  /// Moving targets never triggers a new factorisation.
  /// @{

  /// sets the target of the control vertex `v` (ignored if `v` is not a control vertex).
  /// The rotation-aware start then takes the rotation of `v`'s group from the targets (see \ref LapDefStart).
  void set_target_position(vertex_descriptor v, const Point& target)
  {
    if(!is_control_vertex(v))
      return;
    m_target[index(v)] = target;
    m_rotation_known[index(v)] = 0;
  }
  /// the target of the control vertex `v`.
  const Point& target_position(vertex_descriptor v) const
  {
    CGAL_precondition(is_control_vertex(v));
    return m_target[index(v)];
  }
  /// translates the target of `v` by `t` (`Vect` has `operator[]` for its coordinates);
  /// ignored if `v` is not a control vertex.
  template <class Vect>
  void translate(vertex_descriptor v, const Vect& t)
  {
    if(!is_control_vertex(v))
      return;
    Point& p = m_target[index(v)];
    p = Point(p.x() + t[0], p.y() + t[1], p.z() + t[2]);   // keeps the rotation given by rotate()
  }
  /// translates the targets of `[begin, end)` by `t`.
  template <class InputIterator, class Vect>
  void translate(InputIterator begin, InputIterator end, const Vect& t)
  {
    for(; begin != end; ++begin)
      translate(*begin, t);
  }
  /// rotates the target of `v` by the quaternion `quat` about `center`, as CGAL does
  /// (`Vect` is constructible from three coordinates, has `operator[]`, and `quat * Vect` is a `Vect`);
  /// ignored if `v` is not a control vertex. The rotation-aware start uses the composed rotations
  /// given here (with their winding, up to 360 degrees, when `Quaternion` is an `Eigen::Quaternion`)
  /// as long as the target is set only by `rotate()` and `translate()` since the control was
  /// inserted at its rest position or since `reset()`.
  template <class Quaternion, class Vect>
  void rotate(vertex_descriptor v, const Vect& center, const Quaternion& quat)
  {
    if(!is_control_vertex(v))
      return;
    Point& p = m_target[index(v)];
    const Vect r = quat * Vect(CGAL::to_double(p.x()) - center[0], CGAL::to_double(p.y()) - center[1],
                               CGAL::to_double(p.z()) - center[2]);
    p = Point(center[0] + r[0], center[1] + r[1], center[2] + r[2]);
    m_target_rotation[index(v)] = (as_quaternion<Vect>(quat) * m_target_rotation[index(v)]).normalized();
  }
  /// rotates the targets of `[begin, end)`.
  template <class InputIterator, class Quaternion, class Vect>
  void rotate(InputIterator begin, InputIterator end, const Vect& center, const Quaternion& quat)
  {
    for(; begin != end; ++begin)
      rotate(*begin, center, quat);
  }
  /// @}

  /// \name Constraints and iterations
  /// @{

  /// control vertices become soft constraints of relative weight `weight` (> 0); refactors at the next call.
  void set_soft_constraints(double weight) { m_soft = true; m_soft_weight = weight; m_need_preprocess = true; }
  /// control vertices become hard constraints (the default); refactors at the next call.
  void set_hard_constraints() { m_soft = false; m_need_preprocess = true; }
  /// whether the controls are soft.
  bool has_soft_constraints() const { return m_soft; }
  /// the relative weight of soft constraints.
  double soft_constraint_weight() const { return m_soft_weight; }
  /// the number of iterations of `deform()` (default 4, as `deform_mesh()` and the `laplacian_deform` tool: the paper uses 3 to 4).
  void set_iterations(unsigned int iterations) { m_iterations = iterations; }
  /// the relative change below which `deform()` stops early (default 1e-4); a negative, infinite or
  /// NaN tolerance makes `deform()` fail with `INVALID_PARAMETER`.
  void set_tolerance(double tolerance) { m_tolerance = tolerance; }
  /// the number of iterations of `deform()`.
  unsigned int iterations() const { return m_iterations; }
  /// the tolerance of `deform()`.
  double tolerance() const { return m_tolerance; }
  /// the transforms of the first solve after `preprocess()`, `reset()` or a restart (default
  /// `IDENTITY_START`; `ROTATION_START` for large rotations of the handles, see \ref LapDefStart). Changing it never refactors the deformation system;
  /// it takes effect at the next start.
  void set_start(Deformation_start start) { m_start = start; }
  /// the start of the iterations.
  Deformation_start start() const { return m_start; }
  /// adds, with relative weight `weight` (>= 0; default 0: none), one rigidity row per spoke of
  /// the node graph: <code>sqrt(c_ab) (x'_a - x'_b) = sqrt(c_ab) T_a (x_a - x_b)</code>, next to
  /// the Laplacian rows (see \ref LapDefTwist). The weight is relative to the Laplacian rows (the
  /// squared Frobenius norms of both operators over the rows that touch the ROI), so that a uniform scaling of the problem does not
  /// change the result. Refactors at the next call.
  void set_rigidity_weight(double weight) { m_rigidity_weight = weight; m_need_preprocess = true; }
  /// the relative weight of the spoke rigidity rows.
  double rigidity_weight() const { return m_rigidity_weight; }
  /// whether `deform()` computes the energy after each iteration (`Deformation_result::energies`
  /// and `Deformation_result::energy`; default `true`). The energy is reported, never used: the
  /// iterations stop on the relative change of the positions. Computing it is a pass over the rows
  /// of the system, about 8% of an edge-based iteration on the whole 26k-vertex armadillo; an
  /// interactive caller that does not show it can turn it off (the positions stay the same, bit for
  /// bit; `energies` is then empty and `energy` 0).
  void set_energy_tracking(bool on) { m_energy_tracking = on; }
  /// whether `deform()` computes the energies.
  bool energy_tracking() const { return m_energy_tracking; }
  /// @}

  /// \name Deformation
  /// @{

  /// builds and factors the system. Returns `false` on failure (see `last_result()`), leaving the mesh unchanged.
  bool preprocess()
  {
    if(!prepare())
      return false;
    restore_vertices_outside_roi();
    return true;
  }
  /// \cond SKIP_IN_MANUAL
  // preprocess() without any write to the mesh
  bool prepare()
  {
    const auto t0 = std::chrono::steady_clock::now();
    m_last = Deformation_result();
    if(!check_topology() || !check_mesh())
      return false;
    if(m_foreign_vertex)
      return fail(INVALID_PARAMETER, "a vertex descriptor given to insert_roi_vertex() or insert_control_vertex() "
                                     "is not a vertex of the mesh");
    if(m_roi.empty())
      return fail(EMPTY_REGION_OF_INTEREST, "the region of interest is empty");
    if(m_soft && !(m_soft_weight > 0 && std::isfinite(m_soft_weight)))
      return fail(INVALID_PARAMETER, "the soft constraint weight must be positive and finite");
    if(!(m_rigidity_weight >= 0 && std::isfinite(m_rigidity_weight)))
      return fail(INVALID_PARAMETER, "the rigidity weight must be non-negative and finite");
    build_operator();
    if(!check_umbrellas())
      return false;
    if(m_rigidity_weight > 0)
      build_rigidity_rows();
    // the roles, in m_next_role: fixed everywhere but at the ROI's vertices (written here, and
    // written back to fixed on failure, or once they are the previous roles): the cost is the
    // ROI's, not the mesh's
    std::vector<std::size_t> roi_index = roi_by_index();
    if(m_next_role.size() != m_number_of_vertices)
      m_next_role.assign(m_number_of_vertices, internal::FIXED_VERTEX);
    for(std::size_t i : roi_index)
      m_next_role[i] = !m_is_control[i] ? internal::FREE_VERTEX
                       : m_soft ? internal::SOFT_CONTROL_VERTEX : internal::HARD_CONTROL_VERTEX;
    try
    {
      m_last = m_rigidity_weight > 0
                   ? m_core.preprocess(m_stencils, m_rigid_d, m_rigid_delta, m_rest_nodes, m_next_role, roi_index,
                                       m_soft_weight, &m_rigid_owner)
                   : m_core.preprocess(m_stencils, m_d, m_delta, m_rest_nodes, m_next_role, roi_index, m_soft_weight);
    }
    catch(...)
    {
      for(std::size_t i : roi_index)
        m_next_role[i] = internal::FIXED_VERTEX;
      throw;
    }
    m_last.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if(!m_last)
    {
      for(std::size_t i : roi_index)
        m_next_role[i] = internal::FIXED_VERTEX;
      return false;
    }
    m_need_preprocess = false;
    m_role.swap(m_next_role);
    if(m_next_role.size() == m_number_of_vertices)   // the previous roles: fixed again
      for(std::size_t i : m_roi_index)
        m_next_role[i] = internal::FIXED_VERTEX;
    m_roi_index.swap(roi_index);
    m_row_nodes.clear();
    for(std::size_t a : m_core.rows())
      m_row_nodes.push_back(m_stencils.node_index(a));
    for(std::size_t i : m_written)            // deform()'s buffer: every vertex at rest again
      m_positions[i] = m_rest[i];
    m_written.clear();
    m_diagonal = region_diagonal();
    m_field_ready = false;
    if(uses_start() && m_start == ROTATION_START && !build_start_field())
      return false;
    prepare_checks();
    m_last.warnings = m_preprocess_warnings;
    m_last.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return true;
  }
  /// \endcond
  /// deforms with `iterations()` and `tolerance()`.
  Deformation_result deform() { return deform(m_iterations, m_tolerance); }
  /// deforms with at most `iterations` iterations, stopping when the relative change is at most `tolerance`.
  /// With `iterations == 0` it only preprocesses if needed and writes nothing.
  Deformation_result deform(unsigned int iterations, double tolerance)
  {
    const auto t0 = std::chrono::steady_clock::now();
    if(!(tolerance >= 0 && tolerance < HUGE_VAL))
      return fail(INVALID_PARAMETER, "the tolerance must be non-negative and finite"), m_last;
    if(m_need_preprocess || !check_topology())
      if(!prepare())
        return m_last;
    if(iterations == 0)
    {
      m_last = Deformation_result();
      m_last.warnings = m_preprocess_warnings;
      m_last.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return m_last;
    }
    // the positions of every vertex: the fixed ones at rest (kept so in m_positions), the ROI's
    // written here (O(ROI) per call, no buffer proportional to the mesh allocated per call)
    // The ROI is visited by increasing vertex index (m_roi_index), whatever the order in which
    // it was inserted: nearly sequential accesses to the per-vertex arrays (the ROI of the 26k
    // armadillo inserted by height cost 0.6 ms more per call in these loops).
    std::vector<Eigen::Vector3d>& p = m_positions;
    if(m_written.empty())
      m_written = m_roi_index;
    for(std::size_t i : m_roi_index)
    {
      const vertex_descriptor v = m_vertex_at_index[i];
      p[i] = m_is_control[i] ? to_vector(m_target[i]) : to_vector(get(m_vpm, v));
      if(!p[i].allFinite())
        return fail(NON_FINITE_INPUT, "a target or a current position is not finite"), m_last;
    }
    if(!m_core.has_solution() && !apply_start(p))
      return m_last;
    m_last = m_core.iterate(p, iterations, tolerance, m_diagonal, m_energy_tracking);
    if(m_last)
    {
      for(std::size_t i : m_roi_index)
        put_position(m_vertex_at_index[i], p[i], true);
      restore_vertices_outside_roi();
      m_moved_vertices = m_roi_index;        // now exactly the ROI (the ROI holds each vertex once)
      add_warnings(p);
    }
    m_last.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return m_last;
  }
  /// puts the ROI back at its rest positions, the targets of the controls too, and restarts the
  /// iterations from the start transforms (`start()`).
  void reset()
  {
    for(vertex_descriptor v : m_roi)
    {
      put_position(v, m_rest[index(v)], false);
      if(is_control_vertex(v))
      {
        m_target[index(v)] = get(m_vpm, v);
        m_target_rotation[index(v)] = Eigen::Quaterniond::Identity();
        m_rotation_known[index(v)] = 1;
      }
    }
    m_core.restart();
  }
  /// warm start: the next iteration fits the transforms to the current positions of the mesh
  /// (for instance a pose saved earlier) instead of starting with `T = I`. Preprocesses if needed;
  /// returns `false` if that fails.
  bool start_from_current_positions()
  {
    if(m_need_preprocess && !preprocess())
      return false;
    m_core.start_from(internal::vertex_positions(m_tm, m_vpm, m_vim));
    return true;
  }
  /// makes the current positions the rest positions (the Laplacian coordinates and weights are
  /// recomputed at the next `preprocess()`).
  void overwrite_initial_geometry()
  {
    m_rest = internal::vertex_positions(m_tm, m_vpm, m_vim);
    m_positions = m_rest;
    m_written.clear();
    std::fill(m_moved.begin(), m_moved.end(), 0);
    m_moved_vertices.clear();
    for(vertex_descriptor v : m_roi)     // rotations given to rotate() are relative to the new rest
      if(is_control_vertex(v))
      {
        m_target_rotation[index(v)] = Eigen::Quaterniond::Identity();
        m_rotation_known[index(v)] = to_vector(m_target[index(v)]) == m_rest[index(v)];
      }
    m_operator_ready = false;
    scan_rest_positions();
    m_need_preprocess = true;
  }
  /// the outcome of the last `preprocess()` or `deform()`.
  const Deformation_result& last_result() const { return m_last; }
  /// @}

  /// \name Access
  /// @{

  /// the mesh.
  const Triangle_mesh& triangle_mesh() const { return m_tm; }
  /// the vertex point map.
  const Vertex_point_map& point_map() const { return m_vpm; }
  /// the nodes of the representation (available after a successful `preprocess()`).
  const Nodes& nodes() const { CGAL_precondition(m_nodes.has_value()); return *m_nodes; }
  /// the dense indices of the nodes that carry a row (a fitted transform), increasing.
  const std::vector<std::size_t>& row_nodes() const { return m_row_nodes; }
  /// the transform `T_a` of node index `a` used by the last iteration (identity outside the rows).
  Eigen::Matrix3d node_transform(std::size_t a) const
  {
    const auto it = std::lower_bound(m_row_nodes.begin(), m_row_nodes.end(), a);
    return it != m_row_nodes.end() && *it == a ? m_core.transforms()[std::size_t(it - m_row_nodes.begin())]
                                               : Eigen::Matrix3d::Identity().eval();
  }
  /// the number of factorisations of the deformation system performed so far.
  std::size_t number_of_factorizations() const { return m_core.number_of_factorizations(); }
  /// the number of control groups (connected components of the control vertices) of the
  /// rotation-aware start (available after a successful `preprocess()` with `ROTATION_START`; 0 otherwise).
  std::size_t number_of_control_groups() const { return m_field_ready ? m_field.number_of_groups() : 0; }
  /// the control vertices of group `g`, `g < number_of_control_groups()`.
  std::vector<vertex_descriptor> control_group(std::size_t g) const
  {
    CGAL_precondition(g < number_of_control_groups());
    std::vector<vertex_descriptor> group;
    for(vertex_descriptor v : m_roi)
      if(m_field.group_of(index(v)) == long(g))
        group.push_back(v);
    return group;
  }
  /// the harmonic field `phi_g` of the rotation-aware start on every vertex, by vertex index (1 on
  /// group `g`, 0 on the other groups and outside the ROI); empty if it is not available
  /// (`g >= number_of_control_groups()`). One back-substitution with the field's factor.
  std::vector<double> start_field(std::size_t g) const
  {
    std::vector<double> phi;
    if(g >= number_of_control_groups() || !m_field.field(g, phi))
      phi.clear();
    return phi;
  }
  /// the number of factorisations of the rotation-aware start's harmonic field performed so far
  /// (one per `preprocess()` with `ROTATION_START`; moving targets never refactors it).
  std::size_t number_of_start_field_factorizations() const { return m_field.number_of_factorizations(); }
  /// @}

private:
  typedef typename CGAL::GetInitializedVertexIndexMap<TriangleMesh>::const_type Vertex_index_map;

  std::size_t index(vertex_descriptor v) const { return static_cast<std::size_t>(get(m_vim, v)); }

  // the start applies to the policies that fit a transform (Fixed_transform keeps T = I), also
  // when a run-time policy holds it
  bool uses_start() const { return internal::fits_transform(m_core.policy()); }

  // a quaternion as an Eigen one: exactly (with its winding) for Eigen's, else from its action
  template <class Vect, class Quaternion>
  static Eigen::Quaterniond as_quaternion(const Quaternion& q)
  {
    if constexpr(std::is_base_of<Eigen::QuaternionBase<Quaternion>, Quaternion>::value)
      return q.template cast<double>().normalized();
    else
    {
      Eigen::Matrix3d r;
      for(int k = 0; k < 3; ++k)
      {
        const Vect e = q * Vect(k == 0 ? 1. : 0., k == 1 ? 1. : 0., k == 2 ? 1. : 0.);
        r.col(k) = Eigen::Vector3d(CGAL::to_double(e[0]), CGAL::to_double(e[1]), CGAL::to_double(e[2]));
      }
      Eigen::Quaterniond e(r);
      return e.w() < 0 ? Eigen::Quaterniond(-e.coeffs()) : e;
    }
  }

  bool build_start_field()
  {
    if(m_field.build(m_tm, m_vim, m_roi, m_is_control, m_rest))
      return m_field_ready = true;
    return fail(FACTORIZATION_FAILED, "the harmonic field of the rotation-aware start could not be factored");
  }

  // before the first solve after preprocess(), reset() or a restart: the start transforms. `p`
  // holds the targets of the controls.
  bool apply_start(const std::vector<Eigen::Vector3d>& p)
  {
    if(!uses_start() || m_start != ROTATION_START)
      return true;
    if(!m_field_ready && !build_start_field())
      return false;
    const std::size_t groups = m_field.number_of_groups();
    std::vector<Eigen::Vector3d> omega(groups, Eigen::Vector3d::Zero());
    bool rotated = false;
    for(std::size_t g = 0; g < groups; ++g)
    {
      const std::vector<std::size_t>& group = m_field.groups()[g];
      bool exact = true;
      for(std::size_t i : group)
        exact = exact && m_rotation_known[i] &&
                m_target_rotation[i].coeffs() == m_target_rotation[group.front()].coeffs();
      if(exact)
      {
        omega[g] = internal::quaternion_log(m_target_rotation[group.front()]);
        if(!(omega[g].norm() > internal::start_rotation_snap))
          omega[g].setZero();
      }
      else if(!internal::group_rotation_log(group, m_rest, p, omega[g]))
        return fail(NON_FINITE_INPUT, "a target is not finite");
      rotated = rotated || omega[g] != Eigen::Vector3d::Zero();
    }
    if(!rotated)
      return true;                       // a pure translation: exactly the identity start
    // the field's values per vertex: 0 but at the ROI's vertices, which are set back to 0 after use
    std::vector<Eigen::Vector3d>& values = m_start_values;
    if(values.size() != m_number_of_vertices)
      values.assign(m_number_of_vertices, Eigen::Vector3d::Zero());
    struct Clear
    {
      const internal::Rotation_start_field& field;
      std::vector<Eigen::Vector3d>& values;
      ~Clear() { field.clear_values(values); }
    } clear{m_field, values};
    if(!m_field.propagate(omega, values))
      return fail(SOLVE_FAILED, "the harmonic field of the rotation-aware start could not be solved");
    const internal::Laplacian_stencils& s = m_stencils;
    m_core.set_start_transforms([&](std::size_t a) {
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
        w += s.combination_coefficient[k] * values[s.combination_vertex[k]];
      return internal::rotation_exp(w);
    });
    return true;
  }
  // a vertex of this mesh: its index is in range and names `v` itself (an index map may return
  // a valid index for a foreign key, e.g. 0 for a vertex of another Polyhedron_3)
  bool is_vertex(vertex_descriptor v) const
  {
    return v != boost::graph_traits<TriangleMesh>::null_vertex() && index(v) < m_number_of_vertices &&
           m_vertex_at_index[index(v)] == v;
  }
  static Eigen::Vector3d to_vector(const Point& p)
  {
    return Eigen::Vector3d(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  void put_position(vertex_descriptor v, const Eigen::Vector3d& p, bool moved)
  {
    put(m_vpm, v, Point(p.x(), p.y(), p.z()));
    m_moved[index(v)] = moved;
  }
  bool fail(Deformation_status status, const char* message)
  {
    m_last = Deformation_result();
    m_last.status = status;
    m_last.message = message;
    return false;
  }
  // vertices that left the ROI go back to their rest positions. Only the vertices deform() moved
  // are looked at (m_moved_vertices lists them, with stale entries whose flag was cleared since):
  // the cost is the previous ROI's, not the mesh's (this runs after every deform()).
  void restore_vertices_outside_roi()
  {
    std::size_t kept = 0;
    for(std::size_t k = 0; k < m_moved_vertices.size(); ++k)
    {
      const std::size_t i = m_moved_vertices[k];
      if(!m_moved[i])
        continue;
      if(m_role[i] == internal::FIXED_VERTEX)
        put_position(m_vertex_at_index[i], m_rest[i], false);
      else
        m_moved_vertices[kept++] = i;
    }
    m_moved_vertices.resize(kept);
  }
  // the ROI's vertex indices, increasing: sorted when the ROI is small next to the mesh, else by
  // one pass over the ROI flags (the same list either way: the ROI holds each vertex once)
  std::vector<std::size_t> roi_by_index() const
  {
    std::vector<std::size_t> r;
    r.reserve(m_roi.size());
    if(m_roi.size() < m_number_of_vertices / 64)
    {
      for(vertex_descriptor v : m_roi)
        r.push_back(index(v));
      std::sort(r.begin(), r.end());
    }
    else
      for(std::size_t i = 0; i < m_number_of_vertices; ++i)
        if(m_is_roi[i])
          r.push_back(i);
    return r;
  }
  bool check_topology()
  {
    if(num_vertices(m_tm) == m_number_of_vertices && num_edges(m_tm) == m_number_of_edges)
      return true;
    return fail(TOPOLOGY_CHANGED, "the mesh's topology changed since the deformer was constructed");
  }
  // whether the rest positions are finite, and their largest coordinate (for the weights' scaling:
  // see internal::build_rest_operator()); by the constructor and overwrite_initial_geometry(), which
  // read every rest position anyway, so that preprocess() costs what its region costs (before
  // 2026-12-07 the first preprocess() scanned the whole mesh: 3.8 ms at 416k vertices)
  void scan_rest_positions()
  {
    double largest = 0;
    bool finite = true;
    for(const Eigen::Vector3d& p : m_rest)
    {
      finite = finite && p.allFinite();
      largest = (std::max)(largest, p.cwiseAbs().maxCoeff());
    }
    m_rest_finite = finite;
    m_largest_coordinate = finite ? largest : 0.;
  }
  bool check_mesh()
  {
    if(!m_rest_finite)
      return fail(NON_FINITE_INPUT, "a rest position of the mesh is not finite");
    return true;
  }
  // the vertices whose umbrellas the operator was built from (every vertex of a built node's
  // combination) are manifold: the halfedges pointing to the vertex form one umbrella (the cycle
  // around halfedge(v)) with at most one border halfedge (PMP::non_manifold_vertices() is several
  // times slower). Each vertex is walked once per deformer (the walk, with its scattered reads of the
  // mesh, is what a check of the whole mesh spent its time on: the cost is now the region's).
  bool check_umbrellas()
  {
    // the vertices not checked yet, each once (marked 2 while listed), then walked in blocks (on
    // TBB's threads with Parallel_tag): 1 when manifold; on failure the listed marks are cleared
    const internal::Laplacian_stencils& st = m_stencils;
    std::vector<std::uint32_t> unchecked;
    for(std::size_t k = 0; k < st.combination_vertex.size(); ++k)
    {
      const std::size_t i = st.combination_vertex[k];
      if(m_umbrella_checked[i] == 0)
      {
        m_umbrella_checked[i] = 2;
        unchecked.push_back(static_cast<std::uint32_t>(i));
      }
    }
    std::atomic<bool> manifold(true);
    internal::for_each_block(unchecked.size(), internal::runs_in_parallel<ConcurrencyTag>(),
                             [&](std::size_t begin, std::size_t end) {
      for(std::size_t k = begin; k < end && manifold.load(std::memory_order_relaxed); ++k)
      {
        const std::size_t i = unchecked[k];
        const vertex_descriptor v = m_vertex_at_index[i];
        if(halfedge(v, m_tm) == boost::graph_traits<TriangleMesh>::null_halfedge())
          continue;
        std::size_t around = 0, border = 0;
        for(auto h : halfedges_around_target(halfedge(v, m_tm), m_tm))
        {
          ++around;
          border += is_border(h, m_tm);
        }
        if(around != m_pointing[i] || border > 1)
          manifold.store(false, std::memory_order_relaxed);
      }
    }, 2048);
    const unsigned char mark = manifold ? 1 : 0;
    for(std::uint32_t i : unchecked)
      m_umbrella_checked[i] = mark;
    if(!manifold)
      return fail(INVALID_MESH, "a vertex of the mesh is non-manifold (its faces form several fans)");
    return true;
  }
  // the rest-geometry operator: stencils, weights, D, delta = D p_rest. With representations whose
  // nodes have incident_nodes() (both of the package's), only the rows that touch the ROI and the
  // neighbours they need are built: the cost is the ROI's, not the mesh's; it is reused by later
  // preprocess() calls while it covers the ROI (its rows are then bitwise those of a whole-mesh build).
  void build_operator()
  {
    if(m_operator_ready && operator_covers_roi())
      return;
    m_nodes.emplace(m_tm, m_vpm);
    internal::Rest_operator r;
    internal::build_rest_operator(r, *m_nodes, m_vim, m_rest, m_weights, Geom_traits(),
                                  internal::runs_in_parallel<ConcurrencyTag>(), m_largest_coordinate, &m_roi);
    m_stencils = std::move(r.stencils);
    m_rest_nodes = std::move(r.rest_nodes);
    m_d.swap(r.d);   // Eigen 3.4's sparse matrices have no move assignment: std::move would copy
    m_delta = std::move(r.delta);
    if(!m_stencils.global_node.empty())
    {
      m_operator_region.assign(m_number_of_vertices, 0);
      for(vertex_descriptor v : m_roi)
        m_operator_region[index(v)] = 1;
    }
    m_operator_ready = true;
  }
  // whether the operator was built for a superset of the ROI (always with a whole-mesh build)
  bool operator_covers_roi() const
  {
    if(m_stencils.global_node.empty())
      return true;
    for(vertex_descriptor v : m_roi)
      if(!m_operator_region[index(v)])
        return false;
    return true;
  }
  // [D; lambda S]: S has one row sqrt(c_ab) (x_a - x_b) per spoke (a, b), owned by a;
  // lambda^2 = weight |D_R|_F^2 / |S_R|_F^2 over the rows R that touch the ROI (so that lambda
  // depends on the ROI only, not on how much of the mesh the operator covers). Rebuilt at every
  // preprocess (its cost is the ROI's).
  void build_rigidity_rows()
  {
    const internal::Laplacian_stencils& s = m_stencils;
    typedef Eigen::SparseMatrix<double, Eigen::RowMajor> Operator;
    std::vector<Eigen::Triplet<double> > triplets;
    std::vector<std::size_t> spoke_owner;
    for(std::size_t a = 0; a < s.number_of_nodes; ++a)
      for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
      {
        const double c = std::sqrt((std::max)(s.weight[k], 0.));
        if(!(c > 0))
          continue;
        const Eigen::Index row = Eigen::Index(spoke_owner.size());
        const std::size_t b = s.neighbor[k];
        for(std::size_t i = s.combination_start[a]; i < s.combination_start[a + 1]; ++i)
          triplets.emplace_back(row, Eigen::Index(s.combination_vertex[i]), c * s.combination_coefficient[i]);
        for(std::size_t i = s.combination_start[b]; i < s.combination_start[b + 1]; ++i)
          triplets.emplace_back(row, Eigen::Index(s.combination_vertex[i]), -c * s.combination_coefficient[i]);
        spoke_owner.push_back(a);
      }
    Operator spokes(Eigen::Index(spoke_owner.size()), Eigen::Index(m_number_of_vertices));
    spokes.setFromTriplets(triplets.begin(), triplets.end());
    std::vector<Eigen::Triplet<double> >().swap(triplets);
    spokes.prune([](Eigen::Index, Eigen::Index, double v) { return v != 0; });   // x_a - x_b shares vertices
    auto squared_norm_near_roi = [this](const Operator& m) {
      double sum = 0;
      for(Eigen::Index r = 0; r < m.rows(); ++r)
      {
        double row = 0;
        bool touches = false;
        for(Operator::InnerIterator it(m, r); it; ++it)
        {
          row += it.value() * it.value();
          touches = touches || m_is_roi[std::size_t(it.col())];
        }
        sum += touches ? row : 0.;
      }
      return sum;
    };
    const double ds = squared_norm_near_roi(m_d), ss = squared_norm_near_roi(spokes);
    const double lambda = ss > 0 ? std::sqrt(m_rigidity_weight * ds / ss) : 0.;
    spokes *= lambda;
    const Eigen::Index n1 = m_d.rows(), n2 = spokes.rows();
    m_rigid_d.resize(n1 + n2, Eigen::Index(m_number_of_vertices));
    m_rigid_d.reserve(m_d.nonZeros() + spokes.nonZeros());
    for(const Operator* m : { &m_d, &spokes })
      for(Eigen::Index r = 0; r < m->rows(); ++r)
      {
        const Eigen::Index row = (m == &m_d ? 0 : n1) + r;
        m_rigid_d.startVec(row);
        for(Operator::InnerIterator it(*m, r); it; ++it)
          m_rigid_d.insertBack(row, it.col()) = it.value();
      }
    m_rigid_d.finalize();
    m_rigid_owner.resize(std::size_t(n1 + n2));
    std::iota(m_rigid_owner.begin(), m_rigid_owner.begin() + n1, std::size_t(0));
    std::copy(spoke_owner.begin(), spoke_owner.end(), m_rigid_owner.begin() + n1);
    m_rigid_delta.resize(n1 + n2, 3);
    m_rigid_delta.topRows(n1) = m_delta;
    m_rigid_delta.bottomRows(n2) = internal::operator_times_positions(spokes, m_rest);
  }
  // at preprocess: the controls adjacent to fixed vertices (a warning), and the faces with a
  // vertex in the ROI, with their rest normals (for the folded-face check of deform())
  void prepare_checks()
  {
    m_preprocess_warnings.clear();
    std::size_t touching = 0;
    for(vertex_descriptor v : m_roi)
    {
      if(!m_is_control[index(v)] || halfedge(v, m_tm) == boost::graph_traits<TriangleMesh>::null_halfedge())
        continue;
      for(vertex_descriptor w : vertices_around_target(halfedge(v, m_tm), m_tm))
        if(m_role[index(w)] == internal::FIXED_VERTEX)
        {
          ++touching;
          break;
        }
    }
    if(touching > 0)
      m_preprocess_warnings.push_back({HANDLE_TOUCHES_FIXED, touching, std::to_string(touching) +
          " control vertices are adjacent to fixed vertices (no free vertex between them): moving them "
          "stretches the edges to the fixed part into a thin tongue; grow the region of interest around them"});
    // the faces around the ROI's vertices, each once: from its ROI vertex of smallest index. The
    // ROI is cut into chunks (walked on TBB's threads with Parallel_tag), each collecting its faces
    // in order; the chunks are then joined in order (the same faces in the same order either way).
    // At least eight chunks unless a chunk would be smaller than 256 vertices: the walk's scattered
    // reads of the mesh are its cost, also on a small ROI of a large mesh.
    const bool parallel = internal::runs_in_parallel<ConcurrencyTag>();
    // The ROI is walked by increasing vertex index, so that the faces' vertices, read after every
    // deform() by the folded-face count, are near each other in memory.
    const std::size_t chunk = (std::max)(std::size_t(256), (std::min)(std::size_t(4096), (m_roi_index.size() + 7) / 8)),
                      chunks = (m_roi_index.size() + chunk - 1) / chunk;
    struct Faces
    {
      std::vector<std::size_t> start;           // the end of each face in `vertex`
      std::vector<std::uint32_t> vertex;        // vertex indices (32-bit: the system's limit is 2^31 - 1)
    };
    std::vector<Faces> found(chunks);
    internal::for_each_block(chunks, parallel, [&](std::size_t first, std::size_t last) {
      for(std::size_t c = first; c < last; ++c)
      {
        Faces& f = found[c];
        f.vertex.reserve(6 * chunk);
        for(std::size_t i = c * chunk; i < (std::min)(m_roi_index.size(), (c + 1) * chunk); ++i)
        {
          const vertex_descriptor v = m_vertex_at_index[m_roi_index[i]];
          if(halfedge(v, m_tm) == boost::graph_traits<TriangleMesh>::null_halfedge())
            continue;
          const std::size_t iv = index(v);
          for(auto h : halfedges_around_target(halfedge(v, m_tm), m_tm))
          {
            if(is_border(h, m_tm))
              continue;
            const std::size_t begin = f.vertex.size();
            bool first = true;
            for(vertex_descriptor w : vertices_around_face(h, m_tm))
            {
              const std::size_t iw = index(w);
              f.vertex.push_back(static_cast<std::uint32_t>(iw));
              first = first && (iw >= iv || m_role[iw] == internal::FIXED_VERTEX);
            }
            if(!first)
              f.vertex.resize(begin);
            else
              f.start.push_back(f.vertex.size());
          }
        }
      }
    }, 1);
    std::size_t faces = 0, entries = 0;
    for(const Faces& f : found)
    {
      faces += f.start.size();
      entries += f.vertex.size();
    }
    m_face_start.clear();
    m_face_vertex.clear();
    internal::reserve_huge(m_face_start, faces + 1);
    internal::reserve_huge(m_face_vertex, entries);
    m_face_start.push_back(0);
    for(Faces& f : found)
    {
      const std::size_t offset = m_face_vertex.size();
      for(std::size_t end : f.start)
        m_face_start.push_back(offset + end);
      m_face_vertex.insert(m_face_vertex.end(), f.vertex.begin(), f.vertex.end());
      Faces().start.swap(f.start);
      Faces().vertex.swap(f.vertex);
    }
    m_rest_normals.clear();
    internal::resize_huge(m_rest_normals, faces);
    internal::for_each_block(faces, parallel, [&](std::size_t begin, std::size_t end) {
      for(std::size_t k = begin; k < end; ++k)
        m_rest_normals[k] = face_normal(m_rest, k);
    }, 4096);
  }
  // the (unnormalised) normal of the k-th ROI face at positions `p`, Newell-like from its first
  // vertex, on edge vectors scaled by a power of two (no overflow or underflow at any model size);
  // small enough to be inlined in the folded-face count that follows every deform(): triangles
  // take triangle_normal(), other polygons polygon_normal()
  Eigen::Vector3d face_normal(const std::vector<Eigen::Vector3d>& p, std::size_t k) const
  {
    const std::size_t first = m_face_start[k], end = m_face_start[k + 1];
    if(end - first == 3)
      return triangle_normal(p[m_face_vertex[first]], p[m_face_vertex[first + 1]], p[m_face_vertex[first + 2]]);
    return polygon_normal(p, first, end);
  }
  // face_normal() of a triangle (o, a, b), without loops: the numbers of polygon_normal() (up to
  // the sign of a zero component)
  static Eigen::Vector3d triangle_normal(const Eigen::Vector3d& o, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
  {
    const Eigen::Vector3d e1 = a - o, e2 = b - o;
    const double unit =
        internal::normalizing_power_of_two((std::max)(e1.cwiseAbs().maxCoeff(), e2.cwiseAbs().maxCoeff()));
    return (unit * e1).cross(unit * e2);
  }
  // face_normal() of the face whose vertices are m_face_vertex[first, end)
  Eigen::Vector3d polygon_normal(const std::vector<Eigen::Vector3d>& p, std::size_t first, std::size_t end) const
  {
    const Eigen::Vector3d& o = p[m_face_vertex[first]];
    double largest = 0;
    for(std::size_t i = first + 1; i < end; ++i)
      largest = (std::max)(largest, (p[m_face_vertex[i]] - o).cwiseAbs().maxCoeff());
    const double unit = internal::normalizing_power_of_two(largest);
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for(std::size_t i = first + 1; i + 1 < end; ++i)
      n += (unit * (p[m_face_vertex[i]] - o)).cross(unit * (p[m_face_vertex[i + 1]] - o));
    return n;
  }
  // after a successful deform(): folded faces, the preprocess warnings, no motion
  void add_warnings(const std::vector<Eigen::Vector3d>& p)
  {
    std::vector<Deformation_warning>& w = m_last.warnings;
    std::atomic<std::size_t> folded_faces(0);   // counted in blocks (on TBB's threads with Parallel_tag)
    internal::for_each_block(m_rest_normals.size(), internal::runs_in_parallel<ConcurrencyTag>(),
                             [&](std::size_t begin, std::size_t end) {
      std::size_t count = 0;
      for(std::size_t k = begin; k < end; ++k)
        count += m_rest_normals[k].dot(face_normal(p, k)) < 0;
      folded_faces += count;
    }, 4096);
    const std::size_t folded = folded_faces;
    if(folded > 0)
      w.push_back({FOLDED_FACES, folded, std::to_string(folded) + " of the " + std::to_string(m_rest_normals.size()) +
          " faces of the region of interest turned by more than 90 degrees from their rest orientation "
          "(the surface folded over itself, e.g. a spike at a handle): grow the region of interest or move "
          "the handles less"});
    w.insert(w.end(), m_preprocess_warnings.begin(), m_preprocess_warnings.end());
    const double unit = internal::normalizing_power_of_two(m_diagonal), threshold = 1e-12 * unit * m_diagonal;
    std::size_t controls = 0;
    // the largest squared norms, then their square roots (the same values: the square root is
    // monotonic and correctly rounded; one square root instead of one per vertex)
    double target_move = 0, solution_move = 0;
    for(std::size_t i : m_roi_index)
    {
      solution_move = (std::max)(solution_move, (unit * (p[i] - m_rest[i])).squaredNorm());
      if(m_is_control[i])
      {
        ++controls;
        target_move = (std::max)(target_move, (unit * (to_vector(m_target[i]) - m_rest[i])).squaredNorm());
      }
    }
    solution_move = std::sqrt(solution_move);
    target_move = std::sqrt(target_move);
    if(controls == 0)
      w.push_back({NO_MOTION, 0, "there is no control vertex: the region of interest stays at its rest shape"});
    else if(target_move <= threshold)
      w.push_back({NO_MOTION, controls, "every control vertex's target is its rest position: the deformation "
                                        "moves nothing (give the handles a translation, or rotate several of them)"});
    else if(solution_move <= threshold)
      w.push_back({NO_MOTION, controls, "the solution is the rest shape: no vertex moved by more than 1e-12 of "
                                        "the region of interest's diagonal"});
  }
  double region_diagonal() const
  {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
    for(vertex_descriptor v : m_roi)
    {
      lo = lo.cwiseMin(m_rest[index(v)]);
      hi = hi.cwiseMax(m_rest[index(v)]);
    }
    // scaled by a power of two (exact), so that the norm neither overflows nor underflows
    const double unit = internal::normalizing_power_of_two((hi - lo).maxCoeff());
    return (unit * (hi - lo)).norm() / unit;
  }

  Triangle_mesh& m_tm;
  Vertex_point_map m_vpm;
  Vertex_index_map m_vim;
  std::size_t m_number_of_vertices, m_number_of_edges;
  std::vector<Eigen::Vector3d> m_rest;
  std::vector<vertex_descriptor> m_roi;
  std::vector<vertex_descriptor> m_vertex_at_index;   // the mesh's vertices by index, for is_vertex()
  std::vector<Deformation_warning> m_preprocess_warnings;
  std::vector<std::size_t> m_face_start;                  // the faces with a vertex in the ROI: their
  std::vector<std::uint32_t> m_face_vertex;               // vertices (32-bit indices: see Deformation_core)
  std::vector<Eigen::Vector3d> m_rest_normals;             // and their rest normals
  std::vector<unsigned char> m_is_roi, m_is_control, m_moved, m_role;
  std::vector<unsigned char> m_next_role;         // prepare()'s roles: fixed but at the ROI being prepared
  std::vector<std::size_t> m_moved_vertices;   // a superset of the vertices whose m_moved is set
  std::vector<Point> m_target;
  Weight_policy m_weights;
  std::optional<Nodes> m_nodes;
  internal::Laplacian_stencils m_stencils;
  Eigen::SparseMatrix<double, Eigen::RowMajor> m_d;
  Eigen::MatrixX3d m_delta;
  std::vector<Eigen::Vector3d> m_rest_nodes;
  internal::Deformation_core<Transform_policy, Solver_traits, ConcurrencyTag> m_core;
  internal::Rotation_start_field m_field;
  std::vector<Eigen::Vector3d> m_start_values;      // apply_start()'s field values: 0 but during a call
  std::vector<Eigen::Quaterniond> m_target_rotation;   // per control: the rotation given by rotate()
  std::vector<unsigned char> m_rotation_known;         // whether it is known (see rotate())
  Deformation_start m_start = IDENTITY_START;
  bool m_field_ready = false;
  Eigen::SparseMatrix<double, Eigen::RowMajor> m_rigid_d;   // [D; lambda S] when rigidity_weight() > 0
  Eigen::MatrixX3d m_rigid_delta;
  std::vector<std::size_t> m_rigid_owner;
  double m_rigidity_weight = 0;
  bool m_energy_tracking = true;
  std::vector<unsigned char> m_operator_region;   // the ROI the operator was built for (by vertex index)
  std::vector<std::size_t> m_row_nodes;           // the fitted nodes' node indices, increasing
  std::vector<Eigen::Vector3d> m_positions;       // deform()'s positions: fixed vertices at rest
  std::vector<std::size_t> m_written;             // the vertices deform() wrote in m_positions
  std::vector<std::size_t> m_roi_index;           // the ROI's vertex indices, increasing (set by prepare())
  Deformation_result m_last;
  double m_diagonal = 0;
  double m_soft_weight = 1.;
  unsigned int m_iterations = 4;
  double m_tolerance = 1e-4;
  bool m_soft = false;
  bool m_operator_ready = false;
  bool m_rest_finite = true;                        // every rest position is finite (scan_rest_positions())
  double m_largest_coordinate = 0;                  // of the rest positions (scan_rest_positions())
  std::vector<std::uint32_t> m_pointing;            // per vertex: the halfedges pointing to it (constructor)
  std::vector<unsigned char> m_umbrella_checked;    // per vertex: its umbrella found manifold (check_umbrellas())
  bool m_foreign_vertex = false;
  bool m_need_preprocess = true;
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_MESH_DEFORMER_H
