// Reading the "robotics" section of a scene (docs/robotics.md) into the build
// layer's specs; the builders (build/goals.h) add the virtual robots, paths,
// obstacles and attractors to the model.
#include "scene/scene_robotics.h"

#include <fmt/format.h>

#include <stdexcept>

#include "robophi/build/goals.h"
#include "robophi/joints.h"

namespace robophi::scene {

namespace {

// Runs one builder; an argument it refuses becomes an error at `at`.
template <typename Build>
bool tryBuild(DiagnosticSink& sink, const std::string& at, Build&& run) {
  try {
    run();
    return true;
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    // The builders' messages start with their function's name, which means nothing here.
    const auto colon = what.find(": ");
    sink.error(at, colon == std::string::npos ? what : what.substr(colon + 2));
    return false;
  }
}

// "points": [{"name", "link", "point"}]: named points of links, for goals and paths
// to name and for the output to follow (particles.csv).
void readLinkPoint(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
                   Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("point {}", at));
  if (!r.valid()) return;
  build::LinkPointSpec spec;
  const auto name = r.string("name", true);
  const auto link = r.string("link", true);
  spec.p_LP = r.vec3("point", "m").value_or(Vec3{});
  r.finish();
  if (!name || !link) return;
  for (const ObjectInfo& object : scene.model.objects)
    if (object.name == *name) {
      sink.error(r.memberPointer("name"),
                 fmt::format("the name '{}' is given to an object of the model already", *name));
      return;
    }
  spec.link = *link;
  tryBuild(sink, at, [&] { build::addLinkPoint(scene.model, scene.initial, spec, *name); });
}

std::vector<ParticleIndex> readRefs(ObjectReader& r, const char* key, const ParticleLookup& lookup,
                                    bool& ok) {
  std::vector<ParticleIndex> out;
  const nlohmann::json* list = r.member(key);
  if (list == nullptr || !list->is_array() || list->empty()) {
    r.sink().error(r.memberPointer(key),
                   fmt::format("'{}': expected a non-empty array of \"object:index\" or "
                               "link points (\"robot.link\", {{\"link\", \"point\"}})",
                               key));
    ok = false;
    return out;
  }
  for (std::size_t i = 0; i < list->size(); ++i) {
    const auto p = resolveParticle(r.sink(), (*list)[i],
                                   fmt::format("{}/{}", r.memberPointer(key), i), lookup);
    ok = ok && p.has_value();
    out.push_back(p.value_or(0));
  }
  return out;
}

// "targets": one [x, y, z] (m) per particle.
std::optional<std::vector<Vec3>> readTargets(DiagnosticSink& sink, const nlohmann::json& targets,
                                             const std::string& at, std::size_t count) {
  if (!targets.is_array() || targets.size() != count) {
    sink.error(at,
               fmt::format("'targets': expected {} positions [x, y, z], one per particle, got {}",
                           count, describeJson(targets)));
    return std::nullopt;
  }
  std::vector<Vec3> where;
  for (std::size_t k = 0; k < count; ++k) {
    const auto& v = targets[k];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number()) {
      sink.error(fmt::format("{}/{}", at, k),
                 fmt::format("expected a position [x, y, z] (m), got {}", describeJson(v)));
      return std::nullopt;
    }
    where.push_back({v[0].get<double>(), v[1].get<double>(), v[2].get<double>()});
  }
  return where;
}

std::optional<build::EscapeSpec> readEscape(DiagnosticSink& sink, const nlohmann::json& entry,
                                            const std::string& at) {
  ObjectReader e(sink, entry, at, "escape");
  if (!e.valid()) return std::nullopt;
  build::EscapeSpec spec;
  spec.speedThreshold = e.numberOr("speedThreshold", spec.speedThreshold, Bound::kPositive, "m/s");
  spec.window = e.numberOr("window", spec.window, Bound::kPositive, "s");
  spec.obstacleRadius = e.numberOr("obstacleRadius", 0.0, Bound::kNonNegative, "m");
  spec.maxObstacles = e.integer("maxObstacles", 1).value_or(spec.maxObstacles);
  spec.settleDistance = e.numberOr("settleDistance", 0.0, Bound::kNonNegative, "m");
  spec.maxWork = e.numberOr("maxWork", 0.0, Bound::kNonNegative, "J");
  spec.workBudget = e.numberOr("workBudget", 0.0, Bound::kNonNegative, "J");
  spec.pushInterval = e.numberOr("pushInterval", 0.0, Bound::kNonNegative, "s");
  e.finish();
  return spec;
}

