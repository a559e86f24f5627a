// robophi study experiments: the paper's experiments played from their scene
// files, with their outcomes and wall times (docs/experiments.md).
#include "study_experiments.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>

#include "robotics/tasks.h"

namespace robophi::cli {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The time of the first "goal '...' reached at t = ..." event.
std::optional<double> goalReachedTime(const std::vector<std::string>& events) {
  static const std::string kMarker = "reached at t = ";
  for (const std::string& e : events) {
    const auto at = e.find(kMarker);
    if (at != std::string::npos) return std::strtod(e.c_str() + at + kMarker.size(), nullptr);
  }
  return std::nullopt;
}

void addGoalTime(const RunReport& report, ExperimentFigures& f) {
  const auto reached = goalReachedTime(report.events);
  if (reached) {
    f.values["goal_reached_s"] = *reached;
    f.words.push_back(fmt::format("goal reached at t = {:.4g} s", *reached));
  } else {
    f.values["goal_reached_s"] = nullptr;
    f.words.push_back("goal not reached");
  }
}

// Mean position and mean velocity of an object's particles.
Vec3 centroid(const std::vector<Vec3>& v, const ObjectInfo& object) {
  Vec3 sum;
  for (ParticleIndex i = object.firstParticle; i < object.firstParticle + object.particleCount; ++i)
    sum += v[static_cast<std::size_t>(i)];
  return object.particleCount > 0 ? sum / static_cast<double>(object.particleCount) : sum;
}

// Experiment 2: how far each centroid went along x, and the final speeds.
ExperimentProbe wheelCubeProbe(const Scene&) {
  ExperimentProbe probe;
  probe.finish = [](const Scene& scene, const State& last, const RunReport&, ExperimentFigures& f) {
    const ObjectInfo& wheel = scene.model.objects.at(0);
    const ObjectInfo& cube = scene.model.objects.at(1);
    const double wheelDistance =
        centroid(last.position, wheel).x - centroid(scene.initial.position, wheel).x;
    const double cubeDistance =
        centroid(last.position, cube).x - centroid(scene.initial.position, cube).x;
    const double wheelSpeed = norm(centroid(last.velocity, wheel));
    const double cubeSpeed = norm(centroid(last.velocity, cube));
    f.values["wheel_distance_x_m"] = wheelDistance;
    f.values["cube_distance_x_m"] = cubeDistance;
    f.values["wheel_final_speed_m_s"] = wheelSpeed;
    f.values["cube_final_speed_m_s"] = cubeSpeed;
    f.words.push_back(
        fmt::format("wheel {:.3f} m along x, ends at {:.3f} m/s", wheelDistance, wheelSpeed));
    f.words.push_back(
        fmt::format("cube {:.3f} m along x, ends at {:.2e} m/s", cubeDistance, cubeSpeed));
  };
  return probe;
}

// Experiment 1 (flexion): the tip stiffness from the anchor springs' pull (object
// 1 holds the anchors) and the loaded layer's mean deflection, against 3 E I / L³.
ExperimentProbe barProbe(const Scene&) {
  ExperimentProbe probe;
  probe.finish = [](const Scene& scene, const State& last, const RunReport&, ExperimentFigures& f) {
    double load = 0.0, deflection = 0.0;
    int loaded = 0;
    for (const LinearSpring& s : scene.model.linearSprings) {
      if (scene.model.objectOf[static_cast<std::size_t>(s.b)] != 1) continue;
      const Vec3 d = last.position[static_cast<std::size_t>(s.b)] -
                     last.position[static_cast<std::size_t>(s.a)];
      load += -d.z / norm(d) * s.stiffness * (norm(d) - s.restLength);
      deflection += scene.initial.position[static_cast<std::size_t>(s.a)].z -
                    last.position[static_cast<std::size_t>(s.a)].z;
      ++loaded;
    }
    deflection /= std::max(loaded, 1);
    const double h = 0.03, length = 0.15, young = 1e6;
    const double theory = 3.0 * young * (h * h * h * h / 12.0) / (length * length * length);
    f.values["tip_load_n"] = load;
    f.values["tip_deflection_m"] = deflection;
    f.values["stiffness_over_theory"] = load / deflection / theory;
    f.words.push_back(fmt::format("tip stiffness {:.2f} N/m against 3EI/L³ = {:.2f} N/m ({:.4f})",
                                  load / deflection, theory, load / deflection / theory));
    f.words.push_back(
        "traction 1.0003 and torsion 0.9999 of theory in tests/robotics/test_bar_calibration.cpp");
  };
  return probe;
}

// Experiment 3: the chassis (particles 0..11, the 3×2×2 lattice that comes first).
ExperimentProbe vehicleProbe(const Scene&) {
  constexpr ParticleIndex kChassis = 12;
  struct Watch {
    double largestTilt = 0.0;  // rad
    bool chassisTouched = false;
  };
  auto watch = std::make_shared<Watch>();
  ExperimentProbe probe;
  probe.betweenSteps = [watch](World& world, std::vector<std::string>&) {
    const State& s = world.state();
    // The chassis lattice's own vertical (particle 0 → 1) against +z.
    const Vec3 up = s.position[1] - s.position[0];
    watch->largestTilt =
        std::max(watch->largestTilt, std::acos(std::clamp(up.z / norm(up), -1.0, 1.0)));
    for (const Contact& c : world.contacts())
      if (c.withEnvironment() && c.a < kChassis) watch->chassisTouched = true;
    return true;
  };
  probe.finish = [watch](const Scene&, const State& last, const RunReport& report,
                         ExperimentFigures& f) {
    Vec3 chassis;
    for (ParticleIndex i = 0; i < kChassis; ++i)
      chassis += last.position[static_cast<std::size_t>(i)] / static_cast<double>(kChassis);
    const double tiltDegrees = watch->largestTilt * 180.0 / kPi;
    f.values["chassis_final_x_m"] = chassis.x;
    f.values["largest_tilt_deg"] = tiltDegrees;
    f.values["chassis_touched_ground"] = watch->chassisTouched;
    f.words.push_back(fmt::format("chassis ends at x = {:.3f} m", chassis.x));
    f.words.push_back(fmt::format("largest tilt {:.2f}°", tiltDegrees));
    f.words.push_back(watch->chassisTouched ? "chassis touched the ground"
                                            : "chassis never touched the ground");
    addGoalTime(report, f);
  };
  return probe;
}

// Experiment 4: the grasp check's verdict.
ExperimentProbe graspProbe(const Scene&) {
  ExperimentProbe probe;
  probe.finish = [](const Scene&, const State&, const RunReport& report, ExperimentFigures& f) {
    static const std::string kMarker = "largest drift ";
    for (const std::string& e : report.events) {
      const auto at = e.find(kMarker);
      if (at == std::string::npos) continue;
      f.values["grasp_verdict"] = e;
      f.values["grasp_stable"] = e.rfind("grasp stable", 0) == 0;
      f.values["largest_drift_m"] = std::strtod(e.c_str() + at + kMarker.size(), nullptr);
      f.words.push_back(e);
      return;
    }
    f.values["grasp_verdict"] = nullptr;
    f.words.push_back("no grasp verdict");
  };
  return probe;
}

// Experiment 5: local minima met (one virtual obstacle each), and the goal.
ExperimentProbe obstacleProbe(const Scene&) {
  ExperimentProbe probe;
  probe.finish = [](const Scene&, const State&, const RunReport& report, ExperimentFigures& f) {
    std::int64_t minima = 0;
    for (const std::string& e : report.events)
      if (e.find("local minimum") != std::string::npos) ++minima;
    f.values["local_minima"] = minima;
    f.words.push_back(fmt::format("{} local minim{}", minima, minima == 1 ? "um" : "a"));
    addGoalTime(report, f);
  };
  return probe;
}

// §5.1 and experiment 6: the time the goal was reached.
ExperimentProbe goalProbe(const Scene&) {
  ExperimentProbe probe;
  probe.finish = [](const Scene&, const State&, const RunReport& report, ExperimentFigures& f) {
    addGoalTime(report, f);
  };
  return probe;
}

std::string escapeCell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

std::string joined(const std::vector<std::string>& words, const char* separator) {
  std::string out;
  for (const std::string& w : words) {
    if (!out.empty()) out += separator;
    out += w;
  }
  return out;
}

}  // namespace

