// Mesh files → TriangleMesh (loadMesh) and ShadedMesh (loadShadedMesh, for the
// replay page) through assimp, both by one checked road (readMesh: assimp in a
// child process).

#include <assimp/DefaultIOSystem.h>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "build/checks.h"
#include "build/child_process.h"
#include "robophi/build/input_files.h"
#include "robophi/build/rigid_body.h"
#include "robophi/build/shaded_mesh.h"

namespace robophi::build {

namespace {

[[noreturn]] void meshError(const std::string& path, const std::string& problem) {
  throw std::runtime_error("mesh '" + path + "': " + problem);
}

// Appends the meshes of the node tree (vertices through each node's accumulated
// transform), walked with a stack of its own (a deep tree is no deep recursion).
// With `shaded`, also each vertex's normal (turned by the inverse transpose) and
// each triangle's material.
void collect(const aiScene& scene, const Vec3& scale, TriangleMesh& out, ShadedMesh* shaded) {
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{scene.mRootNode, aiMatrix4x4{}}};
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    const aiMatrix4x4 transform = parent * node->mTransformation;
    aiMatrix3x3 normalTurn(transform);
    normalTurn.Inverse().Transpose();
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh& mesh = *scene.mMeshes[node->mMeshes[m]];
      const auto base = static_cast<std::int32_t>(out.vertices.size());
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const aiVector3D p = transform * mesh.mVertices[v];
        out.vertices.push_back({p.x * scale.x, p.y * scale.y, p.z * scale.z});
        if (shaded == nullptr) continue;
        aiVector3D n = mesh.HasNormals() ? normalTurn * mesh.mNormals[v] : aiVector3D(0, 0, 0);
        const ai_real length = n.Length();
        n = length > 0 && std::isfinite(length) ? n / length : aiVector3D(0, 0, 0);
        shaded->normals.push_back({n.x, n.y, n.z});
      }
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines carry no volume
        out.triangles.push_back({base + static_cast<std::int32_t>(face.mIndices[0]),
                                 base + static_cast<std::int32_t>(face.mIndices[1]),
                                 base + static_cast<std::int32_t>(face.mIndices[2])});
        if (shaded != nullptr)
          shaded->materialOf.push_back(std::min(mesh.mMaterialIndex, scene.mNumMaterials));
      }
    }
    for (unsigned c = node->mNumChildren; c-- > 0;)
      stack.emplace_back(node->mChildren[c], transform);
  }
}

// assimp's file access through readInputFile: every file a mesh reads (an OBJ's
// .mtl, a glTF's .bin too) is a regular file within the budget, never a FIFO
// or a folder waited on, and is recorded with the load's inputs. The mesh file
// itself is read once, before assimp starts, and served from memory. The first
// refusal is kept for the message (assimp's own would say only "unable to open").
struct OtherFile {
  std::string path;
  bool found = false;  // Exists said so, or Open read it
  bool opened = false;
  std::string bytes;  // what Open read
};

class InputFileSystem : public Assimp::DefaultIOSystem {
 public:
  InputFileSystem(std::string path, std::string bytes)
      : path_(std::move(path)), bytes_(std::move(bytes)) {}
  bool Exists(const char* file) const override {
    if (file == path_) return true;
    std::error_code error;
    const bool exists = std::filesystem::exists(file, error);  // any kind: Open says why not
    asked.push_back({file, exists, false, {}});
    return exists;
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::strchr(mode, 'w') != nullptr || std::strchr(mode, 'a') != nullptr) return nullptr;
    if (file == path_)
      return new Assimp::MemoryIOStream(reinterpret_cast<const std::uint8_t*>(bytes_.data()),
                                        bytes_.size());
    try {
      std::string bytes = readInputFile(file);
      auto* copy = new std::uint8_t[bytes.size()];
      std::memcpy(copy, bytes.data(), bytes.size());
      auto* stream = new Assimp::MemoryIOStream(copy, bytes.size(), /*own=*/true);
      asked.push_back({file, true, true, std::move(bytes)});
      return stream;
    } catch (const InputFileError& e) {
      if (refused.empty()) refused = e.what();
      asked.push_back({file, false, true, {}});
      return nullptr;
    }
  }
  /// The first file Open refused, and why ("<path>: <problem>").
  std::string refused;
  /// The other files assimp asked about or read, in order (what a kept mesh depends on).
  mutable std::vector<OtherFile> asked;

 private:
  const std::string path_, bytes_;
};

