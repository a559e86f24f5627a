#pragma once
// Helpers shared by the scene-file tests: every error as text, the error that
// says something, and test names from a case's label.

#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <string_view>

#include "robophi/scene/scene.h"

namespace robophi::test {

/// Every error of a load, formatted, one a line (for failure messages).
inline std::string allErrors(const SceneLoadResult& result) {
  std::string text;
  for (const auto& e : result.errors) text += e.format() + "\n";
  return text;
}

/// The last error whose message contains `fragment`, or nullptr.
inline const Diagnostic* findError(const SceneLoadResult& result, std::string_view fragment) {
  const Diagnostic* match = nullptr;
  for (const auto& e : result.errors)
    if (e.message.find(fragment) != std::string::npos) match = &e;
  return match;
}

/// A parameterised test's name from its case's `label` (non-alphanumerics → '_').
struct LabelName {
  template <typename Case>
  std::string operator()(const ::testing::TestParamInfo<Case>& param) const {
    std::string name = param.param.label;
    for (char& ch : name)
      if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return name;
  }
};

}  // namespace robophi::test
