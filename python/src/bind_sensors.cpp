// robophi.World's sensors (robophi/sensors.h; docs/python.md "Sensors and vector
// I/O") and its joints read and written as arrays, one entry a joint in the model's
// joint order (world.joint_names): efforts, targets, gains, limits, and gravity
// compensation switched at run time. Names as MuJoCo's where one exists
// (sensordata).
#include <cmath>
#include <limits>

#include "py_robophi.h"
#include "robophi/joints.h"
#include "robophi/multibody.h"
#include "robophi/sensors.h"

namespace robophi::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

py::array_t<double> toArray(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

// One value a joint from a number (every joint) or an array of joint count; NaN
// entries leave that joint as it is.
std::vector<double> perJointValues(const PyWorld& w, const py::object& given, const char* call,
                                   const char* what) {
  const std::size_t n = w.world().model().joints.size();
  if (py::isinstance<py::float_>(given) || py::isinstance<py::int_>(given))
    return std::vector<double>(n, given.cast<double>());
  const Array a = given.cast<Array>();
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
    throw std::invalid_argument(std::string(call) + ": expected " + std::to_string(n) + " " + what +
                                " (one per joint, world.joint_names), got " +
                                std::to_string(a.size()));
  return {a.data(), a.data() + n};
}

// Pose X_LS from a position and a 3 × 3 rotation (None: identity).
Pose poseOf(const py::object& position, const py::object& rotation) {
  Pose X;
  if (!position.is_none()) X.translation = position.cast<Vec3>();
  if (!rotation.is_none()) {
    const Array r = rotation.cast<Array>();
    if (r.ndim() != 2 || r.shape(0) != 3 || r.shape(1) != 3)
      throw std::invalid_argument("add_sensor: rotation: expected a 3 × 3 matrix");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) X.rotation.m[i][j] = r.at(i, j);
  }
  return X;
}

py::array_t<double> readAll(PyWorld& w) {
  w.syncViews();
  std::vector<double> values(w.sensors.valueCount());
  w.sensors.read(w.world(), values.data());
  return toArray(values);
}

// Effort and velocity limits of joint j: its drive's, and a rigid tree joint's own bound.
double effortLimitOf(const Model& model, const Joint& joint) {
  double limit = joint.drive.effortLimit;
  if (joint.inTree()) {
    const MultibodyBody& body = model.rigidTrees[static_cast<std::size_t>(joint.tree)]
                                    .multibody.bodies[static_cast<std::size_t>(joint.treeBody)];
    limit = std::min(limit, body.effortLimit);
  }
  return limit;
}

}  // namespace

