// Robotics tasks between steps (MODEL §5): goal monitoring, local-minimum escape,
// grasp checks, joint limits. Public API only.
#include "robotics/tasks.h"

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "output/json_numbers.h"
#include "robophi/surface_points.h"

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

// What holds a robot at a local minimum: its contacts with what is outside it.
struct Blocking {
  double force = 0.0;  ///< |Σ F_n n| (N)
  Vec3 normal;         ///< unit: Σ F_n n, each normal pointing into the robot
  Vec3 push;           ///< Σ F_n n (N)
  Vec3 point;  ///< the blocked points (a particle's, a surface vertex's, a ball's centre), by force
  double radius = 0.0;         ///< the patch they span about `point` (m), with their radii
  std::vector<Vec3> touching;  ///< every contact's normal (into the robot), blocking or not
  Vec3 held;  ///< Σ F_n n (N) of every contact against the pull, the virtual obstacles' too
};

// How far (× its radius) from the most loaded holding contact the others count
// as the same place.
constexpr double kPatchReach = 4.0;

// Where contact `c` touches the robot (its particle `mine`), and the radius
// there: a particle's centre and radius, a surface vertex (and its heaviest
// particle's radius), a round ball's centre and radius.
std::pair<Vec3, double> blockedPoint(const Model& model, const State& s, const Contact& c,
                                     ParticleIndex mine) {
  if (c.rim >= 0 && model.rims[static_cast<std::size_t>(c.rim)].isSphere()) {
    const RimRing& ball = model.rims[static_cast<std::size_t>(c.rim)];
    Vec3 sum;
    double mass = 0.0;
    for (ParticleIndex j = ball.first; j < ball.first + ball.count; ++j) {
      sum += s.position[j] * model.mass[j];
      mass += model.mass[j];
    }
    return {mass > 0.0 ? sum / mass : s.position[mine], ball.sphereRadius};
  }
  if (c.vertex >= 0 && mine == c.a)  // a vertex, or a point of an edge
    return {touchingPoint(model, c, s.position), model.radius[mine]};
  return {s.position[mine], model.radius[mine]};
}

// The contacts that hold the robot against its pull `toGoal` (their normals
// oppose it), those of the escape's own obstacles (material `virtualMaterial`;
// -1: none yet) left out but in `held`.
Blocking blockingContacts(const World& world, const RobotOf& robot, std::int32_t virtualMaterial,
                          const Vec3& toGoal) {
  const Model& model = world.model();
  const Environment& environment = model.environment;
  const std::int32_t firstSphere =
      environment.itemCount() - static_cast<std::int32_t>(environment.spheres.size());
  const auto isVirtual = [&](const Contact& c) {
    const std::int32_t item = c.environmentItem();
    return c.withEnvironment() && virtualMaterial >= 0 && item >= firstSphere &&
           environment.spheres[static_cast<std::size_t>(item - firstSphere)].material ==
               virtualMaterial;
  };
  const State& s = world.state();
  Blocking out;
  // The holding contacts about the most loaded one (within kPatchReach of its
  // radius): the place one obstacle can lift; contacts farther along the robot
  // (an arm's link elsewhere) are another place.
  struct Held {
    Vec3 at, normal;
    double radius, force;
  };
  std::vector<Held> held;
  for (const Contact& c : world.contacts()) {
    const bool aIn = robot.has(c.a);
    const bool otherIn = !c.withEnvironment() && robot.has(c.other);
    if (aIn == otherIn || !(c.normalForce > 0.0)) continue;
    const Vec3 normal = aIn ? c.normal : c.normal * -1.0;
    const bool holds = dot(normal, toGoal) < 0.0;
    if (holds) out.held += normal * c.normalForce;
    if (isVirtual(c)) continue;
    out.touching.push_back(normal);
    if (!holds) continue;
    const auto [at, radius] = blockedPoint(model, s, c, aIn ? c.a : c.other);
    held.push_back({at, normal, radius, c.normalForce});
  }
  if (held.empty()) return out;
  const Held most = *std::max_element(
      held.begin(), held.end(), [](const Held& x, const Held& y) { return x.force < y.force; });
  std::erase_if(held, [&](const Held& h) {
    return norm(h.at - most.at) > kPatchReach * std::max(most.radius, h.radius);
  });
  double weight = 0.0;
  for (const Held& h : held) {
    out.push += h.normal * h.force;
    out.point += h.at * h.force;
    weight += h.force;
  }
  out.force = norm(out.push);
  if (!(out.force > 0.0)) return out;
  out.normal = out.push / out.force;
  out.point = out.point / weight;
  for (const Held& h : held) out.radius = std::max(out.radius, norm(h.at - out.point) + h.radius);
  return out;
}

