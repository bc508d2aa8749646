// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_HARNESS_METHODS_H
#define CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_HARNESS_METHODS_H

// The methods the comparison harness (compare_deformations.cpp) runs on every task: ours, every
// representation x weights x transform (the names of the tools' catalogue policy_names.h, as
// run-time policies) with both starts, the rigid configurations, and CGAL's
// Surface_mesh_deformation; what one run reports (Record, sent back by the child process).

#include "deformation_task.h"
#include "policy_names.h"
#include "tool_defaults.h"

#include <CGAL/Laplacian_deformation.h>
#include <CGAL/Laplacian_deformation/metrics.h>
#include <CGAL/Surface_mesh_deformation.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace Laplacian_deformation_benchmark {

namespace LD = CGAL::Laplacian_deformation;
namespace policy_names = Laplacian_deformation_policy_names;
namespace defaults = Laplacian_deformation_tool_defaults;

typedef std::chrono::steady_clock Clock;

// what a child process sends back (trivially copyable)
struct Record
{
  int ok = 0;
  char message[240] = {0};
  unsigned iterations = 0;
  double preprocess_seconds = 0;
  double iteration_seconds = 0, local_step_seconds = 0, right_hand_side_seconds = 0, solve_seconds = 0;  // per iteration
  double peak_rss_mb = 0, extra_rss_mb = 0;
  LD::Deformation_quality quality;
  Task_metrics metrics;
};

// called after every iteration with its number (from 1) and the deformed mesh
typedef std::function<void(unsigned, const Mesh&)> Step;

struct Method
{
  std::string method, representation, weights, transform, start, panel;   // panel: PLY name of a default combination
  typedef std::function<bool(const Task&, unsigned, Mesh&, Record&, const Step&)> Runner;
  Runner run;
};

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline void set_message(Record& r, const std::string& m) { std::snprintf(r.message, sizeof(r.message), "%s", m.c_str()); }

// the weights and the transform are run-time policies named in policy_names.h (the tools' one
// catalogue): one Mesh_deformer per representation
template <class Representation>
bool run_ours(const Task& task, unsigned iterations, const std::string& weights, const std::string& transform,
              LD::Deformation_start start, double rigidity, Mesh& m, Record& r, const Step& step)
{
  m = task.mesh;
  LD::Mesh_deformer<Mesh, Representation, LD::Any_weights, LD::Any_transform> d(
      m, policy_names::weight_policy(weights), policy_names::transform_policy(transform));
  d.set_start(start);
  d.set_rigidity_weight(rigidity);
  d.insert_roi_vertices(task.roi.begin(), task.roi.end());
  d.insert_control_vertices(task.handle.begin(), task.handle.end());
  const Clock::time_point t0 = Clock::now();
  if(!d.preprocess())
    return set_message(r, d.last_result().message), false;
  r.preprocess_seconds = seconds_since(t0);
  for(std::size_t i = 0; i < task.handle.size(); ++i)
    d.set_target_position(task.handle[i], task.targets[i]);
  for(unsigned it = 0; it < iterations; ++it)
  {
    const LD::Deformation_result result = d.deform(1, 0.);
    if(!result)
      return set_message(r, result.message), false;
    r.iteration_seconds += result.seconds;
    r.local_step_seconds += result.local_step_seconds;
    r.right_hand_side_seconds += result.right_hand_side_seconds;
    r.solve_seconds += result.solve_seconds;
    ++r.iterations;
    if(step)
      step(r.iterations, m);
  }
  return true;
}

template <CGAL::Deformation_algorithm_tag Tag>
bool run_cgal(const Task& task, unsigned iterations, Mesh& m, Record& r, const Step& step)
{
  m = task.mesh;
  CGAL::Surface_mesh_deformation<Mesh, CGAL::Default, CGAL::Default, Tag> d(m);
  d.insert_roi_vertices(task.roi.begin(), task.roi.end());
  for(vertex_descriptor v : task.handle)
    d.insert_control_vertex(v);
  const Clock::time_point t0 = Clock::now();
  if(!d.preprocess())
    return set_message(r, "CGAL's preprocess() failed"), false;
  r.preprocess_seconds = seconds_since(t0);
  for(std::size_t i = 0; i < task.handle.size(); ++i)
    d.set_target_position(task.handle[i], task.targets[i]);
  for(unsigned it = 0; it < iterations; ++it)
  {
    const Clock::time_point t1 = Clock::now();
    d.deform(1, 0.);
    r.iteration_seconds += seconds_since(t1);
    ++r.iterations;
    if(step)
      step(r.iterations, m);
  }
  return true;
}

