// Rigid robots from Python (docs/python.md "Rigid robots"): a URDF or MJCF file as a
// tree of rigid bodies (build::makeUrdfMultibody, build::makeMjcfMultibody,
// include/robophi/multibody.h), with its state, kinematics (include/robophi/
// kinematics.h), dynamics terms and step, numpy in and out. Names follow MuJoCo's
// where one exists (qpos → q, qvel → v, qfrc_bias → bias_forces), Drake's otherwise.
#include <algorithm>
#include <cmath>

#include "py_robophi.h"
#include "robophi/build/mjcf_multibody.h"
#include "robophi/build/urdf_multibody.h"
#include "robophi/kinematics.h"
#include "robophi/multibody.h"

namespace robophi::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

struct PyRigidRobot {
  build::UrdfMultibody robot;
  build::MjcfExtras mjcf;
  std::vector<double> q, v;
  Vec3 gravity{0, 0, -9.81};
  MultibodyWorkspace workspace;
  MultibodyKinematics kinematics;

  const Multibody& mb() const { return robot.multibody; }
  std::size_t nv() const { return static_cast<std::size_t>(mb().velocityCount); }

  // Values of a given size from an optional array (None: `fallback`).
  std::vector<double> values(const py::object& given, std::size_t size, const std::vector<double>& fallback,
                             const char* what) const {
    if (given.is_none()) return fallback;
    const Array a = given.cast<Array>();
    if (static_cast<std::size_t>(a.size()) != size)
      throw std::invalid_argument(std::string(what) + ": expected " + std::to_string(size) +
                                  " values, got " + std::to_string(a.size()));
    return {a.data(), a.data() + a.size()};
  }
  std::vector<double> perRate(const py::object& given, const char* what) const {
    return values(given, nv(), {}, what);
  }
  void at(const py::object& qGiven, const py::object& vGiven) {
    const std::vector<double> qa = values(qGiven, q.size(), q, "q");
    const std::vector<double> va = values(vGiven, v.size(), v, "v");
    updateKinematics(mb(), qa.data(), kinematics);
    updateVelocities(mb(), va.data(), kinematics);
  }
  // One value a joint (robot.joints' order), as a numpy array.
  template <class Field>
  py::array_t<double> perJoint(Field field) const {
    std::vector<double> x;
    for (const build::UrdfMultibodyJoint& j : robot.joints) x.push_back(field(j));
    return py::array_t<double>(static_cast<py::ssize_t>(x.size()), x.data());
  }
  std::int32_t frame(const std::string& name) const {
    std::int32_t f = mb().frameIndex(name);
    if (f < 0) f = mb().frameIndex(mb().name + "." + name);
    if (f >= 0) return f;
    std::string known;
    for (const MultibodyFrame& fr : mb().frames) known += (known.empty() ? "" : ", ") + fr.name;
    throw py::key_error("no frame named '" + name + "' (the robot has: " + known + ")");
  }
};

Mat3 rotationOf(const py::object& given) {
  const Array a = given.cast<Array>();
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
    throw std::invalid_argument("rotation: expected a 3 × 3 matrix");
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.at(i, j);
  return r;
}

py::array_t<double> toArray(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

py::array_t<double> matrixOf(const Mat3& m) {
  py::array_t<double> a({3, 3});
  auto r = a.mutable_unchecked<2>();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = m.m[i][j];
  return a;
}

}  // namespace

