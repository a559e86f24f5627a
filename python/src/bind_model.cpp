// robophi.Model (read-only views of the particle arrays, connectors as
// structured arrays, objects and joints by name), robophi.State (a plain value
// with (n, 3) views), robophi.EnergyTally, and the small records they list.
#include <cstdio>
#include <cstring>

#include "py_robophi.h"
#include "robophi/joints.h"

namespace robophi::python {

namespace {

// A property getter: a read-only view of one of the model's arrays, whose base is
// the Python Model (it keeps the model alive).
template <auto Field>
auto modelArray() {
  return [](py::object self) { return vectorView(self.cast<PyModel&>().model().*Field, self); };
}

// A property getter: a writable (n, 3) view of one of a State's arrays, whose
// base is the Python State (a plain value: writing edits only that copy).
template <auto Field>
auto stateArray() {
  return [](py::object self) {
    auto& data = self.cast<State&>().*Field;
    return vec3View(data.data(), data.size(), self, true);
  };
}

const ObjectInfo& objectByName(const Model& model, const std::string& name) {
  for (const ObjectInfo& o : model.objects)
    if (o.name == name) return o;
  std::string known;
  for (const ObjectInfo& o : model.objects) known += (known.empty() ? "" : ", ") + o.name;
  throw py::key_error("no object named '" + name + "' (the model has: " + known + ")");
}

py::tuple vec3Tuple(const Vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

}  // namespace

void bindModel(py::module_& m) {
  // The connectors' records as numpy structured dtypes (views of the model's vectors).
  PYBIND11_NUMPY_DTYPE_EX(LinearSpring, a, "a", b, "b", restLength, "rest_length", stiffness,
                          "stiffness", damping, "damping");
  PYBIND11_NUMPY_DTYPE_EX(TorsionSpring, a, "a", c, "c", b, "b", restAngle, "rest_angle", stiffness,
                          "stiffness", damping, "damping");
  PYBIND11_NUMPY_DTYPE_EX(JointSpring, a, "a", c, "c", b, "b", d, "d", restAngle, "rest_angle",
                          stiffness, "stiffness", damping, "damping");
  py::class_<ObjectInfo>(m, "Object", "A named group of particles made by one generator.")
      .def_readonly("name", &ObjectInfo::name)
      .def_readonly("kind", &ObjectInfo::kind)
      .def_readonly("first_particle", &ObjectInfo::firstParticle)
      .def_readonly("particle_count", &ObjectInfo::particleCount)
      .def_readonly("material", &ObjectInfo::material)
      .def_readonly("rigid", &ObjectInfo::rigid)
      .def_property_readonly(
          "touches", [](const ObjectInfo& o) { return o.contact.touches; },
          "False for an object that touches nothing (goal copies, path ends, inertia carriers).")
      .def_property_readonly(
          "friction_per_particle", [](const ObjectInfo& o) { return o.contact.frictionPerParticle; },
          "True when each particle's contacts decide their friction alone (a rope's links).")
      .def_property_readonly(
          "turns", [](const ObjectInfo& o) { return o.contact.turns; },
          "False when its contact points do not turn with its particles (a rope's).")
      .def_property_readonly(
          "particles",
          [](const ObjectInfo& o) {
            return py::slice(o.firstParticle, o.firstParticle + o.particleCount, 1);
          },
          "A slice of the particle arrays: world.positions[obj.particles].")
      .def("__repr__", [](const ObjectInfo& o) {
        return "<robophi.Object '" + o.name + "' " + o.kind + ", particles " +
               std::to_string(o.firstParticle) + ".." +
               std::to_string(o.firstParticle + o.particleCount - 1) + ">";
      });

  py::class_<Joint>(m, "Joint", "A named joint (revolute: rad; prismatic: m).")
      .def_readonly("name", &Joint::name)
      .def_property_readonly(
          "kind",
          [](const Joint& j) { return j.kind == JointKind::kRevolute ? "revolute" : "prismatic"; })
      .def_readonly("connector", &Joint::connector)
      .def_readonly("drive_spring", &Joint::driveSpring)
      .def_readonly("zero", &Joint::zero)
      .def("__repr__", [](const Joint& j) {
        return "<robophi.Joint '" + j.name + "' " +
               (j.kind == JointKind::kRevolute ? "revolute" : "prismatic") + ">";
      });

  py::class_<Material>(m, "Material", "Contact properties (MODEL §3).")
      .def(py::init([](std::string name, double stiffness, double damping, double staticFriction,
                       double kineticFriction, double rollingResistance) {
             return Material{std::move(name), stiffness,       damping,
                             staticFriction,  kineticFriction, rollingResistance};
           }),
           py::arg("name") = "default", py::arg("contact_stiffness") = 1.0e4,
           py::arg("contact_damping") = 10.0, py::arg("static_friction") = 0.5,
           py::arg("kinetic_friction") = 0.4, py::arg("rolling_resistance") = 0.0)
      .def_readwrite("name", &Material::name)
      .def_readwrite("contact_stiffness", &Material::contactStiffness, "κ_c (N/m)")
      .def_readwrite("contact_damping", &Material::contactDamping, "μ_c (N·s/m)")
      .def_readwrite("static_friction", &Material::staticFriction, "μ_s (-)")
      .def_readwrite("kinetic_friction", &Material::kineticFriction, "μ_k (-)")
      .def_readwrite("rolling_resistance", &Material::rollingResistance, "μ_r (-)");

  py::class_<EnergyTally>(m, "EnergyTally", "The energy account at a state (J).")
      .def_readonly("kinetic", &EnergyTally::kinetic)
      .def_readonly("linear_spring", &EnergyTally::linearSpring)
      .def_readonly("torsion_spring", &EnergyTally::torsionSpring)
      .def_readonly("joint_spring", &EnergyTally::jointSpring)
      .def_readonly("gravity", &EnergyTally::gravity)
      .def_readonly("contact", &EnergyTally::contact)
      .def_readonly("dissipated", &EnergyTally::dissipated)
      .def_readonly("external", &EnergyTally::external)
      .def_property_readonly("potential", &EnergyTally::potential)
      .def_property_readonly("mechanical", &EnergyTally::mechanical)
      .def_property_readonly("total", &EnergyTally::total,
                             "E + dissipated - external: constant for an exact integration")
      .def("__repr__", [](const EnergyTally& e) {
        return "<robophi.EnergyTally kinetic=" + std::to_string(e.kinetic) +
               " potential=" + std::to_string(e.potential()) +
               " total=" + std::to_string(e.total()) + ">";
      });

  py::class_<PyModel>(m, "Model",
                      "A compiled model: read-only. Particle arrays are views (no copy).")
      .def_property_readonly("particle_count",
                             [](const PyModel& p) { return p.model().particleCount(); })
      .def_property_readonly("masses", modelArray<&Model::mass>(), "(n) kg")
      .def_property_readonly("inverse_masses", modelArray<&Model::inverseMass>(),
                             "(n) 1/kg; 0 for a fixed particle")
      .def_property_readonly("radii", modelArray<&Model::radius>(), "(n) m")
      .def_property_readonly("linear_damping", modelArray<&Model::linearDamping>(), "(n) N·s/m")
      .def_property_readonly("object_of", modelArray<&Model::objectOf>(), "(n) index into objects")
      .def_property_readonly(
          "linear_springs", modelArray<&Model::linearSprings>(),
          "LS: structured array (a, b, rest_length m, stiffness N/m, damping N·s/m)")
      .def_property_readonly("torsion_springs", modelArray<&Model::torsionSprings>(),
                             "TS: structured array (a, c, b, rest_angle rad, stiffness, damping)")
      .def_property_readonly(
          "joint_springs", modelArray<&Model::jointSprings>(),
          "JS: structured array (a, c, b, d, rest_angle rad, stiffness, damping)")
      .def_property_readonly("objects", [](const PyModel& p) { return p.model().objects; })
      .def(
          "object",
          [](const PyModel& p, const std::string& name) { return objectByName(p.model(), name); },
          py::arg("name"))
      .def_property_readonly("joints", [](const PyModel& p) { return p.model().joints; })
      .def(
          "joint",
          [](const PyModel& p, const std::string& name) {
            return jointIndex(p.model(), py::str(name));
          },
          py::arg("name"), "The index of the joint called `name` (KeyError if none).")
      .def_property_readonly("materials", [](const PyModel& p) { return p.model().materials; })
      .def_property_readonly("gravity",
                             [](const PyModel& p) { return vec3Tuple(p.model().gravity); })
      .def("__repr__", [](const PyModel& p) {
        const Model& model = p.model();
        return "<robophi.Model " + std::to_string(model.particleCount()) + " particles, " +
               std::to_string(model.linearSprings.size()) + " LS, " +
               std::to_string(model.torsionSprings.size()) + " TS, " +
               std::to_string(model.jointSprings.size()) + " JS, " +
               std::to_string(model.objects.size()) + " objects, " +
               std::to_string(model.joints.size()) + " joints>";
      });

  py::class_<State>(m, "State",
                    "What a step advances: a plain value (copying it is a snapshot). Its arrays "
                    "are writable views on the state's own memory.")
      .def(py::init([](const PyModel& model) { return State::sizedFor(model.model()); }),
           py::arg("model"), "A state at rest with every particle at the origin.")
      .def_readwrite("time", &State::time, "t (s)")
      .def_readwrite("step_count", &State::stepCount)
      .def_property_readonly("positions", stateArray<&State::position>(), "(n, 3) m")
      .def_property_readonly("velocities", stateArray<&State::velocity>(), "(n, 3) m/s")
      .def_property_readonly("spins", stateArray<&State::spin>(),
                             "(n, 3) rad/s (may be empty before the state entered a World)")
      .def_readonly("dissipated", &State::dissipated, "J")
      .def_readonly("external", &State::external, "J")
      .def_property_readonly("contact_count",
                             [](const State& s) { return s.frictionHistory.size(); })
      .def(
          "hash", [](const State& s) { return stateHash(s); },
          "The 64-bit hash of the whole state (summary.json's state_hash, as an int).")
      .def("copy", [](const State& s) { return State(s); })
      .def("__copy__", [](const State& s) { return State(s); })
      .def(
          "__deepcopy__", [](const State& s, py::dict) { return State(s); }, py::arg("memo"))
      .def("__repr__", [](const State& s) {
        return "<robophi.State t=" + std::to_string(s.time) + " s, " +
               std::to_string(s.position.size()) + " particles, " + std::to_string(s.stepCount) +
               " steps>";
      });

  m.def(
      "state_hash", [](const State& s) { return stateHash(s); }, py::arg("state"),
      "stateHash: equal hashes mean bit-identical states.");
  m.def(
      "format_hash",
      [](std::uint64_t h) {
        char text[17];
        std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
        return std::string(text);
      },
      py::arg("hash"), "A hash as summary.json writes it (16 hex digits).");
}

}  // namespace robophi::python
