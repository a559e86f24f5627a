// Checkpoint serialisation: State, Contact, model edits, the adaptive step's and
// the run's settings, each field by field and bit-exactly.
#include "run/checkpoint.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "output/json_numbers.h"
#include "robophi/build/input_files.h"

namespace robophi {

namespace {

using nlohmann::json;
using output::exactNumber;
using output::exactVec3;
using output::numberFromJson;
using output::vec3FromJson;

using output::exactNumbers;
using output::exactVec3s;
using output::numbersFromJson;
using output::vec3sFromJson;

double number(const json& j, const char* key) { return numberFromJson(j.at(key), key); }

}  // namespace

// ---- State and Contact: one line per field.

json contactToJson(const Contact& c) {
  json out = {{"a", c.a},
              {"other", c.other},
              {"depth", exactNumber(c.depth)},
              {"normal_force", exactNumber(c.normalForce)},
              {"friction_force", exactVec3(c.frictionForce)},
              {"anchor_energy", exactNumber(c.anchorEnergy)},
              {"normal", exactVec3(c.normal)},
              {"slip", exactVec3(c.slip)},
              {"anchor", exactVec3(c.anchor)},
              {"roll_velocity", exactVec3(c.rollVelocity)},
              {"rim", c.rim},
              {"arm", exactVec3(c.arm)},
              {"give_way", exactNumber(c.giveWay)},
              {"sliding", c.sliding},
              {"vertex", c.vertex},
              {"facet", c.facet},
              {"facet_weights", exactVec3(c.facetWeights)}};
  if (c.edgeVertex >= 0) {  // an edge contact's (older checkpoints have none)
    out["edge_vertex"] = c.edgeVertex;
    out["edge_weight"] = exactNumber(c.edgeWeight);
  }
  return out;
}

Contact contactFromJson(const json& j) {
  Contact c;
  c.a = j.at("a").get<std::int32_t>();
  c.other = j.at("other").get<std::int32_t>();
  c.depth = number(j, "depth");
  c.normalForce = number(j, "normal_force");
  c.frictionForce = vec3FromJson(j.at("friction_force"), "friction_force");
  c.anchorEnergy = number(j, "anchor_energy");
  c.normal = vec3FromJson(j.at("normal"), "normal");
  c.slip = vec3FromJson(j.at("slip"), "slip");
  c.anchor = vec3FromJson(j.at("anchor"), "anchor");
  c.rollVelocity = vec3FromJson(j.at("roll_velocity"), "roll_velocity");
  c.rim = j.at("rim").get<std::int32_t>();
  c.arm = vec3FromJson(j.at("arm"), "arm");
  c.giveWay = number(j, "give_way");
  c.sliding = j.at("sliding").get<std::int32_t>();
  c.vertex = j.at("vertex").get<std::int32_t>();
  c.facet = j.at("facet").get<std::int32_t>();
  c.facetWeights = vec3FromJson(j.at("facet_weights"), "facet_weights");
  if (j.contains("edge_vertex")) {
    c.edgeVertex = j.at("edge_vertex").get<std::int32_t>();
    c.edgeWeight = number(j, "edge_weight");
  }
  return c;
}

json stateToJson(const State& s) {
  const auto trees = [](const std::vector<std::vector<double>>& values) {
    json out = json::array();
    for (const std::vector<double>& tree : values) out.push_back(exactNumbers(tree));
    return out;
  };
  json history = json::array();
  for (const Contact& c : s.frictionHistory) history.push_back(contactToJson(c));
  return {{"time", exactNumber(s.time)},
          {"step_count", s.stepCount},
          {"position", exactVec3s(s.position)},
          {"velocity", exactVec3s(s.velocity)},
          {"spin", exactVec3s(s.spin)},
          {"tree_positions", trees(s.treePositions)},
          {"tree_velocities", trees(s.treeVelocities)},
          {"friction_history", history},
          {"dissipated", exactNumber(s.dissipated)},
          {"implicit_loss", exactNumber(s.implicitLoss)},
          {"external", exactNumber(s.external)}};
}

namespace {

// The friction history's references into the model in range, and its order
// the contacts' (Contact::key): a checkpoint written for another scene, or
// edited, is refused by name rather than read out of bounds.
void checkHistory(const std::vector<Contact>& history, const Model& model) {
  const auto count = [](const auto& items) { return static_cast<std::int64_t>(items.size()); };
  const std::int64_t particles = model.particleCount();
  for (std::size_t k = 0; k < history.size(); ++k) {
    const Contact& c = history[k];
    const auto check = [&](const char* field, std::int64_t value, std::int64_t low,
                           std::int64_t end) {
      if (value < low || value >= end)
        throw std::runtime_error(
            fmt::format("the checkpoint's friction_history[{}].{} = {} is outside [{}, {})", k,
                        field, value, low, end));
    };
    check("a", c.a, 0, particles);
    check("other", c.other, -model.environment.itemCount(), particles);
    check("vertex", c.vertex, -1, count(model.surfaceVertices));
    check("edge_vertex", c.edgeVertex, -1, count(model.surfaceVertices));
    check("facet", c.facet, -1, count(model.surfaceTriangles));
    check("rim", c.rim, -1, count(model.rims));
    if (k > 0 && !(history[k - 1].key() < c.key()))
      throw std::runtime_error(
          fmt::format("the checkpoint's friction_history[{}] is out of the contacts' order", k));
  }
}

}  // namespace

State stateFromJson(const json& j, const Model& model) {
  State s;
  s.time = number(j, "time");
  s.stepCount = j.at("step_count").get<std::int64_t>();
  s.position = vec3sFromJson(j.at("position"), "position");
  s.velocity = vec3sFromJson(j.at("velocity"), "velocity");
  s.spin = vec3sFromJson(j.at("spin"), "spin");
  // The rigid trees' coordinates and rates (docs/model.md §7); a checkpoint of a
  // model without trees may lack them.
  for (const auto& [key, values] : {std::pair{"tree_positions", &s.treePositions},
                                    std::pair{"tree_velocities", &s.treeVelocities}}) {
    if (!j.contains(key)) continue;
    for (const json& tree : j.at(key)) values->push_back(numbersFromJson(tree, key));
  }
  if (s.treePositions.size() != model.rigidTrees.size() ||
      s.treeVelocities.size() != model.rigidTrees.size())
    throw std::runtime_error(fmt::format("the checkpoint's state has {} rigid trees, the scene {}",
                                         s.treePositions.size(), model.rigidTrees.size()));
  for (const json& c : j.at("friction_history")) s.frictionHistory.push_back(contactFromJson(c));
  checkHistory(s.frictionHistory, model);
  s.dissipated = number(j, "dissipated");
  // (Optional: checkpoints written before it have none.)
  s.implicitLoss = j.contains("implicit_loss") ? number(j, "implicit_loss") : 0.0;
  s.external = number(j, "external");
  const auto n = static_cast<std::size_t>(model.particleCount());
  if (s.position.size() != n || s.velocity.size() != n) {
    throw std::runtime_error(
        fmt::format("the checkpoint's state has {} particles, the scene {}", s.position.size(), n));
  }
  return s;
}

json evaluationToJson(const Evaluation& e) {
  json contacts = json::array();
  for (const Contact& c : e.contacts) contacts.push_back(contactToJson(c));
  const EnergyTally& t = e.energy;
  const ContactStats& st = e.contactStats;
  return {{"force", exactVec3s(e.force)},
          {"torque", exactVec3s(e.torque)},
          {"energy",
           {{"kinetic", exactNumber(t.kinetic)},
            {"linear_spring", exactNumber(t.linearSpring)},
            {"torsion_spring", exactNumber(t.torsionSpring)},
            {"joint_spring", exactNumber(t.jointSpring)},
            {"gravity", exactNumber(t.gravity)},
            {"contact", exactNumber(t.contact)},
            {"dissipated", exactNumber(t.dissipated)},
            {"external", exactNumber(t.external)}}},
          {"dissipative_power", exactNumber(e.dissipativePower)},
          {"driving_power", exactNumber(e.drivingPower)},
          {"dissipative_kick", exactNumber(e.dissipativeKick)},
          {"driving_kick", exactNumber(e.drivingKick)},
          {"kick_step", exactNumber(e.kickStep)},
          {"joint_motor_effort", exactNumbers(e.jointMotorEffort)},
          {"joint_loss_effort", exactNumbers(e.jointLossEffort)},
          {"released_anchor_energy", exactNumber(e.releasedAnchorEnergy)},
          {"contact_critical_step", exactNumber(e.contactCriticalStep)},
          {"drive_damping_rate", exactNumber(e.driveDampingRate)},
          {"contacts", contacts},
          {"contact_stats",
           {{"pair_tests", st.pairTests},
            {"node_tests", st.nodeTests},
            {"environment_tests", st.environmentTests},
            {"particle_contacts", st.particleContacts},
            {"environment_contacts", st.environmentContacts},
            {"max_penetration", exactNumber(st.maxPenetration)},
            {"max_penetration_fraction", exactNumber(st.maxPenetrationFraction)}}}};
}

Evaluation evaluationFromJson(const json& j) {
  Evaluation e;
  e.force = vec3sFromJson(j.at("force"), "force");
  e.torque = vec3sFromJson(j.at("torque"), "torque");
  const json& t = j.at("energy");
  e.energy.kinetic = number(t, "kinetic");
  e.energy.linearSpring = number(t, "linear_spring");
  e.energy.torsionSpring = number(t, "torsion_spring");
  e.energy.jointSpring = number(t, "joint_spring");
  e.energy.gravity = number(t, "gravity");
  e.energy.contact = number(t, "contact");
  e.energy.dissipated = number(t, "dissipated");
  e.energy.external = number(t, "external");
  e.dissipativePower = number(j, "dissipative_power");
  e.drivingPower = number(j, "driving_power");
  // (A checkpoint from before the kick's booking: none.)
  if (j.contains("kick_step")) {
    e.dissipativeKick = number(j, "dissipative_kick");
    e.drivingKick = number(j, "driving_kick");
    e.kickStep = number(j, "kick_step");
  }
  if (j.contains("joint_motor_effort")) {
    e.jointMotorEffort = numbersFromJson(j.at("joint_motor_effort"), "joint_motor_effort");
    e.jointLossEffort = numbersFromJson(j.at("joint_loss_effort"), "joint_loss_effort");
  }
  e.releasedAnchorEnergy = number(j, "released_anchor_energy");
  e.contactCriticalStep = number(j, "contact_critical_step");
  // (A checkpoint from before the drives' damping bound: none.)
  if (j.contains("drive_damping_rate")) e.driveDampingRate = number(j, "drive_damping_rate");
  for (const json& c : j.at("contacts")) e.contacts.push_back(contactFromJson(c));
  const json& st = j.at("contact_stats");
  e.contactStats.pairTests = st.at("pair_tests").get<std::int64_t>();
  e.contactStats.nodeTests = st.at("node_tests").get<std::int64_t>();
  e.contactStats.environmentTests = st.at("environment_tests").get<std::int64_t>();
  e.contactStats.particleContacts = st.at("particle_contacts").get<std::int64_t>();
  e.contactStats.environmentContacts = st.at("environment_contacts").get<std::int64_t>();
  e.contactStats.maxPenetration = number(st, "max_penetration");
  e.contactStats.maxPenetrationFraction = number(st, "max_penetration_fraction");
  return e;
}

// ---- What World's edit API changes in a model.

json modelEditsToJson(const Model& m) {
  json linear = json::array(), torsion = json::array(), joint = json::array();
  for (const LinearSpring& s : m.linearSprings)
    linear.push_back(
        {s.a, s.b, exactNumber(s.restLength), exactNumber(s.stiffness), exactNumber(s.damping)});
  for (const TorsionSpring& s : m.torsionSprings)
    torsion.push_back({s.a, s.c, s.b, exactNumber(s.restAngle), exactNumber(s.stiffness),
                       exactNumber(s.damping)});
  for (const JointSpring& s : m.jointSprings)
    joint.push_back({s.a, s.c, s.b, s.d, exactNumber(s.restAngle), exactNumber(s.stiffness),
                     exactNumber(s.damping)});
  json materials = json::array(), objects = json::array(), spheres = json::array(),
       pairs = json::array();
  for (const Material& mt : m.materials)
    materials.push_back({mt.name, exactNumber(mt.contactStiffness), exactNumber(mt.contactDamping),
                         exactNumber(mt.staticFriction), exactNumber(mt.kineticFriction)});
  for (const ObjectInfo& o : m.objects) objects.push_back(o.material);
  for (const SphereObstacle& s : m.environment.spheres)
    spheres.push_back({exactVec3(s.center), exactNumber(s.radius), s.material});
  const ContactSettings& c = m.contact;
  for (const ContactPairOverride& p : c.pairOverrides)
    pairs.push_back({p.objectA, p.objectB, exactNumber(p.stiffness), exactNumber(p.damping),
                     exactNumber(p.staticFriction), exactNumber(p.kineticFriction)});
  json drives = json::array(), servos = json::array();
  for (const Joint& jt : m.joints) {
    // A rigid tree's joint servo and gravity compensation (World::setJointServo,
    // setGravityCompensation: a passive joint's servo is off).
    servos.push_back({exactNumber(jt.servoStiffness), exactNumber(jt.servoDamping),
                      exactNumber(jt.servoTarget), jt.compensateGravity});
    const JointDrive& d = jt.drive;
    drives.push_back({exactNumber(d.effort), exactNumber(d.rateGain), exactNumber(d.targetRate),
                      exactNumber(d.effortLimit), exactNumber(d.velocityLimit),
                      exactNumber(d.damping), exactNumber(d.friction),
                      exactNumber(d.frictionVelocity)});
  }
  return {{"linear_springs", linear},
          {"torsion_springs", torsion},
          {"joint_springs", joint},
          {"joint_drives", drives},
          {"joint_servos", servos},
          {"inverse_mass", exactNumbers(m.inverseMass)},
          {"gravity", exactVec3(m.gravity)},
          {"materials", materials},
          {"object_materials", objects},
          {"spheres", spheres},
          {"viscosity", exactNumber(m.environment.viscosity)},
          {"contact",
           {{"enabled", c.enabled},
            {"self_collision", c.selfCollision},
            {"tangential_stiffness_ratio", exactNumber(c.tangentialStiffnessRatio)},
            {"tangential_damping_ratio", exactNumber(c.tangentialDampingRatio)},
            {"stick_velocity", exactNumber(c.stickVelocity)},
            {"stribeck_velocity", exactNumber(c.stribeckVelocity)},
            {"rolling", c.rolling},
            {"leaf_size", c.leafSize},
            {"pairs", pairs}}}};
}

void applyModelEdits(const json& j, Model& m) {
  const json& linear = j.at("linear_springs");
  const json& torsion = j.at("torsion_springs");
  const json& joint = j.at("joint_springs");
  const json& inverseMass = j.at("inverse_mass");
  const json& objects = j.at("object_materials");
  if (linear.size() != m.linearSprings.size() || torsion.size() != m.torsionSprings.size() ||
      joint.size() != m.jointSprings.size() ||
      inverseMass.size() != static_cast<std::size_t>(m.particleCount()) ||
      objects.size() != m.objects.size()) {
    throw std::runtime_error(
        "the checkpoint's model has other connectors, particles or objects than the scene");
  }
  for (std::size_t k = 0; k < linear.size(); ++k) {
    const json& s = linear[k];
    m.linearSprings[k] = {s.at(0).get<ParticleIndex>(), s.at(1).get<ParticleIndex>(),
                          numberFromJson(s.at(2), "rest length"),
                          numberFromJson(s.at(3), "stiffness"), numberFromJson(s.at(4), "damping")};
  }
  for (std::size_t k = 0; k < torsion.size(); ++k) {
    const json& s = torsion[k];
    m.torsionSprings[k] = {
        s.at(0).get<ParticleIndex>(),         s.at(1).get<ParticleIndex>(),
        s.at(2).get<ParticleIndex>(),         numberFromJson(s.at(3), "angle"),
        numberFromJson(s.at(4), "stiffness"), numberFromJson(s.at(5), "damping")};
  }
  for (std::size_t k = 0; k < joint.size(); ++k) {
    const json& s = joint[k];
    m.jointSprings[k] = {s.at(0).get<ParticleIndex>(),      s.at(1).get<ParticleIndex>(),
                         s.at(2).get<ParticleIndex>(),      s.at(3).get<ParticleIndex>(),
                         numberFromJson(s.at(4), "angle"),  numberFromJson(s.at(5), "stiffness"),
                         numberFromJson(s.at(6), "damping")};
  }
  // MODEL §1.6 joint drives (checkpoints written before them have none: the scene's stand).
  if (const auto drives = j.find("joint_drives"); drives != j.end()) {
    if (drives->size() != m.joints.size())
      throw std::runtime_error("the checkpoint's model has other joints than the scene");
    for (std::size_t k = 0; k < drives->size(); ++k) {
      const json& d = (*drives)[k];
      m.joints[k].drive = {
          numberFromJson(d.at(0), "effort"),         numberFromJson(d.at(1), "rate gain"),
          numberFromJson(d.at(2), "target rate"),    numberFromJson(d.at(3), "effort limit"),
          numberFromJson(d.at(4), "velocity limit"), numberFromJson(d.at(5), "joint damping"),
          numberFromJson(d.at(6), "joint friction"), numberFromJson(d.at(7), "friction velocity")};
    }
  }
  // (Checkpoints written before the servos were saved: the scene's stand.)
  if (const auto servos = j.find("joint_servos"); servos != j.end()) {
    if (servos->size() != m.joints.size())
      throw std::runtime_error("the checkpoint's model has other joints than the scene");
    for (std::size_t k = 0; k < servos->size(); ++k) {
      const json& v = (*servos)[k];
      m.joints[k].servoStiffness = numberFromJson(v.at(0), "servo stiffness");
      m.joints[k].servoDamping = numberFromJson(v.at(1), "servo damping");
      m.joints[k].servoTarget = numberFromJson(v.at(2), "servo target");
      m.joints[k].compensateGravity = v.at(3).get<bool>();
    }
  }
  m.inverseMass = numbersFromJson(inverseMass, "inverse mass");
  m.gravity = vec3FromJson(j.at("gravity"), "gravity");
  m.materials.clear();
  for (const json& mt : j.at("materials")) {
    m.materials.push_back({mt.at(0).get<std::string>(), numberFromJson(mt.at(1), "stiffness"),
                           numberFromJson(mt.at(2), "damping"),
                           numberFromJson(mt.at(3), "static friction"),
                           numberFromJson(mt.at(4), "kinetic friction")});
  }
  for (std::size_t o = 0; o < objects.size(); ++o)
    m.objects[o].material = objects[o].get<std::int32_t>();
  m.environment.spheres.clear();
  for (const json& s : j.at("spheres")) {
    SphereObstacle sphere;
    sphere.center = vec3FromJson(s.at(0), "sphere centre");
    sphere.radius = numberFromJson(s.at(1), "sphere radius");
    sphere.material = s.at(2).get<std::int32_t>();
    m.environment.spheres.push_back(sphere);
  }
  m.environment.viscosity = number(j, "viscosity");
  const json& c = j.at("contact");
  ContactSettings& settings = m.contact;
  settings.enabled = c.at("enabled").get<bool>();
  settings.selfCollision = c.at("self_collision").get<bool>();
  settings.tangentialStiffnessRatio = number(c, "tangential_stiffness_ratio");
  settings.tangentialDampingRatio = number(c, "tangential_damping_ratio");
  settings.stickVelocity = number(c, "stick_velocity");
  // (Checkpoints written before v_S existed slide at μ_k: 0.)
  settings.stribeckVelocity =
      c.contains("stribeck_velocity") ? number(c, "stribeck_velocity") : 0.0;
  settings.rolling = c.at("rolling").get<bool>();
  settings.leafSize = c.at("leaf_size").get<std::int32_t>();
  settings.pairOverrides.clear();
  for (const json& p : c.at("pairs")) {
    settings.pairOverrides.push_back(
        {p.at(0).get<std::int32_t>(), p.at(1).get<std::int32_t>(),
         numberFromJson(p.at(2), "stiffness"), numberFromJson(p.at(3), "damping"),
         numberFromJson(p.at(4), "static friction"), numberFromJson(p.at(5), "kinetic friction")});
  }
}

// ---- The adaptive step and the run settings.

namespace {

// The counts of what set the steps, in kStepCauses' order.
std::vector<std::int64_t> setByCounts(const AdaptiveStepStats& s) {
  std::vector<std::int64_t> counts;
  for (const StepCause& cause : kStepCauses) counts.push_back(s.*cause.count);
  return counts;
}

}  // namespace

json adaptiveProgressToJson(const AdaptiveStepper::Progress& p) {
  const AdaptiveStepStats& s = p.stats;
  return {{"step", exactNumber(p.step)},
          {"stability_limit", exactNumber(p.stabilityLimit)},
          {"stability_omega", exactNumber(p.stabilityOmega)},
          {"stability_damping", exactNumber(p.stabilityDamping)},
          {"error_order", exactNumber(p.errorOrder)},
          {"gravity_scale", exactNumber(p.gravityScale)},
          {"refined_limit", p.refinedLimit},
          {"accepted", s.accepted},
          {"rejected", s.rejected},
          {"smallest_step", exactNumber(s.smallestStep)},
          {"largest_step", exactNumber(s.largestStep)},
          {"sum_of_steps", exactNumber(s.sumOfSteps)},
          {"last_energy_error", exactNumber(s.lastEnergyError)},
          {"last_step", exactNumber(s.lastStep)},
          {"set_by", setByCounts(s)},
          {"jump_error", exactNumber(p.jumpError)},
          {"jump_trial", exactNumber(p.jumpTrial)},
          {"jump_time", exactNumber(p.jumpTime)}};
}

AdaptiveStepper::Progress adaptiveProgressFromJson(const json& j) {
  AdaptiveStepper::Progress p;
  p.step = number(j, "step");
  p.stabilityLimit = number(j, "stability_limit");
  // (A checkpoint from before the drives' damping bound: no connector ω to add it to.)
  if (j.contains("stability_omega")) {
    p.stabilityOmega = number(j, "stability_omega");
    p.stabilityDamping = number(j, "stability_damping");
  }
  p.errorOrder = number(j, "error_order");
  p.gravityScale = number(j, "gravity_scale");
  p.refinedLimit = j.at("refined_limit").get<bool>();
  // (A checkpoint from before energy jumps were told apart: none suspected.)
  if (j.contains("jump_error")) {
    p.jumpError = number(j, "jump_error");
    p.jumpTrial = number(j, "jump_trial");
    p.jumpTime = number(j, "jump_time");
  }
  p.stats.accepted = j.at("accepted").get<std::int64_t>();
  p.stats.rejected = j.at("rejected").get<std::int64_t>();
  p.stats.smallestStep = number(j, "smallest_step");
  p.stats.largestStep = number(j, "largest_step");
  p.stats.sumOfSteps = number(j, "sum_of_steps");
  p.stats.lastEnergyError = number(j, "last_energy_error");
  p.stats.lastStep = number(j, "last_step");
  // (Checkpoints written before the counts were kept have none: they start at 0.)
  if (const auto it = j.find("set_by"); it != j.end()) {
    const std::vector<std::int64_t> counts = it->get<std::vector<std::int64_t>>();
    // (Checkpoints written before the energy jumps were counted hold one count fewer.)
    constexpr std::size_t kCauses = std::size(kStepCauses);
    if (counts.size() != kCauses && counts.size() != kCauses - 1)
      throw std::runtime_error("the checkpoint's adaptive set_by holds " +
                               std::to_string(counts.size()) + " counts, not " +
                               std::to_string(kCauses));
    for (std::size_t k = 0; k < counts.size(); ++k) p.stats.*kStepCauses[k].count = counts[k];
  }
  return p;
}

json runSettingsToJson(const RunSettings& r) {
  const AdaptiveStepSettings& a = r.adaptive;
  return {{"duration", exactNumber(r.duration)},
          {"dt", exactNumber(r.dt)},
          {"step_mode", r.stepMode == StepMode::kAdaptive ? "adaptive" : "constant"},
          {"integrator", integratorName(r.integrator)},
          {"fps", exactNumber(r.fps)},
          {"adaptive",
           {{"initial_step", exactNumber(a.initialStep)},
            {"min_step", exactNumber(a.minStep)},
            {"max_step", exactNumber(a.maxStep)},
            {"energy_tolerance", exactNumber(a.energyTolerance)},
            {"loss_tolerance_factor", exactNumber(a.lossToleranceFactor)},
            {"energy_floor", exactNumber(a.energyFloor)},
            {"shrink_factor", exactNumber(a.shrinkFactor)},
            {"grow_factor", exactNumber(a.growFactor)},
            {"safety", exactNumber(a.safety)},
            {"error_order", exactNumber(a.errorOrder)},
            {"max_penetration_fraction", exactNumber(a.maxPenetrationFraction)},
            {"stability_safety", exactNumber(a.stabilitySafety)},
            {"max_rejections_in_a_row", a.maxRejectionsInARow},
            {"jump_limit", exactNumber(a.jumpLimit)}}}};
}

RunSettings runSettingsFromJson(const json& j) {
  RunSettings r;
  r.duration = number(j, "duration");
  r.dt = number(j, "dt");
  r.stepMode = j.at("step_mode").get<std::string>() == "adaptive" ? StepMode::kAdaptive
                                                                  : StepMode::kConstant;
  if (!parseIntegrator(j.at("integrator").get<std::string>(), r.integrator))
    throw std::runtime_error("the checkpoint names an unknown integrator");
  r.fps = number(j, "fps");
  const json& a = j.at("adaptive");
  AdaptiveStepSettings& s = r.adaptive;
  s.initialStep = number(a, "initial_step");
  s.minStep = number(a, "min_step");
  s.maxStep = number(a, "max_step");
  s.energyTolerance = number(a, "energy_tolerance");
  s.lossToleranceFactor = number(a, "loss_tolerance_factor");
  s.energyFloor = number(a, "energy_floor");
  s.shrinkFactor = number(a, "shrink_factor");
  s.growFactor = number(a, "grow_factor");
  s.safety = number(a, "safety");
  s.errorOrder = number(a, "error_order");
  s.maxPenetrationFraction = number(a, "max_penetration_fraction");
  s.stabilitySafety = number(a, "stability_safety");
  s.maxRejectionsInARow = a.at("max_rejections_in_a_row").get<int>();
  // (Checkpoints written before energy jumps were taken have none: none was taken.)
  if (a.contains("jump_limit"))
    s.jumpLimit = number(a, "jump_limit");
  else
    s.jumpLimit = 0.0;
  return r;
}

namespace {

// 64-bit FNV-1a of the bytes `in` gives from where it stands, at most `limit`
// of them; `read` counts them.
std::uint64_t fnv1a(std::istream& in, std::uintmax_t limit, std::uintmax_t& read) {
  std::uint64_t h = 1469598103934665603ULL;
  char buffer[65536];
  read = 0;
  while (read < limit && in) {
    in.read(buffer,
            static_cast<std::streamsize>(std::min<std::uintmax_t>(sizeof buffer, limit - read)));
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      h ^= static_cast<unsigned char>(buffer[i]);
      h *= 1099511628211ULL;
    }
    read += static_cast<std::uintmax_t>(in.gcount());
  }
  return h;
}

}  // namespace

std::string fileHash(const std::string& path) {
  std::istringstream in;
  try {
    in.str(build::readInputFile(path));  // a regular file, never a FIFO
  } catch (const build::InputFileError&) {
    return {};
  }
  std::uintmax_t read = 0;
  return fmt::format("{:016x}", fnv1a(in, std::numeric_limits<std::uintmax_t>::max(), read));
}

std::string seriesDigest(const std::string& path, std::uintmax_t length) {
  std::ifstream in(path, std::ios::binary);
  const std::uintmax_t start = length > kSeriesDigestBytes ? length - kSeriesDigestBytes : 0;
  if (!in || !in.seekg(static_cast<std::streamoff>(start))) return {};
  std::uintmax_t read = 0;
  const std::uint64_t h = fnv1a(in, length - start, read);
  // (Shorter than `length`: not the file the checkpoint was written with.)
  return read == length - start ? fmt::format("{:016x}", h) : std::string();
}

nlohmann::json inputDigests(const std::vector<std::string>& files) {
  json inputs = json::array();
  for (const std::string& path : files)
    inputs.push_back({{"path", path}, {"hash", fileHash(path)}});
  return inputs;
}

}  // namespace robophi
