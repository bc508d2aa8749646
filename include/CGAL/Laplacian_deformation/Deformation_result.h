// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_RESULT_H
#define CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_RESULT_H

#include <cstddef>
#include <string>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationRef
\brief Why a `Mesh_deformer::preprocess()` or `Mesh_deformer::deform()` call succeeded or failed.
Whatever the failure, the mesh is left exactly as it was.
*/
enum Deformation_status
{
  SUCCESS = 0,                 ///< the call succeeded
  EMPTY_REGION_OF_INTEREST,    ///< no vertex is in the region of interest
  UNANCHORED_REGION,           ///< a connected part of the free vertices touches no fixed or control vertex (the system is singular)
  FACTORIZATION_FAILED,        ///< the normal matrix could not be factored (numerically singular)
  SOLVE_FAILED,                ///< the back-substitution failed
  NON_FINITE_INPUT,            ///< a rest position or a target is NaN or infinite
  NON_FINITE_RESULT,           ///< the solution contains NaN or infinity (nothing was written)
  INVALID_PARAMETER,           ///< a parameter is out of its range (negative tolerance, soft weight not positive)
  TOPOLOGY_CHANGED,            ///< the mesh's number of vertices or edges changed since construction
  INVALID_MESH                 ///< the mesh cannot be deformed: a vertex is non-manifold (its incident faces form several fans)
};

/*!
\ingroup PkgLaplacianDeformationRef
\brief What a `preprocess()` or `deform()` call did: success or the reason for failure,
iterations performed, energies and the largest constraint residual.
*/
struct Deformation_result
{
  /// the outcome.
  Deformation_status status = SUCCESS;
  /// a human-readable explanation (empty on success).
  std::string message;
  /// for `UNANCHORED_REGION`: the number of vertices in the largest unanchored part.
  std::size_t unanchored_size = 0;
  /// the number of iterations performed by `deform()`.
  std::size_t iterations = 0;
  /// the energy <code>sum_a |T_a delta_a - D_a p'|^2</code> (plus the soft terms) after each iteration.
  /// Not guaranteed to decrease: the transforms are fitted to the cells, not to this energy.
  std::vector<double> energies;
  /// the last entry of `energies` (0 if none).
  double energy = 0;
  /// the largest vertex displacement of the last iteration, relative to the region's bounding-box diagonal.
  double last_change = 0;
  /// the largest distance between a control vertex and its target (0 for hard constraints).
  double max_constraint_residual = 0;
  /// wall-clock seconds of the whole call.
  double seconds = 0;
  /// `deform()` only: wall-clock seconds spent fitting the transforms (the local step), summed over the iterations.
  double local_step_seconds = 0;
  /// `deform()` only: wall-clock seconds spent assembling the right-hand sides `b = T delta - K p_known`
  /// and `A^T b` (the input of the solve), summed over the iterations.
  double right_hand_side_seconds = 0;
  /// `deform()` only: wall-clock seconds spent in the forward and backward substitutions with the
  /// factor of `A^T A`, summed over the iterations.
  double solve_seconds = 0;

  /// `true` on success.
  explicit operator bool() const { return status == SUCCESS; }
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_RESULT_H
