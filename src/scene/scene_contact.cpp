// The contact keys of a scene file (docs/contact.md): materials, the objects'
// materials, medium, contact settings and pair overrides; the environment is in
// scene_environment.cpp.
#include "scene/scene_contact.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

namespace robophi::scene {

namespace {

std::vector<std::string> materialNames(const Model& model) {
  std::vector<std::string> names;
  for (const Material& m : model.materials) names.push_back(m.name);
  return names;
}

// "materials": [{name, contactStiffness, contactDamping, staticFriction, kineticFriction}].
void readMaterials(DiagnosticSink& sink, const nlohmann::json& list, Model& model) {
  if (!list.is_array()) {
    sink.error("/materials", fmt::format("'materials': expected an array of materials, got {}",
                                         describeJson(list)));
    return;
  }
  std::map<std::string, std::string> firstDefinedAt;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = fmt::format("/materials/{}", k);
    const nlohmann::json& entry = list[k];
    const auto label = entry.is_object() && entry.contains("name") && entry["name"].is_string()
                           ? fmt::format("material '{}'", entry["name"].get<std::string>())
                           : fmt::format("material {}", at);
    ObjectReader r(sink, entry, at, label);
    if (!r.valid()) continue;
    const auto name = r.string("name", true);
    // Naming one "default" redefines material 0, starting from its values.
    Material material = name && *name == model.materials[0].name ? model.materials[0] : Material{};
    material.contactStiffness =
        r.numberOr("contactStiffness", material.contactStiffness, Bound::kPositive, "N/m");
    material.contactDamping =
        r.numberOr("contactDamping", material.contactDamping, Bound::kNonNegative, "N·s/m");
    material.staticFriction =
        r.numberOr("staticFriction", material.staticFriction, Bound::kNonNegative, "");
    material.kineticFriction =
        r.numberOr("kineticFriction", material.kineticFriction, Bound::kNonNegative, "");
    material.rollingResistance =
        r.numberOr("rollingResistance", material.rollingResistance, Bound::kNonNegative, "");
    r.finish();
    if (material.kineticFriction > material.staticFriction) {
      sink.error(r.memberPointer("kineticFriction"),
                 fmt::format("'kineticFriction' {} must not exceed 'staticFriction' {}",
                             material.kineticFriction, material.staticFriction));
    }
    if (!name) continue;
    if (name->empty()) {
      sink.error(r.memberPointer("name"), "'name': a material needs a non-empty name");
      continue;
    }
    const auto [first, fresh] = firstDefinedAt.emplace(*name, at);
    if (!fresh) {
      sink.error(r.memberPointer("name"),
                 fmt::format("material '{}' is defined twice (first at {})", *name, first->second));
      continue;
    }
    material.name = *name;
    if (*name == model.materials[0].name) {
      model.materials[0] = material;
    } else {
      model.materials.push_back(material);
    }
  }
}

// objects/k/material, matched to the model's objects by name.
void readObjectMaterials(DiagnosticSink& sink, const nlohmann::json& list, Model& model) {
  if (!list.is_array()) return;  // reported by the object reader
  for (std::size_t k = 0; k < list.size(); ++k) {
    const nlohmann::json& entry = list[k];
    if (!entry.is_object() || !entry.contains("material")) continue;
    // Only "material" is read here (the object reader knows the other keys): no finish().
    ObjectReader r(sink, entry, fmt::format("/objects/{}", k), "object");
    const std::int32_t material = readMaterialName(r, model);
    const auto name = entry.find("name");
    if (name == entry.end() || !name->is_string()) continue;
    // A URDF robot's links are "<name>.<link>" (docs/robots.md).
    const std::string& named = name->get<std::string>();
    for (ObjectInfo& object : model.objects)
      if (object.name == named || (object.kind == "link" && object.name.rfind(named + ".", 0) == 0))
        object.material = material;
  }
}

void readMedium(DiagnosticSink& sink, const nlohmann::json& value, Model& model) {
  ObjectReader r(sink, value, "/medium", "'medium'");
  if (!r.valid()) return;
  model.environment.viscosity =
      r.numberOr("viscosity", model.environment.viscosity, Bound::kNonNegative, "N·s/m");
  r.finish();
}

void readContactSettings(DiagnosticSink& sink, const nlohmann::json& value, Model& model) {
  ObjectReader r(sink, value, "/contact", "'contact'");
  if (!r.valid()) return;
  ContactSettings& s = model.contact;
  s.enabled = r.boolean("enabled").value_or(s.enabled);
  s.selfCollision = r.boolean("selfCollision").value_or(s.selfCollision);
  s.tangentialStiffnessRatio =
      r.numberOr("tangentialStiffnessRatio", s.tangentialStiffnessRatio, Bound::kNonNegative, "");
  s.tangentialDampingRatio =
      r.numberOr("tangentialDampingRatio", s.tangentialDampingRatio, Bound::kNonNegative, "");
  s.stickVelocity = r.numberOr("stickVelocity", s.stickVelocity, Bound::kNonNegative, "m/s");
  s.stribeckVelocity =
      r.numberOr("stribeckVelocity", s.stribeckVelocity, Bound::kNonNegative, "m/s");
  s.rolling = r.boolean("rolling").value_or(s.rolling);
  s.leafSize = r.integer("leafSize", 1).value_or(s.leafSize);
  r.finish();
}

// One name of a pair's "objects": its object index, -1 for "environment" (second
// name only), nullopt when unknown (reported).
std::optional<std::int32_t> pairObject(DiagnosticSink& sink, const nlohmann::json& name,
                                       const std::string& at, const Model& model,
                                       bool environmentAllowed) {
  const std::string text = name.get<std::string>();
  if (environmentAllowed && text == "environment") return -1;
  std::vector<std::string> names;
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    if (model.objects[o].name == text) return static_cast<std::int32_t>(o);
    names.push_back(model.objects[o].name);
  }
  if (environmentAllowed) names.emplace_back("environment");
  sink.error(at, fmt::format("no object named '{}'{}", text, didYouMean(text, names)));
  return std::nullopt;
}

