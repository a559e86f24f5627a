// Sensors (robophi/sensors.h): observers that read a World at its state, each in
// its own frame. Nothing here is part of the step.
#include "robophi/sensors.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "collision/facets.h"
#include "collision/rim_contact.h"
#include "integrate/rigid_trees.h"
#include "robophi/kinematics.h"

namespace robophi {

namespace {

constexpr std::array<const char*, 4> kKindNames = {"force_torque", "contact", "imu", "range"};

double determinant(const Mat3& a) { return dot(a.row(0), cross(a.row(1), a.row(2))); }

// The rotation nearest A (its polar factor), by Higham's iteration R ← ½ (R + R⁻ᵀ);
// the identity when A is singular (one particle, or particles on a line).
Mat3 nearestRotation(const Mat3& A) {
  Mat3 R = A;
  for (int k = 0; k < 50; ++k) {
    const double det = determinant(R);
    if (!(std::abs(det) > 1e-300)) return Mat3::identity();
    // R⁻ᵀ = cofactor(R) / det.
    const Vec3 r0 = R.row(0), r1 = R.row(1), r2 = R.row(2);
    const Vec3 c0 = cross(r1, r2), c1 = cross(r2, r0), c2 = cross(r0, r1);
    Mat3 next;
    for (int c = 0; c < 3; ++c) {
      next.m[0][c] = 0.5 * (R.m[0][c] + c0[c] / det);
      next.m[1][c] = 0.5 * (R.m[1][c] + c1[c] / det);
      next.m[2][c] = 0.5 * (R.m[2][c] + c2[c] / det);
    }
    double change = 0.0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) change = std::max(change, std::abs(next.m[r][c] - R.m[r][c]));
    R = next;
    if (change < 1e-15) break;
  }
  return R;
}

// x = A⁻¹ b for a symmetric 3×3 A (Cramer); 0 when A is singular.
Vec3 solve3(const Mat3& A, const Vec3& b) {
  const double det = determinant(A);
  if (!(std::abs(det) > 1e-300)) return {};
  const Vec3 c0 = A.column(0), c1 = A.column(1), c2 = A.column(2);
  return Vec3{dot(b, cross(c1, c2)), dot(c0, cross(b, c2)), dot(c0, cross(c1, b))} / det;
}

// Where a contact acts (docs/contact.md "Where a contact acts"): a vertex, a point
// of a triangle, a round body's surface point, a's own surface against the
// environment, or midway through the overlap of two particles' spheres.
Vec3 contactPoint(const Model& model, const State& state, const Contact& c) {
  if (c.vertex >= 0) return touchingPoint(model, c, state.position);  // a vertex, or on an edge
  if (c.facet >= 0) {
    const SurfaceTriangle& t = model.surfaceTriangles[static_cast<std::size_t>(c.facet)];
    return surfaceVertexPoint(model, t.vertex[0], state.position) * c.facetWeights.x +
           surfaceVertexPoint(model, t.vertex[1], state.position) * c.facetWeights.y +
           surfaceVertexPoint(model, t.vertex[2], state.position) * c.facetWeights.z;
  }
  if (c.rim >= 0)
    return rimCenter(model, model.rims[static_cast<std::size_t>(c.rim)], state.position) + c.arm;
  const auto a = static_cast<std::size_t>(c.a);
  if (c.other < 0) return state.position[a] - c.normal * model.radius[a];
  return state.position[a] - c.normal * (model.radius[a] + 0.5 * c.depth);
}

// The distance along the unit ray o + t d (t >= 0) to a sphere, or infinity.
double raySphere(const Vec3& o, const Vec3& d, const Vec3& center, double radius) {
  const Vec3 oc = o - center;
  const double b = dot(oc, d), c = squaredNorm(oc) - radius * radius;
  if (c <= 0.0) return 0.0;  // starts inside
  const double disc = b * b - c;
  if (disc < 0.0 || b > 0.0) return std::numeric_limits<double>::infinity();
  return -b - std::sqrt(disc);
}

double rayBox(const Vec3& o, const Vec3& d, const BoxObstacle& box) {
  // Slabs in the box's own axes.
  const Vec3 r = o - box.center;
  const Vec3 axes[3] = {box.axisX, box.axisY, box.axisZ};
  double enter = 0.0, leave = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double p = dot(r, axes[k]), v = dot(d, axes[k]), h = box.halfExtents[k];
    if (v == 0.0) {
      if (std::abs(p) > h) return std::numeric_limits<double>::infinity();
      continue;
    }
    double t0 = (-h - p) / v, t1 = (h - p) / v;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return enter <= leave ? enter : std::numeric_limits<double>::infinity();
}

double rayPlane(const Vec3& o, const Vec3& d, const GroundPlane& plane) {
  const double height = dot(o - plane.point, plane.normal);
  if (height <= 0.0) return 0.0;  // starts inside the solid
  const double rate = dot(d, plane.normal);
  if (rate >= 0.0) return std::numeric_limits<double>::infinity();
  return -height / rate;
}

// The first crossing of z = h(x, y) along the ray within [0, reach]: marched in steps
// of a quarter of the smaller cell, then bisected to the bit.
double rayHeightfield(const Vec3& o, const Vec3& d, const Heightfield& field, double reach) {
  const double inf = std::numeric_limits<double>::infinity();
  const auto [low, high] = std::minmax_element(field.heights.begin(), field.heights.end());
  // Where the ray is over the grid and between its lowest and highest sample.
  double t0 = 0.0, t1 = std::min(reach, 1e6);
  const double lo[3] = {field.originX, field.originY, *low};
  const double hi[3] = {field.originX + field.cellSizeX * (field.columns - 1),
                        field.originY + field.cellSizeY * (field.rows - 1), *high};
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < lo[k] || o[k] > hi[k]) return inf;
      continue;
    }
    double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return inf;
  const auto above = [&](double t) {
    const Vec3 p = o + d * t;
    return p.z - field.heightAt(p.x, p.y);
  };
  if (above(t0) <= 0.0) return t0;
  const double step = 0.25 * std::min(field.cellSizeX, field.cellSizeY);
  double previous = t0;
  for (double t = t0 + step;; t += step) {
    const double at = std::min(t, t1);
    if (above(at) <= 0.0) {
      double a = previous, b = at;  // above at a, not above at b
      for (int k = 0; k < 200 && b - a > 1e-12 * std::max(1.0, b); ++k) {
        const double mid = 0.5 * (a + b);
        (above(mid) > 0.0 ? a : b) = mid;
      }
      return b;
    }
    if (at >= t1) return inf;
    previous = at;
  }
}

}  // namespace

