"""World files: ``models:`` with includes and namespaces, ``joint_groups:``, ``initial:``,
``processors:``, flattened into one :class:`WorldDescription` with every name namespaced.

Nothing here reads a URDF or touches pinocchio; :mod:`.assembly` does that.
"""

from __future__ import annotations

import math

import re
from dataclasses import dataclass, field
from pathlib import Path

from ..diagnostics import Diagnostic, DiagnosticError, SourceFile, Span, did_you_mean
from ..sources import URDF, WORLD, refusal
from . import paths
from .yaml_source import YamlList, YamlMap, load_yaml

ROOT = "world"
JOINT_TYPES = ("fixed", "revolute", "continuous", "prismatic", "floating", "planar")
_DURATION = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(us|ms|s)\s*$")
_SECONDS = {"us": 1e-6, "ms": 1e-3, "s": 1.0}
_NUMBER = re.compile(r"[-+]?[0-9]*\.?[0-9]+[eE][-+]?[0-9]+")
_MODEL_KEYS = {"include", "path", "namespace", "joint", "srdf", "free"}
_JOINT_KEYS = {"parent", "type", "axis", "position", "limits", "name"}
_LIMIT_KEYS = {"lower", "upper", "velocity", "effort"}
_TOP_KEYS = {"models", "joint_groups", "initial", "processors", "allowed_collisions",
             "physics"}
_PHYSICS_KEYS = {"gravity", "friction"}
DEFAULT_GRAVITY = (0.0, 0.0, -9.81)
"""[m/s^2], in the world frame."""
DEFAULT_FRICTION = (1.0, 0.005, 0.0001)
"""Sliding [-], torsional [m] and rolling [m] friction coefficients (MuJoCo's order)."""
_PROCESSOR_KEYS = {"type", "options"}


@dataclass(frozen=True)
class Located:
    """Where a piece of a world description was written."""

    source: SourceFile
    span: Span

    def error(self, code: str, message: str, hint: str | None = None) -> Diagnostic:
        return self.source.error(code, message, self.span, hint)


@dataclass
class JointSpec:
    """The joint that attaches a model's root link to its parent body (SI units)."""

    parent: str = ROOT
    type: str = "fixed"
    axis: tuple = (0.0, 0.0, 1.0)
    xyz: tuple = (0.0, 0.0, 0.0)
    rpy: tuple = (0.0, 0.0, 0.0)
    limits: dict = field(default_factory=dict)
    name: str | None = None
    parent_at: Located | None = None


@dataclass
class ModelEntry:
    """One ``path:`` model: a URDF to add with a name prefix and a joint, and the SRDF
    whose ``disable_collisions`` pairs are left out of collision checks. A ``free``
    model hangs on a floating joint whose pose a physics driver measures."""

    urdf: Path
    prefix: str
    joint: JointSpec
    at: Located
    srdf: Path | None = None
    free: bool = False


@dataclass
class Physics:
    """The world's ``physics:``: gravity [m/s^2] and the contacts' friction
    coefficients (sliding [-], torsional [m], rolling [m])."""

    gravity: tuple = DEFAULT_GRAVITY
    friction: tuple = DEFAULT_FRICTION


@dataclass
class GroupEntry:
    name: str
    members: list
    member_spans: list
    at: Located


@dataclass
class ProcessorEntry:
    """A ``processors:`` entry as written (:mod:`.processors` checks it): where its name,
    its ``type:`` value and its ``options:`` key are."""

    name: str
    type: str
    options: YamlMap
    at: Located
    type_at: Located
    options_at: Located


@dataclass
class WorldDescription:
    path: Path
    models: list = field(default_factory=list)
    groups: dict = field(default_factory=dict)
    initial: list = field(default_factory=list)
    processors: dict = field(default_factory=dict)
    allowed_collisions: list = field(default_factory=list)
    """``(body, body, Located)``: pairs never checked for collisions."""
    physics: Physics = field(default_factory=Physics)
    diagnostics: list = field(default_factory=list)


def prefixed(prefix: str, name: str) -> str:
    """``name`` in namespace ``prefix``; the world root keeps its name."""
    if not prefix or name == ROOT:
        return name
    return f"{prefix}_{name}"


def to_seconds(value):
    """``"5ms"`` -> 0.005; any other value is returned unchanged."""
    if isinstance(value, str):
        match = _DURATION.match(value)
        if match:
            return float(match.group(1)) * _SECONDS[match.group(2)]
    return value


def read_description(path: Path) -> WorldDescription:
    """Read a world file and its includes; problems go to ``description.diagnostics``."""
    description = WorldDescription(path=Path(path).resolve())
    _Reader(description).read(description.path, "", ())
    return description


