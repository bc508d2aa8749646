// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_DEFORM_MESH_H
#define CGAL_LAPLACIAN_DEFORMATION_DEFORM_MESH_H

#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/parameters.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <functional>
#include <iterator>
#include <type_traits>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// CGAL's named parameters keep a non-copyable value as a std::reference_wrapper: the policy
// concepts only require DefaultConstructible, so the looked-up type is unwrapped.
template <class T>
struct Unwrap_parameter { typedef T type; };
template <class T>
struct Unwrap_parameter<std::reference_wrapper<T> > { typedef std::remove_const_t<T> type; };

template <class Tag, class NamedParameters, class Default>
using Policy_parameter_t = typename Unwrap_parameter<
    typename CGAL::internal_np::Lookup_named_param_def<Tag, NamedParameters, Default>::type>::type;

// the policy instance of a named parameter (a copy), or a default-constructed one
template <class Policy, class Tag, class NamedParameters>
Policy policy_parameter(const NamedParameters& np, Tag tag)
{
  if constexpr(CGAL::parameters::is_default_parameter<NamedParameters, Tag>::value)
    return Policy();
  else
    return CGAL::internal_np::get_reference(CGAL::parameters::get_parameter(np, tag));
}

// The deformer of deform_mesh(): with copies of the policy instances of `np`. A policy that is
// not CopyConstructible cannot be stored: it is default-constructed (the weights only when both
// are not copyable, the transform whenever it is not).
template <class Deformer, class TriangleMesh, class VertexPointMap, class NamedParameters>
Deformer make_deformer(TriangleMesh& tm, const VertexPointMap& vpm, const NamedParameters& np)
{
  typedef typename Deformer::Weight_policy Weights;
  typedef typename Deformer::Transform_policy Transform;
  constexpr bool copy_weights = std::is_copy_constructible<Weights>::value;
  constexpr bool copy_transform = std::is_copy_constructible<Transform>::value;
  if constexpr(copy_weights && copy_transform)
    return Deformer(tm, vpm, policy_parameter<Weights>(np, internal_np::weight_policy),
                    policy_parameter<Transform>(np, internal_np::transform_policy));
  else if constexpr(copy_weights)
    return Deformer(tm, vpm, policy_parameter<Weights>(np, internal_np::weight_policy));
  else
    return Deformer(tm, vpm);
}

} // namespace internal

