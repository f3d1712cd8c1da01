"""What the contacts of a MuJoCo simulation do to a body: the wrench it exerts on the
environment, and whether two sets of bodies touch.

A body's *carried set* is its kinematic subtree in MuJoCo (its fixed children, the
links its joints carry: a hand's fingers) and every free body that an active weld
(``attach``) ties to a member of the set, with what that body carries. Its wrench is the
sum, over the active contacts between a geom of the set and a geom outside it, of the
force the set exerts on the other geom: in the world frame, the torque about the body's
origin, force [N] then torque [N m]. MuJoCo's contact normal points from ``geom1`` to
``geom2`` and :func:`mujoco.mj_contactForce` gives the force ``geom1`` exerts on
``geom2`` in the contact frame: a hand pressing down on a table exerts a force of
negative ``z``.

Contacts are those of the latest physics step; the wrenches of every body asked so far
are computed together, once per step.
"""

from __future__ import annotations

import numpy as np


class ContactReader:
    """Reads the contacts of ``data`` (a ``mujoco.MjData`` of ``model``).

    Args:
        mujoco: The ``mujoco`` module.
        model: The ``mujoco.MjModel``.
        data: Its ``mujoco.MjData``.
        welds: ``{(free body, body): weld equality id}``, the welds ``attach`` turns on.
    """

    def __init__(self, mujoco, model, data, welds: dict):
        self._mujoco = mujoco
        self.model = model
        self.data = data
        self._ids = {model.body(i).name: i for i in range(model.nbody)}
        self._subtrees = _subtrees(model.body_parentid)
        pairs = [(self._ids[free], self._ids[body], weld)
                 for (free, body), weld in welds.items()]
        self._welds = np.array(pairs, dtype=int).reshape(-1, 3)
        self._bodies: list = []            # the bodies asked so far, computed together
        self._body_ids = np.zeros(0, dtype=int)
        self._wrenches: dict = {}
        self._sets: dict = {}
        self._carried: dict = {}

    def invalidate(self) -> None:
        """The physics moved on: read the contacts again on the next request."""
        self._wrenches = {}

    def body_id(self, body: str) -> int:
        """MuJoCo's id of ``body``.

        Raises:
            KeyError: no such body in the simulation.
        """
        try:
            return self._ids[body]
        except KeyError:
            raise KeyError(f"no body '{body}' in the simulation") from None

    def wrench(self, body: str) -> np.ndarray:
        """The wrench ``body`` and what it carries exert on the environment: ``[fx, fy,
        fz, tx, ty, tz]`` [N, N m], world frame, torque about the body's origin."""
        if body not in self._wrenches:
            if body not in self._bodies:
                self._body_ids = np.append(self._body_ids, self.body_id(body))
                self._bodies.append(body)
                self._carried = {}
            self._wrenches = dict(zip(self._bodies, self._compute()))
        return self._wrenches[body].copy()

    def touching(self, first, second) -> bool:
        """Whether an active contact joins a geom of a body of ``first`` and one of a
        body of ``second`` (iterables of body names)."""
        bodies1, bodies2, _ = self._contacts()
        a, b = self._set(first), self._set(second)
        return bool(np.any((a[bodies1] & b[bodies2]) | (b[bodies1] & a[bodies2])))

    def carried(self, body: str) -> np.ndarray:
        """Which bodies ``body`` carries now (itself included), a mask over MuJoCo's
        bodies."""
        return self._carried_by(body, self._active_welds())

    def _active_welds(self) -> np.ndarray:
        return self._welds[self.data.eq_active[self._welds[:, 2]].astype(bool)]

    def _carried_by(self, body: str, welds: np.ndarray) -> np.ndarray:
        """:meth:`carried`, with the active ``welds`` (free body, body, weld) rows."""
        carried = self._subtrees[self.body_id(body)].copy()
        grown = True
        while grown:
            joined = welds[carried[welds[:, 1]] & ~carried[welds[:, 0]], 0]
            for free in joined:
                carried |= self._subtrees[free]
            grown = len(joined) > 0
        return carried

    def _set(self, bodies) -> np.ndarray:
        key = frozenset(bodies)
        mask = self._sets.get(key)
        if mask is None:
            mask = np.zeros(self.model.nbody, dtype=bool)
            mask[[self.body_id(b) for b in key]] = True
            self._sets[key] = mask
        return mask

    def _contacts(self) -> tuple:
        """The bodies of both geoms of each active contact, and the contacts' indices."""
        contact = self.data.contact
        active = np.flatnonzero(contact.efc_address >= 0)
        pairs = self.model.geom_bodyid[contact.geom[active]]
        return pairs[:, 0], pairs[:, 1], active

    def _compute(self) -> np.ndarray:
        """The wrenches of the bodies asked so far, one row each."""
        key = self.data.eq_active.tobytes()
        carried = self._carried.get(key)
        if carried is None:
            welds = self._active_welds()
            carried = np.array([self._carried_by(body, welds) for body in self._bodies],
                               dtype=float)
            self._carried = {key: carried}
        contact = self.data.contact
        inside = carried[:, self.model.geom_bodyid[contact.geom]]     # bodies x contacts x 2
        signs = (inside[:, :, 0] - inside[:, :, 1]) * (contact.efc_address >= 0)
        used = np.flatnonzero(signs.any(axis=0))                      # +1: geom1 is theirs
        wrenches = np.zeros((len(self._bodies), 6))
        if not len(used):
            return wrenches
        local = np.empty((len(used), 6))
        for row, index in enumerate(used):
            self._mujoco.mj_contactForce(self.model, self.data, int(index), local[row])
        on_geom2 = local.reshape(-1, 2, 3) @ contact.frame[used].reshape(-1, 3, 3)
        signs = signs[:, used]
        force = on_geom2[:, 0]                                          # world frame
        wrenches[:, :3] = signs @ force
        moments = _cross(np.concatenate((contact.pos[used], self.data.xpos[self._body_ids])),
                         np.concatenate((force, wrenches[:, :3])))
        wrenches[:, 3:] = signs @ (on_geom2[:, 1] + moments[:len(used)]) \
            - moments[len(used):]                                       # about each origin
        return wrenches


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of two n x 3 arrays (``np.cross`` costs tens of
    microseconds on a few rows)."""
    a, b = np.concatenate((a, a), axis=1), np.concatenate((b, b), axis=1)
    return a[:, 1:4] * b[:, 2:5] - a[:, 2:5] * b[:, 1:4]


def _subtrees(parents: np.ndarray) -> np.ndarray:
    """``subtrees[b]``: the mask of the bodies below body ``b`` in MuJoCo's tree (itself
    included); ``parents`` gives each body's parent (body 0, the world, is its own)."""
    count = len(parents)
    masks = np.eye(count, dtype=bool)
    for body in range(count - 1, 0, -1):     # a child's id is above its parent's
        masks[parents[body]] |= masks[body]
    return masks
