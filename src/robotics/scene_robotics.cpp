// Reading the "robotics" section of a scene (docs/robotics.md).
#include "robotics/scene_robotics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace robophi::robotics {

namespace {

using io::Bound;
using io::ObjectReader;

// Adds a fixed virtual particle (MODEL §5.1) of object `object`; returns its index.
ParticleIndex addVirtual(Scene& scene, std::int32_t object, const Vec3& p) {
  const ParticleIndex i = scene.model.addParticle(1.0, kVirtualRadius, true, object);
  scene.initial.position.push_back(p);
  scene.initial.velocity.push_back(Vec3{});
  scene.initial.force.push_back(Vec3{});
  return i;
}

std::int32_t addVirtualObject(Scene& scene, const std::string& name) {
  const std::int32_t id = scene.model.addObject(name, "virtual");
  scene.model.objects[static_cast<std::size_t>(id)].firstParticle = scene.model.particleCount();
  return id;
}

void closeObject(Scene& scene, std::int32_t id) {
  ObjectInfo& info = scene.model.objects[static_cast<std::size_t>(id)];
  info.particleCount = scene.model.particleCount() - info.firstParticle;
}

Vec3 rotateAbout(const Vec3& v, const Vec3& axis, double angle) {
  // Rodrigues: v cos + (k × v) sin + k (k·v)(1 - cos).
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1.0 - c));
}

std::vector<ParticleIndex> readRefs(ObjectReader& r, const char* key,
                                    const io::ParticleLookup& lookup, bool& ok) {
  std::vector<ParticleIndex> out;
  const nlohmann::json* list = r.member(key);
  if (list == nullptr || !list->is_array() || list->empty()) {
    r.sink().error(r.memberPointer(key),
                   fmt::format("'{}': expected a non-empty array of \"object:index\"", key));
    ok = false;
    return out;
  }
  for (std::size_t i = 0; i < list->size(); ++i) {
    const auto p = io::resolveParticle(r.sink(), (*list)[i],
                                       fmt::format("{}/{}", r.memberPointer(key), i), lookup);
    ok = ok && p.has_value();
    out.push_back(p.value_or(0));
  }
  return out;
}

void readGoal(io::DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
              const io::ParticleLookup& lookup, Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("goal {}", at));
  if (!r.valid()) return;
  bool ok = true;
  const std::string name = r.string("name", true).value_or("goal");
  const auto particles = readRefs(r, "particles", lookup, ok);
  const auto stiffness = r.number("stiffness", Bound::kPositive, "N/m", true);
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·s/m");
  const auto translation = r.vec3("translation", "m");
  const auto rotation = r.numbers("rotation", 4, "[ax, ay, az, angle (rad)]");
  const nlohmann::json* targets = r.member("targets");
  GoalSpec goal;
  goal.name = name;
  goal.tolerance = r.numberOr("tolerance", goal.tolerance, Bound::kPositive, "m");
  goal.speedTolerance = r.numberOr("speedTolerance", goal.speedTolerance, Bound::kPositive, "m/s");
  goal.stopWhenReached = r.boolean("stopWhenReached").value_or(false);
  const auto speed = r.number("speed", Bound::kPositive, "m/s");
  const nlohmann::json* escape = r.member("escape");
  r.finish();
  if (!ok || !stiffness) return;
  // The goal pose: explicit targets, or the particles moved by rotation then translation
  // about their centroid.
  std::vector<Vec3> where;
  const auto& x = scene.initial.position;
  if (targets != nullptr) {
    if (!targets->is_array() || targets->size() != particles.size()) {
      sink.error(at + "/targets", fmt::format("'targets': expected {} positions [x, y, z], one "
                                              "per particle",
                                              particles.size()));
      return;
    }
    for (std::size_t k = 0; k < particles.size(); ++k) {
      const auto& v = (*targets)[k];
      if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
          !v[2].is_number()) {
        sink.error(fmt::format("{}/targets/{}", at, k), "expected a position [x, y, z] (m)");
        return;
      }
      where.push_back({v[0].get<double>(), v[1].get<double>(), v[2].get<double>()});
    }
  } else {
    Vec3 centroid;
    for (ParticleIndex p : particles) centroid += x[p];
    centroid = centroid / static_cast<double>(particles.size());
    for (ParticleIndex p : particles) {
      Vec3 offset = x[p] - centroid;
      if (rotation) {
        const Vec3 axis{(*rotation)[0], (*rotation)[1], (*rotation)[2]};
        if (norm(axis) > 0.0) offset = rotateAbout(offset, axis / norm(axis), (*rotation)[3]);
      }
      where.push_back(centroid + offset + translation.value_or(Vec3{}));
    }
  }
  // MODEL §5.1: the virtual robot (fixed particles at the goal pose), tied to the
  // real one by LS attractors.
  // With a speed, the virtual robot starts on the robot and moves to the goal.
  if (speed) {
    double farthest = 0.0;
    for (std::size_t k = 0; k < particles.size(); ++k)
      farthest = std::max(farthest, norm(where[k] - x[particles[k]]));
    goal.travelTime = farthest / *speed;
  }
  const std::int32_t object = addVirtualObject(scene, name);
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const bool moving = goal.travelTime > 0.0;
    const ParticleIndex target = addVirtual(scene, object, moving ? x[particles[k]] : where[k]);
    if (moving) scene.initial.velocity[target] = (where[k] - x[particles[k]]) / goal.travelTime;
    goal.goalPositions.push_back(where[k]);
    goal.particles.push_back(particles[k]);
    goal.targets.push_back(target);
    scene.model.linearSprings.push_back(
        {particles[k], target, kAttractorRestLength, *stiffness, damping});
  }
  closeObject(scene, object);
  const std::size_t goalIndex = scene.robotics.goals.size();
  scene.robotics.goals.push_back(goal);
  if (escape != nullptr) {
    ObjectReader e(sink, *escape, at + "/escape", "escape");
    EscapeSpec spec;
    spec.goal = goalIndex;
    spec.speedThreshold =
        e.numberOr("speedThreshold", spec.speedThreshold, Bound::kPositive, "m/s");
    spec.window = e.numberOr("window", spec.window, Bound::kPositive, "s");
    spec.obstacleRadius = e.numberOr("obstacleRadius", spec.obstacleRadius, Bound::kPositive, "m");
    spec.maxObstacles = e.integer("maxObstacles", 1).value_or(spec.maxObstacles);
    e.finish();
    scene.robotics.escapes.push_back(spec);
  }
}

