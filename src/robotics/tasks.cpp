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

namespace {

// The robot a particle belongs to: its rigid tree when a tree carries it (every
// link, and a goal's point on a link: docs/robotics.md "Links in goals"), else its
// object.
struct RobotOf {
  const Model& model;
  std::int32_t tree = -1, object = -1;
  RobotOf(const Model& m, ParticleIndex i) : model(m) {
    if (m.isCarried(i))
      tree = m.carriedBy[static_cast<std::size_t>(i)];
    else
      object = m.objectOf[static_cast<std::size_t>(i)];
  }
  bool has(std::int32_t j) const {
    if (j < 0) return false;
    return tree >= 0 ? model.isCarried(j) && model.carriedBy[static_cast<std::size_t>(j)] == tree
                     : model.objectOf[static_cast<std::size_t>(j)] == object;
  }
};

// Whether any particle of the robot touches something outside it (another
// object or the environment): a robot blocked by an obstacle.
bool touchesOutside(const World& world, const RobotOf& robot) {
  for (const Contact& c : world.contacts()) {
    const bool aIn = robot.has(c.a);
    const bool otherIn = !c.withEnvironment() && robot.has(c.other);
    if (aIn != otherIn) return true;
  }
  return false;
}

}  // namespace

std::optional<std::string> LocalMinimumEscape::update(World& world, const GoalSpec& goal) {
  const GoalStatus status = goalStatus(world, goal);
  const double t = world.state().time;
  const State& s = world.state();
  // MODEL §5.2: a local minimum is null speed away from the goal where an
  // obstacle holds the robot. A robot slow near its goal (within the settle
  // distance), or slow and touching nothing (an arm sagging under gravity to
  // its equilibrium next to the goal), is settling, not stuck.
  const double settleDistance =
      spec_.settleDistance > 0.0 ? spec_.settleDistance : 5.0 * goal.tolerance;
  // The stuck particle: the attracted one farthest from its target.
  std::size_t worst = 0;
  for (std::size_t k = 0; k < goal.particles.size(); ++k)
    if (norm(s.position[goal.particles[k]] - s.position[goal.targets[k]]) >
        norm(s.position[goal.particles[worst]] - s.position[goal.targets[worst]]))
      worst = k;
  const ParticleIndex i = goal.particles[worst];
  const RobotOf robot(world.model(), i);
  const bool touching = touchesOutside(world, robot);
  std::optional<std::string> event;
  if (pushing_) {
    // Free: nearer the goal by a tenth of where it was stuck, or touching nothing.
    if (status.worstDistance < 0.9 * stuckDistance_ || !touching) {
      pushing_ = false;
      stoppedSince_ = -1.0;
      return fmt::format(
          "goal '{}': out of the local minimum at t = {:.4g} s after {} virtual obstacle{} "
          "(work {:.3g} J), {:.3g} m from the goal",
          goal.name, t, pushes_, pushes_ == 1 ? "" : "s", pushWork_, status.worstDistance);
    }
    const double interval = spec_.pushInterval > 0.0 ? spec_.pushInterval : spec_.window;
    if (t - lastPush_ < interval || static_cast<int>(added_.size()) >= spec_.maxObstacles)
      return std::nullopt;
  } else {
    const bool stuck = status.meanSpeed < spec_.speedThreshold &&
                       status.worstDistance > settleDistance && touching;
    if (!stuck) {
      stoppedSince_ = -1.0;
      return std::nullopt;
    }
    if (stoppedSince_ < 0.0) stoppedSince_ = t;
    if (t - stoppedSince_ < spec_.window || static_cast<int>(added_.size()) >= spec_.maxObstacles)
      return std::nullopt;
    pushing_ = true;
    stuckDistance_ = status.worstDistance;
    pushStart_ = t;
    pushes_ = 0;
    pushWork_ = 0.0;
    event = fmt::format(
        "goal '{}': local minimum at t = {:.4g} s ({:.3g} m from the goal, speed {:.3g} m/s); "
        "virtual obstacles from now on",
        goal.name, t, status.worstDistance, status.meanSpeed);
  }
  // A virtual obstacle at the local minimum, beside the stuck particle, so that
  // it pushes it across its pull to the goal. The side is chosen once (the
  // horizontal perpendicular to the pull, turned the way the robot's blocking
  // contacts leave free), so successive obstacles push the same way and stay
  // behind it, filling the minimum.
  const double worstDistance = status.worstDistance;
  const Vec3 toGoal = (s.position[goal.targets[worst]] - s.position[i]) / worstDistance;
  if (!side_) {
    Vec3 sideways = cross(toGoal, Vec3{0.0, 0.0, 1.0});
    if (norm(sideways) < 1e-6) sideways = cross(toGoal, Vec3{1.0, 0.0, 0.0});
    sideways = sideways / norm(sideways);
    // The contacts' push on the robot, across the pull: go the way it points.
    Vec3 contactPush;
    for (const Contact& c : world.contacts()) {
      const bool aIn = robot.has(c.a);
      const bool otherIn = !c.withEnvironment() && robot.has(c.other);
      if (aIn && !otherIn) contactPush += c.normal * c.normalForce;
      if (otherIn && !aIn) contactPush -= c.normal * c.normalForce;
    }
    if (dot(contactPush, sideways) < 0.0) sideways = sideways * -1.0;
    side_ = sideways;
  }
  Vec3 push = *side_ - toGoal * dot(*side_, toGoal);
  push = norm(push) > 1e-9 ? push / norm(push) : *side_;
  const Model& model = world.model();
  const auto isVirtual = [&](ParticleIndex j) {
    return model.objects[static_cast<std::size_t>(model.objectOf[static_cast<std::size_t>(j)])].kind ==
           "virtual";
  };
  const double radius = spec_.obstacleRadius;
  // The pushed particle for a push along d: the stuck one, or for a point a link
  // carries (it touches nothing) the robot's rearmost particle along d within two
  // obstacle radii of it (the nearest if none; ties: the lower index), so that the
  // sphere behind it meets the link's back and not its flank.
  const auto pushedFor = [&](const Vec3& d) {
    if (!isVirtual(i)) return i;
    ParticleIndex pushed = i, nearest = i;
    double rearmost = 1e300, closest = 1e300;
    for (ParticleIndex j = 0; j < model.particleCount(); ++j) {
      if (!robot.has(j) || isVirtual(j)) continue;
      const double distance = norm(s.position[j] - s.position[i]);
      if (distance < closest) {
        closest = distance;
        nearest = j;
      }
      if (distance <= 2.0 * radius && dot(s.position[j], d) < rearmost) {
        rearmost = dot(s.position[j], d);
        pushed = j;
      }
    }
    return rearmost < 1e300 ? pushed : nearest;
  };
  // The elastic energy (J) a sphere at `c` would add, ½ κ_c d² over every
  // particle it overlaps (virtual ones touch nothing), with κ_c the stiffest
  // material's: an upper bound of the work the World will book.
  double stiffness = 0.0;
  for (const Material& m : model.materials) stiffness = std::max(stiffness, m.contactStiffness);
  for (const ContactPairOverride& p : model.contact.pairOverrides)
    stiffness = std::max(stiffness, p.stiffness);
  const auto overlapEnergy = [&](const Vec3& c) {
    double energy = 0.0;
    for (ParticleIndex j = 0; j < model.particleCount(); ++j) {
      if (!model.moves(j) || isVirtual(j)) continue;
      const double d = norm(s.position[j] - c) - radius - model.radius[j];
      if (d < 0.0) energy += 0.5 * stiffness * d * d;
    }
    return energy;
  };
  // Where it goes: beside the stuck particle on the pushing side, turned by up
  // to 60° in the plane of the push and the pull if that side is taken by the
  // robot's own particles (a sphere landing on them would inject their overlap);
  // at the first obstacle the other side is as good, and is then kept.
  // It then overlaps the stuck particle by half the smaller radius, halved
  // until the work it injects is within maxWork.
  const auto centreFor = [&](const Vec3& direction, double o) {
    const ParticleIndex pushed = pushedFor(direction);
    return s.position[pushed] - direction * (radius + model.radius[pushed] - o);
  };
  const double bound = spec_.maxWork > 0.0 ? spec_.maxWork : 1e300;
  std::optional<Vec3> direction;
  for (double degrees : {0.0, -20.0, 20.0, -40.0, 40.0, -60.0, 60.0}) {
    for (double flip : {1.0, -1.0}) {
      if (flip < 0.0 && !added_.empty()) break;  // the side is kept once chosen
      const double beta = degrees * M_PI / 180.0;
      const Vec3 d = push * (flip * std::cos(beta)) + toGoal * std::sin(beta);
      if (overlapEnergy(centreFor(d, 0.0)) <= bound) {
        direction = d;
        break;
      }
    }
    if (direction) break;
  }
  if (!direction) return event;  // no free place this time; the next interval tries again
  if (dot(*direction, *side_) < 0.0) side_ = *side_ * -1.0;
  double overlap = 0.5 * std::min(radius, model.radius[pushedFor(*direction)]);
  for (int k = 0; k < 30 && overlapEnergy(centreFor(*direction, overlap)) > bound; ++k)
    overlap *= 0.5;
  SphereObstacle sphere;
  sphere.center = centreFor(*direction, overlap);
  sphere.radius = radius;
  world.bookExternalWork();  // what earlier edits did is not this obstacle's
  world.addSphereObstacle(sphere);
  const double work = world.bookExternalWork();
  work_ += work;
  pushWork_ += work;
  ++pushes_;
  lastPush_ = t;
  added_.push_back(sphere);
  return event;
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

ObjectMotion objectMotion(const World& world, std::int32_t object) {
  return objectMotion(world.model(), world.state(), object);
}

ObjectMotion objectMotion(const Model& model, const State& s, std::int32_t object) {
  const ObjectInfo& info = model.objects[static_cast<std::size_t>(object)];
  ObjectMotion motion;
  double mass = 0.0;
  Vec3 momentum;
  for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i) {
    motion.center += s.position[i] * model.mass[i];
    momentum += s.velocity[i] * model.mass[i];
    mass += model.mass[i];
  }
  if (!(mass > 0.0)) return motion;
  motion.center = motion.center / mass;
  motion.velocity = momentum / mass;
  // L = Σ m r × v' and I = Σ m (|r|² 1 − r rᵀ) about the centre of mass; ω = I⁻¹ L.
  Vec3 angular;
  double I[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i) {
    const Vec3 r = s.position[i] - motion.center;
    const double m = model.mass[i];
    angular += cross(r, s.velocity[i] - motion.velocity) * m;
    const double rr[3] = {r.x, r.y, r.z};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) I[a][b] += m * ((a == b ? dot(r, r) : 0.0) - rr[a] * rr[b]);
  }
  const double det = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) -
                     I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0]) +
                     I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]);
  if (!(std::abs(det) > 0.0)) return motion;  // one particle, or a line: no rotation measured
  const auto cofactor = [&I](int a, int b) {
    const int a1 = (a + 1) % 3, a2 = (a + 2) % 3, b1 = (b + 1) % 3, b2 = (b + 2) % 3;
    return I[a1][b1] * I[a2][b2] - I[a1][b2] * I[a2][b1];
  };
  const double L[3] = {angular.x, angular.y, angular.z};
  double w[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) w[a] += cofactor(b, a) / det * L[b];
  motion.angularVelocity = {w[0], w[1], w[2]};
  return motion;
}

