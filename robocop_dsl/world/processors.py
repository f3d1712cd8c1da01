"""The ``processors:`` of a world file: each type's options (kind, default, required),
and their check when a world loads.

Kinds: ``duration`` [s] > 0 (``5ms``, ``250us``, ``0.5s`` or a number of seconds),
``rate`` [Hz] > 0 (``1kHz``, ``500Hz`` or a number of hertz), ``group`` (a joint group
or joint of the world), ``body`` (a body of the world), ``solver`` (``auto`` or an
installed QP solver), ``choice``, ``flag`` (true/false), ``port`` (a TCP port),
``driver`` (a driver processor of the world), ``positive`` and ``non_negative``
(finite numbers > 0 and >= 0), ``gains`` (a joint servo's ``{kp, kv}``, each a number
> 0 or one per joint).

RoboCoP's own option names are accepted where they mean what this package does, and
refused with the supported equivalent where they do not (see :data:`ROBOCOP_OPTIONS`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace

from ..diagnostics import did_you_mean
from .description import to_seconds


@dataclass(frozen=True)
class Processor:
    """A checked ``processors:`` entry. ``options`` are those its implementation takes,
    durations in seconds and rates in hertz; ``driver`` is, for a ``qp_controller``,
    the driver processor it commands (``None`` when none is on its joint group);
    ``run_options`` are the given options a run reads instead (a ``qp_controller``'s
    ``state_tolerance``)."""

    name: str
    type: str
    options: dict
    driver: str | None = None
    run_options: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Option:
    """One option of a processor type."""

    kind: str
    default: object = None
    required: bool = False
    choices: tuple = ()


@dataclass(frozen=True)
class RobocopOption:
    """A RoboCoP option: accepted (and dropped) when its value is ``means``, else
    refused with ``hint``."""

    means: object
    hint: str


@dataclass(frozen=True)
class ProcessorType:
    """A processor type: its options, the RoboCoP options it accepts, the options that
    tie it to other processors rather than configure its implementation, and those a
    run reads rather than its implementation."""

    options: dict
    robocop: dict = field(default_factory=dict)
    world_only: tuple = ()
    run_only: tuple = ()


_VELOCITIES_ONLY = "this qp_controller is kinematic: it outputs joint velocities only"
ROBOCOP_OPTIONS = {
    "velocity_output": RobocopOption(True, f"{_VELOCITIES_ONLY}; remove the option or "
                                           "set it to true"),
    "force_output": RobocopOption(False, f"{_VELOCITIES_ONLY}; remove the option"),
    "include_bias_force_in_command": RobocopOption(
        False, "this qp_controller sends no force command; remove the option"),
}
"""RoboCoP's ``qp_controller`` options, and the only value this package supports."""

_DRIVER = {
    "joint_group": Option("group", required=True),
    "state_timeout": Option("duration", 0.25),
    "connect_timeout": Option("duration", 5.0),
    "rate": Option("rate", 1000.0),
    "period": Option("duration", 0.001),
    "command_timeout": Option("duration", 0.05),
}
PROCESSOR_TYPES = {
    "model": ProcessorType({"implementation": Option("choice", "pinocchio",
                                                     choices=("pinocchio",))}),
    "qp_controller": ProcessorType({
        "joint_group": Option("group", required=True),
        "time_step": Option("duration", required=True),
        "solver": Option("solver", "auto"),
        "hierarchy": Option("choice", "strict", choices=("strict", "weighted")),
        "damping": Option("positive", 1e-6),
        "lm_damping": Option("non_negative", 1e-2),
        "driver": Option("driver"),
        "state_tolerance": Option("non_negative", 0.05),
    }, ROBOCOP_OPTIONS, world_only=("driver",), run_only=("state_tolerance",)),
    "meshcat": ProcessorType({"period": Option("duration", 0.04)}),
    "simulated": ProcessorType(dict(_DRIVER)),
    "loopback": ProcessorType({**_DRIVER, "port": Option("port"),
                               "launch": Option("flag", False)}),
    "mujoco": ProcessorType({"joint_group": Option("group", required=True),
                             "time_step": Option("duration", 0.001),
                             "gains": Option("gains", {"kp": 2000.0, "kv": 100.0})}),
    "force_sensor": ProcessorType({"body": Option("body", required=True),
                                   "filter": Option("rate")}),
}
"""Every processor type and its options. A ``qp_controller``'s ``state_tolerance``
[rad] is how far past its URDF position limits the driver may report a joint of its
group before the run faults (a prismatic joint: a tenth of it, in metres). A
``force_sensor`` measures the wrench its ``body`` exerts on the environment; its
``filter`` [Hz] is the cutoff frequency of a first-order low-pass filter on the
reading (none when absent)."""

