#pragma once
/// \file
/// What the robots look like, for the replay page (docs/viewer.md "Robots as they
/// look"): the model's visual shapes (robophi/visuals.h), each with the particles
/// whose best-fit rigid motion from their start moves it, and the mesh files the
/// page embeds. WorldView writes it as world.json's "robots" block.

#include <nlohmann/json.hpp>

#include "robophi/scene/scene.h"

namespace robophi::output {

/// {"carriers": [{"particles": [...], "rest": [x, y, z, ...]}], "meshes": [{"path",
/// "format"}], "visuals": [...]} of the scene's model, or null when it has no visuals.
nlohmann::ordered_json visualsJson(const Scene& scene);

/// The shapes the model knows of its built-in objects (docs/viewer.md "Objects'
/// shapes"): {"rims": [RimRing's fields], "surfaces": {"slots", "particles",
/// "weights" (slots a vertex), "triangles" (3 vertices each), "objects" (one a
/// triangle)}}, or null when it has neither.
nlohmann::ordered_json shapesJson(const Model& model);

}  // namespace robophi::output
