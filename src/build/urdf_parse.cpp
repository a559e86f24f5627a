// The URDF reader: tinyxml2 for the XML (it keeps line numbers), then the
// checks a URDF needs before anything is built (docs/robots.md "Importing a URDF").
#include "build/urdf_parse.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "build/checks.h"
#include "robophi/build/input_files.h"
#include "robophi/build/urdf.h"
#include "robophi/build/urdf_error.h"

namespace robophi::build {

namespace {
std::string lineText(const std::string& file, int line) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " : file + ": ";
}
}  // namespace

std::string substituteRosArgs(std::string text) {
  for (std::size_t at = text.find("$("); at != std::string::npos; at = text.find("$(", at)) {
    const std::size_t end = text.find(')', at);
    if (end == std::string::npos) break;
    std::istringstream in(text.substr(at + 2, end - at - 2));
    std::string command, name, rest, word;
    in >> command >> name;
    while (in >> word) rest += (rest.empty() ? "" : " ") + word;
    const char* value = name.empty() ? nullptr : std::getenv(name.c_str());
    std::string replacement;
    if (command == "optenv") {
      replacement = value != nullptr ? value : rest;
    } else if (command == "env" && value != nullptr) {
      replacement = value;
    } else {
      throw std::invalid_argument(
          "'" + text.substr(at, end - at + 1) +
          "': only $(optenv NAME default) and $(env NAME) (NAME set) are understood");
    }
    text.replace(at, end - at + 1, replacement);
    at += replacement.size();
  }
  return text;
}

UrdfError::UrdfError(std::string file, int line, const std::string& message)
    : std::runtime_error(lineText(file, line) + message),
      file_(std::move(file)),
      line_(line),
      message_(message) {}

namespace urdf {

namespace {

namespace fs = std::filesystem;
using tinyxml2::XMLElement;

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const XMLElement* e, const std::string& message) const {
    throw UrdfError(file_, e != nullptr ? e->GetLineNum() : 0, message);
  }

  // Attribute text or nullptr.
  static const char* attribute(const XMLElement* e, const char* name) {
    return e != nullptr ? e->Attribute(name) : nullptr;
  }

  std::string required(const XMLElement* e, const char* name) const {
    const char* value = attribute(e, name);
    if (value == nullptr || *value == '\0')
      fail(e, "<" + std::string(e->Name()) + "> needs the attribute '" + name + "'");
    return value;
  }

  // roslaunch's substitution args, as generated URDFs keep them (substituteRosArgs).
  std::string substitute(const XMLElement* e, std::string text) const {
    try {
      return substituteRosArgs(std::move(text));
    } catch (const std::invalid_argument& problem) {
      fail(e, problem.what());
    }
  }

