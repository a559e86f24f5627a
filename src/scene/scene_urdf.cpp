// Scene objects {"type": "urdf"}: the keys → build::UrdfSpec → build::makeUrdfRobot.
#include "scene/scene_urdf.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "robophi/build/input_files.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/objects.h"
#include "robophi/build/spec_error.h"
#include "robophi/build/urdf.h"
#include "robophi/build/urdf_multibody.h"

namespace robophi::scene {

namespace {

// "orientation": [roll, pitch, yaw] (rad) or a quaternion [x, y, z, w].
std::optional<build::Frame> readOrientation(ObjectReader& r) {
  const nlohmann::json* value = r.member("orientation");
  if (value == nullptr) return build::Frame{};
  const auto bad = [&] {
    r.sink().error(r.memberPointer("orientation"),
                   fmt::format("'orientation': expected [roll, pitch, yaw] (rad) or a quaternion "
                               "[x, y, z, w], got {}",
                               describeJson(*value)));
    return std::optional<build::Frame>{};
  };
  if (!value->is_array() || (value->size() != 3 && value->size() != 4)) return bad();
  std::vector<double> v;
  for (const auto& x : *value) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) return bad();
    v.push_back(x.get<double>());
  }
  if (v.size() == 3) return build::Frame::fromXyzRpy({}, {v[0], v[1], v[2]});
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
  if (!(n > 0.0)) return bad();
  const double x = v[0] / n, y = v[1] / n, z = v[2] / n, w = v[3] / n;
  build::Frame f;
  f.axes[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
  f.axes[1] = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
  f.axes[2] = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
  return f;
}

// A path with roslaunch's $(optenv NAME default) or $(env NAME) expanded
// (build::substituteRosArgs), then, when relative, taken from the scene's folder.
std::optional<std::string> scenePath(ObjectReader& r, const std::string& pointer,
                                     const std::string& text, const std::string& directory) {
  std::filesystem::path p;
  try {
    p = build::substituteRosArgs(text);
  } catch (const std::invalid_argument& problem) {
    r.sink().error(pointer, problem.what());
    return std::nullopt;
  }
  if (p.is_relative() && !directory.empty()) p = std::filesystem::path(directory) / p;
  return p.string();
}

std::optional<std::vector<std::string>> readPaths(ObjectReader& r, const std::string& directory) {
  std::vector<std::string> paths;
  const nlohmann::json* value = r.member("packagePaths");
  if (value == nullptr) return paths;
  if (!value->is_array()) {
    r.sink().error(r.memberPointer("packagePaths"),
                   "'packagePaths': expected an array of folder paths (strings)");
    return std::nullopt;
  }
  for (std::size_t i = 0; i < value->size(); ++i) {
    const auto& item = (*value)[i];
    if (!item.is_string()) {
      r.sink().error(
          fmt::format("{}/{}", r.memberPointer("packagePaths"), i),
          fmt::format("'packagePaths': expected a folder path, got {}", describeJson(item)));
      return std::nullopt;
    }
    const auto p = scenePath(r, fmt::format("{}/{}", r.memberPointer("packagePaths"), i),
                             item.get<std::string>(), directory);
    if (!p) return std::nullopt;
    paths.push_back(*p);
  }
  return paths;
}

// "inertiaFromGeometry": true (every link) or ["link", ...] (MuJoCo's inertiafromgeom).
struct InertiaFromGeometry {
  bool all = false;
  std::vector<std::string> links;
};
std::optional<InertiaFromGeometry> readInertiaFromGeometry(ObjectReader& r) {
  InertiaFromGeometry result;
  const nlohmann::json* value = r.member("inertiaFromGeometry");
  if (value == nullptr) return result;
  if (value->is_boolean()) {
    result.all = value->get<bool>();
    return result;
  }
  if (value->is_array() && std::all_of(value->begin(), value->end(),
                                        [](const nlohmann::json& x) { return x.is_string(); })) {
    for (const auto& x : *value) result.links.push_back(x.get<std::string>());
    return result;
  }
  r.sink().error(r.memberPointer("inertiaFromGeometry"),
                 fmt::format("'inertiaFromGeometry': expected true, false or an array of URDF link "
                             "names, got {}",
                             describeJson(*value)));
  return std::nullopt;
}

}  // namespace

