// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// The one catalogue of the policy names of the tools (not part of the package's API): the
// laplacian_deform command line (--representation, --weights, --transform), the editor's JSON API
// (laplacian_deform --serve, /api/policy) and the comparison harness (compare_deformations) all
// resolve their names here, to the run-time policies Any_weights and Any_transform, so that
// each tool instantiates Mesh_deformer once per representation and solver.

#ifndef LAPLACIAN_DEFORMATION_POLICY_NAMES_H
#define LAPLACIAN_DEFORMATION_POLICY_NAMES_H

#include <CGAL/Laplacian_deformation/Any_transform.h>
#include <CGAL/Laplacian_deformation/Any_weights.h>

#include <array>
#include <string>

namespace Laplacian_deformation_policy_names {

namespace LD = CGAL::Laplacian_deformation;

/// A policy by name: the canonical name, another accepted name (or null), a label for humans.
template <class Policy>
struct Named_policy
{
  const char* name;
  const char* alias;
  const char* label;
  Policy policy;
};

/// the representations (a type of Mesh_deformer, so the tools dispatch on it: `Representation`)
enum class Representation { VERTEX, EDGE };

/// every representation, in the order of the tools' help
inline const std::array<Named_policy<Representation>, 2>& representations()
{
  static const std::array<Named_policy<Representation>, 2> table = {{
      {"edge", nullptr, "edge-based", Representation::EDGE},
      {"vertex", nullptr, "vertex-based", Representation::VERTEX}}};
  return table;
}

/// every weight policy: the first is the library's default
inline const std::array<Named_policy<LD::Any_weights>, 2>& weight_policies()
{
  static const std::array<Named_policy<LD::Any_weights>, 2> table = {{
      {"cotangent", nullptr, "cotangent", LD::Cotangent_weights()},
      {"uniform", nullptr, "uniform", LD::Uniform_weights()}}};
  return table;
}

/// every transform policy: the first is the library's default (S*R1, "scaled_rotation" in the editor)
inline const std::array<Named_policy<LD::Any_transform>, 7>& transform_policies()
{
  static const std::array<Named_policy<LD::Any_transform>, 7> table = {{
      {"sr1", "scaled_rotation", "S*R1", LD::Scaled_rotation_transform()},
      {"fixed", nullptr, "fixed (T = I)", LD::Fixed_transform()},
      {"rotation", nullptr, "rotation", LD::Rotation_transform()},
      {"similarity", nullptr, "similarity", LD::Similarity_transform()},
      {"principal", nullptr, "principal-axes S*R1", LD::Principal_scaled_rotation_transform()},
      {"rsr", nullptr, "R2*S*R1", LD::Rotation_scale_rotation_transform()},
      {"anchored", nullptr, "anchored S*R1", LD::Anchored_scaled_rotation_transform()}}};
  return table;
}

/// the entry of `table` named `name` (its canonical name or its alias), if any
template <class Table>
const typename Table::value_type* find(const Table& table, const std::string& name)
{
  for(const auto& entry : table)
    if(name == entry.name || (entry.alias != nullptr && name == entry.alias))
      return &entry;
  return nullptr;
}

/// the canonical names of `table` as "a, b or c", each quoted with `quote`; with `aliases`,
/// "a (or a2), b or c"
template <class Table>
std::string name_list(const Table& table, const std::string& quote = "", bool aliases = false)
{
  std::string list;
  for(std::size_t i = 0; i < table.size(); ++i)
  {
    list += (i == 0 ? "" : i + 1 == table.size() ? " or " : ", ") + quote + table[i].name + quote;
    if(aliases && table[i].alias != nullptr)
      list += " (or " + quote + table[i].alias + quote + ")";
  }
  return list;
}

/// the canonical names of `table` as "a|b|c"
template <class Table>
std::string name_choices(const Table& table)
{
  std::string list;
  for(std::size_t i = 0; i < table.size(); ++i)
    list += (i == 0 ? "" : "|") + std::string(table[i].name);
  return list;
}

/// the policies named `name` (for valid names; the defaults otherwise)
inline Representation representation(const std::string& name)
{
  const auto* e = find(representations(), name);
  return e ? e->policy : Representation::EDGE;
}
inline LD::Any_weights weight_policy(const std::string& name)
{
  const auto* e = find(weight_policies(), name);
  return e ? e->policy : LD::Any_weights();
}
inline LD::Any_transform transform_policy(const std::string& name)
{
  const auto* e = find(transform_policies(), name);
  return e ? e->policy : LD::Any_transform();
}

} // namespace Laplacian_deformation_policy_names

#endif // LAPLACIAN_DEFORMATION_POLICY_NAMES_H
