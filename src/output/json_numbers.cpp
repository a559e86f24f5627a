#include "output/json_numbers.h"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <limits>
#include <stdexcept>

namespace robophi::output {

void appendShortest(std::string& out, double value) {
  char text[32];  // the longest is 24: "-2.2250738585072014e-308"
  char* end = fmt::format_to(text, FMT_COMPILE("{}"), value);
  out.append(text, static_cast<std::size_t>(end - text));
}

void nullNonFinite(nlohmann::ordered_json& j, std::vector<std::string>& nonFinite,
                   const std::string& pointer) {
  if (j.is_number_float()) {
    if (!std::isfinite(j.get<double>())) {
      nonFinite.push_back(pointer);
      j = nullptr;
    }
  } else if (j.is_object()) {
    for (auto& [key, value] : j.items()) nullNonFinite(value, nonFinite, pointer + "/" + key);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      nullNonFinite(j[i], nonFinite, fmt::format("{}/{}", pointer, i));
  }
}

nlohmann::json exactNumber(double value) {
  if (std::isfinite(value)) return value;
  if (std::isnan(value)) return "nan";
  return value > 0.0 ? "inf" : "-inf";
}

double numberFromJson(const nlohmann::json& j, const std::string& what) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const auto& s = j.get_ref<const std::string&>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  }
  throw std::runtime_error(fmt::format("{}: expected a number, found {}", what, j.dump()));
}

nlohmann::json exactVec3(const Vec3& v) {
  return nlohmann::json::array({exactNumber(v.x), exactNumber(v.y), exactNumber(v.z)});
}

Vec3 vec3FromJson(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3)
    throw std::runtime_error(fmt::format("{}: expected [x, y, z], found {}", what, j.dump()));
  return Vec3{numberFromJson(j[0], what), numberFromJson(j[1], what), numberFromJson(j[2], what)};
}

nlohmann::json exactNumbers(const std::vector<double>& values) {
  auto out = nlohmann::json::array();
  for (double v : values) out.push_back(exactNumber(v));
  return out;
}

std::vector<double> numbersFromJson(const nlohmann::json& j, const std::string& what) {
  std::vector<double> out;
  out.reserve(j.size());
  for (const nlohmann::json& v : j) out.push_back(numberFromJson(v, what));
  return out;
}

nlohmann::json exactVec3s(const std::vector<Vec3>& values) {
  auto out = nlohmann::json::array();
  for (const Vec3& v : values) out.push_back(exactVec3(v));
  return out;
}

std::vector<Vec3> vec3sFromJson(const nlohmann::json& j, const std::string& what) {
  std::vector<Vec3> out;
  out.reserve(j.size());
  for (const nlohmann::json& v : j) out.push_back(vec3FromJson(v, what));
  return out;
}

}  // namespace robophi::output
