// Goals, paths, obstacles and grasp attractors built into a model (MODEL §5,
// docs/robotics.md). Every argument is checked before anything is added.
#include "robophi/build/goals.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "robophi/multibody.h"

namespace robophi::build {

namespace {

// Throws std::invalid_argument("<function>: <what>") when `ok` is false.
void require(bool ok, const char* function, const std::string& what) {
  if (!ok) throw std::invalid_argument(std::string(function) + ": " + what);
}

std::string describe(double x) {
  std::ostringstream text;
  text << x;
  return text.str();
}

void requireStiffness(const char* function, const char* name, double stiffness, double damping) {
  require(std::isfinite(stiffness) && stiffness > 0.0, function,
          std::string(name) + ".stiffness must be > 0, got " + describe(stiffness));
  require(std::isfinite(damping) && damping >= 0.0, function,
          std::string(name) + ".damping must be >= 0, got " + describe(damping));
}

void requireParticle(const char* function, const std::string& name, const Model& model,
                     const State& state, ParticleIndex p) {
  require(
      p >= 0 && p < model.particleCount() && static_cast<std::size_t>(p) < state.position.size(),
      function,
      name + " " + std::to_string(p) + " is not a particle of the model (it has " +
          std::to_string(model.particleCount()) + ")");
}

void requireFinite(const char* function, const std::string& name, const Vec3& v) {
  require(isFinite(v), function, name + " must be finite");
}

// A fixed virtual particle (MODEL §5.1) of object `object` at `p`; returns its index.
ParticleIndex addVirtual(Model& model, State& state, std::int32_t object, const Vec3& p) {
  const ParticleIndex i = model.addParticle(1.0, kVirtualRadius, true, object);
  state.position.push_back(p);
  state.velocity.push_back(Vec3{});
  return i;
}

std::int32_t openVirtualObject(Model& model, const std::string& name) {
  const std::int32_t id = model.addObject(name, "virtual");
  model.objects[static_cast<std::size_t>(id)].contact.touches = false;  // (goals, paths: markers)
  model.objects[static_cast<std::size_t>(id)].firstParticle = model.particleCount();
  return id;
}

void closeVirtualObject(Model& model, std::int32_t id) {
  ObjectInfo& info = model.objects[static_cast<std::size_t>(id)];
  info.particleCount = model.particleCount() - info.firstParticle;
}

Vec3 rotateAbout(const Vec3& v, const Vec3& axis, double angle) {
  // Rodrigues: v cos + (k × v) sin + k (k·v)(1 - cos).
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1.0 - c));
}

}  // namespace

std::vector<Vec3> movedPose(const std::vector<Vec3>& position,
                            const std::vector<ParticleIndex>& particles, const Vec3& translation,
                            const Vec3& axis, double angle) {
  require(!particles.empty(), "movedPose", "particles must not be empty");
  for (ParticleIndex p : particles)
    require(p >= 0 && static_cast<std::size_t>(p) < position.size(), "movedPose",
            "particle " + std::to_string(p) + " has no position");
  Vec3 centroid;
  for (ParticleIndex p : particles) centroid += position[p];
  centroid = centroid / static_cast<double>(particles.size());
  std::vector<Vec3> where;
  for (ParticleIndex p : particles) {
    Vec3 offset = position[p] - centroid;
    if (norm(axis) > 0.0) offset = rotateAbout(offset, axis / norm(axis), angle);
    where.push_back(centroid + offset + translation);
  }
  return where;
}

