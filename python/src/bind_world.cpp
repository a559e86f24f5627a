// robophi.World: step, advance, run with a callback, views of positions,
// velocities and forces, contacts as a structured array, joints, edits.
#include <cmath>
#include <cstring>
#include <limits>

#include "py_robophi.h"
#include "run/live_view.h"
#include "robophi/joints.h"

namespace robophi::python {

namespace {

/// One contact as world.contacts lists it (a numpy structured record).
struct ContactRecord {
  std::int32_t a;
  /// The other particle, or -1 for the environment.
  std::int32_t other;
  /// The environment item (planes, heightfields, boxes, spheres), or -1.
  std::int32_t environment;
  /// 0 sticking, 1 sliding, 2 breaking away (MODEL §3.3).
  std::int32_t sliding;
  double depth;
  double normal[3];
  double normalForce;
  double frictionForce[3];
};

}  // namespace

PyWorld::PyWorld(const CompiledModel& model, State initial, Integrator integrator,
                 AdaptiveStepSettings adaptive)
    : world_(model, std::move(initial), integrator), adaptive_(adaptive) {
  sensorReference = world_.state();
}

void PyWorld::viewCreated() {
  if (liveViews_ == 0 && !checkPending_) {
    shadowPosition_ = world_.state().position;
    shadowVelocity_ = world_.state().velocity;
  }
  ++liveViews_;
  checkPending_ = true;
}

void PyWorld::reshadow() {
  if (liveViews_ == 0 && !checkPending_) return;
  // Copy-assignment of equal sizes keeps the buffers: no allocation per step.
  shadowPosition_ = world_.state().position;
  shadowVelocity_ = world_.state().velocity;
}

void PyWorld::syncViews() {
  if (liveViews_ == 0 && !checkPending_) return;
  checkPending_ = false;
  // The state's arrays as the views left them (the views write the World's own memory).
  auto& position = const_cast<std::vector<Vec3>&>(world_.state().position);
  auto& velocity = const_cast<std::vector<Vec3>&>(world_.state().velocity);
  struct Write {
    std::size_t particle;
    bool isVelocity;
    Vec3 value;
  };
  std::vector<Write> writes;
  for (std::size_t i = 0; i < position.size(); ++i) {
    if (std::memcmp(&position[i], &shadowPosition_[i], sizeof(Vec3)) != 0) {
      writes.push_back({i, false, position[i]});
      position[i] = shadowPosition_[i];
    }
    if (std::memcmp(&velocity[i], &shadowVelocity_[i], sizeof(Vec3)) != 0) {
      writes.push_back({i, true, velocity[i]});
      velocity[i] = shadowVelocity_[i];
    }
  }
  if (writes.empty()) return;
  // Each write becomes an edit: checked, and its work booked as external. A bad
  // value (NaN) throws with the state as it was before that write.
  try {
    for (const Write& w : writes) {
      const auto i = static_cast<ParticleIndex>(w.particle);
      if (w.isVelocity)
        world_.setVelocity(i, w.value);
      else
        world_.setPosition(i, w.value);
    }
  } catch (...) {
    reshadow();
    throw;
  }
  reshadow();
}

void PyWorld::throwDiverged() const {
  const ParticleIndex bad = world_.firstNonFiniteParticle();
  std::string where =
      bad == kNoParticle ? std::string("the energy") : "particle " + std::to_string(bad);
  if (bad != kNoParticle) {
    const auto object = world_.model().objectOf[static_cast<std::size_t>(bad)];
    where += " (object '" + world_.model().objects[static_cast<std::size_t>(object)].name + "')";
  }
  throw Diverged("the step at t = " + std::to_string(world_.state().time) +
                 " s made the state non-finite: " + where + " is NaN or infinite");
}

robotics::Controller& PyWorld::controller() {
  if (!controller_)
    controller_ = std::make_unique<robotics::Controller>(robotics::ControlSpec{}, world_.model());
  return *controller_;
}

void PyWorld::beforeStep() {
  syncViews();
  if (controller_) {
    controller_->apply(world_);
    reshadow();
  }
}

void PyWorld::step(double dt) {
  beforeStep();
  StepStatus status;
  {
    py::gil_scoped_release release;
    status = world_.step(dt);
  }
  reshadow();
  if (status != StepStatus::kOk) throwDiverged();
  afterStep();
}

void PyWorld::stepWithoutTunnelling(double dt) {
  beforeStep();
  StepStatus status;
  {
    py::gil_scoped_release release;
    status = robophi::stepWithoutTunnelling(world_, dt, adaptive_.maxPenetrationFraction,
                                            adaptive_.stabilitySafety);
  }
  reshadow();
  if (status != StepStatus::kOk) throwDiverged();
  afterStep();
}

double PyWorld::advance(double maxDt) {
  beforeStep();
  if (!stepper_) stepper_.emplace(world_.model(), adaptive_);
  AdaptiveStepResult result;
  {
    py::gil_scoped_release release;
    result = stepper_->advance(world_, maxDt);
  }
  reshadow();
  if (!result.ok) throw Diverged(result.failure);
  afterStep();
  return result.dt;
}

void PyWorld::afterStep() {
  if (!live_) return;
  {
    py::gil_scoped_release release;  // (it may wait: pacing, a pause)
    live_->afterStep(world_);
  }
  reshadow();  // a drag's velocity edit is the world's own, already booked
}

std::string PyWorld::view(int port, double waitSeconds, double speed) {
  if (live_) return live_->url();
  if (port < 0 || port > 65535)
    throw std::invalid_argument("view: port = " + std::to_string(port) + ": expected 0 to 65535");
  if (!(waitSeconds >= 0.0) || !std::isfinite(waitSeconds))
    throw std::invalid_argument("view: wait = " + std::to_string(waitSeconds) +
                                " s must be a finite number >= 0");
  if (!(speed >= 0.0) || !std::isfinite(speed))
    throw std::invalid_argument("view: speed = " + std::to_string(speed) +
                                ": expected model seconds per wall second >= 0 (0: as fast as "
                                "possible)");
  syncViews();
  Scene scene;
  scene.name = "python";
  scene.sourcePath = "<python>";
  scene.model = world_.model();
  scene.initial = world_.state();
  LiveViewSettings settings;
  settings.port = port;
  settings.waitSeconds = waitSeconds;
  settings.speed = speed;
  live_ = std::make_shared<LiveView>(scene, world_.state(), settings);  // (RuntimeError: not built, port)
  if (waitSeconds > 0.0) {
    py::gil_scoped_release release;
    live_->waitForViewer();
  }
  return live_->url();
}

void PyWorld::closeView() {
  if (!live_) return;
  live_->finish(&world_.state());
  live_.reset();
}

void PyWorld::setState(const State& state) {
  syncViews();
  // A world of the same (edited) model at `state`, whose snapshot is copied into
  // this one: the arrays keep their memory, so the views stay valid.
  World fresh(world_.compiled(), state, world_.integrator());
  world_.restore(fresh.snapshot());
  stepper_.reset();
  reshadow();
}

void PyWorld::restore(const World::Snapshot& snapshot) {
  syncViews();
  world_.restore(snapshot);
  reshadow();
}

double PyWorld::jointTarget(std::size_t joint) const {
  const Model& model = world_.model();
  const JointServo servo = jointServo(model, joint);
  if (!servo.hasDrive) return std::numeric_limits<double>::quiet_NaN();
  const Joint& j = model.joints[joint];
  return j.wraps() ? wrapSigned(servo.target - j.zero) : servo.target - j.zero;
}

double PyWorld::jointEffort(std::size_t joint) const {
  const Model& model = world_.model();
  const JointServo servo = jointServo(model, joint);
  if (!servo.hasDrive) return 0.0;
  // MODEL §1: the servo spring on the error q − q_target (wrapped for an angle).
  const double q = jointPosition(model, world_.state(), joint);
  const double target = jointTarget(joint);
  const double error =
      model.joints[joint].wraps() ? wrapSigned(q - target) : q - target;
  return -servo.stiffness * error - servo.damping * jointRate(model, world_.state(), joint);
}

void PyWorld::setJointTarget(std::size_t joint, double position) {
  if (!std::isfinite(position))
    throw std::invalid_argument("set_joint_target: position " + std::to_string(position) +
                                " must be finite");
  world_.setJointTarget(joint, jointRawValue(world_.model().joints.at(joint), position));
}

namespace {

/// The base object of a writable view of a World's state: keeps the World
/// alive and tells it when the view is gone.
struct WorldView {
  py::object owner;
  PyWorld* world;
  WorldView(py::object o, PyWorld* w) : owner(std::move(o)), world(w) { world->viewCreated(); }
  WorldView(const WorldView&) = delete;
  WorldView& operator=(const WorldView&) = delete;
  ~WorldView() { world->viewReleased(); }
};

py::array writableView(py::object self, bool velocities) {
  auto& w = self.cast<PyWorld&>();
  const State& s = w.world().state();
  const std::vector<Vec3>& data = velocities ? s.velocity : s.position;
  py::object token = py::cast(new WorldView(self, &w), py::return_value_policy::take_ownership);
  return vec3View(data.data(), data.size(), token, true);
}

Vec3 toVec3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// A method that edits one particle of the state (World::setPosition, setVelocity,
// applyImpulse): writes through the views first, the copy they are compared with after.
template <void (World::*Edit)(ParticleIndex, const Vec3&)>
auto particleEdit() {
  return [](PyWorld& w, ParticleIndex i, const Vec3& value) {
    w.syncViews();
    (w.world().*Edit)(i, value);
    w.reshadow();
  };
}

py::array contactArray(const World& world) {
  const std::vector<Contact>& contacts = world.contacts();
  py::array_t<ContactRecord> out(static_cast<py::ssize_t>(contacts.size()));
  auto* records = out.mutable_data();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    ContactRecord& r = records[k];
    r.a = c.a;
    r.other = c.withEnvironment() ? -1 : c.other;
    r.environment = c.withEnvironment() ? c.environmentItem() : -1;
    r.sliding = c.sliding;
    r.depth = c.depth;
    r.normal[0] = c.normal.x;
    r.normal[1] = c.normal.y;
    r.normal[2] = c.normal.z;
    r.normalForce = c.normalForce;
    r.frictionForce[0] = c.frictionForce.x;
    r.frictionForce[1] = c.frictionForce.y;
    r.frictionForce[2] = c.frictionForce.z;
  }
  return out;
}

py::array doubles(const std::vector<double>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// A property getter: a numpy array of value(world, j) for every joint j, after
// the writes through the views are booked.
template <class Value>
auto perJoint(Value value) {
  return [value](PyWorld& w) {
    w.syncViews();
    std::vector<double> v(w.world().model().joints.size());
    for (std::size_t j = 0; j < v.size(); ++j) v[j] = value(w, j);
    return doubles(v);
  };
}

AdaptiveStepSettings sceneAdaptive(const Scene& scene) {
  AdaptiveStepSettings a = scene.run.adaptive;
  a.initialStep = scene.run.dt;  // RunSettings::dt is the first trial step (as the runner)
  return a;
}

}  // namespace

void bindWorld(py::module_& m) {
  PYBIND11_NUMPY_DTYPE_EX(ContactRecord, a, "a", other, "other", environment, "environment",
                          sliding, "sliding", depth, "depth", normal, "normal", normalForce,
                          "normal_force", frictionForce, "friction_force");
  py::class_<WorldView>(m, "_WorldView");

  py::class_<AdaptiveStepSettings>(m, "AdaptiveSettings",
                                   "The adaptive step's settings (docs/adaptive-step.md).")
      .def(py::init<>())
      .def_readwrite("initial_step", &AdaptiveStepSettings::initialStep, "s")
      .def_readwrite("min_step", &AdaptiveStepSettings::minStep, "s; 0: relative")
      .def_readwrite("max_step", &AdaptiveStepSettings::maxStep, "s")
      .def_readwrite("energy_tolerance", &AdaptiveStepSettings::energyTolerance, "-")
      .def_readwrite("max_penetration_fraction", &AdaptiveStepSettings::maxPenetrationFraction, "-")
      .def_readwrite("max_approach_fraction", &AdaptiveStepSettings::maxApproachFraction, "-")
      .def_readwrite("stability_safety", &AdaptiveStepSettings::stabilitySafety, "-")
      .def_readwrite("jump_limit", &AdaptiveStepSettings::jumpLimit, "-")
      .def_readwrite("max_rejections_in_a_row", &AdaptiveStepSettings::maxRejectionsInARow);

  py::class_<World::Snapshot>(m, "Snapshot",
                              "Everything needed to undo steps exactly (World.snapshot()).")
      .def_property_readonly("state", [](const World::Snapshot& s) { return s.state(); })
      .def_property_readonly("time", [](const World::Snapshot& s) { return s.state().time; });

  py::class_<PyWorld>(m, "World",
                      "A compiled model, its state and the step. positions and velocities are "
                      "writable (n, 3) views on the world's own memory: a write is an edit, "
                      "booked as external work at the next step.")
      .def(
          py::init([](const PyModel& model, std::optional<State> state,
                      const std::string& integrator, std::optional<AdaptiveStepSettings> adaptive) {
            return new PyWorld(
                *model.compiled, state ? std::move(*state) : State::sizedFor(model.model()),
                integratorFromName(integrator), adaptive.value_or(AdaptiveStepSettings{}));
          }),
          py::arg("model"), py::arg("state") = py::none(), py::arg("integrator") = "symplectic",
          py::arg("adaptive") = py::none())
      .def(py::init([](const PyScene& scene) {
             auto* w = new PyWorld(*scene.model.compiled, scene.scene->initial,
                                   scene.scene->run.integrator, sceneAdaptive(*scene.scene));
             for (const SensorSpec& spec : scene.scene->sensors)
               w->sensors.add(w->world().model(), w->sensorReference, spec);
             return w;
           }),
           py::arg("scene"),
           "The scene's model at its initial state, with its integrator and "
           "adaptive settings.")
      // ---- Stepping.
      .def("step", &PyWorld::step, py::arg("dt"),
           "One step of dt (s). DivergedError if the state becomes non-finite.")
      .def("advance", &PyWorld::advance,
           py::arg("max_dt") = std::numeric_limits<double>::infinity(),
           "One accepted adaptive step (MODEL §4) of at most max_dt (s); returns the step taken.")
      .def(
          "run",
          [](py::object self, double duration, py::object callback, std::optional<double> dt) {
            auto& w = self.cast<PyWorld&>();
            if (!(duration >= 0.0) || !std::isfinite(duration))
              throw std::invalid_argument("run: duration = " + std::to_string(duration) +
                                          " s must be a finite number >= 0");
            if (dt && (!(*dt > 0.0) || !std::isfinite(*dt)))
              throw std::invalid_argument("run: dt = " + std::to_string(*dt) +
                                          " s must be > 0 and finite");
            // As the runner: constant steps are counted and land on start + k dt
            // (the last clipped to the end); adaptive steps run until t reaches the end.
            const double start = w.world().state().time;
            const double end = start + duration;
            const std::int64_t constantSteps =
                dt ? static_cast<std::int64_t>(std::ceil(duration / *dt - 1e-9)) : 0;
            std::int64_t steps = 0;
            while (true) {
              if (dt) {
                if (steps >= constantSteps) break;
                const double target = std::min(start + static_cast<double>(steps + 1) * *dt, end);
                w.stepWithoutTunnelling(target - w.world().state().time);
              } else {
                if (w.world().state().time >= end - 1e-12 * std::abs(end)) break;
                w.advance(end - w.world().state().time);
              }
              ++steps;
              if (!callback.is_none()) {
                py::object go = callback(self);
                if (!go.is_none() && !go.cast<bool>()) break;
              }
            }
            return steps;
          },
          py::arg("duration"), py::arg("callback") = py::none(), py::arg("dt") = py::none(),
          "Advances by `duration` (s) as `robophi run` does: adaptive steps, or constant steps "
          "of dt (split where approaching surfaces need it, landing on start + k dt). "
          "callback(world) runs after each step; returning False ends the run. Returns the "
          "steps taken.")
      // ---- The state.
      .def_property_readonly(
          "positions", [](py::object self) { return writableView(self, false); },
          "(n, 3) m, writable view")
      .def_property_readonly(
          "velocities", [](py::object self) { return writableView(self, true); },
          "(n, 3) m/s, writable view")
      .def_property_readonly(
          "forces",
          [](py::object self) {
            auto& w = self.cast<PyWorld&>();
            w.syncViews();
            const auto& f = w.world().forces();
            return vec3View(f.data(), f.size(), self, false);
          },
          "(n, 3) N at the current state, read-only view")
      .def_property_readonly(
          "spins",
          [](py::object self) {
            auto& w = self.cast<PyWorld&>();
            const auto& s = w.world().state().spin;
            return vec3View(s.data(), s.size(), self, false);
          },
          "(n, 3) rad/s, read-only view")
      .def_property_readonly(
          "time", [](const PyWorld& w) { return w.world().state().time; }, "s")
      .def_property_readonly("step_count",
                             [](const PyWorld& w) { return w.world().state().stepCount; })
      .def_property_readonly("particle_count",
                             [](const PyWorld& w) { return w.world().model().particleCount(); })
      .def_property_readonly(
          "state",
          [](PyWorld& w) {
            w.syncViews();
            return w.world().state();
          },
          "A copy of the state (a plain value).")
      .def("view", &PyWorld::view, py::arg("port") = LiveViewSettings{}.port,
           py::arg("wait") = 0.0, py::arg("speed") = 1.0,
           "Serves a live view of this world on 127.0.0.1 (docs/viewer.md \"Live view\") and "
           "returns its address; each step sends a frame (at most 60 per second). While a "
           "viewer is connected the steps are paced to `speed` model seconds per wall second "
           "(0: as fast as possible) and the viewer can pause them and drag a particle (its "
           "work is external work). port 0: any free port; wait: seconds to wait for a first "
           "viewer. RuntimeError when robophi was built without the live view or the port is "
           "taken.")
      .def("close_view", &PyWorld::closeView, "Stops serving the live view.")
      .def("set_state", &PyWorld::setState, py::arg("state"),
           "Puts the world at `state` (a state of this model, e.g. world.state taken earlier).")
      .def("snapshot",
           [](PyWorld& w) {
             w.syncViews();
             return w.world().snapshot();
           })
      .def("restore", &PyWorld::restore, py::arg("snapshot"), "Undoes steps exactly.")
      .def(
          "hash",
          [](PyWorld& w) {
            w.syncViews();
            return stateHash(w.world().state());
          },
          "stateHash of the current state (summary.json's state_hash, as an int).")
      .def_property_readonly("energy",
                             [](PyWorld& w) {
                               w.syncViews();
                               return w.world().energy();
                             })
      .def_property_readonly(
          "contacts",
          [](PyWorld& w) {
            w.syncViews();
            return contactArray(w.world());
          },
          "Structured array: a, other (-1: environment), environment (item "
          "or -1), sliding, depth (m), normal (3), normal_force (N), "
          "friction_force (3, N).")
      .def_property_readonly(
          "model",
          [](const PyWorld& w) {
            return PyModel{std::make_shared<const CompiledModel>(w.world().compiled())};
          },
          "A copy of the world's model, with the edits made so far.")
      .def_property(
          "integrator",
          [](const PyWorld& w) { return std::string(integratorName(w.world().integrator())); },
          [](PyWorld& w, const std::string& name) {
            w.world().setIntegrator(integratorFromName(name));
          })
      // ---- Joints (q counted from Joint::zero: rad in (-π, π], or m).
      .def_property_readonly("joint_positions", perJoint([](const PyWorld& w, std::size_t j) {
                               return jointPosition(w.world().model(), w.world().state(), j);
                             }),
                             "q of every joint (rad or m)")
      .def_property_readonly("joint_values", perJoint([](const PyWorld& w, std::size_t j) {
                               return jointValue(w.world().model(), w.world().state(), j);
                             }),
                             "The joints' raw values (jointValue: rad in [0, 2π), or m)")
      .def_property_readonly("joint_rates", perJoint([](const PyWorld& w, std::size_t j) {
                               return jointRate(w.world().model(), w.world().state(), j);
                             }),
                             "q̇ of every joint (rad/s or m/s)")
      .def_property_readonly("joint_efforts", perJoint([](const PyWorld& w, std::size_t j) {
                               return w.jointEffort(j);
                             }),
                             "The servos' efforts −κ(q − q_target) − μ q̇ (N·m or N)")
      .def_property_readonly("joint_targets", perJoint([](const PyWorld& w, std::size_t j) {
                               return w.jointTarget(j);
                             }),
                             "q_target of every joint (NaN: a prismatic joint without a drive)")
      .def(
          "joint_position",
          [](PyWorld& w, py::handle joint) {
            w.syncViews();
            return jointPosition(w.world().model(), w.world().state(),
                                 jointIndex(w.world().model(), joint));
          },
          py::arg("joint"), "q of a joint given by name or index")
      .def(
          "set_joint_target",
          [](PyWorld& w, py::handle joint, double position) {
            w.syncViews();
            w.setJointTarget(jointIndex(w.world().model(), joint), position);
          },
          py::arg("joint"), py::arg("position"),
          "The servo's target q (rad or m, the coordinate of joint_positions), between steps.")
      .def(
          "set_joint_targets",
          [](PyWorld& w, const py::array_t<double, py::array::c_style | py::array::forcecast>& q) {
            w.syncViews();
            const std::size_t n = w.world().model().joints.size();
            if (q.ndim() != 1 || static_cast<std::size_t>(q.shape(0)) != n)
              throw std::invalid_argument("set_joint_targets: expected " + std::to_string(n) +
                                          " targets (one per joint), got shape (" +
                                          std::to_string(q.size()) + ")");
            for (std::size_t j = 0; j < n; ++j)
              if (!std::isnan(q.data()[j])) w.setJointTarget(j, q.data()[j]);
          },
          py::arg("positions"), "Targets of every joint (NaN: leave that joint's as it is).")
      .def(
          "set_joint_servo",
          [](PyWorld& w, py::handle joint, double stiffness, double damping) {
            w.syncViews();
            w.world().setJointServo(jointIndex(w.world().model(), joint), stiffness, damping);
          },
          py::arg("joint"), py::arg("stiffness"), py::arg("damping"),
          "Servo stiffness (N·m/rad or N/m) and damping (N·m·s/rad or N·s/m), >= 0.")
      // ---- Edits (booked as external work).
      .def("set_position", particleEdit<&World::setPosition>(), py::arg("particle"),
           py::arg("position"), "p (m)")
      .def("set_velocity", particleEdit<&World::setVelocity>(), py::arg("particle"),
           py::arg("velocity"), "v (m/s)")
      .def("apply_impulse", particleEdit<&World::applyImpulse>(), py::arg("particle"),
           py::arg("impulse"),
           "An impulse p (N·s) at the particle: v += p/m, or, for a particle a rigid tree "
           "carries, the tree's rates += M⁻¹ Jᵀ p (World::applyImpulse)")
      .def(
          "set_gravity",
          [](PyWorld& w, const std::array<double, 3>& g) {
            w.syncViews();
            w.world().setGravity(toVec3(g));
          },
          py::arg("gravity"), "g (m/s²)")
      .def(
          "set_particle_fixed",
          [](PyWorld& w, ParticleIndex i, bool fixed) {
            w.syncViews();
            w.world().setParticleFixed(i, fixed);
          },
          py::arg("particle"), py::arg("fixed") = true)
      .def(
          "set_viscosity",
          [](PyWorld& w, double k) {
            w.syncViews();
            w.world().setViscosity(k);
          },
          py::arg("viscosity"), "k (N·s/m)")
      .def(
          "add_sphere_obstacle",
          [](PyWorld& w, const std::array<double, 3>& center, double radius,
             std::int32_t material) {
            w.syncViews();
            return w.world().addSphereObstacle({toVec3(center), radius, material});
          },
          py::arg("center"), py::arg("radius"), py::arg("material") = 0)
      .def(
          "book_external_work",
          [](PyWorld& w) {
            w.syncViews();
            return w.world().bookExternalWork();
          },
          "The work (J) the edits since the last call did (booked as external).")
      .def("__repr__", [](const PyWorld& w) {
        return "<robophi.World t=" + std::to_string(w.world().state().time) + " s, " +
               std::to_string(w.world().model().particleCount()) + " particles, " +
               integratorName(w.world().integrator()) + ">";
      });
}

}  // namespace robophi::python
