// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_START_H
#define CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_START_H

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationRef
\brief The transforms of the first solve after `Mesh_deformer::preprocess()`, `Mesh_deformer::reset()`
or a restart (see \ref LapDefStart).
*/
enum Deformation_start
{
  /// `T_a = I` (the default): the first solve is plain Laplacian editing; a handle's rotation
  /// reaches the region of interest only through the iterations.
  IDENTITY_START = 0,
  /// `T_a = exp(sum_g phi_g(a) log R_g)`: each control group's rotation `R_g`, propagated into
  /// the region of interest by a harmonic field `phi_g` (1 on the group, 0 on the fixed vertices
  /// and the other groups). A pure translation of the controls gives exactly the identity start.
  ROTATION_START
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_DEFORMATION_START_H
