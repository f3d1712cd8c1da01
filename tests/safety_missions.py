"""Missions written to break the safety layer, and a check of its promises from the log.

:func:`safety_case` writes, for a robot and a seed, the text of a mission that an
unlucky user or an attacker could write (limits above and below the URDF's, collision
constraints with tight margins, targets under the work surface, out of reach or at the
joint limits, wild gains and interpolators) and the :class:`Limits` every logged cycle
must keep. :func:`check_run` recomputes the promises from the run's log with tools of
its own: joint positions and commands from ``timeseries.parquet``, distances with coal
on pinocchio's collision model built from the URDF (meshes as meshes), events from
``events.jsonl``. Deterministic for a seed, so a failure is reproduced by its seed.
"""

from __future__ import annotations

import json
import math
import random
from dataclasses import asdict, dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import pinocchio as pin
import pyarrow.parquet as pq

from robocop_dsl.world import load_world
from robocop_dsl.world.collisions import checked_pairs

POSITION_SLACK = 1e-3
"""Allowed excess past a position limit [rad or m]."""
CLEARANCE_SLACK = 1e-3
"""Allowed approach below a constraint's ``min_distance`` [m]."""
RELATIVE_SLACK = 1e-6
"""Allowed relative excess over a velocity or acceleration limit [-]."""
ACCELERATION_SLACK = 1e-4
"""Allowed absolute excess over an acceleration limit [rad/s^2 or m/s^2]."""
COUNTED_EVENTS = ("qp_failure", "constraint_relaxed", "solver_budget", "fault")


@dataclass(frozen=True)
class Robot:
    """What the generated missions name in a world."""

    world: str
    kinematic_groups: tuple[str, ...]
    """Groups a ``joint_kinematic`` constraint may limit."""
    task_groups: tuple[str, ...]
    """Groups a ``joint_position`` task may drive."""
    tools: tuple[str, ...]
    collision_sets: tuple[tuple[str, str], ...]
    surface: float
    """Height of the work surface [m]."""
    area: tuple[tuple[float, float], tuple[float, float]]
    """Low and high corners (x, y) of the work surface [m]."""
    anchors: tuple[str, ...]
    """Bodies just above the surface, for targets offset from them."""
    center: str
    """A body at the robot's shoulders, for targets out of reach."""


ROBOTS = {
    "bazar": Robot("bazar/sophia.yaml", ("bazar_upper_joints", "bazar_arms"),
                   ("bazar_left_arm", "bazar_right_arm", "bazar_arms"),
                   ("bazar_left_hankamp_tool_object_side",
                    "bazar_right_hankamp_tool_object_side"),
                   (("bazar_arms", "workbench"), ("bazar_left_arm", "bazar_right_arm")),
                   0.74, ((0.4, -0.6), (1.0, 0.6)), ("pickup_point", "drop_point", "part_body"),
                   "bazar_shoulders"),
    "panda": Robot("panda/panda_on_table.yaml", ("panda_arm",), ("panda_arm",),
                   ("panda_hand", "panda_hand_tcp"),
                   (("panda_arm", "table"), ("panda_arm", "panda_arm")),
                   0.75, ((-0.1, -0.5), (0.7, 0.5)), ("target_point",), "panda_link1"),
}


@dataclass(frozen=True)
class CollisionLimit:
    """A ``collision_avoidance`` constraint: its two sets and ``min_distance`` [m]."""

    name: str
    first: str
    other: str
    min_distance: float


@dataclass(frozen=True)
class Limits:
    """What every cycle of a run in ``world`` must keep, per logged joint (in log
    order) and per collision constraint. Positions [rad or m], velocities [rad/s or m/s],
    accelerations [rad/s^2 or m/s^2]; ``inf`` where unlimited."""

    world: str
    joints: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    max_velocity: tuple[float, ...]
    max_acceleration: tuple[float, ...]
    collisions: tuple[CollisionLimit, ...]


