#pragma once
/// \file
/// ModelBuilder: the one road from generated objects to a Model and its initial
/// State. It places objects (their particles, connectors and named joints, with
/// their initial velocities), materials, environment items and connectors
/// between objects, checking every argument (SpecError), and hands back the
/// model and the state together:
///
///     build::ModelBuilder builder;
///     const auto rubber = builder.addMaterial({"rubber", 1e5, 30.0, 0.8, 0.6});
///     builder.addPlane({{0, 0, 0}, {0, 0, 1}, rubber});
///     builder.addObject({.name = "arm", .kind = "arm", .geometry = build::makeArm(armSpec)});
///     auto [model, initial] = std::move(builder).build();

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "robophi/build/objects.h"
#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi::build {

/// A generated object and how it starts, ready to be placed in a model.
struct ObjectPlacement {
  /// Unique among the model's objects, not empty, no ':' ("object:index").
  std::string name{};
  /// The generator's name (ObjectInfo::kind), e.g. "rope", "arm".
  std::string kind{};
  /// Particles and connectors in local indices; geometry.fixed marks fixed particles.
  GeneratedObject geometry{};
  /// (n) or empty (at rest): initial velocities (m/s). Fixed particles start at rest.
  std::vector<Vec3> velocity{};
  /// Linear damping c of every particle (N·s/m), >= 0: force -c v.
  double linearDamping = 0.0;
  /// Index into the model's materials (ModelBuilder::addMaterial); 0 is the default.
  std::int32_t material = 0;
};

/// Velocities of a rigid motion of `object` (m/s): v_i = velocity + ω × (p_i − c),
/// c the centre of mass, ω = angularVelocity (rad/s).
std::vector<Vec3> rigidVelocity(const GeneratedObject& object, const Vec3& velocity,
                                const Vec3& angularVelocity);
/// Adds the spin ω × (p_i − c) about the centre of mass to each velocity[i] (m/s).
void addSpin(const GeneratedObject& object, const Vec3& angularVelocity,
             std::vector<Vec3>& velocity);

/// Where a placed object's particles are in the model.
struct PlacedObject {
  /// Index into Model::objects.
  std::int32_t object = 0;
  ParticleIndex firstParticle = 0;
  ParticleIndex particleCount = 0;
  /// The model index of local particle `local` (negative counts from the end);
  /// throws SpecError when out of range.
  ParticleIndex particle(std::int64_t local) const;
};

/// A model and the state it starts in (State::sizedFor plus positions and velocities).
struct BuiltModel {
  Model model{};
  State initial{};
};

/// Builds a Model and its initial State. Every method checks its arguments and
/// throws SpecError (a std::invalid_argument naming the field and its value)
/// before it changes anything.
class ModelBuilder {
 public:
  ModelBuilder() = default;

  /// Gravity g (m/s²), finite; default [0, 0, -9.81].
  void setGravity(const Vec3& gravity);

  /// Adds a material (contact stiffness > 0, damping >= 0, 0 <= kinetic <=
  /// static friction) and returns its index. The name must be new and not empty;
  /// "default" replaces material 0 (once).
  std::int32_t addMaterial(const Material& material);
  /// The index of the material called `name`, or -1.
  std::int32_t findMaterial(std::string_view name) const;

  /// Environment items (MODEL §3); each names an existing material. A plane's
  /// normal (non-zero) is normalised; a box's axes must be orthonormal.
  void addPlane(const GroundPlane& plane);
  void addHeightfield(Heightfield field);
  void addBox(const BoxObstacle& box);
  void addSphere(const SphereObstacle& sphere);
  /// The medium's viscosity k (N·s/m per particle), >= 0.
  void setViscosity(double viscosity);
  /// Contact settings (docs/contact.md); pair overrides name placed objects.
  void setContactSettings(const ContactSettings& settings);

  /// Places an object: its particles after the ones already placed, its
  /// connectors and named joints ("<name>.<joint>") renumbered.
  PlacedObject addObject(const ObjectPlacement& object);

  /// Connectors between placed particles (model indices); rest values > 0,
  /// stiffness and damping >= 0, particles distinct. Each returns its index.
  std::int32_t addConnector(const LinearSpring& spring);
  std::int32_t addConnector(const TorsionSpring& spring);
  std::int32_t addConnector(const JointSpring& spring);

  /// A named joint over connectors already added (model indices, Joint::connector
  /// and driveSpring as in Model::joints): a new, non-empty name; returns its index.
  std::int32_t addJoint(const Joint& joint);
  /// Placed objects a and b (distinct) never touch each other (Model::noContactPairs).
  void excludeContact(std::int32_t objectA, std::int32_t objectB);
  /// Placed objects (distinct) none of which touches another (a robot's links):
  /// one new ObjectInfo::contactGroup, in memory linear in their count; objects
  /// already in a group get pairs instead (Model::noContactPairs).
  void excludeContactWithin(const std::vector<std::int32_t>& objects);
  /// Adds a rigid body (MODEL §1.7) of placed particles, its rest shape their present
  /// offsets from their mass centre; shape matching at `frequency` (rad/s, >= 0; 0:
  /// none) with damping ratio `dampingRatio` (>= 0). Returns its index in Model::bodies.
  std::int32_t addBody(const std::string& name, std::vector<ParticleIndex> particles,
                       double frequency, double dampingRatio);
  /// Adds a body link (MODEL §1.7) between two added bodies at the joint point `point`
  /// (m) with the axis `axis` (any length > 0), both in the world as built, with the
  /// gains of `gains` (its stiffness, damping, angularStiffness, angularDamping).
  /// Returns its index in Model::bodyLinks.
  std::int32_t addBodyLink(BodyLinkKind kind, std::int32_t child, std::int32_t parent,
                           const Vec3& point, const Vec3& axis, const BodyLink& gains);

  /// The model so far, and the initial positions and velocities of its particles.
  const Model& model() const { return model_; }
  const std::vector<Vec3>& positions() const { return position_; }
  const std::vector<Vec3>& velocities() const { return velocity_; }

  /// Adds a rigid tree (docs/model.md §7, Model::rigidTrees) whose particles are
  /// fixed particles already placed (BodyParticle::particle, model indices),
  /// starting at coordinates q (empty: neutral) and rates v (empty: at rest); the
  /// particles are moved to where its bodies put them. Returns its index. Throws
  /// SpecError naming what is wrong.
  std::int32_t addRigidTree(RigidTree tree, std::vector<double> q = {}, std::vector<double> v = {});
  /// Adds a visual shape (display only: robophi/visuals.h).
  void addVisual(VisualShape visual) { model_.visuals.push_back(std::move(visual)); }

  /// The model and its initial state; the builder is left empty.
  BuiltModel build() &&;

 private:
  void checkMaterialIndex(const char* spec, std::int32_t material) const;
  Vec3 bodyCenter(std::int32_t body) const;

  Model model_;
  std::vector<Vec3> position_;  // (particleCount) m
  std::vector<Vec3> velocity_;  // (particleCount) m/s
  std::vector<std::vector<double>> treePositions_, treeVelocities_;  // (rigidTrees)
  bool defaultReplaced_ = false;
};

}  // namespace robophi::build
