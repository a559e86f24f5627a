#include "output/run_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "output/json_numbers.h"
#include "output/results_folder.h"
#include "output/run_reader.h"
#include "robophi/connector_forces.h"
#include "robophi/joints.h"
#include "robophi/version.h"

namespace robophi {

namespace {

std::ofstream openOrThrow(const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw output::WriteError(fmt::format("cannot write {}", path.string()));
  return out;
}

}  // namespace

// Numbers are written in their shortest round-trip form, so a CSV read back
// gives the bits that were simulated.
void RunWriter::add(double value) { output::appendShortest(line_, value); }

void RunWriter::gather(ReplaySeries& series, const double* row) {
  const std::size_t width = series.columns.size();
  if (!reserveReplay(width * sizeof(double))) return;
  series.values.insert(series.values.end(), row, row + width);
}

bool RunWriter::reserveReplay(std::size_t bytes) {
  // Rows past the memory bound leave the page to the files.
  if (replay_->bytes + bytes > kReplayGatherBytes) {
    replay_.reset();
    return false;
  }
  replay_->bytes += bytes;
  return true;
}

const std::vector<std::string>& runFileNames() {
  static const std::vector<std::string> names = {
      "summary.json", "model.json",      "energy.csv",   "particles.csv",
      "objects.csv",  "joints.csv",      "contacts.csv", "sensors.csv",
      "replay.html",  "checkpoint.json", "world.json",   "trajectory.json"};
  return names;
}

std::ofstream RunWriter::open(const std::string& name, bool append) {
  const std::filesystem::path path = std::filesystem::path(dir_) / name;
  if (!append) return openOrThrow(path);
  std::ofstream out(path, std::ios::binary | std::ios::app);
  if (!out) throw output::WriteError(fmt::format("cannot append to {}", path.string()));
  return out;
}

namespace {

// The series files a run of `scene` writes, in the marker's order.
std::vector<std::string> seriesFiles(const Scene& scene) {
  std::vector<std::string> files = {"energy.csv", "particles.csv", "objects.csv"};
  if (scene.model.contact.enabled) files.push_back("contacts.csv");
  if (!scene.model.joints.empty()) files.push_back("joints.csv");
  if (!scene.sensors.empty()) files.push_back("sensors.csv");
  return files;
}

// trajectory.json (docs/output-format.md): joints.csv's positions and rates as a
// joint trajectory a robot can replay (the scene's control "replay" reads it back).
nlohmann::json jointTrajectoryJson(const Scene& scene, const std::string& jointsCsv) {
  output::CsvTable table;
  std::string error;
  if (!output::readCsvTable(jointsCsv, {"t"}, table, error)) throw output::WriteError(error);
  nlohmann::json names = nlohmann::json::array();
  std::vector<std::size_t> qColumn, rateColumn;
  for (const Joint& joint : scene.model.joints) {
    names.push_back(joint.name);
    qColumn.push_back(table.columnIndex(joint.name + ":q"));
    rateColumn.push_back(table.columnIndex(joint.name + ":rate"));
    if (qColumn.back() == table.columns.size() || rateColumn.back() == table.columns.size())
      throw output::WriteError(
          fmt::format("{}: no columns {}:q and {}:rate", jointsCsv, joint.name, joint.name));
  }
  nlohmann::json time = nlohmann::json::array(), position = nlohmann::json::array(),
                 velocity = nlohmann::json::array();
  for (std::size_t row = 0; row < table.rowCount; ++row) {
    time.push_back(table.at(row, 0));
    nlohmann::json q = nlohmann::json::array(), rate = nlohmann::json::array();
    for (std::size_t j = 0; j < qColumn.size(); ++j) {
      q.push_back(table.at(row, qColumn[j]));
      rate.push_back(table.at(row, rateColumn[j]));
    }
    position.push_back(std::move(q));
    velocity.push_back(std::move(rate));
  }
  return {{"format", "robophi joint trajectory"},
          {"version", 1},
          {"units", {{"time", "s"}, {"position", "rad or m"}, {"velocity", "rad/s or m/s"}}},
          {"joints", names},
          {"time", time},
          {"position", position},
          {"velocity", velocity}};
}

}  // namespace

RunWriter::RunWriter(const std::string& dir, const Scene& scene, const ReplayOptions* replay,
                     bool ownThread)
    : dir_(dir), world_(scene) {
  // The marker first: a folder cut short at any point is still robophi's (the
  // page as it is written too, until it is ended: writeReplayHtml).
  files_ = seriesFiles(scene);
  if (replay != nullptr) {
    replay_.emplace();
    page_ = std::make_unique<ReplayPageStream>(dir_, replay->sizeCapBytes);
    files_.push_back(kReplayPagePartial);
  }
  std::filesystem::create_directories(dir_);
  output::writeResultsMarker(dir_, "run", files_);
  energy_ = open("energy.csv");
  const char* energyHeader = "t,dt,kinetic,potential,dissipated,external,total";
  energy_ << energyHeader << '\n';
  if (replay_) replay_->energy.columns = output::csvHeaderColumns(energyHeader);
  particles_ = open("particles.csv");
  line_ = "t";
  for (ParticleIndex i = 0; i < scene.model.particleCount(); ++i) {
    fmt::format_to(std::back_inserter(line_), ",x{0},y{0},z{0},vx{0},vy{0},vz{0}", i);
  }
  particles_ << line_ << '\n';
  objects_ = open("objects.csv");
  objects_ << "t,object,mass,kinetic,gravity,elastic,x,y,z,vx,vy,vz\n";
  if (scene.model.contact.enabled) {
    contacts_ = open("contacts.csv");
    const char* contactsHeader = "t,a,b,fx,fy,fz,tx,ty,tz,sliding,fn,ft";
    contacts_ << contactsHeader << '\n';
    if (replay_) {
      replay_->hasContacts = true;
      replay_->contacts.columns = output::csvHeaderColumns(contactsHeader);
    }
  }
  if (!scene.model.joints.empty()) {
    joints_ = open("joints.csv");
    line_ = "t";
    for (const Joint& joint : scene.model.joints) line_ += "," + joint.name;
    for (const Joint& joint : scene.model.joints)
      fmt::format_to(std::back_inserter(line_), ",{0}:q,{0}:rate,{0}:effort", joint.name);
    joints_ << line_ << '\n';
    if (replay_) {
      replay_->hasJoints = true;
      replay_->joints.columns = output::csvHeaderColumns(line_);
    }
  }
  if (!scene.sensors.empty()) {
    sensors_ = open("sensors.csv");
    line_ = "t";
    for (const SensorSpec& spec : scene.sensors)
      for (const char* value : SensorSet::valueNames(spec.kind))
        fmt::format_to(std::back_inserter(line_), ",{}:{}", spec.name, value);
    sensors_ << line_ << '\n';
  }
  start(scene, ownThread);
}

RunWriter::RunWriter(const std::string& dir, const Scene& scene,
                     const std::map<std::string, std::uintmax_t>& progress, bool ownThread)
    : dir_(dir), world_(scene) {
  files_ = seriesFiles(scene);
  if (std::filesystem::exists(std::filesystem::path(dir_) / "checkpoint.json"))
    files_.push_back("checkpoint.json");
  output::writeResultsMarker(dir_, "run", files_);
  for (const std::string& name : seriesFiles(scene)) {
    const std::filesystem::path path = std::filesystem::path(dir_) / name;
    const auto it = progress.find(name);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (it == progress.end() || ec || size < it->second) {
      throw std::runtime_error(fmt::format(
          "{}: {} than the checkpoint says ({} bytes): the run folder does not go with its "
          "checkpoint",
          path.string(), ec ? "missing, or not readable" : "shorter",
          it == progress.end() ? 0 : it->second));
    }
    std::filesystem::resize_file(path, it->second);
  }
  energy_ = open("energy.csv", true);
  particles_ = open("particles.csv", true);
  objects_ = open("objects.csv", true);
  if (scene.model.contact.enabled) contacts_ = open("contacts.csv", true);
  if (!scene.model.joints.empty()) joints_ = open("joints.csv", true);
  if (!scene.sensors.empty()) sensors_ = open("sensors.csv", true);
  start(scene, ownThread);
}

RunWriter::~RunWriter() {
  try {
    drain();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a writer given up on (an error elsewhere)
  }
  stop();
}

void RunWriter::start(const Scene& scene, bool ownThread) {
  particleCount_ = static_cast<std::size_t>(scene.model.particleCount());
  jointCount_ = scene.model.joints.size();
  // The sensors as the scene loader resolved them (against its model and initial state).
  for (const SensorSpec& spec : scene.sensors) sensorSet_.add(scene.model, scene.initial, spec);
  // A second core formats while the run steps; one core formats at each hand-over.
  if (ownThread && std::thread::hardware_concurrency() > 1)
    thread_ = std::thread([this] { writeLoop(); });
}

void RunWriter::writeLoop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return handed_ || stopped_; });
    if (!handed_) return;  // stopped with nothing left
    lock.unlock();
    try {
      writeBatch(writing_);
    } catch (...) {
      lock.lock();
      failure_ = std::current_exception();
      lock.unlock();
    }
    lock.lock();
    handed_ = false;
    changed_.notify_all();
  }
}

