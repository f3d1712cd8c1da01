"""The Python entry point: ``load_mission(path)`` -> :class:`Mission`, whose
``runner()`` builds everything a run needs: a :class:`Runner`, or a
:class:`~robocop_dsl.runtime.cascade.CascadeRunner` for a mission of cascaded
controllers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from ..compile import spec as s
from ..compile.load import check_file
from ..control import Kinematics
from ..diagnostics import DiagnosticError, RobocopError
from .build import build_controller, build_program
from ..drivers import DriverConfigError, create_driver
from .cascade import CascadeRunner, ControllerThread, Link, Remote
from .runner import Runner


class Mission:
    """A checked, compiled mission bound to its world.

    Attributes:
        spec: The compiled mission (:class:`robocop_dsl.compile.spec.MissionSpec`).
        world: The world it runs in.
    """

    def __init__(self, spec: s.MissionSpec, world):
        self.spec = spec
        self.world = world

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def path(self) -> Path:
        return Path(self.spec.source.path)

    def __repr__(self) -> str:
        return f"Mission({self.name}, {len(self.spec.states)} states, world={self.world.path.name})"

    def runner(self, solver: str | None = None, hierarchy: str | None = None,
               time_step: float | None = None, initial: np.ndarray | None = None,
               body_placements: dict | None = None, driver=None,
               drivers: dict | None = None, realtime: bool = False,
               physics: dict | None = None) -> Runner:
        """A runner on private copies of the world's model.

        A mission run by several controllers (``spec.cascaded``) gets a
        :class:`~robocop_dsl.runtime.cascade.CascadeRunner`: one world copy, driver and
        thread per controller.

        Args:
            solver: QP solver name; ``None`` keeps the controller processors'.
            hierarchy: ``strict`` or ``weighted``; ``None`` keeps the processors'.
            time_step: Control period [s]; ``None`` keeps the processor's (a cascade
                keeps its controllers' periods).
            initial: Start configuration (``model.nq``); default the world's ``initial:``.
            body_placements: ``{body: 4x4 world pose}`` for bodies fixed to the world.
            driver: A driver (``connect``/``read``/``write``/``hold``/``disconnect``);
                default the one the world's ``processors:`` describe.
            drivers: For a cascade, drivers by controller name; the others are those of
                the world's driver processors on the controllers' joint groups.
            realtime: Whether the run will keep to the wall clock (a simulated driver
                then runs in its own thread; otherwise it integrates in the loop).
            physics: Changes to the physics of a ``mujoco`` driver: ``friction`` (the
                sliding coefficient of every contact [-]) and ``mass`` ({free body: kg}).

        Raises:
            DiagnosticError: an option the world or the controller refuses.
        """
        if self.spec.cascaded:
            if time_step is not None or driver is not None:
                raise DiagnosticError([self.spec.source.error(
                    "run-options", "a cascade keeps its controllers' periods and drivers",
                    None, "give drivers by controller name (drivers=...), not time_step "
                    "or driver")])
            return self._cascade(solver, hierarchy, initial, body_placements,
                                 dict(drivers or {}), realtime)
        world, kinematics = self._world_copy(body_placements)
        controller = self._controller(world, kinematics, None, solver=solver,
                                      hierarchy=hierarchy, time_step=time_step)
        if driver is None:
            driver = self._driver(world, self.spec.controller, controller, initial,
                                  realtime, physics=physics)
        return Runner(build_program(self.spec), controller, driver, self.name)

    def _cascade(self, solver, hierarchy, initial, body_placements, drivers: dict,
                 realtime: bool) -> CascadeRunner:
        names = self.spec.controllers
        controllers, links = {}, {}
        for name in names:
            world, kinematics = self._world_copy(body_placements)
            controllers[name] = self._controller(world, kinematics, name, solver=solver,
                                                 hierarchy=hierarchy)
            if name not in drivers:
                drivers[name] = self._driver(world, name, controllers[name], initial,
                                             realtime, cascade=True)
            links[name] = Link(name, controllers[name].joint_group,
                               [other for other in names if other != name])
        owners = {n: t.controller for n, t in (*self.spec.tasks.items(),
                                                *self.spec.constraints.items())}
        remote = Remote(owners, links, names[0])
        threads = [ControllerThread(name, controllers[name], drivers[name], links[name],
                                    [links[o] for o in names if o != name], index)
                   for index, name in enumerate(names[1:], start=1)]
        return CascadeRunner(build_program(self.spec, remote), controllers[names[0]],
                             drivers[names[0]], self.name, links[names[0]], threads, remote)

    def _world_copy(self, body_placements: dict | None):
        world = self.world.copy()
        kinematics = Kinematics(world)
        for body, pose in (body_placements or {}).items():
            kinematics.place(body, "world", pin.SE3(np.asarray(pose, dtype=float)))
        return world, kinematics

    def _controller(self, world, kinematics, processor: str | None, **options):
        try:
            return build_controller(self.spec, world, kinematics, processor, **options)
        except RobocopError as error:
            raise DiagnosticError([self.spec.source.error(
                "run-options", str(error), None, "the controller refused this value: check "
                "the mission's parameters and the run options (--solver, --hierarchy)")]) from None

    def _driver(self, world, controller_name: str, controller, initial, realtime: bool,
                cascade: bool = False, physics: dict | None = None):
        try:
            processor = driver_of(world, controller_name) if cascade else None
            if cascade and world.processors[processor].type == "mujoco":
                raise DriverConfigError(
                    f"'{controller_name}' is cascaded and its driver '{processor}' is a "
                    "mujoco one: each controller of a cascade has a driver of its own, "
                    "and one physics cannot be split between them; run the mission with "
                    "one controller on a physics world")
            return create_driver(world, processor, realtime=realtime,
                                 time_step=controller.time_step, initial=initial,
                                 controller=controller_name, physics=physics)
        except RobocopError as error:
            raise DiagnosticError([self.spec.source.error(
                "run-driver", str(error), None,
                f"see the driver processors in {world.path.name}")]) from None


def driver_of(world, controller: str) -> str:
    """The name of the driver processor of the qp_controller ``controller``: the one
    its ``driver:`` option names, or the only one on its joint group.

    Raises:
        DriverConfigError: No driver processor drives its joint group.
    """
    driver = getattr(world.processors.get(controller), "driver", None)
    if driver is None:
        group = world.processors[controller].options.get("joint_group")
        raise DriverConfigError(f"no driver processor drives the joint group '{group}' of "
                                f"'{controller}' in {world.path.name}: a cascade needs one "
                                "per controller, on the controller's joint group")
    return driver


def load_mission(path: str | Path, world=None) -> Mission:
    """Parse, check and compile a mission file.

    Args:
        path: The ``.mission`` file.
        world: A world to use instead of the one the mission names (a variant).

    Raises:
        DiagnosticError: every diagnostic of the file when it has an error.
    """
    checked = check_file(path, world=world)
    if checked.mission is None:
        raise DiagnosticError(checked.diagnostics)
    return Mission(checked.mission, checked.world)
