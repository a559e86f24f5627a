// robophi.load (scene files), robophi.Scene, robophi.run (the CLI's run: the same
// results folder and replay page) and robophi.rollout (many worlds in parallel).
#include <atomic>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <thread>

#include "output/results_folder.h"
#include "py_robophi.h"
#include "robophi/joints.h"
#include "robophi/scene/scene_mjcf.h"
#include "robophi/stability.h"
#include "robotics/tasks.h"
#include "run/runner.h"

namespace robophi::python {

namespace {

PyScene sceneFrom(std::shared_ptr<const Scene> scene) {
  PyModel model{std::make_shared<const CompiledModel>(scene->model)};
  return PyScene{std::move(scene), std::move(model), {}};
}

/// The exit code `robophi run` gives a report (docs/output-format.md#exit-codes).
int exitCode(const RunReport& report) {
  if (report.status == "ok" || report.status == "stopped") return 0;
  if (report.status == "interrupted") return 130;
  if (report.status == "energy_account_broken") return 4;
  if (report.status == "goal_not_reached") return 5;
  return 3;
}

std::string hex(std::uint64_t h) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

py::dict runScenePython(const py::handle& sceneArg, std::optional<std::string> out,
                        std::optional<double> duration, std::optional<std::string> step,
                        std::optional<double> dt, std::optional<std::string> integrator,
                        std::optional<double> fps, bool force, bool replay) {
  // A path: a scene file, or a bare URDF with the CLI's defaults (robophi.load's
  // options need a loaded robophi.Scene).
  std::shared_ptr<const Scene> scene;
  if (py::isinstance<PyScene>(sceneArg)) {
    scene = sceneArg.cast<const PyScene&>().scene;
  } else {
    const std::string path = pathText(sceneArg);
    scene = isMjcfPath(path)   ? sceneOrThrow(loadMjcfFile(path), path)
            : isUrdfPath(path) ? sceneOrThrow(loadUrdfFile(path), path)
                               : loadScene(path);
  }
  RunOptions options;
  options.settings = scene->run;
  RunSettings& run = options.settings;
  const auto positive = [](const char* name, std::optional<double> value, double& target) {
    if (!value) return;
    if (!(*value > 0.0) || !std::isfinite(*value))
      throw std::invalid_argument(std::string("robophi.run: ") + name + " = " +
                                  std::to_string(*value) + ": expected a positive number");
    target = *value;
  };
  positive("duration", duration, run.duration);
  positive("dt", dt, run.dt);
  positive("fps", fps, run.fps);
  if (integrator) run.integrator = integratorFromName(*integrator);
  if (step) {
    if (*step == "constant")
      run.stepMode = StepMode::kConstant;
    else if (*step == "adaptive")
      run.stepMode = StepMode::kAdaptive;
    else
      throw std::invalid_argument("robophi.run: step '" + *step +
                                  "': expected adaptive or constant");
  }
  if (const auto problem = checkRunSettings(run, options.energyRate))
    throw std::invalid_argument("robophi.run: " + problem->field + ": " + problem->message +
                                "; nothing was run or written");
  options.outDir =
      out ? *out
          : (std::filesystem::path("out") / std::filesystem::path(scene->sourcePath).stem())
                .string();
  options.force = force;
  options.writeReplay = replay;
  if (const std::string problem = outputFolderProblem(options); !problem.empty())
    throw std::invalid_argument(
        "robophi.run: out: " + problem +
        ". robophi deletes nothing it did not write: choose another out "
        "or move those away" +
        (force ? "" : ", or pass force=True to write robophi's files beside them") +
        "; nothing was run or written");
  const StabilityEstimate stability = estimateStability(scene->model, &scene->initial.position);
  if (run.stepMode == StepMode::kAdaptive) {
    const double fewest = run.duration / (run.adaptive.stabilitySafety * stability.criticalStep);
    if (!(fewest <= kMaxRunSteps))
      throw std::invalid_argument("robophi.run: " + scene->sourcePath +
                                  ": the model's fastest mode keeps the adaptive step so small "
                                  "that the duration takes more than the limit of 1e9 steps "
                                  "(docs/scene-format.md#limits); nothing was run or written");
  }
  options.tasks = {robotics::makeSceneTasks(*scene)};
  // Ctrl-C: the progress callback (about every 0.1 s of wall time) asks Python
  // for pending signals; a KeyboardInterrupt stops the run with its results so far.
  std::atomic<bool> stop{false};
  options.stop = &stop;
  options.progress = [&stop](const RunProgress&) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) stop = true;
  };
  State finalState;
  RunReport report;
  {
    py::gil_scoped_release release;
    report = runScene(*scene, options, &finalState);
  }
  if (stop && PyErr_Occurred()) throw py::error_already_set();
  py::dict result;
  result["status"] = report.status;
  result["exit_code"] = exitCode(report);
  result["ok"] = report.ok();
  result["failure"] = report.failure;
  result["steps"] = report.steps;
  result["simulated_time"] = report.simulatedTime;
  result["wall_seconds"] = report.wallSeconds;
  result["energy_drift"] = report.energyDrift;
  result["state_hash"] = hex(report.stateHash);
  result["out"] = options.outDir;
  result["warnings"] = report.warnings;
  result["events"] = report.events;
  result["state"] = std::move(finalState);
  return result;
}