@dataclass(frozen=True)
class SafetyCase:
    """A generated mission and the limits its run must keep."""

    robot: str
    seed: int
    text: str
    limits: Limits

    @property
    def name(self) -> str:
        return f"safety_{self.robot}_{self.seed}"

    @property
    def handles_failure(self) -> bool:
        """Whether the mission has a ``controller.failed`` clause."""
        return "when controller.failed" in self.text

    def fault_expected(self, figures: RunFigures) -> bool:
        """Whether a ``fault`` outcome is the mission's due: a cycle the controller had
        to relax (or answer with the braking QP), and no clause to handle it."""
        announced = figures.events["constraint_relaxed"] + figures.events["solver_budget"]
        return bool(announced) and not self.handles_failure

    def write(self, folder: str | Path) -> Path:
        """Write ``NAME.mission`` and ``NAME.limits.json`` to ``folder``; return the
        mission's path."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{self.name}.mission"
        path.write_text(self.text, encoding="utf-8")
        (folder / f"{self.name}.limits.json").write_text(
            json.dumps(asdict(self.limits), indent=1), encoding="utf-8")
        return path


@lru_cache(maxsize=4)
def world_of(path: str):
    """The world file ``path``, loaded once per process."""
    return load_world(path)


def _log_uniform(rng: random.Random, low: float, high: float) -> float:
    return float(f"{math.exp(rng.uniform(math.log(low), math.log(high))):.4g}")


def _vector(values, unit: str) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + f"] {unit}"


class _Writer:
    """Writes one mission for a robot and a seed; :meth:`case` gives it."""

    def __init__(self, robot: str, seed: int):
        self.robot, self.seed = robot, seed
        self.scene = ROBOTS[robot]
        self.world = world_of(self.scene.world)
        self.rng = random.Random(f"{robot}:{seed}")

    def per_dof(self, dofs: int, low: float, high: float, unit: str) -> tuple[str, np.ndarray]:
        """One random value or one per dof, log-uniform in [low, high]: as written in
        ``unit`` and per dof."""
        if self.rng.random() < 0.5:
            value = _log_uniform(self.rng, low, high)
            return f"{value:g} {unit}", np.full(dofs, value)
        values = np.array([_log_uniform(self.rng, low, high) for _ in range(dofs)])
        return _vector(values, unit), values

    def fractions(self, dofs: int) -> np.ndarray:
        """Per dof, how much of the room between the start and a URDF limit a narrowed
        position limit keeps [-]."""
        return np.array([self.rng.uniform(0.15, 1.0) for _ in range(dofs)])

    def kinematic(self) -> tuple[str, dict]:
        """A ``joint_kinematic`` declaration and its limits by joint: (lower, upper,
        max_velocity, max_acceleration)."""
        rng = self.rng
        name = rng.choice(self.scene.kinematic_groups)
        group = self.world.joint_group(name)
        velocity_text, velocity = self.per_dof(group.dofs, 0.2, 6.0, "rad/s")
        acceleration_text, acceleration = self.per_dof(group.dofs, 0.5, 50.0, "rad/s^2")
        lines = [f"    max_velocity = {velocity_text}",
                 f"    max_acceleration = {acceleration_text}"]
        lower, upper = group.lower.copy(), group.upper.copy()
        start = self.world.initial_configuration()[group.q_indices]
        if rng.random() < 0.35:
            lower = np.round(start - (start - group.lower) * self.fractions(group.dofs), 4)
            lines.append(f"    min_position = {_vector(lower, 'rad')}")
        if rng.random() < 0.35:
            upper = np.round(start + (group.upper - start) * self.fractions(group.dofs), 4)
            lines.append(f"    max_position = {_vector(upper, 'rad')}")
        limits = {joint: values for joint, *values in
                  zip(group.joints, lower, upper, velocity, acceleration)}
        text = f"constraint limits: joint_kinematic({name}) {{\n" + "\n".join(lines) + "\n}"
        return text, limits

    def collisions(self) -> tuple[list[str], list[CollisionLimit]]:
        """One to all ``collision_avoidance`` constraints of the robot's sets."""
        rng, sets = self.rng, self.scene.collision_sets
        chosen = [s for s in sets if rng.random() < 0.85] or [rng.choice(sets)]
        texts, limits = [], []
        for index, (first, other) in enumerate(chosen):
            min_distance = round(rng.uniform(0.005, 0.05), 4)
            influence = round(min_distance + rng.uniform(0.02, 0.15), 4)
            damping = _log_uniform(rng, 0.5, 10.0)
            texts.append(f"constraint clear_{index}: collision_avoidance({first}, {other}) {{\n"
                         f"    min_distance = {min_distance:g} m\n"
                         f"    influence = {influence:g} m\n"
                         f"    damping = {damping:g}\n}}")
            limits.append(CollisionLimit(f"clear_{index}", first, other, min_distance))
        return texts, limits

    def body_velocity(self) -> list[str]:
        """Sometimes a ``body_velocity`` bound on a tool: a speed or one per axis."""
        rng = self.rng
        if rng.random() >= 0.3:
            return []
        lines = []
        if rng.random() < 0.8:
            lines.append(f"    max_linear = {_norm_or_axes(rng, 0.1, 2.0, 'm/s')}")
        if not lines or rng.random() < 0.5:
            lines.append(f"    max_angular = {_norm_or_axes(rng, 0.3, 5.0, 'rad/s')}")
        tool = rng.choice(self.scene.tools)
        return [f"constraint tool_speed: body_velocity({tool}) {{\n" + "\n".join(lines) + "\n}"]

    def task(self, name: str) -> tuple[str, str, str]:
        """A task declaration, its type and its subject."""
        rng = self.rng
        kind = rng.choices(("body_pose", "body_position", "joint_position"), (4, 2.5, 3.5))[0]
        joint = kind == "joint_position"
        subject = rng.choice(self.scene.task_groups if joint else self.scene.tools)
        if rng.random() < 0.4:
            interpolator = "none"
        elif joint:
            interpolator = (f"otg(max_velocity = {_log_uniform(rng, 0.5, 6.0):g} rad/s, "
                            f"max_acceleration = {_log_uniform(rng, 0.5, 60.0):g} rad/s^2)")
        else:
            interpolator = (f"otg(max_velocity = {_log_uniform(rng, 0.1, 3.0):g} m/s, "
                            f"max_acceleration = {_log_uniform(rng, 0.5, 20.0):g} m/s^2)")
        text = (f"task {name}: {kind}({subject}) {{\n"
                f"    interpolator = {interpolator}\n"
                f"    feedback = proportional(gain = {_log_uniform(rng, 1.0, 50.0):g})\n"
                f"    priority = {rng.randint(0, 1)}\n}}")
        return text, kind, subject

    def target(self, kind: str, subject: str) -> str:
        """A target that the safety layer must refuse to reach in full: joints within 5 %
        of their limits, a point under the surface, out of reach, or through a body."""
        rng = self.rng
        if kind == "joint_position":
            group = self.world.joint_group(subject)
            span = group.upper - group.lower
            near = [rng.uniform(0.0, 0.05) * s for s in span]
            values = [lo + n if rng.random() < 0.5 else hi - n
                      for lo, hi, n in zip(group.lower, group.upper, near)]
            return _vector(np.clip(np.round(values, 4), group.lower, group.upper), "rad")
        choice = rng.random()
        if choice < 0.25:
            anchor = rng.choice(self.scene.anchors + self.scene.tools)
            offset = [rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-40, -2)]
            return f"{anchor} offset {_vector(offset, 'cm')}"
        if choice < 0.4:
            center = self.world.body_pose(self.scene.center,
                                          self.world.initial_configuration()).translation
            direction = np.array([rng.gauss(0, 1) for _ in range(3)])
            point = center + rng.uniform(1.2, 2.5) * direction / np.linalg.norm(direction)
        else:
            (x0, y0), (x1, y1) = self.scene.area
            point = [rng.uniform(x0, x1), rng.uniform(y0, y1),
                     self.scene.surface - rng.uniform(0.02, 0.3)]
        if kind == "body_position":
            return _vector(point, "m")
        rpy = [180, 0, 0] if rng.random() < 0.7 else [rng.uniform(-180, 180) for _ in range(3)]
        return f"pose(position = {_vector(point, 'm')}, rpy = {_vector(rpy, 'deg')})"

    def states(self, tasks: list) -> list[str]:
        """One to four states, each ending the run at 1 to 4 s of mission time by a
        timeout, chained by ``reached`` or ``elapsed`` at planned times."""
        rng = self.rng
        count = rng.randint(1, 4)
        weights = [rng.uniform(0.5, 1.5) for _ in range(count)]
        total = rng.uniform(1.0, 4.0)
        texts, begin = [], 0.0
        for index, weight in enumerate(weights):
            chosen = rng.sample(range(len(tasks)), rng.randint(1, min(2, len(tasks))))
            enter = [f"        enable {', '.join(f't{i}' for i in chosen)}"]
            enter += [f"        t{i}.target = {self.target(*tasks[i][1:])}" for i in chosen]
            clauses = []
            if index + 1 < count:
                planned = round(total * weight / sum(weights), 2)
                condition = rng.choice((f"t{rng.choice(chosen)}.reached",
                                        f"elapsed > {planned:g} s",
                                        f"t{rng.choice(chosen)}.reached or "
                                        f"elapsed > {planned:g} s"))
                clauses.append(f"    when {condition} -> s{index + 1}")
            clauses.append(f"    when elapsed > {round(total - begin, 2):g} s -> done")
            begin += total * weight / sum(weights)
            texts.append(f"state s{index} {{\n    enter {{\n" + "\n".join(enter)
                         + "\n    }\n" + "\n".join(clauses) + "\n}")
        return texts

    def case(self) -> SafetyCase:
        """The mission: its limits and collision constraints, maybe a tool speed bound,
        one to three tasks, its states, maybe a ``controller.failed`` handler."""
        kinematic, mission_limits = self.kinematic()
        collisions, collision_limits = self.collisions()
        tasks = [self.task(f"t{i}") for i in range(self.rng.randint(1, 3))]
        parts = [f'mission {self.robot}_{self.seed} "A randomised safety case."\n\n'
                 f'world "{self.scene.world}"', kinematic, *collisions, *self.body_velocity(),
                 *(text for text, _, _ in tasks), *self.states(tasks)]
        finals = "final done"
        if self.rng.random() < 0.5:
            goal = "failed" if self.rng.random() < 0.7 else "done"
            parts.append(f"when controller.failed -> {goal}")
            finals += "\nfinal failed: failure" if goal == "failed" else ""
        text = "\n\n".join(parts + [finals]) + "\n"
        return SafetyCase(self.robot, self.seed, text,
                          self.limits(mission_limits, tuple(collision_limits)))

    def limits(self, mission: dict, collisions: tuple) -> Limits:
        """The limits of the joints the controller drives (the logged ones): the
        URDF's and the mission's, whichever is stricter; for accelerations, the
        world's and the mission's."""
        controller = self.world.processors[self.world.controller_names()[0]]
        group = self.world.joint_group(controller.options["joint_group"])
        rows = []
        for index, joint in enumerate(group.joints):
            own = (group.lower[index], group.upper[index], group.max_velocity[index],
                   group.max_acceleration[index])
            lower, upper, velocity, acceleration = mission.get(joint, own)
            rows.append((max(own[0], lower), min(own[1], upper), min(own[2], velocity),
                         min(own[3], acceleration)))
        columns = [tuple(float(v) for v in column) for column in zip(*rows)]
        return Limits(self.scene.world, tuple(group.joints), *columns, collisions)


