// robotics::Controller: actuators, mimic joints, moving bases and sequences
// between steps (docs/robots.md "Controlling joints"). Uses the public API only:
// World's edits (servo, drive, positions of fixed particles) and joint readings.
#include "robotics/controller.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "output/json_numbers.h"
#include "robophi/build/goals.h"
#include "robophi/joints.h"

namespace robophi::robotics {

namespace {

using nlohmann::json;
using output::exactNumber;
using output::exactNumbers;
using output::exactVec3s;
using output::numberFromJson;
using output::numbersFromJson;
using output::vec3sFromJson;

void require(const std::string& problem, const std::string& where) {
  if (!problem.empty()) throw std::invalid_argument(where + ": " + problem);
}

json optionalNumber(const std::optional<double>& v) { return v ? exactNumber(*v) : json(); }
std::optional<double> optionalFromJson(const json& j, const char* what) {
  if (j.is_null()) return std::nullopt;
  return numberFromJson(j, what);
}

json trajectoryToJson(const Trajectory& t) {
  return {{"kind", static_cast<int>(t.kind)},
          {"value", exactNumber(t.value)},
          {"times", exactNumbers(t.times)},
          {"values", exactNumbers(t.values)},
          {"interpolation", static_cast<int>(t.interpolation)},
          {"sine",
           {exactNumber(t.amplitude), exactNumber(t.period), exactNumber(t.phase),
            exactNumber(t.offset)}}};
}

Trajectory trajectoryFromJson(const json& j) {
  Trajectory t;
  t.kind = static_cast<Trajectory::Kind>(j.at("kind").get<int>());
  t.value = numberFromJson(j.at("value"), "trajectory value");
  t.times = numbersFromJson(j.at("times"), "trajectory times");
  t.values = numbersFromJson(j.at("values"), "trajectory values");
  t.interpolation = static_cast<build::Interpolation>(j.at("interpolation").get<int>());
  const json& s = j.at("sine");
  t.amplitude = numberFromJson(s.at(0), "sine amplitude");
  t.period = numberFromJson(s.at(1), "sine period");
  t.phase = numberFromJson(s.at(2), "sine phase");
  t.offset = numberFromJson(s.at(3), "sine offset");
  return t;
}

json actuatorToJson(const ActuatorSpec& a) {
  return {{"joint", a.joint},
          {"mode", static_cast<int>(a.mode)},
          {"gains", {exactNumber(a.kp), exactNumber(a.kd), exactNumber(a.kv)}},
          {"feed_forward", exactNumber(a.feedForward)},
          {"limits", {optionalNumber(a.effortLimit), optionalNumber(a.velocityLimit)}},
          {"losses", {optionalNumber(a.damping), optionalNumber(a.friction)}},
          {"target", trajectoryToJson(a.target)}};
}

ActuatorSpec actuatorFromJson(const json& j) {
  ActuatorSpec a;
  a.joint = j.at("joint").get<std::size_t>();
  a.mode = static_cast<JointMode>(j.at("mode").get<int>());
  a.kp = numberFromJson(j.at("gains").at(0), "kp");
  a.kd = numberFromJson(j.at("gains").at(1), "kd");
  a.kv = numberFromJson(j.at("gains").at(2), "kv");
  a.feedForward = numberFromJson(j.at("feed_forward"), "feed forward");
  a.effortLimit = optionalFromJson(j.at("limits").at(0), "effort limit");
  a.velocityLimit = optionalFromJson(j.at("limits").at(1), "velocity limit");
  a.damping = optionalFromJson(j.at("losses").at(0), "damping");
  a.friction = optionalFromJson(j.at("losses").at(1), "friction");
  a.target = trajectoryFromJson(j.at("target"));
  return a;
}

json baseToJson(const BaseMotionSpec& b) {
  json axes = json::array();
  for (const Trajectory& t : b.translation) axes.push_back(trajectoryToJson(t));
  return {{"name", b.name},
          {"particles", b.particles},
          {"translation", axes},
          {"axis", output::exactVec3(b.axis)},
          {"angle", trajectoryToJson(b.angle)}};
}

BaseMotionSpec baseFromJson(const json& j) {
  BaseMotionSpec b;
  b.name = j.at("name").get<std::string>();
  b.particles = j.at("particles").get<std::vector<ParticleIndex>>();
  for (std::size_t k = 0; k < 3; ++k) b.translation[k] = trajectoryFromJson(j.at("translation")[k]);
  b.axis = output::vec3FromJson(j.at("axis"), "base axis");
  b.angle = trajectoryFromJson(j.at("angle"));
  return b;
}

// The joint's position is an angle taken the short way round (not a rigid tree's,
// whose coordinate is not wrapped: Joint::wraps).
bool revolute(const World& world, std::size_t joint) {
  return world.model().joints[joint].wraps();
}

// The signed difference to − from (the short way round for an angle).
double difference(double from, double to, bool isRevolute) {
  return isRevolute ? wrapSigned(to - from) : to - from;
}

// Applies a command: the servo (position mode) or the servo off, and the drive.
void applyCommand(World& world, std::size_t joint, JointMode mode,
                  const build::JointCommand& command) {
  const Joint& j = world.model().joints[joint];
  const bool hasServo = j.hasServo();
  if (mode == JointMode::kPosition) {
    world.setJointServo(joint, command.stiffness, command.damping);
    double raw = jointRawValue(j, command.target);
    if (j.kind == JointKind::kPrismatic && j.driveSpring >= 0)
      raw = std::max(raw, 1e-9);  // a drive LS needs l0 > 0
    world.setJointTarget(joint, raw);
  } else if (hasServo) {
    world.setJointServo(joint, 0.0, 0.0);
  }
  world.setJointDrive(joint, command.drive);
}

}  // namespace

Controller::Controller(ControlSpec spec, const Model& model)
    : spec_(std::move(spec)), jointCount_(model.joints.size()) {
  for (std::size_t k = 0; k < spec_.actuators.size(); ++k)
    require(build::checkActuator(spec_.actuators[k], model), fmt::format("actuator {}", k));
  for (std::size_t k = 0; k < spec_.mimics.size(); ++k) {
    const MimicSpec& m = spec_.mimics[k];
    if (m.joint >= jointCount_ || m.leader >= jointCount_ || m.joint == m.leader)
      throw std::invalid_argument(
          fmt::format("mimic {}: joints {} and {} must be two different joints of the {}", k,
                      m.joint, m.leader, jointCount_));
    ActuatorSpec a{.joint = m.joint, .mode = JointMode::kPosition, .kp = m.kp, .kd = m.kd};
    require(build::checkActuator(a, model), fmt::format("mimic {}", k));
  }
  const auto checkBase = [&](const BaseMotionSpec& b, const std::string& where) {
    for (ParticleIndex p : b.particles)
      if (p < 0 || p >= model.particleCount())
        throw std::invalid_argument(fmt::format("{}: particle {} does not exist (the model has {})",
                                                where, p, model.particleCount()));
    for (const Trajectory& t : b.translation) require(build::checkTrajectory(t), where);
    require(build::checkTrajectory(b.angle), where + " angle");
    if (!isFinite(b.axis)) throw std::invalid_argument(where + ": the axis must be finite");
  };
  for (const BaseMotionSpec& b : spec_.bases) checkBase(b, "base '" + b.name + "'");
  for (std::size_t p = 0; p < spec_.phases.size(); ++p) {
    const PhaseSpec& phase = spec_.phases[p];
    const std::string where = fmt::format("phase '{}'", phase.name);
    for (const ActuatorSpec& a : phase.actuators) require(build::checkActuator(a, model), where);
    for (const BaseMotionSpec& b : phase.bases) checkBase(b, where + " base '" + b.name + "'");
    for (std::size_t j : phase.start.joints)
      if (j >= jointCount_)
        throw std::invalid_argument(fmt::format("{}: joint {} does not exist", where, j));
  }
  for (const ActuatorSpec& a : spec_.actuators) channel(a.joint).spec = a;
  for (const BaseMotionSpec& b : spec_.bases) bases_.push_back({b, -1.0, {}});
  phaseStarts_.assign(spec_.phases.size(), -1.0);
  phaseReasons_.assign(spec_.phases.size(), "");
}

Controller::Channel& Controller::channel(std::size_t joint) {
  if (joint >= jointCount_)
    throw std::out_of_range(
        fmt::format("Controller: joint {} does not exist (the model has {})", joint, jointCount_));
  for (Channel& c : channels_)
    if (c.spec.joint == joint) return c;
  Channel c;
  c.spec.joint = joint;
  channels_.push_back(c);
  return channels_.back();
}

const ActuatorSpec* Controller::actuator(std::size_t joint) const {
  for (const Channel& c : channels_)
    if (c.spec.joint == joint) return &c.spec;
  return nullptr;
}

double Controller::servoTarget(std::size_t joint) const {
  for (const Channel& c : channels_)
    if (c.spec.joint == joint) return c.servoTarget;
  return 0.0;
}

void Controller::setActuator(const ActuatorSpec& actuator) {
  Channel& c = channel(actuator.joint);
  c.spec = actuator;
  c.start = -1.0;
}

void Controller::setMode(std::size_t joint, JointMode mode) { channel(joint).spec.mode = mode; }

void Controller::setTarget(std::size_t joint, double value) {
  Channel& c = channel(joint);
  c.spec.target = Trajectory::constant(value);
  c.start = -1.0;
}

void Controller::setTrajectory(std::size_t joint, const Trajectory& trajectory) {
  require(build::checkTrajectory(trajectory), "Controller::setTrajectory");
  Channel& c = channel(joint);
  c.spec.target = trajectory;
  c.start = -1.0;
}

void Controller::setGains(std::size_t joint, double kp, double kd, double kv) {
  Channel& c = channel(joint);
  c.spec.kp = kp;
  c.spec.kd = kd;
  c.spec.kv = kv;
}

void Controller::addMimic(const MimicSpec& mimic) {
  if (mimic.joint >= jointCount_ || mimic.leader >= jointCount_ || mimic.joint == mimic.leader)
    throw std::invalid_argument("Controller::addMimic: joints must be two different joints");
  spec_.mimics.push_back(mimic);
}

void Controller::setBaseMotion(const BaseMotionSpec& base) {
  for (Base& b : bases_)
    if (b.spec.name == base.name) {
      b = {base, -1.0, {}};
      return;
    }
  bases_.push_back({base, -1.0, {}});
}

std::optional<std::string> Controller::conditionHolds(const ConditionSpec& c, const World& world,
                                                      double t) const {
  const double previous = nextPhase_ == 0 ? 0.0 : phaseStarts_[nextPhase_ - 1];
  switch (c.kind) {
    case ConditionSpec::Kind::kAt:
      if (t >= c.time) return fmt::format("at {:.6g} s", c.time);
      return std::nullopt;
    case ConditionSpec::Kind::kAfter:
      if (t - previous >= c.time) return fmt::format("{:.6g} s after the previous phase", c.time);
      return std::nullopt;
    case ConditionSpec::Kind::kJointsAtTarget: {
      double worst = 0.0;
      const Model& model = world.model();
      for (const Channel& ch : channels_) {
        const std::size_t j = ch.spec.joint;
        const bool listed = c.joints.empty()
                                ? ch.spec.mode == JointMode::kPosition
                                : std::find(c.joints.begin(), c.joints.end(), j) != c.joints.end();
        if (!listed) continue;
        // Keyframes: their last (held) value, where the joint is going; otherwise the
        // target now.
        const Trajectory& k = ch.spec.target;
        const double target = k.kind == Trajectory::Kind::kKeyframes
                                  ? k.values.back()
                                  : build::trajectoryValue(k, t - std::max(ch.start, 0.0));
        const double q = jointPosition(model, world.state(), j);
        worst = std::max(worst, std::abs(difference(q, target, revolute(world, j))));
      }
      if (worst <= c.tolerance)
        return fmt::format("joints within {:.3g} of their targets (worst {:.3g})", c.tolerance,
                           worst);
      return std::nullopt;
    }
    case ConditionSpec::Kind::kContactForce: {
      const Model& model = world.model();
      double force = 0.0;
      for (const Contact& contact : world.contacts()) {
        const std::int32_t a = model.objectOf[static_cast<std::size_t>(contact.a)];
        const std::int32_t b =
            contact.other >= 0 ? model.objectOf[static_cast<std::size_t>(contact.other)] : -1;
        const auto is = [&](std::int32_t x, std::int32_t y) {
          return x == c.object && (c.other < 0 ? y != c.object : y == c.other);
        };
        if (is(a, b) || is(b, a)) force += contact.normalForce;
      }
      if (force > c.force) return fmt::format("contact force {:.4g} N > {:.4g} N", force, c.force);
      return std::nullopt;
    }
  }
  return std::nullopt;
}

void Controller::startPhase(std::size_t phase, World& world, double t, const std::string& reason,
                            std::vector<std::string>* events) {
  (void)world;
  const PhaseSpec& p = spec_.phases[phase];
  phaseStarts_[phase] = t;
  phaseReasons_[phase] = reason;
  for (const ActuatorSpec& a : p.actuators) {
    Channel& c = channel(a.joint);
    c.spec = a;
    c.start = t;
  }
  for (const BaseMotionSpec& b : p.bases) setBaseMotion(b);
  if (events != nullptr)
    events->push_back(fmt::format("phase '{}' started at t = {:.6g} s ({})", p.name, t, reason));
}

void Controller::applyChannel(Channel& c, World& world, double t) {
  const std::size_t j = c.spec.joint;
  if (c.start < 0.0) c.start = t;
  const double q = jointPosition(world.model(), world.state(), j);
  // The first command of a rate-limited target starts from where the joint is.
  const std::optional<double> previous = c.command ? c.command : std::optional<double>(q);
  const double dt = c.command ? t - c.commandTime : 0.0;
  const build::JointCommand command = build::actuatorCommand(
      c.spec, world.model().joints[j].drive, revolute(world, j), t - c.start, q, previous, dt);
  if (c.spec.mode == JointMode::kPosition) {
    c.command = command.command;
    c.commandTime = t;
    c.servoTarget = command.target;
  }
  applyCommand(world, j, c.spec.mode, command);
}

void Controller::applyBase(Base& b, World& world, double t) {
  if (b.start < 0.0) {
    b.start = t;
    b.origin.clear();
    for (ParticleIndex p : b.spec.particles) b.origin.push_back(world.state().position[p]);
  }
  const double s = t - b.start;
  const Vec3 offset{build::trajectoryValue(b.spec.translation[0], s),
                    build::trajectoryValue(b.spec.translation[1], s),
                    build::trajectoryValue(b.spec.translation[2], s)};
  const Vec3 rate{build::trajectoryRate(b.spec.translation[0], s),
                  build::trajectoryRate(b.spec.translation[1], s),
                  build::trajectoryRate(b.spec.translation[2], s)};
  // MODEL §2.3: fixed particles keep their velocity, so between two applies they
  // move on at the trajectory's rate; the position is put back on it each time.
  // MODEL §2.3: fixed particles keep their velocity, so between two applies they
  // move on at the trajectory's rate; the position is put back on it each time.
  const double angle = build::trajectoryValue(b.spec.angle, s);
  const double angleRate = build::trajectoryRate(b.spec.angle, s);
  const double axisLength = norm(b.spec.axis);
  if (!(axisLength > 0.0) || (angle == 0.0 && angleRate == 0.0)) {
    for (std::size_t k = 0; k < b.spec.particles.size(); ++k) {
      world.setPosition(b.spec.particles[k], b.origin[k] + offset);
      world.setVelocity(b.spec.particles[k], rate);
    }
    return;
  }
  // Turning about the axis through the centroid (build::movedPose): v = ṫ + ω × (p − c).
  std::vector<ParticleIndex> local(b.origin.size());
  for (std::size_t k = 0; k < local.size(); ++k) local[k] = static_cast<ParticleIndex>(k);
  const std::vector<Vec3> moved = build::movedPose(b.origin, local, offset, b.spec.axis, angle);
  Vec3 center{};
  for (const Vec3& o : b.origin) center += o;
  center = center / static_cast<double>(b.origin.size()) + offset;
  const Vec3 spin = b.spec.axis * (angleRate / axisLength);
  for (std::size_t k = 0; k < b.spec.particles.size(); ++k) {
    world.setPosition(b.spec.particles[k], moved[k]);
    world.setVelocity(b.spec.particles[k], rate + cross(spin, moved[k] - center));
  }
}

void Controller::apply(World& world, std::vector<std::string>* events) {
  const double t = world.state().time;
  while (nextPhase_ < spec_.phases.size()) {
    const ConditionSpec& c = spec_.phases[nextPhase_].start;
    std::optional<std::string> reason = conditionHolds(c, world, t);
    const double previous = nextPhase_ == 0 ? 0.0 : phaseStarts_[nextPhase_ - 1];
    if (!reason && c.timeout > 0.0 && t - previous >= c.timeout)
      reason =
          fmt::format("timeout: {:.6g} s after the previous phase, its condition unmet", c.timeout);
    if (!reason) break;
    startPhase(nextPhase_, world, t, *reason, events);
    ++nextPhase_;
  }
  for (Channel& c : channels_) applyChannel(c, world, t);
  for (const MimicSpec& m : spec_.mimics) {
    // MODEL §1.5: the follower's servo target is multiplier · q_leader + offset.
    const Model& model = world.model();
    const double qLeader = jointPosition(model, world.state(), m.leader);
    const double rateLeader = jointRate(model, world.state(), m.leader);
    ActuatorSpec a{.joint = m.joint, .mode = JointMode::kPosition, .kp = m.kp, .kd = m.kd};
    a.target = Trajectory::constant(m.multiplier * qLeader + m.offset);
    a.feedForward = m.kd * m.multiplier * rateLeader;
    const double q = jointPosition(model, world.state(), m.joint);
    const build::JointCommand command = build::actuatorCommand(
        a, model.joints[m.joint].drive, revolute(world, m.joint), 0.0, q, std::nullopt, 0.0);
    applyCommand(world, m.joint, JointMode::kPosition, command);
  }
  for (Base& b : bases_) applyBase(b, world, t);
}

bool Controller::step(World& world, std::vector<std::string>& events) {
  apply(world, &events);
  return true;
}

json Controller::save() const {
  json channels = json::array(), bases = json::array(), mimics = json::array();
  for (const Channel& c : channels_)
    channels.push_back({{"spec", actuatorToJson(c.spec)},
                        {"start", exactNumber(c.start)},
                        {"command", optionalNumber(c.command)},
                        {"command_time", exactNumber(c.commandTime)},
                        {"servo_target", exactNumber(c.servoTarget)}});
  for (const Base& b : bases_)
    bases.push_back({{"spec", baseToJson(b.spec)},
                     {"start", exactNumber(b.start)},
                     {"origin", exactVec3s(b.origin)}});
  for (const MimicSpec& m : spec_.mimics)
    mimics.push_back({m.joint, m.leader, exactNumber(m.multiplier), exactNumber(m.offset),
                      exactNumber(m.kp), exactNumber(m.kd)});
  return {{"channels", channels},
          {"bases", bases},
          {"mimics", mimics},
          {"phase_starts", exactNumbers(phaseStarts_)},
          {"phase_reasons", phaseReasons_},
          {"next_phase", nextPhase_}};
}

void Controller::restore(const json& saved) {
  const auto starts = numbersFromJson(saved.at("phase_starts"), "phase starts");
  if (starts.size() != spec_.phases.size())
    throw std::runtime_error("control: the checkpoint is of a scene with other phases");
  channels_.clear();
  for (const json& c : saved.at("channels")) {
    Channel ch;
    ch.spec = actuatorFromJson(c.at("spec"));
    if (ch.spec.joint >= jointCount_)
      throw std::runtime_error("control: the checkpoint names a joint the scene does not have");
    ch.start = numberFromJson(c.at("start"), "channel start");
    ch.command = optionalFromJson(c.at("command"), "channel command");
    ch.commandTime = numberFromJson(c.at("command_time"), "channel command time");
    ch.servoTarget = numberFromJson(c.at("servo_target"), "channel servo target");
    channels_.push_back(ch);
  }
  bases_.clear();
  for (const json& b : saved.at("bases"))
    bases_.push_back({baseFromJson(b.at("spec")), numberFromJson(b.at("start"), "base start"),
                      vec3sFromJson(b.at("origin"), "base origin")});
  spec_.mimics.clear();
  for (const json& m : saved.at("mimics"))
    spec_.mimics.push_back(
        {m.at(0).get<std::size_t>(), m.at(1).get<std::size_t>(),
         numberFromJson(m.at(2), "mimic multiplier"), numberFromJson(m.at(3), "mimic offset"),
         numberFromJson(m.at(4), "mimic kp"), numberFromJson(m.at(5), "mimic kd")});
  phaseStarts_ = starts;
  phaseReasons_ = saved.at("phase_reasons").get<std::vector<std::string>>();
  nextPhase_ = saved.at("next_phase").get<std::size_t>();
}

json Controller::outcomes(const World& world) const {
  (void)world;
  if (spec_.phases.empty()) return nullptr;
  json phases = json::array();
  for (std::size_t p = 0; p < spec_.phases.size(); ++p)
    phases.push_back({{"name", spec_.phases[p].name},
                      {"started", phaseStarts_[p] >= 0.0},
                      {"started_s", phaseStarts_[p] >= 0.0 ? json(phaseStarts_[p]) : json()},
                      {"by", phaseReasons_[p]}});
  return {{"control", {{"phases", phases}}}};
}

}  // namespace robophi::robotics