  // `count` numbers separated by spaces.
  std::vector<double> numbers(const XMLElement* e, const char* name, std::size_t count) const {
    const std::string text = substitute(e, attribute(e, name));
    std::istringstream in(text);
    std::vector<double> values;
    std::string word;
    while (in >> word) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0' || !std::isfinite(v))
        fail(e, "<" + std::string(e->Name()) + " " + name + "=\"" + text + "\">: '" + word +
                    "' is not a finite number");
      values.push_back(v);
    }
    if (values.size() != count)
      fail(e, "<" + std::string(e->Name()) + " " + name + "=\"" + text + "\">: expected " +
                  std::to_string(count) + " number" + (count > 1 ? "s" : "") + ", got " +
                  std::to_string(values.size()));
    return values;
  }

  double number(const XMLElement* e, const char* name, double fallback) const {
    if (attribute(e, name) == nullptr) return fallback;
    return numbers(e, name, 1)[0];
  }

  Vec3 vector(const XMLElement* e, const char* name, const Vec3& fallback) const {
    if (attribute(e, name) == nullptr) return fallback;
    const auto v = numbers(e, name, 3);
    return {v[0], v[1], v[2]};
  }

  Origin origin(const XMLElement* parent) const {
    const XMLElement* e = parent->FirstChildElement("origin");
    if (e == nullptr) return {};
    return {vector(e, "xyz", {}), vector(e, "rpy", {})};
  }

  // A warning of its own (not one a kind).
  void note(const XMLElement* e, const std::string& message) {
    notes_.push_back({file_, e->GetLineNum(), message});
  }

  // A warning given once for each key.
  void noteOnce(const XMLElement* e, const std::string& key, const std::string& message) {
    if (noted_.insert(key).second) note(e, message);
  }

  void ignore(const XMLElement* e, const std::string& kind) {
    ignored_.emplace(kind, e->GetLineNum());  // keeps the first of each kind
  }

  std::vector<UrdfWarning> warnings() const {
    // One a kind, in the order of their first appearance.
    std::vector<std::pair<int, std::string>> first;
    for (const auto& [kind, line] : ignored_) first.emplace_back(line, kind);
    std::sort(first.begin(), first.end());
    std::vector<UrdfWarning> out;
    for (const auto& [line, kind] : first)
      out.push_back({file_, line,
                     kind + " ignored (robophi does not model it; one warning for all of them)"});
    out.insert(out.end(), notes_.begin(), notes_.end());
    return out;
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::map<std::string, int> ignored_;
  std::vector<UrdfWarning> notes_;
  std::set<std::string> noted_;
};

// package://NAME/rest: NAME a folder directly under a package path, or the
// package path itself ending in NAME. Where no package path holds it, the
// URDF's own folder and the folders above it are the package paths (a robot
// published with its meshes beside it loads as published, as in PyBullet and
// MuJoCo, which look beside the file), with one warning a package.
std::string resolvePackage(Reader& reader, const XMLElement* e, const std::string& uri,
                           const std::vector<std::string>& packagePaths) {
  const std::string body = uri.substr(std::string("package://").size());
  const auto slash = body.find('/');
  const std::string name = body.substr(0, slash);
  const std::string rest = slash == std::string::npos ? "" : body.substr(slash + 1);
  std::vector<std::string> roots = packagePaths;
  if (const char* ros = std::getenv("ROS_PACKAGE_PATH"); ros != nullptr) {
    std::stringstream in(ros);
    std::string item;
    while (std::getline(in, item, ':'))
      if (!item.empty()) roots.push_back(item);
  }
  std::vector<std::string> tried;
  for (const std::string& root : roots) {
    const fs::path base(root);
    for (const fs::path& candidate :
         {base / name / rest,
          fs::path(base.lexically_normal().filename() == name ||
                           (base.filename().empty() && base.parent_path().filename() == name)
                       ? (base / rest)
                       : fs::path())}) {
      if (candidate.empty()) continue;
      tried.push_back(candidate.string());
      std::error_code error;
      if (fs::is_regular_file(candidate, error)) return candidate.string();
    }
  }
  std::error_code error;
  fs::path folder = fs::absolute(fs::path(reader.file()), error).parent_path();
  for (; !folder.empty(); folder = folder.parent_path()) {
    for (const fs::path& candidate :
         {folder / name / rest, folder.filename() == name ? folder / rest : fs::path()}) {
      if (candidate.empty() || !fs::is_regular_file(candidate, error)) continue;
      reader.noteOnce(e, "package:" + name,
                      "package '" + name + "' taken from " + candidate.string().substr(
                          0, candidate.string().size() - rest.size()) +
                          " (beside the URDF; no package path held it)");
      return candidate.string();
    }
    if (folder == folder.root_path()) break;
  }
  std::string message = "mesh '" + uri + "' not found: ";
  if (tried.empty()) {
    message +=
        "not beside the URDF (in its folder or one above it) and no package path to look in "
        "(give --package-path DIR or the scene's \"packagePaths\", or set ROS_PACKAGE_PATH)";
  } else {
    message += "tried";
    for (std::size_t k = 0; k < tried.size(); ++k) message += (k ? ", " : " ") + tried[k];
  }
  reader.fail(e, message);
}

