"""The Python package's benchmark (not a test; docs/python.md "Benchmark").

1. The overhead of one world.step() call from Python on a small model: µs per
   call of a Python loop of single steps, against the same steps in one C++ call
   (world.run(duration, dt=...), a C++ loop over the same step). Target < 2 µs.
2. rollout throughput: 64 copies of scenes/hand_grasp.json, on 1 and 2 threads,
   against a Python loop of single steps over the same worlds. Target: 2 threads
   >= 1.8x one thread.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/bench_step.py [--quick]

Figures move with the machine's load: the results file says when and where.
"""

import argparse
import os
import pathlib
import platform
import time

import numpy as np

import robophi

ROOT = pathlib.Path(__file__).resolve().parents[2]


def small_model():
    """A rope of 4 particles under gravity: a small model, nothing to touch."""
    b = robophi.ModelBuilder()
    b.add(robophi.Rope(start=(0, 0, 1), end=(0.3, 0, 1), particles=4, mass=0.4), name="rope")
    return b.build()


def best_of(repeats, function):
    """The least wall time (s) of `repeats` calls: the run least disturbed by other work."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def step_overhead(steps, repeats):
    model, state = small_model()
    dt = 1e-5
    world = robophi.World(model, state)

    def python_loop():
        step = world.step
        for _ in range(steps):
            step(dt)

    def one_call():
        world.run(steps * dt, dt=dt)

    python_s = best_of(repeats, python_loop)
    cpp_s = best_of(repeats, one_call)
    return python_s / steps * 1e6, cpp_s / steps * 1e6


def rollout_throughput(copies, steps, repeats):
    scene = robophi.load(ROOT / "scenes" / "hand_grasp.json")
    dt = scene.dt  # 2e-4 s, the scene's step: constant steps
    states = [scene.initial] * copies
    args = dict(steps=steps, dt=dt, integrator=scene.integrator)
    results = {}
    hashes = {}
    busiest = {}  # the CPU time (s) of the busiest thread, least over the repeats
    for threads in (1, 2):
        busiest[threads] = float("inf")

        def run():
            r = robophi.rollout(scene.model, states, threads=threads, **args)
            hashes[threads] = r["hashes"]
            busiest[threads] = min(busiest[threads], max(r["thread_cpu_seconds"]))

        results[threads] = best_of(repeats, run)
    assert hashes[1] == hashes[2], "rollout must not depend on the thread count"

    def python_loop():
        for s in states:
            world = robophi.World(scene.model, s, integrator=scene.integrator)
            for _ in range(steps):
                world.step(dt)

    loop_s = best_of(1, python_loop)
    world_steps = copies * steps
    return scene.model.particle_count, {t: world_steps / s for t, s in results.items()}, \
        world_steps / loop_s, busiest[1] / busiest[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps (a smoke run)")
    parser.add_argument("--record", help="append the figures to this file")
    args = parser.parse_args()
    steps = 20_000 if args.quick else 200_000
    rollout_steps = 20 if args.quick else 200
    lines = [f"# python/bench/bench_step.py, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
             f"{os.cpu_count()}-core {platform.machine()} machine shared with other work "
             f"(figures move with load; best of 5; load average "
             f"{os.getloadavg()[0]:.1f} at the start), Python {platform.python_version()}, "
             f"numpy {np.__version__}"]
    python_us, cpp_us = step_overhead(steps, 5)
    lines.append(f"STEP-CALL  model=rope-4 steps={steps} python_loop_us_per_step={python_us:.3f} "
                 f"cpp_loop_us_per_step={cpp_us:.3f} call_overhead_us={python_us - cpp_us:.3f} "
                 f"(target < 2)")
    particles, per_s, loop_per_s, cpu_split = rollout_throughput(64, rollout_steps, 3)
    lines.append(f"ROLLOUT    scene=hand_grasp copies=64 particles={particles} steps={rollout_steps} "
                 f"threads=1 world_steps_per_s={per_s[1]:.0f} threads=2 "
                 f"world_steps_per_s={per_s[2]:.0f} speedup={per_s[2] / per_s[1]:.2f} (target >= 1.8)")
    # How the work splits: one thread's CPU time over the busiest of two threads'
    # (CPU time, which other programs on a shared machine do not stretch as they
    # stretch the wall time). About 2: no serial part, the work evenly shared; the
    # wall-clock speedup reaches it when two cores are free.
    lines.append(f"ROLLOUT    cpu_split: one thread's CPU time / the busiest of 2 threads' = "
                 f"{cpu_split:.2f} (~2: evenly split, no serial part)")
    lines.append(f"ROLLOUT    python loop of single world.step() over the same worlds: "
                 f"world_steps_per_s={loop_per_s:.0f}; rollout threads=2 / python loop = "
                 f"{per_s[2] / loop_per_s:.2f}")
    text = "\n".join(lines)
    print(text)
    if args.record:
        with open(args.record, "a", encoding="utf-8") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
