#include "scene/scene_links.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <set>

#include "robophi/connector_forces.h"
#include "robophi/joints.h"

namespace robophi::scene {

namespace {

std::string refText(const nlohmann::json& ref) {
  return ref.is_string() ? ref.get<std::string>() : ref.dump();
}

// A list of particle references of exactly `count` entries at `pointer`.
std::optional<std::vector<ParticleIndex>> resolveList(DiagnosticSink& sink,
                                                      const nlohmann::json* list,
                                                      const std::string& pointer, std::size_t count,
                                                      std::string_view what,
                                                      const ParticleLookup& lookup) {
  if (list == nullptr) return std::nullopt;
  if (!list->is_array() || list->size() != count) {
    sink.error(pointer, fmt::format("'particles': {} needs {} particles {}, got {}", what, count,
                                    count == 2   ? "[a, b]"
                                    : count == 3 ? "[a, centre, b]"
                                                 : "[a, centre, b, axis]",
                                    describeJson(*list)));
    // Still check each reference, so that its own errors are reported too.
    if (list->is_array()) {
      for (std::size_t i = 0; i < list->size(); ++i)
        resolveParticle(sink, (*list)[i], fmt::format("{}/{}", pointer, i), lookup);
    }
    return std::nullopt;
  }
  std::vector<ParticleIndex> indices;
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) {
    const auto index = resolveParticle(sink, (*list)[i], fmt::format("{}/{}", pointer, i), lookup);
    ok = ok && index.has_value();
    indices.push_back(index.value_or(kNoParticle));
  }
  if (!ok) return std::nullopt;
  // The connector laws need distinct particles.
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t j = i + 1; j < count; ++j) {
      if (indices[i] == indices[j]) {
        sink.error(
            fmt::format("{}/{}", pointer, j),
            fmt::format("{} uses particle {} twice ({} and {}): its particles must differ", what,
                        refText((*list)[j]), refText((*list)[i]), refText((*list)[j])));
        return std::nullopt;
      }
    }
  }
  return indices;
}

// The robot object whose joints' names "<robot>.<joint>" `name` would share, or "".
std::string robotOwningName(const ParticleLookup& lookup, const std::string& name) {
  const auto dot = name.find('.');
  if (dot == std::string::npos || lookup.byName == nullptr) return {};
  const auto it = lookup.byName->find(name.substr(0, dot));
  if (it == lookup.byName->end()) return {};
  const SceneObject& object = (*lookup.objects)[it->second];
  const bool robot = object.kind == "arm" || object.kind == "vehicle" || object.kind == "hand";
  return robot ? object.name : std::string();
}

// Below this sine of the angle between an arm and a JS's axis (or between a TS's
// arms), the plane the connector turns in is undefined (MODEL §1.2, §1.3: no force
// is applied there), so a connector that starts there is refused.
constexpr double kMinSine = 1e-6;

// |a × b| / (|a| |b|): the sine of the angle between a and b (both non-zero).
double sineBetween(const Vec3& a, const Vec3& b) { return norm(cross(a, b)) / (norm(a) * norm(b)); }

// A JS's angle is measured about the axis c→d between the arms' projections on the
// plane normal to it (MODEL §1.3): undefined when an arm lies along the axis line.
std::string armOnAxis(const Vec3& pa, const Vec3& pc, const Vec3& pb, const Vec3& pd,
                      const char* nameA, const char* nameB) {
  const Vec3 axis = pd - pc;
  for (const auto& [name, p] : {std::pair{nameA, pa}, std::pair{nameB, pb}}) {
    if (sineBetween(p - pc, axis) < kMinSine)
      return fmt::format(
          "particle '{}' starts on the axis line through the centre and the axis particle: "
          "its angle about the axis is undefined; move it off that line",
          name);
  }
  return {};
}