std::string resolveMesh(Reader& reader, const XMLElement* e, const std::string& filename,
                        const std::vector<std::string>& packagePaths) {
  if (filename.rfind("package://", 0) == 0)
    return resolvePackage(reader, e, filename, packagePaths);
  std::string path = filename;
  if (path.rfind("file://", 0) == 0) path = path.substr(7);
  fs::path candidate(path);
  if (candidate.is_relative()) candidate = fs::path(reader.file()).parent_path() / candidate;
  std::error_code error;
  if (!fs::is_regular_file(candidate, error))
    reader.fail(e, "mesh '" + filename + "' not found: tried " + candidate.string());
  return candidate.string();
}

Geometry geometry(Reader& reader, const XMLElement* owner,
                  const std::vector<std::string>& packagePaths) {
  const XMLElement* g = owner->FirstChildElement("geometry");
  if (g == nullptr) reader.fail(owner, "<collision> needs a <geometry>");
  const XMLElement* shape = g->FirstChildElement();
  if (shape == nullptr)
    reader.fail(g, "<geometry> is empty (expected box, cylinder, sphere or mesh)");
  Geometry out;
  const std::string kind = shape->Name();
  const auto positive = [&](double value, const char* name) {
    if (!(value > 0.0))
      reader.fail(shape,
                  "<" + kind + " " + name + "=\"" + check::number(value) + "\">: must be > 0 m");
    return value;
  };
  if (kind == "box") {
    out.kind = Geometry::Kind::kBox;
    if (Reader::attribute(shape, "size") == nullptr) reader.required(shape, "size");
    out.size = reader.vector(shape, "size", {});
    positive(out.size.x, "size");
    positive(out.size.y, "size");
    positive(out.size.z, "size");
  } else if (kind == "cylinder") {
    out.kind = Geometry::Kind::kCylinder;
    reader.required(shape, "radius");
    reader.required(shape, "length");
    out.radius = positive(reader.number(shape, "radius", 0), "radius");
    out.length = positive(reader.number(shape, "length", 0), "length");
  } else if (kind == "sphere") {
    out.kind = Geometry::Kind::kSphere;
    reader.required(shape, "radius");
    out.radius = positive(reader.number(shape, "radius", 0), "radius");
  } else if (kind == "mesh") {
    out.kind = Geometry::Kind::kMesh;
    out.mesh = resolveMesh(reader, shape, reader.required(shape, "filename"), packagePaths);
    out.scale = reader.vector(shape, "scale", {1, 1, 1});
  } else {
    reader.fail(
        shape, "<geometry>: unknown shape <" + kind + "> (expected box, cylinder, sphere or mesh)");
  }
  return out;
}

// A <material>'s <color rgba>, when it has one.
bool materialColor(Reader& reader, const XMLElement* material, std::array<double, 4>& rgba) {
  const XMLElement* color = material != nullptr ? material->FirstChildElement("color") : nullptr;
  if (color == nullptr || Reader::attribute(color, "rgba") == nullptr) return false;
  const std::vector<double> v = reader.numbers(color, "rgba", 4);
  for (std::size_t k = 0; k < 4; ++k) rgba[k] = std::clamp(v[k], 0.0, 1.0);
  return true;
}

// A <visual> (display only, docs/viewer.md): what cannot be drawn is a warning, never an error.
Visual visual(Reader& reader, const XMLElement* e, const std::vector<std::string>& packagePaths) {
  Visual out;
  out.line = e->GetLineNum();
  try {
    out.origin = reader.origin(e);
    out.geometry = geometry(reader, e, packagePaths);
  } catch (const UrdfError& problem) {
    out.geometry.kind = Geometry::Kind::kMesh;
    out.geometry.mesh.clear();
    out.warning = problem.what();
  }
  if (const XMLElement* m = e->FirstChildElement("material"); m != nullptr) {
    const char* name = Reader::attribute(m, "name");
    out.material = name != nullptr ? name : "";
    try {
      out.hasColor = materialColor(reader, m, out.rgba);
    } catch (const UrdfError&) {  // NOLINT(bugprone-empty-catch): a colour is display only
    }
  }
  return out;
}

