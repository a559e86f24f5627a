// MJCF as rigid bodies (build/mjcf_multibody.h): MuJoCo's compiler reads the file;
// the compiled mjModel becomes a Multibody, its collision geoms the URDF importer's
// shapes, its actuators and joint equalities data. Without libmujoco, a clear error.
#include "robophi/build/mjcf_multibody.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#ifdef ROBOPHI_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

#include "build/mass_sum.h"

namespace robophi::build {

bool isMjcfPath(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  return extension == ".xml" || extension == ".mjcf" || extension == ".XML";
}

#ifndef ROBOPHI_HAVE_MUJOCO

bool mjcfAvailable() { return false; }

UrdfMultibody makeMjcfMultibody(const MjcfMultibodySpec& spec, MjcfExtras*) {
  throw UrdfError(spec.path, 0,
                  "MJCF needs libmujoco-dev: this robophi was built without MuJoCo's compiler "
                  "(install libmujoco-dev, scripts/install-deps.sh, and build again)");
}

#else

bool mjcfAvailable() { return true; }

namespace {

Vec3 vec3At(const mjtNum* a) { return {a[0], a[1], a[2]}; }

Pose poseAt(const mjtNum* pos, const mjtNum* quat) {
  return {rotationMatrix(normalized({quat[0], quat[1], quat[2], quat[3]})), vec3At(pos)};
}

Pose translation(const Vec3& p) { return {Mat3::identity(), p}; }

// The model's element name, or "#index" when it has none.
std::string nameOf(const mjModel* m, int type, int id) {
  const char* name = mj_id2name(m, type, id);
  return name && *name ? std::string(name) : "#" + std::to_string(id);
}

// The line of the main file's first <tag ... name="name"> (0: not found on one line,
// e.g. an element from an <include> or made by a default class).
int lineOf(const std::string& file, const std::string& tag, const std::string& name) {
  std::ifstream in(file);
  std::string text;
  for (int line = 1; std::getline(in, text); ++line)
    if (text.find("<" + tag) != std::string::npos &&
        text.find("name=\"" + name + "\"") != std::string::npos)
      return line;
  return 0;
}

class Converter {
 public:
  Converter(const mjModel* m, const MjcfMultibodySpec& spec, UrdfMultibody& out)
      : m_(m), spec_(spec), out_(out), place_(static_cast<std::size_t>(m->nbody)) {}

  void run(MjcfExtras* extras) {
    refuseUnrepresentable();
    std::string prefix = spec_.name;
    if (prefix.empty()) prefix = m_->names[0] ? std::string(m_->names) : "mjcf";
    if (prefix.empty()) prefix = "mjcf";
    prefix_ = prefix;
    out_.multibody.name = prefix;
    place_[0] = {-1, spec_.placement};
    for (int b = 1; b < m_->nbody; ++b) addBody(b);
    for (int g = 0; g < m_->ngeom; ++g) addGeom(g);
    for (int s = 0; s < m_->nsite; ++s) {
      const Place& p = place_[static_cast<std::size_t>(m_->site_bodyid[s])];
      if (p.body >= 0)
        out_.multibody.frames.push_back(
            {prefix_ + "." + nameOf(m_, mjOBJ_SITE, s), p.body,
             p.X_BM * poseAt(m_->site_pos + 3 * s, m_->site_quat + 4 * s)});
    }
    finishMasses();
    try {
      finalize(out_.multibody);
    } catch (const std::invalid_argument& error) {
      throw UrdfError(spec_.path, 0, error.what());
    }
    for (UrdfMultibodyJoint& joint : out_.joints) {
      const MultibodyBody& body = out_.multibody.bodies[static_cast<std::size_t>(joint.body)];
      joint.positionIndex = body.qStart;
      joint.velocityIndex = body.vStart;
    }
    addEqualities();
    MjcfExtras local;
    addActuators(extras ? *extras : local);
    if (extras) {
      extras->gravity = vec3At(m_->opt.gravity);
      extras->timestep = m_->opt.timestep;
    }
  }

 private:
  // Where an MJCF body's frame M sits: the robophi body and X_BM.
  struct Place {
    std::int32_t body = -1;
    Pose X_BM{};
  };