void readPath(io::DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
              const io::ParticleLookup& lookup, Scene& scene, std::size_t index) {
  ObjectReader r(sink, entry, at, fmt::format("path {}", at));
  if (!r.valid()) return;
  const auto type = r.string("type", true);
  const nlohmann::json* ref = r.member("particle");
  const auto stiffness = r.number("stiffness", Bound::kPositive, "N·m/rad or N/m", true);
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·m·s/rad or N·s/m");
  std::optional<Vec3> from, to, center;
  const nlohmann::json* heading = nullptr;
  std::optional<double> headingStiffness;
  if (type && *type == "line") {
    from = r.vec3("from", "m", true);
    to = r.vec3("to", "m", true);
  } else if (type && *type == "arc") {
    center = r.vec3("center", "m", true);
    heading = r.member("heading");
    headingStiffness = r.number("headingStiffness", Bound::kPositive, "N·m/rad");
  } else if (type) {
    sink.error(r.memberPointer("type"), fmt::format("unknown path type \"{}\" (expected line or "
                                                    "arc)",
                                                    *type));
  }
  r.finish();
  if (ref == nullptr) r.missing("particle", "a particle reference");
  if (!type || ref == nullptr || !stiffness) return;
  const auto p = io::resolveParticle(sink, *ref, r.memberPointer("particle"), lookup);
  if (!p) return;
  const auto& x = scene.initial.position;
  const std::int32_t object = addVirtualObject(scene, fmt::format("path{}", index));
  if (*type == "line") {
    if (!from || !to) return;
    // MODEL §5.1: a TS at 180° centred on the robot keeps it on the segment.
    const Vec3 u = x[*p] - *from, w = *to - *from;
    if (!(norm(w) > 0.0) || norm(cross(u, w)) > 1e-6 * norm(w) * std::max(norm(u), 1e-9) ||
        dot(u, w) < 0.0 || dot(u, w) > dot(w, w)) {
      sink.error(at, "line path: the particle must start on the segment from 'from' to 'to'");
      return;
    }
    const ParticleIndex a = addVirtual(scene, object, *from);
    const ParticleIndex b = addVirtual(scene, object, *to);
    scene.model.torsionSprings.push_back({a, *p, b, M_PI, *stiffness, damping});
  } else {
    if (!center) return;
    // An arc of circle: the robot keeps its distance to the fixed centre (LS), and
    // optionally its heading tangent (TS at 90° centred on the robot).
    const double radius = norm(x[*p] - *center);
    if (!(radius > 0.0)) {
      sink.error(at, "arc path: the particle starts on the centre");
      return;
    }
    const ParticleIndex c = addVirtual(scene, object, *center);
    scene.model.linearSprings.push_back({*p, c, radius, *stiffness, damping});
    if (heading != nullptr) {
      const auto h = io::resolveParticle(sink, *heading, at + "/heading", lookup);
      if (!h) return;
      scene.model.torsionSprings.push_back(
          {c, *p, *h, M_PI / 2.0, headingStiffness.value_or(*stiffness * radius * radius), 0.0});
    }
  }
  closeObject(scene, object);
}