GoalSpec addGoal(Model& model, State& state, const AttractorGoalSpec& spec) {
  constexpr const char* kFunction = "addGoal";
  require(!spec.particles.empty(), kFunction, "spec.particles must not be empty");
  require(spec.goalPositions.size() == spec.particles.size(), kFunction,
          "spec.goalPositions must have one position per particle (" +
              std::to_string(spec.particles.size()) + "), got " +
              std::to_string(spec.goalPositions.size()));
  for (std::size_t k = 0; k < spec.particles.size(); ++k) {
    requireParticle(kFunction, "spec.particles[" + std::to_string(k) + "]", model, state,
                    spec.particles[k]);
    requireFinite(kFunction, "spec.goalPositions[" + std::to_string(k) + "]",
                  spec.goalPositions[k]);
  }
  requireStiffness(kFunction, "spec", spec.stiffness, spec.damping);
  require(std::isfinite(spec.speed) && spec.speed >= 0.0, kFunction,
          "spec.speed must be >= 0, got " + describe(spec.speed));
  require(spec.tolerance > 0.0 && spec.speedTolerance > 0.0, kFunction,
          "spec.tolerance and spec.speedTolerance must be > 0");

  GoalSpec goal;
  goal.name = spec.name;
  goal.tolerance = spec.tolerance;
  goal.speedTolerance = spec.speedTolerance;
  goal.stopWhenReached = spec.stopWhenReached;
  const auto& x = state.position;
  const auto& where = spec.goalPositions;
  // With a speed, the virtual robot starts on the robot and moves to the goal.
  if (spec.speed > 0.0) {
    double farthest = 0.0;
    for (std::size_t k = 0; k < spec.particles.size(); ++k)
      farthest = std::max(farthest, norm(where[k] - x[spec.particles[k]]));
    goal.travelTime = farthest / spec.speed;
  }
  // MODEL §5.1: the virtual robot (fixed particles at the goal pose), tied to the
  // real one by LS attractors.
  const std::int32_t object = openVirtualObject(model, spec.name);
  for (std::size_t k = 0; k < spec.particles.size(); ++k) {
    const ParticleIndex particle = spec.particles[k];
    const bool moving = goal.travelTime > 0.0;
    const ParticleIndex target = addVirtual(model, state, object, moving ? x[particle] : where[k]);
    if (moving) state.velocity[target] = (where[k] - x[particle]) / goal.travelTime;
    goal.goalPositions.push_back(where[k]);
    goal.particles.push_back(particle);
    goal.targets.push_back(target);
    model.linearSprings.push_back(
        {particle, target, kAttractorRestLength, spec.stiffness, spec.damping});
  }
  closeVirtualObject(model, object);
  return goal;
}

ParticleIndex addLinkPoint(Model& model, State& state, const LinkPointSpec& spec,
                           const std::string& name) {
  constexpr const char* kFunction = "addLinkPoint";
  requireFinite(kFunction, "spec.p_LP", spec.p_LP);
  require(state.treePositions.size() == model.rigidTrees.size(), kFunction,
          "the state has no coordinates for the model's rigid trees");
  // The link: a body of a tree, or a named frame fixed to one (X_BL).
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const Multibody& mb = model.rigidTrees[t].multibody;
    std::int32_t body = mb.bodyIndex(spec.link);
    Pose X_BL{};
    if (body < 0) {
      const std::int32_t frame = mb.frameIndex(spec.link);
      if (frame < 0) continue;
      body = mb.frames[static_cast<std::size_t>(frame)].body;
      X_BL = mb.frames[static_cast<std::size_t>(frame)].X_BF;
    }
    const Vec3 p_BP = X_BL * spec.p_LP;
    MultibodyKinematics kin;
    updateKinematics(mb, state.treePositions[t].data(), kin);
    updateVelocities(mb, state.treeVelocities[t].data(), kin);
    const std::int32_t object = openVirtualObject(model, name);
    const Vec3 p_WP = kin.X_WB[static_cast<std::size_t>(body)] * p_BP;
    const ParticleIndex i = addVirtual(model, state, object, p_WP);
    state.velocity[static_cast<std::size_t>(i)] = pointVelocity(kin, body, p_WP);
    closeVirtualObject(model, object);
    // Carried by the tree (docs/model.md §7): its step sets it and takes its loads.
    model.carriedBy.resize(static_cast<std::size_t>(model.particleCount()), -1);
    model.carriedBy[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(t);
    model.rigidTrees[t].particles.push_back({i, body, p_BP});
    return i;
  }
  std::vector<std::string> names;
  for (const RigidTree& tree : model.rigidTrees)
    for (const MultibodyBody& b : tree.multibody.bodies) names.push_back(b.name);
  std::string known;
  for (std::size_t k = 0; k < names.size() && k < 12; ++k) known += (k ? ", " : "") + names[k];
  require(false, kFunction,
          "no rigid robot has a link or frame named '" + spec.link + "'" +
              (names.empty() ? std::string(" (the scene has no rigid robot)")
                             : " (links: " + known + (names.size() > 12 ? ", ..." : "") + ")"));
  return kNoParticle;
}

void addLinePath(Model& model, State& state, const LinePathSpec& spec) {
  constexpr const char* kFunction = "addLinePath";
  requireParticle(kFunction, "spec.particle", model, state, spec.particle);
  requireFinite(kFunction, "spec.from", spec.from);
  requireFinite(kFunction, "spec.to", spec.to);
  requireStiffness(kFunction, "spec", spec.stiffness, spec.damping);
  // MODEL §5.1: a TS at 180° centred on the robot keeps it on the segment.
  const Vec3 u = state.position[spec.particle] - spec.from, w = spec.to - spec.from;
  require(norm(w) > 0.0 && !(norm(cross(u, w)) > 1e-6 * norm(w) * std::max(norm(u), 1e-9)) &&
              !(dot(u, w) < 0.0) && !(dot(u, w) > dot(w, w)),
          kFunction, "line path: the particle must start on the segment from 'from' to 'to'");
  const std::int32_t object = openVirtualObject(model, spec.name);
  const ParticleIndex a = addVirtual(model, state, object, spec.from);
  const ParticleIndex b = addVirtual(model, state, object, spec.to);
  model.torsionSprings.push_back({a, spec.particle, b, M_PI, spec.stiffness, spec.damping});
  closeVirtualObject(model, object);
}