std::vector<Experiment> paperExperiments() {
  std::vector<Experiment> list;
  list.push_back(
      {"bar_flexion", "1", "calibrated bar in flexion", "scenes/bar_flexion.json", "", barProbe});
  list.push_back(
      {"wheel_cube", "2", "wheel and cube", "scenes/wheel_cube.json", "", wheelCubeProbe});
  list.push_back(
      {"vehicle_hills", "3", "vehicle over hills", "scenes/vehicle_hills.json", "", vehicleProbe});
  list.push_back({"hand_grasp", "4", "hand grasp", "scenes/hand_grasp.json", "", graspProbe});
  list.push_back({"arm_obstacle", "5", "arm around an obstacle", "scenes/arm_obstacle.json", "",
                  obstacleProbe});
  list.push_back(
      {"mobile_line", "6", "mobile robot on a line", "scenes/mobile_line.json", "", goalProbe});
  list.push_back(
      {"mobile_arc", "6", "mobile robot on an arc", "scenes/mobile_arc.json", "", goalProbe});
  list.push_back(
      {"arm_reach", "§5.1", "passive arm reach", "scenes/arm_reach.json", "", goalProbe});
  return list;
}

ExperimentResult runExperiment(const Experiment& experiment, const std::atomic<bool>* stop) {
  ExperimentResult r;
  r.id = experiment.id;
  r.number = experiment.number;
  r.title = experiment.title;
  r.scene = experiment.scene;
  if (experiment.scene.empty()) {
    r.figures.words.push_back(experiment.note);
    return r;
  }
  SceneLoadResult loaded = loadSceneFile(experiment.scene);
  if (!loaded.ok()) {
    r.status = "load error";
    std::vector<std::string> messages;
    for (const Diagnostic& d : loaded.errors) messages.push_back(d.format());
    r.failure = joined(messages, "; ");
    return r;
  }
  const Scene& scene = *loaded.scene;
  ExperimentProbe probe = experiment.probe ? experiment.probe(scene) : ExperimentProbe{};
  RunOptions options;
  options.settings = scene.run;  // as the scene asks; no outDir: nothing written
  options.tasks = {robotics::makeSceneTasks(scene), probe.betweenSteps};
  options.stop = stop;
  State last;
  const RunReport report = runScene(scene, options, &last);
  r.status = report.status;
  r.failure = report.failure;
  r.simulatedSeconds = report.simulatedTime;
  r.wallSeconds = report.wallSeconds;
  r.steps = report.steps;
  r.rejected = report.adaptive.rejected;
  r.energyDrift = report.energyDrift;
  r.externalWork = report.externalWork;
  r.events = report.events;
  if (probe.finish) probe.finish(scene, last, report, r.figures);
  return r;
}

