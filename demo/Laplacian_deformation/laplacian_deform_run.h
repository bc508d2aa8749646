// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform tool: one deformation of a task with policies chosen
// at run time. Every transform policy is instantiated in its own translation unit
// (laplacian_deform_run_<policy>.cpp) so that the 48 policy combinations compile in parallel.

#ifndef LAPLACIAN_DEFORM_RUN_H
#define LAPLACIAN_DEFORM_RUN_H

#include "laplacian_deform_cli.h"

#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Cotangent_weights.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/Fixed_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Principal_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_scale_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Anchored_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Least_squares_solver.h>
#ifdef LAPLACIAN_DEFORM_HAS_CHOLMOD
#include <CGAL/Laplacian_deformation/Cholmod_solver_traits.h>
#endif

#include <chrono>
#include <string>

namespace laplacian_deform {

/// Deforms `task` with the policies of the template arguments into `run.mesh` (a copy of the
/// rest mesh): preprocess, set the targets of the handles, then one `deform(1, tolerance)` per
/// iteration (which the library guarantees equal to one `deform(iterations, tolerance)` call)
/// so that each iteration is timed and reported.
template <class Representation, class Weights, class Transform, class Solver>
void deform_run(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
  typedef std::chrono::steady_clock Clock;
  run.mesh = task.mesh;
  LD::Mesh_deformer<Mesh, Representation, Weights, Transform, Solver> deformer(run.mesh);
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

namespace detail {

template <class Representation, class Weights, class Transform>
void with_solver(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
#ifdef LAPLACIAN_DEFORM_HAS_CHOLMOD
  if(run.solver == "cholmod")
    return deform_run<Representation, Weights, Transform, LD::Cholmod_solver_traits>(task, o, run, progress);
#endif
  deform_run<Representation, Weights, Transform, LD::Eigen_simplicial_solver_traits>(task, o, run, progress);
}

template <class Representation, class Transform>
void with_weights(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
  if(run.weights == "uniform")
    with_solver<Representation, LD::Uniform_weights, Transform>(task, o, run, progress);
  else
    with_solver<Representation, LD::Cotangent_weights, Transform>(task, o, run, progress);
}

} // namespace detail

/// `deform_run()` with the representation, weights and solver named in `run`.
template <class Transform>
void run_with_transform(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
  if(run.representation == "vertex")
    detail::with_weights<LD::Vertex_based_representation, Transform>(task, o, run, progress);
  else
    detail::with_weights<LD::Edge_based_representation, Transform>(task, o, run, progress);
}

#define LAPLACIAN_DEFORM_TRANSFORMS(X)                                                   \
  X(LD::Scaled_rotation_transform) X(LD::Fixed_transform) X(LD::Rotation_transform)     \
  X(LD::Similarity_transform) X(LD::Principal_scaled_rotation_transform)                \
  X(LD::Rotation_scale_rotation_transform) X(LD::Anchored_scaled_rotation_transform)

#define LAPLACIAN_DEFORM_EXTERN(T) \
  extern template void run_with_transform<T>(const Task&, const Options&, Run_record&, Progress&);
LAPLACIAN_DEFORM_TRANSFORMS(LAPLACIAN_DEFORM_EXTERN)
#undef LAPLACIAN_DEFORM_EXTERN

#define LAPLACIAN_DEFORM_INSTANTIATE(T) \
  template void run_with_transform<T>(const Task&, const Options&, Run_record&, Progress&);

/// `deform_run()` with every policy named in `run` (set its representation, weights, transform
/// and solver first).
inline void run_deformation(const Task& task, const Options& o, Run_record& run, Progress& progress)
{
  if(run.transform == "fixed") run_with_transform<LD::Fixed_transform>(task, o, run, progress);
  else if(run.transform == "rotation") run_with_transform<LD::Rotation_transform>(task, o, run, progress);
  else if(run.transform == "similarity") run_with_transform<LD::Similarity_transform>(task, o, run, progress);
  else if(run.transform == "principal") run_with_transform<LD::Principal_scaled_rotation_transform>(task, o, run, progress);
  else if(run.transform == "anchored") run_with_transform<LD::Anchored_scaled_rotation_transform>(task, o, run, progress);
  else if(run.transform == "rsr") run_with_transform<LD::Rotation_scale_rotation_transform>(task, o, run, progress);
  else run_with_transform<LD::Scaled_rotation_transform>(task, o, run, progress);
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_RUN_H
