#include "scene/scene_objects.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robophi/build/calibration.h"
#include "robophi/build/objects.h"
#include "scene/scene_mesh.h"
#include "scene/scene_robots.h"

namespace robophi::scene {

namespace {

using build::GeneratedObject;
using build::kMaxParticlesPerObject;
using build::SpringSettings;

const char* kMass = "kg";
const char* kMetres = "m";

// The type names and the generator each stands for.
struct TypeName {
  const char* name;
  const char* kind;
};
constexpr TypeName kTypes[] = {
    {"rope", "rope"},   {"chain", "rope"},          {"bar", "bar"},     {"box", "box"},
    {"cube", "box"},    {"plate", "plate"},         {"cloth", "plate"}, {"ball", "ball"},
    {"wheel", "wheel"}, {"particles", "particles"}, {"arm", "arm"},     {"vehicle", "vehicle"},
    {"hand", "hand"},  // io/scene_robots.cpp
    {"mesh", "mesh"},  // scene/scene_mesh.cpp
};

// `cells`: an integer n (n in every direction) or an array of `count` integers >= 1.
std::optional<std::array<int, 3>> readCells(ObjectReader& r, std::size_t count, bool required) {
  const nlohmann::json* value = r.member("cells");
  const std::string at = r.memberPointer("cells");
  if (value == nullptr) {
    if (required && r.valid()) r.missing("cells", fmt::format("{} integers >= 1", count));
    return std::nullopt;
  }
  std::array<int, 3> cells{1, 1, 1};
  const auto readOne = [&](const nlohmann::json& v, const std::string& p, std::size_t i) {
    if (!v.is_number_integer() || v.get<std::int64_t>() < 1 || v.get<std::int64_t>() > 100000) {
      r.sink().error(
          p, fmt::format("'cells': expected an integer in [1, 100000], got {}", describeJson(v)));
      return false;
    }
    cells[i] = v.get<int>();
    return true;
  };
  if (value->is_number()) {
    if (!readOne(*value, at, 0)) return std::nullopt;
    for (std::size_t i = 1; i < count; ++i) cells[i] = cells[0];
  } else if (value->is_array() && value->size() == count) {
    bool ok = true;
    for (std::size_t i = 0; i < count; ++i)
      ok = readOne((*value)[i], fmt::format("{}/{}", at, i), i) && ok;
    if (!ok) return std::nullopt;
  } else {
    r.sink().error(
        at, fmt::format("'cells': expected an integer or an array of {} integers, got {}", count,
                        describeJson(*value)));
    return std::nullopt;
  }
  // The builder checks the lattice against the size budget before it allocates.
  return cells;
}

// Each generator: reads its parameters; returns false if any is missing or bad.
bool readRope(ObjectReader& r, GeneratedObject& out) {
  const auto start = r.vec3("start", kMetres, true);
  const auto end = r.vec3("end", kMetres, true);
  const auto count = r.integer("particles", 2, true);
  const auto mass = r.number("mass", Bound::kPositive, kMass, true);
  const auto radius = r.number("radius", Bound::kPositive, kMetres);
  const SpringSettings springs = readSprings(r);
  if (!start || !end || !count || !mass) return false;
  out = build::makeRope({*start, *end, *count, *mass, radius.value_or(0.0)});
  build::resolveSprings(out, springs);
  return true;
}

bool readBox(ObjectReader& r, GeneratedObject& out, bool cube) {
  const auto center = r.vec3("center", kMetres, true);
  std::optional<Vec3> size;
  if (cube) {
    const auto side = r.number("size", Bound::kPositive, kMetres, true);
    if (side) size = Vec3{*side, *side, *side};
  } else {
    size = r.vec3("size", kMetres, true);
    if (size && !(size->x > 0.0 && size->y > 0.0 && size->z > 0.0)) {
      r.sink().error(r.memberPointer("size"),
                     fmt::format("'size' must be > 0 m in each direction, got [{}, {}, {}]",
                                 size->x, size->y, size->z));
      size.reset();
    }
  }
  const auto cells = readCells(r, 3, true);
  const auto mass = r.number("mass", Bound::kPositive, kMass, true);
  const auto radius = r.number("radius", Bound::kPositive, kMetres);
  const SpringSettings springs = readSprings(r);
  // Elastic moduli instead of spring stiffness (docs/robotics.md#bar-calibration-experiment-1).
  const auto young = r.number("youngModulus", Bound::kPositive, "Pa");
  const auto shear = r.number("shearModulus", Bound::kPositive, "Pa");
  const auto facets = r.boolean("facets");  // MODEL §3.8 flat faces, default on
  if (!center || !size || !cells || !mass) return false;
  build::BoxSpec spec{*center, *size, *cells, *mass, radius.value_or(0.0)};
  spec.facets = facets.value_or(true);
  out = build::makeBox(spec);
  build::resolveSprings(out, springs);
  if (young) build::calibrateLattice(out, spec, *young, shear);
  return applyRotation(r, out, *center);
}

bool readPlate(ObjectReader& r, GeneratedObject& out) {
  const auto center = r.vec3("center", kMetres, true);
  auto size = r.numbers("size", 2, "[Lx, Ly] (m)", true);
  if (size && !((*size)[0] > 0.0 && (*size)[1] > 0.0)) {
    r.sink().error(r.memberPointer("size"), fmt::format("'size' must be > 0 m in each direction, "
                                                        "got [{}, {}]",
                                                        (*size)[0], (*size)[1]));
    size.reset();
  }
  const auto thickness = r.number("thickness", Bound::kPositive, kMetres);
  const auto cells = readCells(r, 2, true);
  const auto mass = r.number("mass", Bound::kPositive, kMass, true);
  const auto radius = r.number("radius", Bound::kPositive, kMetres);
  const SpringSettings springs = readSprings(r);
  const auto facets = r.boolean("facets");  // MODEL §3.8 flat faces, default on
  if (!center || !size || !cells || !mass) return false;
  out = build::makePlate({*center,
                          (*size)[0],
                          (*size)[1],
                          thickness.value_or(0.0),
                          {(*cells)[0], (*cells)[1]},
                          *mass,
                          radius.value_or(0.0),
                          facets.value_or(true)});
  // A single layer bends only through its TS: default κ_b = 0.1 κ h².
  build::resolveSprings(out, springs, 0.1);
  return applyRotation(r, out, *center);
}

bool readBall(ObjectReader& r, GeneratedObject& out) {
  const auto center = r.vec3("center", kMetres, true);
  const auto radius = r.number("radius", Bound::kPositive, kMetres, true);
  const auto cells = r.integer("cells", 1);
  const auto mass = r.number("mass", Bound::kPositive, kMass, true);
  const auto particleRadius = r.number("particleRadius", Bound::kPositive, kMetres);
  const SpringSettings springs = readSprings(r);
  const auto round = r.boolean("round");  // MODEL §3.1 a round ball, default on
  if (cells && *cells > 400) {
    r.sink().error(r.memberPointer("cells"), fmt::format("'cells' must be <= 400, got {}", *cells));
    return false;
  }
  if (!center || !radius || !mass || (r.member("cells") && !cells)) return false;
  out = build::makeBall({*center, *radius, cells.value_or(1), *mass, particleRadius.value_or(0.0),
                         round.value_or(true)});
  build::resolveSprings(out, springs);
  return applyRotation(r, out, *center);
}

bool readWheel(ObjectReader& r, GeneratedObject& out) {
  const auto center = r.vec3("center", kMetres, true);
  const auto radius = r.number("radius", Bound::kPositive, kMetres, true);
  const auto width = r.number("width", Bound::kPositive, kMetres, true);
  const auto axis = r.vec3("axis", "-");
  const auto rim = r.integer("rimParticles", 3);
  const auto mass = r.number("mass", Bound::kPositive, kMass, true);
  const SpringSettings springs = readSprings(r);
  if (!center || !radius || !width || !mass || (r.member("rimParticles") && !rim)) return false;
  out = build::makeWheel(
      {*center, *radius, *width, axis.value_or(Vec3{0, 1, 0}), rim.value_or(16), *mass, 0.0});
  build::resolveSprings(out, springs);
  return true;
}

// "particles": explicit particles; their connectors are read after placement.
bool readParticles(ObjectReader& r, SceneObject& object) {
  r.allow({"connectors"});
  const nlohmann::json* list = r.member("particles");
  const std::string at = r.memberPointer("particles");
  if (list == nullptr) {
    if (r.valid()) r.missing("particles", "an array of {\"position\", \"mass\", \"radius\"}");
    return false;
  }
  if (!list->is_array() || list->empty()) {
    r.sink().error(at, fmt::format("'particles': expected a non-empty array of particles, got {}",
                                   describeJson(*list)));
    return false;
  }
  bool ok = true;
  auto& g = object.geometry;
  for (std::size_t i = 0; i < list->size(); ++i) {
    ObjectReader p(r.sink(), (*list)[i], fmt::format("{}/{}", at, i),
                   fmt::format("particle {} of '{}'", i, object.name));
    const auto position = p.vec3("position", kMetres, true);
    const auto mass = p.number("mass", Bound::kPositive, kMass, true);
    const auto radius = p.number("radius", Bound::kPositive, kMetres, true);
    const auto velocity = p.vec3("velocity", "m/s");
    const auto fixed = p.boolean("fixed");
    p.finish();
    ok = ok && position && mass && radius;
    g.position.push_back(position.value_or(Vec3{}));
    g.mass.push_back(mass.value_or(1.0));
    g.radius.push_back(radius.value_or(1.0));
    object.velocity.push_back(velocity.value_or(Vec3{}));
    g.fixed.push_back(fixed.value_or(false));
  }
  return ok;
}

// "fixed": true, false, or a list of local indices (negative counts from the end).
bool readFixed(ObjectReader& r, SceneObject& object) {
  const nlohmann::json* value = r.member("fixed");
  if (value == nullptr || !object.valid) return true;
  const auto n = static_cast<std::int64_t>(object.geometry.size());
  const std::string at = r.memberPointer("fixed");
  if (value->is_boolean()) {
    if (value->get<bool>()) object.geometry.fixed.assign(object.geometry.size(), true);
    return true;
  }
  if (!value->is_array()) {
    r.sink().error(at, fmt::format("'fixed': expected true, false or an array of particle "
                                   "indices, got {}",
                                   describeJson(*value)));
    return false;
  }
  bool ok = true;
  for (std::size_t k = 0; k < value->size(); ++k) {
    const auto& item = (*value)[k];
    const std::string itemAt = fmt::format("{}/{}", at, k);
    if (!item.is_number_integer()) {
      r.sink().error(itemAt, fmt::format("'fixed[{}]': expected a particle index, got {}", k,
                                         describeJson(item)));
      ok = false;
      continue;
    }
    const auto index = item.get<std::int64_t>();
    if (index < -n || index >= n) {
      r.sink().error(itemAt, fmt::format("'fixed[{}]': index {} is out of range: {} '{}' has {} "
                                         "particles (0..{} or -{}..-1)",
                                         k, index, object.kind, object.name, n, n - 1, n));
      ok = false;
      continue;
    }
    object.geometry.fixed[static_cast<std::size_t>(index < 0 ? index + n : index)] = true;
  }
  return ok;
}

}  // namespace

SpringSettings readSprings(ObjectReader& r, bool bend) {
  SpringSettings s;
  s.stiffness = r.number("stiffness", Bound::kNonNegative, "N/m");
  s.damping = r.number("damping", Bound::kNonNegative, "N·s/m");
  if (bend) {
    s.bendStiffness = r.number("bendStiffness", Bound::kNonNegative, "N·m/rad");
    s.bendDamping = r.number("bendDamping", Bound::kNonNegative, "N·m·s/rad");
  } else {
    s.bendStiffness = 0.0;
    s.bendDamping = 0.0;
  }
  // The default stiffness comes from a natural frequency, never from the step.
  if (const auto omega = r.number("naturalFrequency", Bound::kPositive, "rad/s")) {
    if (s.stiffness)
      r.sink().error(r.memberPointer("naturalFrequency"),
                     "'naturalFrequency' sets the default of 'stiffness': give one of them, not "
                     "both");
    s.naturalFrequency = *omega;
  }
  return s;
}

bool applyRotation(ObjectReader& r, GeneratedObject& object, const Vec3& pivot) {
  const auto axisAngle = r.numbers("rotation", 4, "[ax, ay, az, angle (rad)]");
  const auto rpy = r.vec3("rpy", "rad");
  bool ok = true;
  if (axisAngle) {
    const Vec3 axis{(*axisAngle)[0], (*axisAngle)[1], (*axisAngle)[2]};
    if (!(norm(axis) > 0.0)) {
      r.sink().error(r.memberPointer("rotation"), "'rotation': the axis [ax, ay, az] is zero");
      ok = false;
    } else {
      build::rotateObject(object, pivot, axis, (*axisAngle)[3]);
    }
  }
  if (rpy) build::rotateObjectRpy(object, pivot, *rpy);
  return ok;
}

const std::vector<std::string>& objectTypeNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const auto& t : kTypes) list.emplace_back(t.name);
    return list;
  }();
  return names;
}