void readGoal(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
              const ParticleLookup& lookup, Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("goal {}", at));
  if (!r.valid()) return;
  bool ok = true;
  build::AttractorGoalSpec spec;
  spec.name = r.string("name", true).value_or("goal");
  spec.particles = readRefs(r, "particles", lookup, ok);
  const auto stiffness = r.number("stiffness", Bound::kPositive, "N/m", true);
  spec.damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·s/m");
  const auto translation = r.vec3("translation", "m");
  const auto rotation = r.numbers("rotation", 4, "[ax, ay, az, angle (rad)]");
  const nlohmann::json* targets = r.member("targets");
  spec.tolerance = r.numberOr("tolerance", spec.tolerance, Bound::kPositive, "m");
  spec.speedTolerance = r.numberOr("speedTolerance", spec.speedTolerance, Bound::kPositive, "m/s");
  spec.stopWhenReached = r.boolean("stopWhenReached").value_or(false);
  spec.speed = r.number("speed", Bound::kPositive, "m/s").value_or(0.0);
  const nlohmann::json* escapeEntry = r.member("escape");
  r.finish();
  if (targets != nullptr &&
      (r.member("translation") != nullptr || r.member("rotation") != nullptr)) {
    sink.error(
        r.memberPointer("targets"),
        "give the goal pose either as 'targets' or as 'translation' and 'rotation', not both");
    ok = false;
  }
  const auto escape = escapeEntry ? readEscape(sink, *escapeEntry, at + "/escape") : std::nullopt;
  if (!ok || !stiffness) return;
  spec.stiffness = *stiffness;
  // The goal pose: explicit targets, or the particles moved by rotation then
  // translation about their centroid.
  if (targets != nullptr) {
    auto where = readTargets(sink, *targets, r.memberPointer("targets"), spec.particles.size());
    if (!where) return;
    spec.goalPositions = std::move(*where);
  } else {
    const Vec3 axis = rotation ? Vec3{(*rotation)[0], (*rotation)[1], (*rotation)[2]} : Vec3{};
    spec.goalPositions =
        build::movedPose(scene.initial.position, spec.particles, translation.value_or(Vec3{}), axis,
                         rotation ? (*rotation)[3] : 0.0);
  }
  build::GoalSpec goal;
  if (!tryBuild(sink, at, [&] { goal = build::addGoal(scene.model, scene.initial, spec); })) return;
  const std::size_t goalIndex = scene.robotics.goals.size();
  scene.robotics.goals.push_back(std::move(goal));
  if (escape) {
    scene.robotics.escapes.push_back(*escape);
    scene.robotics.escapes.back().goal = goalIndex;
  }
}