Vec3 circleCenter(const Vec3& a, const Vec3& b, const Vec3& c) {
  // The circumcentre: a + (|u|² (w × (u × w)) + |w|² ((u × w) × u)) / (2 |u × w|²).
  const Vec3 u = b - a, w = c - a, n = cross(u, w);
  return a + (cross(w, n) * dot(u, u) + cross(n, u) * dot(w, w)) / (2.0 * dot(n, n));
}

void addArcPath(Model& model, State& state, const ArcPathSpec& spec) {
  constexpr const char* kFunction = "addArcPath";
  requireParticle(kFunction, "spec.particle", model, state, spec.particle);
  requireFinite(kFunction, "spec.from", spec.from);
  requireFinite(kFunction, "spec.to", spec.to);
  requireStiffness(kFunction, "spec", spec.stiffness, spec.damping);
  if (spec.heading) requireParticle(kFunction, "spec.heading", model, state, *spec.heading);
  if (spec.headingStiffness)
    require(std::isfinite(*spec.headingStiffness) && *spec.headingStiffness > 0.0, kFunction,
            "spec.headingStiffness must be > 0, got " + describe(*spec.headingStiffness));
  const Vec3 p = state.position[spec.particle];
  const Vec3 u = spec.from - p, w = spec.to - p;
  require(norm(spec.to - spec.from) > 0.0 &&
              norm(cross(u, w)) > 1e-6 * std::max(norm(u) * norm(w), 1e-18),
          kFunction,
          "arc path: 'from' and 'to' must differ and the particle must not start on their line");
  // MODEL §5.1: a TS centred on the robot between the two fixed ends, at rest at
  // the inscribed angle it starts with, holds it on the arc through them.
  const double inscribed = std::atan2(norm(cross(u, w)), dot(u, w));
  const std::int32_t object = openVirtualObject(model, spec.name);
  const ParticleIndex a = addVirtual(model, state, object, spec.from);
  const ParticleIndex b = addVirtual(model, state, object, spec.to);
  model.torsionSprings.push_back({a, spec.particle, b, inscribed, spec.stiffness, spec.damping});
  if (spec.heading) {
    const ParticleIndex c = addVirtual(model, state, object, circleCenter(spec.from, spec.to, p));
    model.torsionSprings.push_back({c, spec.particle, *spec.heading, M_PI / 2.0,
                                    spec.headingStiffness.value_or(spec.stiffness), 0.0});
  }
  closeVirtualObject(model, object);
}

void addObstacle(Model& model, const ObstacleSpec& spec) {
  constexpr const char* kFunction = "addObstacle";
  requireFinite(kFunction, "spec.center", spec.center);
  const double margin = spec.securityDistance;
  require(std::isfinite(margin) && margin >= 0.0, kFunction,
          "spec.securityDistance must be >= 0, got " + describe(margin));
  // MODEL §5.2: where contact is not allowed, the obstacle grows by a security distance.
  if (spec.shape == ObstacleShape::kSphere) {
    require(std::isfinite(spec.radius) && spec.radius > 0.0, kFunction,
            "spec.radius must be > 0, got " + describe(spec.radius));
    model.environment.spheres.push_back({spec.center, spec.radius + margin, 0});
    return;
  }
  require(isFinite(spec.size) && spec.size.x > 0.0 && spec.size.y > 0.0 && spec.size.z > 0.0,
          kFunction, "every side of spec.size must be > 0");
  BoxObstacle box;
  box.center = spec.center;
  box.halfExtents = spec.size * 0.5 + Vec3{margin, margin, margin};
  model.environment.boxes.push_back(box);
}

void addTipAttractors(Model& model, const std::vector<ParticleIndex>& tips, double stiffness,
                      double damping) {
  constexpr const char* kFunction = "addTipAttractors";
  for (std::size_t i = 0; i < tips.size(); ++i)
    require(tips[i] >= 0 && tips[i] < model.particleCount(), kFunction,
            "tips[" + std::to_string(i) + "] " + std::to_string(tips[i]) +
                " is not a particle of the model");
  requireStiffness(kFunction, "tip attractor", stiffness, damping);
  // MODEL §5.3: finger tips attracted to each other by LS.
  for (std::size_t i = 0; i < tips.size(); ++i)
    for (std::size_t j = i + 1; j < tips.size(); ++j)
      model.linearSprings.push_back({tips[i], tips[j], kAttractorRestLength, stiffness, damping});
}

}  // namespace robophi::build
