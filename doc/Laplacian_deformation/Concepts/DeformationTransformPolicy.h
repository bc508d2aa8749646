/*!
\ingroup PkgLaplacianDeformationConcepts
\cgalConcept

@brief A transform policy fits, for one node, the linear map `T_a` that is applied to its rest
Laplacian coordinate before the next solve.

A Laplacian coordinate `delta_a` is invariant under translations only; when the handles rotate
or scale a part of the mesh, the rest coordinates must be rotated or scaled too. Each iteration
of `Mesh_deformer::deform()` therefore (1) fits `T_a` for every node from the change of its cell,
then (2) solves <code>min sum_a |T_a delta_a - D_a p'|^2</code> for the vertex positions <code>p'</code>. The policy
is step (1): from the cell's rest edge vectors `e_ab = x_a - x_b`, current edge vectors <code>e'_ab</code>
and fit weights `c_ab = max(w_ab, 0)` (see `CGAL::Laplacian_deformation::Transform_cell`), it
returns `T_a`, usually the minimiser of <code>sum_b c_ab |e'_ab - T_a e_ab|^2</code> over some family of
maps (the paper's equation 7).

The policy is called for every node that carries a row of the system, in parallel when the
deformer's `ConcurrencyTag` allows it: `transform()` is `const` and must be safe to call
concurrently. The deformer keeps one instance: default-constructed, or a copy of the one given to
its constructor, to `set_transform_policy()` or to `deform_mesh()` (the policy may then have
state, and must be `CopyConstructible`, or `CopyAssignable` for the setter; otherwise it need
not be copyable or assignable, see \ref LapDefRunTime). It reads the cell only through the
documented members of `Transform_cell`. The first iteration after `preprocess()` or
`reset()` does not call it (it uses `T_a = I`). A returned matrix that is not finite makes
`deform()` fail with `NON_FINITE_RESULT` (nothing is written).

<b>Scale.</b> The deformer passes every cell with its rest and current edge vectors multiplied by
one power of two (exact in floating point) that brings their largest coordinate close to 1, so
that products and squares of edge vectors neither overflow nor underflow whatever the size of
the model (1e-300 to 1e300). `T_a` must therefore not depend on a common positive scaling of the
edge vectors, as the package's policies do not (a rotation, and scales that are ratios); the
weights are passed unchanged.

The map need not be a rotation, but the fit is to the cell, not to the
Laplacian energy, so the energy is not guaranteed to decrease from one iteration to the next.

<b>Optional batch method.</b> A policy may also provide
<code>void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const</code>,
which must set `out[i]` to what `transform(cells[i])` returns, for `i < n`. The deformer detects it at
compile time and then passes the cells of its local step in groups (currently 32 cells per call,
`n` smaller for the last group of a block of rows) instead of one at a time, so that the policy can
fit several cells at once with vector instructions; without it, `transform()` is called per cell.
The same thread-safety rules apply (calls on different groups run concurrently). All the
package's policies except `Fixed_transform` have one, computed by vectorised kernels that give
the results of their `transform()` (see \ref LapDefPerformance); for them the local step goes
through an internal entry point of the same kernels instead, which takes the spokes already in
the kernels' layout (the same results, bit for bit).

\cgalRefines{DefaultConstructible}

\cgalHasModelsBegin
\cgalHasModels{CGAL::Laplacian_deformation::Fixed_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Rotation_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Similarity_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Scaled_rotation_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Principal_scaled_rotation_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Rotation_scale_rotation_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Anchored_scaled_rotation_transform}
\cgalHasModels{CGAL::Laplacian_deformation::Transform_policy_variant}
\cgalHasModelsEnd

\sa `CGAL::Laplacian_deformation::Transform_cell`

A minimal model: an isotropic scale without rotation, `T_a = s_a I` with
<code>s_a = sum c e'.e / sum c |e|^2</code> (the least-squares scale of the cell; 1 for a cell without extent).
\code
struct Scale_only_transform
{
  Eigen::Matrix3d transform(const CGAL::Laplacian_deformation::Transform_cell& cell) const
  {
    double num = 0, den = 0;
    for(std::size_t i = 0; i < cell.size(); ++i)
    {
      num += cell.weight(i) * cell.current(i).dot(cell.rest(i));
      den += cell.weight(i) * cell.rest(i).squaredNorm();
    }
    return (den > 0 ? num / den : 1.) * Eigen::Matrix3d::Identity();
  }
};
\endcode
*/
class DeformationTransformPolicy
{
public:
/// \name Operations
/// @{

  /// returns `T_a` for the cell `cell` (rest and current edge vectors, fit weights).
  Eigen::Matrix3d transform(const CGAL::Laplacian_deformation::Transform_cell& cell) const;

  /// optional: sets `out[i] = transform(cells[i])` for `i < n` (see <b>Optional batch method</b> above).
  void transform_block(const CGAL::Laplacian_deformation::Transform_cell* cells, std::size_t n,
                       Eigen::Matrix3d* out) const;

/// @}
};