nlohmann::ordered_json toJson(const ExperimentResult& r) {
  nlohmann::ordered_json j;
  j["id"] = r.id;
  j["experiment"] = r.number;
  j["title"] = r.title;
  j["scene"] = r.scene.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.scene);
  j["status"] = r.status;
  if (!r.failure.empty()) j["failure"] = r.failure;
  j["outcome"] = joined(r.figures.words, "; ");
  j["figures"] = r.figures.values;
  if (r.status == "not run") return j;
  j["simulated_s"] = r.simulatedSeconds;
  j["wall_s"] = r.wallSeconds;
  j["real_time_factor"] = r.wallSeconds > 0.0 ? r.simulatedSeconds / r.wallSeconds : 0.0;
  j["accepted_steps"] = r.steps;
  j["rejected_steps"] = r.rejected;
  j["energy_drift"] = r.energyDrift;
  j["external_work_J"] = r.externalWork;
  j["events"] = r.events;
  return j;
}

std::string summaryLine(const ExperimentResult& r) {
  const std::string name = fmt::format("{} {}", r.number, r.title);
  if (r.status == "not run") return fmt::format("{:<28} {}", name, joined(r.figures.words, "; "));
  if (r.status == "load error")
    return fmt::format("{:<28} {}: load error: {}", name, r.scene, r.failure);
  return fmt::format(
      "{:<28} {:<8} {:>7.4g} s in {:>7.3g} s wall (x{:.3g} real time), {} steps ({} rejected), "
      "drift {:.2g}: {}{}",
      name, r.status, r.simulatedSeconds, r.wallSeconds,
      r.wallSeconds > 0.0 ? r.simulatedSeconds / r.wallSeconds : 0.0, r.steps, r.rejected,
      r.energyDrift, joined(r.figures.words, "; "),
      r.failure.empty() ? std::string() : " [" + r.failure + "]");
}

