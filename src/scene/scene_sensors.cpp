// Reading the scene's "sensors" (docs/scene-format.md "Sensors") into SensorSpecs:
// the kind by name with a suggestion, the frame, and the target resolved against
// the model (SensorSet::add names what there is).
#include "scene/scene_sensors.h"

#include <fmt/format.h>

#include <stdexcept>

#include "robophi/sensors.h"

namespace robophi::scene {

void readSensors(DiagnosticSink& sink, const nlohmann::json& list, const std::string& pointer,
                 Scene& scene) {
  if (!list.is_array()) {
    sink.error(pointer, fmt::format("'sensors': expected an array of sensors, got {}",
                                    describeJson(list)));
    return;
  }
  SensorSet resolved;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = fmt::format("{}/{}", pointer, k);
    ObjectReader r(sink, list[k], at, fmt::format("sensor {}", k));
    if (!r.valid()) continue;
    SensorSpec spec;
    const auto name = r.string("name", true);
    const auto type = r.string("type", true);
    const auto on = r.string("on", true);
    bool ok = name && type && on;
    if (type && !parseSensorKind(*type, spec.kind)) {
      sink.error(r.memberPointer("type"),
                 fmt::format("unknown sensor type \"{}\"{} (expected force_torque, contact, imu "
                             "or range)",
                             *type, didYouMean(*type, {"force_torque", "contact", "imu", "range"})));
      ok = false;
    }
    if (const auto position = r.vec3("position", "m")) spec.X_LS.translation = *position;
    if (const auto rpy = r.vec3("rpy", "rad")) spec.X_LS.rotation = rotationFromRollPitchYaw(*rpy);
    if (const auto range = r.number("maxRange", Bound::kPositive, "m")) spec.maxRange = *range;
    r.finish();
    if (!ok) continue;
    spec.name = *name;
    spec.on = *on;
    try {
      resolved.add(scene.model, scene.initial, spec);
      scene.sensors.push_back(spec);
    } catch (const std::invalid_argument& e) {
      sink.error(at, e.what());
    }
  }
}

}  // namespace robophi::scene
