"""The replay file and the live page in a real browser (headless Chromium): the robot
is drawn, compared pixel by pixel with an empty scene seen from the same camera."""

import shutil
import subprocess

import meshcat
import numpy as np
import pytest
from PIL import Image

from robocop_dsl.viewer import LiveViewer, ReplayRecorder, Scene, write_replay
from robocop_dsl.viewer.camera import set_camera
from robocop_dsl.viewer.commands import CommandLog
from viewer_runs import pickup_run

CHROMIUM = shutil.which("chromium")
pytestmark = pytest.mark.skipif(
    CHROMIUM is None, reason="Chromium is not installed (Debian: apt-get install chromium)")

SIZE = (1024, 768)
HANG_GUARD = 300    # [s] for a browser that never exits; a screenshot takes seconds
SYNC = 60.0         # [s] hang guard for the live viewer to publish


def screenshot(url, path, tmp_path):
    """A headless Chromium screenshot of ``url`` (run as root, network closed)."""
    profile = tmp_path / f"profile-{path.stem}"
    profile.mkdir()
    subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                    "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
                    "--disable-background-networking", "--disable-component-update",
                    "--disable-sync", f"--user-data-dir={profile}",
                    f"--window-size={SIZE[0]},{SIZE[1]}", "--hide-scrollbars",
                    "--virtual-time-budget=5000", f"--screenshot={path}", url],
                   check=True, capture_output=True, timeout=HANG_GUARD)
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def robot_orange(image):
    """Pixels of the arms' orange links (URDF colour 1, 0.45, 0 under the lights); the
    world axes' x line has a few."""
    red, green, blue = image[..., 0], image[..., 1], image[..., 2]
    return (red > 180) & (green > 60) & (green < 170) & (blue < 80)


def changed(image, empty):
    """Fraction of pixels that differ clearly from the empty scene."""
    return float(np.mean(np.abs(image - empty).sum(axis=2) > 60))


@pytest.fixture(scope="module")
def empty_scene(bazar, tmp_path_factory):
    """The empty scene seen from the camera the viewer uses for BAZAR's world."""
    folder = tmp_path_factory.mktemp("empty")
    log = CommandLog()
    set_camera(meshcat.Visualizer(window=log), *Scene(bazar).camera)
    page = write_replay(folder / "empty.html", log.commands, "empty")
    return screenshot(page.as_uri(), folder / "empty.png", folder)


def mid_grasp(result):
    """A run time [s] halfway through the pickup's grasp state."""
    starts = {t.target: t.time for t in result.transitions if "/" not in t.target}
    return (starts["grasp"] + starts["lift"]) / 2


def test_replay_file_draws_the_robot(empty_scene, tmp_path):
    """The pickup's replay, paused mid-grasp, shows the robot where the empty scene
    shows sky."""
    result, (recorder,) = pickup_run(
        lambda world: [ReplayRecorder(world, tmp_path / "pickup.html")])
    url = f"{recorder.path.as_uri()}#t={mid_grasp(result):.3f}"
    image = screenshot(url, tmp_path / "replay.png", tmp_path)
    assert changed(image, empty_scene) > 0.05
    assert robot_orange(image).sum() - robot_orange(empty_scene).sum() > 2000


def test_live_page_draws_the_robot(empty_scene, tmp_path):
    """The live page of a pickup run shows the robot too."""
    result, (viewer,) = pickup_run(lambda world: [LiveViewer(world)])
    with viewer:
        assert result.outcome == "success" and viewer.sync(SYNC)
        image = screenshot(viewer.web_url, tmp_path / "live.png", tmp_path)
    assert changed(image, empty_scene) > 0.05
    assert robot_orange(image).sum() - robot_orange(empty_scene).sum() > 2000
