// Trajectories of the control specs (docs/robots.md "Controlling joints"):
// constant, keyframes (linear or cubic Hermite with Catmull-Rom tangents), sine.
#include "robophi/build/control.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "build/checks.h"

namespace robophi::build {

namespace {

using check::number;

// The keyframe interval [i, i + 1] holding t (times increasing, at least two).
std::size_t intervalOf(const std::vector<double>& times, double t) {
  const auto upper = std::upper_bound(times.begin(), times.end(), t);
  const auto i = static_cast<std::size_t>(upper - times.begin());
  return std::min(i == 0 ? 0 : i - 1, times.size() - 2);
}

// Catmull-Rom tangent at keyframe i: the slope between its neighbours, one-sided at the ends.
double tangentAt(const Trajectory& k, std::size_t i) {
  const std::size_t lo = i == 0 ? 0 : i - 1;
  const std::size_t hi = std::min(i + 1, k.times.size() - 1);
  return (k.values[hi] - k.values[lo]) / (k.times[hi] - k.times[lo]);
}

// Value (derivative 0) or rate (derivative 1) of the keyframes at t.
double keyframes(const Trajectory& k, double t, int derivative) {
  const std::size_t n = k.times.size();
  if (n == 1 || t <= k.times.front()) return derivative == 0 ? k.values.front() : 0.0;
  if (t >= k.times.back()) return derivative == 0 ? k.values.back() : 0.0;
  const std::size_t i = intervalOf(k.times, t);
  const double h = k.times[i + 1] - k.times[i];
  const double s = (t - k.times[i]) / h;
  const double v0 = k.values[i], v1 = k.values[i + 1];
  if (k.interpolation == Interpolation::kLinear)
    return derivative == 0 ? v0 + s * (v1 - v0) : (v1 - v0) / h;
  // Cubic Hermite on [t_i, t_i+1] with s = (t − t_i)/h.
  const double m0 = tangentAt(k, i) * h, m1 = tangentAt(k, i + 1) * h;
  if (derivative == 0) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * v1 +
           (s3 - s2) * m1;
  }
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * v0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * v1 +
          (3 * s2 - 2 * s) * m1) /
         h;
}

}  // namespace

double trajectoryValue(const Trajectory& k, double t) {
  switch (k.kind) {
    case Trajectory::Kind::kConstant:
      return k.value;
    case Trajectory::Kind::kKeyframes:
      return keyframes(k, t, 0);
    case Trajectory::Kind::kSine:
      return k.offset + k.amplitude * std::sin(2.0 * std::numbers::pi * t / k.period + k.phase);
  }
  return k.value;
}

double trajectoryRate(const Trajectory& k, double t) {
  switch (k.kind) {
    case Trajectory::Kind::kConstant:
      return 0.0;
    case Trajectory::Kind::kKeyframes:
      return keyframes(k, t, 1);
    case Trajectory::Kind::kSine: {
      const double w = 2.0 * std::numbers::pi / k.period;
      return k.amplitude * w * std::cos(w * t + k.phase);
    }
  }
  return 0.0;
}

std::string checkTrajectory(const Trajectory& k) {
  switch (k.kind) {
    case Trajectory::Kind::kConstant:
      if (!std::isfinite(k.value)) return "value " + number(k.value) + " must be finite";
      return {};
    case Trajectory::Kind::kKeyframes:
      if (k.times.empty() || k.times.size() != k.values.size())
        return "keyframes: " + std::to_string(k.times.size()) + " times and " +
               std::to_string(k.values.size()) + " values; expected as many, at least one";
      for (std::size_t i = 0; i < k.times.size(); ++i) {
        if (!std::isfinite(k.times[i]) || k.times[i] < 0.0)
          return "keyframe " + std::to_string(i) + ": time " + number(k.times[i]) +
                 " s must be finite and >= 0";
        if (!std::isfinite(k.values[i]))
          return "keyframe " + std::to_string(i) + ": value " + number(k.values[i]) +
                 " must be finite";
        if (i > 0 && !(k.times[i] > k.times[i - 1]))
          return "keyframe " + std::to_string(i) + ": time " + number(k.times[i]) +
                 " s must be after the previous one (" + number(k.times[i - 1]) + " s)";
      }
      return {};
    case Trajectory::Kind::kSine:
      if (!(k.period > 0.0) || !std::isfinite(k.period))
        return "sine: period " + number(k.period) + " s must be > 0";
      if (!std::isfinite(k.amplitude) || !std::isfinite(k.phase) || !std::isfinite(k.offset))
        return "sine: amplitude, phase and offset must be finite";
      return {};
  }
  return {};
}

