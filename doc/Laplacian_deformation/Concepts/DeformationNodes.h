/*!
\ingroup PkgLaplacianDeformationConcepts
\cgalConcept

@brief The nodes of a representation on one mesh: where Laplacian coordinates are evaluated,
which nodes form each cell, and the fan triangles that geometric weights need.

The package turns a model of this concept, once per rest geometry, into flat stencils from which
everything else is computed: the node positions `x = P p` (from `combination()`), the cells
`N(a)` (from `neighbors()`), the weights (a `DeformationWeightPolicy` sees each cell and its fan
triangles through `CGAL::Laplacian_deformation::Node_cell`) and the Laplacian operator
`D = L_w P`, with `delta_a = sum_{b in N(a)} w_ab (x_a - x_b)`. The algorithm never sees the
mesh through anything else, which is why the vertex-based and the edge-based paths share all
their code.

Requirements the algorithm relies on:
- `index()` is a bijection from `nodes()` onto `[0, number_of_nodes())`;
- the coefficients of `combination(a, f)` sum to 1 (a node is a point of the mesh), so that `D`
  annihilates translations;
- `neighbors(a)` lists each neighbour once and does not contain `a`;
- both nodes of a fan triangle of `a` are in `neighbors(a)` (checked by an assertion); with
  `CGAL::Laplacian_deformation::Cotangent_weights`, each spoke `(x_a, x_b)` of an interior node
  should lie in exactly two fan triangles, on the boundary in one, and the fan should cover the
  node's neighbourhood once (its area is the node's Voronoi area). On a polygon face the
  package's models use the face's edges or vertices next to the node (\ref LapDefPolygons).

With a parallel concurrency tag (`Mesh_deformer`'s default when \tbb is found), `combination()`,
`neighbors()`, `fan_triangles()`, `incident_nodes()` and `index()` are called from several threads
at once on one model (the stencils are built in parallel): they must only read.

Nothing else is used: the package constructs a model in place from `(tm, vpm)` and never copies,
assigns or default-constructs it; it never compares, orders or hashes `node_descriptor`s (it
only passes them back to `index()`, `combination()`, `neighbors()` and `fan_triangles(`); and the
ranges are only traversed with a range-based `for`. The archetype test
(`test/Laplacian_deformation/test_archetypes.cpp`) instantiates `Mesh_deformer`, `deform_mesh()`
and `laplacian_matrix()` with a model that provides exactly this.

Models are produced by a `DeformationRepresentation`: `Representation::Nodes<TriangleMesh, VertexPointMap>`.
`CGAL::Laplacian_deformation::Mesh_deformer::nodes()` gives access to them after `preprocess()`
(for instance to relate `node_transform()` indices to nodes, or to run a BGL algorithm on `graph()`).

\cgalHasModelsBegin
\cgalHasModels{CGAL::Laplacian_deformation::Vertex_based_representation::Nodes<TriangleMesh, VertexPointMap>}
\cgalHasModels{CGAL::Laplacian_deformation::Edge_based_representation::Nodes<TriangleMesh, VertexPointMap>}
\cgalHasModelsEnd

\sa `DeformationRepresentation`

A minimal model: one node per vertex (`x_v = p_v`), the one-ring as cell, the faces around the
vertex as fan, for a mesh with an internal vertex index (such as `CGAL::Surface_mesh`):
\code
template <class TriangleMesh, class VertexPointMap>
class My_vertex_nodes
{
  const TriangleMesh* m_tm;
public:
  typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor vertex_descriptor;
  typedef vertex_descriptor node_descriptor;
  typedef TriangleMesh Node_graph;

  My_vertex_nodes(const TriangleMesh& tm, VertexPointMap) : m_tm(&tm) {}
  const Node_graph& graph() const { return *m_tm; }
  std::size_t number_of_nodes() const { return num_vertices(*m_tm); }
  auto nodes() const { return vertices(*m_tm); }
  std::size_t index(node_descriptor a) const { return get(boost::vertex_index, *m_tm, a); }
  template <class F> void combination(node_descriptor a, F&& f) const { f(a, 1.); }
  auto neighbors(node_descriptor a) const { return CGAL::vertices_around_target(a, *m_tm); }
  template <class F> void fan_triangles(node_descriptor a, F&& f) const
  {
    for(auto h : CGAL::halfedges_around_target(a, *m_tm))
      if(!is_border(h, *m_tm))
        f(target(next(h, *m_tm), *m_tm), source(h, *m_tm));   // face (a, k, l)
  }
};
\endcode
*/
class DeformationNodes
{
public:
/// \name Types
/// @{

  /// a node. Default constructible and copyable; for `Vertex_based_representation` the mesh's
  /// `vertex_descriptor`, for `Edge_based_representation` the mesh's `edge_descriptor`.
  typedef unspecified_type node_descriptor;

  /// the mesh's `boost::graph_traits<TriangleMesh>::%vertex_descriptor`.
  typedef unspecified_type vertex_descriptor;

  /// a graph whose vertices are the nodes (`boost::graph_traits<Node_graph>::%vertex_descriptor`
  /// is `node_descriptor`): the mesh itself for the vertex-based representation,
  /// `CGAL::Laplacian_deformation::Edge_midpoint_graph` for the edge-based one.
  typedef unspecified_type Node_graph;

/// @}

/// \name Creation
/// @{

  /// builds the nodes of `tm`, whose vertex positions are given by `vpm`. `tm` must outlive
  /// this object; the object must not depend on positions that change after construction
  /// (the package reads positions itself, through `combination()`).
  DeformationNodes(const TriangleMesh& tm, VertexPointMap vpm);

/// @}

/// \name Operations
/// @{

  /// the node graph.
  const Node_graph& graph() const;

  /// the number of nodes.
  std::size_t number_of_nodes() const;

  /// a range of every node (each once, in any order), usable in a range-based `for`.
  unspecified_type nodes() const;

  /// the dense index of node `a`, in `[0, number_of_nodes())`.
  std::size_t index(node_descriptor a) const;

  /// calls `f(v, c)` (`v` a `vertex_descriptor`, `c` a `double`) for each term of
  /// `x_a = sum_v c_v p_v`; the coefficients must sum to 1.
  template <class F>
  void combination(node_descriptor a, F&& f) const;

  /// a range of the neighbours `N(a)` of `a` (its cell), each once, `a` excluded.
  unspecified_type neighbors(node_descriptor a) const;

  /// calls `f(b, c)` (`b`, `c` of type `node_descriptor`, both in `neighbors(a)`) for each fan
  /// triangle `(x_a, x_b, x_c)` of `a`. The orientation of `(b, c)` does not matter.
  template <class F>
  void fan_triangles(node_descriptor a, F&& f) const;

  /// (optional) calls `f(a)` (`a` a `node_descriptor`) for each node whose combination
  /// involves the mesh vertex `v` (each once). With it, `CGAL::Laplacian_deformation::Mesh_deformer`
  /// builds the stencils, weights and operator rows of the nodes near the region of interest only
  /// (the nodes of its vertices, their neighbours, and the neighbours' neighbours for their
  /// positions), so that a small selection on a big mesh costs what the selection costs (see
  /// \ref LapDefPerformance); the neighbour relation must then be symmetric (`b` in
  /// `neighbors(a)` if and only if `a` in `neighbors(b)`). Without it the whole mesh's stencils
  /// are built. Both of the package's models provide it.
  template <class F>
  void incident_nodes(vertex_descriptor v, F&& f) const;

/// @}
};