def _norm_or_axes(rng: random.Random, low: float, high: float, unit: str) -> str:
    if rng.random() < 0.5:
        return f"{_log_uniform(rng, low, high):g} {unit}"
    return _vector([_log_uniform(rng, low, high) for _ in range(3)], unit)


def safety_case(robot: str, seed: int) -> SafetyCase:
    """The mission of ``robot`` (``bazar`` or ``panda``) for ``seed``, and its limits."""
    return _Writer(robot, seed).case()


@dataclass
class RunFigures:
    """What a run's log says of the promises. Excesses are zero when every sample
    keeps its limit."""

    outcome: str
    cycles: int
    events: dict[str, int]
    """Events of :data:`COUNTED_EVENTS` by kind."""
    compute_ratio: float
    """Largest cycle compute time over the median one [-]."""
    position_excess: float = 0.0
    """Worst excess past a position limit [rad or m]."""
    velocity_excess: float = 0.0
    """Worst ``|command| / limit - 1`` [-]."""
    acceleration_excess: float = 0.0
    """Worst ``|acceleration| / limit - 1``, announced relaxations included [-]."""
    clearance_margin: dict[str, float] = field(default_factory=dict)
    """Per collision constraint, smallest distance minus ``min_distance`` [m]."""
    violations: dict[str, int] = field(default_factory=dict)
    """Samples breaking a promise, by kind: ``position``, ``clearance``, ``velocity``,
    ``acceleration`` (over the limit in a cycle with no ``constraint_relaxed``
    event), ``non_finite`` (rows)."""
    worst: dict[str, str] = field(default_factory=dict)
    """By kind of violation, its worst sample: joint or pair, cycle, value and limit."""

    def report(self) -> str:
        """The figures, one per line, and the worst violation of each kind."""
        margins = ", ".join(f"{name} {margin * 1e3:.2f} mm"
                            for name, margin in self.clearance_margin.items())
        lines = [f"outcome {self.outcome} after {self.cycles} cycles",
                 f"position excess {self.position_excess * 1e3:.3f} mrad",
                 f"clearance margins: {margins or 'none'}",
                 f"velocity excess {self.velocity_excess:.3g}, "
                 f"acceleration excess {self.acceleration_excess:.3g} (relative)",
                 f"events {self.events}, compute max/median {self.compute_ratio:.1f}"]
        lines += [f"{kind}: {count} samples, worst {self.worst[kind]}"
                  for kind, count in self.violations.items()]
        return "\n".join(lines)

    def record(self, kind: str, count: int, worst: str) -> None:
        """Note ``count`` samples breaking the promise ``kind``, the worst described."""
        self.violations[kind] = count
        self.worst[kind] = worst


