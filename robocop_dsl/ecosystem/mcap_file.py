"""``run.mcap``: an MCAP file of the ``ros2`` profile (ROS 2 message definitions, CDR
messages), written while the run goes and readable at every moment.

Messages gather in zstd-compressed chunks; :meth:`McapFile.checkpoint` closes the chunk
in progress and ends the file with a provisional footer (no summary: readers scan the
chunks), which the next chunk overwrites. A run killed between two checkpoints leaves a
file whose every message up to the last checkpoint can be read;
:meth:`McapFile.close` writes the summary and the real footer.
"""

from __future__ import annotations

import struct
from pathlib import Path

from .. import __version__
from .msgdefs import message_definition

MCAP_FILE = "run.mcap"
"""The MCAP file's name in a log folder."""
MAGIC = b"\x89MCAP0\r\n"
PROVISIONAL_END = (b"\x0f" + struct.pack("<QI", 4, 0)                  # data end, no CRC
                   + b"\x02" + struct.pack("<QQQI", 20, 0, 0, 0)       # footer, no summary
                   + MAGIC)
TRANSIENT_LOCAL = ("- history: 3\n  depth: 0\n  reliability: 1\n  durability: 1\n"
                   "  deadline:\n    sec: 2147483647\n    nsec: 4294967295\n"
                   "  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n"
                   "  liveliness: 1\n  liveliness_lease_duration:\n    sec: 2147483647\n"
                   "    nsec: 4294967295\n  avoid_ros_namespace_conventions: false\n")
"""The QoS profile ``ros2 bag`` records for a latched topic (``/tf_static``)."""


class McapFile:
    """An MCAP file of a run's topics.

    Args:
        path: Where to write it (replaced).
        topics: The :class:`~.topics.Topic` s it will hold.
    """

    def __init__(self, path: str | Path, topics: list):
        from mcap.writer import CompressionType, Writer

        self.path = Path(path)
        self._stream = _ProvisionalEnd(self.path)
        self._writer = Writer(self._stream, compression=CompressionType.ZSTD)
        self._writer.start(profile="ros2", library=f"robocop-mission {__version__}")
        self._channels: dict = {}
        schemas: dict = {}
        for topic in topics:
            if topic.type not in schemas:
                schemas[topic.type] = self._writer.register_schema(
                    topic.type, "ros2msg", message_definition(topic.type).encode())
            metadata = {"offered_qos_profiles": TRANSIENT_LOCAL} if topic.latched else {}
            self._channels[topic.name] = self._writer.register_channel(
                topic.name, "cdr", schemas[topic.type], metadata)

    def write(self, messages: list) -> None:
        """Add ``(topic, time [ns], bytes)`` messages."""
        for topic, time, data in messages:
            self._writer.add_message(self._channels[topic], int(time), data, int(time))

    def checkpoint(self) -> None:
        """Write what was added so far, the file readable up to it."""
        self._writer.flush()

    def close(self) -> None:
        """Write the summary and the footer."""
        self._writer.finish()
        self._stream.close()


class _ProvisionalEnd:
    """A file written through ``write``, ``tell`` and ``flush`` (as the MCAP writer
    does), that ends with :data:`PROVISIONAL_END` after every ``flush``; what comes
    after is written over it."""

    def __init__(self, path: Path):
        self._file = open(path, "wb")
        self._pending = bytearray()
        self._written = 0

    def write(self, data: bytes) -> int:
        self._pending += data
        return len(data)

    def tell(self) -> int:
        return self._written + len(self._pending)

    def flush(self) -> None:
        self._file.seek(self._written)
        self._file.write(bytes(self._pending) + PROVISIONAL_END)
        self._file.flush()
        self._written += len(self._pending)
        self._pending.clear()

    def close(self) -> None:
        self._file.seek(self._written)
        self._file.write(bytes(self._pending))
        self._file.truncate()
        self._file.close()