namespace {

// The signed difference to − from, the short way round for an angle.
double difference(double from, double to, bool revolute) {
  const double d = to - from;
  if (!revolute) return d;
  const double twoPi = 2.0 * std::numbers::pi;
  double w = std::fmod(d, twoPi);
  if (w > std::numbers::pi) w -= twoPi;
  if (w <= -std::numbers::pi) w += twoPi;
  return w;
}

}  // namespace

JointCommand actuatorCommand(const ActuatorSpec& a, const JointDrive& current, bool revolute,
                             double t, double q, std::optional<double> previousTarget, double dt) {
  JointCommand c;
  c.drive = current;
  JointDrive& d = c.drive;
  if (a.effortLimit) d.effortLimit = *a.effortLimit;
  if (a.velocityLimit) d.velocityLimit = *a.velocityLimit;
  if (a.damping) d.damping = *a.damping;
  if (a.friction) d.friction = *a.friction;
  d.effort = 0.0;
  d.rateGain = 0.0;
  d.targetRate = 0.0;
  const double value = trajectoryValue(a.target, t);
  switch (a.mode) {
    case JointMode::kPosition: {
      c.stiffness = a.kp;
      c.damping = a.kd;
      // MODEL §1.5: the target moves at most at the velocity limit ...
      double command = value;
      bool held = false;
      if (previousTarget && std::isfinite(d.velocityLimit)) {
        const double step = d.velocityLimit * dt;
        const double change = difference(*previousTarget, value, revolute);
        if (std::abs(change) > step) {
          command = *previousTarget + (change > 0.0 ? step : -step);
          held = true;
        }
      }
      c.command = command;
      // ... and pulls with at most the effort limit: |kp (q* − q)| <= τ_max.
      double offset = difference(q, command, revolute);
      if (a.kp > 0.0 && std::isfinite(d.effortLimit))
        offset = std::clamp(offset, -d.effortLimit / a.kp, d.effortLimit / a.kp);
      c.target = q + offset;
      // The damper acts on q̇* − q̇: the motor adds kd q̇* (and the feed-forward).
      // While the velocity limit holds the target back there is no rate
      // feed-forward: its zero would make the joint overshoot the limit, where an
      // over-damped servo without it does not.
      double rate = held ? 0.0 : trajectoryRate(a.target, t);
      rate = std::clamp(rate, -d.velocityLimit, d.velocityLimit);
      d.effort = a.feedForward + a.kd * rate;
      break;
    }
    case JointMode::kVelocity:
      d.rateGain = a.kv;
      d.targetRate = value;
      d.effort = a.feedForward;
      break;
    case JointMode::kEffort:
      d.effort = value;
      break;
    case JointMode::kPassive:
      break;
  }
  return c;
}

