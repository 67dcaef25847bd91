// Lowering: evaluated scene items (blocks whose properties have been checked
// against the property tables) become ir::Scene entries. Owns the checks that
// involve several properties (box min <= max, light area, mesh files), the
// transforms (world_from_object, in double precision), the deduplicated
// materials table and the one-settings/camera/background rule.
#pragma once

#include <bitset>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "compiler/properties.hpp"
#include "compiler/value.hpp"
#include "language/diagnostics.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::compile {

struct EvaluatedProp {
  const PropInfo* info = nullptr;
  lang::Span name_span;
  lang::Span value_span;
  Value value;
  std::vector<EvaluatedProp> nested;  // a Block property (motion { ... })
  // A Block property: how many properties its block holds as written, those that
  // failed (left out of `nested`) and one a syntax error cut short included.
  std::uint32_t written = 0;
};

// Builds an ir::Material or ir::Texture value from a constructor's properties
// (lower_kinds.cpp: the block's kind struct, filled field by field).
// Problems only the whole block shows (a colour map's stops out of order) are
// reported to `diags` and give an error value.
// §15 `color_map { stop <at, color> … }` into `map`: false when its stops are out
// of order or none was written (both reported here), or none was read (each stop's
// error, or the block's syntax error, said already). Checked also when another
// property of the pattern is wrong (§10: independent errors).
bool color_map_of(const EvaluatedProp& p, lang::DiagnosticEngine& diags,
                  std::vector<ir::ColorStop>& map);

Value make_constructor_value(const BlockInfo& block, const std::vector<EvaluatedProp>& props,
                             lang::DiagnosticEngine& diags);

// §12: why a shape of this kind has no inside whatever its properties (a disc, a
// triangle), or ""; and the NotASolid error of a child `why` in CSG block `csg`.
std::string no_inside_of_kind(const BlockInfo& shape);
void report_no_inside(const BlockInfo& child, lang::Span child_kw, const BlockInfo& csg,
                      lang::Span csg_kw, const std::string& why, lang::DiagnosticEngine& diags);

class SceneBuilder;
struct ObjectNode;
// An object's own transform (its translate/rotate/scale in the order written) and
// the motion of its `motion { }` property (none when null).
ir::Transform object_transforms(const std::vector<EvaluatedProp>& props);
ir::Motion object_motion(const EvaluatedProp* motion);
const EvaluatedProp* find_evaluated(const std::vector<EvaluatedProp>& props, PropId id);

// What a kind's lowering hook (lower_kinds.cpp) sees: the block's keyword, its
// checked properties, the diagnostics, and the builder (for its mesh table).
struct LowerContext {
  SceneBuilder& builder;
  lang::Span keyword;
  const std::vector<EvaluatedProp>& props;
  lang::DiagnosticEngine& diags;
  // Set when the block had errors of its own (check_shape_rest): the properties
  // that failed, whose defaults stand in for them in `props`. A check that
  // involves one of them is not made (it would judge a value nobody wrote).
  const std::bitset<kPropCount>* failed = nullptr;
  const EvaluatedProp* get(PropId id) const { return find_evaluated(props, id); }
  bool judged(std::initializer_list<PropId> ids) const {
    if (failed)
      for (PropId id : ids)
        if (failed->test(static_cast<std::size_t>(id))) return false;
    return true;
  }
};

// The object-space geometry of a shape block (its kind struct, filled field by
// field, then the kind's own checks); false when an error was reported.
bool lower_shape(const BlockInfo& block, LowerContext& cx, ir::ShapeGeom& out);
// The checks of §11 that involve several properties, on a shape block whose own
// properties had errors (`failed`): §10 asks for every independent error at once,
// and `cylinder { base 0 cap 0 radius -1 }` has two. Nothing is made (a mesh's
// file is not read).
void check_shape_rest(const BlockInfo& block, SceneBuilder& builder, lang::Span keyword,
                      const std::vector<EvaluatedProp>& props,
                      const std::bitset<kPropCount>& failed, lang::DiagnosticEngine& diags);

inline constexpr std::size_t kMaxSceneObjects = 20'000'000;

class SceneBuilder {
 public:
  SceneBuilder(const lang::SourceManager& sources, lang::DiagnosticEngine& diags);

