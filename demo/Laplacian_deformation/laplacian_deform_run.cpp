// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform: one deformation of a task with the policies chosen at run time. The weights
// and the transform are run-time policies (Any_weights, Any_transform, named in policy_names.h):
// Mesh_deformer is instantiated once per representation and solver, in this translation unit.

#include "laplacian_deform_run.h"

#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Any_weights.h>
#include <CGAL/Laplacian_deformation/Any_transform.h>
#include <CGAL/Laplacian_deformation/Least_squares_solver.h>
#ifdef CGAL_LAPLACIAN_DEFORMATION_HAS_CHOLMOD
#include <CGAL/Laplacian_deformation/Cholmod_solver_traits.h>
#endif

#include <chrono>
#include <string>

namespace laplacian_deform {

namespace {

/// Deforms `task` with the representation and solver of the template arguments and the weights
/// and transform named in `run` (run-time policies) into `run.mesh` (a copy of the rest mesh):
/// preprocess, set the targets of the handles, then one `deform(1, tolerance)` per iteration
/// (which the library guarantees equal to one `deform(iterations, tolerance)` call) so that each
/// iteration is timed and reported.
template <class Representation, class Solver>
void deform_run(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
  typedef std::chrono::steady_clock Clock;
  run.mesh = task.mesh;
  LD::Mesh_deformer<Mesh, Representation, LD::Any_weights, LD::Any_transform, Solver> deformer(
      run.mesh, policy_names::weight_policy(run.weights), policy_names::transform_policy(run.transform));
  std::vector<vertex_descriptor> handles;
  for(vertex_descriptor v : vertices(run.mesh))
  {
    if(task.status[v] == LD::IO::BOTSCH08_REGION_OF_INTEREST)
      deformer.insert_roi_vertex(v);
    else if(task.status[v] == LD::IO::BOTSCH08_HANDLE)
    {
      deformer.insert_control_vertex(v);
      handles.push_back(v);
    }
  }
  if(o.soft)
    deformer.set_soft_constraints(o.soft_weight);
  deformer.set_start(o.start == "identity" ? LD::IDENTITY_START : LD::ROTATION_START);
  deformer.set_rigidity_weight(o.rigidity);

  progress.stage(run.name() + ": preprocessing (building and factoring the system)");
  const Clock::time_point t0 = Clock::now();
  const bool prepared = deformer.preprocess();
  run.preprocess_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if(!prepared)
  {
    run.status = status_name(deformer.last_result().status);
    run.message = deformer.last_result().message;
    return;
  }
  run.row_nodes = deformer.row_nodes().size();
  if(task.has_rotation)        // --rotate: through rotate(), so that the start knows the turn exactly
  {
    deformer.rotate(handles.begin(), handles.end(), task.rotation_center, task.rotation);
    deformer.translate(handles.begin(), handles.end(), task.translation);
  }
  else
    for(vertex_descriptor v : handles)
    {
      const Point_3& p = run.mesh.point(v);
      const Eigen::Vector4d q = task.transform * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
      deformer.set_target_position(v, Point_3(q.x(), q.y(), q.z()));
    }
  const Clock::time_point t1 = Clock::now();
  for(unsigned int k = 0; k < o.iterations; ++k)
  {
    progress.stage(run.name() + ": iteration " + std::to_string(k + 1) + "/" + std::to_string(o.iterations));
    const LD::Deformation_result r = deformer.deform(1, o.tolerance);
    if(!r)
    {
      run.status = status_name(r.status);
      run.message = r.message;
      return;
    }
    Iteration_record it;
    it.seconds = r.seconds;
    it.local_step_seconds = r.local_step_seconds;
    it.right_hand_side_seconds = r.right_hand_side_seconds;
    it.solve_seconds = r.solve_seconds;
    it.energy = r.energy;
    it.change = r.last_change;
    run.iterations.push_back(it);
    run.energy = r.energy;
    run.last_change = r.last_change;
    run.max_constraint_residual = r.max_constraint_residual;
    run.warnings = r.warnings;
    if(r.iterations == 0 || r.last_change <= o.tolerance)   // no unknown, or converged
      break;
  }
  run.deform_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  run.factorizations = deformer.number_of_factorizations();
  run.ok = true;
  run.status = status_name(LD::SUCCESS);
  measure(task, run);
}

template <class Representation>
void with_solver(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
#ifdef CGAL_LAPLACIAN_DEFORMATION_HAS_CHOLMOD
  if(run.solver == "cholmod")
    return deform_run<Representation, LD::Cholmod_solver_traits>(task, o, run, progress);
#endif
  deform_run<Representation, LD::Eigen_simplicial_solver_traits>(task, o, run, progress);
}

} // namespace

void run_deformation(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
  if(policy_names::representation(run.representation) == policy_names::Representation::VERTEX)
    with_solver<LD::Vertex_based_representation>(task, o, run, progress);
  else
    with_solver<LD::Edge_based_representation>(task, o, run, progress);
}

} // namespace laplacian_deform
