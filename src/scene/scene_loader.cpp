// Scene files → Scene (docs/scene-format.md). The loader reads the whole file,
// reports every problem with its line, column and JSON pointer, and returns a
// scene only when there is none: nothing half-built leaves this file.

#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <string_view>
#include <utility>
#include <vector>

#include "robophi/build/input_files.h"
#include "robophi/build/rigid_object.h"
#include "robophi/scene/scene.h"
#include "scene/json_locator.h"
#include "scene/scene_contact.h"
#include "scene/scene_control.h"
#include "scene/scene_fields.h"
#include "scene/scene_links.h"
#include "scene/scene_objects.h"
#include "scene/scene_robotics.h"
#include "scene/scene_run.h"
#include "scene/scene_sensors.h"
#include "scene/scene_urdf.h"

namespace robophi {

namespace {

using scene::DiagnosticSink;
using scene::ObjectReader;
using scene::SceneObject;

constexpr int kFormatVersion = 1;

// The names an entry gives the model, each with where it comes from: a
// generated object's own name and its joints' ("<object>.<joint>"), or a URDF
// robot's link objects ("<robot>.<link>", their carriers "<robot>.<link>.carriers")
// and joints ("<robot>.<joint>").
std::vector<std::pair<std::string, std::string>> modelNames(const SceneObject& object) {
  std::vector<std::pair<std::string, std::string>> names;
  if (object.rigidUrdf) {
    // A rigid robot's bodies and joints are "<robot>.<link>" and "<robot>.<joint>".
    const Multibody& mb = object.rigidUrdf->robot.multibody;
    for (const MultibodyBody& body : mb.bodies) {
      names.emplace_back(body.name, fmt::format("link '{}' of robot '{}' ({})", body.name,
                                                object.name, object.pointer));
      if (velocityCountOf(body.joint) == 1)
        names.emplace_back(body.jointName, fmt::format("joint '{}' of robot '{}' ({})",
                                                       body.jointName, object.name, object.pointer));
    }
    return names;
  }
  if (!object.urdf) {
    names.emplace_back(object.name, fmt::format("object '{}' ({})", object.name, object.pointer));
    for (const Joint& joint : object.geometry.joints)
      names.emplace_back(
          object.name + "." + joint.name,
          fmt::format("joint '{}' of object '{}' ({})", joint.name, object.name, object.pointer));
    return names;
  }
  // A robot's names begin "<robot>.": what follows.
  const auto local = [&](const std::string& name) {
    const std::string prefix = object.name + ".";
    return name.starts_with(prefix) ? name.substr(prefix.size()) : name;
  };
  constexpr std::string_view kCarriers = ".carriers";
  for (const build::ObjectPlacement& link : object.urdf->objects) {
    const bool carriers = !link.geometry.contact.touches;
    std::string linkName = local(link.name);
    if (carriers && linkName.ends_with(kCarriers))
      linkName.resize(linkName.size() - kCarriers.size());
    names.emplace_back(
        link.name, fmt::format("{}link '{}' of robot '{}' ({})", carriers ? "the carriers of " : "",
                               linkName, object.name, object.pointer));
  }
  for (const build::UrdfModelJoint& joint : object.urdf->modelJoints)
    names.emplace_back(joint.name, fmt::format("joint '{}' of robot '{}' ({})", local(joint.name),
                                               object.name, object.pointer));
  return names;
}

// Reads every object entry; names must be unique: the entries' and every name
// they give the model (objects, robots' links and joints), which share one
// space (model.json, joints.csv, the robotics targets).
std::vector<SceneObject> readObjects(DiagnosticSink& sink, const nlohmann::json* list,
                                     std::map<std::string, std::size_t>& byName,
                                     const std::string& sceneDirectory) {
  std::vector<SceneObject> objects;
  if (list == nullptr) {
    sink.error("", "missing required key 'objects' (an array of objects)");
    return objects;
  }
  if (!list->is_array()) {
    sink.error("/objects", fmt::format("'objects': expected an array of objects, got {}",
                                       scene::describeJson(*list)));
    return objects;
  }
  // The whole scene's size budget (docs/scene-format.md#limits): each object is
  // checked by its builder before it allocates, the sum here after each object,
  // so no more than the budget and one object is ever held.
  std::size_t particles = 0, connectors = 0;
  std::map<std::string, std::string> placesByName;  // every name in the model → where from
  for (std::size_t i = 0; i < list->size(); ++i) {
    const nlohmann::json& entry = (*list)[i];
    const std::string pointer = fmt::format("/objects/{}", i);
    const bool urdf = entry.is_object() && entry.contains("type") && entry["type"] == "urdf";
    SceneObject object = urdf ? scene::readUrdfObject(sink, entry, pointer, sceneDirectory)
                              : scene::readSceneObject(sink, entry, pointer, sceneDirectory);
    if (object.valid) {
      std::size_t objectParticles = 0, objectConnectors = 0;
      const auto count = [&](const build::GeneratedObject& g) {
        objectParticles += g.size();
        objectConnectors +=
            g.linearSprings.size() + g.torsionSprings.size() + g.jointSprings.size();
      };
      count(object.geometry);
      if (object.urdf) {
        for (const auto& link : object.urdf->objects) count(link.geometry);
        objectConnectors += object.urdf->linearSprings.size() + object.urdf->torsionSprings.size() +
                            object.urdf->jointSprings.size();
      }
      if (particles + objectParticles > static_cast<std::size_t>(build::kMaxParticlesPerObject) ||
          connectors + objectConnectors >
              static_cast<std::size_t>(build::kMaxConnectorsPerObject)) {
        sink.error(object.pointer,
                   fmt::format("{} '{}' brings the scene to {} particles and {} connectors, more "
                               "than the budget of a scene, {} particles and {} connectors "
                               "(docs/scene-format.md#limits)",
                               object.kind, object.name, particles + objectParticles,
                               connectors + objectConnectors, build::kMaxParticlesPerObject,
                               build::kMaxConnectorsPerObject));
        object.valid = false;
        object.geometry = {};
        object.velocity = {};
        object.urdf = nullptr;
        object.rigidUrdf = nullptr;
      } else {
        particles += objectParticles;
        connectors += objectConnectors;
      }
    }
    if (!object.name.empty()) {
      const auto [it, fresh] = byName.emplace(object.name, objects.size());
      if (!fresh) {
        sink.error(object.pointer + "/name",
                   fmt::format("duplicate object name '{}' (first defined at {})", object.name,
                               objects[it->second].pointer));
        object.valid = false;
      }
    }
    if (object.valid) {
      for (auto& [name, place] : modelNames(object)) {
        const auto [it, fresh] = placesByName.emplace(name, place);
        if (fresh) continue;
        sink.error(object.pointer + "/name",
                   fmt::format("the name '{}' is given twice in the model: to {} and to {}; "
                               "objects, robots' links and joints share one set of names",
                               name, it->second, place));
        object.valid = false;
        break;
      }
    }
    objects.push_back(std::move(object));
  }
  return objects;
}

// Places the valid objects in the model (build::ModelBuilder, the one road to a Model).
void placeObjects(DiagnosticSink& sink, std::vector<SceneObject>& objects, Scene& scene) {
  build::ModelBuilder builder;
  builder.setGravity(scene.model.gravity);
  std::vector<std::int32_t> held;  // rigid trees whose joints hold their start pose
  std::vector<std::pair<std::int32_t, const SceneObject::RigidUrdf*>> servoed;  // built-in robots
  for (auto& object : objects) {
    if (!object.valid) continue;
    try {
      if (object.rigidUrdf) {  // one object per body with <collision> (docs/robots.md)
        object.firstParticle = builder.model().particleCount();
        const auto placed = build::placeUrdfMultibody(builder, object.rigidUrdf->robot,
                                                      object.rigidUrdf->placement);
        if (object.rigidUrdf->holdJoints) held.push_back(placed.tree);
        if (object.rigidUrdf->servoStiffness > 0.0)
          servoed.emplace_back(placed.tree, object.rigidUrdf.get());
      } else if (object.urdf) {  // one object per link (docs/robots.md)
        object.firstParticle = builder.model().particleCount();
        build::placeUrdfRobot(builder, *object.urdf);
        scene.urdfRobots.push_back(object.urdf);
      } else if (object.rigid) {  // one free rigid body (docs/model.md §7)
        object.firstParticle =
            build::placeRigidObject(builder, object, object.rigidVelocity, object.rigidSpin)
                .object.firstParticle;
      } else {
        object.firstParticle = builder.addObject(object).firstParticle;
      }
    } catch (const build::SpecError& e) {  // (names clash in readObjects, never here)
      sink.error(object.pointer, e.message());
      object.valid = false;
    } catch (const build::UrdfError& e) {  // a rigid robot's collision mesh
      sink.error(object.pointer + "/file", e.what());
      object.valid = false;
    }
  }
  build::BuiltModel built = std::move(builder).build();
  for (const std::int32_t tree : held) scene::holdRigidJoints(built.model, built.initial, tree);
  for (const auto& [tree, robot] : servoed)
    scene::servoRigidJoints(built.model, built.initial, tree, robot->servoStiffness,
                            robot->servoDamping);
  scene.model = std::move(built.model);
  scene.initial = std::move(built.initial);
}

void readScene(DiagnosticSink& sink, const nlohmann::json& root, const std::string& sceneDirectory,
               Scene& scene) {
  ObjectReader r(sink, root, "", "the scene");
  if (!r.valid()) return;
  r.allow({"$schema"});
  if (const auto version = r.integer("robophi", 0)) {
    if (*version != kFormatVersion)
      sink.error("/robophi", fmt::format("'robophi': format version {} is not supported "
                                         "(this program reads version {})",
                                         *version, kFormatVersion));
  }
  scene.name = r.string("name").value_or("");
  scene.description = r.string("description").value_or("");
  scene.run = scene::readRunSettings(sink, r.member("run"));
  if (const auto g = r.vec3("gravity", "m/s²")) scene.model.gravity = *g;

  // Objects first: connectors and joints refer to their particles.
  std::map<std::string, std::size_t> byName;
  std::vector<SceneObject> objects = readObjects(sink, r.member("objects"), byName, sceneDirectory);
  placeObjects(sink, objects, scene);

  scene::ParticleLookup lookup{&objects, &byName, &scene.initial.position, nullptr};
  // Points of rigid robots' links stand where particles do (docs/robotics.md "Links in goals").
  if (!scene.model.rigidTrees.empty())
    lookup.linkPoint = [&scene](DiagnosticSink& s, const nlohmann::json& ref, const std::string& at) {
      return scene::resolveLinkPoint(s, ref, at, scene);
    };
  // Connectors inside "particles" objects use local indices.
  // (objects[i] was read from the entry objects[i].)
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const SceneObject& object = objects[i];
    const nlohmann::json& entry = (*r.member("objects"))[i];
    if (object.kind != "particles" || !entry.is_object() || !entry.contains("connectors")) continue;
    scene::ParticleLookup local = lookup;
    local.local = &object;
    scene::readConnectors(sink, entry["connectors"], object.pointer + "/connectors", local,
                          scene.model);
  }
  if (const auto* list = r.member("connectors"))
    scene::readConnectors(sink, *list, "/connectors", lookup, scene.model);
  if (const auto* list = r.member("joints"))
    scene::readJoints(sink, *list, "/joints", lookup, scene.model);
  // Robotics before the contact keys: its obstacles are the first environment items.
  if (const auto* section = r.member("robotics"))  // goals, paths, limits (docs/robotics.md)
    scene::readRoboticsSection(sink, *section, "/robotics", lookup, scene);
  if (const auto* section = r.member("control"))  // actuators, sequences (docs/robots.md)
    scene::readControlSection(sink, *section, "/control", scene);
  // Materials, environment, medium, contact settings, pairs (docs/contact.md).
  scene::readContactKeys(r, sceneDirectory, scene.model);
  if (const auto* list = r.member("sensors"))  // observers (docs/scene-format.md "Sensors")
    scene::readSensors(sink, *list, "/sensors", scene);
  r.finish();
}

}  // namespace

