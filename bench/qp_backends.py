"""ProxQP against DAQP (called directly, and through qpsolvers) on the controller's QPs.

Problems (the controller's own, built by :class:`~robocop_dsl.control.Controller`):

- Panda (7 dofs, ``panda_arm``): a body_pose task on the hand (priority 0), a
  joint_position posture task (priority 1, weight 1e-2), joint_kinematic limits (URDF
  position and velocity limits, 10 rad/s^2).
- BAZAR (16 dofs, ``bazar_upper_joints``): body_pose tasks on both tools, the posture
  task, the joint limits and body_velocity limits on both tools (52 rows).
- TALOS (30 dofs, ``talos_body``, base fixed): body_pose tasks on the hands and the
  feet, the posture task, the joint limits.

Each in the weighted hierarchy (one QP) and the strict one (level 0, then level 1 with
the equality rows of level 0's tasks), with targets 5 cm and 0.2 rad away ("reach": the
acceleration limits bind on the first cycles) and 0.6 m away ("far": out of reach, the
joints run into their position limits and stay there); and, Panda and BAZAR, far, with
two more levels ("4 levels": a body_position task 10 cm away at priority 2, a posture
0.3 rad away at priority 3), whose equality rows outnumber the dofs. A controller on
ProxQP drives the robot; every cycle, each level's QP and the braking QP are solved by
three more solvers kept for that QP from cycle to cycle: ProxQP (warm-started but on
the braking QP, as in the controller), DAQP direct (warm-started), DAQP through
qpsolvers (from scratch), in turns (the first of the three changes every cycle), each timed
with the calling thread's CPU time (``time.thread_time_ns``). Printed per QP: its size
``n/eq/in`` (variables, equality rows, inequality rows), the mean number of rows binding
at DAQP's solution (bounds and rows), the median ProxQP time, the ratios
``daqp/proxqp`` and ``qpsolvers-daqp/proxqp`` (median over turns of 50 cycles of the
ratio of their medians; below 1: faster than ProxQP), DAQP's mean iterations, and the
largest difference between ProxQP's and DAQP's answers where both found one, and the
cycles where each found none.

Then the whole control cycle with ``solver`` proxqp, daqp and auto (three controllers
on the same problem, in turns of 50 cycles), as ratios to proxqp.

Usage: ``python bench/qp_backends.py [--cycles N] [--only WORLD]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

from robocop_dsl.control import Controller
from robocop_dsl.control.solvers import make_solver
from robocop_dsl.control.solvers.qpsolvers_backend import QpsolversSolver
from robocop_dsl.world import load_world

GAIN, POSTURE_WEIGHT, DAMPING, ACCELERATION = 5.0, 1e-2, 1e-6, 10.0
BLOCK = 50
CASES = {
    "Panda": dict(world="panda/panda_on_table.yaml", group="panda_arm", time_step=0.002,
                  bodies=("panda_hand",), body_velocity=False),
    "BAZAR": dict(world="bazar/sophia.yaml", group="bazar_upper_joints", time_step=0.005,
                  bodies=("bazar_left_hankamp_tool_object_side",
                          "bazar_right_hankamp_tool_object_side"), body_velocity=True),
    "TALOS": dict(world="talos/talos.yaml", group="talos_body", time_step=0.005,
                  bodies=("gripper_left_base_link", "gripper_right_base_link",
                          "left_sole_link", "right_sole_link"), body_velocity=False),
}
SHIFTS = {"reach": 0.05, "far": 0.6}
"""Target offsets [m] along x, y, z (with a 0.2 rad turn) of each scenario."""
BACKENDS = ("proxqp", "daqp", "qpsolvers-daqp")


def build(case, world, hierarchy, shift, solver="proxqp", deep=False):
    """The case's controller, its targets ``shift`` [m] away from the start; ``deep``:
    two more levels (a body_position task 10 cm away, a posture 0.3 rad away), whose
    equality rows outnumber the dofs."""
    q0 = world.initial_configuration()
    control = Controller(world, case["group"], case["time_step"], solver, hierarchy,
                         damping=DAMPING)
    control.add_constraint("joint_kinematic", "limits", case["group"],
                           max_acceleration=ACCELERATION)
    if case["body_velocity"]:
        for body in case["bodies"]:
            control.add_constraint("body_velocity", f"{body}_speed", body, max_linear=0.5,
                                   max_angular=1.0)
    control.set_auto_enable(True)
    offset = pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.2])), np.array([shift, -shift, shift]))
    for body in case["bodies"]:
        control.add_task("body_pose", body, body, target=world.body_pose(body, q0) * offset,
                         gain=GAIN)
    control.add_task("joint_position", "posture", case["group"], priority=1,
                     weight=POSTURE_WEIGHT, gain=GAIN, target=q0[control.state.q_indices])
    if deep:
        body = case["bodies"][0]
        control.add_task("body_position", "lift", body, priority=2, gain=GAIN,
                         target=world.body_pose(body, q0).translation + 0.1)
        control.add_task("joint_position", "spread", case["group"], priority=3, gain=GAIN,
                         target=q0[control.state.q_indices] + 0.3)
    return control, q0


def new_solver(backend: str, warm_start: bool):
    return QpsolversSolver("daqp") if backend == "qpsolvers-daqp" else make_solver(
        backend, warm_start=warm_start)


def binding(program, x, tolerance=1e-7) -> int:
    """Bounds and inequality rows binding at ``x``."""
    count = np.count_nonzero((x - program.lower < tolerance) | (program.upper - x < tolerance))
    if program.l.size:
        cx = program.C @ x
        count += np.count_nonzero((cx - program.l < tolerance) | (program.u - cx < tolerance))
    return int(count)


def per_qp(case, world, hierarchy, shift, cycles, deep=False):
    """Rows ``(label, size, binding, proxqp us, daqp ratio, qpsolvers ratio, daqp
    iterations, largest difference, (proxqp failures, daqp failures))`` of every QP of
    one run."""
    control, q = build(case, world, hierarchy, shift, deep=deep)
    indices = world.joint_group(case["group"]).q_indices
    solvers, times, stats = {}, {}, {}
    for cycle in range(cycles):
        command = control.compute(q).velocity
        q[indices] += command * case["time_step"]
        plan = control._cached_plan
        programs = [(f"level {index}", program) for index, program
                    in enumerate(control.problems)] + [("braking", plan.braking.program)]
        for label, program in programs:
            if label not in solvers:
                solvers[label] = [new_solver(backend, label != "braking" or backend != "proxqp")
                                  for backend in BACKENDS]
                times[label] = [[] for _ in BACKENDS]
                stats[label] = [program.size, [], [], 0.0, [0, 0]]
            answers = [None] * len(BACKENDS)
            for turn in range(len(BACKENDS)):
                index = (turn + cycle) % len(BACKENDS)
                start = time.thread_time_ns()
                answers[index] = solvers[label][index].solve(program)
                times[label][index].append(time.thread_time_ns() - start)
            proxqp, daqp = answers[0], answers[1]
            record = stats[label]
            record[4][0] += not proxqp.found
            record[4][1] += not daqp.found
            record[1].append(binding(program, daqp.x))
            record[2].append(daqp.iterations)
            if proxqp.found and daqp.found:
                record[3] = max(record[3], float(np.max(np.abs(proxqp.x - daqp.x))))
    rows = []
    for label, spent in times.items():
        turns = len(spent[0]) // BLOCK
        blocks = [np.array(t[:turns * BLOCK]).reshape(turns, BLOCK)[turns // 10:]
                  for t in spent]
        ratios = [float(np.median(np.median(b, axis=1) / np.median(blocks[0], axis=1)))
                  for b in blocks[1:]]
        size, bound, iterations, difference, failures = stats[label]
        rows.append((label, size, float(np.mean(bound)), np.median(blocks[0]) / 1e3,
                     *ratios, float(np.mean(iterations)), difference, failures))
    return rows


def whole_cycle(case, world, hierarchy, shift, cycles):
    """Median thread CPU time per cycle [us] with proxqp, and the ratios of daqp and
    auto to it (median over turns of the ratio of their medians)."""
    runs = []
    for solver in ("proxqp", "daqp", "auto"):
        control, q = build(case, world, hierarchy, shift, solver)
        runs.append((control, q, []))
    indices = world.joint_group(case["group"]).q_indices
    for _ in range(0, cycles, BLOCK):
        for control, q, spent in runs:
            for _ in range(BLOCK):
                start = time.thread_time_ns()
                command = control.compute(q).velocity
                spent.append(time.thread_time_ns() - start)
                q[indices] += command * case["time_step"]
    turns = len(runs[0][2]) // BLOCK
    blocks = [np.array(spent).reshape(turns, BLOCK)[turns // 10:] for _, _, spent in runs]
    base = np.median(blocks[0], axis=1)
    return (np.median(blocks[0]) / 1e3, *(float(np.median(np.median(b, axis=1) / base))
                                          for b in blocks[1:]))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=600)
    parser.add_argument("--only", choices=sorted(CASES))
    args = parser.parse_args(argv)
    cases = {name: case for name, case in CASES.items() if args.only in (None, name)}
    print(f"{'problem':<30}{'QP':<9}{'n/eq/in':>10}{'binding':>8}{'proxqp us':>10}"
          f"{'daqp':>7}{'qps-daqp':>9}{'daqp it':>8}{'|dx| max':>10}{'failed p/d':>11}")
    runs = [(name, scenario, hierarchy) for name in cases for scenario in SHIFTS
            for hierarchy in ("weighted", "strict")]
    runs += [(name, "far", "4 levels") for name in cases if name != "TALOS"]
    worlds = {name: load_world(case["world"]) for name, case in cases.items()}
    for name, scenario, hierarchy in runs:
        deep = hierarchy == "4 levels"
        for (label, size, bound, proxqp, daqp, qpsolvers, iterations, difference,
             failures) in per_qp(cases[name], worlds[name], "strict" if deep else hierarchy,
                                 SHIFTS[scenario], args.cycles, deep):
            print(f"{f'{name}, {hierarchy}, {scenario}':<30}{label:<9}"
                  f"{'/'.join(map(str, size)):>10}{bound:>8.1f}{proxqp:>10.1f}"
                  f"{daqp:>6.2f}x{qpsolvers:>8.2f}x{iterations:>8.1f}"
                  f"{difference:>10.1e}{'/'.join(map(str, failures)):>11}")
    print(f"\n{'whole cycle':<30}{'proxqp us':>10}{'daqp':>8}{'auto':>8}")
    for name, case in cases.items():
        for scenario, shift in SHIFTS.items():
            for hierarchy in ("weighted", "strict"):
                proxqp, daqp, auto = whole_cycle(case, worlds[name], hierarchy, shift,
                                                 args.cycles)
                print(f"{f'{name}, {hierarchy}, {scenario}':<30}{proxqp:>10.1f}"
                      f"{daqp:>7.2f}x{auto:>7.2f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
