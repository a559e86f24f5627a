// Parsing of the contact keys of a scene file (docs/contact.md).
#include "collision/contact_scene.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <optional>

namespace robophi {

namespace {

// Reads fields of one JSON object, reporting problems with their pointer.
class Reader {
 public:
  Reader(const nlohmann::json& value, std::string pointer, const ContactErrorSink& error, bool& ok)
      : value_(value), pointer_(std::move(pointer)), error_(error), ok_(ok) {}

  bool isObject() {
    if (value_.is_object()) return true;
    fail(pointer_, fmt::format("expected an object, got {}", value_.dump()));
    return false;
  }
  const nlohmann::json* member(const char* key) const {
    const auto it = value_.find(key);
    return it == value_.end() ? nullptr : &*it;
  }
  std::string at(const char* key) const { return pointer_ + "/" + key; }

  // A number >= lower (or > lower when strict), in `unit`.
  std::optional<double> number(const char* key, double lower, bool strict, const char* unit) {
    const nlohmann::json* v = member(key);
    if (v == nullptr) return std::nullopt;
    if (!v->is_number() || !std::isfinite(v->get<double>()) ||
        (strict ? !(v->get<double>() > lower) : !(v->get<double>() >= lower))) {
      fail(at(key), fmt::format("'{}': expected a number {} {} ({}), got {}", key,
                                strict ? ">" : ">=", lower, unit, v->dump()));
      return std::nullopt;
    }
    return v->get<double>();
  }
  void number(const char* key, double lower, bool strict, const char* unit, double& out) {
    if (const auto v = number(key, lower, strict, unit)) out = *v;
  }
  std::optional<Vec3> vec3(const char* key, const char* unit) {
    const nlohmann::json* v = member(key);
    if (v == nullptr) return std::nullopt;
    if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() ||
        !(*v)[2].is_number()) {
      fail(at(key), fmt::format("'{}': expected [x, y, z] ({}), got {}", key, unit, v->dump()));
      return std::nullopt;
    }
    return Vec3{(*v)[0].get<double>(), (*v)[1].get<double>(), (*v)[2].get<double>()};
  }
  std::optional<bool> boolean(const char* key) {
    const nlohmann::json* v = member(key);
    if (v == nullptr) return std::nullopt;
    if (!v->is_boolean()) {
      fail(at(key), fmt::format("'{}': expected true or false, got {}", key, v->dump()));
      return std::nullopt;
    }
    return v->get<bool>();
  }
  void onlyKeys(std::initializer_list<const char*> keys) {
    for (const auto& [key, value] : value_.items()) {
      bool known = false;
      for (const char* k : keys) known = known || key == k;
      if (!known) fail(pointer_ + "/" + key, fmt::format("unknown key '{}'", key));
    }
  }
  void fail(const std::string& pointer, const std::string& message) {
    ok_ = false;
    error_(pointer, message);
  }

 private:
  const nlohmann::json& value_;
  std::string pointer_;
  const ContactErrorSink& error_;
  bool& ok_;
};

std::int32_t materialIndex(const Model& model, const std::string& name) {
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    if (model.materials[m].name == name) return static_cast<std::int32_t>(m);
  }
  return -1;
}

std::int32_t objectIndex(const Model& model, const std::string& name) {
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    if (model.objects[o].name == name) return static_cast<std::int32_t>(o);
  }
  return -1;
}

// "material": a material name; returns its index (0 when absent).
std::int32_t readMaterial(Reader& r, const Model& model) {
  const nlohmann::json* v = r.member("material");
  if (v == nullptr) return 0;
  if (v->is_string()) {
    const std::int32_t m = materialIndex(model, v->get<std::string>());
    if (m >= 0) return m;
  }
  r.fail(r.at("material"), fmt::format("'material': {} is not a material defined in "
                                       "/materials",
                                       v->dump()));
  return 0;
}