namespace {

// Calls set(joint, M_ii, q_i) for each joint of tree `treeIndex`, M(q) its mass
// matrix at the state's q: a servo holding the joint where it is.
template <class Set>
void forEachTreeJoint(Model& model, const State& state, std::int32_t treeIndex, Set set) {
  const RigidTree& tree = model.rigidTrees[static_cast<std::size_t>(treeIndex)];
  const Multibody& mb = tree.multibody;
  const std::vector<double>& q = state.treePositions[static_cast<std::size_t>(treeIndex)];
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  MultibodyKinematics kin;
  updateKinematics(mb, q.data(), kin);
  std::vector<double> M(n * n);
  massMatrix(mb, kin, M.data());
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t k = tree.jointOfRate[i];
    if (k < 0) continue;
    Joint& joint = model.joints[static_cast<std::size_t>(k)];
    // M(q)'s diagonal is >= 0; a link of no mass can round it to -1e-15..-1e-10
    // (a fuzz finding: a negative servo stiffness, refused by checkModel).
    set(joint, std::max(0.0, M[i * n + i]),
        q[static_cast<std::size_t>(mb.bodies[static_cast<std::size_t>(joint.treeBody)].qStart)]);
  }
}

}  // namespace

void holdRigidJoints(Model& model, const State& state, std::int32_t treeIndex) {
  constexpr double omega = 30.0;
  forEachTreeJoint(model, state, treeIndex, [](Joint& joint, double inertia, double q) {
    joint.servoStiffness = omega * omega * inertia;
    joint.servoDamping = 2.0 * omega * inertia;
    joint.servoTarget = q;
    joint.compensateGravity = true;
  });
}

void servoRigidJoints(Model& model, const State& state, std::int32_t treeIndex, double stiffness,
                      std::optional<double> damping) {
  forEachTreeJoint(model, state, treeIndex, [&](Joint& joint, double inertia, double q) {
    joint.servoStiffness = stiffness;
    joint.servoDamping = damping.value_or(2.0 * std::sqrt(stiffness * inertia));
    joint.servoTarget = q;
  });
}

