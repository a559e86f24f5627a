// ModelBuilder: generated objects, materials, environment items and connectors
// into a Model and its initial State, every argument checked first.
#include "robophi/build/model_builder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "build/checks.h"

namespace robophi::build {

namespace {

constexpr const char* kPlacement = "ObjectPlacement";

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Connector values: a rest value > 0 (rest angles may be 0) and stiffness,
// damping >= 0, each finite.
void checkSpringValues(const char* spec, double stiffness, double damping) {
  check::nonNegative(spec, "stiffness", stiffness, "");
  check::nonNegative(spec, "damping", damping, "");
}

// Particle indices `ends` of a connector are in [0, count) and distinct.
template <std::size_t N>
void checkEnds(const char* spec, const char* field, const std::array<ParticleIndex, N>& ends,
               ParticleIndex count) {
  for (std::size_t i = 0; i < N; ++i) {
    if (ends[i] < 0 || ends[i] >= count)
      check::fail(spec, field,
                  "'" + std::string(field) + "': particle " + std::to_string(ends[i]) +
                      " is out of range (" + std::to_string(count) + " particles)");
    for (std::size_t j = 0; j < i; ++j)
      if (ends[i] == ends[j])
        check::fail(
            spec, field,
            "'" + std::string(field) + "': particle " + std::to_string(ends[i]) + " appears twice");
  }
}

void checkLinear(const char* spec, const LinearSpring& s, ParticleIndex count) {
  checkEnds<2>(spec, "linearSprings", {s.a, s.b}, count);
  check::positive(spec, "restLength", s.restLength, "m");
  checkSpringValues(spec, s.stiffness, s.damping);
}

void checkTorsion(const char* spec, const TorsionSpring& s, ParticleIndex count) {
  checkEnds<3>(spec, "torsionSprings", {s.a, s.c, s.b}, count);
  if (!(s.restAngle >= 0.0 && s.restAngle <= std::numbers::pi))
    check::fail(spec, "restAngle",
                "'restAngle' must be in [0, π] rad, got " + check::number(s.restAngle));
  checkSpringValues(spec, s.stiffness, s.damping);
}

void checkJoint(const char* spec, const JointSpring& s, ParticleIndex count) {
  checkEnds<4>(spec, "jointSprings", {s.a, s.c, s.b, s.d}, count);
  if (!(s.restAngle >= 0.0 && s.restAngle < 2.0 * std::numbers::pi))
    check::fail(spec, "restAngle",
                "'restAngle' must be in [0, 2π) rad, got " + check::number(s.restAngle));
  checkSpringValues(spec, s.stiffness, s.damping);
}

// Everything of an object before it is placed: sizes, values, local indices.
void checkGeometry(const GeneratedObject& g, const std::vector<Vec3>& velocity) {
  const std::size_t n = g.size();
  if (n == 0) check::fail(kPlacement, "geometry", "'geometry' has no particle");
  if (n > static_cast<std::size_t>(kMaxParticlesPerObject))
    check::fail(kPlacement, "geometry",
                "'geometry' has " + std::to_string(n) + " particles, more than " +
                    std::to_string(kMaxParticlesPerObject));
  const auto sized = [n](std::size_t size, bool optional) {
    return size == n || (optional && size == 0);
  };
  if (!sized(g.mass.size(), false) || !sized(g.radius.size(), false) ||
      !sized(g.fixed.size(), true) || !sized(velocity.size(), true))
    check::fail(kPlacement, "geometry",
                "'geometry': " + std::to_string(n) + " positions but " +
                    std::to_string(g.mass.size()) + " masses, " + std::to_string(g.radius.size()) +
                    " radii, " + std::to_string(g.fixed.size()) + " fixed flags and " +
                    std::to_string(velocity.size()) + " velocities");
  for (std::size_t i = 0; i < n; ++i) {
    check::finite(kPlacement, "position", g.position[i], "m");
    check::positive(kPlacement, "mass", g.mass[i], "kg");
    check::positive(kPlacement, "radius", g.radius[i], "m");
    if (!velocity.empty()) check::finite(kPlacement, "velocity", velocity[i], "m/s");
  }
  const auto count = static_cast<ParticleIndex>(n);
  for (const LinearSpring& s : g.linearSprings) checkLinear(kPlacement, s, count);
  for (const TorsionSpring& s : g.torsionSprings) checkTorsion(kPlacement, s, count);
  for (const JointSpring& s : g.jointSprings) checkJoint(kPlacement, s, count);
  for (const Joint& joint : g.joints) {
    const std::size_t connectors =
        joint.kind == JointKind::kRevolute ? g.jointSprings.size() : g.torsionSprings.size();
    const bool driveOk = joint.driveSpring == -1 ||
                         (joint.driveSpring >= 0 &&
                          static_cast<std::size_t>(joint.driveSpring) < g.linearSprings.size());
    bool motorOk = true;
    for (ParticleIndex p : joint.motorParticles) motorOk = motorOk && p >= 0 && p < count;
    if (joint.connector < 0 || static_cast<std::size_t>(joint.connector) >= connectors ||
        !driveOk || !motorOk || joint.name.empty())
      check::fail(kPlacement, "joints",
                  "'joints': joint '" + joint.name + "' names connector " +
                      std::to_string(joint.connector) + " (drive " +
                      std::to_string(joint.driveSpring) + ") that the object does not have");
  }
}

}  // namespace

void addSpin(const GeneratedObject& object, const Vec3& angularVelocity,
             std::vector<Vec3>& velocity) {
  check::finite("addSpin", "angularVelocity", angularVelocity, "rad/s");
  const std::size_t n = object.size();
  if (velocity.size() != n)
    check::fail("addSpin", "velocity",
                "'velocity' has " + std::to_string(velocity.size()) + " entries for " +
                    std::to_string(n) + " particles");
  // Spin about the centre of mass: v += ω × (p - c).
  Vec3 center;
  double mass = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    center += object.position[i] * object.mass[i];
    mass += object.mass[i];
  }
  center = center / mass;
  for (std::size_t i = 0; i < n; ++i)
    velocity[i] += cross(angularVelocity, object.position[i] - center);
}

