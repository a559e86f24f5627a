// Reading the "control" section of a scene (docs/robots.md "Controlling
// joints") into build::ControlSpec: every value checked where it stands, joint
// and object names with a suggestion, the actuators checked against the model.
#include "scene/scene_control.h"

#include <fmt/format.h>

#include <filesystem>

#include "robophi/build/control.h"
#include "robophi/build/input_files.h"
#include "scene/scene_robotics.h"

namespace robophi::scene {

namespace {

using build::ActuatorSpec;
using build::BaseMotionSpec;
using build::ConditionSpec;
using build::ControlSpec;
using build::JointMode;
using build::PhaseSpec;
using build::Trajectory;

// "linear" or "cubic" at `key` of `r` (default linear).
build::Interpolation readInterpolation(ObjectReader& r) {
  const auto name = r.string("interpolation");
  if (!name || *name == "linear") return build::Interpolation::kLinear;
  if (*name == "cubic") return build::Interpolation::kCubic;
  r.sink().error(r.memberPointer("interpolation"),
                 fmt::format("unknown interpolation \"{}\"{} (expected linear or cubic)", *name,
                             didYouMean(*name, {"linear", "cubic"})));
  return build::Interpolation::kLinear;
}

// [[t, v], ...] with `width` values per keyframe (1: numbers, 3: [x, y, z]).
// With `angles`, a keyframe may end with an angle (rad): [t, [x, y, z], angle].
bool readKeyframes(DiagnosticSink& sink, const nlohmann::json& list, const std::string& at,
                   std::size_t width, std::vector<double>& times,
                   std::vector<std::vector<double>>& values,
                   std::vector<double>* angles = nullptr) {
  if (!list.is_array() || list.empty()) {
    sink.error(at, fmt::format("'keyframes': expected a non-empty array of [t, {}], got {}",
                               width == 1 ? "value" : "[x, y, z]", describeJson(list)));
    return false;
  }
  bool ok = true;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string where = fmt::format("{}/{}", at, k);
    const nlohmann::json& e = list[k];
    const bool withAngle = angles != nullptr && e.is_array() && e.size() == 3 && e[2].is_number();
    const bool shape = e.is_array() && (e.size() == 2 || withAngle) && e[0].is_number() &&
                       (width == 1 ? e[1].is_number()
                                   : e[1].is_array() && e[1].size() == 3 && e[1][0].is_number() &&
                                         e[1][1].is_number() && e[1][2].is_number());
    if (!shape) {
      sink.error(
          where,
          fmt::format("expected a keyframe [t, {}{}], got {}", width == 1 ? "value" : "[x, y, z]",
                      angles != nullptr ? "] or [t, [x, y, z], angle" : "", describeJson(e)));
      ok = false;
      continue;
    }
    const double t = e[0].get<double>();
    if (!times.empty() && !(t > times.back())) {
      sink.error(where + "/0", fmt::format("keyframe time {} s must be after the previous one "
                                           "({} s)",
                                           t, times.back()));
      ok = false;
    } else if (t < 0.0) {
      sink.error(where + "/0", fmt::format("keyframe time {} s must be >= 0", t));
      ok = false;
    }
    times.push_back(t);
    if (angles != nullptr) angles->push_back(withAngle ? e[2].get<double>() : 0.0);
    if (width == 1) {
      values.push_back({e[1].get<double>()});
    } else {
      values.push_back({e[1][0].get<double>(), e[1][1].get<double>(), e[1][2].get<double>()});
    }
  }
  return ok;
}

// A target: a number, {"keyframes": [[t, v], ...], "interpolation"} or
// {"sine": {"amplitude", "period", "phase", "offset"}}.
std::optional<Trajectory> readTrajectory(DiagnosticSink& sink, const nlohmann::json& value,
                                         const std::string& at, std::string_view unit) {
  if (value.is_number()) return Trajectory::constant(value.get<double>());
  ObjectReader r(sink, value, at, "target");
  if (!r.valid()) return std::nullopt;
  const nlohmann::json* keyframes = r.member("keyframes");
  const nlohmann::json* sine = r.member("sine");
  Trajectory t;
  std::optional<Trajectory> out;
  if ((keyframes != nullptr) == (sine != nullptr)) {
    sink.error(at, fmt::format("a target is a number ({}), {{\"keyframes\": [[t, value], ...]}} "
                               "or {{\"sine\": {{...}}}}",
                               unit));
  } else if (keyframes != nullptr) {
    t.kind = Trajectory::Kind::kKeyframes;
    t.interpolation = readInterpolation(r);
    std::vector<std::vector<double>> values;
    if (readKeyframes(sink, *keyframes, r.memberPointer("keyframes"), 1, t.times, values)) {
      for (const auto& v : values) t.values.push_back(v[0]);
      out = t;
    }
  } else {
    ObjectReader s(sink, *sine, r.memberPointer("sine"), "sine");
    if (s.valid()) {
      t.kind = Trajectory::Kind::kSine;
      const auto amplitude = s.number("amplitude", Bound::kAny, unit, true);
      const auto period = s.number("period", Bound::kPositive, "s", true);
      t.phase = s.numberOr("phase", 0.0, Bound::kAny, "rad");
      t.offset = s.numberOr("offset", 0.0, Bound::kAny, unit);
      s.finish();
      if (amplitude && period) {
        t.amplitude = *amplitude;
        t.period = *period;
        out = t;
      }
    }
  }
  r.finish();
  return out;
}

std::optional<JointMode> readMode(ObjectReader& r) {
  const auto name = r.string("mode", true);
  if (!name) return std::nullopt;
  if (*name == "position") return JointMode::kPosition;
  if (*name == "velocity") return JointMode::kVelocity;
  if (*name == "effort") return JointMode::kEffort;
  if (*name == "passive") return JointMode::kPassive;
  r.sink().error(
      r.memberPointer("mode"),
      fmt::format("unknown mode \"{}\"{} (expected position, velocity, effort or "
                  "passive)",
                  *name, didYouMean(*name, {"position", "velocity", "effort", "passive"})));
  return std::nullopt;
}

// One joint's actuator: {"mode", "kp", "kd", "kv", "target", "feedForward",
// "effortLimit", "velocityLimit", "damping", "friction"}.
std::optional<ActuatorSpec> readActuator(DiagnosticSink& sink, const nlohmann::json& entry,
                                         const std::string& at, std::size_t joint,
                                         const Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("actuator of '{}'", scene.model.joints[joint].name));
  if (!r.valid()) return std::nullopt;
  const bool revolute = scene.model.joints[joint].kind == JointKind::kRevolute;
  const auto mode = readMode(r);
  ActuatorSpec a;
  a.joint = joint;
  a.kp = r.numberOr("kp", 0.0, Bound::kNonNegative, revolute ? "N·m/rad" : "N/m");
  a.kd = r.numberOr("kd", 0.0, Bound::kNonNegative, revolute ? "N·m·s/rad" : "N·s/m");
  a.kv = r.numberOr("kv", 0.0, Bound::kNonNegative, revolute ? "N·m·s/rad" : "N·s/m");
  a.feedForward = r.numberOr("feedForward", 0.0, Bound::kAny, revolute ? "N·m" : "N");
  a.effortLimit = r.number("effortLimit", Bound::kPositive, revolute ? "N·m" : "N");
  a.velocityLimit = r.number("velocityLimit", Bound::kPositive, revolute ? "rad/s" : "m/s");
  a.damping = r.number("damping", Bound::kNonNegative, revolute ? "N·m·s/rad" : "N·s/m");
  a.friction = r.number("friction", Bound::kNonNegative, revolute ? "N·m" : "N");
  const nlohmann::json* target = r.member("target");
  bool ok = mode.has_value();
  if (mode) {
    a.mode = *mode;
    const char* unit = *mode == JointMode::kPosition   ? (revolute ? "rad" : "m")
                       : *mode == JointMode::kVelocity ? (revolute ? "rad/s" : "m/s")
                                                       : (revolute ? "N·m" : "N");
    if (*mode == JointMode::kPosition && target == nullptr) {
      r.missing("target", fmt::format("a position target ({})", unit));
      ok = false;
    } else if (target != nullptr) {
      const auto t = readTrajectory(sink, *target, r.memberPointer("target"), unit);
      if (t) a.target = *t;
      ok = ok && t.has_value();
    }
    if (*mode == JointMode::kPosition && entry.is_object() && !entry.contains("kp")) {
      r.missing("kp", "the position gain kp");
      ok = false;
    }
    if (*mode == JointMode::kVelocity && entry.is_object() && !entry.contains("kv")) {
      r.missing("kv", "the velocity gain kv");
      ok = false;
    }
  }
  r.finish();
  if (!ok) return std::nullopt;
  if (const std::string problem = build::checkActuator(a, scene.model); !problem.empty()) {
    sink.error(at, problem);
    return std::nullopt;
  }
  return a;
}