/*!
\ingroup PkgLaplacianDeformationFunctions

\brief deforms `tm` in one call: the vertices of `roi` are free, those of `controls` (which
should belong to `roi`; they are added to it otherwise) are moved to `targets`, every other
vertex stays fixed.

Equivalent to a `Mesh_deformer` with the chosen policies, `insert_roi_vertices(roi)`,
`insert_control_vertices(controls)`, one `set_target_position()` per control, and
`deform(number_of_iterations, tolerance)`. On failure the mesh is left unchanged and the
result says why; in particular `INVALID_PARAMETER` if `targets` has not exactly as many points
as `controls`.

\tparam TriangleMesh a model of `FaceGraph`; its faces may be polygons (see \ref LapDefPolygons)
\tparam VertexRange a range of `boost::graph_traits<TriangleMesh>::%vertex_descriptor`
\tparam ControlRange a range of `boost::graph_traits<TriangleMesh>::%vertex_descriptor`
\tparam PointRange a range of points, as many as `controls`

\cgalNamedParamsBegin
  \cgalParamNBegin{vertex_point_map}
    \cgalParamDescription{a property map associating points to the vertices of `tm`}
    \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
  \cgalParamNEnd
  \cgalParamNBegin{representation}
    \cgalParamDescription{a model of `DeformationRepresentation` (package parameter `CGAL::Laplacian_deformation::parameters::representation()`; its type selects the representation)}
    \cgalParamDefault{`Edge_based_representation()`}
  \cgalParamNEnd
  \cgalParamNBegin{weight_policy}
    \cgalParamDescription{a model of `DeformationWeightPolicy` (package parameter): the deformer uses a copy of it if it is `CopyConstructible` (a stateful policy, or an `Any_weights` chosen at run time), else a default-constructed one}
    \cgalParamDefault{`Cotangent_weights()`}
  \cgalParamNEnd
  \cgalParamNBegin{transform_policy}
    \cgalParamDescription{a model of `DeformationTransformPolicy` (package parameter): the deformer uses a copy of it if it is `CopyConstructible` (a stateful policy, or an `Any_transform` chosen at run time), else a default-constructed one}
    \cgalParamDefault{`Scaled_rotation_transform()`}
  \cgalParamNEnd
  \cgalParamNBegin{sparse_linear_solver}
    \cgalParamDescription{an instance of the solver traits (its type selects the solver)}
    \cgalParamDefault{`Default_solver_traits()`}
  \cgalParamNEnd
  \cgalParamNBegin{number_of_iterations}
    \cgalParamDescription{the largest number of iterations}
    \cgalParamDefault{`4` (the paper uses 3 to 4)}
  \cgalParamNEnd
  \cgalParamNBegin{tolerance}
    \cgalParamDescription{stop when an iteration moves no vertex by more than this fraction of the ROI's bounding-box diagonal (package parameter)}
    \cgalParamDefault{`1e-4`}
  \cgalParamNEnd
  \cgalParamNBegin{soft_constraint_weight}
    \cgalParamDescription{if given, the controls are soft with this relative weight (package parameter); otherwise hard}
    \cgalParamDefault{hard constraints}
  \cgalParamNEnd
  \cgalParamNBegin{start}
    \cgalParamDescription{the transforms of the first solve, a `Deformation_start` (package parameter; see \ref LapDefStart)}
    \cgalParamDefault{`IDENTITY_START`}
  \cgalParamNEnd
  \cgalParamNBegin{concurrency_tag}
    \cgalParamDescription{`CGAL::Sequential_tag`, `CGAL::Parallel_tag` or `CGAL::Parallel_if_available_tag`: whether the local step, the right-hand sides, the rest-cell weights and \f$A^T A\f$ use \tbb's threads, as `Mesh_deformer`'s `ConcurrencyTag` (package parameter; the weight and transform policies are then called from several threads at once)}
    \cgalParamDefault{`CGAL::Parallel_if_available_tag`}
  \cgalParamNEnd
\cgalNamedParamsEnd
*/
template <class TriangleMesh, class VertexRange, class ControlRange, class PointRange,
          class NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_result deform_mesh(TriangleMesh& tm, const VertexRange& roi, const ControlRange& controls,
                               const PointRange& targets,
                               const NamedParameters& np = CGAL::parameters::default_values())
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using CGAL::parameters::is_default_parameter;
  typedef internal::Policy_parameter_t<
      internal_np::representation_t, NamedParameters, Edge_based_representation> Representation;
  typedef internal::Policy_parameter_t<
      internal_np::weight_policy_t, NamedParameters, Cotangent_weights> Weights;
  typedef internal::Policy_parameter_t<
      internal_np::transform_policy_t, NamedParameters, Scaled_rotation_transform> Transform;
  typedef typename CGAL::internal_np::Lookup_named_param_def<
      CGAL::internal_np::sparse_linear_solver_t, NamedParameters, Default_solver_traits>::type Solver;
  typedef typename CGAL::internal_np::Lookup_named_param_def<
      internal_np::concurrency_tag_t, NamedParameters, CGAL::Parallel_if_available_tag>::type Concurrency;
  typedef typename GetVertexPointMap<TriangleMesh, NamedParameters>::type Vertex_point_map;

  typedef Mesh_deformer<TriangleMesh, Representation, Weights, Transform, Solver, Vertex_point_map, Concurrency>
      Deformer;
  Deformer deformer = internal::make_deformer<Deformer>(
      tm, choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point), get_property_map(CGAL::vertex_point, tm)),
      np);
  if(std::distance(std::begin(controls), std::end(controls)) != std::distance(std::begin(targets), std::end(targets)))
  {
    Deformation_result result;
    result.status = INVALID_PARAMETER;
    result.message = "deform_mesh() needs exactly one target per control vertex";
    return result;
  }
  deformer.insert_roi_vertices(std::begin(roi), std::end(roi));
  deformer.insert_control_vertices(std::begin(controls), std::end(controls));
  auto target = std::begin(targets);
  for(auto v : controls)
    deformer.set_target_position(v, *target++);
  deformer.set_start(choose_parameter(get_parameter(np, internal_np::start), IDENTITY_START));
  if(!is_default_parameter<NamedParameters, internal_np::soft_constraint_weight_t>::value)
    deformer.set_soft_constraints(choose_parameter(get_parameter(np, internal_np::soft_constraint_weight), 1.));
  return deformer.deform(choose_parameter(get_parameter(np, CGAL::internal_np::number_of_iterations), 4u),
                         choose_parameter(get_parameter(np, internal_np::tolerance), 1e-4));
}

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_DEFORM_MESH_H
