"""The active state's name, drawn as a text sprite that always faces the camera.

One sprite per state; the viewer shows the active state's sprite and hides the others,
so a replay switches labels with plain visibility keyframes."""

from __future__ import annotations

import meshcat.geometry as mg
import numpy as np

ROOT = "states"
SIZE = 0.9              # [m] side of the square sprite; the text spans its width
FONT_SIZE = 48          # [px] on the 256 px texture, shrunk to fit long names
FONT_FACE = "sans-serif"


def label_path(state: str) -> str:
    """Meshcat path of the label of a state or active configuration: one node under
    ``states``, its paths' ``/`` written ``.`` (a state name has no dot)."""
    return f"{ROOT}/{state.replace('/', '.')}"


class _SpriteMaterial(mg.GenericMaterial):
    _type = "SpriteMaterial"


class _Sprite(mg.Object):
    """A three.js ``Sprite``: a textured square facing the camera (no geometry)."""

    def __init__(self, material):
        mg.SceneElement.__init__(self)
        self.material = material

    def lower(self) -> dict:
        data = {"metadata": {"version": 4.5, "type": "Object"},
                "materials": [],
                "object": {"uuid": self.uuid, "type": "Sprite",
                           "material": self.material.uuid,
                           "matrix": list(np.eye(4).flatten())}}
        self.material.lower_in_object(data)
        return data


def load_label(visualizer, state: str, position: np.ndarray) -> None:
    """Send the label of ``state`` at ``position`` [m], hidden until the state is active."""
    texture = mg.GenericTexture({"type": "_text", "text": state,
                                 "font_size": FONT_SIZE, "font_face": FONT_FACE})
    material = _SpriteMaterial(map=texture, transparent=True, depthTest=False)
    node = visualizer[label_path(state)]
    node.set_object(_Sprite(material))
    pose = np.diag([SIZE, SIZE, SIZE, 1.0])
    pose[:3, 3] = position
    node.set_transform(pose)
    node.set_property("visible", False)