// The budgets of a mesh file (kMaxMeshVertices, kMaxMeshFaces,
// kMaxMeshFaceIndices, kMaxMeshPolygonWork): a problem in words, or "". Before
// the triangulation (`triangulated` false) the faces as read; after it the
// meshes as the node tree instances them. Also: every index names a vertex.
std::string meshBudgetProblem(const aiScene& scene, bool triangulated) {
  const auto count = [](std::uint64_t n) { return std::to_string(n); };
  std::uint64_t polygonWork = 0;
  for (unsigned m = 0; m < scene.mNumMeshes && !triangulated; ++m) {
    const aiMesh& mesh = *scene.mMeshes[m];
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const std::uint64_t corners = mesh.mFaces[f].mNumIndices;
      if (corners > kMaxMeshFaceIndices)
        return "face " + count(f) + " of mesh " + count(m) + " has " + count(corners) +
               " vertex indices, more than the budget of " + count(kMaxMeshFaceIndices) + " a face";
      if (corners > 4) polygonWork += corners * corners;
      for (unsigned k = 0; k < corners; ++k)
        if (mesh.mFaces[f].mIndices[k] >= mesh.mNumVertices)
          return "face " + count(f) + " of mesh " + count(m) + " names vertex " +
                 count(mesh.mFaces[f].mIndices[k]) + " of " + count(mesh.mNumVertices);
    }
  }
  if (polygonWork > kMaxMeshPolygonWork)
    return "has polygons whose triangulation costs " + count(polygonWork) +
           " (the sum of their corners squared, faces of more than four corners), more than the "
           "budget of " +
           count(kMaxMeshPolygonWork);
  // The meshes as the node tree places them (a mesh placed twice counts twice).
  std::uint64_t vertices = 0, faces = 0;
  std::vector<const aiNode*> nodes{scene.mRootNode};
  while (!nodes.empty()) {
    const aiNode* node = nodes.back();
    nodes.pop_back();
    if (node == nullptr) continue;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      if (node->mMeshes[k] >= scene.mNumMeshes)
        return "node '" + std::string(node->mName.C_Str()) + "' names mesh " +
               count(node->mMeshes[k]) + " of " + count(scene.mNumMeshes);
      vertices += scene.mMeshes[node->mMeshes[k]]->mNumVertices;
      faces += scene.mMeshes[node->mMeshes[k]]->mNumFaces;
    }
    const auto past = [&](std::uint64_t n, const char* what, std::uint64_t budget) {
      return "has at least " + count(n) + " " + what +
             " as its nodes place its meshes, more than the budget of " + count(budget);
    };
    if (vertices > kMaxMeshVertices) return past(vertices, "vertices", kMaxMeshVertices);
    if (faces > kMaxMeshFaces) return past(faces, "faces", kMaxMeshFaces);
    nodes.insert(nodes.end(), node->mChildren, node->mChildren + node->mNumChildren);
  }
  return {};
}

// assimp 5.2's COLLADA reader takes a token that is not a number in an index
// list (<p>, <vcount>, <v>) for a count and allocates gigabytes (12.6 GB and 30 s
// for "<p>0 2x1 ...</p>", a fuzz finding): such a list is refused before it
// reads the file. A problem in words, or "".
std::string colladaIndexProblem(const std::string& path, const std::string& text) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".dae") return {};
  for (const char* tag : {"<p>", "<vcount>", "<v>"}) {
    for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1)) {
      const std::size_t start = at + std::strlen(tag);
      const std::size_t end = text.find('<', start);
      for (std::size_t k = start; k < std::min(end, text.size()); ++k) {
        const char c = text[k];
        if (!std::isdigit(static_cast<unsigned char>(c)) &&
            !std::isspace(static_cast<unsigned char>(c)))
          return "a COLLADA index list " + std::string(tag) + " at line " +
                 std::to_string(1 + std::count(text.begin(),
                                               text.begin() + static_cast<std::ptrdiff_t>(k),
                                               '\n')) +
                 " holds a character that is not a digit (byte " +
                 std::to_string(static_cast<unsigned char>(c)) + ")";
      }
    }
  }
  return {};
}