DRIVER_TYPES = ("simulated", "loopback", "mujoco")
_RATE = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(Hz|kHz|MHz)\s*$")
_HERTZ = {"Hz": 1.0, "kHz": 1e3, "MHz": 1e6}


def option_default(type_name: str, option: str):
    """The default of ``option`` of processor type ``type_name`` (SI units)."""
    return PROCESSOR_TYPES[type_name].options[option].default


class _Refused(Exception):
    """A value an option cannot take."""

    def __init__(self, message: str, hint: str | None = None, code: str = "wrong-option"):
        super().__init__(message)
        self.hint, self.code = hint, code


@dataclass
class Names:
    """The joint groups (name -> joints), joints and bodies of an assembled world, and
    which joints move on their own (have dofs: not fixed, not mimic)."""

    groups: dict
    joints: set
    moving: set = field(default_factory=set)
    bodies: list = field(default_factory=list)

    def joints_of(self, name) -> frozenset | None:
        """The joints of group or joint ``name``; ``None`` when it is neither."""
        if name in self.groups:
            return frozenset(self.groups[name])
        return frozenset([name]) if name in self.joints else None


def check_processors(entries: dict, names: Names | None) -> tuple[dict, list]:
    """The checked processors of a world and the diagnostics of their problems.

    Args:
        entries: :class:`~.description.ProcessorEntry` by name.
        names: The world's groups and joints; ``None`` skips the checks that need them.
    """
    out: list = []
    built = {}
    for name, entry in entries.items():
        processor = _check(entry, names, out)
        if processor is not None:
            built[name] = processor
    if names is not None:
        _link_drivers(built, entries, names, out)
        _physics_rules(built, entries, names, out)
    _one_sensor_per_body(built, entries, out)
    return built, out


def _check(entry, names, out: list) -> Processor | None:
    kind = PROCESSOR_TYPES.get(entry.type)
    if kind is None:
        out.append(entry.type_at.error(
            "unknown-processor-type", f"unknown processor type '{entry.type}'",
            did_you_mean(entry.type, PROCESSOR_TYPES)
            or "expected one of: " + ", ".join(PROCESSOR_TYPES)))
        return None
    options = {}
    for key, value in entry.options.items():
        converted = _option(entry, kind, str(key), value, names, out)
        if converted is not None:
            options[str(key)] = converted
    _required(entry, kind, out)
    _rules(entry, options, out)
    passed = {k: v for k, v in options.items() if k not in kind.world_only + kind.run_only}
    run_options = {k: v for k, v in options.items() if k in kind.run_only}
    return Processor(entry.name, entry.type, passed, run_options=run_options)


def _option(entry, kind: ProcessorType, key: str, value, names, out: list):
    """The option's value in SI units, or ``None`` when refused or dropped."""
    source, options = entry.type_at.source, entry.options
    if key in kind.robocop:
        robocop = kind.robocop[key]
        if value is not robocop.means:
            out.append(source.error("unsupported-option", f"'{key}: {_yaml(value)}' is not "
                                    f"supported", options.value_span(key), robocop.hint))
        return None
    option = kind.options.get(key)
    if option is None:
        known = sorted(kind.options) + sorted(kind.robocop)
        out.append(source.error(
            "unknown-option", f"unknown option '{key}' of a {entry.type} processor",
            options.span(key), did_you_mean(key, known) or "options: " + ", ".join(known)))
        return None
    try:
        return _CONVERT[option.kind](value, option, names)
    except _Refused as refused:
        out.append(source.error(refused.code, f"'{key}' {refused}", options.value_span(key),
                                refused.hint))
        return None


def _required(entry, kind: ProcessorType, out: list) -> None:
    unknown = [str(k) for k in entry.options if k not in kind.options and k not in kind.robocop]
    for key, option in kind.options.items():
        if option.required and key not in entry.options and not _misspelt(key, unknown):
            out.append(entry.options_at.error(
                "missing-option", f"processor '{entry.name}' ({entry.type}) needs option "
                f"'{key}'", f"add it to its options, for example {key}: {_EXAMPLE[key]}"))


def _misspelt(key: str, unknown: list) -> bool:
    """Whether an unknown option (already reported) looks like ``key``."""
    return any(did_you_mean(given, [key]) for given in unknown)


def _rules(entry, options: dict, out: list) -> None:
    """The rules that tie a driver's options together."""
    if entry.type not in DRIVER_TYPES:
        return
    if "rate" in options and "period" in options:
        out.append(entry.type_at.source.error(
            "wrong-option", "give either 'rate' or 'period', not both",
            entry.options.span("period"), "remove one of them"))
    if entry.type == "loopback" and "port" not in entry.options and not options.get("launch"):
        out.append(entry.options_at.error(
            "missing-option", f"processor '{entry.name}' (loopback) needs option 'port' "
            "or 'launch: true'", "give the simulator's TCP port, or launch: true to start it"))


