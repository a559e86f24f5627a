// Results folders: the marker, the check before writing, and the move of a
// finished staging folder into place that deletes nothing robophi did not write.
#include "output/results_folder.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "robophi/version.h"

namespace robophi::output {

namespace {

namespace fs = std::filesystem;

// The marker of `dir` as JSON, when it is a regular file holding an object
// with a "files" array of names.
std::optional<nlohmann::json> readMarker(const fs::path& dir) {
  const fs::path path = dir / kResultsMarker;
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(path, ec))) return std::nullopt;
  std::ifstream in(path);
  nlohmann::json marker = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!marker.is_object() || !marker.contains("files") || !marker["files"].is_array())
    return std::nullopt;
  for (const auto& name : marker["files"])
    if (!name.is_string()) return std::nullopt;
  return marker;
}

// "a, b and 3 more": at most five names.
std::string listed(const std::vector<std::string>& names) {
  constexpr std::size_t kShown = 5;
  std::string text;
  for (std::size_t i = 0; i < std::min(names.size(), kShown); ++i) {
    if (i > 0) text += ", ";
    text += names[i];
  }
  if (names.size() > kShown) text += fmt::format(" and {} more", names.size() - kShown);
  return text;
}

// Renames `from` to `to` (replacing a file there); copies across file systems.
void moveFile(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (!ec) return;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  fs::remove(from);
}

}  // namespace

FolderContents inspectResultsFolder(const fs::path& dir) {
  FolderContents contents;
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);  // a link to a folder is that folder
  if (!fs::exists(status)) return contents;
  contents.exists = true;
  contents.isFolder = fs::is_directory(status);
  if (!contents.isFolder) return contents;
  std::set<std::string> files;
  if (const auto marker = readMarker(dir)) {
    contents.marked = true;
    contents.kind = marker->value("kind", "");
    for (const auto& name : (*marker)["files"]) files.insert(name.get<std::string>());
  }
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    const fs::file_status entryStatus = entry.symlink_status();
    if (fs::is_directory(entryStatus)) {
      const FolderContents sub = inspectResultsFolder(entry.path());
      (sub.marked && sub.foreign.empty() ? contents.owned : contents.foreign).push_back(name + "/");
    } else if (fs::is_regular_file(entryStatus) &&
               (name == kResultsMarker ? contents.marked : files.count(name) > 0)) {
      contents.owned.push_back(name);
    } else {
      contents.foreign.push_back(name);
    }
  }
  std::sort(contents.owned.begin(), contents.owned.end());
  std::sort(contents.foreign.begin(), contents.foreign.end());
  return contents;
}

std::string resultsFolderProblem(const fs::path& dir, std::string_view kind, bool force,
                                 const std::vector<std::string>& incoming) {
  const FolderContents contents = inspectResultsFolder(dir);
  if (!contents.exists) return {};
  if (!contents.isFolder) return fmt::format("{} exists and is not a folder", dir.string());
  if (contents.marked && contents.kind != kind) {
    return fmt::format("{} holds robophi's {} results, not a {}'s", dir.string(), contents.kind,
                       kind);
  }
  if (contents.foreign.empty()) return {};
  if (!force) {
    return fmt::format(
        "{} is not a robophi results folder: it holds {}, which robophi did not write{}",
        dir.string(), listed(contents.foreign),
        contents.marked ? "" : fmt::format(" (it has no {})", kResultsMarker));
  }
  // --force keeps foreign entries; one that a result would replace is still refused.
  std::vector<std::string> clashes;
  for (const std::string& name : contents.foreign) {
    const std::string bare = name.back() == '/' ? name.substr(0, name.size() - 1) : name;
    if (bare == kResultsMarker ||
        std::find(incoming.begin(), incoming.end(), bare) != incoming.end())
      clashes.push_back(name);
  }
  if (clashes.empty()) return {};
  return fmt::format("{} holds {}, which robophi did not write and would have to replace",
                     dir.string(), listed(clashes));
}

