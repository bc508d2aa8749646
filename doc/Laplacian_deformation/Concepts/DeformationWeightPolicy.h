/*!
\ingroup PkgLaplacianDeformationConcepts
\cgalConcept

@brief A weight policy gives the weights `w_ab` of the spokes of one node's rest cell.

The Laplacian coordinate of node `a` is `delta_a = sum_{b in N(a)} w_ab (x_a - x_b)`. The
algorithm calls the policy once per node, on the rest geometry, when it builds the Laplacian
operator (the first `preprocess()`, and the first one after `overwrite_initial_geometry()`), in
parallel when the deformer's `ConcurrencyTag` allows it: `weights()` is `const` and must be safe
to call concurrently (with a different output vector per thread); moving targets or changing the region of interest never calls it again. The same weights,
clamped to `c_ab = max(w_ab, 0)`, weight the spokes when a `DeformationTransformPolicy` fits
the node transforms, so the policy shapes both the linear system and the local fits.

The policy sees the cell through `CGAL::Laplacian_deformation::Node_cell`: the node position,
its neighbours' positions and its fan triangles (as pairs of local neighbour indices), as points
of the kernel `GeomTraits` deduced from the vertex point map.
The weights must be finite; they may be negative (as cotangent weights across obtuse angles).
`Mesh_deformer` keeps one instance: default-constructed, or a copy of the one given to its
constructor, to `set_weight_policy()` or to `deform_mesh()`; `laplacian_matrix()` uses the
instance it is given. A policy may therefore have state (it must then be `CopyConstructible`, or
`CopyAssignable` for the setter; otherwise it need not be copyable or assignable, see
\ref LapDefRunTime). It only reads the cell through the documented members of `Node_cell`.

\cgalRefines{DefaultConstructible}

\cgalHasModelsBegin
\cgalHasModels{CGAL::Laplacian_deformation::Uniform_weights}
\cgalHasModels{CGAL::Laplacian_deformation::Cotangent_weights}
\cgalHasModels{CGAL::Laplacian_deformation::Weight_policy_variant}
\cgalHasModelsEnd

\sa `DeformationNodes`
\sa `CGAL::Laplacian_deformation::Node_cell`

A minimal model: inverse-distance weights, normalised to sum to one.
\code
struct Inverse_distance_weights
{
  template <class GeomTraits>
  void weights(const CGAL::Laplacian_deformation::Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    w.assign(cell.number_of_neighbors(), 0.);
    double sum = 0;
    for(std::size_t i = 0; i < w.size(); ++i)
      sum += w[i] = 1. / (std::sqrt(CGAL::to_double(CGAL::squared_distance(cell.center(), cell.neighbor(i)))) + 1e-12);
    for(double& x : w)
      x /= sum;
  }
};
\endcode
*/
class DeformationWeightPolicy
{
public:
/// \name Operations
/// @{

  /*!
  fills `w` with the weights of the spokes of `cell`: after the call `w.size()` is
  `cell.number_of_neighbors()` and `w[i]` is the weight of the spoke from `cell.center()` to
  `cell.neighbor(i)`. The content of `w` on entry is unspecified (the vector is reused between
  nodes). With a parallel `ConcurrencyTag` (the default of `Mesh_deformer` and `deform_mesh()`,
  when \tbb is found) it is called from several threads at once, on one policy object: it must
  not modify shared state (a `const` member function without mutable members is enough; each
  thread has its own `w`).

  \tparam GeomTraits a model of `Kernel`
  */
  template <class GeomTraits>
  void weights(const CGAL::Laplacian_deformation::Node_cell<GeomTraits>& cell, std::vector<double>& w) const;

/// @}
};
