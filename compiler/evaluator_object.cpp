// §12-§13: object blocks as values, CSG blocks' bodies, and `object { EXPR }`.
// Evaluating a block makes an ObjectNode (object_value.hpp); making one as a
// statement places it: into the CSG block being evaluated (collectors_), or, at the
// outermost level, into the scene through the builder.
#include <fmt/format.h>

#include <bitset>

#include "compiler/evaluator.hpp"
#include "compiler/povray_forms.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Expr;
using lang::Span;

bool Evaluator::inside_group_error(std::string_view what, Span at) {
  if (collectors_.empty()) return false;
  const Collector& c = collectors_.back();
  error(DiagKind::NotInsideCsg, at,
        "'" + std::string(what) + "' cannot be inside a '" + std::string(c.block->name) +
            "' block: a CSG block holds objects only")
      .note(c.keyword, "the '" + std::string(c.block->name) + "' block is here");
  return true;
}

void Evaluator::emit(std::shared_ptr<const ObjectNode> node) {
  if (!collectors_.empty()) {
    collectors_.back().children->push_back(std::move(node));
    return;
  }
  // Placing costs a step per object it makes, checked before anything is made:
  // values of values multiply (each line can double them), so a few steps of
  // evaluation could make 16 M objects, 19 s and 6 GB, under any budget. A
  // placement past the budget is refused alone; evaluation goes on.
  if (aborted_) return;
  const double n = node->leaf_count();
  if (double(steps_) + n > double(step_budget_)) {
    error(DiagKind::StepBudget, node->keyword,
          fmt::format("placing this {} makes {:.3g} objects, past the evaluation step budget "
                      "({} steps, a step per object placed)",
                      node->keyword_name(), n, step_budget_))
        .note("raise the budget with --max-steps N if the scene really needs it");
    return;
  }
  steps_ += static_cast<std::uint64_t>(n);
  builder_.add_object_tree(node);
}

Value Evaluator::eval_object_expr(const Expr& e, const std::shared_ptr<Env>& env) {
  const BlockInfo* block = symbol_block_[symbol_of(e)];
  bool instance = lang::is_instance_name(e.text);
  if (!instance && !(block && block->is_object)) {
    std::vector<std::string_view> names;
    for (std::string_view n : block_names(BlockKind::Item))
      if (const BlockInfo* b = find_block(n); b && b->is_object) names.push_back(n);
    names.push_back("object");
    // An unknown word before `{` may be a misspelt material or pattern too
    // (`material dielectrc { ... }`): those are candidates, and the message does
    // not claim an object was meant.
    if (!block)
      for (std::string_view n : block_names(BlockKind::Constructor)) names.push_back(n);
    auto d = error(DiagKind::UnknownBlock, e.span,
                   block ? "'" + e.text + "' is not an object block, so it is not a value"
                         : "there is no block '" + e.text + "' (no object, material or pattern)");
    std::string guess = lang::closest_match(e.text, names);
    if (const char* pov = povray_note(PovrayWordKind::Block, e.text))
      d.note(pov);
    else if (!guess.empty())
      d.note("did you mean '" + guess + "'?");
    else if (block && block->kind == BlockKind::Item)
      d.note("a '" + e.text + "' is a scene item: write it as a statement");
    return Value::error();
  }
  Span kw{e.span.file, e.span.begin, e.span.begin + static_cast<std::uint32_t>(e.text.size())};
  return eval_object(e.text, instance ? nullptr : block, *e.block, kw, env);
}