std::string experimentsMarkdown(const nlohmann::ordered_json& record) {
  std::string md = fmt::format(
      "# The paper's experiments, played from their scene files\n\n"
      "Generated by `robophi study experiments` (apps/robophi/study_experiments.cpp) on {},\n"
      "robophi {}; the same data is in bench/results/experiments.json. Each scene file is\n"
      "loaded and run as `robophi run` runs it (its own run settings and robotics tasks),\n"
      "writing nothing; a scene whose goal stops the run when reached ends there, so its\n"
      "simulated time is the time the goal was reached. Everything but the wall times (and\n"
      "the real-time factors) is deterministic. Wall times are single-threaded (the step\n"
      "does not run in parallel, whatever the machine's core count), measured on the\n"
      "machine that ran the command, and move with its load. Steps are accepted steps,\n"
      "with the adaptive step's rejected trials in parentheses.\n\n"
      "| experiment | scene | outcome | simulated s | wall s | × real time | steps (rejected) "
      "|\n|---|---|---|---|---|---|---|\n",
      record.value("date", std::string("?")).substr(0, 10),
      record.value("robophi", std::string("?")));
  for (const auto& e : record["experiments"]) {
    const std::string name =
        fmt::format("{} {}", e["experiment"].get<std::string>(), e["title"].get<std::string>());
    const std::string scene =
        e["scene"].is_string() ? fmt::format("`{}`", e["scene"].get<std::string>()) : "—";
    std::string outcome = e["outcome"].get<std::string>();
    const std::string status = e["status"].get<std::string>();
    if (status != "ok" && status != "not run")
      outcome = fmt::format("**{}**: {}{}{}", status, e.value("failure", std::string()),
                            outcome.empty() ? "" : "; ", outcome);
    if (status == "not run" || status == "load error") {
      md += fmt::format("| {} | {} | {} | — | — | — | — |\n", name, scene, escapeCell(outcome));
      continue;
    }
    md +=
        fmt::format("| {} | {} | {} | {:.4g} | {:.3g} | {:.3g} | {} ({}) |\n", name, scene,
                    escapeCell(outcome), e["simulated_s"].get<double>(), e["wall_s"].get<double>(),
                    e["real_time_factor"].get<double>(), e["accepted_steps"].get<std::int64_t>(),
                    e["rejected_steps"].get<std::int64_t>());
  }
  md +=
      "\n## Energy and events\n\n"
      "Energy drift is the change of E + dissipated − external work over the run, relative\n"
      "to the initial mechanical energy; external work is what the robotics tasks and the\n"
      "moving virtual robots put in (J).\n";
  for (const auto& e : record["experiments"]) {
    if (!e.contains("events")) continue;
    md += fmt::format("\n### {} {} (`{}`)\n\n", e["experiment"].get<std::string>(),
                      e["title"].get<std::string>(), e["scene"].get<std::string>());
    md += fmt::format("- status {}, energy drift {:.3g}, external work {:.4g} J\n",
                      e["status"].get<std::string>(), e["energy_drift"].get<double>(),
                      e["external_work_J"].get<double>());
    for (const auto& event : e["events"]) md += fmt::format("- {}\n", event.get<std::string>());
  }
  return md;
}

}  // namespace robophi::cli
