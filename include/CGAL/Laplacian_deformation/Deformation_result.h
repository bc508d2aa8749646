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
  UNANCHORED_REGION,           ///< a connected part of the free vertices touches no fixed or control vertex, or the Laplacian operator is zero at some free vertices (every weight of their cells vanishes); the system is singular
  FACTORIZATION_FAILED,        ///< the normal matrix could not be factored (numerically singular), or its diagonal overflows or underflows (Laplacian weights too large or too small to be squared)
  SOLVE_FAILED,                ///< the back-substitution failed
  NON_FINITE_INPUT,            ///< a rest position or a target is NaN or infinite, or the weight policy gave a NaN or infinite weight
  NON_FINITE_RESULT,           ///< the solution, or a transform fitted by the transform policy, contains NaN or infinity (nothing was written)
  INVALID_PARAMETER,           ///< a parameter is out of its range (tolerance negative, infinite or NaN, soft weight not positive and finite), or a vertex descriptor is not a vertex of the mesh
  TOPOLOGY_CHANGED,            ///< the mesh's number of vertices or edges changed since construction
  INVALID_MESH                 ///< the mesh cannot be deformed: a vertex the operator is built from (around the ROI) is non-manifold (its incident faces form several fans)
};

/*!
\ingroup PkgLaplacianDeformationRef
\brief The kinds of `Deformation_warning`: results that succeeded but look wrong.
*/
enum Deformation_warning_kind
{
  /// `deform()`: faces of the region of interest (faces with a vertex in it) whose normal turned by
  /// more than 90 degrees from its rest direction: the surface folded over itself, typically a
  /// spike or a fold near a handle moved far relative to the size of the region of interest.
  /// `count` is the number of such faces. Computed once per call, after the iterations.
  FOLDED_FACES = 0,
  /// `preprocess()` and `deform()`: control vertices adjacent (by an edge) to fixed vertices, i.e.
  /// not separated from the fixed part by a free vertex; moving them stretches the edges to the
  /// fixed vertices into a thin tongue. `count` is the number of such control vertices.
  /// Computed at `preprocess()`.
  HANDLE_TOUCHES_FIXED,
  /// `deform()`: the deformation moves nothing: every control vertex's target is its rest
  /// position, there is no control vertex, or the solution is the rest shape (no vertex moved by
  /// more than `1e-12` times the ROI's bounding-box diagonal). `count` is the number of control vertices.
  NO_MOTION
};

/// \ingroup PkgLaplacianDeformationRef
/// the name of a warning kind, as spelled in the enum (`"FOLDED_FACES"`, ...).
inline const char* warning_kind_name(Deformation_warning_kind kind)
{
  switch(kind)
  {
    case FOLDED_FACES: return "FOLDED_FACES";
    case HANDLE_TOUCHES_FIXED: return "HANDLE_TOUCHES_FIXED";
    case NO_MOTION: return "NO_MOTION";
  }
  return "UNKNOWN";
}

/*!
\ingroup PkgLaplacianDeformationRef
\brief A warning of `Deformation_result::warnings`: the call succeeded (its status stays `SUCCESS`)
but its result probably is not what was meant.
*/
struct Deformation_warning
{
  /// what looks wrong.
  Deformation_warning_kind kind = FOLDED_FACES;
  /// how many faces or vertices are concerned (see `Deformation_warning_kind`).
  std::size_t count = 0;
  /// a human-readable explanation.
  std::string message;
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
  /// Empty when the deformer's energy tracking is off (`Mesh_deformer::set_energy_tracking()`).
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

  /// results that succeeded but look wrong (folded faces, handles touching fixed vertices, no
  /// motion), in the order of `Deformation_warning_kind`; empty when nothing looks wrong or on failure.
  /// The warnings cost nothing per iteration: the adjacency of the handles is found at
  /// `preprocess()`, the folded faces and the motion are checked once at the end of `deform()`.
  std::vector<Deformation_warning> warnings;

  /// `true` on success (with or without warnings).
  explicit operator bool() const { return status == SUCCESS; }
  /// the warning of kind `kind`, or `nullptr` if there is none.
  const Deformation_warning* warning(Deformation_warning_kind kind) const
  {
    for(const Deformation_warning& w : warnings)
      if(w.kind == kind)
        return &w;
    return nullptr;
  }
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_RESULT_H