SceneObject readSceneObject(DiagnosticSink& sink, const nlohmann::json& entry,
                            const std::string& pointer, const std::string& sceneDirectory) {
  SceneObject object;
  object.pointer = pointer;
  const std::size_t errorsBefore = sink.errorCount();
  ObjectReader r(sink, entry, pointer, fmt::format("object {}", pointer));
  if (!r.valid()) return object;
  object.name = r.string("name", true).value_or("");
  const auto type = r.string("type", true);
  const std::string what = fmt::format("{} '{}'", type.value_or("object"), object.name);
  ObjectReader reader(sink, entry, pointer, what);
  // "material" is read by the contact keys (src/collision/contact_scene.cpp).
  reader.allow({"name", "type", "fixed", "material"});
  if (r.member("name") && r.member("name")->is_string() && object.name.empty())
    sink.error(r.memberPointer("name"), "'name' must not be empty");
  if (object.name.find(':') != std::string::npos)
    sink.error(
        r.memberPointer("name"),
        fmt::format("'name' \"{}\" must not contain ':' (used in \"object:index\")", object.name));

  for (const auto& t : kTypes) {
    if (type && *type == t.name) object.kind = t.kind;
  }
  if (type && object.kind.empty()) {
    sink.error(r.memberPointer("type"),
               fmt::format("unknown object type \"{}\"{} (expected one of rope, chain, bar, box, "
                           "cube, plate, cloth, ball, wheel, particles, arm, vehicle, hand, mesh)",
                           *type, didYouMean(*type, objectTypeNames())));
  }
  const auto velocity = reader.vec3("velocity", "m/s");
  const auto angularVelocity = reader.vec3("angularVelocity", "rad/s");
  object.linearDamping = reader.numberOr("linearDamping", 0.0, Bound::kNonNegative, "N·s/m");
  object.rigid = reader.boolean("rigid").value_or(false);
  if (object.rigid && isRobotKind(object.kind) && !hasRigidRobot(object.kind))
    sink.error(reader.memberPointer("rigid"),
               fmt::format("'rigid': {} has joints; a robot is not one rigid body (the arm "
                           "and the hand can be rigid bodies)",
                           what));

  bool generated = false;
  const std::string& kind = object.kind;
  try {
    if (kind == "rope") generated = readRope(reader, object.geometry);
    if (kind == "bar" || kind == "box")
      generated = readBox(reader, object.geometry, *type == "cube");
    if (kind == "plate") generated = readPlate(reader, object.geometry);
    if (kind == "ball") generated = readBall(reader, object.geometry);
    if (kind == "wheel") generated = readWheel(reader, object.geometry);
    if (kind == "particles") generated = readParticles(reader, object);
    if (kind == "mesh") generated = readMesh(reader, object.geometry, sceneDirectory);
    if (isRobotKind(kind)) generated = readRobot(reader, object);
  } catch (const build::SpecError& e) {
    // The builders name the spec field, which is the scene key of the same name.
    sink.error(reader.memberPointer(e.field()), e.message());
    generated = false;
  }
  // Unknown keys are reported only when the type is known (else every key would be).
  if (!kind.empty()) reader.finish();

  if (generated && object.geometry.size() > static_cast<std::size_t>(kMaxParticlesPerObject)) {
    sink.error(pointer, fmt::format("{} has {} particles, more than {}", what,
                                    object.geometry.size(), kMaxParticlesPerObject));
    generated = false;
  }
  object.valid = generated;
  if (generated) {
    const std::size_t n = object.geometry.size();
    object.geometry.fixed.resize(n, false);
    object.velocity.resize(n, velocity.value_or(Vec3{}));
    if (velocity && kind == "particles") {
      // The object's velocity is the default of each particle's own.
      const auto& list = entry.at("particles");
      for (std::size_t i = 0; i < n; ++i)
        if (!list[i].contains("velocity")) object.velocity[i] = *velocity;
    }
    if (angularVelocity) build::addSpin(object.geometry, *angularVelocity, object.velocity);
  }
  readFixed(reader, object);
  if (object.rigid) {
    object.rigidVelocity = velocity.value_or(Vec3{});
    object.rigidSpin = angularVelocity.value_or(Vec3{});
    if (std::any_of(object.geometry.fixed.begin(), object.geometry.fixed.end(), [](bool f) { return f; }))
      sink.error(reader.memberPointer("fixed"),
                 fmt::format("'fixed': {} is rigid: it moves as a whole (fix none of its particles)", what));
  }
  object.valid = generated && sink.errorCount() == errorsBefore;
  return object;
}

}  // namespace robophi::scene
