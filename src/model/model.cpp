#include "robophi/model.h"

#include <cmath>
#include <numbers>

#include "core/text.h"

namespace robophi {

Material combineMaterials(const Material& a, const Material& b) {
  const auto series = [](double x, double y) { return x + y > 0.0 ? x * y / (x + y) : 0.0; };
  Material pair;
  pair.name = a.name + "+" + b.name;
  pair.contactStiffness = series(a.contactStiffness, b.contactStiffness);
  pair.contactDamping = series(a.contactDamping, b.contactDamping);
  pair.staticFriction = std::sqrt(a.staticFriction * b.staticFriction);
  pair.kineticFriction = std::sqrt(a.kineticFriction * b.kineticFriction);
  pair.rollingResistance = 0.5 * (a.rollingResistance + b.rollingResistance);
  return pair;
}

ParticleIndex Model::addParticle(double particleMass, double particleRadius, bool fixed,
                                 std::int32_t object, double damping) {
  const auto index = particleCount();
  mass.push_back(particleMass);
  inverseMass.push_back(fixed ? 0.0 : 1.0 / particleMass);
  radius.push_back(particleRadius);
  linearDamping.push_back(damping);
  objectOf.push_back(object);
  if (!carriedBy.empty()) carriedBy.push_back(-1);
  if (object >= 0 && object < static_cast<std::int32_t>(objects.size())) {
    auto& info = objects[object];
    if (info.particleCount == 0) info.firstParticle = index;
    ++info.particleCount;
  }
  return index;
}

std::int32_t Model::addObject(std::string name, std::string kind, std::int32_t material) {
  objects.push_back(ObjectInfo{std::move(name), std::move(kind), particleCount(), 0, material});
  return static_cast<std::int32_t>(objects.size()) - 1;
}

namespace {

bool inRange(ParticleIndex i, ParticleIndex n) { return i >= 0 && i < n; }

}  // namespace

std::string checkConnector(const LinearSpring& s, std::size_t k, ParticleIndex n) {
  if (!inRange(s.a, n) || !inRange(s.b, n) || s.a == s.b)
    return detail::text("LS {}: particles ({}, {}) must be two different particles of {}", k, s.a,
                        s.b, n);
  if (!(s.restLength > 0.0) || !std::isfinite(s.restLength))
    return detail::text("LS {}: rest length {} must be > 0", k, s.restLength);
  if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0) || !std::isfinite(s.stiffness) ||
      !std::isfinite(s.damping))
    return detail::text("LS {}: stiffness {} and damping {} must be >= 0", k, s.stiffness,
                        s.damping);
  return {};
}

std::string checkConnector(const TorsionSpring& s, std::size_t k, ParticleIndex n) {
  if (!inRange(s.a, n) || !inRange(s.b, n) || !inRange(s.c, n) || s.a == s.c || s.b == s.c ||
      s.a == s.b)
    return detail::text("TS {}: particles ({}, {}, {}) must be three different particles of {}", k,
                        s.a, s.c, s.b, n);
  if (!(s.restAngle >= 0.0 && s.restAngle <= std::numbers::pi))
    return detail::text("TS {}: rest angle {} must be in [0, π]", k, s.restAngle);
  if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0) || !std::isfinite(s.stiffness) ||
      !std::isfinite(s.damping))
    return detail::text("TS {}: stiffness {} and damping {} must be >= 0", k, s.stiffness,
                        s.damping);
  return {};
}

std::string checkConnector(const JointSpring& s, std::size_t k, ParticleIndex n) {
  if (!inRange(s.a, n) || !inRange(s.b, n) || !inRange(s.c, n) || !inRange(s.d, n) || s.a == s.c ||
      s.b == s.c || s.a == s.b || s.d == s.c)
    return detail::text("JS {}: particles ({}, {}, {}, {}) must be different particles of {}", k,
                        s.a, s.c, s.b, s.d, n);
  if (!(s.restAngle >= 0.0 && s.restAngle < 2.0 * std::numbers::pi))
    return detail::text("JS {}: rest angle {} must be in [0, 2π)", k, s.restAngle);
  if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0) || !std::isfinite(s.stiffness) ||
      !std::isfinite(s.damping))
    return detail::text("JS {}: stiffness {} and damping {} must be >= 0", k, s.stiffness,
                        s.damping);
  return {};
}