// Box axes from "rotation" [ax, ay, az, angle (rad)] (Rodrigues) or "rpy" [roll, pitch, yaw].
void readOrientation(Reader& r, BoxObstacle& box) {
  Vec3 columns[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (const nlohmann::json* v = r.member("rotation")) {
    if (!v->is_array() || v->size() != 4) {
      r.fail(r.at("rotation"), "'rotation': expected [ax, ay, az, angle (rad)]");
      return;
    }
    Vec3 axis{(*v)[0].get<double>(), (*v)[1].get<double>(), (*v)[2].get<double>()};
    const double angle = (*v)[3].get<double>();
    if (!(norm(axis) > 0.0)) {
      r.fail(r.at("rotation"), "'rotation': the axis must not be zero");
      return;
    }
    axis = axis / norm(axis);
    for (Vec3& c : columns) {
      c = c * std::cos(angle) + cross(axis, c) * std::sin(angle) +
          axis * (dot(axis, c) * (1.0 - std::cos(angle)));
    }
  } else if (const auto rpy = r.vec3("rpy", "rad")) {
    // R = Rz(yaw) Ry(pitch) Rx(roll).
    const double cr = std::cos(rpy->x), sr = std::sin(rpy->x);
    const double cp = std::cos(rpy->y), sp = std::sin(rpy->y);
    const double cy = std::cos(rpy->z), sy = std::sin(rpy->z);
    columns[0] = {cy * cp, sy * cp, -sp};
    columns[1] = {cy * sp * sr - sy * cr, sy * sp * sr + cy * cr, cp * sr};
    columns[2] = {cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr};
  }
  box.axisX = columns[0];
  box.axisY = columns[1];
  box.axisZ = columns[2];
}

void readPlane(Reader& r, Model& model) {
  if (!r.isObject()) return;
  r.onlyKeys({"point", "normal", "material"});
  GroundPlane plane;
  if (const auto p = r.vec3("point", "m")) plane.point = *p;
  if (const auto n = r.vec3("normal", "-")) {
    if (!(norm(*n) > 0.0)) {
      r.fail(r.at("normal"), "'normal': must not be zero");
    } else {
      plane.normal = *n / norm(*n);
    }
  }
  plane.material = readMaterial(r, model);
  model.environment.planes.push_back(plane);
}

void readHeightfield(Reader& r, const std::string& directory, Model& model) {
  if (!r.isObject()) return;
  r.onlyKeys({"origin", "cellSize", "heights", "pgm", "minHeight", "maxHeight", "material"});
  Heightfield field;
  if (const nlohmann::json* o = r.member("origin")) {
    if (!o->is_array() || o->size() != 2 || !(*o)[0].is_number() || !(*o)[1].is_number()) {
      r.fail(r.at("origin"), "'origin': expected [x, y] (m)");
    } else {
      field.originX = (*o)[0].get<double>();
      field.originY = (*o)[1].get<double>();
    }
  }
  if (const nlohmann::json* c = r.member("cellSize")) {
    if (c->is_number() && c->get<double>() > 0.0) {
      field.cellSizeX = field.cellSizeY = c->get<double>();
    } else if (c->is_array() && c->size() == 2 && (*c)[0].is_number() && (*c)[1].is_number() &&
               (*c)[0].get<double>() > 0.0 && (*c)[1].get<double>() > 0.0) {
      field.cellSizeX = (*c)[0].get<double>();
      field.cellSizeY = (*c)[1].get<double>();
    } else {
      r.fail(r.at("cellSize"), "'cellSize': expected a number > 0 or [dx, dy] (m)");
    }
  }
  field.material = readMaterial(r, model);
  const nlohmann::json* heights = r.member("heights");
  const nlohmann::json* pgm = r.member("pgm");
  if ((heights == nullptr) == (pgm == nullptr)) {
    r.fail(r.at("heights"), "a heightfield needs exactly one of 'heights' or 'pgm'");
    return;
  }
  if (pgm != nullptr) {
    if (!pgm->is_string()) {
      r.fail(r.at("pgm"), "'pgm': expected a file name");
      return;
    }
    std::filesystem::path path = pgm->get<std::string>();
    if (path.is_relative()) path = std::filesystem::path(directory) / path;
    const double low = r.number("minHeight", -1e300, false, "m").value_or(0.0);
    const double high = r.number("maxHeight", -1e300, false, "m").value_or(1.0);
    const std::string problem =
        loadHeightfieldPgm(path.string(), field.originX, field.originY, field.cellSizeX,
                           field.cellSizeY, low, high, field);
    if (!problem.empty()) {
      r.fail(r.at("pgm"), problem);
      return;
    }
  } else {
    // heights[j][i]: row j at y0 + j dy, column i at x0 + i dx.
    bool good = heights->is_array() && heights->size() >= 2 && (*heights)[0].is_array() &&
                (*heights)[0].size() >= 2;
    const std::size_t columns = good ? (*heights)[0].size() : 0;
    for (std::size_t j = 0; good && j < heights->size(); ++j) {
      const auto& row = (*heights)[j];
      good = row.is_array() && row.size() == columns;
      for (std::size_t i = 0; good && i < columns; ++i) {
        good = row[i].is_number();
        if (good) field.heights.push_back(row[i].get<double>());
      }
    }
    if (!good) {
      r.fail(r.at("heights"),
             "'heights': expected rows of numbers (m), at least 2×2, all rows of equal length");
      return;
    }
    field.columns = static_cast<std::int32_t>(columns);
    field.rows = static_cast<std::int32_t>(heights->size());
  }
  model.environment.heightfields.push_back(std::move(field));
}

void readBox(Reader& r, Model& model) {
  if (!r.isObject()) return;
  r.onlyKeys({"center", "size", "rotation", "rpy", "material"});
  BoxObstacle box;
  if (const auto c = r.vec3("center", "m")) box.center = *c;
  if (const auto s = r.vec3("size", "m")) {
    if (!(s->x > 0.0 && s->y > 0.0 && s->z > 0.0)) {
      r.fail(r.at("size"), "'size': every side must be > 0 (m)");
    } else {
      box.halfExtents = *s * 0.5;
    }
  } else {
    r.fail(r.at("size"), "a box needs 'size' [sx, sy, sz] (m)");
  }
  readOrientation(r, box);
  box.material = readMaterial(r, model);
  model.environment.boxes.push_back(box);
}

void readSphere(Reader& r, Model& model) {
  if (!r.isObject()) return;
  r.onlyKeys({"center", "radius", "material"});
  SphereObstacle sphere;
  if (const auto c = r.vec3("center", "m")) sphere.center = *c;
  if (const auto radius = r.number("radius", 0.0, true, "m")) {
    sphere.radius = *radius;
  } else if (r.member("radius") == nullptr) {
    r.fail(r.at("radius"), "a sphere needs 'radius' (m)");
  }
  sphere.material = readMaterial(r, model);
  model.environment.spheres.push_back(sphere);
}

template <typename Read>
void readList(const nlohmann::json& env, const char* key, const std::string& pointer,
              const ContactErrorSink& error, bool& ok, Read read) {
  const auto it = env.find(key);
  if (it == env.end()) return;
  if (!it->is_array()) {
    ok = false;
    error(pointer + "/" + key, fmt::format("'{}': expected an array", key));
    return;
  }
  for (std::size_t k = 0; k < it->size(); ++k) {
    Reader r((*it)[k], fmt::format("{}/{}/{}", pointer, key, k), error, ok);
    read(r);
  }
}

}  // namespace

