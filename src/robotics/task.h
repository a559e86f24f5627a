#pragma once
/// \file
/// A task run between steps (docs/robotics.md): it may change the world through
/// its edit API and add lines to the run's events. A task also says what it
/// reached (summary.json "outcomes") and saves and restores its own state for a
/// checkpoint (docs/output-format.md "Checkpoint and restart").

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "robophi/world.h"

namespace robophi {

/// What runs between steps. Subclasses hold their own state; the world's model
/// edits they make are saved by the runner, not by them.
class Task {
 public:
  virtual ~Task() = default;
  /// Called once before the first step of a run (not when it resumes from a
  /// checkpoint): a controller's commands at t = 0.
  virtual void start(World& world, std::vector<std::string>& events) {
    (void)world;
    (void)events;
  }
  /// Called after each accepted step; false ends the run (e.g. a goal reached).
  virtual bool step(World& world, std::vector<std::string>& events) = 0;
  /// The task's state as JSON (null: it has none), bit-exact for numbers that
  /// decide what it does next.
  virtual nlohmann::json save() const { return nullptr; }
  /// Puts back a state save() returned (same scene). Throws std::runtime_error
  /// naming what does not fit.
  virtual void restore(const nlohmann::json& saved) { (void)saved; }
  /// Machine-readable outcomes at the end of the run, merged into summary.json
  /// (e.g. {"goals": [...], "grasps": [...]}); null when none.
  virtual nlohmann::json outcomes(const World& world) const {
    (void)world;
    return nullptr;
  }
};

/// A handle on a Task, as RunOptions::tasks holds them: made from a Task or from
/// a plain function bool(World&, events) (a task without state), or empty.
class StepTask {
 public:
  using Function = std::function<bool(World& world, std::vector<std::string>& events)>;
  StepTask() = default;
  StepTask(std::nullptr_t) {}  // NOLINT(google-explicit-constructor): an empty task
  StepTask(std::shared_ptr<Task> task) : task_(std::move(task)) {}  // NOLINT
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, StepTask> &&
                                              std::is_invocable_r_v<bool, F&, World&,
                                                                    std::vector<std::string>&>>>
  StepTask(F function) {  // NOLINT(google-explicit-constructor): lambdas convert
    Function f(std::move(function));
    if (f) task_ = std::make_shared<FunctionTask>(std::move(f));
  }
  explicit operator bool() const { return task_ != nullptr; }
  bool operator()(World& world, std::vector<std::string>& events) const {
    return task_->step(world, events);
  }
  Task* get() const { return task_.get(); }
  Task* operator->() const { return task_.get(); }

 private:
  struct FunctionTask final : Task {
    explicit FunctionTask(Function f) : function(std::move(f)) {}
    bool step(World& world, std::vector<std::string>& events) override {
      return function(world, events);
    }
    Function function;
  };
  std::shared_ptr<Task> task_;
};

}  // namespace robophi