// One connector entry {"type", "particles", "stiffness", ...}.
void readConnector(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& pointer,
                   const ParticleLookup& lookup, Model& model) {
  ObjectReader r(sink, entry, pointer, fmt::format("connector {}", pointer));
  if (!r.valid()) return;
  const auto type = r.string("type", true);
  const auto stiffness =
      r.number("stiffness", Bound::kNonNegative, type && *type == "LS" ? "N/m" : "N·m/rad", true);
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative,
                                    type && *type == "LS" ? "N·s/m" : "N·m·s/rad");
  const std::vector<std::string> types = {"LS", "TS", "JS"};
  std::size_t arity = 0;
  if (type) {
    if (*type == "LS") arity = 2;
    if (*type == "TS") arity = 3;
    if (*type == "JS") arity = 4;
    if (arity == 0) {
      sink.error(r.memberPointer("type"),
                 fmt::format("unknown connector type \"{}\"{} (expected LS, TS or JS)", *type,
                             didYouMean(*type, types)));
    }
  }
  std::optional<double> restLength, restAngle;
  if (arity == 2) restLength = r.number("restLength", Bound::kPositive, "m");
  if (arity >= 3) restAngle = r.number("restAngle", Bound::kAny, "rad");
  const nlohmann::json* list = r.member("particles");
  if (list == nullptr) r.missing("particles", "an array of particle references");
  if (arity != 0) r.finish();
  if (arity == 0) return;
  const auto p = resolveList(sink, list, r.memberPointer("particles"), arity, *type, lookup);
  if (!p || !stiffness) return;
  const auto& x = *lookup.position;
  if (arity == 2) {
    const double length = restLength.value_or(norm(x[(*p)[0]] - x[(*p)[1]]));
    if (!(length > 0.0)) {
      sink.error(r.memberPointer("particles"),
                 "LS particles start at the same position: the rest length would be 0; give "
                 "'restLength' > 0 (m)");
      return;
    }
    model.linearSprings.push_back({(*p)[0], (*p)[1], length, *stiffness, damping});
    return;
  }
  const Vec3 &pa = x[(*p)[0]], &pc = x[(*p)[1]], &pb = x[(*p)[2]];
  if (!(norm(pa - pc) > 0.0) || !(norm(pb - pc) > 0.0)) {
    sink.error(r.memberPointer("particles"),
               fmt::format("{} arm of zero length: the centre particle starts on a or b", *type));
    return;
  }
  if (arity == 3) {
    const double initial = torsionAngle(pa, pc, pb);
    const double angle = restAngle.value_or(initial);
    if (!(angle >= 0.0 && angle <= M_PI)) {
      sink.error(r.memberPointer("restAngle"),
                 fmt::format("'restAngle' of a TS must be in [0, π] rad, got {}", angle));
      return;
    }
    // Straight (or folded) arms define no plane: the TS cannot start bending
    // towards another angle (MODEL §1.2). At its own angle, 0 or π, it is fine.
    if (sineBetween(pa - pc, pb - pc) < kMinSine && std::abs(angle - initial) > 1e-9) {
      sink.error(r.memberPointer("particles"),
                 fmt::format("TS arms start collinear (angle {:.6g} rad), so the plane it would "
                             "bend in is undefined and it cannot reach 'restAngle' {:.6g} rad; "
                             "move the centre off the line a-b, or use restAngle {:.6g}",
                             initial, angle, initial > 1.0 ? M_PI : 0.0));
      return;
    }
    model.torsionSprings.push_back({(*p)[0], (*p)[1], (*p)[2], angle, *stiffness, damping});
    return;
  }
  const Vec3& pd = x[(*p)[3]];
  if (!(norm(pd - pc) > 0.0)) {
    sink.error(r.memberPointer("particles"),
               "JS axis particle starts on the centre: the axis would be undefined");
    return;
  }
  if (const std::string problem = armOnAxis(pa, pc, pb, pd, "a", "b"); !problem.empty()) {
    sink.error(r.memberPointer("particles"), "JS " + problem);
    return;
  }
  const double angle = wrapAngle(restAngle.value_or(jointAngle(pa, pc, pb, pd)));
  model.jointSprings.push_back({(*p)[0], (*p)[1], (*p)[2], (*p)[3], angle, *stiffness, damping});
}

// A single particle reference member of a joint.
std::optional<ParticleIndex> jointParticle(ObjectReader& r, std::string_view key,
                                           const ParticleLookup& lookup) {
  const nlohmann::json* ref = r.member(key);
  if (ref == nullptr) {
    if (r.valid()) r.missing(key, "a particle reference \"object:index\"");
    return std::nullopt;
  }
  return resolveParticle(r.sink(), *ref, r.memberPointer(key), lookup);
}

bool distinct(ObjectReader& r, std::initializer_list<std::pair<const char*, ParticleIndex>> refs) {
  for (auto i = refs.begin(); i != refs.end(); ++i) {
    for (auto j = std::next(i); j != refs.end(); ++j) {
      if (i->second == j->second) {
        r.sink().error(
            r.memberPointer(j->first),
            fmt::format("{}: '{}' and '{}' are the same particle", r.what(), i->first, j->first));
        return false;
      }
    }
  }
  return true;
}