std::vector<Vec3> rigidVelocity(const GeneratedObject& object, const Vec3& velocity,
                                const Vec3& angularVelocity) {
  check::finite("rigidVelocity", "velocity", velocity, "m/s");
  std::vector<Vec3> result(object.size(), velocity);
  addSpin(object, angularVelocity, result);
  return result;
}

ParticleIndex PlacedObject::particle(std::int64_t local) const {
  const std::int64_t n = particleCount;
  if (local < -n || local >= n)
    check::fail("PlacedObject", "local",
                "'local': index " + std::to_string(local) + " is out of range: the object has " +
                    std::to_string(n) + " particles");
  return static_cast<ParticleIndex>(firstParticle + (local < 0 ? local + n : local));
}

void ModelBuilder::setGravity(const Vec3& gravity) {
  check::finite("setGravity", "gravity", gravity, "m/s²");
  model_.gravity = gravity;
}

std::int32_t ModelBuilder::findMaterial(std::string_view name) const {
  for (std::size_t m = 0; m < model_.materials.size(); ++m)
    if (model_.materials[m].name == name) return static_cast<std::int32_t>(m);
  return -1;
}

std::int32_t ModelBuilder::addMaterial(const Material& material) {
  constexpr const char* kSpec = "Material";
  if (material.name.empty()) check::fail(kSpec, "name", "a material needs a non-empty 'name'");
  const std::int32_t existing = findMaterial(material.name);
  const bool replacesDefault = material.name == "default" && !defaultReplaced_;
  if (existing >= 0 && !replacesDefault)
    check::fail(kSpec, "name", "'name': material '" + material.name + "' is defined twice");
  check::positive(kSpec, "contactStiffness", material.contactStiffness, "N/m");
  check::nonNegative(kSpec, "contactDamping", material.contactDamping, "N·s/m");
  check::nonNegative(kSpec, "staticFriction", material.staticFriction, "-");
  check::nonNegative(kSpec, "kineticFriction", material.kineticFriction, "-");
  if (material.kineticFriction > material.staticFriction)
    check::fail(kSpec, "kineticFriction",
                "'kineticFriction' " + check::number(material.kineticFriction) +
                    " must not exceed 'staticFriction' " + check::number(material.staticFriction));
  if (replacesDefault) {
    defaultReplaced_ = true;
    model_.materials[0] = material;
    return 0;
  }
  model_.materials.push_back(material);
  return static_cast<std::int32_t>(model_.materials.size()) - 1;
}