GraspCheck::GraspCheck(GraspSpec spec, const Model& model) : spec_(std::move(spec)) {
  outcome_.object = model.objects.at(static_cast<std::size_t>(spec_.object)).name;
  outcome_.tolerance = spec_.tolerance;
}

std::optional<std::string> GraspCheck::update(World& world) {
  const Model& model = world.model();
  const State& s = world.state();
  const double t = s.time;
  const ObjectInfo& info = model.objects[static_cast<std::size_t>(spec_.object)];
  const auto inObject = [&](ParticleIndex i) {
    return i >= info.firstParticle && i < info.firstParticle + info.particleCount;
  };
  const ObjectMotion motion = objectMotion(world, spec_.object);
  // MODEL §5.3: the hand closes by its joints. Each closing joint's target moves
  // from its start value towards the object (the way that turns the joint's
  // moving arm towards the object's centre), by closeAngle over closeTime.
  if (start_.empty()) {
    for (std::size_t joint : spec_.closeJoints) {
      const JointSpring& js =
          model.jointSprings[static_cast<std::size_t>(model.joints[joint].connector)];
      const Vec3 axis = s.position[js.d] - s.position[js.c];
      const Vec3 arm = s.position[js.b] - s.position[js.c];
      // Turning b positively about the axis (c → d) increases the joint angle.
      const double towards = dot(cross(axis, arm), motion.center - s.position[js.b]);
      start_.push_back(jointValue(model, s, joint));
      direction_.push_back(towards >= 0.0 ? 1.0 : -1.0);
    }
  }
  const double closing = spec_.closeTime > 0.0 ? std::min(1.0, t / spec_.closeTime) : 1.0;
  for (std::size_t k = 0; k < spec_.closeJoints.size(); ++k)
    setJointTarget(world, spec_.closeJoints[k],
                   start_[k] + direction_[k] * closing * spec_.closeAngle);

  // The hand's force on the object: the contact forces between them (normal and
  // friction), i.e. the object's net force less gravity and its own drag (its
  // connectors and self-contacts sum to zero); the torque about its centre of mass.
  Vec3 force, torque;
  for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i) {
    const Vec3 f =
        world.forces()[i] - model.gravity * model.mass[i] + s.velocity[i] * model.linearDamping[i];
    force += f;
    torque += cross(s.position[i] - motion.center, f);
  }
  int contacts = 0, fixedContacts = 0;
  double grip = 0.0;
  for (const Contact& c : world.contacts()) {
    if (c.withEnvironment() || inObject(c.a) == inObject(c.other)) continue;
    const ParticleIndex other = inObject(c.a) ? c.other : c.a;
    if (spec_.hand >= 0 && model.objectOf[static_cast<std::size_t>(other)] != spec_.hand) continue;
    ++contacts;
    if (model.isFixed(other)) ++fixedContacts;
    grip += c.normalForce;
  }
  outcome_.netForce = force;
  outcome_.netTorque = torque;
  outcome_.gripForce = grip;
  outcome_.contacts = contacts;
  outcome_.fixedContacts = fixedContacts;
  outcome_.speed = norm(motion.velocity);
  outcome_.angularSpeed = norm(motion.angularVelocity);

  // Settled by velocity: slow in translation and rotation for settleHold, once closed.
  const bool slow = closing >= 1.0 && outcome_.speed < spec_.settleSpeed &&
                    outcome_.angularSpeed < spec_.settleAngularSpeed && contacts > 0;
  if (!slow) slowSince_ = -1.0;
  if (slow && slowSince_ < 0.0) slowSince_ = t;
  const bool held = slow && t - slowSince_ >= spec_.settleHold;
  std::optional<std::string> event;
  if (!outcome_.settled) {
    if (!held) return std::nullopt;
    outcome_.settled = true;
    outcome_.settledAt = t;
    rest_ = motion.center;
    event = fmt::format(
        "grasp: object '{}' at rest in the hand at t = {:.4g} s at [{:.4g}, {:.4g}, {:.4g}] "
        "(speed {:.2g} m/s, {:.2g} rad/s); hand's net force {:.3g} N, torque {:.3g} N·m, grip "
        "{:.3g} N through {} contacts",
        outcome_.object, t, rest_.x, rest_.y, rest_.z, outcome_.speed, outcome_.angularSpeed,
        norm(force), norm(torque), grip, contacts);
  }
  outcome_.largestDrift = std::max(outcome_.largestDrift, norm(motion.center - rest_));
  if (!outcome_.disturbed && spec_.disturbanceTime >= 0.0 && t >= spec_.disturbanceTime) {
    outcome_.disturbed = true;
    for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i)
      if (!model.isFixed(i)) world.setVelocity(i, s.velocity[i] + spec_.disturbance);
    slowSince_ = -1.0;
    event = fmt::format("grasp: disturbance of [{:.3g}, {:.3g}, {:.3g}] m/s at t = {:.4g} s",
                        spec_.disturbance.x, spec_.disturbance.y, spec_.disturbance.z, t);
  } else if (outcome_.disturbed && !outcome_.resettled && held) {
    outcome_.resettled = true;
    outcome_.resettledAt = t;
    event = fmt::format(
        "grasp: object at rest again at t = {:.4g} s, {:.3g} m from its rest "
        "position",
        t, norm(motion.center - rest_));
  }
  const bool disturbance = spec_.disturbanceTime >= 0.0;
  outcome_.stable = outcome_.settled && outcome_.largestDrift <= spec_.tolerance &&
                    (!disturbance || outcome_.resettled);
  return event;
}