/// What one world of a rollout ends with.
struct RolloutWorld {
  State final;
  std::string error;  // empty when it ran to the end
};

/// Runs world `w` of a rollout: `steps` control intervals of `dt` seconds; before
/// interval k the joint targets are set from controls[w][k] (NaN: unchanged).
/// Each world is sequential and owns everything it touches, so which thread runs
/// it cannot change its result.
RolloutWorld rolloutOne(const CompiledModel& model, const State& initial, Integrator integrator,
                        const double* controls, std::size_t joints, std::int64_t steps, double dt,
                        int substeps, const std::optional<AdaptiveStepSettings>& adaptive,
                        double* jointTrace) {
  RolloutWorld out;
  try {
    World world(model, initial, integrator);
    std::optional<AdaptiveStepper> stepper;
    if (adaptive) stepper.emplace(world.model(), *adaptive);
    const double h = dt / substeps;
    for (std::int64_t k = 0; k < steps; ++k) {
      if (controls) {
        for (std::size_t j = 0; j < joints; ++j) {
          const double q = controls[static_cast<std::size_t>(k) * joints + j];
          if (!std::isnan(q)) world.setJointTarget(j, jointRawValue(world.model().joints[j], q));
        }
      }
      if (stepper) {
        const double target = initial.time + static_cast<double>(k + 1) * dt;
        while (target - world.state().time > 1e-12 * std::max(1.0, std::abs(target))) {
          const AdaptiveStepResult r = stepper->advance(world, target - world.state().time);
          if (!r.ok) throw std::runtime_error(r.failure);
        }
      } else {
        for (int s = 0; s < substeps; ++s) {
          if (world.step(h) != StepStatus::kOk)
            throw std::runtime_error(
                "the state became non-finite at t = " + std::to_string(world.state().time) + " s");
        }
      }
      if (jointTrace) {
        for (std::size_t j = 0; j < joints; ++j)
          jointTrace[static_cast<std::size_t>(k) * joints + j] =
              jointPosition(world.model(), world.state(), j);
      }
    }
    out.final = world.state();
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  return out;
}

py::dict rollout(const PyModel& model, py::object initialStates, py::object controls,
                 std::optional<std::int64_t> stepsArg, double dt, int threads, int substeps,
                 const std::string& integratorName, std::optional<AdaptiveStepSettings> adaptive) {
  // The initial states: one State (every world starts there) or a list of them.
  std::vector<State> initial;
  std::optional<std::int64_t> worldsArg;
  if (py::isinstance<State>(initialStates)) {
    initial.push_back(initialStates.cast<State>());
  } else {
    for (py::handle s : initialStates) initial.push_back(s.cast<State>());
  }
  if (initial.empty()) throw std::invalid_argument("rollout: initial_states is empty");
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::invalid_argument("rollout: dt = " + std::to_string(dt) + " s must be > 0");
  if (threads < 1)
    throw std::invalid_argument("rollout: threads = " + std::to_string(threads) + " must be >= 1");
  if (substeps < 1) throw std::invalid_argument("rollout: substeps must be >= 1");
  const Integrator integrator = integratorFromName(integratorName);
  const std::size_t joints = model.model().joints.size();
  // The controls: (worlds, steps, joints) or (steps, joints) for every world.
  std::vector<double> u;
  std::int64_t steps = stepsArg.value_or(-1);
  std::size_t worlds = initial.size();
  bool perWorld = false;
  if (!controls.is_none()) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(controls);
    if (!a) throw std::invalid_argument("rollout: controls must be an array of joint targets");
    if (a.ndim() == 3) {
      perWorld = true;
      worldsArg = a.shape(0);
    } else if (a.ndim() != 2) {
      throw std::invalid_argument(
          "rollout: controls must have shape (steps, joints) or (worlds, "
          "steps, joints), got " +
          std::to_string(a.ndim()) + " dimensions");
    }
    const auto ctrlSteps = a.shape(a.ndim() - 2);
    if (static_cast<std::size_t>(a.shape(a.ndim() - 1)) != joints)
      throw std::invalid_argument(
          "rollout: controls have " + std::to_string(a.shape(a.ndim() - 1)) +
          " targets per step; the model has " + std::to_string(joints) + " joints");
    if (steps >= 0 && steps != ctrlSteps)
      throw std::invalid_argument("rollout: steps = " + std::to_string(steps) +
                                  " but controls have " + std::to_string(ctrlSteps) + " steps");
    steps = ctrlSteps;
    u.assign(a.data(), a.data() + a.size());
  }
  if (steps < 0) throw std::invalid_argument("rollout: give steps, or controls");
  if (worldsArg) {
    if (initial.size() == 1)
      worlds = static_cast<std::size_t>(*worldsArg);
    else if (static_cast<std::size_t>(*worldsArg) != initial.size())
      throw std::invalid_argument("rollout: " + std::to_string(initial.size()) +
                                  " initial states but controls for " + std::to_string(*worldsArg) +
                                  " worlds");
  }
  const auto n = static_cast<std::size_t>(model.model().particleCount());
  for (std::size_t w = 0; w < initial.size(); ++w) {
    if (initial[w].position.size() != n)
      throw std::invalid_argument("rollout: initial state " + std::to_string(w) + " has " +
                                  std::to_string(initial[w].position.size()) +
                                  " particles; the model has " + std::to_string(n));
  }
  py::array_t<double> trace({static_cast<py::ssize_t>(worlds), static_cast<py::ssize_t>(steps),
                             static_cast<py::ssize_t>(joints)});
  double* traceData = trace.mutable_data();
  std::vector<RolloutWorld> results(worlds);
  std::vector<double> threadSeconds;  // CPU time of each thread (s)
  {
    py::gil_scoped_release release;
    // Worlds are handed out in index order to whichever thread is free; each
    // world's result depends on its inputs only.
    std::atomic<std::size_t> next{0};
    const int extra = std::min<int>(threads, static_cast<int>(worlds)) - 1;
    threadSeconds.assign(static_cast<std::size_t>(extra + 1), 0.0);
    const auto work = [&](std::size_t thread) {
      timespec start{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &start);
      for (std::size_t w; (w = next.fetch_add(1)) < worlds;) {
        const double* c =
            u.empty() ? nullptr
                      : u.data() + (perWorld ? w * static_cast<std::size_t>(steps) * joints : 0);
        results[w] = rolloutOne(*model.compiled, initial[initial.size() == 1 ? 0 : w], integrator,
                                c, joints, steps, dt, substeps, adaptive,
                                traceData + w * static_cast<std::size_t>(steps) * joints);
      }
      timespec end{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &end);
      threadSeconds[thread] = static_cast<double>(end.tv_sec - start.tv_sec) +
                              1e-9 * static_cast<double>(end.tv_nsec - start.tv_nsec);
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < extra; ++t) pool.emplace_back(work, static_cast<std::size_t>(t + 1));
    work(0);
    for (std::thread& t : pool) t.join();
  }
  for (std::size_t w = 0; w < worlds; ++w) {
    if (!results[w].error.empty())
      throw Diverged("rollout: world " + std::to_string(w) + ": " + results[w].error);
  }
  py::list states;
  py::list hashes;
  for (RolloutWorld& r : results) {
    hashes.append(stateHash(r.final));
    states.append(std::move(r.final));
  }
  py::dict out;
  out["states"] = states;
  out["hashes"] = hashes;
  out["joint_positions"] = trace;
  out["thread_cpu_seconds"] = threadSeconds;
  return out;
}

}  // namespace

