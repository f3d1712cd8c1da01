"""The MuJoCo driver: the world's joints and free bodies simulated with rigid-body
physics (gravity, inertia, contacts, friction), commanded in joint velocity.

Each ``read()`` writes the last command to the joint servos (:mod:`.servo`), steps
the physics ``period / time_step`` times and returns the configuration: the joints'
positions and the free bodies' poses as physics left them. Joints outside the driven
group are servoed to their initial positions. ``attach`` turns on a weld between a
free body and another body; ``detach`` turns it off. ``wrench`` and ``contact`` read
the contacts of the latest physics step (:mod:`.contacts`).
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from .contacts import ContactReader
from .model import initial_state, physics_model
from .servo import Servo


class MujocoDriver:
    """A simulated robot in a simulated world; time advances one control period per
    ``read()``, so a run may go faster than real time.

    Args:
        world: The world.
        joint_group: The driven group's name.
        period: The control period [s], a multiple of ``time_step``.
        time_step: The physics step [s].
        servo: The joint servo's gains (default gains when ``None``).
        initial: Initial configuration (nq); defaults to the world's ``initial:``.
        physics: Changes to the world's physics: ``friction`` (the sliding coefficient
            of every contact [-]) and ``mass`` ({free body: kg}; its inertia scales
            with it).
    """

    realtime = False
    """Time advances one period per ``read()``: a loop may run faster than real time."""

    def __init__(self, world, joint_group: str, period: float, time_step: float,
                 servo: Servo | None = None, initial: np.ndarray | None = None,
                 physics: dict | None = None):
        import mujoco

        self._mujoco = mujoco
        self.world = world
        self.pinocchio = world.model
        self.group = world.joint_group(joint_group)
        self.period = float(period)
        self.time_step = float(time_step)
        self.steps = max(1, round(self.period / self.time_step))
        self.servo = servo or Servo.default(world)
        self.physics = physics_model(world, self.time_step, self.servo)
        self.model = self.physics.model
        self._change(physics or {})
        self.data = mujoco.MjData(self.model)
        self.contacts = ContactReader(mujoco, self.model, self.data, self.physics.welds)
        self.initial = np.array(world.initial_configuration() if initial is None else initial,
                                dtype=float)
        self._joints = self._joint_table()
        self._free = self._free_table()
        self.step_time = 0.0
        """Wall-clock time [s] spent in MuJoCo's steps so far."""
        self._command = np.zeros(self.group.dofs)
        self._reset()

    def __repr__(self) -> str:
        return (f"MujocoDriver({self.group.name}, {self.group.dofs} dofs, "
                f"{self.steps} x {self.time_step:g} s per period)")

    def _change(self, physics: dict) -> None:
        """Apply a sample's friction and masses to the compiled model."""
        mujoco, model = self._mujoco, self.model
        if "friction" in physics:
            model.geom_friction[:, 0] = physics["friction"]
        for body, mass in physics.get("mass", {}).items():
            if body not in self.physics.free:
                raise ValueError(f"cannot change the mass of '{body}': it is not a free body")
            index = self.physics.free[body][2]
            model.body_inertia[index] *= mass / model.body_mass[index]
            model.body_mass[index] = mass
        if physics:
            mujoco.mj_setConst(model, mujoco.MjData(model))

    def _joint_table(self) -> dict:
        """Per servoed joint: MuJoCo's qpos, dof and activation addresses, pinocchio's
        q and v addresses and nq (a mimic joint has none of its own), the window
        [rad or m], the command's index (-1 outside the group) and its scale (a mimic
        joint follows its primary's command times its multiplier)."""
        pin_model, physics = self.pinocchio, self.physics
        group = {name: index for index, name in enumerate(self.group.joints)}
        offsets = np.cumsum([0] + [self.world.joint(j).dofs for j in self.group.joints])
        rows = []
        for number, name in enumerate(physics.servoed):
            qpos, dof = physics.joints[name]
            primary, scale, _ = physics.mimics.get(name, (name, 1.0, 0.0))
            joint = pin_model.joints[pin_model.getJointId(primary)]
            nq = 0 if name in physics.mimics else joint.nq
            act = int(self.model.actuator_actadr[2 * number])
            window = self.servo.window(name, *physics.limits[name])
            command = int(offsets[group[primary]]) if primary in group else -1
            rows.append((qpos, dof, act, joint.idx_q, joint.idx_v, nq, window, command, scale))
        table = np.array(rows, dtype=float).reshape(-1, 9)
        columns = ("qpos", "dof", "act", "q", "v", "nq", "window", "command", "scale")
        out = {key: table[:, i].astype(int) for i, key in enumerate(columns)}
        out["window"], out["scale"] = table[:, 6], table[:, 8]
        out["continuous"] = out["nq"] == 2
        out["commanded"] = out["command"] >= 0
        out["own"] = out["nq"] > 0
        ranges = self.model.jnt_range[[self.model.dof_jntid[d] for d in out["dof"]]]
        limited = self.model.jnt_limited[[self.model.dof_jntid[d] for d in out["dof"]]]
        out["lower"] = np.where(limited, ranges[:, 0], -np.inf)
        out["upper"] = np.where(limited, ranges[:, 1], np.inf)
        return out

    def _free_table(self) -> dict:
        """Per free body: MuJoCo's qpos and dof addresses, pinocchio's q and v
        addresses and the joint's placement (the free body's frame at its neutral
        configuration)."""
        model = self.pinocchio
        table = {}
        for body, (qpos, dof, _) in self.physics.free.items():
            joint = model.frames[self.world.body_frame_id(body)].parentJoint
            table[body] = (qpos, dof, model.joints[joint].idx_q, model.joints[joint].idx_v,
                           model.jointPlacements[joint])
        return table

    # ---- the driver interface --------------------------------------------------------

    def connect(self) -> None:
        """Nothing to reach: the simulation is this object."""

    def disconnect(self) -> None:
        """Nothing to release."""

    def read(self) -> tuple:
        """Step the physics one control period under the last command; return
        ``(q, v)``: the world's configuration (nq) and velocity (nv)."""
        mujoco, data, joints = self._mujoco, self.data, self._joints
        velocity = np.where(joints["commanded"], self._command[joints["command"]], 0.0)
        velocity *= joints["scale"]
        data.ctrl[0::2] = velocity
        data.ctrl[1::2] = velocity
        measured = data.qpos[joints["qpos"]]
        window = joints["window"]
        target = np.clip(data.act[joints["act"]], measured - window, measured + window)
        data.act[joints["act"]] = np.clip(target, joints["lower"], joints["upper"])
        started = time.perf_counter()
        mujoco.mj_step(self.model, data, nstep=self.steps)
        self.step_time += time.perf_counter() - started
        self.contacts.invalidate()
        return self._state()

    def write(self, velocity: np.ndarray) -> None:
        """Set the group's joint-velocity command [rad/s or m/s]."""
        self._command = np.array(velocity, dtype=float)

    def hold(self) -> None:
        """Command zero velocity."""
        self._command = np.zeros(self.group.dofs)

    # ---- contacts ----------------------------------------------------------------------

    def wrench(self, body: str) -> np.ndarray:
        """The wrench ``body`` and what it carries (its subtree, the free bodies welded
        to it) exert on the environment through contacts at the latest physics step:
        ``[fx, fy, fz, tx, ty, tz]`` [N, N m], world frame, torque about the body's
        origin (pressing down on a table: negative ``fz``).

        Raises:
            KeyError: ``body`` is not a body of the simulation.
        """
        return self.contacts.wrench(body)

    def contact(self, first_bodies, second_bodies) -> bool:
        """Whether a body of ``first_bodies`` touches one of ``second_bodies`` (body
        names) at the latest physics step.

        Raises:
            KeyError: a name is not a body of the simulation.
        """
        return self.contacts.touching(first_bodies, second_bodies)

    # ---- free bodies -------------------------------------------------------------------

    @property
    def free_bodies(self) -> list:
        return list(self._free)

    def attach(self, body: str, parent: str) -> None:
        """Weld free ``body`` to ``parent`` where they are now (the weld holds the pose
        of ``parent`` in the frame of ``body``).

        Raises:
            ValueError: ``body`` is not a free body of the world.
        """
        if body not in self._free:
            raise ValueError(f"cannot attach '{body}' in physics: it is not a free body "
                             "(give its model 'free: true' in the world file)")
        self.detach(body)
        mujoco, model, data = self._mujoco, self.model, self.data
        weld = self.physics.welds[(body, parent)]
        first = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        second = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, parent)
        relative = _se3(data.xpos[first], data.xquat[first]).actInv(
            _se3(data.xpos[second], data.xquat[second]))
        model.eq_data[weld, 0:3] = 0.0
        model.eq_data[weld, 3:6] = relative.translation
        model.eq_data[weld, 6:10] = _wxyz(pin.Quaternion(relative.rotation))
        model.eq_data[weld, 10] = 1.0
        data.eq_active[weld] = 1

    def set_pose(self, body: str, pose: pin.SE3) -> None:
        """Put free ``body`` at ``pose`` (world frame), at rest, as a camera saw it."""
        if body not in self._free:
            raise ValueError(f"'{body}' is not a free body: physics does not move it")
        qpos, dof, *_ = self._free[body]
        self.data.qpos[qpos:qpos + 3] = pose.translation
        self.data.qpos[qpos + 3:qpos + 7] = _wxyz(pin.Quaternion(pose.rotation))
        self.data.qvel[dof:dof + 6] = 0.0
        self._mujoco.mj_forward(self.model, self.data)

    def detach(self, body: str) -> None:
        """Release every weld of ``body``: it falls unless something holds it."""
        for (free, _), weld in self.physics.welds.items():
            if free == body:
                self.data.eq_active[weld] = 0

    # ---- state ---------------------------------------------------------------------------

    def _reset(self) -> None:
        """Put the physics at ``initial``: joints, servo targets, free bodies."""
        self.data.qpos[:], self.data.act[:] = initial_state(self.physics, self.world,
                                                            self.initial)
        self._mujoco.mj_forward(self.model, self.data)
        self.contacts.invalidate()

    def _state(self) -> tuple:
        data, joints = self.data, self._joints
        q = self.initial.copy()
        v = np.zeros(self.pinocchio.nv)
        own, continuous = joints["own"], joints["continuous"]
        angle = data.qpos[joints["qpos"]]
        plain = own & ~continuous
        q[joints["q"][plain]] = angle[plain]
        turning = joints["q"][continuous]
        q[turning] = np.cos(angle[continuous])
        q[turning + 1] = np.sin(angle[continuous])
        v[joints["v"][own]] = data.qvel[joints["dof"][own]]
        for qpos, dof, start, speed, placement in self._free.values():
            pose = _se3(data.qpos[qpos:qpos + 3], data.qpos[qpos + 3:qpos + 7])
            q[start:start + 7] = pin.SE3ToXYZQUAT(placement.actInv(pose))
            v[speed:speed + 3] = pose.rotation.T @ data.qvel[dof:dof + 3]
            v[speed + 3:speed + 6] = data.qvel[dof + 3:dof + 6]
        return q, v

    def body_pose(self, body: str) -> pin.SE3:
        """The world pose of a MuJoCo body, as physics left it."""
        mujoco = self._mujoco
        index = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, body)
        return _se3(self.data.xpos[index], self.data.xquat[index])


def _se3(position, wxyz) -> pin.SE3:
    """The pose at ``position`` [m] with MuJoCo's quaternion (w, x, y, z)."""
    return pin.XYZQUATToSE3(np.concatenate([position, wxyz[1:], wxyz[:1]]))


def _wxyz(quaternion: pin.Quaternion) -> list:
    return [quaternion.w, quaternion.x, quaternion.y, quaternion.z]