std::string checkJointDrive(const JointDrive& d) {
  const auto bad = [](const char* field, double value, const char* rule) {
    return detail::text("drive {} = {} must be {}", field, value, rule);
  };
  if (!std::isfinite(d.effort)) return bad("effort", d.effort, "finite");
  if (!std::isfinite(d.targetRate)) return bad("targetRate", d.targetRate, "finite");
  if (!(d.rateGain >= 0.0) || !std::isfinite(d.rateGain))
    return bad("rateGain", d.rateGain, "finite and >= 0");
  if (!(d.effortLimit > 0.0)) return bad("effortLimit", d.effortLimit, "> 0");
  if (!(d.velocityLimit > 0.0)) return bad("velocityLimit", d.velocityLimit, "> 0");
  if (!(d.damping >= 0.0) || !std::isfinite(d.damping))
    return bad("damping", d.damping, "finite and >= 0");
  if (!(d.friction >= 0.0) || !std::isfinite(d.friction))
    return bad("friction", d.friction, "finite and >= 0");
  if (!(d.frictionVelocity > 0.0) || !std::isfinite(d.frictionVelocity))
    return bad("frictionVelocity", d.frictionVelocity, "finite and > 0");
  return {};
}

std::string checkModel(const Model& model) {
  const auto n = model.particleCount();
  const auto size = static_cast<std::size_t>(n);
  if (model.mass.size() != size || model.inverseMass.size() != size ||
      model.radius.size() != size || model.linearDamping.size() != size ||
      model.objectOf.size() != size) {
    return "particle arrays have different sizes";
  }
  for (ParticleIndex i = 0; i < n; ++i) {
    if (!(model.mass[i] > 0.0) || !std::isfinite(model.mass[i]))
      return detail::text("particle {}: mass {} must be a positive number (kg)", i, model.mass[i]);
    if (!(model.radius[i] > 0.0) || !std::isfinite(model.radius[i]))
      return detail::text("particle {}: radius {} must be a positive number (m)", i,
                          model.radius[i]);
    if (!(model.linearDamping[i] >= 0.0))
      return detail::text("particle {}: damping {} must be >= 0 (N·s/m)", i,
                          model.linearDamping[i]);
  }
  if (!model.carriedBy.empty() && model.carriedBy.size() != size)
    return detail::text("carriedBy has {} entries for {} particles", model.carriedBy.size(), size);
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const RigidTree& tree = model.rigidTrees[t];
    for (const BodyParticle& bp : tree.particles)
      if (bp.particle >= 0 && bp.particle < n &&
          (model.carriedBy.empty() || model.carriedBy[static_cast<std::size_t>(bp.particle)] != static_cast<std::int32_t>(t)))
        return detail::text("rigid tree {}: particle {} is not marked carried by it (carriedBy)", t, bp.particle);
    const Multibody& mb = tree.multibody;
    if (static_cast<std::size_t>(mb.velocityCount) != mb.dofBody.size())
      return detail::text("rigid tree {} '{}': not finalized (finalize(Multibody))", t, mb.name);
    const auto bodies = static_cast<std::int32_t>(mb.bodies.size());
    for (const BodyParticle& bp : tree.particles) {
      if (bp.particle < 0 || bp.particle >= n || bp.body < 0 || bp.body >= bodies)
        return detail::text("rigid tree {} '{}': particle {} on body {} out of range", t, mb.name,
                            bp.particle, bp.body);
      if (model.inverseMass[bp.particle] != 0.0)
        return detail::text("rigid tree {} '{}': particle {} must be fixed (the body moves it)", t,
                            mb.name, bp.particle);
    }
    const auto nv = static_cast<std::size_t>(mb.velocityCount);
    if (tree.jointOfRate.size() != nv)
      return detail::text("rigid tree {} '{}': jointOfRate has {} entries for {} rates", t, mb.name,
                          tree.jointOfRate.size(), nv);
    for (std::size_t i = 0; i < nv; ++i) {
      const std::int32_t k = tree.jointOfRate[i];
      if (k == -1) continue;
      const auto own = [&] {
        if (k < 0 || k >= static_cast<std::int32_t>(model.joints.size())) return false;
        const Joint& j = model.joints[static_cast<std::size_t>(k)];
        return j.tree == static_cast<std::int32_t>(t) && j.treeBody >= 0 &&
               static_cast<std::size_t>(j.treeBody) < mb.bodies.size() &&
               mb.bodies[static_cast<std::size_t>(j.treeBody)].vStart == static_cast<std::int32_t>(i);
      };
      if (!own())
        return detail::text("rigid tree {} '{}': rate {} names joint {}, not its own", t, mb.name, i, k);
    }
  }
  for (std::size_t k = 0; k < model.objects.size(); ++k) {
    if (model.objects[k].contactGroup < -1)
      return detail::text("objects {} '{}': contactGroup {} must be >= 0, or -1 for none", k,
                          model.objects[k].name, model.objects[k].contactGroup);
  }
  for (std::size_t k = 0; k < model.noContactPairs.size(); ++k) {
    const auto& [a, b] = model.noContactPairs[k];
    const auto objectCount = static_cast<std::int32_t>(model.objects.size());
    if (a < 0 || a >= b || b >= objectCount ||
        (k > 0 && !(model.noContactPairs[k - 1] < model.noContactPairs[k])))
      return detail::text("noContactPairs {}: {{{}, {}}} must be objects a < b (of {}), sorted", k,
                          a, b, objectCount);
  }
  for (std::size_t k = 0; k < model.linearSprings.size(); ++k) {
    if (std::string problem = checkConnector(model.linearSprings[k], k, n); !problem.empty())
      return problem;
  }
  for (std::size_t k = 0; k < model.torsionSprings.size(); ++k) {
    if (std::string problem = checkConnector(model.torsionSprings[k], k, n); !problem.empty())
      return problem;
  }
  for (std::size_t k = 0; k < model.jointSprings.size(); ++k) {
    if (std::string problem = checkConnector(model.jointSprings[k], k, n); !problem.empty())
      return problem;
  }
  const auto objects = static_cast<std::int32_t>(model.objects.size());
  const auto materials = static_cast<std::int32_t>(model.materials.size());
  if (materials == 0) return "the model needs at least one material (the default)";
  for (ParticleIndex i = 0; i < n; ++i) {
    if (model.objectOf[i] < -1 || model.objectOf[i] >= objects)
      return detail::text("particle {}: object {} does not exist (there are {})", i,
                          model.objectOf[i], objects);
  }
  for (std::int32_t o = 0; o < objects; ++o) {
    const ObjectInfo& info = model.objects[static_cast<std::size_t>(o)];
    if (info.material < 0 || info.material >= materials)
      return detail::text("object '{}': material {} does not exist (there are {})", info.name,
                          info.material, materials);
  }
  for (std::size_t k = 0; k < model.rims.size(); ++k) {
    const RimRing& rim = model.rims[k];
    if (rim.isCylinder()) {  // an imported robot's wheel (NaN radii fail here)
      const auto inRing = [&](ParticleIndex i) {
        return i >= rim.first && i < rim.first + rim.count;
      };
      if (!(rim.sphereRadius > 0.0 && std::isfinite(rim.sphereRadius)) ||
          !(rim.halfLength >= 0.0 && std::isfinite(rim.halfLength)) ||
          !std::isfinite(rim.axialOffset) || rim.count < 2 || rim.first < 0 ||
          rim.first + rim.count > n || !inRing(rim.hub) || !inRing(rim.axisParticle) ||
          rim.hub == rim.axisParticle)
        return detail::text(
            "rim {} (a cylinder): particles [{}, {}) with radius {} m, half length {} m, offset "
            "{} m about the axis {} -> {} are not >= 2 particles of the {} holding two distinct "
            "axis particles, with a finite radius > 0 and half length >= 0",
            k, rim.first, rim.first + rim.count, rim.sphereRadius, rim.halfLength, rim.axialOffset,
            rim.hub, rim.axisParticle, n);
      continue;
    }
    if (rim.sphereRadius != 0.0) {  // a ball (NaN and negative radii fail here)
      if (!(rim.sphereRadius > 0.0 && std::isfinite(rim.sphereRadius)) || rim.count < 2 ||
          rim.first < 0 || rim.first + rim.count > n)
        return detail::text(
            "rim {} (a ball): particles [{}, {}) with sphere radius {} m are not >= 2 particles of "
            "the {} "
            "with a finite radius > 0",
            k, rim.first, rim.first + rim.count, rim.sphereRadius, n);
      continue;
    }
    if (rim.count < 3 || rim.first < 0 || rim.first + rim.count > n || rim.hub < 0 ||
        rim.hub >= n || (rim.hub >= rim.first && rim.hub < rim.first + rim.count))
      return detail::text(
          "rim {}: particles [{}, {}) about hub {} are not a ring of >= 3 particles of the {}", k,
          rim.first, rim.first + rim.count, rim.hub, n);
  }
  for (const ContactPairOverride& pair : model.contact.pairOverrides) {
    if (pair.objectA < 0 || pair.objectA >= objects || pair.objectB < -1 || pair.objectB >= objects)
      return detail::text("contact pair ({}, {}): object does not exist (there are {})",
                          pair.objectA, pair.objectB, objects);
  }
  if (model.contact.leafSize < 1)
    return detail::text("contact leafSize {} must be >= 1", model.contact.leafSize);
  if (!(model.contact.neighbourSkin >= 0.0) || !std::isfinite(model.contact.neighbourSkin))
    return detail::text("contact neighbourSkin {} must be finite and >= 0",
                        model.contact.neighbourSkin);
  for (const RigidGroup& body : model.bodies) {
    if (body.particles.empty() || body.rest.size() != body.particles.size())
      return detail::text("body '{}': {} particles and {} rest offsets", body.name,
                          body.particles.size(), body.rest.size());
    for (ParticleIndex p : body.particles)
      if (p < 0 || p >= n)
        return detail::text("body '{}': particle {} does not exist", body.name, p);
    if (!(body.frequency >= 0.0) || !std::isfinite(body.frequency) || !(body.dampingRatio >= 0.0) ||
        !std::isfinite(body.dampingRatio))
      return detail::text("body '{}': frequency {} and damping ratio {} must be finite and >= 0",
                          body.name, body.frequency, body.dampingRatio);
  }
  for (const BodyLink& link : model.bodyLinks) {
    const auto bodies = static_cast<std::int32_t>(model.bodies.size());
    if (link.child < 0 || link.parent < 0 || link.child >= bodies || link.parent >= bodies ||
        link.child == link.parent)
      return detail::text("body link {}-{}: not two bodies of the {}", link.child, link.parent,
                          bodies);
    for (double v : {link.stiffness, link.damping, link.angularStiffness, link.angularDamping})
      if (!(v >= 0.0) || !std::isfinite(v))
        return detail::text("body link {}-{}: gain {} must be finite and >= 0", link.child,
                            link.parent, v);
    for (std::int32_t b : link.weightBodies)
      if (b < 0 || b >= bodies)
        return detail::text("body link {}-{}: weight body {} is not one of the {}", link.child,
                            link.parent, b, bodies);
  }
  for (const auto& joint : model.joints) {
    const auto count = joint.kind == JointKind::kRevolute ? model.jointSprings.size()
                                                          : model.torsionSprings.size();
    if (joint.inTree()) {
      if (static_cast<std::size_t>(joint.tree) >= model.rigidTrees.size())
        return detail::text("joint '{}': rigid tree {} does not exist", joint.name, joint.tree);
      const Multibody& mb = model.rigidTrees[static_cast<std::size_t>(joint.tree)].multibody;
      if (joint.treeBody < 0 || static_cast<std::size_t>(joint.treeBody) >= mb.bodies.size() ||
          velocityCountOf(mb.bodies[static_cast<std::size_t>(joint.treeBody)].joint) != 1)
        return detail::text("joint '{}': body {} of rigid tree {} has no revolute or prismatic joint",
                            joint.name, joint.treeBody, joint.tree);
    } else if (joint.connector < 0 || static_cast<std::size_t>(joint.connector) >= count)
      return detail::text("joint '{}': connector {} does not exist", joint.name, joint.connector);
    if (const std::string problem = checkJointDrive(joint.drive); !problem.empty())
      return detail::text("joint '{}': {}", joint.name, problem);
    if (!joint.motorParticles.empty() && joint.kind != JointKind::kRevolute)
      return detail::text("joint '{}': motor particles on a prismatic joint", joint.name);
    for (ParticleIndex p : joint.motorParticles)
      if (p < 0 || p >= model.particleCount())
        return detail::text("joint '{}': motor particle {} does not exist", joint.name, p);
    if (joint.bodyLink < -1 || joint.bodyLink >= static_cast<std::int32_t>(model.bodyLinks.size()))
      return detail::text("joint '{}': body link {} does not exist", joint.name, joint.bodyLink);
    for (std::int32_t b : joint.subtreeBodies)
      if (b < 0 || b >= static_cast<std::int32_t>(model.bodies.size()))
        return detail::text("joint '{}': subtree body {} does not exist", joint.name, b);
    for (const auto& [field, value] : {std::pair{"servoStiffness", joint.servoStiffness},
                                       std::pair{"servoDamping", joint.servoDamping}})
      if (!(value >= 0.0) || !std::isfinite(value))
        return detail::text("joint '{}': {} = {} must be finite and >= 0", joint.name, field,
                            value);
    if (!std::isfinite(joint.servoTarget))
      return detail::text("joint '{}': servoTarget = {} must be finite", joint.name,
                          joint.servoTarget);
    if (joint.driveSpring >= 0 &&
        static_cast<std::size_t>(joint.driveSpring) >= model.linearSprings.size())
      return detail::text("joint '{}': drive spring {} does not exist", joint.name,
                          joint.driveSpring);
  }
  return {};
}

}  // namespace robophi
