"""robophi: particles tied by spring/damper connectors, for robots (docs/python.md).

    import robophi
    scene = robophi.load("scenes/revolute_arm.json")
    world = robophi.World(scene)
    world.run(0.5, callback=lambda w: print(w.time, w.joint_positions))
    world.positions          # (n, 3) float64 view on the world's own memory

The extension module robophi._robophi holds the classes; this file adds the
keyword constructors of the builder specs and robophi.load.
"""

import os as _os

from ._robophi import (  # noqa: F401
    AdaptiveSettings,
    Arm,
    Ball,
    Box,
    DivergedError,
    EnergyTally,
    Error,
    Hand,
    Joint,
    JointDrive,
    Material,
    Model,
    ModelBuilder,
    Object,
    Plate,
    RigidBody,
    RigidRobot,
    Rope,
    Scene,
    SceneError,
    Shape,
    Snapshot,
    SpecError,
    State,
    Trajectory,
    Urdf,
    Vehicle,
    Wheel,
    World,
    format_hash,
    rollout,
    run,
    state_hash,
)
from ._robophi import _is_mjcf_path, _is_urdf_path, _load_mjcf, _load_scene, _load_urdf

__all__ = [
    "AdaptiveSettings", "Arm", "Ball", "Box", "DivergedError", "EnergyTally", "Error", "Hand",
    "Joint", "JointDrive", "Material", "Model", "ModelBuilder", "Object", "Plate", "RigidBody",
    "RigidRobot", "Rope", "Scene", "SceneError", "Shape", "Snapshot", "SpecError", "State", "Trajectory",
    "Urdf", "Vehicle", "Wheel", "World",
    "format_hash", "load", "rollout", "run", "state_hash",
]


def load(path, *, package_paths=None, base=None, rigid=True, particle_size=0.0,
         particles_per_link=30):
    """Loads a scene file (.json), a bare URDF robot (.urdf) or an MJCF robot (.xml, read by
    MuJoCo's compiler: rigid bodies held by its position actuators) into a robophi.Scene.

    A scene file: SceneError (a ValueError) lists every problem as the CLI does, each
    as file:line:column: error: message (at /JSON pointer); its .diagnostics holds
    them as dicts.

    A URDF (.urdf, .xacro) becomes the scene `robophi run ROBOT.urdf` runs: the robot
    on a ground plane (z = 0) under gravity, resting on it, its joints held where they
    are built by servos. rigid (the default): its links rigid bodies with the file's
    exact mass properties, joints in reduced coordinates; rigid=False (--particles):
    the paper's model, links filled with particles tied by connectors, whose
    resolution particle_size (m, 0: by count) or particles_per_link set.
    package_paths: folders for package://NAME/... meshes (--package-path; then
    ROS_PACKAGE_PATH; then beside the file); base: "fixed" or "free" (--base; None:
    free for a wheeled base, fixed otherwise). A URDF that cannot be
    imported is a SceneError with the CLI's lines (FILE:LINE: error: message);
    ignored elements (<gazebo>, <visual>, ...) are in scene.warnings, and what the
    file declares in scene.urdf_robots.
    """
    text = _os.fspath(path)
    if _is_mjcf_path(text):
        if package_paths is not None or base is not None:
            raise TypeError(f"robophi.load: {text}: package_paths and base are for a URDF; "
                            "an MJCF file names its meshes and base itself")
        return _load_mjcf(text, particle_size=particle_size, particles_per_link=particles_per_link)
    if _is_urdf_path(text):
        return _load_urdf(text, package_paths=[_os.fspath(p) for p in package_paths or []],
                          base=base, rigid=rigid, particle_size=particle_size,
                          particles_per_link=particles_per_link)
    if package_paths is not None or base is not None or particle_size != 0.0 \
            or particles_per_link != 30 or rigid is not True:
        raise TypeError(f"robophi.load: {text}: package_paths, base, rigid, particle_size and "
                        "particles_per_link are for a URDF (.urdf); a scene file sets them "
                        "in its {\"type\": \"urdf\"} objects")
    return _load_scene(text)


def _keyword_init(cls):
    """Gives a spec class a constructor taking its fields as keywords:
    robophi.Box(center=(0, 0, 0.1), size=(0.1, 0.1, 0.1), cells=(2, 2, 2), mass=0.5)."""
    base_init = cls.__init__
    fields = sorted(name for name, value in vars(cls).items()
                    if not name.startswith("_") and isinstance(value, property))

    def __init__(self, **fields_given):
        base_init(self)
        for name, value in fields_given.items():
            if name not in fields:
                raise TypeError(f"{cls.__name__}() has no field '{name}' (fields: "
                                f"{', '.join(fields)})")
            setattr(self, name, value)

    def __repr__(self):
        shown = ", ".join(f"{name}={getattr(self, name)!r}" for name in fields)
        return f"robophi.{cls.__name__}({shown})"

    __init__.__doc__ = f"{cls.__doc__}\n\nKeywords: {', '.join(fields)}."
    cls.__init__ = __init__
    cls.__repr__ = __repr__
    return cls


for _spec in (Rope, Box, Plate, Ball, Wheel, RigidBody, Arm, Hand, Vehicle, Urdf):
    _keyword_init(_spec)
del _spec