void bindRun(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A loaded scene file: its model, initial state and run settings.")
      .def_property_readonly("model", [](const PyScene& s) { return s.model; })
      .def_property_readonly(
          "initial", [](const PyScene& s) { return s.scene->initial; },
          "A copy of the initial state.")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene->name; })
      .def_property_readonly("description", [](const PyScene& s) { return s.scene->description; })
      .def_property_readonly("source_path", [](const PyScene& s) { return s.scene->sourcePath; })
      .def_property_readonly(
          "duration", [](const PyScene& s) { return s.scene->run.duration; }, "s")
      .def_property_readonly(
          "dt", [](const PyScene& s) { return s.scene->run.dt; }, "s")
      .def_property_readonly("integrator",
                             [](const PyScene& s) {
                               return std::string(robophi::integratorName(s.scene->run.integrator));
                             })
      .def_property_readonly(
          "adaptive_step",
          [](const PyScene& s) { return s.scene->run.stepMode == StepMode::kAdaptive; })
      .def(
          "world", [](const PyScene& s) { return py::module_::import("robophi").attr("World")(s); },
          "A World at the scene's initial state (robophi.World(scene)).")
      .def("__repr__", [](const PyScene& s) {
        return "<robophi.Scene '" + s.scene->name + "' from " + s.scene->sourcePath + ">";
      });

  m.def(
      "_load_scene",
      [](const py::handle& path) {
        const std::string text = pathText(path);
        std::vector<std::string> warnings;
        PyScene scene = sceneFrom(sceneOrThrow(loadSceneFile(text), text, &warnings));
        scene.warnings = std::move(warnings);
        return scene;
      },
      py::arg("path"));
  m.def("run", &runScenePython, py::arg("scene"), py::arg("out") = py::none(), py::kw_only(),
        py::arg("duration") = py::none(), py::arg("step") = py::none(), py::arg("dt") = py::none(),
        py::arg("integrator") = py::none(), py::arg("fps") = py::none(), py::arg("force") = false,
        py::arg("replay") = true,
        "Runs a scene (a path or a robophi.Scene) as `robophi run` does: the same results folder "
        "(default out/<scene>) with summary.json and replay.html. Returns a dict: status, "
        "exit_code, state_hash (summary.json's), steps, simulated_time, energy_drift, state, ...");
  m.def("rollout", &rollout, py::arg("model"), py::arg("initial_states"),
        py::arg("controls") = py::none(), py::kw_only(), py::arg("steps") = py::none(),
        py::arg("dt"), py::arg("threads") = 1, py::arg("substeps") = 1,
        py::arg("integrator") = "symplectic", py::arg("adaptive") = py::none(),
        "Steps many independent worlds of one model in parallel. Bit-identical whatever "
        "`threads`. Returns a dict: states (final State of each world), hashes, joint_positions "
        "(worlds, steps, joints), thread_cpu_seconds (the CPU time of each thread).");
}

}  // namespace robophi::python