void ModelBuilder::checkMaterialIndex(const char* spec, std::int32_t material) const {
  if (material < 0 || static_cast<std::size_t>(material) >= model_.materials.size())
    check::fail(spec, "material",
                "'material' " + std::to_string(material) + " is not a material (" +
                    std::to_string(model_.materials.size()) + " defined)");
}

void ModelBuilder::addPlane(const GroundPlane& plane) {
  check::finite("GroundPlane", "point", plane.point, "m");
  check::nonZero("GroundPlane", "normal", plane.normal);
  checkMaterialIndex("GroundPlane", plane.material);
  GroundPlane unitPlane = plane;
  unitPlane.normal = plane.normal / norm(plane.normal);
  model_.environment.planes.push_back(unitPlane);
}

void ModelBuilder::addHeightfield(Heightfield field) {
  constexpr const char* kSpec = "Heightfield";
  check::finite(kSpec, "originX", field.originX, "m");
  check::finite(kSpec, "originY", field.originY, "m");
  check::positive(kSpec, "cellSizeX", field.cellSizeX, "m");
  check::positive(kSpec, "cellSizeY", field.cellSizeY, "m");
  check::atLeast(kSpec, "columns", field.columns, 2);
  check::atLeast(kSpec, "rows", field.rows, 2);
  if (field.heights.size() != static_cast<std::size_t>(field.columns) * field.rows)
    check::fail(kSpec, "heights",
                "'heights' has " + std::to_string(field.heights.size()) + " samples for " +
                    std::to_string(field.rows) + " rows × " + std::to_string(field.columns) +
                    " columns");
  for (double h : field.heights) check::finite(kSpec, "heights", h, "m");
  checkMaterialIndex(kSpec, field.material);
  model_.environment.heightfields.push_back(std::move(field));
}

void ModelBuilder::addBox(const BoxObstacle& box) {
  constexpr const char* kSpec = "BoxObstacle";
  check::finite(kSpec, "center", box.center, "m");
  check::positiveEach(kSpec, "halfExtents", box.halfExtents, "m");
  const Vec3* axes[3] = {&box.axisX, &box.axisY, &box.axisZ};
  constexpr double kTolerance = 1e-9;
  bool orthonormal = std::abs(dot(cross(box.axisX, box.axisY), box.axisZ) - 1.0) < kTolerance;
  for (int i = 0; i < 3; ++i) {
    orthonormal = orthonormal && finite(*axes[i]) && std::abs(norm(*axes[i]) - 1.0) < kTolerance;
    for (int j = 0; j < i; ++j)
      orthonormal = orthonormal && std::abs(dot(*axes[i], *axes[j])) < kTolerance;
  }
  if (!orthonormal)
    check::fail(kSpec, "axisX",
                "'axisX', 'axisY' and 'axisZ' must be orthonormal and right-handed, got " +
                    check::vector(box.axisX) + ", " + check::vector(box.axisY) + ", " +
                    check::vector(box.axisZ));
  checkMaterialIndex(kSpec, box.material);
  model_.environment.boxes.push_back(box);
}

void ModelBuilder::addSphere(const SphereObstacle& sphere) {
  check::finite("SphereObstacle", "center", sphere.center, "m");
  check::positive("SphereObstacle", "radius", sphere.radius, "m");
  checkMaterialIndex("SphereObstacle", sphere.material);
  model_.environment.spheres.push_back(sphere);
}

void ModelBuilder::setViscosity(double viscosity) {
  check::nonNegative("setViscosity", "viscosity", viscosity, "N·s/m");
  model_.environment.viscosity = viscosity;
}

