"""The Python entry point: ``load_mission(path)`` -> :class:`Mission`, whose
``runner()`` builds everything a run needs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from ..compile import spec as s
from ..compile.load import check_file
from ..control import Kinematics
from ..diagnostics import DiagnosticError, RobocopError
from .build import build_controller, build_program
from ..drivers import create_driver
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
               realtime: bool = False) -> Runner:
        """A runner on a private copy of the world's model.

        Args:
            solver: QP solver name; ``None`` keeps the controller processor's.
            hierarchy: ``strict`` or ``weighted``; ``None`` keeps the processor's.
            time_step: Control period [s]; ``None`` keeps the processor's.
            initial: Start configuration (``model.nq``); default the world's ``initial:``.
            body_placements: ``{body: 4x4 world pose}`` for bodies fixed to the world.
            driver: A driver (``connect``/``read``/``write``/``hold``/``disconnect``);
                default the one the world's ``processors:`` describe.
            realtime: Whether the run will keep to the wall clock (a simulated driver
                then runs in its own thread; otherwise it integrates in the loop).

        Raises:
            DiagnosticError: an option the world or the controller refuses.
        """
        world = self.world.copy()
        kinematics = Kinematics(world)
        for body, pose in (body_placements or {}).items():
            kinematics.place(body, "world", pin.SE3(np.asarray(pose, dtype=float)))
        try:
            controller = build_controller(self.spec, world, kinematics, solver=solver,
                                          hierarchy=hierarchy, time_step=time_step)
        except RobocopError as error:
            raise DiagnosticError([self.spec.source.error(
                "run-options", str(error), None, "the controller refused this value: check "
                "the mission's parameters and the run options (--solver, --hierarchy)")]) from None
        if driver is None:
            try:
                driver = create_driver(world, realtime=realtime,
                                       time_step=controller.time_step, initial=initial)
            except RobocopError as error:
                raise DiagnosticError([self.spec.source.error(
                    "run-driver", str(error), None,
                    f"see the driver processor in {world.path.name}")]) from None
        return Runner(build_program(self.spec), controller, driver, self.name)


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