void readRevolute(ObjectReader& r, const std::string& name, const ParticleLookup& lookup,
                  Model& model) {
  const auto a = jointParticle(r, "a", lookup);
  const auto c = jointParticle(r, "center", lookup);
  const auto b = jointParticle(r, "b", lookup);
  const auto d = jointParticle(r, "axis", lookup);
  const double stiffness = r.numberOr("stiffness", 0.0, Bound::kNonNegative, "N·m/rad");
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·m·s/rad");
  const auto target = r.number("target", Bound::kAny, "rad");
  r.finish();
  if (!a || !b || !c || !d) return;
  if (!distinct(r, {{"a", *a}, {"center", *c}, {"b", *b}, {"axis", *d}})) return;
  const auto& x = *lookup.position;
  if (!(norm(x[*a] - x[*c]) > 0.0) || !(norm(x[*b] - x[*c]) > 0.0) ||
      !(norm(x[*d] - x[*c]) > 0.0)) {
    r.sink().error(r.pointer(), fmt::format("{}: 'a', 'b' and 'axis' must start away from "
                                            "'center' (an arm or the axis has length 0)",
                                            r.what()));
    return;
  }
  if (const std::string problem = armOnAxis(x[*a], x[*c], x[*b], x[*d], "a", "b");
      !problem.empty()) {
    r.sink().error(r.pointer(), fmt::format("{}: {}", r.what(), problem));
    return;
  }
  // MODEL §1 JS: θ in [0, 2π) about n = p_axis - p_center; default target: the initial angle.
  const double initial = wrapAngle(jointAngle(x[*a], x[*c], x[*b], x[*d]));
  const double angle = wrapAngle(target.value_or(initial));
  model.jointSprings.push_back({*a, *c, *b, *d, angle, stiffness, damping});
  model.joints.push_back({name, JointKind::kRevolute,
                          static_cast<std::int32_t>(model.jointSprings.size()) - 1, -1, initial});
}

void readPrismatic(ObjectReader& r, const std::string& name, const ParticleLookup& lookup,
                   Model& model) {
  const auto origin = jointParticle(r, "origin", lookup);
  const auto slider = jointParticle(r, "slider", lookup);
  const auto end = jointParticle(r, "end", lookup);
  const auto stiffness = r.number("stiffness", Bound::kNonNegative, "N·m/rad", true);
  const double damping = r.numberOr("damping", 0.0, Bound::kNonNegative, "N·m·s/rad");
  std::optional<double> driveStiffness, driveTarget;
  double driveDamping = 0.0;
  const nlohmann::json* drive = r.member("drive");
  bool driveOk = true;
  if (drive != nullptr) {
    ObjectReader dr(r.sink(), *drive, r.memberPointer("drive"),
                    fmt::format("drive of joint '{}'", name));
    driveStiffness = dr.number("stiffness", Bound::kNonNegative, "N/m", true);
    driveDamping = dr.numberOr("damping", 0.0, Bound::kNonNegative, "N·s/m");
    driveTarget = dr.number("target", Bound::kPositive, "m");
    dr.finish();
    driveOk = dr.valid() && driveStiffness.has_value() &&
              (dr.member("target") == nullptr || driveTarget.has_value());
  }
  r.finish();
  if (!origin || !slider || !end || !stiffness || !driveOk) return;
  if (!distinct(r, {{"origin", *origin}, {"slider", *slider}, {"end", *end}})) return;
  const auto& x = *lookup.position;
  // The TS at 180° (MODEL §1) holds the slider on the segment origin-end.
  const double angle = (norm(x[*origin] - x[*slider]) > 0.0 && norm(x[*end] - x[*slider]) > 0.0)
                           ? torsionAngle(x[*origin], x[*slider], x[*end])
                           : 0.0;
  if (angle < M_PI - 1e-3) {
    r.sink().error(r.memberPointer("slider"),
                   fmt::format("{}: the slider must start on the segment from 'origin' to 'end' "
                               "(angle origin-slider-end is {:.4g}°, expected 180°)",
                               r.what(), angle * 180.0 / M_PI));
    return;
  }
  model.torsionSprings.push_back({*origin, *slider, *end, M_PI, *stiffness, damping});
  Joint joint{name, JointKind::kPrismatic,
              static_cast<std::int32_t>(model.torsionSprings.size()) - 1, -1};
  if (drive != nullptr) {
    const double rest = driveTarget.value_or(norm(x[*slider] - x[*origin]));
    model.linearSprings.push_back({*origin, *slider, rest, *driveStiffness, driveDamping});
    joint.driveSpring = static_cast<std::int32_t>(model.linearSprings.size()) - 1;
  }
  model.joints.push_back(joint);
}

}  // namespace