void ModelBuilder::setContactSettings(const ContactSettings& settings) {
  constexpr const char* kSpec = "ContactSettings";
  check::nonNegative(kSpec, "tangentialStiffnessRatio", settings.tangentialStiffnessRatio, "-");
  check::nonNegative(kSpec, "tangentialDampingRatio", settings.tangentialDampingRatio, "-");
  check::nonNegative(kSpec, "stickVelocity", settings.stickVelocity, "m/s");
  check::nonNegative(kSpec, "stribeckVelocity", settings.stribeckVelocity, "m/s");
  check::atLeast(kSpec, "leafSize", settings.leafSize, 1);
  const auto objects = static_cast<std::int32_t>(model_.objects.size());
  for (const ContactPairOverride& pair : settings.pairOverrides) {
    if (pair.objectA < 0 || pair.objectA >= objects || pair.objectB < -1 || pair.objectB >= objects)
      check::fail(kSpec, "pairOverrides",
                  "'pairOverrides': objects " + std::to_string(pair.objectA) + " and " +
                      std::to_string(pair.objectB) + " are not both placed objects (" +
                      std::to_string(objects) + " placed; -1 is the environment)");
    check::positive(kSpec, "stiffness", pair.stiffness, "N/m");
    check::nonNegative(kSpec, "damping", pair.damping, "N·s/m");
    check::nonNegative(kSpec, "staticFriction", pair.staticFriction, "-");
    check::nonNegative(kSpec, "kineticFriction", pair.kineticFriction, "-");
  }
  model_.contact = settings;
}

PlacedObject ModelBuilder::addObject(const ObjectPlacement& object) {
  if (object.name.empty()) check::fail(kPlacement, "name", "'name' must not be empty");
  if (object.name.find(':') != std::string::npos)
    check::fail(kPlacement, "name",
                "'name' \"" + object.name + "\" must not contain ':' (used in \"object:index\")");
  for (const ObjectInfo& placed : model_.objects)
    if (placed.name == object.name)
      check::fail(kPlacement, "name", "duplicate object name '" + object.name + "'");
  const GeneratedObject& g = object.geometry;
  checkGeometry(g, object.velocity);
  check::nonNegative(kPlacement, "linearDamping", object.linearDamping, "N·s/m");
  checkMaterialIndex(kPlacement, object.material);
  if (static_cast<double>(model_.particleCount()) + static_cast<double>(g.size()) >
      std::numeric_limits<ParticleIndex>::max())
    check::fail(kPlacement, "geometry", "the model would have more particles than an index holds");

  const std::int32_t id = model_.addObject(object.name, object.kind, object.material);
  PlacedObject placed{id, model_.particleCount(), static_cast<ParticleIndex>(g.size())};
  for (std::size_t i = 0; i < g.size(); ++i) {
    const bool fixed = !g.fixed.empty() && g.fixed[i];
    model_.addParticle(g.mass[i], g.radius[i], fixed, id, object.linearDamping);
    position_.push_back(g.position[i]);
    velocity_.push_back(fixed || object.velocity.empty() ? Vec3{} : object.velocity[i]);
  }
  const ParticleIndex offset = placed.firstParticle;
  for (LinearSpring s : g.linearSprings) {
    s.a += offset;
    s.b += offset;
    model_.linearSprings.push_back(s);
  }
  for (TorsionSpring s : g.torsionSprings) {
    s.a += offset;
    s.c += offset;
    s.b += offset;
    model_.torsionSprings.push_back(s);
  }
  for (RimRing rim : g.rims) {
    rim.first += offset;
    if (rim.hub != kNoParticle) rim.hub += offset;
    if (rim.axisParticle != kNoParticle) rim.axisParticle += offset;
    model_.rims.push_back(rim);
  }
  // Robots: joint springs and named joints "<object>.<joint>" (docs/robotics.md).
  const auto jointBase = static_cast<std::int32_t>(model_.jointSprings.size());
  const auto torsionBase =
      static_cast<std::int32_t>(model_.torsionSprings.size() - g.torsionSprings.size());
  const auto linearBase =
      static_cast<std::int32_t>(model_.linearSprings.size() - g.linearSprings.size());
  for (JointSpring s : g.jointSprings) {
    for (ParticleIndex* p : {&s.a, &s.b, &s.c, &s.d}) *p += offset;
    model_.jointSprings.push_back(s);
  }
  // Surface mesh (MODEL §3.8) in model indices.
  ObjectInfo& info = model_.objects[static_cast<std::size_t>(id)];
  info.rigid = g.rigid;
  info.contact = g.contact;
  info.surfaceRadius = g.surfaceRadius;
  info.firstVertex = static_cast<std::int32_t>(model_.surfaceVertices.size());
  info.vertexCount = static_cast<std::int32_t>(g.surfaceVertices.size());
  info.firstTriangle = static_cast<std::int32_t>(model_.surfaceTriangles.size());
  info.triangleCount = static_cast<std::int32_t>(g.surfaceTriangles.size());
  for (SurfaceVertex v : g.surfaceVertices) {
    for (std::int32_t& particle : v.particle)
      if (particle >= 0) particle += offset;
    v.object = id;
    model_.surfaceVertices.push_back(v);
  }
  for (SurfaceTriangle t : g.surfaceTriangles) {
    for (std::int32_t& vertex : t.vertex) vertex += info.firstVertex;
    t.object = id;
    model_.surfaceTriangles.push_back(t);
  }
  for (Joint joint : g.joints) {
    joint.name = object.name + "." + joint.name;
    joint.connector += joint.kind == JointKind::kRevolute ? jointBase : torsionBase;
    if (joint.driveSpring >= 0) joint.driveSpring += linearBase;
    for (ParticleIndex& p : joint.motorParticles) p += offset;
    model_.joints.push_back(std::move(joint));
  }
  return placed;
}

