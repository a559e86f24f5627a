#pragma once
/// \file
/// Numbers in robophi's JSON files. JSON has no NaN or infinity: summary.json
/// writes a non-finite number as null and lists where (finiteOrNull), and the
/// checkpoint files write every double bit-exactly, a non-finite one as a string
/// ("inf", "-inf", "nan"), through exactNumber / numberFromJson.

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robophi/vec3.h"

namespace robophi::output {

/// Appends `value` in its shortest round-trip form, as fmt's "{}" writes it (a
/// CSV or JSON read back gives the bits that were simulated), without parsing a
/// format string or growing `out` one character at a time.
void appendShortest(std::string& out, double value);

/// `value` as JSON: itself when finite, else null, and `path` is added to
/// `nonFinite` (when given) so that the file can say which numbers were not.
inline nlohmann::json finiteOrNull(double value, const std::string& path,
                                   std::vector<std::string>* nonFinite) {
  if (std::isfinite(value)) return value;
  if (nonFinite) nonFinite->push_back(path);
  return nullptr;
}

/// Replaces every non-finite number in `j` by null, adding its JSON pointer to
/// `nonFinite`.
void nullNonFinite(nlohmann::ordered_json& j, std::vector<std::string>& nonFinite,
                   const std::string& pointer = "");

/// A double that reads back to the same bits: a JSON number (shortest round-trip
/// form) when finite, else "inf", "-inf" or "nan".
nlohmann::json exactNumber(double value);
/// Reads what exactNumber wrote. Throws std::runtime_error naming `what` otherwise.
double numberFromJson(const nlohmann::json& j, const std::string& what);
nlohmann::json exactVec3(const Vec3& v);
Vec3 vec3FromJson(const nlohmann::json& j, const std::string& what);
/// Arrays of exactNumber / exactVec3, and back (throwing as numberFromJson).
nlohmann::json exactNumbers(const std::vector<double>& values);
std::vector<double> numbersFromJson(const nlohmann::json& j, const std::string& what);
nlohmann::json exactVec3s(const std::vector<Vec3>& values);
std::vector<Vec3> vec3sFromJson(const nlohmann::json& j, const std::string& what);

}  // namespace robophi::output
