// Whether a checkpoint can be continued (checkpoint.h, checkpointProblem): its
// numbers in their ranges, the files the run read unchanged, and the series
// files of its folder the ones it was written with.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "output/json_numbers.h"
#include "run/checkpoint.h"

namespace robophi {

namespace {

using nlohmann::json;

// What a number of a checkpoint must be.
enum class Range {
  kFinite,              // any finite number
  kNonNegative,         // finite, >= 0
  kPositive,            // finite, > 0
  kPositiveOrInfinite,  // > 0, infinity allowed (no ceiling)
};

struct NumberRule {
  const char* pointer;
  Range range;
};

// The numbers of a checkpoint and their ranges (docs/output-format.md
// "Checkpoint and restart"); the adaptive step's progress only in adaptive runs.
constexpr NumberRule kNumbers[] = {
    {"/state/time", Range::kNonNegative},
    {"/state/dissipated", Range::kFinite},
    {"/state/external", Range::kFinite},
    {"/settings/duration", Range::kPositive},
    {"/settings/dt", Range::kPositive},
    {"/settings/fps", Range::kPositive},
    {"/settings/adaptive/initial_step", Range::kPositive},
    {"/settings/adaptive/min_step", Range::kNonNegative},
    {"/settings/adaptive/max_step", Range::kPositiveOrInfinite},
    {"/settings/adaptive/energy_tolerance", Range::kPositive},
    {"/settings/adaptive/loss_tolerance_factor", Range::kPositive},
    {"/settings/adaptive/energy_floor", Range::kNonNegative},
    {"/settings/adaptive/shrink_factor", Range::kPositive},
    {"/settings/adaptive/grow_factor", Range::kPositive},
    {"/settings/adaptive/safety", Range::kPositive},
    {"/settings/adaptive/error_order", Range::kNonNegative},
    {"/settings/adaptive/max_penetration_fraction", Range::kNonNegative},
    {"/settings/adaptive/stability_safety", Range::kPositive},
    {"/energy_rate", Range::kPositive},
    {"/checkpoint_every", Range::kNonNegative},
    {"/energy_account_bound", Range::kPositive},
    {"/run/initial_total", Range::kFinite},
    {"/run/initial_scale", Range::kPositive},
    {"/run/energy_scale", Range::kPositive},
    {"/run/largest_account_error", Range::kNonNegative},
    {"/run/wall_seconds", Range::kNonNegative},
};
constexpr NumberRule kAdaptiveNumbers[] = {
    {"/adaptive/step", Range::kPositive},
    {"/adaptive/smallest_step", Range::kPositiveOrInfinite},
    {"/adaptive/largest_step", Range::kNonNegative},
    {"/adaptive/sum_of_steps", Range::kNonNegative},
    {"/adaptive/last_step", Range::kNonNegative},
};

struct CountRule {
  const char* pointer;
  std::int64_t least;
};
constexpr CountRule kCounts[] = {
    {"/state/step_count", 0},      {"/settings/adaptive/max_rejections_in_a_row", 1},
    {"/run/next_frame", 0},        {"/run/next_energy_row", 0},
    {"/run/next_checkpoint", 0},   {"/run/last_frame_step", -1},
    {"/run/last_energy_step", -1}, {"/run/checkpoints", 0},
};
constexpr CountRule kAdaptiveCounts[] = {{"/adaptive/accepted", 0}, {"/adaptive/rejected", 0}};

const char* rangeWords(Range range) {
  switch (range) {
    case Range::kFinite:
      return "a finite number";
    case Range::kNonNegative:
      return "a finite number >= 0";
    case Range::kPositive:
      return "a finite number > 0";
    case Range::kPositiveOrInfinite:
      return "a number > 0";
  }
  return "";
}

bool inRange(double x, Range range) {
  switch (range) {
    case Range::kFinite:
      return std::isfinite(x);
    case Range::kNonNegative:
      return std::isfinite(x) && x >= 0.0;
    case Range::kPositive:
      return std::isfinite(x) && x > 0.0;
    case Range::kPositiveOrInfinite:
      return x > 0.0;
  }
  return false;
}

// "field /x/y = value: expected ..." for the first number or count out of range.
std::string numbersProblem(const json& checkpoint) {
  const bool adaptive = checkpoint.contains("adaptive") && !checkpoint["adaptive"].is_null();
  const auto checkNumbers = [&](const auto& rules) -> std::string {
    for (const NumberRule& rule : rules) {
      const json::json_pointer at(rule.pointer);
      if (!checkpoint.contains(at)) return fmt::format("{}: missing", rule.pointer);
      const json& value = checkpoint.at(at);
      const double x = output::numberFromJson(value, rule.pointer);
      if (!inRange(x, rule.range))
        return fmt::format("{} = {}: expected {}", rule.pointer, value.dump(),
                           rangeWords(rule.range));
    }
    return {};
  };
  const auto checkCounts = [&](const auto& rules) -> std::string {
    for (const CountRule& rule : rules) {
      const json::json_pointer at(rule.pointer);
      if (!checkpoint.contains(at)) return fmt::format("{}: missing", rule.pointer);
      const json& value = checkpoint.at(at);
      if (!value.is_number_integer() || value.get<std::int64_t>() < rule.least)
        return fmt::format("{} = {}: expected a whole number >= {}", rule.pointer, value.dump(),
                           rule.least);
    }
    return {};
  };
  for (const std::string& problem : {checkNumbers(kNumbers), checkCounts(kCounts),
                                     adaptive ? checkNumbers(kAdaptiveNumbers) : std::string(),
                                     adaptive ? checkCounts(kAdaptiveCounts) : std::string()})
    if (!problem.empty()) return problem;
  // The numbers together: the time within the duration, the floor below the ceiling.
  const double time = output::numberFromJson(checkpoint.at("state").at("time"), "time");
  const json& settings = checkpoint.at("settings");
  const double duration = output::numberFromJson(settings.at("duration"), "duration");
  if (!(duration >= time))
    return fmt::format("/settings/duration = {}: expected at least /state/time = {}",
                       settings.at("duration").dump(), checkpoint["state"]["time"].dump());
  const json& a = settings.at("adaptive");
  if (!(output::numberFromJson(a.at("min_step"), "min_step") <=
        output::numberFromJson(a.at("max_step"), "max_step")))
    return fmt::format("/settings/adaptive/min_step = {}: expected at most max_step = {}",
                       a.at("min_step").dump(), a.at("max_step").dump());
  // Every position and velocity finite (a checkpoint is written between good steps).
  for (const char* key : {"position", "velocity", "spin"}) {
    const json& values = checkpoint.at("state").at(key);
    for (std::size_t i = 0; i < values.size(); ++i)
      for (std::size_t d = 0; d < values[i].size(); ++d)
        if (!std::isfinite(output::numberFromJson(values[i][d], key)))
          return fmt::format("/state/{}/{}/{} = {}: expected a finite number", key, i, d,
                             values[i][d].dump());
  }
  for (const auto& [name, size] : checkpoint.at("files").items())
    if (!size.is_number_unsigned())
      return fmt::format("/files/{} = {}: expected a whole number >= 0", name, size.dump());
  return {};
}

}  // namespace

std::string checkpointProblem(const std::string& dir, const json& checkpoint) {
  const std::string file = (std::filesystem::path(dir) / "checkpoint.json").string();
  try {
    if (std::string problem = numbersProblem(checkpoint); !problem.empty())
      return fmt::format("{}: {}", file, problem);
    // The files the run read, as they were when it started.
    for (const json& input : checkpoint.value("inputs", json::array())) {
      const std::string path = input.at("path").get<std::string>();
      const std::string hash = input.at("hash").get<std::string>();
      if (fileHash(path) != hash) {
        return fmt::format(
            "{}: the run read {}, which is missing or has changed since the run started (hash "
            "{}, now {}): the checkpoint cannot be continued",
            file, path, hash, fileHash(path).empty() ? "unreadable" : fileHash(path));
      }
    }
    // The series files it was written with: their last bytes as they were then.
    const json& digests = checkpoint.value("files_digest", json::object());
    for (const auto& [name, size] : checkpoint.at("files").items()) {
      if (!digests.contains(name)) continue;
      const std::string series = (std::filesystem::path(dir) / name).string();
      if (seriesDigest(series, size.get<std::uintmax_t>()) != digests[name].get<std::string>()) {
        return fmt::format(
            "{}: {} is not the file this checkpoint was written with (the digest of its bytes "
            "before {} differs): a checkpoint belongs to its own run's folder",
            file, series, size.get<std::uintmax_t>());
      }
    }
  } catch (const std::exception& e) {  // a missing key, a wrong type
    return fmt::format("{}: {}", file, e.what());
  }
  return {};
}

}  // namespace robophi
