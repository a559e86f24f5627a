// The robots' mesh files in the replay page: see output/replay_meshes.h.
#include "output/replay_meshes.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "output/base64.h"
#include "output/mesh_decimation.h"

namespace robophi::output {

std::string meshFilesJson(const std::string& world, double capBytes, std::size_t budgetBytes,
                          std::size_t triangleBudget, std::vector<std::string>* warnings) {
  if (world.empty()) return {};
  nlohmann::json parsed;
  try {
    parsed = nlohmann::json::parse(world);
  } catch (const nlohmann::json::exception&) {
    return {};
  }
  const auto robots = parsed.find("robots");
  if (robots == parsed.end() || !robots->is_object() || !robots->contains("meshes")) return {};
  const nlohmann::json& meshes = (*robots)["meshes"];
  if (!meshes.is_array() || meshes.empty()) return {};
  // What may go in: the budget of files, and a third of the page's cap in base64.
  const double capShare = capBytes / 3.0;
  const std::size_t budget = std::min(
      budgetBytes, capShare > 0.0 ? static_cast<std::size_t>(capShare * 3.0 / 4.0) : std::size_t{0});
  std::size_t used = 0;
  std::string out = ",\"meshFiles\":[";
  bool first = true;
  for (const nlohmann::json& mesh : meshes) {
    if (!first) out += ',';
    first = false;
    const std::string path = mesh.value("path", std::string{});
    // Read by the checked reader (output/mesh_decimation.h): the file as it is, or
    // written back under the triangle budget; a problem leaves it out, a warning.
    PageMesh file = pageMesh(path, mesh.value("format", std::string{}), triangleBudget);
    nlohmann::json entry = {{"format", file.format}};
    if (file.rewritten) {
      entry["triangles"] = file.trianglesAfter;
      entry["decimatedFrom"] = file.trianglesBefore;
    }
    std::string note;
    std::string bytes;
    const std::size_t size = file.bytes.size() + file.materials.size();
    if (!file.problem.empty()) {
      note = "not drawn: " + file.problem;
    } else if (used + size > budget) {
      note = fmt::format(
          "left out: the page's mesh budget ({:.1f} MB of files) is spent; {} has {} bytes",
          static_cast<double>(budget) / 1e6, path, size);
    } else {
      bytes = std::move(file.bytes);
      used += file.materials.size();
      if (!file.materials.empty()) entry["mtl"] = file.materials;
    }
    if (!note.empty() && warnings != nullptr) warnings->push_back("replay.html: visual mesh " + note);
    entry["bytes"] = bytes.size();
    if (!note.empty()) entry["note"] = note;
    std::string text = entry.dump();
    // Inside <script>: no "</" (a path could hold one).
    for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
      text.replace(at, 2, "<\\/");
    text.pop_back();  // the closing brace: the data follows
    out += text + ",\"data\":";
    if (note.empty()) {
      used += bytes.size();
      out += '"';
      appendBase64(out, bytes.data(), bytes.size());
      out += '"';
    } else {
      out += "null";
    }
    out += '}';
  }
  out += ']';
  return out;
}

}  // namespace robophi::output
