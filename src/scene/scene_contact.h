#pragma once
// The contact keys of a scene file (docs/contact.md): "materials", each object
// entry's "material", "environment", "medium", "contact" and "contactPairs",
// read on the loader's one diagnostics path (unknown keys get a suggestion).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "robophi/model.h"
#include "scene/scene_fields.h"

namespace robophi::scene {

/// Reads the contact keys of the scene whose top-level object `root` reads into
/// `model` (and marks them as known keys of the scene). Object names (in
/// contactPairs and objects/k/material) resolve against model.objects, so call it
/// once the objects are placed. `sceneDirectory` resolves relative PGM paths.
void readContactKeys(ObjectReader& root, const std::string& sceneDirectory, Model& model);

/// The "material" member of `r`: its index in model.materials; 0 (the default
/// material) when absent or unknown (reported).
std::int32_t readMaterialName(ObjectReader& r, const Model& model);

/// Reads the "environment" object at `pointer` into model.environment (after
/// whatever it holds already): ground, planes, heightfield(s), boxes, spheres.
void readEnvironment(DiagnosticSink& sink, const nlohmann::json& value, const std::string& pointer,
                     const std::string& sceneDirectory, Model& model);

}  // namespace robophi::scene
