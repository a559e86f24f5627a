// The built-in robots as rigid bodies (include/robophi/build/rigid_robots.h):
// each described as a URDF would describe it, then makeUrdfMultibody's road.
#include "robophi/build/rigid_robots.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "build/urdf_multibody_description.h"

namespace robophi::build {

namespace {

Vec3 unitVector(const Vec3& v) { return v / norm(v); }

// URDF's rpy (R = Rz(yaw) Ry(pitch) Rx(roll)) of a rotation matrix.
Vec3 rollPitchYawOf(const Mat3& R) {
  const double pitch = std::asin(std::clamp(-R.m[2][0], -1.0, 1.0));
  if (std::abs(R.m[2][0]) > 1.0 - 1e-12)  // gimbal lock: yaw carries it all
    return {0.0, pitch, std::atan2(-R.m[0][1], R.m[1][1])};
  return {std::atan2(R.m[2][1], R.m[2][2]), pitch, std::atan2(R.m[1][0], R.m[0][0])};
}

// A frame whose z axis is `z` (unit) and whose y axis is `y` made normal to it.
Mat3 frameFromZY(const Vec3& z, const Vec3& y) {
  const Vec3 yy = unitVector(y - z * dot(y, z));
  const Vec3 x = cross(yy, z);
  Mat3 R;
  for (int r = 0; r < 3; ++r) {
    R.m[r][0] = x[r];
    R.m[r][1] = yy[r];
    R.m[r][2] = z[r];
  }
  return R;
}

urdf::Link boxLink(const std::string& name, double mass, const Vec3& size, const Vec3& center) {
  urdf::Link link;
  link.name = name;
  link.inertial.present = true;
  link.inertial.mass = mass;
  link.inertial.origin.xyz = center;
  link.inertial.inertia = {mass * (size.y * size.y + size.z * size.z) / 12.0,
                           mass * (size.x * size.x + size.z * size.z) / 12.0,
                           mass * (size.x * size.x + size.y * size.y) / 12.0,
                           0.0,
                           0.0,
                           0.0};
  urdf::Collision box;
  box.origin.xyz = center;
  box.geometry.kind = urdf::Geometry::Kind::kBox;
  box.geometry.size = size;
  link.collisions.push_back(box);
  return link;
}

void addLink(urdf::Description& d, urdf::Link link, int parentJoint) {
  d.links.push_back(std::move(link));
  d.parentJoint.push_back(parentJoint);
}

// A straight serial chain of revolute joints on link `parent` (index into d.links):
// the first joint at `base` (parent frame), every link frame rotated by R from the
// parent's with its z along the chain; link k a box `thickness` square and
// links[k] long, of mass masses[k]; axes in the parent's frame.
void appendChain(urdf::Description& d, int parent, const Vec3& base, const Mat3& R,
                 const std::vector<double>& links, const std::vector<Vec3>& axes,
                 const std::vector<double>& masses, double thickness, double damping,
                 const std::string& linkPrefix, const std::string& jointPrefix) {
  int previous = parent;
  for (std::size_t k = 0; k < links.size(); ++k) {
    urdf::Joint joint;
    joint.name = jointPrefix + std::to_string(k + 1);
    joint.type = urdf::Joint::Type::kRevolute;
    joint.typeName = "revolute";
    if (k == 0) {
      joint.origin.xyz = base;
      joint.origin.rpy = rollPitchYawOf(R);
    } else {
      joint.origin.xyz = {0.0, 0.0, links[k - 1]};
    }
    joint.axis = unitVector(transpose(R) * axes[k]);
    joint.damping = damping;
    joint.parent = d.links[static_cast<std::size_t>(previous)].name;
    joint.parentIndex = previous;
    const auto child = static_cast<int>(d.links.size());
    joint.child = linkPrefix + std::to_string(k + 1);
    joint.childIndex = child;
    d.joints.push_back(joint);
    addLink(d,
            boxLink(joint.child, masses[k], {thickness, thickness, links[k]},
                    {0.0, 0.0, 0.5 * links[k]}),
            static_cast<int>(d.joints.size()) - 1);
    previous = child;
  }
}

UrdfMultibody build(const urdf::Description& d, const std::string& name, const Vec3& at) {
  UrdfMultibodySpec spec;
  spec.name = name;
  spec.placement.translation = at;
  spec.fixedBase = true;
  return makeUrdfMultibody(d, spec);
}

}  // namespace

UrdfMultibody makeRigidHand(const HandSpec& spec, const std::string& name) {
  makeHand(spec);  // the particle hand's checks (SpecError naming the field)
  const double rho = spec.palmRadius;
  const double fingerLength = spec.links[0] + spec.links[1] + spec.links[2];
  const double w = spec.width.value_or(0.15 * fingerLength / 3.0);
  const double palmHalfThickness = 0.25 * rho;  // the particle palm's particle radius
  const double thickness = 0.45 * std::min({spec.links[0], spec.links[1], spec.links[2]});
  urdf::Description d;
  d.file = "hand '" + name + "'";
  d.robotName = name;
  // The palm: a cylinder, its top where the particle palm's particles end.
  urdf::Link palm;
  palm.name = "palm";
  palm.inertial.present = true;
  const double palmMass = 0.25 * spec.mass;
  palm.inertial.mass = palmMass;
  const double side =
      palmMass * (3.0 * rho * rho + 4.0 * palmHalfThickness * palmHalfThickness) / 12.0;
  palm.inertial.inertia = {side, side, 0.5 * palmMass * rho * rho, 0.0, 0.0, 0.0};
  urdf::Collision disc;
  disc.geometry.kind = urdf::Geometry::Kind::kCylinder;
  disc.geometry.radius = rho;
  disc.geometry.length = 2.0 * palmHalfThickness;
  palm.collisions.push_back(disc);
  addLink(d, palm, -1);
  // The fingers in the Salisbury layout (makeHand): f1, f2 at ±45°, the thumb f3 at 180°.
  const double angles[3] = {M_PI / 4.0, -M_PI / 4.0, M_PI};
  const std::vector<double> links(spec.links.begin(), spec.links.end());
  std::vector<double> masses;
  for (double l : links) masses.push_back(0.75 * spec.mass / 3.0 * l / fingerLength);
  for (int f = 0; f < 3; ++f) {
    const double phi = angles[f];
    const Vec3 radial{std::cos(phi), std::sin(phi), 0.0};
    const Vec3 tangential{-std::sin(phi), std::cos(phi), 0.0};
    const Vec3 direction = Vec3{0, 0, 1} * std::cos(spec.spread) - radial * std::sin(spec.spread);
    // y = −tangential: a positive turn about it moves the tip toward the palm's axis.
    const Mat3 R = frameFromZY(direction, tangential * -1.0);
    const std::string prefix = "f" + std::to_string(f + 1);
    appendChain(d, 0, radial * (rho + w) + Vec3{0.0, 0.0, palmHalfThickness}, R, links,
                {radial, tangential * -1.0, tangential * -1.0}, masses, thickness,
                spec.jointDamping.value_or(0.0), prefix + ".l", prefix + ".j");
  }
  return build(d, name, spec.center);
}

UrdfMultibody makeRigidArm(const ArmSpec& spec, const std::string& name) {
  makeArm(spec);  // the particle arm's checks (SpecError naming the field)
  const std::size_t n = spec.links.size();
  std::vector<Vec3> axes;
  if (spec.axes.size() <= 1)
    axes.assign(n, spec.axes.empty() ? Vec3{0, 0, 1} : spec.axes[0]);
  else
    axes = spec.axes;
  for (Vec3& axis : axes) axis = unitVector(axis);
  const Vec3 direction = unitVector(spec.direction);
  const double total = std::accumulate(spec.links.begin(), spec.links.end(), 0.0);
  double minSpacing = spec.links[0] / spec.particlesPerLink;
  for (double l : spec.links) minSpacing = std::min(minSpacing, l / spec.particlesPerLink);
  const double thickness = 2.0 * (spec.radius > 0.0 ? spec.radius : 0.45 * minSpacing);
  urdf::Description d;
  d.file = "arm '" + name + "'";
  d.robotName = name;
  urdf::Link base;
  base.name = "base";
  addLink(d, base, -1);
  std::vector<double> masses;
  for (double l : spec.links) masses.push_back(spec.mass * l / total);
  const Mat3 R =
      frameFromZY(direction, std::abs(dot(axes[0], direction)) < 0.999 ? axes[0] : Vec3{0, 0, 1});
  appendChain(d, 0, {}, R, spec.links, axes, masses, thickness, spec.jointDamping.value_or(0.0),
              "l", "j");
  return build(d, name, spec.base);
}

}  // namespace robophi::build