  // `tag` names the element; actuators and equalities are found by name on any tag.
  [[noreturn]] void refuse(const std::string& tag, int type, int id, const std::string& why) const {
    const std::string name = nameOf(m_, type, id);
    const bool anyTag = type == mjOBJ_ACTUATOR || type == mjOBJ_EQUALITY;
    throw UrdfError(spec_.path, lineOf(spec_.path, anyTag ? "" : tag, name),
                    "<" + tag + "> '" + name + "': " + why + " (robophi cannot represent it)");
  }

  void refuseUnrepresentable() const {
    for (int j = 0; j < m_->njnt; ++j) {
      if (m_->jnt_type[j] == mjJNT_BALL && m_->jnt_limited[j])
        refuse("joint", mjOBJ_JOINT, j,
               "a ball joint with a range (a cone limit) of body '" +
                   nameOf(m_, mjOBJ_BODY, m_->jnt_bodyid[j]) + "'");
      if ((m_->jnt_type[j] == mjJNT_HINGE || m_->jnt_type[j] == mjJNT_SLIDE) &&
          m_->qpos0[m_->jnt_qposadr[j]] != 0.0)
        refuse("joint", mjOBJ_JOINT, j,
               "ref = " + std::to_string(m_->qpos0[m_->jnt_qposadr[j]]) + " is not 0");
    }
    if (m_->ntendon > 0) refuse("tendon", mjOBJ_TENDON, 0, "a tendon");
  }

  void addBody(int b) {
    const auto parentPlace = place_[static_cast<std::size_t>(m_->body_parentid[b])];
    // M at q = 0 in the parent's robophi body (the world's frame for the world).
    Pose X_PM = parentPlace.X_BM * poseAt(m_->body_pos + 3 * b, m_->body_quat + 4 * b);
    std::int32_t parent = parentPlace.body;
    const std::string bodyName = nameOf(m_, mjOBJ_BODY, b);
    const int jointCount = m_->body_jntnum[b];
    if (jointCount == 0 && parent >= 0) {
      // Welded to a moving body: merged into it.
      place_[static_cast<std::size_t>(b)] = {parent, X_PM};
      out_.adjustments.push_back("body '" + bodyName + "': merged into body '" +
                                 out_.multibody.bodies[static_cast<std::size_t>(parent)].name +
                                 "' (no joint)");
    } else if (jointCount == 0) {
      place_[static_cast<std::size_t>(b)] = {
          newBody(bodyName, -1, BodyJointKind::kWeld, X_PM, "", {}), Pose{}};
    } else {
      Pose X_BM{};
      for (int k = 0; k < jointCount; ++k) {
        const int j = m_->body_jntadr[b] + k;
        const std::string jointName = nameOf(m_, mjOBJ_JOINT, j);
        // Joints after the first move a massless body each, in MuJoCo's order.
        const std::string name = k + 1 == jointCount ? bodyName : bodyName + "." + jointName;
        if (m_->jnt_type[j] == mjJNT_FREE) {
          if (parent != -1 || jointCount != 1)
            refuse("joint", mjOBJ_JOINT, j,
                   "a free joint below another body or beside other joints");
          parent = newBody(name, -1, BodyJointKind::kFree, X_PM, jointName, {1, 0, 0});
          X_BM = Pose{};
          addJoint(j, parent, "free");
          continue;
        }
        // Ball, hinge and slide: J at the anchor a, with M's axes; M sits at −a in the body.
        const Vec3 anchor = vec3At(m_->jnt_pos + 3 * j);
        if (m_->jnt_type[j] == mjJNT_BALL) {
          // A ball joint turns B by its quaternion about a (MuJoCo's ball qpos). It is
          // passive here: its damping, armature and friction loss are not represented.
          parent = newBody(name, parent, BodyJointKind::kBall, X_PM * translation(anchor), jointName,
                           {1, 0, 0});
          X_PM = translation(-anchor);
          X_BM = X_PM;
          const int dof = m_->jnt_dofadr[j];
          for (int axis = 0; axis < 3; ++axis)
            if (m_->dof_damping[dof + axis] != 0.0 || m_->dof_armature[dof + axis] != 0.0 ||
                m_->dof_frictionloss[dof + axis] != 0.0) {
              out_.adjustments.push_back("joint '" + jointName +
                                         "': a ball joint's damping, armature and friction loss "
                                         "are not represented (it turns freely)");
              break;
            }
          addJoint(j, parent, "ball");
          between_.back() = k + 1 < jointCount;
          continue;
        }
        const Vec3 axis = vec3At(m_->jnt_axis + 3 * j);
        const bool hinge = m_->jnt_type[j] == mjJNT_HINGE;
        parent = newBody(name, parent, hinge ? BodyJointKind::kRevolute : BodyJointKind::kPrismatic,
                         X_PM * translation(anchor), jointName, axis / norm(axis));
        X_PM = translation(-anchor);
        X_BM = X_PM;
        MultibodyBody& body = out_.multibody.bodies.back();
        if (m_->jnt_limited[j]) {
          body.lower = m_->jnt_range[2 * j];
          body.upper = m_->jnt_range[2 * j + 1];
        }
        const int dof = m_->jnt_dofadr[j];
        body.damping = m_->dof_damping[dof];
        body.armature = m_->dof_armature[dof];
        body.friction = m_->dof_frictionloss[dof];
        addJoint(j, parent, hinge ? "hinge" : "slide");
        between_.back() = k + 1 < jointCount;
      }
      place_[static_cast<std::size_t>(b)] = {parent, X_BM};
    }
    // The body's own mass properties, in its robophi body.
    const Place& p = place_[static_cast<std::size_t>(b)];
    if (m_->body_mass[b] > 0.0) {
      const Pose X_BI = p.X_BM * poseAt(m_->body_ipos + 3 * b, m_->body_iquat + 4 * b);
      const Mat3 I = X_BI.rotation * Mat3::diagonal(vec3At(m_->body_inertia + 3 * b)) *
                     transpose(X_BI.rotation);
      mass_[static_cast<std::size_t>(p.body)].add(m_->body_mass[b], X_BI.translation, I);
    }
    out_.multibody.frames.push_back({prefix_ + "." + bodyName, p.body, p.X_BM});
  }