// the ours(representation, weights, transform, start, rigidity) runner (names of policy_names.h)
inline Method::Runner ours(const std::string& representation, const std::string& weights, const std::string& transform,
                    LD::Deformation_start start, double rigidity)
{
  if(!policy_names::find(policy_names::weight_policies(), weights) ||
     !policy_names::find(policy_names::transform_policies(), transform))
    throw std::logic_error("compare_deformations: no policy named " + weights + " or " + transform);
  const bool vertex = policy_names::representation(representation) == policy_names::Representation::VERTEX;
  return [=](const Task& task, unsigned iterations, Mesh& m, Record& r, const Step& step) {
    return vertex ? run_ours<LD::Vertex_based_representation>(task, iterations, weights, transform, start, rigidity, m, r, step)
                  : run_ours<LD::Edge_based_representation>(task, iterations, weights, transform, start, rigidity, m, r, step);
  };
}

// one combination with both starts (the start and the policies are chosen at run time);
// `panel` names the PLY of the identity start (the library's default start), if any
inline void add_starts(std::vector<Method>& methods, const std::string& representation, const std::string& weights,
                const std::string& transform, const std::string& panel)
{
  const std::pair<LD::Deformation_start, const char*> starts[] = {{LD::IDENTITY_START, "identity"},
                                                                  {LD::ROTATION_START, "rotation"}};
  for(const auto& s : starts)
    methods.push_back({"ours", representation, weights, transform, s.second,
                       s.first == LD::IDENTITY_START ? panel : std::string(),
                       ours(representation, weights, transform, s.first, 0.)});
}

// the recommended configurations for large rotations: rotation start and spoke rigidity rows of
// weight 0.3 (Mesh_deformer::set_rigidity_weight), named TRANSFORM+rigid
inline void add_rigid(std::vector<Method>& methods, const std::string& representation, const std::string& weights,
               const std::string& transform)
{
  methods.push_back({"ours", representation, weights, transform + "+rigid", "rotation", std::string(),
                     ours(representation, weights, transform, LD::ROTATION_START, defaults::recommended_rigidity)});
}

inline void add_transforms(std::vector<Method>& methods, const std::string& representation, const std::string& weights)
{
  // the panels: the tools' defaults (tool_defaults.h: cotangent weights, S*R1, identity start)
  const std::string panel = weights == defaults::weights() ? representation : std::string();
  // in the order of the result files (every name of policy_names::transform_policies())
  for(const char* transform : {"fixed", "rotation", "similarity", "sr1", "principal", "rsr", "anchored"})
    add_starts(methods, representation, weights, transform,
               std::string(transform) == defaults::transform() ? panel : std::string());
  if(weights == "cotangent")
  {
    add_rigid(methods, representation, weights, "rotation");
    add_rigid(methods, representation, weights, "anchored");
  }
}

inline std::vector<Method> all_methods()
{
  std::vector<Method> methods;
  for(const char* representation : {"vertex", "edge"})
    for(const char* weights : {"uniform", "cotangent"})
      add_transforms(methods, representation, weights);
  methods.push_back({"cgal", "vertex", "cotangent", "ORIGINAL_ARAP", "", "cgal_arap", run_cgal<CGAL::ORIGINAL_ARAP>});
  methods.push_back({"cgal", "vertex", "cotangent", "SPOKES_AND_RIMS", "", "", run_cgal<CGAL::SPOKES_AND_RIMS>});
  methods.push_back({"cgal", "vertex", "cotangent", "SRE_ARAP", "", "", run_cgal<CGAL::SRE_ARAP>});
  return methods;
}

} // namespace Laplacian_deformation_benchmark

#endif // CGAL_LAPLACIAN_DEFORMATION_BENCHMARK_HARNESS_METHODS_H