void addMount(Model& model, const std::vector<Vec3>& position, const MountSpec& spec) {
  const auto objects = static_cast<std::int32_t>(model.objects.size());
  const auto fail = [](const std::string& message) {
    throw std::invalid_argument("addMount: " + message);
  };
  if (spec.object < 0 || spec.object >= objects || spec.on < 0 || spec.on >= objects)
    fail("objects " + std::to_string(spec.object) + " and " + std::to_string(spec.on) +
         " must exist (the model has " + std::to_string(objects) + ")");
  if (spec.object == spec.on) fail("an object cannot be mounted on itself");
  if (!(spec.stiffness > 0.0) || !std::isfinite(spec.stiffness))
    fail("stiffness " + number(spec.stiffness) + " N/m must be > 0");
  if (spec.damping && (!(*spec.damping >= 0.0) || !std::isfinite(*spec.damping)))
    fail("damping " + number(*spec.damping) + " N·s/m must be >= 0");
  const ObjectInfo& base = model.objects[static_cast<std::size_t>(spec.object)];
  const ObjectInfo& on = model.objects[static_cast<std::size_t>(spec.on)];
  if (spec.links < 1 || spec.links > on.particleCount)
    fail("links " + std::to_string(spec.links) + " must be in [1, " +
         std::to_string(on.particleCount) + "] (the particles of '" + on.name + "')");
  std::vector<ParticleIndex> fixed;
  for (ParticleIndex i = base.firstParticle; i < base.firstParticle + base.particleCount; ++i)
    if (model.isFixed(i)) fixed.push_back(i);
  if (fixed.empty()) fail("'" + base.name + "' has no fixed particle to mount");
  for (ParticleIndex i : fixed) {
    // The nearest particles of the carrier (ties broken by index: deterministic).
    std::vector<ParticleIndex> near;
    for (ParticleIndex j = on.firstParticle; j < on.firstParticle + on.particleCount; ++j)
      near.push_back(j);
    const auto distance = [&](ParticleIndex j) { return norm(position[j] - position[i]); };
    std::stable_sort(near.begin(), near.end(),
                     [&](ParticleIndex a, ParticleIndex b) { return distance(a) < distance(b); });
    for (int k = 0; k < spec.links; ++k) {
      const ParticleIndex j = near[static_cast<std::size_t>(k)];
      const double rest = distance(j);
      if (!(rest > 0.0)) fail("a base particle sits on a particle of '" + on.name + "'");
      const double lighter = std::min(model.mass[i], model.mass[j]);
      const double damping = spec.damping.value_or(0.2 * std::sqrt(spec.stiffness * lighter / 2.0));
      model.linearSprings.push_back({i, j, rest, spec.stiffness, damping});
    }
  }
  for (ParticleIndex i : fixed) model.inverseMass[i] = 1.0 / model.mass[i];
}

std::string checkActuator(const ActuatorSpec& a, const Model& model) {
  if (a.joint >= model.joints.size())
    return "joint " + std::to_string(a.joint) + " does not exist (the model has " +
           std::to_string(model.joints.size()) + ")";
  const Joint& joint = model.joints[a.joint];
  const auto bad = [](const char* field, double v, const char* rule) {
    return std::string("'") + field + "' = " + number(v) + " must be " + rule;
  };
  if (!(a.kp >= 0.0) || !std::isfinite(a.kp)) return bad("kp", a.kp, "finite and >= 0");
  if (!(a.kd >= 0.0) || !std::isfinite(a.kd)) return bad("kd", a.kd, "finite and >= 0");
  if (!(a.kv >= 0.0) || !std::isfinite(a.kv)) return bad("kv", a.kv, "finite and >= 0");
  if (!std::isfinite(a.feedForward)) return bad("feedForward", a.feedForward, "finite");
  if (a.effortLimit && !(*a.effortLimit > 0.0)) return bad("effortLimit", *a.effortLimit, "> 0");
  if (a.velocityLimit && !(*a.velocityLimit > 0.0))
    return bad("velocityLimit", *a.velocityLimit, "> 0");
  if (a.damping && (!(*a.damping >= 0.0) || !std::isfinite(*a.damping)))
    return bad("damping", *a.damping, "finite and >= 0");
  if (a.friction && (!(*a.friction >= 0.0) || !std::isfinite(*a.friction)))
    return bad("friction", *a.friction, "finite and >= 0");
  if (a.mode == JointMode::kPosition && !joint.hasServo())
    return "prismatic joint '" + joint.name +
           "' has no drive spring: position mode needs one (use velocity or effort mode)";
  if (const std::string problem = checkTrajectory(a.target); !problem.empty())
    return "target: " + problem;
  return {};
}

}  // namespace robophi::build
