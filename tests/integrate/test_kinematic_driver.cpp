// A fixed particle given a velocity moves kinematically (a moving virtual robot,
// MODEL §5.1). The work it does on the system is booked as external work, so
// E + dissipated - external stays constant up to the integration error, which
// falls as δ² (Verlet). Work done between steps is booked by bookExternalWork.
#include <gtest/gtest.h>

#include <cmath>

#include "robophi/world.h"

namespace robophi {
namespace {

// A free 1 kg particle towed by an LS (damping in N·s/m) from a fixed particle
// moving at 0.5 m/s along x; gravity off; velocity Verlet.
World makeTow(double damping) {
  Model model;
  model.gravity = {};
  const int object = model.addObject("tow", "particles");
  model.addParticle(1.0, 0.05, true, object);   // the driver (fixed)
  model.addParticle(1.0, 0.05, false, object);  // the load
  model.linearSprings.push_back({0, 1, 0.5, 100.0, damping});
  State state = State::sizedFor(model);
  state.position[1] = {-0.5, 0.1, 0.0};
  state.velocity[0] = {0.5, 0.0, 0.0};
  return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
}

// |ΔE_total| after 2 s of towing at step dt, and the external work booked.
struct Tow {
  double totalError, externalWork, driverX, loadX;
};

Tow tow(double dt, double damping) {
  World world = makeTow(damping);
  world.refresh();
  const double e0 = world.energy().total();
  const int steps = static_cast<int>(std::lround(2.0 / dt));
  for (int s = 0; s < steps; ++s) world.step(dt);
  const State& st = world.state();
  return {std::abs(world.energy().total() - e0), world.energy().external, st.position[0].x,
          st.position[1].x};
}

TEST(KinematicDriver, MovesAtItsVelocityAndItsWorkIsBooked) {
  const Tow t = tow(1e-3, 2.0);
  EXPECT_NEAR(t.driverX, 1.0, 1e-12);  // 0.5 m/s for 2 s, untouched by the spring
  EXPECT_GT(t.loadX, 0.0);             // the load was towed along
  // The driver did real work: the load's kinetic energy alone is ~0.125 J.
  EXPECT_GT(t.externalWork, 0.1);
  // Velocity Verlet evaluates the damping force with half-kicked velocities, so
  // with damping the account is first order in δ: 5e-4 of the work here.
  EXPECT_LT(t.totalError, 1e-3 * t.externalWork);
}

// Undamped, the driver's work is booked to second order, like the integration.
TEST(KinematicDriver, AccountErrorFallsAsTheSquareOfTheStep) {
  const Tow coarse = tow(4e-3, 0.0), fine = tow(1e-3, 0.0);
  ASSERT_GT(coarse.totalError, 0.0);
  const double order = std::log(coarse.totalError / fine.totalError) / std::log(4.0);
  EXPECT_GT(order, 1.7) << coarse.totalError << " " << fine.totalError;
  EXPECT_NEAR(coarse.externalWork, fine.externalWork, 5e-3 * fine.externalWork);
}

TEST(KinematicDriver, ChangesBetweenStepsAreBookedAsExternalWork) {
  World world = makeTow(2.0);
  world.refresh();
  const double before = world.energy().total();
  const double potentialBefore = world.energy().linearSpring;
  world.setPosition(0, world.state().position[0] + Vec3{0.1, 0.0, 0.0});  // stretch by hand
  const double work = world.bookExternalWork();
  EXPECT_NEAR(work, world.energy().linearSpring - potentialBefore, 1e-15);
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(world.energy().total(), before, 1e-14);
  EXPECT_EQ(world.bookExternalWork(), 0.0);  // nothing changed since
}

}  // namespace
}  // namespace robophi
