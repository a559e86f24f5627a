// Results folders: the marker, the check before writing, and the move of a
// finished staging folder into place that deletes nothing robophi did not write.
#include "output/results_folder.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
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

// A file the marker lists, or one being written whole in its place (NAME.partial,
// writeFileAtomically) of a listed file or of the marker itself.
bool isListed(const std::string& name, const std::set<std::string>& files) {
  constexpr std::string_view kPartial = ".partial";
  if (files.count(name) > 0) return true;
  if (!name.ends_with(kPartial)) return false;
  const std::string whole = name.substr(0, name.size() - kPartial.size());
  return whole == kResultsMarker || files.count(whole) > 0;
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
               (name == kResultsMarker ? contents.marked : isListed(name, files))) {
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

namespace {

// `target` without a trailing separator ("out/" is "out").
fs::path folderPath(const fs::path& target) {
  return target.filename().empty() ? target.parent_path() : target;
}

// The folder that holds `target` ("." for a bare name).
fs::path parentOf(const fs::path& target) {
  const fs::path parent = folderPath(target).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

// Renames `from` to `to`; throws WriteError naming both when it cannot.
void renameOrThrow(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec) {
    throw WriteError(
        fmt::format("cannot rename {} to {} ({})", from.string(), to.string(), ec.message()));
  }
}

// Flushes every file under `dir`, then `dir`, to disk.
void syncTree(const fs::path& dir) {
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file() || entry.is_directory()) syncToDisk(entry.path());
  syncToDisk(dir);
}

// --force beside foreign entries (or a `target` that is a link): robophi's
// files replaced one by one, each by a rename; the marker lists the old and the
// new ones until the old are gone, so the folder stays robophi's throughout.
void publishFileByFile(const fs::path& staging, const fs::path& target, std::string_view kind,
                       const FolderContents& previous, const std::vector<std::string>& incoming) {
  std::vector<std::string> listed;
  for (const std::string& name : incoming)
    if (name != kResultsMarker) listed.push_back(name);
  for (const std::string& name : previous.owned)
    if (name != kResultsMarker && name.back() != '/' &&
        std::find(listed.begin(), listed.end(), name) == listed.end())
      listed.push_back(name);
  writeResultsMarker(target, kind, listed);
  for (const std::string& name : incoming)
    if (name != kResultsMarker) moveFile(staging / name, target / name);
  for (const std::string& name : previous.owned) {
    if (name == kResultsMarker) continue;
    if (name.back() == '/') {
      removeOwnedEntries(target / name.substr(0, name.size() - 1), /*removeFolder=*/true);
    } else if (std::find(incoming.begin(), incoming.end(), name) == incoming.end()) {
      fs::remove(target / name);
    }
  }
  moveFile(staging / kResultsMarker, target / kResultsMarker);
  fs::remove(staging);
  syncToDisk(target);
}

}  // namespace

fs::path stagingFolderOf(const fs::path& target) {
  const fs::path path = folderPath(target);
  return path.parent_path() / ("." + path.filename().string() + ".partial");
}

fs::path previousFolderOf(const fs::path& target) {
  const fs::path path = folderPath(target);
  return path.parent_path() / ("." + path.filename().string() + ".old");
}

void syncToDisk(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const std::string reason = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    throw WriteError(fmt::format("{}: cannot flush to disk ({})", path.string(), reason));
  }
  ::close(fd);
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
  // On disk before any rename: a power cut must not publish empty files.
  syncTree(staging);
  const fs::path to = folderPath(target);
  const FolderContents contents = inspectResultsFolder(to);
  std::error_code ec;
  if (!contents.exists) {
    renameOrThrow(staging, to);
    syncToDisk(parentOf(to));
    return;
  }
  if (!contents.foreign.empty() || fs::is_symlink(to, ec)) {
    publishFileByFile(staging, to, kind, contents, incoming);
    return;
  }
  // The earlier results step aside, the new ones take their name, then the
  // earlier ones go: a kill between the renames is undone by recoverResultsFolder.
  const fs::path previous = previousFolderOf(to);
  removeOwnedEntries(previous, /*removeFolder=*/true);  // a killed replacement's, robophi's
  renameOrThrow(to, previous);
  renameOrThrow(staging, to);
  syncToDisk(parentOf(to));
  removeOwnedEntries(previous, /*removeFolder=*/true);
}

std::string recoverResultsFolder(const fs::path& target) {
  const fs::path to = folderPath(target);
  const fs::path previous = previousFolderOf(to);
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(previous, ec))) return {};
  if (!fs::exists(fs::symlink_status(to, ec))) {
    renameOrThrow(previous, to);
    syncToDisk(parentOf(to));
    return fmt::format(
        "{}: the earlier results were put back from {} (their replacement was cut short)",
        to.string(), previous.string());
  }
  removeOwnedEntries(previous, /*removeFolder=*/true);
  return {};
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
      const std::string reason = std::strerror(errno);  // the failed write's, as a rule
      fs::remove(temporary, ec);
      throw WriteError(fmt::format("{}: cannot write ({})", path.string(), reason));
    }
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(temporary, ec);
    throw WriteError(fmt::format("{}: cannot write ({})", path.string(), reason));
  }
}

}  // namespace robophi::output
