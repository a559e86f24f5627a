// The rigid trees' stage of the step (integrate/rigid_trees.h, docs/model.md §7).
#include "integrate/rigid_trees.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/contact_law.h"
#include "collision/facets.h"
#include "collision/rim_contact.h"
#include "forces/forces.h"
#include "model/multibody_contacts.h"
#include "robophi/stability.h"

namespace robophi {

namespace {

// Position and velocity of a tree particle from its body's pose and velocity.
// Position, velocity and spin (its body's angular velocity) of a tree particle.
void bodyPoint(const MultibodyKinematics& kin, const BodyParticle& bp, Vec3& p_WP, Vec3& v_WP,
               Vec3& w_W) {
  p_WP = kin.X_WB[static_cast<std::size_t>(bp.body)] * bp.p_BP;
  v_WP = pointVelocity(kin, bp.body, p_WP);
  w_W = kin.velocity[static_cast<std::size_t>(bp.body)].angular;
}

// The tree's inputs for a step from its joints (Joint::inTree, docs/model.md §7):
// per rate, the joint's servo (κ, β, q*) and its drive — a rate drive and viscous
// losses join the servo's damper (implicit), a velocity-limited motor alone is a
// rate servo to ±its velocity limit bounded by its effort, any other motor and
// Coulomb losses are explicit efforts — and, with gravity compensation, the
// effort that holds the tree at q against gravity.
void composeTreeInputs(const Model& model, const RigidTree& tree, const std::vector<double>& q,
                       const std::vector<double>& v, MultibodyWorkspace& ws) {
  const Multibody& mb = tree.multibody;
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  MultibodyInputs& in = ws.inputs;
  for (auto* values :
       {&in.effort, &in.servoStiffness, &in.servoDamping, &in.servoTarget, &in.servoTargetRate})
    values->assign(n, 0.0);
  in.effortLimit.assign(n, std::numeric_limits<double>::infinity());
  bool compensate = false;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t k = tree.jointOfRate[i];
    if (k < 0) continue;
    const Joint& joint = model.joints[static_cast<std::size_t>(k)];
    const JointDrive& d = joint.drive;
    compensate = compensate || joint.compensateGravity;
    double damping = joint.servoDamping + d.rateGain + d.damping;
    double dampedRate = d.rateGain * d.targetRate;  // Σ β q̇* of the dampers
    double effort = -d.friction * std::clamp(v[i] / d.frictionVelocity, -1.0, 1.0);
    const bool limited = std::isfinite(d.velocityLimit) && d.effort != 0.0;
    if (limited && joint.servoStiffness == 0.0 && d.rateGain == 0.0) {
      // Pushes with |τ0| up to the velocity limit, then holds that rate: a rate
      // servo whose damper (ten times τ0's over the limit) stays implicit.
      const double pushRate = d.velocityLimit * (d.effort > 0.0 ? 1.0 : -1.0);
      const double gain = 10.0 * std::abs(d.effort) / d.velocityLimit;
      damping += gain;
      dampedRate += gain * pushRate;
      in.effortLimit[i] = std::min(std::abs(d.effort), d.effortLimit);
    } else {
      JointDrive motor = d;  // the commanded effort alone, explicit
      motor.rateGain = motor.damping = motor.friction = 0.0;
      effort += motorEffort(motor, v[i]);
      in.effortLimit[i] = d.effortLimit;
    }
    in.effort[i] = effort;
    in.servoStiffness[i] = joint.servoStiffness;
    in.servoTarget[i] = joint.servoStiffness > 0.0
                            ? joint.servoTarget
                            : q[static_cast<std::size_t>(
                                  mb.bodies[static_cast<std::size_t>(mb.dofBody[i])].qStart)];
    in.servoDamping[i] = damping;
    in.servoTargetRate[i] = damping > 0.0 ? dampedRate / damping : 0.0;
  }
  if (!compensate) return;
  // The efforts that hold the tree at q against gravity (inverse dynamics at rest).
  std::vector<double>& held = ws.tau;
  held.resize(n);
  std::vector<double>& zero = ws.rhs;
  zero.assign(n, 0.0);
  MultibodyKinematics& kin = ws.kinematics;
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, zero.data(), kin);
  inverseDynamics(mb, kin, nullptr, model.gravity, nullptr, held.data());
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t k = tree.jointOfRate[i];
    if (k >= 0 && model.joints[static_cast<std::size_t>(k)].compensateGravity)
      in.effort[i] += held[i];
  }
}

