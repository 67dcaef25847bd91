// Lowering of object trees (§12-§13): CSG blocks, instances and the objects made
// inside them. What each construct becomes in the IR:
//   a shape          a Shape (in the scene, or a part of a CSG object or prototype)
//   union            its children, placed one by one (it keeps every surface, as
//                    POV-Ray's does); inside another CSG block, a node of the tree
//   merge, intersection, difference
//                    a Shape of kind Csg whose tree (Scene::csg_nodes) has the
//                    children as leaves (Scene::parts) in the CSG object's space
//   object { V }     a Shape of kind Instance of V's prototype, made once per value
//                    and shared by every instance of it. An `object { W }` inside V
//                    (through unions) is not copied into V's prototype: each
//                    placement of V places W's prototype too, with the two
//                    placements composed (one level of instancing in the BVH, any
//                    depth of values). Inside a CSG operation (merge, intersection,
//                    difference) W's tree is copied in, and so it is where a value
//                    moves or holds a plane outside a CSG block (the BVH instances
//                    bounded, static geometry)
// Children inherit the transform (applied after their own), the material (when
// they have none) and the motion of the objects around them. Motions compose: an
// object's motion acts after its own transforms, in its parent's space, and the
// parent's transforms and motion act after it (ir::nest_motion); a CSG leaf's
// motion is kept in its CSG object's space, so the leaf moves inside the object.
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "compiler/lower.hpp"
#include "compiler/object_value.hpp"
#include "runtime/ir/bounds.hpp"

namespace snell::compile {

using lang::DiagKind;

namespace {

ir::CsgOp op_of(const ObjectNode& n) {
  return static_cast<ir::CsgOp>(n.block->csg_op);
}

}  // namespace

void report_no_inside(const BlockInfo& child, lang::Span child_kw, const BlockInfo& csg,
                      lang::Span csg_kw, const std::string& why, lang::DiagnosticEngine& diags) {
  std::string_view csg_name = csg.name;
  diags
      .report(DiagKind::NotASolid, child_kw,
              "this " + std::string(child.name) + " cannot be part of the '" +
                  std::string(csg_name) + "': " + why)
      .note(csg_kw, "the '" + std::string(csg_name) +
                        "' is here; its objects must be solids: sphere, box, cylinder, "
                        "cone, torus, plane, closed mesh or CSG of them ('union' takes "
                        "any object)");
}

std::string no_inside_of_kind(const BlockInfo& shape) {
  if (shape.shape_kind == static_cast<int>(ir::ShapeKind::Disc)) return "a disc has no inside";
  if (shape.shape_kind == static_cast<int>(ir::ShapeKind::Triangle))
    return "a triangle has no inside";
  return "";
}

namespace {

// Why a CSG child has no inside (§12), or "" when it is a solid (a mesh is one when
// its file's triangles are closed: MeshData::closed, checked at load).
std::string no_inside(const ir::ShapeGeom& g, const ir::Scene& scene) {
  return std::visit(
      ir::Overloaded{
          [](const ir::Cylinder& c) -> std::string {
            return c.open ? "an open cylinder has no inside" : "";
          },
          [](const ir::Cone& c) -> std::string {
            return c.open ? "an open cone has no inside" : "";
          },
          [](const ir::Disc&) -> std::string { return no_inside_of_kind(*find_block("disc")); },
          [](const ir::Triangle&) -> std::string {
            return no_inside_of_kind(*find_block("triangle"));
          },
          [&](const ir::Mesh& m) -> std::string {
            if (m.mesh >= scene.meshes.size()) return "the mesh has no data";
            const ir::MeshData& d = scene.meshes[m.mesh];
            if (d.closed) return "";
            return "mesh '" + d.path + "' is not closed" +
                   (d.open_reason.empty() ? std::string() : ": it " + d.open_reason);
          },
          [](const auto&) -> std::string { return ""; }},
      g);
}

// §12: whether the shape `c` (its geometry `geom`) may be a child of the CSG
// operation `csg`; reports why not.
bool report_not_solid(const ObjectNode& c, const ir::ShapeGeom& geom, const ObjectNode& csg,
                      const ir::Scene& scene, lang::DiagnosticEngine& diags) {
  std::string why = no_inside(geom, scene);
  if (why.empty()) return true;
  report_no_inside(*c.block, c.keyword, *csg.block, csg.keyword, why, diags);
  return false;
}

// Whether an object value can be a prototype that the BVH instances: bounded and
// static (no plane outside a CSG block, nothing moves).
bool instanceable(const ObjectNode& n, bool in_csg) {
  if (find_evaluated(n.props, PropId::object_motion)) return false;
  if (n.instance()) return instanceable(*n.children[0], in_csg);
  if (n.csg()) {
    bool solid = in_csg || op_of(n) != ir::CsgOp::Union;
    for (const auto& c : n.children)
      if (!instanceable(*c, solid)) return false;
    return true;
  }
  return in_csg || n.block->shape_kind != static_cast<int>(ir::ShapeKind::Plane);
}

}  // namespace

namespace {
// While an object is checked or placed, its errors note the call it was made in.
class CallContext {
 public:
  CallContext(lang::DiagnosticEngine& diags, const ObjectNode& n)
      : diags_(diags), outer_(diags.set_call_context(n.call)) {}
  ~CallContext() { diags_.set_call_context(outer_); }
  CallContext(const CallContext&) = delete;
  CallContext& operator=(const CallContext&) = delete;

