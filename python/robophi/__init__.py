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
    Material,
    Model,
    ModelBuilder,
    Object,
    Plate,
    RigidBody,
    Rope,
    Scene,
    SceneError,
    Shape,
    Snapshot,
    SpecError,
    State,
    Vehicle,
    Wheel,
    World,
    format_hash,
    rollout,
    run,
    state_hash,
)
from ._robophi import _load_scene

__all__ = [
    "AdaptiveSettings", "Arm", "Ball", "Box", "DivergedError", "EnergyTally", "Error", "Hand",
    "Joint", "Material", "Model", "ModelBuilder", "Object", "Plate", "RigidBody", "Rope",
    "Scene", "SceneError", "Shape", "Snapshot", "SpecError", "State", "Vehicle", "Wheel", "World",
    "format_hash",
    "load", "rollout", "run", "state_hash",
]


def load(path):
    """Loads a scene file (.json) into a robophi.Scene.

    SceneError (a ValueError) lists every problem as the CLI does, each as
    file:line:column: error: message (at /JSON pointer); its .diagnostics holds them
    as dicts. A .urdf file goes to the URDF importer once it is part of robophi.
    """
    text = _os.fspath(path)
    if text.lower().endswith(".urdf"):
        importer = getattr(_robophi_module(), "_load_urdf", None)
        if importer is None:
            raise NotImplementedError(
                f"{text}: this robophi has no URDF importer yet; load a scene file (.json)")
        return importer(text)
    return _load_scene(text)


def _robophi_module():
    from . import _robophi
    return _robophi


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


for _spec in (Rope, Box, Plate, Ball, Wheel, RigidBody, Arm, Hand, Vehicle):
    _keyword_init(_spec)
del _spec
