"""``run --foxglove``: the run live over the Foxglove WebSocket protocol (protocol v1,
``foxglove.sdk.v1`` as foxglove-sdk names it, formerly ``foxglove.websocket.v1``). A
plain WebSocket client offering either name sees every topic advertised and gets
``/joint_states`` once subscribed; bad or remote addresses and taken ports are refused
with a clear error."""

import asyncio
import json
import re
import signal
import socket
import struct
import subprocess
import sys
from pathlib import Path

import pytest
import websockets
from rosbags.typesys import Stores, get_typestore

from conftest import MISSIONS
from robocop_dsl.cli.main import main
from robocop_dsl.ecosystem import (FoxgloveAddressError, FoxgloveError, FoxgloveServer,
                                   parse_address)
from robocop_dsl.ecosystem.topics import Topic

REPO = Path(__file__).resolve().parent.parent
TOPICS = {"/robot_description", "/tf_static", "/joint_states", "/tf", "/mission/state",
          "/mission/events", "/rosout", "/mission/targets"}


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


async def watch(url: str, count: int, subprotocol: str) -> tuple:
    """Connect offering ``subprotocol`` alone, read the advertised channels, subscribe
    to ``/joint_states``; the negotiated subprotocol, the channels and ``count``
    messages' payloads."""
    async with websockets.connect(url, subprotocols=[subprotocol], compression=None) as ws:
        channels: dict = {}
        while "/joint_states" not in channels:
            message = await ws.recv()
            if isinstance(message, str) and json.loads(message)["op"] == "advertise":
                channels.update({c["topic"]: c for c in json.loads(message)["channels"]})
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": [
            {"id": 1, "channelId": channels["/joint_states"]["id"]}]}))
        payloads = []
        while len(payloads) < count:
            message = await ws.recv()
            if isinstance(message, bytes) and message[0] == 1:      # message data
                subscription, time = struct.unpack_from("<IQ", message, 1)
                assert subscription == 1
                payloads.append((time, message[13:]))
        return ws.subprotocol, channels, payloads


async def watch_both(url: str, count: int) -> list:
    """Two clients at once, one offering the protocol's current name, one its former."""
    return await asyncio.gather(watch(url, count, "foxglove.sdk.v1"),
                                watch(url, count, "foxglove.websocket.v1"))