void sizeScratch(const Model& model, std::vector<MultibodyWorkspace>& scratch) {
  if (scratch.size() != model.rigidTrees.size()) scratch.resize(model.rigidTrees.size());
}

// One side of contact c (`sideA`: a, else other) when its tree's step takes the
// contact's load implicitly (docs/model.md §7 "Contacts on rigid trees"), else
// tree -1: a pressing contact whose point on that side one tree body carries
// whole (a tree particle; a round wheel its body carries, c.rim; a surface
// vertex on one body touching the environment, vertexCarrier) and whose other
// side is not of the same tree (a tree's contact with itself would couple two
// branches: explicit). `point` is the contact point on that side, `inverseMass`
// the contact law's there.
struct ImplicitSide {
  std::int32_t tree = -1, body = -1;
  Vec3 point;
  double inverseMass = 0.0;
};

ImplicitSide implicitSide(const Model& model, const ContactTables& tables,
                          const std::vector<Vec3>& position, const Contact& c, bool sideA) {
  ImplicitSide out;
  const std::int32_t side = sideA ? c.a : c.other;
  if (side < 0) return out;
  if (c.involvesFacets()) {
    // A vertex on the environment only: a particle or a vertex on a carried
    // triangle stays explicit (taken implicitly, on either side or both, the
    // shake of scenes/panda_shake_rigid.json with "facets" on ends with its
    // account 5.6 % off, over the 5 % bound, against 4.5 % with the box's
    // particles touching; explicit, 0.007 %, at three times the steps), and
    // with it the side it touches (so no facet contact needs the other side's
    // inverse mass for c_t: the environment's is 0).
    if (!sideA || c.vertex < 0 || c.facet >= 0 || c.normalForce <= 0.0) return out;
    const FacetCarrier vertex = vertexCarrier(model, tables, position, c);
    if (vertex.tree >= 0) out = {vertex.tree, vertex.body, vertex.point, vertex.inverseMass};
    return out;
  }
  const auto i = static_cast<std::size_t>(side);
  out.inverseMass = tables.contactInverseMass[i];
  const std::int32_t tree = tables.treeOf[i];
  const std::int32_t opposite = sideA ? c.other : c.a;
  if (c.normalForce <= 0.0 || tree < 0 ||
      (opposite >= 0 && tables.treeOf[static_cast<std::size_t>(opposite)] == tree))
    return out;
  out.tree = tree;
  out.body = tables.treeBodyOf[i];
  if (c.rim >= 0) {
    // A round wheel's contact: c.arm from its particles' mass centre to the
    // contact point on its own surface (rim_contact.cpp).
    out.point = rimCenter(model, model.rims[static_cast<std::size_t>(c.rim)], position) + c.arm;
  } else {
    out.point = position[i] + c.normal * (sideA ? -model.radius[i] : model.radius[i]);
  }
  return out;
}

