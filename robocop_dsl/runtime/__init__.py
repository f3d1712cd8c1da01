"""Running missions: the periodic loop, the simulated driver, logs and plots."""

from .driver import SimulatedDriver
from .log import RunLogger, read_events, read_timeseries
from .mission import Mission, load_mission
from .records import CycleRecord, Event, Observer, TaskView
from .result import RunResult, TransitionRecord
from .runner import Runner

__all__ = ["CycleRecord", "Event", "Mission", "Observer", "RunLogger", "RunResult", "Runner",
           "SimulatedDriver", "TaskView", "TransitionRecord", "load_mission", "read_events",
           "read_timeseries"]