class _Reader:
    def __init__(self, description: WorldDescription):
        self.out = description
        self.set_by: dict = {}
        """What set each processor and the physics: the include chain to its file."""

    def read(self, path: Path, prefix: str, stack: tuple) -> None:
        try:
            source = SourceFile.read(path)
            data = load_yaml(source)
        except DiagnosticError as error:
            self.out.diagnostics.extend(error.diagnostics)
            return
        except OSError as error:
            self.out.diagnostics.append(Diagnostic("world-not-found", f"cannot read world file: {error}",
                                                   str(path), None))
            return
        for key in data:
            if key not in _TOP_KEYS:
                self._unknown_key(source, data, key, _TOP_KEYS)
        stack = stack + (path,)
        self._models(source, data.get("models"), data, prefix, stack)
        self._groups(source, data.get("joint_groups"), data, prefix)
        self._initial(source, data.get("initial"), data, prefix)
        self._processors(source, data.get("processors"), data, stack)
        self._allowed_collisions(source, data.get("allowed_collisions"), data, prefix)
        self._physics(source, data.get("physics"), data, stack)

    def _unknown_key(self, source, mapping: YamlMap, key, allowed) -> None:
        self.out.diagnostics.append(source.error(
            "invalid-entry", f"unknown key '{key}'", mapping.span(key),
            did_you_mean(str(key), allowed) or "expected one of: " + ", ".join(sorted(allowed))))

    def _expect(self, source, value, kind, parent: YamlMap, key) -> bool:
        if isinstance(value, kind):
            return True
        name = "a list" if kind is YamlList else "a mapping"
        self.out.diagnostics.append(source.error("invalid-entry", f"'{key}' must be {name}",
                                                 parent.span(key)))
        return False

    def _models(self, source, models, data, prefix, stack) -> None:
        if models is None:
            return
        if not self._expect(source, models, YamlList, data, "models"):
            return
        for index, entry in enumerate(models):
            at = Located(source, models.span(index))
            if not isinstance(entry, YamlMap):
                self.out.diagnostics.append(at.error(
                    "invalid-entry", "a model must be a mapping with 'include:' or 'path:'"))
                continue
            for key in entry:
                if key not in _MODEL_KEYS:
                    self._unknown_key(source, entry, key, _MODEL_KEYS)
            namespace = entry.get("namespace")
            inner = prefixed(prefix, str(namespace)) if namespace else prefix
            if ("include" in entry) == ("path" in entry):
                self.out.diagnostics.append(at.error(
                    "invalid-entry", "a model needs exactly one of 'include:' and 'path:'"))
            elif "include" in entry:
                self._include(source, entry, inner, stack)
            else:
                self._model(source, entry, prefix, inner)

    def _include(self, source, entry: YamlMap, inner: str, stack) -> None:
        name = str(entry["include"])
        at = Located(source, entry.value_span("include"))
        target = paths.resolve(name, Path(source.path).parent)
        if target is None:
            self.out.diagnostics.append(at.error(
                "world-not-found", f"cannot find included world file '{name}'",
                _looked_in(Path(source.path).parent)))
            return
        refused = refusal(target, WORLD)
        if refused is not None:
            self.out.diagnostics.append(at.error(
                "unreadable-file", f"cannot read included world file '{name}': {refused}",
                "include a world file (.yaml or .yml) of the project"))
            return
        if target in stack:
            chain = " -> ".join(p.name for p in stack[stack.index(target):] + (target,))
            self.out.diagnostics.append(at.error(
                "include-cycle", f"include cycle: {chain}", "remove one of the includes in the cycle"))
            return
        self.read(target, inner, stack)

    def _model(self, source, entry: YamlMap, outer: str, inner: str) -> None:
        name = str(entry["path"])
        at = Located(source, entry.value_span("path"))
        urdf = paths.resolve(name, Path(source.path).parent)
        if urdf is None:
            self.out.diagnostics.append(at.error(
                "urdf-not-found", f"cannot find URDF '{name}'", _looked_in(Path(source.path).parent)))
            return
        refused = refusal(urdf, URDF)
        if refused:
            self.out.diagnostics.append(at.error(
                "unreadable-file", f"cannot read URDF '{name}': {refused}"))
            return
        joint = self._joint(source, entry.get("joint"), entry, outer)
        free = self._free(source, entry, joint)
        srdf = None
        if "srdf" in entry:
            srdf = paths.resolve(str(entry["srdf"]), Path(source.path).parent)
            refused = srdf is not None and refusal(srdf, URDF)
            if srdf is None:
                self.out.diagnostics.append(source.error(
                    "urdf-not-found", f"cannot find SRDF '{entry['srdf']}'",
                    entry.value_span("srdf"), _looked_in(Path(source.path).parent)))
            elif refused:
                self.out.diagnostics.append(source.error(
                    "unreadable-file", f"cannot read SRDF '{entry['srdf']}': {refused}",
                    entry.value_span("srdf")))
                srdf = None
        self.out.models.append(ModelEntry(urdf, inner, joint, at, srdf, free))

    def _free(self, source, entry: YamlMap, joint: JointSpec) -> bool:
        """Whether the model is ``free: true``; its joint becomes a floating one."""
        if "free" not in entry:
            return False
        if not isinstance(entry["free"], bool):
            self.out.diagnostics.append(source.error(
                "invalid-entry", "'free' must be true or false", entry.value_span("free")))
            return False
        if not entry["free"]:
            return False
        if joint.type != "fixed":
            self.out.diagnostics.append(source.error(
                "invalid-entry", f"a free model cannot have a {joint.type} joint",
                entry.value_span("free"), "remove 'type:' from its joint: a free model "
                "floats, its 'position:' is where it starts"))
        joint.type = "floating"
        return True

    def _joint(self, source, data, entry: YamlMap, outer: str) -> JointSpec:
        spec = JointSpec(parent_at=Located(source, entry.value_span("path")))
        if data is None or not self._expect(source, data, YamlMap, entry, "joint"):
            return spec
        for key in data:
            if key not in _JOINT_KEYS:
                self._unknown_key(source, data, key, _JOINT_KEYS)
        if "parent" in data:
            spec.parent = prefixed(outer, str(data["parent"]))
            spec.parent_at = Located(source, data.value_span("parent"))
        if "name" in data:
            spec.name = prefixed(outer, str(data["name"]))
        if "type" in data:
            spec.type = str(data["type"])
            if spec.type not in JOINT_TYPES:
                self.out.diagnostics.append(source.error(
                    "invalid-entry", f"unknown joint type '{spec.type}'", data.value_span("type"),
                    did_you_mean(spec.type, JOINT_TYPES)
                    or "expected one of: " + ", ".join(JOINT_TYPES)))
                spec.type = "fixed"
        if "axis" in data:
            errors = len(self.out.diagnostics)
            spec.axis = self._vector(source, data, "axis", data["axis"], 3)
            if not any(spec.axis) and len(self.out.diagnostics) == errors:
                self.out.diagnostics.append(source.error(
                    "invalid-entry", "'axis' must not be zero", data.span("axis"),
                    "give the direction the joint moves along or about: [0, 0, 1]"))
        position = data.get("position")
        if position is not None and self._expect(source, position, YamlMap, data, "position"):
            for key in position:
                if key not in ("linear", "angular"):
                    self._unknown_key(source, position, key, ("linear", "angular"))
            if "linear" in position:
                spec.xyz = self._vector(source, position, "linear", position["linear"], 3)
            if "angular" in position:
                spec.rpy = self._vector(source, position, "angular", position["angular"], 3)
        limits = data.get("limits")
        if limits is not None and self._expect(source, limits, YamlMap, data, "limits"):
            for key in limits:
                if key not in _LIMIT_KEYS:
                    self._unknown_key(source, limits, key, _LIMIT_KEYS)
                else:
                    spec.limits[key] = self._number(source, limits, key)
        return spec

    def _number(self, source, mapping: YamlMap, key) -> float:
        value = mapping[key]
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value)
        self.out.diagnostics.append(source.error("invalid-entry", f"'{key}' must be a number",
                                                 mapping.span(key)))
        return 0.0

    def _vector(self, source, mapping: YamlMap, key, value, length: int | None) -> tuple:
        """``value`` as a tuple of ``length`` (any, if ``None``) finite numbers; zeros and
        a diagnostic when it is not."""
        ok = isinstance(value, list) and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            for v in value)
        if not ok or (length is not None and len(value) != length):
            size = f"{length} finite numbers" if length is not None else "a list of finite numbers"
            self.out.diagnostics.append(source.error(
                "invalid-entry", f"'{key}' must be {size}", mapping.span(key),
                "YAML reads 1e3 as text: write 1.0e+3" if _exponent_text(value) else None))
            return tuple([0.0] * (length or 0))
        return tuple(float(v) for v in value)

    def _groups(self, source, groups, data, prefix) -> None:
        if groups is None or not self._expect(source, groups, YamlMap, data, "joint_groups"):
            return
        for key, members in groups.items():
            name = prefixed(prefix, str(key))
            at = Located(source, groups.span(key))
            if not isinstance(members, YamlList) or not members:
                self.out.diagnostics.append(at.error(
                    "invalid-entry", f"joint group '{name}' must be a non-empty list of joints or groups"))
                continue
            self.out.groups[name] = GroupEntry(
                name, [prefixed(prefix, str(m)) for m in members],
                [Located(source, members.span(i)) for i in range(len(members))], at)

    def _initial(self, source, initial, data, prefix) -> None:
        if initial is None or not self._expect(source, initial, YamlMap, data, "initial"):
            return
        for key, values in initial.items():
            if isinstance(values, (int, float)) and not isinstance(values, bool):
                values = [values]
            reported = len(self.out.diagnostics)
            vector = self._vector(source, initial, key, values, None)
            if len(self.out.diagnostics) == reported:
                self.out.initial.append((prefixed(prefix, str(key)), vector,
                                         Located(source, initial.span(key))))

    def _wins(self, stack: tuple, key) -> bool:
        """Whether the file at the end of ``stack`` sets ``key`` (a processor's name, or
        ``physics``): when nothing set it yet, or a file it includes did (a file
        overrides its includes; of two files that do not include each other, the
        first read wins)."""
        previous = self.set_by.get(key)
        if previous is not None and previous[:len(stack)] != stack:
            return False
        self.set_by[key] = stack
        return True

    def _processors(self, source, processors, data, stack: tuple) -> None:
        if processors is None or not self._expect(source, processors, YamlMap, data,
                                                  "processors"):
            return
        for name, entry in processors.items():
            at = Located(source, processors.span(name))
            if not isinstance(entry, YamlMap) or "type" not in entry:
                self.out.diagnostics.append(at.error(
                    "invalid-entry", f"processor '{name}' needs a 'type:'",
                    "for example: {type: qp_controller, options: {...}}"))
                continue
            for key in entry:
                if key not in _PROCESSOR_KEYS:
                    self._unknown_key(source, entry, key, _PROCESSOR_KEYS)
            options = entry.get("options")
            if options is None:
                options = YamlMap()
            elif not self._expect(source, options, YamlMap, entry, "options"):
                options = YamlMap()
            if self._wins(stack, ("processor", str(name))):
                self.out.processors[name] = ProcessorEntry(
                    str(name), str(entry["type"]), options, at,
                    Located(source, entry.value_span("type")),
                    Located(source, entry.span("options") if "options" in entry else at.span))

    def _physics(self, source, physics, data, stack: tuple) -> None:
        if physics is None or not self._expect(source, physics, YamlMap, data, "physics"):
            return
        for key in physics:
            if key not in _PHYSICS_KEYS:
                self._unknown_key(source, physics, key, _PHYSICS_KEYS)
        if not self._wins(stack, "physics"):
            return
        gravity = self.out.physics.gravity
        if "gravity" in physics:
            gravity = self._vector(source, physics, "gravity", physics["gravity"], 3)
        friction = self.out.physics.friction
        if "friction" in physics:
            value = physics["friction"]
            value = [value] if isinstance(value, (int, float)) else value
            friction = self._vector(source, physics, "friction", value, None)
            if not 1 <= len(friction) <= 3 or min(friction, default=0) < 0:
                self.out.diagnostics.append(source.error(
                    "invalid-entry", "'friction' must be 1 to 3 numbers >= 0",
                    physics.span("friction"), "sliding [-], torsional [m], rolling [m], "
                    "for example [1.0, 0.005, 0.0001]"))
                friction = DEFAULT_FRICTION
            friction = friction + DEFAULT_FRICTION[len(friction):]
        self.out.physics = Physics(gravity, friction)

    def _allowed_collisions(self, source, pairs, data, prefix) -> None:
        if pairs is None or not self._expect(source, pairs, YamlList, data,
                                             "allowed_collisions"):
            return
        for index, pair in enumerate(pairs):
            at = Located(source, pairs.span(index))
            if (not isinstance(pair, list) or len(pair) != 2
                    or not all(isinstance(name, str) for name in pair)):
                self.out.diagnostics.append(at.error(
                    "invalid-entry", "an allowed collision is a pair of body names",
                    "for example: [bazar_left_link_7, bazar_left_hankamp_tool_robot_side]"))
                continue
            self.out.allowed_collisions.append(
                (prefixed(prefix, pair[0]), prefixed(prefix, pair[1]), at))


def _looked_in(folder: Path) -> str:
    searched = ", ".join(str(p) for p in paths.search_folders(folder))
    return f"looked in: {searched} (add folders with ROBOCOP_PATH)"


def _exponent_text(value) -> bool:
    """Whether ``value`` holds a number YAML 1.1 read as text (``1e3``, no dot)."""
    return isinstance(value, list) and any(
        isinstance(v, str) and _NUMBER.fullmatch(v) for v in value)
