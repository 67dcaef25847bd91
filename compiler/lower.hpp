// Lowering: evaluated scene items (blocks whose properties have been checked
// against the property tables) become ir::Scene entries. Owns the checks that
// involve several properties (box min <= max, light area, mesh files), the
// transforms (world_from_object, in double precision), the deduplicated
// materials table and the one-settings/camera/background rule.
#pragma once

#include <cstdint>
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
};

// Builds an ir::Material or ir::Texture value from a constructor's properties.
Value make_constructor_value(const BlockInfo& block, const std::vector<EvaluatedProp>& props);

inline constexpr std::size_t kMaxSceneObjects = 20'000'000;

class SceneBuilder {
 public:
  SceneBuilder(const lang::SourceManager& sources, lang::DiagnosticEngine& diags);

  // `keyword_span` is the block keyword; props have passed the table checks.
  void add_item(const BlockInfo& block, lang::Span keyword_span,
                const std::vector<EvaluatedProp>& props);
  void set_background(const Value& color, lang::Span span);

  // Settings overrides from the command line (--set, --spp, --res, --seed),
  // applied after the program ran. `value` has passed check_value.
  void override_setting(const PropInfo& prop, const Value& value);

  std::size_t object_count() const { return scene_.shapes.size(); }
  bool too_many_objects() const { return scene_.shapes.size() >= kMaxSceneObjects; }

  // Fills defaults (focal_distance), the file table, and returns the scene.
  ir::Scene finish();

 private:
  ir::SourceRef ref(lang::Span span) const;
  std::uint32_t material_index(const ir::Material& m);
  void add_object(const BlockInfo& block, lang::Span kw, const std::vector<EvaluatedProp>& props);
  void apply_settings(const std::vector<EvaluatedProp>& props);
  void apply_camera(const std::vector<EvaluatedProp>& props);
  bool load_mesh(const std::string& file, lang::Span span, std::uint32_t& index);
  bool first_of_kind(std::string_view kind, lang::Span span);

  const lang::SourceManager& sources_;
  lang::DiagnosticEngine& diags_;
  ir::Scene scene_;
  bool focal_distance_set_ = false;
  std::unordered_map<std::string, lang::Span> singletons_;  // settings, camera, background
  // Indices into scene_.materials, hashed and compared by value: deduplication
  // without a second copy of every material.
  struct MaterialHash {
    const std::vector<ir::Material>* table;
    std::size_t operator()(std::uint32_t i) const;
  };
  struct MaterialEq {
    const std::vector<ir::Material>* table;
    bool operator()(std::uint32_t a, std::uint32_t b) const { return (*table)[a].same_as((*table)[b]); }
  };
  std::unordered_set<std::uint32_t, MaterialHash, MaterialEq> material_ids_{
      64, MaterialHash{&scene_.materials}, MaterialEq{&scene_.materials}};
  std::unordered_map<std::string, std::uint32_t> mesh_ids_;
  std::int64_t default_material_ = -1;
};

}  // namespace snell::compile
