// CompiledModel: the model checked once, with the tables the step derives from it.
#include "robophi/compiled_model.h"

#include <atomic>
#include <stdexcept>

#include "collision/contact_tables.h"
#include "forces/forces.h"

namespace robophi {

namespace {

// Revisions are unique in the process, so a cache built for one compiled model
// is never taken for another's.
std::int64_t nextRevision() {
  static std::atomic<std::int64_t> counter{0};
  return ++counter;
}

}  // namespace

CompiledModel::CompiledModel(Model model) : model_(std::move(model)) {
  if (const std::string problem = checkModel(model_); !problem.empty()) {
    throw std::invalid_argument("model: " + problem);
  }
  tables_ = std::make_unique<ContactTables>(compileContactTables(model_));
  springIncidence_ = std::make_unique<SpringIncidence>(compileSpringIncidence(model_));
  revision_ = contactRevision_ = nextRevision();
}

CompiledModel::~CompiledModel() = default;
CompiledModel::CompiledModel(const CompiledModel& other)
    : model_(other.model_),
      tables_(std::make_unique<ContactTables>(*other.tables_)),
      springIncidence_(std::make_unique<SpringIncidence>(*other.springIncidence_)),
      revision_(other.revision_),
      contactRevision_(other.contactRevision_) {}
CompiledModel& CompiledModel::operator=(const CompiledModel& other) {
  if (this != &other) {
    model_ = other.model_;
    tables_ = std::make_unique<ContactTables>(*other.tables_);
    springIncidence_ = std::make_unique<SpringIncidence>(*other.springIncidence_);
    revision_ = other.revision_;
    contactRevision_ = other.contactRevision_;
  }
  return *this;
}
CompiledModel::CompiledModel(CompiledModel&&) noexcept = default;
CompiledModel& CompiledModel::operator=(CompiledModel&&) noexcept = default;

void CompiledModel::changed(unsigned change) {
  revision_ = nextRevision();
  if ((change & kContactTables) != 0) {
    *tables_ = compileContactTables(model_);
    // A connector's ends or the particles changed (kContactTables covers both).
    *springIncidence_ = compileSpringIncidence(model_);
    contactRevision_ = revision_;
  }
}

}  // namespace robophi