 private:
  lang::DiagnosticEngine& diags_;
  lang::Span outer_;
};

// Records the top-level object's space on `s` where it differs from s's own
// (patterns see the same space either way when it does not).
void set_object_space(ir::Shape& s, const ir::ObjectSpace* object) {
  if (!object) return;
  if (object->world_from_object.m == s.world_from_object().m &&
      ir::same_motion(object->motion, s.motion()))
    return;
  s.set_object_space(*object);
}
}  // namespace

// The outermost objects inherit "no material yet": the default material is made
// only for an object that ends up without one (so a scene's material table is the
// same whichever way its objects are written).
void SceneBuilder::add_object_tree(const std::shared_ptr<const ObjectNode>& node) {
  // Refused before anything is placed: values of values multiply, and placing
  // them until the scene's cap would take minutes and gigabytes first.
  const double room = double(kMaxSceneObjects) - double(scene_.shapes.size() + scene_.parts.size());
  if (const double n = node->leaf_count(); n > room) {
    diags_.report(DiagKind::StepBudget, node->keyword,
                  fmt::format("this {} makes {:.3g} objects, more than the scene's {} at most",
                              node->keyword_name(), n, kMaxSceneObjects));
    return;
  }
  place(*node, Placement{ir::Transform{}, ir::kInheritMaterial, {}}, nullptr);
}

namespace {
// The motion of `props`'s object placed in a space that `frame` places (in the
// world, or in a CSG object's space) and that moves by `outer`.
ir::Motion motion_in(const ir::Motion& outer, const ir::Transform& frame,
                     const std::vector<EvaluatedProp>& props) {
  const EvaluatedProp* own = find_evaluated(props, PropId::object_motion);
  return own ? ir::nest_motion(outer, frame, object_motion(own)) : outer;
}
}  // namespace

void SceneBuilder::check_value(const std::shared_ptr<const ObjectNode>& node) {
  if (!node || wrong(*node)) return;
  CheckMemo seen[2];
  if (!check_tree(*node, nullptr, seen)) wrong_values_.emplace(node.get(), node);
}

bool SceneBuilder::check_tree(const ObjectNode& n, const ObjectNode* csg, CheckMemo (&seen)[2]) {
  if (wrong(n)) return false;
  CheckMemo& memo = seen[csg ? 1 : 0];
  if (auto it = memo.find(&n); it != memo.end()) return it->second;
  CallContext call(diags_, n);
  bool ok = true;
  if (n.instance()) {
    ok = check_tree(*n.children[0], csg, seen);
  } else if (n.csg()) {
    const ObjectNode* solid_of = op_of(n) == ir::CsgOp::Union ? csg : &n;
    for (const auto& c : n.children) ok = check_tree(*c, solid_of, seen) && ok;
  } else if (n.block->shape_kind != static_cast<int>(ir::ShapeKind::Mesh)) {
    ir::ShapeGeom geom;
    LowerContext cx{*this, n.keyword, n.props, diags_};
    ok = lower_shape(*n.block, cx, geom) &&
         (!csg || report_not_solid(n, geom, *csg, scene_, diags_));
  }
  memo.emplace(&n, ok);
  return ok;
}

void SceneBuilder::place(const ObjectNode& n, const Placement& at,
                         std::vector<std::uint32_t>* proto) {
  if (wrong(n)) return;  // check_value reported it
  CallContext call(diags_, n);
  Placement inner{at.world_from_parent * object_transforms(n.props),
                  material_of(n.props, at.material),
                  motion_in(at.motion, at.world_from_parent, n.props), at.object};
  if (too_many_motions(inner.motion, n)) return;
  // An object that moves inside its top-level object (a union's child) carries
  // that object's space along, as a moving CSG leaf does (§15: the pattern moves
  // with the object's motion): the space's motion becomes this object's whole
  // motion, which is the space's own (the same as at.motion, kept so at every
  // moving level) nested with this one.
  if (inner.object && find_evaluated(n.props, PropId::object_motion))
    inner.object = std::make_shared<const ir::ObjectSpace>(
        ir::ObjectSpace{inner.object->world_from_object, inner.motion});
  // In the scene (not a prototype) an object without a material has the default.
  auto settle = [&] {
    if (!proto && inner.material == ir::kInheritMaterial) inner.material = default_material();
  };
  auto add = [&](ir::ShapeGeom geom) {
    settle();
    std::vector<ir::Shape>& list = proto ? scene_.parts : scene_.shapes;
    if (proto) proto->push_back(static_cast<std::uint32_t>(list.size()));
    ir::Shape& s = list.emplace_back();
    s.geom = std::move(geom);
    s.material = inner.material;
    s.set_world_from_object(inner.world_from_parent);
    s.set_motion(inner.motion);
    if (!proto) set_object_space(s, inner.object.get());
    s.src = ref(n.keyword);
  };
  if (n.instance()) {
    const std::shared_ptr<const ObjectNode>& value = n.children[0];
    if (instanceable(*value, false)) {
      if (!proto) {
        place_instance(value, n.keyword, inner);
        return;
      }
      if (nesting_) {  // held by reference in the prototype being built
        nesting_->push_back({&n, value, inner.world_from_parent, inner.material});
        return;
      }
    }
    place(*value, inner, proto);
    return;
  }
  if (n.csg()) {
    if (op_of(n) == ir::CsgOp::Union) {
      // Its children go into the scene one by one; §15's `space "object"` is still
      // the whole union's (in a prototype, the instance's: no record needed).
      if (!proto && !inner.object)
        inner.object = std::make_shared<const ir::ObjectSpace>(
            ir::ObjectSpace{inner.world_from_parent, inner.motion});
      for (const auto& c : n.children) place(*c, inner, proto);
      return;
    }
    settle();
    std::int64_t root = csg_children(n, ir::Transform{}, ir::Motion{}, inner.material, n);
    if (root >= 0) add(ir::Csg{static_cast<std::uint32_t>(root)});
    return;
  }
  ir::ShapeGeom geom;
  LowerContext cx{*this, n.keyword, n.props, diags_};
  if (lower_shape(*n.block, cx, geom)) add(std::move(geom));
}

bool SceneBuilder::too_many_motions(const ir::Motion& m, const ObjectNode& at) {
  if (m.nested.size() <= kMaxNestedMotions) return false;
  // Only the level that crosses the limit gets here: its callers stop there, so the
  // deeper ones are never reached.
  diags_.report(DiagKind::NestingTooDeep, at.keyword,
                "moving objects nest more than " + std::to_string(kMaxNestedMotions) +
                    " deep here (a 'motion' on an object inside a moving object's value "
                    "adds a level)");
  return true;
}

std::int64_t SceneBuilder::csg_children(const ObjectNode& n, const ir::Transform& csg_from_node,
                                        const ir::Motion& motion, std::uint32_t material,
                                        const ObjectNode& csg) {
  struct Level {
    std::uint32_t& depth;
    explicit Level(std::uint32_t& d) : depth(++d) {}
    ~Level() { --depth; }
  } level(csg_depth_);
  if (csg_depth_ > kMaxCsgDepth) {
    if (csg_too_deep_ != &csg)
      diags_.report(DiagKind::NestingTooDeep, csg.keyword,
                    "merge, intersection and difference nest more than " +
                        std::to_string(kMaxCsgDepth) +
                        " levels deep in this object (values placed with 'object' count)");
    csg_too_deep_ = &csg;
    return -1;
  }
  ir::CsgNode node;
  node.op = op_of(n);
  bool ok = true;
  for (const auto& c : n.children) {
    std::int64_t k = csg_node(*c, csg_from_node, motion, material, csg);
    if (k < 0) {
      ok = false;
      continue;
    }
    node.children.push_back(static_cast<std::uint32_t>(k));
  }
  if (!ok) return -1;
  scene_.csg_nodes.push_back(std::move(node));
  return static_cast<std::int64_t>(scene_.csg_nodes.size() - 1);
}

std::int64_t SceneBuilder::csg_node(const ObjectNode& c, const ir::Transform& csg_from_parent,
                                    const ir::Motion& motion, std::uint32_t material,
                                    const ObjectNode& csg) {
  if (wrong(c)) return -1;  // check_value reported it
  CallContext call(diags_, c);
  ir::Transform xf = csg_from_parent * object_transforms(c.props);
  ir::Motion moves = motion_in(motion, csg_from_parent, c.props);
  if (too_many_motions(moves, c)) return -1;
  std::uint32_t mat = material_of(c.props, material);
  if (c.instance()) return csg_node(*c.children[0], xf, moves, mat, csg);
  if (c.csg()) return csg_children(c, xf, moves, mat, csg);
  ir::ShapeGeom geom;
  LowerContext cx{*this, c.keyword, c.props, diags_};
  if (!lower_shape(*c.block, cx, geom)) return -1;
  if (!report_not_solid(c, geom, csg, scene_, diags_)) return -1;
  ir::Shape& s = scene_.parts.emplace_back();
  s.geom = std::move(geom);
  s.material = mat;
  s.set_world_from_object(xf);
  s.set_motion(std::move(moves));
  s.src = ref(c.keyword);
  ir::CsgNode leaf;
  leaf.part = static_cast<std::uint32_t>(scene_.parts.size() - 1);
  scene_.csg_nodes.push_back(std::move(leaf));
  return static_cast<std::int64_t>(scene_.csg_nodes.size() - 1);
}

const SceneBuilder::PrototypeEntry& SceneBuilder::prototype_for(
    const std::shared_ptr<const ObjectNode>& value) {
  if (auto it = prototypes_.find(value.get()); it != prototypes_.end()) return it->second;
  PrototypeEntry entry;
  ir::Prototype p;
  p.src = ref(value->keyword);
  std::size_t errors = diags_.error_count();
  std::vector<NestedInstance>* outer = nesting_;
  nesting_ = &entry.nested;
  place(*value, Placement{ir::Transform{}, ir::kInheritMaterial, {}}, &p.parts);
  nesting_ = outer;
  entry.failed = diags_.error_count() != errors;
  if (!entry.failed && !p.parts.empty()) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t i : p.parts)
      ir::world_hull_points(scene_.parts[i], scene_, [&](ir::Vec3 q) {
        for (int k = 0; k < 3; ++k) lo[k] = std::fmin(lo[k], q[k]), hi[k] = std::fmax(hi[k], q[k]);
      });
    if (lo[0] <= hi[0]) p.lo = {lo[0], lo[1], lo[2]}, p.hi = {hi[0], hi[1], hi[2]};
    entry.id = static_cast<std::int64_t>(scene_.prototypes.size());
    scene_.prototypes.push_back(std::move(p));
  }
  prototype_values_.push_back(value);
  return prototypes_.emplace(value.get(), std::move(entry)).first->second;
}

