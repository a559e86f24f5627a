#pragma once
/// \file
/// CompiledModel: a Model checked once and completed with the tables the step
/// derives from it (the contact stage's exclusion lists, material-pair table,
/// grid and sphere-tree classification). Read-only: the only changes are the
/// edits of World (world.h), which rebuild exactly what each one invalidates.

#include <cstdint>
#include <memory>

#include "robophi/model.h"

namespace robophi {

struct ContactTables;
struct SpringIncidence;

class CompiledModel {
 public:
  /// Checks `model` (checkModel) and derives its tables. Throws
  /// std::invalid_argument naming the first problem.
  explicit CompiledModel(Model model);
  ~CompiledModel();
  CompiledModel(const CompiledModel& other);
  CompiledModel& operator=(const CompiledModel& other);
  CompiledModel(CompiledModel&&) noexcept;
  CompiledModel& operator=(CompiledModel&&) noexcept;

  const Model& model() const { return model_; }
  /// The contact stage's tables (an internal type of the core).
  const ContactTables& contactTables() const { return *tables_; }
  /// The linear springs at each particle, for the parallel gather (an internal type).
  const SpringIncidence& springIncidence() const { return *springIncidence_; }
  // Revisions: numbers unique across the process that change with the edits
  // (World's edit API), for caches derived from the model to compare.
  /// Changes with every edit of the model.
  std::int64_t revision() const { return revision_; }
  /// Changes whenever the contact tables are rebuilt (a Workspace's sphere trees).
  std::int64_t contactRevision() const { return contactRevision_; }

  /// What an edit changed (World's edits say so when they change the model).
  enum Change : unsigned { kValues = 0, kContactTables = 1 };

 private:
  friend class World;
  /// Called by World after it changed model_: bumps the revisions and rebuilds
  /// the contact tables if the change calls for it.
  void changed(unsigned change);
  Model model_;
  std::unique_ptr<ContactTables> tables_;
  std::unique_ptr<SpringIncidence> springIncidence_;
  std::int64_t revision_ = 0;
  std::int64_t contactRevision_ = 0;
};

}  // namespace robophi
