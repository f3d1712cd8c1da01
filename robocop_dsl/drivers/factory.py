"""Building a world's driver from its ``processors:`` entry.

```yaml
processors:
  driver:
    type: simulated                  # or loopback
    options: {joint_group: bazar_upper_joints, rate: 1kHz, command_timeout: 50ms}
```

Options (durations in seconds or as ``5ms``; a rate as ``1kHz`` or a number of hertz):

- every type: ``joint_group`` (required), ``state_timeout`` (250ms), ``connect_timeout``
  (5s);
- ``simulated``: ``rate`` or ``period`` of its thread (1kHz), ``command_timeout`` (50ms);
- ``loopback``: ``port``, ``launch`` (start the simulator process, default false), and
  for a launched simulator ``rate``/``period`` and ``command_timeout``;
- ``mujoco``: ``time_step`` of the physics (1ms, dividing the control period) and the
  joint servo's ``gains: {kp, kv}`` (:mod:`robocop_dsl.physics.servo`); it takes none
  of the timeouts (the physics steps in the control loop's thread).
"""

from __future__ import annotations

from ..world.processors import DRIVER_TYPES, PROCESSOR_TYPES, option_default
from .errors import DriverConfigError
from .loopback import LoopbackDriver
from .simulated import ThreadedSimulatedDriver
from .timing import parse_duration, period_from_options

DRIVER_OPTIONS = {kind: set(PROCESSOR_TYPES[kind].options) for kind in DRIVER_TYPES}
"""The options each driver type accepts (declared in :mod:`robocop_dsl.world.processors`)."""


def driver_processor(world, name: str | None = None, controller: str | None = None):
    """The world's driver processor: ``name``; else the driver of the qp_controller
    ``controller`` (the one its ``driver:`` option names, or the only one on its joint
    group); else the world's only driver processor.

    Raises:
        DriverConfigError: No such processor, or several and nothing to choose one.
    """
    drivers = {p.name: p for p in world.processors.values() if p.type in DRIVER_OPTIONS}
    if name is None and controller in world.processors:
        name = getattr(world.processors[controller], "driver", None)
    if name is not None:
        if name not in drivers:
            raise DriverConfigError(f"{world.path.name} has no driver processor '{name}' "
                                    f"(driver processors: {', '.join(drivers) or 'none'})")
        return drivers[name]
    if len(drivers) != 1:
        raise DriverConfigError(f"{world.path.name} has {len(drivers)} driver processors "
                                f"({', '.join(drivers) or 'none'}): give the qp_controller "
                                "the one it commands with the option 'driver: NAME'")
    return next(iter(drivers.values()))


def create_driver(world, name: str | None = None, realtime: bool = True,
                  time_step: float | None = None, initial=None,
                  controller: str | None = None, physics: dict | None = None):
    """Build the driver described by the world's processor ``name``.

    Args:
        world: The loaded world.
        name: The driver processor's name; optional when the world has one, or when
            ``controller`` is given.
        realtime: For ``simulated``: build the threaded driver, which follows the wall
            clock. When false, build the in-thread
            :class:`~robocop_dsl.runtime.driver.SimulatedDriver`, which integrates
            exactly one ``time_step`` per ``read()`` so a run may go faster than real
            time. ``loopback`` is always real time.
        time_step: The control period [s]; required for the in-thread driver.
        initial: Initial configuration (nq); defaults to the world's ``initial:``.
        controller: The qp_controller processor whose driver to build (see
            :func:`driver_processor`).
        physics: For ``mujoco``: ``friction`` [-] and ``mass`` ({free body: kg}) to
            simulate instead of the world's.

    Returns:
        The driver, not yet connected. ``driver.realtime`` tells whether the control
        loop must keep to the wall clock.

    Raises:
        DriverConfigError: Unknown type or option, missing or invalid value.
    """
    processor = driver_processor(world, name, controller)
    options = dict(processor.options)
    unknown = sorted(set(options) - DRIVER_OPTIONS[processor.type])
    if unknown:
        raise DriverConfigError(
            f"driver '{processor.name}' ({processor.type}): unknown option(s) "
            f"{', '.join(unknown)}; valid: {', '.join(sorted(DRIVER_OPTIONS[processor.type]))}")
    group = _joint_group(world, processor)
    kind = processor.type
    if kind == "mujoco":
        return _mujoco(world, processor, group, time_step, initial, physics or {})
    if physics:
        raise DriverConfigError(f"driver '{processor.name}' ({kind}) simulates no physics: "
                                "friction and masses need a mujoco driver")
    common = {"initial": initial, "state_timeout": _seconds(options, kind, "state_timeout"),
              "connect_timeout": _seconds(options, kind, "connect_timeout")}
    period = period_from_options(options, option_default(kind, "period"))
    command_timeout = _seconds(options, kind, "command_timeout")
    if processor.type == "loopback":
        return LoopbackDriver(world, group, _port(processor), bool(options.get("launch")),
                              1.0 / period, command_timeout, **common)
    if realtime:
        return ThreadedSimulatedDriver(world, group, period, command_timeout, **common)
    if time_step is None:
        raise DriverConfigError("the in-thread simulated driver needs the control period "
                                "(time_step)")
    from ..runtime.driver import SimulatedDriver

    return SimulatedDriver(world, group, time_step, initial)


def _mujoco(world, processor, group: str, period: float | None, initial, physics: dict):
    from ..physics.driver import MujocoDriver
    from ..physics.servo import Servo

    if period is None:
        raise DriverConfigError("the mujoco driver needs the control period (time_step)")
    options = processor.options
    step = options.get("time_step", option_default("mujoco", "time_step"))
    steps = period / step
    if abs(steps - round(steps)) > 1e-9 * steps or round(steps) < 1:
        raise DriverConfigError(f"driver '{processor.name}': the physics step "
                                f"{step * 1e3:g} ms does not divide the control period "
                                f"{period * 1e3:g} ms")
    try:
        servo = Servo.from_options(world, {**options, "joint_group": group})
    except ValueError as error:
        raise DriverConfigError(f"driver '{processor.name}': {error}") from None
    return MujocoDriver(world, group, period, step, servo, initial, physics)


def _joint_group(world, processor) -> str:
    group = processor.options.get("joint_group")
    if group is None:
        raise DriverConfigError(f"driver '{processor.name}' needs options: {{joint_group: ...}}")
    if not world.has_group(group) and group not in world.joint_names():
        raise DriverConfigError(f"driver '{processor.name}': no joint group or joint "
                                f"'{group}' in {world.path.name}")
    return group


def _seconds(options: dict, kind: str, key: str) -> float:
    """Option ``key`` [s], or its default for driver type ``kind``."""
    return parse_duration(options[key], key) if key in options else option_default(kind, key)


def _port(processor) -> int | None:
    port = processor.options.get("port")
    if port is None and not processor.options.get("launch"):
        raise DriverConfigError(f"driver '{processor.name}' (loopback) needs a 'port' "
                                f"or 'launch: true'")
    if port is not None and (not isinstance(port, int) or not 0 <= port <= 65535):
        raise DriverConfigError(f"driver '{processor.name}': port '{port}' is not a TCP port")
    return port
