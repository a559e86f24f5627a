// Robotics tasks between steps (MODEL §5): goal monitoring, local-minimum escape,
// grasp checks, joint limits. Public API only.
#include "robotics/tasks.h"

#include <fmt/format.h>

#include <algorithm>
#include <memory>

namespace robophi::robotics {

GoalStatus goalStatus(const World& world, const GoalSpec& goal) {
  GoalStatus status;
  const State& s = world.state();
  for (std::size_t k = 0; k < goal.particles.size(); ++k) {
    const ParticleIndex i = goal.particles[k];
    status.worstDistance =
        std::max(status.worstDistance, norm(s.position[i] - s.position[goal.targets[k]]));
    status.meanSpeed += norm(s.velocity[i]);
  }
  if (!goal.particles.empty()) status.meanSpeed /= static_cast<double>(goal.particles.size());
  status.reached = goal.travelTime == 0.0 && status.worstDistance <= goal.tolerance &&
                   status.meanSpeed <= goal.speedTolerance;
  return status;
}

std::optional<std::string> LocalMinimumEscape::update(World& world, const GoalSpec& goal) {
  if (start_.empty())
    for (ParticleIndex i : goal.particles) start_.push_back(world.state().position[i]);
  const GoalStatus status = goalStatus(world, goal);
  const double t = world.state().time;
  const bool stuck =
      status.meanSpeed < spec_.speedThreshold && status.worstDistance > goal.tolerance;
  if (!stuck) {
    stoppedSince_ = -1.0;
    return std::nullopt;
  }
  if (stoppedSince_ < 0.0) stoppedSince_ = t;
  if (t - stoppedSince_ < spec_.window || static_cast<int>(added_.size()) >= spec_.maxObstacles)
    return std::nullopt;
  // MODEL §5.2: a virtual obstacle at the local minimum, overlapping the stuck
  // particle (the one farthest from its goal) from one side so that it pushes
  // it sideways, across its pull towards the goal. The side is chosen once: the
  // way the particle has drifted sideways since the start (else a fixed
  // perpendicular), so that successive obstacles push the same way.
  std::size_t worst = 0;
  double worstDistance = -1.0;
  const State& s = world.state();
  for (std::size_t k = 0; k < goal.particles.size(); ++k) {
    const double d = norm(s.position[goal.particles[k]] - s.position[goal.targets[k]]);
    if (d > worstDistance) {
      worstDistance = d;
      worst = k;
    }
  }
  const ParticleIndex i = goal.particles[worst];
  const Vec3 toGoal = (s.position[goal.targets[worst]] - s.position[i]) / worstDistance;
  if (!side_) {
    const Vec3 drift = s.position[i] - start_[worst];
    Vec3 sideways = drift - toGoal * dot(drift, toGoal);
    if (norm(sideways) < 1e-3 * std::max(norm(drift), 1e-9)) {
      sideways = cross(toGoal, Vec3{0.0, 0.0, 1.0});
      if (norm(sideways) < 1e-6) sideways = cross(toGoal, Vec3{1.0, 0.0, 0.0});
    }
    side_ = sideways / norm(sideways);
  }
  Vec3 push = *side_ - toGoal * dot(*side_, toGoal);
  push = norm(push) > 1e-9 ? push / norm(push) : *side_;
  const double r = world.model().radius[i];
  SphereObstacle sphere;
  sphere.center = s.position[i] - push * (spec_.obstacleRadius + r * (1.0 - kOverlap));
  sphere.radius = spec_.obstacleRadius;
  world.addSphereObstacle(sphere);
  added_.push_back(sphere);
  stoppedSince_ = -1.0;
  return fmt::format(
      "goal '{}': local minimum at t = {:.4g} s ({:.3g} m from the goal, speed {:.3g} m/s); "
      "virtual obstacle {} added at [{:.4g}, {:.4g}, {:.4g}], radius {:.3g} m",
      goal.name, t, worstDistance, status.meanSpeed, added_.size(), sphere.center.x,
      sphere.center.y, sphere.center.z, sphere.radius);
}

std::optional<std::string> arriveVirtualRobot(World& world, GoalSpec& goal) {
  if (!(goal.travelTime > 0.0) || world.state().time < goal.travelTime) return std::nullopt;
  // Within a step of the goal pose: put it there exactly, and stop.
  for (std::size_t k = 0; k < goal.targets.size(); ++k) {
    world.setPosition(goal.targets[k], goal.goalPositions[k]);
    world.setVelocity(goal.targets[k], Vec3{});
  }
  const double arrival = goal.travelTime;
  goal.travelTime = 0.0;
  return fmt::format("goal '{}': the virtual robot is at the goal pose at t = {:.4g} s", goal.name,
                     arrival);
}

Vec3 objectCenterOfMass(const World& world, std::int32_t object) {
  const Model& model = world.model();
  const ObjectInfo& info = model.objects[static_cast<std::size_t>(object)];
  Vec3 sum;
  double mass = 0.0;
  for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i) {
    sum += world.state().position[i] * model.mass[i];
    mass += model.mass[i];
  }
  return mass > 0.0 ? sum / mass : sum;
}

