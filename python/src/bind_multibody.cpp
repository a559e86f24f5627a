// Rigid robots from Python (docs/python.md "Rigid robots"): a URDF as a tree of
// rigid bodies (build::makeUrdfMultibody, include/robophi/multibody.h), with its
// state, kinematics, dynamics terms and step, numpy in and out. Names follow
// MuJoCo's where one exists (qpos → q, qvel → v, qfrc_bias → bias_forces).
#include <algorithm>

#include "py_robophi.h"
#include "robophi/build/urdf_multibody.h"
#include "robophi/multibody.h"

namespace robophi::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

struct PyRigidRobot {
  build::UrdfMultibody robot;
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
  std::int32_t frame(const std::string& name) const {
    std::int32_t f = mb().frameIndex(name);
    if (f < 0) f = mb().frameIndex(mb().name + "." + name);
    if (f >= 0) return f;
    std::string known;
    for (const MultibodyFrame& fr : mb().frames) known += (known.empty() ? "" : ", ") + fr.name;
    throw py::key_error("no frame named '" + name + "' (the robot has: " + known + ")");
  }
};

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
      .def(py::init([](const py::object& path, bool fixedBase, const std::vector<py::object>& packagePaths,
                       bool balanceInertia, bool inertiaFromGeometry) {
             build::UrdfMultibodySpec spec;
             spec.path = pathText(path);
             for (const py::object& p : packagePaths) spec.packagePaths.push_back(pathText(p));
             spec.fixedBase = fixedBase;
             spec.balanceInertia = balanceInertia;
             spec.inertiaFromGeometry = inertiaFromGeometry;
             auto robot = std::make_unique<PyRigidRobot>();
             robot->robot = build::makeUrdfMultibody(spec);
             robot->q = neutralConfiguration(robot->mb());
             robot->v.assign(robot->nv(), 0.0);
             return robot;
           }),
           py::arg("path"), py::arg("fixed_base") = true, py::arg("package_paths") = std::vector<py::object>{},
           py::arg("balance_inertia") = true, py::arg("inertia_from_geometry") = false)
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
      .def_property_readonly("adjustments", [](const PyRigidRobot& r) { return r.robot.adjustments; })
      .def_property_readonly("lower",
                             [](const PyRigidRobot& r) {
                               std::vector<double> x;
                               for (const auto& j : r.robot.joints) x.push_back(r.mb().bodies[j.body].lower);
                               return toArray(x);
                             })
      .def_property_readonly("upper",
                             [](const PyRigidRobot& r) {
                               std::vector<double> x;
                               for (const auto& j : r.robot.joints) x.push_back(r.mb().bodies[j.body].upper);
                               return toArray(x);
                             })
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
          py::arg("q") = py::none(), "The generalized forces that hold the robot at q against gravity.")
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
          py::arg("frame"), py::arg("q") = py::none(), "X_WF: (position, 3×3 rotation) of a link frame.")
      .def(
          "jacobian",
          [](PyRigidRobot& r, const std::string& name, const py::object& q) {
            r.at(q, py::none());
            const std::int32_t f = r.frame(name);
            const Pose X = framePose(r.mb(), r.kinematics, f);
            const auto n = r.nv();
            std::vector<double> J(6 * n);
            pointJacobian(r.mb(), r.kinematics, r.mb().frames[static_cast<std::size_t>(f)].body,
                          X.translation, J.data(), J.data() + 3 * n);
            py::array_t<double> out({py::ssize_t{6}, static_cast<py::ssize_t>(n)});
            std::copy(J.begin(), J.end(), out.mutable_data());
            return out;
          },
          py::arg("frame"), py::arg("q") = py::none(),
          "The geometric Jacobian (6 × nv: linear rows, then angular) of the frame's origin.")
      .def("energy",
           [](PyRigidRobot& r) {
             r.at(py::none(), py::none());
             return py::make_tuple(kineticEnergy(r.kinematics), gravitationalEnergy(r.kinematics, r.gravity));
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
          py::arg("kd") = py::none(), py::arg("target") = py::none(), py::arg("target_rate") = py::none(),
          "One step: efforts applied as given; servos τ = −kp (q − target) − kd (q̇ − target_rate) "
          "integrated implicitly (stable at any gain); joint limits are hard stops. Returns the "
          "number of joints at a stop or held by friction.");
}

}  // namespace robophi::python