class _Distances:
    """Coal distances of the pairs of a world's collision constraints, on pinocchio's
    collision model built from the URDF.

    Args:
        world: The world.
        sets: The two sets of each collision constraint: :func:`checked_pairs` gives its
            pairs of bodies, every collision element of one against every one of the
            other.
    """

    def __init__(self, world, sets: tuple[tuple[str, str], ...]):
        model = self.model = world.model
        self.data = model.createData()
        self.geometry = pin.buildGeomFromUrdfString(model, world.urdf,
                                                    pin.GeometryType.COLLISION)
        shapes: dict = {}
        for index, obj in enumerate(self.geometry.geometryObjects):
            shapes.setdefault(model.frames[obj.parentFrame].name, []).append(index)
        pairs: dict = {}
        self.names: list[str] = []
        self.members: list[np.ndarray] = []
        """Per constraint, the indices of its pairs."""
        for first, other in sets:
            members = []
            for a, b in checked_pairs(world, first, other):
                for i in shapes[a]:
                    for j in shapes[b]:
                        if (i, j) not in pairs:
                            pairs[i, j] = len(pairs)
                            self.geometry.addCollisionPair(pin.CollisionPair(i, j))
                            self.names.append(f"{a} / {b}")
                        members.append(pairs[i, j])
            self.members.append(np.array(members, dtype=int))
        self.geometry_data = pin.GeometryData(self.geometry)
        self.start = world.initial_configuration()

    def configuration(self, joints: tuple[str, ...], positions: np.ndarray) -> np.ndarray:
        """The world's configuration with ``joints`` at ``positions``, the others at
        the start."""
        q = self.start.copy()
        q[[self.model.joints[self.model.getJointId(j)].idx_q for j in joints]] = positions
        return q

    def __call__(self, q: np.ndarray) -> np.ndarray:
        """Distance of every pair at the world's configuration ``q`` [m]."""
        pin.computeDistances(self.model, self.data, self.geometry, self.geometry_data, q)
        return np.array([result.min_distance for result in self.geometry_data.distanceResults])


