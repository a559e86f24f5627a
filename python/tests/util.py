"""Small models the tests build without a scene file."""

import robophi


def single_ball(z=1.0, gravity=(0.0, 0.0, -9.81), mass=1.0):
    """One free particle (a ball of one cell) at height z, nothing to touch."""
    b = robophi.ModelBuilder()
    b.set_gravity(gravity)
    b.add(robophi.Ball(center=(0.0, 0.0, z), radius=0.05, mass=mass), name="ball")
    return b.build()


def vertical_arm(joint_stiffness=20.0):
    """A two-link arm swinging in the x-z plane (axes +y), horizontal at the start:
    gravity loads both joints."""
    b = robophi.ModelBuilder()
    b.add(robophi.Arm(base=(0.0, 0.0, 1.0), direction=(1.0, 0.0, 0.0), links=[0.5, 0.4],
                      axes=[(0.0, 1.0, 0.0)], mass=1.0, joint_stiffness=joint_stiffness, joint_damping=3.0),
          name="arm")
    return b.build()
