// World's edit API: the only way to change the model or the state between
// steps. Each edit checks its arguments, makes the evaluation stale (its work is
// booked as external at the next evaluation) and tells the compiled model what
// it changed, so that the derived tables are rebuilt exactly when they must be.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "core/text.h"
#include "integrate/rigid_trees.h"
#include "robophi/joints.h"
#include "robophi/world.h"

namespace robophi {

namespace {

void requireFinite(const char* function, const char* argument, double value) {
  if (!std::isfinite(value))
    throw std::invalid_argument(
        detail::text("{}: {} = {} must be finite", function, argument, value));
}

void requireFinite(const char* function, const char* argument, const Vec3& value) {
  if (!isFinite(value))
    throw std::invalid_argument(detail::text("{}: {} = ({}, {}, {}) must be finite", function,
                                             argument, value.x, value.y, value.z));
}

void requireNonNegative(const char* function, const char* argument, double value) {
  if (!(value >= 0.0) || !std::isfinite(value))
    throw std::invalid_argument(
        detail::text("{}: {} = {} must be a finite number >= 0", function, argument, value));
}

template <class Index>
void requireIndex(const char* function, const char* what, Index index, std::size_t count) {
  if (index < 0 || static_cast<std::size_t>(index) >= count)
    throw std::out_of_range(
        detail::text("{}: {} {} does not exist (there are {})", function, what, index, count));
}

void requireIndex(const char* function, const char* what, std::size_t index, std::size_t count) {
  if (index >= count)
    throw std::out_of_range(
        detail::text("{}: {} {} does not exist (there are {})", function, what, index, count));
}

void requireMaterial(const char* function, const Material& m) {
  requireNonNegative(function, "material.contactStiffness", m.contactStiffness);
  requireNonNegative(function, "material.contactDamping", m.contactDamping);
  requireNonNegative(function, "material.staticFriction", m.staticFriction);
  requireNonNegative(function, "material.kineticFriction", m.kineticFriction);
}


}  // namespace

void World::edited() {
  ++changes_;
  Snapshot& s = current_;
  if (s.evaluated_ && !s.edited_) {
    s.edited_ = true;
    s.totalBeforeEdits_ = s.energy().total();
  }
  s.evaluated_ = false;
}

void World::setPosition(ParticleIndex particle, const Vec3& position) {
  requireIndex("World::setPosition", "particle", particle,
               static_cast<std::size_t>(model().particleCount()));
  requireFinite("World::setPosition", "position", position);
  Vec3& p = current_.state_.position[particle];
  if (p.x == position.x && p.y == position.y && p.z == position.z) return;
  edited();
  p = position;
}

void World::setVelocity(ParticleIndex particle, const Vec3& velocity) {
  requireIndex("World::setVelocity", "particle", particle,
               static_cast<std::size_t>(model().particleCount()));
  requireFinite("World::setVelocity", "velocity", velocity);
  Vec3& v = current_.state_.velocity[particle];
  if (v.x == velocity.x && v.y == velocity.y && v.z == velocity.z) return;
  edited();
  v = velocity;
}

void World::applyImpulse(ParticleIndex particle, const Vec3& impulse) {
  const Model& m = model();
  requireIndex("World::applyImpulse", "particle", particle,
               static_cast<std::size_t>(m.particleCount()));
  requireFinite("World::applyImpulse", "impulse", impulse);
  if (impulse.x == 0.0 && impulse.y == 0.0 && impulse.z == 0.0) return;
  const auto i = static_cast<std::size_t>(particle);
  if (!m.isFixed(particle)) {
    edited();
    current_.state_.velocity[i] += m.inverseMass[i] * impulse;
    return;
  }
  if (!m.isCarried(particle)) return;
  // docs/model.md §7: the tree struck at the particle's point P of body b,
  // M Δv = Jᵀ p with M the joint-space mass matrix (armature on its diagonal, as
  // the step has it) and J the translational Jacobian of P.
  const auto t = static_cast<std::size_t>(m.carriedBy[i]);
  const RigidTree& tree = m.rigidTrees[t];
  const auto carrier = std::find_if(tree.particles.begin(), tree.particles.end(),
                                    [particle](const BodyParticle& b) { return b.particle == particle; });
  if (carrier == tree.particles.end()) return;
  const Multibody& multibody = tree.multibody;
  const auto n = static_cast<std::size_t>(multibody.velocityCount);
  if (n == 0) return;
  State& state = current_.state_;
  MultibodyKinematics kinematics;
  updateKinematics(multibody, state.treePositions[t].data(), kinematics);
  const Vec3 p_WP = kinematics.X_WB[static_cast<std::size_t>(carrier->body)] * carrier->p_BP;
  std::vector<double> J(3 * n), dv(n, 0.0);
  pointJacobian(multibody, kinematics, carrier->body, p_WP, J.data(), nullptr);
  for (std::size_t k = 0; k < n; ++k)
    dv[k] = J[k] * impulse.x + J[n + k] * impulse.y + J[2 * n + k] * impulse.z;
  solveMassMatrix(multibody, kinematics, dv.data());
  edited();
  std::vector<double>& v = state.treeVelocities[t];
  for (std::size_t k = 0; k < n; ++k) v[k] += dv[k];
  // The carried particles' velocities follow the tree's new rates.
  placeTreeParticles(m, state, treeWorkspaces_);
}

void World::setJointTarget(std::size_t joint, double target) {
  const Model& m = model();
  requireIndex("World::setJointTarget", "joint", joint, m.joints.size());
  requireFinite("World::setJointTarget", "target", target);
  const Joint& j = m.joints[joint];
  if (j.actsThroughBodies() || j.inTree()) {
    // MODEL §1.7: the servo of a joint with bodies is the joint's own; a tree
    // joint's target is its coordinate q* (docs/model.md §7), not wrapped.
    const double raw = j.wraps() ? wrapAngle(target) : target;
    double& stored = model_.model_.joints[joint].servoTarget;
    if (stored == raw) return;
    edited();
    stored = raw;
  } else if (j.kind == JointKind::kRevolute) {
    const double wrapped = wrapAngle(target);
    double& rest = model_.model_.jointSprings[static_cast<std::size_t>(j.connector)].restAngle;
    if (rest == wrapped) return;
    edited();
    rest = wrapped;
  } else {
    if (j.driveSpring < 0)
      throw std::invalid_argument(
          detail::text("World::setJointTarget: prismatic joint '{}' has no drive spring", j.name));
    if (!(target > 0.0))
      throw std::invalid_argument(
          detail::text("World::setJointTarget: target {} m of prismatic joint '{}' must be > 0",
                       target, j.name));
    double& rest = model_.model_.linearSprings[static_cast<std::size_t>(j.driveSpring)].restLength;
    if (rest == target) return;
    edited();
    rest = target;
  }
  model_.changed(CompiledModel::kValues);
}

void World::setJointServo(std::size_t joint, double stiffness, double damping) {
  const Model& m = model();
  requireIndex("World::setJointServo", "joint", joint, m.joints.size());
  requireNonNegative("World::setJointServo", "stiffness", stiffness);
  requireNonNegative("World::setJointServo", "damping", damping);
  const Joint& j = m.joints[joint];
  double* k = nullptr;
  double* c = nullptr;
  if (j.actsThroughBodies() || j.inTree()) {
    k = &model_.model_.joints[joint].servoStiffness;
    c = &model_.model_.joints[joint].servoDamping;
  } else if (j.kind == JointKind::kRevolute) {
    JointSpring& s = model_.model_.jointSprings[static_cast<std::size_t>(j.connector)];
    k = &s.stiffness;
    c = &s.damping;
  } else {
    if (j.driveSpring < 0)
      throw std::invalid_argument(
          detail::text("World::setJointServo: prismatic joint '{}' has no drive spring", j.name));
    LinearSpring& s = model_.model_.linearSprings[static_cast<std::size_t>(j.driveSpring)];
    k = &s.stiffness;
    c = &s.damping;
  }
  if (*k == stiffness && *c == damping) return;
  edited();
  *k = stiffness;
  *c = damping;
  model_.changed(CompiledModel::kValues);
}

void World::setJointEffort(std::size_t joint, double effort) {
  requireIndex("World::setJointEffort", "joint", joint, model().joints.size());
  requireFinite("World::setJointEffort", "effort", effort);
  double& current = model_.model_.joints[joint].drive.effort;
  if (current == effort) return;
  edited();
  current = effort;
  model_.changed(CompiledModel::kValues);
}

void World::setGravityCompensation(std::size_t joint, bool on) {
  requireIndex("World::setGravityCompensation", "joint", joint, model().joints.size());
  Joint& j = model_.model_.joints[joint];
  if (on && !j.inTree() && (!j.actsThroughBodies() || j.subtreeBodies.empty()))
    throw std::invalid_argument(detail::text(
        "World::setGravityCompensation: joint '{}' has no bodies to carry (no body link)", j.name));
  if (j.compensateGravity == on) return;
  edited();
  j.compensateGravity = on;
  model_.changed(CompiledModel::kValues);
}

void World::setJointDrive(std::size_t joint, const JointDrive& drive) {
  requireIndex("World::setJointDrive", "joint", joint, model().joints.size());
  if (const std::string problem = checkJointDrive(drive); !problem.empty())
    throw std::invalid_argument(
        detail::text("World::setJointDrive: joint '{}': {}", model().joints[joint].name, problem));
  JointDrive& d = model_.model_.joints[joint].drive;
  const auto fields = [](const JointDrive& x) {
    return std::tie(x.effort, x.rateGain, x.targetRate, x.effortLimit, x.velocityLimit, x.damping,
                    x.friction, x.frictionVelocity);
  };
  if (fields(d) == fields(drive)) return;
  edited();
  d = drive;
  model_.changed(CompiledModel::kValues);
}

namespace {

bool sameEnds(const LinearSpring& a, const LinearSpring& b) { return a.a == b.a && a.b == b.b; }
bool sameEnds(const TorsionSpring& a, const TorsionSpring& b) {
  return a.a == b.a && a.b == b.b && a.c == b.c;
}
bool sameEnds(const JointSpring& a, const JointSpring& b) {
  return a.a == b.a && a.b == b.b && a.c == b.c && a.d == b.d;
}

// Checks connector `index` of `list` and its replacement; returns what the
// replacement changes (new ends change the contact exclusion lists).
template <class Connector>
unsigned checkReplacement(const char* function, const std::vector<Connector>& list,
                          std::size_t index, const Connector& connector, ParticleIndex particles) {
  requireIndex(function, "connector", index, list.size());
  if (const std::string problem = checkConnector(connector, index, particles); !problem.empty())
    throw std::invalid_argument(std::string(function) + ": " + problem);
  return sameEnds(list[index], connector) ? CompiledModel::kValues : CompiledModel::kContactTables;
}

}  // namespace

void World::setLinearSpring(std::size_t index, const LinearSpring& spring) {
  const unsigned change = checkReplacement("World::setLinearSpring", model().linearSprings, index,
                                           spring, model().particleCount());
  edited();
  model_.model_.linearSprings[index] = spring;
  model_.changed(change);
}

void World::setTorsionSpring(std::size_t index, const TorsionSpring& spring) {
  const unsigned change = checkReplacement("World::setTorsionSpring", model().torsionSprings, index,
                                           spring, model().particleCount());
  edited();
  model_.model_.torsionSprings[index] = spring;
  model_.changed(change);
}

void World::setJointSpring(std::size_t index, const JointSpring& spring) {
  const unsigned change = checkReplacement("World::setJointSpring", model().jointSprings, index,
                                           spring, model().particleCount());
  edited();
  model_.model_.jointSprings[index] = spring;
  model_.changed(change);
}

void World::setMaterial(std::int32_t index, const Material& material) {
  requireIndex("World::setMaterial", "material", index, model().materials.size());
  requireMaterial("World::setMaterial", material);
  edited();
  model_.model_.materials[static_cast<std::size_t>(index)] = material;
  model_.changed(CompiledModel::kContactTables);
}

std::int32_t World::addMaterial(const Material& material) {
  requireMaterial("World::addMaterial", material);
  edited();
  model_.model_.materials.push_back(material);
  model_.changed(CompiledModel::kContactTables);
  return static_cast<std::int32_t>(model().materials.size()) - 1;
}

void World::setObjectMaterial(std::int32_t object, std::int32_t material) {
  requireIndex("World::setObjectMaterial", "object", object, model().objects.size());
  requireIndex("World::setObjectMaterial", "material", material, model().materials.size());
  edited();
  model_.model_.objects[static_cast<std::size_t>(object)].material = material;
  model_.changed(CompiledModel::kContactTables);
}

void World::setContactPair(const ContactPairOverride& pair) {
  const char* function = "World::setContactPair";
  requireIndex(function, "object", pair.objectA, model().objects.size());
  if (pair.objectB != -1) requireIndex(function, "object", pair.objectB, model().objects.size());
  requireNonNegative(function, "stiffness", pair.stiffness);
  requireNonNegative(function, "damping", pair.damping);
  requireNonNegative(function, "staticFriction", pair.staticFriction);
  requireNonNegative(function, "kineticFriction", pair.kineticFriction);
  edited();
  const auto samePair = [&](const ContactPairOverride& o) {
    const auto ordered = [](std::int32_t a, std::int32_t b) {
      return b >= 0 && b < a ? std::make_pair(b, a) : std::make_pair(a, b);
    };
    return ordered(o.objectA, o.objectB) == ordered(pair.objectA, pair.objectB);
  };
  auto& overrides = model_.model_.contact.pairOverrides;
  overrides.erase(std::remove_if(overrides.begin(), overrides.end(), samePair), overrides.end());
  overrides.push_back(pair);
  model_.changed(CompiledModel::kContactTables);
}

void World::setContactSettings(const ContactSettings& settings) {
  const char* function = "World::setContactSettings";
  requireNonNegative(function, "tangentialStiffnessRatio", settings.tangentialStiffnessRatio);
  requireNonNegative(function, "tangentialDampingRatio", settings.tangentialDampingRatio);
  requireNonNegative(function, "stickVelocity", settings.stickVelocity);
  requireNonNegative(function, "stribeckVelocity", settings.stribeckVelocity);
  if (settings.leafSize < 1)
    throw std::invalid_argument(
        detail::text("{}: leafSize = {} must be >= 1", function, settings.leafSize));
  for (const ContactPairOverride& o : settings.pairOverrides) {
    requireIndex(function, "object", o.objectA, model().objects.size());
    if (o.objectB != -1) requireIndex(function, "object", o.objectB, model().objects.size());
  }
  edited();
  model_.model_.contact = settings;
  model_.changed(CompiledModel::kContactTables);
}

void World::setParticleFixed(ParticleIndex particle, bool fixed) {
  requireIndex("World::setParticleFixed", "particle", particle,
               static_cast<std::size_t>(model().particleCount()));
  Model& m = model_.model_;
  const double inverseMass = fixed ? 0.0 : 1.0 / m.mass[particle];
  if (m.inverseMass[particle] == inverseMass) return;
  edited();
  m.inverseMass[particle] = inverseMass;
  model_.changed(CompiledModel::kContactTables);
}

void World::setGravity(const Vec3& gravity) {
  requireFinite("World::setGravity", "gravity", gravity);
  edited();
  model_.model_.gravity = gravity;
  model_.changed(CompiledModel::kValues);
}

std::int32_t World::addSphereObstacle(const SphereObstacle& sphere) {
  const char* function = "World::addSphereObstacle";
  requireFinite(function, "center", sphere.center);
  if (!(sphere.radius > 0.0) || !std::isfinite(sphere.radius))
    throw std::invalid_argument(
        detail::text("{}: radius = {} m must be a finite number > 0", function, sphere.radius));
  requireIndex(function, "material", sphere.material, model().materials.size());
  edited();
  Environment& environment = model_.model_.environment;
  environment.spheres.push_back(sphere);
  model_.changed(CompiledModel::kContactTables);
  return environment.itemCount() - 1;
}

void World::moveSphereObstacle(std::int32_t item, const Vec3& center) {
  const char* function = "World::moveSphereObstacle";
  requireFinite(function, "center", center);
  Environment& environment = model_.model_.environment;
  const std::int32_t first = environment.itemCount() - static_cast<std::int32_t>(environment.spheres.size());
  if (item < first || item >= environment.itemCount())
    throw std::invalid_argument(detail::text("{}: environment item {} is not a sphere (spheres are {} to {})",
                                             function, item, first, environment.itemCount() - 1));
  edited();
  environment.spheres[static_cast<std::size_t>(item - first)].center = center;
  model_.changed(CompiledModel::kContactTables);
}

void World::setViscosity(double viscosity) {
  requireNonNegative("World::setViscosity", "viscosity", viscosity);
  edited();
  model_.model_.environment.viscosity = viscosity;
  model_.changed(CompiledModel::kValues);
}

}  // namespace robophi