// {"joint name": {actuator}, ...}.
std::vector<ActuatorSpec> readJoints(DiagnosticSink& sink, const nlohmann::json& list,
                                     const std::string& at, const Scene& scene) {
  std::vector<ActuatorSpec> out;
  if (!list.is_object()) {
    sink.error(at,
               fmt::format("'joints': expected an object {{\"joint name\": {{\"mode\": ...}}}}, "
                           "got {}",
                           describeJson(list)));
    return out;
  }
  for (const auto& [name, entry] : list.items()) {
    const std::string where = fmt::format("{}/{}", at, name);
    const auto joint = findNamedJoint(sink, scene.model, name, where);
    if (!joint) continue;
    if (auto a = readActuator(sink, entry, where, *joint, scene)) out.push_back(*a);
  }
  return out;
}

// {"name", "object" | "particles", "keyframes": [[t, [x, y, z]], ...], "interpolation"}:
// the object's fixed particles (or those listed) carried by the translation.
std::optional<BaseMotionSpec> readBase(DiagnosticSink& sink, const nlohmann::json& entry,
                                       const std::string& at, const Scene& scene) {
  ObjectReader r(sink, entry, at, "base");
  if (!r.valid()) return std::nullopt;
  BaseMotionSpec b;
  const auto objectName = r.string("object", true);
  b.name = r.string("name").value_or(objectName.value_or("base"));
  const build::Interpolation interpolation = readInterpolation(r);
  const nlohmann::json* keyframes = r.member("keyframes");
  const auto axis = r.vec3("axis", "-");
  r.finish();
  if (keyframes == nullptr) r.missing("keyframes", "[[t, [x, y, z]], ...] (s, m)");
  if (axis) b.axis = *axis;
  if (!objectName || keyframes == nullptr) return std::nullopt;
  const auto object = findObject(sink, scene, *objectName, r.memberPointer("object"));
  if (!object) return std::nullopt;
  const ObjectInfo& info = scene.model.objects[static_cast<std::size_t>(*object)];
  for (ParticleIndex p = info.firstParticle; p < info.firstParticle + info.particleCount; ++p)
    if (scene.model.isFixed(p)) b.particles.push_back(p);
  if (b.particles.empty()) {
    sink.error(r.memberPointer("object"),
               fmt::format("object '{}' has no fixed particle to move as a base", *objectName));
    return std::nullopt;
  }
  std::vector<double> times, angles;
  std::vector<std::vector<double>> values;
  if (!readKeyframes(sink, *keyframes, r.memberPointer("keyframes"), 3, times, values, &angles))
    return std::nullopt;
  b.angle.kind = Trajectory::Kind::kKeyframes;
  b.angle.interpolation = interpolation;
  b.angle.times = times;
  b.angle.values = angles;
  for (std::size_t k = 0; k < 3; ++k) {
    Trajectory& t = b.translation[k];
    t.kind = Trajectory::Kind::kKeyframes;
    t.interpolation = interpolation;
    t.times = times;
    for (const auto& v : values) t.values.push_back(v[k]);
  }
  return b;
}

