// The number of members of an aggregate, for tables that must name every member of a
// struct (scene/material.h kMaterialParams): T{a, b, ...} compiles with at most one
// initialiser per member, and a value convertible to anything initialises any member.
#pragma once

#include <cstddef>

namespace whitted {
namespace aggregate_detail {

struct AnyMember {
  template <typename T>
  operator T() const;  // never defined: only named in unevaluated operands
};

template <typename T, typename... Initialisers>
constexpr size_t member_count() {
  if constexpr (requires { T{Initialisers{}..., AnyMember{}}; }) {
    return member_count<T, Initialisers..., AnyMember>();
  } else {
    return sizeof...(Initialisers);
  }
}

}  // namespace aggregate_detail

// The members of aggregate T (a struct without bases or array members).
template <typename T>
constexpr size_t aggregate_member_count() {
  return aggregate_detail::member_count<T>();
}

}  // namespace whitted
