// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve, the deformer of a session: the representation chosen at run time
// behind a type-erased interface, the weights and the transform as run-time policies (Any_weights,
// Any_transform, named in policy_names.h), and the handle motion of a drag.
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_DEFORMER_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_DEFORMER_H

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Any_weights.h>
#include <CGAL/Laplacian_deformation/Any_transform.h>

#include "policy_names.h"
#include "tool_defaults.h"

#include <Eigen/Geometry>

#include <memory>
#include <string>

namespace Laplacian_deformation_server {

namespace LD = CGAL::Laplacian_deformation;
namespace policy_names = Laplacian_deformation_policy_names;

typedef CGAL::Simple_cartesian<double>               Kernel;
typedef Kernel::Point_3                              Point_3;
typedef CGAL::Surface_mesh<Point_3>                  Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

/// The policies a session deforms with.
struct Policy
{
  /// "edge" or "vertex"
  std::string representation = Laplacian_deformation_tool_defaults::representation();
  /// a name of policy_names::weight_policies()
  std::string weights = Laplacian_deformation_tool_defaults::weights();
  /// a name of policy_names::transform_policies() (S*R1 under the editor's name, "scaled_rotation")
  std::string transform = Laplacian_deformation_tool_defaults::editor_transform();
  /// "identity" or "rotation" (Mesh_deformer::set_start)
  std::string start = Laplacian_deformation_tool_defaults::start();
};

class Deformer_interface
{
public:
  virtual ~Deformer_interface() = default;
  virtual void insert_roi_vertex(vertex_descriptor v) = 0;
  virtual void insert_control_vertex(vertex_descriptor v) = 0;
  virtual void clear_roi_vertices() = 0;
  virtual bool preprocess() = 0;
  virtual void set_target_position(vertex_descriptor v, const Point_3& p) = 0;
  virtual LD::Deformation_result deform(unsigned int iterations, double tolerance) = 0;
  virtual void reset() = 0;
  virtual void set_start(LD::Deformation_start start) = 0;
  virtual void set_weight_policy(const LD::Any_weights& weights) = 0;
  virtual void set_transform_policy(const LD::Any_transform& transform) = 0;
  virtual const LD::Deformation_result& last_result() const = 0;
  virtual std::size_t number_of_factorizations() const = 0;
};

template <class Representation>
class Deformer_model : public Deformer_interface
{
public:
  // the editor shows no energy: the deformer computes none (a pass over the rows per iteration)
  Deformer_model(Mesh& mesh, const LD::Any_weights& weights, const LD::Any_transform& transform)
    : m_deformer(mesh, weights, transform)
  {
    m_deformer.set_energy_tracking(false);
  }
  void insert_roi_vertex(vertex_descriptor v) override { m_deformer.insert_roi_vertex(v); }
  void insert_control_vertex(vertex_descriptor v) override { m_deformer.insert_control_vertex(v); }
  void clear_roi_vertices() override { m_deformer.clear_roi_vertices(); }
  bool preprocess() override { return m_deformer.preprocess(); }
  void set_target_position(vertex_descriptor v, const Point_3& p) override { m_deformer.set_target_position(v, p); }
  LD::Deformation_result deform(unsigned int iterations, double tolerance) override
  {
    return m_deformer.deform(iterations, tolerance);
  }
  void reset() override { m_deformer.reset(); }
  void set_start(LD::Deformation_start start) override { m_deformer.set_start(start); }
  void set_weight_policy(const LD::Any_weights& weights) override { m_deformer.set_weight_policy(weights); }
  void set_transform_policy(const LD::Any_transform& transform) override { m_deformer.set_transform_policy(transform); }
  const LD::Deformation_result& last_result() const override { return m_deformer.last_result(); }
  std::size_t number_of_factorizations() const override { return m_deformer.number_of_factorizations(); }

private:
  LD::Mesh_deformer<Mesh, Representation, LD::Any_weights, LD::Any_transform> m_deformer;
};

/// A deformer for `mesh` (whose current positions become the rest positions) with the policies of `p`
/// (assumed valid; see `validate_policy`).
inline std::unique_ptr<Deformer_interface> make_deformer(Mesh& mesh, const Policy& p)
{
  const LD::Any_weights weights = policy_names::weight_policy(p.weights);
  const LD::Any_transform transform = policy_names::transform_policy(p.transform);
  std::unique_ptr<Deformer_interface> d;
  if(policy_names::representation(p.representation) == policy_names::Representation::VERTEX)
    d = std::make_unique<Deformer_model<LD::Vertex_based_representation> >(mesh, weights, transform);
  else
    d = std::make_unique<Deformer_model<LD::Edge_based_representation> >(mesh, weights, transform);
  d->set_start(p.start == "rotation" ? LD::ROTATION_START : LD::IDENTITY_START);
  return d;
}

/// The handle motion of the last drag: `p -> R (p - center) + center + translation`.
struct Drag
{
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double angle = 0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  unsigned int iterations = Laplacian_deformation_tool_defaults::iterations;

  /// the 4x4 affine matrix (Botsch08 .def).
  Eigen::Matrix4d matrix() const
  {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = r;
    m.topRightCorner<3, 1>() = translation + center - r * center;
    return m;
  }
};

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_DEFORMER_H