void SceneBuilder::place_instance(const std::shared_ptr<const ObjectNode>& value,
                                  lang::Span keyword, const Placement& at) {
  const PrototypeEntry& e = prototype_for(value);
  if (e.failed) return;
  if (e.id >= 0) {
    ir::Shape& s = scene_.shapes.emplace_back();
    s.geom = ir::Instance{static_cast<std::uint32_t>(e.id)};
    // An instance without a material has the default, which its parts without
    // one take (as they would copied into the scene).
    s.material = at.material == ir::kInheritMaterial ? default_material() : at.material;
    s.set_world_from_object(at.world_from_parent);
    s.set_motion(at.motion);
    // §15 space "object": the value's top object placed with its own transforms
    // too (a box's translate, a union's), as the same objects written out have it
    // (§13: the instance's transforms come after the value's own). It was the
    // instance's frame alone, so a value `box { ... translate <0.5, 0, 0> }` put
    // its object-space gradient half a unit off, and a zero motion on a leaf
    // (which copies the value in) moved it back.
    const ir::ObjectSpace own{at.world_from_parent * object_transforms(value->props), at.motion};
    set_object_space(s, at.object ? at.object.get() : &own);
    s.src = ref(keyword);
  }
  // The value's own instances are placed beside it, in its space (§15).
  std::shared_ptr<const ir::ObjectSpace> object = at.object;
  if (!object && !e.nested.empty())
    object = std::make_shared<const ir::ObjectSpace>(
        ir::ObjectSpace{at.world_from_parent * object_transforms(value->props), at.motion});
  for (const NestedInstance& k : e.nested)
    place_instance(k.value, k.site->keyword,
                   Placement{at.world_from_parent * k.proto_from_object,
                             k.material == ir::kInheritMaterial ? at.material : k.material,
                             at.motion, object});
}

}  // namespace snell::compile
