#pragma once
/// \file
/// `robophi info` (docs/robots.md "robophi info"): every object of a scene (and every link of
/// its URDF robots) with its particle count, mass, centre of mass and inertia, next to the
/// values its URDF declares, and the relative errors.

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robophi/build/rigid_body.h"
#include "robophi/scene/scene.h"

namespace robophi {

/// One placed object, world frame at the initial state.
struct ObjectReport {
  std::string name, kind;
  int particles = 0;
  int fixedParticles = 0;
  /// A rigid body's (kind "rigid body"): its mass properties are its body's.
  bool rigidBody = false;
  /// Of its particles: mass (kg), centre of mass (m), inertia about it (kg·m², world axes).
  build::MassProperties built{};
  std::array<double, 3> principalMoments{};  // kg·m², ascending
  /// A URDF link: its robot's file, the link's name, the URDF's <inertial> in the world.
  bool urdfLink = false;
  std::string urdfFile, link;
  /// A fixed base without mass in the URDF, given notional particles (its declared values
  /// are not compared).
  bool notional = false;
  build::MassProperties declared{};
  std::array<double, 3> declaredMoments{};
  /// |built − declared| / declared (mass, each principal moment; 0 when declared is 0) and
  /// the centre of mass's distance (m).
  double massError = 0.0, centerOfMassError = 0.0;
  std::array<double, 3> momentError{};
  /// Links without particles of their own that move with this one (URDF frames).
  std::vector<std::string> frames{};
  std::vector<std::string> notes{};
  /// A URDF link's carrier particles (a virtual object "<link object>.carriers", counted in
  /// `built` here and not listed on its own).
  int carriers = 0;
  std::string partOf{};
};

struct SceneReport {
  std::string file;
  std::vector<ObjectReport> objects{};
};

/// The report of a loaded scene (a scene file or a bare URDF).
SceneReport reportScene(const Scene& scene);
/// As JSON: {"file", "objects": [{"name", "kind", "particles", "carriers", "fixedParticles",
/// "mass", "centerOfMass", "inertia": {xx..yz}, "principalMoments", "urdf": {"file", "link",
/// "notional", "mass", "centerOfMass", "inertia", "principalMoments", "frames"}, "errors":
/// {"mass", "centerOfMass", "principalMoments"}, "notes"}]}.
nlohmann::json reportJson(const SceneReport& report);
/// As a table, one object a line and a line of declared values under each URDF link.
std::string reportText(const SceneReport& report);

}  // namespace robophi