std::int32_t ModelBuilder::addConnector(const LinearSpring& spring) {
  checkLinear("LinearSpring", spring, model_.particleCount());
  model_.linearSprings.push_back(spring);
  return static_cast<std::int32_t>(model_.linearSprings.size()) - 1;
}

std::int32_t ModelBuilder::addConnector(const TorsionSpring& spring) {
  checkTorsion("TorsionSpring", spring, model_.particleCount());
  model_.torsionSprings.push_back(spring);
  return static_cast<std::int32_t>(model_.torsionSprings.size()) - 1;
}

std::int32_t ModelBuilder::addConnector(const JointSpring& spring) {
  checkJoint("JointSpring", spring, model_.particleCount());
  model_.jointSprings.push_back(spring);
  return static_cast<std::int32_t>(model_.jointSprings.size()) - 1;
}

std::int32_t ModelBuilder::addJoint(const Joint& joint) {
  constexpr const char* kSpec = "Joint";
  if (joint.name.empty()) check::fail(kSpec, "name", "'name' must not be empty");
  for (const Joint& j : model_.joints)
    if (j.name == joint.name)
      check::fail(kSpec, "name", "duplicate joint name '" + joint.name + "'");
  const bool revolute = joint.kind == JointKind::kRevolute;
  const std::size_t connectors =
      revolute ? model_.jointSprings.size() : model_.torsionSprings.size();
  if (joint.inTree()) {
    // Made by addRigidTree before the tree is stored: its index is the next tree's.
    if (joint.tree != static_cast<std::int32_t>(model_.rigidTrees.size()) || joint.treeBody < 0 ||
        joint.connector != -1 || joint.driveSpring != -1 || joint.bodyLink != -1)
      check::fail(kSpec, "tree", "'tree' " + std::to_string(joint.tree) + " / 'treeBody' " +
                                     std::to_string(joint.treeBody) +
                                     ": a tree joint is made by addRigidTree, with no connectors");
  } else if (joint.connector < 0 || static_cast<std::size_t>(joint.connector) >= connectors)
    check::fail(kSpec, "connector",
                "'connector' " + std::to_string(joint.connector) + " is not a " +
                    (revolute ? "JS" : "TS") + " (" + std::to_string(connectors) + " placed)");
  if (joint.driveSpring != -1 &&
      (revolute || joint.driveSpring < 0 ||
       static_cast<std::size_t>(joint.driveSpring) >= model_.linearSprings.size()))
    check::fail(kSpec, "driveSpring",
                "'driveSpring' " + std::to_string(joint.driveSpring) +
                    " is not an LS of a prismatic joint");
  check::finite(kSpec, "zero", joint.zero, joint.kind == JointKind::kRevolute ? "rad" : "m");
  if (joint.bodyLink < -1 || joint.bodyLink >= static_cast<std::int32_t>(model_.bodyLinks.size()))
    check::fail(kSpec, "bodyLink",
                "'bodyLink' " + std::to_string(joint.bodyLink) + " is not a placed body link (" +
                    std::to_string(model_.bodyLinks.size()) + " placed)");
  for (std::int32_t b : joint.subtreeBodies)
    if (b < 0 || b >= static_cast<std::int32_t>(model_.bodies.size()))
      check::fail(kSpec, "subtreeBodies",
                  "'subtreeBodies': body " + std::to_string(b) + " is not placed (" +
                      std::to_string(model_.bodies.size()) + " placed)");
  check::nonNegative(kSpec, "servoStiffness", joint.servoStiffness, revolute ? "N·m/rad" : "N/m");
  check::nonNegative(kSpec, "servoDamping", joint.servoDamping, revolute ? "N·m·s/rad" : "N·s/m");
  check::finite(kSpec, "servoTarget", joint.servoTarget, revolute ? "rad" : "m");
  model_.joints.push_back(joint);
  return static_cast<std::int32_t>(model_.joints.size()) - 1;
}

