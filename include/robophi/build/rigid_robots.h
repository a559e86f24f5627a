#pragma once
/// \file
/// The built-in robots as rigid bodies ("rigid": true; docs/robots.md "Rigid
/// bodies", docs/robotics.md): each is described in memory as a URDF would
/// describe it (links with box and cylinder collision shapes, their masses and
/// inertias, revolute joints with their axes) and built by the URDF's road,
/// build::makeUrdfMultibody, to be placed by build::placeUrdfMultibody: every
/// link one rigid body, every joint a joint of a tree in reduced coordinates,
/// named as the particle robot's ("<name>.f1.j1", "<name>.j1"), contact by
/// particles on the links' surfaces.
///
///     build::UrdfMultibody hand = build::makeRigidHand(build::HandSpec{}, "hand");
///     build::placeUrdfMultibody(builder, hand, {});

#include <string>

#include "robophi/build/robots.h"
#include "robophi/build/urdf_multibody.h"

namespace robophi::build {

/// The hand (HandSpec, the particle hand's geometry and mass) as rigid bodies: the
/// palm a cylinder of radius palmRadius and thickness palmRadius / 2 (its top face
/// the particle palm's top, a quarter of the mass), welded at `center`; each
/// finger link a box as long as the link and 0.45 × the shortest link thick (the
/// particle finger's thickness) on the particle finger's line, the fingers' mass
/// (three quarters) shared in proportion to length. Links "<name>.palm",
/// "<name>.f1.l1".."<name>.f3.l3"; joints "<name>.f1.j1".."<name>.f3.j3": j1
/// about the finger's radial direction (sideways), j2 and j3 about its tangent,
/// q = 0 straight (as the hand is built, `spread` included) and q > 0 flexing the
/// finger toward the palm's axis; no position limits, damping `jointDamping`
/// (unset: 0). jointStiffness is the scene's servo (not part of the bodies).
UrdfMultibody makeRigidHand(const HandSpec& spec, const std::string& name);

/// The arm (ArmSpec) as rigid bodies: a fixed base, then each link a box as long as
/// the link and 2 × its particles' radius thick (0.9 × its spacing when `radius` is
/// 0) along the straight arm, the mass shared in proportion to length; links
/// "<name>.base", "<name>.l1".., joints "<name>.j1".. about `axes`, q = 0 straight.
UrdfMultibody makeRigidArm(const ArmSpec& spec, const std::string& name);

}  // namespace robophi::build
