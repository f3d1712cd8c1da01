"""What a run publishes, as ROS 2 messages (CDR) on the standard topics:

=========================  ====================================  ==========================
topic                      type                                  when
=========================  ====================================  ==========================
``/robot_description``     ``std_msgs/msg/String``               at 0 (the world's URDF)
``/tf_static``             ``tf2_msgs/msg/TFMessage``            at 0: bodies fixed to the
                                                                 world, parent ``world``
``/joint_states``          ``sensor_msgs/msg/JointState``        every cycle: every joint's
                                                                 position [rad or m] and
                                                                 velocity (see
                                                                 :mod:`.joint_states`)
``/tf``                    ``tf2_msgs/msg/TFMessage``            every ``tf_period``: every
                                                                 other body (and any the
                                                                 run moved), parent
                                                                 ``world``
``/mission/state``         ``std_msgs/msg/String``               on each change of the
                                                                 active configuration
``/mission/events``        ``std_msgs/msg/String``               each event, the JSON of
                                                                 its ``events.jsonl`` line
``/rosout``                ``rcl_interfaces/msg/Log``            each event, one line
``/mission/targets``       ``visualization_msgs/msg/MarkerArray``  every 0.1 s while tasks
                                                                 with targets are enabled
``/mission/wrench/BODY``   ``geometry_msgs/msg/WrenchStamped``   every cycle, per force
                                                                 sensor (world frame)
=========================  ====================================  ==========================

Times are mission time [ns], from 0; a message's header stamp is its log time.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass

import numpy as np

from ..runtime.views import view_kinds
from .cdr import Layout, encoder, stamp
from .description import robot_description
from .frames import BodyFrames, position_quaternion
from .joint_states import JointStates
from .markers import DRAWN_KINDS, TargetMarkers

TARGETS_PERIOD = 0.1
"""Mission time [s] between two ``/mission/targets`` messages (and at each change of
the drawn tasks)."""
LOG_LEVELS = {"fault": 40, "qp_failure": 40, "overrun": 30, "dropped": 30,
              "constraint_relaxed": 30, "solver_budget": 30}
"""``rcl_interfaces/msg/Log`` level of an event's ``/rosout`` line (else 20, INFO)."""


RECENT_EVENTS = 50
"""How many of the run's last events a live client gets when it subscribes."""


@dataclass(frozen=True)
class Topic:
    """A topic: its name, its message type, whether a late subscriber should get its
    last message (``transient_local`` durability), and how many of its last messages
    a live stream's client gets when it is the first to subscribe (``history``: the
    run's recent events)."""

    name: str
    type: str
    latched: bool = False
    history: int = 0


def wrench_topic(body: str) -> str:
    """``/mission/wrench/BODY``, characters a ROS name cannot hold replaced by ``_``."""
    return "/mission/wrench/" + re.sub(r"[^A-Za-z0-9_]", "_", body)


def to_ns(time: float) -> int:
    """Mission time [s] in integer nanoseconds."""
    return int(round(time * 1e9))