const char* sensorKindName(SensorKind kind) { return kKindNames[static_cast<std::size_t>(kind)]; }

bool parseSensorKind(const std::string& name, SensorKind& kind) {
  for (std::size_t k = 0; k < kKindNames.size(); ++k) {
    if (name == kKindNames[k]) {
      kind = static_cast<SensorKind>(k);
      return true;
    }
  }
  return false;
}

const std::vector<const char*>& SensorSet::valueNames(SensorKind kind) {
  static const std::vector<std::vector<const char*>> names = {
      {"fx", "fy", "fz", "tx", "ty", "tz"},
      {"fx", "fy", "fz", "px", "py", "pz", "fn"},
      {"ax", "ay", "az", "wx", "wy", "wz", "qw", "qx", "qy", "qz"},
      {"d"}};
  return names[static_cast<std::size_t>(kind)];
}

std::size_t SensorSet::valueCountOf(SensorKind kind) { return valueNames(kind).size(); }

std::int32_t SensorSet::find(const std::string& name) const {
  for (std::size_t k = 0; k < sensors_.size(); ++k)
    if (sensors_[k].spec.name == name) return static_cast<std::int32_t>(k);
  return -1;
}

std::vector<std::string> SensorSet::columns() const {
  std::vector<std::string> out;
  for (const Resolved& s : sensors_)
    for (const char* value : valueNames(s.spec.kind)) out.push_back(s.spec.name + ":" + value);
  return out;
}