bool parseContactScene(const nlohmann::json& root, const std::string& sceneDirectory, Model& model,
                       const ContactErrorSink& error) {
  bool ok = true;
  // "materials": [{name, contactStiffness, contactDamping, staticFriction, kineticFriction}].
  if (const auto it = root.find("materials"); it != root.end()) {
    if (!it->is_array()) {
      ok = false;
      error("/materials", "'materials': expected an array of materials");
    } else {
      for (std::size_t k = 0; k < it->size(); ++k) {
        Reader r((*it)[k], fmt::format("/materials/{}", k), error, ok);
        if (!r.isObject()) continue;
        r.onlyKeys(
            {"name", "contactStiffness", "contactDamping", "staticFriction", "kineticFriction"});
        const nlohmann::json* name = r.member("name");
        if (name == nullptr || !name->is_string() || name->get<std::string>().empty()) {
          r.fail(r.at("name"), "a material needs a non-empty 'name'");
          continue;
        }
        std::int32_t index = materialIndex(model, name->get<std::string>());
        if (index > 0 || (index == 0 && k > 0 && name->get<std::string>() != "default")) {
          r.fail(r.at("name"),
                 fmt::format("material '{}' is defined twice", name->get<std::string>()));
          continue;
        }
        Material material;
        if (index == 0) material = model.materials[0];  // redefines "default"
        material.name = name->get<std::string>();
        r.number("contactStiffness", 0.0, true, "N/m", material.contactStiffness);
        r.number("contactDamping", 0.0, false, "N·s/m", material.contactDamping);
        r.number("staticFriction", 0.0, false, "-", material.staticFriction);
        r.number("kineticFriction", 0.0, false, "-", material.kineticFriction);
        if (material.kineticFriction > material.staticFriction) {
          r.fail(r.at("kineticFriction"),
                 fmt::format("'kineticFriction' {} must not exceed 'staticFriction' {}",
                             material.kineticFriction, material.staticFriction));
        }
        if (index == 0) {
          model.materials[0] = material;
        } else {
          model.materials.push_back(material);
        }
      }
    }
  }
  // objects/k/material, matched to model objects by name.
  if (const auto it = root.find("objects"); it != root.end() && it->is_array()) {
    for (std::size_t k = 0; k < it->size(); ++k) {
      const nlohmann::json& entry = (*it)[k];
      if (!entry.is_object() || !entry.contains("material")) continue;
      Reader r(entry, fmt::format("/objects/{}", k), error, ok);
      const std::int32_t material = readMaterial(r, model);
      const auto name = entry.find("name");
      if (name == entry.end() || !name->is_string()) continue;
      for (ObjectInfo& object : model.objects) {
        if (object.name == name->get<std::string>()) object.material = material;
      }
    }
  }
  // "environment": {ground, planes, heightfields, boxes, spheres}.
  if (const auto it = root.find("environment"); it != root.end()) {
    Reader env(*it, "/environment", error, ok);
    if (env.isObject()) {
      env.onlyKeys({"ground", "planes", "heightfield", "heightfields", "boxes", "spheres"});
      if (const nlohmann::json* ground = env.member("ground")) {
        if (ground->is_boolean()) {
          if (ground->get<bool>()) model.environment.planes.push_back(GroundPlane{});
        } else {
          Reader r(*ground, "/environment/ground", error, ok);
          readPlane(r, model);
        }
      }
      readList(*it, "planes", "/environment", error, ok, [&](Reader& r) { readPlane(r, model); });
      if (const nlohmann::json* single = env.member("heightfield")) {
        Reader r(*single, "/environment/heightfield", error, ok);
        readHeightfield(r, sceneDirectory, model);
      }
      readList(*it, "heightfields", "/environment", error, ok,
               [&](Reader& r) { readHeightfield(r, sceneDirectory, model); });
      readList(*it, "boxes", "/environment", error, ok, [&](Reader& r) { readBox(r, model); });
      readList(*it, "spheres", "/environment", error, ok, [&](Reader& r) { readSphere(r, model); });
    }
  }
  // "medium": {viscosity}.
  if (const auto it = root.find("medium"); it != root.end()) {
    Reader r(*it, "/medium", error, ok);
    if (r.isObject()) {
      r.onlyKeys({"viscosity"});
      r.number("viscosity", 0.0, false, "N·s/m", model.environment.viscosity);
    }
  }
  // "contact": settings.
  if (const auto it = root.find("contact"); it != root.end()) {
    Reader r(*it, "/contact", error, ok);
    if (r.isObject()) {
      ContactSettings& s = model.contact;
      r.onlyKeys({"enabled", "selfCollision", "tangentialStiffnessRatio", "tangentialDampingRatio",
                  "stickVelocity", "leafSize"});
      if (const auto v = r.boolean("enabled")) s.enabled = *v;
      if (const auto v = r.boolean("selfCollision")) s.selfCollision = *v;
      r.number("tangentialStiffnessRatio", 0.0, false, "-", s.tangentialStiffnessRatio);
      r.number("tangentialDampingRatio", 0.0, false, "-", s.tangentialDampingRatio);
      r.number("stickVelocity", 0.0, false, "m/s", s.stickVelocity);
      if (const auto v = r.number("leafSize", 1.0, false, "particles")) {
        s.leafSize = static_cast<std::int32_t>(*v);
      }
    }
  }
  // "contactPairs": [{objects: [a, b | "environment"], contactStiffness, ...}]; values
  // not given come from the two materials' combination.
  if (const auto it = root.find("contactPairs"); it != root.end()) {
    if (!it->is_array()) {
      ok = false;
      error("/contactPairs", "'contactPairs': expected an array");
    } else {
      for (std::size_t k = 0; k < it->size(); ++k) {
        Reader r((*it)[k], fmt::format("/contactPairs/{}", k), error, ok);
        if (!r.isObject()) continue;
        r.onlyKeys(
            {"objects", "contactStiffness", "contactDamping", "staticFriction", "kineticFriction"});
        const nlohmann::json* names = r.member("objects");
        if (names == nullptr || !names->is_array() || names->size() != 2 ||
            !(*names)[0].is_string() || !(*names)[1].is_string()) {
          r.fail(r.at("objects"), "'objects': expected [objectName, objectName | \"environment\"]");
          continue;
        }
        const std::int32_t a = objectIndex(model, (*names)[0].get<std::string>());
        const bool withEnvironment = (*names)[1].get<std::string>() == "environment";
        const std::int32_t b =
            withEnvironment ? -1 : objectIndex(model, (*names)[1].get<std::string>());
        if (a < 0 || (!withEnvironment && b < 0)) {
          r.fail(r.at("objects"),
                 fmt::format("'objects': {} names an object that does not exist", names->dump()));
          continue;
        }
        const Material& ma = model.materials[static_cast<std::size_t>(model.objects[a].material)];
        const Material& mb =
            b >= 0 ? model.materials[static_cast<std::size_t>(model.objects[b].material)] : ma;
        const auto series = [](double x, double y) { return x + y > 0 ? x * y / (x + y) : 0.0; };
        ContactPairOverride o;
        o.objectA = a;
        o.objectB = b;
        o.stiffness = series(ma.contactStiffness, mb.contactStiffness);
        o.damping = series(ma.contactDamping, mb.contactDamping);
        o.staticFriction = std::sqrt(ma.staticFriction * mb.staticFriction);
        o.kineticFriction = std::sqrt(ma.kineticFriction * mb.kineticFriction);
        r.number("contactStiffness", 0.0, true, "N/m", o.stiffness);
        r.number("contactDamping", 0.0, false, "N·s/m", o.damping);
        r.number("staticFriction", 0.0, false, "-", o.staticFriction);
        r.number("kineticFriction", 0.0, false, "-", o.kineticFriction);
        model.contact.pairOverrides.push_back(o);
      }
    }
  }
  return ok;
}

}  // namespace robophi