void RunWriter::handOver() {
  if (taken_.kinds.empty()) return;
  if (thread_.joinable()) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !handed_; });
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
    std::swap(writing_, taken_);  // taken_ now holds the batch written last
    handed_ = true;
    changed_.notify_all();
  } else {
    writeBatch(taken_);
  }
  taken_.kinds.clear();
  taken_.values.clear();
}

void RunWriter::drain() {
  handOver();
  if (!thread_.joinable()) return;
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return !handed_; });
  if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
}

void RunWriter::stop() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void RunWriter::checkWritten(const std::ofstream& out, const std::string& name) const {
  // The stream's state is sticky: one failed write (a full disk) fails it for good.
  if (!out) {
    throw output::WriteError(fmt::format("{}: cannot write ({})",
                                         (std::filesystem::path(dir_) / name).string(),
                                         std::strerror(errno)));
  }
}

void RunWriter::checkStreams() const {
  checkWritten(energy_, "energy.csv");
  checkWritten(particles_, "particles.csv");
  checkWritten(objects_, "objects.csv");
  if (contacts_.is_open()) checkWritten(contacts_, "contacts.csv");
  if (joints_.is_open()) checkWritten(joints_, "joints.csv");
  if (sensors_.is_open()) checkWritten(sensors_, "sensors.csv");
}

