#pragma once
// The contact keys of a scene file (docs/contact.md): "materials", per-object
// "material", "contactPairs", "environment", "medium" and "contact". Written for
// the scene loader to call once the objects are in the model.

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "robophi/model.h"

namespace robophi {

/// Receives one error: the JSON pointer of the offending value and a message.
using ContactErrorSink =
    std::function<void(const std::string& pointer, const std::string& message)>;

/// Reads the contact keys of the scene document `root` into `model`. Object names
/// (in contactPairs and objects/k/material) resolve against model.objects, so call
/// it after the objects are built. `sceneDirectory` resolves relative PGM paths.
/// Reports every problem through `error` and returns false if there was any.
bool parseContactScene(const nlohmann::json& root, const std::string& sceneDirectory, Model& model,
                       const ContactErrorSink& error);

}  // namespace robophi