class RunTopics:
    """Turns a run's cycles and events into messages: lists of ``(topic, time [ns],
    bytes)``. Make it before the run (it copies the world's kinematic model), then feed
    it the cycles in order, from one thread.

    Args:
        world: The run's :class:`~robocop_dsl.world.World`.
        joint_names: The controlled joints, in command order.
        tf_period: Mission time [s] between two ``/tf`` messages (0: every cycle).
    """

    def __init__(self, world, joint_names: list, tf_period: float = 0.0):
        self.joint_names = list(joint_names)
        self.tf_period = tf_period
        self._next_tf = 0.0
        self.sensors = list(world.force_sensors())
        self.topics = [Topic("/robot_description", "std_msgs/msg/String", True),
                       Topic("/tf_static", "tf2_msgs/msg/TFMessage", True),
                       Topic("/joint_states", "sensor_msgs/msg/JointState"),
                       Topic("/tf", "tf2_msgs/msg/TFMessage"),
                       Topic("/mission/state", "std_msgs/msg/String", True),
                       Topic("/mission/events", "std_msgs/msg/String",
                             history=RECENT_EVENTS),
                       Topic("/rosout", "rcl_interfaces/msg/Log", history=RECENT_EVENTS),
                       Topic("/mission/targets", "visualization_msgs/msg/MarkerArray", True)]
        self.topics += [Topic(wrench_topic(body), "geometry_msgs/msg/WrenchStamped")
                        for body in self.sensors]
        self._description = robot_description(world)
        self._frames = BodyFrames(world)
        self._static = dict(zip(self._frames.fixed, self._frames.fixed_poses))
        self._moving = {body: index for index, body in enumerate(self._frames.moving)}
        self._string = encoder("std_msgs/msg/String")
        self._log = encoder("rcl_interfaces/msg/Log")
        self._every_joint = JointStates(world, self.joint_names)
        names = self._every_joint.names
        self._joint_states = Layout()
        self._joint_states.stamp()
        self._joint_states.string("")
        self._joint_states.strings(names)
        self._joint_states.sequence(len(names))
        self._joint_states.sequence(len(names))
        self._joint_states.uint32(0)                     # effort: none
        self._wrench = {body: _wrench_layout() for body in self.sensors}
        self._transforms: tuple = ((), None)             # bodies, their layout
        self._moved: dict = {}                            # body -> last 4x4 pose
        self._state: str | None = None
        self._markers = TargetMarkers()
        self._targets: tuple = ((), -np.inf)              # drawn tasks, time [s]

    def opening(self) -> list:
        """The messages at mission time 0: the URDF and the bodies fixed to the world."""
        frames = self._frames
        static = _transforms_layout(frames.fixed).encode(
            np.zeros(1, dtype=np.int64), position_quaternion(frames.fixed_poses)[None])
        return [("/robot_description", 0, self._string({"data": self._description})),
                ("/tf_static", 0, static[0])]

    def cycles(self, records: list) -> list:
        """The messages of consecutive cycles (:class:`~robocop_dsl.runtime.CycleRecord`)."""
        if not records:
            return []
        times = np.array([to_ns(record.time) for record in records], dtype=np.int64)
        joints = self._every_joint.values(records)
        messages = [("/joint_states", time, data) for time, data in
                    zip(times, self._joint_states.encode(times, joints))]
        shown = []
        for row, record in enumerate(records):
            if record.time >= self._next_tf - 1e-9:
                shown.append(row)
                self._next_tf = record.time + self.tf_period
        messages += self._tf(records, times, shown)
        for body, layout in self._wrench.items():
            wrenches = np.array([record.wrenches.get(body, np.full(6, np.nan))
                                 for record in records])
            messages += [(wrench_topic(body), time, data)
                         for time, data in zip(times, layout.encode(times, wrenches))]
        for record, time in zip(records, times):
            if record.state != self._state:
                self._state = record.state
                messages.append(("/mission/state", time, self._string({"data": record.state})))
            messages += self._target_markers(record, time)
        return messages

    def event(self, line: str) -> list:
        """The messages of one event, given as its line of ``events.jsonl``."""
        event = json.loads(line)
        time = to_ns(event.get("time", 0.0))
        log = {"stamp": stamp(time), "level": LOG_LEVELS.get(event.get("kind"), 20),
               "name": "mission", "msg": event_line(event), "file": "", "function": "",
               "line": 0}
        return [("/mission/events", time, self._string({"data": line})),
                ("/rosout", time, self._log(log))]

    def _tf(self, records: list, times: np.ndarray, shown: list) -> list:
        """``/tf`` at the cycles ``records[shown]``: the moving bodies, then the bodies
        the run moved so far (free bodies as physics put them, attached or placed
        bodies; a released body stays where it was left)."""
        moving = self._moving
        last = dict(self._moved)
        for record in records:
            last.update({body: None for body in record.body_poses
                         if body not in moving and body not in last and body in self._static})
        others = list(last)
        for body in others:
            if last[body] is None:
                last[body] = self._static[body]
        bodies = tuple(moving) + tuple(others)
        if bodies != self._transforms[0]:
            self._transforms = (bodies, _transforms_layout(bodies))
        poses = np.empty((len(shown), len(bodies), 4, 4))
        if shown:
            poses[:, :len(moving)] = self._frames.moving_poses(
                np.array([records[row].q for row in shown]))
        rows = dict(zip(shown, range(len(shown))))
        for row, record in enumerate(records):
            for body, pose in record.body_poses.items():
                if body in last:
                    last[body] = pose
                elif body in moving and row in rows:
                    poses[rows[row], moving[body]] = pose
            if row in rows:
                for column, body in enumerate(others, start=len(moving)):
                    poses[rows[row], column] = last[body]
        self._moved = last
        if not shown:
            return []
        numbers = position_quaternion(poses).reshape(len(shown), -1)
        return [("/tf", time, data) for time, data in
                zip(times[shown], self._transforms[1].encode(times[shown], numbers))]

    def _target_markers(self, record, time: int) -> list:
        """``/mission/targets`` at this cycle: every :data:`TARGETS_PERIOD` while tasks
        with targets are enabled, and when they change (an empty array once when none
        is left)."""
        names = tuple(name for name, kind in view_kinds(record.tasks) if kind in DRAWN_KINDS)
        shown, last = self._targets
        if names == shown and (not names or record.time < last + TARGETS_PERIOD - 1e-9):
            return []
        self._targets = (names, record.time)
        views = [view for view in record.tasks if view.name in names]
        return [("/mission/targets", time, self._markers.encode(views, time))]


def event_line(event: dict) -> str:
    """One line saying what an event is: ``transition A -> B (CONDITION)``, ``fault:
    MESSAGE``, ``log: MESSAGE``, ..."""
    kind = event.get("kind", "event")
    if kind == "transition":
        return f"transition {event.get('from')} -> {event.get('to')} ({event.get('condition')})"
    if kind == "action":
        return "action " + " ".join(f"{key}={value}" for key, value in event.items()
                                    if key not in ("kind", "time", "cycle"))
    if kind == "event":
        return f"event {event.get('name')}"
    if kind == "start":
        return f"start in state {event.get('state')}"
    if kind == "end":
        return f"end: {event.get('outcome')} in state {event.get('state')}: {event.get('message')}"
    return f"{kind}: {event.get('message', '')}".rstrip(": ")


def _transforms_layout(bodies) -> Layout:
    """A ``TFMessage`` of one transform per body, each from ``world``."""
    layout = Layout()
    layout.uint32(len(bodies))
    for body in bodies:
        layout.stamp()
        layout.string("world")
        layout.string(body)
        layout.numbers(7)                    # translation, rotation (x, y, z, w)
    return layout


def _wrench_layout() -> Layout:
    """A ``WrenchStamped`` in the world frame: force [N] then torque [N m]."""
    layout = Layout()
    layout.stamp()
    layout.string("world")
    layout.numbers(6)
    return layout
