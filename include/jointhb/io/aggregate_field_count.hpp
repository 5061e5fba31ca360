#pragma once
// The number of members of an aggregate struct, portable C++20 (no sizeof, no compiler builtins),
// for compile-time checks that a serialiser (io/stage_cache.cpp) still covers every member:
//   static_assert(aggregate_field_count<PreloadStep>() == 7, "... serialise it ...");
//
// The count is the largest N for which T{placeholder × N} is well-formed. The placeholder converts
// to any type through a templated conversion operator, so each initializer initialises one whole
// member, whatever its type (std::string, Eigen matrices, std::vector<bool>, a class without a
// default constructor, a nested struct). That conversion is also what keeps a nested aggregate at
// one member: brace elision ([dcl.init.aggr]) is only tried when the initializer cannot convert
// to the member's type, and the placeholder always can. Fewer initializers than members is
// well-formed only when the remaining members can be value-initialised, so the search goes down
// from an upper bound instead of stopping at the first failure.
//
// Limits: a C array member counts as its elements (no conversion to an array type exists, so
// brace elision applies); base classes count as one member each; a member whose type is
// constructible from anything (std::any, a type with an unconstrained converting constructor
// template) can make the conversion ambiguous and the count too small. None of these occur in the
// serialised types; the unit test (stage_cache_test.cpp) checks the cases that do.

#include <cstddef>
#include <type_traits>
#include <utility>

namespace jointhb::io::detail {

/// Converts to anything; only ever used in unevaluated operands, hence no definition.
struct AnyMember {
  template <class T>
  operator T() const;  // NOLINT(google-explicit-constructor): implicit by design
};

template <class T, std::size_t... I>
constexpr bool brace_initializable_with(std::index_sequence<I...>) {
  return requires { T{(static_cast<void>(I), AnyMember{})...}; };
}

/// Above any serialised struct's member count; raise it for a larger struct.
inline constexpr std::size_t max_aggregate_fields = 48;

template <class T, std::size_t N>
constexpr std::size_t largest_brace_initializable() {
  if constexpr (brace_initializable_with<T>(std::make_index_sequence<N>{}))
    return N;
  else if constexpr (N == 0)
    return 0;
  else
    return largest_brace_initializable<T, N - 1>();
}

/// The number of members of the aggregate T (see the file comment for what counts as one).
template <class T>
constexpr std::size_t aggregate_field_count() {
  static_assert(std::is_aggregate_v<T>,
                "aggregate_field_count: T is not an aggregate (constructors, private members, virtual functions)");
  constexpr std::size_t n = largest_brace_initializable<T, max_aggregate_fields>();
  static_assert(n < max_aggregate_fields, "aggregate_field_count: raise max_aggregate_fields");
  return n;
}

}  // namespace jointhb::io::detail
