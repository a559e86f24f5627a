#pragma once
/// \file
/// Scene files (JSON with // comments, SI units): docs/scene-format.md,
/// schema docs/scene.schema.json. Loading reports every error, never only the first,
/// each with its file:line:column, JSON pointer and, for a misspelt name, a suggestion.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robophi/adaptive_step.h"
#include "robophi/build/goals.h"
#include "robophi/build/tasks.h"
#include "robophi/build/urdf.h"
#include "robophi/model.h"
#include "robophi/state.h"
#include "robophi/sensors.h"
#include "robophi/world.h"

namespace robophi {

/// How the step size is chosen.
enum class StepMode : std::uint8_t {
  /// Energy-based adaptive step (ATS, MODEL §4); `dt` is the first trial step.
  kAdaptive,
  /// Constant step (CTS) of `dt`.
  kConstant,
};

/// How a scene asks to be run; the command line may override each field.
struct RunSettings {
  /// Model time to simulate (s), > 0.
  double duration = 1.0;
  /// Constant step δ (s), > 0; the first trial step in adaptive mode.
  double dt = 1.0e-4;
  StepMode stepMode = StepMode::kAdaptive;
  /// The adaptive controller's settings (used in adaptive mode): the scene's
  /// `run.adaptive` keys, one per field except initialStep (which is `dt`).
  AdaptiveStepSettings adaptive;
  Integrator integrator = Integrator::kVelocityVerlet;
  /// Frames per second written to particles.csv, > 0.
  double fps = 60.0;
};

/// The limits of a run (docs/scene-format.md#limits): a run is at least one step
/// (dt <= duration), takes at most kMaxRunSteps steps (constant steps, or the
/// fewest adaptive steps of at most maxStep) and writes at most kMaxRunFrames
/// frames and kMaxRunEnergyRows energy rows. Beyond them a run would overflow its
/// step counter or its files, or not end in a lifetime.
inline constexpr double kMaxRunSteps = 1e9;
inline constexpr double kMaxRunFrames = 1e6;
inline constexpr double kMaxRunEnergyRows = 1e7;

/// A problem with a run's settings taken together (each value alone is valid).
struct RunSettingsProblem {
  /// The RunSettings field to blame: "dt" (longer than the duration, or too many
  /// constant steps), "duration" (too many adaptive steps), "fps" or "energyRate".
  std::string field;
  /// What is wrong, with the values and units, e.g. "the step dt = 10 s is
  /// longer than the duration 1 s".
  std::string message;
};

/// Checks `run` against the limits above; `energyRate` is the rows of energy.csv
/// per model second (RunOptions::energyRate). nullopt when it is fine.
std::optional<RunSettingsProblem> checkRunSettings(const RunSettings& run,
                                                   double energyRate = 1000.0);

/// A loaded scene: the model, its initial state, and how to run it.
struct Scene {
  std::string name;
  std::string description;
  /// The file it came from ("<text>" for a scene parsed from a string).
  std::string sourcePath;
  Model model;
  State initial;
  RunSettings run;
  /// Robotics tasks run between steps (docs/robotics.md); empty for most scenes.
  build::SceneTasks robotics;
  /// The robotics section's obstacles and paths as given, for drawing them (the
  /// replay's world view): the model holds them built (obstacles grown by their
  /// security distance, paths as virtual particles and connectors).
  std::vector<build::ObstacleSpec> obstacles;
  std::vector<build::LinePathSpec> linePaths;
  std::vector<build::ArcPathSpec> arcPaths;
  /// The URDF robots placed ({"type": "urdf"} or a bare URDF, docs/robots.md): what each
  /// file declares, next to what was built (`robophi info`).
  std::vector<std::shared_ptr<const build::UrdfRobot>> urdfRobots;
  /// The "sensors" (robophi/sensors.h), resolved against the model and the initial
  /// state: sampled every frame into sensors.csv.
  std::vector<SensorSpec> sensors;
  /// Every file the load read (absolute): the scene file, URDF files, mesh
  /// files, heightfields (build::InputFileLog). A run's checkpoints record a
  /// digest of each; robophi resume refuses one that changed.
  std::vector<std::string> inputFiles;
};

/// One problem found in a scene file.
struct Diagnostic {
  std::string file;
  /// 1-based line and column of the offending value; 0 when unknown.
  int line = 0;
  int column = 0;
  /// JSON pointer of the offending value, e.g. "/objects/2/mass".
  std::string pointer;
  /// What is wrong: names the value and what was expected.
  std::string message;

  /// "file:line:column: error: message (at /pointer)".
  std::string format(const char* severity = "error") const;
};

/// The outcome of loading: a scene if and only if there is no error.
struct SceneLoadResult {
  std::optional<Scene> scene;
  std::vector<Diagnostic> errors;
  std::vector<Diagnostic> warnings;
  bool ok() const { return errors.empty() && scene.has_value(); }
};

/// Loads and validates a scene file. Every error is collected.
SceneLoadResult loadSceneFile(const std::string& path);
/// Same, from text; `fileName` is used in the messages.
SceneLoadResult loadSceneText(const std::string& text, const std::string& fileName);

/// How a bare URDF becomes a scene (`robophi run ROBOT.urdf`, docs/robots.md "A bare URDF").
struct UrdfSceneOptions {
  /// Folders for package:// meshes (--package-path), before ROS_PACKAGE_PATH.
  std::vector<std::string> packagePaths{};
  /// The root link fixed; nullopt: fixed unless the robot has a wheeled base (two or more
  /// continuous joints).
  std::optional<bool> fixedBase{};
  /// build::UrdfSpec's resolution: lattice spacing (m, 0: by count) or particles a link.
  double particleSize = 0.0;
  int particlesPerLink = 30;
  /// The robot as rigid bodies, the default (docs/robots.md "Rigid bodies",
  /// build::makeUrdfMultibody): exact mass properties, joints in reduced coordinates,
  /// contact by its <collision> geometry only; its joints held by servos with gravity
  /// compensation. False: the paper's model, links filled with particles
  /// (build::makeUrdfRobot; --particles).
  bool rigid = true;
};
/// A URDF robot on a ground plane (z = 0) under gravity: its lowest particle resting on it,
/// its joints held where they are built by servos (build::UrdfSpec::holdJoints). URDF
/// problems are errors with the URDF's file:line; its ignored elements are warnings.
SceneLoadResult loadUrdfFile(const std::string& path, const UrdfSceneOptions& options = {});
/// Whether `path` names a URDF (or xacro) file rather than a scene: ".urdf", ".xacro".
bool isUrdfPath(const std::string& path);

}  // namespace robophi