std::string GraspCheck::verdict() const {
  const GraspOutcome& o = outcome_;
  if (!o.settled)
    return fmt::format(
        "grasp NOT stable: '{}' never came to rest in the hand (speed {:.3g} m/s, "
        "{:.3g} rad/s at the end)",
        o.object, o.speed, o.angularSpeed);
  return fmt::format(
      "grasp {}: largest drift {:.3g} m after settling (tolerance {:.3g} m){}; hand's net force "
      "{:.3g} N and torque {:.3g} N·m on the object against a grip of {:.3g} N ({} contacts, {} "
      "on the palm)",
      o.stable ? "stable" : "NOT stable", o.largestDrift, o.tolerance,
      o.disturbed ? (o.resettled ? ", at rest again after the disturbance"
                                 : ", not at rest again after the disturbance")
                  : "",
      norm(o.netForce), norm(o.netTorque), o.gripForce, o.contacts, o.fixedContacts);
}

namespace {

using nlohmann::json;
using output::exactNumber;
using output::exactVec3;
using output::numberFromJson;
using output::vec3FromJson;

// A time (s) or a count that is "not yet" below zero, as summary.json has it: null.
json timeOrNull(double t) { return t >= 0.0 ? json(t) : json(); }

json vec3Json(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

}  // namespace

json GraspCheck::save() const {
  const GraspOutcome& o = outcome_;
  return {{"settled", o.settled},
          {"settled_at", exactNumber(o.settledAt)},
          {"disturbed", o.disturbed},
          {"resettled", o.resettled},
          {"resettled_at", exactNumber(o.resettledAt)},
          {"largest_drift", exactNumber(o.largestDrift)},
          {"stable", o.stable},
          {"start", output::exactNumbers(start_)},
          {"direction", output::exactNumbers(direction_)},
          {"slow_since", exactNumber(slowSince_)},
          {"rest", exactVec3(rest_)}};
}

void GraspCheck::restore(const json& saved) {
  GraspOutcome& o = outcome_;
  o.settled = saved.at("settled").get<bool>();
  o.settledAt = numberFromJson(saved.at("settled_at"), "grasp settled_at");
  o.disturbed = saved.at("disturbed").get<bool>();
  o.resettled = saved.at("resettled").get<bool>();
  o.resettledAt = numberFromJson(saved.at("resettled_at"), "grasp resettled_at");
  o.largestDrift = numberFromJson(saved.at("largest_drift"), "grasp largest_drift");
  o.stable = saved.at("stable").get<bool>();
  start_ = output::numbersFromJson(saved.at("start"), "grasp start");
  direction_ = output::numbersFromJson(saved.at("direction"), "grasp direction");
  if (direction_.size() != start_.size() ||
      (!start_.empty() && start_.size() != spec_.closeJoints.size()))
    throw std::runtime_error("grasp: the checkpoint closes other joints than the scene");
  slowSince_ = numberFromJson(saved.at("slow_since"), "grasp slow_since");
  rest_ = vec3FromJson(saved.at("rest"), "grasp rest");
}

json LocalMinimumEscape::save() const {
  auto added = json::array();
  for (const SphereObstacle& o : added_)
    added.push_back({exactVec3(o.center), exactNumber(o.radius), o.material});
  return {{"stopped_since", exactNumber(stoppedSince_)},
          {"pushing", pushing_},
          {"stuck_distance", exactNumber(stuckDistance_)},
          {"last_push", exactNumber(lastPush_)},
          {"push_start", exactNumber(pushStart_)},
          {"pushes", pushes_},
          {"push_work", exactNumber(pushWork_)},
          {"work", exactNumber(work_)},
          {"added", added},
          {"side", side_ ? exactVec3(*side_) : json()}};
}

void LocalMinimumEscape::restore(const json& saved) {
  stoppedSince_ = numberFromJson(saved.at("stopped_since"), "escape stopped_since");
  pushing_ = saved.at("pushing").get<bool>();
  stuckDistance_ = numberFromJson(saved.at("stuck_distance"), "escape stuck_distance");
  lastPush_ = numberFromJson(saved.at("last_push"), "escape last_push");
  pushStart_ = numberFromJson(saved.at("push_start"), "escape push_start");
  pushes_ = saved.at("pushes").get<int>();
  pushWork_ = numberFromJson(saved.at("push_work"), "escape push_work");
  work_ = numberFromJson(saved.at("work"), "escape work");
  added_.clear();
  for (const auto& o : saved.at("added")) {
    SphereObstacle sphere;
    sphere.center = vec3FromJson(o.at(0), "escape obstacle centre");
    sphere.radius = numberFromJson(o.at(1), "escape obstacle radius");
    sphere.material = o.at(2).get<std::int32_t>();
    added_.push_back(sphere);
  }
  side_.reset();
  if (!saved.at("side").is_null()) side_ = vec3FromJson(saved.at("side"), "escape side");
}

namespace {

// The scene's robotics tasks (SceneTasks) run as one Task: joint limits, escapes,
// grasps, then goals, in that order. Their outcomes live in a shared block the
// hook's caller may read after each step.
class SceneTaskSet final : public Task {
 public:
  SceneTaskSet(const Scene& scene, std::shared_ptr<TaskOutcomes> outcomes)
      : limiter_(scene.robotics.limits),
        goals_(scene.robotics.goals),
        out_(std::move(outcomes)),
        duration_(scene.run.duration),
        previousTime_(scene.initial.time) {
    for (const EscapeSpec& e : scene.robotics.escapes) escapes_.emplace_back(e);
    for (const GraspSpec& g : scene.robotics.grasps) grasps_.emplace_back(g, scene.model);
    for (const auto& grasp : grasps_) out_->grasps.push_back(grasp.outcome());
    if (!scene.robotics.control.empty()) controller_.emplace(scene.robotics.control, scene.model);
  }

