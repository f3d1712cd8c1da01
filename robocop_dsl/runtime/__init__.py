"""Running missions: the periodic loop, the simulated driver, logs and plots.

The names below are imported on first use, so that a module of the package (the run
log's, in its writing process) comes without the compiler and the controller.
"""

import importlib

_SOURCES = {"SimulatedDriver": ".driver", "RunLogger": ".log", "read_events": ".log",
            "read_timeseries": ".log", "Mission": ".mission", "load_mission": ".mission",
            "CycleRecord": ".records", "Event": ".records", "Observer": ".records",
            "TaskView": ".records", "RunResult": ".result", "TransitionRecord": ".result",
            "Runner": ".runner"}

__all__ = sorted(_SOURCES)


def __getattr__(name: str):
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(_SOURCES[name], __name__), name)