Link link(Reader& reader, const XMLElement* e, const std::vector<std::string>& packagePaths) {
  Link out;
  out.name = reader.required(e, "name");
  out.line = e->GetLineNum();
  for (const XMLElement* child = e->FirstChildElement(); child != nullptr;
       child = child->NextSiblingElement()) {
    const std::string kind = child->Name();
    if (kind == "inertial") {
      if (out.inertial.present) reader.fail(child, "link '" + out.name + "' has two <inertial>");
      Inertial& in = out.inertial;
      in.present = true;
      in.line = child->GetLineNum();
      in.origin = reader.origin(child);
      const XMLElement* mass = child->FirstChildElement("mass");
      if (mass == nullptr) reader.fail(child, "<inertial> of link '" + out.name + "' needs <mass>");
      reader.required(mass, "value");
      in.mass = reader.number(mass, "value", 0.0);
      if (in.mass < 0.0)
        reader.fail(mass, "<mass value=\"" + check::number(in.mass) + "\"> of link '" + out.name +
                              "' must be >= 0 kg");
      if (const XMLElement* inertia = child->FirstChildElement("inertia"); inertia != nullptr) {
        const char* names[6] = {"ixx", "iyy", "izz", "ixy", "ixz", "iyz"};
        for (int k = 0; k < 6; ++k) in.inertia[k] = reader.number(inertia, names[k], 0.0);
      }
    } else if (kind == "collision") {
      Collision c{reader.origin(child), {}, child->GetLineNum()};
      try {
        c.geometry = geometry(reader, child, packagePaths);
      } catch (const UrdfError& missing) {
        // A missing collision mesh: the link's visual mesh stands in when it exists.
        const XMLElement* shape = child->FirstChildElement("geometry");
        shape = shape != nullptr ? shape->FirstChildElement("mesh") : nullptr;
        const XMLElement* visual = e->FirstChildElement("visual");
        for (; visual != nullptr; visual = visual->NextSiblingElement("visual")) {
          const XMLElement* g = visual->FirstChildElement("geometry");
          if (g == nullptr || g->FirstChildElement("mesh") == nullptr) continue;
          try {
            c.geometry = geometry(reader, visual, packagePaths);
            c.origin = reader.origin(visual);
            break;
          } catch (const UrdfError&) {
          }
        }
        if (shape == nullptr || visual == nullptr) throw;
        reader.note(child, "link '" + out.name + "': " + missing.message() +
                               "; its <visual> mesh (line " + std::to_string(visual->GetLineNum()) +
                               ") stands in for it");
      }
      out.collisions.push_back(std::move(c));
    } else if (kind == "visual") {
      reader.ignore(child, "<visual>");  // by the physics; kept for display
      out.visuals.push_back(visual(reader, child, packagePaths));
    } else {
      reader.ignore(child, "<" + kind + ">");
    }
  }
  return out;
}