std::map<std::string, std::uintmax_t> RunWriter::progress() {
  drain();
  std::map<std::string, std::uintmax_t> sizes;
  auto length = [&](const char* name, std::ofstream& out) {
    if (!out.is_open()) return;
    out.flush();
    checkWritten(out, name);
    sizes[name] = static_cast<std::uintmax_t>(out.tellp());
  };
  length("energy.csv", energy_);
  length("particles.csv", particles_);
  length("objects.csv", objects_);
  length("contacts.csv", contacts_);
  length("joints.csv", joints_);
  length("sensors.csv", sensors_);
  return sizes;
}

void RunWriter::writeCheckpoint(const nlohmann::json& checkpoint) {
  // Listed before it is written: a kill in between leaves a folder wholly robophi's.
  if (std::find(files_.begin(), files_.end(), "checkpoint.json") == files_.end()) {
    files_.push_back("checkpoint.json");
    output::writeResultsMarker(dir_, "run", files_);
  }
  output::writeFileAtomically(std::filesystem::path(dir_) / "checkpoint.json",
                              [&](std::ostream& out) { out << checkpoint.dump() << '\n'; });
}

// How many rows are taken before they are handed to the writer thread.
constexpr std::size_t kBatchValues = std::size_t{1} << 15;

void RunWriter::writeEnergyRow(const World& world, double dt) {
  const State& state = world.state();
  const EnergyTally e = world.energy();
  taken_.kinds.push_back(RowKind::kEnergy);
  taken_.values.insert(taken_.values.end(), {state.time, dt, e.kinetic, e.potential(), e.dissipated,
                                             e.external, e.total()});
  if (taken_.values.size() >= kBatchValues) handOver();
}