void SensorSet::add(const Model& model, const State& reference, const SensorSpec& spec) {
  const std::string what = "sensor '" + spec.name + "'";
  if (spec.name.empty()) throw std::invalid_argument("a sensor needs a name");
  if (find(spec.name) >= 0)
    throw std::invalid_argument(what + ": the name is given to another sensor already");
  if (spec.kind == SensorKind::kRange && !(spec.maxRange > 0.0))
    throw std::invalid_argument(what + ": max_range = " + std::to_string(spec.maxRange) +
                                " m must be > 0");
  Resolved r;
  r.spec = spec;
  if (spec.kind == SensorKind::kJointForceTorque) {
    std::string known;
    for (std::size_t j = 0; j < model.joints.size(); ++j) {
      const Joint& joint = model.joints[j];
      if (!joint.inTree()) continue;
      known += (known.empty() ? "" : ", ") + joint.name;
      if (joint.name == spec.on) {
        r.tree = joint.tree;
        r.body = joint.treeBody;
      }
    }
    if (r.tree < 0)
      throw std::invalid_argument(what + ": no joint of a rigid tree named '" + spec.on +
                                  "' (force_torque sensors read a rigid robot's joints; there " +
                                  (known.empty() ? std::string("is none") : "are: " + known) + ")");
  } else {
    // A rigid tree's frame first (by name, or with its robot's name as prefix), then an object.
    for (std::size_t t = 0; t < model.rigidTrees.size() && r.tree < 0; ++t) {
      const Multibody& mb = model.rigidTrees[t].multibody;
      std::int32_t f = mb.frameIndex(spec.on);
      if (f < 0) f = mb.frameIndex(mb.name + "." + spec.on);
      if (f < 0) continue;
      r.tree = static_cast<std::int32_t>(t);
      r.frame = f;
      r.body = mb.frames[static_cast<std::size_t>(f)].body;
    }
    if (r.tree < 0) {
      for (std::size_t o = 0; o < model.objects.size(); ++o)
        if (model.objects[o].name == spec.on) r.object = static_cast<std::int32_t>(o);
      if (r.object < 0) {
        std::string known;
        for (const RigidTree& tree : model.rigidTrees)
          for (const MultibodyFrame& f : tree.multibody.frames) known += (known.empty() ? "" : ", ") + f.name;
        for (const ObjectInfo& o : model.objects) known += (known.empty() ? "" : ", ") + o.name;
        throw std::invalid_argument(what + ": no link or object named '" + spec.on +
                                    "' (there are: " + known + ")");
      }
      const ObjectInfo& object = model.objects[static_cast<std::size_t>(r.object)];
      // An object that one body of a rigid tree carries (a rigid object) is that body.
      if (model.isCarried(object.firstParticle)) {
        const auto t = static_cast<std::size_t>(model.carriedBy[static_cast<std::size_t>(object.firstParticle)]);
        std::int32_t body = -1;
        bool one = true;
        for (const BodyParticle& bp : model.rigidTrees[t].particles) {
          if (bp.particle < object.firstParticle || bp.particle >= object.firstParticle + object.particleCount)
            continue;
          if (body >= 0 && bp.body != body) one = false;
          body = bp.body;
        }
        if (one && body >= 0) {
          r.object = -1;
          r.tree = static_cast<std::int32_t>(t);
          r.body = body;
        }
      }
    }
    if (r.object >= 0) {
      const ObjectInfo& object = model.objects[static_cast<std::size_t>(r.object)];
      if (reference.position.size() != static_cast<std::size_t>(model.particleCount()))
        throw std::invalid_argument(what + ": the reference state is not sized for the model");
      // The particles' offsets from their centre of mass: the object frame's reference.
      Vec3 center;
      double mass = 0.0;
      for (ParticleIndex i = object.firstParticle; i < object.firstParticle + object.particleCount; ++i) {
        center += reference.position[static_cast<std::size_t>(i)] * model.mass[static_cast<std::size_t>(i)];
        mass += model.mass[static_cast<std::size_t>(i)];
      }
      center = center / mass;
      for (ParticleIndex i = object.firstParticle; i < object.firstParticle + object.particleCount; ++i)
        r.referenceOffsets.push_back(reference.position[static_cast<std::size_t>(i)] - center);
    }
  }
  // Its own particles: the object's, or those the link's body carries.
  if (spec.kind != SensorKind::kJointForceTorque) {
    r.own.assign(static_cast<std::size_t>(model.particleCount()), 0);
    if (r.object >= 0) {
      const ObjectInfo& object = model.objects[static_cast<std::size_t>(r.object)];
      std::fill_n(r.own.begin() + object.firstParticle, object.particleCount, 1);
    } else {
      for (const BodyParticle& bp : model.rigidTrees[static_cast<std::size_t>(r.tree)].particles)
        if (bp.body == r.body) r.own[static_cast<std::size_t>(bp.particle)] = 1;
    }
    // A ray passes through virtual particles too (goals, paths, carriers: they touch nothing).
    if (spec.kind == SensorKind::kRange)
      for (std::size_t i = 0; i < r.own.size(); ++i)
        if (model.objectOf[i] >= 0 && !model.objects[static_cast<std::size_t>(model.objectOf[i])].contact.touches)
          r.own[i] = 1;
  }
  needsTreeDynamics_ = needsTreeDynamics_ || (r.tree >= 0 && (spec.kind == SensorKind::kJointForceTorque ||
                                                              spec.kind == SensorKind::kImu));
  r.offset = valueCount_;
  valueCount_ += valueCountOf(spec.kind);
  sensors_.push_back(std::move(r));
}

