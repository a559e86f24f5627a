// Robotics tasks between steps (MODEL §5): goal monitoring, local-minimum escape,
// grasp checks, joint limits. Public API only.
#include "robotics/tasks.h"

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "output/json_numbers.h"

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
    settledAt_ = t;
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

nlohmann::json GraspCheck::outcome() const {
  return {{"object", spec_.object},
          {"settled", settled_},
          {"settled_time_s", settled_ ? nlohmann::json(settledAt_) : nlohmann::json()},
          {"stable", stable()},
          {"largest_drift_m", largestDrift_},
          {"tolerance_m", spec_.tolerance}};
}

namespace {

using output::exactNumber;
using output::exactVec3;
using output::numberFromJson;
using output::vec3FromJson;

}  // namespace

nlohmann::json GraspCheck::save() const {
  return {{"settled", settled_},
          {"disturbed", disturbed_},
          {"settled_at", exactNumber(settledAt_)},
          {"rest", exactVec3(rest_)},
          {"largest_drift", exactNumber(largestDrift_)}};
}

void GraspCheck::restore(const nlohmann::json& saved) {
  settled_ = saved.at("settled").get<bool>();
  disturbed_ = saved.at("disturbed").get<bool>();
  settledAt_ = numberFromJson(saved.at("settled_at"), "grasp settled_at");
  rest_ = vec3FromJson(saved.at("rest"), "grasp rest");
  largestDrift_ = numberFromJson(saved.at("largest_drift"), "grasp largest_drift");
}

nlohmann::json LocalMinimumEscape::save() const {
  auto added = nlohmann::json::array(), start = nlohmann::json::array();
  for (const SphereObstacle& o : added_)
    added.push_back({exactVec3(o.center), exactNumber(o.radius), o.material});
  for (const Vec3& p : start_) start.push_back(exactVec3(p));
  return {{"stopped_since", exactNumber(stoppedSince_)},
          {"added", added},
          {"start", start},
          {"side", side_ ? exactVec3(*side_) : nlohmann::json()}};
}

void LocalMinimumEscape::restore(const nlohmann::json& saved) {
  stoppedSince_ = numberFromJson(saved.at("stopped_since"), "escape stopped_since");
  added_.clear();
  for (const auto& o : saved.at("added")) {
    SphereObstacle sphere;
    sphere.center = vec3FromJson(o.at(0), "escape obstacle centre");
    sphere.radius = numberFromJson(o.at(1), "escape obstacle radius");
    sphere.material = o.at(2).get<std::int32_t>();
    added_.push_back(sphere);
  }
  start_.clear();
  for (const auto& p : saved.at("start")) start_.push_back(vec3FromJson(p, "escape start"));
  side_.reset();
  if (!saved.at("side").is_null()) side_ = vec3FromJson(saved.at("side"), "escape side");
}

namespace {

// The scene's robotics tasks (SceneTasks) run as one Task: joint limits, escapes,
// grasps, then goals, in that order.
class SceneTaskSet final : public Task {
 public:
  explicit SceneTaskSet(const Scene& scene)
      : limiter_(scene.robotics.limits),
        goals_(scene.robotics.goals),
        reached_(goals_.size(), false),
        reachedAt_(goals_.size(), -1.0),
        duration_(scene.run.duration) {
    for (const EscapeSpec& e : scene.robotics.escapes) escapes_.emplace_back(e);
    for (const GraspSpec& g : scene.robotics.grasps) grasps_.emplace_back(g);
  }

  bool step(World& world, std::vector<std::string>& events) override {
    limiter_.update(world);
    for (auto& escape : escapes_)
      if (auto event = escape.update(world, goals_[escape.goal()])) events.push_back(*event);
    for (auto& grasp : grasps_)
      if (auto event = grasp.update(world)) events.push_back(*event);
    bool keepGoing = true;
    for (std::size_t g = 0; g < goals_.size(); ++g) {
      if (auto event = arriveVirtualRobot(world, goals_[g])) events.push_back(*event);
      const GoalStatus status = goalStatus(world, goals_[g]);
      if (status.reached && !reached_[g]) {
        reached_[g] = true;
        reachedAt_[g] = world.state().time;
        events.push_back(fmt::format("goal '{}' reached at t = {:.4g} s (within {:.3g} m)",
                                     goals_[g].name, world.state().time, status.worstDistance));
        if (goals_[g].stopWhenReached) keepGoing = false;
      }
    }
    const bool last = !keepGoing || world.state().time >= duration_ * (1.0 - 1e-12);
    if (last && !reported_) {
      reported_ = true;
      for (std::size_t g = 0; g < goals_.size(); ++g) {
        if (reached_[g]) continue;
        const GoalStatus status = goalStatus(world, goals_[g]);
        events.push_back(fmt::format("goal '{}' not reached: {:.3g} m away at the end",
                                     goals_[g].name, status.worstDistance));
      }
      for (const auto& grasp : grasps_) events.push_back(grasp.verdict());
      if (limiter_.engagements() > 0)
        events.push_back(fmt::format("joint limits engaged {} times", limiter_.engagements()));
    }
    return keepGoing;
  }