def _link_drivers(built: dict, entries: dict, names: Names, out: list) -> None:
    """Give each qp_controller its driver: the one it names, else the only one on its
    joint group; several there and none named is an error."""
    drivers = {n: p for n, p in built.items() if p.type in DRIVER_TYPES}
    for name, processor in built.items():
        group = names.joints_of(processor.options.get("joint_group"))
        if processor.type != "qp_controller" or group is None:
            continue
        on_group = [d for d, p in drivers.items()
                    if names.joints_of(p.options.get("joint_group")) == group]
        driver = _driver(entries[name], processor, drivers, on_group, out)
        built[name] = replace(processor, driver=driver)


def _physics_rules(built: dict, entries: dict, names: Names, out: list) -> None:
    """A mujoco driver steps its physics a whole number of times per control period,
    and drives only joints a controller drives."""
    controllers = [p for p in built.values() if p.type == "qp_controller"]
    for name, processor in built.items():
        if processor.type != "mujoco":
            continue
        entry, options = entries[name], processor.options
        source = entry.type_at.source
        driven = names.joints_of(options.get("joint_group")) or frozenset()
        commanded = frozenset().union(*(names.joints_of(c.options.get("joint_group"))
                                        or frozenset() for c in controllers))
        stray = sorted(driven - commanded)
        if stray and "joint_group" in options:
            out.append(source.error(
                "wrong-option", f"driver '{name}' drives joints no controller commands: "
                f"{', '.join(stray)}", entry.options.value_span("joint_group"),
                "drive the joint group of a qp_controller (the physics servos the "
                "other joints to their initial positions)"))
        moving = [j for j in names.groups.get(options.get("joint_group"), (options.get(
            "joint_group"),)) if j in names.moving]
        for key, value in options.get("gains", {}).items():
            if isinstance(value, list) and len(value) != len(moving):
                out.append(source.error(
                    "wrong-option", f"gains: '{key}' has {len(value)} values, the joint "
                    f"group '{options['joint_group']}' has {len(moving)} joints",
                    entry.options["gains"].value_span(key),
                    f"give one value for every joint, or one for all: {', '.join(moving)}"))
        step = options.get("time_step", option_default("mujoco", "time_step"))
        for controller in controllers:
            period = controller.options.get("time_step")
            if period is None or controller.driver not in (None, name):
                continue
            steps = period / step
            if abs(steps - round(steps)) > 1e-9 * max(steps, 1) or round(steps) < 1:
                at = (entry.options.value_span("time_step") if "time_step" in entry.options
                      else entry.options_at.span)
                out.append(source.error(
                    "wrong-option", f"the physics step {step * 1e3:g} ms of '{name}' does not "
                    f"divide the period {period * 1e3:g} ms of '{controller.name}'", at,
                    f"give a step that divides it, for example time_step: "
                    f"{_divisor(period, step) * 1e3:g}ms"))


def _one_sensor_per_body(built: dict, entries: dict, out: list) -> None:
    """Two force sensors on one body would measure the same wrench twice."""
    first: dict = {}
    for name, processor in built.items():
        body = processor.options.get("body")
        if processor.type != "force_sensor" or body is None:
            continue
        if body in first:
            entry = entries[name]
            out.append(entry.type_at.source.error(
                "duplicate-sensor", f"body '{body}' already has force sensor '{first[body]}'",
                entry.options.value_span("body"), "keep one force sensor per body"))
        else:
            first[body] = name


def _divisor(period: float, step: float) -> float:
    """The largest step [s] no longer than ``step`` that divides ``period``."""
    return period / max(1, math.ceil(period / step - 1e-9))


def _driver(entry, processor: Processor, drivers: dict, on_group: list, out: list):
    group = processor.options["joint_group"]
    named = entry.options.get("driver")
    if named is None:
        if len(on_group) > 1:
            out.append(entry.at.error(
                "ambiguous-driver", f"several driver processors drive '{group}', the joint "
                f"group of '{entry.name}': {', '.join(on_group)}",
                f"name the one it commands in its options: driver: {on_group[0]}"))
            return None
        return on_group[0] if on_group else None
    if named in on_group:
        return named
    at, span = entry.type_at.source, entry.options.value_span("driver")
    if named in drivers:
        message = (f"driver '{named}' drives '{drivers[named].options.get('joint_group')}', "
                   f"not '{group}'")
    else:
        message = f"no driver processor '{named}'"
    hint = (did_you_mean(str(named), on_group) if named not in drivers else None) or (
        "drivers on '" + group + "': " + (", ".join(on_group) or "none"))
    out.append(at.error("wrong-option", message, span, hint))
    return None


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


