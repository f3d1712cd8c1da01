"""The live viewer against real Meshcat servers: what the server ends up showing, a
server bound to the loopback interface, and dead, stalled or missing servers."""

import base64
import re
import socket
import threading
from pathlib import Path

import numpy as np
import pytest
import zmq

from robocop_dsl.runtime import Observer
from robocop_dsl.viewer import (LiveViewer, MeshcatServer, ViewerConnectionError,
                                ViewerOptions)
from robocop_dsl.viewer.commands import unpack
from robocop_dsl.viewer.geometry import WorldGeometry
from viewer_runs import pickup_run, synthetic_run

SYNC = 60.0     # [s] a hang guard only; publishing takes a fraction of it


def server_scene(zmq_url):
    """The commands a Meshcat server replays to a new browser, decoded."""
    context = zmq.Context.instance()
    request = context.socket(zmq.REQ)
    request.setsockopt(zmq.LINGER, 0)
    request.connect(zmq_url)
    request.send(b"get_scene")
    page = request.recv().decode("utf-8")
    request.close()
    blobs = re.findall(r'fetch\("data:application/octet-binary;base64,([A-Za-z0-9+/=]+)"\)',
                       page)
    return [unpack(base64.b64decode(blob)) for blob in blobs]


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def records(bazar):
    return synthetic_run(bazar)


def test_server_shows_the_latest_cycle(bazar, records):
    """After a run, the server holds every geometry at the last cycle's pose (the part
    where it was released), the last state's label shown and the enabled task's markers."""
    with LiveViewer(bazar, options=ViewerOptions(period=0.01)) as viewer:
        for item in records:
            viewer.on_cycle(item)
        viewer.on_stop(None)
        assert viewer.sync(SYNC)
        assert viewer.published >= 1 and viewer.problems == []
        commands = server_scene(viewer.zmq_url)
    objects = {c["path"] for c in commands if c["type"] == "set_object"}
    transforms = {c["path"]: np.array(c["matrix"]).reshape(4, 4).T
                  for c in commands if c["type"] == "set_transform"}
    geometry = WorldGeometry(bazar)
    last = records[-1]
    moved = {}
    for item in records:
        moved.update(item.body_poses)
    assert "part_body" in moved and not last.body_poses
    for path, pose in geometry.poses(last.q, moved).items():
        np.testing.assert_allclose(transforms[f"/meshcat/{path}"], pose, atol=1e-9)
    for path, offset in geometry.offsets().items():
        assert f"/meshcat/{path}" in objects
        np.testing.assert_allclose(transforms[f"/meshcat/{path}"], offset, atol=1e-9)
    visible = {c["path"]: c["value"] for c in commands
               if c["type"] == "set_property" and c["property"] == "visible"}
    assert visible[f"/meshcat/states/{last.state}"] is True
    assert visible["/meshcat/targets/right_point/target"] is True


def test_started_server_listens_on_loopback_only(bazar):
    """Both the ZeroMQ and the web addresses are on 127.0.0.1, and the web port is
    bound to 127.0.0.1 (not to every interface)."""
    table = Path("/proc/net/tcp")
    with LiveViewer(bazar) as viewer:
        assert viewer.zmq_url.startswith("tcp://127.0.0.1:")
        assert viewer.web_url.startswith("http://127.0.0.1:")
        if not table.exists():
            pytest.skip("no /proc/net/tcp to read listening addresses from")
        port = int(viewer.web_url.split(":")[2].split("/")[0])
        listening = [line.split()[1] for line in table.read_text().splitlines()[1:]
                     if line.split()[3] == "0A"]
    assert f"0100007F:{port:04X}" in listening
    assert f"00000000:{port:04X}" not in listening


def test_dead_server_is_reported_once_and_the_run_goes_on(bazar, records):
    """Killing the server mid-run: cycles keep being accepted, the viewer stops and the
    failure is reported exactly once, through the list and the callback."""
    reported = []
    viewer = LiveViewer(bazar, timeout=0.5, on_problem=reported.append)
    assert viewer.sync(SYNC)
    viewer.server.process.kill()
    viewer.server.process.wait()
    for item in records:
        viewer.on_cycle(item)
    assert not viewer.sync(SYNC)
    for item in records:
        viewer.on_cycle(item)
    viewer.on_stop(None)
    viewer.close()
    assert reported == viewer.problems and len(reported) == 1
    assert "viewer stopped" in reported[0] and "the run goes on" in reported[0]


