#pragma once
/// \file
/// Checkpoint files (docs/output-format.md "Checkpoint and restart"): what a run
/// needs to go on bit-identically. Every double is written in its shortest
/// round-trip form (output/json_numbers.h), so it reads back to the same bits.
/// State and Contact are written field by field in one function each: a new
/// field is one line in each of stateToJson/stateFromJson or
/// contactToJson/contactFromJson.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

/// The bytes of a series file a checkpoint's digest covers: the last up to
/// this many before the length the checkpoint records.
inline constexpr std::uintmax_t kSeriesDigestBytes = 4096;

/// fileHash of the kSeriesDigestBytes bytes of `path` before `length` (all of
/// them when shorter); "" when they cannot be read.
std::string seriesDigest(const std::string& path, std::uintmax_t length);

/// The checkpoint's "inputs": each file the run read (Scene::inputFiles) with
/// its fileHash now.
nlohmann::json inputDigests(const std::vector<std::string>& files);

/// Why `checkpoint`, read from the run folder `dir`, cannot be continued; empty
/// when it can. Names the field and its value, or the file: a number out of its
/// range (a time that is not finite and >= 0, a duration below it, a step that
/// is not finite and > 0, a count below 0, ...); an input file (the scene, a
/// URDF, a mesh, a heightfield) missing or changed since the run started; a
/// series file of `dir` that is not the one the checkpoint was written with
/// (its digest differs: a checkpoint copied into another run's folder).
std::string checkpointProblem(const std::string& dir, const nlohmann::json& checkpoint);

}  // namespace robophi