  std::int32_t newBody(const std::string& name, std::int32_t parent, BodyJointKind kind,
                       const Pose& X_PJ, const std::string& jointName, const Vec3& axis) {
    MultibodyBody body;
    body.name = prefix_ + "." + name;
    body.parent = parent;
    body.joint = kind;
    body.jointName = jointName.empty() ? "" : prefix_ + "." + jointName;
    body.X_PJ = parent == -1 ? spec_.placement * X_PJ : X_PJ;
    body.axis = axis;
    out_.multibody.bodies.push_back(body);
    mass_.emplace_back();
    between_.push_back(false);
    return static_cast<std::int32_t>(out_.multibody.bodies.size() - 1);
  }

  void addJoint(int j, std::int32_t body, const char* type) {
    UrdfMultibodyJoint joint;
    joint.urdfName = nameOf(m_, mjOBJ_JOINT, j);
    joint.name = prefix_ + "." + joint.urdfName;
    joint.type = type;
    joint.body = body;
    joint.line = lineOf(spec_.path, "joint", joint.urdfName);
    out_.joints.push_back(joint);
  }

  // Every body its summed mass; a body of joints only (between two joints of one
  // MJCF body) a negligible one; another body without mass the notional minimum.
  void finishMasses() {
    for (std::size_t b = 0; b < out_.multibody.bodies.size(); ++b) {
      MultibodyBody& body = out_.multibody.bodies[b];
      body.mass = mass_[b].properties();
      if (body.mass.mass > 0.0) continue;
      const double m = between_[b] ? 1e-9 : spec_.minimumMass;
      const double i = between_[b] ? 0.0 : 0.4 * m * 1e-4;
      body.mass = {m, {}, Mat3::diagonal({i, i, i})};
      if (!between_[b])
        out_.adjustments.push_back("body '" + body.name + "': no mass: given " + std::to_string(m) +
                                   " kg as a 1 cm sphere (minimumMass)");
    }
  }