void readPath(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
              const ParticleLookup& lookup, Scene& scene, std::size_t index) {
  ObjectReader r(sink, entry, at, fmt::format("path {}", at));
  if (!r.valid()) return;
  const auto type = r.string("type", true);
  const nlohmann::json* ref = r.member("particle");
  const auto stiffness = r.number("stiffness", Bound::kPositive, "N·m/rad or N/m", true);
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·m·s/rad or N·s/m");
  std::optional<Vec3> from, to;
  const nlohmann::json* heading = nullptr;
  std::optional<double> headingStiffness;
  if (type && *type == "line") {
    from = r.vec3("from", "m", true);
    to = r.vec3("to", "m", true);
  } else if (type && *type == "arc") {
    from = r.vec3("from", "m", true);
    to = r.vec3("to", "m", true);
    heading = r.member("heading");
    headingStiffness = r.number("headingStiffness", Bound::kPositive, "N·m/rad");
  } else if (type) {
    sink.error(r.memberPointer("type"), fmt::format("unknown path type \"{}\"{} (expected line or "
                                                    "arc)",
                                                    *type, didYouMean(*type, {"line", "arc"})));
  }
  r.finish();
  if (ref == nullptr) r.missing("particle", "a particle reference");
  if (!type || ref == nullptr || !stiffness) return;
  const auto p = resolveParticle(sink, *ref, r.memberPointer("particle"), lookup);
  if (!p) return;
  const std::string name = fmt::format("path{}", index);
  if (*type == "line") {
    if (!from || !to) return;
    tryBuild(sink, at, [&] {
      build::addLinePath(scene.model, scene.initial, {name, *p, *from, *to, *stiffness, damping});
      scene.linePaths.push_back({name, *p, *from, *to, *stiffness, damping});
    });
  } else if (*type == "arc") {
    if (!from || !to) return;
    std::optional<ParticleIndex> h;
    if (heading != nullptr) {
      h = resolveParticle(sink, *heading, r.memberPointer("heading"), lookup);
      if (!h) return;
    }
    tryBuild(sink, at, [&] {
      const build::ArcPathSpec spec{name, *p, *from, *to, *stiffness, damping, h, headingStiffness};
      build::addArcPath(scene.model, scene.initial, spec);
      scene.arcPaths.push_back(spec);
    });
  }
}

void readObstacle(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
                  Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("obstacle {}", at));
  if (!r.valid()) return;
  const auto type = r.string("type", true);
  build::ObstacleSpec spec;
  const auto center = r.vec3("center", "m", true);
  spec.securityDistance = r.numberOr("securityDistance", 0.0, Bound::kNonNegative, "m");
  bool ok = center.has_value();
  if (type && *type == "sphere") {
    spec.shape = build::ObstacleShape::kSphere;
    const auto radius = r.number("radius", Bound::kPositive, "m", true);
    ok = ok && radius;
    spec.radius = radius.value_or(spec.radius);
  } else if (type && *type == "box") {
    spec.shape = build::ObstacleShape::kBox;
    const auto size = r.vec3("size", "m", true);
    ok = ok && size;
    spec.size = size.value_or(spec.size);
  } else if (type) {
    sink.error(r.memberPointer("type"),
               fmt::format("unknown obstacle type \"{}\"{} (expected sphere or box)", *type,
                           didYouMean(*type, {"sphere", "box"})));
    return;
  }
  r.finish();
  if (!type || !ok) return;
  spec.center = *center;
  if (tryBuild(sink, at, [&] { build::addObstacle(scene.model, spec); }))
    scene.obstacles.push_back(spec);
}

void readLimit(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
               Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("limit {}", at));
  if (!r.valid()) return;
  const auto name = r.string("joint", true);
  const auto min = r.number("min", Bound::kAny, "rad or m", true);
  const auto max = r.number("max", Bound::kAny, "rad or m", true);
  const auto stiffness = r.number("stiffness", Bound::kPositive, "N·m/rad or N/m", true);
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·m·s/rad or N·s/m");
  r.finish();
  if (!name || !min || !max || !stiffness) return;
  const auto joint = findJoint(scene.model, *name);
  if (!joint) {
    std::vector<std::string> names;
    for (const Joint& j : scene.model.joints) names.push_back(j.name);
    sink.error(r.memberPointer("joint"),
               fmt::format("no joint named '{}'{}", *name, didYouMean(*name, names)));
    return;
  }
  scene.robotics.limits.push_back({*joint, *min, *max, *stiffness, damping});
}