Joint joint(Reader& reader, const XMLElement* e) {
  Joint out;
  out.name = reader.required(e, "name");
  out.line = e->GetLineNum();
  out.typeName = reader.required(e, "type");
  const std::string& type = out.typeName;
  const std::string who = "joint '" + out.name + "'";
  if (type == "revolute") {
    out.type = Joint::Type::kRevolute;
  } else if (type == "continuous") {
    out.type = Joint::Type::kContinuous;
  } else if (type == "prismatic") {
    out.type = Joint::Type::kPrismatic;
  } else if (type == "fixed") {
    out.type = Joint::Type::kFixed;
  } else if (type == "floating" || type == "planar") {
    reader.fail(e, who + ": type \"" + type +
                       "\" is not supported (robophi imports revolute, continuous, prismatic "
                       "and fixed joints; a floating base is \"fixedBase\": false)");
  } else {
    reader.fail(e, who + ": unknown type \"" + type +
                       "\" (expected revolute, continuous, prismatic or fixed)");
  }
  const XMLElement* parent = e->FirstChildElement("parent");
  const XMLElement* child = e->FirstChildElement("child");
  if (parent == nullptr) reader.fail(e, who + " needs <parent link=\"...\">");
  if (child == nullptr) reader.fail(e, who + " needs <child link=\"...\">");
  out.parent = reader.required(parent, "link");
  out.child = reader.required(child, "link");
  out.origin = reader.origin(e);
  const bool moves = out.type != Joint::Type::kFixed;
  if (const XMLElement* axis = e->FirstChildElement("axis"); axis != nullptr) {
    const Vec3 v = reader.vector(axis, "xyz", {1, 0, 0});
    if (moves) {
      if (!(norm(v) > 1e-12))
        reader.fail(axis, who + ": <axis xyz=\"" + Reader::attribute(axis, "xyz") +
                              "\"> is zero (a " + type + " joint needs a direction)");
      out.axis = v / norm(v);
    }
  }
  for (const XMLElement* item = e->FirstChildElement(); item != nullptr;
       item = item->NextSiblingElement()) {
    const std::string kind = item->Name();
    if (kind == "limit") {
      out.hasLimit = true;
      out.lower = reader.number(item, "lower", 0.0);
      out.upper = reader.number(item, "upper", 0.0);
      out.velocity = reader.number(item, "velocity", 0.0);
      out.effort = reader.number(item, "effort", 0.0);
      if (out.velocity < 0.0 || out.effort < 0.0)
        reader.fail(item, who + ": <limit> velocity and effort must be >= 0");
      if (moves && out.type != Joint::Type::kContinuous && out.lower > out.upper)
        reader.fail(item, who + ": <limit lower=\"" + check::number(out.lower) + "\" upper=\"" +
                              check::number(out.upper) + "\">: lower > upper");
    } else if (kind == "dynamics") {
      out.damping = reader.number(item, "damping", 0.0);
      out.friction = reader.number(item, "friction", 0.0);
      if (out.damping < 0.0 || out.friction < 0.0)
        reader.fail(item, who + ": <dynamics> damping and friction must be >= 0");
    } else if (kind == "mimic") {
      out.hasMimic = true;
      out.mimicJoint = reader.required(item, "joint");
      out.multiplier = reader.number(item, "multiplier", 1.0);
      out.offset = reader.number(item, "offset", 0.0);
    } else if (kind != "parent" && kind != "child" && kind != "origin" && kind != "axis") {
      reader.ignore(item, "<" + kind + ">");
    }
  }
  if ((out.type == Joint::Type::kRevolute || out.type == Joint::Type::kPrismatic) && !out.hasLimit)
    reader.fail(e, who + ": a " + type + " joint needs <limit lower upper effort velocity>");
  return out;
}

// A xacro file: its extension, or xacro elements (<xacro:macro>, <xacro:include>, ...)
// anywhere. (Generated URDFs often keep the xmlns:xacro declaration: that alone is not xacro.)
const XMLElement* firstXacroElement(const XMLElement* e) {
  for (; e != nullptr; e = e->NextSiblingElement()) {
    if (std::string(e->Name()).rfind("xacro:", 0) == 0) return e;
    if (const XMLElement* inner = firstXacroElement(e->FirstChildElement())) return inner;
  }
  return nullptr;
}

}  // namespace