// MODEL §5.2, docs/robotics.md "Escape": how an obstacle meets the robot (rad
// from the blocking normal towards the escape), how hard it pushes (× the
// blocking force), and the default shares of the energy scale one obstacle and
// all of them may inject.
constexpr double kTilt = M_PI / 4.0;
constexpr double kPushShare = 2.0;
constexpr double kObstacleShare = 0.01;
constexpr double kBudgetShare = 0.1;

}  // namespace

std::optional<std::string> LocalMinimumEscape::update(World& world, const GoalSpec& goal) {
  // The energy scale (as the run's account has it): the largest kinetic and
  // elastic energy so far. Shares of it bound the work the obstacles inject.
  {
    const EnergyTally e = world.energy();
    energyScale_ = std::max(
        energyScale_, e.kinetic + e.linearSpring + e.torsionSpring + e.jointSpring + e.contact);
  }
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
    // Free: nearer the goal by a tenth of where it was stuck, or touching nothing
    // for a window (an obstacle lifts it off what held it for a moment).
    if (touching)
      untouchedSince_ = -1.0;
    else if (untouchedSince_ < 0.0)
      untouchedSince_ = t;
    if (status.worstDistance < 0.9 * stuckDistance_ ||
        (untouchedSince_ >= 0.0 && t - untouchedSince_ >= spec_.window)) {
      untouchedSince_ = -1.0;
      pushing_ = false;
      stoppedSince_ = -1.0;
      return fmt::format(
          "goal '{}': out of the local minimum at t = {:.4g} s after {} virtual obstacle{} "
          "(work {:.3g} J), {:.3g} m from the goal",
          goal.name, t, pushes_, pushes_ == 1 ? "" : "s", pushWork_, status.worstDistance);
    }
    const double interval = spec_.pushInterval > 0.0 ? spec_.pushInterval : spec_.window / 3.0;
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
  // Nothing more once the work budget is spent: the goal is then reported not reached.
  const double budget = spec_.workBudget > 0.0 ? spec_.workBudget : kBudgetShare * energyScale_;
  const double perObstacle = spec_.maxWork > 0.0 ? spec_.maxWork : kObstacleShare * energyScale_;
  if (budget - work_ < 0.1 * perObstacle) return event;
  const double worstDistance = status.worstDistance;
  const Vec3 toGoal = (s.position[goal.targets[worst]] - s.position[i]) / worstDistance;
  const Blocking blocking = blockingContacts(world, robot, material_, toGoal);
  if (!(blocking.force > 0.0)) return event;
  // The escape direction, along the blocking surface: the one the last obstacle
  // pushed towards, else the first that no contact of the robot's opposes (a
  // corner, a trap's side, the ground) of: across the pull (first the way the
  // blocking contacts push across it, then the other way), the third direction
  // either way, back from the goal.
  const auto alongSurface = [&](const Vec3& d) -> std::optional<Vec3> {
    const Vec3 v = d - blocking.normal * dot(d, blocking.normal);
    if (norm(v) < 0.3) return std::nullopt;
    const Vec3 u = v / norm(v);
    for (const Vec3& n : blocking.touching)
      if (dot(u, n) < -0.2) return std::nullopt;
    return u;
  };
  Vec3 sideways = cross(toGoal, Vec3{0.0, 0.0, 1.0});
  if (norm(sideways) < 1e-6) sideways = cross(toGoal, Vec3{1.0, 0.0, 0.0});
  sideways = sideways / norm(sideways);
  if (dot(blocking.push, sideways) < 0.0) sideways = sideways * -1.0;
  const Vec3 side = side_.value_or(sideways);
  Vec3 third = cross(toGoal, side);
  third = norm(third) > 1e-9 ? third / norm(third) : cross(side, blocking.normal);
  std::optional<Vec3> along;
  for (const Vec3& d : {side, third, third * -1.0, side * -1.0, toGoal * -1.0}) {
    if ((along = alongSurface(d))) break;
  }
  if (!along) return event;  // boxed in on every side: the next interval tries again
  side_ = *along;
  // The obstacle comes in from under the blocking surface towards the robot's
  // blocking point, turned towards the escape direction by kTilt: the robot is
  // lifted off what holds it (no friction: the obstacle's material has none) and
  // rests on a slope that its own pull slides it down, along the surface.
  const Vec3 approach = blocking.normal * std::cos(kTilt) +
                        *along * std::sin(kTilt);  // from the obstacle to the robot
  const Model& model = world.model();
  if (material_ < 0) {
    Material virtualMaterial = model.materials.front();
    virtualMaterial.name = "escape (virtual obstacles)";
    virtualMaterial.staticFriction = virtualMaterial.kineticFriction = 0.0;
    virtualMaterial.rollingResistance = 0.0;
    material_ = world.addMaterial(virtualMaterial);
  }
  SphereObstacle sphere;
  sphere.radius = spec_.obstacleRadius > 0.0 ? spec_.obstacleRadius : blocking.radius;
  sphere.material = material_;
  const auto centreAt = [&](double distance) { return blocking.point - approach * distance; };
  // Placed by trial in the World (its contact law, whatever the robot's shape):
  // the obstacle's push on the robot kPushShare × the blocking force, its work
  // within the bound; found by bisection on its distance from the blocking point.
  const double bound = std::min(perObstacle, budget - work_);
  double far = sphere.radius + 2.0 * blocking.radius;
  sphere.center = centreAt(far);
  world.bookExternalWork();  // what earlier edits did is not this obstacle's
  const std::int32_t item = world.addSphereObstacle(sphere);
  double work = world.bookExternalWork();
  const auto pushOf = [&]() {
    double push = 0.0;
    for (const Contact& c : world.contacts())
      if (c.withEnvironment() && c.environmentItem() == item) push += c.normalForce;
    return push;
  };
  for (int k = 0; k < 20 && pushOf() > 0.0; ++k) {  // out of reach first
    far *= 2.0;
    world.moveSphereObstacle(item, centreAt(far));
    work += world.bookExternalWork();
  }
  double near = 0.0;
  const double wanted = kPushShare * norm(blocking.held);
  for (int k = 0; k < 40; ++k) {
    const double middle = 0.5 * (near + far);
    world.moveSphereObstacle(item, centreAt(middle));
    work += world.bookExternalWork();
    if (pushOf() > wanted || work > bound)
      near = middle;
    else
      far = middle;
  }
  world.moveSphereObstacle(item, centreAt(far));
  work += world.bookExternalWork();
  sphere.center = centreAt(far);
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
          {"side", side_ ? exactVec3(*side_) : json()},
          {"energy_scale", exactNumber(energyScale_)},
          {"untouched_since", exactNumber(untouchedSince_)},
          {"material", material_}};
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
  // (Checkpoints before stop 49 have neither: the scale is then measured again.)
  energyScale_ = saved.contains("energy_scale")
                     ? numberFromJson(saved.at("energy_scale"), "escape energy_scale")
                     : 0.0;
  material_ = saved.contains("material") ? saved.at("material").get<std::int32_t>() : -1;
  untouchedSince_ = saved.contains("untouched_since")
                        ? numberFromJson(saved.at("untouched_since"), "escape untouched_since")
                        : -1.0;
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
