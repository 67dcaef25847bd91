// §13: object values. An object block evaluated (its properties checked, a CSG
// block's statements run) is a tree of ObjectNodes, shared by every variable and
// call result that holds it. Nothing is in the scene until a tree is placed: as a
// statement, as a child of a CSG block, or by `object { EXPR }`; the scene builder
// then lowers it (lower_objects.cpp), sharing one copy of the geometry among the
// instances of one value.
#pragma once

#include <memory>
#include <vector>

#include "compiler/lower.hpp"
#include "compiler/properties.hpp"
#include "language/source.hpp"

namespace snell::compile {

struct ObjectNode {
  const BlockInfo* block = nullptr;  // a shape or CSG block; null: an instance
  lang::Span keyword;
  // The outermost function call it was made in (empty: none), noted on the errors
  // that placing it finds (its shape's checks, §12's solids), as on the others.
  lang::Span call;
  std::vector<EvaluatedProp> props;  // checked: the kind's own and the object ones
  // A CSG block's objects in the order made; an instance: the value it places.
  std::vector<std::shared_ptr<const ObjectNode>> children;
  // How many shapes, parts and instances placing it can make at most (its leaves,
  // through shared values); counted once, when first asked (leaf_count).
  mutable double expanded = 0;
  // That count: a value of two copies of a value of two copies... is 2^40 after
  // forty lines, found in forty steps.
  double leaf_count() const {
    if (children.empty()) return 1;
    if (expanded == 0)
      for (const auto& c : children) expanded += c->leaf_count();
    return expanded;
  }
  bool instance() const { return block == nullptr; }
  bool csg() const { return block && block->csg_op >= 0; }
  std::string_view keyword_name() const { return block ? block->name : "object"; }
};

}  // namespace snell::compile
