"""What the writers of a run need to know of it before its first cycle, as plain data
that another process can receive: its period, its tasks (each one's logged reference
width, error unit, kind and body), free bodies, force sensors, vars and joint groups.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace


@dataclass(frozen=True)
class TaskInfo:
    """A task as the log knows it: the width of its logged reference, the unit of its
    error (``m``, ``rad``, ``m+rad``, ``N`` or ``None``), its
    :class:`~robocop_dsl.runtime.TaskView` kind and its body (``None`` if none)."""

    width: int
    unit: str | None
    kind: str
    body: str | None


@dataclass(frozen=True)
class RunInfo:
    """A run seen from its writers.

    Attributes:
        time_step: The control period [s].
        joint_names: The controlled joints, in command order.
        tasks: Every task of the mission, by name (:class:`TaskInfo`).
        free_bodies: The world's free bodies.
        sensors: The bodies of the world's force sensors.
        variables: Each var's size and unit, by qualified name.
        joint_groups: The world's joint groups made of controlled joints only.
        world_path: The world file's path.
        report: The runner's :meth:`~robocop_dsl.runtime.Runner.report` (``None`` in
            another process).
    """

    time_step: float
    joint_names: list
    tasks: dict
    free_bodies: list
    sensors: list
    variables: dict
    joint_groups: dict
    world_path: str
    report: object = field(default=None, compare=False)

    @classmethod
    def of(cls, runner) -> RunInfo:
        """The info of a :class:`~robocop_dsl.runtime.Runner` (a ``RunInfo`` as is)."""
        if isinstance(runner, RunInfo):
            return runner
        from .log import declared_groups, error_unit, reference_width
        from .views import view_kind

        tasks = {task.name: TaskInfo(reference_width(task), error_unit(task), view_kind(task),
                                     getattr(task, "body", None)) for task in runner.tasks()}
        world = runner.controller.world
        variables = getattr(runner, "variables", None)
        return cls(runner.time_step, list(runner.joint_names), tasks,
                   list(getattr(runner, "free_bodies", ())),
                   list(runner.sensors.bodies) if hasattr(runner, "sensors") else [],
                   {name: (spec.size, spec.unit)
                    for name, spec in (variables.specs.items() if variables else ())},
                   declared_groups(world, runner.joint_names), str(world.path),
                   getattr(runner, "report", None))

    def portable(self) -> RunInfo:
        """This info without the runner's ``report``, for another process."""
        return replace(self, report=None)