// Meshes read, kept for the next load of the same file (a robot's links share
// files; the rigid importer places a robot twice; a sweep, the Python bindings
// and the fuzz targets load the same robots again): keyed by the path, the
// scale's bits and the file's bytes, and valid while every other file assimp
// asked about answers as it did (the same bytes, or still absent). A kept mesh
// is the one the load would give. Bounded in bytes, least recently used first.
class MeshFileMemo {
 public:
  // The mesh kept for this load, or null; reads the other files again (so the
  // load's inputs are recorded as a load records them).
  std::shared_ptr<const TriangleMesh> find(const std::string& path, const Vec3& scale,
                                           const std::string& bytes) {
    std::shared_ptr<const Entry> entry;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      for (auto& [used, kept] : entries_) {
        if (kept->path != path || std::memcmp(&kept->scale, &scale, sizeof(Vec3)) != 0 ||
            kept->bytes != bytes)
          continue;
        used = ++clock_;
        entry = kept;
        break;
      }
    }
    if (entry == nullptr) return nullptr;
    for (const OtherFile& other : entry->others) {
      if (!other.opened) {
        std::error_code error;
        if (std::filesystem::exists(other.path, error) != other.found) return nullptr;
        continue;
      }
      try {
        const std::string now = readInputFile(other.path);
        if (!other.found || now != other.bytes) return nullptr;
      } catch (const InputFileError&) {
        if (other.found) return nullptr;
      }
    }
    return entry->mesh;
  }

  void keep(const std::string& path, const Vec3& scale, std::string bytes,
            std::vector<OtherFile> others, const TriangleMesh& mesh) {
    auto entry = std::make_shared<Entry>();
    entry->path = path;
    entry->scale = scale;
    entry->bytes = std::move(bytes);
    entry->others = std::move(others);
    entry->mesh = std::make_shared<const TriangleMesh>(mesh);
    std::size_t size = sizeof(Entry) + entry->path.size() + entry->bytes.size() +
                       mesh.vertices.size() * sizeof(Vec3) +
                       mesh.triangles.size() * sizeof(mesh.triangles[0]);
    for (const OtherFile& other : entry->others) size += other.path.size() + other.bytes.size();
    entry->size = size;
    if (size > kBudgetBytes / 4) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    while (!entries_.empty() && bytes_ + size > kBudgetBytes) {
      const auto oldest =
          std::min_element(entries_.begin(), entries_.end(),
                           [](const auto& a, const auto& b) { return a.first < b.first; });
      bytes_ -= oldest->second->size;
      entries_.erase(oldest);
    }
    entries_.emplace_back(++clock_, std::move(entry));
    bytes_ += size;
  }

 private:
  static constexpr std::size_t kBudgetBytes = 64u << 20;
  struct Entry {
    std::string path;
    Vec3 scale{};
    std::string bytes;
    std::vector<OtherFile> others;
    std::shared_ptr<const TriangleMesh> mesh;
    std::size_t size = 0;
  };
  std::mutex mutex_;
  // (last use, entry)
  std::vector<std::pair<std::uint64_t, std::shared_ptr<const Entry>>> entries_;
  std::size_t bytes_ = 0;
  std::uint64_t clock_ = 0;
};

MeshFileMemo& meshFileMemo() {
  static MeshFileMemo memo;
  return memo;
}

// assimp 5.2's COLLADA reader reads an array element's count attribute without
// checking that it is there: a <float_array> without one is a null read (a crash,
// a fuzz finding: 'couft="12"'). Such an element is refused before assimp reads
// the file. A problem in words, or "".
std::string colladaArrayProblem(const std::string& path, const std::string& text) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".dae") return {};
  for (const char* tag : {"<float_array", "<int_array", "<Name_array", "<IDREF_array",
                          "<bool_array", "<SIDREF_array", "<token_array"}) {
    for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1)) {
      const std::size_t end = std::min(text.find('>', at), text.size());
      const std::string element = text.substr(at, end - at);
      bool counted = false;  // a ' count=' attribute (not "count" inside a value)
      for (std::size_t k = element.find("count="); k != std::string::npos && !counted;
           k = element.find("count=", k + 1))
        counted = k > 0 && std::isspace(static_cast<unsigned char>(element[k - 1]));
      if (counted) continue;
      return "a COLLADA " + std::string(tag) + "> at line " +
             std::to_string(1 + std::count(text.begin(),
                                           text.begin() + static_cast<std::ptrdiff_t>(at), '\n')) +
             " has no count attribute";
    }
  }
  return {};
}

