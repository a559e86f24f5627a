// robophi info: objects and URDF links, built against declared.
#include "run/object_report.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "robophi/multibody.h"

namespace robophi {

namespace {

double relative(double built, double declared) {
  return declared != 0.0 ? std::abs(built - declared) / std::abs(declared) : 0.0;
}

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json tensor(const build::Inertia& i) {
  return {{"xx", i.xx}, {"yy", i.yy}, {"zz", i.zz}, {"xy", i.xy}, {"xz", i.xz}, {"yz", i.yz}};
}

// A rigid tree body's own mass properties (docs/model.md §7: the URDF's, exactly)
// in the world at the scene's start: its particles carry no inertia of their own.
build::MassProperties bodyMassProperties(const Multibody& mb, const MultibodyKinematics& kin,
                                         std::size_t body) {
  const BodyMassProperties& mp = mb.bodies[body].mass;
  const Pose& X_WB = kin.X_WB[body];
  const Mat3 I = X_WB.rotation * mp.inertia * transpose(X_WB.rotation);
  build::MassProperties world;
  world.mass = mp.mass;
  world.centerOfMass = X_WB * mp.centerOfMass;
  world.inertia = {I.m[0][0], I.m[1][1], I.m[2][2], I.m[0][1], I.m[0][2], I.m[1][2]};
  return world;
}

}  // namespace

SceneReport reportScene(const Scene& scene) {
  SceneReport report;
  report.file = scene.sourcePath;
  const Model& model = scene.model;
  // The rigid trees' bodies at the start: the body carrying each tree particle.
  std::vector<MultibodyKinematics> kinematics(model.rigidTrees.size());
  std::map<ParticleIndex, std::pair<std::size_t, std::size_t>> carrier;  // particle: (tree, body)
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const RigidTree& tree = model.rigidTrees[t];
    updateKinematics(tree.multibody, scene.initial.treePositions[t].data(), kinematics[t]);
    for (const BodyParticle& bp : tree.particles)
      carrier[bp.particle] = {t, static_cast<std::size_t>(bp.body)};
  }
  std::map<std::string, std::size_t> byName;
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    const ObjectInfo& info = model.objects[o];
    ObjectReport r;
    r.name = info.name;
    r.kind = info.kind;
    r.particles = info.particleCount;
    std::vector<Vec3> position;
    std::vector<double> mass;
    for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i) {
      position.push_back(scene.initial.position[static_cast<std::size_t>(i)]);
      mass.push_back(model.mass[i]);
      r.fixedParticles += model.isFixed(i) ? 1 : 0;
    }
    if (const auto carried = carrier.find(info.firstParticle);
        info.particleCount > 0 && carried != carrier.end()) {
      const auto [t, body] = carried->second;
      r.kind = "rigid body";
      r.rigidBody = true;
      r.built = bodyMassProperties(model.rigidTrees[t].multibody, kinematics[t], body);
      r.principalMoments = build::principalMoments(r.built.inertia);
    } else if (!position.empty()) {
      r.built = build::massProperties(position, mass);
      r.principalMoments = build::principalMoments(r.built.inertia);
    }
    byName[r.name] = report.objects.size();
    report.objects.push_back(std::move(r));
  }
  for (const auto& robot : scene.urdfRobots) {
    for (const build::UrdfLink& link : robot->links) {
      if (link.object < 0) continue;
      const std::string& objectName = robot->objects[static_cast<std::size_t>(link.object)].name;
      const auto found = byName.find(objectName);
      if (found == byName.end()) continue;
      ObjectReport& r = report.objects[found->second];
      if (link.attachedTo != &link - robot->links.data()) {
        r.frames.push_back(link.name);
        continue;
      }
      if (link.carrierObject >= 0) {
        // The carriers are part of the link's mass (a virtual object of their own).
        const std::string& carrierName =
            robot->objects[static_cast<std::size_t>(link.carrierObject)].name;
        const auto carriers = byName.find(carrierName);
        if (carriers != byName.end()) {
          report.objects[carriers->second].partOf = r.name;
          std::vector<Vec3> position;
          std::vector<double> mass;
          for (const std::string& name : {objectName, carrierName}) {
            const ObjectInfo& info = model.objects[byName[name]];
            for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount;
                 ++i) {
              position.push_back(scene.initial.position[static_cast<std::size_t>(i)]);
              mass.push_back(model.mass[i]);
            }
          }
          r.carriers = report.objects[carriers->second].particles;
          r.built = build::massProperties(position, mass);
          r.principalMoments = build::principalMoments(r.built.inertia);
        }
      }
      r.urdfLink = true;
      r.urdfFile = robot->file;
      r.link = link.name;
      r.notional = link.notional;
      r.declared = link.declaredWorld;
      r.declaredMoments = build::principalMoments(r.declared.inertia);
      r.notes = link.notes;
      if (!r.notional) {
        r.massError = relative(r.built.mass, r.declared.mass);
        r.centerOfMassError = norm(r.built.centerOfMass - r.declared.centerOfMass);
        for (int k = 0; k < 3; ++k)
          r.momentError[k] = relative(r.principalMoments[k], r.declaredMoments[k]);
      }
    }
  }
  // Carrier objects are reported with their link.
  std::erase_if(report.objects, [](const ObjectReport& r) { return !r.partOf.empty(); });
  return report;
}

