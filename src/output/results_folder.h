#pragma once
/// \file
/// Results folders that robophi can replace without losing anything it did not
/// write (docs/output-format.md "Safe results folders"). Every folder robophi
/// makes holds a marker file that lists the files robophi wrote there; robophi
/// deletes or overwrites only those, never anything else.

#include <filesystem>
#include <functional>
#include <future>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace robophi::output {

/// The marker robophi writes into every results folder it makes (JSON:
/// {"robophi": version, "kind": "run" | "vtk", "files": [names]}).
inline constexpr std::string_view kResultsMarker = "robophi-results.json";

/// A results folder that robophi refuses to write into: the message names the
/// folder and what is in it.
class ResultsFolderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a folder holds, as robophi sees it.
struct FolderContents {
  bool exists = false;
  /// False when the path exists but is not a folder (a file, a link).
  bool isFolder = false;
  /// It holds a readable marker, which says what robophi wrote there ("run",
  /// "vtk").
  bool marked = false;
  std::string kind;
  /// Entries robophi wrote: the marker, the files it lists (regular files only),
  /// and sub-folders that are wholly robophi's (marked, nothing else inside,
  /// e.g. robophi export vtk's DIR/vtk). Sorted; a sub-folder ends in '/'.
  std::vector<std::string> owned;
  /// Every other entry, sorted; a sub-folder ends in '/'.
  std::vector<std::string> foreign;
};

/// Looks at `dir` (it need not exist).
FolderContents inspectResultsFolder(const std::filesystem::path& dir);

/// Why robophi must not write results named `incoming` into `dir` (a message
/// naming the folder and the entries in the way), or empty when it may. It may
/// when `dir` does not exist, or holds nothing but robophi's own files (an
/// empty folder included). With `force` it may also write into a folder that
/// holds other entries (they are kept as they are), unless one of them has the
/// name of a file robophi would write or of the marker. A folder that robophi
/// made for another `kind` of results (a run's, an export's) is refused.
std::string resultsFolderProblem(const std::filesystem::path& dir, std::string_view kind,
                                 bool force, const std::vector<std::string>& incoming);

/// Writes (replaces) the marker of `dir`, listing `files` (names inside `dir`).
/// Throws std::runtime_error when it cannot be written.
void writeResultsMarker(const std::filesystem::path& dir, std::string_view kind,
                        const std::vector<std::string>& files);

/// Adds `file` to the marker of `dir` when `dir` has one (a file robophi added
/// to one of its folders later, e.g. robophi export html's replay.html).
void addToResultsMarker(const std::filesystem::path& dir, const std::string& file);

/// Takes `file` off the marker of `dir` when it lists it.
void removeFromResultsMarker(const std::filesystem::path& dir, const std::string& file);

/// Deletes what robophi wrote in `dir` (its owned entries, sub-folders
/// recursively by the same rule, the marker last) and keeps everything else.
/// Removes `dir` itself when nothing else is left in it and `removeFolder`.
void removeOwnedEntries(const std::filesystem::path& dir, bool removeFolder);

/// Moves the finished results folder `staging` (beside `target`, holding
/// files and its marker of `kind`) to `target`. A missing `target` is renamed into place in one
/// step; otherwise robophi's previous files in `target` are deleted, the new
/// marker moved in, then the new files, and `staging` is removed. Throws
/// ResultsFolderError, leaving `staging` as it is, when `target` may not
/// receive them (resultsFolderProblem).
void publishResultsFolder(const std::filesystem::path& staging, const std::filesystem::path& target,
                          std::string_view kind, bool force);

/// Removes robophi's previous results from `target` ahead of
/// publishResultsFolder, on a thread of its own (while a run writes its last
/// files): only when `target` may take results of `kind` holding any of
/// `incoming` (resultsFolderProblem finds nothing); else it leaves `target` as it
/// is, and publishResultsFolder says why or removes them itself. Wait for it
/// before publishing. (The previous results are then gone once a run has ended,
/// whether or not its last files could be written.)
std::future<void> clearPreviousResults(const std::filesystem::path& target, std::string_view kind,
                                       bool force, std::vector<std::string> incoming);

/// Writes `path` through a temporary file beside it (`path`.partial) that
/// `write` fills and that is then renamed over `path`, so that `path` is never
/// half written. Creates the parent folder if needed. Throws std::runtime_error
/// naming the file on failure (and removes the temporary file).
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

}  // namespace robophi::output
