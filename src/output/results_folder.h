#pragma once
/// \file
/// Results folders that robophi can replace without losing anything it did not
/// write (docs/output-format.md "Safe results folders"). Every folder robophi
/// makes holds a marker file that lists the files robophi wrote there; robophi
/// deletes or overwrites only those, never anything else.

#include <filesystem>
#include <functional>
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

/// A file robophi could not write whole (a full disk, a lost device): the
/// message names the file.
class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The staging folder of the results folder `target`: `.NAME.partial` beside
/// it, where the results are written before they are moved into place.
std::filesystem::path stagingFolderOf(const std::filesystem::path& target);

/// Where the earlier results of `target` wait while new ones take their place
/// (`.NAME.old` beside it): publishResultsFolder renames them there, renames
/// the staging folder to `target`, then deletes them.
std::filesystem::path previousFolderOf(const std::filesystem::path& target);

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
/// files and its marker of `kind`) to `target`, as one transaction: its files
/// are flushed to disk first; a missing `target` is renamed into place in one
/// step; a `target` holding nothing but robophi's results is renamed to
/// previousFolderOf(target), `staging` renamed to `target`, and the earlier
/// results deleted, so that a kill at any point leaves the earlier results or
/// the new ones whole (recoverResultsFolder puts the earlier ones back when the
/// kill came between the two renames). With `force` and foreign entries in
/// `target`, robophi's files are replaced one by one (each whole; the marker
/// lists old and new until the end) and the foreign ones kept. Throws
/// ResultsFolderError, leaving `staging` as it is, when `target` may not
/// receive them (resultsFolderProblem).
void publishResultsFolder(const std::filesystem::path& staging, const std::filesystem::path& target,
                          std::string_view kind, bool force);

/// Finishes what a killed publishResultsFolder left beside `target`: when
/// `target` is missing and previousFolderOf(target) exists, renames it back
/// (the earlier results; the message says so); when both exist, deletes
/// robophi's files in the earlier one. Returns what it did, or empty. Call it
/// holding the folder's lock (ResultsFolderLock).
std::string recoverResultsFolder(const std::filesystem::path& target);

/// Flushes the file or folder `path` to disk (fsync); throws WriteError naming
/// it when that fails.
void syncToDisk(const std::filesystem::path& path);

/// Writes `path` through a temporary file beside it (`path`.partial) that
/// `write` fills and that is then renamed over `path`, so that `path` is never
/// half written. Creates the parent folder if needed. Throws WriteError naming
/// the file on failure (and removes the temporary file).
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

}  // namespace robophi::output