  // `keyword_span` is the block keyword; props have passed the table checks.
  void add_item(const BlockInfo& block, lang::Span keyword_span,
                const std::vector<EvaluatedProp>& props);
  void set_background(const Value& color, lang::Span span);
  // A settings, camera or background item that had errors of its own still takes
  // its place, so a second one is reported too (§10: every independent error).
  void failed_singleton(std::string_view kind, lang::Span span) { first_of_kind(kind, span); }
  // §17: the image file an `image` pattern names, relative to the file naming it;
  // false (an error reported at span, exit 3) when it is not a readable file.
  bool add_image(const std::string& file, lang::Span span, std::uint32_t& index);
  // §12-§13 (lower_objects.cpp): places an object value's tree in the scene: a CSG
  // block, an instance, or any object made where a CSG block was being evaluated.
  void add_object_tree(const std::shared_ptr<const ObjectNode>& node);
  // Reports what placing the object value `node` would report of its own shapes
  // (each shape's checks, §12's solids under merge, intersection and difference),
  // without placing anything: a value bound by `let` may never be placed, and its
  // errors are still errors (§5). A value found wrong is not placed later, so each
  // error is reported once. Mesh files are read only when a mesh is placed.
  void check_value(const std::shared_ptr<const ObjectNode>& node);
  // The checks between an item's properties (the camera's view, an area light's
  // area) on an item whose own properties had errors, leaving out those that
  // involve a failed one (`failed`); nothing is added (§10: independent errors).
  void check_item_rest(const BlockInfo& block, lang::Span kw,
                       const std::vector<EvaluatedProp>& props,
                       const std::bitset<kPropCount>& failed);

  // Settings overrides from the command line (--set, --spp, --res, --seed),
  // applied after the program ran. `value` has passed check_value.
  void override_setting(const PropInfo& prop, const Value& value);

  std::size_t object_count() const { return scene_.shapes.size(); }
  // §17: the image files named so far (known to exist), also when there were errors.
  const std::vector<ir::ImageFile>& images() const { return scene_.images; }

  // A hint that about `n` more objects follow (a loop of n iterations that makes
  // an object each time): reserves room for them at once, so a million objects are
  // written once into pages faulted in once, instead of being moved through every
  // doubling of the vector (on this VM a fresh page costs about a microsecond of
  // system time, as much as evaluating the object). Never shrinks or grows by less
  // than doubling, so a wrong hint costs only untouched address space.
  void expect_objects(std::size_t n);
  bool too_many_objects() const {
    return scene_.shapes.size() + scene_.parts.size() >= kMaxSceneObjects;
  }

  // Fills defaults (focal_distance), the file table, and returns the scene.
  ir::Scene finish();

  // Loads (once per file) the mesh `file` named at `span`; false when an error
  // was reported.
  bool load_mesh(const std::string& file, lang::Span span, std::uint32_t& index);

