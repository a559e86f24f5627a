#pragma once
// What bench and study records (bench/results/*.json) share.

#include <ctime>
#include <nlohmann/json.hpp>

#include "robophi/version.h"

namespace robophi::cli {

/// A record's header: {"robophi": version, "date": now (UTC, ISO 8601)}.
inline nlohmann::ordered_json recordHeader() {
  nlohmann::ordered_json record;
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  record["robophi"] = kVersion;
  record["date"] = date;
  return record;
}

}  // namespace robophi::cli
