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

enum class BarLoad { kTraction, kTorsion };

// Experiment 1, traction and torsion, on the bar of the flexion scene: its anchor
// springs (object 1) moved to pull the loaded layer along the axis (0.05 N each)
// or round it (tangential, ∝ r), relaxed to rest (every particle slower than
// 1e-7 m/s at 5 checks 0.01 s apart, at most 2 s of 1e-4 s steps; MODEL §6.1),
// as tests/robotics/test_bar_calibration.cpp measures them. Returns the measured
// stiffness (N/m, or N·m/rad).
double relaxedBarStiffness(const Scene& flexion, BarLoad load) {
  Model model = flexion.model;
  State state = flexion.initial;
  constexpr double kForce = 0.05, kDistance = 1.0;
  std::vector<std::size_t> anchors;
  Vec3 axis;  // the section's centre, on the loaded layer
  for (std::size_t q = 0; q < model.linearSprings.size(); ++q)
    if (model.objectOf[static_cast<std::size_t>(model.linearSprings[q].b)] == 1) {
      anchors.push_back(q);
      axis += state.position[static_cast<std::size_t>(model.linearSprings[q].a)];
    }
  axis = axis / static_cast<double>(anchors.size());
  const double cell = 0.01;
  for (std::size_t q : anchors) {
    LinearSpring& spring = model.linearSprings[q];
    const Vec3 p = state.position[static_cast<std::size_t>(spring.a)];
    const double y = p.y - axis.y, z = p.z - axis.z, r = std::hypot(y, z);
    Vec3 direction{1.0, 0.0, 0.0};
    double force = kForce;
    if (load == BarLoad::kTorsion) {
      direction = r > 1e-9 ? Vec3{0.0, -z / r, y / r} : Vec3{1.0, 0.0, 0.0};
      force = r > 1e-9 ? kForce * r / cell : 0.0;  // a couple: tangential force ∝ r
    }
    state.position[static_cast<std::size_t>(spring.b)] = p + direction * kDistance;
    spring.restLength = kDistance - force / spring.stiffness;
  }
  World world(model, state, Integrator::kSymplecticEuler);
  const auto fastest = [&world] {
    double v = 0.0;
    for (const Vec3& u : world.state().velocity) v = std::max(v, norm(u));
    return v;
  };
  int still = 0;
  for (int steps = 0; steps < 20000 && still < 5; steps += 100) {
    for (int k = 0; k < 100; ++k) world.step(1e-4);
    still = fastest() < 1e-7 ? still + 1 : 0;
  }
  const State& last = world.state();
  double pull = 0.0, torque = 0.0, stretch = 0.0, rotation = 0.0, r2 = 0.0;
  for (std::size_t q : anchors) {
    const LinearSpring& spring = model.linearSprings[q];
    const auto a = static_cast<std::size_t>(spring.a), b = static_cast<std::size_t>(spring.b);
    const Vec3 d = last.position[b] - last.position[a];
    const Vec3 f = d / norm(d) * (spring.stiffness * (norm(d) - spring.restLength));
    const Vec3 p0 = state.position[a] - axis, u = last.position[a] - state.position[a];
    pull += f.x;
    torque += (last.position[a].y - axis.y) * f.z - (last.position[a].z - axis.z) * f.y;
    stretch += u.x / static_cast<double>(anchors.size());
    rotation += p0.y * u.z - p0.z * u.y;
    r2 += p0.y * p0.y + p0.z * p0.z;
  }
  return load == BarLoad::kTraction ? pull / stretch : torque / (rotation / r2);
}

// Experiment 1: flexion from the scene's own run (the tip stiffness from the
// anchor springs' pull, object 1, and the loaded layer's mean deflection, against
// 3 E I / L³); traction and torsion measured on the same bar (relaxedBarStiffness).
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
    // The scene's bar: 16 × 3 × 3 cells of 1 cm, E = 1 MPa, G = 0.4 MPa, clamped
    // at its first layer and loaded at its last, L = 15 cells.
    const double h = 0.03, length = 0.15, young = 1e6, shear = 4e5;
    const double theory = 3.0 * young * (h * h * h * h / 12.0) / (length * length * length);
    f.values["tip_load_n"] = load;
    f.values["tip_deflection_m"] = deflection;
    f.values["stiffness_over_theory"] = load / deflection / theory;
    f.words.push_back(fmt::format("tip stiffness {:.2f} N/m against 3EI/L³ = {:.2f} N/m ({:.4f})",
                                  load / deflection, theory, load / deflection / theory));
    const double traction =
        relaxedBarStiffness(scene, BarLoad::kTraction) / (young * h * h / length);
    const double torsion =
        relaxedBarStiffness(scene, BarLoad::kTorsion) / (shear * 0.1406 * h * h * h * h / length);
    f.values["traction_over_theory"] = traction;
    f.values["torsion_over_theory"] = torsion;
    f.words.push_back(fmt::format(
        "traction {:.4f} and torsion {:.4f} of theory (E·A/L, G·J/L), measured on the same bar",
        traction, torsion));
  };
  return probe;
}