namespace {

// The offset of the first byte of `text` that is not valid UTF-8 (RFC 3629: no
// overlong form, no surrogate, at most U+10FFFF), or npos.
std::size_t firstInvalidUtf8(const std::string& text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = byte(i);
    std::size_t length = 1;
    unsigned char low = 0x80, high = 0xBF;  // the second byte's range
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      length = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      length = 3;
      low = c == 0xE0 ? 0xA0 : 0x80;
      high = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
      length = 4;
      low = c == 0xF0 ? 0x90 : 0x80;
      high = c == 0xF4 ? 0x8F : 0xBF;
    } else {
      return i;
    }
    if (i + length > text.size() || byte(i + 1) < low || byte(i + 1) > high) return i;
    for (std::size_t k = 2; k < length; ++k)
      if ((byte(i + k) & 0xC0) != 0x80) return i;
    i += length;
  }
  return std::string::npos;
}

}  // namespace

Description readUrdf(const std::string& path, const std::vector<std::string>& packagePaths) {
  Reader reader(path);
  const std::string xacro = "a xacro file: run xacro first: xacro " + path + " > " +
                            fs::path(path).replace_extension(".urdf").filename().string();
  if (fs::path(path).extension() == ".xacro") throw UrdfError(path, 0, xacro);
  std::string text;
  try {
    text = readInputFile(path);  // a regular file (never a FIFO), recorded
  } catch (const InputFileError& e) {
    throw UrdfError(path, 0, "cannot read the file: " + e.problem());
  }
  // Names and messages reach model.json, summary.json and the terminal: UTF-8 only.
  if (const std::size_t bad = firstInvalidUtf8(text); bad != std::string::npos) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(text[bad]));
    throw UrdfError(path,
                    1 + static_cast<int>(std::count(
                            text.begin(), text.begin() + static_cast<std::ptrdiff_t>(bad), '\n')),
                    std::string("not UTF-8 text: byte ") + hex + " at offset " +
                        std::to_string(bad) + " (names and messages must be UTF-8)");
  }
  tinyxml2::XMLDocument document;
  if (document.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw UrdfError(path, document.ErrorLineNum(),
                    std::string("malformed XML: ") + document.ErrorName());
  if (const XMLElement* x = firstXacroElement(document.RootElement()))
    throw UrdfError(path, x->GetLineNum(), "<" + std::string(x->Name()) + ">: " + xacro);
  const XMLElement* robot = document.RootElement();
  if (robot == nullptr || std::string(robot->Name()) != "robot")
    reader.fail(robot, "expected <robot> as the root element, got <" +
                           std::string(robot != nullptr ? robot->Name() : "") + ">");
  Description d;
  d.file = path;
  d.robotName = reader.required(robot, "name");
  std::map<std::string, int> linkIndex;
  std::vector<const XMLElement*> jointElements, linkElements;
  for (const XMLElement* e = robot->FirstChildElement(); e != nullptr;
       e = e->NextSiblingElement()) {
    const std::string kind = e->Name();
    if (kind == "link") {
      Link l = link(reader, e, packagePaths);
      if (!linkIndex.emplace(l.name, static_cast<int>(d.links.size())).second)
        reader.fail(e, "link '" + l.name + "' is defined twice (first at line " +
                           std::to_string(d.links[linkIndex[l.name]].line) + ")");
      d.links.push_back(std::move(l));
      linkElements.push_back(e);
    } else if (kind == "joint") {
      jointElements.push_back(e);
    } else {
      std::array<double, 4> rgba{};
      if (kind == "material" && Reader::attribute(e, "name") != nullptr) {
        try {
          if (materialColor(reader, e, rgba)) d.materials.emplace_back(e->Attribute("name"), rgba);
        } catch (const UrdfError&) {  // NOLINT(bugprone-empty-catch): a colour is display only
        }
      }
      reader.ignore(e, "<" + kind + ">");
    }
  }
  if (d.links.empty()) reader.fail(robot, "robot '" + d.robotName + "' has no <link>");
  std::vector<Joint> joints;
  std::map<std::string, int> jointIndex;
  std::vector<int> parentOf(d.links.size(), -1);
  for (const XMLElement* e : jointElements) {
    Joint j = joint(reader, e);
    if (!jointIndex.emplace(j.name, static_cast<int>(joints.size())).second)
      reader.fail(e, "joint '" + j.name + "' is defined twice (first at line " +
                         std::to_string(joints[jointIndex[j.name]].line) + ")");
    for (const auto& [role, name, index] : {std::tuple{"parent", j.parent, &j.parentIndex},
                                            std::tuple{"child", j.child, &j.childIndex}}) {
      const auto found = linkIndex.find(name);
      if (found == linkIndex.end())
        reader.fail(e->FirstChildElement(role), "joint '" + j.name + "': " + role + " link '" +
                                                    name + "' is not defined (no <link name=\"" +
                                                    name + "\">)");
      *index = found->second;
    }
    if (j.parentIndex == j.childIndex)
      reader.fail(e, "joint '" + j.name + "': link '" + j.child + "' is its own parent");
    int& parent = parentOf[static_cast<std::size_t>(j.childIndex)];
    if (parent >= 0)
      reader.fail(e, "link '" + j.child + "' has two parents: joint '" + j.name + "' and joint '" +
                         joints[parent].name + "' (line " + std::to_string(joints[parent].line) +
                         "); a URDF is a tree (a closed loop is not supported)");
    parent = static_cast<int>(joints.size());
    joints.push_back(std::move(j));
  }
  for (const Joint& j : joints)
    if (j.hasMimic && jointIndex.find(j.mimicJoint) == jointIndex.end())
      reader.fail(
          jointElements[static_cast<std::size_t>(jointIndex[j.name])]->FirstChildElement("mimic"),
          "joint '" + j.name + "': <mimic joint=\"" + j.mimicJoint + "\"> names no joint");
  // The root: the one link without a parent.
  std::vector<int> roots;
  for (std::size_t l = 0; l < d.links.size(); ++l)
    if (parentOf[l] < 0) roots.push_back(static_cast<int>(l));
  if (roots.empty())
    reader.fail(robot, "robot '" + d.robotName +
                           "': every link has a parent (the joints form a cycle): no root link");
  if (roots.size() > 1)
    reader.fail(linkElements[static_cast<std::size_t>(roots[1])],
                "links '" + d.links[roots[0]].name + "' and '" + d.links[roots[1]].name +
                    "' both have no parent joint: a robot has one root link (is a joint "
                    "missing?)");
  d.root = roots[0];
  // Tree order (breadth first from the root); a link not reached is in a cycle.
  std::vector<std::vector<int>> childJoints(d.links.size());
  for (std::size_t k = 0; k < joints.size(); ++k)
    childJoints[static_cast<std::size_t>(joints[k].parentIndex)].push_back(static_cast<int>(k));
  std::vector<int> order;
  std::vector<int> queue{d.root};
  for (std::size_t q = 0; q < queue.size(); ++q)
    for (int k : childJoints[static_cast<std::size_t>(queue[q])]) {
      order.push_back(k);
      queue.push_back(joints[static_cast<std::size_t>(k)].childIndex);
    }
  if (order.size() != joints.size())
    for (std::size_t k = 0; k < joints.size(); ++k)
      if (std::find(order.begin(), order.end(), static_cast<int>(k)) == order.end())
        reader.fail(jointElements[k], "joint '" + joints[k].name + "' is part of a cycle: link '" +
                                          joints[k].child + "' is its own ancestor");
  d.parentJoint.assign(d.links.size(), -1);
  for (int k : order) {
    d.parentJoint[static_cast<std::size_t>(joints[static_cast<std::size_t>(k)].childIndex)] =
        static_cast<int>(d.joints.size());
    d.joints.push_back(joints[static_cast<std::size_t>(k)]);
  }
  d.warnings = reader.warnings();
  return d;
}

}  // namespace urdf
}  // namespace robophi::build
