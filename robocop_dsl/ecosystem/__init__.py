"""The run in the robotics ecosystem: its cycles and events as ROS 2 messages on the
standard topics (:mod:`.topics`), written to ``run.mcap`` beside the run log and served
live to Foxglove, and older logs converted (:func:`export_mcap`)::

    runner.add_observer(mcap_log(mission.world, runner.joint_names, "log"))
    live = foxglove_live(mission.world, runner.joint_names, "127.0.0.1", 8765)
    print(live.sink.url)
    runner.add_observer(live)
"""

from pathlib import Path

from ..runtime.writer_thread import BATCH, DROP

from .export import ExportError, export_mcap
from .foxglove_live import (DEFAULT_ADDRESS, FoxgloveAddressError, FoxgloveError,
                            FoxgloveServer, parse_address)
from .mcap_file import MCAP_FILE, McapFile
from .stream import LIVE_PERIOD, MCAP_PERIOD, MCAP_TF_PERIOD, TopicStream
from .topics import RunTopics

__all__ = ["DEFAULT_ADDRESS", "ExportError", "FoxgloveAddressError", "FoxgloveError",
           "FoxgloveServer", "MCAP_FILE", "McapFile", "RunTopics", "TopicStream",
           "export_mcap", "foxglove_live", "mcap_log", "parse_address"]


def mcap_log(world, joint_names: list, folder, policy: str = BATCH) -> TopicStream:
    """The observer writing ``FOLDER/run.mcap`` while the run goes, its writer's
    ``policy`` as :class:`~robocop_dsl.runtime.RunLogger`'s. Make it before the run."""
    topics = RunTopics(world, joint_names, MCAP_TF_PERIOD)
    Path(folder).mkdir(parents=True, exist_ok=True)
    sink = McapFile(Path(folder) / MCAP_FILE, topics.topics)
    return TopicStream(topics, sink, MCAP_FILE, MCAP_PERIOD, policy)


def foxglove_live(world, joint_names: list, host: str, port: int,
                  name: str = "robocop-mission") -> TopicStream:
    """The observer serving the run live to Foxglove on ``host:port`` (its ``sink.url``).

    Raises:
        FoxgloveError: the server cannot listen there.
    """
    topics = RunTopics(world, joint_names, LIVE_PERIOD)
    sink = FoxgloveServer(host, port, topics.topics, name)
    return TopicStream(topics, sink, "foxglove", LIVE_PERIOD, DROP)