std::vector<BaseMotionSpec> readBases(DiagnosticSink& sink, const nlohmann::json& list,
                                      const std::string& at, const Scene& scene) {
  std::vector<BaseMotionSpec> out;
  if (!list.is_array()) {
    sink.error(at, fmt::format("'bases': expected an array, got {}", describeJson(list)));
    return out;
  }
  for (std::size_t k = 0; k < list.size(); ++k)
    if (auto b = readBase(sink, list[k], fmt::format("{}/{}", at, k), scene)) out.push_back(*b);
  return out;
}

// "when": {"contactForce": {"object", "with", "above"}} or
// {"jointsAtTarget": {"joints", "tolerance"}}.
bool readWhen(DiagnosticSink& sink, const nlohmann::json& when, const std::string& at,
              const Scene& scene, ConditionSpec& c) {
  ObjectReader r(sink, when, at, "'when'");
  if (!r.valid()) return false;
  const nlohmann::json* force = r.member("contactForce");
  const nlohmann::json* joints = r.member("jointsAtTarget");
  r.finish();
  if ((force != nullptr) == (joints != nullptr)) {
    sink.error(at, "'when': expected one of \"contactForce\" or \"jointsAtTarget\"");
    return false;
  }
  if (force != nullptr) {
    ObjectReader f(sink, *force, r.memberPointer("contactForce"), "contactForce");
    if (!f.valid()) return false;
    c.kind = ConditionSpec::Kind::kContactForce;
    const auto object = f.string("object", true);
    const auto with = f.string("with");
    const auto above = f.number("above", Bound::kNonNegative, "N", true);
    f.finish();
    if (!object || !above) return false;
    const auto o = findObject(sink, scene, *object, f.memberPointer("object"));
    if (!o) return false;
    c.object = *o;
    if (with) {
      const auto w = findObject(sink, scene, *with, f.memberPointer("with"));
      if (!w) return false;
      c.other = *w;
    }
    c.force = *above;
    return true;
  }
  ObjectReader j(sink, *joints, r.memberPointer("jointsAtTarget"), "jointsAtTarget");
  if (!j.valid()) return false;
  c.kind = ConditionSpec::Kind::kJointsAtTarget;
  c.tolerance = j.numberOr("tolerance", c.tolerance, Bound::kPositive, "rad or m");
  const nlohmann::json* names = j.member("joints");
  j.finish();
  bool ok = true;
  if (names != nullptr) {
    if (!names->is_array()) {
      sink.error(j.memberPointer("joints"), "'joints': expected an array of joint names");
      return false;
    }
    for (std::size_t k = 0; k < names->size(); ++k) {
      const std::string where = fmt::format("{}/{}", j.memberPointer("joints"), k);
      if (!(*names)[k].is_string()) {
        sink.error(where, fmt::format("expected a joint name, got {}", describeJson((*names)[k])));
        ok = false;
        continue;
      }
      const auto joint = findNamedJoint(sink, scene.model, (*names)[k].get<std::string>(), where);
      if (joint) c.joints.push_back(*joint);
      ok = ok && joint.has_value();
    }
  }
  return ok;
}