SHORTEST = 1e-5
"""The shortest duration an option takes [s]: no processor runs faster than 100 kHz."""


def _duration(value, option, names) -> float:
    seconds = to_seconds(value)
    if not _number(seconds) or not math.isfinite(seconds) or seconds <= 0:
        raise _Refused(f"must be a duration > 0, not {_yaml(value)}",
                       "write it with a unit: 5ms, 250us or 0.5s (a bare number is seconds)")
    if seconds < SHORTEST:
        raise _Refused(f"must be at least {SHORTEST * 1e6:g}us, not {_yaml(value)}",
                       "a period or time step that short is a typo (5ms, 250us)")
    return float(seconds)


def _rate(value, option, names) -> float:
    match = _RATE.match(value) if isinstance(value, str) else None
    hertz = float(match.group(1)) * _HERTZ[match.group(2)] if match else value
    if not _number(hertz) or not math.isfinite(hertz) or hertz <= 0:
        raise _Refused(f"must be a rate > 0, not {_yaml(value)}",
                       "write it with a unit: 1kHz or 500Hz (a bare number is hertz)")
    return float(hertz)


def _group(value, option, names) -> str:
    if not isinstance(value, str):
        raise _Refused(f"must name a joint group or joint, not {_yaml(value)}")
    if names is not None and names.joints_of(value) is None:
        known = list(names.groups) + sorted(names.joints)
        raise _Refused(f"names unknown joint group or joint '{value}'",
                       did_you_mean(value, known) or "joint groups: " + ", ".join(names.groups),
                       code="unknown-joint")
    return value


def _body(value, option, names) -> str:
    if not isinstance(value, str):
        raise _Refused(f"must name a body, not {_yaml(value)}")
    if names is not None and value not in names.bodies:
        raise _Refused(f"names unknown body '{value}'",
                       did_you_mean(value, names.bodies) or "see the bodies with "
                       "robocop-mission world FILE.yaml", code="unknown-body")
    return value


def _solver(value, option, names) -> str:
    if value in ("auto", "daqp", "proxqp"):  # built in: daqp and proxsuite are dependencies
        return value
    from ..control.solvers import available_solvers

    installed = available_solvers()
    if value not in installed:
        listed = "installed solvers: " + ", ".join(installed)
        close = did_you_mean(str(value), installed)
        raise _Refused(f"names unknown solver '{value}'", f"{close} ({listed})" if close
                       else listed)
    return value


def _choice(value, option, names) -> str:
    if value not in option.choices:
        raise _Refused(f"must be {' or '.join(option.choices)}, not {_yaml(value)}",
                       did_you_mean(str(value), option.choices))
    return value


def _flag(value, option, names) -> bool:
    if not isinstance(value, bool):
        raise _Refused(f"must be true or false, not {_yaml(value)}")
    return value


def _port(value, option, names) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= 65535:
        raise _Refused(f"must be a TCP port (0 to 65535), not {_yaml(value)}")
    return value


def _driver_name(value, option, names) -> str:
    if not isinstance(value, str):
        raise _Refused(f"must name a driver processor, not {_yaml(value)}")
    return value


def _positive(value, option, names) -> float:
    if not _number(value) or not math.isfinite(value) or value <= 0:
        raise _Refused(f"must be a number > 0, not {_yaml(value)}")
    return float(value)


def _non_negative(value, option, names) -> float:
    if not _number(value) or not math.isfinite(value) or value < 0:
        raise _Refused(f"must be a number >= 0, not {_yaml(value)}")
    return float(value)


def _gains(value, option, names) -> dict:
    if not hasattr(value, "items") or set(value) - {"kp", "kv"}:
        raise _Refused(f"must be a mapping with kp and kv, not {_yaml(value)}",
                       "for example gains: {kp: 2000, kv: 100} (one value, or one per joint)")
    gains = dict(option.default)
    for key, given in value.items():
        values = list(given) if isinstance(given, list) else [given]
        if not values or not all(_number(v) and math.isfinite(v) and v > 0 for v in values):
            raise _Refused(f"'{key}' must be a number > 0 or a list of them, not "
                           f"{_yaml(given)}")
        gains[str(key)] = [float(v) for v in values] if isinstance(given, list) \
            else float(given)
    return gains


def _yaml(value) -> str:
    """``value`` as written in YAML."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return "null" if value is None else str(value)


_CONVERT = {"duration": _duration, "rate": _rate, "group": _group, "body": _body,
            "solver": _solver, "choice": _choice, "flag": _flag, "port": _port,
            "driver": _driver_name, "positive": _positive, "non_negative": _non_negative,
            "gains": _gains}
_EXAMPLE = {"joint_group": "NAME", "time_step": "5ms", "body": "NAME"}