// assimp's reason may quote the file's bytes (a COLLADA element '<in\x90\x93t>', an
// STL's primitive type 'ts\xa8e', fuzz findings): bytes past ASCII as \xNN, so the
// message stays valid UTF-8 for the JSON it reaches.
std::string assimpReason(const Assimp::Importer& importer) {
  std::string reason;
  for (const char c : std::string(importer.GetErrorString())) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x80) {
      reason += c;
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      reason += {'\\', 'x', kHex[byte >> 4], kHex[byte & 0xF]};
    }
  }
  return reason;
}

// A mesh file's bytes through readInputFile (a regular file within the budget,
// recorded), or a throw of meshError.
std::string readMeshBytes(const std::string& path) {
  try {
    return readInputFile(path);
  } catch (const InputFileError& e) {
    meshError(path, e.problem());
  }
}

// A mesh file as read: its triangles as collect leaves them, unscaled (with
// normals and materials when read for display), and the other files assimp
// asked about (what a kept mesh depends on).
struct MeshRead {
  ShadedMesh shaded;  // (its bytes unused)
  std::vector<OtherFile> asked;
};

// The materials of `scene` into `out` (at least one).
void readMaterials(const aiScene& scene, ShadedMesh& out) {
  for (unsigned k = 0; k < scene.mNumMaterials; ++k) {
    const aiMaterial& material = *scene.mMaterials[k];
    MeshMaterial m;
    m.name = material.GetName().C_Str();
    aiColor4D diffuse;
    if (material.Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == AI_SUCCESS) {
      m.hasColor = true;
      m.rgba = {diffuse.r, diffuse.g, diffuse.b, diffuse.a};
      ai_real opacity = 1;
      if (material.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) m.rgba[3] = opacity;
      for (double& c : m.rgba) c = std::isfinite(c) ? std::clamp(c, 0.0, 1.0) : 1.0;
    }
    out.materials.push_back(std::move(m));
  }
  // (A mesh naming no material of the file: one of the reader's own.)
  if (out.materials.empty() ||
      std::find(out.materialOf.begin(), out.materialOf.end(), scene.mNumMaterials) !=
          out.materialOf.end())
    out.materials.push_back({"default", {0.7, 0.7, 0.7, 1.0}, false});
}

// The mesh file `path`, whose bytes are `bytes`, read by assimp in this process
// and checked against the budgets before and after the triangulation, or a
// throw of meshError.
MeshRead readMeshHere(const std::string& path, const std::string& bytes, bool shaded) {
  Assimp::Importer importer;
  auto* files = new InputFileSystem(path, bytes);  // the importer owns it
  importer.SetIOHandler(files);
  // ROS meshes are Z-up whatever a COLLADA file's <up_axis> says (as rviz reads them).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Read as it is, checked against the budgets, then triangulated: a polygon of
  // 200 000 corners is refused here instead of hanging the triangulator.
  const aiScene* scene = importer.ReadFile(path, 0);
  if (scene == nullptr) {
    const std::string reason = assimpReason(importer);
    meshError(path, !files->refused.empty()
                        ? "cannot be read: " + files->refused
                        : "cannot be read (" +
                              (reason.empty() ? std::string("unknown format") : reason) + ")");
  }
  // A file without geometry (an empty or skeleton-only COLLADA scene): assimp
  // stands a placeholder skeleton mesh in for it and flags the scene incomplete.
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mNumMeshes == 0)
    meshError(path, "has no geometry (no mesh in the file)");
  if (const std::string problem = meshBudgetProblem(*scene, false); !problem.empty())
    meshError(path, problem + " (docs/scene-format.md#limits)");
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                       aiProcess_SortByPType);
  if (scene == nullptr) meshError(path, "cannot be triangulated (" + assimpReason(importer) + ")");
  if (const std::string problem = meshBudgetProblem(*scene, true); !problem.empty())
    meshError(path, problem + " (docs/scene-format.md#limits)");
  MeshRead out;
  // Unscaled: loadMesh multiplies by its scale after, the same product as here.
  if (scene->mRootNode != nullptr)
    collect(*scene, {1, 1, 1}, out.shaded.mesh, shaded ? &out.shaded : nullptr);
  if (shaded) readMaterials(*scene, out.shaded);
  out.asked = std::move(files->asked);
  return out;
}

