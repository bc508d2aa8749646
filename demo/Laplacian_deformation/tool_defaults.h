// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// The tools' one set of defaults (not part of the package's API): what the laplacian_deform
// command line, the editor (laplacian_deform --serve) and the comparison harness's figure panels
// use when nothing else is asked for. The policies are the first entries of the catalogue of
// policy names (policy_names.h), which are the library's defaults.

#ifndef LAPLACIAN_DEFORMATION_TOOL_DEFAULTS_H
#define LAPLACIAN_DEFORMATION_TOOL_DEFAULTS_H

#include "policy_names.h"

namespace Laplacian_deformation_tool_defaults {

namespace policy_names = Laplacian_deformation_policy_names;

/// "edge": nodes at the edge midpoints
inline const char* representation() { return policy_names::representations()[0].name; }
/// "cotangent"
inline const char* weights() { return policy_names::weight_policies()[0].name; }
/// "sr1", the paper's S*R1
inline const char* transform() { return policy_names::transform_policies()[0].name; }
/// "scaled_rotation": S*R1 under the editor's name (its other accepted name)
inline const char* editor_transform() { return policy_names::transform_policies()[0].alias; }
/// "identity": the first solve with T = I (Mesh_deformer's default start)
inline const char* start() { return "identity"; }
/// iterations of a deformation (the paper's 3 to 4), of a drag in the editor too
inline constexpr unsigned int iterations = 4;
/// iterations of every run of the comparison harness (compare_deformations --iterations)
inline constexpr unsigned int comparison_iterations = 10;
/// 0: run every iteration (no early stop)
inline constexpr double tolerance = 0;
/// 0: no rigidity rows
inline constexpr double rigidity = 0;
/// the rigidity weight the tools recommend for large rotations (with the rotation start; see the manual)
inline constexpr double recommended_rigidity = 0.3;
/// the relative weight of soft handle constraints when asked for without a weight
inline constexpr double soft_weight = 1;
/// the folder the tools write into when not told (the main job's results, the editor's saves)
inline const char* output_dir() { return "laplacian_deform_output"; }

/// the library's Default_solver_traits: CHOLMOD when the package target found it
inline const char* solver()
{
#ifdef CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD
  return "cholmod";
#else
  return "eigen";
#endif
}

} // namespace Laplacian_deformation_tool_defaults

#endif // LAPLACIAN_DEFORMATION_TOOL_DEFAULTS_H