SceneObject readUrdfObject(DiagnosticSink& sink, const nlohmann::json& entry,
                           const std::string& pointer, const std::string& sceneDirectory) {
  SceneObject object;
  object.pointer = pointer;
  object.kind = "urdf";
  const std::size_t errorsBefore = sink.errorCount();
  ObjectReader r(sink, entry, pointer, fmt::format("object {}", pointer));
  if (!r.valid()) return object;
  object.name = r.string("name", true).value_or("");
  ObjectReader reader(sink, entry, pointer, fmt::format("urdf '{}'", object.name));
  reader.allow({"name", "type", "material"});  // "material": scene_contact.cpp
  if (object.name.find(':') != std::string::npos || (entry.contains("name") && object.name.empty()))
    sink.error(r.memberPointer("name"),
               fmt::format("'name' \"{}\" must be non-empty, without ':'", object.name));
  build::UrdfSpec spec;
  const auto file = reader.string("file", true);
  const auto position = reader.vec3("position", "m");
  const auto orientation = readOrientation(reader);
  const auto fixedBase = reader.boolean("fixedBase");
  const auto paths = readPaths(reader, sceneDirectory);
  const auto size = reader.number("particleSize", Bound::kPositive, "m");
  const auto perLink = reader.integer("particlesPerLink", 1);
  const auto omega = reader.number("naturalFrequency", Bound::kPositive, "rad/s");
  const auto self = reader.boolean("selfCollision");
  const auto hold = reader.boolean("holdJoints");
  const auto roundWheels = reader.boolean("roundWheels");
  const bool rigid = reader.boolean("rigid").value_or(false);
  const auto balance = reader.boolean("balanceInertia");
  const auto fromGeometry = readInertiaFromGeometry(reader);
  if (const nlohmann::json* initial = reader.member("initialPositions")) {
    if (!initial->is_object()) {
      sink.error(reader.memberPointer("initialPositions"),
                 "'initialPositions': expected an object {\"joint\": q (rad or m)}");
    } else {
      for (const auto& [joint, q] : initial->items()) {
        if (!q.is_number() || !std::isfinite(q.get<double>()))
          sink.error(reader.memberPointer("initialPositions") + "/" + joint,
                     fmt::format("'initialPositions': '{}' must be a number (rad or m), got {}",
                                 joint, describeJson(q)));
        else
          spec.initialPositions[joint] = q.get<double>();
      }
    }
  }
  reader.finish();
  const auto path =
      file ? scenePath(reader, reader.memberPointer("file"), *file, sceneDirectory) : std::nullopt;
  if (!path || !orientation || !paths || !fromGeometry || sink.errorCount() != errorsBefore)
    return object;
  if (rigid) {
    // As rigid bodies (docs/robots.md "Rigid bodies"): the same keys, read by
    // build::makeUrdfMultibody; the particle importer's own (naturalFrequency,
    // roundWheels) have no meaning there.
    for (const char* key : {"naturalFrequency", "roundWheels"})
      if (entry.contains(key))
        sink.error(reader.memberPointer(key),
                   fmt::format("'{}' is a key of the particle importer; a rigid robot (\"rigid\": true) "
                               "has none", key));
    build::UrdfMultibodySpec rigidSpec;
    rigidSpec.path = *path;
    rigidSpec.packagePaths = *paths;
    rigidSpec.name = object.name;
    for (int c = 0; c < 3; ++c) {
      const Vec3& axis = orientation->axes[static_cast<std::size_t>(c)];
      rigidSpec.placement.rotation.m[0][c] = axis.x;
      rigidSpec.placement.rotation.m[1][c] = axis.y;
      rigidSpec.placement.rotation.m[2][c] = axis.z;
    }
    rigidSpec.placement.translation = position.value_or(Vec3{});
    rigidSpec.fixedBase = fixedBase.value_or(true);
    rigidSpec.balanceInertia = balance.value_or(true);
    rigidSpec.inertiaFromGeometry = fromGeometry->all;
    rigidSpec.inertiaFromGeometryLinks = fromGeometry->links;
    try {
      build::InputFileLog::record(rigidSpec.path);
      auto placed = std::make_shared<SceneObject::RigidUrdf>();
      placed->robot = build::makeUrdfMultibody(rigidSpec);
      placed->placement.particleSize = size.value_or(0.0);
      placed->placement.particlesPerBody = perLink.value_or(placed->placement.particlesPerBody);
      placed->placement.selfCollision = self.value_or(false);
      placed->holdJoints = hold.value_or(false);
      const build::UrdfMultibody& robot = placed->robot;
      placed->placement.q = neutralConfiguration(robot.multibody);
      for (const auto& initial : spec.initialPositions) {
        const std::string& joint = initial.first;  // (named: clang 14 captures no binding)
        const double q = initial.second;
        const auto it = std::find_if(robot.joints.begin(), robot.joints.end(),
                                     [&](const build::UrdfMultibodyJoint& j) { return j.urdfName == joint; });
        if (it == robot.joints.end() || it->positionIndex < 0) {
          std::vector<std::string> names;
          for (const build::UrdfMultibodyJoint& j : robot.joints) names.push_back(j.urdfName);
          sink.error(reader.memberPointer("initialPositions") + "/" + joint,
                     fmt::format("'initialPositions': the URDF has no moving joint '{}'{}", joint,
                                 didYouMean(joint, names)));
          continue;
        }
        placed->placement.q[static_cast<std::size_t>(it->positionIndex)] = q;
      }
      for (const build::UrdfWarning& w : robot.warnings)
        sink.warning(reader.memberPointer("file"), fmt::format("{}:{}: {}", w.file, w.line, w.message));
      for (const std::string& adjustment : robot.adjustments)
        sink.warning(reader.memberPointer("file"), "adjusted: " + adjustment);
      object.rigidUrdf = std::move(placed);
    } catch (const build::UrdfError& e) {
      sink.error(reader.memberPointer("file"), e.what());
    } catch (const build::SpecError& e) {
      sink.error(reader.memberPointer(e.field()), e.message());
    }
    object.valid = object.rigidUrdf != nullptr && sink.errorCount() == errorsBefore;
    return object;
  }
  for (const char* key : {"balanceInertia", "inertiaFromGeometry"})
    if (entry.contains(key))
      sink.error(reader.memberPointer(key),
                 fmt::format("'{}' is a key of a rigid robot (\"rigid\": true)", key));
  if (sink.errorCount() != errorsBefore) return object;
  spec.path = *path;
  spec.name = object.name;
  spec.placement = *orientation;
  spec.placement.origin = position.value_or(Vec3{});
  spec.fixedBase = fixedBase.value_or(true);
  spec.packagePaths = *paths;
  spec.particleSize = size.value_or(0.0);
  spec.particlesPerLink = perLink.value_or(spec.particlesPerLink);
  spec.naturalFrequency = omega.value_or(spec.naturalFrequency);
  spec.selfCollision = self.value_or(false);
  spec.holdJoints = hold.value_or(false);
  spec.roundWheels = roundWheels.value_or(true);
  try {
    build::InputFileLog::record(spec.path);
    auto robot = std::make_shared<build::UrdfRobot>(build::makeUrdfRobot(spec));
    for (const build::UrdfWarning& w : robot->warnings)
      sink.warning(reader.memberPointer("file"),
                   fmt::format("{}:{}: {}", w.file, w.line, w.message));
    object.urdf = std::move(robot);
  } catch (const build::UrdfError& e) {
    sink.error(reader.memberPointer("file"), e.what());
  } catch (const build::SpecError& e) {
    sink.error(reader.memberPointer(e.field()), e.message());
  }
  object.valid = object.urdf != nullptr && sink.errorCount() == errorsBefore;
  return object;
}

}  // namespace robophi::scene

