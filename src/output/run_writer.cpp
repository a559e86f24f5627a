#include "output/run_writer.h"

#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "output/results_folder.h"
#include "robophi/joints.h"
#include "robophi/version.h"

namespace robophi {

namespace {

std::ofstream openOrThrow(const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
  return out;
}

// Numbers are written in their shortest round-trip form, so a CSV read back
// gives the bits that were simulated.
void appendNumber(std::string& line, double value) {
  fmt::format_to(std::back_inserter(line), "{}", value);
}

}  // namespace

const std::vector<std::string>& runFileNames() {
  static const std::vector<std::string> names = {"summary.json",  "model.json", "energy.csv",
                                                 "particles.csv", "joints.csv", "contacts.csv",
                                                 "replay.html",   "world.json"};
  return names;
}

std::ofstream RunWriter::open(const std::string& name) {
  return openOrThrow(std::filesystem::path(dir_) / name);
}

RunWriter::RunWriter(const std::string& dir, const Scene& scene) : dir_(dir), world_(scene) {
  // The marker first: a folder cut short at any point is still robophi's.
  files_ = {"energy.csv", "particles.csv"};
  if (scene.model.contact.enabled) files_.push_back("contacts.csv");
  if (!scene.model.joints.empty()) files_.push_back("joints.csv");
  std::filesystem::create_directories(dir_);
  output::writeResultsMarker(dir_, "run", files_);
  energy_ = open("energy.csv");
  energy_ << "t,dt,kinetic,potential,dissipated,total\n";
  particles_ = open("particles.csv");
  line_ = "t";
  for (ParticleIndex i = 0; i < scene.model.particleCount(); ++i) {
    fmt::format_to(std::back_inserter(line_), ",x{0},y{0},z{0}", i);
  }
  particles_ << line_ << '\n';
  if (scene.model.contact.enabled) {
    contacts_ = open("contacts.csv");
    contacts_ << "t,a,b,fx,fy,fz\n";
  }
  if (!scene.model.joints.empty()) {
    joints_ = open("joints.csv");
    line_ = "t";
    for (const Joint& joint : scene.model.joints) line_ += "," + joint.name;
    joints_ << line_ << '\n';
  }
}

void RunWriter::writeEnergyRow(const World& world, double dt) {
  line_.clear();
  const State& state = world.state();
  const EnergyTally e = world.energy();
  for (double value : {state.time, dt, e.kinetic, e.potential(), e.dissipated, e.total()}) {
    if (!line_.empty()) line_ += ',';
    appendNumber(line_, value);
  }
  energy_ << line_ << '\n';
}

void RunWriter::writeFrame(const World& world) {
  const Model& model = world.model();
  const State& state = world.state();
  world_.observe(world);  // virtual obstacles appear during the run
  line_.clear();
  appendNumber(line_, state.time);
  for (const Vec3& p : state.position) {
    for (double value : {p.x, p.y, p.z}) {
      line_ += ',';
      appendNumber(line_, value);
    }
  }
  particles_ << line_ << '\n';
  if (contacts_.is_open()) {
    // The normal force on a (N); b is the other particle, or particleCount + the
    // environment item.
    for (const Contact& c : world.contacts()) {
      if (c.normalForce <= 0.0) continue;
      line_.clear();
      appendNumber(line_, state.time);
      const std::int64_t b =
          c.withEnvironment()
              ? static_cast<std::int64_t>(model.particleCount()) + c.environmentItem()
              : c.other;
      fmt::format_to(std::back_inserter(line_), ",{},{}", c.a, b);
      const Vec3 f = c.normal * c.normalForce;
      for (double value : {f.x, f.y, f.z}) {
        line_ += ',';
        appendNumber(line_, value);
      }
      contacts_ << line_ << '\n';
    }
  }
  if (joints_.is_open()) {
    line_.clear();
    appendNumber(line_, state.time);
    for (std::size_t j = 0; j < model.joints.size(); ++j) {
      line_ += ',';
      appendNumber(line_, jointValue(model, state, j));
    }
    joints_ << line_ << '\n';
  }
}

std::string modelJson(const Scene& scene) {
  const Model& model = scene.model;
  nlohmann::ordered_json j;
  j["name"] = scene.name;
  std::vector<int> fixed;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i)
    fixed.push_back(model.isFixed(i) ? 1 : 0);
  j["particles"] = {{"count", model.particleCount()},
                    {"mass", model.mass},
                    {"radius", model.radius},
                    {"object", model.objectOf},
                    {"fixed", fixed}};
  auto objects = nlohmann::ordered_json::array();
  for (const ObjectInfo& o : model.objects) {
    objects.push_back({{"name", o.name},
                       {"kind", o.kind},
                       {"first", o.firstParticle},
                       {"count", o.particleCount},
                       {"material", o.material}});
  }
  j["objects"] = objects;
  auto linear = nlohmann::ordered_json::array(), torsion = nlohmann::ordered_json::array(),
       joint = nlohmann::ordered_json::array();
  for (const auto& s : model.linearSprings) linear.push_back({s.a, s.b, s.restLength});
  for (const auto& s : model.torsionSprings) torsion.push_back({s.a, s.c, s.b, s.restAngle});
  for (const auto& s : model.jointSprings) joint.push_back({s.a, s.c, s.b, s.d, s.restAngle});
  j["connectors"] = {{"linear", linear}, {"torsion", torsion}, {"joint", joint}};
  auto joints = nlohmann::ordered_json::array();
  for (const Joint& jt : model.joints) {
    joints.push_back(
        {{"name", jt.name}, {"kind", jt.kind == JointKind::kRevolute ? "revolute" : "prismatic"}});
  }
  j["joints"] = joints;
  j["gravity"] = {model.gravity.x, model.gravity.y, model.gravity.z};
  return j.dump(1);
}

