// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_POLICY_VARIANT_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_POLICY_VARIANT_H

#include <CGAL/Laplacian_deformation/Fixed_transform.h>

#include <cstddef>
#include <type_traits>
#include <utility>
#include <variant>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// The base of the run-time policies (Weight_policy_variant, Transform_policy_variant): a policy
// chosen at run time among `Policies...`, held by value in a std::variant. The package's loops
// over cells call visit_policy() once per call, outside the loop, so that the loop itself calls
// the concrete policy (inlined, no dispatch per cell).
struct Policy_variant_tag {};

template <class... Policies>
class Policy_variant : public Policy_variant_tag
{
public:
  typedef std::variant<Policies...> Variant;

  // the first alternative, default-constructed
  Policy_variant() = default;
  // one of the alternatives (implicit, as std::variant's)
  template <class Policy, class = std::enable_if_t<(std::is_same<Policy, Policies>::value || ...)> >
  Policy_variant(const Policy& policy) : m_policy(policy) {}

  template <class F>
  decltype(auto) visit(F&& f) const { return std::visit(std::forward<F>(f), m_policy); }
  std::size_t index() const { return m_policy.index(); }
  template <class Policy>
  bool holds() const { return std::holds_alternative<Policy>(m_policy); }
  template <class Policy>
  const Policy* get_if() const { return std::get_if<Policy>(&m_policy); }
  const Variant& variant() const { return m_policy; }

private:
  Variant m_policy;
};

template <class Policy>
struct is_policy_variant : std::is_base_of<Policy_variant_tag, Policy> {};

// f(concrete policy): the alternative held by a run-time policy, or `policy` itself
template <class Policy, class F>
decltype(auto) visit_policy(const Policy& policy, F&& f)
{
  if constexpr(is_policy_variant<Policy>::value)
    return policy.visit(std::forward<F>(f));
  else
    return std::forward<F>(f)(policy);
}

// whether a transform policy fits transforms (the start applies to it): every policy but
// Fixed_transform (T = I), also when a run-time policy holds it
template <class TransformPolicy>
bool fits_transform(const TransformPolicy& policy)
{
  if constexpr(is_policy_variant<TransformPolicy>::value)
    return policy.visit([](const auto& p) { return fits_transform(p); });
  else
    return !std::is_same<TransformPolicy, Fixed_transform>::value;
}

// for the constructors of Mesh_deformer: a policy built by its default constructor (no copy, so
// that non-copyable policies work) or copied from an instance
struct Default_policy {};
template <class Policy>
Policy make_policy(Default_policy) { return Policy(); }
template <class Policy>
Policy make_policy(const Policy& policy) { return policy; }

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_POLICY_VARIANT_H