// Experiment 5 (the paper's): the first rebound's apex gives the restitution,
// e = sqrt(rise / drop) for the one particle (the exit depth, microns, neglected),
// the apex from the first step in flight.
ExperimentProbe ballProbe(const Scene&) {
  struct Watch {
    bool touched = false, left = false, done = false;
    double apex = -1.0;
  };
  auto watch = std::make_shared<Watch>();
  ExperimentProbe probe;
  probe.betweenSteps = [watch](World& world, std::vector<std::string>&) {
    const bool touching = !world.contacts().empty();
    const State& s = world.state();
    if (touching && !watch->left) watch->touched = true;
    if (watch->touched && !touching) watch->left = true;
    if (watch->left && !watch->done) {
      // In flight z + v_z²/(2g) is the apex whatever the step: the adaptive step
      // takes long ones in flight, and a sampled height would miss it.
      const double g = std::abs(world.model().gravity.z);
      const double vz = s.velocity[0].z;
      watch->apex = g > 0.0 ? s.position[0].z + vz * vz / (2.0 * g) : s.position[0].z;
      watch->done = true;
    }
    return true;
  };
  probe.finish = [watch](const Scene& scene, const State&, const RunReport&, ExperimentFigures& f) {
    const double r = scene.model.radius[0], drop = scene.initial.position[0].z - r;
    if (!watch->done) {
      f.values["restitution"] = nullptr;
      f.words.push_back("no rebound measured");
      return;
    }
    const double e = std::sqrt((watch->apex - r) / drop);
    f.values["restitution"] = e;
    f.values["rebound_m"] = watch->apex - r;
    f.words.push_back(
        fmt::format("rebound {:.4f} m of {:.3f} m: restitution {:.5f}", watch->apex - r, drop, e));
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
    std::int64_t minima = 0, obstacles = 0;
    double work = 0.0;
    static const std::string kAfter = "after ", kWork = "(work ";
    for (const std::string& e : report.events) {
      if (e.find("': local minimum at") != std::string::npos) ++minima;
      const auto after = e.find(kAfter), at = e.find(kWork);
      if (e.find("out of the local minimum") == std::string::npos || after == std::string::npos ||
          at == std::string::npos)
        continue;
      obstacles += std::strtoll(e.c_str() + after + kAfter.size(), nullptr, 10);
      work += std::strtod(e.c_str() + at + kWork.size(), nullptr);
    }
    f.values["local_minima"] = minima;
    f.values["virtual_obstacles"] = obstacles;
    f.values["escape_work_J"] = work;
    f.words.push_back(fmt::format("{} local minim{}, out after {} virtual obstacles ({:.3g} J)",
                                  minima, minima == 1 ? "um" : "a", obstacles, work));
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
  list.push_back({"wheel_cube_ramp", "2", "wheel and cube on a ramp, from rest",
                  "scenes/wheel_cube_ramp.json", "", wheelCubeProbe});
  list.push_back({"hand_grasp", "4", "hand grasp", "scenes/hand_grasp.json", "", graspProbe});
  list.push_back(
      {"ball_drop", "5", "ball falling on the ground", "scenes/ball_drop.json", "", ballProbe});
  list.push_back({"arm_obstacle", "§5.2", "arm around an obstacle", "scenes/arm_obstacle.json", "",
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
      "robophi {}; the same data is in bench/results/experiments.json. Regenerate both from\n"
      "the checkout's root with `build/robophi study experiments --out docs --record\n"
      "bench/results`: tests/apps/test_experiments_document.cpp runs the study afresh and\n"
      "fails when any line of this page but the date, the version and the wall-time columns\n"
      "differs from it. Each scene file is\n"
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