void RunWriter::writeFrame(const World& world) {
  const Model& model = world.model();
  const State& state = world.state();
  world_.observe(world);  // virtual obstacles appear during the run
  std::vector<double>& values = taken_.values;
  taken_.kinds.push_back(RowKind::kFrame);
  values.push_back(state.time);
  for (std::size_t i = 0; i < state.position.size(); ++i) {
    const Vec3& p = state.position[i];
    const Vec3& v = state.velocity[i];
    values.insert(values.end(), {p.x, p.y, p.z, v.x, v.y, v.z});
  }
  takeObjects(world);
  if (contacts_.is_open()) {
    // The normal and the friction force on a (N); b is the other particle, or
    // particleCount + the environment item.
    for (const Contact& c : world.contacts()) {
      if (c.normalForce <= 0.0) continue;
      const std::int64_t b =
          c.withEnvironment()
              ? static_cast<std::int64_t>(model.particleCount()) + c.environmentItem()
              : c.other;
      const Vec3 f = c.normal * c.normalForce;
      taken_.kinds.push_back(RowKind::kContact);
      // (Indices and the regime as doubles: exact, far below 2^53.)
      values.insert(values.end(),
                    {state.time, static_cast<double>(c.a), static_cast<double>(b), f.x, f.y, f.z,
                     c.frictionForce.x, c.frictionForce.y, c.frictionForce.z,
                     static_cast<double>(c.sliding), c.normalForce, norm(c.frictionForce)});
    }
  }
  if (joints_.is_open()) {
    taken_.kinds.push_back(RowKind::kJoints);
    values.push_back(state.time);
    for (std::size_t j = 0; j < model.joints.size(); ++j)
      values.push_back(jointValue(model, state, j));
    // Per joint: q (rad or m), its rate, and the effort applied to it: servo (a
    // limit's included) + motor + losses (MODEL §1.5, §1.6).
    const Evaluation& e = world.evaluation();
    for (std::size_t j = 0; j < model.joints.size(); ++j) {
      const double drive = (j < e.jointMotorEffort.size() ? e.jointMotorEffort[j] : 0.0) +
                           (j < e.jointLossEffort.size() ? e.jointLossEffort[j] : 0.0);
      values.insert(values.end(), {jointPosition(model, state, j), jointRate(model, state, j),
                                   jointServoEffort(model, state, j) + drive});
    }
  }
  if (sensors_.is_open()) {
    // Every sensor at the state (robophi/sensors.h): observers, the state unchanged.
    taken_.kinds.push_back(RowKind::kSensors);
    values.push_back(state.time);
    const std::size_t at = values.size();
    values.resize(at + sensorSet_.valueCount());
    sensorSet_.read(world, values.data() + at);
  }
  if (values.size() >= kBatchValues) handOver();
}

void RunWriter::writeBatch(const Batch& batch) {
  const double* v = batch.values.data();
  // line_ from `count` numbers at v (comma-separated), v moved past them.
  const auto numbers = [&](std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) {
      if (k > 0) line_ += ',';
      add(*v++);
    }
  };
  const auto index = [&] { return static_cast<std::int64_t>(*v++); };
  for (const RowKind kind : batch.kinds) {
    line_.clear();
    const double* row = v;
    switch (kind) {
      case RowKind::kEnergy:
        numbers(7);
        energy_ << line_ << '\n';
        if (replay_) gather(replay_->energy, row);
        break;
      case RowKind::kFrame: {
        add(*v++);
        if (particleCount_ > 0) {
          line_ += ',';
          numbers(6 * particleCount_);
        }
        particles_ << line_ << '\n';
        // The page's frame: t and the positions, in single precision.
        if (replay_ && reserveReplay(sizeof(double) + 3 * particleCount_ * sizeof(float))) {
          replay_->frameTime.push_back(row[0]);
          for (std::size_t i = 0; i < particleCount_; ++i) {
            for (std::size_t d = 1; d <= 3; ++d)
              replay_->framePosition.push_back(static_cast<float>(row[6 * i + d]));
          }
        }
        break;
      }
      case RowKind::kObjects: {
        add(*v++);
        fmt::format_to(std::back_inserter(line_), ",{},", index());
        numbers(10);
        objects_ << line_ << '\n';
        break;
      }
      case RowKind::kContact: {
        add(*v++);
        const std::int64_t a = index(), b = index();
        fmt::format_to(std::back_inserter(line_), ",{},{},", a, b);
        numbers(6);
        fmt::format_to(std::back_inserter(line_), ",{},", index());
        numbers(2);
        contacts_ << line_ << '\n';
        if (replay_) gather(replay_->contacts, row);
        break;
      }
      case RowKind::kJoints:
        numbers(1 + 4 * jointCount_);
        joints_ << line_ << '\n';
        if (replay_) gather(replay_->joints, row);
        break;
      case RowKind::kSensors:
        numbers(1 + sensorSet_.valueCount());
        sensors_ << line_ << '\n';
        break;
    }
  }
  checkStreams();
  // The page's pieces whose rows are all here (none once the rows are dropped).
  if (page_) {
    if (replay_) {
      page_->write(*replay_, particleCount_);
    } else {
      page_.reset();
    }
  }
}