void RunWriter::finish(const Scene& scene, const RunSettings& settings, const RunReport& report) {
  energy_.close();
  particles_.close();
  if (joints_.is_open()) joints_.close();
  if (contacts_.is_open()) contacts_.close();
  files_.insert(files_.end(), {"model.json", "world.json", "summary.json"});
  output::writeResultsMarker(dir_, "run", files_);
  world_.write(dir_);
  {
    auto out = open("model.json");
    out << modelJson(scene) << '\n';
  }
  nlohmann::ordered_json s;
  s["robophi"] = kVersion;
  s["scene"] = scene.sourcePath;
  s["name"] = scene.name;
  s["status"] = report.status;
  if (!report.failure.empty()) s["failure"] = report.failure;
  s["integrator"] = integratorName(settings.integrator);
  const bool adaptive = settings.stepMode == StepMode::kAdaptive;
  s["step_mode"] = adaptive ? "adaptive" : "constant";
  s["steps"] = report.steps;
  if (adaptive) {
    const AdaptiveStepStats& a = report.adaptive;
    s["adaptive"] = {{"accepted_steps", a.accepted},
                     {"rejected_steps", a.rejected},
                     {"smallest_dt_s", a.accepted > 0 ? a.smallestStep : 0.0},
                     {"largest_dt_s", a.largestStep},
                     {"mean_dt_s", a.meanStep()},
                     {"final_energy_error", a.lastEnergyError},
                     // the settings in use (scene run.adaptive, command line)
                     {"energy_tolerance", settings.adaptive.energyTolerance},
                     {"min_step_s", settings.adaptive.minStep},
                     {"max_step_s", settings.adaptive.maxStep},
                     {"max_penetration_fraction", settings.adaptive.maxPenetrationFraction}};
  }
  s["duration_s"] = settings.duration;  // asked for; simulated_time_s is how far it got
  s["simulated_time_s"] = report.simulatedTime;
  s["wall_time_s"] = report.wallSeconds;
  s["dt_s"] = settings.dt;  // the constant step, or the first trial step
  s["critical_dt_s"] = report.stability.criticalStep;
  s["omega_max_rad_s"] = report.stability.omegaMax;
  s["particles"] = scene.model.particleCount();
  s["linear_springs"] = scene.model.linearSprings.size();
  s["torsion_springs"] = scene.model.torsionSprings.size();
  s["joint_springs"] = scene.model.jointSprings.size();
  s["energy"] = {{"initial_total_J", report.initialTotal},
                 {"final_total_J", report.finalTotal},
                 {"drift", report.energyDrift},
                 {"dissipated_J", report.dissipated},
                 {"external_work_J", report.externalWork}};
  s["state_hash"] = fmt::format("{:016x}", report.stateHash);
  s["warnings"] = report.warnings;
  if (!report.events.empty()) s["events"] = report.events;
  auto out = open("summary.json");
  out << s.dump(2) << '\n';
}

}  // namespace robophi