// A phase: {"name", one of "at" (s) | "after" (s) | "when" {...}, "timeout" (s),
// "joints": {...}, "bases": [...]}.
std::optional<PhaseSpec> readPhase(DiagnosticSink& sink, const nlohmann::json& entry,
                                   const std::string& at, std::size_t index, const Scene& scene) {
  ObjectReader r(sink, entry, at, fmt::format("phase {}", index));
  if (!r.valid()) return std::nullopt;
  PhaseSpec p;
  p.name = r.string("name").value_or(fmt::format("phase{}", index + 1));
  const auto atTime = r.number("at", Bound::kNonNegative, "s");
  const auto after = r.number("after", Bound::kNonNegative, "s");
  const nlohmann::json* when = r.member("when");
  p.start.timeout = r.numberOr("timeout", 0.0, Bound::kNonNegative, "s");
  const nlohmann::json* joints = r.member("joints");
  const nlohmann::json* bases = r.member("bases");
  r.finish();
  const int starts = (entry.is_object() && entry.contains("at") ? 1 : 0) +
                     (entry.is_object() && entry.contains("after") ? 1 : 0) + (when ? 1 : 0);
  bool ok = true;
  if (starts > 1) {
    sink.error(at, fmt::format("phase '{}': give one of \"at\", \"after\" or \"when\"", p.name));
    ok = false;
  } else if (atTime) {
    p.start.kind = ConditionSpec::Kind::kAt;
    p.start.time = *atTime;
  } else if (after) {
    p.start.kind = ConditionSpec::Kind::kAfter;
    p.start.time = *after;
  } else if (when != nullptr) {
    ok = readWhen(sink, *when, r.memberPointer("when"), scene, p.start);
  } else if (starts == 0) {
    p.start.kind = ConditionSpec::Kind::kAfter;  // right after the previous phase
    p.start.time = 0.0;
  }
  if (joints != nullptr) p.actuators = readJoints(sink, *joints, r.memberPointer("joints"), scene);
  if (bases != nullptr) p.bases = readBases(sink, *bases, r.memberPointer("bases"), scene);
  if (!ok) return std::nullopt;
  return p;
}

