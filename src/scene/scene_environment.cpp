// The "environment" of a scene file (docs/contact.md): the ground and other
// planes, heightfields (inline heights or a PGM image), boxes and spheres.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "robophi/scene/heightfield_pgm.h"
#include "scene/scene_contact.h"

namespace robophi::scene {

namespace {

// Box axes from "rotation" [ax, ay, az, angle (rad)] (Rodrigues) or "rpy" [roll, pitch, yaw].
void readOrientation(ObjectReader& r, BoxObstacle& box) {
  const auto rotation = r.numbers("rotation", 4, "[ax, ay, az, angle (rad)]");
  const auto rpy = r.vec3("rpy", "rad");
  Vec3 columns[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (rotation && rpy) {
    r.sink().error(r.memberPointer("rpy"),
                   "give the box's orientation either as 'rotation' or "
                   "as 'rpy', not both");
    return;
  }
  if (rotation) {
    Vec3 axis{(*rotation)[0], (*rotation)[1], (*rotation)[2]};
    const double angle = (*rotation)[3];
    if (!(norm(axis) > 0.0)) {
      r.sink().error(r.memberPointer("rotation"), "'rotation': the axis must not be zero");
      return;
    }
    axis = axis / norm(axis);
    for (Vec3& c : columns) {
      c = c * std::cos(angle) + cross(axis, c) * std::sin(angle) +
          axis * (dot(axis, c) * (1.0 - std::cos(angle)));
    }
  } else if (rpy) {
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

void readPlane(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
               const std::string& what, Model& model) {
  ObjectReader r(sink, entry, at, what);
  if (!r.valid()) return;
  GroundPlane plane;
  plane.point = r.vec3("point", "m").value_or(plane.point);
  if (const auto n = r.vec3("normal", "-")) {
    if (!(norm(*n) > 0.0)) {
      sink.error(r.memberPointer("normal"), "'normal': must not be zero");
    } else {
      plane.normal = *n / norm(*n);
    }
  }
  plane.material = readMaterialName(r, model);
  r.finish();
  model.environment.planes.push_back(plane);
}

// "cellSize": one number > 0 (m), or [dx, dy] (m).
void readCellSize(ObjectReader& r, Heightfield& field) {
  const nlohmann::json* c = r.member("cellSize");
  if (c == nullptr) return;
  const std::string at = r.memberPointer("cellSize");
  if (c->is_number()) {
    if (const auto size = checkNumber(r.sink(), *c, at, "cellSize", Bound::kPositive, "m"))
      field.cellSizeX = field.cellSizeY = *size;
    return;
  }
  if (!c->is_array() || c->size() != 2) {
    r.sink().error(at, fmt::format("'cellSize': expected a number > 0 or [dx, dy] (m), got {}",
                                   describeJson(*c)));
    return;
  }
  const auto dx = checkNumber(r.sink(), (*c)[0], at + "/0", "cellSize[0]", Bound::kPositive, "m");
  const auto dy = checkNumber(r.sink(), (*c)[1], at + "/1", "cellSize[1]", Bound::kPositive, "m");
  if (dx && dy) {
    field.cellSizeX = *dx;
    field.cellSizeY = *dy;
  }
}

// "heights": rows j of columns i, at least 2×2, rows of equal length (m).
bool readHeights(DiagnosticSink& sink, const nlohmann::json& heights, const std::string& at,
                 Heightfield& field) {
  // heights[j][i]: row j at y0 + j dy, column i at x0 + i dx.
  bool good =
      heights.is_array() && heights.size() >= 2 && heights[0].is_array() && heights[0].size() >= 2;
  const std::size_t columns = good ? heights[0].size() : 0;
  for (std::size_t j = 0; good && j < heights.size(); ++j) {
    const auto& row = heights[j];
    good = row.is_array() && row.size() == columns;
    for (std::size_t i = 0; good && i < columns; ++i) {
      good = row[i].is_number();
      if (good) field.heights.push_back(row[i].get<double>());
    }
  }
  if (!good) {
    sink.error(at,
               "'heights': expected rows of numbers (m), at least 2×2, all rows of equal length");
    return false;
  }
  field.columns = static_cast<std::int32_t>(columns);
  field.rows = static_cast<std::int32_t>(heights.size());
  return true;
}

void readHeightfield(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
                     const std::string& directory, Model& model) {
  ObjectReader r(sink, entry, at, fmt::format("heightfield {}", at));
  if (!r.valid()) return;
  Heightfield field;
  if (const auto origin = r.numbers("origin", 2, "[x, y] (m)")) {
    field.originX = (*origin)[0];
    field.originY = (*origin)[1];
  }
  readCellSize(r, field);
  field.material = readMaterialName(r, model);
  const nlohmann::json* heights = r.member("heights");
  const auto pgm = r.string("pgm");
  // The PGM image's pixel range maps to [minHeight, maxHeight].
  const double low = r.number("minHeight", Bound::kAny, "m").value_or(0.0);
  const double high = r.number("maxHeight", Bound::kAny, "m").value_or(1.0);
  r.finish();
  if ((heights == nullptr) == (r.member("pgm") == nullptr)) {
    sink.error(
        at, fmt::format("{}: needs exactly one of 'heights' (m) or 'pgm' (a file name)", r.what()));
    return;
  }
  if (heights != nullptr) {
    if (!readHeights(sink, *heights, r.memberPointer("heights"), field)) return;
  } else {
    if (!pgm) return;  // not a string: reported
    std::filesystem::path path = *pgm;
    if (path.is_relative()) path = std::filesystem::path(directory) / path;
    const std::string problem =
        loadHeightfieldPgm(path.string(), field.originX, field.originY, field.cellSizeX,
                           field.cellSizeY, low, high, field);
    if (!problem.empty()) {
      sink.error(r.memberPointer("pgm"), problem);
      return;
    }
  }
  model.environment.heightfields.push_back(std::move(field));
}

void readBox(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
             Model& model) {
  ObjectReader r(sink, entry, at, fmt::format("box {}", at));
  if (!r.valid()) return;
  BoxObstacle box;
  box.center = r.vec3("center", "m").value_or(box.center);
  if (const auto s = r.vec3("size", "m", true)) {
    if (!(s->x > 0.0 && s->y > 0.0 && s->z > 0.0)) {
      sink.error(r.memberPointer("size"), "'size': every side must be > 0 (m)");
    } else {
      box.halfExtents = *s * 0.5;
    }
  }
  readOrientation(r, box);
  box.material = readMaterialName(r, model);
  r.finish();
  model.environment.boxes.push_back(box);
}

void readSphere(DiagnosticSink& sink, const nlohmann::json& entry, const std::string& at,
                Model& model) {
  ObjectReader r(sink, entry, at, fmt::format("sphere {}", at));
  if (!r.valid()) return;
  SphereObstacle sphere;
  sphere.center = r.vec3("center", "m").value_or(sphere.center);
  sphere.radius = r.number("radius", Bound::kPositive, "m", true).value_or(sphere.radius);
  sphere.material = readMaterialName(r, model);
  r.finish();
  model.environment.spheres.push_back(sphere);
}

template <typename Read>
void readList(ObjectReader& env, const char* key, Read read) {
  const nlohmann::json* list = env.member(key);
  if (list == nullptr) return;
  const std::string at = env.memberPointer(key);
  if (!list->is_array()) {
    env.sink().error(at, fmt::format("'{}': expected an array, got {}", key, describeJson(*list)));
    return;
  }
  for (std::size_t k = 0; k < list->size(); ++k) read((*list)[k], fmt::format("{}/{}", at, k));
}

}  // namespace

void readEnvironment(DiagnosticSink& sink, const nlohmann::json& value, const std::string& pointer,
                     const std::string& sceneDirectory, Model& model) {
  ObjectReader env(sink, value, pointer, "'environment'");
  if (!env.valid()) return;
  // Items are numbered planes first, then heightfields, boxes, spheres (contact.h),
  // each kind in the order of the file.
  if (const nlohmann::json* ground = env.member("ground")) {
    if (ground->is_boolean()) {
      if (ground->get<bool>()) model.environment.planes.push_back(GroundPlane{});
    } else if (ground->is_object()) {
      readPlane(sink, *ground, env.memberPointer("ground"), "the ground plane", model);
    } else {
      sink.error(env.memberPointer("ground"),
                 fmt::format("'ground': expected true, false or a plane {{point, normal, "
                             "material}}, got {}",
                             describeJson(*ground)));
    }
  }
  readList(env, "planes", [&](const nlohmann::json& e, const std::string& at) {
    readPlane(sink, e, at, fmt::format("plane {}", at), model);
  });
  if (const nlohmann::json* single = env.member("heightfield"))
    readHeightfield(sink, *single, env.memberPointer("heightfield"), sceneDirectory, model);
  readList(env, "heightfields", [&](const nlohmann::json& e, const std::string& at) {
    readHeightfield(sink, e, at, sceneDirectory, model);
  });
  readList(env, "boxes",
           [&](const nlohmann::json& e, const std::string& at) { readBox(sink, e, at, model); });
  readList(env, "spheres",
           [&](const nlohmann::json& e, const std::string& at) { readSphere(sink, e, at, model); });
  env.finish();
}

}  // namespace robophi::scene