// A MeshRead as bytes, from the child that read it to its parent.
class MeshRecord {
 public:
  static std::string encode(const MeshRead& read) {
    MeshRecord r;
    r.vector(read.shaded.mesh.vertices);
    r.vector(read.shaded.mesh.triangles);
    r.vector(read.shaded.normals);
    r.vector(read.shaded.materialOf);
    r.value(read.shaded.materials.size());
    for (const MeshMaterial& m : read.shaded.materials) {
      r.text(m.name);
      r.value(m.rgba);
      r.value(m.hasColor);
    }
    r.value(read.asked.size());
    for (const OtherFile& f : read.asked) {
      r.text(f.path);
      r.value(f.found);
      r.value(f.opened);
      r.text(f.bytes);
    }
    return std::move(r.bytes_);
  }
  // A request to the reader's process: the file's path, its bytes, shaded.
  static std::string request(const std::string& path, const std::string& bytes, bool shaded) {
    MeshRecord r;
    r.text(path);
    r.text(bytes);
    r.value(shaded);
    return std::move(r.bytes_);
  }
  static void readRequest(std::string request, std::string& path, std::string& bytes,
                          bool& shaded) {
    MeshRecord r;
    r.bytes_ = std::move(request);
    r.text("(request)", path);
    r.text(path, bytes);
    r.value(path, shaded);
  }
  // Throws meshError on a record cut short (a child that did not finish writing).
  static MeshRead decode(const std::string& path, std::string bytes) {
    MeshRecord r;
    r.bytes_ = std::move(bytes);
    MeshRead read;
    r.vector(path, read.shaded.mesh.vertices);
    r.vector(path, read.shaded.mesh.triangles);
    r.vector(path, read.shaded.normals);
    r.vector(path, read.shaded.materialOf);
    read.shaded.materials.resize(r.count(path));
    for (MeshMaterial& m : read.shaded.materials) {
      r.text(path, m.name);
      r.value(path, m.rgba);
      r.value(path, m.hasColor);
    }
    read.asked.resize(r.count(path));
    for (OtherFile& f : read.asked) {
      r.text(path, f.path);
      r.value(path, f.found);
      r.value(path, f.opened);
      r.text(path, f.bytes);
    }
    return read;
  }

 private:
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    value(s.size());
    bytes_ += s;
  }
  const char* take(const std::string& path, std::size_t size) {
    if (size > bytes_.size() - at_) meshError(path, "the reader's process sent a record cut short");
    const char* from = bytes_.data() + at_;
    at_ += size;
    return from;
  }
  template <typename T>
  void value(const std::string& path, T& v) {
    std::memcpy(&v, take(path, sizeof v), sizeof v);
  }
  std::size_t count(const std::string& path) {
    std::size_t n = 0;
    value(path, n);
    if (n > bytes_.size()) meshError(path, "the reader's process sent a record cut short");
    return n;
  }
  template <typename T>
  void vector(const std::string& path, std::vector<T>& v) {
    v.resize(count(path));
    if (!v.empty()) std::memcpy(v.data(), take(path, v.size() * sizeof(T)), v.size() * sizeof(T));
  }
  void text(const std::string& path, std::string& s) {
    const std::size_t n = count(path);
    s.assign(take(path, n), n);
  }
  std::string bytes_;
  std::size_t at_ = 0;
};

// How long assimp may take to read a mesh file before it counts as a hang (s).
constexpr int kMeshReadSeconds = 30;

// The mesh reader's process's answer to a request (MeshRecord::request): "K"
// and the MeshRecord, or "E" and the error's message.
std::string answerMeshRequest(const std::string& request) {
  std::string path, bytes;
  try {
    bool shaded = false;
    MeshRecord::readRequest(request, path, bytes, shaded);
    return "K" + MeshRecord::encode(readMeshHere(path, bytes, shaded));
  } catch (const std::exception& e) {
    return std::string("E") + e.what();
  } catch (...) {
    return "Emesh '" + path + "': an unknown error while reading it";
  }
}

// The process that reads mesh files for this one (forked at the first read).
ChildServer& meshReader() {
  static ChildServer reader(&answerMeshRequest);
  return reader;
}