// "mimic": [{"joint", "leader", "multiplier", "offset", "kp", "kd"}].
void readMimics(DiagnosticSink& sink, const nlohmann::json& list, const std::string& at,
                Scene& scene) {
  if (!list.is_array()) {
    sink.error(at, fmt::format("'mimic': expected an array, got {}", describeJson(list)));
    return;
  }
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string where = fmt::format("{}/{}", at, k);
    ObjectReader r(sink, list[k], where, "mimic");
    if (!r.valid()) continue;
    const auto joint = r.string("joint", true);
    const auto leader = r.string("leader", true);
    build::MimicSpec m;
    m.multiplier = r.numberOr("multiplier", 1.0, Bound::kAny, "-");
    m.offset = r.numberOr("offset", 0.0, Bound::kAny, "rad or m");
    const auto kp = r.number("kp", Bound::kPositive, "N·m/rad or N/m", true);
    m.kd = r.numberOr("kd", 0.0, Bound::kNonNegative, "N·m·s/rad or N·s/m");
    r.finish();
    if (!joint || !leader || !kp) continue;
    const auto j = findNamedJoint(sink, scene.model, *joint, r.memberPointer("joint"));
    const auto l = findNamedJoint(sink, scene.model, *leader, r.memberPointer("leader"));
    if (!j || !l) continue;
    if (*j == *l) {
      sink.error(r.memberPointer("leader"), "a joint cannot mimic itself");
      continue;
    }
    m.joint = *j;
    m.leader = *l;
    m.kp = *kp;
    scene.robotics.control.mimics.push_back(m);
  }
}

// "mounts": [{"object", "on", "stiffness", "damping", "links"}]: applied to the model now.
void readMounts(DiagnosticSink& sink, const nlohmann::json& list, const std::string& at,
                Scene& scene) {
  if (!list.is_array()) {
    sink.error(at, fmt::format("'mounts': expected an array, got {}", describeJson(list)));
    return;
  }
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string where = fmt::format("{}/{}", at, k);
    ObjectReader r(sink, list[k], where, "mount");
    if (!r.valid()) continue;
    build::MountSpec m;
    const auto object = r.string("object", true);
    const auto on = r.string("on", true);
    m.stiffness = r.numberOr("stiffness", m.stiffness, Bound::kPositive, "N/m");
    m.damping = r.number("damping", Bound::kNonNegative, "N·s/m");
    m.links = r.integer("links", 1).value_or(m.links);
    r.finish();
    if (!object || !on) continue;
    const auto o = findObject(sink, scene, *object, r.memberPointer("object"));
    const auto c = findObject(sink, scene, *on, r.memberPointer("on"));
    if (!o || !c) continue;
    m.object = *o;
    m.on = *c;
    try {
      build::addMount(scene.model, scene.initial.position, m);
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      sink.error(where, what.substr(what.find(": ") + 2));
    }
  }
}

// The joint trajectory file (trajectory.json, docs/output-format.md): its joints'
// names, times and positions, checked; the problems reported at `at`, naming the file.
struct ReplayFile {
  std::vector<std::string> joints;
  std::vector<double> times;
  std::vector<std::vector<double>> positions;  // (times) one value per joint
};
std::optional<ReplayFile> readReplayFile(DiagnosticSink& sink, const std::string& path,
                                         const std::string& at) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(build::readInputFile(path));
  } catch (const build::InputFileError& e) {
    sink.error(at, fmt::format("cannot read the joint trajectory: {}", e.what()));
    return std::nullopt;
  } catch (const nlohmann::json::exception& e) {
    sink.error(at, fmt::format("{}: not a JSON joint trajectory: {}", path, e.what()));
    return std::nullopt;
  }
  const auto bad = [&](const std::string& what) {
    sink.error(at, fmt::format("{}: {}", path, what));
    return std::optional<ReplayFile>{};
  };
  if (!doc.is_object() || !doc.contains("joints") || !doc.contains("time") ||
      !doc.contains("position"))
    return bad("expected an object with \"joints\", \"time\" and \"position\" (a run's "
               "trajectory.json)");
  ReplayFile file;
  const nlohmann::json &joints = doc["joints"], &times = doc["time"], &rows = doc["position"];
  if (!joints.is_array() || !times.is_array() || !rows.is_array() || times.empty() ||
      rows.size() != times.size())
    return bad(fmt::format("'joints', 'time' and 'position' must be arrays, 'position' one row "
                           "per time ({} times, {} rows)",
                           times.is_array() ? times.size() : 0, rows.is_array() ? rows.size() : 0));
  for (const auto& name : joints) {
    if (!name.is_string()) return bad(fmt::format("joints: expected names, got {}", name.dump()));
    file.joints.push_back(name.get<std::string>());
  }
  for (std::size_t k = 0; k < times.size(); ++k) {
    const nlohmann::json& row = rows[k];
    if (!times[k].is_number() || !row.is_array() || row.size() != file.joints.size())
      return bad(fmt::format("sample {}: expected a time and {} positions", k, file.joints.size()));
    const double t = times[k].get<double>();
    if (!std::isfinite(t) || (!file.times.empty() && !(t > file.times.back())))
      return bad(fmt::format("time[{}] = {} s must be finite and after the previous one", k, t));
    std::vector<double> q;
    for (const auto& value : row) {
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        return bad(fmt::format("position[{}]: expected finite numbers, got {}", k, row.dump()));
      q.push_back(value.get<double>());
    }
    file.times.push_back(t);
    file.positions.push_back(std::move(q));
  }
  return file;
}