Value Evaluator::eval_object(std::string_view keyword, const BlockInfo* block,
                             const lang::Block& body, Span kw, const std::shared_ptr<Env>& env) {
  auto node = std::make_shared<ObjectNode>();
  node->block = block;
  node->keyword = kw;
  if (depth_ > 0) node->call = outer_call_;
  bool ok = true;
  if (!block) {
    // object { EXPR ... }: EXPR is the object value placed.
    if (!body.subject) return Value::error();  // reported by the parser
    static const BlockInfo* const object_props = find_block("object");
    Value v = eval(*body.subject, env);
    if (!v.is_error() && v.type != Type::Object) {
      error(DiagKind::TypeMismatch, body.subject->span,
            "'" + std::string(keyword) + " { }' places an object value, not " + a_type(v.type))
          .note("an object value is an object block used as a value: let w = union { ... };");
      v = Value::error();
    }
    if (v.is_error()) {
      // The instance's own properties are still checked (§10: independent errors).
      PropsLease props(*this);
      eval_props(*object_props, body, kw, env, props.list(), ok);
      return Value::error();
    }
    node->children.push_back(v.object());
    eval_props(*object_props, body, kw, env, node->props, ok);
    return ok ? Value::of_object(std::move(node)) : Value::error();
  }
  if (block->csg_op >= 0) {
    // The body runs in a scope of its own, as a loop body does; its properties see
    // the names it defines.
    auto scope = std::make_shared<Env>();
    scope->parent = env;
    collectors_.push_back({&node->children, block, kw});
    Frame frame;
    const std::size_t errors = diags_.error_count();
    exec_block(body.statements, scope, frame);
    const bool child_failed = collectors_.back().failed;
    collectors_.pop_back();
    eval_props(*block, body, kw, scope, node->props, ok);
    if (node->children.empty()) {
      // A warning, as POV-Ray's: a loop that made no children (a generated scene)
      // leaves nothing here, and the scene renders without it. Not where the body
      // had errors or an object in it failed (a value whose error was said where
      // it was made): those objects were there (no warning cascades). Either way
      // the block is left out: an empty CSG node is no object.
      if (!aborted_ && !child_failed && diags_.error_count() == errors)
        error(DiagKind::EmptyCsg, kw,
              "this '" + std::string(block->name) + "' holds no object: it adds nothing");
      ok = false;
    }
    return ok ? Value::of_object(std::move(node)) : Value::error();
  }
  eval_props(*block, body, kw, env, node->props, ok);
  if (!ok) check_rest(*block, kw, body, node->props);
  return ok ? Value::of_object(std::move(node)) : Value::error();
}

}  // namespace snell::compile

namespace snell::compile {

void Evaluator::check_rest(const BlockInfo& block, Span kw, const lang::Block& body,
                           const std::vector<EvaluatedProp>& props) {
  if (aborted_) return;
  // Failed: written but refused (a default may stand in), or required and absent,
  // or misspelt (`locaton`: its did-you-mean names it; the default in its place
  // is not what was meant, so no check across properties judges it). An unknown
  // property that is near none (`camera { position … }`) may have been meant as
  // any property left out, so then every default is unjudged: "the camera's 'up'
  // is parallel to its view direction" of the default location was an error
  // about nothing the user wrote.
  std::bitset<kPropCount> failed;
  const auto names = prop_names(block);
  std::vector<std::string> guessed;
  bool unplaced = false;
  for (const lang::Property& p : body.properties)
    if (!find_prop(block, p.name)) {
      guessed.push_back(lang::closest_match(p.name, names));
      unplaced |= guessed.back().empty();
    }
  for (const PropInfo* info : block.props) {
    bool written = false, attempted = false;
    for (const EvaluatedProp& ep : props)
      written |= ep.info == info && ep.name_span.begin != kw.begin;
    for (const lang::Property& p : body.properties) attempted |= p.name == info->name;
    for (const std::string& g : guessed) attempted |= g == info->name;
    if (!written && (attempted || unplaced || info->required())) failed.set(std::size_t(info->id));
  }
  if (block.shape_kind >= 0)
    check_shape_rest(block, builder_, kw, props, failed, diags_);
  else
    builder_.check_item_rest(block, kw, props, failed);
}

}  // namespace snell::compile
