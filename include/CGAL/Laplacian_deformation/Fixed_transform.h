// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_FIXED_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_FIXED_TRANSFORM_H

#include <CGAL/Laplacian_deformation/Node_cell.h>

#include <Eigen/Core>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief `T_a = I`: plain Laplacian editing (the paper's equation 5).

The Laplacian coordinates keep their rest orientation and length, so rotations and scalings of
the handles are not propagated to the details. One solve gives the result; further iterations
change nothing (the deformer stops after the second, whose change is zero).
Invariant under translations and uniform scalings of the whole problem, not under rotations.

\cgalModels{DeformationTransformPolicy}
*/
struct Fixed_transform
{
  /// returns the identity.
  Eigen::Matrix3d transform(const Transform_cell&) const { return Eigen::Matrix3d::Identity(); }
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_FIXED_TRANSFORM_H
