"""Every joint of the world as ``/joint_states`` gives it: the controlled joints first
(their positions and their commands as velocities), then the joints no controller
commands (their positions read from the configuration: a continuous joint's angle in
(-pi, pi]; velocity NaN, as none is known), then the mimic joints (the position of the
joint they follow, scaled and offset; its velocity scaled, when known). A free body's
floating or planar joint is not a joint here: its body is on ``/tf``."""

from __future__ import annotations

import numpy as np


class JointStates:
    """The names, positions and velocities of ``/joint_states`` for a world.

    Args:
        world: The run's :class:`~robocop_dsl.world.World`.
        controlled: The controlled joints, in command order.

    Attributes:
        names: Every joint, in the order of :meth:`values`.
    """

    def __init__(self, world, controlled: list):
        model = world.model
        self.names = list(controlled)
        self._others: list = []        # (q index, nq) of each uncommanded joint
        mimics: list = []              # (master, scaling, offset, q index) of each mimic
        for index in range(1, model.njoints):
            name, joint = model.names[index], model.joints[index]
            if name in controlled:
                continue
            if joint.shortname() == "JointModelMimic":
                mimic, master = joint.extract(), world.joint(name).mimic
                mimics.append((name, master, mimic.scaling, mimic.offset,
                               model.joints[model.getJointId(master)].idx_q,
                               model.joints[model.getJointId(master)].nq))
            elif joint.nv == 1 and joint.nq in (1, 2):
                self.names.append(name)
                self._others.append((joint.idx_q, joint.nq))
        self.names += [name for name, *_ in mimics]
        column = {name: index for index, name in enumerate(self.names)}
        self._commanded = len(controlled)
        self._mimics = [(column.get(master), scaling, offset, idx_q, nq)
                        for _, master, scaling, offset, idx_q, nq in mimics]

    def values(self, records: list) -> np.ndarray:
        """Per record (:class:`~robocop_dsl.runtime.CycleRecord`), the positions [rad or
        m] of :attr:`names`, then their velocities [rad/s or m/s]."""
        rows, count = len(records), len(self.names)
        positions = np.full((rows, count), np.nan)
        velocities = np.full((rows, count), np.nan)
        commanded = self._commanded
        if commanded:
            positions[:, :commanded] = [record.positions for record in records]
            velocities[:, :commanded] = [record.command for record in records]
        if self._others or self._mimics:
            q = np.array([record.q for record in records])
            for column, (start, nq) in enumerate(self._others, commanded):
                positions[:, column] = _angle(q, start, nq)
            for column, (master, scaling, offset, start, nq) in enumerate(
                    self._mimics, commanded + len(self._others)):
                positions[:, column] = scaling * _angle(q, start, nq) + offset
                if master is not None:
                    velocities[:, column] = scaling * velocities[:, master]
        return np.hstack([positions, velocities])


def _angle(q: np.ndarray, start: int, nq: int) -> np.ndarray:
    """The position [rad or m] of a one-dof joint in each row of ``q``, its coordinates
    from ``start``: the coordinate itself, or a continuous joint's angle from its cosine
    and sine."""
    return q[:, start] if nq == 1 else np.arctan2(q[:, start + 1], q[:, start])
