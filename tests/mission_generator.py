"""Valid missions generated from the catalogue for a world: random parameter values
within their declared ranges, random targets among the world's bodies, random state
graphs. Deterministic for a seed, so a failure is reproduced by its seed."""

from __future__ import annotations

import math
import random

import numpy as np

from robocop_dsl.lang import catalogue as cat
from robocop_dsl.lang.units import (ANGLE, ANGULAR_ACCELERATION, ANGULAR_JERK,
                                    ANGULAR_VELOCITY, DIMENSIONLESS, LENGTH,
                                    LINEAR_ACCELERATION, LINEAR_JERK, LINEAR_VELOCITY,
                                    SI_SYMBOL, TIME)

RATES = {cat.POSITION: 0, cat.VELOCITY: 1, cat.ACCELERATION: 2, cat.JERK: 3}
LINEAR = (LENGTH, LINEAR_VELOCITY, LINEAR_ACCELERATION, LINEAR_JERK)
ANGULAR = (ANGLE, ANGULAR_VELOCITY, ANGULAR_ACCELERATION, ANGULAR_JERK)
SKIPPED = {"target", "interpolator", "feedback", "reference", "enabled", "tolerance",
           "priority", "min_position", "max_position"}
"""Parameters written by the generator's own rules rather than at random."""


class Scene:
    """What a generated mission may name in a world: its controlled joint group, the
    bodies that group moves, and every body."""

    def __init__(self, world, path: str):
        self.path = path
        controller = world.processors[world.controller_names()[0]]
        self.group = world.joint_group(controller.options["joint_group"])
        model = world.model
        joints = {model.getJointId(name) for name in self.group.joints}
        self.tools = [b for b in world.body_names()
                      if joints & set(model.supports[
                          model.frames[world.body_frame_id(b)].parentJoint])]
        self.bodies = world.body_names()
        self.revolute = not any(world.joint(j).type == "prismatic" for j in self.group.joints)
        self.sensed = [p.options["body"] for p in world.processors.values()
                       if p.type == "force_sensor"]


def _unit(dimension: str) -> str:
    return SI_SYMBOL[dimension]


def _dimension(parameter, space: str, revolute: bool, angular: bool = False) -> str:
    """The SI dimension of ``parameter`` in a task or constraint of ``space``."""
    if parameter.dimension not in RATES:
        return parameter.dimension
    rate = RATES[parameter.dimension]
    if space in (cat.JOINT_SPACE, cat.JOINT_VELOCITY_SPACE):
        return (ANGULAR if revolute else LINEAR)[rate]
    return (ANGULAR if angular or space in (cat.ORIENTATION_SPACE, cat.GAZE_SPACE)
            else LINEAR)[rate]


