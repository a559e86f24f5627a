#pragma once
// The Python package's C++ side (docs/python.md): the wrappers the bindings
// share. Arrays handed to Python are views on robophi's own memory (no copy);
// their base object keeps the owner (a Model, State or World) alive.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "robophi/adaptive_step.h"
#include "robophi/compiled_model.h"
#include "robophi/scene/scene.h"
#include "robophi/state.h"
#include "robophi/world.h"
#include "robotics/controller.h"

namespace robophi {
class LiveView;
}

// robophi::Vec3 from any sequence of three numbers (list, tuple, numpy array),
// and to a tuple.
namespace pybind11::detail {
template <>
struct type_caster<robophi::Vec3> {
  PYBIND11_TYPE_CASTER(robophi::Vec3, const_name("Vec3"));
  bool load(handle src, bool) {
    if (!src || PyUnicode_Check(src.ptr()) || !PySequence_Check(src.ptr())) return false;
    const auto items = reinterpret_borrow<sequence>(src);
    if (items.size() != 3) return false;
    try {
      value = {items[0].cast<double>(), items[1].cast<double>(), items[2].cast<double>()};
    } catch (const cast_error&) {
      return false;
    }
    return true;
  }
  static handle cast(const robophi::Vec3& v, return_value_policy, handle) {
    return make_tuple(v.x, v.y, v.z).release();
  }
};
}  // namespace pybind11::detail

