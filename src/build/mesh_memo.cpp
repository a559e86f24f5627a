#include "build/mesh_memo.h"

#include <algorithm>
#include <cstring>

// The digest and the comparison are bookkeeping, not behaviour to explore: a
// fuzz build's coverage instrumentation of their loops cost a third of a run.
#if defined(__clang__)
#define ROBOPHI_NO_COVERAGE __attribute__((no_sanitize("coverage")))
#else
#define ROBOPHI_NO_COVERAGE
#endif

namespace robophi::build::detail {

namespace {

// FNV-1a's prime over 64-bit words, each mixed (multiply, xor-shift) first.
ROBOPHI_NO_COVERAGE std::uint64_t mixWords(std::uint64_t hash, const void* data,
                                           std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t at = 0; at < bytes; at += sizeof(std::uint64_t)) {
    std::uint64_t word = 0;
    std::memcpy(&word, p + at, std::min(sizeof(word), bytes - at));
    word *= 0x9E3779B97F4A7C15ull;
    word ^= word >> 29;
    hash = (hash ^ word) * 0x100000001B3ull;
  }
  return hash;
}

std::size_t meshBytes(const TriangleMesh& mesh) {
  return mesh.vertices.size() * sizeof(Vec3) + mesh.triangles.size() * sizeof(mesh.triangles[0]);
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

}  // namespace

ROBOPHI_NO_COVERAGE std::uint64_t meshDigest(const TriangleMesh& mesh) {
  std::uint64_t hash = 0xCBF29CE484222325ull;
  const std::uint64_t sizes[2] = {mesh.vertices.size(), mesh.triangles.size()};
  hash = mixWords(hash, sizes, sizeof(sizes));
  hash = mixWords(hash, mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3));
  return mixWords(hash, mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
}

ROBOPHI_NO_COVERAGE bool sameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  // (memcmp of an empty vector's null data is undefined: compared only when not empty.)
  return a.vertices.size() == b.vertices.size() && a.triangles.size() == b.triangles.size() &&
         (a.vertices.empty() || std::memcmp(a.vertices.data(), b.vertices.data(),
                                            a.vertices.size() * sizeof(Vec3)) == 0) &&
         (a.triangles.empty() || std::memcmp(a.triangles.data(), b.triangles.data(),
                                             a.triangles.size() * sizeof(a.triangles[0])) == 0);
}

MeshWorkMemo& MeshWorkMemo::shared() {
  static MeshWorkMemo memo(64u << 20);
  return memo;
}

MeshWorkMemo::Entry* MeshWorkMemo::findLocked(const TriangleMesh& mesh, std::uint64_t digest) {
  for (const auto& entry : entries_) {
    if (entry->digest != digest || !sameMesh(*entry->mesh, mesh)) continue;
    entry->used = ++clock_;
    return entry.get();
  }
  return nullptr;
}

MeshWorkMemo::Entry& MeshWorkMemo::entryLocked(const TriangleMesh& mesh, std::uint64_t digest) {
  if (Entry* found = findLocked(mesh, digest)) return *found;
  auto entry = std::make_unique<Entry>();
  entry->digest = digest;
  entry->mesh = std::make_shared<const TriangleMesh>(mesh);
  entry->bytes = sizeof(Entry) + meshBytes(mesh);
  entry->used = ++clock_;
  bytes_ += entry->bytes;
  entries_.push_back(std::move(entry));
  return *entries_.back();
}

void MeshWorkMemo::trimLocked(const Entry* keep) {
  // A mesh whose work alone passes a quarter of the budget forgets its lattices.
  for (const auto& entry : entries_) {
    if (entry->bytes <= budgetBytes_ / 4) continue;
    for (const auto& kept : entry->lattices)
      entry->bytes -= kept.second->local.size() * sizeof(Vec3) + sizeof(MeshLattice);
    bytes_ -= entry->bytes;
    entry->lattices.clear();
    entry->bytes = sizeof(Entry) + meshBytes(*entry->mesh);
    bytes_ += entry->bytes;
  }
  while (bytes_ > budgetBytes_ && entries_.size() > 1) {
    auto oldest = entries_.end();
    for (auto at = entries_.begin(); at != entries_.end(); ++at)
      if (at->get() != keep && (oldest == entries_.end() || (*at)->used < (*oldest)->used))
        oldest = at;
    bytes_ -= (*oldest)->bytes;
    entries_.erase(oldest);
  }
  // A single mesh past the budget is not kept at all.
  if (bytes_ > budgetBytes_) {
    entries_.clear();
    bytes_ = 0;
  }
}

std::optional<double> MeshWorkMemo::volume(const TriangleMesh& mesh, std::uint64_t digest) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const Entry* entry = findLocked(mesh, digest);
  return entry != nullptr ? entry->volume : std::nullopt;
}

void MeshWorkMemo::keepVolume(const TriangleMesh& mesh, std::uint64_t digest, double volume) {
  const std::lock_guard<std::mutex> lock(mutex_);
  Entry& entry = entryLocked(mesh, digest);
  entry.volume = volume;
  trimLocked(&entry);
}

std::shared_ptr<const MeshLattice> MeshWorkMemo::lattice(const TriangleMesh& mesh,
                                                         std::uint64_t digest, double spacing) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const Entry* entry = findLocked(mesh, digest);
  if (entry == nullptr) return nullptr;
  for (const auto& kept : entry->lattices)
    if (sameBits(kept.first, spacing)) return kept.second;
  return nullptr;
}

void MeshWorkMemo::keepLattice(const TriangleMesh& mesh, std::uint64_t digest, double spacing,
                               std::shared_ptr<const MeshLattice> made) {
  const std::lock_guard<std::mutex> lock(mutex_);
  Entry& entry = entryLocked(mesh, digest);
  const std::size_t bytes = made->local.size() * sizeof(Vec3) + sizeof(MeshLattice);
  entry.lattices.emplace_back(spacing, std::move(made));
  entry.bytes += bytes;
  bytes_ += bytes;
  trimLocked(&entry);
}

}  // namespace robophi::build::detail
