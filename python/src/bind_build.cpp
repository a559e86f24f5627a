// The build layer's specs as Python classes (robophi.Box(...), robophi.Arm(...),
// ...) and robophi.ModelBuilder: a model without a scene file. Every spec is
// checked by its builder (SpecError naming the field, as the scene reader's).
#include "py_robophi.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/objects.h"
#include "robophi/build/robots.h"

namespace robophi::python {

namespace {

using namespace robophi::build;

// RobotLinks fields as properties of a robot spec (stiffness, damping, natural_frequency).
template <class Spec, class Class>
void robotLinks(Class& c) {
  c.def_property(
       "stiffness", [](const Spec& s) { return s.structure.stiffness; },
       [](Spec& s, std::optional<double> v) { s.structure.stiffness = v; },
       "LS stiffness of the structure (N/m); None: from natural_frequency")
      .def_property(
          "damping", [](const Spec& s) { return s.structure.damping; },
          [](Spec& s, std::optional<double> v) { s.structure.damping = v; }, "LS damping (N·s/m)")
      .def_property(
          "natural_frequency", [](const Spec& s) { return s.structure.naturalFrequency; },
          [](Spec& s, double v) { s.structure.naturalFrequency = v; },
          "ω of the fastest mode (rad/s) when stiffness is None");
}

/// The spring settings of a passive object (SpringSettings) from add()'s keywords.
SpringSettings springSettings(std::optional<double> stiffness, std::optional<double> damping,
                              std::optional<double> bendStiffness,
                              std::optional<double> bendDamping, double naturalFrequency) {
  SpringSettings s;
  s.stiffness = stiffness;
  s.damping = damping;
  s.bendStiffness = bendStiffness;
  s.bendDamping = bendDamping;
  s.naturalFrequency = naturalFrequency;
  return s;
}

/// Generates the object a spec describes, with its kind (the scene reader's
/// generators: the same builders and spring defaults).
std::pair<GeneratedObject, std::string> generate(const py::handle& spec,
                                                 const SpringSettings& springs) {
  if (py::isinstance<RopeSpec>(spec)) {
    GeneratedObject o = makeRope(spec.cast<const RopeSpec&>());
    resolveSprings(o, springs);
    return {std::move(o), "rope"};
  }
  if (py::isinstance<BoxSpec>(spec)) {
    GeneratedObject o = makeBox(spec.cast<const BoxSpec&>());
    resolveSprings(o, springs);
    return {std::move(o), "box"};
  }
  if (py::isinstance<PlateSpec>(spec)) {
    GeneratedObject o = makePlate(spec.cast<const PlateSpec&>());
    resolveSprings(o, springs, 0.1);  // a single layer bends through its TS (as the scene's)
    return {std::move(o), "plate"};
  }
  if (py::isinstance<BallSpec>(spec)) {
    GeneratedObject o = makeBall(spec.cast<const BallSpec&>());
    resolveSprings(o, springs);
    return {std::move(o), "ball"};
  }
  if (py::isinstance<WheelSpec>(spec)) {
    GeneratedObject o = makeWheel(spec.cast<const WheelSpec&>());
    resolveSprings(o, springs);
    return {std::move(o), "wheel"};
  }
  if (py::isinstance<ArmSpec>(spec)) return {makeArm(spec.cast<const ArmSpec&>()), "arm"};
  if (py::isinstance<HandSpec>(spec)) return {makeHand(spec.cast<const HandSpec&>()), "hand"};
  if (py::isinstance<VehicleSpec>(spec))
    return {makeVehicle(spec.cast<const VehicleSpec&>()), "vehicle"};
  throw py::type_error(
      "ModelBuilder.add: expected a spec (robophi.Rope, Box, Plate, Ball, "
      "Wheel, Arm, Hand, Vehicle), got " +
      std::string(py::str(spec.get_type())));
}

}  // namespace

void bindBuild(py::module_& m) {
  py::class_<RopeSpec>(m, "Rope", "A rope or chain of particles (build::RopeSpec).")
      .def(py::init<>())
      .def_readwrite("start", &RopeSpec::start, "m")
      .def_readwrite("end", &RopeSpec::end, "m")
      .def_readwrite("particles", &RopeSpec::particles)
      .def_readwrite("mass", &RopeSpec::mass, "kg")
      .def_readwrite("radius", &RopeSpec::radius, "m; 0: half the spacing");
  py::class_<BoxSpec>(m, "Box", "A box lattice (build::BoxSpec).")
      .def(py::init<>())
      .def_readwrite("center", &BoxSpec::center, "m")
      .def_readwrite("size", &BoxSpec::size, "m")
      .def_readwrite("cells", &BoxSpec::cells)
      .def_readwrite("mass", &BoxSpec::mass, "kg")
      .def_readwrite("radius", &BoxSpec::radius, "m; 0: half the smallest cell side")
      .def_readwrite("facets", &BoxSpec::facets);
  py::class_<PlateSpec>(m, "Plate", "A plate or cloth (build::PlateSpec).")
      .def(py::init<>())
      .def_readwrite("center", &PlateSpec::center, "m")
      .def_readwrite("size_x", &PlateSpec::sizeX, "m")
      .def_readwrite("size_y", &PlateSpec::sizeY, "m")
      .def_readwrite("thickness", &PlateSpec::thickness, "m")
      .def_readwrite("cells", &PlateSpec::cells)
      .def_readwrite("mass", &PlateSpec::mass, "kg")
      .def_readwrite("radius", &PlateSpec::radius, "m")
      .def_readwrite("facets", &PlateSpec::facets);
  py::class_<BallSpec>(m, "Ball", "A ball (build::BallSpec).")
      .def(py::init<>())
      .def_readwrite("center", &BallSpec::center, "m")
      .def_readwrite("radius", &BallSpec::radius, "m")
      .def_readwrite("cells", &BallSpec::cells)
      .def_readwrite("mass", &BallSpec::mass, "kg")
      .def_readwrite("particle_radius", &BallSpec::particleRadius, "m")
      .def_readwrite("round", &BallSpec::round);
  py::class_<WheelSpec>(m, "Wheel", "A wheel (build::WheelSpec).")
      .def(py::init<>())
      .def_readwrite("center", &WheelSpec::center, "m")
      .def_readwrite("radius", &WheelSpec::radius, "m")
      .def_readwrite("width", &WheelSpec::width, "m")
      .def_readwrite("axis", &WheelSpec::axis)
      .def_readwrite("rim_particles", &WheelSpec::rimParticles)
      .def_readwrite("mass", &WheelSpec::mass, "kg");

  py::class_<ArmSpec> arm(m, "Arm", "A serial arm fixed at its base (build::ArmSpec).");
  arm.def(py::init<>())
      .def_readwrite("base", &ArmSpec::base, "m")
      .def_readwrite("direction", &ArmSpec::direction)
      .def_readwrite("links", &ArmSpec::links, "m")
      .def_readwrite("axes", &ArmSpec::axes)
      .def_readwrite("mass", &ArmSpec::mass, "kg")
      .def_readwrite("width", &ArmSpec::width, "m")
      .def_readwrite("particles_per_link", &ArmSpec::particlesPerLink)
      .def_readwrite("radius", &ArmSpec::radius, "m")
      .def_readwrite("joint_stiffness", &ArmSpec::jointStiffness, "N·m/rad")
      .def_readwrite("joint_damping", &ArmSpec::jointDamping, "N·m·s/rad");
  robotLinks<ArmSpec>(arm);
  py::class_<HandSpec> hand(m, "Hand", "A three-finger hand (build::HandSpec).");
  hand.def(py::init<>())
      .def_readwrite("center", &HandSpec::center, "m")
      .def_readwrite("palm_radius", &HandSpec::palmRadius, "m")
      .def_readwrite("links", &HandSpec::links, "m")
      .def_readwrite("mass", &HandSpec::mass, "kg")
      .def_readwrite("width", &HandSpec::width, "m")
      .def_readwrite("joint_stiffness", &HandSpec::jointStiffness, "N·m/rad")
      .def_readwrite("joint_damping", &HandSpec::jointDamping, "N·m·s/rad")
      .def_readwrite("spread", &HandSpec::spread, "rad");
  robotLinks<HandSpec>(hand);
  py::class_<VehicleSpec> vehicle(m, "Vehicle", "A chassis on four wheels (build::VehicleSpec).");
  vehicle.def(py::init<>())
      .def_readwrite("center", &VehicleSpec::center, "m")
      .def_readwrite("size", &VehicleSpec::size, "m")
      .def_readwrite("mass", &VehicleSpec::mass, "kg")
      .def_readwrite("wheel_radius", &VehicleSpec::wheelRadius, "m")
      .def_readwrite("wheel_width", &VehicleSpec::wheelWidth, "m")
      .def_readwrite("wheel_mass", &VehicleSpec::wheelMass, "kg")
      .def_readwrite("rim_particles", &VehicleSpec::rimParticles)
      .def_readwrite("wheelbase", &VehicleSpec::wheelbase, "m")
      .def_readwrite("track", &VehicleSpec::track, "m")
      .def_readwrite("suspension_stiffness", &VehicleSpec::suspensionStiffness, "N/m")
      .def_readwrite("suspension_damping", &VehicleSpec::suspensionDamping, "N·s/m")
      .def_readwrite("axle_damping", &VehicleSpec::axleDamping, "N·m·s/rad");
  robotLinks<VehicleSpec>(vehicle);

  py::class_<ModelBuilder>(m, "ModelBuilder",
                           "Builds a Model and its initial State from specs (build::ModelBuilder).")
      .def(py::init<>())
      .def("set_gravity", &ModelBuilder::setGravity, py::arg("gravity"), "g (m/s²)")
      .def("add_material", &ModelBuilder::addMaterial, py::arg("material"),
           "Adds a robophi.Material; returns its index.")
      .def(
          "add_plane",
          [](ModelBuilder& b, const Vec3& point, const Vec3& normal, std::int32_t material) {
            b.addPlane({point, normal, material});
          },
          py::arg("point") = Vec3{}, py::arg("normal") = Vec3{0.0, 0.0, 1.0},
          py::arg("material") = 0, "A half-space the particles stay above (the ground).")
      .def(
          "add_box_obstacle",
          [](ModelBuilder& b, const Vec3& center, const Vec3& halfExtents, std::int32_t material) {
            BoxObstacle box;
            box.center = center;
            box.halfExtents = halfExtents;
            box.material = material;
            b.addBox(box);
          },
          py::arg("center"), py::arg("half_extents"), py::arg("material") = 0)
      .def(
          "add_sphere_obstacle",
          [](ModelBuilder& b, const Vec3& center, double radius, std::int32_t material) {
            b.addSphere({center, radius, material});
          },
          py::arg("center"), py::arg("radius"), py::arg("material") = 0)
      .def("set_viscosity", &ModelBuilder::setViscosity, py::arg("viscosity"), "k (N·s/m)")
      .def(
          "add",
          [](ModelBuilder& b, py::handle spec, const std::string& name, std::vector<Vec3> velocity,
             std::int32_t material, double linearDamping, std::optional<double> stiffness,
             std::optional<double> damping, std::optional<double> bendStiffness,
             std::optional<double> bendDamping, double naturalFrequency) {
            auto [geometry, kind] = generate(spec, springSettings(stiffness, damping, bendStiffness,
                                                                  bendDamping, naturalFrequency));
            ObjectPlacement placement;
            placement.name = name;
            placement.kind = kind;
            placement.geometry = std::move(geometry);
            placement.velocity = std::move(velocity);
            placement.linearDamping = linearDamping;
            placement.material = material;
            const PlacedObject placed = b.addObject(placement);
            return py::make_tuple(placed.object, placed.firstParticle, placed.particleCount);
          },
          py::arg("spec"), py::arg("name"), py::arg("velocity") = std::vector<Vec3>{},
          py::arg("material") = 0, py::arg("linear_damping") = 0.0,
          py::arg("stiffness") = py::none(), py::arg("damping") = py::none(),
          py::arg("bend_stiffness") = py::none(), py::arg("bend_damping") = py::none(),
          py::arg("natural_frequency") = kDefaultNaturalFrequency,
          "Places the object a spec describes (joints named '<name>.<joint>'); returns "
          "(object index, first particle, particle count). The spring keywords are the scene "
          "keys' (passive objects; robots take theirs from the spec).")
      .def(
          "build",
          [](ModelBuilder& b) {
            BuiltModel built = std::move(b).build();
            PyModel model{std::make_shared<const CompiledModel>(std::move(built.model))};
            return py::make_tuple(model, std::move(built.initial));
          },
          "The (Model, State) built; the builder is left empty.");
}

}  // namespace robophi::python