// "close": {"joints": [names], "angle" (rad), "time" (s)}: the hand closes by its joints.
bool readClose(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
               const Scene& scene, build::GraspSpec& spec) {
  ObjectReader c(sink, entry, at, "close");
  if (!c.valid()) return false;
  const nlohmann::json* joints = c.member("joints");
  const auto angle = c.number("angle", Bound::kPositive, "rad", true);
  spec.closeTime = c.numberOr("time", 0.0, Bound::kNonNegative, "s");
  c.finish();
  bool ok = angle.has_value();
  spec.closeAngle = angle.value_or(0.0);
  if (joints == nullptr || !joints->is_array() || joints->empty()) {
    sink.error(c.memberPointer("joints"), "'joints': expected a non-empty array of joint names");
    return false;
  }
  std::vector<std::string> names;
  for (const Joint& j : scene.model.joints) names.push_back(j.name);
  for (std::size_t k = 0; k < joints->size(); ++k) {
    const std::string where = fmt::format("{}/{}", c.memberPointer("joints"), k);
    if (!(*joints)[k].is_string()) {
      sink.error(where, fmt::format("expected a joint name, got {}", describeJson((*joints)[k])));
      ok = false;
      continue;
    }
    const std::string name = (*joints)[k].get<std::string>();
    const auto joint = findJoint(scene.model, name);
    if (!joint || scene.model.joints[*joint].kind != JointKind::kRevolute) {
      sink.error(where,
                 fmt::format("no revolute joint named '{}'{}", name, didYouMean(name, names)));
      ok = false;
      continue;
    }
    spec.closeJoints.push_back(*joint);
  }
  return ok;
}

void readGrasp(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
               const ParticleLookup& lookup, Scene& scene) {
  ObjectReader r(sink, entry, at, "grasp");
  if (!r.valid()) return;
  const auto objectName = r.string("object", true);
  const auto handName = r.string("hand");
  build::GraspSpec spec;
  spec.settleSpeed = r.numberOr("settleSpeed", spec.settleSpeed, Bound::kPositive, "m/s");
  spec.settleAngularSpeed =
      r.numberOr("settleAngularSpeed", spec.settleAngularSpeed, Bound::kPositive, "rad/s");
  spec.settleHold = r.numberOr("settleHold", spec.settleHold, Bound::kNonNegative, "s");
  spec.tolerance = r.numberOr("tolerance", spec.tolerance, Bound::kPositive, "m");
  spec.disturbance = r.vec3("disturbance", "m/s").value_or(Vec3{});
  spec.disturbanceTime = r.numberOr("disturbanceTime", -1.0, Bound::kAny, "s");
  const nlohmann::json* close = r.member("close");
  bool ok = true;
  std::vector<ParticleIndex> tips;
  if (r.member("tips") != nullptr) tips = readRefs(r, "tips", lookup, ok);
  const double tipStiffness = r.numberOr("tipStiffness", 0.0, Bound::kNonNegative, "N/m");
  const double tipDamping = r.numberOr("tipDamping", 0.0, Bound::kNonNegative, "N·s/m");
  r.finish();
  if (close != nullptr) ok = readClose(sink, *close, r.memberPointer("close"), scene, spec) && ok;
  if (!objectName || !ok) return;
  const auto object = findObject(sink, scene, *objectName, r.memberPointer("object"));
  if (!object) return;
  spec.object = *object;
  if (handName) {
    const auto hand = findObject(sink, scene, *handName, r.memberPointer("hand"));
    if (!hand) return;
    spec.hand = *hand;
  }
  if (tipStiffness > 0.0 && !tryBuild(sink, at, [&] {
        build::addTipAttractors(scene.model, tips, tipStiffness, tipDamping);
      }))
    return;
  scene.robotics.grasps.push_back(spec);
}

template <typename Read>
void forEach(DiagnosticSink& sink, const nlohmann::json* list, const std::string& at, Read read) {
  if (list == nullptr) return;
  if (!list->is_array()) {
    sink.error(at, fmt::format("expected an array, got {}", describeJson(*list)));
    return;
  }
  for (std::size_t i = 0; i < list->size(); ++i) read((*list)[i], fmt::format("{}/{}", at, i), i);
}

}  // namespace

