// A bare MJCF file as a scene (scene/scene_mjcf.h): the rigid tree MuJoCo's compiler
// and build::makeMjcfMultibody make of it, on the ground, held by its position
// actuators with gravity compensation.
#include "robophi/scene/scene_mjcf.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "robophi/build/input_files.h"
#include "robophi/build/mjcf_multibody.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/spec_error.h"

namespace robophi {

bool isMjcfPath(const std::string& path) { return build::isMjcfPath(path); }

namespace {

// The lowest point of the robot's surface particles (z, m); infinity: none.
double lowestSurface(const build::UrdfMultibody& robot,
                     const build::UrdfMultibodyPlacement& placement) {
  build::ModelBuilder trial;
  build::placeUrdfMultibody(trial, robot, placement);
  const Model& m = trial.model();
  double lowest = std::numeric_limits<double>::infinity();
  for (ParticleIndex i = 0; i < m.particleCount(); ++i)
    lowest = std::min(lowest, trial.positions()[static_cast<std::size_t>(i)].z - m.radius[i]);
  return lowest;
}

// Servos of the position actuators' gains (kp gear², MuJoCo's force kp (ctrl − gear q)
// through the gear) on their joints (the model's joints of the tree), with targets
// where they start, and every joint's gravity compensated.
void holdByActuators(Model& model, std::int32_t treeIndex, const build::MjcfExtras& extras) {
  const RigidTree& tree = model.rigidTrees[static_cast<std::size_t>(treeIndex)];
  for (const std::int32_t k : tree.jointOfRate)
    if (k >= 0) model.joints[static_cast<std::size_t>(k)].compensateGravity = true;
  for (const build::MjcfActuator& a : extras.actuators) {
    if (a.kind != build::MjcfActuator::Kind::kPosition) continue;
    const std::int32_t k = tree.jointOfRate[static_cast<std::size_t>(a.velocityIndex)];
    if (k >= 0) model.joints[static_cast<std::size_t>(k)].servoStiffness += a.gain * a.gear * a.gear;
  }
}

}  // namespace

SceneLoadResult loadMjcfFile(const std::string& path, const UrdfSceneOptions& options) {
  SceneLoadResult result;
  const build::InputFileLog read;
  build::InputFileLog::record(path);
  try {
    build::MjcfMultibodySpec spec;
    spec.path = path;
    build::MjcfExtras extras;
    build::UrdfMultibody robot = build::makeMjcfMultibody(spec, &extras);
    build::UrdfMultibodyPlacement placement;
    placement.particleSize = options.particleSize;
    placement.particlesPerBody = options.particlesPerLink;
    // A floating robot is set on the ground; a fixed one stays where the file puts it.
    const bool floating =
        std::any_of(robot.multibody.bodies.begin(), robot.multibody.bodies.end(),
                    [](const MultibodyBody& b) { return b.joint == BodyJointKind::kFree; });
    const double lowest = floating ? lowestSurface(robot, placement) : 0.0;
    if (std::isfinite(lowest) && lowest != 0.0)
      for (MultibodyBody& body : robot.multibody.bodies)
        if (body.parent == -1) body.X_PJ.translation.z -= lowest;
    for (const std::string& adjustment : robot.adjustments)
      result.warnings.push_back(Diagnostic{path, 0, 0, "", "adjusted: " + adjustment});
    build::ModelBuilder builder;
    builder.addPlane({{0, 0, 0}, {0, 0, 1}, 0});
    const build::PlacedUrdfMultibody placed = build::placeUrdfMultibody(builder, robot, placement);
    build::BuiltModel built = std::move(builder).build();
    holdByActuators(built.model, placed.tree, extras);
    Scene scene;
    scene.name = robot.multibody.name;
    scene.sourcePath = path;
    scene.model = std::move(built.model);
    scene.initial = std::move(built.initial);
    scene.run.duration = 2.0;
    scene.inputFiles = read.files();
    result.scene = std::move(scene);
  } catch (const build::UrdfError& e) {
    result.errors.push_back(Diagnostic{
        e.line() > 0 ? fmt::format("{}:{}", e.file(), e.line()) : e.file(), 0, 0, "", e.message()});
  } catch (const build::SpecError& e) {
    result.errors.push_back(Diagnostic{path, 0, 0, "", e.what()});
  }
  return result;
}

}  // namespace robophi