namespace robophi {

bool isUrdfPath(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  return extension == ".urdf" || extension == ".xacro" || extension == ".URDF";
}

namespace {

// A bare rigid URDF's <mimic> joints follow their leaders (q = multiplier q_leader +
// offset) by a position servo (build::MimicSpec, run by the scene's controller)
// ω = 300 rad/s on the follower's own inertia: a gripper's second finger closes with
// its first.
void coupleMimics(const build::UrdfMultibody& robot, const Model& model, Scene& scene,
                  SceneLoadResult& result) {
  const auto indexOf = [&](const std::string& name) -> std::optional<std::size_t> {
    for (std::size_t k = 0; k < model.joints.size(); ++k)
      if (model.joints[k].name == name) return k;
    return std::nullopt;
  };
  constexpr double kHold = 30.0, kMimic = 300.0;  // holdRigidJoints' ω, the coupling's
  for (const build::UrdfMultibodyJoint& follower : robot.joints) {
    if (follower.mimicJoint.empty()) continue;
    const auto leader = std::find_if(robot.joints.begin(), robot.joints.end(), [&](const auto& j) {
      return j.urdfName == follower.mimicJoint;
    });
    const auto f = indexOf(follower.name);
    const auto l = leader == robot.joints.end() ? std::nullopt : indexOf(leader->name);
    if (!f || !l || *f == *l) continue;
    const double inertia = model.joints[*f].servoStiffness / (kHold * kHold);  // M_ii
    build::MimicSpec mimic;
    mimic.joint = *f;
    mimic.leader = *l;
    mimic.multiplier = follower.multiplier;
    mimic.offset = follower.offset;
    mimic.kp = kMimic * kMimic * inertia;
    mimic.kd = 2.0 * kMimic * inertia;
    scene.robotics.control.mimics.push_back(mimic);
    result.warnings.push_back(Diagnostic{
        scene.sourcePath, 0, 0, "",
        fmt::format("adjusted: joint '{}' follows '{}' (<mimic>) by a servo kp {:.4g}, kd {:.4g}",
                    follower.urdfName, follower.mimicJoint, mimic.kp, mimic.kd)});
  }
}

// A bare rigid URDF's default material: κ_c (N/m) and μ_c (N·s/m) a contact point.
constexpr double kRigidContactStiffness = 1e6;
constexpr double kRigidContactDamping = 100.0;

// A bare URDF as rigid bodies on the ground plane: its lowest surface particle's
// bottom at z = 0.
SceneLoadResult loadRigidUrdf(const std::string& path, const UrdfSceneOptions& options) {
  SceneLoadResult result;
  const auto fail = [&](std::string where, std::string message) {
    result.errors.push_back(Diagnostic{std::move(where), 0, 0, "", std::move(message)});
    return result;
  };
  const build::InputFileLog read;  // the URDF file and its meshes
  build::InputFileLog::record(path);
  try {
    build::UrdfMultibodySpec spec;
    spec.path = path;
    spec.packagePaths = options.packagePaths;
    spec.fixedBase = options.fixedBase.value_or(true);
    build::UrdfMultibody robot = build::makeUrdfMultibody(spec);
    if (!options.fixedBase) {
      // A wheeled base (two or more wheels: wheelCount) stands free on its wheels.
      if (build::wheelCount(robot) >= 2) {
        spec.fixedBase = false;
        robot = build::makeUrdfMultibody(spec);
      }
    }
    build::UrdfMultibodyPlacement placement;
    placement.particleSize = options.particleSize;
    placement.particlesPerBody = options.particlesPerLink;
    double lowest = std::numeric_limits<double>::infinity();
    {
      build::ModelBuilder trial;
      build::placeUrdfMultibody(trial, robot, placement);
      const Model& m = trial.model();
      for (ParticleIndex i = 0; i < m.particleCount(); ++i)
        lowest = std::min(lowest, trial.positions()[static_cast<std::size_t>(i)].z - m.radius[i]);
    }
    if (std::isfinite(lowest)) {
      spec.placement.translation.z -= lowest;
      robot = build::makeUrdfMultibody(spec);
    }
    for (const build::UrdfWarning& w : robot.warnings)
      result.warnings.push_back(Diagnostic{fmt::format("{}:{}", w.file, w.line), 0, 0, "", w.message});
    for (const std::string& adjustment : robot.adjustments)
      result.warnings.push_back(Diagnostic{path, 0, 0, "", "adjusted: " + adjustment});
    build::ModelBuilder builder;
    // A rigid robot's contacts are implicit in its step (docs/model.md §7): a stiff
    // contact costs no step, and keeps a wheel's rolling radius (the Husky sinks 0.4
    // mm and drives at 0.994 ωR, against 9 mm and 0.946 ωR at the particles' 1e4 N/m).
    Material contact;
    contact.contactStiffness = kRigidContactStiffness;
    contact.contactDamping = kRigidContactDamping;
    builder.addMaterial(contact);
    builder.addPlane({{0, 0, 0}, {0, 0, 1}, 0});
    const build::PlacedUrdfMultibody placed = build::placeUrdfMultibody(builder, robot, placement);
    Scene scene;
    scene.name = robot.multibody.name;
    scene.sourcePath = path;
    build::BuiltModel built = std::move(builder).build();
    scene::holdRigidJoints(built.model, built.initial, placed.tree);
    // Values past what can be simulated (a <mass value="1e300"/>) show in the servos
    // that hold the joints, whose squares the step's products reach: refused here,
    // naming the joint, not a run of NaN.
    for (const Joint& joint : built.model.joints) {
      const double kappa = joint.servoStiffness, beta = joint.servoDamping;
      if (!joint.inTree() || (std::isfinite(kappa * kappa) && std::isfinite(beta * beta))) continue;
      return fail(path, fmt::format("joint '{}': the servo that holds it would need κ = {} and "
                                    "β = {}: the bodies it moves are too heavy or their inertia "
                                    "too large to simulate (see their <inertial>)",
                                    joint.name, joint.servoStiffness, joint.servoDamping));
    }
    coupleMimics(robot, built.model, scene, result);
    scene.model = std::move(built.model);
    scene.initial = std::move(built.initial);
    scene.run.duration = 2.0;
    // Its joints' servos and its contacts are implicit (docs/model.md §7): nothing
    // stiff bounds the step and the energy error sees little of their error; steps
    // of at most MuJoCo's default 2 ms keep them accurate.
    scene.run.adaptive.maxStep = 2e-3;
    scene.inputFiles = read.files();
    result.scene = std::move(scene);
  } catch (const build::UrdfError& e) {
    return fail(e.line() > 0 ? fmt::format("{}:{}", e.file(), e.line()) : e.file(), e.message());
  } catch (const build::SpecError& e) {
    return fail(path, e.what());
  }
  return result;
}

}  // namespace

SceneLoadResult loadUrdfFile(const std::string& path, const UrdfSceneOptions& options) {
  if (options.rigid) return loadRigidUrdf(path, options);
  SceneLoadResult result;
  build::UrdfSpec spec;
  spec.path = path;
  spec.packagePaths = options.packagePaths;
  spec.particleSize = options.particleSize;
  spec.particlesPerLink = options.particlesPerLink;
  spec.holdJoints = true;
  const auto fail = [&](std::string where, std::string message) {
    result.errors.push_back(Diagnostic{std::move(where), 0, 0, "", std::move(message)});
    return result;
  };
  build::UrdfRobot robot;
  const build::InputFileLog read;  // the URDF file and its meshes
  build::InputFileLog::record(path);
  try {
    spec.fixedBase = options.fixedBase.value_or(true);
    robot = build::makeUrdfRobot(spec);
    if (!options.fixedBase) {
      // A wheeled base (two or more wheels: UrdfJoint::wheel) stands free on them.
      int wheels = 0;
      for (const build::UrdfJoint& j : robot.joints) wheels += j.wheel ? 1 : 0;
      if (wheels >= 2) {
        spec.fixedBase = false;
        robot = build::makeUrdfRobot(spec);
      }
    }
  } catch (const build::UrdfError& e) {
    return fail(e.line() > 0 ? fmt::format("{}:{}", e.file(), e.line()) : e.file(), e.message());
  } catch (const build::SpecError& e) {
    return fail(path, e.what());
  }
  // The scene's size budget (docs/scene-format.md#limits), as the scene loader holds a
  // {"type": "urdf"} object to it: refused before anything is built.
  std::size_t particles = 0, connectors = robot.linearSprings.size() + robot.torsionSprings.size() +
                                          robot.jointSprings.size();
  for (const build::ObjectPlacement& object : robot.objects) {
    particles += object.geometry.size();
    connectors += object.geometry.linearSprings.size() + object.geometry.torsionSprings.size() +
                  object.geometry.jointSprings.size();
  }
  if (particles > static_cast<std::size_t>(build::kMaxParticlesPerObject) ||
      connectors > static_cast<std::size_t>(build::kMaxConnectorsPerObject))
    return fail(path, fmt::format("the robot makes {} particles and {} connectors, more than the "
                                  "budget of a scene, {} particles and {} connectors "
                                  "(docs/scene-format.md#limits)",
                                  particles, connectors, build::kMaxParticlesPerObject,
                                  build::kMaxConnectorsPerObject));
  // On the ground: the lowest particle's bottom at z = 0 (carriers touch nothing).
  double lowest = std::numeric_limits<double>::infinity();
  for (const build::ObjectPlacement& object : robot.objects)
    for (std::size_t i = 0; i < object.geometry.size() && object.kind == "link"; ++i)
      lowest = std::min(lowest, object.geometry.position[i].z - object.geometry.radius[i]);
  // A round wheel's lowest point is its cylinder's (docs/contact.md "Round wheels").
  for (const build::ObjectPlacement& object : robot.objects)
    for (const RimRing& rim : object.geometry.rims) {
      if (!rim.isCylinder()) continue;
      const Vec3 hub = object.geometry.position[static_cast<std::size_t>(rim.hub)];
      const Vec3 along = object.geometry.position[static_cast<std::size_t>(rim.axisParticle)] - hub;
      const Vec3 axis = along / norm(along);
      const Vec3 center = hub + axis * rim.axialOffset;
      const double across = std::sqrt(std::max(0.0, 1.0 - axis.z * axis.z));
      lowest = std::min(lowest,
                        center.z - rim.sphereRadius * across - rim.halfLength * std::abs(axis.z));
    }
  build::translateUrdfRobot(robot, {0.0, 0.0, -lowest});
  for (const build::UrdfWarning& w : robot.warnings)
    result.warnings.push_back(
        Diagnostic{fmt::format("{}:{}", w.file, w.line), 0, 0, "", w.message});
  Scene scene;
  scene.name = robot.name;
  scene.sourcePath = path;
  scene.inputFiles = read.files();
  build::ModelBuilder builder;
  builder.addPlane({{0, 0, 0}, {0, 0, 1}, 0});
  try {
    // What the file's values make of the robot (a mass of 1e300 kg: a damping of
    // inf) is refused by the builder: bad input, named, exit 2.
    build::placeUrdfRobot(builder, robot);
  } catch (const build::SpecError& e) {
    return fail(path, e.what());
  } catch (const std::invalid_argument& e) {
    return fail(path, e.what());
  }
  build::BuiltModel built = std::move(builder).build();
  scene.model = std::move(built.model);
  scene.initial = std::move(built.initial);
  scene.run.duration = 2.0;
  scene.urdfRobots.push_back(std::make_shared<const build::UrdfRobot>(std::move(robot)));
  result.scene = std::move(scene);
  return result;
}

}  // namespace robophi
