// The live view: the replay page served on localhost, fed frame by frame
// (docs/viewer.md "Live view", where the protocol is described).
#include "run/live_view.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "output/replay.h"
#include "output/results_folder.h"
#include "output/run_writer.h"
#include "output/world_view.h"

namespace robophi {

namespace {

namespace fs = std::filesystem;

// The frame message's header: eight little-endian doubles before the positions.
constexpr std::size_t kFrameHeaderNumbers = 8;

// The replay page of `scene` with `state` as its one frame and the live flag
// set, made by the replay's own writer in a private temporary folder.
std::string livePage(const Scene& scene, const State& state) {
  static std::atomic<int> counter{0};
  const fs::path dir = fs::temp_directory_path() /
                       fmt::format("robophi-live-{}-{}", ::getpid(), counter.fetch_add(1));
  fs::remove_all(dir);
  fs::create_directories(dir);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  output::writeResultsMarker(dir, "run", {"model.json", "world.json"});
  {
    std::ofstream out(dir / "model.json");
    out << modelJson(scene) << '\n';
  }
  output::WorldView(scene).write(dir.string());
  ReplayRows rows;
  rows.frameTime = {state.time};
  for (const Vec3& p : state.position) {
    rows.framePosition.insert(rows.framePosition.end(), {static_cast<float>(p.x),
                                                         static_cast<float>(p.y),
                                                         static_cast<float>(p.z)});
  }
  rows.energy.columns = {"t", "dt", "kinetic", "potential", "dissipated", "external", "total"};
  rows.energy.values = {state.time, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  ReplayOptions options;
  options.outputPath = (dir / "live.html").string();
  options.live = true;
  std::string error;
  if (!writeReplayHtml(dir.string(), options, rows, nullptr, error))
    throw std::runtime_error("the live view's page: " + error);
  std::ifstream in(options.outputPath, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A number from a viewer's message, or `fallback` when absent or not finite.
double numberIn(const nlohmann::json& message, const char* key, double fallback) {
  const auto it = message.find(key);
  if (it == message.end() || !it->is_number()) return fallback;
  const double value = it->get<double>();
  return std::isfinite(value) ? value : fallback;
}

}  // namespace

LiveView::LiveView(const Scene& scene, const State& state, const LiveViewSettings& settings,
                   const std::atomic<bool>* stop)
    : settings_(settings), stop_(stop), speed_(settings.speed) {
  server_ = std::make_unique<output::LiveServer>(livePage(scene, state), settings.port);
  objectMass_.assign(scene.model.objects.size(), 0.0);
  for (std::size_t i = 0; i < scene.model.mass.size(); ++i) {
    const auto o = static_cast<std::size_t>(scene.model.objectOf[i]);
    if (o < objectMass_.size()) objectMass_[o] += scene.model.mass[i];
  }
  lastTime_ = state.time;
}

LiveView::~LiveView() = default;

std::string LiveView::url() const { return server_->url(); }

bool LiveView::waitForViewer() {
  const auto until =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(std::max(settings_.waitSeconds, 0.0)));
  while (server_->viewers() == 0 && Clock::now() < until) {
    if (stop_ && stop_->load(std::memory_order_relaxed)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return server_->viewers() > 0;
}

void LiveView::start(World& world, std::vector<std::string>& events) {
  (void)events;
  waitForViewer();
  lastTime_ = world.state().time;
  sendStatus(world);
  sendFrame(world);
  anchor(world);
}

bool LiveView::step(World& world, std::vector<std::string>& events) {
  (void)events;
  return afterStep(world);
}

nlohmann::json LiveView::outcomes(const World& world) const {
  (void)world;
  return {{"live",
           {{"dragWork", dragWork_},
            {"drags", drags_},
            {"frames", frames_},
            {"viewers", server_->connections()}}}};
}

void LiveView::anchor(const World& world) {
  anchorWall_ = Clock::now();
  anchorTime_ = world.state().time;
}

void LiveView::handleMessages(const World& world) {
  const std::vector<std::string> messages = server_->takeMessages();
  if (messages.empty()) return;
  for (const std::string& text : messages) {
    const nlohmann::json message = nlohmann::json::parse(text, nullptr, false);
    if (!message.is_object()) continue;  // (not ours: ignored)
    const std::string type = message.value("type", "");
    if (type == "pause") {
      paused_ = true;
    } else if (type == "resume") {
      paused_ = false;
      anchor(world);
    } else if (type == "speed") {
      const double speed = numberIn(message, "value", speed_);
      if (speed >= 0.0) speed_ = speed;
      anchor(world);
    } else if (type == "stop") {
      endRequested_ = true;
      paused_ = false;
    } else if (type == "drag") {
      const double particle = numberIn(message, "particle", -1.0);
      const auto target = message.find("target");
      const auto count = static_cast<double>(world.model().particleCount());
      if (particle >= 0.0 && particle < count && target != message.end() &&
          target->is_array() && target->size() == 3 && (*target)[0].is_number() &&
          (*target)[1].is_number() && (*target)[2].is_number()) {
        const Vec3 point{(*target)[0].get<double>(), (*target)[1].get<double>(),
                         (*target)[2].get<double>()};
        const auto index = static_cast<std::int64_t>(particle);
        if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z) &&
            world.model().moves(static_cast<ParticleIndex>(index))) {
          if (dragParticle_ != index) ++drags_;
          dragParticle_ = index;
          dragTarget_ = point;
        }
      }
    } else if (type == "release") {
      dragParticle_ = -1;
    }
  }
  sendStatus(world);
}

void LiveView::sendFrame(const World& world) {
  if (server_->viewers() == 0) return;  // (a viewer that comes gets the next step's frame)
  lastFrame_ = Clock::now();
  sendFrame(world.state(), world.energy());
}

void LiveView::sendFrame(const State& state, const EnergyTally& energy) {
  lastEnergy_ = energy;
  const double header[kFrameHeaderNumbers] = {state.time,
                                              static_cast<double>(state.stepCount),
                                              energy.kinetic,
                                              energy.potential(),
                                              energy.dissipated,
                                              energy.external,
                                              dragWork_,
                                              static_cast<double>(dragParticle_)};
  std::string bytes(sizeof header + state.position.size() * 3 * sizeof(float), '\0');
  std::memcpy(bytes.data(), header, sizeof header);
  char* at = bytes.data() + sizeof header;
  for (const Vec3& p : state.position) {
    const float xyz[3] = {static_cast<float>(p.x), static_cast<float>(p.y),
                          static_cast<float>(p.z)};
    std::memcpy(at, xyz, sizeof xyz);
    at += sizeof xyz;
  }
  server_->sendFrame(std::move(bytes));
  ++frames_;
}

void LiveView::sendStatus(const World& world) {
  if (server_->viewers() == 0) return;
  server_->sendText(nlohmann::json{{"type", "status"},
                                   {"paused", paused_},
                                   {"speed", speed_},
                                   {"time", world.state().time},
                                   {"dragWork", dragWork_},
                                   {"dragging", dragParticle_},
                                   {"ended", false}}
                        .dump());
}

void LiveView::applyDrag(World& world) {
  const auto i = static_cast<std::size_t>(dragParticle_);
  const Model& model = world.model();
  const State& state = world.state();
  const double dt = state.time - lastTime_;  // the step just taken
  if (!(dt > 0.0)) return;
  // MODEL §5's attraction: a spring of rest length ~0 from the particle to the
  // mouse point, its stiffness and damping set on the dragged object's mass M
  // (k = M ω², c = 2 ζ sqrt(k M)), capped for the particle's own mass m at this
  // step (k δ²/m ≤ 0.2, c δ/m ≤ 0.5) so that the kick stays stable. A particle
  // a rigid tree carries stands for its link: m is the link's (object's) mass.
  const auto o = static_cast<std::size_t>(model.objectOf[i]);
  const double ownMass = model.mass[i];
  const double objectMass = o < objectMass_.size() ? std::max(objectMass_[o], ownMass) : ownMass;
  const double m = model.isCarried(static_cast<ParticleIndex>(i)) ? objectMass : ownMass;
  const double omega = 2.0 * std::numbers::pi * settings_.dragFrequency;
  const double k = std::min(objectMass * omega * omega, 0.2 * m / (dt * dt));
  const double c =
      std::min(2.0 * settings_.dragDampingRatio * std::sqrt(k * objectMass), 0.5 * m / dt);
  const Vec3 x = state.position[i];
  const Vec3 v = state.velocity[i];
  const Vec3 force = k * (dragTarget_ - x) - c * v;
  // The spring's impulse over the step, at the particle (a rigid tree struck
  // there: World::applyImpulse): World books the kinetic energy it adds as
  // external work (EnergyTally::external).
  world.bookExternalWork();  // (the work of the tasks before this one)
  world.applyImpulse(static_cast<ParticleIndex>(i), dt * force);
  dragWork_ += world.bookExternalWork();
}

void LiveView::waitUntil(const World& world, Clock::time_point until) {
  const double period = 1.0 / std::max(settings_.frameRate, 1.0);
  for (;;) {
    const auto now = Clock::now();
    if (now >= until || paused_ || endRequested_) return;
    if (stop_ && stop_->load(std::memory_order_relaxed)) return;
    if (std::chrono::duration<double>(now - lastFrame_).count() >= period) sendFrame(world);
    std::this_thread::sleep_for(std::min<Clock::duration>(until - now, std::chrono::milliseconds(5)));
    handleMessages(world);
  }
}

bool LiveView::afterStep(World& world) {
  if (dragParticle_ >= 0) applyDrag(world);
  lastTime_ = world.state().time;
  const double period = 1.0 / std::max(settings_.frameRate, 1.0);
  auto now = Clock::now();
  if (std::chrono::duration<double>(now - lastFrame_).count() >= period) {
    handleMessages(world);
    sendFrame(world);
  }
  // Paused: the run waits, still serving, until resumed, stopped, or every
  // viewer has gone (a closed tab never holds a run forever).
  if (paused_) {
    sendFrame(world);
    while (paused_ && !endRequested_ && server_->viewers() > 0 &&
           !(stop_ && stop_->load(std::memory_order_relaxed))) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      handleMessages(world);
    }
    paused_ = false;
    anchor(world);
  }
  // Real time × speed: ahead of it, wait; far behind (a slow scene), start again from here.
  if (speed_ > 0.0 && server_->viewers() > 0) {
    const double ahead = (world.state().time - anchorTime_) / speed_ -
                         std::chrono::duration<double>(Clock::now() - anchorWall_).count();
    if (ahead > 1e-3) {
      waitUntil(world, Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(ahead)));
    } else if (ahead < -0.25) {
      anchor(world);
    }
  }
  return !endRequested_;
}

void LiveView::finish(const State* last) {
  if (last && server_->viewers() > 0) sendFrame(*last, lastEnergy_);
  server_->sendText(nlohmann::json{{"type", "status"}, {"ended", true}, {"dragWork", dragWork_}}
                        .dump());
  // A moment for the last messages to leave before the server closes.
  if (server_->viewers() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

}  // namespace robophi
