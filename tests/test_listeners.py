"""Every listener binds the loopback interface unless told ``--allow-remote``: the
Meshcat server; a sweep's worker processes on this machine listen on no port."""

from __future__ import annotations

import socket
import subprocess
import sys

import psutil
import pytest

from robocop_dsl.campaign import open_engine
from robocop_dsl.viewer.connection import MeshcatServer
from robocop_dsl.viewer.errors import ViewerConnectionError

SERVER = [sys.executable, "-m", "robocop_dsl.viewer.server"]


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.mark.parametrize("url", ["tcp://0.0.0.0:{port}", "tcp://*:{port}",
                                 "tcp://[::]:{port}", "tcp://example.org:{port}"])
def test_viewer_server_refuses_a_remote_address(url):
    url = url.format(port=_free_port())
    done = subprocess.run([*SERVER, "--zmq-url", url], capture_output=True, text=True,
                          stdin=subprocess.DEVNULL)
    assert done.returncode == 2
    assert "--allow-remote" in done.stderr and url in done.stderr
    assert "zmq_url=" not in done.stdout


def _listening_addresses(pid: int) -> list[str]:
    """The address of each socket ``pid`` listens on."""
    return [c.laddr.ip for c in psutil.Process(pid).net_connections(kind="tcp")
            if c.status == psutil.CONN_LISTEN]


def _wait_listening(pid: int, count: int) -> set:
    """The addresses ``pid`` listens on, once it listens on ``count`` sockets."""
    found = _listening_addresses(pid)
    while len(found) < count:
        found = _listening_addresses(pid)
    return set(found)


def test_viewer_server_listens_remotely_when_allowed():
    port = _free_port()
    server = subprocess.Popen([*SERVER, "--zmq-url", f"tcp://0.0.0.0:{port}",
                               "--allow-remote"], stdout=subprocess.PIPE, text=True)
    try:
        assert server.stdout.readline().strip() == f"zmq_url=tcp://0.0.0.0:{port}"
        assert server.stdout.readline().startswith("web_url=http://0.0.0.0:")
        assert _wait_listening(server.pid, 2) == {"0.0.0.0"}
    finally:
        server.terminate()
        server.wait()


def test_viewer_server_listens_on_loopback_by_default():
    server = MeshcatServer()
    try:
        assert server.zmq_url.startswith("tcp://127.0.0.1:")
        assert server.web_url.startswith("http://127.0.0.1:")
        assert _wait_listening(server.process.pid, 2) == {"127.0.0.1"}
    finally:
        server.close()


def test_meshcat_server_api_refuses_a_remote_address_before_starting():
    with pytest.raises(ViewerConnectionError, match="beyond this machine"):
        MeshcatServer(zmq_url="tcp://0.0.0.0:6010")


def test_local_sweep_workers_listen_on_no_port():
    with open_engine(workers=1) as engine:
        assert len(engine.pids) == 1
        assert not [a for pid in engine.pids for a in _listening_addresses(pid)]