  void start(World& world, std::vector<std::string>& events) override {
    if (controller_) controller_->start(world, events);
  }

  bool step(World& world, std::vector<std::string>& events) override {
    TaskOutcomes& out = *out_;
    // The controller first: a joint limit then overrides its servo where it must.
    if (controller_) controller_->step(world, events);
    limiter_.update(world);
    for (auto& escape : escapes_) {
      if (auto event = escape.update(world, goals_[escape.goal()])) events.push_back(*event);
      out.goals[escape.goal()].virtualObstacles = static_cast<int>(escape.added().size());
      out.goals[escape.goal()].escapeWork = escape.work();
    }
    for (std::size_t k = 0; k < grasps_.size(); ++k) {
      if (auto event = grasps_[k].update(world)) events.push_back(*event);
      out.grasps[k] = grasps_[k].outcome();
    }
    bool keepGoing = true;
    const double t = world.state().time;
    for (std::size_t g = 0; g < goals_.size(); ++g) {
      if (auto event = arriveVirtualRobot(world, goals_[g])) events.push_back(*event);
      const GoalStatus status = goalStatus(world, goals_[g]);
      out.goals[g].distance = status.worstDistance;
      if (status.reached && !out.goals[g].reached) {
        out.goals[g].reached = true;
        out.goals[g].reachedAt = t;
        events.push_back(fmt::format("goal '{}' reached at t = {:.4g} s (within {:.3g} m)",
                                     goals_[g].name, t, status.worstDistance));
        if (goals_[g].stopWhenReached) keepGoing = false;
      }
    }
    // The last step: the run ends within half a step of its duration (a constant
    // step's accumulated time may fall short of it by rounding).
    const double step = t - previousTime_;
    previousTime_ = t;
    const bool last = !keepGoing || t + 0.5 * step >= duration_;
    if (last && !reported_) {
      reported_ = true;
      for (std::size_t g = 0; g < goals_.size(); ++g) {
        if (out.goals[g].reached) continue;
        events.push_back(fmt::format("goal '{}' not reached: {:.3g} m away at the end",
                                     goals_[g].name, out.goals[g].distance));
      }
      for (const auto& grasp : grasps_) events.push_back(grasp.verdict());
      if (limiter_.engagements() > 0)
        events.push_back(fmt::format("joint limits engaged {} times", limiter_.engagements()));
    }
    return keepGoing;
  }