@lru_cache(maxsize=8)
def _distances(world: str, sets: tuple[tuple[str, str], ...]) -> _Distances:
    return _Distances(world_of(world), sets)


def _read_events(folder: Path) -> list[dict]:
    events = []
    for line in (folder / "events.jsonl").read_text(encoding="utf-8").splitlines():
        try:
            events.append(json.loads(line))
        except json.JSONDecodeError:
            continue
    return events


def check_run(folder: str | Path, limits: Limits) -> RunFigures:
    """Recompute the promises over every logged cycle of a run, the stop included.

    Args:
        folder: The run's log folder (``--log``).
        limits: What the run must keep (:attr:`SafetyCase.limits`).
    """
    folder = Path(folder)
    table = pq.read_table(folder / "timeseries.parquet")
    series = {name: table.column(name).to_numpy() for name in table.column_names
              if name != "state"}
    events = _read_events(folder)
    q = np.column_stack([series[f"q.{joint}"] for joint in limits.joints])
    command = np.column_stack([series[f"command.{joint}"] for joint in limits.joints])
    cycles, compute = series["cycle"], series["compute_time"]
    end = next((e for e in events if e["kind"] == "end"), {})
    figures = RunFigures(end.get("outcome", "none"), len(cycles),
                         {kind: sum(e["kind"] == kind for e in events)
                          for kind in COUNTED_EVENTS},
                         float(compute.max() / max(np.median(compute), 1e-9)))
    finite = np.isfinite(q).all(axis=1) & np.isfinite(command).all(axis=1)
    if not finite.all():
        figures.record("non_finite", int((~finite).sum()), f"cycle {cycles[np.argmin(finite)]}")
    lower, upper = np.array(limits.lower), np.array(limits.upper)
    excess = np.maximum(lower - q, q - upper)
    figures.position_excess = _worst(
        figures, "position", excess, excess > POSITION_SLACK, np.where(q < lower, lower, upper),
        limits.joints, cycles, q, "rad")
    velocity = np.array(limits.max_velocity)
    relative = np.abs(command) / velocity - 1.0
    figures.velocity_excess = _worst(figures, "velocity", relative, relative > RELATIVE_SLACK,
                                     velocity, limits.joints, cycles, command, "rad/s")
    time = series["time"]
    step = np.diff(time, prepend=time[0] - (time[1] - time[0] if len(time) > 1 else 1.0))
    acceleration = np.diff(command, axis=0, prepend=0.0) / step[:, None]
    limit = np.array(limits.max_acceleration)
    relaxed = np.isin(cycles, [e["cycle"] for e in events if e["kind"] == "constraint_relaxed"])
    over = (np.abs(acceleration) > limit * (1 + RELATIVE_SLACK) + ACCELERATION_SLACK) \
        & ~relaxed[:, None]
    figures.acceleration_excess = _worst(figures, "acceleration", np.abs(acceleration) / limit - 1,
                                         over, limit, limits.joints, cycles, acceleration,
                                         "rad/s^2")
    if limits.collisions:
        _clearances(figures, limits, q, finite, cycles)
    return figures