// The mesh file `path`, whose bytes are `bytes`, read and checked, or a throw
// of meshError. A mesh file is untrusted input, and assimp 5.2's readers crash
// on some malformed files (a null read in the COLLADA reader, a fuzz finding of
// stop 39; an array without a count, refused below before assimp sees it). So
// assimp reads it in a child process (meshReader, a ChildServer kept for the
// next file): a crash, an abort or a hang there ends only the child, and the
// file is refused with what happened (exit 2 for the command line, as any bad
// mesh). The child sends the triangles back; the files it read are recorded
// here as this process's inputs. Where no child can be started, the file is
// read in this process.
MeshRead readMesh(const std::string& path, const std::string& bytes, bool shaded) {
  if (const std::string problem = colladaIndexProblem(path, bytes); !problem.empty())
    meshError(path, problem);
  if (const std::string problem = colladaArrayProblem(path, bytes); !problem.empty())
    meshError(path, problem);
  const ChildOutcome outcome = meshReader().ask(MeshRecord::request(path, bytes, shaded), kMeshReadSeconds);
  switch (outcome.kind) {
    case ChildOutcome::kNotStarted:
      return readMeshHere(path, bytes, shaded);
    case ChildOutcome::kTimedOut:
      meshError(path, "assimp took more than " + std::to_string(kMeshReadSeconds) +
                          " s to read it (a hang): refused");
    case ChildOutcome::kCrashed:
      meshError(path, "assimp's reader crashed on it (" + outcome.how() +
                          "; a bug of assimp's on a malformed file): refused");
    case ChildOutcome::kAnswered:
      break;
  }
  if (outcome.answer.empty()) meshError(path, "the reader's process sent no answer");
  if (outcome.answer[0] == 'E') throw std::runtime_error(outcome.answer.substr(1));
  MeshRead read = MeshRecord::decode(path, outcome.answer.substr(1));
  for (const OtherFile& f : read.asked)
    if (f.opened && f.found) InputFileLog::record(f.path);
  return read;
}

// A mesh as collected: some triangles, finite vertices, some area. Throws meshError.
void checkGeometry(const std::string& path, const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) meshError(path, "has no triangles");
  for (const Vec3& v : mesh.vertices) {
    if (!isFinite(v)) meshError(path, "has a vertex that is not a finite number");
  }
  // Triangles that all collapse to a line or a point enclose nothing to fill.
  const auto area = [&](const std::array<std::int32_t, 3>& t) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    return norm(cross(mesh.vertices[static_cast<std::size_t>(t[1])] - a,
                      mesh.vertices[static_cast<std::size_t>(t[2])] - a));
  };
  if (std::none_of(mesh.triangles.begin(), mesh.triangles.end(),
                   [&](const auto& t) { return area(t) > 0.0; }))
    meshError(path, "has no triangle of non-zero area: no geometry to fill");
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, const Vec3& scale) {
  check::finite("loadMesh", "scale", scale, "");
  if (scale.x == 0.0 || scale.y == 0.0 || scale.z == 0.0)
    meshError(path, "the scale (" + std::to_string(scale.x) + ", " + std::to_string(scale.y) +
                        ", " + std::to_string(scale.z) +
                        ") has a zero factor: the mesh would have no volume");
  std::string bytes = readMeshBytes(path);
  if (const auto kept = meshFileMemo().find(path, scale, bytes)) return *kept;
  MeshRead read = readMesh(path, bytes, false);
  TriangleMesh mesh = std::move(read.shaded.mesh);
  for (Vec3& v : mesh.vertices) v = {v.x * scale.x, v.y * scale.y, v.z * scale.z};
  checkGeometry(path, mesh);
  // A mirroring scale (an odd number of negative factors) turns the winding inside out.
  if (scale.x * scale.y * scale.z < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  meshFileMemo().keep(path, scale, std::move(bytes), std::move(read.asked), mesh);
  return mesh;
}

ShadedMesh loadShadedMesh(const std::string& path) {
  std::string bytes = readMeshBytes(path);
  ShadedMesh out = std::move(readMesh(path, bytes, true).shaded);
  out.bytes = std::move(bytes);
  checkGeometry(path, out.mesh);
  return out;
}

}  // namespace robophi::build
