// Warnings about a scene as a whole that a user would want before spending a
// render on it (issue #18): no object, no light while some surface needs one,
// the camera inside a closed object. They are the CLI's (`snell check` and
// `snell render` print them), not compiler diagnostics: the camera test needs
// the runtime's solid intervals, and a lightless scene is legitimate in the
// language's own test cases (a mirror under a background needs no light).
#pragma once

#include <string>
#include <vector>

#include "runtime/ir/ir.hpp"

namespace snell::rt {

// One line each ("the scene has no light: ..."), without a "warning:" prefix,
// with the object it is about (line 0: none, the scene as a whole); empty when
// there is nothing to say. Limits: the camera test covers the top-level objects
// that do not move and have an inside: spheres, boxes, closed cylinders and cones,
// tori, closed meshes, CSG objects (by their trees) and instances (inside any
// part of their value).
struct SceneWarning {
  std::string message;
  ir::SourceRef where;
};
std::vector<SceneWarning> scene_warnings(const ir::Scene& scene);

}  // namespace snell::rt
