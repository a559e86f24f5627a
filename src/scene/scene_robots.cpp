// Robot objects of a scene (docs/robotics.md): each entry's keys → its build
// spec (robophi/build/robots.h) → the builder. The keys' types and ranges are
// checked here, with their places in the file; what the builder refuses comes
// back as a SpecError naming the key (reported by readSceneObject).
#include "scene/scene_robots.h"

#include <fmt/format.h>

#include <memory>
#include <optional>
#include <utility>

#include "robophi/build/rigid_robots.h"
#include "robophi/build/robots.h"

namespace robophi::scene {

namespace {

// "stiffness", "damping", "naturalFrequency": the robot's structural LS.
build::RobotLinks readStructure(ObjectReader& r) {
  const build::SpringSettings s = readSprings(r, false);
  return {s.stiffness, s.damping, s.naturalFrequency};
}

// "axes": one axis [x, y, z] for every joint, or one per joint.
bool readAxes(ObjectReader& r, std::size_t joints, std::vector<Vec3>& axes) {
  const nlohmann::json* value = r.member("axes");
  if (value == nullptr) return true;
  const bool single = value->is_array() && value->size() == 3 && (*value)[0].is_number();
  if (!value->is_array() || (!single && value->size() != joints)) {
    r.sink().error(r.memberPointer("axes"),
                   fmt::format("'axes': expected one axis [x, y, z] or {} of them", joints));
    return false;
  }
  for (std::size_t i = 0; i < (single ? 1 : joints); ++i) {
    const nlohmann::json& v = single ? *value : (*value)[i];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number()) {
      r.sink().error(r.memberPointer("axes"), "'axes': each axis must be [x, y, z]");
      return false;
    }
    axes.push_back(Vec3{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()});
  }
  return true;
}

// "rigid": true (docs/robots.md "Rigid bodies"): the robot as rigid bodies, placed by
// build::placeUrdfMultibody, "particleSize" (m) the spacing of its links' contact
// particles (unset: about 30 a link); its joints' servos hold the start pose at
// jointStiffness (N·m/rad) and jointDamping (N·m·s/rad; unset: critical for the
// joint's own inertia at that stiffness, set at placement).
void makeRigid(ObjectReader& r, SceneObject& object, build::UrdfMultibody robot,
               double jointStiffness, std::optional<double> jointDamping,
               std::optional<double> particleSize) {
  auto rigid = std::make_shared<SceneObject::RigidUrdf>();
  rigid->robot = std::move(robot);
  rigid->placement.particleSize = particleSize.value_or(0.0);
  rigid->placement.q = neutralConfiguration(rigid->robot.multibody);
  rigid->servoStiffness = jointStiffness;
  rigid->servoDamping = jointDamping;
  for (const std::string& adjustment : rigid->robot.adjustments)
    r.sink().warning(r.memberPointer("type"), "adjusted: " + adjustment);
  object.rigidUrdf = std::move(rigid);
}

bool readArm(ObjectReader& r, SceneObject& object) {
  build::ArmSpec spec;
  const auto base = r.vec3("base", "m", true);
  const auto direction = r.vec3("direction", "-");
  const nlohmann::json* links = r.member("links");
  r.member("axes");
  const auto mass = r.number("mass", Bound::kPositive, "kg", true);
  spec.width = r.number("width", Bound::kPositive, "m");
  const auto perLink = r.integer("particlesPerLink", 2);
  const auto radius = r.number("radius", Bound::kPositive, "m");
  spec.jointStiffness = r.numberOr("jointStiffness", 0.0, Bound::kNonNegative, "N·m/rad");
  spec.jointDamping = r.number("jointDamping", Bound::kNonNegative, "N·m·s/rad");
  spec.structure = readStructure(r);
  const auto particleSize =
      object.rigid ? r.number("particleSize", Bound::kPositive, "m") : std::nullopt;
  bool ok = base && mass && (!r.member("particlesPerLink") || perLink);
  spec.links.clear();
  if (links == nullptr) {
    r.missing("links", "an array of link lengths (m)");
    ok = false;
  } else if (!links->is_array() || links->empty()) {
    r.sink().error(r.memberPointer("links"), "'links': expected a non-empty array of lengths (m)");
    ok = false;
  } else {
    for (std::size_t i = 0; i < links->size(); ++i) {
      const auto v =
          checkNumber(r.sink(), (*links)[i], fmt::format("{}/{}", r.memberPointer("links"), i),
                      "links", Bound::kPositive, "m");
      ok = ok && v.has_value();
      spec.links.push_back(v.value_or(1.0));
    }
  }
  if (!ok || !readAxes(r, spec.links.size(), spec.axes)) return false;
  spec.base = *base;
  spec.direction = direction.value_or(Vec3{1, 0, 0});
  spec.mass = *mass;
  spec.particlesPerLink = perLink.value_or(3);
  spec.radius = radius.value_or(0.0);
  if (object.rigid) {
    makeRigid(r, object, build::makeRigidArm(spec, object.name), spec.jointStiffness,
              spec.jointDamping, particleSize);
    return true;
  }
  object.geometry = build::makeArm(spec);
  return true;
}

bool readVehicle(ObjectReader& r, SceneObject& object) {
  build::VehicleSpec spec;
  const auto center = r.vec3("center", "m", true);
  const auto size = r.vec3("size", "m", true);
  const auto chassisMass = r.number("mass", Bound::kPositive, "kg", true);
  const auto wheelRadius = r.number("wheelRadius", Bound::kPositive, "m", true);
  const auto wheelWidth = r.number("wheelWidth", Bound::kPositive, "m", true);
  const auto wheelMass = r.number("wheelMass", Bound::kPositive, "kg", true);
  const auto rim = r.integer("rimParticles", 6);
  spec.wheelbase = r.number("wheelbase", Bound::kPositive, "m");
  spec.track = r.number("track", Bound::kPositive, "m");
  const auto suspension = r.number("suspensionStiffness", Bound::kPositive, "N/m", true);
  spec.suspensionDamping = r.number("suspensionDamping", Bound::kNonNegative, "N·s/m");
  spec.axleDamping = r.numberOr("axleDamping", 0.0, Bound::kNonNegative, "N·m·s/rad");
  spec.wheelSpeed = r.numberOr("wheelSpeed", 0.0, Bound::kAny, "rad/s");
  spec.wheelGain = r.numberOr("wheelGain", 0.0, Bound::kNonNegative, "N·m·s/rad");
  spec.wheelTorque = r.numberOr("wheelTorque", 0.0, Bound::kAny, "N·m");
  spec.wheelTorqueLimit = r.number("wheelTorqueLimit", Bound::kPositive, "N·m");
  spec.structure = readStructure(r);
  if (!center || !size || !chassisMass || !wheelRadius || !wheelWidth || !wheelMass ||
      !suspension || (r.member("rimParticles") && !rim))
    return false;
  spec.center = *center;
  spec.size = *size;
  spec.mass = *chassisMass;
  spec.wheelRadius = *wheelRadius;
  spec.wheelWidth = *wheelWidth;
  spec.wheelMass = *wheelMass;
  spec.rimParticles = rim.value_or(12);
  spec.suspensionStiffness = *suspension;
  object.geometry = build::makeVehicle(spec);
  return true;
}

bool readHand(ObjectReader& r, SceneObject& object) {
  build::HandSpec spec;
  const auto center = r.vec3("center", "m", true);
  const auto palmRadius = r.number("palmRadius", Bound::kPositive, "m", true);
  const auto links = r.numbers("links", 3, "[proximal, middle, distal] (m)", true);
  const auto mass = r.number("mass", Bound::kPositive, "kg", true);
  spec.width = r.number("width", Bound::kPositive, "m");
  spec.jointStiffness = r.numberOr("jointStiffness", 0.0, Bound::kNonNegative, "N·m/rad");
  spec.jointDamping = r.number("jointDamping", Bound::kNonNegative, "N·m·s/rad");
  spec.spread = r.number("spread", Bound::kAny, "rad").value_or(0.0);
  spec.structure = readStructure(r);
  const auto particleSize =
      object.rigid ? r.number("particleSize", Bound::kPositive, "m") : std::nullopt;
  if (!center || !palmRadius || !links || !mass) return false;
  spec.center = *center;
  spec.palmRadius = *palmRadius;
  spec.links = {(*links)[0], (*links)[1], (*links)[2]};
  spec.mass = *mass;
  if (object.rigid) {
    makeRigid(r, object, build::makeRigidHand(spec, object.name), spec.jointStiffness,
              spec.jointDamping, particleSize);
    return true;
  }
  object.geometry = build::makeHand(spec);
  return true;
}

}  // namespace

bool isRobotKind(const std::string& kind) {
  return kind == "arm" || kind == "vehicle" || kind == "hand";
}

bool hasRigidRobot(const std::string& kind) { return kind == "arm" || kind == "hand"; }

bool readRobot(ObjectReader& r, SceneObject& object) {
  if (object.kind == "arm") return readArm(r, object);
  if (object.kind == "vehicle") return readVehicle(r, object);
  return readHand(r, object);
}

}  // namespace robophi::scene