SceneLoadResult loadSceneText(const std::string& text, const std::string& fileName) {
  SceneLoadResult result;
  scene::JsonReadResult json = scene::readLocatedJson(text);
  DiagnosticSink sink(fileName, json.json ? &*json.json : nullptr);
  for (const auto& problem : json.errors)
    sink.errorAt(problem.where, problem.pointer, problem.message);
  if (!json.json) {
    result.errors = sink.takeErrors();
    return result;
  }

  Scene scene;
  scene.sourcePath = fileName;
  readScene(sink, json.json->value, std::filesystem::path(fileName).parent_path().string(), scene);

  if (sink.errorCount() == 0) {
    // Internal check: the loader's own output must be a consistent model.
    if (const std::string problem = checkModel(scene.model); !problem.empty())
      sink.error("", "internal error, the model built from this scene is inconsistent: " + problem);
    if (scene.model.particleCount() == 0) sink.error("/objects", "the scene has no particle");
  }
  result.errors = sink.takeErrors();
  result.warnings = sink.takeWarnings();
  if (result.errors.empty()) result.scene = std::move(scene);
  return result;
}

SceneLoadResult loadSceneFile(const std::string& path) {
  SceneLoadResult result;
  const build::InputFileLog read;  // the scene file and what it names (URDF, meshes, heightfields)
  std::string text;
  try {
    text = build::readInputFile(path);  // a regular file, recorded in `read`
  } catch (const build::InputFileError& e) {
    result.errors.push_back(
        Diagnostic{path, 0, 0, "", "cannot open the scene file: " + e.problem()});
    return result;
  }
  result = loadSceneText(text, path);
  if (result.scene) result.scene->inputFiles = read.files();
  return result;
}

}  // namespace robophi
