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
// through the gear) on their joints, with targets where they start.
void holdByActuators(RigidTree& tree, const std::vector<double>& q,
                     const build::MjcfExtras& extras) {
  const auto n = static_cast<std::size_t>(tree.multibody.velocityCount);
  tree.inputs.servoStiffness.assign(n, 0.0);
  tree.inputs.servoDamping.assign(n, 0.0);
  tree.inputs.servoTarget.assign(n, 0.0);
  for (const MultibodyBody& body : tree.multibody.bodies)
    if (velocityCountOf(body.joint) == 1)
      tree.inputs.servoTarget[static_cast<std::size_t>(body.vStart)] =
          q[static_cast<std::size_t>(body.qStart)];
  for (const build::MjcfActuator& a : extras.actuators)
    if (a.kind == build::MjcfActuator::Kind::kPosition)
      tree.inputs.servoStiffness[static_cast<std::size_t>(a.velocityIndex)] +=
          a.gain * a.gear * a.gear;
  tree.compensateGravity = true;
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
    const auto tree = static_cast<std::size_t>(placed.tree);
    holdByActuators(built.model.rigidTrees[tree], built.initial.treePositions[tree], extras);
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