  // summary.json "outcomes" (docs/output-format.md).
  json outcomes(const World& world) const override {
    const TaskOutcomes& o = *out_;
    json out = json::object();
    if (!goals_.empty()) {
      auto goals = json::array();
      for (std::size_t g = 0; g < goals_.size(); ++g) {
        const GoalOutcome& goal = o.goals[g];
        const GoalStatus status = goalStatus(world, goals_[g]);
        goals.push_back({{"name", goal.name},
                         {"reached", goal.reached},
                         {"time_s", timeOrNull(goal.reachedAt)},
                         {"final_distance_m", status.worstDistance},
                         {"final_mean_speed_m_s", status.meanSpeed},
                         {"tolerance_m", goals_[g].tolerance},
                         {"virtual_obstacles", goal.virtualObstacles},
                         {"escape_work_J", goal.escapeWork}});
      }
      out["goals"] = goals;
    }
    if (!grasps_.empty()) {
      auto grasps = json::array();
      for (const GraspOutcome& g : o.grasps)
        grasps.push_back({{"object", g.object},
                          {"settled", g.settled},
                          {"settled_time_s", g.settled ? json(g.settledAt) : json()},
                          {"disturbed", g.disturbed},
                          {"resettled", g.resettled},
                          {"resettled_time_s", g.resettled ? json(g.resettledAt) : json()},
                          {"stable", g.stable},
                          {"largest_drift_m", g.largestDrift},
                          {"tolerance_m", g.tolerance},
                          {"net_force_N", vec3Json(g.netForce)},
                          {"net_torque_N_m", vec3Json(g.netTorque)},
                          {"grip_force_N", g.gripForce},
                          {"contacts", g.contacts},
                          {"palm_contacts", g.fixedContacts},
                          {"speed_m_s", g.speed},
                          {"angular_speed_rad_s", g.angularSpeed}});
      out["grasps"] = grasps;
    }
    if (!escapes_.empty()) {
      auto escapes = json::array();
      for (const auto& escape : escapes_)
        escapes.push_back({{"goal", goals_[escape.goal()].name},
                           {"virtual_obstacles", escape.added().size()},
                           {"work_J", escape.work()}});
      out["escapes"] = escapes;
    }
    out["joint_limit_engagements"] = limiter_.engagements();
    if (controller_)
      if (const json control = controller_->outcomes(world); control.is_object())
        out.update(control);
    return out;
  }