std::optional<ParticleIndex> resolveParticle(DiagnosticSink& sink, const nlohmann::json& ref,
                                             const std::string& pointer,
                                             const ParticleLookup& lookup) {
  const auto inRange = [&](const scene::SceneObject& object, std::int64_t index,
                           const std::string& text) -> std::optional<ParticleIndex> {
    if (!object.valid) return std::nullopt;  // its own errors are already reported
    const auto n = static_cast<std::int64_t>(object.geometry.size());
    if (index < -n || index >= n) {
      sink.error(pointer, fmt::format("'{}': object '{}' has {} particles (0..{} or -{}..-1)", text,
                                      object.name, n, n - 1, n));
      return std::nullopt;
    }
    return static_cast<ParticleIndex>(object.firstParticle + (index < 0 ? index + n : index));
  };
  if (lookup.local != nullptr && ref.is_number_integer())
    return inRange(*lookup.local, ref.get<std::int64_t>(), ref.dump());
  // A point of a rigid robot's link (docs/robotics.md "Links in goals").
  if (lookup.linkPoint && (ref.is_object() || (ref.is_string() &&
                                               ref.get<std::string>().find(':') == std::string::npos)))
    return lookup.linkPoint(sink, ref, pointer);
  if (!ref.is_string()) {
    sink.error(pointer, fmt::format("expected a particle reference \"object:index\"{}, got {}",
                                    lookup.local ? " or a local index" : "", describeJson(ref)));
    return std::nullopt;
  }
  const std::string text = ref.get<std::string>();
  const auto colon = text.rfind(':');
  std::int64_t index = 0;
  const char* first = text.data() + (colon == std::string::npos ? 0 : colon + 1);
  const char* last = text.data() + text.size();
  const auto parsed = std::from_chars(first, last, index);
  if (colon == std::string::npos || colon == 0 || parsed.ec != std::errc() || parsed.ptr != last ||
      first == last) {
    sink.error(pointer, fmt::format("particle reference \"{}\" must be \"object:index\", e.g. "
                                    "\"chain:0\" or \"chain:-1\" for the last",
                                    text));
    return std::nullopt;
  }
  const std::string objectName = text.substr(0, colon);
  const auto it = lookup.byName->find(objectName);
  if (it == lookup.byName->end()) {
    std::vector<std::string> names;
    for (const auto& [name, i] : *lookup.byName) names.push_back(name);
    sink.error(pointer, fmt::format("'{}': no object named '{}'{}", text, objectName,
                                    didYouMean(objectName, names)));
    return std::nullopt;
  }
  return inRange((*lookup.objects)[it->second], index, text);
}

void readConnectors(DiagnosticSink& sink, const nlohmann::json& list, const std::string& pointer,
                    const ParticleLookup& lookup, Model& model) {
  if (!list.is_array()) {
    sink.error(pointer, fmt::format("'connectors': expected an array of connectors, got {}",
                                    describeJson(list)));
    return;
  }
  for (std::size_t i = 0; i < list.size(); ++i)
    readConnector(sink, list[i], fmt::format("{}/{}", pointer, i), lookup, model);
}

void readJoints(DiagnosticSink& sink, const nlohmann::json& list, const std::string& pointer,
                const ParticleLookup& lookup, Model& model) {
  if (!list.is_array()) {
    sink.error(pointer,
               fmt::format("'joints': expected an array of joints, got {}", describeJson(list)));
    return;
  }
  std::map<std::string, std::string> seen;  // name → pointer of its first definition
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string at = fmt::format("{}/{}", pointer, i);
    ObjectReader head(sink, list[i], at, fmt::format("joint {}", at));
    if (!head.valid()) continue;
    const std::string name = head.string("name", true).value_or("");
    const auto type = head.string("type", true);
    if (head.member("name") && head.member("name")->is_string()) {
      if (name.empty()) {
        sink.error(head.memberPointer("name"), "'name' must not be empty");
      } else if (const auto [it, fresh] = seen.emplace(name, at); !fresh) {
        sink.error(
            head.memberPointer("name"),
            fmt::format("duplicate joint name '{}' (first defined at {})", name, it->second));
      } else if (const std::string robot = robotOwningName(lookup, name); !robot.empty()) {
        // Robots name their joints "<object>.<joint>" (joints.csv, robotics targets).
        sink.error(head.memberPointer("name"),
                   fmt::format("joint name '{}' is taken: names '{}.…' belong to the joints of "
                               "robot '{}'; choose a name without the prefix '{}.'",
                               name, robot, robot, robot));
      } else if (findJoint(model, name)) {
        sink.error(
            head.memberPointer("name"),
            fmt::format("joint name '{}' is already the name of a joint of the scene", name));
      }
    }
    ObjectReader r(sink, list[i], at, fmt::format("{} joint '{}'", type.value_or("?"), name));
    r.allow({"name", "type"});
    if (type && *type == "revolute") {
      readRevolute(r, name, lookup, model);
    } else if (type && *type == "prismatic") {
      readPrismatic(r, name, lookup, model);
    } else if (type) {
      sink.error(head.memberPointer("type"),
                 fmt::format("unknown joint type \"{}\"{} (expected revolute or prismatic)", *type,
                             didYouMean(*type, {"revolute", "prismatic"})));
    }
  }
}

}  // namespace robophi::scene