struct SensorSet::TreeMotion {
  bool kinematics = false, dynamics = false;
  /// (bodies) each body's spatial acceleration (gravity as −g) and joint wrench.
  std::vector<SpatialVector> acceleration, jointWrench;
};

void SensorSet::read(const World& world, double* values) const {
  if (sensors_.empty()) return;
  const Model& model = world.model();
  const State& state = world.state();
  const Evaluation& evaluation = world.evaluation();
  scratch_.resize(model.rigidTrees.size());
  std::vector<TreeMotion> trees(model.rigidTrees.size());
  // Each tree a sensor is on: its kinematics and, when needed, its accelerations and
  // joint wrenches at the state (forward dynamics, then inverse dynamics at that a).
  for (const Resolved& s : sensors_) {
    if (s.tree < 0) continue;
    const auto t = static_cast<std::size_t>(s.tree);
    const Multibody& mb = model.rigidTrees[t].multibody;
    MultibodyWorkspace& ws = scratch_[t];
    TreeMotion& motion = trees[t];
    const bool dynamics = s.spec.kind == SensorKind::kJointForceTorque || s.spec.kind == SensorKind::kImu;
    if (dynamics && !motion.dynamics) {
      std::vector<double> a, tau(static_cast<std::size_t>(mb.velocityCount));
      treeAccelerations(model, t, state, evaluation, ws, a);
      motion.acceleration.resize(mb.bodies.size());
      motion.jointWrench.resize(mb.bodies.size());
      inverseDynamics(mb, ws.kinematics, a.data(), model.gravity, ws.inputs.wrench.data(), tau.data(),
                      motion.acceleration.data(), motion.jointWrench.data());
      motion.dynamics = motion.kinematics = true;
    } else if (!motion.kinematics) {
      updateKinematics(mb, state.treePositions[t].data(), ws.kinematics);
      updateVelocities(mb, state.treeVelocities[t].data(), ws.kinematics);
      motion.kinematics = true;
    }
  }
  for (const Resolved& s : sensors_) {
    double* out = values + s.offset;
    // The sensor frame S in the world, its velocity and (tree links) its spatial
    // acceleration; and which particles are its own.
    Pose X_WS;
    Vec3 omega, specificForce;
    const ObjectInfo* object = s.object >= 0 ? &model.objects[static_cast<std::size_t>(s.object)] : nullptr;
    if (s.tree >= 0) {
      const auto t = static_cast<std::size_t>(s.tree);
      const Multibody& mb = model.rigidTrees[t].multibody;
      const MultibodyKinematics& kin = scratch_[t].kinematics;
      const auto b = static_cast<std::size_t>(s.body);
      if (s.spec.kind == SensorKind::kJointForceTorque) {
        // The wrench about the world origin, moved to the child body's origin, in its axes.
        const Pose& X_WB = kin.X_WB[b];
        const SpatialVector& w = trees[t].jointWrench[b];
        const Vec3 force = transposeTimes(X_WB.rotation, w.linear);
        const Vec3 torque = transposeTimes(X_WB.rotation, w.angular - cross(X_WB.translation, w.linear));
        out[0] = force.x, out[1] = force.y, out[2] = force.z;
        out[3] = torque.x, out[4] = torque.y, out[5] = torque.z;
        continue;
      }
      X_WS = (s.frame >= 0 ? framePose(mb, kin, s.frame) : kin.X_WB[b]) * s.spec.X_LS;
      omega = kin.velocity[b].angular;
      if (s.spec.kind == SensorKind::kImu) {
        // The point's acceleration less g: A's linear part (at the origin, with −g)
        // carried to the point, plus ω × v_P.
        const SpatialVector& A = trees[t].acceleration[b];
        const Vec3 p = X_WS.translation;
        specificForce = A.linear + cross(A.angular, p) + cross(omega, pointVelocity(kin, s.body, p));
      }
    } else {
      // The object's frame: centre of mass, fitted rotation; its motion from its
      // particles' momentum and net force.
      const std::size_t first = static_cast<std::size_t>(object->firstParticle);
      const std::size_t count = static_cast<std::size_t>(object->particleCount);
      Vec3 center, velocity, force;
      double mass = 0.0, movingMass = 0.0;
      for (std::size_t i = first; i < first + count; ++i) {
        center += state.position[i] * model.mass[i];
        velocity += state.velocity[i] * model.mass[i];
        mass += model.mass[i];
        if (model.inverseMass[i] != 0.0) {
          force += evaluation.force[i];
          movingMass += model.mass[i];
        }
      }
      center = center / mass;
      velocity = velocity / mass;
      Mat3 fit = Mat3::zero(), inertia = Mat3::zero();
      Vec3 momentum;
      for (std::size_t i = first; i < first + count; ++i) {
        const Vec3 r = state.position[i] - center;
        const double m = model.mass[i];
        fit = fit + m * outer(r, s.referenceOffsets[i - first]);
        inertia = inertia + m * (squaredNorm(r) * Mat3::identity() - outer(r, r));
        momentum += cross(r, state.velocity[i] - velocity) * m;
      }
      X_WS = Pose{nearestRotation(fit), center} * s.spec.X_LS;
      omega = count == 1 ? (first < state.spin.size() ? state.spin[first] : Vec3{}) : solve3(inertia, momentum);
      if (s.spec.kind == SensorKind::kImu) {
        const Vec3 acceleration = movingMass > 0.0 ? force / movingMass : Vec3{};
        const Vec3 r = X_WS.translation - center;
        specificForce = acceleration - model.gravity + cross(omega, cross(omega, r));
      }
    }
    const auto own = [&](std::int32_t particle) {
      return particle >= 0 && s.own[static_cast<std::size_t>(particle)] != 0;
    };
    switch (s.spec.kind) {
      case SensorKind::kImu: {
        const Vec3 a = transposeTimes(X_WS.rotation, specificForce);
        const Vec3 w = transposeTimes(X_WS.rotation, omega);
        const Quaternion q = quaternionFromMatrix(X_WS.rotation);
        const double row[10] = {a.x, a.y, a.z, w.x, w.y, w.z, q.w, q.x, q.y, q.z};
        std::copy(row, row + 10, out);
        break;
      }
      case SensorKind::kContact: {
        // The resultant force and its moment about the world origin, and the contact
        // points' mean weighted by their normal forces.
        Vec3 force, moment, weighted;
        double normal = 0.0;
        for (const Contact& c : evaluation.contacts) {
          if (c.normalForce <= 0.0 && squaredNorm(c.frictionForce) == 0.0) continue;
          const bool onA = own(c.a), onOther = own(c.other);
          if (onA == onOther) continue;  // not its contact, or one with itself
          const Vec3 f = (c.normal * c.normalForce + c.frictionForce) * (onA ? 1.0 : -1.0);
          const Vec3 x = contactPoint(model, state, c);
          force += f;
          moment += cross(x, f);
          normal += c.normalForce;
          weighted += x * c.normalForce;
        }
        // The centre of pressure: where the resultant's line of action (its central
        // axis, p̄ + F × M_p̄ / |F|²) crosses the plane through the mean contact point p̄
        // normal to F. Unlike the mean itself it does not depend on how the contact
        // points happen to sit (two particle lattices): under a box at rest it is the
        // projection of the box's centre of mass.
        Vec3 centre;
        if (normal > 0.0) {
          const Vec3 mean = weighted / normal;
          const double f2 = squaredNorm(force);
          centre = f2 > 0.0 ? mean + cross(force, moment - cross(mean, force)) / f2 : mean;
        }
        const Vec3 f = transposeTimes(X_WS.rotation, force);
        const Vec3 p = normal > 0.0 ? inverse(X_WS) * centre : Vec3{};
        const double row[7] = {f.x, f.y, f.z, p.x, p.y, p.z, normal};
        std::copy(row, row + 7, out);
        break;
      }
      case SensorKind::kRange: {
        const Vec3 o = X_WS.translation, d = X_WS.rotation.column(2);
        const Environment& env = model.environment;
        double t = std::numeric_limits<double>::infinity();
        for (const GroundPlane& plane : env.planes) t = std::min(t, rayPlane(o, d, plane));
        for (const Heightfield& field : env.heightfields)
          t = std::min(t, rayHeightfield(o, d, field, std::min(t, s.spec.maxRange)));
        for (const BoxObstacle& box : env.boxes) t = std::min(t, rayBox(o, d, box));
        for (const SphereObstacle& sphere : env.spheres) t = std::min(t, raySphere(o, d, sphere.center, sphere.radius));
        for (ParticleIndex i = 0; i < model.particleCount(); ++i)
          if (!own(i))
            t = std::min(t, raySphere(o, d, state.position[static_cast<std::size_t>(i)],
                                      model.radius[static_cast<std::size_t>(i)]));
        out[0] = t <= s.spec.maxRange ? t : -1.0;
        break;
      }
      case SensorKind::kJointForceTorque:
        break;
    }
  }
}

}  // namespace robophi