// "replay": {"file", "kp", "kd", "interpolation", "joints"}: each joint of the file
// (or those listed) a position servo following its positions in time.
void readReplay(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
                Scene& scene) {
  ObjectReader r(sink, entry, at, "'replay'");
  if (!r.valid()) return;
  const auto fileName = r.string("file", true);
  const auto kp = r.number("kp", Bound::kPositive, "N·m/rad or N/m", true);
  const double kd = r.numberOr("kd", 0.0, Bound::kNonNegative, "N·m·s/rad or N·s/m");
  const build::Interpolation interpolation = readInterpolation(r);
  r.finish();
  if (!fileName || !kp) return;
  std::filesystem::path path(*fileName);
  if (path.is_relative())
    path = std::filesystem::path(scene.sourcePath).parent_path() / path;
  const auto file = readReplayFile(sink, path.string(), r.memberPointer("file"));
  if (!file) return;
  for (std::size_t j = 0; j < file->joints.size(); ++j) {
    const auto joint = findNamedJoint(sink, scene.model, file->joints[j], r.memberPointer("file"));
    if (!joint) continue;
    ActuatorSpec a;
    a.joint = *joint;
    a.mode = JointMode::kPosition;
    a.kp = *kp;
    a.kd = kd;
    a.target.kind = Trajectory::Kind::kKeyframes;
    a.target.interpolation = interpolation;
    a.target.times = file->times;
    for (const auto& q : file->positions) a.target.values.push_back(q[j]);
    if (const std::string problem = build::checkActuator(a, scene.model); !problem.empty()) {
      sink.error(at, problem);
      continue;
    }
    scene.robotics.control.actuators.push_back(std::move(a));
  }
}

}  // namespace

void readControlSection(DiagnosticSink& sink, const nlohmann::json& section,
                        const std::string& pointer, Scene& scene) {
  ObjectReader r(sink, section, pointer, "'control'");
  if (!r.valid()) return;
  const nlohmann::json* joints = r.member("joints");
  const nlohmann::json* mimic = r.member("mimic");
  const nlohmann::json* bases = r.member("bases");
  const nlohmann::json* sequence = r.member("sequence");
  const nlohmann::json* mounts = r.member("mounts");
  const nlohmann::json* replay = r.member("replay");
  r.finish();
  // Mounts first: they free the base particles that a base motion would otherwise move.
  if (mounts != nullptr) readMounts(sink, *mounts, pointer + "/mounts", scene);
  ControlSpec& control = scene.robotics.control;
  if (joints != nullptr) control.actuators = readJoints(sink, *joints, pointer + "/joints", scene);
  if (replay != nullptr) readReplay(sink, *replay, pointer + "/replay", scene);
  if (mimic != nullptr) readMimics(sink, *mimic, pointer + "/mimic", scene);
  if (bases != nullptr) control.bases = readBases(sink, *bases, pointer + "/bases", scene);
  if (sequence != nullptr) {
    if (!sequence->is_array()) {
      sink.error(
          pointer + "/sequence",
          fmt::format("'sequence': expected an array of phases, got {}", describeJson(*sequence)));
      return;
    }
    for (std::size_t k = 0; k < sequence->size(); ++k)
      if (auto p =
              readPhase(sink, (*sequence)[k], fmt::format("{}/sequence/{}", pointer, k), k, scene))
        control.phases.push_back(*p);
  }
}

}  // namespace robophi::scene