void bindMultibody(py::module_& m) {
  py::class_<PyRigidRobot>(m, "RigidRobot",
                           "A URDF robot as rigid bodies in reduced coordinates: exact mass "
                           "properties, joints that hold, implicit servos (docs/python.md).")
      .def(py::init([](const py::object& path, bool fixedBase,
                       const std::vector<py::object>& packagePaths, bool balanceInertia,
                       bool inertiaFromGeometry) {
             auto robot = std::make_unique<PyRigidRobot>();
             if (build::isMjcfPath(pathText(path))) {
               build::MjcfMultibodySpec spec;
               spec.path = pathText(path);
               robot->robot = build::makeMjcfMultibody(spec, &robot->mjcf);
               robot->gravity = robot->mjcf.gravity;
             } else {
               build::UrdfMultibodySpec spec;
               spec.path = pathText(path);
               for (const py::object& p : packagePaths) spec.packagePaths.push_back(pathText(p));
               spec.fixedBase = fixedBase;
               spec.balanceInertia = balanceInertia;
               spec.inertiaFromGeometry = inertiaFromGeometry;
               robot->robot = build::makeUrdfMultibody(spec);
             }
             robot->q = neutralConfiguration(robot->mb());
             robot->v.assign(robot->nv(), 0.0);
             return robot;
           }),
           py::arg("path"), py::arg("fixed_base") = true,
           py::arg("package_paths") = std::vector<py::object>{}, py::arg("balance_inertia") = true,
           py::arg("inertia_from_geometry") = false,
           "A .urdf, or an MJCF .xml read by MuJoCo's compiler (libmujoco-dev; the URDF "
           "keywords do not apply to it).")
      .def_property_readonly("name", [](const PyRigidRobot& r) { return r.mb().name; })
      .def_property_readonly("nq", [](const PyRigidRobot& r) { return r.mb().positionCount; })
      .def_property_readonly("nv", [](const PyRigidRobot& r) { return r.mb().velocityCount; })
      .def_property_readonly("joint_names",
                             [](const PyRigidRobot& r) {
                               std::vector<std::string> names;
                               for (const auto& j : r.robot.joints) names.push_back(j.urdfName);
                               return names;
                             })
      .def_property_readonly("frame_names",
                             [](const PyRigidRobot& r) {
                               std::vector<std::string> names;
                               for (const auto& f : r.mb().frames) names.push_back(f.name);
                               return names;
                             })
      .def_property_readonly("adjustments",
                             [](const PyRigidRobot& r) { return r.robot.adjustments; })
      .def_property_readonly("lower",
                             [](const PyRigidRobot& r) {
                               return r.perJoint([&](const build::UrdfMultibodyJoint& j) {
                                 return r.mb().bodies[j.body].lower;
                               });
                             })
      .def_property_readonly("upper",
                             [](const PyRigidRobot& r) {
                               return r.perJoint([&](const build::UrdfMultibodyJoint& j) {
                                 return r.mb().bodies[j.body].upper;
                               });
                             })
      .def_property_readonly("effort_limit",
                             [](const PyRigidRobot& r) {
                               return r.perJoint([&](const build::UrdfMultibodyJoint& j) {
                                 return r.mb().bodies[j.body].effortLimit;
                               });
                             })
      .def_property_readonly(
          "velocity_limit",
          [](const PyRigidRobot& r) {
            return r.perJoint([](const build::UrdfMultibodyJoint& j) { return j.velocityLimit; });
          })
      .def_property_readonly("joint_q_start",
                             [](const PyRigidRobot& r) {
                               std::vector<int> x;
                               for (const auto& j : r.robot.joints) x.push_back(j.positionIndex);
                               return x;
                             })
      .def_property_readonly("joint_v_start",
                             [](const PyRigidRobot& r) {
                               std::vector<int> x;
                               for (const auto& j : r.robot.joints) x.push_back(j.velocityIndex);
                               return x;
                             })
      .def_property_readonly(
          "actuators",
          [](const PyRigidRobot& r) {
            py::list out;
            for (const build::MjcfActuator& a : r.mjcf.actuators) {
              py::dict d;
              d["name"] = a.name;
              d["kind"] = a.kind == build::MjcfActuator::Kind::kMotor      ? "motor"
                          : a.kind == build::MjcfActuator::Kind::kPosition ? "position"
                                                                           : "velocity";
              d["joint"] = a.joint;
              d["v_index"] = a.velocityIndex;
              d["gear"] = a.gear;
              d["gain"] = a.gain;
              d["ctrl_range"] = py::make_tuple(a.ctrlLower, a.ctrlUpper);
              d["force_range"] = py::make_tuple(a.forceLower, a.forceUpper);
              out.append(d);
            }
            return out;
          },
          "An MJCF file's actuators (motor, position, velocity) as data; [] for a URDF.")
      .def_property_readonly(
          "timestep", [](const PyRigidRobot& r) { return r.mjcf.timestep; },
          "An MJCF file's <option timestep> (s); 0.002 for a URDF.")
      .def_property(
          "q", [](const PyRigidRobot& r) { return toArray(r.q); },
          [](PyRigidRobot& r, const py::object& q) { r.q = r.values(q, r.q.size(), r.q, "q"); },
          "Joint coordinates (nq): a free base's x y z qw qx qy qz first, then one a joint.")
      .def_property(
          "v", [](const PyRigidRobot& r) { return toArray(r.v); },
          [](PyRigidRobot& r, const py::object& v) { r.v = r.values(v, r.v.size(), r.v, "v"); },
          "Joint rates (nv): a free base's ω and origin velocity (world) first.")
      .def_readwrite("gravity", &PyRigidRobot::gravity)
      .def(
          "gravity_forces",
          [](PyRigidRobot& r, const py::object& q) {
            r.at(q, py::cast(std::vector<double>(r.v.size(), 0.0)));
            std::vector<double> tau(r.nv());
            inverseDynamics(r.mb(), r.kinematics, nullptr, r.gravity, nullptr, tau.data());
            return toArray(tau);
          },
          py::arg("q") = py::none(),
          "The generalized forces that hold the robot at q against gravity.")
      .def(
          "bias_forces",
          [](PyRigidRobot& r, const py::object& q, const py::object& v) {
            r.at(q, v);
            std::vector<double> tau(r.nv());
            inverseDynamics(r.mb(), r.kinematics, nullptr, r.gravity, nullptr, tau.data());
            return toArray(tau);
          },
          py::arg("q") = py::none(), py::arg("v") = py::none(),
          "c(q, v): Coriolis, centrifugal and gravity forces (MuJoCo's qfrc_bias).")
      .def(
          "mass_matrix",
          [](PyRigidRobot& r, const py::object& q) {
            r.at(q, py::none());
            const auto n = static_cast<py::ssize_t>(r.nv());
            py::array_t<double> M({n, n});
            massMatrix(r.mb(), r.kinematics, M.mutable_data());
            return M;
          },
          py::arg("q") = py::none())
      .def(
          "frame_pose",
          [](PyRigidRobot& r, const std::string& name, const py::object& q) {
            r.at(q, py::none());
            const Pose X = framePose(r.mb(), r.kinematics, r.frame(name));
            return py::make_tuple(X.translation, matrixOf(X.rotation));
          },
          py::arg("frame"), py::arg("q") = py::none(),
          "X_WF: (position, 3×3 rotation) of a link frame.")
      .def(
          "jacobian",
          [](PyRigidRobot& r, const std::string& name, const py::object& q, const Vec3& point) {
            r.at(q, py::none());
            const auto n = r.nv();
            py::array_t<double> out({py::ssize_t{6}, static_cast<py::ssize_t>(n)});
            calcFrameJacobian(r.mb(), r.kinematics, r.frame(name), point, out.mutable_data());
            return out;
          },
          py::arg("frame"), py::arg("q") = py::none(), py::arg("point") = Vec3{},
          "The geometric Jacobian (6 × nv: the point's velocity rows, then the frame's angular "
          "velocity rows, in the world) of the point p_FP = `point` fixed to the frame (its origin "
          "by default): MuJoCo's mj_jac (jacp over jacr).")
      .def(
          "frame_velocity",
          [](PyRigidRobot& r, const std::string& name, const py::object& q, const py::object& v,
             const Vec3& point) {
            r.at(q, v);
            const SpatialVector V =
                calcFrameSpatialVelocity(r.mb(), r.kinematics, r.frame(name), point);
            return toArray(
                {V.linear.x, V.linear.y, V.linear.z, V.angular.x, V.angular.y, V.angular.z});
          },
          py::arg("frame"), py::arg("q") = py::none(), py::arg("v") = py::none(),
          py::arg("point") = Vec3{},
          "The frame's velocity at the point (6: the point's velocity, then the angular velocity, "
          "in "
          "the world) = jacobian(frame, q, point) @ v: MuJoCo's mj_objectVelocity in world axes.")
      .def(
          "frame_transform",
          [](PyRigidRobot& r, const std::string& name, const py::object& q) {
            r.at(q, py::none());
            const Pose X = framePose(r.mb(), r.kinematics, r.frame(name));
            py::array_t<double> T({py::ssize_t{4}, py::ssize_t{4}});
            auto t = T.mutable_unchecked<2>();
            const double p[3] = {X.translation.x, X.translation.y, X.translation.z};
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) t(i, j) = X.rotation.m[i][j];
              t(i, 3) = p[i];
              t(3, i) = 0.0;
            }
            t(3, 3) = 1.0;
            return T;
          },
          py::arg("frame"), py::arg("q") = py::none(), "X_WF as a 4 × 4 homogeneous matrix.")
      .def(
          "forward_kinematics",
          [](PyRigidRobot& r, const py::object& q) {
            r.at(q, py::none());
            py::dict poses;
            for (std::size_t f = 0; f < r.mb().frames.size(); ++f) {
              const Pose X = framePose(r.mb(), r.kinematics, static_cast<std::int32_t>(f));
              poses[py::str(r.mb().frames[f].name)] =
                  py::make_tuple(X.translation, matrixOf(X.rotation));
            }
            return poses;
          },
          py::arg("q") = py::none(),
          "Every frame's X_WF at q: {frame name: (position, 3×3 rotation)} (MuJoCo's xpos, xmat).")
      .def(
          "inverse_kinematics",
          [](PyRigidRobot& r, const std::string& name, const py::object& position,
             const py::object& rotation, const py::object& q0, double positionWeight,
             double orientationWeight, int maxIterations, int restarts, std::uint64_t seed,
             double positionTolerance, double orientationTolerance) {
            const std::int32_t f = r.frame(name);
            const std::vector<double> start = r.values(q0, r.q.size(), r.q, "q0");
            InverseKinematicsSettings s;
            s.positionWeight = position.is_none() ? 0.0 : positionWeight;
            s.orientationWeight = rotation.is_none() ? 0.0 : orientationWeight;
            s.maxIterations = maxIterations;
            s.restarts = restarts;
            s.seed = seed;
            s.positionTolerance = positionTolerance;
            s.orientationTolerance = orientationTolerance;
            Pose target;
            if (!position.is_none()) target.translation = position.cast<Vec3>();
            if (!rotation.is_none()) target.rotation = rotationOf(rotation);
            const InverseKinematicsResult ik = solveInverseKinematics(r.mb(), f, target, start, s);
            py::dict out;
            out["q"] = toArray(ik.q);
            out["success"] = ik.success;
            out["position_error"] = ik.positionError;
            out["orientation_error"] = ik.orientationError;
            out["iterations"] = ik.iterations;
            out["attempts"] = ik.attempts;
            return out;
          },
          py::arg("frame"), py::arg("position") = py::none(), py::arg("rotation") = py::none(),
          py::kw_only(), py::arg("q0") = py::none(), py::arg("position_weight") = 1.0,
          py::arg("orientation_weight") = 1.0, py::arg("max_iterations") = 100,
          py::arg("restarts") = 20, py::arg("seed") = 1, py::arg("position_tolerance") = 1e-6,
          py::arg("orientation_tolerance") = 1e-5,
          "Damped least-squares IK for the frame's pose (position and/or 3×3 rotation; None leaves "
          "it free), within the joint limits, from q0 (default: q) and then from random restarts "
          "(deterministic by seed). Returns {q, success, position_error (m), orientation_error "
          "(rad), iterations, attempts}; q is the best found, robot.q is unchanged.")
      .def(
          "energy",
          [](PyRigidRobot& r) {
            r.at(py::none(), py::none());
            return py::make_tuple(kineticEnergy(r.kinematics),
                                  gravitationalEnergy(r.kinematics, r.gravity));
          },
          "(kinetic, gravitational) energy (J).")
      .def(
          "step",
          [](PyRigidRobot& r, double dt, const py::object& effort, const py::object& kp,
             const py::object& kd, const py::object& target, const py::object& targetRate) {
            if (!(dt > 0.0)) throw std::invalid_argument("dt must be > 0 s");
            MultibodyInputs in;
            in.effort = r.perRate(effort, "effort");
            in.servoStiffness = r.perRate(kp, "kp");
            in.servoDamping = r.perRate(kd, "kd");
            in.servoTarget = r.perRate(target, "target");
            in.servoTargetRate = r.perRate(targetRate, "target_rate");
            const MultibodyStepReport report = stepMultibody(r.mb(), r.q, r.v, in, dt, r.gravity, r.workspace);
            return report.constrainedJoints;
          },
          py::arg("dt"), py::arg("effort") = py::none(), py::arg("kp") = py::none(),
          py::arg("kd") = py::none(), py::arg("target") = py::none(),
          py::arg("target_rate") = py::none(),
          "One step: efforts applied as given; servos τ = −kp (q − target) − kd (q̇ − target_rate) "
          "integrated implicitly (stable at any gain); joint limits are hard stops. Returns the "
          "number of joints at a stop or held by friction.");
}

}  // namespace robophi::python
