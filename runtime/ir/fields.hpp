// Field lists: each IR kind struct names its fields once, in a static `fields()`
// (name, member pointer) tuple, and the dump, the hash that deduplicates
// materials and the finiteness checks are written once over any such list
// instead of once per kind. The order is the dump's order.
#pragma once

#include <tuple>
#include <utility>
#include <variant>

namespace snell::ir {

template <class S, class T>
struct Field {
  const char* name;
  T S::*ptr;
};
template <class S, class T>
constexpr Field<S, T> field(const char* name, T S::*ptr) {
  return {name, ptr};
}

// f(name, value) for each field of `s`, in order (value is const when s is).
template <class S, class F>
void for_each_field(S& s, F&& f) {
  std::apply([&](auto... fl) { (f(fl.name, s.*(fl.ptr)), ...); }, std::remove_const_t<S>::fields());
}

// The language's name of a kind struct: KindName<Sphere>::value is "sphere"
// (specialised from kinds.def rows with SNELL_KIND_NAME).
template <class T>
struct KindName;
#define SNELL_KIND_NAME(name, Type)             \
  template <>                                   \
  struct KindName<Type> {                       \
    static constexpr const char* value = #name; \
  };

// std::visit(Overloaded{[](const A&) {...}, [](const B&) {...}}, v): one lambda
// per kind; a kind without one is a compile error, never a silent default.
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

// variant_of<A, B, ..., ListEnd>: std::variant<A, B, ...>. kinds.def rows expand
// to "Type," each, and ListEnd closes the list.
struct ListEnd {};
namespace detail {
template <class Acc, class... Ts>
struct StripEnd;
template <class... Acc>
struct StripEnd<std::variant<Acc...>, ListEnd> {
  using type = std::variant<Acc...>;
};
template <class... Acc, class T, class... Ts>
struct StripEnd<std::variant<Acc...>, T, Ts...> {
  using type = typename StripEnd<std::variant<Acc..., T>, Ts...>::type;
};
}  // namespace detail
template <class... Ts>
using variant_of = typename detail::StripEnd<std::variant<>, Ts...>::type;

}  // namespace snell::ir