void readObstacle(io::DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
                  Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("obstacle {}", at));
  if (!r.valid()) return;
  const auto type = r.string("type", true);
  const auto center = r.vec3("center", "m", true);
  // MODEL §5.2: where contact is not allowed, the obstacle grows by a security distance.
  const double margin = r.numberOr("securityDistance", 0.0, Bound::kNonNegative, "m");
  if (type && *type == "sphere") {
    const auto radius = r.number("radius", Bound::kPositive, "m", true);
    r.finish();
    if (center && radius) scene.model.environment.spheres.push_back({*center, *radius + margin, 0});
  } else if (type && *type == "box") {
    const auto size = r.vec3("size", "m", true);
    r.finish();
    if (center && size) {
      BoxObstacle box;
      box.center = *center;
      box.halfExtents = *size * 0.5 + Vec3{margin, margin, margin};
      scene.model.environment.boxes.push_back(box);
    }
  } else if (type) {
    sink.error(r.memberPointer("type"),
               fmt::format("unknown obstacle type \"{}\" (expected sphere or box)", *type));
  }
}

void readLimit(io::DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
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
  // By name here: robotics::findJoint belongs to the application layer above.
  const std::vector<Joint>& joints = scene.model.joints;
  const auto joint =
      std::find_if(joints.begin(), joints.end(), [&](const Joint& j) { return j.name == *name; });
  if (joint == joints.end()) {
    sink.error(r.memberPointer("joint"), fmt::format("no joint named '{}'", *name));
    return;
  }
  scene.robotics.limits.push_back(
      {static_cast<std::size_t>(joint - joints.begin()), *min, *max, *stiffness, damping});
}

void readGrasp(io::DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
               const io::ParticleLookup& lookup, Scene& scene) {
  ObjectReader r(sink, entry, at, "grasp");
  if (!r.valid()) return;
  const auto objectName = r.string("object", true);
  GraspSpec spec;
  spec.settleTime = r.numberOr("settleTime", spec.settleTime, Bound::kNonNegative, "s");
  spec.tolerance = r.numberOr("tolerance", spec.tolerance, Bound::kPositive, "m");
  spec.disturbance = r.vec3("disturbance", "m/s").value_or(Vec3{});
  spec.disturbanceTime = r.numberOr("disturbanceTime", -1.0, Bound::kAny, "s");
  bool ok = true;
  std::vector<ParticleIndex> tips;
  if (r.member("tips") != nullptr) tips = readRefs(r, "tips", lookup, ok);
  const double tipStiffness = r.numberOr("tipStiffness", 0.0, Bound::kNonNegative, "N/m");
  const double tipDamping = r.numberOr("tipDamping", 0.0, Bound::kNonNegative, "N·s/m");
  r.finish();
  if (!objectName || !ok) return;
  for (std::size_t o = 0; o < scene.model.objects.size(); ++o)
    if (scene.model.objects[o].name == *objectName) spec.object = static_cast<std::int32_t>(o);
  if (spec.object < 0) {
    sink.error(r.memberPointer("object"), fmt::format("no object named '{}'", *objectName));
    return;
  }
  // MODEL §5.3: finger tips attracted to each other by LS.
  if (tipStiffness > 0.0)
    for (std::size_t i = 0; i < tips.size(); ++i)
      for (std::size_t j = i + 1; j < tips.size(); ++j)
        scene.model.linearSprings.push_back(
            {tips[i], tips[j], kAttractorRestLength, tipStiffness, tipDamping});
  scene.robotics.grasps.push_back(spec);
}

template <typename Read>
void forEach(io::DiagnosticSink& sink, const nlohmann::json* list, const std::string& at,
             Read read) {
  if (list == nullptr) return;
  if (!list->is_array()) {
    sink.error(at, fmt::format("expected an array, got {}", io::describeJson(*list)));
    return;
  }
  for (std::size_t i = 0; i < list->size(); ++i) read((*list)[i], fmt::format("{}/{}", at, i), i);
}

}  // namespace

void readRoboticsSection(io::DiagnosticSink& sink, const nlohmann::json& section,
                         const std::string& pointer, const io::ParticleLookup& lookup,
                         Scene& scene) {
  ObjectReader r(sink, section, pointer, "'robotics'");
  if (!r.valid()) return;
  const auto* obstacles = r.member("obstacles");
  const auto* goals = r.member("goals");
  const auto* paths = r.member("paths");
  const auto* limits = r.member("limits");
  const auto* grasps = r.member("grasps");
  r.finish();
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

}  // namespace robophi::robotics
