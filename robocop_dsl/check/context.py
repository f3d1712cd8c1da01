"""What every check needs: the source to quote, the world's names, the mission's symbols.

:class:`WorldNames` answers the questions checks ask of a world (bodies, joint groups,
limits, controllers) and answers "unknown" for everything when the world did not load,
so the mission's own checks still run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..diagnostics import Diagnostic, SourceFile, Span, did_you_mean
from ..lang import ast
from ..lang.follow_on import Broken
from ..lang.units import ANGLE, LENGTH

_ROTATIONAL = ("revolute", "continuous")
MEASURES = {"elapsed": "the time spent in the state", "time": "the mission time"}
"""The words of measures that conditions and expressions read without brackets."""
NAMED = ("task", "constraint", "task or constraint", "body", "joint group", "event", "state",
         "behavior")


@dataclass(frozen=True)
class Joints:
    """A joint group (or a single joint) as checks see it; limits in SI."""

    name: str
    dofs: int
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    max_velocity: tuple[float, ...]
    joint_types: tuple[str, ...]

    @property
    def position_dimensions(self) -> tuple[str, ...]:
        """Dimensions a position of these joints may be written in."""
        moving = [t for t in self.joint_types if t not in ("fixed", "mimic")]
        if moving and all(t in _ROTATIONAL for t in moving):
            return (ANGLE,)
        if moving and all(t == "prismatic" for t in moving):
            return (LENGTH,)
        return (ANGLE, LENGTH)


class WorldNames:
    """A world's names and limits, or nothing known when ``world`` is ``None``."""

    def __init__(self, world=None):
        self.world = world
        self._joints: dict[str, Joints | None] = {}

    @property
    def known(self) -> bool:
        return self.world is not None

    def body_names(self) -> list[str]:
        return list(self.world.body_names()) if self.world else []

    def sensed_bodies(self) -> list[str]:
        """The bodies a ``force_sensor`` processor measures."""
        if self.world is None:
            return []
        return [p.options.get("body") for p in self.world.processors.values()
                if p.type == "force_sensor"]

    @property
    def simulated(self) -> bool:
        """Whether a physics driver (``mujoco``) runs the world."""
        return self.world is not None and any(
            p.type == "mujoco" for p in self.world.processors.values())

    @property
    def measures_wrenches(self) -> bool:
        """Whether a driver of the world can measure wrenches (``mujoco`` from its
        contacts, ``loopback`` from the robot); ``simulated`` measures none."""
        return self.world is not None and any(
            p.type in ("mujoco", "loopback") for p in self.world.processors.values())

    def free_bodies(self) -> list[str]:
        """The bodies physics moves (the roots of ``free: true`` models)."""
        return list(self.world.free_bodies()) if self.world else []

    def has_body(self, name: str) -> bool:
        return self.world is None or self.world.has_body(name)

    def joint_names(self) -> list[str]:
        if self.world is None:
            return []
        return list(self.world.group_names()) + list(self.world.joint_names())

    def joints(self, name: str) -> Joints | None:
        """The joint group or joint ``name``; ``None`` when unknown or no world (looked up
        once per name)."""
        if name not in self._joints:
            self._joints[name] = self._looked_up(name)
        return self._joints[name]

    def _looked_up(self, name: str) -> Joints | None:
        if self.world is None:
            return None
        if self.world.has_group(name):
            infos = self.world.moving_joints(name)
            return Joints(name, sum(i.dofs for i in infos), _stacked(infos, "lower"),
                          _stacked(infos, "upper"), _stacked(infos, "max_velocity"),
                          tuple(i.type for i in infos))
        if name in self.world.joint_names():
            joint = self.world.joint(name)
            return Joints(name, joint.dofs, _floats(joint.lower), _floats(joint.upper),
                          _floats(joint.max_velocity), (joint.type,))
        return None

    def has_joints(self, name: str) -> bool:
        return self.world is None or self.joints(name) is not None

    def controller_names(self) -> list[str]:
        return list(self.world.controller_names()) if self.world else []

    def controller_group(self, name: str) -> str | None:
        """The joint group a ``qp_controller`` processor drives."""
        return self.world.processors[name].options.get("joint_group")

    def controller_time_step(self, name: str) -> float:
        """A controller's period [s] (``inf`` when it gives none)."""
        step = self.world.processors[name].options.get("time_step")
        return float(step) if isinstance(step, (int, float)) else math.inf

    def controller_joints(self, name: str) -> set:
        """The moving joints a controller drives (empty when its group is unknown)."""
        group = self.controller_group(name)
        return self.group_joints(group) if isinstance(group, str) else set()

    def group_joints(self, name: str) -> set:
        """The moving joints of a joint group or joint (empty when unknown)."""
        if self.world is None:
            return set()
        if self.world.has_group(name) or name in self.world.joint_names():
            return {i.name for i in self.world.moving_joints(name)}
        return set()

    def body_joints(self, body: str) -> set:
        """The moving joints between the world and ``body`` (a mimic joint counts as the
        joint it follows)."""
        if self.world is None or not self.world.has_body(body):
            return set()
        joints = set()
        info = self.world.body(body)
        while info.parent is not None:
            joint = self.world.joint(info.joint)
            if joint.dofs:
                joints.add(joint.name)
            elif joint.mimic:
                joints.add(joint.mimic)
            info = self.world.body(info.parent)
        return joints

    def hangs_from(self, body: str, ancestor: str, moved: dict | None = None) -> bool:
        """Whether ``ancestor`` is on the chain from ``body`` to the world, as the world
        file places them, each body of ``moved`` hanging from the parent it gives."""
        moved = moved or {}
        name, seen = body, {body}
        while self.world is not None and self.world.has_body(name):
            parent = moved[name] if name in moved else self.world.body(name).parent
            if parent is None or parent in seen:
                return False
            if parent == ancestor:
                return True
            seen.add(parent)
            name = parent
        return False


