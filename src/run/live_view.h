#pragma once
/// \file
/// The live view (docs/viewer.md "Live view"): a task between steps that serves
/// the replay page on localhost (output::LiveServer) and feeds it the run as it
/// goes; it paces the run (real time × k, or as fast as possible), pauses it, and
/// applies the viewer's mouse drag as a spring (MODEL §5's attraction) whose
/// work is booked as external work. Without a viewer it changes nothing: the
/// state is bit-identical to a run without it, as long as nobody drags.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "output/live_server.h"
#include "robophi/scene/scene.h"
#include "robotics/task.h"

namespace robophi {

/// How the live view runs.
struct LiveViewSettings {
  /// The port on 127.0.0.1 (0: a free one).
  int port = 8765;
  /// How long (s of wall time) the run waits for a first viewer before it starts
  /// anyway; 0: it does not wait.
  double waitSeconds = 30.0;
  /// Model seconds per wall second at the start (the page changes it); 0: as
  /// fast as possible.
  double speed = 1.0;
  /// The most frames sent per wall second.
  double frameRate = 60.0;
  /// The drag spring's natural frequency on the dragged object's mass (Hz):
  /// its stiffness is M (2π f)², its damping 2 ζ sqrt(k M) with ζ = dragDampingRatio.
  double dragFrequency = 1.5;
  double dragDampingRatio = 0.7;
};

/// The live view of one world. As a Task (robophi run --live) it runs after
/// each step; world.view() from Python calls afterStep itself.
class LiveView : public Task {
 public:
  /// Makes the page of `scene` (its model, world view and `state` as the first
  /// frame) and starts serving it. Throws std::runtime_error when the server is
  /// not built or the port cannot be bound. `stop` (may be null): a pause or a
  /// wait ends when it becomes true.
  LiveView(const Scene& scene, const State& state, const LiveViewSettings& settings,
           const std::atomic<bool>* stop = nullptr);
  ~LiveView() override;

  /// The page's address, "http://127.0.0.1:PORT/".
  std::string url() const;
  /// Waits for a first viewer (LiveViewSettings::waitSeconds), then sends the
  /// first frame. False when none came.
  bool waitForViewer();

  void start(World& world, std::vector<std::string>& events) override;
  bool step(World& world, std::vector<std::string>& events) override;
  /// {"live": {"dragWork": J, "drags": n, "frames": n, "viewers": n}}.
  nlohmann::json outcomes(const World& world) const override;

  /// After a step: the viewers' commands, the drag, pacing and pauses, a frame
  /// when one is due. Returns false when a viewer asked to end the run.
  bool afterStep(World& world);
  /// Sends the run's last state (`last`, may be null) and tells the viewers that
  /// the run ended (the page keeps its last frame).
  void finish(const State* last);

  /// Work the drag did on the world so far (J): part of EnergyTally::external.
  double dragWork() const { return dragWork_; }
  /// Whether a viewer holds a particle now.
  bool dragging() const { return dragParticle_ >= 0; }

 private:
  using Clock = std::chrono::steady_clock;
  void handleMessages(const World& world);
  void sendFrame(const World& world);
  /// The frame message of `state` with the energies `energy`.
  void sendFrame(const State& state, const EnergyTally& energy);
  void sendStatus(const World& world);
  void applyDrag(World& world);
  /// Sleeps in short slices until `until`, serving messages and frames meanwhile.
  void waitUntil(const World& world, Clock::time_point until);
  /// Restarts the pacing from now at the world's time.
  void anchor(const World& world);

  LiveViewSettings settings_;
  const std::atomic<bool>* stop_;
  std::unique_ptr<output::LiveServer> server_;
  std::vector<double> objectMass_;  // (objects) kg
  bool paused_ = false;
  bool endRequested_ = false;
  double speed_ = 1.0;
  Clock::time_point anchorWall_{}, lastFrame_{};
  double anchorTime_ = 0.0;
  double lastTime_ = 0.0;  // the world's time after the previous step (s)
  // The drag: the particle held (-1: none) and the mouse point (m).
  std::int64_t dragParticle_ = -1;
  Vec3 dragTarget_{};
  double dragWork_ = 0.0;
  std::int64_t drags_ = 0, frames_ = 0;
  EnergyTally lastEnergy_{};  // of the last frame sent
};

}  // namespace robophi
