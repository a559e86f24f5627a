#pragma once
/// \file
/// Sensors (docs/python.md "Sensors and vector I/O", docs/scene-format.md "Sensors"):
/// observers that read a World at its current state — a joint's force and torque, the
/// contact force and centre of pressure on a link or object, an IMU, a range finder —
/// each in its own frame. Reading never changes the world: a run's state hash is the
/// same with and without sensors, and a world without sensors pays nothing for them.
///
/// Frames: a link's sensor sits at X_LS on the link frame L (a rigid tree's frame);
/// an object's at X_OS on the object's frame O, whose origin is its particles' centre
/// of mass and whose orientation is the rotation that best carries the particles'
/// offsets from it in the reference state (the state the sensor set was made with,
/// the scene's initial state) to their offsets now (mass-weighted fit).

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "robophi/rotation.h"
#include "robophi/world.h"

namespace robophi {

/// What a sensor measures, and its values (SensorSet::columns).
enum class SensorKind : std::uint8_t {
  /// The wrench a rigid tree's joint transmits: the force and the torque the child
  /// body and everything below it receive from the parent through the joint, in the
  /// child body's frame at its origin (the joint frame as q turns it), N and N·m:
  /// fx fy fz tx ty tz (MuJoCo's force and torque sensors at the child's frame).
  kJointForceTorque,
  /// The sum of the contact forces on a link's or object's particles (N) and their
  /// centre of pressure (the contact points weighted by their normal forces, m) in
  /// the sensor frame, and the sum of the normal forces (N): fx fy fz px py pz fn
  /// (the centre of pressure is 0 0 0 when nothing touches). MuJoCo's touch sensor is fn.
  kContact,
  /// An accelerometer, gyro and orientation at the sensor frame: the specific force
  /// (the frame's acceleration less g, m/s², 0 in free fall, −g at rest), the
  /// angular velocity (rad/s), both in S, and R_WS as a unit quaternion: ax ay az
  /// wx wy wz qw qx qy qz (MuJoCo's accelerometer, gyro and framequat).
  kImu,
  /// The distance (m) along the sensor frame's +z axis from its origin to the first
  /// thing that collides — the environment's planes, heightfields, boxes and spheres,
  /// and every particle not of the sensor's own link or object — or −1 when nothing
  /// is within its range: d (MuJoCo's rangefinder).
  kRange,
};

/// "force_torque", "contact", "imu", "range"; parseSensorKind returns false on an
/// unknown name.
const char* sensorKindName(SensorKind kind);
bool parseSensorKind(const std::string& name, SensorKind& kind);

/// A sensor as declared (a scene file's "sensors" entry, World.add_sensor in Python).
struct SensorSpec {
  /// Its name, unique in a set (the columns of sensors.csv are "<name>:<value>").
  std::string name;
  SensorKind kind = SensorKind::kImu;
  /// What it is on: a joint's name (force_torque: a joint of a rigid tree), a link
  /// (a rigid tree's frame, by its name or with the robot's name as prefix) or an
  /// object (its name).
  std::string on;
  /// The sensor frame S in the link's or object's frame (force_torque: unused).
  Pose X_LS{};
  /// The range finder's reach (m), > 0.
  double maxRange = std::numeric_limits<double>::infinity();
};

/// Sensors resolved against a model, read from a World of that model.
class SensorSet {
 public:
  SensorSet() = default;

  /// Adds a sensor; `reference` is the state an object's frame is fitted against
  /// (its particles' offsets from their centre of mass there). Throws
  /// std::invalid_argument naming the sensor and the value: a name given twice, an
  /// unknown joint, link or object (with the names there are), a joint outside a
  /// rigid tree for force_torque, a range <= 0.
  void add(const Model& model, const State& reference, const SensorSpec& spec);

  bool empty() const { return sensors_.empty(); }
  std::size_t size() const { return sensors_.size(); }
  const SensorSpec& spec(std::size_t sensor) const { return sensors_[sensor].spec; }
  /// The index of the sensor named `name`, or -1.
  std::int32_t find(const std::string& name) const;
  /// Every value's name, in reading order: "<sensor>:<value>" (SensorKind's lists).
  std::vector<std::string> columns() const;
  /// The number of values a reading gives, and sensor k's first one and count.
  std::size_t valueCount() const { return valueCount_; }
  std::size_t offset(std::size_t sensor) const { return sensors_[sensor].offset; }
  static std::size_t valueCountOf(SensorKind kind);
  /// A kind's value names, in reading order (fx fy fz tx ty tz, ...).
  static const std::vector<const char*>& valueNames(SensorKind kind);

  /// Reads every sensor at the world's current state into `values` (valueCount()).
  /// Brings the world's evaluation up to date (as any accessor does); changes nothing else.
  /// Uses scratch of its own: one set is not read from two threads at once.
  void read(const World& world, double* values) const;

 private:
  struct Resolved {
    SensorSpec spec;
    std::size_t offset = 0;
    /// A rigid tree's link: the tree, its body and frame (-1: an object's).
    std::int32_t tree = -1, body = -1, frame = -1;
    /// An object (-1: a link's) and its particles' reference offsets from their centre.
    std::int32_t object = -1;
    std::vector<Vec3> referenceOffsets;
    /// (particleCount, contact, IMU and range sensors) 1 for its own particles.
    std::vector<char> own;
  };
  /// What the readings of one state share: each tree's accelerations, computed once.
  struct TreeMotion;
  std::vector<Resolved> sensors_;
  std::size_t valueCount_ = 0;
  /// Whether any sensor needs a tree's accelerations (force_torque, an IMU on a link).
  bool needsTreeDynamics_ = false;
  mutable std::vector<MultibodyWorkspace> scratch_;
};

}  // namespace robophi