std::int32_t ModelBuilder::addBody(const std::string& name, std::vector<ParticleIndex> particles,
                                   double frequency, double dampingRatio) {
  constexpr const char* kSpec = "RigidGroup";
  if (particles.empty()) check::fail(kSpec, "particles", "body '" + name + "' has no particles");
  check::nonNegative(kSpec, "frequency", frequency, "rad/s");
  check::nonNegative(kSpec, "dampingRatio", dampingRatio, "-");
  RigidGroup body;
  body.name = name;
  double mass = 0.0;
  Vec3 moment{};
  for (ParticleIndex p : particles) {
    if (p < 0 || p >= model_.particleCount())
      check::fail(kSpec, "particles",
                  "body '" + name + "': particle " + std::to_string(p) + " is not placed (" +
                      std::to_string(model_.particleCount()) + " placed)");
    mass += model_.mass[static_cast<std::size_t>(p)];
    moment += position_[static_cast<std::size_t>(p)] * model_.mass[static_cast<std::size_t>(p)];
  }
  const Vec3 center = moment / mass;
  for (ParticleIndex p : particles)
    body.rest.push_back(position_[static_cast<std::size_t>(p)] - center);
  body.particles = std::move(particles);
  body.frequency = frequency;
  body.dampingRatio = dampingRatio;
  model_.bodies.push_back(std::move(body));
  return static_cast<std::int32_t>(model_.bodies.size()) - 1;
}

Vec3 ModelBuilder::bodyCenter(std::int32_t body) const {
  const RigidGroup& b = model_.bodies.at(static_cast<std::size_t>(body));
  double mass = 0.0;
  Vec3 moment{};
  for (ParticleIndex p : b.particles) {
    mass += model_.mass[static_cast<std::size_t>(p)];
    moment += position_[static_cast<std::size_t>(p)] * model_.mass[static_cast<std::size_t>(p)];
  }
  return moment / mass;
}