  void addGeom(int g) {
    const int b = m_->geom_bodyid[g];
    const int type = m_->geom_type[g];
    if (m_->geom_contype[g] == 0 && m_->geom_conaffinity[g] == 0) return;  // visual only
    const std::string bodyName = nameOf(m_, mjOBJ_BODY, b);
    if (b == 0) {
      out_.adjustments.push_back("geom '" + nameOf(m_, mjOBJ_GEOM, g) +
                                 "' of the world body left out (robophi's scene gives the ground)");
      return;
    }
    const Place& p = place_[static_cast<std::size_t>(b)];
    UrdfCollisionShape shape;
    shape.body = p.body;
    shape.link = bodyName;
    shape.X_BS = p.X_BM * poseAt(m_->geom_pos + 3 * g, m_->geom_quat + 4 * g);
    shape.line = lineOf(spec_.path, "geom", nameOf(m_, mjOBJ_GEOM, g));
    const mjtNum* size = m_->geom_size + 3 * g;
    switch (type) {
      case mjGEOM_BOX:
        shape.kind = UrdfCollisionShape::Kind::kBox;
        shape.size = {2 * size[0], 2 * size[1], 2 * size[2]};
        break;
      case mjGEOM_SPHERE:
        shape.kind = UrdfCollisionShape::Kind::kSphere;
        shape.size = {size[0], size[0], size[0]};
        break;
      case mjGEOM_CYLINDER:
        shape.kind = UrdfCollisionShape::Kind::kCylinder;
        shape.size = {size[0], size[0], 2 * size[1]};
        break;
      case mjGEOM_CAPSULE:
        shape.kind = UrdfCollisionShape::Kind::kCylinder;
        shape.size = {size[0], size[0], 2 * size[1] + 2 * size[0]};
        out_.adjustments.push_back("geom '" + nameOf(m_, mjOBJ_GEOM, g) + "' of body '" + bodyName +
                                   "': a capsule, made its bounding cylinder");
        break;
      case mjGEOM_MESH:
        shape.kind = UrdfCollisionShape::Kind::kMesh;
        shape.mesh = writeMesh(m_->geom_dataid[g]);
        break;
      default:
        refuse("geom", mjOBJ_GEOM, g,
               std::string(type == mjGEOM_ELLIPSOID ? "an ellipsoid"
                           : type == mjGEOM_PLANE   ? "a plane"
                                                    : "a height field") +
                   " on body '" + bodyName + "'");
    }
    out_.collisions.push_back(shape);
  }

  // A compiled mesh (MuJoCo has moved it into its geom's frame) as an OBJ file for the
  // collision filler, in a folder of the temporary directory.
  std::string writeMesh(int mesh) const {
    const auto dir = std::filesystem::temp_directory_path() / "robophi-mjcf";
    std::filesystem::create_directories(dir);
    const auto path = dir / (prefix_ + "-" + nameOf(m_, mjOBJ_MESH, mesh) + ".obj");
    const auto partial = path.string() + ".partial";
    {
      std::ofstream out(partial);
      const int v0 = m_->mesh_vertadr[mesh], f0 = m_->mesh_faceadr[mesh];
      for (int v = v0; v < v0 + m_->mesh_vertnum[mesh]; ++v)
        out << "v " << m_->mesh_vert[3 * v] << ' ' << m_->mesh_vert[3 * v + 1] << ' '
            << m_->mesh_vert[3 * v + 2] << '\n';
      for (int f = f0; f < f0 + m_->mesh_facenum[mesh]; ++f)
        out << "f " << m_->mesh_face[3 * f] + 1 << ' ' << m_->mesh_face[3 * f + 1] + 1 << ' '
            << m_->mesh_face[3 * f + 2] + 1 << '\n';
      if (!out) throw UrdfError(spec_.path, 0, "cannot write the mesh file " + partial);
    }
    std::filesystem::rename(partial, path);
    return path.string();
  }

  UrdfMultibodyJoint* jointNamed(const std::string& name) {
    for (UrdfMultibodyJoint& j : out_.joints)
      if (j.urdfName == name) return &j;
    return nullptr;
  }

  // <equality joint>: q1 = c0 + c1 q2 as a mimic; anything else refused.
  void addEqualities() {
    for (int e = 0; e < m_->neq; ++e) {
      const mjtNum* c = m_->eq_data + mjNEQDATA * e;
      if (m_->eq_type[e] != mjEQ_JOINT)
        refuse(m_->eq_type[e] == mjEQ_CONNECT ? "equality connect"
               : m_->eq_type[e] == mjEQ_WELD  ? "equality weld"
                                              : "equality tendon",
               mjOBJ_EQUALITY, e, "an equality other than a joint coupling");
      if (m_->eq_obj2id[e] < 0 || c[2] != 0.0 || c[3] != 0.0 || c[4] != 0.0)
        refuse("equality joint", mjOBJ_EQUALITY, e,
               "a joint equality other than joint1 = c0 + c1 joint2 (a second joint, polycoef "
               "c2..c4 = 0)");
      UrdfMultibodyJoint* follower = jointNamed(nameOf(m_, mjOBJ_JOINT, m_->eq_obj1id[e]));
      if (!follower)
        refuse("equality joint", mjOBJ_EQUALITY, e, "couples a joint that is not a hinge or slide");
      follower->mimicJoint = nameOf(m_, mjOBJ_JOINT, m_->eq_obj2id[e]);
      follower->offset = c[0];
      follower->multiplier = c[1];
      out_.adjustments.push_back("joint '" + follower->urdfName + "': <equality joint> on '" +
                                 follower->mimicJoint + "' kept as data (a mimic)");
    }
  }