// Each tree's implicit contact loads (implicitSide) at the evaluation's contacts:
// the contact point on the tree's side, the pair's normal stiffness and damping,
// and while it sticks its anchor's k_t and c_t (c_t for the pair's effective
// mass, as the contact law's).
void collectImplicitLoads(const Model& model, const ContactTables& tables, const State& state,
                          const std::vector<Contact>& contacts,
                          std::vector<std::vector<PointLoadStiffness>>& loads) {
  loads.resize(model.rigidTrees.size());
  for (auto& list : loads) list.clear();
  PairParameters overridden;
  for (const Contact& c : contacts) {
    const ImplicitSide sides[2] = {implicitSide(model, tables, state.position, c, true),
                                   implicitSide(model, tables, state.position, c, false)};
    for (const ImplicitSide& side : sides) {
      if (side.tree < 0) continue;
      const PairParameters& pair = pairParameters(model, tables, c.a, c.other, overridden);
      PointLoadStiffness load;
      load.body = side.body;
      load.normal = c.normal;  // from the other side to a
      load.point = side.point;
      load.normalStiffness = pair.stiffness;
      load.normalDamping = pair.damping;
      if (c.sliding == 0 && pair.tangentialStiffness > 0.0) {
        const double inverseMass = sides[0].inverseMass + sides[1].inverseMass;
        load.tangentialStiffness = pair.tangentialStiffness;
        load.tangentialDamping = law::tangentialDamping(pair.tangentialDampingRatio,
                                                        pair.tangentialStiffness, inverseMass);
      }
      loads[static_cast<std::size_t>(side.tree)].push_back(load);
    }
  }
}

// addRigidTreeTerms' contact limit: per touching body, Gershgorin on the stiffness
// and damping sums of its contacts that its step takes explicitly, with the body's
// inverse effective mass bound.
void limitTreeContactStep(const Model& model, const ContactTables& tables,
                          const std::vector<Vec3>& position, Evaluation& evaluation) {
  if (evaluation.contacts.empty()) return;
  // Stiffness and damping sums per (tree, body) (allocated per evaluation: a
  // vector per touching tree).
  std::vector<std::vector<law::Rates>> sums(model.rigidTrees.size());
  bool any = false;
  PairParameters overridden;
  const auto book = [&](const Contact& c, std::int32_t particle) {
    if (particle < 0 || implicitSide(model, tables, position, c, particle == c.a).tree >= 0) return;
    const std::int32_t a = c.a, other = c.other;
    const std::int32_t t = tables.treeOf[static_cast<std::size_t>(particle)];
    if (t < 0) return;
    const auto tree = static_cast<std::size_t>(t);
    if (sums[tree].empty()) sums[tree].assign(model.rigidTrees[tree].multibody.bodies.size(), {});
    const PairParameters& pair = pairParameters(model, tables, a, other, overridden);
    const auto b = static_cast<std::size_t>(tables.treeBodyOf[static_cast<std::size_t>(particle)]);
    // The anchor's damper while it holds or breaks away (MODEL §3.3), none
    // while it slides: c_t for the two sides' particles' inverse mass bounds
    // (the contact law takes the touching vertex's and triangle's, from the
    // same bodies).
    double tangentialDamping = 0.0;
    if (c.sliding != 1 && pair.tangentialStiffness > 0.0) {
      double inverseMass = tables.contactInverseMass[static_cast<std::size_t>(a)];
      if (other >= 0) inverseMass += tables.contactInverseMass[static_cast<std::size_t>(other)];
      tangentialDamping = law::tangentialDamping(pair.tangentialDampingRatio,
                                                 pair.tangentialStiffness, inverseMass);
    }
    sums[tree][b].add(law::stabilityRates(pair.stiffness, pair.damping, pair.tangentialStiffness,
                                          tangentialDamping, 1.0));
    any = true;
  };
  for (const Contact& c : evaluation.contacts) {
    if (c.a < 0) continue;
    book(c, c.a);
    if (c.other >= 0) book(c, c.other);
  }
  if (!any) return;
  // Each body's inverse effective mass bound is its particles' (ContactTables).
  double step = evaluation.contactCriticalStep;
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    if (sums[t].empty()) continue;
    const RigidTree& tree = model.rigidTrees[t];
    std::vector<double> w(tree.multibody.bodies.size(), 0.0);
    for (const BodyParticle& bp : tree.particles)
      w[static_cast<std::size_t>(bp.body)] =
          std::max(w[static_cast<std::size_t>(bp.body)],
                   tables.contactInverseMass[static_cast<std::size_t>(bp.particle)]);
    for (std::size_t b = 0; b < sums[t].size(); ++b)
      if (sums[t][b].stiffness != 0.0)
        step = std::min(step, dampedCriticalStep(std::sqrt(2.0 * sums[t][b].stiffness * w[b]),
                                                 2.0 * sums[t][b].damping * w[b]));
  }
  evaluation.contactCriticalStep = step;
}

}  // namespace