nlohmann::json reportJson(const SceneReport& report) {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectReport& r : report.objects) {
    nlohmann::json o = {{"name", r.name},
                        {"kind", r.kind},
                        {"particles", r.particles},
                        {"carriers", r.carriers},
                        {"fixedParticles", r.fixedParticles},
                        {"mass", r.built.mass},
                        {"centerOfMass", vec(r.built.centerOfMass)},
                        {"inertia", tensor(r.built.inertia)},
                        {"principalMoments", r.principalMoments}};
    if (r.urdfLink) {
      o["urdf"] = {{"file", r.urdfFile},
                   {"link", r.link},
                   {"notional", r.notional},
                   {"mass", r.declared.mass},
                   {"centerOfMass", vec(r.declared.centerOfMass)},
                   {"inertia", tensor(r.declared.inertia)},
                   {"principalMoments", r.declaredMoments},
                   {"frames", r.frames}};
      if (!r.notional)
        o["errors"] = {{"mass", r.massError},
                       {"centerOfMass", r.centerOfMassError},
                       {"principalMoments", r.momentError}};
      o["notes"] = r.notes;
    }
    objects.push_back(std::move(o));
  }
  return {{"file", report.file}, {"objects", std::move(objects)}};
}

std::string reportText(const SceneReport& report) {
  std::string out = fmt::format("{}: {} objects\n", report.file, report.objects.size());
  out += fmt::format("{:<32} {:>6} {:>10} {:>28} {:>32}\n", "object", "parts", "mass kg",
                     "centre of mass m", "principal moments kg·m²");
  const auto row = [&](const std::string& label, const std::string& count,
                       const build::MassProperties& p, const std::array<double, 3>& m) {
    out += fmt::format(
        "{:<32} {:>6} {:>10.4g} [{:>8.4f} {:>8.4f} {:>8.4f}] [{:>9.3e} {:>9.3e} {:>9.3e}]\n", label,
        count, p.mass, p.centerOfMass.x, p.centerOfMass.y, p.centerOfMass.z, m[0], m[1], m[2]);
  };
  for (const ObjectReport& r : report.objects) {
    row(r.name, std::to_string(r.particles), r.built, r.principalMoments);
    if (r.rigidBody)
      out += "    rigid body: its body's own mass properties (the URDF's, after the adjustments\n"
             "    listed when it loads); its particles are its collision surface\n";
    if (!r.urdfLink) continue;
    if (r.notional) {
      out += "    notional base: the URDF gives it no mass (values above are robophi's)\n";
    } else {
      row("    declared (URDF)", "", r.declared, r.declaredMoments);
      out += fmt::format(
          "    errors: mass {:.2e}, centre of mass {:.2e} m, moments {:.2e} {:.2e} {:.2e}\n",
          r.massError, r.centerOfMassError, r.momentError[0], r.momentError[1], r.momentError[2]);
    }
    if (!r.frames.empty()) {
      out += "    frames moving with it:";
      for (const std::string& f : r.frames) out += " " + f;
      out += "\n";
    }
    for (const std::string& note : r.notes) out += "    note: " + note + "\n";
  }
  return out;
}

}  // namespace robophi