// "contactPairs": [{objects: [a, b | "environment"], contactStiffness, ...}]; values
// not given come from the two materials' combination.
void readContactPairs(DiagnosticSink& sink, const nlohmann::json& list, Model& model) {
  if (!list.is_array()) {
    sink.error("/contactPairs",
               fmt::format("'contactPairs': expected an array, got {}", describeJson(list)));
    return;
  }
  constexpr const char* kObjects = "[objectName, objectName or \"environment\"]";
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = fmt::format("/contactPairs/{}", k);
    ObjectReader r(sink, list[k], at, fmt::format("contact pair {}", at));
    if (!r.valid()) continue;
    const nlohmann::json* names = r.member("objects");
    const auto stiffness = r.number("contactStiffness", Bound::kPositive, "N/m");
    const auto damping = r.number("contactDamping", Bound::kNonNegative, "N·s/m");
    const auto staticFriction = r.number("staticFriction", Bound::kNonNegative, "");
    const auto kineticFriction = r.number("kineticFriction", Bound::kNonNegative, "");
    r.finish();
    if (names == nullptr) {
      r.missing("objects", kObjects);
      continue;
    }
    if (!names->is_array() || names->size() != 2 || !(*names)[0].is_string() ||
        !(*names)[1].is_string()) {
      sink.error(r.memberPointer("objects"),
                 fmt::format("'objects': expected {}, got {}", kObjects, describeJson(*names)));
      continue;
    }
    const auto a = pairObject(sink, (*names)[0], r.memberPointer("objects") + "/0", model, false);
    const auto b = pairObject(sink, (*names)[1], r.memberPointer("objects") + "/1", model, true);
    if (!a || !b) continue;
    const Material& ma = model.materials[static_cast<std::size_t>(model.objects[*a].material)];
    const Material& mb =
        *b >= 0 ? model.materials[static_cast<std::size_t>(model.objects[*b].material)] : ma;
    const Material pair = combineMaterials(ma, mb);
    ContactPairOverride o;
    o.objectA = *a;
    o.objectB = *b;
    o.stiffness = stiffness.value_or(pair.contactStiffness);
    o.damping = damping.value_or(pair.contactDamping);
    o.staticFriction = staticFriction.value_or(pair.staticFriction);
    o.kineticFriction = kineticFriction.value_or(pair.kineticFriction);
    if (o.kineticFriction > o.staticFriction) {
      sink.error(
          kineticFriction ? r.memberPointer("kineticFriction") : r.memberPointer("staticFriction"),
          fmt::format("contact pair {}: kinetic friction {} must not exceed static "
                      "friction {}",
                      names->dump(), o.kineticFriction, o.staticFriction));
    }
    model.contact.pairOverrides.push_back(o);
  }
}

}  // namespace

std::int32_t readMaterialName(ObjectReader& r, const Model& model) {
  const auto name = r.string("material");
  if (!name) return 0;
  for (std::size_t m = 0; m < model.materials.size(); ++m)
    if (model.materials[m].name == *name) return static_cast<std::int32_t>(m);
  r.sink().error(r.memberPointer("material"),
                 fmt::format("'material': no material named '{}' in /materials{}", *name,
                             didYouMean(*name, materialNames(model))));
  return 0;
}

void readContactKeys(ObjectReader& root, const std::string& sceneDirectory, Model& model) {
  DiagnosticSink& sink = root.sink();
  // Materials first: the objects, the environment and the pairs name them.
  if (const auto* list = root.member("materials")) readMaterials(sink, *list, model);
  if (const auto* list = root.member("objects")) readObjectMaterials(sink, *list, model);
  if (const auto* value = root.member("environment"))
    readEnvironment(sink, *value, "/environment", sceneDirectory, model);
  if (const auto* value = root.member("medium")) readMedium(sink, *value, model);
  if (const auto* value = root.member("contact")) readContactSettings(sink, *value, model);
  if (const auto* list = root.member("contactPairs")) readContactPairs(sink, *list, model);
}

}  // namespace robophi::scene
