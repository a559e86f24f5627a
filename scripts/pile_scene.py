#!/usr/bin/env python3
"""Writes the PILE benchmark's pile as a scene file (docs/performance.md,
"PILE's tangential damping"): n^3 balls of radius 1 cm, 1000 kg/m^3, on a
2.5 cm lattice jittered by up to 2 mm (the same SplitMix64 sequence and seed as
apps/robophi/pile_layout.h), each ball its own `ball` object, in a box of four
walls on the ground; pair contact stiffness kappa_c, damping ratio 0.3,
friction 0.5; 1 s with symplectic Euler. The adaptive step by default (as a
user would run it), or a constant one.

    python3 scripts/pile_scene.py 10 --out pile1000.json
    build/robophi run pile1000.json --out /tmp/pile --threads 1
"""
import argparse
import json
import math

MASK = (1 << 64) - 1


class SplitMix64:
    def __init__(self, state):
        self.state = state

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    def symmetric(self):
        """Uniform in [-1, 1), as pile::SplitMix64::symmetric."""
        return (self.next() >> 11) * 2.0 ** -52 - 1.0


def pile_scene(n, pair_stiffness, tangential_damping, step, dt):
    radius, spacing, density = 0.01, 0.025, 1000.0
    lowest, jitter, friction, damping_ratio = 0.015, 0.002, 0.5, 0.3
    mass = density * 4.0 / 3.0 * math.pi * radius ** 3
    random = SplitMix64(0x5EED0000 + n)
    half = 0.5 * n * spacing
    objects = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                jx, jy, jz = random.symmetric(), random.symmetric(), random.symmetric()
                centre = [-half + (i + 0.5) * spacing + jx * jitter,
                          -half + (j + 0.5) * spacing + jy * jitter,
                          lowest + k * spacing + jz * jitter]
                objects.append({"name": f"ball{len(objects)}", "type": "ball", "center": centre,
                                "radius": radius, "mass": mass, "material": "pile"})
    reach, half_length = half + 0.025, half + 0.05
    boxes = []
    for side in range(4):
        sign = 1.0 if side % 2 == 0 else -1.0
        if side < 2:
            boxes.append({"center": [sign * reach, 0, 0.3], "size": [0.05, 2 * half_length, 0.6],
                          "material": "pile"})
        else:
            boxes.append({"center": [0, sign * reach, 0.3], "size": [2 * half_length, 0.05, 0.6],
                          "material": "pile"})
    # Every surface has the same material: the pair's values are half the material's (series).
    pair_damping = 2.0 * damping_ratio * math.sqrt(pair_stiffness * 0.5 * mass)
    run = {"duration": 1.0, "dt": dt, "integrator": "symplectic-euler", "fps": 30}
    if step == "constant":
        run["step"] = "constant"
    scene = {
        "robophi": 1,
        "name": f"pile of {n ** 3} balls",
        "run": run,
        "materials": [{"name": "pile", "contactStiffness": 2.0 * pair_stiffness,
                       "contactDamping": 2.0 * pair_damping, "staticFriction": friction,
                       "kineticFriction": friction}],
        "environment": {"ground": {"material": "pile"}, "boxes": boxes},
        "objects": objects,
    }
    if tangential_damping is not None:
        scene["contact"] = {"tangentialDampingRatio": tangential_damping}
    return scene


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("n", type=int, help="balls along each side (n^3 balls), >= 1")
    parser.add_argument("--pair-stiffness", type=float, default=2.0e4,
                        help="kappa_c between two balls (N/m, default PILE's 2e4)")
    parser.add_argument("--tangential-damping", type=float, default=None,
                        help="contact.tangentialDampingRatio (default: robophi's; PILE uses 0.5)")
    parser.add_argument("--step", choices=["adaptive", "constant"], default="adaptive")
    parser.add_argument("--dt", type=float, default=1.0e-4,
                        help="the constant step, or the first trial step (s)")
    parser.add_argument("--out", required=True, help="the scene file to write")
    args = parser.parse_args()
    if args.n < 1:
        parser.error(f"n = {args.n}: at least 1")
    with open(args.out, "w", encoding="utf-8") as out:
        json.dump(pile_scene(args.n, args.pair_stiffness, args.tangential_damping, args.step,
                             args.dt), out)
        out.write("\n")


if __name__ == "__main__":
    main()
