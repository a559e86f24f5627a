#pragma once
// What the robot builders share (src/build/robots.cpp, vehicle_hand.cpp).

#include <optional>

#include "robophi/build/robots.h"

namespace robophi::build::detail {

/// Checks a robot's structural LS settings; `spec` names the robot's spec.
void checkRobotLinks(const char* spec, const RobotLinks& links);
/// Gives every LS of `o` the robot's structural stiffness and damping (no TS).
void resolveRobotLinks(GeneratedObject& o, const RobotLinks& links);
/// Sets every JS's damping: `damping`, or 0.05 √(κ m_min) w² with κ the
/// structural LS stiffness and w the width of the links.
void setJointDamping(GeneratedObject& o, std::optional<double> damping, double width);

}  // namespace robophi::build::detail