// objects.csv: per object its mass, kinetic energy, gravity potential and the
// elastic energy of the connectors wholly inside it (J), centre of mass (m) and
// its velocity (m/s); then a row for object -1: the connectors between objects
// and the contacts (their potential and the friction anchors). The rows of a
// frame sum to energy.csv's kinetic + potential at that state.
void RunWriter::takeObjects(const World& world) {
  const Model& model = world.model();
  const State& state = world.state();
  const auto objectCount = model.objects.size();
  struct Sums {
    double mass = 0.0, kinetic = 0.0, gravity = 0.0, elastic = 0.0;
    Vec3 momentum, moment;
  };
  std::vector<Sums> sums(objectCount + 1);  // the last: between objects
  auto of = [&](ParticleIndex i) -> Sums& {
    const auto o = model.objectOf[static_cast<std::size_t>(i)];
    return o >= 0 && static_cast<std::size_t>(o) < objectCount ? sums[static_cast<std::size_t>(o)]
                                                               : sums[objectCount];
  };
  const auto& p = state.position;
  const auto& v = state.velocity;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    Sums& s = of(i);
    const double m = model.mass[i];
    s.mass += m;
    s.moment += p[i] * m;
    s.momentum += v[i] * m;
    // MODEL §2: the energy account counts free particles only (as gravity.cpp).
    if (model.isFixed(i)) continue;
    s.kinetic += 0.5 * m * squaredNorm(v[i]);
    s.gravity -= m * dot(model.gravity, p[i]);
  }
  auto owner = [&](std::initializer_list<ParticleIndex> ends) -> Sums& {
    const auto o = model.objectOf[static_cast<std::size_t>(*ends.begin())];
    for (ParticleIndex e : ends)
      if (model.objectOf[static_cast<std::size_t>(e)] != o) return sums[objectCount];
    return of(*ends.begin());
  };
  for (const LinearSpring& c : model.linearSprings)
    owner({c.a, c.b}).elastic += linearSpringForce(c, p[c.a], p[c.b], v[c.a], v[c.b]).energy;
  for (const TorsionSpring& c : model.torsionSprings) {
    owner({c.a, c.c, c.b}).elastic +=
        torsionSpringForce(c, p[c.a], p[c.c], p[c.b], v[c.a], v[c.c], v[c.b]).energy;
  }
  for (const JointSpring& c : model.jointSprings) {
    owner({c.a, c.c, c.b, c.d}).elastic +=
        jointSpringForce(c, p[c.a], p[c.c], p[c.b], p[c.d], v[c.a], v[c.c], v[c.b], v[c.d]).energy;
  }
  sums[objectCount].elastic += world.energy().contact;
  for (std::size_t o = 0; o <= objectCount; ++o) {
    const Sums& s = sums[o];
    const Vec3 com = s.mass > 0.0 ? s.moment / s.mass : Vec3{};
    const Vec3 vcom = s.mass > 0.0 ? s.momentum / s.mass : Vec3{};
    taken_.kinds.push_back(RowKind::kObjects);
    taken_.values.insert(
        taken_.values.end(),
        {state.time, o == objectCount ? -1.0 : static_cast<double>(o), s.mass, s.kinetic, s.gravity,
         s.elastic, com.x, com.y, com.z, vcom.x, vcom.y, vcom.z});
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

namespace {

// What set each accepted step's size, by cause (kStepCauses).
nlohmann::json stepCauseCounts(const AdaptiveStepStats& a) {
  nlohmann::json counts = nlohmann::json::object();
  for (const StepCause& cause : kStepCauses) counts[cause.key] = a.*cause.count;
  return counts;
}

}  // namespace

std::string summaryJson(const Scene& scene, const RunSettings& settings, const RunReport& report) {
  nlohmann::ordered_json s;
  s["robophi"] = kVersion;
  s["scene"] = scene.sourcePath;
  s["name"] = scene.name;
  s["status"] = report.status;
  if (!report.failure.empty()) s["failure"] = report.failure;
  if (report.failurePlace) {
    const FailurePlace& at = *report.failurePlace;
    s["failure_at"] = {
        {"time_s", at.time},
        {"step", at.step},
        {"particle", at.particle == kNoParticle ? nlohmann::ordered_json()
                                                : nlohmann::ordered_json(at.particle)},
        {"object",
         at.object.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(at.object)}};
  }
  s["flags"] = {{"diverged", report.status == "diverged"},
                {"stalled", report.status == "stalled"},
                {"interrupted", report.interrupted()},
                {"energy_account_broken", report.largestAccountError > report.accountBound},
                {"goal_not_reached", !report.goalsNotReached.empty()}};
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
                     // what set each accepted step's size
                     {"steps_set_by", stepCauseCounts(a)},
                     // the settings in use (scene run.adaptive, command line; the
                     // floor as applied: minStep 0 is relative to the first step)
                     {"energy_tolerance", settings.adaptive.energyTolerance},
                     {"min_step_s", report.adaptiveFloor},
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
                 {"largest_account_error", report.largestAccountError},
                 {"account_bound", report.accountBound},
                 {"scale_J", report.energyScale},
                 {"dissipated_J", report.dissipated},
                 {"implicit_loss_J", report.implicitLoss},
                 {"external_work_J", report.externalWork}};
  s["outcomes"] = report.outcomes;
  if (!report.goalsNotReached.empty()) s["goals_not_reached"] = report.goalsNotReached;
  if (report.checkpoints > 0 || report.resumedFrom >= 0.0) {
    s["checkpoint"] = {
        {"written", report.checkpoints},
        {"last_time_s", report.checkpoints > 0 ? nlohmann::ordered_json(report.lastCheckpointTime)
                                               : nlohmann::ordered_json()},
        {"resumed_from_s", report.resumedFrom >= 0.0 ? nlohmann::ordered_json(report.resumedFrom)
                                                     : nlohmann::ordered_json()}};
  }
  s["state_hash"] = fmt::format("{:016x}", report.stateHash);
  s["warnings"] = report.warnings;
  if (!report.events.empty()) s["events"] = report.events;
  // JSON has no NaN or infinity (a diverged run has them): null, and where.
  std::vector<std::string> nonFinite;
  output::nullNonFinite(s, nonFinite);
  if (!nonFinite.empty()) s["non_finite"] = nonFinite;
  return s.dump(2);
}

