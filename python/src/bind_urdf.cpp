// URDF robots from Python (docs/python.md "URDF robots"): robophi.load of a bare
// URDF as `robophi run ROBOT.urdf` makes it (loadUrdfFile), the builder spec
// robophi.Urdf placed by ModelBuilder.add_urdf (build::makeUrdfRobot,
// placeUrdfRobot), and what a scene's robots declare (Scene.urdf_robots).
#include "py_robophi.h"
#include "robophi/build/mjcf_multibody.h"
#include "robophi/build/urdf.h"
#include "robophi/scene/scene_mjcf.h"

namespace robophi::python {

namespace {

using build::UrdfJointType;

/// robophi.Urdf: the spec, with its placement as a position and roll-pitch-yaw.
struct PyUrdfSpec {
  build::UrdfSpec spec{};
  Vec3 position{};
  Vec3 orientation{};  // roll, pitch, yaw (rad)
};

const char* jointTypeName(UrdfJointType type) {
  switch (type) {
    case UrdfJointType::kRevolute:
      return "revolute";
    case UrdfJointType::kContinuous:
      return "continuous";
    case UrdfJointType::kPrismatic:
      return "prismatic";
    case UrdfJointType::kFixed:
      break;
  }
  return "fixed";
}

py::dict massDict(const build::MassProperties& m) {
  py::dict d;
  d["mass"] = m.mass;
  d["center_of_mass"] = m.centerOfMass;
  return d;
}

/// What a URDF declares and what was built (the data `robophi info` prints), as dicts.
py::dict robotDict(const build::UrdfRobot& robot) {
  py::list links;
  for (const build::UrdfLink& l : robot.links) {
    py::dict d;
    d["name"] = l.name;
    d["line"] = l.line;
    d["object"] =
        l.object >= 0 ? py::object(py::str(robot.objects[l.object].name)) : py::object(py::none());
    d["declared"] = massDict(l.declared);
    d["achieved"] = massDict(l.achieved);
    d["notional"] = l.notional;
    d["round_wheel"] = l.roundWheel;
    d["notes"] = l.notes;
    links.append(d);
  }
  py::list joints;
  for (const build::UrdfJoint& j : robot.joints) {
    py::dict d;
    d["name"] = j.name;
    d["line"] = j.line;
    d["type"] = jointTypeName(j.type);
    d["axis"] = j.axis;
    d["parent"] = robot.links[j.parent].name;
    d["child"] = robot.links[j.child].name;
    d["lower"] = j.hasPositionLimits ? py::object(py::float_(j.lower)) : py::object(py::none());
    d["upper"] = j.hasPositionLimits ? py::object(py::float_(j.upper)) : py::object(py::none());
    d["velocity"] = j.velocity;
    d["effort"] = j.effort;
    d["damping"] = j.damping;
    d["friction"] = j.friction;
    d["mimic"] = j.hasMimic ? py::object(py::make_tuple(j.mimicJoint, j.multiplier, j.offset))
                            : py::object(py::none());
    d["initial_position"] = j.initialPosition;
    d["model_joint"] =
        j.modelJoint.empty() ? py::object(py::none()) : py::object(py::str(j.modelJoint));
    joints.append(d);
  }
  py::list warnings;
  for (const build::UrdfWarning& w : robot.warnings)
    warnings.append(w.file + ":" + std::to_string(w.line) + ": " + w.message);
  py::dict out;
  out["name"] = robot.name;
  out["file"] = robot.file;
  out["links"] = links;
  out["joints"] = joints;
  out["warnings"] = warnings;
  return out;
}

/// A URDF that cannot be imported as robophi.SceneError: "FILE:LINE: error: message"
/// (the CLI's line for a bare URDF), its diagnostic with the file and line apart.
[[noreturn]] void throwUrdfError(const build::UrdfError& e) {
  const std::string where = e.line() > 0 ? e.file() + ":" + std::to_string(e.line()) : e.file();
  throw SceneLoadError(where + ": error: " + e.message(),
                       {Diagnostic{e.file(), e.line(), 0, "", e.message()}});
}

// A bare robot file as the scene the CLI runs (loadUrdfFile, loadMjcfFile), the GIL
// released while it loads.
PyScene loadBareRobot(const std::string& path, const UrdfSceneOptions& options,
                      SceneLoadResult (*load)(const std::string&, const UrdfSceneOptions&)) {
  SceneLoadResult result;
  {
    py::gil_scoped_release release;
    result = load(path, options);
  }
  PyScene scene;
  scene.scene = sceneOrThrow(std::move(result), path, &scene.warnings);
  scene.model = PyModel{std::make_shared<const CompiledModel>(scene.scene->model)};
  return scene;
}

PyScene loadUrdf(const std::string& path, std::vector<std::string> packagePaths,
                 std::optional<std::string> base, bool rigid, double particleSize,
                 int particlesPerLink) {
  UrdfSceneOptions options;
  options.packagePaths = std::move(packagePaths);
  options.rigid = rigid;
  if (base) {
    if (*base != "fixed" && *base != "free")
      throw std::invalid_argument("robophi.load: base '" + *base + "': expected fixed or free");
    options.fixedBase = *base == "fixed";
  }
  options.particleSize = particleSize;
  options.particlesPerLink = particlesPerLink;
  return loadBareRobot(path, options, &loadUrdfFile);
}

PyScene loadMjcf(const std::string& path, double particleSize, int particlesPerLink) {
  UrdfSceneOptions options;
  options.particleSize = particleSize;
  options.particlesPerLink = particlesPerLink;
  return loadBareRobot(path, options, &loadMjcfFile);
}

}  // namespace

void bindUrdf(py::module_& m) {
  py::class_<PyUrdfSpec>(m, "Urdf",
                         "A URDF robot for ModelBuilder.add_urdf (build::UrdfSpec): one object "
                         "per link filled with particles that carry the link's mass and "
                         "inertia, joined by the paper's connectors.")
      .def(py::init<>())
      .def_property(
          "file", [](const PyUrdfSpec& s) { return s.spec.path; },
          [](PyUrdfSpec& s, const py::handle& p) { s.spec.path = pathText(p); },
          "The .urdf file (run xacro first for a .xacro)")
      .def_property(
          "package_paths", [](const PyUrdfSpec& s) { return s.spec.packagePaths; },
          [](PyUrdfSpec& s, std::vector<std::string> v) { s.spec.packagePaths = std::move(v); },
          "Folders for package://NAME/... meshes, before ROS_PACKAGE_PATH")
      .def_property(
          "name", [](const PyUrdfSpec& s) { return s.spec.name; },
          [](PyUrdfSpec& s, std::string v) { s.spec.name = std::move(v); },
          "Prefix of the object and joint names ('<name>.<link>'); empty: the URDF's robot name")
      .def_property(
          "position", [](const PyUrdfSpec& s) { return s.position; },
          [](PyUrdfSpec& s, const Vec3& v) { s.position = v; },
          "Where the root link's frame is (m)")
      .def_property(
          "orientation", [](const PyUrdfSpec& s) { return s.orientation; },
          [](PyUrdfSpec& s, const Vec3& v) { s.orientation = v; },
          "The root link's frame as roll, pitch, yaw (rad)")
      .def_property(
          "fixed_base", [](const PyUrdfSpec& s) { return s.spec.fixedBase; },
          [](PyUrdfSpec& s, bool v) { s.spec.fixedBase = v; },
          "The root link's particles fixed (a mounted arm); False: a free robot")
      .def_property(
          "particle_size", [](const PyUrdfSpec& s) { return s.spec.particleSize; },
          [](PyUrdfSpec& s, double v) { s.spec.particleSize = v; },
          "Lattice spacing of every link (m); 0: about particles_per_link a link")
      .def_property(
          "particles_per_link", [](const PyUrdfSpec& s) { return s.spec.particlesPerLink; },
          [](PyUrdfSpec& s, int v) { s.spec.particlesPerLink = v; }, ">= 1")
      .def_property(
          "natural_frequency", [](const PyUrdfSpec& s) { return s.spec.naturalFrequency; },
          [](PyUrdfSpec& s, double v) { s.spec.naturalFrequency = v; },
          "ω of each link's fastest mode (rad/s); the joints are as stiff as their links")
      .def_property(
          "initial_positions", [](const PyUrdfSpec& s) { return s.spec.initialPositions; },
          [](PyUrdfSpec& s, std::map<std::string, double> v) {
            s.spec.initialPositions = std::move(v);
          },
          "q (rad or m) to build at, by URDF joint name; the others at 0")
      .def_property(
          "self_collision", [](const PyUrdfSpec& s) { return s.spec.selfCollision; },
          [](PyUrdfSpec& s, bool v) { s.spec.selfCollision = v; },
          "Links touch each other (never a joint's parent and child)")
      .def_property(
          "hold_joints", [](const PyUrdfSpec& s) { return s.spec.holdJoints; },
          [](PyUrdfSpec& s, bool v) { s.spec.holdJoints = v; },
          "Moving joints held where built by servos as stiff as their links (a bare "
          "`robophi run`); False: passive joints for actuators to drive")
      .def_property(
          "round_wheels", [](const PyUrdfSpec& s) { return s.spec.roundWheels; },
          [](PyUrdfSpec& s, bool v) { s.spec.roundWheels = v; },
          "A cylinder coaxial with its revolute or continuous joint touches the environment as "
          "that cylinder (docs/contact.md \"Round wheels\"); False: as its particles");

  auto builder = py::reinterpret_borrow<py::class_<build::ModelBuilder>>(m.attr("ModelBuilder"));
  builder.def(
      "add_urdf",
      [](build::ModelBuilder& b, const PyUrdfSpec& s) {
        build::UrdfSpec spec = s.spec;
        spec.placement = build::Frame::fromXyzRpy(s.position, s.orientation);
        build::UrdfRobot robot;
        try {
          py::gil_scoped_release release;
          robot = build::makeUrdfRobot(spec);
        } catch (const build::UrdfError& e) {
          throwUrdfError(e);
        }
        const build::PlacedUrdfRobot placed = build::placeUrdfRobot(b, robot);
        py::list objects;
        for (std::size_t k = 0; k < placed.objects.size(); ++k)
          objects.append(py::make_tuple(robot.objects[k].name, placed.objects[k].object,
                                        placed.objects[k].firstParticle,
                                        placed.objects[k].particleCount));
        py::dict out = robotDict(robot);
        out["objects"] = objects;
        out["model_joints"] = placed.modelJoint;
        return out;
      },
      py::arg("spec"),
      "Imports a URDF robot (a robophi.Urdf) and places it. Returns a dict: name, file, links, "
      "joints (the URDF's: type, limits, dynamics, mimic, model_joint), warnings (ignored "
      "elements), objects ((name, object index, first particle, particle count) per placed "
      "object) and model_joints (per URDF joint, the index into model.joints, -1 for fixed). "
      "A file that cannot be imported is a robophi.SceneError 'FILE:LINE: error: message'; "
      "a bad field a robophi.SpecError.");

  auto scene = py::reinterpret_borrow<py::class_<PyScene>>(m.attr("Scene"));
  scene
      .def_property_readonly(
          "urdf_robots",
          [](const PyScene& s) {
            py::list robots;
            for (const auto& r : s.scene->urdfRobots) robots.append(robotDict(*r));
            return robots;
          },
          "The URDF robots placed (a bare URDF, or {\"type\": \"urdf\"} objects): what each "
          "file declares, as in ModelBuilder.add_urdf's result")
      .def_property_readonly(
          "warnings", [](const PyScene& s) { return s.warnings; },
          "The loader's warnings, as `robophi validate` prints them (a URDF's ignored "
          "elements)");

  m.def("_is_urdf_path", &isUrdfPath, py::arg("path"));
  m.def("_is_mjcf_path", &isMjcfPath, py::arg("path"));
  m.def("_mjcf_available", &build::mjcfAvailable, "Whether MJCF import was built (libmujoco-dev).");
  m.def("_load_mjcf", &loadMjcf, py::arg("path"), py::arg("particle_size") = 0.0,
        py::arg("particles_per_link") = 30);
  m.def(
      "_load_urdf",
      [](const py::handle& path, std::vector<std::string> packagePaths,
         std::optional<std::string> base, bool rigid, double particleSize,
         int particlesPerLink) {
        return loadUrdf(pathText(path), std::move(packagePaths), std::move(base), rigid,
                        particleSize, particlesPerLink);
      },
      py::arg("path"), py::arg("package_paths") = std::vector<std::string>{},
      py::arg("base") = py::none(), py::arg("rigid") = true, py::arg("particle_size") = 0.0,
      py::arg("particles_per_link") = 30);
}

}  // namespace robophi::python