def _floats(values) -> tuple[float, ...]:
    return tuple(float(v) for v in values)


def _stacked(joints, limit: str) -> tuple[float, ...]:
    """One ``limit`` (``lower``, ``upper``, ``max_velocity``) per dof of ``joints``."""
    return tuple(float(v) for joint in joints for v in getattr(joint, limit))


@dataclass
class Symbols:
    """The mission's own names, first declaration of each."""

    tasks: dict[str, ast.TaskDecl] = field(default_factory=dict)
    constraints: dict[str, ast.ConstraintDecl] = field(default_factory=dict)
    states: dict[str, ast.StateDecl] = field(default_factory=dict)
    events: set[str] = field(default_factory=set)

    def controlled(self) -> list[str]:
        """Names that ``enable``/``disable`` accept."""
        return list(self.tasks) + list(self.constraints)


class CheckContext:
    """Collects diagnostics for one mission file and the files it imports.

    ``notes`` name the behaviour instances being checked (each diagnostic gets them);
    ``generic`` holds names that stand for any value of their kind: the parameters of a
    behaviour checked on its own, and constants whose value is wrong (reported once, at
    their ``let``). ``constants`` are the ``let`` declarations by name. ``scope`` is the
    chain of machines (local state name to declaration, innermost first) whose states
    the clause being checked may read, and ``owner`` the state whose machine is being
    checked (``None`` for the mission's or a behaviour checked on its own);
    ``all_states`` every state name of the mission at any depth, with the state
    whose machine holds it; ``numbers`` and ``vectors`` the constants that hold a
    number or a vector. ``expanded`` is the mission with constants and behaviour
    instances bound, once checked, and ``unused`` the behaviours that no instance exposes (name and machine, checked with
    generic bindings); ``imports_parsed`` is false when an imported file has a syntax
    error, and ``broken`` the statements of each such file that did not parse (by its
    path as shown). ``declared`` holds, by constraint name, the value and numbers [SI] its
    declaration gives to each parameter that must stay ordered (``min_position``...).
    ``variables`` are the vars the machine being checked sees (name to
    :class:`~.variables.VarInfo`), ``mission_variables`` those the mission declares at
    its top, which every behaviour sees; ``all_variables`` the names of every var
    declared anywhere; ``in_target`` is true while an action's target is checked (the
    one value that may hold vars). ``instance_notes`` are the notes naming behaviour
    instances, written so far (see :func:`~.expand.instance_note`).
    """

    def __init__(self, source: SourceFile, world=None):
        self.source = source
        self.sources = {source.path: source}
        self.world = WorldNames(world)
        self.symbols = Symbols()
        self.diagnostics: list[Diagnostic] = []
        self.notes: tuple[str, ...] = ()
        self.generic: frozenset[str] = frozenset()
        self.constants: dict[str, ast.Let] = {}
        self.scope: tuple = ()
        self.owner: str | None = None
        self.all_states: dict[str, str | None] = {}
        self.numbers: list[str] = []
        self.vectors: list[str] = []
        self.expanded = ast.Mission()
        self.unused: list[tuple[ast.Name, ast.Machine]] = []
        self.imports_parsed = True
        self.broken: dict[str, Broken] = {}
        self.declared: dict[str, dict[str, tuple]] = {}
        self.variables: dict = {}
        self.mission_variables: dict = {}
        self.all_variables: set[str] = set()
        self.in_target = False
        self.instance_notes: dict[int, tuple[ast.Instance, str]] = {}

    def source_of(self, span: Span | None) -> SourceFile:
        """The file a span is in."""
        if span is not None and span.file is not None:
            return self.sources.get(span.file, self.source)
        return self.source

    def where(self, span: Span) -> str:
        """``line N`` in the file being checked, ``FILE:LINE`` in another."""
        if span.file is None or span.file == self.source.path:
            return f"line {span.line}"
        return f"{span.file}:{span.line}"

    def opaque(self, value) -> bool:
        """Whether ``value`` stands for any value (a name of ``generic``)."""
        return isinstance(value, ast.Reference) and value.name.text in self.generic

    def error(self, code: str, message: str, span: Span | None, hint: str | None = None):
        self.diagnostics.append(self.source_of(span).error(code, message, _located(span),
                                                           hint, notes=self.notes))

    def warning(self, code: str, message: str, span: Span | None, hint: str | None = None):
        self.diagnostics.append(self.source_of(span).warning(code, message, _located(span),
                                                             hint, notes=self.notes))

    def unknown(self, code: str, what: str, name: ast.Name, candidates, extra: str = "",
                where: str = ""):
        """``unknown body 'x'`` (then ``where``) with a "did you mean" among
        ``candidates``, else the ``extra`` hint. A constant where a declared name
        (``what``: a task, body, event, state...) is expected is reported as such."""
        let = self.constants.get(name.text)
        if let is not None and what in NAMED:
            self.error("wrong-kind", f"'{name.text}' is a constant, not a {what}", name.span,
                       f"'{name.text}' is declared at {self.where(let.span)}")
            return
        hint = did_you_mean(name.text, candidates) or extra or None
        self.error(code, f"unknown {what} '{name.text}'{where}", name.span, hint)

    def measure_name(self, name: ast.Name, what: str) -> bool:
        """Report a ``what`` (a constant, a var, a parameter) named ``elapsed`` or
        ``time``: conditions and expressions read those words as the measures, so it could
        never be read. True when it was reported."""
        if name.text not in MEASURES:
            return False
        self.error("reserved-name", f"{what} '{name.text}' can never be read: "
                   f"'{name.text}' is {MEASURES[name.text]} wherever a value is read",
                   name.span, "give it another name")
        return True


def _located(span: Span | None) -> Span | None:
    if span is None or span.line <= 0:
        return None
    return span


def finite(value: float) -> bool:
    return math.isfinite(value)