void RunWriter::finish(const Scene& scene, const RunSettings& settings, const RunReport& report) {
  drain();
  stop();
  // Each file checked once closed (its last bytes written): a full disk fails the run.
  const auto closeChecked = [&](std::ofstream& out, const char* name) {
    if (!out.is_open()) return;
    out.close();
    checkWritten(out, name);
  };
  closeChecked(energy_, "energy.csv");
  closeChecked(particles_, "particles.csv");
  closeChecked(objects_, "objects.csv");
  closeChecked(joints_, "joints.csv");
  closeChecked(contacts_, "contacts.csv");
  closeChecked(sensors_, "sensors.csv");
  files_.insert(files_.end(), {"model.json", "world.json", "summary.json"});
  if (!scene.model.joints.empty()) files_.push_back("trajectory.json");
  output::writeResultsMarker(dir_, "run", files_);
  world_.write(dir_);
  {
    auto out = open("model.json");
    out << modelJson(scene) << '\n';
    closeChecked(out, "model.json");
  }
  if (!scene.model.joints.empty()) {
    const std::string joints = (std::filesystem::path(dir_) / "joints.csv").string();
    auto trajectory = open("trajectory.json");
    trajectory << jointTrajectoryJson(scene, joints).dump() << '\n';
    closeChecked(trajectory, "trajectory.json");
  }
  auto out = open("summary.json");
  out << summaryJson(scene, settings, report) << '\n';
  closeChecked(out, "summary.json");
}

}  // namespace robophi