 private:
  ir::SourceRef ref(lang::Span span) const;
  // The last two spans ref() resolved (an object's keyword and its material's):
  // items made in a loop share them, so this spares line-table searches.
  struct RefCache {
    lang::Span span{static_cast<lang::FileId>(-1), 0, 0};
    ir::SourceRef ref;
  };
  mutable RefCache ref_cache_[2];
  mutable unsigned ref_next_ = 0;
  std::uint32_t material_index(const ir::Material& m);
  std::uint32_t default_material();
  // The material of `props`, or `inherited` when it gives none.
  std::uint32_t material_of(const std::vector<EvaluatedProp>& props, std::uint32_t inherited);
  // What an object inherits from the objects around it (lower_objects.cpp).
  struct Placement {
    ir::Transform world_from_parent;  // or the CSG object's / prototype's space
    std::uint32_t material = 0;       // the material of the nearest enclosing object with one
    ir::Motion motion;                // how the enclosing objects move the parent's space
    // The top-level object's space (a union's, an outer instance's) when the
    // objects placed are not it; null: each is its own top-level object.
    std::shared_ptr<const ir::ObjectSpace> object = nullptr;
  };
  // Places `node` into the scene's shapes, or, with `proto`, into prototype parts.
  void place(const ObjectNode& node, const Placement& at, std::vector<std::uint32_t>* proto);
  // The CSG node of `node` (a CSG child) in its CSG object's space, or -1 after errors.
  // `motion`: how the objects between it and the CSG object move the parent's
  // space, in the CSG object's space.
  std::int64_t csg_node(const ObjectNode& node, const ir::Transform& csg_from_parent,
                        const ir::Motion& motion, std::uint32_t material, const ObjectNode& csg);
  // check_value below `n`; `csg`: the merge, intersection or difference it is a
  // solid of, or null.
  // `seen`: the nodes of this value already checked, by context (0: free, 1: a
  // solid of a CSG operation), and their answers. A value of values shares its
  // nodes (a 30-line chain of doublings is 31 nodes and 2^30 paths), so each is
  // checked once per context.
  using CheckMemo = std::unordered_map<const ObjectNode*, bool>;
  bool check_tree(const ObjectNode& n, const ObjectNode* csg, CheckMemo (&seen)[2]);
  bool wrong(const ObjectNode& n) const {
    return !wrong_values_.empty() && wrong_values_.count(&n) != 0;
  }
  // The values check_value found wrong, held so that no other node takes their
  // address while the scene is built.
  std::unordered_map<const ObjectNode*, std::shared_ptr<const ObjectNode>> wrong_values_;
  std::int64_t csg_children(const ObjectNode& node, const ir::Transform& csg_from_node,
                            const ir::Motion& motion, std::uint32_t material,
                            const ObjectNode& csg);
  // The renderer walks a CSG object's tree recursively (building, bounding, inside
  // tests): merge, intersection and difference nested deeper than this are an
  // error at the object (a crash from the stack at 14 000 levels before). The
  // syntax's own limit; a `union` at the top places its children one by one and
  // does not count.
  static constexpr std::uint32_t kMaxCsgDepth = 1000;
  // Moving objects inside moving objects' values: each level's motion holds every
  // outer one (ir::Motion::nested), so N levels cost N²/2 blocks (2000 levels took
  // 1.4 GB, 9000 would take 29) and each ray's placement N steps. Past this many
  // the object is an error.
  static constexpr std::size_t kMaxNestedMotions = 100;
  bool too_many_motions(const ir::Motion& m, const ObjectNode& at);
  std::uint32_t csg_depth_ = 0;
  const ObjectNode* csg_too_deep_ = nullptr;  // the object already reported
  // §13: an `object { W }` reached through unions inside a value V that is made
  // a prototype is not copied into V's prototype: V's placements place W's own
  // prototype, so values of values of a mesh still hold one copy of the mesh.
  struct NestedInstance {
    const ObjectNode* site = nullptr;  // the `object { W }` node (its keyword)
    std::shared_ptr<const ObjectNode> value;
    ir::Transform proto_from_object;  // the site's placement in V's space
    std::uint32_t material = 0;       // the site's, or ir::kInheritMaterial
  };
  struct PrototypeEntry {
    std::int64_t id = -1;  // into Scene::prototypes; -1: no parts of its own, or errors
    bool failed = false;   // errors: nothing is placed
    std::vector<NestedInstance> nested;
  };
  // The prototype of an object value placed by `object { }`, made once per value.
  const PrototypeEntry& prototype_for(const std::shared_ptr<const ObjectNode>& value);
  // Places an instanceable value: its prototype and, by their own prototypes, the
  // instances nested in it (`keyword`: the `object` that places it).
  void place_instance(const std::shared_ptr<const ObjectNode>& value, lang::Span keyword,
                      const Placement& at);
  std::unordered_map<const ObjectNode*, PrototypeEntry> prototypes_;  // references stay valid
  std::vector<std::shared_ptr<const ObjectNode>> prototype_values_;   // keeps the keys alive
  std::vector<NestedInstance>* nesting_ = nullptr;                    // the prototype being built's
  void add_object(const BlockInfo& block, lang::Span kw, const std::vector<EvaluatedProp>& props);
  void apply_settings(const std::vector<EvaluatedProp>& props);
  void apply_camera(const std::vector<EvaluatedProp>& props);
  bool check_camera_view(const std::vector<EvaluatedProp>& props, bool with_up = true);
  bool check_light_area(const std::vector<EvaluatedProp>& props);
  bool check_light_samples(const std::vector<EvaluatedProp>& props);
  bool first_of_kind(std::string_view kind, lang::Span span);

  const lang::SourceManager& sources_;
  lang::DiagnosticEngine& diags_;
  ir::Scene scene_;
  bool focal_distance_set_ = false;
  std::unordered_map<std::string, lang::Span> singletons_;  // settings, camera, background
  // Deduplication of materials by value: an open-addressing table of (hash,
  // index into scene_.materials) with linear probing, kept at most half full.
  // The stored hash spares growing from rehashing and probing from touching
  // materials that cannot match; a million distinct materials cost 32 MiB here.
  struct MaterialSlot {
    std::uint64_t hash = 0;
    std::uint32_t index = 0;  // 0: empty; else index into scene_.materials + 1
  };
  std::vector<MaterialSlot> material_slots_;
  std::size_t material_count_ = 0;
  static std::uint64_t material_hash(const ir::Material& m);
  std::unordered_map<std::string, std::uint32_t> mesh_ids_;
  std::unordered_map<std::string, std::uint32_t> image_ids_;  // §17, by normalised path
  std::int64_t default_material_ = -1;
  // Prefaulting of the reserved room of the two big vectors (see prefault()).
  struct Prefault {
    const void* base = nullptr;  // the vector's storage when `done` was measured
    std::size_t done = 0;        // bytes from base already prefaulted
  };
  Prefault shapes_prefault_, materials_prefault_;
  template <class T>
  void prefault(const std::vector<T>& v, Prefault& pf);
};

}  // namespace snell::compile