  nlohmann::json outcomes(const World& world) const override {
    nlohmann::json out = nlohmann::json::object();
    if (!goals_.empty()) {
      auto goals = nlohmann::json::array();
      for (std::size_t g = 0; g < goals_.size(); ++g) {
        const GoalStatus status = goalStatus(world, goals_[g]);
        goals.push_back({{"name", goals_[g].name},
                         {"reached", static_cast<bool>(reached_[g])},
                         {"time_s", reached_[g] ? nlohmann::json(reachedAt_[g]) : nlohmann::json()},
                         {"final_distance_m", status.worstDistance},
                         {"final_mean_speed_m_s", status.meanSpeed},
                         {"tolerance_m", goals_[g].tolerance}});
      }
      out["goals"] = goals;
    }
    if (!grasps_.empty()) {
      auto grasps = nlohmann::json::array();
      for (const auto& grasp : grasps_) grasps.push_back(grasp.outcome());
      out["grasps"] = grasps;
    }
    if (!escapes_.empty()) {
      auto escapes = nlohmann::json::array();
      for (const auto& escape : escapes_)
        escapes.push_back(
            {{"goal", goals_[escape.goal()].name}, {"virtual_obstacles", escape.added().size()}});
      out["escapes"] = escapes;
    }
    out["joint_limit_engagements"] = limiter_.engagements();
    return out;
  }

  nlohmann::json save() const override {
    auto goals = nlohmann::json::array();
    for (std::size_t g = 0; g < goals_.size(); ++g) {
      goals.push_back({{"travel_time", exactNumber(goals_[g].travelTime)},
                       {"reached", static_cast<bool>(reached_[g])},
                       {"reached_at", exactNumber(reachedAt_[g])}});
    }
    auto escapes = nlohmann::json::array(), grasps = nlohmann::json::array();
    for (const auto& e : escapes_) escapes.push_back(e.save());
    for (const auto& g : grasps_) grasps.push_back(g.save());
    return {{"limiter", limiter_.save()},
            {"goals", goals},
            {"escapes", escapes},
            {"grasps", grasps},
            {"reported", reported_}};
  }

  void restore(const nlohmann::json& saved) override {
    const auto& goals = saved.at("goals");
    const auto& escapes = saved.at("escapes");
    const auto& grasps = saved.at("grasps");
    if (goals.size() != goals_.size() || escapes.size() != escapes_.size() ||
        grasps.size() != grasps_.size())
      throw std::runtime_error("robotics tasks: the checkpoint is of a scene with other tasks");
    limiter_.restore(saved.at("limiter"));
    for (std::size_t g = 0; g < goals_.size(); ++g) {
      goals_[g].travelTime = numberFromJson(goals[g].at("travel_time"), "goal travel_time");
      reached_[g] = goals[g].at("reached").get<bool>();
      reachedAt_[g] = numberFromJson(goals[g].at("reached_at"), "goal reached_at");
    }
    for (std::size_t k = 0; k < escapes_.size(); ++k) escapes_[k].restore(escapes[k]);
    for (std::size_t k = 0; k < grasps_.size(); ++k) grasps_[k].restore(grasps[k]);
    reported_ = saved.at("reported").get<bool>();
  }

 private:
  JointLimiter limiter_;
  std::vector<GoalSpec> goals_;
  std::vector<bool> reached_;
  std::vector<double> reachedAt_;
  std::vector<LocalMinimumEscape> escapes_;
  std::vector<GraspCheck> grasps_;
  double duration_ = 0.0;
  bool reported_ = false;
};

}  // namespace

StepTask makeSceneTasks(const Scene& scene) {
  if (scene.robotics.empty()) return {};
  return StepTask(std::make_shared<SceneTaskSet>(scene));
}

}  // namespace robophi::robotics