void treeParticleWrenches(const RigidTree& tree, const State& state, const Evaluation& evaluation,
                          std::vector<SpatialVector>& wrench) {
  // About the world origin: the force at the particle, and the torque of a contact
  // off its centre.
  wrench.assign(tree.multibody.bodies.size(), SpatialVector{});
  for (const BodyParticle& bp : tree.particles) {
    const auto i = static_cast<std::size_t>(bp.particle);
    const Vec3& f = evaluation.force[i];
    Vec3 moment = cross(state.position[i], f);
    if (i < evaluation.torque.size()) moment += evaluation.torque[i];
    SpatialVector& w = wrench[static_cast<std::size_t>(bp.body)];
    w.angular += moment;
    w.linear += f;
  }
}

void treeAccelerations(const Model& model, std::size_t treeIndex, const State& state,
                       const Evaluation& evaluation, MultibodyWorkspace& ws,
                       std::vector<double>& a) {
  const RigidTree& tree = model.rigidTrees[treeIndex];
  const Multibody& mb = tree.multibody;
  const std::vector<double>& q = state.treePositions[treeIndex];
  const std::vector<double>& v = state.treeVelocities[treeIndex];
  composeTreeInputs(model, tree, q, v, ws);
  const MultibodyInputs& in = ws.inputs;
  treeParticleWrenches(tree, state, evaluation, ws.inputs.wrench);
  // Each rate's effort as the step's implicit terms give it at v⁺ = v: the explicit
  // effort and servo together within their bound, less the joint's damping.
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  std::vector<double> tau(n);
  for (std::size_t i = 0; i < n; ++i) {
    const MultibodyBody& body = mb.bodies[static_cast<std::size_t>(mb.dofBody[i])];
    const bool oneDof = velocityCountOf(body.joint) == 1;
    double effort = in.effort[i];
    if (oneDof) {
      effort +=
          -in.servoStiffness[i] * (q[static_cast<std::size_t>(body.qStart)] - in.servoTarget[i]) -
          in.servoDamping[i] * (v[i] - in.servoTargetRate[i]);
      const double limit = std::min(body.effortLimit, in.effortLimit[i]);
      effort = std::clamp(effort, -limit, limit) - body.damping * v[i];
    }
    tau[i] = effort;
  }
  MultibodyKinematics& kin = ws.kinematics;
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  a.resize(n);
  forwardDynamics(mb, kin, tau.data(), model.gravity, in.wrench.data(), a.data());
}

void placeTreeParticles(const Model& model, State& state,
                        std::vector<MultibodyWorkspace>& scratch) {
  sizeScratch(model, scratch);
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const RigidTree& tree = model.rigidTrees[t];
    MultibodyKinematics& kin = scratch[t].kinematics;
    updateKinematics(tree.multibody, state.treePositions[t].data(), kin);
    updateVelocities(tree.multibody, state.treeVelocities[t].data(), kin);
    for (const BodyParticle& bp : tree.particles) {
      const auto i = static_cast<std::size_t>(bp.particle);
      bodyPoint(kin, bp, state.position[i], state.velocity[i], state.spin[i]);
    }
  }
}