void bindSensors(py::module_& m) {
  auto world = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
  world
      // ---- Sensors.
      .def(
          "add_sensor",
          [](PyWorld& w, const std::string& name, const std::string& type, const std::string& on,
             const py::object& position, const py::object& rotation, double maxRange) {
            SensorSpec spec;
            if (!parseSensorKind(type, spec.kind))
              throw std::invalid_argument("add_sensor: sensor '" + name + "': unknown type '" + type +
                                          "' (expected force_torque, contact, imu or range)");
            spec.name = name;
            spec.on = on;
            spec.X_LS = poseOf(position, rotation);
            spec.maxRange = maxRange;
            w.sensors.add(w.world().model(), w.sensorReference, spec);
            return w.sensors.size() - 1;
          },
          py::arg("name"), py::arg("type"), py::arg("on"), py::arg("position") = py::none(),
          py::arg("rotation") = py::none(),
          py::arg("max_range") = std::numeric_limits<double>::infinity(),
          "Adds a sensor (an observer: the physics is unchanged): type 'force_torque' on a rigid "
          "robot's joint, 'contact', 'imu' or 'range' on a link (a rigid robot's frame) or an "
          "object, at X_LS = (position, 3 × 3 rotation) on it. Returns its index.")
      .def_property_readonly(
          "sensor_names",
          [](const PyWorld& w) {
            std::vector<std::string> names;
            for (std::size_t k = 0; k < w.sensors.size(); ++k) names.push_back(w.sensors.spec(k).name);
            return names;
          },
          "The sensors' names, in the order of sensordata.")
      .def_property_readonly(
          "sensor_columns", [](const PyWorld& w) { return w.sensors.columns(); },
          "Each value of sensordata as '<sensor>:<value>' (sensors.csv's columns).")
      .def_property_readonly("sensordata", &readAll,
                             "Every sensor's values at the current state, one array "
                             "(MuJoCo's data.sensordata; sensor_columns names them).")
      .def(
          "sensor",
          [](PyWorld& w, const std::string& name) {
            const std::int32_t k = w.sensors.find(name);
            if (k < 0) throw py::key_error("no sensor named '" + name + "'");
            const auto s = static_cast<std::size_t>(k);
            const py::array_t<double> all = readAll(w);
            const std::size_t first = w.sensors.offset(s);
            return toArray(std::vector<double>(
                all.data() + first, all.data() + first + SensorSet::valueCountOf(w.sensors.spec(s).kind)));
          },
          py::arg("name"), "One sensor's values at the current state (MuJoCo's data.sensor(name).data).")
      // ---- Joints as arrays (world.joint_names' order).
      .def_property_readonly(
          "joint_names",
          [](const PyWorld& w) {
            std::vector<std::string> names;
            for (const Joint& j : w.world().model().joints) names.push_back(j.name);
            return names;
          },
          "The joints' names: the order of every per-joint array.")
      .def_property_readonly(
          "joint_limits",
          [](const PyWorld& w) {
            const Model& model = w.world().model();
            const double inf = std::numeric_limits<double>::infinity();
            std::vector<double> lower, upper, effort, velocity;
            for (const Joint& j : model.joints) {
              double lo = -inf, hi = inf;
              if (j.inTree()) {
                const MultibodyBody& body = model.rigidTrees[static_cast<std::size_t>(j.tree)]
                                                .multibody.bodies[static_cast<std::size_t>(j.treeBody)];
                lo = body.lower;
                hi = body.upper;
              }
              lower.push_back(lo);
              upper.push_back(hi);
              effort.push_back(effortLimitOf(model, j));
              velocity.push_back(j.drive.velocityLimit);
            }
            py::dict out;
            out["lower"] = toArray(lower);
            out["upper"] = toArray(upper);
            out["effort"] = toArray(effort);
            out["velocity"] = toArray(velocity);
            return out;
          },
          "{'lower', 'upper' (rad or m; ±inf: none — a rigid robot's URDF limits), 'effort' (N·m "
          "or N), 'velocity' (rad/s or m/s; inf: none)}: arrays (MuJoCo's jnt_range, "
          "actuator_forcerange).")
      .def(
          "set_joint_efforts",
          [](PyWorld& w, const py::object& efforts) {
            w.syncViews();
            const std::vector<double> tau = perJointValues(w, efforts, "set_joint_efforts", "efforts");
            for (std::size_t j = 0; j < tau.size(); ++j)
              if (!std::isnan(tau[j])) w.world().setJointEffort(j, tau[j]);
          },
          py::arg("efforts"),
          "Every joint's commanded motor effort τ0 (N·m or N) at once (NaN: leave that joint's), "
          "between steps: MuJoCo's data.ctrl of motors, or qfrc_applied.")
      .def(
          "set_joint_gains",
          [](PyWorld& w, const py::object& kp, const py::object& kd) {
            w.syncViews();
            const Model& model = w.world().model();
            const std::size_t n = model.joints.size();
            std::vector<double> stiffness(n), damping(n);
            for (std::size_t j = 0; j < n; ++j) {
              const JointServo servo = jointServo(model, j);
              stiffness[j] = servo.stiffness;
              damping[j] = servo.damping;
            }
            const auto given = [&](const py::object& values, std::vector<double>& into, const char* what) {
              if (values.is_none()) return;
              const std::vector<double> v = perJointValues(w, values, "set_joint_gains", what);
              for (std::size_t j = 0; j < n; ++j)
                if (!std::isnan(v[j])) into[j] = v[j];
            };
            given(kp, stiffness, "kp");
            given(kd, damping, "kd");
            for (std::size_t j = 0; j < n; ++j) {
              const JointServo servo = jointServo(model, j);
              if (!servo.hasDrive) continue;
              if (stiffness[j] != servo.stiffness || damping[j] != servo.damping)
                w.world().setJointServo(j, stiffness[j], damping[j]);
            }
          },
          py::arg("kp") = py::none(), py::arg("kd") = py::none(),
          "Every joint's servo stiffness kp (N·m/rad or N/m) and damping kd (N·m·s/rad or N·s/m) "
          "at once: a number for all, or an array (NaN: leave that joint's); None keeps them "
          "(MuJoCo's actuator_gainprm / biasprm of position actuators).")
      .def(
          "set_gravity_compensation",
          [](PyWorld& w, const py::object& robot, bool on) {
            w.syncViews();
            const Model& model = w.world().model();
            const std::string prefix = robot.is_none() ? std::string() : robot.cast<std::string>() + ".";
            int changed = 0;
            for (std::size_t j = 0; j < model.joints.size(); ++j) {
              const Joint& joint = model.joints[j];
              if (joint.name.compare(0, prefix.size(), prefix) != 0) continue;
              if (!joint.inTree() && (!joint.actsThroughBodies() || joint.subtreeBodies.empty()))
                continue;
              w.world().setGravityCompensation(j, on);
              ++changed;
            }
            if (changed == 0)
              throw std::invalid_argument(
                  "set_gravity_compensation: " +
                  (robot.is_none() ? std::string("the world has") : "robot '" + prefix.substr(0, prefix.size() - 1) + "' has") +
                  " no joint that carries bodies (a rigid robot's, or an imported robot's body link)");
            return changed;
          },
          py::arg("robot") = py::none(), py::arg("on") = true,
          "Gravity compensation of a robot's joints (those named '<robot>.<joint>'; None: every "
          "robot) on or off, between steps: each joint's motor adds the effort that holds what it "
          "carries against gravity (MuJoCo's qfrc_bias at rest, gravcomp). Returns the joints set.")
      .def(
          "link_pose",
          [](PyWorld& w, const std::string& name) {
            w.syncViews();
            const Model& model = w.world().model();
            const State& state = w.world().state();
            std::string known;
            for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
              const Multibody& mb = model.rigidTrees[t].multibody;
              std::int32_t f = mb.frameIndex(name);
              if (f < 0) f = mb.frameIndex(mb.name + "." + name);
              for (const MultibodyFrame& frame : mb.frames) known += (known.empty() ? "" : ", ") + frame.name;
              if (f < 0) continue;
              MultibodyKinematics kin;
              updateKinematics(mb, state.treePositions[t].data(), kin);
              const Pose X = framePose(mb, kin, f);
              py::array_t<double> R({py::ssize_t{3}, py::ssize_t{3}});
              auto r = R.mutable_unchecked<2>();
              for (py::ssize_t i = 0; i < 3; ++i)
                for (py::ssize_t k = 0; k < 3; ++k)
                  r(i, k) = X.rotation.m[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
              return py::make_tuple(X.translation, R);
            }
            throw py::key_error("link_pose: no rigid robot's link or frame named '" + name +
                                "' (there are: " + known + ")");
          },
          py::arg("link"),
          "X_WL of a rigid robot's link (or any frame of it: a site, a URDF link merged into its "
          "parent) at the world's current state: (position, 3×3 rotation), MuJoCo's data.xpos and "
          "data.xmat. By its name, with or without the robot's name in front.");
}

}  // namespace robophi::python
