/*!
\ingroup PkgLaplacianDeformationConcepts
\cgalConcept

@brief A representation decides which points of a mesh carry Laplacian coordinates.

The deformation algorithm is written once, against nodes: points `x_a` that are fixed linear
combinations of vertex positions, each with a cell (its neighbours `N(a)`) and a fan of
triangles around it. A representation is the factory of these nodes: for a mesh type and a
vertex point map type, its nested class template `Nodes` is a model of `DeformationNodes`.
`CGAL::Laplacian_deformation::Mesh_deformer`, `CGAL::Laplacian_deformation::deform_mesh()` and
`CGAL::Laplacian_deformation::laplacian_matrix()` only name the type
`Representation::Nodes<TriangleMesh, VertexPointMap>` and construct it from the mesh and its
point map, so the representation itself is a stateless tag: it is never default-constructed nor
copied by the package, and an instance passed to `laplacian_matrix()` or `deform_mesh()` only
selects the type.

This is the one axis along which the vertex-based and the edge-based methods differ: weights,
transforms, constraints and the solve are shared.

\cgalHasModelsBegin
\cgalHasModels{CGAL::Laplacian_deformation::Vertex_based_representation}
\cgalHasModels{CGAL::Laplacian_deformation::Edge_based_representation}
\cgalHasModelsEnd

\sa `DeformationNodes`

A minimal model: the vertex-based representation, with the `My_vertex_nodes` class template
shown in `DeformationNodes` as its nodes (a nested class template works as well as an alias).
\code
struct My_vertex_representation
{
  template <class TriangleMesh, class VertexPointMap>
  using Nodes = My_vertex_nodes<TriangleMesh, VertexPointMap>;   // a model of DeformationNodes
};

// the deformer only needs the type
typedef CGAL::Laplacian_deformation::Mesh_deformer<Mesh, My_vertex_representation> Deformer;
\endcode
*/
class DeformationRepresentation
{
public:
/// \name Types
/// @{

  /*!
  the nodes of this representation on a mesh of type `TriangleMesh` (a model of `FaceGraph`;
  the package's representations accept polygon faces, see \ref LapDefPolygons) whose points are
  given by `VertexPointMap` (a readable property map from the mesh's vertices to points of a
  \cgal kernel). It is a model of `DeformationNodes`.
  */
  template <class TriangleMesh, class VertexPointMap>
  using Nodes = unspecified_type;

/// @}
};
