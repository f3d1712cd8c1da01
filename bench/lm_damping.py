"""Levenberg-Marquardt damping: chatter toward a target out of reach, and cycles to
converge toward reachable ones, for several ``lm_damping`` values on the Panda.

Counts cycles of the simulated loop (``q += dq * dt``), so the table does not depend
on the machine. Usage: ``python bench/lm_damping.py``
"""

from __future__ import annotations

import numpy as np
from rich.console import Console
from rich.table import Table

from robocop_dsl.control import Controller, ProportionalFeedback
from robocop_dsl.world import load_world

VALUES = (0.0, 1e-3, 1e-2, 3e-2, 1e-1, 1.0)
OUT_OF_REACH = np.array([1.5, 0.8, 1.5])
"""A hand position 0.9 m beyond the Panda's reach [m]."""
TARGETS = 20
CYCLES = 2000


def controller(world, lm_damping: float, target) -> tuple[Controller, object]:
    """The Panda's controller with its URDF limits and a hand task toward ``target``."""
    control = Controller.from_world(world, lm_damping=lm_damping)
    control.add_constraint("joint_kinematic", "limits", "panda_arm", max_acceleration=100.0)
    kind = "body_position" if isinstance(target, np.ndarray) else "body_pose"
    task = control.add_task(kind, "hand", "panda_hand", target=target,
                            feedback=ProportionalFeedback(gain=5.0))
    task.enable()
    return control, task


def simulate(world, control, task, q, cycles: int, until: float | None = None):
    """Commands of ``cycles`` cycles [rad/s], or the cycles until ``task.error`` is
    below ``until``."""
    indices = control.joint_group.q_indices
    commands = []
    for cycle in range(cycles):
        result = control.compute(q)
        if not result.solved:
            raise RuntimeError(result.reason)
        q[indices] += result.velocity * control.time_step
        commands.append(result.velocity)
        if until is not None and task.error < until:
            return cycle + 1
    return np.array(commands) if until is None else cycles


def chatter(world, lm_damping: float) -> tuple[float, int]:
    """Over the last second toward :data:`OUT_OF_REACH`: the largest joint speed
    [rad/s] and the sign changes of commands above 0.01 rad/s."""
    control, task = controller(world, lm_damping, OUT_OF_REACH)
    last = simulate(world, control, task, world.initial_configuration(), CYCLES)[-200:]
    moving = np.abs(last) > 0.01
    flips = np.sign(last[1:]) != np.sign(last[:-1])
    return float(np.abs(last).max()), int(np.sum(flips & moving[1:] & moving[:-1]))


def reachable_targets(world, seed: int = 0):
    """Hand poses of random configurations near random starts: ``(start, pose)``."""
    rng = np.random.default_rng(seed)
    group = world.joint_group("panda_arm")
    pairs = []
    for _ in range(TARGETS):
        start = world.initial_configuration()
        middle = (group.lower + group.upper) / 2
        start[group.q_indices] = middle + rng.uniform(-0.5, 0.5, group.dofs) * (
            group.upper - group.lower) / 2
        goal = start.copy()
        goal[group.q_indices] = np.clip(goal[group.q_indices] + rng.normal(0, 0.3, group.dofs),
                                        group.lower, group.upper)
        pairs.append((start, world.body_pose("panda_hand", goal)))
    return pairs


def convergence(world, lm_damping: float, pairs) -> list[int]:
    """Cycles until the hand pose error is below 1 mm (:data:`CYCLES` if never)."""
    cycles = []
    for start, pose in pairs:
        control, task = controller(world, lm_damping, pose)
        cycles.append(simulate(world, control, task, start.copy(), CYCLES, until=1e-3))
    return cycles


def main() -> None:
    world = load_world("panda/panda_on_table.yaml")
    pairs = reachable_targets(world)
    reference = np.array(convergence(world, 0.0, pairs), dtype=float)
    table = Table(title="Panda: lm_damping, out of reach and reachable targets")
    for column in ("lm_damping", "max |dq| last s [rad/s]", "sign flips last s",
                   f"converged (of {TARGETS})", "cycles vs lm_damping 0 (mean ratio)"):
        table.add_column(column, justify="right")
    for value in VALUES:
        speed, flips = chatter(world, value)
        cycles = np.array(convergence(world, value, pairs), dtype=float)
        table.add_row(f"{value:g}", f"{speed:.3f}", str(flips),
                      str(int(np.sum(cycles < CYCLES))), f"{np.mean(cycles / reference):.3f}")
    Console().print(table)


if __name__ == "__main__":
    main()
