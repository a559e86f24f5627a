// The build layer's specs as Python classes (robophi.Box(...), robophi.Arm(...),
// ...) and robophi.ModelBuilder: a model without a scene file. Every spec is
// checked by its builder (SpecError naming the field, as the scene reader's).
#include "py_robophi.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/objects.h"
#include "robophi/build/rigid_body.h"
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

/// A shape's frame in the body frame from URDF-style xyz (m) and rpy (rad).
Frame shapeFrame(const Vec3& xyz, const Vec3& rpy) { return Frame::fromXyzRpy(xyz, rpy); }

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
  if (py::isinstance<RigidBodySpec>(spec)) {
    GeneratedObject o = makeRigidBody(spec.cast<const RigidBodySpec&>()).object;
    // Spring values given: they replace the body's stiffness rule (as a scene's mesh object).
    if (springs.stiffness || springs.damping) resolveSprings(o, springs);
    return {std::move(o), "rigid_body"};
  }
  if (py::isinstance<ArmSpec>(spec)) return {makeArm(spec.cast<const ArmSpec&>()), "arm"};
  if (py::isinstance<HandSpec>(spec)) return {makeHand(spec.cast<const HandSpec&>()), "hand"};
  if (py::isinstance<VehicleSpec>(spec))
    return {makeVehicle(spec.cast<const VehicleSpec&>()), "vehicle"};
  throw py::type_error(
      "ModelBuilder.add: expected a spec (robophi.Rope, Box, Plate, Ball, "
      "Wheel, RigidBody, Arm, Hand, Vehicle), got " +
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
      .def_readwrite("mass", &WheelSpec::mass, "kg")
      .def_readwrite("hub_span", &WheelSpec::hubSpan, "m");

  // Rigid bodies from geometry (build/rigid_body.h): shapes filled with fitted particles.
  py::class_<ShapeSpec>(m, "Shape", "One piece of a rigid body's volume (build::ShapeSpec).")
      .def_static(
          "box",
          [](const Vec3& size, const Vec3& xyz, const Vec3& rpy) {
            ShapeSpec s;
            s.kind = ShapeSpec::Kind::kBox;
            s.size = size;
            s.frame = shapeFrame(xyz, rpy);
            return s;
          },
          py::arg("size"), py::arg("xyz") = Vec3{}, py::arg("rpy") = Vec3{},
          "A box of full side lengths `size` (m) at xyz (m), turned by rpy (rad).")
      .def_static(
          "cylinder",
          [](double radius, double length, const Vec3& xyz, const Vec3& rpy) {
            ShapeSpec s;
            s.kind = ShapeSpec::Kind::kCylinder;
            s.radius = radius;
            s.length = length;
            s.frame = shapeFrame(xyz, rpy);
            return s;
          },
          py::arg("radius"), py::arg("length"), py::arg("xyz") = Vec3{}, py::arg("rpy") = Vec3{},
          "A cylinder along its local z (m).")
      .def_static(
          "sphere",
          [](double radius, const Vec3& xyz) {
            ShapeSpec s;
            s.kind = ShapeSpec::Kind::kSphere;
            s.radius = radius;
            s.frame = shapeFrame(xyz, Vec3{});
            return s;
          },
          py::arg("radius"), py::arg("xyz") = Vec3{})
      .def_static(
          "mesh",
          [](const std::string& path, const Vec3& scale, const Vec3& xyz, const Vec3& rpy) {
            ShapeSpec s;
            s.kind = ShapeSpec::Kind::kMesh;
            s.mesh = loadMesh(path, scale);
            s.frame = shapeFrame(xyz, rpy);
            return s;
          },
          py::arg("path"), py::arg("scale") = Vec3{1.0, 1.0, 1.0}, py::arg("xyz") = Vec3{},
          py::arg("rpy") = Vec3{},
          "A triangle mesh file (STL, OBJ, DAE, ...), scaled per axis; RuntimeError naming the "
          "file when it cannot be read.")
      .def_property_readonly("kind", [](const ShapeSpec& s) {
        switch (s.kind) {
          case ShapeSpec::Kind::kBox:
            return "box";
          case ShapeSpec::Kind::kCylinder:
            return "cylinder";
          case ShapeSpec::Kind::kSphere:
            return "sphere";
          case ShapeSpec::Kind::kMesh:
            return "mesh";
        }
        return "?";
      });
  py::class_<RigidBodySpec>(m, "RigidBody",
                            "A rigid body of particles with the given mass, centre of mass and "
                            "inertia, filling the union of its shapes (build::RigidBodySpec).")
      .def(py::init<>())
      .def_readwrite("shapes", &RigidBodySpec::shapes)
      .def_readwrite("mass", &RigidBodySpec::mass, "kg")
      .def_readwrite("center_of_mass", &RigidBodySpec::centerOfMass, "m, body frame")
      .def_property(
          "inertia",
          [](const RigidBodySpec& s) {
            const Inertia& i = s.inertia;
            return std::array<double, 6>{i.xx, i.yy, i.zz, i.xy, i.xz, i.yz};
          },
          [](RigidBodySpec& s, const std::array<double, 6>& i) {
            s.inertia = {i[0], i[1], i[2], i[3], i[4], i[5]};
          },
          "(xx, yy, zz, xy, xz, yz) about the centre of mass (kg·m²); zeros: uniform density")
      .def_readwrite("uniform_density", &RigidBodySpec::uniformDensity)
      .def_readwrite("required_points", &RigidBodySpec::requiredPoints, "m, body frame")
      .def_readwrite("particle_size", &RigidBodySpec::particleSize, "m; 0: from particle_count")
      .def_readwrite("particle_count", &RigidBodySpec::particleCount)
      .def_readwrite("min_mass_fraction", &RigidBodySpec::minMassFraction)
      .def_readwrite("max_carrier_distance", &RigidBodySpec::maxCarrierDistance, "m; 0: none")
      .def_readwrite("natural_frequency", &RigidBodySpec::naturalFrequency, "rad/s");

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