std::optional<std::string> GraspCheck::update(World& world) {
  const double t = world.state().time;
  const Vec3 com = objectCenterOfMass(world, spec_.object);
  if (!settled_) {
    if (t < spec_.settleTime) return std::nullopt;
    settled_ = true;
    rest_ = com;
    return fmt::format("grasp: object settled at t = {:.4g} s at [{:.4g}, {:.4g}, {:.4g}]", t,
                       com.x, com.y, com.z);
  }
  largestDrift_ = std::max(largestDrift_, norm(com - rest_));
  if (!disturbed_ && spec_.disturbanceTime >= 0.0 && t >= spec_.disturbanceTime) {
    disturbed_ = true;
    const ObjectInfo& info = world.model().objects[static_cast<std::size_t>(spec_.object)];
    for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i)
      if (!world.model().isFixed(i))
        world.setVelocity(i, world.state().velocity[i] + spec_.disturbance);
    return fmt::format("grasp: disturbance of [{:.3g}, {:.3g}, {:.3g}] m/s at t = {:.4g} s",
                       spec_.disturbance.x, spec_.disturbance.y, spec_.disturbance.z, t);
  }
  return std::nullopt;
}

std::string GraspCheck::verdict() const {
  return fmt::format("grasp {}: largest drift {:.3g} m after settling (tolerance {:.3g} m)",
                     stable() ? "stable" : "NOT stable", largestDrift_, spec_.tolerance);
}

std::function<bool(World&, std::vector<std::string>&)> makeSceneTasks(const Scene& scene) {
  const SceneTasks& tasks = scene.robotics;
  if (tasks.empty()) return {};
  // The tasks' own state lives in a shared block the hook owns.
  struct Running {
    JointLimiter limiter;
    std::vector<GoalSpec> goals;
    std::vector<bool> reached;
    std::vector<LocalMinimumEscape> escapes;
    std::vector<GraspCheck> grasps;
    double duration = 0.0;
    bool reported = false;
  };
  auto run = std::make_shared<Running>(Running{JointLimiter(tasks.limits),
                                               tasks.goals,
                                               std::vector<bool>(tasks.goals.size(), false),
                                               {},
                                               {},
                                               scene.run.duration,
                                               false});
  for (const EscapeSpec& e : tasks.escapes) run->escapes.emplace_back(e);
  for (const GraspSpec& g : tasks.grasps) run->grasps.emplace_back(g);
  return [run](World& world, std::vector<std::string>& events) {
    run->limiter.update(world);
    for (auto& escape : run->escapes)
      if (auto event = escape.update(world, run->goals[escape.goal()])) events.push_back(*event);
    for (auto& grasp : run->grasps)
      if (auto event = grasp.update(world)) events.push_back(*event);
    bool keepGoing = true;
    for (std::size_t g = 0; g < run->goals.size(); ++g) {
      if (auto event = arriveVirtualRobot(world, run->goals[g])) events.push_back(*event);
      const GoalStatus status = goalStatus(world, run->goals[g]);
      if (status.reached && !run->reached[g]) {
        run->reached[g] = true;
        events.push_back(fmt::format("goal '{}' reached at t = {:.4g} s (within {:.3g} m)",
                                     run->goals[g].name, world.state().time, status.worstDistance));
        if (run->goals[g].stopWhenReached) keepGoing = false;
      }
    }
    const bool last = !keepGoing || world.state().time >= run->duration * (1.0 - 1e-12);
    if (last && !run->reported) {
      run->reported = true;
      for (std::size_t g = 0; g < run->goals.size(); ++g) {
        if (run->reached[g]) continue;
        const GoalStatus status = goalStatus(world, run->goals[g]);
        events.push_back(fmt::format("goal '{}' not reached: {:.3g} m away at the end",
                                     run->goals[g].name, status.worstDistance));
      }
      for (const auto& grasp : run->grasps) events.push_back(grasp.verdict());
      if (run->limiter.engagements() > 0)
        events.push_back(fmt::format("joint limits engaged {} times", run->limiter.engagements()));
    }
    return keepGoing;
  };
}

}  // namespace robophi::robotics