def _worst(figures: RunFigures, kind: str, excess: np.ndarray, broken: np.ndarray,
           limit: np.ndarray, joints: tuple, cycles: np.ndarray, values: np.ndarray,
           unit: str) -> float:
    """Record the samples of ``kind`` that break their ``limit`` (samples x joints,
    or per joint); return the largest finite excess, zero if none is positive."""
    if broken.any():
        row, column = np.unravel_index(np.argmax(np.where(broken, excess, -np.inf)),
                                       broken.shape)
        bound = np.broadcast_to(limit, broken.shape)[row, column]
        figures.record(kind, int(broken.sum()),
                       f"{joints[column]} at cycle {cycles[row]}: {kind} "
                       f"{values[row, column]:.6g} {unit}, limit {bound:.6g} {unit}")
    return float(max(excess[np.isfinite(excess)].max(initial=0.0), 0.0))


def _clearances(figures: RunFigures, limits: Limits, q: np.ndarray, finite: np.ndarray,
                cycles: np.ndarray) -> None:
    """Smallest distance of each collision constraint over the finite rows of ``q``
    (a row equal to the one before, as when the robot holds, is not measured again)."""
    distances = _distances(limits.world, tuple((limit.first, limit.other)
                                               for limit in limits.collisions))
    table = np.full((len(q), len(distances.names)), np.inf)
    previous = None
    for row in np.flatnonzero(finite):
        if previous is not None and np.array_equal(q[row], q[previous]):
            table[row] = table[previous]
        else:
            table[row] = distances(distances.configuration(limits.joints, q[row]))
        previous = row
    broken, worst = 0, (np.inf, "")
    for limit, members in zip(limits.collisions, distances.members):
        own = table[:, members]
        row, column = np.unravel_index(np.argmin(own), own.shape)
        margin = float(own[row, column]) - limit.min_distance
        figures.clearance_margin[limit.name] = margin
        closer = own.min(axis=1) < limit.min_distance - CLEARANCE_SLACK
        broken += int(closer.sum())
        if closer.any() and margin < worst[0]:
            worst = (margin, f"{distances.names[members[column]]} at cycle {cycles[row]}: "
                             f"{own[row, column] * 1e3:.2f} mm, min_distance "
                             f"{limit.min_distance * 1e3:.1f} mm ({limit.name})")
    if broken:
        figures.record("clearance", broken, worst[1])