def stalling_server(port, stall, done):
    """A ZeroMQ endpoint that answers like a Meshcat server until ``stall`` is set, then
    leaves the next request unanswered until ``done`` is set."""
    reply = zmq.Context.instance().socket(zmq.REP)
    reply.setsockopt(zmq.LINGER, 0)
    reply.bind(f"tcp://127.0.0.1:{port}")
    while not done.is_set():
        if not reply.poll(50):
            continue
        frames = reply.recv_multipart()
        if stall.is_set():
            done.wait()
            break
        reply.send(b"http://127.0.0.1:1/static/" if frames == [b"url"] else b"ok")
    reply.close()


def test_stalled_server_never_holds_the_control_thread(bazar, records):
    """While the publisher waits on a server that stopped answering, every cycle is
    handed over at once; the wait ends in one reported problem."""
    port = free_port()
    stall, done = threading.Event(), threading.Event()
    endpoint = threading.Thread(target=stalling_server, args=(port, stall, done))
    endpoint.start()
    try:
        viewer = LiveViewer(bazar, zmq_url=f"tcp://127.0.0.1:{port}", timeout=2.0)
        stall.set()
        for item in records:
            viewer.on_cycle(item)
        assert not viewer.sync(SYNC)
        viewer.close()
    finally:
        done.set()
        endpoint.join()
    assert viewer.published == 0
    assert len(viewer.problems) == 1 and "did not answer within 2 s" in viewer.problems[0]


def test_connects_to_an_existing_server_and_leaves_it_running(bazar, records):
    """With a ZeroMQ address the viewer starts no server and does not stop that one."""
    server = MeshcatServer()
    try:
        with LiveViewer(bazar, zmq_url=server.zmq_url) as viewer:
            assert viewer.server is None and viewer.web_url == server.web_url
            viewer.on_cycle(records[0])
            assert viewer.sync(SYNC)
        assert server.process.poll() is None
        assert any(c["path"].startswith("/meshcat/world/visuals/")
                   for c in server_scene(server.zmq_url))
    finally:
        server.close()


def test_unreachable_server_is_an_error(bazar):
    """Nobody at the given address: the viewer cannot be created and says where."""
    url = f"tcp://127.0.0.1:{free_port()}"
    with pytest.raises(ViewerConnectionError, match="did not answer") as error:
        LiveViewer(bazar, zmq_url=url, timeout=0.2)
    assert error.value.zmq_url == url


class LastRecord(Observer):
    """An observer keeping the last cycle's record."""

    record = None

    def on_cycle(self, record):
        self.record = record


def killed_viewer(world):
    viewer = LiveViewer(world, timeout=0.5)
    viewer.server.process.kill()
    viewer.server.process.wait()
    return viewer


@pytest.mark.parametrize("make_viewer", [LiveViewer, killed_viewer], ids=["live", "dead"])
def test_viewer_changes_nothing_in_the_run(make_viewer):
    """The pickup mission takes the same transitions and ends in the same posture (to
    the solver's last digits, which vary from run to run) with a live viewer, or one
    whose server died, as without a viewer."""
    headless, (alone,) = pickup_run(lambda world: [LastRecord()])
    watched, (last, viewer) = pickup_run(lambda world: [LastRecord(), make_viewer(world)])
    viewer.close()
    assert watched.outcome == headless.outcome == "success"
    assert watched.cycles == headless.cycles
    assert [(t.time, t.target) for t in watched.transitions] == \
        [(t.time, t.target) for t in headless.transitions]
    np.testing.assert_allclose(last.record.q, alone.record.q, rtol=0, atol=1e-9)
    assert len(viewer.problems) == (1 if make_viewer is killed_viewer else 0)


def test_malformed_address_is_an_error(bazar):
    """An address ZeroMQ cannot use is refused with the address in the message."""
    with pytest.raises(ViewerConnectionError, match="cannot connect to a Meshcat server at "
                                                    "'localhost:6000'"):
        LiveViewer(bazar, zmq_url="localhost:6000")