// docs/robotics.md "Links in goals" (scene_robotics.h).
std::optional<ParticleIndex> resolveLinkPoint(DiagnosticSink& sink, const nlohmann::json& ref,
                                              const std::string& at, Scene& scene) {
  build::LinkPointSpec spec;
  if (ref.is_string()) {
    spec.link = ref.get<std::string>();
    // A point the section's "points" named already: its particle.
    for (const ObjectInfo& object : scene.model.objects)
      if (object.name == spec.link && !object.contact.touches && object.particleCount == 1 &&
          scene.model.isCarried(object.firstParticle))
        return object.firstParticle;
  } else {
    ObjectReader r(sink, ref, at, "link point");
    if (!r.valid()) return std::nullopt;
    const auto link = r.string("link", true);
    const auto point = r.vec3("point", "m");
    r.finish();
    if (!link) return std::nullopt;
    spec.link = *link;
    spec.p_LP = point.value_or(Vec3{});
  }
  std::optional<ParticleIndex> particle;
  tryBuild(sink, at, [&] {
    const std::string name = fmt::format("{}.point{}", spec.link, scene.model.objects.size());
    particle = build::addLinkPoint(scene.model, scene.initial, spec, name);
  });
  return particle;
}

std::optional<std::int32_t> findObject(DiagnosticSink& sink, const Scene& scene,
                                       const std::string& name, const std::string& at) {
  std::vector<std::string> names;
  for (std::size_t o = 0; o < scene.model.objects.size(); ++o) {
    names.push_back(scene.model.objects[o].name);
    if (scene.model.objects[o].name == name) return static_cast<std::int32_t>(o);
  }
  sink.error(at, fmt::format("no object named '{}'{}", name, didYouMean(name, names)));
  return std::nullopt;
}

std::optional<std::size_t> findNamedJoint(DiagnosticSink& sink, const Model& model,
                                          const std::string& name, const std::string& at) {
  if (const auto joint = findJoint(model, name)) return joint;
  std::vector<std::string> names;
  for (const Joint& j : model.joints) names.push_back(j.name);
  sink.error(at, fmt::format("no joint named '{}'{}", name, didYouMean(name, names)));
  return std::nullopt;
}

void readRoboticsSection(DiagnosticSink& sink, const nlohmann::json& section,
                         const std::string& pointer, const ParticleLookup& lookup, Scene& scene) {
  ObjectReader r(sink, section, pointer, "'robotics'");
  if (!r.valid()) return;
  const auto* obstacles = r.member("obstacles");
  const auto* goals = r.member("goals");
  const auto* paths = r.member("paths");
  const auto* limits = r.member("limits");
  const auto* grasps = r.member("grasps");
  const auto* points = r.member("points");
  r.finish();
  forEach(sink, points, pointer + "/points",
          [&](const nlohmann::json& e, const std::string& at, std::size_t) {
            readLinkPoint(sink, e, at, scene);
          });
  // The order fixes the numbering of environment items and virtual objects.
  forEach(sink, obstacles, pointer + "/obstacles",
          [&](const nlohmann::json& e, const std::string& at, std::size_t) {
            readObstacle(sink, e, at, scene);
          });
  forEach(sink, goals, pointer + "/goals",
          [&](const nlohmann::json& e, const std::string& at, std::size_t) {
            readGoal(sink, e, at, lookup, scene);
          });
  forEach(sink, paths, pointer + "/paths",
          [&](const nlohmann::json& e, const std::string& at, std::size_t i) {
            readPath(sink, e, at, lookup, scene, i);
          });
  forEach(sink, limits, pointer + "/limits",
          [&](const nlohmann::json& e, const std::string& at, std::size_t) {
            readLimit(sink, e, at, scene);
          });
  forEach(sink, grasps, pointer + "/grasps",
          [&](const nlohmann::json& e, const std::string& at, std::size_t) {
            readGrasp(sink, e, at, lookup, scene);
          });
}

}  // namespace robophi::scene