void writeResultsMarker(const fs::path& dir, std::string_view kind,
                        const std::vector<std::string>& files) {
  nlohmann::ordered_json marker;
  marker["robophi"] = kVersion;
  marker["kind"] = std::string(kind);
  marker["files"] = files;
  writeFileAtomically(dir / kResultsMarker,
                      [&](std::ostream& out) { out << marker.dump(1) << '\n'; });
}

namespace {

// Rewrites the marker of `dir`, when it has one, with its file list as `edit`
// leaves it (edit returns false: nothing to change).
template <class Edit>
void editResultsMarker(const fs::path& dir, const Edit& edit) {
  auto marker = readMarker(dir);
  if (!marker) return;
  std::vector<std::string> files = (*marker)["files"].get<std::vector<std::string>>();
  if (edit(files)) writeResultsMarker(dir, marker->value("kind", "run"), files);
}

}  // namespace

void addToResultsMarker(const fs::path& dir, const std::string& file) {
  editResultsMarker(dir, [&](std::vector<std::string>& files) {
    if (std::find(files.begin(), files.end(), file) != files.end()) return false;
    files.push_back(file);
    return true;
  });
}

void removeFromResultsMarker(const fs::path& dir, const std::string& file) {
  editResultsMarker(dir, [&](std::vector<std::string>& files) {
    const auto it = std::find(files.begin(), files.end(), file);
    if (it == files.end()) return false;
    files.erase(it);
    return true;
  });
}

void removeOwnedEntries(const fs::path& dir, bool removeFolder) {
  const FolderContents contents = inspectResultsFolder(dir);
  if (!contents.isFolder) return;
  for (const std::string& name : contents.owned) {
    if (name == kResultsMarker) continue;  // last: the folder stays marked until it is empty
    if (name.back() == '/') {
      removeOwnedEntries(dir / name.substr(0, name.size() - 1), /*removeFolder=*/true);
    } else {
      fs::remove(dir / name);
    }
  }
  if (contents.marked) fs::remove(dir / kResultsMarker);
  if (removeFolder && fs::is_empty(dir)) fs::remove(dir);
}

void publishResultsFolder(const fs::path& staging, const fs::path& target, std::string_view kind,
                          bool force) {
  std::vector<std::string> incoming;
  for (const fs::directory_entry& entry : fs::directory_iterator(staging))
    incoming.push_back(entry.path().filename().string());
  const std::string problem = resultsFolderProblem(target, kind, force, incoming);
  if (!problem.empty()) {
    throw ResultsFolderError(
        fmt::format("{}; the results were kept in {}", problem, staging.string()));
  }
  std::error_code ec;
  if (!fs::exists(target, ec)) {
    fs::rename(staging, target);
    return;
  }
  // Replace robophi's previous files and keep the rest. The new marker goes in
  // first, so that the folder stays marked if the move is cut short.
  removeOwnedEntries(target, /*removeFolder=*/false);
  moveFile(staging / kResultsMarker, target / kResultsMarker);
  for (const std::string& name : incoming)
    if (name != kResultsMarker) moveFile(staging / name, target / name);
  fs::remove(staging);
}

std::future<void> clearPreviousResults(const fs::path& target, std::string_view kind, bool force,
                                       std::vector<std::string> incoming) {
  return std::async(std::launch::async,
                    [target, kind = std::string(kind), force, incoming = std::move(incoming)] {
                      try {
                        if (!resultsFolderProblem(target, kind, force, incoming).empty()) return;
                        removeOwnedEntries(target, /*removeFolder=*/false);
                      } catch (const std::exception&) {  // publishResultsFolder tries again
                      }
                    });
}

void writeFileAtomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  const fs::path temporary = path.string() + ".partial";
  {
    std::ofstream out(temporary, std::ios::binary);
    if (out) write(out);
    if (out) out.close();
    if (!out) {
      fs::remove(temporary, ec);
      throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
    }
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(temporary, ec);
    throw std::runtime_error(fmt::format("{}: cannot write ({})", path.string(), reason));
  }
}

}  // namespace robophi::output
