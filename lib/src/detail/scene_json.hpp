#pragma once
// Scene I/O internals shared by scenes and studies: a scene from parsed JSON, and setting one
// dotted key on it (what --set and every study point do).

#include "gapchain/scene.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace gapchain::detail {

/// root["a"]["b"]["c"] = value for path "a.b.c", creating the objects on the way; throws
/// SceneError (prefixed by context) for an empty part or a part that is not an object.
void set_scene_key(nlohmann::json& root, const std::string& path, nlohmann::json value,
                   const std::string& context);

/// The validated scene of parsed JSON, overrides ("section.key=value") applied first; every
/// bad input is a SceneError.
Scene scene_from_parsed_json(nlohmann::json root, const std::vector<std::string>& overrides,
                             const std::string& source);

} // namespace gapchain::detail