  void addActuators(MjcfExtras& extras) {
    for (int u = 0; u < m_->nu; ++u) {
      const mjtNum* gain = m_->actuator_gainprm + mjNGAIN * u;
      const mjtNum* bias = m_->actuator_biasprm + mjNBIAS * u;
      if (m_->actuator_trntype[u] != mjTRN_JOINT || m_->actuator_dyntype[u] != mjDYN_NONE ||
          m_->actuator_gaintype[u] != mjGAIN_FIXED)
        refuse("actuator", mjOBJ_ACTUATOR, u,
               "an actuator other than a motor, position or velocity servo on a joint");
      MjcfActuator a;
      a.name = nameOf(m_, mjOBJ_ACTUATOR, u);
      a.gear = m_->actuator_gear[6 * u];
      a.gain = gain[0];
      if (m_->actuator_biastype[u] == mjBIAS_NONE && gain[0] == 1.0) {
        a.kind = MjcfActuator::Kind::kMotor;
      } else if (m_->actuator_biastype[u] == mjBIAS_AFFINE && bias[0] == 0.0 &&
                 bias[1] == -gain[0] && bias[2] == 0.0) {
        a.kind = MjcfActuator::Kind::kPosition;
      } else if (m_->actuator_biastype[u] == mjBIAS_AFFINE && bias[0] == 0.0 && bias[1] == 0.0 &&
                 bias[2] == -gain[0]) {
        a.kind = MjcfActuator::Kind::kVelocity;
      } else {
        refuse("actuator", mjOBJ_ACTUATOR, u,
               "an actuator other than a motor, position or velocity servo");
      }
      a.joint = nameOf(m_, mjOBJ_JOINT, m_->actuator_trnid[2 * u]);
      const UrdfMultibodyJoint* joint = jointNamed(a.joint);
      if (!joint || joint->type == "free" || joint->type == "ball")
        refuse("actuator", mjOBJ_ACTUATOR, u,
               std::string("drives a ") + (joint ? joint->type : std::string("free")) + " joint");
      a.velocityIndex = joint->velocityIndex;
      if (m_->actuator_ctrllimited[u]) {
        a.ctrlLower = m_->actuator_ctrlrange[2 * u];
        a.ctrlUpper = m_->actuator_ctrlrange[2 * u + 1];
      }
      if (m_->actuator_forcelimited[u]) {
        a.forceLower = m_->actuator_forcerange[2 * u];
        a.forceUpper = m_->actuator_forcerange[2 * u + 1];
      }
      extras.actuators.push_back(a);
    }
  }

  const mjModel* m_;
  const MjcfMultibodySpec& spec_;
  UrdfMultibody& out_;
  std::string prefix_;
  std::vector<Place> place_;
  std::vector<MassSum> mass_;
  std::vector<bool> between_;
};

}  // namespace

UrdfMultibody makeMjcfMultibody(const MjcfMultibodySpec& spec, MjcfExtras* extras) {
  if (!(spec.minimumMass > 0.0))
    throw UrdfError(spec.path, 0,
                    "minimumMass must be > 0 kg, got " + std::to_string(spec.minimumMass));
  if (!std::filesystem::exists(spec.path)) throw UrdfError(spec.path, 0, "no such file");
  char error[1000] = "";
  mjModel* m = mj_loadXML(spec.path.c_str(), nullptr, error, sizeof error);
  if (!m) throw UrdfError(spec.path, 0, std::string("MuJoCo's compiler: ") + error);
  UrdfMultibody out;
  try {
    Converter(m, spec, out).run(extras);
  } catch (...) {
    mj_deleteModel(m);
    throw;
  }
  mj_deleteModel(m);
  return out;
}

#endif  // ROBOPHI_HAVE_MUJOCO

}  // namespace robophi::build