void stepRigidTrees(const Model& model, const ContactTables& tables, double dt,
                    const Evaluation& evaluation, State& state,
                    std::vector<MultibodyWorkspace>& scratch) {
  sizeScratch(model, scratch);
  thread_local std::vector<std::vector<PointLoadStiffness>> implicitLoads;
  // (The contacts found at t are the friction history by now: World::step.)
  collectImplicitLoads(model, tables, state, state.frictionHistory, implicitLoads);
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const RigidTree& tree = model.rigidTrees[t];
    const Multibody& mb = tree.multibody;
    MultibodyWorkspace& ws = scratch[t];
    MultibodyInputs& inputs = ws.inputs;
    std::vector<double>& q = state.treePositions[t];
    std::vector<double>& v = state.treeVelocities[t];
    composeTreeInputs(model, tree, q, v, ws);
    treeParticleWrenches(tree, state, evaluation, inputs.wrench);
    const MultibodyStepReport report =
        stepMultibody(mb, q, v, inputs, implicitLoads[t], dt, model.gravity, ws);
    state.dissipated += report.dissipated;
    state.implicitLoss += report.implicitLoss;
    state.external += report.inputWork;
    MultibodyKinematics& kin = ws.kinematics;
    updateKinematics(mb, q.data(), kin);
    updateVelocities(mb, v.data(), kin);
    for (const BodyParticle& bp : tree.particles) {
      const auto i = static_cast<std::size_t>(bp.particle);
      Vec3 p, velocity;
      bodyPoint(kin, bp, p, velocity, state.spin[i]);
      state.velocity[i] = velocity;
      state.position[i] = p - velocity * dt;
    }
  }
}

void addRigidTreeTerms(const Model& model, const ContactTables& tables, const State& state,
                       Evaluation& evaluation, std::vector<MultibodyWorkspace>& scratch,
                       bool kinematicsCurrent) {
  sizeScratch(model, scratch);
  limitTreeContactStep(model, tables, state.position, evaluation);
  for (std::size_t t = 0; t < model.rigidTrees.size(); ++t) {
    const RigidTree& tree = model.rigidTrees[t];
    const Multibody& mb = tree.multibody;
    MultibodyKinematics& kin = scratch[t].kinematics;
    const std::vector<double>& q = state.treePositions[t];
    if (!kinematicsCurrent) {
      updateKinematics(mb, q.data(), kin);
      updateVelocities(mb, state.treeVelocities[t].data(), kin);
    }
    evaluation.energy.kinetic += kineticEnergy(kin);
    // The joints' rotors (MJCF armature): ½ a q̇², inertia the step's matrix carries.
    const std::vector<double>& rates = state.treeVelocities[t];
    for (const MultibodyBody& body : mb.bodies)
      if (body.armature != 0.0 && velocityCountOf(body.joint) == 1)
        evaluation.energy.kinetic += 0.5 * body.armature *
                                     rates[static_cast<std::size_t>(body.vStart)] *
                                     rates[static_cast<std::size_t>(body.vStart)];
    evaluation.energy.gravity += gravitationalEnergy(kin, model.gravity);
    // The joints' servos' springs ½ κ (q − q*)².
    double servo = 0.0;
    for (const std::int32_t k : tree.jointOfRate) {
      if (k < 0) continue;
      const Joint& joint = model.joints[static_cast<std::size_t>(k)];
      if (joint.servoStiffness == 0.0) continue;
      const MultibodyBody& body = mb.bodies[static_cast<std::size_t>(joint.treeBody)];
      const double e = q[static_cast<std::size_t>(body.qStart)] - joint.servoTarget;
      servo += 0.5 * joint.servoStiffness * e * e;
    }
    evaluation.energy.jointSpring += servo;
    // The fixed-particle rule booked −F·v for each tree particle as driving power.
    double taken = 0.0;
    for (const BodyParticle& bp : tree.particles) {
      const auto i = static_cast<std::size_t>(bp.particle);
      taken += dot(evaluation.force[i], state.velocity[i]);
    }
    evaluation.drivingPower += taken;
  }
}

}  // namespace robophi