namespace robophi::python {

namespace py = pybind11;

// The (n, 3) float64 views rest on Vec3 being three packed doubles.
static_assert(std::is_standard_layout_v<Vec3> && sizeof(Vec3) == 3 * sizeof(double),
              "Vec3 must be three packed doubles for the numpy views");

/// A model as Python sees it: compiled once, read-only, shared by the worlds,
/// states and rollouts made from it.
struct PyModel {
  std::shared_ptr<const CompiledModel> compiled;
  const Model& model() const { return compiled->model(); }
};

/// A loaded scene: the model (compiled) with its initial state, run settings and
/// robotics section.
struct PyScene {
  std::shared_ptr<const Scene> scene;
  PyModel model;
  /// The loader's warnings as the CLI prints them (a bare URDF's ignored elements).
  std::vector<std::string> warnings{};
};

/// An (n, 3) float64 view on `data` whose base is `owner`.
py::array vec3View(const Vec3* data, std::size_t n, py::handle owner, bool writable);
/// A read-only 1-d view on `data` (numbers, or records of a registered numpy
/// dtype) whose base is `owner`.
template <class T>
py::array vectorView(const std::vector<T>& data, py::handle owner) {
  py::array view(py::dtype::of<T>(), {static_cast<py::ssize_t>(data.size())},
                 {static_cast<py::ssize_t>(sizeof(T))}, data.data(), owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

/// A path given as str or os.PathLike, as text (os.fspath).
std::string pathText(const py::handle& path);
/// Integrator from its name ("taylor", "symplectic", "verlet"); ValueError otherwise.
Integrator integratorFromName(const std::string& name);

/// A World with what Python needs around it: the adaptive stepper of
/// world.advance() and the bookkeeping that turns writes through the numpy views
/// of positions and velocities into World edits (booked as external work).
///
/// How writes are detected: while a writable view is alive (or was handed out
/// since the last check), the wrapper keeps a copy of the positions and
/// velocities as they were after the last step or edit. Before anything reads
/// or advances the world (syncViews), each particle whose value differs from
/// that copy is put back and set again through World::setPosition /
/// setVelocity, which checks it (finite) and books the jump of E + dissipated
/// as external work at the next evaluation. With no view out, nothing is compared.
class PyWorld {
 public:
  PyWorld(const CompiledModel& model, State initial, Integrator integrator,
          AdaptiveStepSettings adaptive);

  World& world() { return world_; }
  const World& world() const { return world_; }
  const AdaptiveStepSettings& adaptiveSettings() const { return adaptive_; }

  /// Books writes made through the views since the last call (see above).
  void syncViews();
  /// Takes the copy the next syncViews compares against (after a step or an edit).
  void reshadow();
  /// A writable view was created / released.
  void viewCreated();
  void viewReleased() { --liveViews_; }

  /// One constant step of dt (s). DivergedError when the state becomes non-finite.
  void step(double dt);
  /// One constant step of dt (s) as `robophi run --step constant` takes it: in
  /// equal substeps where approaching surfaces or a touching contact need them
  /// (stepWithoutTunnelling, with the adaptive settings' maxPenetrationFraction
  /// and stabilitySafety), landing on t + dt.
  void stepWithoutTunnelling(double dt);
  /// One accepted adaptive step of at most maxDt (s); returns the step taken.
  double advance(double maxDt);
  /// Replaces the state (a copy of one taken earlier): a fresh World on the
  /// current (edited) model, the same integrator; the adaptive controller restarts.
  void setState(const State& state);
  /// Puts back a snapshot of this world: undoes steps exactly.
  void restore(const World::Snapshot& snapshot);

  /// The joint's target position (rad or m: jointPosition's q, counted from Joint::zero).
  double jointTarget(std::size_t joint) const;
  /// The servo's effort at the current state: torque (N·m) of a revolute joint,
  /// force (N) of a prismatic joint's drive, −κ (q − q_target) − μ q̇ (0 without drive).
  double jointEffort(std::size_t joint) const;
  /// Sets a joint's target position q (rad or m, as jointPosition).
  void setJointTarget(std::size_t joint, double position);

  /// The world's actuators (world.set_actuator...): a robotics::Controller made
  /// at the first call, applied before every step (as the runner applies a
  /// scene's controller between steps).
  robotics::Controller& controller();
  const robotics::Controller* controllerIfAny() const { return controller_.get(); }

  /// Throws DivergedError (robophi::python::Diverged) naming the first bad particle.
  [[noreturn]] void throwDiverged() const;

  /// world.view(): serves the live view of this world (docs/viewer.md "Live
  /// view") and returns its address; the frames follow the steps taken.
  std::string view(int port, double waitSeconds, double speed);
  /// Stops serving the live view (nothing when none).
  void closeView();

  /// The sensors (world.add_sensor, a scene's "sensors"; robophi/sensors.h) and the
  /// state an object sensor's frame is fitted against (the world's first state).
  SensorSet sensors;
  State sensorReference;

 private:
  /// Books the views' writes and brings the actuators' commands to the world's time.
  void beforeStep();
  /// After a step: the live view's frame, pacing, pause and drag (when served).
  void afterStep();

  World world_;
  AdaptiveStepSettings adaptive_;
  std::optional<AdaptiveStepper> stepper_;
  std::unique_ptr<robotics::Controller> controller_;
  std::shared_ptr<LiveView> live_;
  int liveViews_ = 0;
  bool checkPending_ = false;
  std::vector<Vec3> shadowPosition_, shadowVelocity_;
};

/// The errors robophi raises in Python besides ValueError, IndexError and
/// RuntimeError (docs/python.md "Errors").
struct SceneLoadError : std::invalid_argument {
  SceneLoadError(const std::string& message, std::vector<Diagnostic> found)
      : std::invalid_argument(message), diagnostics(std::move(found)) {}
  std::vector<Diagnostic> diagnostics;
};
struct Diverged : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Loads a scene file; SceneLoadError carrying the CLI's messages otherwise.
std::shared_ptr<const Scene> loadScene(const std::string& path);
/// The scene of a load result, or SceneLoadError with the CLI's lines (each error,
/// then "PATH: N errors; nothing was run or written"). The warnings, formatted as
/// the CLI prints them, go to `warnings` when given.
std::shared_ptr<const Scene> sceneOrThrow(SceneLoadResult result, const std::string& path,
                                          std::vector<std::string>* warnings = nullptr);
/// The index of a joint given by name or index; IndexError / KeyError otherwise.
std::size_t jointIndex(const Model& model, const py::handle& joint);

void bindErrors(py::module_& m);
void bindModel(py::module_& m);
void bindWorld(py::module_& m);
void bindBuild(py::module_& m);
void bindRun(py::module_& m);
void bindUrdf(py::module_& m);
void bindActuators(py::module_& m);
void bindMultibody(py::module_& m);
/// World's sensors and its joints' vector reads and writes (bind_sensors.cpp).
void bindSensors(py::module_& m);

}  // namespace robophi::python