class MissionGenerator:
    """One random mission per call of :meth:`mission`."""

    def __init__(self, scene: Scene, seed: int):
        self.scene = scene
        self.rng = random.Random(seed)

    def number(self, parameter, dimension: str) -> float:
        """A value in the parameter's range: log-uniform over six decades for a
        positive quantity, a small integer-like gain for a dimensionless one."""
        valid = parameter.valid
        if dimension == TIME:
            return round(self.rng.uniform(0.05, 3.0), 3)
        if valid is not None and valid.strict:
            return float(f"{10 ** self.rng.uniform(-2, 2):.4g}")
        if valid is not None:
            return float(f"{self.rng.choice([0.0, 10 ** self.rng.uniform(-2, 2)]):.4g}")
        return float(f"{self.rng.uniform(-2, 2):.4g}")

    def value(self, parameter, space: str, axes: int) -> str:
        """A parameter's value as written in a mission."""
        dimension = _dimension(parameter, space, self.scene.revolute)
        unit = f" {_unit(dimension)}" if dimension != DIMENSIONLESS else ""
        if parameter.kind == cat.INTEGER:
            return str(self.rng.randint(0, 3))
        if parameter.kind == cat.SWITCH:
            return self.rng.choice(cat.SWITCH_WORDS)
        vector = {cat.PER_DOF: axes, cat.PER_AXIS: axes, cat.NORM_OR_AXES: 3}.get(
            parameter.kind)
        if vector and self.rng.random() < 0.5:
            values = ", ".join(f"{self.number(parameter, dimension):g}" for _ in range(vector))
            return f"[{values}]{unit}"
        return f"{self.number(parameter, dimension):g}{unit}"

    def interpolator(self, space: str, axes: int) -> str:
        kind = cat.INTERPOLATORS.get(self.rng.choice(cat.INTERPOLATORS.names()))
        arguments = []
        for parameter in kind.parameters:
            if parameter.spaces is not None and space not in parameter.spaces:
                continue
            if parameter.required or self.rng.random() < 0.3:
                vector_ok = space in (cat.JOINT_SPACE, cat.JOINT_VELOCITY_SPACE)
                value = self.value(parameter, space, axes if vector_ok else 1)
                if not vector_ok and value.startswith("["):
                    value = value[1:value.index("]")].split(",")[0] + value[value.index("]") + 1:]
                arguments.append(f"{parameter.name} = {value}")
        return f"{kind.name}({', '.join(arguments)})" if kind.parameters else kind.name

    def feedback(self, space: str, axes: int) -> str:
        kind = cat.FEEDBACKS.get(self.rng.choice(cat.FEEDBACKS.names()))
        arguments = [f"{p.name} = {self.value(p, space, axes)}" for p in kind.parameters
                     if self.rng.random() < 0.7]
        return f"{kind.name}({', '.join(arguments)})"

    def joint_target(self) -> str:
        group = self.scene.group
        low = np.where(np.isfinite(group.lower), group.lower, -math.pi)
        high = np.where(np.isfinite(group.upper), group.upper, math.pi)
        values = [self.rng.uniform(a, b) for a, b in zip(low, high)]
        unit = "rad" if self.scene.revolute else "m"
        return "[" + ", ".join(f"{v:.3f}" for v in values) + f"] {unit}"

    def body_target(self, space: str) -> str:
        body = self.rng.choice(self.scene.bodies)
        choice = self.rng.random()
        if choice < 0.3:
            return body
        if choice < 0.7 and space != cat.ORIENTATION_SPACE:
            offset = ", ".join(f"{self.rng.uniform(-0.3, 0.3):.3f}" for _ in range(3))
            return f"{body} offset [{offset}] m"
        if choice < 0.85:
            return "current"
        position = ", ".join(f"{self.rng.uniform(-1, 1):.3f}" for _ in range(3))
        rpy = ", ".join(f"{self.rng.uniform(-180, 180):.1f}" for _ in range(3))
        parts = {cat.POSITION_SPACE: [f"position = [{position}] m"],
                 cat.ORIENTATION_SPACE: [f"rpy = [{rpy}] deg"]}.get(
            space, [f"position = [{position}] m", f"rpy = [{rpy}] deg"])
        return f"pose({', '.join(parts)})"

    def force_task(self, name: str) -> tuple[str, str, str]:
        """A body_force task on a sensed body, and a force target for it."""
        rng = self.rng
        axes = rng.sample("xyz", rng.randint(1, 3))
        lines = [f"    gain = {rng.uniform(0.0002, 0.002):.4f} (m/s)/N",
                 f"    max_velocity = {rng.uniform(0.005, 0.05):.3f} m/s",
                 f"    axes = [{', '.join(axes)}]", f"    priority = {rng.randint(0, 2)}"]
        target = "[" + ", ".join(f"{rng.uniform(-10, 10):.1f}" for _ in range(3)) + "] N"
        body = "\n".join(lines)
        return (f"task {name}: body_force({rng.choice(self.scene.sensed)}) {{\n{body}\n}}",
                target, "body_force")

    def task(self, name: str) -> tuple[str, str, str]:
        """A task declaration, and a target assignment for it (``""`` for none)."""
        names = [n for n in cat.TASKS.names() if n != "body_force"]
        if self.scene.sensed and self.rng.random() < 0.2:
            return self.force_task(name)
        kind = cat.TASKS.get(self.rng.choice(names))
        joint = kind.subject == cat.JOINT_GROUP
        subject = self.scene.group.name if joint else self.rng.choice(self.scene.tools)
        axes = self.scene.group.dofs if joint else cat.SPACE_AXES[kind.space]
        lines = [f"    interpolator = {self.interpolator(kind.space, axes)}",
                 f"    feedback = {self.feedback(kind.space, axes)}",
                 f"    priority = {self.rng.randint(0, 2)}"]
        for parameter in kind.parameters:
            if parameter.name not in SKIPPED and self.rng.random() < 0.4:
                lines.append(f"    {parameter.name} = {self.value(parameter, kind.space, axes)}")
        if kind.space == cat.JOINT_SPACE:
            target = self.joint_target()
        elif kind.space in (cat.JOINT_VELOCITY_SPACE, cat.TWIST_SPACE):
            target = ""
        elif kind.space == cat.GAZE_SPACE:
            target = self.rng.choice(self.scene.bodies)
        else:
            target = self.body_target(kind.space)
        body = "\n".join(lines)
        return f"task {name}: {kind.name}({subject}) {{\n{body}\n}}", target, kind.name

    def constraints(self) -> list[str]:
        group, tool = self.scene.group.name, self.rng.choice(self.scene.tools)
        out = []
        for kind_name, subject in (("joint_kinematic", group), ("body_velocity", tool)):
            kind = cat.CONSTRAINTS.get(kind_name)
            axes = self.scene.group.dofs if subject == group else 3
            lines = [f"    {p.name} = {self.value(p, kind.space, axes)}"
                     for p in kind.parameters
                     if p.name not in SKIPPED and self.rng.random() < 0.7]
            out.append(f"constraint c_{kind_name}: {kind_name}({subject}) {{\n"
                       + "\n".join(lines) + "\n}")
        return out

    def variables(self) -> list[str]:
        """Three vars: a count, a length measured at the start, a position assigned
        later."""
        tool, body = self.rng.choice(self.scene.tools), self.rng.choice(self.scene.bodies)
        return ["var laps: count = 0", f"var reach: length = distance({tool}, {body})",
                "var seen: position"]

    def assignments(self) -> list[str]:
        """Assignments of the vars, with arithmetic over measures and constants."""
        rng = self.rng
        tool, body = rng.choice(self.scene.tools), rng.choice(self.scene.bodies)
        found = ["laps = laps + 1",
                 f"reach = distance({tool}, {body}) * {rng.uniform(0.5, 2):.2f} - "
                 f"{rng.uniform(0, 5):.1f} mm",
                 f"seen = {tool}.position", 'log "lap {laps}, reach {reach}"']
        if self.scene.sensed:
            found.append(f"reach = reach + force({rng.choice(self.scene.sensed)}).z "
                         f"* {rng.uniform(0.001, 0.01):.4f} (m/s)/N * 1 s")
        return rng.sample(found, rng.randint(1, len(found)))

    def value_condition(self) -> str:
        """A condition on a var, a position or a force."""
        rng = self.rng
        choices = [f"laps >= {rng.randint(1, 3)}", f"reach < {rng.uniform(0.05, 1):.2f} m",
                   f"{rng.choice(self.scene.tools)}.position.z > {rng.uniform(0, 1.5):.2f} m"]
        if self.scene.sensed:
            body = rng.choice(self.scene.sensed)
            choices += [f"force({body}).z < -{rng.uniform(0.5, 5):.1f} N",
                        f"torque({body}) > {rng.uniform(0.1, 2):.1f} Nm",
                        f"contact({body}, {rng.choice(self.scene.bodies)})"]
        return rng.choice(choices)

    def mission(self) -> str:
        """A mission: three vars, two constraints, two to four tasks, two to five states
        with random enables, targets, assignments and exits, and the finals ``done`` and
        ``failed``."""
        rng = self.rng
        tasks = [self.task(f"t{i}") for i in range(rng.randint(2, 4))]
        states = [f"s{i}" for i in range(rng.randint(2, 5))]
        text = [f"mission generated\n\nworld \"{self.scene.path}\"\n"]
        text.append("\n".join(self.variables()))
        text += self.constraints()
        text += [declaration for declaration, _, _ in tasks]
        for index, state in enumerate(states):
            chosen = rng.sample(range(len(tasks)), rng.randint(1, len(tasks)))
            enter = [f"        enable {', '.join(f't{i}' for i in chosen)}"]
            enter += [f"        t{i}.target = {tasks[i][1]}" for i in chosen if tasks[i][1]]
            enter += [f"        {line}" for line in self.assignments()]
            clauses = []
            for _ in range(rng.randint(1, 3)):
                task = rng.choice(chosen)
                condition = rng.choice([
                    f"t{task}.reached", f"elapsed > {rng.uniform(0.1, 1.0):.2f} s",
                    f"t{task}.{'position_error' if tasks[task][2] == 'body_pose' else 'error'}"
                    f" < {rng.uniform(0.001, 0.1):.3f}",
                    f"distance({rng.choice(self.scene.tools)}, "
                    f"{rng.choice(self.scene.bodies)}) < {rng.uniform(0.01, 0.5):.2f} m",
                    self.value_condition()])
                goal = rng.choice(states[:index] + states[index + 1:] + ["done", "failed"])
                clauses.append(f"    when {condition} -> {goal}")
            clauses.append("    when elapsed > 2 s -> failed")
            text.append(f"state {state} {{\n    enter {{\n" + "\n".join(enter) + "\n    }\n"
                        + "\n".join(clauses) + "\n}")
        text.append("when controller.failed -> failed\n\nfinal done\nfinal failed: failure\n")
        return "\n\n".join(text)