std::int32_t ModelBuilder::addBodyLink(BodyLinkKind kind, std::int32_t child, std::int32_t parent,
                                       const Vec3& point, const Vec3& axis, const BodyLink& gains) {
  constexpr const char* kSpec = "BodyLink";
  const auto bodies = static_cast<std::int32_t>(model_.bodies.size());
  if (child < 0 || parent < 0 || child >= bodies || parent >= bodies || child == parent)
    check::fail(kSpec, "child",
                "bodies " + std::to_string(child) + " and " + std::to_string(parent) +
                    " are not two placed bodies (" + std::to_string(bodies) + " placed)");
  check::finite(kSpec, "point", point, "m");
  if (!(norm(axis) > 0.0)) check::fail(kSpec, "axis", "'axis' must not be zero");
  check::nonNegative(kSpec, "stiffness", gains.stiffness, "N/m");
  check::nonNegative(kSpec, "damping", gains.damping, "N·s/m");
  check::nonNegative(kSpec, "angularStiffness", gains.angularStiffness, "N·m/rad");
  check::nonNegative(kSpec, "angularDamping", gains.angularDamping, "N·m·s/rad");
  for (std::int32_t b : gains.weightBodies)
    if (b < 0 || b >= bodies)
      check::fail(kSpec, "weightBodies",
                  "'weightBodies': body " + std::to_string(b) + " is not placed (" +
                      std::to_string(bodies) + " placed)");
  BodyLink link = gains;
  link.kind = kind;
  link.child = child;
  link.parent = parent;
  const Vec3 n = axis / norm(axis);
  const Vec3 trial = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 normal = cross(n, trial) / norm(cross(n, trial));
  // The rest frames are the world's as built (rest offsets from the centres).
  link.pointInChild = point - bodyCenter(child);
  link.pointInParent = point - bodyCenter(parent);
  link.axisInChild = link.axisInParent = n;
  link.normalInChild = link.normalInParent = normal;
  model_.bodyLinks.push_back(link);
  return static_cast<std::int32_t>(model_.bodyLinks.size()) - 1;
}

void ModelBuilder::excludeContact(std::int32_t objectA, std::int32_t objectB) {
  const auto objects = static_cast<std::int32_t>(model_.objects.size());
  if (objectA < 0 || objectB < 0 || objectA >= objects || objectB >= objects || objectA == objectB)
    check::fail("excludeContact", "objects",
                "objects " + std::to_string(objectA) + " and " + std::to_string(objectB) +
                    " are not two placed objects (" + std::to_string(objects) + " placed)");
  const std::array<std::int32_t, 2> pair{std::min(objectA, objectB), std::max(objectA, objectB)};
  auto& pairs = model_.noContactPairs;
  const auto at = std::lower_bound(pairs.begin(), pairs.end(), pair);
  if (at == pairs.end() || *at != pair) pairs.insert(at, pair);
}

void ModelBuilder::excludeContactWithin(const std::vector<std::int32_t>& objects) {
  const auto count = static_cast<std::int32_t>(model_.objects.size());
  std::int32_t group = 0;
  bool grouped = false;
  for (const std::int32_t o : objects) {
    if (o < 0 || o >= count)
      check::fail("excludeContactWithin", "objects",
                  "object " + std::to_string(o) + " is not a placed object (" +
                      std::to_string(count) + " placed)");
    grouped = grouped || model_.objects[static_cast<std::size_t>(o)].contactGroup >= 0;
  }
  if (grouped) {
    // (An object has one group: pairs, as few objects as a hand-made call lists.)
    for (std::size_t i = 0; i < objects.size(); ++i)
      for (std::size_t j = i + 1; j < objects.size(); ++j)
        if (objects[i] != objects[j]) excludeContact(objects[i], objects[j]);
    return;
  }
  for (const ObjectInfo& info : model_.objects) group = std::max(group, info.contactGroup + 1);
  for (const std::int32_t o : objects)
    model_.objects[static_cast<std::size_t>(o)].contactGroup = group;
}

