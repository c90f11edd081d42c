#pragma once

// Exhaustive std::visit over a closed set of types (materials, lights):
//
//   std::visit(Overloaded{
//       [](const LambertMaterial& m) { ... },
//       [](const OneOf<MirrorMaterial, DielectricMaterial> auto&) { return Rgb(); },
//   }, material);
//
// OneOf lets one lambda handle several named kinds alike without becoming a catch-all: a
// kind no lambda names still fails to compile ("std::visit requires the visitor to be
// exhaustive"). Never write `const auto&` alone in such a visitor.

#include <concepts>

namespace farm {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

template <class T, class... Kinds>
concept OneOf = (std::same_as<T, Kinds> || ...);

}  // namespace farm