  json save() const override {
    auto goals = json::array();
    for (std::size_t g = 0; g < goals_.size(); ++g) {
      const GoalOutcome& o = out_->goals[g];
      goals.push_back({{"travel_time", exactNumber(goals_[g].travelTime)},
                       {"reached", o.reached},
                       {"reached_at", exactNumber(o.reachedAt)},
                       {"distance", exactNumber(o.distance)}});
    }
    auto escapes = json::array(), grasps = json::array();
    for (const auto& e : escapes_) escapes.push_back(e.save());
    for (const auto& g : grasps_) grasps.push_back(g.save());
    return {{"limiter", limiter_.save()},
            {"goals", goals},
            {"escapes", escapes},
            {"grasps", grasps},
            {"reported", reported_},
            {"previous_time", exactNumber(previousTime_)},
            {"control", controller_ ? controller_->save() : json()}};
  }

  void restore(const json& saved) override {
    const auto& goals = saved.at("goals");
    const auto& escapes = saved.at("escapes");
    const auto& grasps = saved.at("grasps");
    if (goals.size() != goals_.size() || escapes.size() != escapes_.size() ||
        grasps.size() != grasps_.size())
      throw std::runtime_error("robotics tasks: the checkpoint is of a scene with other tasks");
    limiter_.restore(saved.at("limiter"));
    for (std::size_t g = 0; g < goals_.size(); ++g) {
      GoalOutcome& o = out_->goals[g];
      goals_[g].travelTime = numberFromJson(goals[g].at("travel_time"), "goal travel_time");
      o.reached = goals[g].at("reached").get<bool>();
      o.reachedAt = numberFromJson(goals[g].at("reached_at"), "goal reached_at");
      o.distance = numberFromJson(goals[g].at("distance"), "goal distance");
    }
    for (std::size_t k = 0; k < escapes_.size(); ++k) {
      escapes_[k].restore(escapes[k]);
      GoalOutcome& o = out_->goals[escapes_[k].goal()];
      o.virtualObstacles = static_cast<int>(escapes_[k].added().size());
      o.escapeWork = escapes_[k].work();
    }
    for (std::size_t k = 0; k < grasps_.size(); ++k) {
      grasps_[k].restore(grasps[k]);
      out_->grasps[k] = grasps_[k].outcome();
    }
    reported_ = saved.at("reported").get<bool>();
    previousTime_ = numberFromJson(saved.at("previous_time"), "tasks previous_time");
    if (controller_) {
      if (!saved.contains("control") || saved.at("control").is_null())
        throw std::runtime_error("robotics tasks: the checkpoint has no control state");
      controller_->restore(saved.at("control"));
    }
  }

 private:
  std::optional<Controller> controller_;
  JointLimiter limiter_;
  std::vector<GoalSpec> goals_;
  std::vector<LocalMinimumEscape> escapes_;
  std::vector<GraspCheck> grasps_;
  std::shared_ptr<TaskOutcomes> out_;
  double duration_ = 0.0, previousTime_ = 0.0;
  bool reported_ = false;
};

}  // namespace

SceneTaskHook makeSceneTaskHook(const Scene& scene) {
  auto outcomes = std::make_shared<TaskOutcomes>();
  for (const GoalSpec& g : scene.robotics.goals) outcomes->goals.push_back({.name = g.name});
  if (scene.robotics.empty()) return {StepTask(), outcomes};
  return {StepTask(std::make_shared<SceneTaskSet>(scene, outcomes)), outcomes};
}

StepTask makeSceneTasks(const Scene& scene) { return makeSceneTaskHook(scene).task; }

}  // namespace robophi::robotics
