// Joint actuators from Python (docs/python.md "Actuators"): the World's drive
// edits (World::setJointEffort, setJointDrive; MODEL §1.6), robophi.JointDrive,
// robophi.Trajectory, and per joint a position / velocity / effort actuator with
// gains and limits (robotics::Controller, build/control.h), settable between steps.
#include <cmath>
#include <limits>

#include "forces/forces.h"
#include "py_robophi.h"
#include "robophi/joints.h"

namespace robophi::python {

namespace {

using build::ActuatorSpec;
using build::JointMode;
using build::Trajectory;

JointMode modeFromName(const std::string& name) {
  if (name == "position") return JointMode::kPosition;
  if (name == "velocity") return JointMode::kVelocity;
  if (name == "effort") return JointMode::kEffort;
  if (name == "passive") return JointMode::kPassive;
  throw std::invalid_argument("mode '" + name +
                              "': expected position, velocity, effort or passive");
}

const char* modeName(JointMode mode) {
  switch (mode) {
    case JointMode::kPosition:
      return "position";
    case JointMode::kVelocity:
      return "velocity";
    case JointMode::kEffort:
      return "effort";
    case JointMode::kPassive:
      break;
  }
  return "passive";
}

/// A target given as a number (a constant) or a robophi.Trajectory.
Trajectory targetFrom(const py::handle& target) {
  if (py::isinstance<Trajectory>(target)) return target.cast<Trajectory>();
  const double value = target.cast<double>();
  if (!std::isfinite(value))
    throw std::invalid_argument("target = " + std::to_string(value) + " must be finite");
  return Trajectory::constant(value);
}

void require(const std::string& problem, const std::string& where) {
  if (!problem.empty()) throw std::invalid_argument(where + ": " + problem);
}

std::string jointLabel(const Model& model, std::size_t joint) {
  return "joint '" + model.joints[joint].name + "'";
}

/// The actuator of `joint`, or ValueError naming the call and the joint.
const ActuatorSpec& existingActuator(PyWorld& w, std::size_t joint, const char* call) {
  const robotics::Controller* c = w.controllerIfAny();
  const ActuatorSpec* a = c ? c->actuator(joint) : nullptr;
  if (a == nullptr)
    throw std::invalid_argument(std::string(call) + ": " + jointLabel(w.world().model(), joint) +
                                " has no actuator (give it one with world.set_actuator)");
  return *a;
}

py::object optionalNumber(const std::optional<double>& v) {
  return v ? py::object(py::float_(*v)) : py::object(py::none());
}

py::dict actuatorDict(const ActuatorSpec& a, double servoTarget) {
  py::dict d;
  d["mode"] = modeName(a.mode);
  d["kp"] = a.kp;
  d["kd"] = a.kd;
  d["kv"] = a.kv;
  if (a.target.kind == Trajectory::Kind::kConstant)
    d["target"] = a.target.value;
  else
    d["target"] = py::cast(a.target);
  d["feed_forward"] = a.feedForward;
  d["effort_limit"] = optionalNumber(a.effortLimit);
  d["velocity_limit"] = optionalNumber(a.velocityLimit);
  d["damping"] = optionalNumber(a.damping);
  d["friction"] = optionalNumber(a.friction);
  d["servo_target"] = servoTarget;
  return d;
}

py::array doublesOf(const std::vector<double>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

}  // namespace

void bindActuators(py::module_& m) {
  py::class_<JointDrive>(m, "JointDrive",
                         "A joint's motor and losses (MODEL §1.6; N·m and rad for a revolute "
                         "joint, N and m for a prismatic one): τ = clamp(effort + rate_gain "
                         "(target_rate − q̇), ±effort_limit), none past velocity_limit; losses "
                         "−damping q̇ − friction clamp(q̇ / friction_velocity, −1, 1).")
      .def(py::init([](py::kwargs fields) {
        py::object drive = py::cast(JointDrive{});
        for (auto [name, value] : fields) drive.attr(name) = value;
        return drive.cast<JointDrive>();
      }))
      .def_readwrite("effort", &JointDrive::effort, "commanded effort τ0 (N·m or N)")
      .def_readwrite("rate_gain", &JointDrive::rateGain, "k_v (N·m·s/rad or N·s/m), >= 0")
      .def_readwrite("target_rate", &JointDrive::targetRate, "q̇* (rad/s or m/s)")
      .def_readwrite("effort_limit", &JointDrive::effortLimit, "|τ| bound (N·m or N); inf: none")
      .def_readwrite("velocity_limit", &JointDrive::velocityLimit, "rad/s or m/s; inf: none")
      .def_readwrite("damping", &JointDrive::damping, "viscous b (N·m·s/rad or N·s/m), >= 0")
      .def_readwrite("friction", &JointDrive::friction, "Coulomb F_c (N·m or N), >= 0")
      .def_readwrite("friction_velocity", &JointDrive::frictionVelocity,
                     "rate (rad/s or m/s) at which the friction is reached, > 0")
      .def("__repr__", [](const JointDrive& d) {
        return "robophi.JointDrive(effort=" + std::to_string(d.effort) +
               ", rate_gain=" + std::to_string(d.rateGain) +
               ", target_rate=" + std::to_string(d.targetRate) +
               ", effort_limit=" + std::to_string(d.effortLimit) +
               ", velocity_limit=" + std::to_string(d.velocityLimit) +
               ", damping=" + std::to_string(d.damping) +
               ", friction=" + std::to_string(d.friction) + ")";
      });

  py::class_<Trajectory>(m, "Trajectory",
                         "A target that changes in time (build::Trajectory): constant, keyframes "
                         "or a sine; its time counts from when the actuator got it.")
      .def_static(
          "constant", [](double value) { return Trajectory::constant(value); }, py::arg("value"))
      .def_static(
          "keyframes",
          [](std::vector<double> times, std::vector<double> values,
             const std::string& interpolation) {
            Trajectory t;
            t.kind = Trajectory::Kind::kKeyframes;
            t.times = std::move(times);
            t.values = std::move(values);
            if (interpolation == "cubic")
              t.interpolation = build::Interpolation::kCubic;
            else if (interpolation != "linear")
              throw std::invalid_argument("Trajectory.keyframes: interpolation '" + interpolation +
                                          "': expected linear or cubic");
            require(build::checkTrajectory(t), "Trajectory.keyframes");
            return t;
          },
          py::arg("times"), py::arg("values"), py::arg("interpolation") = "linear",
          "Increasing times (s, >= 0) and their values, held before the first and after the last.")
      .def_static(
          "sine",
          [](double amplitude, double period, double phase, double offset) {
            Trajectory t;
            t.kind = Trajectory::Kind::kSine;
            t.amplitude = amplitude;
            t.period = period;
            t.phase = phase;
            t.offset = offset;
            require(build::checkTrajectory(t), "Trajectory.sine");
            return t;
          },
          py::arg("amplitude"), py::arg("period"), py::arg("phase") = 0.0, py::arg("offset") = 0.0,
          "offset + amplitude sin(2π t / period + phase); period (s) > 0.")
      .def("value", &build::trajectoryValue, py::arg("t"), "The value at t (s) since it started.")
      .def("rate", &build::trajectoryRate, py::arg("t"), "The rate (per s) at t (s).")
      .def("__repr__", [](const Trajectory& t) {
        switch (t.kind) {
          case Trajectory::Kind::kConstant:
            return "robophi.Trajectory.constant(" + std::to_string(t.value) + ")";
          case Trajectory::Kind::kKeyframes:
            return "robophi.Trajectory.keyframes(" + std::to_string(t.times.size()) + " keyframes)";
          case Trajectory::Kind::kSine:
            break;
        }
        return "robophi.Trajectory.sine(amplitude=" + std::to_string(t.amplitude) +
               ", period=" + std::to_string(t.period) + ")";
      });

  auto world = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
  world
      // ---- The joint's drive (MODEL §1.6), edited directly.
      .def(
          "set_joint_effort",
          [](PyWorld& w, py::handle joint, double effort) {
            w.syncViews();
            w.world().setJointEffort(jointIndex(w.world().model(), joint), effort);
          },
          py::arg("joint"), py::arg("effort"),
          "The joint's commanded motor effort τ0 (N·m about the axis, or N along the line; "
          "positive increases q), between steps. Its power is booked as external work. The "
          "servo stays as it is (set_joint_servo(joint, 0, 0) for a pure effort).")
      .def(
          "joint_drive",
          [](PyWorld& w, py::handle joint) {
            return w.world().model().joints[jointIndex(w.world().model(), joint)].drive;
          },
          py::arg("joint"), "A copy of the joint's drive (robophi.JointDrive).")
      .def(
          "set_joint_drive",
          [](PyWorld& w, py::handle joint, std::optional<JointDrive> drive, py::kwargs fields) {
            w.syncViews();
            const std::size_t j = jointIndex(w.world().model(), joint);
            py::object d = py::cast(drive.value_or(w.world().model().joints[j].drive));
            for (auto [name, value] : fields) {
              if (!py::hasattr(d, name))
                throw py::type_error("set_joint_drive: no field '" +
                                     py::str(name).cast<std::string>() +
                                     "' (fields: effort, rate_gain, target_rate, effort_limit, "
                                     "velocity_limit, damping, friction, friction_velocity)");
              d.attr(name) = value;
            }
            w.world().setJointDrive(j, d.cast<JointDrive>());
          },
          py::arg("joint"), py::arg("drive") = py::none(),
          "Replaces the joint's drive: `drive` (a robophi.JointDrive; default the joint's "
          "current one) with the keyword fields given changed, e.g. "
          "set_joint_drive('arm.j1', rate_gain=2.0, target_rate=1.0). ValueError names a bad "
          "field.")
      .def_property_readonly(
          "joint_motor_efforts",
          [](PyWorld& w) {
            w.syncViews();
            const Model& model = w.world().model();
            std::vector<double> v(model.joints.size());
            for (std::size_t j = 0; j < v.size(); ++j)
              v[j] = motorEffort(model.joints[j].drive, jointRate(model, w.world().state(), j));
            return doublesOf(v);
          },
          "The motors' efforts at the current state (MODEL §1.6: clamp(τ0 + k_v (q̇* − q̇)), "
          "N·m or N), losses not included")
      // ---- Actuators (robotics::Controller): applied before every step.
      .def(
          "set_actuator",
          [](PyWorld& w, py::handle joint, const std::string& mode, double kp, double kd, double kv,
             py::handle target, double feedForward, std::optional<double> effortLimit,
             std::optional<double> velocityLimit, std::optional<double> damping,
             std::optional<double> friction) {
            w.syncViews();
            const Model& model = w.world().model();
            ActuatorSpec a;
            a.joint = jointIndex(model, joint);
            a.mode = modeFromName(mode);
            a.kp = kp;
            a.kd = kd;
            a.kv = kv;
            a.target = targetFrom(target);
            a.feedForward = feedForward;
            a.effortLimit = effortLimit;
            a.velocityLimit = velocityLimit;
            a.damping = damping;
            a.friction = friction;
            require(build::checkActuator(a, model), "set_actuator: " + jointLabel(model, a.joint));
            w.controller().setActuator(a);
          },
          py::arg("joint"), py::arg("mode") = "position", py::kw_only(), py::arg("kp") = 0.0,
          py::arg("kd") = 0.0, py::arg("kv") = 0.0, py::arg("target") = 0.0,
          py::arg("feed_forward") = 0.0, py::arg("effort_limit") = py::none(),
          py::arg("velocity_limit") = py::none(), py::arg("damping") = py::none(),
          py::arg("friction") = py::none(),
          "Gives a joint an actuator (build::ActuatorSpec), replacing its previous one; from the "
          "next step on it sets the joint's servo and drive before every step.\n"
          "mode 'position': servo of stiffness kp (N·m/rad or N/m), damping kd, target q* "
          "(rad or m, the coordinate of joint_positions); 'velocity': motor effort "
          "kv (q̇* − q̇), target q̇* (rad/s or m/s), servo off; 'effort': motor effort τ "
          "(N·m or N) = target, servo off; 'passive': servo and motor off.\n"
          "target: a number or a robophi.Trajectory (its time counts from the next step). "
          "feed_forward: effort added in position and velocity mode. effort_limit, "
          "velocity_limit (> 0), damping, friction (>= 0): None keeps the joint's own. In "
          "position mode the target is kept within effort_limit / kp of q and moves at most "
          "at velocity_limit. ValueError names a bad field.")
      .def(
          "set_joint_mode",
          [](PyWorld& w, py::handle joint, const std::string& mode) {
            w.syncViews();
            const std::size_t j = jointIndex(w.world().model(), joint);
            ActuatorSpec a = existingActuator(w, j, "set_joint_mode");
            a.mode = modeFromName(mode);
            require(build::checkActuator(a, w.world().model()),
                    "set_joint_mode: " + jointLabel(w.world().model(), j));
            w.controller().setMode(j, a.mode);
          },
          py::arg("joint"), py::arg("mode"),
          "Switches a joint's actuator to another mode (position, velocity, effort, passive), "
          "its gains and target kept: from the next step on.")
      .def(
          "set_actuator_target",
          [](PyWorld& w, py::handle joint, py::handle target) {
            w.syncViews();
            const std::size_t j = jointIndex(w.world().model(), joint);
            existingActuator(w, j, "set_actuator_target");
            const Trajectory t = targetFrom(target);
            if (t.kind == Trajectory::Kind::kConstant)
              w.controller().setTarget(j, t.value);
            else
              w.controller().setTrajectory(j, t);
          },
          py::arg("joint"), py::arg("target"),
          "The actuator's target (rad or m, rad/s or m/s, N·m or N, by its mode): a number or "
          "a robophi.Trajectory, whose time starts at the next step.")
      .def(
          "set_actuator_gains",
          [](PyWorld& w, py::handle joint, std::optional<double> kp, std::optional<double> kd,
             std::optional<double> kv) {
            w.syncViews();
            const std::size_t j = jointIndex(w.world().model(), joint);
            ActuatorSpec a = existingActuator(w, j, "set_actuator_gains");
            a.kp = kp.value_or(a.kp);
            a.kd = kd.value_or(a.kd);
            a.kv = kv.value_or(a.kv);
            require(build::checkActuator(a, w.world().model()),
                    "set_actuator_gains: " + jointLabel(w.world().model(), j));
            w.controller().setGains(j, a.kp, a.kd, a.kv);
          },
          py::arg("joint"), py::kw_only(), py::arg("kp") = py::none(), py::arg("kd") = py::none(),
          py::arg("kv") = py::none(), "Changes the gains given (None keeps one).")
      .def(
          "actuator",
          [](PyWorld& w, py::handle joint) -> py::object {
            const std::size_t j = jointIndex(w.world().model(), joint);
            const robotics::Controller* c = w.controllerIfAny();
            const ActuatorSpec* a = c ? c->actuator(j) : nullptr;
            if (a == nullptr) return py::none();
            return actuatorDict(*a, c->servoTarget(j));
          },
          py::arg("joint"),
          "The joint's actuator as a dict (mode, kp, kd, kv, target, feed_forward, limits, "
          "servo_target: the position target last commanded, after the limits), or None.")
      .def(
          "add_mimic",
          [](PyWorld& w, py::handle joint, py::handle leader, double multiplier, double offset,
             double kp, double kd) {
            w.syncViews();
            const Model& model = w.world().model();
            build::MimicSpec mimic{.joint = jointIndex(model, joint),
                                   .leader = jointIndex(model, leader),
                                   .multiplier = multiplier,
                                   .offset = offset,
                                   .kp = kp,
                                   .kd = kd};
            ActuatorSpec a{.joint = mimic.joint, .mode = JointMode::kPosition, .kp = kp, .kd = kd};
            require(build::checkActuator(a, model), "add_mimic: " + jointLabel(model, mimic.joint));
            if (!std::isfinite(multiplier) || !std::isfinite(offset))
              throw std::invalid_argument("add_mimic: multiplier and offset must be finite");
            w.controller().addMimic(mimic);
          },
          py::arg("joint"), py::arg("leader"), py::kw_only(), py::arg("multiplier") = 1.0,
          py::arg("offset") = 0.0, py::arg("kp"), py::arg("kd") = 0.0,
          "`joint` follows multiplier · q_leader + offset (a URDF mimic) by a position servo of "
          "gains kp, kd, applied before every step.");
}

}  // namespace robophi::python
