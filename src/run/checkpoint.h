#pragma once
/// \file
/// Checkpoint files (docs/output-format.md "Checkpoint and restart"): what a run
/// needs to go on bit-identically. Every double is written in its shortest
/// round-trip form (output/json_numbers.h), so it reads back to the same bits.
/// State and Contact are written field by field in one function each: a new
/// field is one line in each of stateToJson/stateFromJson or
/// contactToJson/contactFromJson.

#include <nlohmann/json.hpp>
#include <string>

#include "robophi/adaptive_step.h"
#include "robophi/evaluation.h"
#include "robophi/model.h"
#include "robophi/scene/scene.h"
#include "robophi/state.h"

namespace robophi {

/// Every field of a Contact.
nlohmann::json contactToJson(const Contact& contact);
Contact contactFromJson(const nlohmann::json& j);

/// Every field of a State (its friction history by contactToJson).
nlohmann::json stateToJson(const State& state);
/// Throws std::runtime_error when `j` is not a state of `model`'s size.
State stateFromJson(const nlohmann::json& j, const Model& model);

/// Every field of an Evaluation (World::evaluation() at a checkpoint: the next
/// step starts from it).
nlohmann::json evaluationToJson(const Evaluation& evaluation);
Evaluation evaluationFromJson(const nlohmann::json& j);

/// The parts of a model that World's edit API changes (connectors, fixed
/// particles, gravity, materials, object materials, sphere obstacles, viscosity,
/// contact settings), and putting them back into the scene's model.
nlohmann::json modelEditsToJson(const Model& model);
/// Throws std::runtime_error when they do not fit `model` (another scene).
void applyModelEdits(const nlohmann::json& j, Model& model);

nlohmann::json adaptiveProgressToJson(const AdaptiveStepper::Progress& progress);
AdaptiveStepper::Progress adaptiveProgressFromJson(const nlohmann::json& j);

/// Every field of RunSettings, exactly.
nlohmann::json runSettingsToJson(const RunSettings& settings);
RunSettings runSettingsFromJson(const nlohmann::json& j);

/// A 64-bit FNV-1a hash of a file's bytes, as 16 hex digits ("" when unreadable).
std::string fileHash(const std::string& path);

}  // namespace robophi
