// The world description of a run (world.json), for the replay page: see
// output/world_view.h and docs/viewer.md "World".
#include "output/world_view.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "output/results_folder.h"
#include "output/visuals_view.h"
#include "robophi/build/goals.h"

namespace robophi::output {

namespace {

using Json = nlohmann::ordered_json;

Json vec(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

bool sameVec(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// The security distance (m) of each environment sphere and box that a robotics
// obstacle made (build::addObstacle grows it by that much); 0 for the others.
void securityDistances(const Scene& scene, std::vector<double>& spheres,
                       std::vector<double>& boxes) {
  const Environment& env = scene.model.environment;
  spheres.assign(env.spheres.size(), 0.0);
  boxes.assign(env.boxes.size(), 0.0);
  std::vector<bool> sphereTaken(env.spheres.size(), false), boxTaken(env.boxes.size(), false);
  for (const build::ObstacleSpec& o : scene.obstacles) {
    const double margin = o.securityDistance;
    if (o.shape == build::ObstacleShape::kSphere) {
      for (std::size_t k = 0; k < env.spheres.size(); ++k) {
        if (!sphereTaken[k] && sameVec(env.spheres[k].center, o.center) &&
            env.spheres[k].radius == o.radius + margin) {
          sphereTaken[k] = true;
          spheres[k] = margin;
          break;
        }
      }
    } else {
      const Vec3 half = o.size * 0.5 + Vec3{margin, margin, margin};
      for (std::size_t k = 0; k < env.boxes.size(); ++k) {
        if (!boxTaken[k] && sameVec(env.boxes[k].center, o.center) &&
            sameVec(env.boxes[k].halfExtents, half)) {
          boxTaken[k] = true;
          boxes[k] = margin;
          break;
        }
      }
    }
  }
}

Json objectsJson(const Model& model) {
  Json objects = Json::array();
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    const ObjectInfo& info = model.objects[o];
    bool allFixed = info.particleCount > 0;
    for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i)
      allFixed = allFixed && i < model.particleCount() && model.isFixed(i);
    objects.push_back({{"name", info.name},
                       {"kind", info.kind},
                       {"first", info.firstParticle},
                       {"count", info.particleCount},
                       {"fixed", allFixed},
                       {"virtual", !info.contact.touches}});
  }
  return objects;
}

Json goalsJson(const Scene& scene) {
  Json goals = Json::array();
  for (std::size_t g = 0; g < scene.robotics.goals.size(); ++g) {
    const build::GoalSpec& goal = scene.robotics.goals[g];
    Json positions = Json::array();
    for (const Vec3& p : goal.goalPositions) positions.push_back(vec(p));
    bool escape = false;
    for (const build::EscapeSpec& e : scene.robotics.escapes) escape = escape || e.goal == g;
    goals.push_back({{"name", goal.name},
                     {"particles", goal.particles},
                     {"targets", goal.targets},
                     {"positions", positions},
                     {"tolerance", goal.tolerance},
                     {"travelTime", goal.travelTime},
                     {"escape", escape}});
  }
  return goals;
}

Json pathsJson(const Scene& scene) {
  Json paths = Json::array();
  for (const build::LinePathSpec& p : scene.linePaths) {
    paths.push_back({{"name", p.name},
                     {"type", "line"},
                     {"particle", p.particle},
                     {"from", vec(p.from)},
                     {"to", vec(p.to)}});
  }
  for (const build::ArcPathSpec& p : scene.arcPaths) {
    // The circle through the two ends and the particle's start (the inscribed
    // angle TS holds it there), in the plane of the three.
    const auto i = static_cast<std::size_t>(p.particle);
    if (i >= scene.initial.position.size()) continue;
    const Vec3 start = scene.initial.position[i];
    Vec3 normal = cross(p.to - p.from, start - p.from);
    if (!(norm(normal) > 0.0)) continue;
    normal = normal / norm(normal);
    const Vec3 center = build::circleCenter(p.from, p.to, start);
    paths.push_back({{"name", p.name},
                     {"type", "arc"},
                     {"particle", p.particle},
                     {"center", vec(center)},
                     {"radius", norm(start - center)},
                     {"normal", vec(normal)},
                     {"from", vec(p.from)},
                     {"to", vec(p.to)}});
  }
  return paths;
}

// Item k of a kind that had `initialCount` at the start: one added during the
// run gets "virtual" and the time it was first seen.
void markAdded(Json& item, std::size_t k, std::size_t initialCount,
               const std::vector<double>& addedAt) {
  if (k < initialCount) return;
  item["addedAt"] = addedAt[k - initialCount];
  item["virtual"] = true;
}

}  // namespace

std::vector<int> attractorSprings(const Model& model) {
  std::vector<int> out;
  auto isVirtual = [&](ParticleIndex i) {
    const std::int32_t o = i >= 0 && static_cast<std::size_t>(i) < model.objectOf.size()
                               ? model.objectOf[static_cast<std::size_t>(i)]
                               : -1;
    return o >= 0 && static_cast<std::size_t>(o) < model.objects.size() &&
           !model.objects[static_cast<std::size_t>(o)].contact.touches;
  };
  for (std::size_t s = 0; s < model.linearSprings.size(); ++s) {
    const LinearSpring& ls = model.linearSprings[s];
    if (isVirtual(ls.a) || isVirtual(ls.b) || ls.restLength <= 10.0 * build::kAttractorRestLength)
      out.push_back(static_cast<int>(s));
  }
  return out;
}

WorldView::WorldView(const Scene& scene)
    : initial_(scene.model.environment), latest_(scene.model.environment), valid_(true) {
  Json j;
  j["objects"] = objectsJson(scene.model);
  j["goals"] = goalsJson(scene);
  j["paths"] = pathsJson(scene);
  j["attractors"] = attractorSprings(scene.model);
  std::vector<double> sphereMargin, boxMargin;
  securityDistances(scene, sphereMargin, boxMargin);
  j["sphereSecurity"] = sphereMargin;
  j["boxSecurity"] = boxMargin;
  if (Json robots = visualsJson(scene); !robots.is_null()) j["robots"] = std::move(robots);
  if (Json shapes = shapesJson(scene.model); !shapes.is_null()) j["shapes"] = std::move(shapes);
  // The URDF joints' position limits (rad or m), by model joint, for the joint plot.
  Json limits = Json::array();
  for (const auto& robot : scene.urdfRobots) {
    if (!robot) continue;
    for (const build::UrdfJoint& joint : robot->joints) {
      if (joint.hasPositionLimits && !joint.modelJoint.empty())
        limits.push_back({{"joint", joint.modelJoint}, {"lower", joint.lower}, {"upper", joint.upper}});
    }
  }
  if (!limits.empty()) j["jointLimits"] = std::move(limits);
  sceneJson_ = j.dump();
}

void WorldView::observe(const World& world) {
  if (!valid_) return;
  const Environment& env = world.model().environment;
  const double t = world.state().time;
  // Items are only ever appended (World::addSphereObstacle); each new one gets the time.
  while (planeAddedAt_.size() + initial_.planes.size() < env.planes.size())
    planeAddedAt_.push_back(t);
  while (boxAddedAt_.size() + initial_.boxes.size() < env.boxes.size()) boxAddedAt_.push_back(t);
  while (sphereAddedAt_.size() + initial_.spheres.size() < env.spheres.size())
    sphereAddedAt_.push_back(t);
  latest_ = env;
}

std::string WorldView::json() const {
  if (!valid_) return "{}";
  const Json base = Json::parse(sceneJson_);
  const auto& sphereMargin = base["sphereSecurity"];
  const auto& boxMargin = base["boxSecurity"];
  Json env;
  Json planes = Json::array();
  for (std::size_t k = 0; k < latest_.planes.size(); ++k) {
    const GroundPlane& p = latest_.planes[k];
    Json item = {{"point", vec(p.point)}, {"normal", vec(p.normal)}};
    markAdded(item, k, initial_.planes.size(), planeAddedAt_);
    planes.push_back(item);
  }
  env["planes"] = planes;
  Json fields = Json::array();
  for (const Heightfield& h : latest_.heightfields) {
    fields.push_back({{"origin", {h.originX, h.originY}},
                      {"cellSize", {h.cellSizeX, h.cellSizeY}},
                      {"columns", h.columns},
                      {"rows", h.rows},
                      {"heights", h.heights}});
  }
  env["heightfields"] = fields;
  Json boxes = Json::array();
  for (std::size_t k = 0; k < latest_.boxes.size(); ++k) {
    const BoxObstacle& b = latest_.boxes[k];
    Json item = {{"center", vec(b.center)},
                 {"halfExtents", vec(b.halfExtents)},
                 {"axes", {vec(b.axisX), vec(b.axisY), vec(b.axisZ)}},
                 {"securityDistance", k < boxMargin.size() ? boxMargin[k].get<double>() : 0.0}};
    markAdded(item, k, initial_.boxes.size(), boxAddedAt_);
    boxes.push_back(item);
  }
  env["boxes"] = boxes;
  Json spheres = Json::array();
  for (std::size_t k = 0; k < latest_.spheres.size(); ++k) {
    const SphereObstacle& s = latest_.spheres[k];
    Json item = {
        {"center", vec(s.center)},
        {"radius", s.radius},
        {"securityDistance", k < sphereMargin.size() ? sphereMargin[k].get<double>() : 0.0}};
    markAdded(item, k, initial_.spheres.size(), sphereAddedAt_);
    spheres.push_back(item);
  }
  env["spheres"] = spheres;
  env["viscosity"] = latest_.viscosity;

  Json j;
  j["environment"] = env;
  j["objects"] = base["objects"];
  j["goals"] = base["goals"];
  j["paths"] = base["paths"];
  j["attractors"] = base["attractors"];
  if (base.contains("robots")) j["robots"] = base["robots"];
  if (base.contains("shapes")) j["shapes"] = base["shapes"];
  if (base.contains("jointLimits")) j["jointLimits"] = base["jointLimits"];
  return j.dump();
}

void WorldView::write(const std::string& dir) const {
  const std::string text = json();
  writeFileAtomically(std::filesystem::path(dir) / kWorldViewFile,
                      [&](std::ostream& out) { out << text << '\n'; });
}

}  // namespace robophi::output