def test_a_client_sees_the_channels_and_gets_joint_states(bazar):
    port = free_port()
    process = subprocess.Popen(
        [sys.executable, "-m", "robocop_dsl", "run", str(MISSIONS / "pickup.mission"),
         "--foxglove", f"127.0.0.1:{port}", "--realtime"],
        cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        line = process.stdout.readline()
        assert line.strip() == f"foxglove: ws://127.0.0.1:{port}"
        watched = asyncio.run(watch_both(f"ws://127.0.0.1:{port}", 5))
    finally:
        process.send_signal(signal.SIGINT)
        process.communicate()
    assert process.returncode == 130
    assert [protocol for protocol, _, _ in watched] == ["foxglove.sdk.v1",
                                                        "foxglove.websocket.v1"]
    for _, channels, payloads in watched:
        check_joint_states(bazar, channels, payloads)


def check_joint_states(bazar, channels: dict, payloads: list) -> None:
    """Every topic advertised, ``/joint_states`` in CDR with the group's joints, in
    order of time, each stamped with its message's time."""
    assert TOPICS <= set(channels)
    joint_states = channels["/joint_states"]
    assert (joint_states["encoding"], joint_states["schemaName"],
            joint_states["schemaEncoding"]) == ("cdr", "sensor_msgs/msg/JointState", "ros2msg")
    typestore = get_typestore(Stores.ROS2_HUMBLE)
    group = bazar.joint_group("bazar_upper_joints")
    times = [time for time, _ in payloads]
    assert times == sorted(times) and len(set(times)) == len(times)
    for time, payload in payloads:
        message = typestore.deserialize_cdr(payload, "sensor_msgs/msg/JointState")
        assert list(message.name) == list(group.joints)
        assert message.header.stamp.sec * 10**9 + message.header.stamp.nanosec == time


@pytest.mark.parametrize("subprotocols", [["other.v1"], None])
def test_a_client_offering_no_foxglove_protocol_is_refused(subprotocols):
    """The server's own refusal (HTTP 400) reaches the client through the address it
    connected to; a client offering the former name on that address gets in."""
    server = FoxgloveServer("127.0.0.1", 0, [])

    async def connect(offered):
        async with websockets.connect(server.url, subprotocols=offered) as ws:
            return ws.subprotocol

    try:
        with pytest.raises(websockets.InvalidStatus, match="HTTP 400"):
            asyncio.run(connect(subprotocols))
        assert asyncio.run(connect(["foxglove.websocket.v1"])) == "foxglove.websocket.v1"
    finally:
        server.close()


def test_an_unknown_host_is_a_clear_error():
    with pytest.raises(FoxgloveError, match="cannot serve Foxglove on nosuchhost.invalid:0"):
        FoxgloveServer("nosuchhost.invalid", 0, [])


@pytest.mark.parametrize("address, allow, message", [
    ("localhost", False, "expected HOST:PORT"),
    ("127.0.0.1:99999", False, "expected HOST:PORT"),
    ("0.0.0.0:8765", False, "add --allow-remote"),
    ("192.168.1.10:8765", False, "add --allow-remote"),
    ("::1", True, r"an IPv6 address goes in brackets, the port after them \(e.g. \[::1\]:8765\)"),
    ("::1:8765", True, "an IPv6 address goes in brackets"),
])
def test_bad_addresses_are_refused(address, allow, message):
    with pytest.raises(FoxgloveAddressError, match=message):
        parse_address(address, allow)


def test_addresses():
    assert parse_address("127.0.0.1:8765") == ("127.0.0.1", 8765)
    assert parse_address("[::1]:0") == ("::1", 0)
    assert parse_address("localhost:9000") == ("localhost", 9000)
    assert parse_address("0.0.0.0:8765", allow_remote=True) == ("0.0.0.0", 8765)


async def subscribed(url: str, topics: list):
    """A client offering ``foxglove.sdk.v1``, subscribed to ``topics`` in one request
    (subscription ids 1, 2...)."""
    ws = await websockets.connect(url, subprotocols=["foxglove.sdk.v1"], compression=None)
    channels: dict = {}
    while not set(topics) <= set(channels):
        message = await ws.recv()
        if isinstance(message, str) and json.loads(message)["op"] == "advertise":
            channels.update({c["topic"]: c["id"] for c in json.loads(message)["channels"]})
    await ws.send(json.dumps({"op": "subscribe", "subscriptions": [
        {"id": index, "channelId": channels[topic]} for index, topic in enumerate(topics, 1)]}))
    return ws


async def received(ws, subscription: int, until: bytes) -> list:
    """The payloads of ``subscription`` that ``ws`` receives up to ``until``."""
    payloads: list = []
    while until not in payloads:
        message = await ws.recv()
        if isinstance(message, bytes) and message[0] == 1 and \
                struct.unpack_from("<I", message, 1)[0] == subscription:
            payloads.append(message[13:])
    return payloads


def test_the_first_client_to_subscribe_gets_the_last_events():
    """A Foxglove opened after the run started shows its last events (here 3 of 5),
    and a second client beside it makes the first get none of them twice."""
    events, state = "/mission/events", "/mission/state"
    server = FoxgloveServer("127.0.0.1", 0, [Topic(events, "std_msgs/msg/String", history=3),
                                             Topic(state, "std_msgs/msg/String", True)])

    async def clients():
        first = await subscribed(server.url, [events])
        early = await received(first, 1, b"event 5")
        second = await subscribed(server.url, [events, state])
        await received(second, 2, b"lift")      # its subscriptions are in place
        server.write([(events, 6, b"event 6")])
        late = await received(first, 1, b"event 6"), await received(second, 1, b"event 6")
        await first.close()
        await second.close()
        return early, late

    try:
        server.write([(state, 0, b"lift")] + [(events, time, f"event {time}".encode())
                                               for time in range(1, 6)])
        early, (first_late, second_late) = asyncio.run(asyncio.wait_for(clients(), 60))
    finally:
        server.close()
    assert early == [b"event 3", b"event 4", b"event 5"]
    assert first_late == [b"event 6"] and second_late == [b"event 6"]


def test_a_server_on_every_address_is_opened_by_this_machine_s_name():
    """``ws://0.0.0.0:PORT`` opens nothing: the URL to give Foxglove names the machine."""
    server = FoxgloveServer("0.0.0.0", 0, [])
    try:
        assert server.url.startswith(f"ws://{socket.gethostname()}:")
        assert int(server.url.rsplit(":", 1)[1]) > 0
    finally:
        server.close()


def test_the_command_line_refuses_a_remote_address_without_consent(capsys):
    code = main(["run", str(MISSIONS / "pickup.mission"), "--foxglove", "0.0.0.0:8765"])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    assert "robocop-mission run: error: --foxglove '0.0.0.0:8765': 0.0.0.0 is not the" in err


def test_a_taken_port_is_a_clear_error(capsys, tmp_path):
    """The run does not start, and leaves no log folder that would look like a run's."""
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        code = main(["run", str(MISSIONS / "pickup.mission"), "--foxglove",
                     f"127.0.0.1:{port}", "--duration", "0.1", "--log", str(tmp_path / "log")])
    err = capsys.readouterr().err
    assert code == 3 and "Traceback" not in err
    assert f"cannot serve Foxglove on 127.0.0.1:{port}: Address already in use" in err
    assert not (tmp_path / "log").exists()


def test_the_layout_shows_the_run_s_topics():
    """docs/foxglove_layout.json: the 3D view, joint plots, the state and the events, on
    topics the run publishes."""
    layout = json.loads((REPO / "docs" / "foxglove_layout.json").read_text())
    panels = {key.split("!")[0] for key in layout["configById"]}
    assert {"3D", "Plot", "StateTransitions", "RawMessages", "RosOut"} <= panels
    used = set(re.findall(r'"(/[a-z_/]+)[."]', json.dumps(layout["configById"])))
    assert {"/robot_description", "/mission/targets", "/joint_states", "/mission/state",
            "/rosout"} == used