std::int32_t ModelBuilder::addRigidTree(RigidTree tree, std::vector<double> q, std::vector<double> v) {
  const std::string what = "rigid tree '" + tree.multibody.name + "'";
  try {
    finalize(tree.multibody);
  } catch (const std::invalid_argument& error) {
    throw SpecError("addRigidTree", "multibody", what + ": " + error.what());
  }
  const Multibody& mb = tree.multibody;
  if (q.empty()) q = neutralConfiguration(mb);
  if (v.empty()) v.assign(static_cast<std::size_t>(mb.velocityCount), 0.0);
  if (q.size() != static_cast<std::size_t>(mb.positionCount) ||
      v.size() != static_cast<std::size_t>(mb.velocityCount))
    throw SpecError("addRigidTree", "q", what + ": " + std::to_string(q.size()) + " coordinates and " +
                    std::to_string(v.size()) + " rates given, expected " +
                    std::to_string(mb.positionCount) + " and " + std::to_string(mb.velocityCount));
  for (double x : q)
    if (!std::isfinite(x)) throw SpecError("addRigidTree", "q", what + ": a coordinate is not finite");
  const ParticleIndex n = model_.particleCount();
  for (const BodyParticle& bp : tree.particles) {
    if (bp.particle < 0 || bp.particle >= n || !model_.isFixed(bp.particle))
      throw SpecError("addRigidTree", "particles", what + ": particle " + std::to_string(bp.particle) +
                      " must be a placed fixed particle");
    if (bp.body < 0 || bp.body >= static_cast<std::int32_t>(mb.bodies.size()))
      throw SpecError("addRigidTree", "particles", what + ": body " + std::to_string(bp.body) + " does not exist");
  }
  MultibodyKinematics kin;
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  for (const BodyParticle& bp : tree.particles) {
    const auto i = static_cast<std::size_t>(bp.particle);
    position_[i] = kin.X_WB[static_cast<std::size_t>(bp.body)] * bp.p_BP;
    velocity_[i] = pointVelocity(kin, bp.body, position_[i]);
  }
  model_.carriedBy.resize(static_cast<std::size_t>(n), -1);
  for (const BodyParticle& bp : tree.particles) {
    if (model_.carriedBy[static_cast<std::size_t>(bp.particle)] >= 0)
      throw SpecError("addRigidTree", "particles", what + ": particle " + std::to_string(bp.particle) +
                                                       " is carried by another tree already");
    model_.carriedBy[static_cast<std::size_t>(bp.particle)] = static_cast<std::int32_t>(model_.rigidTrees.size());
  }
  // Every revolute and prismatic joint of the tree is a model joint (Joint::inTree):
  // read, driven and controlled by name as any other.
  const auto index = static_cast<std::int32_t>(model_.rigidTrees.size());
  tree.jointOfRate.assign(static_cast<std::size_t>(mb.velocityCount), -1);
  for (std::size_t b = 0; b < mb.bodies.size(); ++b) {
    const MultibodyBody& body = mb.bodies[b];
    if (velocityCountOf(body.joint) != 1) continue;
    Joint joint;
    joint.name = body.jointName.empty() ? body.name : body.jointName;
    joint.kind = body.joint == BodyJointKind::kRevolute ? JointKind::kRevolute : JointKind::kPrismatic;
    joint.tree = index;
    joint.treeBody = static_cast<std::int32_t>(b);
    joint.servoTarget = q[static_cast<std::size_t>(body.qStart)];
    tree.jointOfRate[static_cast<std::size_t>(body.vStart)] = addJoint(joint);
  }
  model_.rigidTrees.push_back(std::move(tree));
  treePositions_.push_back(std::move(q));
  treeVelocities_.push_back(std::move(v));
  return static_cast<std::int32_t>(model_.rigidTrees.size()) - 1;
}

BuiltModel ModelBuilder::build() && {
  // Internal check: every method checked its arguments, so the model is consistent.
  if (const std::string problem = checkModel(model_); !problem.empty())
    throw std::logic_error("ModelBuilder: internal error, the model is inconsistent: " + problem);
  BuiltModel built{std::move(model_), {}};
  built.initial = State::sizedFor(built.model);
  built.initial.position = std::move(position_);
  built.initial.velocity = std::move(velocity_);
  built.initial.treePositions = std::move(treePositions_);
  built.initial.treeVelocities = std::move(treeVelocities_);
  *this = ModelBuilder{};
  return built;
}

}  // namespace robophi::build
